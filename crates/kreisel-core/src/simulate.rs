//! Simulation of heavy tops: one entry point for every method, one output format.

use crate::error::{KreiselError, Result};
use crate::integrate::fixed::{self, FixedScheme};
use crate::integrate::implicit::{Gauss4, Midpoint};
use crate::integrate::rk4::Rk4Scheme;
use crate::integrate::splitting::Splitting;
use crate::integrate::verlet::Verlet;
use crate::integrate::{
    Dense, Dop853, EventSpec, IntegrateError, Locator, Observer, OdeSystem, Recorder, WithEvents,
};
use crate::models::heavy_top::{HeavyTop, RigidState};
use crate::rotation::{cross, euler_from_quaternion, Quat};
use std::ops::ControlFlow;

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

/// Settings of one simulation.
#[derive(Debug, Clone)]
pub struct Settings {
    /// Method name (see [`METHODS`]).
    pub method: String,
    /// End time (s), >= 0.
    pub t_end: f64,
    /// Relative tolerance (adaptive methods).
    pub rtol: f64,
    /// Absolute tolerance (adaptive methods).
    pub atol: f64,
    /// Step (fixed-step methods).
    pub dt: Option<f64>,
    /// Output times (ascending, in [0, t_end]); None: every step.
    pub t_eval: Option<Vec<f64>>,
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

/// A simulated motion: times and states.
#[derive(Debug, Clone, Default)]
pub struct Output {
    /// Times (s).
    pub t: Vec<f64>,
    /// States at those times.
    pub states: Vec<RigidState>,
    /// Events that happened: (index of the event function, time).
    pub events: Vec<(usize, f64)>,
    /// Counters.
    pub stats: Stats,
}

/// A user event function of (t, state).
pub type UserEventFn<'a> = Box<dyn FnMut(f64, &RigidState) -> f64 + 'a>;

type RawEventFn<'a, const N: usize> = Box<dyn FnMut(f64, &[f64; N]) -> f64 + 'a>;

/// What an event function looks at.
pub enum EventKind<'a> {
    /// Turning points of the nutation: the sign of theta_dot.
    TurningPoints,
    /// theta crossing a value (rad): `cos(value) - cos(theta)`, increasing with theta.
    ThetaCrossing(f64),
    /// A user function of (t, state).
    User(UserEventFn<'a>),
}

/// An event: what it looks at, which crossings count, and whether it ends the run.
pub struct EventDef<'a> {
    /// The event function.
    pub kind: EventKind<'a>,
    /// -1, 0 or +1: crossings from + to -, both, or from - to +.
    pub direction: i8,
    /// Stop at the first such event.
    pub terminal: bool,
}

impl EventKind<'_> {
    fn eval(&mut self, t: f64, s: &RigidState) -> f64 {
        match self {
            EventKind::TurningPoints => {
                // u = cos(theta) = Gamma_3 and du/dt = (Gamma x omega)_3; theta_dot has the
                // sign of -du/dt.
                let g = s.q.up_in_body();
                -(g[0] * s.omega[1] - g[1] * s.omega[0])
            }
            EventKind::ThetaCrossing(v) => v.cos() - s.q.up_in_body()[2],
            EventKind::User(f) => f(t, s),
        }
    }
}

/// The heavy top as a first-order system in y = (q, omega); `AXIAL` (only for a top that
/// is [`HeavyTop::axial`]) evaluates the right-hand side without its vanishing terms.
pub struct QOmega<'a, const AXIAL: bool>(pub &'a HeavyTop);

impl<const AXIAL: bool> OdeSystem<7> for QOmega<'_, AXIAL> {
    #[inline(always)]
    fn rhs(&self, _t: f64, y: &[f64; 7], dy: &mut [f64; 7]) {
        if AXIAL {
            self.0.rhs_axial(y, dy);
        } else {
            self.0.rhs(y, dy);
        }
    }
    fn project(&self, y: &mut [f64; 7]) {
        let n = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3]).sqrt();
        for v in y.iter_mut().take(4) {
            *v /= n;
        }
    }
}

/// The heavy top in y = (q, M). With Gamma = q* ez q quadratic in q, the energy
/// `M.I^-1 M / 2 + m g c.Gamma(q)` and `|q|^2` are quadratic invariants, which the implicit
/// Gauss methods keep exactly (Mz = M.Gamma is cubic: kept to the method's accuracy).
pub struct QM<'a>(pub &'a HeavyTop);

impl OdeSystem<7> for QM<'_> {
    fn rhs(&self, _t: f64, y: &[f64; 7], dy: &mut [f64; 7]) {
        let top = self.0;
        let q = Quat([y[0], y[1], y[2], y[3]]);
        let m = [y[4], y[5], y[6]];
        let w = top.omega(m);
        let dq = q.hamilton(Quat([0.0, w[0], w[1], w[2]]));
        let dm = cross(m, w);
        let tq = cross(q.up_in_body(), top.mgc());
        for (d, x) in dy.iter_mut().zip(dq.0) {
            *d = 0.5 * x;
        }
        for i in 0..3 {
            dy[4 + i] = dm[i] + tq[i];
        }
    }
}

