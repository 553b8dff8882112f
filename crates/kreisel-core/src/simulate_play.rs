//! Simulation of the play top: a hybrid of smooth phases (slip, roll, flight), each
//! integrated with DOP853 and ended by located events, joined by mode switches and impacts.
//!
//! Switches: slip -> roll when the slip speed falls to (numerically) zero and the rolling
//! force lies in the Coulomb cone; roll -> slip when the rolling force leaves the cone
//! (the slip then starts against the force that rolling would have needed); either contact
//! mode -> flight when the normal force falls to zero; flight -> contact at touchdown,
//! through an impact with restitution and a Coulomb friction impulse.

use crate::error::{KreiselError, Result};
use crate::integrate::{
    Dop853, EventSpec, IntegrateError, Locator, Observer, OdeSystem, Recorder, Stats, WithEvents,
};
use crate::models::play_top::{law, Friction, Mode, PlayTop, RhsConsts, DIM};
use std::cell::Cell;

/// Settings of a play-top simulation.
#[derive(Debug, Clone)]
pub struct PlaySettings {
    /// End time (s).
    pub t_end: f64,
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
    /// Output times (ascending, in [0, t_end]); None: every step.
    pub t_eval: Option<Vec<f64>>,
    /// u level whose upward crossing is reported as "inversion" (None: not watched).
    pub inversion_level: Option<f64>,
    /// Stop at the first inversion.
    pub stop_at_inversion: bool,
    /// Stop when the top comes to rest (kinetic energy below 1e-12 of its start).
    pub stop_at_rest: bool,
}

