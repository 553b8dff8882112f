//! The heavy top's driver behind [`crate::simulate::simulate`]: every method, events for
//! those that locate them, rows streamed to the caller; its diagnostics columns and the
//! running summary a batch keeps.

use super::equations::{pack, unpack, QOmega, QM};
use super::splitting::Splitting;
use super::verlet::Verlet;
use super::{HeavyTop, RigidState};
use crate::error::{KreiselError, Result};
use crate::integrate::fixed::{self, FixedScheme};
use crate::integrate::implicit::{Gauss4, Midpoint};
use crate::integrate::rk4::Rk4Scheme;
use crate::integrate::{Dop853, EventSpec, Locator, OdeSystem, Stream, WithEvents};
use crate::rotation::{dot, euler_from_quaternion, Quat};
use crate::simulate::{
    self, integrate_error, relative, Accumulate, EventKind, EventRecord, MethodInfo, Model,
    RunInfo, Settings, Sink, Stats, Status, Unwrapped, UserFn,
};

/// The events a heavy top has.
const EVENTS: [EventKind; 3] = [
    EventKind::TurningPoints,
    EventKind::ThetaCrossing(0.0),
    EventKind::User,
];

/// An event function on a system's state.
pub(super) type RawEventFn<'a, const N: usize> = Box<dyn FnMut(f64, &[f64; N]) -> f64 + 'a>;

impl Model for HeavyTop {
    type State = RigidState;
    type Row = RigidState;
    type Summary = HeavySummary;
    type Acc<'a> = HeavyAcc<'a>;
    const NAME: &'static str = "heavy top";

    fn check(&self, settings: &Settings, info: &MethodInfo) -> Result<()> {
        settings.unsupported_event(Self::NAME, &EVENTS)?;
        if settings.reduced && !matches!(info.name, "dop853" | "rk4") {
            return Err(KreiselError::InvalidParameter {
                name: "reduced".into(),
                value: "True".into(),
                allowed: "the reduced route runs with the general-purpose methods \"dop853\" \
                          and \"rk4\"; the structure-preserving ones integrate the whole top"
                    .into(),
            });
        }
        Ok(())
    }

    fn run(
        &self,
        s0: &RigidState,
        settings: &Settings,
        user: &mut [UserFn<'_, RigidState>],
        keep_going: &mut dyn FnMut(f64) -> bool,
        sink: Sink<'_, RigidState>,
    ) -> Result<RunInfo> {
        let info = simulate::method(&settings.method)?;
        let top = self;
        if info.adaptive {
            let integrator = settings.dop853();
            if settings.reduced {
                let (sch, y0) = Verlet::new(top, s0)?;
                let y0 = Verlet::pack(&y0);
                let decode = |y: &[f64; 4]| sch.decode_packed(y);
                return run_ode(
                    &integrator,
                    &sch,
                    y0,
                    decode,
                    settings,
                    user,
                    keep_going,
                    sink,
                );
            }
            return if top.axial() {
                let sys = QOmega::<true>(top);
                run_ode(
                    &integrator,
                    &sys,
                    pack(s0),
                    unpack,
                    settings,
                    user,
                    keep_going,
                    sink,
                )
            } else {
                let sys = QOmega::<false>(top);
                run_ode(
                    &integrator,
                    &sys,
                    pack(s0),
                    unpack,
                    settings,
                    user,
                    keep_going,
                    sink,
                )
            };
        }
        match info.name {
            "rk4" if settings.reduced => {
                let (sch, y0) = Verlet::new(top, s0)?;
                let rk = Rk4Scheme::<_, 4> { sys: &sch };
                let y0 = (Verlet::pack(&y0), 0.0);
                let decode = |y: &([f64; 4], f64)| sch.decode_packed(&y.0);
                fixed_info(run_fixed(&rk, y0, settings, decode, keep_going, sink)?, 4)
            }
            "rk4" => {
                let sys = QOmega::<false>(top);
                let rk = Rk4Scheme::<_, 7> { sys: &sys };
                let decode = |y: &([f64; 7], f64)| unpack(&y.0);
                let y0 = (pack(s0), 0.0);
                fixed_info(run_fixed(&rk, y0, settings, decode, keep_going, sink)?, 4)
            }
            "splitting" | "splitting4" | "splitting6" => {
                let sch = Splitting::new(top, info.order)?;
                let decode = |y: &_| sch.decode(y);
                let y0 = sch.encode(s0);
                fixed_info(run_fixed(&sch, y0, settings, decode, keep_going, sink)?, 0)
            }
            "verlet" => {
                let (sch, y0) = Verlet::new(top, s0)?;
                let decode = |y: &_| sch.decode(y);
                fixed_info(run_fixed(&sch, y0, settings, decode, keep_going, sink)?, 0)
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
                    let sch = Midpoint::<_, 7> { sys: &sys };
                    fixed_info(run_fixed(&sch, y0, settings, decode, keep_going, sink)?, 0)
                } else {
                    let sch = Gauss4::<_, 7> { sys: &sys };
                    fixed_info(run_fixed(&sch, y0, settings, decode, keep_going, sink)?, 0)
                }
            }
            other => Err(KreiselError::InvalidParameter {
                name: "method".into(),
                value: format!("{other:?}"),
                allowed: "a method of simulate::METHODS".into(),
            }),
        }
    }

