//! Quaternions `(w, x, y, z)`, scalar first. A unit quaternion q rotates body-frame vectors
//! into the space frame: `v_space = q v_body q*`.

use super::{cross, dot};

/// A quaternion, scalar first.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quat(pub [f64; 4]);

impl Quat {
    /// The identity rotation.
    pub const IDENTITY: Quat = Quat([1.0, 0.0, 0.0, 0.0]);

    /// Rotation by `angle` (rad) about the unit vector `axis`.
    #[inline]
    pub fn from_axis_angle(axis: [f64; 3], angle: f64) -> Quat {
        let (s, c) = (0.5 * angle).sin_cos();
        Quat([c, s * axis[0], s * axis[1], s * axis[2]])
    }

    /// Rotation by the vector `v` (angle |v| about v/|v|), the exponential map.
    #[inline]
    pub fn from_rotation_vector(v: [f64; 3]) -> Quat {
        let a = dot(v, v).sqrt();
        if a < 1e-8 {
            // sin(a/2)/a = 1/2 - a^2/48 + ..., cos(a/2) = 1 - a^2/8 + a^4/384
            let k = 0.5 - a * a / 48.0;
            Quat([
                1.0 - a * a / 8.0 + a * a * a * a / 384.0,
                k * v[0],
                k * v[1],
                k * v[2],
            ])
        } else {
            let (s, c) = (0.5 * a).sin_cos();
            let k = s / a;
            Quat([c, k * v[0], k * v[1], k * v[2]])
        }
    }

    /// Hamilton product `self * o` (also the `*` operator).
    #[inline(always)]
    pub fn hamilton(self, o: Quat) -> Quat {
        let [a0, a1, a2, a3] = self.0;
        let [b0, b1, b2, b3] = o.0;
        Quat([
            a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3,
            a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
            a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1,
            a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0,
        ])
    }

    /// Euclidean norm.
    #[inline(always)]
    pub fn norm(self) -> f64 {
        let q = self.0;
        (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt()
    }

    /// This quaternion scaled to unit norm. Components of any finite size: where the sum of
    /// squares would overflow or underflow, the quaternion is first scaled by a power of two
    /// (exact), so `[1e300, 1e300, 0, 0]` gives `[1/sqrt 2, 1/sqrt 2, 0, 0]` and
    /// `[1e-300, 0, 0, 0]` gives `[1, 0, 0, 0]`. The zero quaternion gives NaN.
    #[inline(always)]
    pub fn normalized(self) -> Quat {
        let q = self.0;
        let n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
        if !(f64::MIN_POSITIVE..=f64::MAX).contains(&n2) {
            return self.normalized_scaled();
        }
        let n = n2.sqrt();
        Quat(q.map(|x| x / n))
    }

    #[cold]
    fn normalized_scaled(self) -> Quat {
        let big = self.0.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if !(big > 0.0 && big.is_finite()) {
            return Quat([f64::NAN; 4]);
        }
        // The power of two nearest below the largest component: after scaling it lies in
        // [1, 2), and so does the norm, within a factor 2.
        let e = ((big.to_bits() >> 52) & 0x7ff) as i32 - 1023;
        let scaled = if e < -1000 {
            self.0.map(|x| x * 2f64.powi(1000) * 2f64.powi(-e - 1000))
        } else if e > 1000 {
            self.0.map(|x| x * 2f64.powi(-1000) * 2f64.powi(1000 - e))
        } else {
            self.0.map(|x| x * 2f64.powi(-e))
        };
        let n = Quat(scaled).norm();
        Quat(scaled.map(|x| x / n))
    }

    /// Rotates a body-frame vector into the space frame.
    #[inline(always)]
    pub fn rotate(self, v: [f64; 3]) -> [f64; 3] {
        let w = self.0[0];
        let u = [self.0[1], self.0[2], self.0[3]];
        let t = cross(u, v).map(|x| 2.0 * x);
        let ut = cross(u, t);
        [
            v[0] + w * t[0] + ut[0],
            v[1] + w * t[1] + ut[1],
            v[2] + w * t[2] + ut[2],
        ]
    }

    /// Rotates a space-frame vector into the body frame (the inverse rotation).
    #[inline(always)]
    pub fn rotate_inv(self, v: [f64; 3]) -> [f64; 3] {
        Quat([self.0[0], -self.0[1], -self.0[2], -self.0[3]]).rotate(v)
    }

    /// The upward vertical e_z seen in the body frame (third row of the rotation matrix).
    #[inline(always)]
    pub fn up_in_body(self) -> [f64; 3] {
        let [w, x, y, z] = self.0;
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            w * w - x * x - y * y + z * z,
        ]
    }

    /// The rotation matrix (row-major).
    pub fn matrix(self) -> [[f64; 3]; 3] {
        let [w, x, y, z] = self.0;
        [
            [
                1.0 - 2.0 * (y * y + z * z),
                2.0 * (x * y - w * z),
                2.0 * (x * z + w * y),
            ],
            [
                2.0 * (x * y + w * z),
                1.0 - 2.0 * (x * x + z * z),
                2.0 * (y * z - w * x),
            ],
            [
                2.0 * (x * z - w * y),
                2.0 * (y * z + w * x),
                1.0 - 2.0 * (x * x + y * y),
            ],
        ]
    }
}

