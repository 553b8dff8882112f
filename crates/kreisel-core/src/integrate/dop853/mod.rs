//! DOP853: adaptive explicit Runge–Kutta method of order 8(5,3) with 7th-order dense output.
//!
//! The method of Dormand & Prince as described in E. Hairer, S. P. Nørsett,
//! G. Wanner, *Solving Ordinary Differential Equations I: Nonstiff Problems*,
//! 2nd ed., Springer 1993, Sec. II.5 (method, error estimation), Sec. II.6 (dense
//! output) and Sec. II.4 (step-size control, starting step), and implemented in
//! Hairer's Fortran code `dop853.f`. Coefficients: see [`coefficients`].
//!
//! * 12 stages per step, the last one being `f(t + h, y_new)` (first-same-as-last),
//!   so an accepted step costs 12 right-hand-side evaluations, a rejected one 11.
//!   [`OdeSystem::project`] is applied to an accepted state before that last
//!   stage is evaluated, so projection costs no extra evaluation.
//! * Error estimate combining the embedded 5th- and 3rd-order estimators as in
//!   `dop853.f` (and SciPy): with `sk_i = atol + rtol * max(|y_i|, |y_new_i|)`,
//!   `err5 = Σ (e5_i / sk_i)^2`, `err3 = Σ (e3_i / sk_i)^2`,
//!   `err = |h| * err5 / sqrt(N * (err5 + 0.01 * err3))`; a step is accepted when
//!   `err <= 1`. The sums run over the first [`OdeSystem::controlled`] components (all
//!   `N` unless a system says otherwise), and `N` is their number.
//! * Step-size control of `dop853.f` with its default parameters: new step
//!   `h * clamp(0.9 * err^(-1/8), 1/3, 6)`, no increase right after a rejection,
//!   never larger than `h_max`. (SciPy uses the factor limits 0.2..10 instead.)
//! * Starting step by Hairer's `hinit` (Sec. II.4) unless `h_init` is given.
//! * Dense output of order 7 (local error `O(h^8)`) from three extra stages. They
//!   are evaluated lazily, only when an observer actually evaluates the dense
//!   output inside a step (3 extra right-hand-side evaluations for that step).
//! * Non-finite trial values (NaN/inf in a stage or in the new state) reject the
//!   step and shrink it by 1/3; if that reaches the minimal step size the run ends
//!   with [`IntegrateError::NonFinite`].
#![allow(clippy::needless_range_loop)] // index loops mirror the Butcher-tableau formulas

pub mod coefficients;

use std::cell::{Cell, RefCell};
use std::ops::ControlFlow;

use self::coefficients as co;
use super::{
    all_finite, fmadd, initial_step, scaled, Dense, IntegrateError, Observer, OdeSystem, Stats,
};

/// Safety factor of the step-size controller (`dop853.f`: `SAFE`).
const SAFETY: f64 = 0.9;
/// Smallest step-size ratio `h_new / h` (`dop853.f`: `FAC1`).
const FAC_MIN: f64 = 1.0 / 3.0;
/// Largest step-size ratio `h_new / h` (`dop853.f`: `FAC2`).
const FAC_MAX: f64 = 6.0;
/// Exponent of the controller, `1 / (q + 1)` with error-estimator order `q = 7`.
const ERR_EXPONENT: f64 = 1.0 / 8.0;

/// Weights `bhh = b - E3` of the embedded 3rd-order solution: nonzero at stages 0, 8 and 11
/// only, so the 3rd-order estimate is the 8th-order combination less three terms (`dop853.f`).
const BHH: [f64; 12] = {
    let mut bhh = [0.0; 12];
    let mut j = 0;
    while j < 12 {
        bhh[j] = co::B[j] - co::E3[j];
        j += 1;
    }
    bhh
};

// `attempt` starts every linear combination of stages with stage 0: its weight is nonzero.
const _: () = {
    let mut s = 1;
    while s < 12 {
        assert!(co::A[s][0] != 0.0);
        s += 1;
    }
    assert!(co::B[0] != 0.0 && co::E5[0] != 0.0 && BHH[0] != 0.0);
};

