//! General-purpose ODE integrators for fixed-size first-order systems `y' = f(t, y)`.
//!
//! The state is a stack array `[f64; N]`; no integrator allocates inside its step
//! loop (all work arrays are `[f64; N]` on the stack or in a preallocated work
//! struct). Three integrators share one interface:
//!
//! * [`Dop853`]: the adaptive explicit Runge–Kutta method of order 8 with embedded
//!   5th- and 3rd-order error estimators and a 7th-order continuous extension
//!   (Dormand & Prince; E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary
//!   Differential Equations I*, 2nd ed., Springer 1993, Sec. II.5/II.6; Hairer's
//!   `dop853.f`).
//! * [`Radau5`]: the adaptive implicit Radau IIA method of order 5 (3 stages) for stiff
//!   systems, with a collocation-polynomial dense output (E. Hairer, G. Wanner, *Solving
//!   Ordinary Differential Equations II*, 2nd ed., Springer 1996, Sec. IV.8). Same
//!   interface as [`Dop853`].
//! * [`Rk4`]: the classic fixed-step 4th-order Runge–Kutta method with a cubic
//!   Hermite dense output (3rd order).
//!
//! The structure-preserving schemes of the tops live beside them: [`splitting`]
//! (explicit Lie-Poisson splitting of heavy tops, orders 2, 4, 6), [`verlet`]
//! (Stoermer-Verlet on the Euler-angle Hamiltonian), [`implicit`] (implicit midpoint and
//! 2-stage Gauss-Legendre), all driven by [`fixed`].
//!
//! They drive an [`Observer`] that sees every accepted step together with a
//! [`Dense`] interpolant over it. Ready-made observers: [`SampleAt`] (values at
//! prescribed times), [`EveryStep`] (every accepted step), [`NullObserver`],
//! [`FnObserver`] (a closure), and event location with [`Locator`] /
//! [`WithEvents`] (see [`events`]).
//!
//! Scope: forward integration only (`t_end >= t0`; `t_end == t0` returns the
//! initial state), scalar tolerances. The drivers allocate nothing; among the
//! observers, [`SampleAt`] allocates its output once at construction, while
//! [`EveryStep`] and [`Locator::events`] grow with the number of steps/events
//! (reserve them to avoid reallocation).
//!
//! ```
//! use kreisel_core::integrate::{Dop853, FnSystem, SampleAt};
//!
//! // Harmonic oscillator x'' = -x.
//! let sys = FnSystem(|_t: f64, y: &[f64; 2], dy: &mut [f64; 2]| {
//!     dy[0] = y[1];
//!     dy[1] = -y[0];
//! });
//! let times = [0.0, 1.0, 2.0];
//! let mut samples = SampleAt::new(&times);
//! let (t, y, stats) = Dop853::new(1e-10, 1e-10)
//!     .integrate(&sys, 0.0, [0.0, 1.0], 2.0, &mut samples)
//!     .unwrap();
//! assert_eq!(t, 2.0);
//! assert!((y[0] - 2f64.sin()).abs() < 1e-9);
//! assert!((samples.out[1][0] - 1f64.sin()).abs() < 1e-9);
//! assert!(stats.steps > 0);
//! ```

pub(crate) use crate::fmadd;
use std::fmt;
use std::ops::ControlFlow;

pub mod dop853;
pub mod events;
pub mod fixed;
pub mod implicit;
pub mod radau5;
pub mod rk4;

pub use dop853::{Dop853, Dop853Dense, Dop853Work, STIFF_STEPS};
pub use events::{Event, EventFn, EventSpec, Locator, WithEvents};
pub use radau5::{Radau5, Radau5Dense};
pub use rk4::{Rk4, Rk4Dense};

/// A first-order system `y' = f(t, y)` of fixed dimension `N`.
pub trait OdeSystem<const N: usize> {
    /// Writes `f(t, y)` into `dy`.
    ///
    /// Every entry of `dy` must be written. Non-finite values are detected by the
    /// integrators and reported as [`IntegrateError::NonFinite`].
    fn rhs(&self, t: f64, y: &[f64; N], dy: &mut [f64; N]);

