//! One simulation vocabulary for every model: [`Settings`] with one [`Settings::check`],
//! [`Solution`], [`Stats`], [`Status`], [`EventRecord`], and the [`Model`] trait that a top
//! implements to get [`simulate`], [`summarise`] and the parallel [`batch`] without a driver
//! of its own.
//!
//! A model's driver lives with its physics (`models::heavy_top::simulate`,
//! `models::play_top::simulate`); this module holds what they share, and every rule on
//! settings and every public name (methods, summaries with units) that Python, the command
//! line and the sweeps read.

pub mod batch;
mod names;

pub use names::{SummaryField, MODES, MOTION_KINDS, SUMMARY_FIELDS};

use crate::error::{KreiselError, Result};
use std::borrow::Cow;

/// What a method is and can do.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MethodInfo {
    /// Public name.
    pub name: &'static str,
    /// Order of accuracy.
    pub order: u32,
    /// Adaptive step size (else `dt` is required).
    pub adaptive: bool,
    /// Symplectic (Lie-Poisson for the splittings).
    pub symplectic: bool,
    /// Supports event location.
    pub events: bool,
    /// One line on what it is.
    pub summary: &'static str,
}

/// Every method `simulate` knows.
pub const METHODS: [MethodInfo; 8] = [
    MethodInfo { name: "dop853", order: 8, adaptive: true, symplectic: false, events: true, summary: "Dormand-Prince 8(5,3), adaptive, dense output of order 7" },
    MethodInfo { name: "rk4", order: 4, adaptive: false, symplectic: false, events: false, summary: "classic fixed-step Runge-Kutta" },
    MethodInfo { name: "splitting", order: 2, adaptive: false, symplectic: true, events: false, summary: "kick-drift-kick of exact free rotation and gravity kick" },
    MethodInfo { name: "splitting4", order: 4, adaptive: false, symplectic: true, events: false, summary: "Yoshida triple jump of the splitting" },
    MethodInfo { name: "splitting6", order: 6, adaptive: false, symplectic: true, events: false, summary: "Yoshida's 7-stage composition of the splitting" },
    MethodInfo { name: "verlet", order: 2, adaptive: false, symplectic: true, events: false, summary: "Stoermer-Verlet on the Euler-angle Hamiltonian (symmetric tops; singular at the vertical)" },
    MethodInfo { name: "midpoint", order: 2, adaptive: false, symplectic: true, events: false, summary: "implicit midpoint rule" },
    MethodInfo { name: "gauss4", order: 4, adaptive: false, symplectic: true, events: false, summary: "2-stage Gauss-Legendre, implicit" },
];

/// Looks a method up by name.
pub fn method(name: &str) -> Result<MethodInfo> {
    METHODS
        .iter()
        .copied()
        .find(|m| m.name == name)
        .ok_or_else(|| KreiselError::InvalidParameter {
            name: "method".into(),
            value: format!("{name:?}"),
            allowed: format!(
                "known methods are {}",
                METHODS
                    .iter()
                    .map(|m| m.name)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        })
}

/// The most steps a run may take (adaptive step attempts, or fixed steps `t_end / dt`).
pub const MAX_STEPS: u64 = 100_000_000;

/// The most rows a run keeps (one per step without `t_eval`): 4 million, about 0.8 GB of a
/// play top's rows in the core and about 3 GB at the peak of their columns in Python. A run
/// that reaches it stops with an error naming `t_end` and `t_eval`, instead of growing until
/// the allocator fails.
pub const MAX_ROWS: usize = 4_000_000;

/// What an event function looks at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EventKind {
    /// Heavy tops: turning points of the nutation (the sign of theta_dot).
    TurningPoints,
    /// Heavy tops: theta crossing a value (rad): `cos(value) - cos(theta)`.
    ThetaCrossing(f64),
    /// Play tops: u = cos(theta) crossing a level upward (each event fires once).
    Inversion(f64),
    /// Play tops: the kinetic energy falling below 1e-12 of its start.
    Rest,
    /// A user function of (t, state): the next of the functions handed to [`simulate`].
    User,
}

