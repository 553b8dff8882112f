//! Bindings of the play top: conversion only.

use crate::errors::IntoPyResult;
use kreisel_core::models::play_top::{Friction, Mode, PlayTop, DIM};
use kreisel_core::rotation::Quat;
use kreisel_core::simulate_play::{self, PlaySettings};
use numpy::{IntoPyArray, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The native play top (parameters only).
#[pyclass(name = "PlayTop", module = "kreisel._core", frozen)]
pub struct PyPlayTop {
    pub inner: PlayTop,
}

/// The states of a play-top run, kept natively so that their diagnostics are computed only
/// when asked for (`columns`).
#[pyclass(name = "PlayRun", module = "kreisel._core", frozen)]
pub struct PyPlayRun {
    top: PlayTop,
    y: Vec<[f64; DIM]>,
    mode: Vec<Mode>,
    dir: Vec<[f64; 3]>,
}

#[pymethods]
impl PyPlayRun {
    /// The diagnostics columns of the run's outputs: Euler angles (phi, psi unwrapped), u,
    /// contact point, slip velocity and speed, normal force, Jellett's J and the energy parts
    /// (translation, rotation, potential) as an (n, 3) array.
    fn columns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let cols =
            py.detach(|| simulate_play::play_columns(&self.top, &self.y, &self.mode, &self.dir));
        let n = self.y.len();
        let v3 = |v: &Vec<[f64; 3]>| -> Vec<f64> { v.iter().flat_map(|x| *x).collect() };
        let d = PyDict::new(py);
        d.set_item("theta", cols.theta.into_pyarray(py))?;
        d.set_item("phi", cols.phi.into_pyarray(py))?;
        d.set_item("psi", cols.psi.into_pyarray(py))?;
        d.set_item("u", cols.u.into_pyarray(py))?;
        d.set_item(
            "contact_point",
            v3(&cols.contact).into_pyarray(py).reshape([n, 3])?,
        )?;
        d.set_item(
            "slip_velocity",
            v3(&cols.slip_velocity).into_pyarray(py).reshape([n, 3])?,
        )?;
        d.set_item("slip_speed", cols.slip_speed.into_pyarray(py))?;
        d.set_item("normal_force", cols.normal_force.into_pyarray(py))?;
        d.set_item("jellett", cols.jellett.into_pyarray(py))?;
        let ep: Vec<f64> = cols.energy_parts.iter().flat_map(|x| *x).collect();
        d.set_item("energy_parts", ep.into_pyarray(py).reshape([n, 3])?)?;
        Ok(d)
    }
}

/// A state as (q, omega, com, com_velocity).
pub type Packed = ([f64; 4], [f64; 3], [f64; 3], [f64; 3]);

/// The core's state vector of a packed state (no energy dissipated yet).
pub fn pack(s: &Packed) -> [f64; DIM] {
    let mut y = [0.0; DIM];
    y[..4].copy_from_slice(&s.0);
    y[4..7].copy_from_slice(&s.1);
    y[7..10].copy_from_slice(&s.2);
    y[10..13].copy_from_slice(&s.3);
    y
}

fn unpack(y: &[f64; DIM]) -> Packed {
    (
        [y[0], y[1], y[2], y[3]],
        [y[4], y[5], y[6]],
        [y[7], y[8], y[9]],
        [y[10], y[11], y[12]],
    )
}

pub fn settings(
    t_end: f64,
    rtol: f64,
    atol: f64,
    t_eval: Option<Vec<f64>>,
    inversion_level: Option<f64>,
    stop_at_inversion: bool,
    stop_at_rest: bool,
) -> PlaySettings {
    PlaySettings {
        t_end,
        rtol,
        atol,
        t_eval,
        inversion_level,
        stop_at_inversion,
        stop_at_rest,
    }
}

