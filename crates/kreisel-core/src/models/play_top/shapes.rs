//! The convex contact parts of a top of revolution, each centred on the figure axis
//! (PHYSICS.md 4.1): where a part's lowest point is, its height above the floor, and the
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
}

impl Shape {
    /// Checks the part's numbers; `at` is its position in the list (errors say `shape[at]`).
    pub fn check(&self, at: usize) -> Result<()> {
        match *self {
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
        }
    }

    /// The part's radius of curvature at its lowest point (a sphere's radius).
    pub fn radius(&self) -> f64 {
        match *self {
            Shape::Sphere { radius, .. } => radius,
        }
    }

    /// The vector from G to the part's lowest point (space frame), `e3` the figure axis.
    #[inline(always)]
    pub fn arm(&self, e3: [f64; 3]) -> [f64; 3] {
        match *self {
            Shape::Sphere { radius, z } => [z * e3[0], z * e3[1], z * e3[2] - radius],
        }
    }

    /// Height of the lowest point above the floor, G at height `zg`.
    #[inline(always)]
    pub fn gap(&self, zg: f64, e3: [f64; 3]) -> f64 {
        zg + self.arm(e3)[2]
    }

    /// The rate of the gap: `vz + (w x d(arm)/d(orientation))`; for a sphere
    /// `vz + z (w x e3) . ez`, the normal velocity of the material point at the lowest point.
    #[inline(always)]
    pub fn gap_rate(&self, vz: f64, w: [f64; 3], e3: [f64; 3]) -> f64 {
        match *self {
            Shape::Sphere { z, .. } => vz + z * cross(w, e3)[2],
        }
    }

    /// The part of the gap's acceleration not proportional to the accelerations (vdot,
    /// wdot): for a sphere `z (w x (w x e3)) . ez`. The part that is, is
    /// `vdot . ez + wdot . (arm x ez)` (the material point's normal acceleration without its
    /// velocity terms).
    #[inline(always)]
    pub fn gap_bias(&self, w: [f64; 3], e3: [f64; 3]) -> f64 {
        match *self {
            Shape::Sphere { z, .. } => z * cross(w, cross(w, e3))[2],
        }
    }

    /// The rate of the slip velocity `v + w x arm` not proportional to the accelerations,
    /// while the lowest point moves over the body: `w x d(arm)/dt`; for a sphere
    /// `w x (z w x e3)`.
    #[inline(always)]
    pub fn slip_bias(&self, w: [f64; 3], e3: [f64; 3]) -> [f64; 3] {
        match *self {
            Shape::Sphere { z, .. } => {
                let we = cross(w, e3);
                cross(w, [z * we[0], z * we[1], z * we[2]])
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
        match *self {
            Shape::Sphere { z, .. } => [z * e3[0], z * e3[1], z * e3[2]],
        }
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

    /// The gap's rate and acceleration are its derivatives: finite differences of the gap
    /// along a motion with constant angular acceleration.
    #[test]
    fn gap_rate_and_bias_are_the_gaps_derivatives() {
        use crate::rotation::Quat;
        let part = Shape::Sphere {
            radius: 0.013,
            z: -0.021,
        };
        // orientation q(t) = exp(t w0 + t^2 wdot / 2) q0 (space-frame rotation vector, small)
        let q0 = Quat::from_axis_angle([0.3, -0.5, 0.8], 2.0).normalized();
        let (w0, wd) = ([1.3, -0.4, 2.2], [0.7, 0.9, -1.1]);
        let (v0, a0) = ([0.1, 0.2, -0.3], [0.5, -0.2, 0.4]);
        let at = |t: f64| {
            let rv = [
                t * w0[0] + 0.5 * t * t * wd[0],
                t * w0[1] + 0.5 * t * t * wd[1],
                t * w0[2] + 0.5 * t * t * wd[2],
            ];
            let q = Quat::from_rotation_vector(rv).hamilton(q0);
            let e3 = q.rotate([0.0, 0.0, 1.0]);
            let zg = 0.05 + v0[2] * t + 0.5 * a0[2] * t * t;
            part.gap(zg, e3)
        };
        let h = 1e-4;
        let e3 = q0.rotate([0.0, 0.0, 1.0]);
        let rate = (at(h) - at(-h)) / (2.0 * h);
        assert!((rate - part.gap_rate(v0[2], w0, e3)).abs() < 1e-7, "{rate}");
        let acc = (at(h) - 2.0 * at(0.0) + at(-h)) / (h * h);
        // Rotation vectors compose to first order only: the exact angular velocity of
        // exp(r(t)) q0 at t = 0 is w0, its acceleration wd (the commutator term is second
        // order in t and enters the acceleration as w0 x w0 = 0).
        let arm = part.arm(e3);
        let model = a0[2] + dot(wd, cross(arm, EZ)) + part.gap_bias(w0, e3);
        assert!((acc - model).abs() < 1e-6, "{acc} {model}");
    }
}
