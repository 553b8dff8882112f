//! Elliptic integrals of the first, second (complete) and third kind (parameter convention `m = k^2`).
//!
//! Thin, validated wrappers over the `ellip` crate, plus the complete integral K from the
//! complementary parameter (accurate as m -> 1) and the incomplete third-kind integral in the
//! Jacobi form used by the exact Lagrange top, whose arguments come straight from sn, cn, dn.

use crate::error::{finite, KreiselError, Result};
use std::f64::consts::FRAC_PI_2;

/// A failure of the `ellip` crate, with the arguments of the call (formatted only then).
fn wrap(r: std::result::Result<f64, ellip::StrErr>, call: impl FnOnce() -> String) -> Result<f64> {
    r.map_err(|e| KreiselError::Numerical(format!("{}: {e}", call())))
}

/// Carlson's symmetric integral R_F(x, y, z).
pub fn rf(x: f64, y: f64, z: f64) -> Result<f64> {
    wrap(ellip::elliprf(x, y, z), || format!("R_F({x}, {y}, {z})"))
}

/// Carlson's symmetric integral R_J(x, y, z, p) (Cauchy principal value for p < 0).
pub fn rj(x: f64, y: f64, z: f64, p: f64) -> Result<f64> {
    wrap(ellip::elliprj(x, y, z, p), || {
        format!("R_J({x}, {y}, {z}, {p})")
    })
}

/// Checks the parameter `m` of a complete integral: finite and <= 1.
fn complete_parameter(m: f64) -> Result<f64> {
    if m.is_finite() && m <= 1.0 {
        Ok(m)
    } else {
        Err(KreiselError::invalid(
            "m",
            m,
            "the parameter must be a finite number <= 1 (the integral is complex for m > 1)",
        ))
    }
}

/// Checks the amplitude and parameter of an incomplete integral: both finite, and for
/// `m >= 1` (where `1 - m sin^2` vanishes at `asin(1/sqrt(m))`) `|phi|` below that
/// amplitude. Beyond it the integrand is complex; at it, infinite.
fn incomplete_arguments(phi: f64, m: f64) -> Result<()> {
    finite("phi", phi)?;
    finite("m", m)?;
    if m >= 1.0 {
        let limit = (1.0 / m.sqrt()).asin();
        if phi.abs() >= limit || phi.is_nan() {
            return Err(KreiselError::invalid(
                "phi",
                phi,
                format!(
                    "with m = {m} >= 1 the integral is real and finite only for \
                     |phi| < asin(1/sqrt(m)) = {limit}"
                ),
            ));
        }
    }
    Ok(())
}

