//! Bindings of the play top's stationary-motion theory: conversion only. Every function
//! takes the body's parameters (m, A, C, s, rho, g) as plain floats.

use crate::errors::IntoPyResult;
use kreisel_core::models::play_top::{Friction, PlayTop, DIM};
use kreisel_core::stability::play_top::{self as st, PlayStability, StationaryMotion};
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;

type Arr<'py> = Bound<'py, PyArray1<f64>>;
/// (kind, u, stable, Omega, omega3, energy)
type Motion = (&'static str, f64, bool, f64, f64, f64);

fn theory(
    py: Python<'_>,
    m: f64,
    a: f64,
    c: f64,
    s: f64,
    rho: f64,
    g: f64,
) -> PyResult<PlayStability> {
    PlayStability::new(m, a, c, s, rho, g).py(py)
}

fn motion(x: &StationaryMotion) -> Motion {
    (x.kind.name(), x.u, x.stable, x.omega, x.omega3, x.energy)
}

/// J_R(u) on the real line at every u (NaN where D(u) <= 0).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn play_j_r<'py>(
    py: Python<'py>,
    m: f64,
    a: f64,
    c: f64,
    s: f64,
    rho: f64,
    g: f64,
    u: PyReadonlyArray1<'py, f64>,
) -> PyResult<Arr<'py>> {
    let t = theory(py, m, a, c, s, rho, g)?;
    let v: Vec<f64> = u.as_slice()?.iter().map(|&x| t.j_r(x)).collect();
    Ok(v.into_pyarray(py))
}

/// V(u) at fixed J at every u.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn play_stationary_energy<'py>(
    py: Python<'py>,
    m: f64,
    a: f64,
    c: f64,
    s: f64,
    rho: f64,
    g: f64,
    j: f64,
    u: PyReadonlyArray1<'py, f64>,
) -> PyResult<Arr<'py>> {
    let t = theory(py, m, a, c, s, rho, g)?;
    let v: Vec<f64> = u.as_slice()?.iter().map(|&x| t.energy(j, x)).collect();
    Ok(v.into_pyarray(py))
}

/// (Omega, omega3, psi_dot, J) of the regular precession at u.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn play_regular_precession(
    py: Python<'_>,
    m: f64,
    a: f64,
    c: f64,
    s: f64,
    rho: f64,
    g: f64,
    u: f64,
) -> PyResult<(f64, f64, f64, f64)> {
    let r = theory(py, m, a, c, s, rho, g)?
        .regular_precession(u)
        .py(py)?;
    Ok((r.omega, r.omega3, r.psi_dot, r.j))
}

/// Every stationary motion at J: (kind, u, stable, Omega, omega3, energy), ascending u.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn play_stationary_motions(
    py: Python<'_>,
    m: f64,
    a: f64,
    c: f64,
    s: f64,
    rho: f64,
    g: f64,
    j: f64,
) -> PyResult<Vec<Motion>> {
    let v = theory(py, m, a, c, s, rho, g)?
        .stationary_motions(j)
        .py(py)?;
    Ok(v.iter().map(motion).collect())
}

/// u_m of (alpha, gamma), None for type I.
#[pyfunction]
pub fn play_u_m(alpha: f64, gamma: f64) -> Option<f64> {
    st::u_min(alpha, gamma)
}

/// (type, zone, fig3) of (alpha, gamma).
#[pyfunction]
pub fn play_classify(
    py: Python<'_>,
    alpha: f64,
    gamma: f64,
) -> PyResult<(&'static str, u8, String)> {
    let c = st::classify(alpha, gamma).py(py)?;
    Ok((c.top_type.name(), c.zone, c.fig3.to_string()))
}

/// Zones of many (alpha, gamma) pairs (0 where alpha or gamma is not > 0).
#[pyfunction]
pub fn play_zones<'py>(
    py: Python<'py>,
    alpha: PyReadonlyArray1<'py, f64>,
    gamma: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, PyArray1<u8>>> {
    let (al, ga) = (alpha.as_slice()?, gamma.as_slice()?);
    if al.len() != ga.len() {
        return Err(pyo3::exceptions::PyValueError::new_err(
            "alpha and gamma must have the same length",
        ));
    }
    let z: Vec<u8> = al
        .iter()
        .zip(ga)
        .map(|(&x, &y)| st::classify(x, y).map_or(0, |c| c.zone))
        .collect();
    Ok(z.into_pyarray(py))
}

/// The zone boundaries gamma(alpha) at every alpha: u_m = 1 (lower, upper), u_m = -1,
/// J_R(1) = J_R(-1) (NaN where a curve does not exist).
#[pyfunction]
pub fn play_zone_boundaries<'py>(
    py: Python<'py>,
    alpha: PyReadonlyArray1<'py, f64>,
) -> PyResult<(Arr<'py>, Arr<'py>, Arr<'py>, Arr<'py>)> {
    let al = alpha.as_slice()?;
    let mut cols: [Vec<f64>; 4] = Default::default();
    for &x in al {
        for (col, v) in cols.iter_mut().zip(st::zone_boundaries(x)) {
            col.push(v);
        }
    }
    let [a, b, c, d] = cols;
    Ok((
        a.into_pyarray(py),
        b.into_pyarray(py),
        c.into_pyarray(py),
        d.into_pyarray(py),
    ))
}

/// (stable, reachable, ending) for a state's J, energy and u.
#[pyfunction]
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
pub fn play_predict(
    py: Python<'_>,
    m: f64,
    a: f64,
    c: f64,
    s: f64,
    rho: f64,
    g: f64,
    j: f64,
    energy: f64,
    u: f64,
) -> PyResult<(Vec<Motion>, Vec<Motion>, Option<Motion>)> {
    let p = theory(py, m, a, c, s, rho, g)?
        .predict(j, energy, u)
        .py(py)?;
    Ok((
        p.stable.iter().map(motion).collect(),
        p.reachable.iter().map(motion).collect(),
        p.ending.as_ref().map(motion),
    ))
}

/// (u_min, u_max, period, lagrange_period) of the frictionless play top from a packed
/// contact state (q, omega, com, com_velocity).
#[pyfunction]
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
pub fn play_frictionless_nutation(
    py: Python<'_>,
    m: f64,
    a: f64,
    c: f64,
    s: f64,
    rho: f64,
    g: f64,
    state: ([f64; 4], [f64; 3], [f64; 3], [f64; 3]),
) -> PyResult<(f64, f64, f64, f64)> {
    let top = PlayTop::new(
        m,
        a,
        c,
        s,
        rho,
        g,
        Friction::Frictionless,
        0.0,
        0.0,
        0.0,
        0.0,
    )
    .py(py)?;
    let mut y = [0.0; DIM];
    y[..4].copy_from_slice(&state.0);
    y[4..7].copy_from_slice(&state.1);
    y[7..10].copy_from_slice(&state.2);
    y[10..13].copy_from_slice(&state.3);
    let r = st::frictionless_nutation(&top, &y).py(py)?;
    Ok((r.u_range.0, r.u_range.1, r.period, r.lagrange_period))
}
