//! Bindings of heavy tops on a moving pivot, damped: conversion only.

use crate::errors::IntoPyResult;
use crate::heavy::{lyapunov_dict, PyHeavyTop};
use kreisel_core::models::heavy_top::driven::{Damping, DrivenTop, PathSpline, Pivot};
use kreisel_core::models::heavy_top::RigidState;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::Arc;

/// The native driven heavy top (parameters only).
#[pyclass(name = "DrivenTop", module = "kreisel._core", frozen)]
pub struct PyDrivenTop {
    pub inner: DrivenTop,
}

#[pymethods]
impl PyDrivenTop {
    /// `pivot` is "fixed", "harmonic" (amplitude, omega, phase) or "path" (breaks and the
    /// coefficients of its degree-5 piecewise polynomial, scipy's `PPoly.c` layout).
    #[new]
    #[pyo3(signature = (top, pivot, amplitude, omega, phase, breaks, coef, viscous, drag, dry, pivot_radius))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        top: PyRef<'_, PyHeavyTop>,
        pivot: &str,
        amplitude: [f64; 3],
        omega: f64,
        phase: [f64; 3],
        breaks: Vec<f64>,
        coef: Vec<f64>,
        viscous: f64,
        drag: f64,
        dry: f64,
        pivot_radius: f64,
    ) -> PyResult<Self> {
        let pivot = match pivot {
            "fixed" => Pivot::Fixed,
            "harmonic" => Pivot::harmonic(amplitude, omega, phase).py(py)?,
            "path" => Pivot::Path(Arc::new(PathSpline::new(breaks, &coef).py(py)?)),
            other => {
                return Err(pyo3::exceptions::PyValueError::new_err(format!(
                    "unknown pivot kind {other:?}"
                )))
            }
        };
        let damping = Damping::new(viscous, drag, dry, pivot_radius).py(py)?;
        Ok(PyDrivenTop {
            inner: DrivenTop::new(top.inner, pivot, damping).py(py)?,
        })
    }

    /// Lab-frame energy and Mz (about the pivot) of a rigid state at time t.
    fn invariants<'py>(
        &self,
        py: Python<'py>,
        q: [f64; 4],
        omega: [f64; 3],
        t: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let s = RigidState::new(q, omega).py(py)?;
        let d = PyDict::new(py);
        d.set_item("energy", self.inner.energy(t, &s))?;
        d.set_item("Mz", self.inner.top().mz(&s))?;
        Ok(d)
    }

    /// The sticking margin `|geff x c| - mu_p r_p |geff|` at time t (<= 0: dry friction holds).
    fn stick_margin(&self, py: Python<'_>, q: [f64; 4], t: f64) -> PyResult<f64> {
        let s = RigidState::new(q, [0.0; 3]).py(py)?;
        Ok(self.inner.stick_margin(t, s.q))
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
        let s0 = RigidState::new(q, omega).py(py)?;
        lyapunov_dict(
            py,
            self.inner.clone(),
            s0,
            (t_end, tau, d0, direction, rtol, atol),
        )
    }
}
