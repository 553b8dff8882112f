//! The play top's driver behind [`crate::simulate::simulate`]: a hybrid of smooth phases
//! (slip, roll, flight), each integrated with DOP853 and ended by located events, joined by
//! the switches of [`super::contact`]; its diagnostics columns and the running summary a
//! batch keeps.

use super::contact::{Phase, Switch};
use super::{law, Friction, Mode, PlayTop, RhsConsts, DIM};
use crate::error::{KreiselError, Result};
use crate::integrate::{
    Dop853, EventSpec, IntegrateError, Locator, Observer, OdeSystem, Stream, WithEvents,
};
use crate::simulate::{
    integrate_error, relative, Accumulate, EventKind, EventRecord, MethodInfo, Model, RunInfo,
    Settings, Sink, Status, UserFn, MAX_STEPS,
};
use std::cell::Cell;

/// One output row of a play-top run: the state, its contact mode, and the slip direction
/// in force at zero slip speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlayRow {
    /// State (see [`DIM`]).
    pub y: [f64; DIM],
    /// Contact mode.
    pub mode: Mode,
    /// Slip direction in force at zero slip speed.
    pub dir: [f64; 3],
}

/// The events a play top has besides its contact switches.
const EVENTS: [EventKind; 2] = [EventKind::Inversion(0.0), EventKind::Rest];

/// The most contact switches a run may make before it is taken for chattering.
const MAX_SWITCHES: usize = 200_000;

type RawEventFn<'a> = Box<dyn FnMut(f64, &[f64; DIM]) -> f64 + 'a>;

impl Model for PlayTop {
    type State = [f64; DIM];
    type Row = PlayRow;
    type Summary = PlaySummary;
    type Acc<'a> = PlayAcc<'a>;
    const NAME: &'static str = "play top";

    fn check(&self, settings: &Settings, info: &MethodInfo) -> Result<()> {
        if info.name != "dop853" {
            return Err(KreiselError::InvalidParameter {
                name: "method".into(),
                value: format!("{:?}", info.name),
                allowed: "a play top's contact modes, events and impacts need the adaptive \
                          \"dop853\""
                    .into(),
            });
        }
        if settings.reduced {
            return Err(KreiselError::InvalidParameter {
                name: "reduced".into(),
                value: "True".into(),
                allowed: "the reduced route is the Lagrange top's".into(),
            });
        }
        settings.unsupported_event(Self::NAME, &EVENTS)
    }