impl EventKind {
    /// The kind's public name.
    pub fn name(&self) -> &'static str {
        match self {
            EventKind::TurningPoints => "turning_points",
            EventKind::ThetaCrossing(_) => "theta_crossing",
            EventKind::Inversion(_) => "inversion",
            EventKind::Rest => "rest",
            EventKind::User => "user",
        }
    }
}

/// An event the user asks for: what it looks at, which crossings count, whether it ends the
/// run, and the name it is reported under.
#[derive(Debug, Clone, PartialEq)]
pub struct EventDef {
    /// Reported name.
    pub name: String,
    /// The event function.
    pub kind: EventKind,
    /// -1, 0 or +1: crossings from + to -, both, or from - to +.
    pub direction: i8,
    /// Stop at the first such event.
    pub terminal: bool,
}

impl EventDef {
    /// The event's own rules (its direction, and the range of its value); `i` is its
    /// position in a list of events, if it is in one (the messages name it).
    pub fn check(&self, i: Option<usize>) -> Result<()> {
        let which = match i {
            Some(i) => format!("events[{i}] ({})", self.name),
            None => format!("event {:?}", self.name),
        };
        if !matches!(self.direction, -1..=1) {
            return Err(KreiselError::InvalidParameter {
                name: "direction".into(),
                value: self.direction.to_string(),
                allowed: format!("{which}: use -1, 0 or +1"),
            });
        }
        match self.kind {
            EventKind::ThetaCrossing(v)
                if !(v.is_finite() && (0.0..=std::f64::consts::PI).contains(&v)) =>
            {
                Err(KreiselError::invalid(
                    "value",
                    v,
                    format!("{which}: theta lies in [0, pi]"),
                ))
            }
            EventKind::Inversion(v) if !(v.is_finite() && (-1.0..=1.0).contains(&v)) => {
                Err(KreiselError::invalid(
                    "level",
                    v,
                    format!("{which}: u = cos(theta) lies in [-1, 1]"),
                ))
            }
            _ => Ok(()),
        }
    }
}

/// A user event function of (t, state).
pub type UserFn<'a, S> = Box<dyn FnMut(f64, &S) -> f64 + 'a>;

/// Settings of one simulation, for every model.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    /// Method name (see [`METHODS`]).
    pub method: String,
    /// End time (s), >= 0.
    pub t_end: f64,
    /// Relative tolerance (adaptive methods), in [1e-15, 1).
    pub rtol: f64,
    /// Absolute tolerance (adaptive methods), > 0.
    pub atol: f64,
    /// Step (fixed-step methods), > 0.
    pub dt: Option<f64>,
    /// What to save: output times (ascending, in [0, t_end]); None: every step.
    pub t_eval: Option<Vec<f64>>,
    /// Events, in the user's order ([`EventRecord::index`] is the position here).
    pub events: Vec<EventDef>,
    /// Lagrange tops: integrate (theta, p_theta) alone and rebuild phi and psi.
    pub reduced: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            method: "dop853".into(),
            t_end: 0.0,
            rtol: 1e-10,
            atol: 1e-12,
            dt: None,
            t_eval: None,
            events: Vec::new(),
            reduced: false,
        }
    }
}

