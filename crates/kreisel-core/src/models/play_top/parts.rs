//! The convex contact parts of a top of revolution, each centred on the figure axis
//! (theory: bodies of revolution): where a part's lowest point is, its height above the floor,
//! and the
//! kinematics of that point while the part touches (the gap's rate and acceleration, and the
//! slip velocity's rate while the point sticks).
//!
//! Conventions: `e3` the figure axis and `ez` the upward vertical, both in the space frame;
//! `z` the position of the part's centre along `e3` from the centre of mass G; `w` the
//! angular velocity in the space frame. The "arm" of a part is the vector from G to its
//! lowest point.

use crate::error::{KreiselError, Result, PARAMETER_RANGE};
use crate::rotation::cross;

/// The most parts a top may have.
pub const MAX_PARTS: usize = 4;

/// One convex contact part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// A sphere of radius `radius >= 0` (0: a sharp point) centred at `z` on the figure axis.
    Sphere {
        /// Radius (m).
        radius: f64,
        /// Position of the centre along e3 from G (m).
        z: f64,
    },
    /// An ellipsoid of revolution about the figure axis, semi-axes `equatorial` (across the
    /// axis) and `axial` (along it), both > 0, centred at `z`.
    Spheroid {
        /// Semi-axis across the figure axis (m).
        equatorial: f64,
        /// Semi-axis along the figure axis (m).
        axial: f64,
        /// Position of the centre along e3 from G (m).
        z: f64,
    },
    /// A ring about the figure axis at `z`: radius `major` > 0 to the tube's centre line,
    /// tube radius `minor` >= 0 (0: a sharp circular edge, a coin's or a disk's rim).
    Torus {
        /// Radius of the tube's centre line (m).
        major: f64,
        /// Tube radius (m).
        minor: f64,
        /// Position of the ring's plane along e3 from G (m).
        z: f64,
    },
}

/// Below this `sin(theta)` a torus lies (numerically) flat: its lowest point is any point of
/// the rim, and the profile's derivatives are taken at this value.
const FLAT: f64 = 1e-12;

impl Shape {
    /// Checks the part's numbers; `at` is its position in the list (errors say `shape[at]`).
    pub fn check(&self, at: usize) -> Result<()> {
        let length = |what: &str, x: f64, zero: bool| -> Result<()> {
            if (zero && x == 0.0)
                || (x.is_finite() && (PARAMETER_RANGE.0..=PARAMETER_RANGE.1).contains(&x))
            {
                Ok(())
            } else {
                Err(KreiselError::invalid(
                    &format!("shape[{at}].{what}"),
                    x,
                    if zero {
                        "it must be 0 or a finite length in [1e-100, 1e+100] m"
                    } else {
                        "it must be a finite length in [1e-100, 1e+100] m"
                    },
                ))
            }
        };
        let centre = |z: f64| -> Result<()> {
            if z.is_finite() && z.abs() <= PARAMETER_RANGE.1 {
                Ok(())
            } else {
                Err(KreiselError::invalid(
                    &format!("shape[{at}].z"),
                    z,
                    "the centre's position on the figure axis must be finite, of magnitude at \
                     most 1e+100 m",
                ))
            }
        };
        match *self {
            Shape::Spheroid {
                equatorial,
                axial,
                z,
            } => {
                length("equatorial", equatorial, false)?;
                length("axial", axial, false)?;
                centre(z)?;
            }
            Shape::Torus { major, minor, z } => {
                length("major", major, false)?;
                length("minor", minor, true)?;
                centre(z)?;
            }
            Shape::Sphere { radius, z } => {
                let name = format!("shape[{at}].radius");
                if !(radius == 0.0
                    || (radius.is_finite()
                        && (PARAMETER_RANGE.0..=PARAMETER_RANGE.1).contains(&radius)))
                {
                    return Err(KreiselError::invalid(
                        &name,
                        radius,
                        "a sphere's radius must be 0 (a sharp point) or a finite length in \
                         [1e-100, 1e+100] m",
                    ));
                }
                if !(z.is_finite() && z.abs() <= PARAMETER_RANGE.1) {
                    return Err(KreiselError::invalid(
                        &format!("shape[{at}].z"),
                        z,
                        "the centre's position on the figure axis must be finite, of magnitude \
                         at most 1e+100 m",
                    ));
                }
            }
        }
        Ok(())
    }

