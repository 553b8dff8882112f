//! Rotations: unit quaternions (scalar first, rotating body vectors into space), Euler
//! angles (z-x-z, theta from the upward vertical) and the exact torque-free rotation of a
//! symmetric body.

mod euler;
mod quaternion;

pub use euler::{
    euler_from_matrix, euler_from_quaternion, omega_body_from_euler, quaternion_from_euler,
};
pub use quaternion::Quat;

/// `a x b`.
#[inline(always)]
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `a . b`.
#[inline(always)]
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    crate::fmadd(a[0], b[0], crate::fmadd(a[1], b[1], a[2] * b[2]))
}

/// Euclidean norm.
#[inline(always)]
pub fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}