    fn run(
        &self,
        y0: &[f64; DIM],
        settings: &Settings,
        _user: &mut [UserFn<'_, [f64; DIM]>],
        keep_going: &mut dyn FnMut(f64) -> bool,
        sink: Sink<'_, PlayRow>,
    ) -> Result<RunInfo> {
        let top = self;
        let t_end = settings.t_end;
        let mut info = RunInfo::default();
        let mut y = *y0;
        let mut phase = top.initial_phase(&mut y, settings.rtol);
        let mut t = 0.0;
        let mut next_sample = 0usize;
        // Each inversion event fires once.
        let mut fired = vec![false; settings.events.len()];
        let coulomb = matches!(top.friction, Friction::Coulomb { .. });
        let ke0 = {
            let (tr, rot, _) = top.energy_parts(&y);
            tr + rot
        };
        let mut first = true;
        let mut stopped = false;
        loop {
            let integrator = Dop853 {
                rtol: settings.rtol,
                atol: settings.atol,
                h_init: None,
                h_max: top.phase_step(&phase, &y),
                max_steps: MAX_STEPS,
            };
            let eps = top.slip_tolerance(&y, settings.rtol);
            let ph = phase;
            // The contact switches of this mode (terminal), then the watched events.
            let last = Cell::new(LastRhs::NONE);
            let switches = Switch::watched(ph.mode, coulomb);
            let mut fns: Vec<RawEventFn<'_>> = Vec::with_capacity(switches.len() + 2);
            let mut specs = Vec::with_capacity(switches.len() + 2);
            for &sw in switches {
                let last = &last;
                fns.push(if sw == Switch::LiftOff {
                    Box::new(move |t: f64, y: &[f64; DIM]| {
                        let c = last.get();
                        if c.t == t && c.q == [y[0], y[1], y[2], y[3]] {
                            // The end of a step, just evaluated by the integrator (LastRhs).
                            return c.n;
                        }
                        top.switch_value(sw, &ph, y, eps)
                    })
                } else {
                    Box::new(move |_t: f64, y: &[f64; DIM]| top.switch_value(sw, &ph, y, eps))
                });
                specs.push(EventSpec::new(-1, true));
            }
            let mut watched = Vec::with_capacity(settings.events.len());
            for (i, e) in settings.events.iter().enumerate() {
                match e.kind {
                    EventKind::Inversion(level) if !fired[i] => {
                        fns.push(Box::new(move |_t: f64, y: &[f64; DIM]| {
                            top.kin(y).u - level
                        }));
                    }
                    EventKind::Rest => {
                        fns.push(Box::new(move |_t: f64, y: &[f64; DIM]| {
                            let (tr, rot, _) = top.energy_parts(y);
                            tr + rot - 1e-12 * ke0
                        }));
                    }
                    _ => continue,
                }
                specs.push(EventSpec::new(e.direction, e.terminal));
                watched.push(i);
            }
            let mut locator = Locator::new();
            for (f, spec) in fns.iter_mut().zip(&specs) {
                locator.add(*spec, f.as_mut());
            }
            // Output times of this phase.
            let seg_times: Option<&[f64]> = settings.t_eval.as_deref().map(|te| {
                let mut i = next_sample;
                while i < te.len() && (te[i] < t || (!first && te[i] <= t)) {
                    i += 1;
                }
                &te[i..]
            });
            let offset = settings
                .t_eval
                .as_deref()
                .map_or(0, |te| te.len() - seg_times.map_or(0, |s| s.len()));
            // Every step's row, except a later phase's first: the switch already gave it.
            let row = |ts: f64, yy: &[f64; DIM]| {
                sink(
                    ts,
                    &PlayRow {
                        y: *yy,
                        mode: ph.mode,
                        dir: ph.dir,
                    },
                )
            };
            let mut stream = Stream::new(seg_times, !first, Some(&mut *keep_going), row);
            let mut obs = WithEvents::new(locator, &mut stream);
            let (t1, y1, st) = integrate_phase(&integrator, top, &ph, &last, t, y, t_end, &mut obs)
                .map_err(|e| match integrate_error(e, t_end) {
                    KreiselError::Numerical(m) => {
                        KreiselError::Numerical(format!("play top, {} mode: {m}", ph.mode.name()))
                    }
                    other => other,
                })?;
            let hits: Vec<(usize, f64)> =
                obs.locator.events.iter().map(|e| (e.index, e.t)).collect();
            drop(obs);
            next_sample = offset + stream.taken;
            drop(fns);
            info.stats += st;
            first = false;
            let mut reason = None;
            for (idx, te) in hits {
                if let Some(&sw) = switches.get(idx) {
                    info.events.push(EventRecord {
                        index: None,
                        name: sw.name().into(),
                        t: te,
                    });
                    reason = Some(sw);
                } else {
                    let i = watched[idx - switches.len()];
                    let e = &settings.events[i];
                    info.events.push(EventRecord {
                        index: Some(i),
                        name: e.name.clone().into(),
                        t: te,
                    });
                    if matches!(e.kind, EventKind::Inversion(_)) {
                        fired[i] = true;
                    }
                    stopped |= e.terminal;
                }
            }
            t = t1;
            y = y1;
            let Some(switch) = reason.filter(|_| !stopped && t < t_end) else {
                break;
            };
            phase = top.switch(switch, &phase, &mut y, settings.rtol);
            // The state after the switch at the same time (impacts make it jump).
            if settings.t_eval.is_none() {
                sink(
                    t,
                    &PlayRow {
                        y,
                        mode: phase.mode,
                        dir: phase.dir,
                    },
                );
            }
            if info.events.len() > MAX_SWITCHES {
                return Err(KreiselError::Numerical(format!(
                    "play top: more than {MAX_SWITCHES} mode switches before t = {t} \
                     (chattering); the model's contact modes do not settle here"
                )));
            }
        }
        info.status = if stopped {
            Status::Event
        } else if t < t_end {
            Status::Interrupted
        } else {
            Status::Completed
        };
        Ok(info)
    }

    fn summary<'a>(&'a self, _y0: &[f64; DIM], settings: &Settings) -> PlayAcc<'a> {
        PlayAcc {
            top: self,
            inversion: settings
                .events
                .iter()
                .position(|e| matches!(e.kind, EventKind::Inversion(_))),
            first: None,
            jd: 0.0,
            ed: 0.0,
            last: None,
        }
    }

    type Columns = PlayColumns;

    fn column_names(&self) -> Vec<&'static str> {
        PlayTop::COLUMN_NAMES.to_vec()
    }

    fn columns(&self, rows: &[PlayRow]) -> PlayColumns {
        PlayTop::columns(self, rows)
    }
}