    /// Called on every accepted step's new state (e.g. to renormalise a quaternion). Default: nothing.
    ///
    /// The integrators project an accepted state before evaluating `f` there, so
    /// the next step and the dense output start from the projected state at no
    /// extra cost; the dense output of a step ends exactly at the projected state
    /// (it is continuous across steps), and its order is unaffected as long as the
    /// projection moves the state by no more than the local error. The initial
    /// state is not projected.
    fn project(&self, _y: &mut [f64; N]) {}

    /// The magnitude below which each component's error is measured as if it had that
    /// magnitude: the adaptive integrators' error scale of component i is
    /// `atol + rtol * max(|y_i|, floor_i)` (default: all 0, the plain `atol + rtol |y_i|`).
    /// For a quadrature carried along (a work, a dissipated energy) that starts at 0 and
    /// crosses it, the floor is the size it is measured against (an energy scale): else its
    /// absolute tolerance near 0 would set the steps.
    #[inline(always)]
    fn magnitude_floor(&self) -> [f64; N] {
        [0.0; N]
    }

    /// The components no right-hand side depends on (`true`: a quadrature carried along, a
    /// position the equations do not see): their columns of the Jacobian vanish, and
    /// [`Radau5`] factorises its Newton matrices without them, solving for them afterwards
    /// by substitution. Default: none.
    #[inline(always)]
    fn passive(&self) -> [bool; N] {
        [false; N]
    }

    /// How many leading components the adaptive integrators' error estimate (and their
    /// starting step) measures: the others are carried along with the steps those choose
    /// (forward sensitivities riding on a trajectory). Default: all `N`.
    #[inline(always)]
    fn controlled(&self) -> usize {
        N
    }

    /// The Jacobian `jac[i][j] = d f_i / d y_j` at `(t, y)`, for the implicit integrator
    /// [`Radau5`]: write every entry and return `true`, or return `false` (the default) to
    /// have it approximated by forward differences of [`OdeSystem::rhs`] (`N` evaluations).
    /// The explicit integrators never call it.
    #[inline(always)]
    fn jacobian(&self, _t: f64, _y: &[f64; N], _jac: &mut [[f64; N]; N]) -> bool {
        false
    }
}

/// An [`OdeSystem`] given by a closure `|t, y, dy| ...` (no projection).
#[derive(Clone, Copy, Debug)]
pub struct FnSystem<F>(pub F);

impl<const N: usize, F> OdeSystem<N> for FnSystem<F>
where
    F: Fn(f64, &[f64; N], &mut [f64; N]),
{
    fn rhs(&self, t: f64, y: &[f64; N], dy: &mut [f64; N]) {
        (self.0)(t, y, dy)
    }
}

/// Dense output over one accepted step [t0, t0 + h]: evaluate the interpolant at any t in it.
///
/// `eval(t0())` returns the step's initial state and `eval(t1())` its final
/// (accepted, projected) state bit-exactly. Evaluating outside `[t0, t1]`
/// extrapolates the polynomial and is not meaningful.
pub trait Dense<const N: usize> {
    /// Start of the step.
    fn t0(&self) -> f64;
    /// End of the step.
    fn t1(&self) -> f64;
    /// Writes the interpolated state at `t` into `out`.
    fn eval(&self, t: f64, out: &mut [f64; N]);
}

/// What the driver reports to its caller after each accepted step (no allocation per step).
///
/// The drivers call [`Observer::start`] once with the initial state, then
/// [`Observer::step`] after every accepted step. When `step` returns
/// `ControlFlow::Break(())` the driver stops and asks [`Observer::stop_point`]
/// for the state to return (default: the end of that step).
pub trait Observer<const N: usize> {
    /// `dense` covers [t_prev, t]; return ControlFlow::Break(()) to stop the integration at t.
    ///
    /// `y` is the accepted (projected) state at `t`; `dense.eval(t)` equals it.
    fn step(&mut self, t: f64, y: &[f64; N], dense: &dyn Dense<N>) -> ControlFlow<()>;

