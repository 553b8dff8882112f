//! Implicit symplectic Runge-Kutta methods: the implicit midpoint rule (order 2) and the
//! 2-stage Gauss-Legendre method (order 4), for any [`OdeSystem`].
//!
//! Both keep every quadratic invariant of the system exactly (up to the solver tolerance);
//! for a heavy top written in (q, M) these are |q| and the energy, since Gamma = q* ez q is
//! quadratic in q (E. Hairer, C. Lubich, G. Wanner, Geometric Numerical Integration, IV.2). The stage
//! equations are solved by fixed-point iteration to round-off; a step too large for it to
//! converge is reported, not silently accepted.

use super::fixed::FixedScheme;
use super::OdeSystem;
use crate::error::{KreiselError, Result};

const MAX_ITER: usize = 200;

fn converged<const N: usize>(a: &[f64; N], b: &[f64; N]) -> bool {
    a.iter()
        .zip(b)
        .all(|(x, y)| (x - y).abs() <= 4.0 * f64::EPSILON * x.abs().max(y.abs()).max(1e-300))
}

fn no_convergence(h: f64) -> KreiselError {
    KreiselError::Numerical(format!(
        "the implicit stage equations did not converge with step {h}; reduce dt"
    ))
}

/// The implicit midpoint rule `y1 = y0 + h f(t + h/2, (y0 + y1)/2)`.
pub struct Midpoint<'a, S, const N: usize> {
    /// The system.
    pub sys: &'a S,
}

impl<const N: usize, S: OdeSystem<N>> FixedScheme for Midpoint<'_, S, N> {
    type Y = ([f64; N], f64);
    fn step(&self, y: &mut ([f64; N], f64), h: f64) -> Result<()> {
        let (y0, t) = *y;
        let mut k = [0.0; N];
        self.sys.rhs(t, &y0, &mut k);
        let mut stage = [0.0; N];
        let mut ok = false;
        let mut last = 0.0;
        for it in 0..MAX_ITER {
            for i in 0..N {
                stage[i] = y0[i] + 0.5 * h * k[i];
            }
            let mut k_new = [0.0; N];
            self.sys.rhs(t + 0.5 * h, &stage, &mut k_new);
            let diff: f64 = k_new.iter().zip(&k).map(|(a, b)| (a - b).abs()).sum();
            let done = converged(&k_new, &k) || (it > 2 && diff >= last && diff < 1e-10);
            last = diff;
            k = k_new;
            if done {
                ok = true;
                break;
            }
        }
        if !ok {
            return Err(no_convergence(h));
        }
        let mut y1 = [0.0; N];
        for i in 0..N {
            y1[i] = y0[i] + h * k[i];
        }
        self.sys.project(&mut y1);
        *y = (y1, t + h);
        Ok(())
    }
}

/// The 2-stage Gauss-Legendre collocation method (order 4).
pub struct Gauss4<'a, S, const N: usize> {
    /// The system.
    pub sys: &'a S,
}

impl<const N: usize, S: OdeSystem<N>> FixedScheme for Gauss4<'_, S, N> {
    type Y = ([f64; N], f64);
    fn step(&self, y: &mut ([f64; N], f64), h: f64) -> Result<()> {
        let r = 3f64.sqrt() / 6.0;
        let a = [[0.25, 0.25 - r], [0.25 + r, 0.25]];
        let c = [0.5 - r, 0.5 + r];
        let (y0, t) = *y;
        let mut k = [[0.0; N]; 2];
        self.sys.rhs(t, &y0, &mut k[0]);
        k[1] = k[0];
        let mut ok = false;
        let mut last = f64::INFINITY;
        for it in 0..MAX_ITER {
            let mut k_new = [[0.0; N]; 2];
            for s in 0..2 {
                let mut stage = [0.0; N];
                for i in 0..N {
                    stage[i] = y0[i] + h * (a[s][0] * k[0][i] + a[s][1] * k[1][i]);
                }
                self.sys.rhs(t + c[s] * h, &stage, &mut k_new[s]);
            }
            let diff: f64 = (0..2)
                .map(|s| {
                    k_new[s]
                        .iter()
                        .zip(&k[s])
                        .map(|(a, b)| (a - b).abs())
                        .sum::<f64>()
                })
                .sum();
            let done = (converged(&k_new[0], &k[0]) && converged(&k_new[1], &k[1]))
                || (it > 2 && diff >= last && diff < 1e-10);
            last = diff;
            k = k_new;
            if done {
                ok = true;
                break;
            }
        }
        if !ok {
            return Err(no_convergence(h));
        }
        let mut y1 = [0.0; N];
        for i in 0..N {
            y1[i] = y0[i] + 0.5 * h * (k[0][i] + k[1][i]);
        }
        self.sys.project(&mut y1);
        *y = (y1, t + h);
        Ok(())
    }
}