/// The equations of the contact mode with code `M` ([`Mode::code`]), with the resistance
/// torques when `RES` ([`PlayTop::has_resistance`]) and the friction law `LAW` ([`law`]):
/// constants, so that each variant's right-hand side is compiled without the dispatch on
/// them.
struct ModeSystem<'a, const M: u8, const RES: bool, const LAW: u8> {
    top: &'a PlayTop,
    consts: RhsConsts,
    dir: [f64; 3],
    last: &'a Cell<LastRhs>,
}

/// The last right-hand side evaluated: its time, orientation and normal force. The
/// integrator evaluates the right-hand side at the (projected) end of every accepted step
/// just before the events are checked there, so the lift-off event takes that normal force
/// instead of computing it again. The key is the time and the orientation (the state's
/// other components are not kept: storing the whole state costs more than it saves); a
/// stage or root-finding state at the same time has another orientation (a step's last
/// stage is not projected), so only the step's end state reuses it.
#[derive(Clone, Copy)]
struct LastRhs {
    t: f64,
    q: [f64; 4],
    n: f64,
}

impl LastRhs {
    const NONE: LastRhs = LastRhs {
        t: f64::NAN,
        q: [f64::NAN; 4],
        n: f64::NAN,
    };
}

impl<const M: u8, const RES: bool, const LAW: u8> OdeSystem<DIM> for ModeSystem<'_, M, RES, LAW> {
    #[inline(always)]
    fn rhs(&self, t: f64, y: &[f64; DIM], dy: &mut [f64; DIM]) {
        let c =
            self.top
                .dynamics_with::<RES, LAW>(&self.consts, Mode::from_code(M), y, self.dir, dy);
        self.last.set(LastRhs {
            t,
            q: [y[0], y[1], y[2], y[3]],
            n: c.n,
        });
    }
    fn project(&self, y: &mut [f64; DIM]) {
        self.top.project(Mode::from_code(M), y);
    }
}

/// Integrates one phase in `mode` (see [`ModeSystem`]); every right-hand side evaluated is
/// left in `last`.
#[allow(clippy::too_many_arguments)]
fn integrate_phase<O: Observer<DIM>>(
    integrator: &Dop853,
    top: &PlayTop,
    phase: &Phase,
    last: &Cell<LastRhs>,
    t: f64,
    y: [f64; DIM],
    t_end: f64,
    obs: &mut O,
) -> std::result::Result<(f64, [f64; DIM], crate::integrate::Stats), IntegrateError> {
    const SLIP: u8 = Mode::Slip.code();
    const ROLL: u8 = Mode::Roll.code();
    const FLIGHT: u8 = Mode::Flight.code();
    let consts = top.rhs_consts();
    let (mode, dir) = (phase.mode, phase.dir);
    macro_rules! run {
        ($m:expr, $res:expr, $law:expr) => {
            integrator.integrate(
                &ModeSystem::<{ $m }, { $res }, { $law }> {
                    top,
                    consts,
                    dir,
                    last,
                },
                t,
                y,
                t_end,
                obs,
            )
        };
    }
    // The friction law matters in slip only; tops with resistance torques look it up.
    match (mode, top.has_resistance(), top.friction.law()) {
        (Mode::Slip, false, law::VISCOUS) => run!(SLIP, false, law::VISCOUS),
        (Mode::Slip, false, law::COULOMB) => run!(SLIP, false, law::COULOMB),
        (Mode::Slip, false, _) => run!(SLIP, false, law::ANY),
        (Mode::Slip, true, _) => run!(SLIP, true, law::ANY),
        (Mode::Roll, false, _) => run!(ROLL, false, law::ANY),
        (Mode::Roll, true, _) => run!(ROLL, true, law::ANY),
        (Mode::Flight, false, _) => run!(FLIGHT, false, law::ANY),
        (Mode::Flight, true, _) => run!(FLIGHT, true, law::ANY),
    }
}