impl Settings {
    /// The one check of the settings, whatever the model: names the setting, its value and
    /// what is allowed. Returns the method's description. (A model adds its own rules in
    /// [`Model::check`].)
    pub fn check(&self) -> Result<MethodInfo> {
        let info = method(&self.method)?;
        let t_end = self.t_end;
        if !(t_end.is_finite() && t_end >= 0.0) {
            return Err(KreiselError::invalid(
                "t_end",
                t_end,
                "it must be a finite number >= 0",
            ));
        }
        if info.adaptive {
            let (r, a) = (self.rtol, self.atol);
            if !(r.is_finite() && (1e-15..1.0).contains(&r)) {
                return Err(KreiselError::invalid(
                    "rtol",
                    r,
                    "it must lie in [1e-15, 1)",
                ));
            }
            if !(a.is_finite() && a > 0.0) {
                return Err(KreiselError::invalid(
                    "atol",
                    a,
                    "it must be a finite number > 0",
                ));
            }
        } else {
            match self.dt {
                None => {
                    return Err(KreiselError::InvalidParameter {
                        name: "dt".into(),
                        value: "None".into(),
                        allowed: format!(
                            "dt is missing: method {:?} takes fixed steps; give dt > 0 (s), \
                             e.g. 1e-4",
                            info.name
                        ),
                    })
                }
                Some(dt) if !(dt.is_finite() && dt > 0.0) => {
                    return Err(KreiselError::invalid(
                        "dt",
                        dt,
                        "it must be a finite number > 0",
                    ))
                }
                Some(dt) if t_end / dt > MAX_STEPS as f64 => {
                    return Err(KreiselError::invalid(
                        "dt",
                        dt,
                        format!(
                            "t_end / dt = {:.3e} steps is more than the {MAX_STEPS} a run may \
                             take: give a larger dt or a shorter t_end",
                            t_end / dt
                        ),
                    ))
                }
                _ => {}
            }
        }
        if let Some(te) = &self.t_eval {
            for (i, w) in te.windows(2).enumerate() {
                if w[1] < w[0] {
                    return Err(KreiselError::invalid(
                        &format!("t_eval[{}]", i + 1),
                        w[1],
                        "output times must be ascending",
                    ));
                }
            }
            if let Some(&bad) = te
                .iter()
                .find(|&&x| !(x.is_finite() && (0.0..=t_end).contains(&x)))
            {
                return Err(KreiselError::invalid(
                    "t_eval",
                    bad,
                    format!("output times must lie in [0, t_end = {t_end}]"),
                ));
            }
        }
        if !self.events.is_empty() && !info.events {
            return Err(KreiselError::InvalidParameter {
                name: "events".into(),
                value: format!("{} event(s)", self.events.len()),
                allowed: format!(
                    "method {:?} has no dense output to locate events; use \"dop853\"",
                    info.name
                ),
            });
        }
        for (i, e) in self.events.iter().enumerate() {
            e.check(Some(i))?;
        }
        Ok(info)
    }

    /// DOP853 with these tolerances, its starting step chosen by the method and at most
    /// [`MAX_STEPS`] step attempts.
    pub fn dop853(&self) -> crate::integrate::Dop853 {
        crate::integrate::Dop853 {
            rtol: self.rtol,
            atol: self.atol,
            h_init: None,
            h_first_max: f64::INFINITY,
            h_max: f64::INFINITY,
            max_steps: MAX_STEPS,
            stiff_stop: None,
        }
    }

    /// The number of user event functions the settings refer to.
    pub fn user_events(&self) -> usize {
        self.events
            .iter()
            .filter(|e| e.kind == EventKind::User)
            .count()
    }

    /// An error for an event kind that `model` has no event function for.
    pub fn unsupported_event(&self, model: &str, allowed: &[EventKind]) -> Result<()> {
        for (i, e) in self.events.iter().enumerate() {
            let known = allowed
                .iter()
                .any(|a| std::mem::discriminant(a) == std::mem::discriminant(&e.kind));
            if !known {
                return Err(KreiselError::InvalidParameter {
                    name: format!("events[{i}]"),
                    value: format!("{:?} ({})", e.name, e.kind.name()),
                    allowed: format!(
                        "a {model} has the events {}",
                        allowed
                            .iter()
                            .map(|a| a.name())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                });
            }
        }
        Ok(())
    }
}

/// Counters of one simulation.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Stats {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected steps.
    pub rejected: u64,
    /// Right-hand-side evaluations (0 for the splittings, which use none).
    pub rhs_evals: u64,
}

impl std::ops::AddAssign<crate::integrate::Stats> for Stats {
    fn add_assign(&mut self, s: crate::integrate::Stats) {
        self.steps += s.steps;
        self.rejected += s.rejected;
        self.rhs_evals += s.rhs_evals;
    }
}

/// How a run ended.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Status {
    /// It reached `t_end`.
    #[default]
    Completed,
    /// A terminal event ended it.
    Event,
    /// It was interrupted (cancelled, or an error in a user event function).
    Interrupted,
}

impl Status {
    /// The status's public name.
    pub fn name(&self) -> &'static str {
        match self {
            Status::Completed => "completed",
            Status::Event => "event",
            Status::Interrupted => "interrupted",
        }
    }
}

