//! Elliptic integrals of the first and third kind (parameter convention `m = k^2`).
//!
//! Thin, validated wrappers over the `ellip` crate, plus the complete integral K from the
//! complementary parameter (accurate as m -> 1) and the incomplete third-kind integral in the
//! Jacobi form used by the exact Lagrange top, whose arguments come straight from sn, cn, dn.

use crate::error::{KreiselError, Result};
use std::f64::consts::FRAC_PI_2;

fn wrap(name: &str, r: std::result::Result<f64, ellip::StrErr>) -> Result<f64> {
    r.map_err(|e| KreiselError::Numerical(format!("{name}: {e}")))
}

/// Carlson's symmetric integral R_F(x, y, z).
pub fn rf(x: f64, y: f64, z: f64) -> Result<f64> {
    wrap("R_F", ellip::elliprf(x, y, z))
}

/// Carlson's symmetric integral R_J(x, y, z, p) (Cauchy principal value for p < 0).
pub fn rj(x: f64, y: f64, z: f64, p: f64) -> Result<f64> {
    wrap("R_J", ellip::elliprj(x, y, z, p))
}

/// Complete elliptic integral of the first kind K(m).
pub fn ellipk(m: f64) -> Result<f64> {
    if m.is_nan() || m > 1.0 {
        return Err(KreiselError::invalid("m", m, "the parameter must be <= 1"));
    }
    if m >= 0.0 {
        Ok(ellipk_m1(1.0 - m))
    } else {
        wrap("K", ellip::ellipk(m))
    }
}

/// K as a function of the complementary parameter `m1 = 1 - m` in [0, 1], by the
/// arithmetic-geometric mean: K = pi / (2 AGM(1, sqrt(m1))). Infinite at m1 = 0.
pub fn ellipk_m1(m1: f64) -> f64 {
    if m1 <= 0.0 {
        return f64::INFINITY;
    }
    let (mut a, mut b) = (1.0f64, m1.sqrt());
    for _ in 0..40 {
        if (a - b).abs() <= 2.0 * f64::EPSILON * a {
            break;
        }
        let an = 0.5 * (a + b);
        b = (a * b).sqrt();
        a = an;
    }
    FRAC_PI_2 / a
}

/// Incomplete elliptic integral of the first kind F(phi | m), any real phi.
pub fn ellipf(phi: f64, m: f64) -> Result<f64> {
    wrap("F", ellip::ellipf(phi, m))
}

/// Complete elliptic integral of the third kind Pi(n | m), any n != 1 (principal value n > 1).
pub fn ellippi(n: f64, m: f64) -> Result<f64> {
    wrap("Pi", ellip::ellippi(n, m))
}

/// Incomplete elliptic integral of the third kind Pi(n; phi | m), any real phi and n
/// (the Cauchy principal value where n sin^2 phi > 1).
pub fn ellippiinc(phi: f64, n: f64, m: f64) -> Result<f64> {
    wrap("Pi", ellip::ellippiinc(phi, n, m))
}

/// `int_0^tau ds / (1 - n sn^2(s | m))` for tau in [-K, K], from the Jacobi functions at tau
/// and `n1 = 1 - n` (pass it exactly: it sets the precision as n -> 1). Valid for n <= 1.
///
/// This is Pi(n; am tau | m) written with Carlson's integrals (DLMF 19.25.14) and
/// F(am tau | m) = tau:  tau + n/3 sn^3 R_J(cn^2, dn^2, 1, cn^2 + n1 sn^2).
pub fn pi_of_tau(tau: f64, sn: f64, cn: f64, dn: f64, n: f64, n1: f64) -> Result<f64> {
    if n == 0.0 || sn == 0.0 {
        return Ok(tau);
    }
    let (c2, d2) = (cn * cn, dn * dn);
    let p = c2 + n1 * sn * sn;
    if p == 0.0 {
        return Ok(f64::INFINITY.copysign(sn));
    }
    Ok(tau + n / 3.0 * sn * sn * sn * rj(c2, d2, 1.0, p)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::special::jacobi;

    #[test]
    fn agm_k_matches_ellip_crate() {
        for &m in &[0.0, 0.1, 0.5, 0.9, 0.999] {
            let a = ellipk_m1(1.0 - m);
            let b = ellip::ellipk(m).unwrap();
            assert!((a - b).abs() < 1e-15 * b, "m={m}: {a} {b}");
        }
    }

    #[test]
    fn pi_of_tau_agrees_with_legendre_form() {
        for &m in &[0.0, 0.3, 0.95] {
            for &n in &[-7.0, -0.4, 0.0, 0.5, 0.99] {
                for i in 0..=8 {
                    let tau = ellipk_m1(1.0 - m) * i as f64 / 8.0;
                    let j = jacobi(tau, m, 1.0 - m);
                    let a = pi_of_tau(tau, j.sn, j.cn, j.dn, n, 1.0 - n).unwrap();
                    let b = ellippiinc(j.am, n, m).unwrap();
                    assert!(
                        (a - b).abs() < 1e-14 * (1.0 + b.abs()),
                        "{m} {n} {tau}: {a} {b}"
                    );
                }
            }
        }
    }
}