    /// Called once before the first step with the initial state (also when
    /// `t_end == t0`). Default: nothing.
    fn start(&mut self, _t0: f64, _y0: &[f64; N]) {}

    /// Where the integration stopped, if `step` broke off at an earlier point of
    /// the last step (e.g. a terminal event). Consulted only after `step`
    /// returned `Break`; `Some((t_stop, y_stop))` with `t_stop` inside that step
    /// makes the driver return `(t_stop, y_stop)` instead of the step's end.
    /// Default: `None`.
    fn stop_point(&self) -> Option<(f64, [f64; N])> {
        None
    }
}

/// A borrowed observer observes too (so a caller can keep ownership of its recorder).
impl<O: Observer<N> + ?Sized, const N: usize> Observer<N> for &mut O {
    fn start(&mut self, t0: f64, y0: &[f64; N]) {
        (**self).start(t0, y0)
    }
    fn step(&mut self, t: f64, y: &[f64; N], dense: &dyn Dense<N>) -> ControlFlow<()> {
        (**self).step(t, y, dense)
    }
    fn stop_point(&self) -> Option<(f64, [f64; N])> {
        (**self).stop_point()
    }
}

/// An observer that goes on observing a run continued by another integrator from where the
/// first stopped ([`Dop853::stiff_stop`]): the second integrator's `start` is not passed on,
/// so the observer's state (its last event-function values, the rows it has written) carries
/// over; every step and the stop point are.
pub struct Resumed<'a, O: ?Sized>(pub &'a mut O);

impl<O: Observer<N> + ?Sized, const N: usize> Observer<N> for Resumed<'_, O> {
    fn step(&mut self, t: f64, y: &[f64; N], dense: &dyn Dense<N>) -> ControlFlow<()> {
        self.0.step(t, y, dense)
    }
    fn stop_point(&self) -> Option<(f64, [f64; N])> {
        self.0.stop_point()
    }
}

/// An [`Observer`] that ignores every step.
#[derive(Clone, Copy, Debug, Default)]
pub struct NullObserver;

impl<const N: usize> Observer<N> for NullObserver {
    fn step(&mut self, _t: f64, _y: &[f64; N], _dense: &dyn Dense<N>) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}

/// An [`Observer`] given by a closure `|t, y, dense| -> ControlFlow<()>`.
#[derive(Clone, Copy, Debug)]
pub struct FnObserver<F>(pub F);

impl<const N: usize, F> Observer<N> for FnObserver<F>
where
    F: FnMut(f64, &[f64; N], &dyn Dense<N>) -> ControlFlow<()>,
{
    fn step(&mut self, t: f64, y: &[f64; N], dense: &dyn Dense<N>) -> ControlFlow<()> {
        (self.0)(t, y, dense)
    }
}

/// Observer that samples the solution at prescribed times from the dense output.
///
/// `out[i]` is the state at `times[i]`. `times` must be sorted ascending. A time
/// equal to `t0` gets the initial state and a time equal to the end of a step
/// (in particular `t_end`) gets the accepted state, both bit-exactly; times in
/// between are interpolated with the integrator's dense output. Times before
/// `t0` get `[NaN; N]` (so indices stay aligned); times after the point where
/// the integration stopped are not filled (`out.len() < times.len()`, see
/// [`SampleAt::is_complete`]). `out` is allocated once, in [`SampleAt::new`].
#[derive(Clone, Debug)]
pub struct SampleAt<'a, const N: usize> {
    /// Requested sample times, ascending.
    pub times: &'a [f64],
    /// Sampled states, `out[i]` at `times[i]`.
    pub out: Vec<[f64; N]>,
}

impl<'a, const N: usize> SampleAt<'a, N> {
    /// Creates the sampler; panics in debug builds if `times` is not sorted.
    pub fn new(times: &'a [f64]) -> Self {
        debug_assert!(
            times.windows(2).all(|w| w[0] <= w[1]),
            "SampleAt: times must be sorted ascending"
        );
        Self {
            times,
            out: Vec::with_capacity(times.len()),
        }
    }

