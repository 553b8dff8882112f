//! The compiled module `kreisel._core`: PyO3 bindings of kreisel-core, no physics here.

mod batch;
mod columns;
mod driven;
mod errors;
mod heavy;
mod lagrange;
mod play;
mod quantum;
mod sensitivity;
mod simulate;
mod special;
mod stability;

use pyo3::prelude::*;

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<lagrange::PyLagrangeTop>()?;
    m.add_class::<heavy::PyHeavyTop>()?;
    m.add_class::<driven::PyDrivenTop>()?;
    m.add_class::<play::PyPlayTop>()?;
    m.add_class::<play::PyFriction>()?;
    m.add_class::<simulate::PyRun>()?;
    m.add_class::<stability::PyPlayStability>()?;
    m.add_class::<quantum::PySymmetricTop>()?;
    m.add_function(wrap_pyfunction!(simulate::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(simulate::many, m)?)?;
    m.add_function(wrap_pyfunction!(sensitivity::simulate_sensitivities, m)?)?;
    m.add_function(wrap_pyfunction!(simulate::names, m)?)?;
    m.add_function(wrap_pyfunction!(simulate::check_settings, m)?)?;
    m.add_function(wrap_pyfunction!(simulate::check_event, m)?)?;
    m.add_function(wrap_pyfunction!(columns::lagrange_columns, m)?)?;
    m.add_function(wrap_pyfunction!(columns::rotation_matrices, m)?)?;
    m.add_function(wrap_pyfunction!(columns::quaternions_from_euler, m)?)?;
    m.add_function(wrap_pyfunction!(batch::lyapunov_many, m)?)?;
    m.add_function(wrap_pyfunction!(lagrange::check_euler_state, m)?)?;
    m.add_function(wrap_pyfunction!(lagrange::check_rate, m)?)?;
    m.add_function(wrap_pyfunction!(heavy::rigid_from_euler, m)?)?;
    m.add_function(wrap_pyfunction!(heavy::methods, m)?)?;
    m.add_function(wrap_pyfunction!(special::ellipj, m)?)?;
    m.add_function(wrap_pyfunction!(special::ellipk, m)?)?;
    m.add_function(wrap_pyfunction!(special::ellipf, m)?)?;
    m.add_function(wrap_pyfunction!(special::ellippiinc, m)?)?;
    m.add_function(wrap_pyfunction!(special::ellippi, m)?)?;
    m.add_function(wrap_pyfunction!(special::cubic_roots, m)?)?;
    m.add_function(wrap_pyfunction!(stability::play_u_m, m)?)?;
    m.add_function(wrap_pyfunction!(stability::play_classify, m)?)?;
    m.add_function(wrap_pyfunction!(stability::play_zones, m)?)?;
    m.add_function(wrap_pyfunction!(stability::play_zone_boundaries, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