    /// The largest distance from G of a point of the part (m): a length scale.
    pub fn reach(&self) -> f64 {
        match *self {
            Shape::Sphere { radius, z } => z.abs() + radius,
            Shape::Spheroid {
                equatorial,
                axial,
                z,
            } => z.abs() + equatorial.max(axial),
            Shape::Torus { major, minor, z } => z.abs() + major + minor,
        }
    }

    /// The lengths that bound the lever of the part's contact force about G, `(l, r)` with
    /// `|arm x ez| <= l` and `|arm| <= l + r` (a sphere: `(|z|, radius)`).
    pub fn levers(&self) -> (f64, f64) {
        match *self {
            Shape::Sphere { radius, z } => (z.abs(), radius),
            _ => (self.reach(), 0.0),
        }
    }

    /// The part's profile along the vertical: with `u = e3 . ez`, its lowest point lies
    /// `phi(u)` below its centre; returns `(phi, phi', phi'')` (derivatives in u). A sphere's
    /// is `(radius, 0, 0)`; a spheroid's `phi = sqrt(a^2 (1 - u^2) + b^2 u^2)`; a torus's
    /// `phi = R sqrt(1 - u^2) + r` (theory: bodies of revolution).
    #[inline(always)]
    pub fn profile(&self, u: f64) -> (f64, f64, f64) {
        match *self {
            Shape::Sphere { radius, .. } => (radius, 0.0, 0.0),
            Shape::Spheroid {
                equatorial: a,
                axial: b,
                ..
            } => {
                let d = b * b - a * a;
                let phi = (a * a + d * u * u).sqrt();
                (phi, d * u / phi, d * a * a / (phi * phi * phi))
            }
            Shape::Torus { major, minor, .. } => {
                let s = (1.0 - u * u).max(0.0).sqrt().max(FLAT);
                (major * s + minor, -major * u / s, -major / (s * s * s))
            }
        }
    }

    /// The part's centre's position along e3 from G.
    #[inline(always)]
    pub(crate) fn z(&self) -> f64 {
        match *self {
            Shape::Sphere { z, .. } | Shape::Spheroid { z, .. } | Shape::Torus { z, .. } => z,
        }
    }

    /// The vector from G to the part's lowest point (space frame), `e3` the figure axis:
    /// `(z - phi') e3 + (phi' u - phi) ez` (the support point of the part in direction -ez).
    #[inline(always)]
    pub fn arm(&self, e3: [f64; 3]) -> [f64; 3] {
        match *self {
            Shape::Sphere { radius, z } => [z * e3[0], z * e3[1], z * e3[2] - radius],
            Shape::Torus { major, minor, z } => {
                // The rim's lowest point, `z e3 - R d/|d| - r ez` with `d = ez - u e3` (the
                // ring plane's most downward direction), from the axis's horizontal part
                // `h` (|d| = |h| sqrt(u^2 + |h|^2)): the same point as the general formula,
                // whose terms of size R/|h| cancel, without the cancellation near flat
                // (there it lost ~1e-16 R/|h| of the height: micrometres). Lying exactly
                // flat every rim point is lowest; the arm is then the circle's centre, of the
                // same height.
                let u = e3[2];
                let s2 = e3[0] * e3[0] + e3[1] * e3[1];
                let s = s2.sqrt();
                let (kh, dz) = if s > 0.0 {
                    let dn = s * (u * u + s2).sqrt();
                    (major * u / dn, major * s2 / dn)
                } else {
                    (0.0, 0.0)
                };
                [(z + kh) * e3[0], (z + kh) * e3[1], z * u - dz - minor]
            }
            _ => {
                let u = e3[2];
                let (phi, dphi, _) = self.profile(u);
                let k = self.z() - dphi;
                [k * e3[0], k * e3[1], k * e3[2] + dphi * u - phi]
            }
        }
    }

    /// Height of the lowest point above the floor, G at height `zg`.
    #[inline(always)]
    pub fn gap(&self, zg: f64, e3: [f64; 3]) -> f64 {
        zg + self.arm(e3)[2]
    }

    /// The rate of the gap, `vz + (z - phi') du/dt` with `du/dt = (w x e3) . ez`: the normal
    /// velocity of the material point at the lowest point.
    #[inline(always)]
    pub fn gap_rate(&self, vz: f64, w: [f64; 3], e3: [f64; 3]) -> f64 {
        match *self {
            Shape::Sphere { z, .. } => vz + z * cross(w, e3)[2],
            _ => vz + (self.z() - self.profile(e3[2]).1) * cross(w, e3)[2],
        }
    }

