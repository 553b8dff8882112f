//! Real roots of polynomials of degree <= 3.
//!
//! Near a double root the roots of a cubic are ill-conditioned in its coefficients (an
//! error eps in the coefficients moves them by ~sqrt(eps)). The cure is to write the cubic
//! about a point where its value is known without cancellation; the exact Lagrange top
//! expands the gyro function about the state's own u, where f(u0) = (du/dt)^2 exactly.
//! The routines here then keep full relative precision in that shifted variable.

use crate::error::{KreiselError, Result};

/// `c[0] + c[1] x + c[2] x^2 + c[3] x^3`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Poly3(pub [f64; 4]);

impl Poly3 {
    /// Value at `x` (Horner).
    #[inline]
    pub fn eval(&self, x: f64) -> f64 {
        let c = &self.0;
        ((c[3] * x + c[2]) * x + c[1]) * x + c[0]
    }

    /// Value and derivative at `x`.
    #[inline]
    pub fn eval_d(&self, x: f64) -> (f64, f64) {
        let c = &self.0;
        let p = ((c[3] * x + c[2]) * x + c[1]) * x + c[0];
        let d = (3.0 * c[3] * x + 2.0 * c[2]) * x + c[1];
        (p, d)
    }

    /// A root in `[a, b]` where the polynomial changes sign (or vanishes at an end):
    /// bisection safeguarded Newton, to full precision. Keeps the invariant
    /// `sign(p(neg)) <= 0 < sign(p(pos))`, so with `p(a) <= 0 < p(b)` it returns the
    /// sign change nearest the side where p > 0 when the bracket holds several.
    pub fn root_in(&self, a: f64, b: f64) -> f64 {
        let (pa, pb) = (self.eval(a), self.eval(b));
        if pa == 0.0 && pb == 0.0 {
            return a;
        }
        // Orient: `neg` is where p <= 0, `pos` where p > 0.
        let (mut neg, mut pos) = if pa <= 0.0 && pb > 0.0 {
            (a, b)
        } else if pb <= 0.0 && pa > 0.0 {
            (b, a)
        } else if pa == 0.0 {
            return a;
        } else if pb == 0.0 {
            return b;
        } else {
            // No sign change: return the end with the smaller |p|.
            return if pa.abs() < pb.abs() { a } else { b };
        };
        let mut x = 0.5 * (neg + pos);
        for step in 0..200 {
            let (p, d) = self.eval_d(x);
            if p == 0.0 {
                return x;
            }
            if p < 0.0 {
                neg = x;
            } else {
                pos = x;
            }
            let newton = x - p / d;
            let (lo, hi) = if neg < pos { (neg, pos) } else { (pos, neg) };
            let next = if d != 0.0 && newton > lo && newton < hi {
                newton
            } else if step < 100 {
                0.5 * (neg + pos)
            } else {
                // Still not converged: a root far smaller than the bracket (near zero).
                // Halving the floats between the ends reaches it in at most 64 steps, to
                // full relative precision.
                unkey(((key(lo) as i128 + key(hi) as i128) / 2) as i64)
            };
            if (next - x).abs() <= 2.0 * f64::EPSILON * x.abs().max(f64::MIN_POSITIVE)
                || (hi - lo) <= 2.0 * f64::EPSILON * lo.abs().max(hi.abs())
            {
                return next;
            }
            x = next;
        }
        x
    }

