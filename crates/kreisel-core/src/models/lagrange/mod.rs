//! The Lagrange top: a heavy symmetric top on a fixed pivot, centre of mass on the figure axis.
//!
//! Parameters follow theory: Lagrange top: `I1` is the transverse moment
//! about the pivot, `I3` the axial moment, `l` the signed pivot-to-centre-of-mass distance
//! along the figure axis. Euler angles are z-x-z with theta from the upward vertical, so
//! the potential energy is `m g l cos(theta)`.

mod columns;
mod exact;

pub use columns::LagrangeColumns;
pub use exact::{LagrangeExact, MotionKind};

use crate::error::{
    finite, non_negative, positive, rate, repr, signed, symmetric_moments, KreiselError, Result,
    RATE_MAX,
};

/// Euler angles (z-x-z) and their rates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EulerState {
    /// Precession angle (rad).
    pub phi: f64,
    /// Nutation angle from the upward vertical, in [0, pi] (rad).
    pub theta: f64,
    /// Spin angle (rad).
    pub psi: f64,
    /// d(phi)/dt (rad/s).
    pub phi_dot: f64,
    /// d(theta)/dt (rad/s).
    pub theta_dot: f64,
    /// d(psi)/dt (rad/s).
    pub psi_dot: f64,
}

impl EulerState {
    /// A validated state: angles finite, theta in [0, pi], rates of magnitude at most
    /// [`RATE_MAX`](crate::error::RATE_MAX).
    pub fn new(
        theta: f64,
        phi: f64,
        psi: f64,
        theta_dot: f64,
        phi_dot: f64,
        psi_dot: f64,
    ) -> Result<Self> {
        finite("phi", phi)?;
        finite("psi", psi)?;
        for (n, v) in [
            ("theta_dot", theta_dot),
            ("phi_dot", phi_dot),
            ("psi_dot", psi_dot),
        ] {
            rate(n, v)?;
        }
        if !(theta.is_finite() && (0.0..=std::f64::consts::PI).contains(&theta)) {
            return Err(KreiselError::invalid(
                "theta",
                theta,
                "theta is the angle from the upward vertical and must lie in [0, pi]",
            ));
        }
        Ok(EulerState {
            phi,
            theta,
            psi,
            phi_dot,
            theta_dot,
            psi_dot,
        })
    }
}

/// The three integrals of the Lagrange top.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Invariants {
    /// Total energy E = T + V (J).
    pub energy: f64,
    /// Vertical component of the angular momentum about the pivot, p_phi (kg m^2/s).
    pub mz: f64,
    /// Axial component of the angular momentum, p_psi = I3 omega3 (kg m^2/s).
    pub m3: f64,
}

/// A heavy symmetric top on a fixed pivot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LagrangeTop {
    i1: f64,
    i3: f64,
    m: f64,
    l: f64,
    g: f64,
}

impl LagrangeTop {
    /// Validates and builds a top. `I1` is about the pivot; `l` may be zero or negative.
    ///
    /// Rejects what no rigid body can be: the principal moments about the pivot obey the
    /// triangle inequality `I3 <= 2 I1`, and by the parallel-axis theorem `I1 >= m l^2`.
    /// Every parameter lies in [`PARAMETER_RANGE`](crate::error::PARAMETER_RANGE) (`l` and
    /// `g` may also be 0).
    pub fn new(i1: f64, i3: f64, m: f64, l: f64, g: f64) -> Result<Self> {
        symmetric_moments(i1, i3)?;
        positive("m", m)?;
        signed("l", l)?;
        non_negative("g", g)?;
        if i1 < m * l * l * (1.0 - 1e-12) {
            return Err(KreiselError::invalid(
                "I1",
                i1,
                format!(
                    "I1 is about the pivot and must be >= m*l**2 = {} (parallel-axis theorem)",
                    m * l * l
                ),
            ));
        }
        Ok(LagrangeTop { i1, i3, m, l, g })
    }

    /// Transverse moment of inertia about the pivot (kg m^2).
    pub fn i1(&self) -> f64 {
        self.i1
    }
    /// Axial moment of inertia (kg m^2).
    pub fn i3(&self) -> f64 {
        self.i3
    }
    /// Mass (kg).
    pub fn m(&self) -> f64 {
        self.m
    }
    /// Signed pivot-to-centre-of-mass distance (m).
    pub fn l(&self) -> f64 {
        self.l
    }
    /// Gravitational acceleration (m/s^2).
    pub fn g(&self) -> f64 {
        self.g
    }
    /// The torque scale m g l (J).
    pub fn mgl(&self) -> f64 {
        self.m * self.g * self.l
    }

