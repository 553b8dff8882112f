//! Columns that figures and animations need, computed by the core: the invariants of an
//! exact Lagrange motion from its angles and rates, rotation matrices of quaternions, and
//! quaternions of Euler angles. Conversion only.

use crate::errors::IntoPyResult;
use kreisel_core::models::lagrange::LagrangeTop;
use kreisel_core::rotation::{quaternion_from_euler, Quat};
use numpy::{IntoPyArray, PyArray2, PyArray3, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Energy, Mz, M3 and the potential of a Lagrange top (I1, I3, m, l, g) at rows of
/// (theta, theta_dot, phi_dot, psi_dot).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn lagrange_columns<'py>(
    py: Python<'py>,
    i1: f64,
    i3: f64,
    m: f64,
    l: f64,
    g: f64,
    theta: PyReadonlyArray1<'py, f64>,
    theta_dot: PyReadonlyArray1<'py, f64>,
    phi_dot: PyReadonlyArray1<'py, f64>,
    psi_dot: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let top = LagrangeTop::new(i1, i3, m, l, g).py(py)?;
    let c = top.columns(
        theta.as_slice()?,
        theta_dot.as_slice()?,
        phi_dot.as_slice()?,
        psi_dot.as_slice()?,
    );
    let d = PyDict::new(py);
    d.set_item("energy", c.energy.into_pyarray(py))?;
    d.set_item("Mz", c.mz.into_pyarray(py))?;
    d.set_item("M3", c.m3.into_pyarray(py))?;
    d.set_item("potential", c.potential.into_pyarray(py))?;
    Ok(d)
}

/// Body-to-space rotation matrices (n, 3, 3) of unit quaternions (n, 4), (w, x, y, z).
#[pyfunction]
pub fn rotation_matrices<'py>(
    py: Python<'py>,
    q: PyReadonlyArray2<'py, f64>,
) -> PyResult<Bound<'py, PyArray3<f64>>> {
    let q = q.as_array();
    if q.ncols() != 4 {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "q has shape ({}, {}): quaternions are rows of 4 numbers",
            q.nrows(),
            q.ncols()
        )));
    }
    let n = q.nrows();
    let mut out = Vec::with_capacity(9 * n);
    for r in q.rows() {
        let m = Quat([r[0], r[1], r[2], r[3]]).matrix();
        for row in m {
            out.extend_from_slice(&row);
        }
    }
    out.into_pyarray(py).reshape([n, 3, 3])
}

/// Quaternions (n, 4) of z-x-z Euler angles (rad): R = Rz(phi) Rx(theta) Rz(psi).
#[pyfunction]
pub fn quaternions_from_euler<'py>(
    py: Python<'py>,
    phi: PyReadonlyArray1<'py, f64>,
    theta: PyReadonlyArray1<'py, f64>,
    psi: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let (a, b, c) = (phi.as_slice()?, theta.as_slice()?, psi.as_slice()?);
    let n = a.len().min(b.len()).min(c.len());
    let mut out = Vec::with_capacity(4 * n);
    for i in 0..n {
        out.extend_from_slice(&quaternion_from_euler(a[i], b[i], c[i]).0);
    }
    out.into_pyarray(py).reshape([n, 4])
}