/// An event that happened.
#[derive(Debug, Clone, PartialEq)]
pub struct EventRecord {
    /// Position in [`Settings::events`]; None for the model's own events (a play top's
    /// contact switches: lift-off, touchdown, slip to roll, roll to slip).
    pub index: Option<usize>,
    /// Reported name.
    pub name: Cow<'static, str>,
    /// Time (s).
    pub t: f64,
    /// The contact part of a play top's contact switch (its position in the top's parts);
    /// None for every other event.
    pub part: Option<usize>,
}

/// What a run reports besides its rows.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunInfo {
    /// Counters.
    pub stats: Stats,
    /// Events, in the order they happened.
    pub events: Vec<EventRecord>,
    /// How it ended.
    pub status: Status,
}

/// A simulated motion: times, rows (a state and what the model records beside it), events,
/// counters and status.
#[derive(Debug, Clone)]
pub struct Solution<R> {
    /// Times (s); an event time appears twice where the state jumps there.
    pub t: Vec<f64>,
    /// Rows at those times.
    pub rows: Vec<R>,
    /// Events, counters and status.
    pub info: RunInfo,
}

/// What receives the rows of a run, in order.
pub type Sink<'a, R> = &'a mut dyn FnMut(f64, &R);

/// The running summary of a run, fed one row at a time.
pub trait Accumulate<R> {
    /// What it gives at the end.
    type Summary;
    /// One more row.
    fn push(&mut self, t: f64, row: &R);
    /// The summary, once the run is over.
    fn finish(self, info: &RunInfo) -> Self::Summary;
}

/// A model kreisel simulates: its state, what a run records, its own rules on the
/// settings, its driver and its summary. Implementing it gives [`simulate`], [`summarise`]
/// and [`batch::many`].
pub trait Model: Sync {
    /// An initial state.
    type State: Send + Sync;
    /// One output row.
    type Row: Copy + Send;
    /// What a batch keeps of a run.
    type Summary: Send;
    /// The running summary of a run.
    type Acc<'a>: Accumulate<Self::Row, Summary = Self::Summary>
    where
        Self: 'a;

    /// What the model is called in messages ("heavy top").
    const NAME: &'static str;

    /// The model's own rules on settings (methods and events it supports), after
    /// [`Settings::check`] passed with `info`.
    fn check(&self, settings: &Settings, info: &MethodInfo) -> Result<()>;

    /// Runs from `s0`, handing every row to `sink`; `user` are the functions of the
    /// settings' [`EventKind::User`] events in order. `keep_going(t)`, asked now and then,
    /// may stop the run (status [`Status::Interrupted`]). Settings are checked.
    fn run(
        &self,
        s0: &Self::State,
        settings: &Settings,
        user: &mut [UserFn<'_, Self::State>],
        keep_going: &mut dyn FnMut(f64) -> bool,
        sink: Sink<'_, Self::Row>,
    ) -> Result<RunInfo>;

    /// A running summary of a run from `s0`.
    fn summary<'a>(&'a self, s0: &Self::State, settings: &Settings) -> Self::Acc<'a>;

    /// The diagnostics of a run's rows (Euler angles, energies, the model's integrals, ...).
    type Columns;
    /// The names of those columns, as the bindings show them.
    fn column_names(&self) -> Vec<&'static str>;
    /// The diagnostics of `rows`.
    fn columns(&self, rows: &[Self::Row]) -> Self::Columns;
}

/// Checks settings for a model: [`Settings::check`], then the model's rules.
pub fn check<M: Model>(model: &M, settings: &Settings, user_fns: usize) -> Result<MethodInfo> {
    let info = settings.check()?;
    model.check(settings, &info)?;
    let wanted = settings.user_events();
    if wanted != user_fns {
        return Err(KreiselError::InvalidParameter {
            name: "events".into(),
            value: format!("{wanted} user event(s)"),
            allowed: format!("{user_fns} user event function(s) were given"),
        });
    }
    Ok(info)
}

/// How often (in calls of `keep_going`, once per accepted step of an adaptive method) a run
/// measures its pace.
const PACE_EVERY: u64 = 1 << 16;