fn pack7(s: &RigidState) -> [f64; 7] {
    let q = s.q.0;
    [q[0], q[1], q[2], q[3], s.omega[0], s.omega[1], s.omega[2]]
}

fn unpack7(y: &[f64; 7]) -> RigidState {
    RigidState {
        q: Quat([y[0], y[1], y[2], y[3]]).normalized(),
        omega: [y[4], y[5], y[6]],
    }
}

/// Validates the settings against the method.
pub fn check(settings: &Settings, info: &MethodInfo) -> Result<()> {
    let t_end = settings.t_end;
    if !(t_end.is_finite() && t_end >= 0.0) {
        return Err(KreiselError::invalid(
            "t_end",
            t_end,
            "it must be a finite number >= 0",
        ));
    }
    if info.adaptive {
        let (r, a) = (settings.rtol, settings.atol);
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
        match settings.dt {
            None => {
                return Err(KreiselError::InvalidParameter {
                    name: "dt".into(),
                    value: "None".into(),
                    allowed: format!("method {:?} has a fixed step: give dt > 0", info.name),
                })
            }
            Some(dt) if !(dt.is_finite() && dt > 0.0) => {
                return Err(KreiselError::invalid(
                    "dt",
                    dt,
                    "it must be a finite number > 0",
                ))
            }
            _ => {}
        }
    }
    if let Some(te) = &settings.t_eval {
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
    Ok(())
}

/// What receives the states of a run, in order: (t, state).
pub type Sink<'a> = &'a mut dyn FnMut(f64, &RigidState);

/// Runs a fixed-step scheme and hands its decoded states to `sink`.
fn run_fixed<S: FixedScheme>(
    scheme: &S,
    y0: S::Y,
    settings: &Settings,
    decode: impl Fn(&S::Y) -> RigidState,
    rhs_per_step: u64,
    sink: Sink<'_>,
) -> Result<Stats> {
    let dt = settings.dt.expect("checked");
    fixed::run(
        scheme,
        y0,
        settings.t_end,
        dt,
        settings.t_eval.as_deref(),
        |t, y| sink(t, &decode(y)),
    )?;
    let steps = ((settings.t_end / dt) * (1.0 - 1e-12)).ceil() as u64;
    Ok(Stats {
        steps,
        rejected: 0,
        rhs_evals: steps * rhs_per_step,
    })
}

/// The adaptive integrator at the settings' tolerances.
fn dop853(settings: &Settings) -> Dop853 {
    Dop853 {
        rtol: settings.rtol,
        atol: settings.atol,
        h_init: None,
        h_max: f64::INFINITY,
        max_steps: 100_000_000,
    }
}

/// An [`Output`] filled by a run that hands its states to a sink.
fn collect(run: impl FnOnce(Sink<'_>) -> Result<Stats>) -> Result<Output> {
    let mut out = Output::default();
    let stats = run(&mut |t, s| {
        out.t.push(t);
        out.states.push(*s);
    })?;
    out.stats = stats;
    Ok(out)
}

/// Simulates a heavy top: every method, events for those that locate them.
///
/// `keep_going(t)` is called after every accepted step; returning false stops the run
/// there (cancellation, or an error raised inside a user event function).
pub fn simulate(
    top: &HeavyTop,
    s0: &RigidState,
    settings: &Settings,
    events: &mut [EventDef<'_>],
    reduced: bool,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<Output> {
    let info = method(&settings.method)?;
    check(settings, &info)?;
    if !events.is_empty() && !info.events {
        return Err(KreiselError::InvalidParameter {
            name: "events".into(),
            value: format!("{} event(s)", events.len()),
            allowed: format!(
                "method {:?} has no dense output to locate events; use \"dop853\"",
                info.name
            ),
        });
    }
    let integrator = match info.name {
        "dop853" => dop853(settings),
        "rk4" => {
            return if reduced {
                let (sch, y0) = Verlet::new(top, s0)?;
                let rk = Rk4Scheme::<_, 4> { sys: &sch };
                collect(|sink| {
                    run_fixed(
                        &rk,
                        (Verlet::pack(&y0), 0.0),
                        settings,
                        |y| sch.decode_packed(&y.0),
                        4,
                        sink,
                    )
                })
            } else {
                collect(|sink| fixed_into(top, s0, settings, sink))
            }
        }
        _ if reduced => {
            return Err(KreiselError::InvalidParameter {
                name: "reduced".into(),
                value: "True".into(),
                allowed: "the reduced route runs with the general-purpose methods \"dop853\" \
                          and \"rk4\"; the structure-preserving ones integrate the whole top"
                    .into(),
            })
        }
        _ => return simulate_fixed(top, s0, settings),
    };
    if reduced {
        let (sch, y0) = Verlet::new(top, s0)?;
        run_ode(
            &integrator,
            &sch,
            Verlet::pack(&y0),
            |y| sch.decode_packed(y),
            settings,
            events,
            keep_going,
        )
    } else if top.axial() {
        run_ode(
            &integrator,
            &QOmega::<true>(top),
            pack7(s0),
            unpack7,
            settings,
            events,
            keep_going,
        )
    } else {
        run_ode(
            &integrator,
            &QOmega::<false>(top),
            pack7(s0),
            unpack7,
            settings,
            events,
            keep_going,
        )
    }
}

fn integrate_error(e: IntegrateError) -> KreiselError {
    KreiselError::Numerical(format!("{e}"))
}

fn run_ode<const N: usize, S: OdeSystem<N>>(
    integrator: &Dop853,
    sys: &S,
    y0: [f64; N],
    decode: impl Fn(&[f64; N]) -> RigidState,
    settings: &Settings,
    events: &mut [EventDef<'_>],
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<Output> {
    let mut recorder = Recorder::new(settings.t_eval.as_deref(), Some(keep_going));
    let specs: Vec<EventSpec> = events
        .iter()
        .map(|e| EventSpec::new(e.direction, e.terminal))
        .collect();
    let mut fns: Vec<RawEventFn<'_, N>> = events
        .iter_mut()
        .map(|e| {
            let kind = &mut e.kind;
            let decode = &decode;
            Box::new(move |t: f64, y: &[f64; N]| kind.eval(t, &decode(y))) as RawEventFn<'_, N>
        })
        .collect();
    let t_end = settings.t_end;
    let (st, hits) = if fns.is_empty() {
        // No events: the recorder alone observes (no locator to consult after every step).
        let result = integrator.integrate(sys, 0.0, y0, t_end, &mut recorder);
        (result.map_err(integrate_error)?.2, Vec::new())
    } else {
        let mut locator = Locator::new();
        for (f, spec) in fns.iter_mut().zip(&specs) {
            locator.add(*spec, f.as_mut());
        }
        let mut obs = WithEvents::new(locator, &mut recorder);
        let result = integrator.integrate(sys, 0.0, y0, t_end, &mut obs);
        let (_, _, st) = result.map_err(integrate_error)?;
        let hits: Vec<(usize, f64)> = obs.locator.events.iter().map(|e| (e.index, e.t)).collect();
        (st, hits)
    };
    drop(fns);
    let mut out = Output {
        events: hits,
        stats: Stats {
            steps: st.steps,
            rejected: st.rejected,
            rhs_evals: st.rhs_evals,
        },
        ..Output::default()
    };
    if let Some(e) = recorder.every {
        out.t = e.ts;
        out.states = e.ys.iter().map(&decode).collect();
    } else if let Some(s) = recorder.sample {
        let n = s.out.len();
        out.t = settings.t_eval.as_ref().expect("sampled")[..n].to_vec();
        out.states = s.out.iter().map(&decode).collect();
    }
    Ok(out)
}

/// Simulates a heavy top with any method and no events, handing every state (each
/// accepted step, or each of `settings.t_eval`) to `sink` instead of keeping them: the
/// same states as [`simulate`] records, in constant memory.
pub fn simulate_each(
    top: &HeavyTop,
    s0: &RigidState,
    settings: &Settings,
    sink: Sink<'_>,
) -> Result<Stats> {
    let info = method(&settings.method)?;
    check(settings, &info)?;
    if !info.adaptive {
        return fixed_into(top, s0, settings, sink);
    }
    if settings.t_eval.is_some() {
        let out = simulate(top, s0, settings, &mut [], false, &mut |_| true)?;
        for (t, s) in out.t.iter().zip(&out.states) {
            sink(*t, s);
        }
        return Ok(out.stats);
    }
    struct Each<'s>(Sink<'s>);
    impl Observer<7> for Each<'_> {
        fn start(&mut self, t0: f64, y0: &[f64; 7]) {
            (self.0)(t0, &unpack7(y0));
        }
        fn step(&mut self, t: f64, y: &[f64; 7], _: &dyn Dense<7>) -> ControlFlow<()> {
            (self.0)(t, &unpack7(y));
            ControlFlow::Continue(())
        }
    }
    let integrator = dop853(settings);
    let mut obs = Each(sink);
    let (y0, t_end) = (pack7(s0), settings.t_end);
    let (_, _, st) = if top.axial() {
        integrator.integrate(&QOmega::<true>(top), 0.0, y0, t_end, &mut obs)
    } else {
        integrator.integrate(&QOmega::<false>(top), 0.0, y0, t_end, &mut obs)
    }
    .map_err(integrate_error)?;
    Ok(Stats {
        steps: st.steps,
        rejected: st.rejected,
        rhs_evals: st.rhs_evals,
    })
}

/// Simulates a heavy top with a fixed-step method.
pub fn simulate_fixed(top: &HeavyTop, s0: &RigidState, settings: &Settings) -> Result<Output> {
    collect(|sink| fixed_into(top, s0, settings, sink))
}

/// A fixed-step run (rk4 on (q, omega) and the structure-preserving methods) handing its
/// states to `sink`.
fn fixed_into(
    top: &HeavyTop,
    s0: &RigidState,
    settings: &Settings,
    sink: Sink<'_>,
) -> Result<Stats> {
    let info = method(&settings.method)?;
    check(settings, &info)?;
    match info.name {
        "rk4" => {
            let sys = QOmega::<false>(top);
            let rk = Rk4Scheme::<_, 7> { sys: &sys };
            run_fixed(&rk, (pack7(s0), 0.0), settings, |y| unpack7(&y.0), 4, sink)
        }
        "splitting" | "splitting4" | "splitting6" => {
            let sch = Splitting::new(top, info.order)?;
            run_fixed(&sch, sch.encode(s0), settings, |y| sch.decode(y), 0, sink)
        }
        "verlet" => {
            let (sch, y0) = Verlet::new(top, s0)?;
            run_fixed(&sch, y0, settings, |y| sch.decode(y), 0, sink)
        }
        "midpoint" | "gauss4" => {
            let sys = QM(top);
            let m = top.momentum(s0.omega);
            let q = s0.q.0;
            let y0 = ([q[0], q[1], q[2], q[3], m[0], m[1], m[2]], 0.0);
            let decode = |y: &([f64; 7], f64)| RigidState {
                q: Quat([y.0[0], y.0[1], y.0[2], y.0[3]]).normalized(),
                omega: top.omega([y.0[4], y.0[5], y.0[6]]),
            };
            if info.name == "midpoint" {
                run_fixed(
                    &Midpoint::<_, 7> { sys: &sys },
                    y0,
                    settings,
                    decode,
                    0,
                    sink,
                )
            } else {
                run_fixed(&Gauss4::<_, 7> { sys: &sys }, y0, settings, decode, 0, sink)
            }
        }
        other => Err(KreiselError::invalid(
            "method",
            f64::NAN,
            format!("{other:?} is not a fixed-step method"),
        )),
    }
}

/// Diagnostics of a simulated motion, as columns.
#[derive(Debug, Clone, Default)]
pub struct Columns {
    /// Euler angles, phi and psi unwrapped.
    pub theta: Vec<f64>,
    /// Precession angle (unwrapped).
    pub phi: Vec<f64>,
    /// Spin angle (unwrapped).
    pub psi: Vec<f64>,
    /// Energy (J).
    pub energy: Vec<f64>,
    /// Vertical angular momentum (kg m^2/s).
    pub mz: Vec<f64>,
    /// Axial angular momentum where it is an integral.
    pub m3: Option<Vec<f64>>,
    /// Kovalevskaya's integral where it is one.
    pub kovalevskaya: Option<Vec<f64>>,
}

/// Computes the diagnostics of every state.
pub fn columns(top: &HeavyTop, states: &[RigidState]) -> Columns {
    let n = states.len();
    let mut c = Columns {
        theta: Vec::with_capacity(n),
        phi: Vec::with_capacity(n),
        psi: Vec::with_capacity(n),
        energy: Vec::with_capacity(n),
        mz: Vec::with_capacity(n),
        m3: states
            .first()
            .and_then(|s| top.m3(s))
            .map(|_| Vec::with_capacity(n)),
        kovalevskaya: states
            .first()
            .and_then(|s| top.kovalevskaya(s))
            .map(|_| Vec::with_capacity(n)),
    };
    let mut angles = Unwrapped::default();
    for s in states {
        let (phi, theta, psi) = euler_from_quaternion(s.q);
        let (phi, psi) = angles.next(phi, psi);
        c.theta.push(theta);
        c.phi.push(phi);
        c.psi.push(psi);
        c.energy.push(top.energy(s));
        c.mz.push(top.mz(s));
        if let Some(v) = c.m3.as_mut() {
            v.push(top.m3(s).unwrap_or(f64::NAN));
        }
        if let Some(v) = c.kovalevskaya.as_mut() {
            v.push(top.kovalevskaya(s).unwrap_or(f64::NAN));
        }
    }
    c
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

#[doc(hidden)]
pub fn _pack(s: &RigidState) -> [f64; 7] {
    pack7(s)
}

#[doc(hidden)]
pub fn _unpack(y: &[f64; 7]) -> RigidState {
    unpack7(y)
}
