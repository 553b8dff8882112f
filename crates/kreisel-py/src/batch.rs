//! Bindings of the parallel batches: conversion only. The GIL is released while the runs go.

use crate::errors::IntoPyResult;
use crate::heavy::lyapunov_settings;
use crate::simulate::{driven, native, Native};
use kreisel_core::models::heavy_top::{HeavyTop, RigidState};
use kreisel_core::simulate::batch;
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

/// Largest Lyapunov exponents of heavy tops in parallel (NaN and a message where one fails).
#[pyfunction]
#[pyo3(signature = (tops, states, t_end, tau, d0, direction, rtol, atol, threads=None))]
#[allow(clippy::too_many_arguments)]
pub fn lyapunov_many<'py>(
    py: Python<'py>,
    tops: Vec<Bound<'py, PyAny>>,
    states: Vec<([f64; 4], [f64; 3])>,
    t_end: f64,
    tau: f64,
    d0: f64,
    direction: [f64; 6],
    rtol: f64,
    atol: f64,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let natives: Vec<Native> = tops.iter().map(native).collect::<PyResult<_>>()?;
    if natives.iter().any(|m| matches!(m, Native::Play(_))) {
        return Err(pyo3::exceptions::PyTypeError::new_err(
            "the Lyapunov exponent is estimated for tops on a pivot, not play tops",
        ));
    }
    let starts: Vec<RigidState> = states
        .iter()
        .map(|(q, w)| RigidState::new(*q, *w))
        .collect::<kreisel_core::Result<_>>()
        .py(py)?;
    let st = lyapunov_settings(t_end, tau, d0, direction, rtol, atol);
    let res = if natives.iter().all(|m| matches!(m, Native::Heavy(_))) {
        let runs: Vec<(HeavyTop, RigidState)> = natives
            .into_iter()
            .zip(starts)
            .map(|(m, s)| match m {
                Native::Heavy(t) => (t, s),
                _ => unreachable!(),
            })
            .collect();
        py.detach(move || batch::lyapunov_many(&runs, &st, threads))
            .py(py)?
    } else {
        let runs: Vec<_> = natives.into_iter().map(driven).zip(starts).collect();
        py.detach(move || batch::lyapunov_many(&runs, &st, threads))
            .py(py)?
    };
    columns(py, &res, &[("lyapunov", &|x| *x)])
}
