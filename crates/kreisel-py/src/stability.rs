//! Bindings of the play top's stationary-motion theory: conversion only. The theory of a
//! native play top is built once (`PlayStability(top)`) and asked for everything.

use crate::errors::IntoPyResult;
use crate::play::{pack, Packed, PyPlayTop};
use kreisel_core::models::play_top::{Friction, PlayTop};
use kreisel_core::stability::play_top::{self as st, PlayStability, StationaryMotion};
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;

type Arr<'py> = Bound<'py, PyArray1<f64>>;
/// (kind, u, stable, Omega, omega3, energy)
type Motion = (&'static str, f64, bool, f64, f64, f64);

fn motion(x: &StationaryMotion) -> Motion {
    (x.kind.name(), x.u, x.stable, x.omega, x.omega3, x.energy)
}

/// The stationary-motion theory of one play top.
#[pyclass(name = "PlayStability", module = "kreisel._core", frozen)]
pub struct PyPlayStability {
    theory: PlayStability,
}

#[pymethods]
impl PyPlayStability {
    #[new]
    fn new(py: Python<'_>, top: PyRef<'_, PyPlayTop>) -> PyResult<Self> {
        let t = top.inner;
        Ok(PyPlayStability {
            theory: PlayStability::new(&t).py(py)?,
        })
    }

    /// J_R(u) at every u in [-1, 1] (NaN where D(u) <= 0; an error for u outside).
    fn j_r<'py>(&self, py: Python<'py>, u: PyReadonlyArray1<'py, f64>) -> PyResult<Arr<'py>> {
        let v: kreisel_core::Result<Vec<f64>> = u
            .as_slice()?
            .iter()
            .map(|&x| self.theory.j_r_at(x))
            .collect();
        Ok(v.py(py)?.into_pyarray(py))
    }

    /// V(u) at fixed J at every u.
    fn stationary_energy<'py>(
        &self,
        py: Python<'py>,
        j: f64,
        u: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Arr<'py>> {
        let v: Vec<f64> = u
            .as_slice()?
            .iter()
            .map(|&x| self.theory.energy(j, x))
            .collect();
        Ok(v.into_pyarray(py))
    }

    /// (Omega, omega3, psi_dot, J) of the regular precession at u.
    fn regular_precession(&self, py: Python<'_>, u: f64) -> PyResult<(f64, f64, f64, f64)> {
        let r = self.theory.regular_precession(u).py(py)?;
        Ok((r.omega, r.omega3, r.psi_dot, r.j))
    }

    /// Every stationary motion at J: (kind, u, stable, Omega, omega3, energy), ascending u.
    fn stationary_motions(&self, py: Python<'_>, j: f64) -> PyResult<Vec<Motion>> {
        let v = self.theory.stationary_motions(j).py(py)?;
        Ok(v.iter().map(motion).collect())
    }

    /// (stable, reachable, ending) for a state's J, energy and u.
    #[allow(clippy::type_complexity)]
    fn predict(
        &self,
        py: Python<'_>,
        j: f64,
        energy: f64,
        u: f64,
    ) -> PyResult<(Vec<Motion>, Vec<Motion>, Option<Motion>)> {
        let p = self.theory.predict(j, energy, u).py(py)?;
        Ok((
            p.stable.iter().map(motion).collect(),
            p.reachable.iter().map(motion).collect(),
            p.ending.as_ref().map(motion),
        ))
    }

    /// (u_min, u_max, period, lagrange_period) of the same body without friction, from a
    /// packed contact state (q, omega, com, com_velocity).
    fn frictionless_nutation(
        &self,
        py: Python<'_>,
        state: Packed,
    ) -> PyResult<(f64, f64, f64, f64)> {
        let top = PlayTop {
            friction: Friction::Frictionless,
            ..*self.theory.top()
        };
        let r = st::frictionless_nutation(&top, &pack(&state)).py(py)?;
        Ok((r.u_range.0, r.u_range.1, r.period, r.lagrange_period))
    }
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
