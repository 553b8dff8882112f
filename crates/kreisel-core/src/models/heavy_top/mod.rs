//! The heavy top: any rigid body on a fixed frictionless pivot under uniform gravity.
//!
//! Body frame along the principal axes of inertia about the pivot, `I = diag(I1, I2, I3)`,
//! centre of mass `c` (from the pivot, body frame), `Gamma` the upward vertical seen in the
//! body frame, `M = I omega` (theory: heavy top):
//!
//! `dM/dt = M x omega + m g (Gamma x c)`,  `dGamma/dt = Gamma x omega`,
//!
//! with the orientation carried as a unit quaternion q (`dq/dt = q (0, omega) / 2`), so
//! theta = 0 or pi is no singularity. Integrals: `E = omega.M / 2 + m g c.Gamma`,
//! `Mz = M.Gamma`; for the Lagrange top also `M3`; for the Kovalevskaya top her quartic
//! integral.
//!
//! - [`equations`]: the first-order systems for the general-purpose integrators;
//! - [`splitting`]: the explicit Lie-Poisson splittings (exact sub-flows);
//! - [`verlet`]: Stoermer-Verlet on the Euler-angle Hamiltonian;
//! - [`sensitivity`]: forward sensitivities (variational equations on the rotation group);
//! - [`simulate`]: the driver behind `simulate::simulate` for heavy tops, its columns and
//!   its summary.

pub mod driven;
pub mod equations;
pub mod sensitivity;
pub mod simulate;
pub mod splitting;
pub mod verlet;

use crate::error::{finite, non_negative, positive, rate, KreiselError, Result};
use crate::models::lagrange::LagrangeTop;
use crate::rotation::{cross, dot, Quat};

/// Which of the classical integrable cases a heavy top is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TopKind {
    /// No torque about the pivot (m g |c| = 0): Euler's free top.
    Euler,
    /// I1 == I2 and the centre of mass on the 3-axis.
    Lagrange,
    /// I1 == I2 == 2 I3 and the centre of mass in the equatorial plane.
    Kovalevskaya,
    /// Anything else: generically chaotic.
    General,
}

impl TopKind {
    /// The public name.
    pub fn name(&self) -> &'static str {
        match self {
            TopKind::Euler => "euler",
            TopKind::Lagrange => "lagrange",
            TopKind::Kovalevskaya => "kovalevskaya",
            TopKind::General => "general",
        }
    }
}

/// Orientation (unit quaternion, body to space) and body angular velocity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidState {
    /// Unit quaternion, scalar first.
    pub q: Quat,
    /// Angular velocity in the body frame (rad/s).
    pub omega: [f64; 3],
}

impl RigidState {
    /// A validated state: the quaternion is normalised; a zero or non-finite one is an error.
    pub fn new(q: [f64; 4], omega: [f64; 3]) -> Result<Self> {
        for (i, &x) in q.iter().enumerate() {
            finite(&format!("q[{i}]"), x)?;
        }
        for (i, &x) in omega.iter().enumerate() {
            rate(&format!("omega[{i}]"), x)?;
        }
        // Any finite non-zero quaternion: `normalized` scales where the squares over- or
        // underflow.
        if q.iter().all(|&x| x == 0.0) {
            return Err(KreiselError::InvalidParameter {
                name: "q".into(),
                value: format!("{q:?}"),
                allowed: "a quaternion must be non-zero (it is normalised)".into(),
            });
        }
        Ok(RigidState {
            q: Quat(q).normalized(),
            omega,
        })
    }
}

/// A rigid body on a fixed pivot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeavyTop {
    inertia: [f64; 3],
    inv_inertia: [f64; 3],
    m: f64,
    com: [f64; 3],
    g: f64,
    /// m g c
    mgc: [f64; 3],
    /// Euler's coefficients `((I2 - I3)/I1, (I3 - I1)/I2, (I1 - I2)/I3)`.
    euler: [f64; 3],
    kind: TopKind,
}

