//! Piecewise polynomial interpolation of several smooth functions at once.
//!
//! Built once, evaluated millions of times: each segment holds a degree-`DEG` Chebyshev
//! interpolant, converted to monomials in the local variable x in [-1, 1] (safe because the
//! Chebyshev coefficients of an accepted segment decay to round-off). Segments are refined
//! by bisection until the last two Chebyshev coefficients of every function fall below the
//! tolerance relative to that function's scale; a uniform lookup grid finds the segment.

use crate::error::{KreiselError, Result};
use std::f64::consts::PI;

/// Polynomial degree of every segment.
pub const DEG: usize = 8;
const NODES: usize = DEG + 1;

/// NF functions interpolated on one interval.
#[derive(Debug, Clone)]
pub struct Piecewise<const NF: usize> {
    lo: f64,
    hi: f64,
    breaks: Vec<f64>,
    /// Per segment: (centre, 1/half-width).
    maps: Vec<(f64, f64)>,
    /// Per segment, DEG+1 rows of NF monomial coefficients, highest degree first.
    coef: Vec<[f64; NF]>,
    lookup: Vec<u32>,
    inv_cell: f64,
    accuracy: f64,
}

impl<const NF: usize> Piecewise<NF> {
    /// Interpolates `f` on `[lo, hi]` to relative accuracy `rel_tol` (per function, relative
    /// to its largest magnitude on the interval). A segment split `max_depth` times is
    /// accepted as it is (its samples are then noisier than the tolerance); the worst such
    /// relative tail is reported by [`Piecewise::accuracy`].
    pub fn build<F>(lo: f64, hi: f64, mut f: F, rel_tol: f64, max_depth: u32) -> Result<Self>
    where
        F: FnMut(f64) -> Result<[f64; NF]>,
    {
        if lo.is_nan() || hi.is_nan() || lo >= hi || !lo.is_finite() || !hi.is_finite() {
            return Err(KreiselError::Numerical(format!(
                "interpolation interval [{lo}, {hi}] is empty or infinite"
            )));
        }
        let mut scale = [0.0f64; NF];
        for i in 0..=64 {
            let v = f(lo + (hi - lo) * i as f64 / 64.0)?;
            for k in 0..NF {
                scale[k] = scale[k].max(v[k].abs());
            }
        }
        let tol: [f64; NF] = std::array::from_fn(|k| rel_tol * scale[k].max(f64::MIN_POSITIVE));

        let mut segments: Vec<(f64, f64, [[f64; NF]; NODES])> = Vec::new();
        let mut noise = 0.0f64;
        let mut stack = vec![(lo, hi, 0u32)];
        while let Some((a, b, depth)) = stack.pop() {
            let cheb = chebyshev_coefficients(a, b, &mut f)?;
            let ok =
                (0..NF).all(|k| cheb[DEG][k].abs() <= tol[k] && cheb[DEG - 1][k].abs() <= tol[k]);
            if ok {
                segments.push((a, b, cheb));
            } else if depth >= max_depth {
                // The tail has reached the noise of the samples: accept, and report it.
                let worst = (0..NF)
                    .map(|k| cheb[DEG][k].abs().max(cheb[DEG - 1][k].abs()) / tol[k] * rel_tol)
                    .fold(0.0, f64::max);
                noise = noise.max(worst);
                segments.push((a, b, cheb));
            } else {
                let m = 0.5 * (a + b);
                stack.push((m, b, depth + 1));
                stack.push((a, m, depth + 1));
            }
        }
        segments.sort_by(|x, y| x.0.partial_cmp(&y.0).unwrap());
        let mut breaks = Vec::with_capacity(segments.len() + 1);
        let mut maps = Vec::with_capacity(segments.len());
        let mut coef = Vec::with_capacity(segments.len() * NODES);
        for (a, b, cheb) in &segments {
            breaks.push(*a);
            maps.push((0.5 * (a + b), 2.0 / (b - a)));
            coef.extend(monomial(cheb).iter().rev());
        }
        breaks.push(hi);
        // Uniform lookup grid, four cells per segment on average.
        let cells = (4 * segments.len()).max(1);
        let inv_cell = cells as f64 / (hi - lo);
        let mut lookup = Vec::with_capacity(cells);
        let mut s = 0usize;
        for c in 0..cells {
            let x = lo + c as f64 / inv_cell;
            while s + 1 < segments.len() && breaks[s + 1] <= x {
                s += 1;
            }
            lookup.push(s as u32);
        }
        Ok(Piecewise {
            lo,
            hi,
            breaks,
            maps,
            coef,
            lookup,
            inv_cell,
            accuracy: noise.max(rel_tol),
        })
    }

    /// Estimated relative accuracy: the tolerance, or the worst tail of a segment accepted
    /// at the depth limit.
    pub fn accuracy(&self) -> f64 {
        self.accuracy
    }

    /// Number of segments.
    pub fn segments(&self) -> usize {
        self.maps.len()
    }

