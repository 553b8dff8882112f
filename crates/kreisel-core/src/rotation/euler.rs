//! Euler angles z-x-z: R = Rz(phi) Rx(theta) Rz(psi), theta from the upward vertical.

use super::Quat;

/// The quaternion of the Euler angles.
pub fn quaternion_from_euler(phi: f64, theta: f64, psi: f64) -> Quat {
    let z = [0.0, 0.0, 1.0];
    Quat::from_axis_angle(z, phi)
        .hamilton(Quat::from_axis_angle([1.0, 0.0, 0.0], theta))
        .hamilton(Quat::from_axis_angle(z, psi))
}

/// Body-frame angular velocity from Euler angles and rates (Goldstein's z-x-z relations).
pub fn omega_body_from_euler(
    theta: f64,
    psi: f64,
    theta_dot: f64,
    phi_dot: f64,
    psi_dot: f64,
) -> [f64; 3] {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = psi.sin_cos();
    [
        phi_dot * st * sp + theta_dot * cp,
        phi_dot * st * cp - theta_dot * sp,
        phi_dot * ct + psi_dot,
    ]
}

/// (phi, theta, psi) of a unit quaternion, phi and psi in (-pi, pi]. At theta = 0 (or pi)
/// only phi + psi (or phi - psi) is defined; psi is then set to 0.
pub fn euler_from_quaternion(q: Quat) -> (f64, f64, f64) {
    euler_from_matrix(q.matrix())
}

/// (phi, theta, psi) of a rotation matrix (row-major), as [`euler_from_quaternion`].
pub fn euler_from_matrix(m: [[f64; 3]; 3]) -> (f64, f64, f64) {
    let s = (m[0][2] * m[0][2] + m[1][2] * m[1][2]).sqrt();
    let theta = s.atan2(m[2][2]);
    if s > 1e-12 {
        (m[0][2].atan2(-m[1][2]), theta, m[2][0].atan2(m[2][1]))
    } else {
        // R = Rz(phi +- psi) (with a flip of the x axis at theta = pi).
        let phi = m[1][0].atan2(m[0][0]);
        (if m[2][2] > 0.0 { phi } else { -phi }, theta, 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn euler_round_trip() {
        for &(phi, theta, psi) in &[(0.3, 1.1, -2.0), (-2.5, 0.2, 0.9), (1.0, 3.0, 2.9)] {
            let (a, b, c) = euler_from_quaternion(quaternion_from_euler(phi, theta, psi));
            assert!(
                (a - phi).abs() < 1e-13 && (b - theta).abs() < 1e-13 && (c - psi).abs() < 1e-13
            );
        }
    }

    #[test]
    fn figure_axis_is_as_in_the_physics_notes() {
        let (phi, theta, psi) = (0.4, 0.9, 1.3);
        let e3 = quaternion_from_euler(phi, theta, psi).rotate([0.0, 0.0, 1.0]);
        let want = [
            theta.sin() * phi.sin(),
            -theta.sin() * phi.cos(),
            theta.cos(),
        ];
        for i in 0..3 {
            assert!((e3[i] - want[i]).abs() < 1e-14);
        }
    }

    #[test]
    fn body_rates_match_quaternion_derivative() {
        // dq/dt = q (0, omega) / 2, checked by central differences along Euler angles.
        let (phi, theta, psi, pd, td, sd) = (0.4, 0.9, 1.3, 0.7, -0.3, 5.0);
        let h = 1e-6;
        let qp = quaternion_from_euler(phi + pd * h, theta + td * h, psi + sd * h);
        let qm = quaternion_from_euler(phi - pd * h, theta - td * h, psi - sd * h);
        let q = quaternion_from_euler(phi, theta, psi);
        let w = omega_body_from_euler(theta, psi, td, pd, sd);
        let dq = q.hamilton(Quat([0.0, w[0], w[1], w[2]]));
        for i in 0..4 {
            let fd = (qp.0[i] - qm.0[i]) / (2.0 * h);
            assert!((fd - 0.5 * dq.0[i]).abs() < 1e-8);
        }
    }
}