    /// Energy, Mz and M3 of a state.
    pub fn invariants(&self, s: &EulerState) -> Invariants {
        let (st, ct) = s.theta.sin_cos();
        let omega3 = s.psi_dot + s.phi_dot * ct;
        let m3 = self.i3 * omega3;
        let mz = self.i1 * s.phi_dot * st * st + m3 * ct;
        let t = 0.5 * self.i1 * (s.theta_dot * s.theta_dot + (s.phi_dot * st).powi(2))
            + 0.5 * self.i3 * omega3 * omega3;
        Invariants {
            energy: t + self.mgl() * ct,
            mz,
            m3,
        }
    }

    /// Effective potential for the nutation, such that `E = I1 thetadot^2 / 2 + Veff(theta)`:
    ///
    /// `Veff = m g l cos(theta) + (Mz - M3 cos(theta))^2 / (2 I1 sin^2(theta)) + M3^2 / (2 I3)`.
    ///
    /// (A "full" form seen in some notes subtracts `M3^2/(2 I1)` as well; that term does not
    /// belong: the kinetic energy of the spin is `M3^2/(2 I3)`; theory: the Lagrange top.) Infinite at theta = 0, pi unless
    /// Mz = +-M3 there, where the limit is taken; next to them it is +inf where it exceeds
    /// the range of f64. Never NaN: `theta` must be finite, and `M3` and `Mz` those of
    /// rates within [`RATE_MAX`](crate::error::RATE_MAX) (`|M3| <= I3 RATE_MAX`,
    /// `|Mz| <= (I1 + I3) RATE_MAX`).
    pub fn effective_potential(&self, theta: f64, mz: f64, m3: f64) -> Result<f64> {
        self.check_momenta(mz, m3)?;
        finite("theta", theta)?;
        let (st, ct) = theta.sin_cos();
        let num = mz - m3 * ct;
        let centrifugal = if num == 0.0 {
            0.0
        } else if st == 0.0 {
            f64::INFINITY
        } else {
            // In this order no intermediate overflows while the value itself is finite.
            (num / (2.0 * self.i1 * st)) * (num / st)
        };
        Ok(self.mgl() * ct + centrifugal + (m3 / (2.0 * self.i3)) * m3)
    }

    /// Checks the momenta given to [`LagrangeTop::effective_potential`].
    fn check_momenta(&self, mz: f64, m3: f64) -> Result<()> {
        let m3_max = self.i3 * RATE_MAX;
        if !(m3.is_finite() && m3.abs() <= m3_max) {
            return Err(KreiselError::invalid(
                "M3",
                m3,
                format!(
                    "it must be finite with |M3| <= I3 * {} rad/s = {}",
                    repr(RATE_MAX),
                    repr(m3_max)
                ),
            ));
        }
        let mz_max = (self.i1 + self.i3) * RATE_MAX;
        if !(mz.is_finite() && mz.abs() <= mz_max) {
            return Err(KreiselError::invalid(
                "Mz",
                mz,
                format!(
                    "it must be finite with |Mz| <= (I1 + I3) * {} rad/s = {}",
                    repr(RATE_MAX),
                    repr(mz_max)
                ),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn energy_equals_radial_kinetic_plus_effective_potential() {
        let top = LagrangeTop::new(1.3, 0.7, 2.0, 0.4, 9.81).unwrap();
        let s = EulerState::new(0.8, 0.1, 0.2, -0.4, 1.1, 17.0).unwrap();
        let inv = top.invariants(&s);
        let v = top.effective_potential(s.theta, inv.mz, inv.m3).unwrap();
        let e = 0.5 * top.i1() * s.theta_dot * s.theta_dot + v;
        assert!((e - inv.energy).abs() < 1e-13 * inv.energy.abs());
    }

    #[test]
    fn validation_names_the_parameter() {
        let e = LagrangeTop::new(1.0, 2.5, 1.0, 0.1, 9.81).unwrap_err();
        assert!(e.to_string().starts_with("I3 = 2.5"));
        let e = LagrangeTop::new(1.0, 0.5, 1.0, 2.0, 9.81).unwrap_err();
        assert!(e.to_string().starts_with("I1 = 1"));
        assert!(LagrangeTop::new(f64::NAN, 0.5, 1.0, 0.1, 9.81).is_err());
        assert!(LagrangeTop::new(1.0, 0.5, 1.0, 0.1, -1.0).is_err());
        assert!(EulerState::new(3.2, 0.0, 0.0, 0.0, 0.0, 0.0).is_err());
    }
}
