//! Core errors become the Python package's own exceptions (defined in `kreisel._errors`,
//! where `ParameterError` derives from both `KreiselError` and `ValueError`).

use kreisel_core::KreiselError;
use pyo3::prelude::*;

/// Converts a core error into the matching `kreisel` exception.
pub fn to_py(py: Python<'_>, e: KreiselError) -> PyErr {
    let class = match e {
        KreiselError::InvalidParameter { .. } => "ParameterError",
        KreiselError::Numerical(_) => "NumericalError",
    };
    let msg = e.to_string();
    match py
        .import("kreisel._errors")
        .and_then(|m| m.getattr(class))
        .and_then(|c| c.call1((msg.clone(),)))
    {
        Ok(obj) => PyErr::from_value(obj),
        Err(_) => pyo3::exceptions::PyValueError::new_err(msg),
    }
}

/// `Result` extension: `.py(py)?` turns a core error into a Python exception.
pub trait IntoPyResult<T> {
    fn py(self, py: Python<'_>) -> PyResult<T>;
}

impl<T> IntoPyResult<T> for kreisel_core::Result<T> {
    fn py(self, py: Python<'_>) -> PyResult<T> {
        self.map_err(|e| to_py(py, e))
    }
}