    fn summary<'a>(&'a self, s0: &RigidState, _settings: &Settings) -> HeavyAcc<'a> {
        HeavyAcc::new(self, s0)
    }

    type Columns = Columns;

    fn column_names(&self) -> Vec<&'static str> {
        HeavyTop::column_names(self)
    }

    fn columns(&self, rows: &[RigidState]) -> Columns {
        HeavyTop::columns(self, rows)
    }
}

/// What a fixed-step run of `steps` steps, completed or not, reports.
pub(super) fn fixed_info((steps, done): (u64, bool), rhs_per_step: u64) -> Result<RunInfo> {
    Ok(RunInfo {
        stats: Stats {
            steps,
            rejected: 0,
            rhs_evals: steps * rhs_per_step,
        },
        events: Vec::new(),
        status: if done {
            Status::Completed
        } else {
            Status::Interrupted
        },
    })
}

/// Runs a fixed-step scheme and hands its decoded states to `sink`: (steps, completed).
fn run_fixed<S: FixedScheme>(
    scheme: &S,
    y0: S::Y,
    settings: &Settings,
    decode: impl Fn(&S::Y) -> RigidState,
    keep_going: &mut dyn FnMut(f64) -> bool,
    sink: Sink<'_, RigidState>,
) -> Result<(u64, bool)> {
    let dt = settings
        .dt
        .ok_or_else(|| KreiselError::invalid("dt", f64::NAN, "a fixed-step method needs dt > 0"))?;
    fixed::run(
        scheme,
        y0,
        settings.t_end,
        dt,
        settings.t_eval.as_deref(),
        |t, y| sink(t, &decode(y)),
        keep_going,
    )
}

/// The event function of a built-in kind, on the decoded state.
pub(super) fn builtin_event(kind: EventKind, s: &RigidState) -> f64 {
    match kind {
        EventKind::TurningPoints => {
            // u = cos(theta) = Gamma_3 and du/dt = (Gamma x omega)_3; theta_dot has the
            // sign of -du/dt.
            let g = s.q.up_in_body();
            -(g[0] * s.omega[1] - g[1] * s.omega[0])
        }
        EventKind::ThetaCrossing(v) => v.cos() - s.q.up_in_body()[2],
        _ => f64::NAN,
    }
}

/// The event functions of `settings` on a system's state (decoded to a rigid state): the
/// built-in kinds and `user`'s functions, in order.
pub(super) fn event_fns<'a, const N: usize>(
    settings: &Settings,
    user: &'a mut [UserFn<'_, RigidState>],
    decode: &'a impl Fn(&[f64; N]) -> RigidState,
) -> Result<Vec<RawEventFn<'a, N>>> {
    let mut users = user.iter_mut();
    let mut fns: Vec<RawEventFn<'a, N>> = Vec::with_capacity(settings.events.len() + 1);
    for e in &settings.events {
        let kind = e.kind;
        fns.push(match kind {
            EventKind::User => {
                let f = users.next().ok_or_else(|| {
                    KreiselError::invalid("events", f64::NAN, "a user event has no function")
                })?;
                Box::new(move |t: f64, y: &[f64; N]| f(t, &decode(y)))
            }
            _ => Box::new(move |_t: f64, y: &[f64; N]| builtin_event(kind, &decode(y))),
        });
    }
    Ok(fns)
}

