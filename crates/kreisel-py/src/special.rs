//! Bindings of the core's special functions (vectorised over the first array argument).

use crate::errors::IntoPyResult;
use kreisel_core::special::{self, cubic::Poly3};
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;

type Arr<'py> = Bound<'py, PyArray1<f64>>;

/// (sn, cn, dn, am) at every u for parameter m in [0, 1].
#[pyfunction]
pub fn ellipj<'py>(
    py: Python<'py>,
    u: PyReadonlyArray1<'py, f64>,
    m: f64,
) -> PyResult<(Arr<'py>, Arr<'py>, Arr<'py>, Arr<'py>)> {
    let u = u.as_slice()?;
    let n = u.len();
    let (mut sn, mut cn, mut dn, mut am) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    );
    for &x in u {
        let j = special::ellipj(x, m).py(py)?;
        sn.push(j.sn);
        cn.push(j.cn);
        dn.push(j.dn);
        am.push(j.am);
    }
    Ok((
        sn.into_pyarray(py),
        cn.into_pyarray(py),
        dn.into_pyarray(py),
        am.into_pyarray(py),
    ))
}

/// K(m).
#[pyfunction]
pub fn ellipk(py: Python<'_>, m: f64) -> PyResult<f64> {
    special::ellipk(m).py(py)
}

/// F(phi | m) at every phi.
#[pyfunction]
pub fn ellipf<'py>(py: Python<'py>, phi: PyReadonlyArray1<'py, f64>, m: f64) -> PyResult<Arr<'py>> {
    let v: kreisel_core::Result<Vec<f64>> = phi
        .as_slice()?
        .iter()
        .map(|&p| special::ellipf(p, m))
        .collect();
    Ok(v.py(py)?.into_pyarray(py))
}

/// Pi(n; phi | m) at every phi (principal value where n sin^2 phi > 1).
#[pyfunction]
pub fn ellippiinc<'py>(
    py: Python<'py>,
    n: f64,
    phi: PyReadonlyArray1<'py, f64>,
    m: f64,
) -> PyResult<Arr<'py>> {
    let v: kreisel_core::Result<Vec<f64>> = phi
        .as_slice()?
        .iter()
        .map(|&p| special::ellippiinc(p, n, m))
        .collect();
    Ok(v.py(py)?.into_pyarray(py))
}

/// Pi(n | m), complete (principal value for n > 1).
#[pyfunction]
pub fn ellippi(py: Python<'_>, n: f64, m: f64) -> PyResult<f64> {
    special::ellippi(n, m).py(py)
}

/// Real roots, ascending with multiplicity, of c0 + c1 x + c2 x^2 + c3 x^3.
#[pyfunction]
pub fn cubic_roots(py: Python<'_>, c0: f64, c1: f64, c2: f64, c3: f64) -> PyResult<Vec<f64>> {
    Poly3([c0, c1, c2, c3]).real_roots().py(py)
}