/// Diagnostics of a play-top motion, as columns.
#[derive(Debug, Clone, Default)]
pub struct PlayColumns {
    /// u = cos(theta).
    pub u: Vec<f64>,
    /// Euler angles (phi, psi unwrapped).
    pub theta: Vec<f64>,
    /// Precession angle.
    pub phi: Vec<f64>,
    /// Spin angle.
    pub psi: Vec<f64>,
    /// Contact point (the sphere's lowest point), space frame.
    pub contact: Vec<[f64; 3]>,
    /// Velocity of the material point at T.
    pub slip_velocity: Vec<[f64; 3]>,
    /// Horizontal slip speed.
    pub slip_speed: Vec<f64>,
    /// Normal force (0 in flight).
    pub normal_force: Vec<f64>,
    /// Jellett's integral.
    pub jellett: Vec<f64>,
    /// Energy parts: translation, rotation, potential.
    pub energy_parts: Vec<[f64; 3]>,
}

impl PlayTop {
    /// The names of the diagnostics columns of a run ([`PlayTop::columns`]), the energy
    /// parts as three columns and their sum.
    pub const COLUMN_NAMES: [&'static str; 13] = [
        "theta",
        "phi",
        "psi",
        "u",
        "contact_point",
        "slip_velocity",
        "slip_speed",
        "normal_force",
        "jellett",
        "energy_translation",
        "energy_rotation",
        "energy_potential",
        "energy",
    ];

    /// The diagnostics of the rows of a play-top run.
    pub fn columns(&self, rows: &[PlayRow]) -> PlayColumns {
        if self.has_resistance() {
            columns_with::<true>(self, rows)
        } else {
            columns_with::<false>(self, rows)
        }
    }
}

/// [`PlayTop::columns`], with the resistance torques compiled in when `RES`
/// ([`PlayTop::dynamics_with`]).
fn columns_with<const RES: bool>(top: &PlayTop, all: &[PlayRow]) -> PlayColumns {
    use crate::rotation::euler_from_matrix;
    use crate::simulate::Unwrapped;
    // Rows in blocks, then the blocks' columns: pushing to ten columns per row costs more
    // than the row's arithmetic, and rows for the whole run would be a large allocation.
    #[derive(Clone, Copy, Default)]
    struct Row {
        u: f64,
        euler: (f64, f64, f64),
        contact: [f64; 3],
        slip_velocity: [f64; 3],
        slip_speed: f64,
        normal_force: f64,
        jellett: f64,
        energy_parts: [f64; 3],
    }
    const BLOCK: usize = 128;
    let n = all.len();
    let mut c = PlayColumns {
        u: Vec::with_capacity(n),
        theta: Vec::with_capacity(n),
        phi: Vec::with_capacity(n),
        psi: Vec::with_capacity(n),
        contact: Vec::with_capacity(n),
        slip_velocity: Vec::with_capacity(n),
        slip_speed: Vec::with_capacity(n),
        normal_force: Vec::with_capacity(n),
        jellett: Vec::with_capacity(n),
        energy_parts: Vec::with_capacity(n),
    };
    let consts = top.rhs_consts();
    let mut angles = Unwrapped::default();
    let mut rows = [Row::default(); BLOCK];
    for start in (0..n).step_by(BLOCK) {
        let end = n.min(start + BLOCK);
        for (row, r) in rows.iter_mut().zip(&all[start..end]) {
            let (y, mode, dir) = (&r.y, r.mode, r.dir);
            let k = top.kin(y);
            let (phi, theta, psi) = euler_from_matrix(k.r);
            let (phi, psi) = angles.next(phi, psi);
            let mut dy = [0.0; DIM];
            let (a, b, p) = top.energy_parts(y);
            *row = Row {
                u: k.u,
                euler: (phi, theta, psi),
                contact: [y[7] + k.a_s[0], y[8] + k.a_s[1], y[9] + k.a_s[2]],
                slip_velocity: k.v_t,
                slip_speed: (k.v_t[0] * k.v_t[0] + k.v_t[1] * k.v_t[1]).sqrt(),
                normal_force: top
                    .dynamics_with::<RES, { law::ANY }>(&consts, mode, y, dir, &mut dy)
                    .n,
                jellett: top.jellett(y),
                energy_parts: [a, b, p],
            };
        }
        let rows = &rows[..end - start];
        c.u.extend(rows.iter().map(|r| r.u));
        c.theta.extend(rows.iter().map(|r| r.euler.1));
        c.phi.extend(rows.iter().map(|r| r.euler.0));
        c.psi.extend(rows.iter().map(|r| r.euler.2));
        c.contact.extend(rows.iter().map(|r| r.contact));
        c.slip_velocity.extend(rows.iter().map(|r| r.slip_velocity));
        c.slip_speed.extend(rows.iter().map(|r| r.slip_speed));
        c.normal_force.extend(rows.iter().map(|r| r.normal_force));
        c.jellett.extend(rows.iter().map(|r| r.jellett));
        c.energy_parts.extend(rows.iter().map(|r| r.energy_parts));
    }
    c
}