    /// All real roots, ascending, with multiplicity (a double root appears twice), for any
    /// finite coefficients: found where the polynomial changes sign between its critical
    /// points, by bisection of the floating-point numbers themselves (at most 64 steps each)
    /// with the value summed at a common power-of-two scale, so that neither overflow nor
    /// underflow spoils it (`1e300 + 4.9 x + 1e300 x^2 + 4.9 x^3` has the root
    /// -2.04e299). A critical point where the value vanishes to round-off is a double root.
    ///
    /// Errors: a coefficient that is not finite; the zero polynomial (every x is a root); a
    /// root beyond the range of f64 (|x| > 1.8e308), which names the leading coefficient.
    pub fn real_roots(&self) -> Result<Vec<f64>> {
        let c = self.0;
        for (i, &x) in c.iter().enumerate() {
            if !x.is_finite() {
                return Err(KreiselError::invalid(
                    &format!("c{i}"),
                    x,
                    "every coefficient must be a finite number",
                ));
            }
        }
        let Some(lead) = (0..4).rev().find(|&i| c[i] != 0.0) else {
            return Err(KreiselError::invalid(
                "c3",
                0.0,
                "c0 = c1 = c2 = c3 = 0 is the zero polynomial: every x is a root",
            ));
        };
        let beyond = || {
            KreiselError::invalid(
                &format!("c{lead}"),
                c[lead],
                format!(
                    "a root of this polynomial lies beyond the range of floating-point numbers \
                     (|x| > {:e}): the leading coefficient is too small for the others",
                    f64::MAX
                ),
            )
        };
        if lead < 3 {
            return quadratic_roots(c[2], c[1], c[0]).ok_or_else(beyond);
        }
        // Critical points, from p'/4 (no overflow at the largest coefficients).
        let crit = quadratic_raw(0.75 * c[3], 0.5 * c[2], 0.25 * c[1])
            .into_iter()
            .map(|x| x.clamp(-f64::MAX, f64::MAX));
        let mut points = vec![-f64::MAX];
        points.extend(crit);
        points.push(f64::MAX);
        points.dedup();
        let signs: Vec<f64> = points
            .iter()
            .map(|&x| {
                let (v, mag) = eval_scaled(&c, x);
                if v.abs() <= 16.0 * f64::EPSILON * mag {
                    0.0
                } else {
                    v.signum()
                }
            })
            .collect();
        let last = points.len() - 1;
        if signs[last] != 0.0 && signs[last] != c[3].signum()
            || signs[0] != 0.0 && signs[0] != -c[3].signum()
        {
            return Err(beyond());
        }
        let mut roots = Vec::with_capacity(3);
        for i in 1..last {
            if signs[i] == 0.0 {
                // A critical point on the axis: a double root (triple where both coincide).
                roots.extend([points[i], points[i]]);
            }
        }
        for i in 0..last {
            let (sa, sb) = (signs[i], signs[i + 1]);
            if sa != 0.0 && sb != 0.0 && sa != sb {
                roots.push(bisect(&c, points[i], points[i + 1], sa));
            }
        }
        roots.truncate(3);
        roots.sort_by(f64::total_cmp);
        Ok(roots)
    }
}

/// Real roots of `a x^2 + b x + c`, ascending, by the cancellation-free formula; None where a
/// root lies beyond the range of f64. A negative discriminant within round-off of zero gives
/// a double root. The variable and the coefficients are scaled by powers of two first (which
/// changes no bit of the result where nothing overflows or underflows), so coefficients of
/// any finite size give the roots that are representable.
pub fn quadratic_roots(a: f64, b: f64, c: f64) -> Option<Vec<f64>> {
    let r = quadratic_raw(a, b, c);
    r.iter().all(|x| x.is_finite()).then_some(r)
}

/// [`quadratic_roots`], with a root beyond the range of f64 given as +-inf.
fn quadratic_raw(a: f64, b: f64, c: f64) -> Vec<f64> {
    let sorted = |x: f64, y: f64| if y < x { vec![y, x] } else { vec![x, y] };
    if a == 0.0 {
        return if b == 0.0 { vec![] } else { vec![-c / b] };
    }
    if c == 0.0 {
        return sorted(-b / a, 0.0);
    }
    // x = 2^k y balances the first and last coefficients; then the largest is about 1.
    let (ea, eb, ec) = (exponent(a), exponent(b), exponent(c));
    let k = (ec - ea).div_euclid(2);
    let top = (ea + 2 * k)
        .max(ec)
        .max(if b == 0.0 { i32::MIN } else { eb + k });
    let (a2, b2, c2) = (ldexp(a, 2 * k - top), ldexp(b, k - top), ldexp(c, -top));
    if a2 == 0.0 || c2 == 0.0 {
        // b^2 exceeds 4 a c by more than the range of f64: the roots are -b/a and -c/b.
        return sorted(-b / a, -c / b);
    }
    let disc = b2 * b2 - 4.0 * a2 * c2;
    let scale = (b2 * b2).max((4.0 * a2 * c2).abs());
    if disc < -8.0 * f64::EPSILON * scale {
        return vec![];
    }
    let sq = disc.max(0.0).sqrt();
    let q = -0.5 * (b2 + sq.copysign(b2));
    sorted(ldexp(q / a2, k), ldexp(c2 / q, k))
}

/// The binary exponent e of a finite non-zero x, 2^(e-1) <= |x| < 2^e (subnormals included).
fn exponent(x: f64) -> i32 {
    let (x, adj) = if x.abs() < f64::MIN_POSITIVE {
        (x * 2f64.powi(64), -64)
    } else {
        (x, 0)
    };
    ((x.to_bits() >> 52) & 0x7ff) as i32 - 1022 + adj
}