/// A simulated play-top motion.
#[derive(Debug, Clone, Default)]
pub struct PlayOutput {
    /// Times (s); an event time appears twice when the state jumps there (impact).
    pub t: Vec<f64>,
    /// States.
    pub y: Vec<[f64; DIM]>,
    /// Mode at each output.
    pub mode: Vec<Mode>,
    /// Slip direction in force at each output (for zero slip speed).
    pub dir: Vec<[f64; 3]>,
    /// Events: (name, time).
    pub events: Vec<(&'static str, f64)>,
    /// Accepted steps.
    pub steps: u64,
    /// Rejected steps.
    pub rejected: u64,
    /// Right-hand-side evaluations.
    pub rhs_evals: u64,
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
    mode: Mode,
    dir: [f64; 3],
    last: &Cell<LastRhs>,
    t: f64,
    y: [f64; DIM],
    t_end: f64,
    obs: &mut O,
) -> std::result::Result<(f64, [f64; DIM], Stats), IntegrateError> {
    const SLIP: u8 = Mode::Slip.code();
    const ROLL: u8 = Mode::Roll.code();
    const FLIGHT: u8 = Mode::Flight.code();
    let consts = top.rhs_consts();
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

/// The normal force sliding would need at a state (negative: the floor would have to pull).
fn slip_normal(top: &PlayTop, y: &[f64; DIM], dir: [f64; 3]) -> f64 {
    let mut dy = [0.0; DIM];
    top.dynamics(Mode::Slip, y, dir, &mut dy).n
}

/// The mode a state starts in.
pub fn initial_mode(top: &PlayTop, y: &[f64; DIM]) -> Mode {
    if top.height(y) > 1e-12 * top.rho {
        return Mode::Flight;
    }
    let k = top.kin(y);
    let sp = (k.v_t[0] * k.v_t[0] + k.v_t[1] * k.v_t[1]).sqrt();
    let mut dy = [0.0; DIM];
    let slip_n = top.dynamics(Mode::Slip, y, [0.0; 3], &mut dy).n;
    if slip_n < 0.0 {
        return Mode::Flight;
    }
    if sp <= 1e-12 * top.slip_scale(&k) && top.roll_admissible(y).0 {
        Mode::Roll
    } else {
        Mode::Slip
    }
}

const MAX_SWITCHES: usize = 200_000;

/// Simulates a play top from `y0` (mode chosen from the state).
pub fn simulate_play(top: &PlayTop, y0: [f64; DIM], settings: &PlaySettings) -> Result<PlayOutput> {
    let t_end = settings.t_end;
    let mut out = PlayOutput::default();
    let mut y = y0;
    let mut mode = initial_mode(top, &y);
    top.project(mode, &mut y);
    let mut dir = [0.0; 3];
    // Expected duration of the current flight after a bounce (infinite: unknown).
    let mut hop = f64::INFINITY;
    let mut t = 0.0;
    let mut next_sample = 0usize;
    let mut inverted = false;
    let mu = match top.friction {
        Friction::Coulomb { mu } => Some(mu),
        _ => None,
    };
    let ke0 = {
        let (tr, rot, _) = top.energy_parts(&y);
        tr + rot
    };
    let mut first = true;
    loop {
        let integrator = Dop853 {
            rtol: settings.rtol,
            atol: settings.atol,
            h_init: None,
            h_max: if mode == Mode::Flight {
                top.flight_step(&y).min(hop / 4.0)
            } else {
                f64::INFINITY
            },
            max_steps: 100_000_000,
        };
        // Slip speed taken as zero: well above the integration error of the slip itself.
        let eps = (10.0 * settings.rtol).max(1e-10) * top.slip_scale(&top.kin(&y));
        // Mode events (terminal) then watched ones.
        let last = Cell::new(LastRhs::NONE);
        let mut g_liftoff = |t: f64, y: &[f64; DIM]| {
            let c = last.get();
            if c.t == t && c.q == [y[0], y[1], y[2], y[3]] {
                // The end of a step, just evaluated by the integrator (see LastRhs).
                return c.n;
            }
            let mut dy = [0.0; DIM];
            top.dynamics(mode, y, dir, &mut dy).n
        };
        let mut g_stop_slip = |_t: f64, y: &[f64; DIM]| {
            let k = top.kin(y);
            (k.v_t[0] * k.v_t[0] + k.v_t[1] * k.v_t[1]).sqrt() - eps
        };
        let mut g_cone = |_t: f64, y: &[f64; DIM]| {
            let mut dy = [0.0; DIM];
            let c = top.dynamics(Mode::Roll, y, dir, &mut dy);
            mu.unwrap_or(0.0) * c.n - (c.ft[0] * c.ft[0] + c.ft[1] * c.ft[1]).sqrt()
        };
        let mut g_touch = |_t: f64, y: &[f64; DIM]| top.height(y);
        let level = settings.inversion_level.unwrap_or(2.0);
        let mut g_inv = |_t: f64, y: &[f64; DIM]| top.kin(y).u - level;
        let mut g_rest = |_t: f64, y: &[f64; DIM]| {
            let (tr, rot, _) = top.energy_parts(y);
            tr + rot - 1e-12 * ke0
        };
        let mut locator = Locator::new();
        let mut names: Vec<&'static str> = Vec::new();
        match mode {
            Mode::Slip => {
                locator.add(EventSpec::new(-1, true), &mut g_liftoff);
                names.push("lift_off");
                if mu.is_some() {
                    locator.add(EventSpec::new(-1, true), &mut g_stop_slip);
                    names.push("slip_to_roll");
                }
            }
            Mode::Roll => {
                locator.add(EventSpec::new(-1, true), &mut g_liftoff);
                names.push("lift_off");
                locator.add(EventSpec::new(-1, true), &mut g_cone);
                names.push("roll_to_slip");
            }
            Mode::Flight => {
                locator.add(EventSpec::new(-1, true), &mut g_touch);
                names.push("touchdown");
            }
        }
        let watch_inv = settings.inversion_level.is_some() && !inverted;
        if watch_inv {
            locator.add(EventSpec::new(1, settings.stop_at_inversion), &mut g_inv);
            names.push("inversion");
        }
        if settings.stop_at_rest {
            locator.add(EventSpec::new(-1, true), &mut g_rest);
            names.push("rest");
        }
        // Output times of this segment.
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
        let mut rec = Recorder::new(seg_times, None);
        let mut obs = WithEvents::new(locator, &mut rec);
        let (t1, y1, st) =
            integrate_phase(&integrator, top, mode, dir, &last, t, y, t_end, &mut obs).map_err(
                |e| KreiselError::Numerical(format!("play top, {} mode: {e}", mode.name())),
            )?;
        let hits: Vec<(usize, f64)> = obs.locator.events.iter().map(|e| (e.index, e.t)).collect();
        drop(obs);
        out.steps += st.steps;
        out.rejected += st.rejected;
        out.rhs_evals += st.rhs_evals;
        let (ts, ys): (Vec<f64>, Vec<[f64; DIM]>) = match (rec.every, rec.sample) {
            (Some(e), _) => (e.ts, e.ys),
            (None, Some(s)) => {
                let n = s.out.len();
                let te = settings.t_eval.as_deref().expect("sampled");
                next_sample = offset + n;
                (te[offset..offset + n].to_vec(), s.out)
            }
            _ => (vec![], vec![]),
        };
        let skip = usize::from(!first && settings.t_eval.is_none() && !ts.is_empty());
        if out.t.is_empty() && skip == 0 {
            // The first segment's columns are taken over, not copied.
            out.t = ts;
            out.y = ys;
        } else {
            out.t.extend_from_slice(&ts[skip..]);
            out.y.extend_from_slice(&ys[skip..]);
        }
        out.mode.resize(out.t.len(), mode);
        out.dir.resize(out.t.len(), dir);
        first = false;
        let mut terminal = None;
        for (idx, te) in hits {
            let name = names[idx];
            out.events.push((name, te));
            if name == "inversion" {
                inverted = true;
            }
            if !matches!(name, "inversion") || settings.stop_at_inversion {
                terminal = Some(name);
            }
        }
        t = t1;
        y = y1;
        let Some(reason) = terminal else {
            break;
        };
        if t >= t_end || reason == "rest" || reason == "inversion" {
            break;
        }
        // Switch.
        match reason {
            "lift_off" => {
                // The top leaves the floor from it: the located state (from the dense output,
                // off the contact by the local error) is put back on the contact first.
                top.project(mode, &mut y);
                mode = Mode::Flight;
                hop = f64::INFINITY;
            }
            "slip_to_roll" => {
                let (ok, c) = top.roll_admissible(&y);
                if ok {
                    mode = Mode::Roll;
                    y = top.stick(&y);
                } else {
                    let ft = (c.ft[0] * c.ft[0] + c.ft[1] * c.ft[1]).sqrt();
                    dir = if ft > 0.0 {
                        [-c.ft[0] / ft, -c.ft[1] / ft, 0.0]
                    } else {
                        dir
                    };
                }
            }
            "roll_to_slip" => {
                let (_, c) = top.roll_admissible(&y);
                let ft = (c.ft[0] * c.ft[0] + c.ft[1] * c.ft[1]).sqrt();
                if ft > 0.0 {
                    dir = [-c.ft[0] / ft, -c.ft[1] / ft, 0.0];
                }
                mode = if slip_normal(top, &y, dir) < 0.0 {
                    hop = f64::INFINITY;
                    Mode::Flight
                } else {
                    Mode::Slip
                };
            }
            "touchdown" => {
                let (yi, sticks) = top.impact(&y);
                y = yi;
                let vn = top.kin(&y).v_t[2];
                hop = if top.g > 0.0 {
                    2.0 * vn / top.g
                } else {
                    f64::INFINITY
                };
                // Flights shorter than a millionth of the free-fall time through the tip's
                // radius are below what the events resolve: such a bounce is absorbed.
                let tiny = 1e-6 * (top.rho / top.g.max(1e-300)).sqrt();
                let bounce = vn > 0.0 && hop > tiny;
                let mut sticks = sticks;
                if !bounce && vn > 0.0 {
                    let (yp, s2) = top.impact_with(&y, 0.0);
                    y = yp;
                    sticks = s2;
                }
                mode = if bounce {
                    Mode::Flight
                } else if sticks && mu.is_some() && top.roll_admissible(&y).0 {
                    Mode::Roll
                } else {
                    Mode::Slip
                };
                if mode == Mode::Slip && slip_normal(top, &y, dir) < 0.0 {
                    // Sliding would need the floor to pull: the top leaves it again, with
                    // no normal speed, so the flight's length is not known in advance.
                    mode = Mode::Flight;
                    hop = f64::INFINITY;
                }
                if mode != Mode::Flight {
                    let k = top.kin(&y);
                    let sp = (k.v_t[0] * k.v_t[0] + k.v_t[1] * k.v_t[1]).sqrt();
                    if sp > 0.0 {
                        dir = [k.v_t[0] / sp, k.v_t[1] / sp, 0.0];
                    }
                }
            }
            _ => {}
        }
        top.project(mode, &mut y);
        // Record the state after the switch at the same time (impacts make it jump).
        if settings.t_eval.is_none() {
            out.t.push(t);
            out.y.push(y);
            out.mode.push(mode);
            out.dir.push(dir);
        }
        if out.events.len() > MAX_SWITCHES {
            break;
        }
    }
    if t < t_end && out.events.len() > MAX_SWITCHES {
        return Err(KreiselError::Numerical(format!(
            "play top: more than {MAX_SWITCHES} mode switches before t = {t} (chattering); \
             the model's contact modes do not settle here"
        )));
    }
    Ok(out)
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

/// Computes the diagnostics of the outputs of a play-top run: states `y` with their modes
/// and slip directions (the fields of [`PlayOutput`]).
pub fn play_columns(
    top: &PlayTop,
    y: &[[f64; DIM]],
    mode: &[Mode],
    dir: &[[f64; 3]],
) -> PlayColumns {
    if top.has_resistance() {
        columns_with::<true>(top, y, mode, dir)
    } else {
        columns_with::<false>(top, y, mode, dir)
    }
}

/// [`play_columns`], with the resistance torques compiled in when `RES`
/// ([`PlayTop::dynamics_with`]).
fn columns_with<const RES: bool>(
    top: &PlayTop,
    y: &[[f64; DIM]],
    mode: &[Mode],
    dir: &[[f64; 3]],
) -> PlayColumns {
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
    let n = y.len();
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
        let states = y[start..end]
            .iter()
            .zip(&mode[start..end])
            .zip(&dir[start..end]);
        for (row, ((y, &mode), &dir)) in rows.iter_mut().zip(states) {
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
pub struct Summary {
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

/// Summarises one run.
pub fn summarise(top: &PlayTop, out: &PlayOutput) -> Summary {
    let j0 = top.jellett(&out.y[0]);
    let e0 = {
        let (a, b, c) = top.energy_parts(&out.y[0]);
        a + b + c
    };
    let (mut jd, mut ed) = (0.0f64, 0.0f64);
    for y in &out.y {
        jd = jd.max((top.jellett(y) - j0).abs());
        let (a, b, c) = top.energy_parts(y);
        ed = ed.max((a + b + c + y[13] - e0).abs());
    }
    let last = out.y.last().expect("a run has at least its start");
    Summary {
        final_u: top.kin(last).u,
        final_mode: *out.mode.last().expect("start"),
        inversion_time: out
            .events
            .iter()
            .find(|e| e.0 == "inversion")
            .map_or(f64::NAN, |e| e.1),
        jellett_drift: if j0 != 0.0 { jd / j0.abs() } else { jd },
        energy_drift: if e0 != 0.0 { ed / e0.abs() } else { ed },
        steps: out.steps,
    }
}