    /// Whether every requested time has been sampled.
    pub fn is_complete(&self) -> bool {
        self.out.len() == self.times.len()
    }
}

impl<const N: usize> Observer<N> for SampleAt<'_, N> {
    fn start(&mut self, t0: f64, y0: &[f64; N]) {
        self.out.clear();
        for &ts in self.times {
            if ts < t0 {
                self.out.push([f64::NAN; N]);
            } else if ts == t0 {
                self.out.push(*y0);
            } else {
                break;
            }
        }
    }

    fn step(&mut self, t: f64, y: &[f64; N], dense: &dyn Dense<N>) -> ControlFlow<()> {
        while let Some(&ts) = self.times.get(self.out.len()) {
            if ts > t {
                break;
            }
            if ts == t {
                self.out.push(*y);
            } else {
                let mut v = [0.0; N];
                dense.eval(ts, &mut v);
                self.out.push(v);
            }
        }
        ControlFlow::Continue(())
    }
}

/// Observer that records `(t, y)` after every accepted step, plus the initial state.
///
/// The vectors grow by one entry per step (amortised reallocation); use
/// [`EveryStep::with_capacity`] to preallocate.
#[derive(Clone, Debug, Default)]
pub struct EveryStep<const N: usize> {
    /// Times: `t0`, then the end of every accepted step.
    pub ts: Vec<f64>,
    /// States at `ts`.
    pub ys: Vec<[f64; N]>,
}

impl<const N: usize> EveryStep<N> {
    /// Creates an empty recorder.
    pub fn new() -> Self {
        Self {
            ts: Vec::new(),
            ys: Vec::new(),
        }
    }

    /// Creates a recorder with room for `n` entries.
    pub fn with_capacity(n: usize) -> Self {
        Self {
            ts: Vec::with_capacity(n),
            ys: Vec::with_capacity(n),
        }
    }
}

impl<const N: usize> Observer<N> for EveryStep<N> {
    fn start(&mut self, t0: f64, y0: &[f64; N]) {
        self.ts.clear();
        self.ys.clear();
        self.ts.push(t0);
        self.ys.push(*y0);
    }

    fn step(&mut self, t: f64, y: &[f64; N], _dense: &dyn Dense<N>) -> ControlFlow<()> {
        self.ts.push(t);
        self.ys.push(*y);
        ControlFlow::Continue(())
    }
}

/// Whether every component is finite.
#[inline]
pub(crate) fn all_finite<const N: usize>(y: &[f64; N]) -> bool {
    y.iter().all(|v| v.is_finite())
}

/// Per-run counters returned by the integrators.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected step attempts (error too large or non-finite trial values).
    pub rejected: u64,
    /// Right-hand-side evaluations, including those of the initial-step
    /// heuristic, of projections and of (lazily computed) dense output; for [`Radau5`]
    /// also those of its finite-difference Jacobians.
    pub rhs_evals: u64,
    /// Jacobians evaluated (analytic or by finite differences; [`Radau5`] only, else 0).
    pub jacobians: u64,
    /// Factorisations of the Newton iteration matrices, each one real and one complex
    /// `N x N` LU decomposition ([`Radau5`] only, else 0).
    pub lu_decomps: u64,
    /// Integrations that stopped because the problem had become stiff
    /// ([`Dop853::stiff_stop`]).
    pub stiff_stops: u64,
}

impl Stats {
    /// The counts of two integrations, one after the other.
    pub fn plus(&self, o: &Stats) -> Stats {
        Stats {
            steps: self.steps + o.steps,
            rejected: self.rejected + o.rejected,
            rhs_evals: self.rhs_evals + o.rhs_evals,
            jacobians: self.jacobians + o.jacobians,
            lu_decomps: self.lu_decomps + o.lu_decomps,
            stiff_stops: self.stiff_stops + o.stiff_stops,
        }
    }
}