    /// The segment holding `x` (clamped into the interval) and the local variable in [-1, 1].
    #[inline(always)]
    fn locate(&self, x: f64) -> (usize, f64) {
        let x = x.clamp(self.lo, self.hi);
        let cell = (((x - self.lo) * self.inv_cell) as usize).min(self.lookup.len() - 1);
        let mut s = self.lookup[cell] as usize;
        let last = self.maps.len() - 1;
        while s < last && self.breaks[s + 1] <= x {
            s += 1;
        }
        let (c, inv) = self.maps[s];
        (s, (x - c) * inv)
    }

    /// Values of all functions at `x` (clamped into the interval).
    #[inline(always)]
    pub fn eval(&self, x: f64) -> [f64; NF] {
        let (s, t) = self.locate(x);
        let rows = &self.coef[s * NODES..(s + 1) * NODES];
        let mut acc = rows[0];
        for row in &rows[1..] {
            for k in 0..NF {
                acc[k] = acc[k] * t + row[k];
            }
        }
        acc
    }

    /// Values at four points at once. The four Horner recurrences are interleaved, so the
    /// processor overlaps their latencies (one point alone waits on every multiply-add).
    /// `FMA` selects fused multiply-adds: only for callers compiled with the `fma` target
    /// feature (elsewhere `mul_add` is a slow library call).
    #[inline(always)]
    pub fn eval4<const FMA: bool>(&self, x: [f64; 4]) -> [[f64; NF]; 4] {
        let loc = x.map(|xi| self.locate(xi));
        let mut acc: [[f64; NF]; 4] = std::array::from_fn(|p| self.coef[loc[p].0 * NODES]);
        for r in 1..NODES {
            for p in 0..4 {
                let row = &self.coef[loc[p].0 * NODES + r];
                let t = loc[p].1;
                for k in 0..NF {
                    acc[p][k] = if FMA {
                        acc[p][k].mul_add(t, row[k])
                    } else {
                        acc[p][k] * t + row[k]
                    };
                }
            }
        }
        acc
    }
}

/// Chebyshev coefficients (first-kind nodes) of f on [a, b]; row j holds c_j of every function.
fn chebyshev_coefficients<const NF: usize, F>(
    a: f64,
    b: f64,
    f: &mut F,
) -> Result<[[f64; NF]; NODES]>
where
    F: FnMut(f64) -> Result<[f64; NF]>,
{
    let mut vals = [[0.0; NF]; NODES];
    for (j, v) in vals.iter_mut().enumerate() {
        let x = (PI * (j as f64 + 0.5) / NODES as f64).cos();
        *v = f(0.5 * (a + b) + 0.5 * (b - a) * x)?;
    }
    let mut c = [[0.0; NF]; NODES];
    for (kk, ck) in c.iter_mut().enumerate() {
        for (j, v) in vals.iter().enumerate() {
            let w = (PI * kk as f64 * (j as f64 + 0.5) / NODES as f64).cos();
            for k in 0..NF {
                ck[k] += w * v[k];
            }
        }
        let norm = if kk == 0 { 1.0 } else { 2.0 } / NODES as f64;
        for v in ck.iter_mut() {
            *v *= norm;
        }
    }
    Ok(c)
}

/// Converts Chebyshev coefficients to monomial ones (row i = coefficient of x^i).
fn monomial<const NF: usize>(cheb: &[[f64; NF]; NODES]) -> [[f64; NF]; NODES] {
    // T_0 = 1, T_1 = x, T_{n+1} = 2x T_n - T_{n-1}, as monomial coefficient vectors.
    let mut t_prev = [0.0f64; NODES];
    let mut t_cur = [0.0f64; NODES];
    t_prev[0] = 1.0;
    t_cur[1] = 1.0;
    let mut out = [[0.0; NF]; NODES];
    for k in 0..NF {
        out[0][k] += cheb[0][k];
        out[1][k] += cheb[1][k];
    }
    for cheb_n in cheb.iter().skip(2) {
        let mut t_next = [0.0f64; NODES];
        for i in 0..NODES {
            let shifted = if i > 0 { 2.0 * t_cur[i - 1] } else { 0.0 };
            t_next[i] = shifted - t_prev[i];
        }
        for (i, &tn) in t_next.iter().enumerate() {
            if tn != 0.0 {
                for k in 0..NF {
                    out[i][k] += cheb_n[k] * tn;
                }
            }
        }
        t_prev = t_cur;
        t_cur = t_next;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_smooth_functions_to_round_off() {
        let p = Piecewise::<2>::build(0.0, 10.0, |x| Ok([x.sin(), (0.3 * x).exp()]), 1e-14, 20)
            .unwrap();
        for i in 0..=1000 {
            let x = 0.01 * i as f64;
            let v = p.eval(x);
            assert!((v[0] - x.sin()).abs() < 1e-14, "{x}");
            assert!((v[1] - (0.3 * x).exp()).abs() < 1e-14 * 20.0);
        }
    }

    #[test]
    fn refines_where_the_function_is_sharp() {
        let f = |x: f64| 1.0 / (1e-4 + x * x);
        let p = Piecewise::<1>::build(-1.0, 1.0, |x| Ok([f(x)]), 1e-13, 30).unwrap();
        assert!(p.segments() > 8);
        for i in 0..=2000 {
            let x = -1.0 + 1e-3 * i as f64;
            assert!((p.eval(x)[0] - f(x)).abs() < 1e-12 * 1e4);
        }
    }
}
