//! Stoermer-Verlet on the canonical Euler-angle Hamiltonian of the symmetric heavy top,
//! the classical route (Goldstein, *Classical Mechanics*, Sec. 5.7; theory: the Lagrange top).
//!
//! With the conserved momenta p_phi = Mz and p_psi = M3,
//! `H = p_theta^2 / (2 I1) + U(theta)` with
//! `U = (p_phi - p_psi cos theta)^2 / (2 I1 sin^2 theta) + p_psi^2 / (2 I3) + m g l cos theta`.
//! The flow of U kicks p_theta and advances phi and
//! psi at the rates dU/dp_phi, dU/dp_psi (both functions of theta alone, so exact); the
//! flow of the kinetic term drifts theta. Kick-drift-kick is symmetric and symplectic,
//! order 2. Euler angles are singular at theta = 0 and pi: the scheme reports an error
//! when the axis comes within 1e-6 rad of the vertical (use "splitting" there).

use crate::error::{KreiselError, Result};
use crate::integrate::fixed::FixedScheme;
use crate::models::heavy_top::{HeavyTop, RigidState, TopKind};
use crate::rotation::{euler_from_quaternion, omega_body_from_euler, quaternion_from_euler};

/// (theta, p_theta, phi, psi, t): t is carried to report where a singularity was met.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Canonical {
    /// Nutation angle.
    pub theta: f64,
    /// Its momentum I1 thetadot.
    pub p_theta: f64,
    /// Precession angle.
    pub phi: f64,
    /// Spin angle.
    pub psi: f64,
    /// Time reached.
    pub t: f64,
}

/// Stoermer-Verlet for a symmetric heavy top (Lagrange or symmetric Euler top).
#[derive(Debug, Clone, Copy)]
pub struct Verlet {
    i1: f64,
    i3: f64,
    mgl: f64,
    p_phi: f64,
    p_psi: f64,
}

const SINGULAR: f64 = 1e-6;

fn singular(t: f64) -> KreiselError {
    KreiselError::Numerical(format!(
        "method \"verlet\" works in Euler angles, which are singular at the vertical: the axis \
         came within {SINGULAR} rad of it at t = {t}; use \"splitting\" or \"dop853\""
    ))
}

impl Verlet {
    /// Prepares the scheme for `top` from the initial state (which fixes the momenta).
    pub fn new(top: &HeavyTop, s: &RigidState) -> Result<(Self, Canonical)> {
        let sym = top.symmetric() && top.com()[0] == 0.0 && top.com()[1] == 0.0;
        if !sym || !matches!(top.kind(), TopKind::Lagrange | TopKind::Euler) {
            return Err(KreiselError::InvalidParameter {
                name: "method".into(),
                value: "\"verlet\"".into(),
                allowed: "it needs a symmetric top (I1 == I2, centre of mass on the 3-axis)".into(),
            });
        }
        let i = top.inertia();
        let v = Verlet {
            i1: i[0],
            i3: i[2],
            mgl: top.mgc()[2],
            p_phi: top.mz(s),
            p_psi: i[2] * s.omega[2],
        };
        let (phi, theta, psi) = euler_from_quaternion(s.q);
        if theta.sin() < SINGULAR {
            return Err(singular(0.0));
        }
        let (sp, cp) = psi.sin_cos();
        let theta_dot = s.omega[0] * cp - s.omega[1] * sp;
        Ok((
            v,
            Canonical {
                theta,
                p_theta: v.i1 * theta_dot,
                phi,
                psi,
                t: 0.0,
            },
        ))
    }

    /// Euler rates (phidot, psidot) at theta.
    #[inline(always)]
    fn rates(&self, theta: f64) -> (f64, f64) {
        let (s, c) = theta.sin_cos();
        let phid = (self.p_phi - self.p_psi * c) / (self.i1 * s * s);
        (phid, self.p_psi / self.i3 - phid * c)
    }

    /// -dU/dtheta.
    #[inline(always)]
    fn force(&self, theta: f64) -> f64 {
        let (s, c) = theta.sin_cos();
        let k = self.p_phi - self.p_psi * c;
        self.mgl * s - k * self.p_psi / (self.i1 * s) + k * k * c / (self.i1 * s * s * s)
    }

    #[inline(always)]
    fn half_kick(&self, y: &mut Canonical, h: f64) -> Result<()> {
        if y.theta.sin() < SINGULAR {
            return Err(singular(y.t));
        }
        let (phid, psid) = self.rates(y.theta);
        y.p_theta += 0.5 * h * self.force(y.theta);
        y.phi += 0.5 * h * phid;
        y.psi += 0.5 * h * psid;
        Ok(())
    }

    /// The rigid state of a canonical state.
    pub fn decode(&self, y: &Canonical) -> RigidState {
        let (phid, psid) = self.rates(y.theta);
        RigidState {
            q: quaternion_from_euler(y.phi, y.theta, y.psi),
            omega: omega_body_from_euler(y.theta, y.psi, y.p_theta / self.i1, phid, psid),
        }
    }
}

impl FixedScheme for Verlet {
    type Y = Canonical;
    fn step(&self, y: &mut Canonical, h: f64) -> Result<()> {
        self.half_kick(y, h)?;
        y.theta += h * y.p_theta / self.i1;
        self.half_kick(y, h)?;
        y.t += h;
        Ok(())
    }
}

/// The same Euler-angle Hamiltonian as a first-order system in y = (theta, p_theta, phi,
/// psi), for the general-purpose integrators: the reduced route, where only the
/// nutation is integrated and phi, psi follow from the conserved momenta.
impl crate::integrate::OdeSystem<4> for Verlet {
    fn rhs(&self, _t: f64, y: &[f64; 4], dy: &mut [f64; 4]) {
        let (phid, psid) = self.rates(y[0]);
        dy[0] = y[1] / self.i1;
        dy[1] = self.force(y[0]);
        dy[2] = phid;
        dy[3] = psid;
    }
}

impl Verlet {
    /// The packed reduced state.
    pub fn pack(y: &Canonical) -> [f64; 4] {
        [y.theta, y.p_theta, y.phi, y.psi]
    }

    /// The rigid state of a packed reduced state.
    pub fn decode_packed(&self, y: &[f64; 4]) -> RigidState {
        self.decode(&Canonical {
            theta: y[0],
            p_theta: y[1],
            phi: y[2],
            psi: y[3],
            t: 0.0,
        })
    }
}
