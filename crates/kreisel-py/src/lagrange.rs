//! Bindings of the Lagrange top: conversion only, physics stays in the core.

use crate::errors::IntoPyResult;
use kreisel_core::models::lagrange::{EulerState, LagrangeExact, LagrangeTop};
use kreisel_core::stability::steady_precession as sp;
use numpy::{IntoPyArray, PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

type StateTuple = (f64, f64, f64, f64, f64, f64);

fn state(py: Python<'_>, s: StateTuple) -> PyResult<EulerState> {
    EulerState::new(s.0, s.1, s.2, s.3, s.4, s.5).py(py)
}

/// The exact solution from a state; a numerical failure names the state.
fn solve(py: Python<'_>, top: &LagrangeTop, s: &EulerState) -> PyResult<LagrangeExact> {
    LagrangeExact::new(top, s)
        .map_err(|e| in_state(e, s))
        .py(py)
}

/// A core failure, with the state it was computing from.
fn in_state(e: kreisel_core::KreiselError, s: &EulerState) -> kreisel_core::KreiselError {
    match e {
        kreisel_core::KreiselError::Numerical(msg) => {
            kreisel_core::KreiselError::Numerical(format!(
                "the exact solution from the state (theta = {}, theta_dot = {}, phi_dot = {}, \
                 psi_dot = {}): {msg}",
                s.theta, s.theta_dot, s.phi_dot, s.psi_dot
            ))
        }
        other => other,
    }
}

/// Validates a state given as (theta, phi, psi, theta_dot, phi_dot, psi_dot).
#[pyfunction]
pub fn check_euler_state(py: Python<'_>, s: StateTuple) -> PyResult<()> {
    state(py, s).map(|_| ())
}

/// Checks an angular rate (rad/s) against the core's rule for rates.
#[pyfunction]
pub fn check_rate(py: Python<'_>, name: &str, value: f64) -> PyResult<f64> {
    kreisel_core::error::rate(name, value).py(py)
}

/// The native Lagrange top (parameters only).
#[pyclass(name = "LagrangeTop", module = "kreisel._core", frozen)]
pub struct PyLagrangeTop {
    inner: LagrangeTop,
}

#[pymethods]
impl PyLagrangeTop {
    #[new]
    fn new(py: Python<'_>, i1: f64, i3: f64, m: f64, l: f64, g: f64) -> PyResult<Self> {
        Ok(PyLagrangeTop {
            inner: LagrangeTop::new(i1, i3, m, l, g).py(py)?,
        })
    }

    /// (E, Mz, M3) of a state.
    fn invariants(&self, py: Python<'_>, s: StateTuple) -> PyResult<(f64, f64, f64)> {
        let inv = self.inner.invariants(&state(py, s)?);
        Ok((inv.energy, inv.mz, inv.m3))
    }

    /// Effective potential at each theta.
    fn effective_potential<'py>(
        &self,
        py: Python<'py>,
        theta: PyReadonlyArray1<'py, f64>,
        mz: f64,
        m3: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let th = theta.as_slice()?;
        let v: kreisel_core::Result<Vec<f64>> = th
            .iter()
            .map(|&x| self.inner.effective_potential(x, mz, m3))
            .collect();
        Ok(v.py(py)?.into_pyarray(py))
    }

    /// Analysis of the motion from a state: kind, turning points, period, mean rate.
    fn analyse<'py>(&self, py: Python<'py>, s: StateTuple) -> PyResult<Bound<'py, PyDict>> {
        let ex = solve(py, &self.inner, &state(py, s)?)?;
        let d = PyDict::new(py);
        let (tmin, tmax) = ex.turning_points();
        d.set_item("kind", ex.kind().name())?;
        d.set_item("theta_min", tmin)?;
        d.set_item("theta_max", tmax)?;
        d.set_item("nutation_period", ex.nutation_period())?;
        d.set_item("mean_precession_rate", ex.mean_precession_rate())?;
        d.set_item("segments", ex.segments())?;
        Ok(d)
    }

    /// The exact motion at times `t`: (theta, phi, psi, theta_dot, phi_dot, psi_dot).
    /// `direct=True` evaluates every time with elliptic functions (slow; for checks).
    #[pyo3(signature = (s, t, direct=false))]
    #[allow(clippy::type_complexity)]
    fn exact<'py>(
        &self,
        py: Python<'py>,
        s: StateTuple,
        t: PyReadonlyArray1<'py, f64>,
        direct: bool,
    ) -> PyResult<Vec<Bound<'py, PyArray1<f64>>>> {
        let st = state(py, s)?;
        let ts = t.as_slice()?;
        let ex = solve(py, &self.inner, &st)?;
        // numpy's own allocation (huge pages for large arrays on Linux) spares the page
        // faults that would otherwise cost as much as the evaluation.
        let arrays: Vec<Bound<'py, PyArray1<f64>>> = (0..6)
            .map(|_| unsafe { PyArray1::<f64>::new(py, ts.len(), false) })
            .collect();
        {
            let mut views: Vec<_> = arrays.iter().map(|a| a.readwrite()).collect();
            let mut slices: Vec<&mut [f64]> = Vec::with_capacity(6);
            for v in views.iter_mut() {
                slices.push(v.as_slice_mut()?);
            }
            let out: [&mut [f64]; 6] = slices
                .try_into()
                .map_err(|_| pyo3::exceptions::PyRuntimeError::new_err("six outputs"))?;
            py.detach(|| {
                if direct {
                    ex.eval_direct_into(ts, out)
                } else {
                    ex.eval_par_into(ts, out)
                }
            })
            .map_err(|e| in_state(e, &st))
            .py(py)?;
        }
        Ok(arrays)
    }

    fn steady_precession(&self, py: Python<'_>, theta0: f64, omega3: f64) -> PyResult<Vec<f64>> {
        sp::steady_precession_rates(&self.inner, theta0, omega3).py(py)
    }

    fn nutation_frequency(
        &self,
        py: Python<'_>,
        theta0: f64,
        omega3: f64,
        rate: f64,
    ) -> PyResult<f64> {
        sp::nutation_frequency(&self.inner, theta0, omega3, rate).py(py)
    }

    fn sleeping_threshold(&self) -> f64 {
        sp::sleeping_threshold(&self.inner)
    }
}