/// Settings of the adaptive DOP853 integrator (Hairer–Nørsett–Wanner).
///
/// Tolerances are scalar: the local error of component `i` is kept below
/// `atol + rtol * |y_i|` (in the RMS-like norm of `dop853.f`). Use `atol > 0`
/// for components that pass through zero.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dop853 {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
    /// First step size; `None` selects it with Hairer's `hinit` heuristic.
    pub h_init: Option<f64>,
    /// Largest first step (`f64::INFINITY` for no limit): caps `h_init` or the heuristic's
    /// choice, for a caller that knows the motion turns sooner than the heuristic's two
    /// evaluations show (a sliding contact whose slip stops within the first step).
    pub h_first_max: f64,
    /// Largest step size (`f64::INFINITY` for no limit; never more than `t_end - t0`).
    pub h_max: f64,
    /// Largest number of step attempts (accepted + rejected), like `NMAX` of `dop853.f`.
    pub max_steps: u64,
    /// Stop where the problem has become stiff: after [`STIFF_STEPS`] accepted steps in a
    /// row whose estimate of `h |lambda|` (the test of `dop853.f`, below) exceeds this
    /// bound, the integration returns at the last step's end with [`Stats::stiff_stops`]
    /// set, for the caller to go on with an implicit method. `None`: never stop.
    ///
    /// The estimate: `h |f(t + h, y_new) - f(t + h, Y_12)| / |y_new - Y_12|`, with `Y_12` the
    /// last stage's value (at `t + h` too), a Lipschitz constant along the direction the
    /// solution's error takes; where it stays near the stability boundary (about 6 on the
    /// negative real axis), stability, not accuracy, sets the steps.
    pub stiff_stop: Option<f64>,
}

/// Accepted steps in a row with `h |lambda|` over [`Dop853::stiff_stop`] that make a problem
/// stiff (`dop853.f` reports stiffness after 15).
pub const STIFF_STEPS: u32 = 15;

impl Default for Dop853 {
    /// `rtol = 1e-8`, `atol = 1e-10`, automatic first step, no `h_max`, `max_steps = 100_000`.
    fn default() -> Self {
        Self {
            rtol: 1e-8,
            atol: 1e-10,
            h_init: None,
            h_first_max: f64::INFINITY,
            h_max: f64::INFINITY,
            max_steps: 100_000,
            stiff_stop: None,
        }
    }
}

/// Work arrays of one DOP853 step, and the dense output of the last step taken.
///
/// Holds the 13 stages (`12` method stages plus `f(t1, y1)`), the step's end
/// points and the lazily computed dense-output coefficients; about `25 * N`
/// floats. [`Dop853::integrate`] keeps one on its stack; [`Dop853::step`] takes one
/// from the caller.
#[derive(Clone, Debug)]
pub struct Dop853Work<const N: usize> {
    k: [[f64; N]; 13],
    /// The last stage's value `Y_12` (at `t + h`) of the last attempt: the stiffness test.
    y12: [f64; N],
    t0: f64,
    t1: f64,
    h: f64,
    y0: [f64; N],
    y1: [f64; N],
    cache: RefCell<DenseCache<N>>,
    dense_evals: Cell<u64>,
}

#[derive(Clone, Debug)]
struct DenseCache<const N: usize> {
    valid: bool,
    /// Extra stages 13, 14, 15.
    kx: [[f64; N]; 3],
    /// Coefficients of the interpolating polynomial (`F` of SciPy, `CONT` of `dop853.f`).
    f: [[f64; N]; 7],
}

impl<const N: usize> Default for Dop853Work<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Dop853Work<N> {
    /// Zeroed work arrays.
    pub fn new() -> Self {
        Self {
            k: [[0.0; N]; 13],
            y12: [0.0; N],
            t0: 0.0,
            t1: 0.0,
            h: 0.0,
            y0: [0.0; N],
            y1: [0.0; N],
            cache: RefCell::new(DenseCache {
                valid: false,
                kx: [[0.0; N]; 3],
                f: [[0.0; N]; 7],
            }),
            dense_evals: Cell::new(0),
        }
    }

    /// Dense output over the last step taken with this work struct.
    ///
    /// `sys` must be the system that step was taken for: the first evaluation
    /// inside the step computes the three extra stages with it.
    pub fn dense<'a, S: OdeSystem<N> + ?Sized>(&'a self, sys: &'a S) -> Dop853Dense<'a, N, S> {
        Dop853Dense { work: self, sys }
    }