    /// The part of the gap's acceleration not proportional to the accelerations (vdot,
    /// wdot): `(z - phi') (w x (w x e3)) . ez - phi'' (du/dt)^2`. The part that is, is
    /// `vdot . ez + wdot . (arm x ez)` (the material point's normal acceleration without its
    /// velocity terms).
    #[inline(always)]
    pub fn gap_bias(&self, w: [f64; 3], e3: [f64; 3]) -> f64 {
        match *self {
            Shape::Sphere { z, .. } => z * cross(w, cross(w, e3))[2],
            _ => {
                let (_, dphi, ddphi) = self.profile(e3[2]);
                let we = cross(w, e3);
                (self.z() - dphi) * cross(w, we)[2] - ddphi * we[2] * we[2]
            }
        }
    }

    /// The rate of the slip velocity `v + w x arm` not proportional to the accelerations,
    /// while the lowest point moves over the body: `w x d(arm)/dt`, with
    /// `d(arm)/dt = (z - phi') w x e3 + phi'' du/dt (u ez - e3)`; for a sphere `w x (z w x e3)`.
    #[inline(always)]
    pub fn slip_bias(&self, w: [f64; 3], e3: [f64; 3]) -> [f64; 3] {
        match *self {
            Shape::Sphere { z, .. } => {
                let we = cross(w, e3);
                cross(w, [z * we[0], z * we[1], z * we[2]])
            }
            _ => {
                let u = e3[2];
                let (_, dphi, ddphi) = self.profile(u);
                let we = cross(w, e3);
                let k = self.z() - dphi;
                let c = ddphi * we[2];
                let darm = [
                    k * we[0] - c * e3[0],
                    k * we[1] - c * e3[1],
                    k * we[2] + c * (u - e3[2]),
                ];
                cross(w, darm)
            }
        }
    }

    /// The lowest point's material velocity `v + w x arm` (its horizontal part is the slip).
    #[inline(always)]
    pub fn point_velocity(&self, v: [f64; 3], w: [f64; 3], e3: [f64; 3]) -> [f64; 3] {
        let wa = cross(w, self.arm(e3));
        [v[0] + wa[0], v[1] + wa[1], v[2] + wa[2]]
    }

    /// The part's centre (space frame, from G).
    pub fn centre(&self, e3: [f64; 3]) -> [f64; 3] {
        let z = self.z();
        [z * e3[0], z * e3[1], z * e3[2]]
    }
}

/// A top's contact parts: the first `n` of `shape`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Parts {
    /// How many parts.
    pub n: usize,
    /// The parts (only the first `n` are used).
    pub shape: [Shape; MAX_PARTS],
}

impl Parts {
    /// One part.
    pub const fn one(part: Shape) -> Parts {
        Parts {
            n: 1,
            shape: [part; MAX_PARTS],
        }
    }

    /// The parts of a list, each checked.
    pub fn new(parts: &[Shape]) -> Result<Parts> {
        if parts.is_empty() || parts.len() > MAX_PARTS {
            return Err(KreiselError::InvalidParameter {
                name: "shape".into(),
                value: format!("{} parts", parts.len()),
                allowed: format!("a top needs between 1 and {MAX_PARTS} contact parts"),
            });
        }
        for (i, p) in parts.iter().enumerate() {
            p.check(i)?;
        }
        let mut shape = [parts[0]; MAX_PARTS];
        shape[..parts.len()].copy_from_slice(parts);
        Ok(Parts {
            n: parts.len(),
            shape,
        })
    }

    /// The parts in use.
    pub fn iter(&self) -> impl Iterator<Item = &Shape> {
        self.shape[..self.n].iter()
    }

    /// The largest reach of a part ([`Shape::reach`]), at least 1e-300.
    pub fn reach(&self) -> f64 {
        self.iter().map(Shape::reach).fold(1e-300, f64::max)
    }