#[allow(clippy::too_many_arguments)]
fn run_ode<const N: usize, S: OdeSystem<N>>(
    integrator: &Dop853,
    sys: &S,
    y0: [f64; N],
    decode: impl Fn(&[f64; N]) -> RigidState,
    settings: &Settings,
    user: &mut [UserFn<'_, RigidState>],
    keep_going: &mut dyn FnMut(f64) -> bool,
    sink: Sink<'_, RigidState>,
) -> Result<RunInfo> {
    let decode = &decode;
    let mut stream = Stream::new(
        settings.t_eval.as_deref(),
        false,
        Some(keep_going),
        |t, y| sink(t, &decode(y)),
    );
    let mut fns = event_fns(settings, user, decode)?;
    let t_end = settings.t_end;
    let (t1, st, hits) = if fns.is_empty() {
        // No events: the stream alone observes (no locator to consult after every step).
        let result = integrator.integrate(sys, 0.0, y0, t_end, &mut stream);
        let (t1, _, st) = result.map_err(|e| integrate_error(e, t_end))?;
        (t1, st, Vec::new())
    } else {
        let mut locator = Locator::new();
        for (f, e) in fns.iter_mut().zip(&settings.events) {
            locator.add(EventSpec::new(e.direction, e.terminal), f.as_mut());
        }
        let mut obs = WithEvents::new(locator, &mut stream);
        let result = integrator.integrate(sys, 0.0, y0, t_end, &mut obs);
        let (t1, _, st) = result.map_err(|e| integrate_error(e, t_end))?;
        let hits: Vec<(usize, f64)> = obs.locator.events.iter().map(|e| (e.index, e.t)).collect();
        (t1, st, hits)
    };
    let terminal = hits.iter().any(|&(i, _)| settings.events[i].terminal);
    let mut stats = Stats::default();
    stats += st;
    Ok(RunInfo {
        stats,
        events: hits
            .into_iter()
            .map(|(i, t)| EventRecord {
                index: Some(i),
                name: settings.events[i].name.clone().into(),
                t,
                part: None,
            })
            .collect(),
        status: if terminal {
            Status::Event
        } else if t1 < t_end {
            Status::Interrupted
        } else {
            Status::Completed
        },
    })
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
    /// Potential energy m g c.Gamma (J).
    pub potential: Vec<f64>,
    /// Axial angular momentum where it is an integral.
    pub m3: Option<Vec<f64>>,
    /// Kovalevskaya's integral where it is one.
    pub kovalevskaya: Option<Vec<f64>>,
}

/// Any state: whether an integral exists depends on the top alone.
const PROBE: RigidState = RigidState {
    q: Quat([1.0, 0.0, 0.0, 0.0]),
    omega: [0.0; 3],
};

impl HeavyTop {
    /// The names of the diagnostics columns of this top's runs ([`HeavyTop::columns`]).
    pub fn column_names(&self) -> Vec<&'static str> {
        let mut names = vec!["theta", "phi", "psi", "energy", "potential", "Mz"];
        if self.m3(&PROBE).is_some() {
            names.push("M3");
        }
        if self.kovalevskaya(&PROBE).is_some() {
            names.push("kovalevskaya");
        }
        names
    }

    /// The diagnostics of every state.
    pub fn columns(&self, states: &[RigidState]) -> Columns {
        let top = self;
        let n = states.len();
        let mut c = Columns {
            theta: Vec::with_capacity(n),
            phi: Vec::with_capacity(n),
            psi: Vec::with_capacity(n),
            energy: Vec::with_capacity(n),
            mz: Vec::with_capacity(n),
            potential: Vec::with_capacity(n),
            m3: top.m3(&PROBE).map(|_| Vec::with_capacity(n)),
            kovalevskaya: top.kovalevskaya(&PROBE).map(|_| Vec::with_capacity(n)),
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
            c.potential.push(dot(top.mgc(), s.q.up_in_body()));
            if let Some(v) = c.m3.as_mut() {
                v.push(top.m3(s).unwrap_or(f64::NAN));
            }
            if let Some(v) = c.kovalevskaya.as_mut() {
                v.push(top.kovalevskaya(s).unwrap_or(f64::NAN));
            }
        }
        c
    }
}