impl HeavyTop {
    /// Validates and builds a heavy top. Moments are principal moments about the pivot.
    pub fn new(i1: f64, i2: f64, i3: f64, m: f64, com: [f64; 3], g: f64) -> Result<Self> {
        let inertia = [i1, i2, i3];
        for (name, v) in [("I1", i1), ("I2", i2), ("I3", i3)] {
            positive(name, v)?;
        }
        positive("m", m)?;
        non_negative("g", g)?;
        for (i, &c) in com.iter().enumerate() {
            finite(&format!("com[{i}]"), c)?;
        }
        let names = ["I1", "I2", "I3"];
        for i in 0..3 {
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            if inertia[i] > (inertia[j] + inertia[k]) * (1.0 + 1e-12) {
                return Err(KreiselError::invalid(
                    names[i],
                    inertia[i],
                    format!(
                        "no rigid body has {} > {} + {} = {} (triangle inequality of principal moments)",
                        names[i],
                        names[j],
                        names[k],
                        inertia[j] + inertia[k]
                    ),
                ));
            }
            // Parallel-axis theorem: the moment about the pivot is at least m times the
            // squared distance of the centre of mass from that axis.
            let d2 = com[j] * com[j] + com[k] * com[k];
            if inertia[i] < m * d2 * (1.0 - 1e-12) {
                return Err(KreiselError::invalid(
                    names[i],
                    inertia[i],
                    format!(
                        "{} is about the pivot and must be >= m * (distance of the centre of \
                         mass from that axis)^2 = {} (parallel-axis theorem)",
                        names[i],
                        m * d2
                    ),
                ));
            }
        }
        let mgc = com.map(|c| m * g * c);
        let torque_free = mgc.iter().all(|&x| x == 0.0);
        let sym12 = i1 == i2;
        let kind = if torque_free {
            TopKind::Euler
        } else if sym12 && com[0] == 0.0 && com[1] == 0.0 {
            TopKind::Lagrange
        } else if sym12 && (i1 - 2.0 * i3).abs() <= 1e-14 * i1 && com[2] == 0.0 {
            TopKind::Kovalevskaya
        } else {
            TopKind::General
        };
        Ok(HeavyTop {
            inertia,
            inv_inertia: inertia.map(|x| 1.0 / x),
            m,
            com,
            g,
            mgc,
            euler: [(i2 - i3) / i1, (i3 - i1) / i2, (i1 - i2) / i3],
            kind,
        })
    }

    /// The heavy-top form of a Lagrange top: I = (I1, I1, I3), c = (0, 0, l).
    pub fn from_lagrange(top: &LagrangeTop) -> HeavyTop {
        HeavyTop::new(
            top.i1(),
            top.i1(),
            top.i3(),
            top.m(),
            [0.0, 0.0, top.l()],
            top.g(),
        )
        .expect("a valid Lagrange top is a valid heavy top")
    }

    /// Principal moments about the pivot.
    pub fn inertia(&self) -> [f64; 3] {
        self.inertia
    }
    /// Mass.
    pub fn m(&self) -> f64 {
        self.m
    }
    /// Centre of mass in the body frame.
    pub fn com(&self) -> [f64; 3] {
        self.com
    }
    /// Gravitational acceleration.
    pub fn g(&self) -> f64 {
        self.g
    }
    /// `m g c`.
    pub fn mgc(&self) -> [f64; 3] {
        self.mgc
    }
    /// The integrable case this top belongs to.
    pub fn kind(&self) -> TopKind {
        self.kind
    }
    /// True when the free rotation (without gravity) is that of a symmetric body about the
    /// 3-axis, so it is available in closed form.
    pub fn symmetric(&self) -> bool {
        self.inertia[0] == self.inertia[1]
    }

    /// Body angular momentum `M = I omega`.
    #[inline(always)]
    pub fn momentum(&self, omega: [f64; 3]) -> [f64; 3] {
        [
            self.inertia[0] * omega[0],
            self.inertia[1] * omega[1],
            self.inertia[2] * omega[2],
        ]
    }

    /// Body angular velocity `omega = I^-1 M`.
    #[inline(always)]
    pub fn omega(&self, m: [f64; 3]) -> [f64; 3] {
        [
            self.inv_inertia[0] * m[0],
            self.inv_inertia[1] * m[1],
            self.inv_inertia[2] * m[2],
        ]
    }

    /// Total energy (J).
    pub fn energy(&self, s: &RigidState) -> f64 {
        let m = self.momentum(s.omega);
        0.5 * dot(s.omega, m) + dot(self.mgc, s.q.up_in_body())
    }

    /// Vertical component of the angular momentum about the pivot (kg m^2/s).
    pub fn mz(&self, s: &RigidState) -> f64 {
        dot(self.momentum(s.omega), s.q.up_in_body())
    }

    /// Axial angular momentum `I3 omega3` where it is an integral (Lagrange and Euler tops
    /// with I1 == I2), else None.
    pub fn m3(&self, s: &RigidState) -> Option<f64> {
        match self.kind {
            TopKind::Lagrange => Some(self.inertia[2] * s.omega[2]),
            TopKind::Euler if self.symmetric() => Some(self.inertia[2] * s.omega[2]),
            _ => None,
        }
    }

    /// Kovalevskaya's integral `(w1^2 - w2^2 - nu G1)^2 + (2 w1 w2 - nu G2)^2`,
    /// `nu = m g |c| / I3`, in body axes turned about the 3-axis so that c lies on the
    /// 1-axis; None unless this is a Kovalevskaya top.
    pub fn kovalevskaya(&self, s: &RigidState) -> Option<f64> {
        if self.kind != TopKind::Kovalevskaya {
            return None;
        }
        // hypot: the squares of a centre of mass of 1e-200 m would underflow to 0
        let r = self.com[0].hypot(self.com[1]);
        let (ca, sa) = (self.com[0] / r, self.com[1] / r);
        let turn = |v: [f64; 3]| [ca * v[0] + sa * v[1], -sa * v[0] + ca * v[1]];
        let w = turn(s.omega);
        let gm = turn(s.q.up_in_body());
        let nu = self.m * self.g * r / self.inertia[2];
        let a = w[0] * w[0] - w[1] * w[1] - nu * gm[0];
        let b = 2.0 * w[0] * w[1] - nu * gm[1];
        Some(a * a + b * b)
    }