    /// Right-hand-side evaluations spent on dense output since the last call.
    pub fn take_dense_evals(&self) -> u64 {
        self.dense_evals.take()
    }

    fn set_step(&mut self, t0: f64, t1: f64, h: f64, y0: &[f64; N], y1: &[f64; N]) {
        self.t0 = t0;
        self.t1 = t1;
        self.h = h;
        self.y0 = *y0;
        self.y1 = *y1;
        self.cache.get_mut().valid = false;
    }

    /// Computes the extra stages and the interpolation coefficients (`dop853.f`, `CONTD8` setup).
    fn fill_dense<S: OdeSystem<N> + ?Sized>(&self, sys: &S, c: &mut DenseCache<N>) {
        let h = self.h;
        for s in 13..16 {
            let mut ys = [0.0; N];
            for i in 0..N {
                let mut acc = 0.0;
                for j in 0..s {
                    let kj = if j < 13 {
                        self.k[j][i]
                    } else {
                        c.kx[j - 13][i]
                    };
                    acc += co::A[s][j] * kj;
                }
                ys[i] = self.y0[i] + h * acc;
            }
            let mut ks = [0.0; N];
            sys.rhs(self.t0 + co::C[s] * h, &ys, &mut ks);
            c.kx[s - 13] = ks;
        }
        self.dense_evals.set(self.dense_evals.get() + 3);
        let (f0, f1) = (&self.k[0], &self.k[12]);
        for i in 0..N {
            let dy = self.y1[i] - self.y0[i];
            let bspl = h * f0[i] - dy;
            c.f[0][i] = dy;
            c.f[1][i] = bspl;
            c.f[2][i] = dy - h * f1[i] - bspl;
        }
        for r in 0..4 {
            let mut acc = [0.0; N];
            for (j, &d) in co::D[r].iter().enumerate() {
                if d == 0.0 {
                    continue;
                }
                let kj = if j < 13 { &self.k[j] } else { &c.kx[j - 13] };
                for i in 0..N {
                    acc[i] = fmadd(d, kj[i], acc[i]);
                }
            }
            for i in 0..N {
                c.f[3 + r][i] = h * acc[i];
            }
        }
        c.valid = true;
    }
}

/// Dense output (7th order) of one DOP853 step; see [`Dop853Work::dense`].
pub struct Dop853Dense<'a, const N: usize, S: OdeSystem<N> + ?Sized> {
    work: &'a Dop853Work<N>,
    sys: &'a S,
}

impl<const N: usize, S: OdeSystem<N> + ?Sized> Dense<N> for Dop853Dense<'_, N, S> {
    fn t0(&self) -> f64 {
        self.work.t0
    }

    fn t1(&self) -> f64 {
        self.work.t1
    }

    /// Evaluates the 7th-degree interpolant of `dop853.f` (`CONTD8`).
    fn eval(&self, t: f64, out: &mut [f64; N]) {
        let w = self.work;
        if t == w.t1 {
            *out = w.y1;
            return;
        }
        if t == w.t0 {
            *out = w.y0;
            return;
        }
        let mut c = w.cache.borrow_mut();
        if !c.valid {
            w.fill_dense(self.sys, &mut c);
        }
        let s = (t - w.t0) / w.h;
        let s1 = 1.0 - s;
        let f = &c.f;
        // y0 + s (F0 + s1 (F1 + s (F2 + s1 (F3 + s (F4 + s1 (F5 + s F6)))))), s1 = 1 - s.
        for i in 0..N {
            let par = f[3][i] + s * (f[4][i] + s1 * (f[5][i] + s * f[6][i]));
            out[i] = w.y0[i] + s * (f[0][i] + s1 * (f[1][i] + s * (f[2][i] + s1 * par)));
        }
    }
}

impl Dop853 {
    /// Settings with the given tolerances and the defaults of [`Dop853::default`] otherwise.
    pub fn new(rtol: f64, atol: f64) -> Self {
        Self {
            rtol,
            atol,
            ..Self::default()
        }
    }

