//! Bindings of heavy tops and their simulation: conversion only.

use crate::errors::IntoPyResult;
use kreisel_core::chaos::{self, LyapunovSettings};
use kreisel_core::models::heavy_top::{HeavyTop, RigidState};
use kreisel_core::rotation::{omega_body_from_euler, quaternion_from_euler};
use kreisel_core::simulate;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The native heavy top (parameters only).
#[pyclass(name = "HeavyTop", module = "kreisel._core", frozen)]
pub struct PyHeavyTop {
    pub inner: HeavyTop,
}

fn rigid(py: Python<'_>, q: [f64; 4], omega: [f64; 3]) -> PyResult<RigidState> {
    RigidState::new(q, omega).py(py)
}

#[pymethods]
impl PyHeavyTop {
    #[new]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        i1: f64,
        i2: f64,
        i3: f64,
        m: f64,
        com: [f64; 3],
        g: f64,
    ) -> PyResult<Self> {
        Ok(PyHeavyTop {
            inner: HeavyTop::new(i1, i2, i3, m, com, g).py(py)?,
        })
    }

    #[getter]
    fn kind(&self) -> &'static str {
        self.inner.kind().name()
    }

    /// Validates a rigid state; returns the normalised quaternion and omega.
    fn check_rigid(
        &self,
        py: Python<'_>,
        q: [f64; 4],
        omega: [f64; 3],
    ) -> PyResult<([f64; 4], [f64; 3])> {
        let s = rigid(py, q, omega)?;
        Ok((s.q.0, s.omega))
    }

    /// Energy, Mz and (where integrals) M3 and Kovalevskaya's K of a rigid state.
    fn invariants<'py>(
        &self,
        py: Python<'py>,
        q: [f64; 4],
        omega: [f64; 3],
    ) -> PyResult<Bound<'py, PyDict>> {
        let s = rigid(py, q, omega)?;
        let d = PyDict::new(py);
        d.set_item("energy", self.inner.energy(&s))?;
        d.set_item("Mz", self.inner.mz(&s))?;
        if let Some(m3) = self.inner.m3(&s) {
            d.set_item("M3", m3)?;
        }
        if let Some(k) = self.inner.kovalevskaya(&s) {
            d.set_item("kovalevskaya", k)?;
        }
        Ok(d)
    }

    /// The largest Lyapunov exponent (Benettin): the estimate and its history.
    #[pyo3(signature = (q, omega, t_end, tau, d0, direction, rtol, atol))]
    #[allow(clippy::too_many_arguments)]
    fn lyapunov<'py>(
        &self,
        py: Python<'py>,
        q: [f64; 4],
        omega: [f64; 3],
        t_end: f64,
        tau: f64,
        d0: f64,
        direction: [f64; 6],
        rtol: f64,
        atol: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let s0 = rigid(py, q, omega)?;
        lyapunov_dict(py, self.inner, s0, (t_end, tau, d0, direction, rtol, atol))
    }
}

/// Runs a Lyapunov estimate with the interpreter released (Ctrl-C stops it) and returns
/// `{"exponent", "t", "running"}`.
pub fn lyapunov_dict<M: chaos::Segments + Send>(
    py: Python<'_>,
    top: M,
    s0: RigidState,
    (t_end, tau, d0, direction, rtol, atol): (f64, f64, f64, [f64; 6], f64, f64),
) -> PyResult<Bound<'_, PyDict>> {
    let st = lyapunov_settings(t_end, tau, d0, direction, rtol, atol);
    let (res, signal) = py.detach(move || {
        let mut signals = crate::simulate::Signals::new();
        let res = chaos::lyapunov_with(&top, &s0, &st, &mut |_| signals.keep_going());
        (res, signals.error)
    });
    if let Some(e) = signal {
        return Err(e);
    }
    let res = res.py(py)?;
    let d = PyDict::new(py);
    d.set_item("exponent", res.exponent)?;
    d.set_item("t", res.t.into_pyarray(py))?;
    d.set_item("running", res.running.into_pyarray(py))?;
    Ok(d)
}

/// The core's settings of a Lyapunov estimate.
pub fn lyapunov_settings(
    t_end: f64,
    tau: f64,
    d0: f64,
    direction: [f64; 6],
    rtol: f64,
    atol: f64,
) -> LyapunovSettings {
    LyapunovSettings {
        t_end,
        tau,
        d0,
        direction,
        rtol,
        atol,
    }
}

/// (q, omega) of Euler angles and rates.
#[pyfunction]
pub fn rigid_from_euler(
    theta: f64,
    phi: f64,
    psi: f64,
    theta_dot: f64,
    phi_dot: f64,
    psi_dot: f64,
) -> ([f64; 4], [f64; 3]) {
    (
        quaternion_from_euler(phi, theta, psi).0,
        omega_body_from_euler(theta, psi, theta_dot, phi_dot, psi_dot),
    )
}

/// Every method: (name, order, adaptive, symplectic, events, summary).
#[pyfunction]
pub fn methods() -> Vec<(&'static str, u32, bool, bool, bool, &'static str)> {
    simulate::METHODS
        .iter()
        .map(|m| {
            (
                m.name,
                m.order,
                m.adaptive,
                m.symplectic,
                m.events,
                m.summary,
            )
        })
        .collect()
}