/// Complete elliptic integral of the first kind K(m), any finite m <= 1 (infinite at m = 1).
pub fn ellipk(m: f64) -> Result<f64> {
    complete_parameter(m)?;
    if m >= 0.0 {
        Ok(ellipk_m1(1.0 - m))
    } else {
        wrap(ellip::ellipk(m), || format!("K(m = {m})"))
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

/// Complete elliptic integral of the second kind E(m), any finite m <= 1 (E(1) = 1).
pub fn ellipe(m: f64) -> Result<f64> {
    complete_parameter(m)?;
    wrap(ellip::ellipe(m), || format!("E(m = {m})"))
}

/// Incomplete elliptic integral of the first kind F(phi | m), any finite phi and m (for
/// m >= 1, |phi| < asin(1/sqrt(m))).
pub fn ellipf(phi: f64, m: f64) -> Result<f64> {
    incomplete_arguments(phi, m)?;
    wrap(ellip::ellipf(phi, m), || {
        format!("F(phi = {phi} | m = {m})")
    })
}

/// Complete elliptic integral of the third kind Pi(n | m), any finite n != 1 (principal
/// value for n > 1) and m <= 1 (infinite at m = 1).
pub fn ellippi(n: f64, m: f64) -> Result<f64> {
    characteristic(n)?;
    complete_parameter(m)?;
    wrap(ellip::ellippi(n, m), || format!("Pi(n = {n} | m = {m})"))
}

/// Checks the characteristic `n` of a third-kind integral: finite and not 1.
fn characteristic(n: f64) -> Result<f64> {
    if !n.is_finite() || n == 1.0 {
        return Err(KreiselError::invalid(
            "n",
            n,
            "the characteristic must be a finite number other than 1 (the integral diverges \
             at n = 1)",
        ));
    }
    Ok(n)
}

/// Incomplete elliptic integral of the third kind Pi(n; phi | m), any finite phi and
/// n != 1 (the Cauchy principal value where n sin^2 phi > 1; an error where
/// n sin^2 phi = 1, where it diverges), m as for [`ellipf`].
pub fn ellippiinc(phi: f64, n: f64, m: f64) -> Result<f64> {
    characteristic(n)?;
    incomplete_arguments(phi, m)?;
    wrap(ellip::ellippiinc(phi, n, m), || {
        format!("Pi(n = {n}; phi = {phi} | m = {m})")
    })
}

/// Jacobi elliptic functions of `u` for a parameter `m` in [0, 1], checked: `u` finite.
pub fn ellipj(u: f64, m: f64) -> Result<super::Jacobi> {
    finite("u", u)?;
    if !(0.0..=1.0).contains(&m) {
        return Err(KreiselError::invalid(
            "m",
            m,
            "the parameter must lie in [0, 1]",
        ));
    }
    if m > 0.0 && m < 1.0 {
        // The functions are periodic in 4K; beyond 2^52 half periods u carries no digit of
        // its place within the period (and the reduction's product would overflow).
        let limit = 2f64.powi(52) * 2.0 * ellipk_m1(1.0 - m);
        if u.abs() > limit {
            return Err(KreiselError::invalid(
                "u",
                u,
                format!(
                    "|u| must be at most 2^53 K(m) = {}: beyond, u keeps no digit of its \
                     place within the period 4K(m)",
                    crate::error::repr(limit)
                ),
            ));
        }
    }
    Ok(super::jacobi(u, m, 1.0 - m))
}

/// Carlson's degenerate integral R_C(x, y) (Cauchy principal value for y < 0).
pub fn rc(x: f64, y: f64) -> Result<f64> {
    wrap(ellip::elliprc(x, y), || format!("R_C({x}, {y})"))
}

/// `int_0^tau ds / (1 - n sn^2(s | m))` for tau in [0, K], from the Jacobi functions at tau,
/// `n1 = 1 - n` and `m1 = 1 - m` (pass both exactly: they set the precision as n -> 1 and
/// m -> 1). Valid for n < 1.
///
/// This is Pi(n; am tau | m) in Carlson's integrals, in one of two forms, each used where it
/// has no cancellation:
///
/// - `tau + n/3 sn^3 R_J(cn^2, dn^2, 1, cn^2 + n1 sn^2)` (DLMF 19.25.14 with
///   F(am tau | m) = tau), for -1 <= n <= 0 and where n1 >= q below;
/// - with `q = 1 - m/n`,
///   `-(m/(3n)) sn^3 R_J(cn^2, dn^2, 1, cn^2 + q sn^2) + sn R_C(cn^2 dn^2, (cn^2 + n1 sn^2)
///   (cn^2 + q sn^2))`: DLMF 19.7.8 (`Pi(n) + Pi(m/n) = F + sqrt(c) R_C(...)`) made
///   homogeneous in sn. Used for n < -1, where the first form's two terms nearly cancel
///   (they approach tau and -tau), and for m < n < 1 with n1 < q, where the first form's
///   R_J would have a last argument near 0 at tau = K (the axis of a top passing close to
///   the vertical).
pub fn pi_of_tau(tau: f64, jac: [f64; 3], n: f64, n1: f64, m: f64, m1: f64) -> Result<f64> {
    let [sn, cn, dn] = jac;
    if n == 0.0 || sn == 0.0 {
        return Ok(tau);
    }
    let (c2, d2, s2) = (cn * cn, dn * dn, sn * sn);
    // q = 1 - m/n, near n = 1 from the exact complements (there 1 - m/n = (m1 - n1)/n).
    let q = if n < 0.5 { 1.0 - m / n } else { (m1 - n1) / n };
    if n < -1.0 || (n > 0.0 && q > n1) {
        let pq = c2 + q * s2;
        let first = if m == 0.0 {
            0.0
        } else {
            -(m / (3.0 * n)) * sn * s2 * rj(c2, d2, 1.0, pq)?
        };
        return Ok(first + sn * rc(c2 * d2, (c2 + n1 * s2) * pq)?);
    }
    let p = c2 + n1 * s2;
    if p == 0.0 {
        return Ok(f64::INFINITY.copysign(sn));
    }
    Ok(tau + n / 3.0 * sn * s2 * rj(c2, d2, 1.0, p)?)
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
            for &n in &[-1e6, -7.0, -1.5, -0.4, 0.0, 0.5, 0.99, 0.999999] {
                for i in 0..=8 {
                    let tau = ellipk_m1(1.0 - m) * i as f64 / 8.0;
                    let j = jacobi(tau, m, 1.0 - m);
                    // At K itself, the exact values (as the exact solution passes them).
                    let jac = if i == 8 {
                        [1.0, 0.0, (1.0 - m).sqrt()]
                    } else {
                        [j.sn, j.cn, j.dn]
                    };
                    let a = pi_of_tau(tau, jac, n, 1.0 - n, m, 1.0 - m).unwrap();
                    let b = ellippiinc(j.am, n, m).unwrap();
                    assert!(
                        (a - b).abs() < 2e-14 * (1.0 + b.abs()),
                        "{m} {n} {tau}: {a} {b}"
                    );
                }
            }
        }
    }
}
