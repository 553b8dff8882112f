//! Binding of a heavy top's run with forward sensitivities: conversion only (the names, the
//! rules and the equations are the core's).

use crate::errors::IntoPyResult;
use crate::simulate::{
    flat, heavy_state, native, play_state, put_play, put_rigid, settings, EventTuple, Native,
    PyRun, Rows, Signals,
};
use kreisel_core::models::heavy_top::sensitivity::{
    euler_derivative, simulate_damped_with_sensitivities, simulate_with_sensitivities,
    Sensitivities,
};
use kreisel_core::models::heavy_top::RigidState;
use kreisel_core::models::play_top::sensitivity as play;
use kreisel_core::models::play_top::PlayTop;
use kreisel_core::rotation::Quat;
use kreisel_core::simulate::Model;
use kreisel_core::simulate::Settings;
use numpy::{IntoPyArray, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Simulates a native heavy top (or a damped one on a fixed pivot, whose damping
/// coefficients "viscous" and "drag" have sensitivities too) from a flat state (q, omega)
/// with DOP853 and the sensitivities of `names`: parameters of the top (of a Lagrange top
/// when `lagrange`) and
/// fields of the initial state (of the Euler-angle state `euler` when given, else
/// "orientation[i]" and "omega[i]"). Returns what `simulate` returns and `sensitivities`:
/// per name a dict of `omega` (n, 3), `orientation` (n, 3, body-frame rotation vector),
/// `quaternion` (n, 4), `theta`, `phi`, `psi` (n,). `control` puts the sensitivities into
/// the step-size control too (off: the steps of a plain run).
#[pyfunction]
#[pyo3(signature = (model, state, t_end, method, rtol, atol, dt, t_eval, events, reduced, names, lagrange, euler=None, control=false))]
#[allow(clippy::too_many_arguments)]
pub fn simulate_sensitivities<'py>(
    py: Python<'py>,
    model: &Bound<'py, PyAny>,
    state: Vec<f64>,
    t_end: f64,
    method: String,
    rtol: f64,
    atol: f64,
    dt: Option<f64>,
    t_eval: Option<PyReadonlyArray1<'py, f64>>,
    events: Vec<EventTuple>,
    reduced: bool,
    names: Vec<String>,
    lagrange: bool,
    euler: Option<[f64; 6]>,
    control: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let model = native(model)?;
    let damped = match &model {
        Native::Heavy(_) => false,
        Native::Driven(_) => true,
        Native::Play(top) => {
            let te = match &t_eval {
                Some(a) => Some(a.as_slice()?.to_vec()),
                None => None,
            };
            let st = settings(t_end, method, rtol, atol, dt, te, &events, reduced)?;
            return play_sensitivities(py, *top, &state, &st, &names);
        }
    };
    let mut sens = Sensitivities::new(&names, lagrange, damped, euler).py(py)?;
    sens.control = control;
    let s0 = heavy_state(py, &state)?;
    let te = match &t_eval {
        Some(a) => Some(a.as_slice()?.to_vec()),
        None => None,
    };
    let st = settings(t_end, method, rtol, atol, dt, te, &events, reduced)?;
    let d = PyDict::new(py);
    let (t, states, values, rows) = match model {
        Native::Heavy(top) => {
            let out = released(py, |go| {
                simulate_with_sensitivities(&top, &s0, &st, &sens, go)
            })?;
            let states = out.rows.clone();
            let names = top.column_names();
            put_rigid(py, &d, states.iter().copied(), names, &out.info)?;
            (out.t, states, out.sens, Rows::Heavy(top, out.rows))
        }
        Native::Driven(top) => {
            let out = released(py, |go| {
                simulate_damped_with_sensitivities(&top, &s0, &st, &sens, go)
            })?;
            let states: Vec<RigidState> = out.rows.iter().map(|r| r.state()).collect();
            let names = top.column_names();
            put_rigid(py, &d, states.iter().copied(), names, &out.info)?;
            (out.t, states, out.sens, Rows::Driven(top, out.rows))
        }
        Native::Play(_) => unreachable!("refused above"),
    };
    let k = sens.params.len();
    let n = states.len();
    let all = PyDict::new(py);
    for (j, name) in sens.names.iter().enumerate() {
        let (mut xi, mut dw, mut dq) = (
            Vec::with_capacity(n),
            Vec::with_capacity(n),
            Vec::with_capacity(n),
        );
        let (mut th, mut ph, mut ps) = (
            Vec::with_capacity(n),
            Vec::with_capacity(n),
            Vec::with_capacity(n),
        );
        for (i, s) in states.iter().enumerate() {
            let v = values[i * k + j];
            let x = [v[0], v[1], v[2]];
            xi.push(x);
            dw.push([v[3], v[4], v[5]]);
            dq.push(s.q.half_times_pure(x));
            let e = euler_derivative(s.q, x);
            th.push(e[0]);
            ph.push(e[1]);
            ps.push(e[2]);
        }
        let one = PyDict::new(py);
        one.set_item("omega", flat(py, &dw)?)?;
        one.set_item("orientation", flat(py, &xi)?)?;
        one.set_item("quaternion", flat(py, &dq)?)?;
        one.set_item("theta", th.into_pyarray(py))?;
        one.set_item("phi", ph.into_pyarray(py))?;
        one.set_item("psi", ps.into_pyarray(py))?;
        all.set_item(name, one)?;
    }
    d.set_item("sensitivities", all)?;
    d.set_item("t", t.into_pyarray(py))?;
    d.set_item("run", PyRun { rows })?;
    Ok(d)
}

/// A play top's run with sensitivities: what `simulate` returns and `sensitivities`, per
/// name a dict of `orientation` (n, 3, body-frame rotation vector), `omega` (n, 3, body
/// rates), `com` (n, 3), `com_velocity` (n, 3), `dissipated` (n,), `quaternion` (n, 4) and
/// `theta`, `phi`, `psi`, `u` (n,).
fn play_sensitivities<'py>(
    py: Python<'py>,
    top: PlayTop,
    state: &[f64],
    st: &Settings,
    names: &[String],
) -> PyResult<Bound<'py, PyDict>> {
    let sens = play::PlaySensitivities::new(&top, names).py(py)?;
    let y0 = play_state(state)?;
    let out = released(py, |go| {
        play::simulate_with_sensitivities(&top, &y0, st, &sens, go)
    })?;
    let d = PyDict::new(py);
    let k = sens.params.len();
    let n = out.rows.len();
    let all = PyDict::new(py);
    for (j, name) in sens.names.iter().enumerate() {
        let mut cols: [Vec<[f64; 3]>; 4] = Default::default();
        let (mut dq, mut dis) = (Vec::with_capacity(n), Vec::with_capacity(n));
        let (mut th, mut ph, mut ps, mut du) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (i, r) in out.rows.iter().enumerate() {
            let v = out.sens[i * k + j];
            for (c, col) in cols.iter_mut().enumerate() {
                col.push([v[3 * c], v[3 * c + 1], v[3 * c + 2]]);
            }
            dis.push(v[12]);
            let q = Quat([r.y[0], r.y[1], r.y[2], r.y[3]]);
            let x = [v[0], v[1], v[2]];
            dq.push(q.half_times_pure(x));
            let e = euler_derivative(q, x);
            let (_, theta, _) = kreisel_core::rotation::euler_from_quaternion(q);
            th.push(e[0]);
            ph.push(e[1]);
            ps.push(e[2]);
            du.push(-theta.sin() * e[0]);
        }
        let one = PyDict::new(py);
        for (key, col) in ["orientation", "omega", "com", "com_velocity"]
            .iter()
            .zip(&cols)
        {
            one.set_item(*key, flat(py, col)?)?;
        }
        one.set_item("dissipated", dis.into_pyarray(py))?;
        one.set_item("quaternion", flat(py, &dq)?)?;
        one.set_item("theta", th.into_pyarray(py))?;
        one.set_item("phi", ph.into_pyarray(py))?;
        one.set_item("psi", ps.into_pyarray(py))?;
        one.set_item("u", du.into_pyarray(py))?;
        all.set_item(name, one)?;
    }
    put_play(py, &d, top, out.t, out.rows, &out.info)?;
    d.set_item("sensitivities", all)?;
    Ok(d)
}

/// Runs `f` with the interpreter released, stopping it at a signal (Ctrl-C), which is then
/// raised.
fn released<T: Send>(
    py: Python<'_>,
    f: impl FnOnce(&mut dyn FnMut(f64) -> bool) -> kreisel_core::Result<T> + Send,
) -> PyResult<T> {
    let (out, signals) = py.detach(|| {
        let mut signals = Signals::new();
        (f(&mut |_| signals.keep_going()), signals)
    });
    if let Some(e) = signals.error {
        return Err(e);
    }
    out.py(py)
}
