//! Jacobi elliptic functions sn, cn, dn and the amplitude am.

use std::f64::consts::PI;

/// Values of the Jacobi elliptic functions at one argument.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jacobi {
    /// sn(u | m)
    pub sn: f64,
    /// cn(u | m)
    pub cn: f64,
    /// dn(u | m)
    pub dn: f64,
    /// am(u | m), continuous in u (am(u + 2K) = am(u) + pi)
    pub am: f64,
}

/// Jacobi elliptic functions of `u` for parameter `m = k^2` in [0, 1], given also
/// `m1 = 1 - m` (pass it exactly when known: it sets the precision for m near 1).
///
/// Method: the arithmetic-geometric mean and descending Landen transformation
/// (Abramowitz and Stegun 16.4), with the argument first reduced by the real period
/// so that the amplitude is exact in its multiple of pi. For `m1 = 0` the functions are
/// hyperbolic: sn = tanh, cn = dn = sech, am = gd.
pub fn jacobi(u: f64, m: f64, m1: f64) -> Jacobi {
    debug_assert!((0.0..=1.0).contains(&m) && (0.0..=1.0).contains(&m1));
    if m1 == 0.0 {
        let sech = 1.0 / u.cosh();
        let sn = u.tanh();
        return Jacobi {
            sn,
            cn: sech,
            dn: sech,
            am: sn.atan2(sech),
        };
    }
    if m == 0.0 {
        let (s, c) = u.sin_cos();
        return Jacobi {
            sn: s,
            cn: c,
            dn: 1.0,
            am: u,
        };
    }
    // Reduce by the half period 2K: am(u) = j pi + am(r), r in [-K, K].
    let kk = super::elliptic::ellipk_m1(m1);
    let j = (u / (2.0 * kk)).round();
    let r = u - j * 2.0 * kk;
    let (phi, _) = landen_amplitude(r, m, m1);
    let (s, c) = phi.sin_cos();
    // Sign flips of sn and cn with each half period are carried by the amplitude.
    let sn = s;
    let cn = c;
    let dn = (c * c + m1 * s * s).sqrt();
    let par = if j.rem_euclid(2.0) == 1.0 { -1.0 } else { 1.0 };
    Jacobi {
        sn: par * sn,
        cn: par * cn,
        dn,
        am: phi + j * PI,
    }
}

/// Amplitude by the AGM and backward Landen recursion. Returns (am, iterations).
fn landen_amplitude(u: f64, m: f64, m1: f64) -> (f64, usize) {
    const N: usize = 16;
    let mut a = [0.0f64; N + 1];
    let mut c = [0.0f64; N + 1];
    a[0] = 1.0;
    let mut b = m1.sqrt();
    c[0] = m.sqrt();
    let mut i = 0;
    while i < N && (c[i] / a[i]).abs() > f64::EPSILON {
        let ai = a[i];
        c[i + 1] = 0.5 * (ai - b);
        let t = (ai * b).sqrt();
        a[i + 1] = 0.5 * (ai + b);
        b = t;
        i += 1;
    }
    let mut phi = (1u64 << i) as f64 * a[i] * u;
    for jj in (1..=i).rev() {
        let t = c[jj] * phi.sin() / a[jj];
        phi = 0.5 * (t.asin() + phi);
    }
    (phi, i)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pythagorean_identities_hold_for_all_moduli() {
        for &m in &[0.0, 1e-12, 0.1, 0.5, 0.9, 0.999999, 1.0 - 1e-14] {
            let m1 = 1.0 - m;
            for i in -50..50 {
                let u = 0.173 * i as f64;
                let j = jacobi(u, m, m1);
                assert!(
                    (j.sn * j.sn + j.cn * j.cn - 1.0).abs() < 4e-16,
                    "m={m} u={u}"
                );
                assert!((j.dn * j.dn + m * j.sn * j.sn - 1.0).abs() < 4e-16);
                assert!((j.am.sin() - j.sn).abs() < 4e-15);
            }
        }
    }

    #[test]
    fn derivative_of_sn_is_cn_dn() {
        // d sn/du = cn dn, checked by a fourth-order central difference.
        let (m, h) = (0.7, 1e-3);
        for i in 0..40 {
            let u = -3.0 + 0.17 * i as f64;
            let f = |x: f64| jacobi(x, m, 1.0 - m).sn;
            let d = (8.0 * (f(u + h) - f(u - h)) - (f(u + 2.0 * h) - f(u - 2.0 * h))) / (12.0 * h);
            let j = jacobi(u, m, 1.0 - m);
            assert!((d - j.cn * j.dn).abs() < 1e-11);
        }
    }

    #[test]
    fn quarter_period_gives_sn_one() {
        for &m in &[0.3, 0.9, 0.99999] {
            let k = super::super::elliptic::ellipk_m1(1.0 - m);
            let j = jacobi(k, m, 1.0 - m);
            assert!((j.sn - 1.0).abs() < 1e-15 && j.cn.abs() < 1e-7);
            assert!((j.am - std::f64::consts::FRAC_PI_2).abs() < 1e-14);
        }
    }
}