/// Why an integration stopped before reaching `t_end`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum IntegrateError {
    /// The step size fell below `10 * f64::EPSILON * |t|` at time `t`.
    StepSizeTooSmall {
        /// Time of the last accepted state.
        t: f64,
        /// The step size that was too small.
        h: f64,
    },
    /// `max_steps` step attempts (accepted + rejected) were used before `t_end`.
    TooManySteps {
        /// Time of the last accepted state.
        t: f64,
        /// Step attempts made.
        steps: u64,
    },
    /// The right-hand side or the new state was NaN or infinite and could not be
    /// avoided by shrinking the step.
    NonFinite {
        /// Time of the last state at which everything was finite.
        t: f64,
    },
}

impl fmt::Display for IntegrateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            IntegrateError::StepSizeTooSmall { t, h } => {
                write!(f, "step size too small (h = {h:e}) at t = {t}")
            }
            IntegrateError::TooManySteps { t, steps } => {
                write!(f, "too many steps ({steps}) at t = {t}")
            }
            IntegrateError::NonFinite { t } => {
                write!(f, "non-finite right-hand side or state after t = {t}")
            }
        }
    }
}

impl std::error::Error for IntegrateError {}

#[cfg(test)]
mod tests;

/// Records either every accepted step or the values at requested times, and stops the run
/// when `keep_going(t)` says so (cancellation, or an error inside an event function).
pub struct Recorder<'a, 'b, const N: usize> {
    /// Every accepted step (when no times were requested).
    pub every: Option<EveryStep<N>>,
    /// The requested times.
    pub sample: Option<SampleAt<'a, N>>,
    keep_going: Option<&'b mut dyn FnMut(f64) -> bool>,
}

impl<'a, 'b, const N: usize> Recorder<'a, 'b, N> {
    /// A recorder of `times` if given, else of every step.
    pub fn new(
        times: Option<&'a [f64]>,
        keep_going: Option<&'b mut dyn FnMut(f64) -> bool>,
    ) -> Self {
        Recorder {
            every: times.is_none().then(EveryStep::new),
            sample: times.map(SampleAt::new),
            keep_going,
        }
    }
}

impl<const N: usize> Observer<N> for Recorder<'_, '_, N> {
    fn start(&mut self, t0: f64, y0: &[f64; N]) {
        if let Some(e) = self.every.as_mut() {
            e.start(t0, y0);
        }
        if let Some(s) = self.sample.as_mut() {
            s.start(t0, y0);
        }
    }
    fn step(&mut self, t: f64, y: &[f64; N], dense: &dyn Dense<N>) -> ControlFlow<()> {
        if let Some(e) = self.every.as_mut() {
            let _ = e.step(t, y, dense);
        }
        if let Some(s) = self.sample.as_mut() {
            let _ = s.step(t, y, dense);
        }
        let go = self.keep_going.as_mut().is_none_or(|k| k(t));
        if go {
            ControlFlow::Continue(())
        } else {
            ControlFlow::Break(())
        }
    }
}

/// Hands each output state to `out`: every accepted step (with the initial state unless
/// `skip_start`), or the values at requested times exactly as [`SampleAt`] takes them; and
/// stops the run when `keep_going(t)` says so. Nothing is kept: a run's memory does not
/// grow with its length.
pub struct Stream<'a, 'b, F, const N: usize> {
    times: Option<&'a [f64]>,
    /// Requested times handed out so far.
    pub taken: usize,
    skip_start: bool,
    keep_going: Option<&'b mut dyn FnMut(f64) -> bool>,
    out: F,
}

impl<'a, 'b, F: FnMut(f64, &[f64; N]), const N: usize> Stream<'a, 'b, F, N> {
    /// A stream of `times` if given, else of every step.
    pub fn new(
        times: Option<&'a [f64]>,
        skip_start: bool,
        keep_going: Option<&'b mut dyn FnMut(f64) -> bool>,
        out: F,
    ) -> Self {
        Stream {
            times,
            taken: 0,
            skip_start,
            keep_going,
            out,
        }
    }
}

