//! Bindings of the parallel batches: conversion only. The GIL is released while the runs go.

use crate::errors::IntoPyResult;
use crate::heavy::{lyapunov_settings, PyHeavyTop};
use crate::play::{pack, settings, Packed, PyPlayTop};
use kreisel_core::batch;
use kreisel_core::models::heavy_top::{HeavyTop, RigidState};
use kreisel_core::simulate::Settings;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// A summary column: its name and how to read it off one run's summary.
type Field<'a, S> = (&'a str, &'a dyn Fn(&S) -> f64);

/// Puts one float column per named field, NaN where a run failed, and the error messages.
fn columns<'py, S>(
    py: Python<'py>,
    res: &[kreisel_core::Result<S>],
    fields: &[Field<'_, S>],
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (name, f) in fields {
        let col: Vec<f64> = res.iter().map(|r| r.as_ref().map_or(f64::NAN, f)).collect();
        d.set_item(*name, col.into_pyarray(py))?;
    }
    let errors: Vec<Option<String>> = res
        .iter()
        .map(|r| r.as_ref().err().map(|e| e.to_string()))
        .collect();
    d.set_item("errors", errors)?;
    Ok(d)
}

/// Play tops in parallel: lists of native tops and packed states of equal length.
#[pyfunction]
#[pyo3(signature = (tops, states, t_end, rtol, atol, inversion_level, threads=None))]
#[allow(clippy::too_many_arguments)]
pub fn play_many<'py>(
    py: Python<'py>,
    tops: Vec<PyRef<'py, PyPlayTop>>,
    states: Vec<Packed>,
    t_end: f64,
    rtol: f64,
    atol: f64,
    inversion_level: f64,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let runs: Vec<_> = tops
        .iter()
        .zip(&states)
        .map(|(t, s)| (t.inner, pack(s)))
        .collect();
    let st = settings(t_end, rtol, atol, None, Some(inversion_level), false, false);
    let res = py
        .detach(move || batch::play_many(&runs, &st, threads))
        .py(py)?;
    let d = columns(
        py,
        &res,
        &[
            ("final_u", &|s| s.final_u),
            ("inversion_time", &|s| s.inversion_time),
            ("jellett_drift", &|s| s.jellett_drift),
            ("energy_drift", &|s| s.energy_drift),
            ("steps", &|s| s.steps as f64),
        ],
    )?;
    let modes: Vec<&str> = res
        .iter()
        .map(|r| r.as_ref().map_or("error", |s| s.final_mode.name()))
        .collect();
    d.set_item("final_mode", modes)?;
    Ok(d)
}

/// Heavy tops in parallel: lists of native tops and (q, omega) states of equal length.
#[pyfunction]
#[pyo3(signature = (tops, states, t_end, method, rtol, atol, dt=None, threads=None))]
#[allow(clippy::too_many_arguments)]
pub fn heavy_many<'py>(
    py: Python<'py>,
    tops: Vec<PyRef<'py, PyHeavyTop>>,
    states: Vec<([f64; 4], [f64; 3])>,
    t_end: f64,
    method: String,
    rtol: f64,
    atol: f64,
    dt: Option<f64>,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let runs = heavy_runs(py, &tops, &states)?;
    let st = Settings {
        method,
        t_end,
        rtol,
        atol,
        dt,
        t_eval: None,
    };
    let res = py
        .detach(move || batch::heavy_many(&runs, &st, threads))
        .py(py)?;
    columns(
        py,
        &res,
        &[
            ("final_theta", &|s| s.final_theta),
            ("theta_min", &|s| s.theta_min),
            ("theta_max", &|s| s.theta_max),
            ("energy_drift", &|s| s.energy_drift),
            ("Mz_drift", &|s| s.mz_drift),
            ("M3_drift", &|s| s.m3_drift),
            ("kovalevskaya_drift", &|s| s.kovalevskaya_drift),
            ("steps", &|s| s.steps as f64),
        ],
    )
}

/// Largest Lyapunov exponents of heavy tops in parallel (NaN and a message where one fails).
#[pyfunction]
#[pyo3(signature = (tops, states, t_end, tau, d0, direction, rtol, atol, threads=None))]
#[allow(clippy::too_many_arguments)]
pub fn lyapunov_many<'py>(
    py: Python<'py>,
    tops: Vec<PyRef<'py, PyHeavyTop>>,
    states: Vec<([f64; 4], [f64; 3])>,
    t_end: f64,
    tau: f64,
    d0: f64,
    direction: [f64; 6],
    rtol: f64,
    atol: f64,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let runs = heavy_runs(py, &tops, &states)?;
    let st = lyapunov_settings(t_end, tau, d0, direction, rtol, atol);
    let res = py
        .detach(move || batch::lyapunov_many(&runs, &st, threads))
        .py(py)?;
    columns(py, &res, &[("lyapunov", &|x| *x)])
}

fn heavy_runs(
    py: Python<'_>,
    tops: &[PyRef<'_, PyHeavyTop>],
    states: &[([f64; 4], [f64; 3])],
) -> PyResult<Vec<(HeavyTop, RigidState)>> {
    tops.iter()
        .zip(states)
        .map(|(t, (q, w))| Ok((t.inner, RigidState::new(*q, *w)?)))
        .collect::<kreisel_core::Result<Vec<_>>>()
        .py(py)
}
