//! Classic fixed-step 4th-order Runge–Kutta method with cubic Hermite dense output.
//!
//! The "RK4" of Kutta (1901), Butcher tableau `c = (0, 1/2, 1/2, 1)`,
//! `b = (1/6, 1/3, 1/3, 1/6)`; see Hairer–Nørsett–Wanner, *Solving ODEs I*,
//! Sec. II.1. Global error `O(dt^4)`.
//!
//! Dense output: the cubic Hermite interpolant through the step's end points and
//! their derivatives `f(t0, y0)`, `f(t1, y1)`. It is 3rd-order accurate (local
//! interpolation error `O(dt^4)`, so it is as accurate as the steps themselves
//! globally), and continuous with a continuous first derivative across steps.
//! `f(t1, y1)` is reused as the next step's first stage, so a step costs 4
//! right-hand-side evaluations.
#![allow(clippy::needless_range_loop)] // index loops mirror the formulas

use std::ops::ControlFlow;

use super::{all_finite, Dense, IntegrateError, Observer, OdeSystem, Stats};

/// Settings of the fixed-step RK4 integrator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rk4 {
    /// Step size (> 0). The last step is shortened to land exactly on `t_end`.
    pub dt: f64,
}

/// Cubic Hermite dense output (3rd order) of one RK4 step.
#[derive(Clone, Copy, Debug)]
pub struct Rk4Dense<const N: usize> {
    /// Start of the step.
    pub t0: f64,
    /// End of the step.
    pub t1: f64,
    /// State at `t0`.
    pub y0: [f64; N],
    /// State at `t1`.
    pub y1: [f64; N],
    /// `f(t0, y0)`.
    pub f0: [f64; N],
    /// `f(t1, y1)`.
    pub f1: [f64; N],
}

impl<const N: usize> Dense<N> for Rk4Dense<N> {
    fn t0(&self) -> f64 {
        self.t0
    }

    fn t1(&self) -> f64 {
        self.t1
    }

    fn eval(&self, t: f64, out: &mut [f64; N]) {
        if t == self.t1 {
            *out = self.y1;
            return;
        }
        if t == self.t0 {
            *out = self.y0;
            return;
        }
        let h = self.t1 - self.t0;
        let s = (t - self.t0) / h;
        let s1 = 1.0 - s;
        let h00 = (1.0 + 2.0 * s) * s1 * s1;
        let h10 = s * s1 * s1 * h;
        let h01 = s * s * (3.0 - 2.0 * s);
        let h11 = -s * s * s1 * h;
        for i in 0..N {
            out[i] = h00 * self.y0[i] + h10 * self.f0[i] + h01 * self.y1[i] + h11 * self.f1[i];
        }
    }
}

impl Rk4 {
    /// RK4 with step size `dt`.
    pub fn new(dt: f64) -> Self {
        Self { dt }
    }