    fn check_tolerances(&self) {
        assert!(
            self.rtol >= 0.0 && self.atol >= 0.0 && (self.rtol > 0.0 || self.atol > 0.0),
            "Dop853: tolerances must be >= 0 and not both zero (rtol = {}, atol = {})",
            self.rtol,
            self.atol
        );
    }

    /// Integrates `sys` from `(t0, y0)` to `t_end`, reporting every accepted step to `obs`.
    ///
    /// Returns the final time and state (`t_end`, or the stop point of the
    /// observer if it broke off) and the run's [`Stats`]. `t_end == t0` returns
    /// `(t0, y0)` after calling `obs.start`. The last step is adjusted to land
    /// exactly on `t_end` (a step is stretched by up to 1 % to reach it, as in
    /// `dop853.f`, but never beyond `h_max`). Nothing is allocated; the work arrays live on the stack
    /// (about `25 * N` floats).
    ///
    /// # Errors
    /// [`IntegrateError::NonFinite`] if `y0` or `f(t0, y0)` is not finite, or if
    /// non-finite trial values persist down to the minimal step;
    /// [`IntegrateError::StepSizeTooSmall`] if the step size falls below
    /// `10 * f64::EPSILON * |t|`; [`IntegrateError::TooManySteps`] after
    /// `max_steps` step attempts.
    ///
    /// # Panics
    /// If `t0` or `t_end` is not finite, if `t_end < t0` (backward integration is
    /// not supported) or if the tolerances are negative or both zero.
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
        #[cfg(target_arch = "x86_64")]
        if avx() {
            // SAFETY: the CPU supports the feature the function is compiled for.
            return unsafe { self.integrate_avx(sys, t0, y0, t_end, obs) };
        }
        self.integrate_with(sys, t0, y0, t_end, obs)
    }

    /// [`Dop853::integrate`] compiled for AVX: the stage combinations take four components
    /// per instruction instead of two. The same operations in the same order (AVX brings no
    /// fused multiply-add), so the same results bit for bit.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn integrate_avx<const N: usize, S, O>(
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
        self.integrate_with(sys, t0, y0, t_end, obs)
    }

    /// The body of [`Dop853::integrate`], inlined into each instruction-set version.
    #[inline(always)]
    pub(crate) fn integrate_with<const N: usize, S, O>(
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
            t0.is_finite() && t_end.is_finite(),
            "Dop853: t0 and t_end must be finite"
        );
        assert!(
            t_end >= t0,
            "Dop853: backward integration (t_end < t0) is not supported"
        );
        self.check_tolerances();

        let mut stats = Stats::default();
        obs.start(t0, &y0);
        if t_end == t0 {
            return Ok((t0, y0, stats));
        }

        let mut work = Dop853Work::<N>::new();
        let mut t = t0;
        let mut y = y0;
        sys.rhs(t, &y, &mut work.k[0]);
        stats.rhs_evals += 1;
        if !all_finite(&y) || !all_finite(&work.k[0]) {
            return Err(IntegrateError::NonFinite { t });
        }

        let span = t_end - t0;
        let h_max = if self.h_max > 0.0 {
            self.h_max.min(span)
        } else {
            span
        };
        let mut h = match self.h_init {
            Some(h) if h > 0.0 && h.is_finite() => h.min(h_max),
            _ => initial_step(
                sys,
                t,
                &y,
                &work.k[0],
                h_max,
                (self.rtol, self.atol),
                ERR_EXPONENT,
                &mut stats,
            ),
        }
        .min(self.h_first_max);

        let mut rejected_last = false;
        let mut nonfinite_last = false;
        let mut stiff_run = 0u32;
        loop {
            let attempts = stats.steps + stats.rejected;
            if attempts >= self.max_steps {
                return Err(IntegrateError::TooManySteps { t, steps: attempts });
            }
            if h.is_nan() || h <= 10.0 * f64::EPSILON * t.abs() {
                return Err(if nonfinite_last {
                    IntegrateError::NonFinite { t }
                } else {
                    IntegrateError::StepSizeTooSmall { t, h }
                });
            }
            // Stretch the step by up to 1 % to land on t_end (dop853.f), but never beyond h_max.
            let last = t_end - t <= (1.01 * h).min(h_max);
            let (h_step, t_new) = if last { (t_end - t, t_end) } else { (h, t + h) };

            let (mut y_new, err, finite) =
                self.attempt(sys, t, &y, h_step, &mut work.k, &mut work.y12);
            stats.rhs_evals += 11;
            if !finite {
                stats.rejected += 1;
                rejected_last = true;
                nonfinite_last = true;
                h = h_step * FAC_MIN;
                continue;
            }
            nonfinite_last = false;

            // err^(1/8) by three square roots: a pow call per step costs more than a stage.
            let fac11 = err.sqrt().sqrt().sqrt();
            if err > 1.0 {
                // Rejected: shrink by at most FAC_MIN.
                stats.rejected += 1;
                rejected_last = true;
                h = h_step / (fac11 / SAFETY).min(1.0 / FAC_MIN);
                continue;
            }

            // Accepted: project, then evaluate f at the (projected) new state. This
            // last stage is not needed by the error estimate, so, as in dop853.f, it
            // is only computed for accepted steps.
            sys.project(&mut y_new);
            sys.rhs(t_new, &y_new, &mut work.k[12]);
            stats.rhs_evals += 1;
            if !all_finite(&y_new) || !all_finite(&work.k[12]) {
                stats.rejected += 1;
                rejected_last = true;
                nonfinite_last = true;
                h = h_step * FAC_MIN;
                continue;
            }
            let fac = (fac11 / SAFETY).clamp(1.0 / FAC_MAX, 1.0 / FAC_MIN);
            let mut h_new = (h_step / fac).min(h_max);
            if rejected_last {
                h_new = h_new.min(h_step);
            }
            rejected_last = false;

            work.set_step(t, t_new, h_step, &y, &y_new);
            stats.steps += 1;
            let flow = obs.step(t_new, &y_new, &work.dense(sys));
            stats.rhs_evals += work.take_dense_evals();
            if let ControlFlow::Break(()) = flow {
                let (ts, ys) = obs.stop_point().unwrap_or((t_new, y_new));
                return Ok((ts, ys, stats));
            }
            if last {
                return Ok((t_new, y_new, stats));
            }
            if let Some(bound) = self.stiff_stop {
                let (mut num, mut den) = (0.0, 0.0);
                for i in 0..N {
                    num += (work.k[12][i] - work.k[11][i]).powi(2);
                    den += (y_new[i] - work.y12[i]).powi(2);
                }
                if den > 0.0 && h_step * (num / den).sqrt() > bound {
                    stiff_run += 1;
                    if stiff_run >= STIFF_STEPS {
                        stats.stiff_stops += 1;
                        return Ok((t_new, y_new, stats));
                    }
                } else {
                    stiff_run = 0;
                }
            }
            work.k[0] = work.k[12];
            t = t_new;
            y = y_new;
            h = h_new;
        }
    }

    /// Takes one DOP853 step of size `h` from `(t, y)`, without step-size control or projection.
    ///
    /// Evaluates `f(t, y)` itself (13 right-hand-side evaluations in total) and
    /// returns the 8th-order solution at `t + h` and the scaled error norm
    /// (`<= 1` means the step would be accepted under `self.rtol`/`self.atol`; it
    /// is NaN or infinite if the trial values were not finite). Afterwards
    /// `work.dense(sys)` is the 7th-order dense output over `[t, t + h]`. Use this
    /// to run DOP853 with a fixed step.
    pub fn step<const N: usize, S: OdeSystem<N> + ?Sized>(
        &self,
        sys: &S,
        t: f64,
        y: &[f64; N],
        h: f64,
        work: &mut Dop853Work<N>,
    ) -> ([f64; N], f64) {
        sys.rhs(t, y, &mut work.k[0]);
        let t_new = t + h;
        let (y_new, err, finite) = self.attempt(sys, t, y, h, &mut work.k, &mut work.y12);
        sys.rhs(t_new, &y_new, &mut work.k[12]);
        work.set_step(t, t_new, h, y, &y_new);
        let finite = finite && all_finite(&work.k[12]);
        (y_new, if finite { err } else { f64::NAN })
    }

    /// Stages 1..12 from `k[0] = f(t, y)`: returns `(y_new, err, all_finite)`.
    ///
    /// Does not evaluate the FSAL stage `k[12] = f(t + h, y_new)`. Always inlined, so that
    /// it is compiled for the instruction set of its caller.
    #[inline(always)]
    fn attempt<const N: usize, S: OdeSystem<N> + ?Sized>(
        &self,
        sys: &S,
        t: f64,
        y: &[f64; N],
        h: f64,
        k: &mut [[f64; N]; 13],
        y12: &mut [f64; N],
    ) -> ([f64; N], f64, bool) {
        let mut finite = all_finite(&k[0]);
        let mut ys = [0.0; N];
        // Linear combinations written out term by term (the macro lists the stage indices):
        // each coefficient is a constant, so zero terms vanish at compile time.
        // The first term initialises the sum (every combination here has a nonzero weight
        // for stage 0): `0.0 + x` is not `x` in IEEE arithmetic, so it would cost an addition.
        macro_rules! combo {
            ($coef:expr; $first:literal $($j:literal)*) => {{
                let c0: f64 = $coef[$first];
                let mut acc = [0.0f64; N];
                for i in 0..N {
                    acc[i] = c0 * k[$first][i];
                }
                $(
                    let cj: f64 = $coef[$j];
                    if cj != 0.0 {
                        for i in 0..N {
                            acc[i] = fmadd(cj, k[$j][i], acc[i]);
                        }
                    }
                )*
                acc
            }};
        }
        macro_rules! stage {
            ($s:literal; $($j:literal)*) => {{
                let acc = combo!(co::A[$s]; $($j)*);
                for i in 0..N {
                    ys[i] = fmadd(h, acc[i], y[i]);
                }
                // No finiteness check per stage: every stage feeds y_new or the error
                // estimate, which are checked below (a NaN there rejects the step).
                sys.rhs(t + co::C[$s] * h, &ys, &mut k[$s]);
            }};
        }
        stage!(1; 0);
        stage!(2; 0 1);
        stage!(3; 0 1 2);
        stage!(4; 0 1 2 3);
        stage!(5; 0 1 2 3 4);
        stage!(6; 0 1 2 3 4 5);
        stage!(7; 0 1 2 3 4 5 6);
        stage!(8; 0 1 2 3 4 5 6 7);
        stage!(9; 0 1 2 3 4 5 6 7 8);
        stage!(10; 0 1 2 3 4 5 6 7 8 9);
        stage!(11; 0 1 2 3 4 5 6 7 8 9 10);
        *y12 = ys;
        let acc = combo!(co::B; 0 1 2 3 4 5 6 7 8 9 10 11);
        let e5 = combo!(co::E5; 0 1 2 3 4 5 6 7 8 9 10 11);
        let bhh = combo!(BHH; 0 1 2 3 4 5 6 7 8 9 10 11);
        let mut y_new = [0.0; N];
        let mut e3 = [0.0; N];
        for i in 0..N {
            y_new[i] = fmadd(h, acc[i], y[i]);
            e3[i] = acc[i] - bhh[i];
        }
        finite &= all_finite(&y_new);

        let (mut err5, mut err3) = (0.0, 0.0);
        let floor = sys.magnitude_floor();
        let nc = sys.controlled().min(N);
        for i in 0..nc {
            let sk = self.atol + self.rtol * y[i].abs().max(y_new[i].abs()).max(floor[i]);
            err5 += scaled(e5[i], sk).powi(2);
            err3 += scaled(e3[i], sk).powi(2);
        }
        let mut deno = err5 + 0.01 * err3;
        if deno <= 0.0 {
            deno = 1.0;
        }
        // err is +inf (reject, shrink) if a zero scale meets a nonzero error estimate.
        let mut err = h.abs() * err5 / (nc as f64 * deno).sqrt();
        if err.is_nan() {
            err = f64::INFINITY;
        }
        (y_new, err, finite)
    }
}

/// Whether the AVX build of the integrator runs: where the CPU has AVX, unless the
/// environment variable `KREISEL_NO_AVX` is set when it is first asked (instruction counts
/// under valgrind, whose decoder lacks some of the AVX instructions the compiler emits).
#[cfg(target_arch = "x86_64")]
fn avx() -> bool {
    static AVX: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *AVX.get_or_init(|| {
        std::arch::is_x86_feature_detected!("avx") && std::env::var_os("KREISEL_NO_AVX").is_none()
    })
}