    /// The height of G at which the lowest part touches the floor (orientation `e3`).
    pub fn resting_height(&self, e3: [f64; 3]) -> f64 {
        self.iter()
            .map(|p| -p.arm(e3)[2])
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotation::dot;
    const EZ: [f64; 3] = [0.0, 0.0, 1.0];

    /// The gap's rate and acceleration, and the lowest point's slip velocity's rate, are
    /// the derivatives of the gap and of that velocity: finite differences along a motion
    /// with constant linear and angular acceleration, for every kind of part.
    #[test]
    fn gap_and_slip_rates_are_their_derivatives() {
        use crate::rotation::Quat;
        let parts = [
            Shape::Sphere {
                radius: 0.013,
                z: -0.021,
            },
            Shape::Spheroid {
                equatorial: 0.02,
                axial: 0.035,
                z: 0.004,
            },
            Shape::Spheroid {
                equatorial: 0.03,
                axial: 0.012,
                z: -0.01,
            },
            Shape::Torus {
                major: 0.0375,
                minor: 0.0,
                z: 0.00625,
            },
            Shape::Torus {
                major: 0.02,
                minor: 0.004,
                z: -0.008,
            },
        ];
        // orientation q(t) = exp(t w0 + t^2 wdot / 2) q0 (space-frame rotation vector)
        let q0 = Quat::from_axis_angle([0.3, -0.5, 0.8], 2.0).normalized();
        let (w0, wd) = ([1.3, -0.4, 2.2], [0.7, 0.9, -1.1]);
        let (v0, a0) = ([0.1, 0.2, -0.3], [0.5, -0.2, 0.4]);
        let state = |t: f64| {
            let rv = [
                t * w0[0] + 0.5 * t * t * wd[0],
                t * w0[1] + 0.5 * t * t * wd[1],
                t * w0[2] + 0.5 * t * t * wd[2],
            ];
            let e3 = Quat::from_rotation_vector(rv)
                .hamilton(q0)
                .rotate([0.0, 0.0, 1.0]);
            let zg = 0.05 + v0[2] * t + 0.5 * a0[2] * t * t;
            let v = [v0[0] + a0[0] * t, v0[1] + a0[1] * t, v0[2] + a0[2] * t];
            // the exact angular velocity of exp(r(t)) q0 is w0 + t wd to first order in t
            let w = [w0[0] + wd[0] * t, w0[1] + wd[1] * t, w0[2] + wd[2] * t];
            (zg, e3, v, w)
        };
        let h = 1e-4;
        for part in parts {
            let gap = |t: f64| {
                let (zg, e3, _, _) = state(t);
                part.gap(zg, e3)
            };
            let (_, e3, _, _) = state(0.0);
            let rate = (gap(h) - gap(-h)) / (2.0 * h);
            let model = part.gap_rate(v0[2], w0, e3);
            assert!((rate - model).abs() < 1e-7, "{part:?}: {rate} {model}");
            let acc = (gap(h) - 2.0 * gap(0.0) + gap(-h)) / (h * h);
            let arm = part.arm(e3);
            let model = a0[2] + dot(wd, cross(arm, EZ)) + part.gap_bias(w0, e3);
            assert!((acc - model).abs() < 1e-6, "{part:?}: {acc} {model}");
            // the lowest point's velocity v + w x arm and its rate
            let pv = |t: f64| {
                let (_, e3, v, w) = state(t);
                part.point_velocity(v, w, e3)
            };
            let (p1, p0) = (pv(h), pv(-h));
            let wa = cross(wd, arm);
            let bias = part.slip_bias(w0, e3);
            for k in 0..3 {
                let fd = (p1[k] - p0[k]) / (2.0 * h);
                let model = a0[k] + wa[k] + bias[k];
                assert!((fd - model).abs() < 1e-6, "{part:?} [{k}]: {fd} {model}");
            }
        }
    }

    /// A spheroid with equal semi-axes is the sphere, to rounding.
    #[test]
    fn a_round_spheroid_is_the_sphere() {
        use crate::rotation::Quat;
        let (r, z) = (0.015, -0.003);
        let ball = Shape::Sphere { radius: r, z };
        let round = Shape::Spheroid {
            equatorial: r,
            axial: r,
            z,
        };
        let e3 = Quat::from_axis_angle([0.6, 0.0, 0.8], 2.2).rotate([0.0, 0.0, 1.0]);
        let w = [3.0, -1.0, 150.0];
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-15 * (1.0 + a.abs());
        for k in 0..3 {
            assert!(close(ball.arm(e3)[k], round.arm(e3)[k]));
            assert!(close(ball.slip_bias(w, e3)[k], round.slip_bias(w, e3)[k]));
        }
        assert!(close(ball.gap(0.02, e3), round.gap(0.02, e3)));
        assert!(close(ball.gap_bias(w, e3), round.gap_bias(w, e3)));
    }
}