impl Quat {
    /// Half the Hamilton product `self * (0, v)` with a pure quaternion: `dq/dt` for the body
    /// angular velocity `v` (12 multiplications instead of the 16 of a full product).
    #[inline(always)]
    pub fn half_times_pure(self, v: [f64; 3]) -> [f64; 4] {
        let [w, x, y, z] = self.0;
        let [a, b, c] = [0.5 * v[0], 0.5 * v[1], 0.5 * v[2]];
        [
            -(x * a + y * b + z * c),
            w * a + y * c - z * b,
            w * b + z * a - x * c,
            w * c + x * b - y * a,
        ]
    }

    /// The rotation matrix (row-major) of `self / |self|`, for a quaternion of any non-zero
    /// norm: one division, no square root. Right-hand sides that use it do not depend on
    /// the norm, so the integrator's error estimate does not see its drift within a step.
    #[inline(always)]
    pub fn unit_matrix(self) -> [[f64; 3]; 3] {
        let [w, x, y, z] = self.0;
        let k = 2.0 / (w * w + x * x + y * y + z * z);
        let (kx, ky, kz) = (k * x, k * y, k * z);
        let (xx, yy, zz) = (kx * x, ky * y, kz * z);
        let (xy, xz, yz) = (kx * y, kx * z, ky * z);
        let (wx, wy, wz) = (kx * w, ky * w, kz * w);
        [
            [1.0 - (yy + zz), xy - wz, xz + wy],
            [xy + wz, 1.0 - (xx + zz), yz - wx],
            [xz - wy, yz + wx, 1.0 - (xx + yy)],
        ]
    }
}

impl std::ops::Mul for Quat {
    type Output = Quat;
    #[inline(always)]
    fn mul(self, o: Quat) -> Quat {
        self.hamilton(o)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalisation_scales_huge_and_tiny_quaternions() {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let q = Quat([1e300, 1e300, 0.0, 0.0]).normalized().0;
        assert!((q[0] - h).abs() < 2e-16 && (q[1] - h).abs() < 2e-16 && q[2] == 0.0);
        assert_eq!(
            Quat([1e-300, 0.0, 0.0, 0.0]).normalized().0,
            [1.0, 0.0, 0.0, 0.0]
        );
        assert_eq!(
            Quat([0.0, 5e-324, 0.0, 0.0]).normalized().0,
            [0.0, 1.0, 0.0, 0.0]
        );
        let q = Quat([-3e-170, 4e-170, 0.0, 0.0]).normalized().0;
        assert!(
            (q[0] + 0.6).abs() < 2e-16 && (q[1] - 0.8).abs() < 2e-16,
            "{q:?}"
        );
        // Ordinary quaternions: the plain formula, bit for bit.
        let q = Quat([0.3, -0.5, 0.7, 0.2]);
        let n = q.norm();
        assert_eq!(q.normalized().0, q.0.map(|x| x / n));
    }

    #[test]
    fn rotation_matches_matrix_and_inverse() {
        let q = Quat([0.3, -0.5, 0.7, 0.2]).normalized();
        let m = q.matrix();
        let v = [0.4, -1.3, 2.2];
        let r = q.rotate(v);
        for i in 0..3 {
            let mv = m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2];
            assert!((r[i] - mv).abs() < 1e-14);
        }
        let back = q.rotate_inv(r);
        for i in 0..3 {
            assert!((back[i] - v[i]).abs() < 1e-14);
        }
        let up = q.up_in_body();
        let up2 = q.rotate_inv([0.0, 0.0, 1.0]);
        for i in 0..3 {
            assert!((up[i] - up2[i]).abs() < 1e-14);
        }
    }

    #[test]
    fn unit_matrix_ignores_the_norm() {
        let q = Quat([0.3, -0.5, 0.7, 0.2]);
        let m = q.normalized().matrix();
        let u = Quat(q.0.map(|x| 3.7 * x)).unit_matrix();
        for i in 0..3 {
            for j in 0..3 {
                assert!((m[i][j] - u[i][j]).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn half_times_pure_is_half_the_product() {
        let q = Quat([0.3, -0.5, 0.7, 0.2]);
        let v = [0.4, -1.3, 2.2];
        let full = q.hamilton(Quat([0.0, v[0], v[1], v[2]]));
        let half = q.half_times_pure(v);
        for (f, h) in full.0.iter().zip(half) {
            assert!((0.5 * f - h).abs() < 1e-15);
        }
    }

    #[test]
    fn composition_is_successive_rotation() {
        let a = Quat::from_axis_angle([0.0, 0.0, 1.0], 0.7);
        let b = Quat::from_rotation_vector([0.3, -0.2, 0.5]);
        let v = [1.0, 2.0, -0.5];
        let ab = a.hamilton(b).rotate(v);
        let seq = a.rotate(b.rotate(v));
        for i in 0..3 {
            assert!((ab[i] - seq[i]).abs() < 1e-14);
        }
    }
}