/// Watches the pace of a run: a run whose steps so far, extrapolated to `t_end`, come to
/// more than [`MAX_STEPS`] stops at once (it would fail there anyway, after taking them: a
/// Lagrange top spun about the vertical at 1e8 rad/s needs 1.7e8 steps a second and ran for
/// half a minute in a batch, where `simulate` ran out of rows at once), and says so in an
/// error naming `t_end`.
///
/// It also watches each window of [`PACE_EVERY`] steps on its own: a run that stalls (its
/// last window, extrapolated to `t_end`, comes to more than ten times [`MAX_STEPS`]) stops
/// too, with an error that says where it stalled, rather than running for hours on ever
/// smaller steps.
struct Pace<'k> {
    inner: &'k mut dyn FnMut(f64) -> bool,
    calls: u64,
    t_end: f64,
    too_long: Option<(u64, f64)>,
    /// The time at the start of the current window.
    window_t: f64,
    stalled: Option<(f64, f64, f64)>,
}

impl<'k> Pace<'k> {
    fn new(inner: &'k mut dyn FnMut(f64) -> bool, t_end: f64) -> Self {
        Pace {
            inner,
            calls: 0,
            t_end,
            too_long: None,
            window_t: 0.0,
            stalled: None,
        }
    }

    fn keep_going(&mut self, t: f64) -> bool {
        self.calls += 1;
        if self.calls % PACE_EVERY == 0 && t > 0.0 {
            let projected = self.calls as f64 * (self.t_end / t);
            if projected > MAX_STEPS as f64 {
                self.too_long = Some((self.calls, projected));
                return false;
            }
            let advanced = t - self.window_t;
            let ahead = PACE_EVERY as f64 * (self.t_end - t) / advanced.max(1e-300);
            if self.calls as f64 + ahead > 10.0 * MAX_STEPS as f64 {
                self.stalled = Some((t, advanced, self.calls as f64 + ahead));
                return false;
            }
            self.window_t = t;
        }
        (self.inner)(t)
    }

    /// The error of a run stopped for its pace, if it was.
    fn check(&self) -> Result<()> {
        if let Some((t, advanced, projected)) = self.stalled {
            return Err(KreiselError::invalid(
                "t_end",
                self.t_end,
                format!(
                    "the run stalled at t = {t:.9e} s: its last {PACE_EVERY} steps advanced it \
                     by {advanced:.1e} s, so it would take about {projected:.1e} steps, more \
                     than the {MAX_STEPS} a run may take (the motion there is too stiff for \
                     the method's steps); give a t_end before the stall or looser tolerances"
                ),
            ));
        }
        match self.too_long {
            None => Ok(()),
            Some((n, projected)) => Err(KreiselError::invalid(
                "t_end",
                self.t_end,
                format!(
                    "at the pace of its first {n} steps this run would take about {:.1e} \
                     steps, more than the {MAX_STEPS} a run may take: give a shorter t_end \
                     (or looser tolerances)",
                    projected
                ),
            )),
        }
    }
}

/// What a run (or its columns) whose memory ran out while keeping `n` rows of `size` bytes
/// tells its user.
pub fn out_of_memory(what: &str, n: usize, size: usize) -> String {
    format!(
        "the process ran out of memory keeping {what} ({n} rows, {:.2} GB, could not grow): \
         pass t_eval to keep rows at chosen times only, or give a shorter t_end",
        (n * size) as f64 / 1e9
    )
}

