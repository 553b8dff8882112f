//! The compiled module `kreisel._core`: PyO3 bindings of kreisel-core, no physics here.

mod errors;
mod lagrange;

use pyo3::prelude::*;

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<lagrange::PyLagrangeTop>()?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