/// `x 2^n` without overflow or underflow of the factor.
fn ldexp(mut x: f64, mut n: i32) -> f64 {
    while n > 1000 && x.is_finite() && x != 0.0 {
        x *= 2f64.powi(1000);
        n -= 1000;
    }
    while n < -1000 && x.is_finite() && x != 0.0 {
        x *= 2f64.powi(-1000);
        n += 1000;
    }
    x * 2f64.powi(n.clamp(-1074, 1023))
}

/// `p(x)` and `sum |c_i x^i|`, both divided by the same power of two so that neither
/// overflows or underflows: the sign of the first and the ratio of the two are exact to
/// rounding.
fn eval_scaled(c: &[f64; 4], x: f64) -> (f64, f64) {
    if x == 0.0 {
        return (c[0], c[0].abs());
    }
    let ex = exponent(x);
    let mx = ldexp(x, -ex);
    let mut terms = [(0.0f64, 0i32); 4];
    let mut pw = 1.0;
    for (i, t) in terms.iter_mut().enumerate() {
        let v = c[i] * pw;
        *t = (v, ex * i as i32);
        pw *= mx;
    }
    let top = terms
        .iter()
        .filter(|t| t.0 != 0.0)
        .map(|t| exponent(t.0) + t.1)
        .max();
    let Some(top) = top else {
        return (0.0, 0.0);
    };
    let (mut v, mut mag) = (0.0, 0.0);
    for (t, s) in terms {
        let y = ldexp(t, s - top);
        v += y;
        mag += y.abs();
    }
    (v, mag)
}

/// Total-order key of a float (as `f64::total_cmp`), and back.
fn key(x: f64) -> i64 {
    let i = x.to_bits() as i64;
    i ^ (((i >> 63) as u64) >> 1) as i64
}
fn unkey(k: i64) -> f64 {
    f64::from_bits((k ^ (((k >> 63) as u64) >> 1) as i64) as u64)
}

/// The root between `lo < hi`, where the sign of p is `s_lo` at lo and the other at hi:
/// bisection of the floats between them (so at most 64 steps to adjacent floats).
fn bisect(c: &[f64; 4], lo: f64, hi: f64, s_lo: f64) -> f64 {
    let (mut a, mut b) = (key(lo) as i128, key(hi) as i128);
    while b - a > 1 {
        let mid = a + (b - a) / 2;
        let x = unkey(mid as i64);
        let (v, _) = eval_scaled(c, x);
        if v == 0.0 {
            return x;
        }
        if v.signum() == s_lo {
            a = mid;
        } else {
            b = mid;
        }
    }
    let (xa, xb) = (unkey(a as i64), unkey(b as i64));
    let rel = |x: f64| {
        let (v, m) = eval_scaled(c, x);
        if m == 0.0 {
            0.0
        } else {
            (v / m).abs()
        }
    };
    if rel(xa) <= rel(xb) {
        xa
    } else {
        xb
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roots_of_a_product_are_recovered() {
        // (x - 1)(x + 2)(x - 3.5) = x^3 - 2.5 x^2 - 5.5 x + 7
        let p = Poly3([7.0, -5.5, -2.5, 1.0]);
        let r = p.real_roots().unwrap();
        assert_eq!(r.len(), 3);
        for (a, b) in r.iter().zip([-2.0, 1.0, 3.5]) {
            assert!((a - b).abs() < 1e-14);
        }
    }

    #[test]
    fn shifted_form_resolves_a_near_double_root() {
        // (x - d)(x + d)(x - 5) with d = 1e-9: in shifted form the tiny roots keep full
        // relative precision (a sqrt(eps) loss would leave ~1e-8 relative error).
        let d = 1e-9;
        let p = Poly3([5.0 * d * d, -d * d, -5.0, 1.0]);
        let lo = p.root_in(-1.0, 0.0);
        let hi = p.root_in(0.0, 1.0);
        assert!((lo + d).abs() < 1e-15 * d * 10.0, "{lo}");
        assert!((hi - d).abs() < 1e-15 * d * 10.0, "{hi}");
    }

    #[test]
    fn quadratic_without_cancellation() {
        let r = quadratic_roots(1.0, -1e8, 1.0).unwrap();
        assert!((r[0] - 1e-8).abs() < 1e-22);
        assert!((r[1] - 1e8).abs() < 1e-6);
    }
}
