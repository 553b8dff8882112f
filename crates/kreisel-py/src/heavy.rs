//! Bindings of heavy tops and their simulation: conversion only.

use crate::errors::IntoPyResult;
use kreisel_core::chaos::{self, LyapunovSettings};
use kreisel_core::models::heavy_top::{HeavyTop, RigidState};
use kreisel_core::rotation::{omega_body_from_euler, quaternion_from_euler, Quat};
use kreisel_core::simulate::{self, EventDef, EventKind, Settings};
use numpy::{IntoPyArray, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::cell::RefCell;

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

    /// The diagnostics columns (Euler angles, energy, Mz, and M3 and Kovalevskaya's K where
    /// they are integrals) of states given as (n, 4) unit quaternions and (n, 3) body rates,
    /// taken as they are.
    fn columns<'py>(
        &self,
        py: Python<'py>,
        quaternion: PyReadonlyArray2<'py, f64>,
        omega: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (q, w) = (quaternion.as_array(), omega.as_array());
        let states: Vec<RigidState> = q
            .rows()
            .into_iter()
            .zip(w.rows())
            .map(|(q, w)| RigidState {
                q: Quat([q[0], q[1], q[2], q[3]]),
                omega: [w[0], w[1], w[2]],
            })
            .collect();
        let top = self.inner;
        let cols = py.detach(move || simulate::columns(&top, &states));
        let d = PyDict::new(py);
        d.set_item("theta", cols.theta.into_pyarray(py))?;
        d.set_item("phi", cols.phi.into_pyarray(py))?;
        d.set_item("psi", cols.psi.into_pyarray(py))?;
        d.set_item("energy", cols.energy.into_pyarray(py))?;
        d.set_item("Mz", cols.mz.into_pyarray(py))?;
        if let Some(v) = cols.m3 {
            d.set_item("M3", v.into_pyarray(py))?;
        }
        if let Some(v) = cols.kovalevskaya {
            d.set_item("kovalevskaya", v.into_pyarray(py))?;
        }
        Ok(d)
    }

    /// Simulates from (q, omega); returns a dict of the states, the names of the diagnostics
    /// columns (see `columns`), events and stats.
    /// `events`: (name, kind, callable or None, value, direction, terminal) with kind
    /// "user", "turning_points" or "theta_crossing".
    #[pyo3(signature = (q, omega, t_end, method, rtol, atol, dt=None, t_eval=None, events=Vec::new(), reduced=false))]
    #[allow(clippy::too_many_arguments)]
    fn simulate<'py>(
        &self,
        py: Python<'py>,
        q: [f64; 4],
        omega: [f64; 3],
        t_end: f64,
        method: String,
        rtol: f64,
        atol: f64,
        dt: Option<f64>,
        t_eval: Option<PyReadonlyArray1<'py, f64>>,
        events: Vec<EventTuple>,
        reduced: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let s0 = rigid(py, q, omega)?;
        let settings = Settings {
            method,
            t_end,
            rtol,
            atol,
            dt,
            t_eval: match &t_eval {
                Some(a) => Some(a.as_slice()?.to_vec()),
                None => None,
            },
        };
        let top = self.inner;
        let failure: RefCell<Option<PyErr>> = RefCell::new(None);
        let has_user = events.iter().any(|e| e.1 == "user");
        let result = if has_user {
            // User event functions are Python: the run keeps the interpreter.
            let mut defs = event_defs(&events, Some((py, &failure)))?;
            let mut keep_going = |_t: f64| failure.borrow().is_none();
            simulate::simulate(&top, &s0, &settings, &mut defs, reduced, &mut keep_going)
        } else {
            let spec: Vec<EventTuple> = events
                .iter()
                .map(|e| (e.0.clone(), e.1.clone(), None, e.3, e.4, e.5))
                .collect();
            py.detach(move || {
                let mut defs = event_defs(&spec, None).expect("built-in events only");
                let mut keep_going = |_t: f64| true;
                simulate::simulate(&top, &s0, &settings, &mut defs, reduced, &mut keep_going)
            })
        };
        if let Some(e) = failure.into_inner() {
            return Err(e);
        }
        let out = result.py(py)?;
        let n = out.t.len();
        let d = PyDict::new(py);
        let (mut quat, mut om) = (Vec::with_capacity(4 * n), Vec::with_capacity(3 * n));
        for s in &out.states {
            quat.extend_from_slice(&s.q.0);
            om.extend_from_slice(&s.omega);
        }
        d.set_item("t", out.t.into_pyarray(py))?;
        d.set_item("quaternion", quat.into_pyarray(py).reshape([n, 4])?)?;
        d.set_item("omega", om.into_pyarray(py).reshape([n, 3])?)?;
        // The diagnostics follow from these states on demand (`columns`): their names.
        let mut derived = vec!["theta", "phi", "psi", "energy", "Mz"];
        if top.m3(&s0).is_some() {
            derived.push("M3");
        }
        if top.kovalevskaya(&s0).is_some() {
            derived.push("kovalevskaya");
        }
        d.set_item("derived", derived)?;
        d.set_item("events", out.events)?;
        let stats = PyDict::new(py);
        stats.set_item("steps", out.stats.steps)?;
        stats.set_item("rejected", out.stats.rejected)?;
        stats.set_item("rhs_evals", out.stats.rhs_evals)?;
        d.set_item("stats", stats)?;
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
        let st = lyapunov_settings(t_end, tau, d0, direction, rtol, atol);
        let top = self.inner;
        let res = py.detach(move || chaos::lyapunov(&top, &s0, &st)).py(py)?;
        let d = PyDict::new(py);
        d.set_item("exponent", res.exponent)?;
        d.set_item("t", res.t.into_pyarray(py))?;
        d.set_item("running", res.running.into_pyarray(py))?;
        Ok(d)
    }
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

type EventTuple = (String, String, Option<Py<PyAny>>, f64, i8, bool);

/// The core's event definitions; user functions are called with the interpreter held and
/// their exceptions kept in `failure` (the run then stops at the next step).
fn event_defs<'a>(
    events: &'a [EventTuple],
    user: Option<(Python<'a>, &'a RefCell<Option<PyErr>>)>,
) -> PyResult<Vec<EventDef<'a>>> {
    events
        .iter()
        .map(|(name, kind, func, value, direction, terminal)| {
            let kind = match kind.as_str() {
                "turning_points" => EventKind::TurningPoints,
                "theta_crossing" => EventKind::ThetaCrossing(*value),
                "user" => {
                    let (py, failure) = user.ok_or_else(|| {
                        pyo3::exceptions::PyRuntimeError::new_err(
                            "user events need the interpreter",
                        )
                    })?;
                    let f = func.as_ref().ok_or_else(|| {
                        pyo3::exceptions::PyValueError::new_err(format!(
                            "event {name:?} has no function"
                        ))
                    })?;
                    EventKind::User(Box::new(move |t: f64, s: &RigidState| {
                        if failure.borrow().is_some() {
                            return 0.0;
                        }
                        match f
                            .call1(py, (t, s.q.0, s.omega))
                            .and_then(|r| r.extract::<f64>(py))
                        {
                            Ok(v) => v,
                            Err(e) => {
                                *failure.borrow_mut() = Some(e);
                                0.0
                            }
                        }
                    }))
                }
                other => {
                    return Err(pyo3::exceptions::PyValueError::new_err(format!(
                        "unknown event kind {other:?}"
                    )))
                }
            };
            Ok(EventDef {
                kind,
                direction: *direction,
                terminal: *terminal,
            })
        })
        .collect()
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
