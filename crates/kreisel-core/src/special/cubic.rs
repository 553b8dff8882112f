//! Real roots of polynomials of degree <= 3.
//!
//! Near a double root the roots of a cubic are ill-conditioned in its coefficients (an
//! error eps in the coefficients moves them by ~sqrt(eps)). The cure is to write the cubic
//! about a point where its value is known without cancellation; the exact Lagrange top
//! expands the gyro function about the state's own u, where f(u0) = (du/dt)^2 exactly.
//! The routines here then keep full relative precision in that shifted variable.

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
        for _ in 0..200 {
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
            } else {
                0.5 * (neg + pos)
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

    /// All real roots, ascending, with multiplicity (a double root appears twice).
    pub fn real_roots(&self) -> Vec<f64> {
        let c = self.0;
        if c[3] == 0.0 {
            return quadratic_roots(c[2], c[1], c[0]);
        }
        // One real root always exists; bracket it with Cauchy's bound.
        let bound = 1.0 + (c[0].abs().max(c[1].abs()).max(c[2].abs())) / c[3].abs();
        let r = self.root_in(-bound, bound);
        // Deflate: c3 x^3 + c2 x^2 + c1 x + c0 = (x - r)(q2 x^2 + q1 x + q0).
        let q2 = c[3];
        let q1 = c[2] + r * q2;
        let q0 = c[1] + r * q1;
        let mut roots = quadratic_roots(q2, q1, q0);
        for x in roots.iter_mut() {
            // One Newton polish on the full cubic.
            let (p, d) = self.eval_d(*x);
            if d != 0.0 && p.is_finite() {
                let y = *x - p / d;
                if self.eval(y).abs() <= p.abs() {
                    *x = y;
                }
            }
        }
        roots.push(r);
        roots.sort_by(|a, b| a.partial_cmp(b).unwrap());
        roots
    }
}

/// Real roots of `a x^2 + b x + c`, ascending, by the cancellation-free formula.
/// A negative discriminant within round-off of zero gives a double root.
pub fn quadratic_roots(a: f64, b: f64, c: f64) -> Vec<f64> {
    if a == 0.0 {
        return if b != 0.0 { vec![-c / b] } else { vec![] };
    }
    let disc = b * b - 4.0 * a * c;
    let scale = (b * b).max((4.0 * a * c).abs());
    if disc < -8.0 * f64::EPSILON * scale {
        return vec![];
    }
    let sq = disc.max(0.0).sqrt();
    let q = -0.5 * (b + sq.copysign(b));
    let (mut r1, mut r2) = if q != 0.0 { (q / a, c / q) } else { (0.0, 0.0) };
    if r1 > r2 {
        std::mem::swap(&mut r1, &mut r2);
    }
    vec![r1, r2]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roots_of_a_product_are_recovered() {
        // (x - 1)(x + 2)(x - 3.5) = x^3 - 2.5 x^2 - 5.5 x + 7
        let p = Poly3([7.0, -5.5, -2.5, 1.0]);
        let r = p.real_roots();
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
        let r = quadratic_roots(1.0, -1e8, 1.0);
        assert!((r[0] - 1e-8).abs() < 1e-22);
        assert!((r[1] - 1e8).abs() < 1e-6);
    }
}