impl<F: FnMut(f64, &[f64; N]), const N: usize> Observer<N> for Stream<'_, '_, F, N> {
    fn start(&mut self, t0: f64, y0: &[f64; N]) {
        match self.times {
            None => {
                if !self.skip_start {
                    (self.out)(t0, y0);
                }
            }
            Some(times) => {
                while let Some(&ts) = times.get(self.taken) {
                    if ts < t0 {
                        (self.out)(ts, &[f64::NAN; N]);
                    } else if ts == t0 {
                        (self.out)(ts, y0);
                    } else {
                        break;
                    }
                    self.taken += 1;
                }
            }
        }
    }

    fn step(&mut self, t: f64, y: &[f64; N], dense: &dyn Dense<N>) -> ControlFlow<()> {
        match self.times {
            None => (self.out)(t, y),
            Some(times) => {
                while let Some(&ts) = times.get(self.taken) {
                    if ts > t {
                        break;
                    }
                    if ts == t {
                        (self.out)(ts, y);
                    } else {
                        let mut v = [0.0; N];
                        dense.eval(ts, &mut v);
                        (self.out)(ts, &v);
                    }
                    self.taken += 1;
                }
            }
        }
        let go = self.keep_going.as_mut().is_none_or(|k| k(t));
        if go {
            ControlFlow::Continue(())
        } else {
            ControlFlow::Break(())
        }
    }
}

/// `e / sk`, the error `e` in units of the scale `sk`: 0 where both are 0, infinite where
/// only the scale is (an error against a zero scale is never acceptable).
pub(crate) fn scaled(e: f64, sk: f64) -> f64 {
    if sk > 0.0 {
        e / sk
    } else if e == 0.0 {
        0.0
    } else {
        f64::INFINITY
    }
}

/// The starting step size of Hairer's codes (`HINIT`, Hairer, Norsett & Wanner I, Sec. II.4),
/// for DOP853 (`exponent` 1/8) and RADAU5 (1/4, in its transformed tolerances): `h` such that
/// `h^(1/exponent) max(|f0|, |f'|) = 0.01` in the tolerance-scaled norm of the controlled
/// components, with `|f'|` estimated by one explicit Euler step (one extra right-hand side,
/// counted in `stats`).
#[allow(clippy::too_many_arguments)]
pub(crate) fn initial_step<const N: usize, S: OdeSystem<N> + ?Sized>(
    sys: &S,
    t: f64,
    y: &[f64; N],
    f0: &[f64; N],
    h_max: f64,
    (rtol, atol): (f64, f64),
    exponent: f64,
    stats: &mut Stats,
) -> f64 {
    let mut sk = [0.0; N];
    let (mut dnf, mut dny) = (0.0, 0.0);
    let floor = sys.magnitude_floor();
    let nc = sys.controlled().min(N);
    for i in 0..nc {
        sk[i] = atol + rtol * y[i].abs().max(floor[i]);
        dnf += scaled(f0[i], sk[i]).powi(2);
        dny += scaled(y[i], sk[i]).powi(2);
    }
    let mut h = if dnf <= 1e-10 || dny <= 1e-10 {
        1e-6
    } else {
        (dny / dnf).sqrt() * 0.01
    };
    h = h.min(h_max);
    let mut y1 = [0.0; N];
    for i in 0..N {
        y1[i] = y[i] + h * f0[i];
    }
    let mut f1 = [0.0; N];
    sys.rhs(t + h, &y1, &mut f1);
    stats.rhs_evals += 1;
    let mut der2 = 0.0;
    for i in 0..nc {
        der2 += scaled(f1[i] - f0[i], sk[i]).powi(2);
    }
    let der2 = der2.sqrt() / h;
    let der12 = der2.abs().max(dnf.sqrt());
    let h1 = if der12 <= 1e-15 {
        (h * 1e-3).max(1e-6)
    } else {
        (0.01 / der12).powf(exponent)
    };
    let h_new = (100.0 * h).min(h1).min(h_max);
    if h_new > 0.0 && h_new.is_finite() {
        h_new
    } else {
        // Degenerate scales (e.g. atol = 0 with a zero component): Hairer's fallback.
        1e-6f64.min(h_max)
    }
}