    /// One classic RK4 step of size `h` from `(t, y)` given `f0 = f(t, y)` (3 evaluations).
    pub fn step<const N: usize, S: OdeSystem<N> + ?Sized>(
        sys: &S,
        t: f64,
        y: &[f64; N],
        f0: &[f64; N],
        h: f64,
    ) -> [f64; N] {
        let mut ys = [0.0; N];
        let (mut k2, mut k3, mut k4) = ([0.0; N], [0.0; N], [0.0; N]);
        for i in 0..N {
            ys[i] = y[i] + 0.5 * h * f0[i];
        }
        sys.rhs(t + 0.5 * h, &ys, &mut k2);
        for i in 0..N {
            ys[i] = y[i] + 0.5 * h * k2[i];
        }
        sys.rhs(t + 0.5 * h, &ys, &mut k3);
        for i in 0..N {
            ys[i] = y[i] + h * k3[i];
        }
        sys.rhs(t + h, &ys, &mut k4);
        let mut y_new = [0.0; N];
        for i in 0..N {
            y_new[i] = y[i] + h / 6.0 * (f0[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
        }
        y_new
    }

    /// Integrates `sys` from `(t0, y0)` to `t_end` with fixed steps, reporting each step to `obs`.
    ///
    /// Step `k` ends at `t0 + (k + 1) * dt` (computed by multiplication, so no
    /// drift accumulates); the last step is shortened to land exactly on `t_end`
    /// (or stretched by at most `1e-9 * dt` to avoid a sliver step). Returns the
    /// final time and state (or the observer's stop point) and the [`Stats`]
    /// (`rejected` is always 0). `t_end == t0` returns `(t0, y0)`. Nothing is
    /// allocated.
    ///
    /// # Errors
    /// [`IntegrateError::NonFinite`] (with the time of the last finite state) if
    /// the state or the right-hand side becomes NaN or infinite. The other
    /// variants are never returned.
    ///
    /// # Panics
    /// If `dt` is not positive and finite, if `t0`/`t_end` are not finite or if
    /// `t_end < t0`.
    pub fn integrate<const N: usize, S, O>(
        &self,
        sys: &S,
        t0: f64,
        y0: [f64; N],
        t_end: f64,
        obs: &mut O,
    ) -> Result<(f64, [f64; N], Stats), IntegrateError>
    where
        S: OdeSystem<N> + ?Sized,
        O: Observer<N> + ?Sized,
    {
        assert!(
            self.dt > 0.0 && self.dt.is_finite(),
            "Rk4: dt must be positive and finite (dt = {})",
            self.dt
        );
        assert!(
            t0.is_finite() && t_end.is_finite(),
            "Rk4: t0 and t_end must be finite"
        );
        assert!(
            t_end >= t0,
            "Rk4: backward integration (t_end < t0) is not supported"
        );

        let mut stats = Stats::default();
        obs.start(t0, &y0);
        if t_end == t0 {
            return Ok((t0, y0, stats));
        }

        let n = (((t_end - t0) / self.dt) - 1e-9).ceil().max(1.0) as u64;
        let mut t = t0;
        let mut y = y0;
        let mut f = [0.0; N];
        sys.rhs(t, &y, &mut f);
        stats.rhs_evals += 1;
        if !all_finite(&y) || !all_finite(&f) {
            return Err(IntegrateError::NonFinite { t });
        }
        for k in 1..=n {
            let t_new = if k == n {
                t_end
            } else {
                t0 + k as f64 * self.dt
            };
            let mut y_new = Self::step(sys, t, &y, &f, t_new - t);
            // Project first, so f(t_new, .) (needed anyway as the next first stage and
            // for the Hermite interpolant) is taken at the projected state for free.
            sys.project(&mut y_new);
            let mut f_new = [0.0; N];
            sys.rhs(t_new, &y_new, &mut f_new);
            stats.rhs_evals += 4;
            if !all_finite(&y_new) || !all_finite(&f_new) {
                return Err(IntegrateError::NonFinite { t });
            }
            stats.steps += 1;
            let dense = Rk4Dense {
                t0: t,
                t1: t_new,
                y0: y,
                y1: y_new,
                f0: f,
                f1: f_new,
            };
            if let ControlFlow::Break(()) = obs.step(t_new, &y_new, &dense) {
                let (ts, ys) = obs.stop_point().unwrap_or((t_new, y_new));
                return Ok((ts, ys, stats));
            }
            t = t_new;
            y = y_new;
            f = f_new;
        }
        Ok((t, y, stats))
    }
}

/// Rk4 as a [`FixedScheme`](super::fixed::FixedScheme) on (y, t), so that it shares the
/// fixed-step driver (output at requested times by a partial step, like the symplectic
/// schemes).
pub struct Rk4Scheme<'a, S: ?Sized, const N: usize> {
    /// The system.
    pub sys: &'a S,
}

impl<S: OdeSystem<N> + ?Sized, const N: usize> super::fixed::FixedScheme for Rk4Scheme<'_, S, N> {
    type Y = ([f64; N], f64);
    fn step(&self, y: &mut ([f64; N], f64), h: f64) -> crate::error::Result<()> {
        let (y0, t) = *y;
        let mut f0 = [0.0; N];
        self.sys.rhs(t, &y0, &mut f0);
        let mut y1 = Rk4::step(self.sys, t, &y0, &f0, h);
        if y1.iter().any(|v| !v.is_finite()) {
            return Err(crate::error::KreiselError::Numerical(format!(
                "rk4: the state became non-finite at t = {}",
                t + h
            )));
        }
        self.sys.project(&mut y1);
        *y = (y1, t + h);
        Ok(())
    }
}