#[pymethods]
impl PyPlayTop {
    #[new]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        m: f64,
        a: f64,
        c: f64,
        s: f64,
        rho: f64,
        g: f64,
        friction: &str,
        mu: f64,
        restitution: f64,
        rolling: f64,
        drilling: f64,
        air: f64,
    ) -> PyResult<Self> {
        let fr = match friction {
            "coulomb" => Friction::Coulomb { mu },
            "viscous" => Friction::Viscous { mu },
            "none" => Friction::Frictionless,
            other => {
                return Err(pyo3::exceptions::PyValueError::new_err(format!(
                    "friction = {other:?} is not allowed: use \"coulomb\", \"viscous\" or \"none\""
                )))
            }
        };
        Ok(PyPlayTop {
            inner: PlayTop::new(m, a, c, s, rho, g, fr, restitution, rolling, drilling, air)
                .py(py)?,
        })
    }

    #[getter]
    fn alpha(&self) -> f64 {
        self.inner.alpha()
    }
    #[getter]
    fn gamma(&self) -> f64 {
        self.inner.gamma()
    }
    #[getter]
    fn j_beta(&self) -> f64 {
        self.inner.j_beta()
    }

    /// (q, omega, com, com_velocity) of a state given by orientation and rates.
    #[pyo3(signature = (q, omega, vx, vy, height=None))]
    fn state(
        &self,
        py: Python<'_>,
        q: [f64; 4],
        omega: [f64; 3],
        vx: f64,
        vy: f64,
        height: Option<f64>,
    ) -> PyResult<Packed> {
        let y = self.inner.state(Quat(q), omega, vx, vy, height).py(py)?;
        Ok(unpack(&y))
    }

    /// (Jellett's J, energy) of a packed state.
    fn invariants(&self, s: Packed) -> (f64, f64) {
        let y = pack(&s);
        let (a, b, c) = self.inner.energy_parts(&y);
        (self.inner.jellett(&y), a + b + c)
    }

    /// Simulates from a packed state; returns a dict of the state columns, the run (a
    /// `PlayRun`, for the diagnostics columns), events and stats.
    #[pyo3(signature = (s, t_end, rtol, atol, t_eval=None, inversion_level=None, stop_at_inversion=false, stop_at_rest=false))]
    #[allow(clippy::too_many_arguments)]
    fn simulate<'py>(
        &self,
        py: Python<'py>,
        s: Packed,
        t_end: f64,
        rtol: f64,
        atol: f64,
        t_eval: Option<PyReadonlyArray1<'py, f64>>,
        inversion_level: Option<f64>,
        stop_at_inversion: bool,
        stop_at_rest: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let te = match &t_eval {
            Some(a) => Some(a.as_slice()?.to_vec()),
            None => None,
        };
        let st = settings(
            t_end,
            rtol,
            atol,
            te,
            inversion_level,
            stop_at_inversion,
            stop_at_rest,
        );
        let top = self.inner;
        let y0 = pack(&s);
        let out = py
            .detach(move || simulate_play::simulate_play(&top, y0, &st))
            .py(py)?;
        let n = out.t.len();
        let d = PyDict::new(py);
        let flat = |k: std::ops::Range<usize>| -> Vec<f64> {
            let mut v = Vec::with_capacity(n * k.len());
            for y in &out.y {
                v.extend_from_slice(&y[k.clone()]);
            }
            v
        };
        d.set_item("quaternion", flat(0..4).into_pyarray(py).reshape([n, 4])?)?;
        d.set_item("omega", flat(4..7).into_pyarray(py).reshape([n, 3])?)?;
        d.set_item("com", flat(7..10).into_pyarray(py).reshape([n, 3])?)?;
        d.set_item(
            "com_velocity",
            flat(10..13).into_pyarray(py).reshape([n, 3])?,
        )?;
        d.set_item("dissipated", flat(13..14).into_pyarray(py))?;
        // Codes (0 slip, 1 roll, 2 flight): one array, not a Python string per output.
        let modes: Vec<u8> = out.mode.iter().map(|m| m.code()).collect();
        d.set_item("mode", modes.into_pyarray(py))?;
        d.set_item("events", out.events)?;
        d.set_item("t", out.t.into_pyarray(py))?;
        let stats = PyDict::new(py);
        stats.set_item("steps", out.steps)?;
        stats.set_item("rejected", out.rejected)?;
        stats.set_item("rhs_evals", out.rhs_evals)?;
        d.set_item("stats", stats)?;
        let run = PyPlayRun {
            top,
            y: out.y,
            mode: out.mode,
            dir: out.dir,
        };
        d.set_item("run", run)?;
        Ok(d)
    }
}