/// What is kept of one heavy-top run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeavySummary {
    /// theta at the end (rad).
    pub final_theta: f64,
    /// Smallest theta over the recorded states (rad).
    pub theta_min: f64,
    /// Largest theta over the recorded states (rad).
    pub theta_max: f64,
    /// Largest |E - E0| over the run, relative to the energy scale T0 + m g |c|.
    pub energy_drift: f64,
    /// Largest |Mz - Mz0| over the run, relative to |M0| (absolute if M0 = 0).
    pub mz_drift: f64,
    /// Largest |M3 - M3_0| relative to |M0| where M3 is an integral (symmetric tops), else NaN.
    pub m3_drift: f64,
    /// Largest |K - K0| relative to |K0| where Kovalevskaya's K is an integral, else NaN.
    pub kovalevskaya_drift: f64,
    /// Accepted steps.
    pub steps: u64,
}

impl HeavySummary {
    /// The summary's fields by their public names ([`crate::simulate::SUMMARY_FIELDS`]).
    pub fn get(&self, name: &str) -> Option<f64> {
        Some(match name {
            "final_theta" => self.final_theta,
            "theta_min" => self.theta_min,
            "theta_max" => self.theta_max,
            "energy_drift" => self.energy_drift,
            "Mz_drift" => self.mz_drift,
            "M3_drift" => self.m3_drift,
            "kovalevskaya_drift" => self.kovalevskaya_drift,
            "steps" => self.steps as f64,
            _ => return None,
        })
    }
}

/// The running summary of a heavy-top run, fed one state at a time.
pub struct HeavyAcc<'a> {
    top: &'a HeavyTop,
    e0: f64,
    mz0: f64,
    m30: Option<f64>,
    k0: Option<f64>,
    m_norm: f64,
    e_scale: f64,
    theta: f64,
    th_min: f64,
    th_max: f64,
    de: f64,
    dmz: f64,
    dm3: f64,
    dk: f64,
}

impl<'a> HeavyAcc<'a> {
    fn new(top: &'a HeavyTop, s0: &RigidState) -> Self {
        let mom = top.momentum(s0.omega);
        let c = top.com();
        let kinetic = 0.5 * (mom[0] * s0.omega[0] + mom[1] * s0.omega[1] + mom[2] * s0.omega[2]);
        HeavyAcc {
            top,
            e0: top.energy(s0),
            mz0: top.mz(s0),
            m30: top.m3(s0),
            k0: top.kovalevskaya(s0),
            m_norm: (mom[0] * mom[0] + mom[1] * mom[1] + mom[2] * mom[2]).sqrt(),
            e_scale: kinetic + top.m() * top.g() * (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt(),
            theta: f64::NAN,
            th_min: f64::INFINITY,
            th_max: f64::NEG_INFINITY,
            de: 0.0,
            dmz: 0.0,
            dm3: 0.0,
            dk: 0.0,
        }
    }
}

impl Accumulate<RigidState> for HeavyAcc<'_> {
    type Summary = HeavySummary;

    fn push(&mut self, _t: f64, s: &RigidState) {
        let top = self.top;
        self.theta = euler_from_quaternion(s.q).1;
        self.th_min = self.th_min.min(self.theta);
        self.th_max = self.th_max.max(self.theta);
        self.de = self.de.max((top.energy(s) - self.e0).abs());
        self.dmz = self.dmz.max((top.mz(s) - self.mz0).abs());
        if let (Some(a), Some(b)) = (self.m30, top.m3(s)) {
            self.dm3 = self.dm3.max((b - a).abs());
        }
        if let (Some(a), Some(b)) = (self.k0, top.kovalevskaya(s)) {
            self.dk = self.dk.max((b - a).abs());
        }
    }

    fn finish(self, info: &RunInfo) -> HeavySummary {
        HeavySummary {
            final_theta: self.theta,
            theta_min: self.th_min,
            theta_max: self.th_max,
            energy_drift: relative(self.de, self.e_scale),
            mz_drift: relative(self.dmz, self.m_norm),
            m3_drift: self
                .m30
                .map_or(f64::NAN, |_| relative(self.dm3, self.m_norm)),
            kovalevskaya_drift: self.k0.map_or(f64::NAN, |k| relative(self.dk, k.abs())),
            steps: info.stats.steps,
        }
    }
}