/// Simulates `model` from `s0`: every row kept.
pub fn simulate<M: Model>(
    model: &M,
    s0: &M::State,
    settings: &Settings,
    user: &mut [UserFn<'_, M::State>],
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<Solution<M::Row>> {
    check(model, settings, user.len())?;
    let (mut t, mut rows) = (Vec::new(), Vec::new());
    let mut pace = Pace::new(keep_going, settings.t_end);
    let full = std::cell::Cell::new(false);
    let short = std::cell::Cell::new(false);
    let info = model.run(
        s0,
        settings,
        user,
        &mut |ti| !full.get() && !short.get() && pace.keep_going(ti),
        &mut |ti, r| {
            if t.len() >= MAX_ROWS {
                full.set(true);
            } else if t.try_reserve(1).is_err() || rows.try_reserve(1).is_err() {
                // The process's memory (a limit on its address space, or the machine's)
                // ran out before the budget: refused, not aborted.
                short.set(true);
            } else {
                t.push(ti);
                rows.push(*r);
            }
        },
    );
    pace.check()?;
    if short.get() {
        return Err(KreiselError::invalid(
            "t_end",
            settings.t_end,
            out_of_memory(
                "the run's rows",
                t.len(),
                std::mem::size_of::<M::Row>() + std::mem::size_of::<f64>(),
            ),
        ));
    }
    if full.get() {
        let size = std::mem::size_of::<M::Row>() + std::mem::size_of::<f64>();
        return Err(KreiselError::invalid(
            "t_end",
            settings.t_end,
            format!(
                "the run keeps a row per step and reached the {MAX_ROWS} rows (about {:.1} \
                 GB) a run may keep at t = {:.9e} s: pass t_eval to keep rows at chosen times \
                 only, or give a shorter t_end",
                (MAX_ROWS * size) as f64 / 1e9,
                t.last().copied().unwrap_or(0.0)
            ),
        ));
    }
    Ok(Solution {
        t,
        rows,
        info: info?,
    })
}

/// Simulates `model` from `s0` and summarises the run as it goes (no rows kept).
pub fn summarise<M: Model>(model: &M, s0: &M::State, settings: &Settings) -> Result<M::Summary> {
    check(model, settings, 0)?;
    run_summary(model, s0, settings)
}

/// [`summarise`] with the settings already checked.
pub(crate) fn run_summary<M: Model>(
    model: &M,
    s0: &M::State,
    settings: &Settings,
) -> Result<M::Summary> {
    let mut acc = model.summary(s0, settings);
    let mut go = |_| true;
    let mut pace = Pace::new(&mut go, settings.t_end);
    let info = model.run(
        s0,
        settings,
        &mut [],
        &mut |t| pace.keep_going(t),
        &mut |t, r| acc.push(t, r),
    );
    pace.check()?;
    Ok(acc.finish(&info?))
}

/// The Euler angles phi and psi of a run's rows made continuous: each the representative
/// (mod 2 pi) nearest to the previous row's (the first row's as they are).
#[derive(Default)]
pub(crate) struct Unwrapped {
    last: Option<(f64, f64)>,
}

impl Unwrapped {
    /// The next row's (phi, psi).
    #[inline]
    pub(crate) fn next(&mut self, phi: f64, psi: f64) -> (f64, f64) {
        let out = match self.last {
            None => (phi, psi),
            Some((lphi, lpsi)) => (unwrap(lphi, phi), unwrap(lpsi, psi)),
        };
        self.last = Some(out);
        out
    }
}

/// The representative of `angle` (mod 2 pi) nearest to `last`.
#[inline]
fn unwrap(last: f64, angle: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    let turns = (last - angle) / tau;
    // Mostly no turn: skip the rounding call (`angle + tau * 0.0` is `angle + 0.0`).
    if turns.abs() < 0.5 {
        return angle + 0.0;
    }
    angle + tau * turns.round()
}

/// An integrator's failure as the user reads it: where it stopped, and for the step cap what
/// to change (`t_end`, the tolerances).
pub(crate) fn integrate_error(e: crate::integrate::IntegrateError, t_end: f64) -> KreiselError {
    use crate::integrate::IntegrateError::{StepSizeTooSmall, TooManySteps};
    match e {
        TooManySteps { .. } => KreiselError::Numerical(format!(
            "{e} before t_end = {}: give a shorter t_end or looser tolerances (rtol, atol)",
            crate::error::repr(t_end)
        )),
        StepSizeTooSmall { .. } => KreiselError::Numerical(format!(
            "{e}: the equations are singular or too stiff there for the method's steps (on a \
             floor: a contact force growing without bound, or friction at the edge of its \
             cone); give a t_end before the stall or looser tolerances (rtol, atol)"
        )),
        _ => KreiselError::Numerical(format!("{e}")),
    }
}

/// The relative form of a drift `d` against `scale` (absolute where the scale is zero).
pub(crate) fn relative(d: f64, scale: f64) -> f64 {
    if scale > 0.0 {
        d / scale
    } else {
        d
    }
}