/// What a batch run keeps of each simulation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaySummary {
    /// u at the end.
    pub final_u: f64,
    /// Mode at the end.
    pub final_mode: Mode,
    /// Time of the first upward crossing of the inversion level (NaN if none).
    pub inversion_time: f64,
    /// Largest |J - J0| / |J0| over the run.
    pub jellett_drift: f64,
    /// Largest |E + dissipated - E0| / |E0| over the run.
    pub energy_drift: f64,
    /// Accepted steps.
    pub steps: u64,
}

impl PlaySummary {
    /// The summary's fields by their public names ([`crate::simulate::SUMMARY_FIELDS`]);
    /// a category as its code.
    pub fn get(&self, name: &str) -> Option<f64> {
        Some(match name {
            "final_u" => self.final_u,
            "final_mode" => self.final_mode.code() as f64,
            "inversion_time" => self.inversion_time,
            "jellett_drift" => self.jellett_drift,
            "energy_drift" => self.energy_drift,
            "steps" => self.steps as f64,
            _ => return None,
        })
    }
}

/// The running summary of a play-top run, fed one row at a time.
pub struct PlayAcc<'a> {
    top: &'a PlayTop,
    /// Position of the inversion event in the settings.
    inversion: Option<usize>,
    /// Jellett's integral and the energy of the first row.
    first: Option<(f64, f64)>,
    jd: f64,
    ed: f64,
    last: Option<PlayRow>,
}

impl Accumulate<PlayRow> for PlayAcc<'_> {
    type Summary = PlaySummary;

    fn push(&mut self, _t: f64, row: &PlayRow) {
        let top = self.top;
        let y = &row.y;
        let (j0, e0) = *self.first.get_or_insert_with(|| {
            let (a, b, c) = top.energy_parts(y);
            (top.jellett(y), a + b + c)
        });
        self.jd = self.jd.max((top.jellett(y) - j0).abs());
        let (a, b, c) = top.energy_parts(y);
        self.ed = self.ed.max((a + b + c + y[13] - e0).abs());
        self.last = Some(*row);
    }

    fn finish(self, info: &RunInfo) -> PlaySummary {
        let (j0, e0) = self.first.unwrap_or((f64::NAN, f64::NAN));
        let last = self.last;
        PlaySummary {
            final_u: last.map_or(f64::NAN, |r| self.top.kin(&r.y).u),
            final_mode: last.map_or(Mode::Flight, |r| r.mode),
            inversion_time: info
                .events
                .iter()
                .find(|e| e.index.is_some() && e.index == self.inversion)
                .map_or(f64::NAN, |e| e.t),
            jellett_drift: relative(self.jd, j0.abs()),
            energy_drift: relative(self.ed, e0.abs()),
            steps: info.stats.steps,
        }
    }
}
