//! Bindings of the play top: conversion only.

use crate::errors::IntoPyResult;
use kreisel_core::models::lagrange::EulerState;
use kreisel_core::models::play_top::{Friction, PlayTop, Shape, DIM};
use kreisel_core::rotation::{omega_body_from_euler, quaternion_from_euler, Quat};
use pyo3::prelude::*;

/// A friction law as a typed value, its coefficient checked by the core.
#[pyclass(name = "Friction", module = "kreisel._core", frozen)]
pub struct PyFriction {
    pub inner: Friction,
}

#[pymethods]
impl PyFriction {
    /// Coulomb friction with coefficient mu (>= 0).
    #[staticmethod]
    fn coulomb(py: Python<'_>, mu: f64) -> PyResult<Self> {
        let inner = Friction::Coulomb { mu }.checked().py(py)?;
        Ok(PyFriction { inner })
    }
    /// Viscous friction, F_t = -mu N v_T (mu >= 0, s/m).
    #[staticmethod]
    fn viscous(py: Python<'_>, mu: f64) -> PyResult<Self> {
        let inner = Friction::Viscous { mu }.checked().py(py)?;
        Ok(PyFriction { inner })
    }
    /// Coulomb-Contensou friction over a patch of radius `radius` (m, >= 0; 0 is Coulomb).
    #[staticmethod]
    fn coulomb_contensou(py: Python<'_>, mu: f64, radius: f64) -> PyResult<Self> {
        let inner = Friction::coulomb_contensou(mu, radius).py(py)?;
        Ok(PyFriction { inner })
    }
    /// No tangential force.
    #[staticmethod]
    fn none() -> Self {
        PyFriction {
            inner: Friction::Frictionless,
        }
    }
    /// The law's name ("coulomb", "viscous", "none").
    #[getter]
    fn law(&self) -> &'static str {
        self.inner.name()
    }
    /// Its coefficient (0 without friction).
    #[getter]
    fn mu(&self) -> f64 {
        self.inner.mu()
    }
}

/// The native play top (parameters only).
#[pyclass(name = "PlayTop", module = "kreisel._core", frozen)]
pub struct PyPlayTop {
    pub inner: PlayTop,
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
        friction: PyRef<'_, PyFriction>,
        restitution: f64,
        rolling: f64,
        drilling: f64,
        air: f64,
    ) -> PyResult<Self> {
        let fr = friction.inner;
        Ok(PyPlayTop {
            inner: PlayTop::new(m, a, c, s, rho, g, fr, restitution, rolling, drilling, air)
                .py(py)?,
        })
    }

    /// This top with the stick threshold `stick` (a share of the speed scale, in
    /// `(0, 1e-3]`; the core's `PlayTop::with_stick_threshold`).
    fn with_stick_threshold(&self, py: Python<'_>, stick: f64) -> PyResult<Self> {
        Ok(PyPlayTop {
            inner: self.inner.with_stick_threshold(stick).py(py)?,
        })
    }

    /// The stick threshold (a share of the speed scale).
    #[getter]
    fn stick_threshold(&self) -> f64 {
        self.inner.stick
    }

    /// A play top of contact parts, each `(kind, a, b, z)`: `("sphere", radius, 0, z)`,
    /// `("spheroid", equatorial, axial, z)` or `("torus", major, minor, z)`.
    #[staticmethod]
    #[allow(clippy::too_many_arguments)]
    fn with_parts(
        py: Python<'_>,
        m: f64,
        a: f64,
        c: f64,
        parts: Vec<(String, f64, f64, f64)>,
        g: f64,
        friction: PyRef<'_, PyFriction>,
        restitution: f64,
        rolling: f64,
        drilling: f64,
        air: f64,
    ) -> PyResult<Self> {
        let shapes = parts
            .iter()
            .enumerate()
            .map(|(i, (kind, x, y, z))| match kind.as_str() {
                "sphere" => Ok(Shape::Sphere { radius: *x, z: *z }),
                "spheroid" => Ok(Shape::Spheroid {
                    equatorial: *x,
                    axial: *y,
                    z: *z,
                }),
                "torus" => Ok(Shape::Torus {
                    major: *x,
                    minor: *y,
                    z: *z,
                }),
                other => Err(pyo3::exceptions::PyValueError::new_err(format!(
                    "shape[{i}] is a {other:?}: the parts known are \"sphere\", \"spheroid\" \
                     and \"torus\""
                ))),
            })
            .collect::<PyResult<Vec<_>>>()?;
        let fr = friction.inner;
        Ok(PyPlayTop {
            inner: PlayTop::with_parts(
                m,
                a,
                c,
                &shapes,
                g,
                fr,
                restitution,
                rolling,
                drilling,
                air,
            )
            .py(py)?,
        })
    }

    /// Sliding's own coefficient at a packed contact state (1/kg): the contact height's
    /// acceleration per unit normal force with the Coulomb force against the slip (or along
    /// `-dir` at zero slip); zero or negative is the Painleve case.
    fn slip_coefficient(&self, s: Packed, dir: [f64; 2]) -> f64 {
        self.inner
            .slip_coefficient(&pack(&s), [dir[0], dir[1], 0.0])
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

    /// (q, omega, com, com_velocity) of a state given by Euler angles and rates, checked as
    /// an `EulerState` is (one call where three were).
    #[pyo3(signature = (euler, vx, vy, height=None))]
    fn state_from_euler(
        &self,
        py: Python<'_>,
        euler: [f64; 6],
        vx: f64,
        vy: f64,
        height: Option<f64>,
    ) -> PyResult<Packed> {
        let [theta, phi, psi, theta_dot, phi_dot, psi_dot] = euler;
        EulerState::new(theta, phi, psi, theta_dot, phi_dot, psi_dot).py(py)?;
        let q = quaternion_from_euler(phi, theta, psi);
        let w = omega_body_from_euler(theta, psi, theta_dot, phi_dot, psi_dot);
        let y = self.inner.state(q, w, vx, vy, height).py(py)?;
        Ok(unpack(&y))
    }

    /// Jellett's integral about the first part's lowest point and the energy of a packed
    /// state.
    fn invariants(&self, s: Packed) -> (f64, f64) {
        let y = pack(&s);
        let (a, b, c) = self.inner.energy_parts(&y);
        (self.inner.jellett(&y), a + b + c)
    }
}