    /// Right-hand side on `y = (q0, q1, q2, q3, omega1, omega2, omega3)`.
    #[inline(always)]
    pub fn rhs(&self, y: &[f64; 7], dy: &mut [f64; 7]) {
        let q = Quat([y[0], y[1], y[2], y[3]]);
        let w = [y[4], y[5], y[6]];
        dy[..4].copy_from_slice(&q.half_times_pure(w));
        // Euler's equations, I1 dw1/dt = (I2 - I3) w2 w3 + torque_1 and cyclically.
        let torque = cross(q.up_in_body(), self.mgc);
        let (e, inv) = (self.euler, self.inv_inertia);
        dy[4] = e[0] * w[1] * w[2] + torque[0] * inv[0];
        dy[5] = e[1] * w[2] * w[0] + torque[1] * inv[1];
        dy[6] = e[2] * w[0] * w[1] + torque[2] * inv[2];
    }

    /// Whether `I1 == I2` and the centre of mass lies on the 3-axis (a Lagrange top, or a
    /// symmetric free one): then [`HeavyTop::rhs_axial`] gives the right-hand side.
    pub fn axial(&self) -> bool {
        self.inertia[0] == self.inertia[1] && self.mgc[0] == 0.0 && self.mgc[1] == 0.0
    }

    /// [`HeavyTop::rhs`] of an [`axial`](HeavyTop::axial) top, without the terms that vanish
    /// there: with `c = (0, 0, c3)` the torque is `m g c3 (Gamma_2, -Gamma_1, 0)`, and with
    /// `I1 == I2` `omega3` is constant. The remaining operations are those of `rhs`, in the
    /// same order, so both give the same values (up to the sign of a zero).
    #[inline(always)]
    pub fn rhs_axial(&self, y: &[f64; 7], dy: &mut [f64; 7]) {
        let [w, x, yq, z] = [y[0], y[1], y[2], y[3]];
        let om = [y[4], y[5], y[6]];
        dy[..4].copy_from_slice(&Quat([w, x, yq, z]).half_times_pure(om));
        // Gamma_1 and Gamma_2 as in `Quat::up_in_body`.
        let g0 = 2.0 * (x * z - w * yq);
        let g1 = 2.0 * (yq * z + w * x);
        let (e, inv, c3) = (self.euler, self.inv_inertia, self.mgc[2]);
        dy[4] = e[0] * om[1] * om[2] + g1 * c3 * inv[0];
        dy[5] = e[1] * om[2] * om[0] - g0 * c3 * inv[1];
        dy[6] = 0.0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_are_recognised() {
        let k = |i1, i2, i3, c| HeavyTop::new(i1, i2, i3, 1.0, c, 9.81).unwrap().kind();
        assert_eq!(k(2.0, 2.0, 1.0, [0.0, 0.0, 0.3]), TopKind::Lagrange);
        assert_eq!(k(2.0, 2.0, 1.0, [0.3, 0.0, 0.0]), TopKind::Kovalevskaya);
        assert_eq!(k(2.0, 3.0, 1.5, [0.0, 0.0, 0.0]), TopKind::Euler);
        assert_eq!(k(2.0, 3.0, 1.5, [0.1, 0.0, 0.2]), TopKind::General);
    }

    #[test]
    fn axial_right_hand_side_is_the_general_one() {
        let top = HeavyTop::new(1.3, 1.3, 0.6, 0.8, [0.0, 0.0, 0.4], 9.81).unwrap();
        assert!(top.axial());
        assert!(!HeavyTop::new(1.3, 1.3, 0.6, 0.8, [0.1, 0.0, 0.4], 9.81)
            .unwrap()
            .axial());
        let y = [0.3, -0.5, 0.7, 0.2, 1.7, -0.4, 9.1];
        let (mut a, mut b) = ([0.0; 7], [0.0; 7]);
        top.rhs(&y, &mut a);
        top.rhs_axial(&y, &mut b);
        assert_eq!(a, b);
    }

    #[test]
    fn invalid_bodies_are_rejected_by_name() {
        let e = HeavyTop::new(1.0, 1.0, 2.5, 1.0, [0.0; 3], 9.81).unwrap_err();
        assert!(e.to_string().starts_with("I3 = 2.5"), "{e}");
        let e = HeavyTop::new(0.1, 0.1, 0.1, 1.0, [0.0, 0.0, 1.0], 9.81).unwrap_err();
        assert!(e.to_string().starts_with("I1 = 0.1"), "{e}");
        assert!(RigidState::new([0.0; 4], [0.0; 3]).is_err());
    }
}
