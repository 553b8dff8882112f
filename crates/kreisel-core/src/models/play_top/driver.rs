//! The hybrid run of a top on a floor: smooth phases, each integrated with DOP853 and ended
//! by located events, joined by contact switches (touchdown, lift-off, slip to stick, stick
//! to slip, the jam's tangential impact, lying flat), each of one part; what each switch
//! does; and the run's guards (energy kept across switches, chattering).

use super::simulate::PlayRow;
use super::solve::{code, Consts, Kernel};
use super::{Contacts, Forces, Mode, PlayTop, Shape, DIM, MAX_PARTS};
use crate::error::{KreiselError, Result};
use crate::integrate::{
    Dense, Dop853, EventSpec, IntegrateError, Locator, Observer, OdeSystem, Radau5, Resumed, Stats,
    Stream, WithEvents,
};
use crate::simulate::{
    integrate_error, EventKind, EventRecord, RunInfo, Settings, Sink, Status, MAX_STEPS,
};
use std::cell::{Cell, RefCell};
use std::ops::ControlFlow;

/// The most contact switches a run may make before it is taken for chattering.
const MAX_SWITCHES: usize = 200_000;

/// Refuses a run (the plain one and the sensitivity run alike) at time `t` as chattering once
/// it has made more than [`MAX_SWITCHES`] contact switches.
pub(crate) fn check_switches(n_switches: usize, t: f64) -> Result<()> {
    if n_switches > MAX_SWITCHES {
        return Err(KreiselError::Numerical(format!(
            "play top: more than {MAX_SWITCHES} mode switches before t = {t} \
             (chattering); the model's contact modes do not settle here"
        )));
    }
    Ok(())
}

/// The bound on DOP853's estimate of `h |lambda|` over which the steps of a phase where a
/// part slides are taken to be held by stability ([`Dop853::stiff_stop`]); the rest of the
/// phase is then integrated by Radau IIA. The explicit method's stability boundary on the
/// negative real axis is about 6. Measured (the estimate over every step): Euler's disk
/// sliding under point Coulomb friction at rtol 1e-6 (T4), median 6.19 and 10 % below 5.03;
/// T3's ball under Coulomb-Contensou friction, accuracy-limited with its fast mode resolved,
/// 1.27 to 1.87 (the explicit method is faster there); T1, at most 2.2. Only sliding
/// phases are tested: a top rolling or in flight has no friction that relaxes, and its
/// oscillatory modes (a spin) may take large `h |lambda|` at high order.
///
/// Under point Coulomb friction the two methods' errors agree (T4: 8.4556105 s against
/// 8.4556225 s at rtol 1e-6, 8.4559016 s against 8.4559021 s at 1e-8; 8.4559033 s
/// converged) and the continuation is 1.4 to 2.2 times faster. Under Coulomb-Contensou
/// friction a part that rolls while its friction cannot hold it without drilling slides at
/// a slip of `rbar w_n |x| / (mu N)`, relaxing at `mu N |W| / (rbar w_n)`: a random floor run
/// (a cone rocking on its side, patch 15 µm) took DOP853 steps of 0.24 µs, 113 775 of them
/// for 27 ms, and the continuation 191. T4 under Coulomb-Contensou friction trips the test
/// only at rtol 1e-6 (at 1.95 s): the disk lies flat at 8.717958 s in 103 ms, against
/// 8.7179186 s in 92 ms by DOP853 alone (8.7179188 s converged); T3 never trips it.
const STIFF_BOUND: f64 = 5.0;

type RawEventFn<'a> = Box<dyn FnMut(f64, &[f64; DIM]) -> f64 + 'a>;

type PhaseResult = std::result::Result<(f64, [f64; DIM], crate::integrate::Stats), IntegrateError>;

/// Every so many accepted steps, [`Watched`] checks their pace for a held slide.
const WATCH_EVERY: u64 = 512;

/// Every so many accepted implicit steps, [`Watched`] checks whether they crawl.
const CRAWL_EVERY: u64 = 1 << 12;

/// The pace (mean accepted step, in units of the top's time `sqrt(reach / g)`) below which a
/// sliding part held within the creep's exit range ends its phase ([`Watched`]).
const HELD_PACE: f64 = 1e-4;

/// An observer of a phase's steps. It keeps the last accepted step (time, state) and counts
/// the steps: where to go on from if the integrator fails after them. It stops the
/// integrator
/// - where, with `crawl`, it crawls: the pace of its last [`CRAWL_EVERY`] steps would take
///   more than the run's [`MAX_STEPS`] to reach `t_end` (the run would be refused as
///   stalled);
/// - where the mean of its last [`WATCH_EVERY`] steps is below `slow` while `held` finds a
///   switch to end the phase on ([`Rules::held_switch`]): a sliding part whose sliding
///   measure is held within the creep's exit range (the law's own equilibrium at the edge of
///   its cone, a few stick speeds up, where the slip's direction turns at 1e9 /s and the
///   event that would try the stick or the creep is never located), or a creeping part.
struct Watched<'a, O, F> {
    obs: &'a mut O,
    held: Option<F>,
    slow: f64,
    found: Option<Switch>,
    crawl: bool,
    crawled: bool,
    /// Ends the integration where the pace falls below `slow` and `held` finds no switch
    /// (`slowed`): explicit steps of a slide held by a stiffness the step-size test missed.
    stiff_when_slow: bool,
    slowed: bool,
    last: (f64, [f64; DIM]),
    steps: u64,
    t_end: f64,
    mark: f64,
    crawl_mark: f64,
}

impl<'a, O, F> Watched<'a, O, F> {
    fn new(
        obs: &'a mut O,
        held: Option<F>,
        slow: f64,
        t: f64,
        y: [f64; DIM],
        t_end: f64,
        crawl: bool,
    ) -> Self {
        Watched {
            obs,
            held,
            slow,
            found: None,
            crawl,
            crawled: false,
            stiff_when_slow: false,
            slowed: false,
            last: (t, y),
            steps: 0,
            t_end,
            mark: t,
            crawl_mark: t,
        }
    }
}

impl<O: Observer<DIM>, F: Fn(&[f64; DIM], f64) -> Option<Switch>> Observer<DIM>
    for Watched<'_, O, F>
{
    fn step(&mut self, t: f64, y: &[f64; DIM], dense: &dyn Dense<DIM>) -> ControlFlow<()> {
        self.last = (t, *y);
        self.steps += 1;
        let flow = self.obs.step(t, y, dense);
        if flow.is_continue() && self.steps % WATCH_EVERY == 0 {
            let pace = (t - self.mark) / WATCH_EVERY as f64;
            self.mark = t;
            if self.crawl && self.steps % CRAWL_EVERY == 0 {
                let crawl_pace = (t - self.crawl_mark) / CRAWL_EVERY as f64;
                self.crawl_mark = t;
                if crawl_pace * (MAX_STEPS as f64) < self.t_end - t {
                    self.crawled = true;
                    return ControlFlow::Break(());
                }
            }
            if pace < self.slow {
                if let Some(held) = &self.held {
                    if let Some(sw) = held(y, pace) {
                        self.found = Some(sw);
                        return ControlFlow::Break(());
                    }
                }
                if self.stiff_when_slow {
                    self.slowed = true;
                    return ControlFlow::Break(());
                }
            }
        }
        flow
    }
    fn start(&mut self, t0: f64, y0: &[f64; DIM]) {
        self.obs.start(t0, y0)
    }
    fn stop_point(&self) -> Option<(f64, [f64; DIM])> {
        if self.found.is_some() || self.crawled || self.slowed {
            None
        } else {
            self.obs.stop_point()
        }
    }
}

/// A switch of the several-part rules, each of one part.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Switch {
    /// The part reaches the floor.
    Touchdown(usize),
    /// The part's normal force falls to zero.
    LiftOff(usize),
    /// The part's sliding (and drilling) falls to zero: it may stick.
    SlipToRoll(usize),
    /// The friction a sticking part needs leaves its cone (or ellipse).
    RollToSlip(usize),
    /// A sliding part's own coefficient falls towards zero (the Painleve case): a tangential
    /// impact ([`PlayTop::jam_level`]).
    Jam(usize),
    /// A ring part's plane comes down onto the floor (the top lies flat on that rim): the
    /// run ends there ([`FLAT_LEVEL`]).
    Flat(usize),
    /// A creeping part's slip grows past the creep's range (about [`CREEP_LAG`] mu g / Omega): it slides
    /// on under its law; or the slip turns 60 degrees away from the creep's direction: it is
    /// put back on it ([`Contacts::creeping`]).
    CreepEnd(usize),
    /// A part alone on the floor under Coulomb-Contensou friction stops slipping while its
    /// patch still drills: it rolls on, drilling ([`Contacts::drilling`]), where the slip
    /// its friction needs is below the stick speed; recorded as `slip_to_roll`.
    SlipToDrill(usize),
    /// A drilling part's drilling falls to the stick speed (`rbar |w_n|`): it sticks.
    DrillEnd(usize),
    /// A resistance's turning rate (0: the rolling resistance's horizontal rate, 1: the
    /// drilling resistance's vertical one) crosses the rate below which its law is linear
    /// ([`PlayTop::resist_bands`]): the law's kink. The phase restarts there, nothing else
    /// changing and nothing recorded, so that no step straddles the kink: DOP853's error
    /// estimate does not see one, and a 2.6 g top's drilling resistance stopped its spin
    /// about the vertical in one step of four of the linear law's relaxation times across
    /// it, E + dissipated rising by 7e-9 of the energy at the default rtol (the floor
    /// campaign's case 5955 of seed 16).
    Band(usize),
}

/// The lag of a creeping part's slip behind the consistent direction at which the creep
/// ends ([`Rules::creep_exit`]): the slip's direction relaxes towards the consistent one at
/// the rate `mu g / |slip|` (about: `mu N` over the contact's effective mass), while the
/// consistent direction turns with the motion at about `Omega = max(|w|, sqrt(g / l))`; the
/// creep's friction, along the consistent direction, is then off by about
/// `Omega |slip| / (mu g)` radians. Past that the law's own direction takes over, relaxing
/// at a rate of `Omega / CREEP_LAG`. The lag is a model error: Euler's disk under point
/// Coulomb friction (benchmark T4) comes down flat at 8.7271 s with a lag of 0.1, 8.4790 s
/// with 0.01, 8.45585 s with 1e-3 and 8.4555-8.4557 s with 1e-4 (rtol 1e-8 and 1e-10),
/// where the law integrated through its creep gave 8.4557-8.4561 s.
pub const CREEP_LAG: f64 = 1e-3;

/// How far inside its cone (as a share of `mu m g`) the force a creeping part needs to stick
/// must come before the part sticks. Between the cone's edge and this the creep holds the
/// part with that force, its slip (of the order of the stick speed) constant, which is
/// sticking but for the slip; the band keeps a part whose friction stays at the cone's edge
/// (a top rolling with the friction it needs at mu N) from switching between the two at
/// every rounding of the margin.
pub const CREEP_STICK: f64 = 1e-3;

/// The least a creeping part's sliding measure grows before the creep ends, as a multiple of
/// the stick speed ([`Rules::tolerance`]): a creep ends above the speed it sticks at.
pub const CREEP_EXIT: f64 = 10.0;

/// The most creep realignments ([`Switch::CreepEnd`] turning the slip back onto the creep's
/// direction) in a row, each within [`REALIGN_QUICK`] of the last and no other switch
/// between: the next hands the part to its law. A creep whose slip turns away again at once
/// is not consistent there: a 2.7 g top on a torus under Coulomb-Contensou friction with
/// rolling and drilling resistance had its creep's slip (of 1e-8 m/s, at 8 stick speeds)
/// turned across it within 1.3e-8 s, 200000 times, until the run was refused as chattering
/// (the floor campaign's case 8713 of seed 17). Euler's disk under point Coulomb friction
/// (benchmark T4) realigns its creeps more slowly: unchanged.
pub const REALIGN_MAX: u32 = 64;

/// The interval (in units of the top's time `sqrt(reach / g)`) within which a creep's
/// realignment follows the last to count as quick ([`REALIGN_MAX`]): 1e-5 (5e-7 s on the top
/// of case 8713, whose realignments followed each other within 1.3e-8 s).
pub const REALIGN_QUICK: f64 = 1e-5;

/// The slip (as a multiple of the stick speed) that a drilling part's friction may need
/// before the part slides on under its law ([`Contacts::drilling`]); it starts drilling only
/// where the slip needed is at most [`DRILL_ENTRY`] stick speeds.
pub const DRILL_EXIT: f64 = 10.0;

/// The slip (as a multiple of the stick speed) that a part's friction may need where its slip
/// falls to the stick speed and it starts drilling. Above one: a slide relaxes to the slip
/// its friction needs, so where that need is just above the stick speed the slip hovers at
/// it, and a limit of one stick speed located the same switch, refused, at every step (2727
/// times in 0.2 ms). Below [`DRILL_EXIT`], so that drilling ends well above where it starts.
pub const DRILL_ENTRY: f64 = 2.0;

/// The inclination's sine at which a ring part is taken to lie flat: the contact point's
/// motion along the rim (and the precession rate) grows without bound as it comes down, as
/// Euler's disk's does, and the run stops there with the event `flat`.
pub const FLAT_LEVEL: f64 = 1e-4;

/// The normal force (in weights `m g`) beyond which a ring part's flat level grows in
/// proportion to it: a sharp rim that comes down nearly level while G still falls (rolling,
/// or sliding) needs its contact point to run round the rim ever faster, and the force that
/// keeps it on the floor grows without bound before the tilt reaches [`FLAT_LEVEL`]; the
/// steps fell with it (a 40 g top rolling on a rim of 9.7 mm at a tilt of 1.8e-4, G falling at
/// 0.22 m/s: 250 N and rising, steps of 1e-13 s, the run refused as stalled: floor campaign
/// case 7829 of seed 1). Such a ring lands flat where its tilt's sine is
/// `FLAT_LEVEL max(1, N / (FLAT_FORCE m g))`: at 2e-4 if the force reaches 200 weights there.
/// Euler's disk (benchmark T4) comes down on a force near its weight and is unchanged.
pub const FLAT_FORCE: f64 = 100.0;

/// The inclination's sine below which a ring part pressed by more than [`FLAT_HELD_FORCE`]
/// weights whose steps stall (the mean of the last 512 below [`FLAT_PACE`] of the top's time) lands
/// flat (Euler's disk, benchmark T4, comes down on a force near its weight, its steps
/// crawling at the end under Coulomb-Contensou friction: unchanged). Coming down nearly level with its
/// horizontal spin kept (a ring upside down, slapping down), the contact point races round the
/// rim and the normal force grows (to 140 and 560 weights at tilts of 2.8e-3 and 7.7e-4) while
/// the tilt still falls slowly; the steps fell to 1.5e-10 s and the runs were refused as
/// stalled (floor campaign seed 5, cases 286 and 2045). The rim's two sides are then within
/// 2 FLAT_HELD of its radius of the floor; the landing is the plastic impact of its face.
pub const FLAT_HELD: f64 = 1e-2;

/// The normal force (in weights `m g`) beyond which a ring within [`FLAT_HELD`] whose steps
/// stall lands flat: ten weights, the ring's face slapping down (a 175 g top rolling on a
/// sharp rim of 12.8 mm came down pressed by 63 weights, its tilt at 1.4e-4 and falling, its
/// steps at 2e-11 s, and was refused as stalled: the floor campaign's case 8633 of seed 13).
/// Euler's disk (benchmark T4) comes down on a force near its weight: unchanged.
pub const FLAT_HELD_FORCE: f64 = 10.0;

/// The mean step (of the last 512, in units of the top's time `sqrt(reach / g)`) below which
/// a ring within [`FLAT_HELD`] lands flat: a thousandth of [`HELD_PACE`]. The stalled runs'
/// steps were 1e-8 of that time; a ring slapping down that rises again (a tangential impact,
/// then 125 weights at a tilt of 4.3e-3: seed 1's case 2387) crawls only briefly, above it.
pub const FLAT_PACE: f64 = 1e-7;

/// The pull (as a share of the weight `m g`) beyond which a touching part's normal force is
/// taken to have jumped through zero rather than crossed it. A lift-off is located on the far
/// side of its crossing, within [`crate::integrate::events::ROOT_TOL`] of it in time, where a
/// normal force that falls continuously is a rounding below zero (at a thousand weights per
/// second, 1e-12 of a weight); one that jumps (another part's force changing branch, as a
/// creep's consistent direction does) is well below it there. Such a switch is not the part's
/// lift-off, and the row at it would show the floor pulling.
pub const PULL: f64 = 1e-9;

impl Switch {
    /// The event's public name.
    pub const fn name(self) -> &'static str {
        match self {
            Switch::Touchdown(_) => "touchdown",
            Switch::LiftOff(_) => "lift_off",
            Switch::SlipToRoll(_) => "slip_to_roll",
            Switch::RollToSlip(_) => "roll_to_slip",
            Switch::Jam(_) => "tangential_impact",
            Switch::Flat(_) => "flat",
            Switch::CreepEnd(_) => "creep_end",
            Switch::SlipToDrill(_) => "slip_to_roll",
            Switch::DrillEnd(_) => "drill_end",
            Switch::Band(_) => "resistance_band",
        }
    }
    /// The part.
    pub const fn part(self) -> usize {
        match self {
            Switch::Touchdown(i)
            | Switch::LiftOff(i)
            | Switch::SlipToRoll(i)
            | Switch::RollToSlip(i)
            | Switch::Jam(i)
            | Switch::Flat(i)
            | Switch::CreepEnd(i)
            | Switch::SlipToDrill(i)
            | Switch::DrillEnd(i)
            | Switch::Band(i) => i,
        }
    }
}

/// Where a phase of the several-part rules stands: each part's mode and slip direction, and
/// the expected flight time of a bounce (infinite: unknown).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Phase {
    /// The parts' modes.
    pub contacts: Contacts,
    /// Expected flight time after a bounce (s).
    pub hop: f64,
}

/// The contact rules of a top on a floor. `last` keeps the forces of the last
/// right-hand side evaluated (its state and contacts as the key): the integrator evaluates it
/// at the end of every accepted step just before the events are checked there, so the events
/// that need the forces (lift-off, roll-to-slip, the jam) take them instead of solving again.
///
/// `floor` holds, per part, how far below the floor the current phase locates the part's
/// touchdown: the [`PlayTop::touchdown_offset`] below where the part starts the phase where
/// that is lower than the floor (a part off the floor while others touch may start a hair
/// below it, by the rounding of their constraints), so that every touchdown event function
/// starts positive. `slack` does the same for a sticking part's cone margin: a part that
/// sticks from where its friction is at the cone's edge starts the phase at a margin of
/// zero, to rounding. `lift` does the same for a touching part's normal force: a part that
/// starts the phase at a force of zero or a pull within [`PULL`] (a part set sliding at its
/// lift-off's threshold) has its lift-off located where the force falls [`PULL`] weights
/// below where it starts: at a start of -0 N, the function never crossed from above, and a
/// 0.33 kg top's rim was pulled by up to 0.114 N for 31 ms before it left (the floor
/// campaign's seed 22 at t_end 5 s, case 72). `jam` does the same for a sliding part's jam event (its sliding
/// coefficient's level and its normal force's cap, [`Switch::Jam`]): a phase that starts
/// beyond either (a switch left a part sliding with its normal force already past the cap,
/// or its coefficient below the level) watches for them halving (the coefficient) or
/// doubling (the force) from where it starts.
///
/// `resolved` is the slip the integration resolves, as a share of the speed scale: ten
/// times its `rtol` (see [`Rules::tolerance`]).
///
/// `forced` is a switch a phase's integration ended on without an event function locating
/// it ([`Rules::integrate`]: a slide held at a few stick speeds), taken by the run as if
/// located there.
pub(crate) struct Rules<'a> {
    pub top: &'a PlayTop,
    pub last: RefCell<Solved>,
    pub floor: Cell<[f64; super::MAX_PARTS]>,
    pub slack: Cell<[f64; super::MAX_PARTS]>,
    pub lift: Cell<[f64; super::MAX_PARTS]>,
    pub jam: Cell<[[f64; 2]; super::MAX_PARTS]>,
    pub resolved: Cell<f64>,
    pub forced: Cell<Option<Switch>>,
    /// The switch being applied is `forced` (a held motion, not a located event): a creep's
    /// end then hands the part to its law (not the turn that puts the slip back on the
    /// creep's direction), and a slide held within the drilling's exit range starts to
    /// drill. Set by the run around the switch's [`Rules::apply`].
    pub unlocated: Cell<bool>,
    /// The side of each resistance's kink ([`Switch::Band`]) the phase starts on: 1 above
    /// the linear law's rate, -1 below it. Set by [`Rules::prepare`] from the state, except
    /// for the one a band switch has just crossed, flipped by [`Rules::apply`] (bit `k` of
    /// `band_crossed`): its located state lies within rounding of the kink.
    pub band: Cell<[f64; 2]>,
    /// The last phase went on by Radau IIA to its end ([`Rules::integrate`]); kept only
    /// across a restart at a resistance's kink ([`Switch::Band`]), where the next phase
    /// starts by Radau IIA too. Started again by DOP853, whose explicit steps are unstable
    /// in the linear band (a drilling resistance relaxing at 1e9 /s), each restart overshot
    /// across the kink and was located again: a 1.4 g frictionless ball top tumbling with
    /// its rate about the vertical in that band made 200 000 restarts and 2.6 million
    /// rejected steps by 2.6 s, its rate held at the kink's (the floor campaign's case 51
    /// of seed 26 at t_end 5 s and rtol 1e-6).
    pub stiff_end: Cell<bool>,
    /// The rates of the two resistances' kinks ([`PlayTop::resist_bands`]: the top's own).
    pub bands: [f64; 2],
    pub band_crossed: Cell<u8>,
    /// The sign of the drilling rate (`w_n`) at the phase's start: a drilling part's
    /// [`Switch::DrillEnd`] is located where the rate, so signed, falls to the stick speed,
    /// so that a step that carries it through zero (where the patch's torque turns round)
    /// cannot pass unseen: `rbar |w_n| - eps` dips below zero only within `2 eps / rbar`
    /// of it, and a drilling patch's rate went from -1.6e-5 to 1.6e-4 rad/s in one step of
    /// 1.6e-6 s, hundreds of times, each adding 1e-14 J (the floor campaign's case 8090 of
    /// seed 5: E + dissipated 1.5e-8 of the energy above the start's).
    pub drill_sign: Cell<f64>,
    /// The parts whose located switch to drilling was refused (bit mask): their
    /// [`Switch::SlipToDrill`] is not watched again until another switch
    /// ([`Rules::apply`]). The slip that refusal left sliding can fall on through the stick
    /// speed, the switch located and refused again at once: a 55 g torus upside down, nearly
    /// flat under Coulomb-Contensou friction, its friction needing 2.8 stick speeds of slip
    /// (above [`DRILL_ENTRY`]) while its slip fell through one, took that switch every
    /// 1e-11 s until refused as stalled (the floor campaign's case 8547 of seed 16 at rtol
    /// 1e-6). A slide held there is still ended by [`Rules::held_switch`].
    pub drill_refused: Cell<u8>,
    /// The creep realignments ([`Switch::CreepEnd`] turning the slip back onto the creep's
    /// direction) in a row, each within [`REALIGN_QUICK`] of the last, no other switch
    /// between, and the time of the last: past [`REALIGN_MAX`] the creep ends.
    pub realigns: Cell<(u32, f64)>,
    /// The time of the switch being applied, set by the run around [`Rules::apply`].
    pub now: Cell<f64>,
}

/// A located event's state `y` (the step's dense output, which unlike the step's end is not
/// put on the phase's constraints: a touching part's gap drifts there by the step's error,
/// 1.2e-9 m after a 5 ms step at rtol 1e-8, seed 1's case 611) put on the constraints of
/// `c`. Putting G's height on the touching parts moves a part touching down there by their
/// drift, below the floor where it sinks G (seed 4's 8342 at rtol 1e-8: 1.26e-9 m): that
/// drift is then shared, half each way; where it exceeds [`LEVEL_DRIFT`] (8859: 3.0e-9 m),
/// the top is turned onto the tilt at which that part and a touching one are level instead
/// ([`PlayTop::tilt_both`], its angular velocity kept), G put on the touching part. The
/// potential energy either move adds is taken from the motion (at most m g times the drift).
///
/// `E + dissipated` is conserved along a phase (the equations book every dissipated power):
/// where the state has less than the phase's start `start`, the difference (the
/// integration's and the dense output's error) is booked as dissipated. Radau IIA's dense
/// output (of order 3) at a ring slapping down flat at rtol 1e-6 had lost 4.6e-6 J of
/// `E + dissipated`, the dissipated energy itself 1.5e-6 J below the row before (the floor
/// campaign's case 7140 of seed 2). Where it has more, only what the projection adds is
/// taken back: the phase's own gain, of the order of rtol times the energy, taken from the
/// motion at a `rest` event (whose kinetic energy is 1e-12 of the start's) stopped the top
/// dead, and its friction's direction at zero slip pulled a part by 0.0037 N (seed 3, 7971).
pub(crate) fn at_event(top: &PlayTop, c: &Contacts, y: &mut [f64; DIM], start: &[f64; DIM]) {
    let before = ledger(top, y).max(ledger(top, start));
    top.project(c, y);
    let gap = |y: &[f64; DIM], i: usize| {
        let k = top.kin(y);
        top.part(i).gap(k.zg, k.e3)
    };
    let low = (0..top.parts.n)
        .filter(|&i| c.mode[i] == Mode::Flight)
        .min_by(|&a, &b| gap(y, a).total_cmp(&gap(y, b)));
    let on = (0..top.parts.n).find(|&i| c.mode[i] != Mode::Flight);
    if let Some(j) = low {
        let drift = -gap(y, j);
        // The turn is taken where it moves no point of the top by more than a hundred times
        // the drift (a larger one is another root of the level tilt, or a lever too short),
        // and sinks no other part off the floor.
        let mut yt = *y;
        let turned = drift > LEVEL_DRIFT
            && !c.flat
            && on.is_some_and(|i| {
                top.tilt_both(i, j, &mut yt).is_some() && {
                    yt[9] -= gap(&yt, i);
                    true
                }
            })
            && {
                let (a, b) = (top.kin(y).e3[2], top.kin(&yt).e3[2]);
                let angle = (a.clamp(-1.0, 1.0).acos() - b.clamp(-1.0, 1.0).acos()).abs();
                angle * top.reach() <= 100.0 * drift
            }
            && (0..top.parts.n)
                .filter(|&l| c.mode[l] == Mode::Flight)
                .all(|l| gap(&yt, l) >= gap(y, l).min(0.0));
        if turned {
            *y = yt;
        } else if on.is_some() && drift > 1e-11 * top.reach() && drift <= LEVEL_DRIFT {
            // (Not in flight, where nothing drifts, nor for the touchdown's own offset of
            // 1e-12 of the reach below the floor.)
            y[9] += 0.5 * drift;
        }
    }
    no_energy_from_a_switch(top, y, before);
}

/// The drift (m) of a located event's touching parts beyond which a part touching down
/// there is levelled with them by a turn ([`at_event`]), not shared with them by G's height
/// (which leaves each part within half the drift of the floor): the floor's tolerance.
const LEVEL_DRIFT: f64 = 1e-9;

/// The forces of the last right-hand side of a phase (see [`Rules`]), keyed by its time and
/// orientation as integrated: the integrator evaluates the right-hand side at the (projected)
/// end of every accepted step just before the events are checked there; a stage or a
/// root-finding state at the same time has another orientation (a step's last stage is not
/// projected), so only the step's end reuses them. Each phase starts with none.
#[derive(Clone, Copy)]
pub(crate) struct Solved {
    t: f64,
    q: [f64; 4],
    forces: Forces,
}

impl Solved {
    const NONE: Solved = Solved {
        t: f64::NAN,
        q: [f64::NAN; 4],
        forces: Forces {
            n: [0.0; super::MAX_PARTS],
            ft: [[0.0; 2]; super::MAX_PARTS],
            mz: [0.0; super::MAX_PARTS],
            den: [0.0; super::MAX_PARTS],
        },
    };
}

impl<'a> Rules<'a> {
    /// The rules of `top`, nothing evaluated yet.
    pub(crate) fn new(top: &'a PlayTop) -> Self {
        Rules {
            top,
            last: RefCell::new(Solved::NONE),
            floor: Cell::new([0.0; super::MAX_PARTS]),
            slack: Cell::new([0.0; super::MAX_PARTS]),
            lift: Cell::new([0.0; super::MAX_PARTS]),
            jam: Cell::new(jam_arming(top)),
            resolved: Cell::new(0.0),
            forced: Cell::new(None),
            unlocated: Cell::new(false),
            band: Cell::new([1.0; 2]),
            stiff_end: Cell::new(false),
            bands: top.resist_bands(top.reach()),
            band_crossed: Cell::new(0),
            drill_sign: Cell::new(1.0),
            drill_refused: Cell::new(0),
            realigns: Cell::new((0, f64::NEG_INFINITY)),
            now: Cell::new(0.0),
        }
    }

    /// The rules of `top` for a run at relative tolerance `rtol` (the slip it resolves: see
    /// [`Rules::tolerance`]).
    pub(crate) fn for_run(top: &'a PlayTop, rtol: f64) -> Self {
        let r = Self::new(top);
        r.resolved.set(10.0 * rtol);
        r
    }

    /// The forces at `(t, y)` with `contacts`, from the last right-hand side where it was
    /// there.
    fn forces(&self, contacts: &Contacts, t: f64, y: &[f64; DIM]) -> Forces {
        {
            let s = self.last.borrow();
            if s.t == t && s.q == [y[0], y[1], y[2], y[3]] {
                return s.forces;
            }
        }
        let mut dy = [0.0; DIM];
        self.top.dynamics(contacts, y, &mut dy)
    }

    /// Ring part `i` lies flat from `y` on (on the part [`PlayTop::flat_support`] picks: a
    /// pole reaching below the ring's plane carries the top): sliding, or stuck where its
    /// sliding is within the tolerance and its law can stick; `y` put on the flat contact.
    fn lie_flat(&self, i: usize, y: &mut [f64; DIM]) -> Phase {
        let contacts = self.flat_on(i, y, self.tolerance(y));
        self.top.project(&contacts, y);
        Phase {
            contacts,
            hop: f64::INFINITY,
        }
    }

    /// The modes of the parts `cand` resolved at `y` ([`PlayTop::resolve_at`]) with `y` put
    /// on their constraints, where every touching part then pushes: the projection moves the
    /// state, and where that turns a normal force into a pull, the modes are resolved again at
    /// the projected state (up to three times). `None`, `y` untouched, where that fails.
    fn resolve_pushing(
        &self,
        y: &mut [f64; DIM],
        cand: u8,
        prev: &Contacts,
        eps: f64,
    ) -> Option<Contacts> {
        let top = self.top;
        let n = top.parts.n;
        let (mut yp, mut c, mut cand) = (*y, *prev, cand);
        let mut dy = [0.0; DIM];
        for _ in 0..4 {
            c = top.resolve_at(&yp, cand, &c, eps)?;
            top.project(&c, &mut yp);
            if c.all_push(&top.dynamics(&c, &yp, &mut dy), n) {
                *y = yp;
                return Some(c);
            }
            cand = c.mask(n);
        }
        None
    }

    /// After an impulse: the parts touching and not separating resolved into modes, the
    /// rest in flight; the bounce's expected flight time.
    /// The contacts of ring `i` lying flat at `y` (on the part that reaches lowest there,
    /// [`PlayTop::flat_support`]): stuck where it can stick and its sliding is within the
    /// stick speed `eps`, else sliding.
    fn flat_on(&self, i: usize, y: &[f64; DIM], eps: f64) -> Contacts {
        let top = self.top;
        let i = top.flat_support(i, y);
        top.flat_contacts(i, top.friction.can_stick() && top.flat_slide(i, y) <= eps)
    }

    fn after_impulse(&self, y: &mut [f64; DIM], prev: &Contacts) -> Phase {
        let top = self.top;
        let l = top.reach();
        // The impact was located a hair below the floor ([`PlayTop::touchdown_offset`]): the
        // top is put back on it, so that a part that bounces starts its flight at the floor
        // and its touchdown event function starts positive (however the rim swings down).
        {
            let k = top.kin(y);
            let lowest = top
                .parts
                .iter()
                .map(|p| p.gap(k.zg, k.e3))
                .fold(f64::INFINITY, f64::min);
            if lowest < 0.0 {
                y[9] -= lowest;
            }
        }
        let vscale = top.speed_scale(y);
        let cand = top.touching(y, 1e-9 * l, 1e-9 * vscale);
        let eps = self.tolerance(y);
        // A ring that comes down flat and does not bounce lies flat.
        let flat = top
            .lying_flat(y, 1e-9 * l)
            .filter(|&i| cand & (1 << i) != 0);
        let mut contacts = if let Some(i) = flat {
            self.flat_on(i, y, eps)
        } else if cand == 0 {
            Contacts::NONE
        } else {
            top.resolve(y, cand, prev, eps)
        };
        top.project(&contacts, y);
        if flat.is_none() {
            // The projection moves the state onto the touching parts' constraints; where
            // that turns a normal force into a pull (two parts that land together: a pushing
            // pair at the impact's state pulled by 0.065 N once projected, and the floor's
            // pull fed energy in through the friction), the modes are resolved again at the
            // projected state, which the phase starts from.
            let n = top.parts.n;
            let mut dy = [0.0; DIM];
            for _ in 0..3 {
                let f = top.dynamics(&contacts, y, &mut dy);
                if contacts.all_push(&f, n) {
                    break;
                }
                contacts = top.resolve(y, contacts.mask(n), &contacts, eps);
                top.project(&contacts, y);
            }
        }
        let k = top.kin(y);
        // The shortest bouncing part's flight, for the step limit; a separation below the
        // bounce cut-off (a round-off velocity) limits nothing, nor does a part off the floor
        // at the impact (its gap's rate and free acceleration say nothing of a bounce: a top
        // upside down bouncing on its ball, its sharp rim 2 cm up and level, whose lowest
        // point's acceleration is 5e9 m/s^2 there, was limited to steps of 8e-7 s through a
        // flight of 0.18 s).
        let mut hop = f64::INFINITY;
        for i in 0..top.parts.n {
            let p = &top.parts.shape[i];
            if contacts.mode[i] == Mode::Flight && p.gap(k.zg, k.e3) <= 1e-9 * l {
                let vn = p.gap_rate(k.v[2], k.w, k.e3);
                hop = hop.min(top.bounce(i, y, vn, &contacts).unwrap_or(f64::INFINITY));
            }
        }
        Phase { contacts, hop }
    }
}

impl Rules<'_> {
    pub(crate) fn start(&self, y: &mut [f64; DIM]) -> (Phase, Option<Switch>) {
        let top = self.top;
        let l = top.reach();
        let eps = self.tolerance(y);
        // A part on the floor and moving into it strikes it: the impact of a touchdown at
        // t = 0 (the fastest such part; the impact resolves the others). Putting it on the
        // contact instead would take its normal velocity unrecorded.
        let vtol = 1e-12 * top.speed_scale(y);
        let strike = {
            let k = top.kin(y);
            (0..top.parts.n)
                .filter(|&i| top.parts.shape[i].gap(k.zg, k.e3) <= 1e-12 * l)
                .map(|i| (i, top.parts.shape[i].gap_rate(k.v[2], k.w, k.e3)))
                .filter(|&(_, vn)| vn < -vtol)
                .min_by(|a, b| a.1.total_cmp(&b.1))
        };
        if let Some((i, _)) = strike {
            let none = Phase {
                contacts: Contacts::NONE,
                hop: f64::INFINITY,
            };
            let phase = self.apply(Switch::Touchdown(i), &none, y);
            return (phase, Some(Switch::Touchdown(i)));
        }
        // Parts moving away from the floor fly.
        let cand = top.touching(y, 1e-12 * l, vtol);
        if let Some(i) = top
            .lying_flat(y, 1e-12 * l)
            .filter(|&i| cand & (1 << i) != 0)
        {
            // A ring that starts lying flat lies flat (sliding, or stuck where it is still).
            return (self.lie_flat(i, y), None);
        }
        let (mut contacts, jam) = if cand == 0 {
            (Contacts::NONE, false)
        } else {
            top.resolve_jam(y, cand, &Contacts::NONE, eps)
        };
        let jam = jam.then(|| Switch::Jam(cand.trailing_zeros() as usize));
        // A part that starts sticking with a round-off slip is stopped exactly.
        for i in 0..top.parts.n {
            if contacts.mode[i] == Mode::Roll {
                let (yi, _) = top.impact(y, contacts.mask(top.parts.n), [0.0; 4]);
                *y = yi;
                break;
            }
        }
        if contacts.mask(top.parts.n) == 0 {
            contacts = Contacts::NONE;
        }
        top.project(&contacts, y);
        (
            Phase {
                contacts,
                hop: f64::INFINITY,
            },
            jam,
        )
    }

    pub(crate) fn watched(&self, phase: &Phase) -> Vec<Switch> {
        let top = self.top;
        let stick = top.friction.can_stick();
        let mut out = Vec::with_capacity(3 * top.parts.n + 2);
        out.extend(
            (0..2)
                .filter(|&j| self.watches_band(&phase.contacts, j))
                .map(Switch::Band),
        );
        if phase.contacts.flat {
            // A ring lying flat: it stays on the floor (its normal force is m g) and can only
            // stop sliding and spinning.
            for i in 0..top.parts.n {
                if stick && phase.contacts.mode[i] == Mode::Slip {
                    out.push(Switch::SlipToRoll(i));
                }
            }
            return out;
        }
        for i in 0..top.parts.n {
            let p = &top.parts.shape[i];
            let (lever, radius) = p.levers();
            let jam = top.may_jam(lever, radius);
            if phase.contacts.mode[i] != Mode::Flight && matches!(p, Shape::Torus { .. }) {
                out.push(Switch::Flat(i));
            }
            match phase.contacts.mode[i] {
                Mode::Flight => out.push(Switch::Touchdown(i)),
                Mode::Slip => {
                    out.push(Switch::LiftOff(i));
                    if stick {
                        out.push(Switch::SlipToRoll(i));
                    }
                    if self.creeps(&phase.contacts, i) {
                        out.push(Switch::CreepEnd(i));
                    }
                    if self.may_drill(&phase.contacts, i)
                        && self.drill_refused.get() & (1 << i) == 0
                    {
                        out.push(Switch::SlipToDrill(i));
                    }
                    if jam {
                        out.push(Switch::Jam(i));
                    }
                }
                Mode::Roll => {
                    out.push(Switch::LiftOff(i));
                    out.push(Switch::RollToSlip(i));
                    if phase.contacts.drilling & (1 << i) != 0 {
                        out.push(Switch::DrillEnd(i));
                    }
                }
            }
        }
        out
    }

    pub(crate) fn value(&self, sw: Switch, phase: &Phase, t: f64, y: &[f64; DIM], eps: f64) -> f64 {
        let top = self.top;
        let forces = || self.forces(&phase.contacts, t, y);
        match sw {
            Switch::Touchdown(i) => {
                // Located a hair below the floor (see [`Rules`]).
                let k = top.kin(y);
                top.parts.shape[i].gap(k.zg, k.e3) + self.floor.get()[i]
            }
            Switch::LiftOff(i) => forces().n[i] + self.lift.get()[i],
            Switch::SlipToRoll(i) if phase.contacts.flat => top.flat_slide(i, y) - eps,
            // A creeping part sticks once the force sticking needs is back in its cone by
            // CREEP_STICK of the friction's scale.
            // The margin is the stick phase's: at the state put on the stick's constraints
            // (its slip and drilling stopped, which ends a drilling resistance's torque).
            Switch::SlipToRoll(i) if self.creeps(&phase.contacts, i) => {
                let mut stuck = phase.contacts;
                stuck.mode[i] = Mode::Roll;
                stuck.creeping &= !(1 << i);
                let mut ys = *y;
                top.project(&stuck, &mut ys);
                CREEP_STICK * top.friction.mu() * top.m * top.g - top.creep_margin(&stuck, i, &ys)
            }
            Switch::SlipToRoll(i) => top.part_slide(&top.kin(y), i) - eps,
            Switch::CreepEnd(i) => self.creep_end_value(&phase.contacts, i, y, eps),
            // A drilling part: the slip its friction needs grows to DRILL_EXIT stick speeds
            // (as a product, smooth where the force nears the cone).
            Switch::RollToSlip(i) if phase.contacts.drilling & (1 << i) != 0 => {
                let f = forces();
                let (x, frac) = top.drill_share(f.ft[i], f.n[i]);
                let k = top.kin(y);
                DRILL_EXIT * eps * frac - top.friction.rbar() * k.w[2].abs() * x
            }
            Switch::RollToSlip(i) => top.stick_margin(&forces(), i) + self.slack.get()[i],
            Switch::SlipToDrill(i) => {
                let k = top.kin(y);
                let vp = top.parts.shape[i].point_velocity(k.v, k.w, k.e3);
                vp[0].hypot(vp[1]) - eps
            }
            Switch::DrillEnd(_) => {
                top.friction.rbar() * top.kin(y).w[2] * self.drill_sign.get() - eps
            }
            Switch::Band(j) => {
                let w = top.kin(y).w;
                let rate = if j == 0 { w[0].hypot(w[1]) } else { w[2].abs() };
                self.band.get()[j] * (rate - self.bands[j]) / self.bands[j]
            }
            Switch::Jam(i) => {
                // Sliding's own coefficient falls to the jam level, or the normal force it
                // gives grows past a hundred weights (the coefficient heading for zero
                // faster than the steps can follow): either way the tangential impact.
                let f = forces();
                let [level, cap] = self.jam.get()[i];
                let own = (f.den[i] - level) / level;
                if cap > 0.0 {
                    own.min((cap - f.n[i]) / cap)
                } else {
                    own
                }
            }
            Switch::Flat(i) => {
                // The level rises in proportion to the part's normal force beyond
                // FLAT_FORCE weights (continuous; see FLAT_FORCE).
                let u = top.kin(y).e3[2];
                let over = forces().n[i] / (FLAT_FORCE * top.m * top.g);
                (1.0 - u * u).max(0.0).sqrt() - FLAT_LEVEL * over.max(1.0)
            }
        }
    }

    /// The event function of part `i`'s creep end at `y`: the slip grows past the creep's
    /// range, or turns more than 60 degrees away from the direction the creep's friction
    /// opposes (the creep does not damp the slip across that direction, as the law does):
    /// the law takes over. So the creep's friction never feeds in more than `2 mu N eps` of
    /// power.
    fn creep_end_value(&self, c: &Contacts, i: usize, y: &[f64; DIM], eps: f64) -> f64 {
        let (size, along) = self.top.creep_slip(c, i, y);
        (self.creep_exit(y, eps) - size).min(creep_turn(size, along, eps))
    }

    /// The sliding measure (m/s) at which a creep ends at `y`: `CREEP_LAG mu g / Omega`
    /// ([`CREEP_LAG`]), at least [`CREEP_EXIT`] times the stick speed `eps`.
    pub(crate) fn creep_exit(&self, y: &[f64; DIM], eps: f64) -> f64 {
        let top = self.top;
        let w = (y[4] * y[4] + y[5] * y[5] + y[6] * y[6]).sqrt();
        let omega = w.max((top.g / top.reach()).sqrt());
        (CREEP_LAG * top.friction.mu() * top.g / omega).max(CREEP_EXIT * eps)
    }

    /// Ends a rocking between parts (the keep rule of a touchdown fired: the parts would
    /// take turns on the floor at ever shorter intervals) with the parts on the floor
    /// together where their friction can hold them: the parts touching (at zero gap, not
    /// separating, whatever the modes the impact left) that slide slower
    /// than the creep's range ([`Self::creep_exit`]) are tried sticking jointly, their slips
    /// stopped by an impulse that keeps every gap's rate ([`PlayTop::stop_slips`]; the
    /// kinetic energy it takes counted as dissipated); kept where the slips are then stopped
    /// and every touching part pushes. Sliding on at
    /// such slips, each part takes the full friction along a slip the impacts left (of the
    /// order of a micrometre per second, in any direction), and those forces' moments tip the
    /// top onto one part and back (a random floor run: a cone on its side rocked between its
    /// ring and its ball until 200 000 switches in a few microseconds refused the run).
    fn settle(&self, phase: &mut Phase, y: &mut [f64; DIM]) {
        let top = self.top;
        let n = top.parts.n;
        let c = phase.contacts;
        let l = top.reach();
        let cand = top.touching(y, 1e-9 * l, 1e-9 * top.speed_scale(y));
        if c.flat || cand.count_ones() < 2 || !top.friction.can_stick() {
            return;
        }
        let range = self.creep_exit(y, self.tolerance(y));
        let k = top.kin(y);
        let mut want = c;
        let mut tried = 0u8;
        for j in 0..n {
            if cand & (1 << j) != 0 && top.part_slide(&k, j) <= range {
                want.mode[j] = Mode::Roll;
                tried |= 1 << j;
            }
        }
        if tried == 0 {
            return;
        }
        want.creeping = 0;
        let mut dy = [0.0; DIM];
        let f = top.demote(&mut want, y, tried, &mut dy);
        let sticking = tried & want.mask_of(Mode::Roll, n);
        if sticking == 0 || !want.all_push(&f, n) {
            return;
        }
        // (Not bounded by the cone: the normal impulses are next to nothing, and the
        // friction would stop such slips within the rocking's last microseconds.)
        let Some(mut ys) = top.stop_slips(y, sticking, top.kept_gap_rates(y)) else {
            return;
        };
        top.project(&want, &mut ys);
        let eps = self.tolerance(&ys);
        let k = top.kin(&ys);
        let still = (0..n).all(|j| sticking & (1 << j) == 0 || top.part_slide(&k, j) <= eps);
        if still && want.all_push(&top.dynamics(&want, &ys, &mut dy), n) {
            *y = ys;
            phase.contacts = want;
        }
    }

    /// Puts creeping part `i`'s slip back on its creep's direction by the dissipative impulse
    /// of [`PlayTop::creep_slave`], the state onto the contacts `c`, the kinetic energy taken
    /// booked as dissipated.
    ///
    /// Where the slip kept lies past the creep's range (or still turned away), the part
    /// stops creeping instead and the law takes over from the slip as it was: the impulse
    /// keeps the slip's projection in the contact's own metric, and a patch's drilling,
    /// stiff in that metric, can stretch the slip along the direction. A torus under
    /// Coulomb-Contensou friction had its slip of 5e-5 m/s set so to 1.9e-3 m/s, ten times
    /// the creep's range, where the creep's end could no longer be located; the creep's
    /// friction then fed in 2e-5 J over 0.1 s (the floor campaign's case 6045 of seed 3).
    fn realign(&self, c: &mut Contacts, i: usize, y: &mut [f64; DIM]) {
        let top = self.top;
        let mut ys = *y;
        // E + dissipated kept whole: the projection books the kinetic energy it removes
        // itself, so a kinetic-energy balance taken around it booked that twice (the floor
        // campaign's case 1528 of seed 1 at rtol 1e-6: E + dissipated up by 2.5e-7 J,
        // 1.7e-4 of E, at a creep's start).
        let before = ledger(top, &ys);
        top.creep_slave(c, i, &mut ys);
        top.project(c, &mut ys);
        no_energy_from_a_switch(top, &mut ys, before);
        if self.creep_end_value(c, i, &ys, self.tolerance(&ys)) > 0.0 {
            *y = ys;
        } else {
            c.creeping &= !(1 << i);
            top.project(c, y);
        }
    }

    /// Whether part `i` creeps in `c`: marked so, sliding, not a ring lying flat, under a
    /// law that can stick ([`Contacts::creeping`]); alone on the floor or beside other
    /// parts ([`PlayTop::joint_creep_friction`]).
    pub(crate) fn creeps(&self, c: &Contacts, i: usize) -> bool {
        PlayTop::joint_creepers(c, self.top.parts.n) & (1 << i) != 0
            && self.top.friction.can_stick()
    }

    /// Whether part `i` of `c` may start drilling ([`Contacts::drilling`]): sliding, the only
    /// part touching, not creeping, under Coulomb-Contensou friction.
    fn may_drill(&self, c: &Contacts, i: usize) -> bool {
        let top = self.top;
        c.mode[i] == Mode::Slip
            && !c.flat
            && c.creeping & (1 << i) == 0
            && c.mask(top.parts.n) == 1 << i
            && top.friction.rbar() > 0.0
            && top.friction.mu() > 0.0
    }

    /// Part `i` of `c` (sliding alone, [`Self::may_drill`]), its slip stopped, tried
    /// drilling: taken (the state put on the contact, its slip zeroed) where it drills
    /// faster than the stick speed `eps` (`rbar |w_n| > eps`), the part then pushes and the
    /// slip its friction needs is at most `limit` (m/s): [`DRILL_ENTRY`] stick speeds, or
    /// [`DRILL_EXIT`] of them for a slide held within that range ([`Rules::held_switch`]).
    fn try_drill(
        &self,
        c: &mut Contacts,
        i: usize,
        y: &mut [f64; DIM],
        eps: f64,
        limit: f64,
    ) -> bool {
        let top = self.top;
        if top.friction.rbar() * top.kin(y).w[2].abs() <= eps {
            return false;
        }
        let mut want = *c;
        want.mode[i] = Mode::Roll;
        want.drilling = 1 << i;
        want.creeping = 0;
        let mut ys = *y;
        top.project(&want, &mut ys);
        let mut dy = [0.0; DIM];
        let f = top.dynamics(&want, &ys, &mut dy);
        let (x, frac) = top.drill_share(f.ft[i], f.n[i]);
        let wn = top.kin(&ys).w[2].abs();
        let ok = f.n[i] > 0.0 && top.friction.rbar() * wn * x <= limit * frac;
        if ok {
            *c = want;
            *y = ys;
        }
        ok
    }

    /// Beside a creeping part, every other touching part must push with the creep's
    /// friction too: one that pulls lifts off, the most pulling first, the state put on the
    /// contacts left (a part sliding beside a creep took a pull of 0.1 N for 0.2 s, its
    /// friction feeding 1.7 mJ in). Returns the parts lifted off.
    fn lift_pullers(&self, c: &mut Contacts, y: &mut [f64; DIM]) -> u8 {
        if c.creeping == 0 {
            return 0;
        }
        let top = self.top;
        let f = top.dynamics(c, y, &mut [0.0; DIM]);
        self.lift_pulled(c, y, f, 1e-12 * top.m * top.g, |c| c.creeping != 0)
            .0
    }

    /// The touching part of `c` pulled hardest (its normal force in `f` below `-level`)
    /// lifts off, the state put on the contacts left and their forces solved again, in turn
    /// while `go` holds and a part is pulled. Returns the parts lifted off and the last
    /// forces.
    fn lift_pulled(
        &self,
        c: &mut Contacts,
        y: &mut [f64; DIM],
        mut f: Forces,
        level: f64,
        go: impl Fn(&Contacts) -> bool,
    ) -> (u8, Forces) {
        let top = self.top;
        let mut lifted = 0u8;
        while go(c) {
            let pull = (0..top.parts.n)
                .filter(|&j| c.mode[j] != Mode::Flight && f.n[j] < -level)
                .min_by(|&a, &b| f.n[a].total_cmp(&f.n[b]));
            let Some(j) = pull else { break };
            c.mode[j] = Mode::Flight;
            c.creeping &= !(1 << j);
            c.drilling &= !(1 << j);
            lifted |= 1 << j;
            top.project(c, y);
            f = top.dynamics(c, y, &mut [0.0; DIM]);
        }
        (lifted, f)
    }

    /// Part `i` of `c`, sliding beside other parts with its slip stopped, and the touching
    /// parts whose slips are nearly stopped too (below the creep's range), tried sticking
    /// together ([`Self::settle`]): the phase where part `i` then sticks, else None (`y`
    /// unchanged). Alone on the floor: None.
    fn settle_beside(&self, c: &Contacts, i: usize, hop: f64, y: &mut [f64; DIM]) -> Option<Phase> {
        if c.mask(self.top.parts.n) == 1 << i {
            return None;
        }
        let mut ph = Phase { contacts: *c, hop };
        self.settle(&mut ph, y);
        (ph.contacts.mode[i] == Mode::Roll).then_some(ph)
    }

    /// The parts of a phase about to start that slide (not creeping) with their slips
    /// already stopped (their sliding measure at most the stick speed `eps`), each stopped as
    /// at its `SlipToRoll` event (sticking, with the parts that can stick beside it, else
    /// creeping): the switch before left them so (the impulse that stuck another part
    /// stopped this one's slip too: a top on a rim and a point, both sliding to rest
    /// together, floor campaign case 5415 of seed 1), and that event, located on the measure
    /// falling to the stick speed, would never be seen from below it: the part's law's
    /// direction chattered at slips of 1e-13 m/s through 4 million steps in 2e-8 s. Returns
    /// the parts stuck and those lifted off (bit masks).
    fn stop_stopped(&self, phase: &mut Phase, y: &mut [f64; DIM], eps: f64) -> (u8, u8) {
        let top = self.top;
        let n = top.parts.n;
        let (mut stuck, mut lifted) = (0u8, 0u8);
        if phase.contacts.flat || !top.friction.can_stick() {
            return (stuck, lifted);
        }
        let mut seen = 0u8;
        for _ in 0..n {
            let c = phase.contacts;
            let k = top.kin(y);
            let stopped = (0..n).find(|&j| {
                c.mode[j] == Mode::Slip
                    && (c.creeping | seen) & (1 << j) == 0
                    && top.part_slide(&k, j) <= eps
            });
            let Some(j) = stopped else { break };
            seen |= 1 << j;
            let next = self.apply(Switch::SlipToRoll(j), phase, y);
            stuck |= c.mask_of(Mode::Slip, n) & next.contacts.mask_of(Mode::Roll, n);
            lifted |= c.mask(n) & !next.contacts.mask(n);
            *phase = next;
            phase.contacts.creep = eps;
        }
        (stuck, lifted)
    }

    /// Where a phase would start with the floor pulling and no set of modes keeps every part
    /// pressing ([`Self::resolve_pushing`]): the sliding parts whose slips are stopped (at
    /// most `eps`) creep, their friction the consistent sliding's instead of the law's at
    /// zero slip (which takes the slip direction kept from before), kept where every part
    /// then pushes: the contacts and their forces. A sharp rim landing at 269 rad/s stopped
    /// by its impact, unable to stick, was left sliding along the direction it had slid in
    /// before, the floor pulling it with 2.71 N on a 48 g top, where its consistent creep
    /// pushes with 0.055 N (the floor campaign's case 1707 of seed 2: the creep was taken or
    /// not as the stick tried at the impact pushed or not, at rounding level).
    fn creep_stopped(
        &self,
        c: &Contacts,
        y: &[f64; DIM],
        eps: f64,
    ) -> Option<(Contacts, super::solve::Forces)> {
        let top = self.top;
        let n = top.parts.n;
        if c.flat || !top.friction.can_stick() {
            return None;
        }
        let k = top.kin(y);
        let stopped = (0..n)
            .filter(|&j| c.mode[j] == Mode::Slip && top.part_slide(&k, j) <= eps)
            .fold(0u8, |m, j| m | 1 << j);
        if stopped & !c.creeping == 0 {
            return None;
        }
        let mut r = *c;
        r.creeping |= stopped;
        let mut dy = [0.0; DIM];
        let f = top.dynamics(&r, y, &mut dy);
        (!pulled(top, &r, &f)).then_some((r, f))
    }

    pub(crate) fn record(&self, sw: Switch) -> (&'static str, Option<usize>) {
        (sw.name(), Some(sw.part()))
    }

    /// Readies a phase to start at `y`: the event functions' offsets, and the parts that stick
    /// where their friction has already left the cone (by more than rounding: the state a
    /// switch leaves them in) slide from the start, creeping where alone; a creeping part
    /// whose creep has no consistent friction lifts off; a part alone that slides with its
    /// slip stopped while it drills rolls on drilling ([`Contacts::drilling`]). Returns the
    /// parts set sliding, those lifted off and those set drilling (bit masks), for the
    /// record.
    pub(crate) fn prepare(&self, phase: &mut Phase, y: &mut [f64; DIM], eps: f64) -> (u8, u8, u8) {
        let top = self.top;
        let n = top.parts.n;
        *self.last.borrow_mut() = Solved::NONE;
        phase.contacts.creep = eps;
        // The side of each resistance's kink the phase starts on, and the drilling's sign.
        let w = top.kin(y).w;
        self.drill_sign.set(if w[2] < 0.0 { -1.0 } else { 1.0 });
        let rates = [w[0].hypot(w[1]), w[2].abs()];
        let bands = self.bands;
        let (mut side, crossed) = (self.band.get(), self.band_crossed.replace(0));
        for j in 0..2 {
            side[j] = if crossed & (1 << j) != 0 {
                -side[j]
            } else if rates[j] < bands[j] {
                -1.0
            } else {
                1.0
            };
        }
        self.band.set(side);
        let mut slid = 0u8;
        // Drilling is a state of a part alone on the floor, rolling.
        let alone = phase.contacts.mask(n);
        if alone.count_ones() != 1 || phase.contacts.mask_of(Mode::Roll, n) != alone {
            phase.contacts.drilling = 0;
        }
        // A part alone that slides with its slip already stopped while it drills (the
        // switch to drilling is located on the slip falling to the stick speed, and would
        // not be seen from below it).
        let mut drilled = 0u8;
        if let Some(i) = (0..n).find(|&i| self.may_drill(&phase.contacts, i)) {
            let k = top.kin(y);
            let vp = top.parts.shape[i].point_velocity(k.v, k.w, k.e3);
            if vp[0].hypot(vp[1]) <= eps
                && self.try_drill(&mut phase.contacts, i, y, eps, DRILL_ENTRY * eps)
            {
                drilled = 1 << i;
            }
        }
        let mut lifted = 0u8;
        let (stuck, left) = self.stop_stopped(phase, y, eps);
        drilled |= stuck;
        lifted |= left;
        if !phase.contacts.flat && phase.contacts.mask_of(Mode::Roll, n) != 0 {
            let mut dy = [0.0; DIM];
            let f = top.dynamics(&phase.contacts, y, &mut dy);
            // Rounding of a cone margin: of the friction's own scale.
            let round = 1e-12 * top.friction.mu() * top.m * top.g.max(1e-300);
            for i in 0..n {
                if phase.contacts.mode[i] == Mode::Roll
                    && phase.contacts.drilling & (1 << i) == 0
                    && top.stick_margin(&f, i) < -round
                    && f.n[i] >= 0.0
                {
                    phase.contacts.slide_against(i, &f);
                    slid |= 1 << i;
                }
            }
            phase.contacts.creeping |= slid;
        }
        // Only a sliding part creeps (a part set sliding here included); several creep
        // together ([`PlayTop::joint_creep_friction`]).
        let c = phase.contacts;
        phase.contacts.creeping = (0..n)
            .filter(|&i| self.creeps(&c, i))
            .fold(0, |m, i| m | 1 << i);
        // A creep that starts with its slip (of the order of the stick speed) turned more than
        // 60 degrees away from its direction (a failed stick's round-off slip, pointing
        // anywhere) has that slip put on the direction first, as at the creep's turn
        // ([`Switch::CreepEnd`]): its event function would start on the far side and never
        // see the slip grow past the creep's range (the floor campaign's case 4311 of seed 1:
        // a creep went on to a slip of 0.23 m/s, its friction feeding in 5.9e-8 J).
        // A creep whose friction has no consistent direction and whose normal force would
        // pull without it lifts off instead ([`PlayTop::creep_friction`]).
        let creeping = phase.contacts.creeping;
        for i in (0..n).filter(|&i| creeping & (1 << i) != 0) {
            let mut dy = [0.0; DIM];
            if top.dynamics(&phase.contacts, y, &mut dy).n[i] < 0.0 {
                phase.contacts.mode[i] = Mode::Flight;
                phase.contacts.creeping &= !(1 << i);
                lifted |= 1 << i;
                continue;
            }
            let (size, along) = top.creep_slip(&phase.contacts, i, y);
            if creep_turn(size, along, eps) <= 0.0 {
                self.realign(&mut phase.contacts, i, y);
            }
        }
        lifted |= self.lift_pullers(&mut phase.contacts, y);
        if lifted != 0 {
            // A part lifted off here (a creep's) may leave another sliding with its slip
            // stopped, which could not stick beside the creep (case 6878 of seed 1): it is
            // stopped now.
            let (stuck, left) = self.stop_stopped(phase, y, eps);
            drilled |= stuck;
            lifted |= left;
        }
        // A phase never starts with the floor pulling a touching part beyond [`PULL`] (the
        // switch before it left modes whose forces pull once prepared: a creep turned back
        // onto its direction beside a part whose normal force changed branch, floor campaign
        // case 632 of seed 1): the touching parts' modes are resolved afresh, where a set
        // keeps every one pressing or lets it leave ([`Self::resolve_pushing`]).
        // The forces the phase starts with (one solve) then give each sticking part's cone
        // slack and each sliding part's jam event its arming ([`Rules`]).
        let mut slack = [0.0; super::MAX_PARTS];
        let mut lift = [0.0; super::MAX_PARTS];
        let mut jam = jam_arming(top);
        if !phase.contacts.flat && phase.contacts.mask(n) != 0 {
            let c = phase.contacts;
            let mut dy = [0.0; DIM];
            let mut f = top.dynamics(&c, y, &mut dy);
            if pulled(top, &c, &f) {
                if let Some(r) = self.resolve_pushing(y, c.mask(n), &c, eps) {
                    lifted |= c.mask(n) & !r.mask(n);
                    slid |= c.mask_of(Mode::Roll, n) & r.mask_of(Mode::Slip, n);
                    drilled |= c.mask_of(Mode::Slip, n) & r.mask_of(Mode::Roll, n);
                    phase.contacts = r;
                    f = top.dynamics(&r, y, &mut dy);
                } else if let Some((r, fr)) = self.creep_stopped(&c, y, eps) {
                    phase.contacts = r;
                    f = fr;
                } else {
                    // No set of modes keeps every touching part pressing: the floor cannot
                    // pull, so the most pulling part leaves, in turn. A sliding part's
                    // measure at the creep speed, where its law's friction changes branch,
                    // had another part's normal force jump through zero; the lift-off
                    // located there was refused at every step and the phases started pulled
                    // (0.165 N on a 0.26 kg top, floor campaign seed 3's case 3546 at rtol
                    // 1e-8; 0.009 N on a 3.2 g top for 0.7 us, seed 1's 6470 at 1e-6).
                    let mut r = c;
                    let (left, fr) = self.lift_pulled(&mut r, y, f, PULL * top.m * top.g, |_| true);
                    lifted |= left;
                    f = fr;
                    phase.contacts = r;
                }
            }
            // Rounding of a cone margin: of the friction's own scale.
            let round = 1e-12 * top.friction.mu() * top.m * top.g.max(1e-300);
            let c = phase.contacts;
            for i in 0..n {
                if c.mode[i] != Mode::Flight && f.n[i] <= 0.0 {
                    lift[i] = PULL * top.m * top.g - f.n[i];
                }
                match c.mode[i] {
                    Mode::Roll if c.drilling & (1 << i) == 0 => {
                        slack[i] = (-top.stick_margin(&f, i)).max(0.0) + round;
                    }
                    Mode::Slip => {
                        if f.den[i] > 0.0 {
                            jam[i][0] = jam[i][0].min(0.5 * f.den[i]);
                        }
                        jam[i][1] = jam[i][1].max(2.0 * f.n[i]);
                    }
                    _ => {}
                }
            }
        }
        self.slack.set(slack);
        self.lift.set(lift);
        self.jam.set(jam);
        let k = top.kin(y);
        let mut floor = [0.0; super::MAX_PARTS];
        for (i, f) in floor.iter_mut().enumerate().take(top.parts.n) {
            let gap = top.parts.shape[i].gap(k.zg, k.e3);
            *f = top.touchdown_offset() + (-gap).max(0.0);
        }
        self.floor.set(floor);
        (slid & !lifted, lifted, drilled)
    }

    pub(crate) fn apply(&self, sw: Switch, phase: &Phase, y: &mut [f64; DIM]) -> Phase {
        let top = self.top;
        let n = top.parts.n;
        let mut c = phase.contacts;
        if !matches!(sw, Switch::Band(_)) {
            self.drill_refused.set(0);
        }
        if !matches!(sw, Switch::Band(_) | Switch::CreepEnd(_)) {
            self.realigns.set((0, f64::NEG_INFINITY));
        }
        match sw {
            Switch::Band(j) => {
                // Only the integration restarts, on the other side of the kink.
                self.band_crossed.set(self.band_crossed.get() | 1 << j);
                *phase
            }
            Switch::LiftOff(i) => {
                // Leaves from the contact: the located state is put back on it first.
                top.project(&c, y);
                let eps = self.tolerance(y);
                let mut dy = [0.0; DIM];
                if top.dynamics(&c, y, &mut dy).n[i] < -PULL * top.m * top.g {
                    // The normal force jumped through zero (see [`PULL`]): the modes of every
                    // touching part, this one included, are resolved afresh at the switch;
                    // the part lifts off only where no set keeps it pressing.
                    if let Some(r) = self.resolve_pushing(y, c.mask(n), &c, eps) {
                        return Phase {
                            contacts: r,
                            hop: f64::INFINITY,
                        };
                    }
                }
                c.mode[i] = Mode::Flight;
                let rest = c.mask(n);
                if rest != 0 {
                    c = top.resolve(y, rest, &c, eps);
                }
                top.project(&c, y);
                Phase {
                    contacts: c,
                    hop: f64::INFINITY,
                }
            }
            Switch::Touchdown(i)
                if c.mask(n) == 0 && top.lying_flat(y, 1e-9 * top.reach()) == Some(i) =>
            {
                // A ring comes down flat: the whole rim strikes at once.
                if top.flat_impact(i, y, top.restitution) {
                    Phase {
                        contacts: Contacts::NONE,
                        hop: 2.0 * y[12] / top.g,
                    }
                } else {
                    self.lie_flat(i, y)
                }
            }
            Switch::Touchdown(i) => {
                let set = c.mask(n) | (1 << i);
                let mut target = [0.0; 4];
                let k = top.kin(y);
                let vn = top.parts.shape[i].gap_rate(k.v[2], k.w, k.e3);
                target[i] = -top.restitution * vn;
                // A bounce below the cut-off is absorbed ([`PlayTop::bounce_height`]).
                if top.bounce(i, y, target[i], &c).is_none() {
                    target[i] = 0.0;
                }
                let (yi, _) = top.impact(y, set, target);
                // A part the impact lifts off so slowly that it would be back within a
                // thousandth of the free-fall time through the reach (a rocking between two
                // parts whose period shrinks to zero, as a rocking block's does) stays on the
                // floor: the impact is taken again with it kept.
                let rock = 1e-3 * (top.reach() / top.g.max(1e-300)).sqrt();
                let k1 = top.kin(&yi);
                let mut keep = 0u8;
                for j in 0..n {
                    if set & (1 << j) != 0 && j != i {
                        let vj = top.parts.shape[j].gap_rate(k1.v[2], k1.w, k1.e3);
                        if vj > 0.0 && top.g > 0.0 && 2.0 * vj / top.g <= rock {
                            keep |= 1 << j;
                        }
                    }
                }
                *y = if keep != 0 {
                    top.impact_keeping(y, set, target, keep).0
                } else {
                    yi
                };
                let mut after = self.after_impulse(y, &c);
                if keep != 0 {
                    self.settle(&mut after, y);
                }
                // Where no impulse keeps them (the kept part would have to pull) and the
                // struck part, its approach unstopped, is left in flight, the impact stands
                // as it was: an 82 g top rolling on a sharp rim whose tip struck the floor
                // had no impulse at all, the tip going on into the floor at 0.7 mm/s, its
                // touchdown located again every 6e-11 s until 200 000 switches refused the
                // run (the floor campaign's case 34 of seed 35 at t_end 5 s).
                if keep != 0 && after.contacts.mode[i] == Mode::Flight {
                    let k = top.kin(y);
                    if top.parts.shape[i].gap_rate(k.v[2], k.w, k.e3) < 0.0 {
                        *y = yi;
                        after = self.after_impulse(y, &c);
                    }
                }
                after
            }
            Switch::SlipToRoll(i) if phase.contacts.flat => {
                // A flat ring's sliding and spinning stop together: it rests.
                let c = top.flat_contacts(i, true);
                top.project(&c, y);
                Phase {
                    contacts: c,
                    hop: f64::INFINITY,
                }
            }
            Switch::SlipToRoll(i) => {
                // Part i stops slipping. Every touching part whose sliding has stopped (within
                // the tolerance) is tried sticking with it, jointly: a part that could not
                // stick alone while another still slid may stick once both do. The impulse
                // that stops the new sticking parts' remaining slips may stop another's: it
                // is tried in turn.
                // "Stopped": within the tolerance, or no faster than part i is as it stops
                // (its located measure may exceed the tolerance by the location's error).
                let measure = top.part_slide(&top.kin(y), i);
                let eps = self.tolerance(y);
                if self.creeps(&c, i)
                    && measure > (CREEP_EXIT * eps).max(1e-2 * self.creep_exit(y, eps))
                {
                    // The friction a creeping part needs is back in its cone, but its slip
                    // has grown to a hundredth of the creep's range: the law's friction stops
                    // it first (below that, the stick's impulse stops it).
                    c.creeping &= !(1 << i);
                    top.project(&c, y);
                    return Phase {
                        contacts: c,
                        hop: phase.hop,
                    };
                }
                let eps = eps.max(measure) * 1.01;
                let mut dy = [0.0; DIM];
                for round in 0..n {
                    let k = top.kin(y);
                    let mut want = c;
                    let mut tried = 0u8;
                    for j in 0..n {
                        if c.mode[j] == Mode::Slip
                            && ((round == 0 && j == i) || top.part_slide(&k, j) <= eps)
                        {
                            want.mode[j] = Mode::Roll;
                            tried |= 1 << j;
                        }
                    }
                    let f = top.demote(&mut want, y, tried, &mut dy);
                    let mut push = want.all_push(&f, n);
                    let mut sticking = tried & want.mask_of(Mode::Roll, n);
                    if !push && sticking != 0 {
                        // A part the stick leaves pulled (beyond [`PULL`]) lifts off: the top
                        // turns on the parts that stick. A 6 g top sliding to rest on a
                        // sphere and a sharp rim, its rotation stopped: the sphere could
                        // stick and the rim not, pulled by 1e-3 of the weight, and both slid
                        // on at the stick speed, each stick refused, until the steps fell to
                        // 1e-14 s (the floor campaign's case 2414 of seed 34 at t_end 5 s).
                        let (mut lc, mut yl) = (want, *y);
                        let (_, fl) =
                            self.lift_pulled(&mut lc, &mut yl, f, PULL * top.m * top.g, |_| true);
                        let stuck = tried & lc.mask_of(Mode::Roll, n);
                        if lc.all_push(&fl, n) && stuck != 0 {
                            (want, push, sticking) = (lc, true, stuck);
                            *y = yl;
                        }
                    }
                    if !push || sticking == 0 {
                        for j in 0..n {
                            if want.mode[j] == Mode::Slip && c.mode[j] == Mode::Slip {
                                c.dir[j] = want.dir[j];
                            }
                        }
                        // A part that cannot stick creeps (alone on the floor, or beside
                        // the others: the joint system's consistent creep). Beside others
                        // whose slips are nearly stopped too (below the creep's range, where
                        // their law's direction turns at rates a creep cannot follow), the
                        // parts are first tried sticking together ([`Self::settle`]).
                        if c.mode[i] == Mode::Slip && push {
                            if let Some(ph) = self.settle_beside(&c, i, phase.hop, y) {
                                c = ph.contacts;
                            } else {
                                c.creeping |= 1 << i;
                                top.project(&c, y);
                                self.lift_pullers(&mut c, y);
                            }
                        }
                        break;
                    }
                    // The remaining (tolerance-sized) slips of the new sticking parts are
                    // stopped by an impulse that keeps every part's gap rate.
                    let (yi, _) = top.impact(y, sticking, top.kept_gap_rates(y));
                    *y = yi;
                    c = want;
                }
                top.project(&c, y);
                Phase {
                    contacts: c,
                    hop: phase.hop,
                }
            }
            Switch::SlipToDrill(i) => {
                let eps = self.tolerance(y);
                // The slip the drilling's friction needs may be up to DRILL_ENTRY stick
                // speeds; for a slide held within the drilling's exit range (its steps
                // crawling), up to that range.
                let limit = if self.unlocated.get() {
                    DRILL_EXIT * eps
                } else {
                    DRILL_ENTRY * eps
                };
                if top.friction.rbar() * top.kin(y).w[2].abs() <= eps {
                    // The drilling has stopped too: the part sticks.
                    return self.apply(Switch::SlipToRoll(i), phase, y);
                }
                if !self.try_drill(&mut c, i, y, eps, limit) {
                    if !self.unlocated.get() {
                        self.drill_refused.set(1 << i);
                    }
                    top.project(&c, y);
                }
                Phase {
                    contacts: c,
                    hop: phase.hop,
                }
            }
            Switch::DrillEnd(i) => {
                // The patch stops drilling (its remaining rate, at the stick speed, is
                // stopped by the projection): the part sticks; where its friction cannot
                // hold it, the phase's start sets it sliding.
                c.drilling &= !(1 << i);
                top.project(&c, y);
                Phase {
                    contacts: c,
                    hop: phase.hop,
                }
            }
            Switch::RollToSlip(i) if c.drilling & (1 << i) != 0 => {
                // The slip the friction needs has grown past DRILL_EXIT stick speeds: the
                // part slides on under its law, from zero slip, its patch drilling.
                c.drilling = 0;
                c.mode[i] = Mode::Slip;
                top.project(&c, y);
                Phase {
                    contacts: c,
                    hop: phase.hop,
                }
            }
            Switch::CreepEnd(i) => {
                // Beside others: the parts nearly stopped are tried sticking together first
                // (the others' law may turn the creep's slip at every step).
                if let Some(ph) = self.settle_beside(&c, i, phase.hop, y) {
                    return ph;
                }
                let (size, _) = top.creep_slip(&c, i, y);
                // Realignments in a row, each within REALIGN_QUICK of the top's time of the last.
                let (count, last) = self.realigns.get();
                let now = self.now.get();
                let quick = REALIGN_QUICK * (top.reach() / top.g).sqrt();
                let count = if now - last <= quick { count + 1 } else { 1 };
                if !self.unlocated.get()
                    && count <= REALIGN_MAX
                    && size < 0.5 * self.creep_exit(y, self.tolerance(y))
                {
                    self.realigns.set((count, now));
                    // The slip turned away from the creep's direction: its component across
                    // it is damped at once, as the law would in a time of |slip| / (mu g),
                    // and the part creeps on (unless the slip kept lies past its range).
                    self.realign(&mut c, i, y);
                } else {
                    // The slip has grown past the creep's range: the law's own direction.
                    c.creeping &= !(1 << i);
                    top.project(&c, y);
                }
                Phase {
                    contacts: c,
                    hop: phase.hop,
                }
            }
            Switch::RollToSlip(i) => {
                let mut dy = [0.0; DIM];
                c.slide_against(i, &top.dynamics(&c, y, &mut dy));
                // The part starts to slide from zero slip: it creeps (beside any others
                // creeping already).
                c.creeping |= 1 << i;
                let f = top.dynamics(&c, y, &mut dy);
                if f.n[i] < 0.0 {
                    // (A creep with no consistent friction: see PlayTop::creep_friction.)
                    c.mode[i] = Mode::Flight;
                    c.creeping &= !(1 << i);
                }
                top.project(&c, y);
                Phase {
                    contacts: c,
                    hop: f64::INFINITY,
                }
            }
            Switch::Flat(i) => {
                // The ring comes down flat: the plastic impact of its face, then it lies flat.
                self.lie_flat(i, y)
            }
            Switch::Jam(i) => {
                // The tangential impact of the Painleve case: an impulse at the part that
                // stops its slip, sticking if the cone allows, else sliding until the slip
                // along its direction is gone.
                *y = match top.jam_impact(y, i) {
                    Some(yi) => yi,
                    None => top.impact(y, c.mask(n), [0.0; 4]).0,
                };
                self.after_impulse(y, &c)
            }
        }
    }

    /// The longest first step of `phase` from `y`: a quarter of the time in which the slip of
    /// a sliding part (not creeping) would stop at its deceleration there, where it
    /// decelerates from more than [`CREEP_EXIT`] stick speeds (a slip starting from rest, or
    /// near the stick speed, where its stop is the located `slip_to_roll`, is left alone). The starting-step heuristic sees the motion's first two derivatives only;
    /// a slip that stops within the step turns its friction round there, which DOP853's
    /// error estimate missed: a 0.3 kg top whose ring came to slide after a run of bounces
    /// at 9e-4 m/s, stopping within 6e-5 s, took a first step of 1.4e-4 s through the stop,
    /// its E + dissipated rising by 5.2e-5 of the energy at rtol 1e-6 (the floor campaign's
    /// case 4290 of seed 19).
    pub(crate) fn first_step(&self, phase: &Phase, y: &[f64; DIM]) -> f64 {
        let top = self.top;
        let c = &phase.contacts;
        let n = top.parts.n;
        let sliding = |i: usize| c.mode[i] == Mode::Slip && c.creeping & (1 << i) == 0;
        if c.flat || !top.friction.can_stick() || !(0..n).any(sliding) {
            return f64::INFINITY;
        }
        // The slips' rates by a forward difference along the phase's own motion.
        let mut dy = [0.0; DIM];
        top.dynamics(c, y, &mut dy);
        let d = 1e-7 * (top.reach() / top.g).sqrt();
        let mut y2 = *y;
        for (a, b) in y2.iter_mut().zip(&dy) {
            *a += d * b;
        }
        let (k, k2) = (top.kin(y), top.kin(&y2));
        let mut cap = f64::INFINITY;
        for i in (0..n).filter(|&i| sliding(i)) {
            let p = &top.parts.shape[i];
            let (v, v2) = (
                p.point_velocity(k.v, k.w, k.e3),
                p.point_velocity(k2.v, k2.w, k2.e3),
            );
            let size = v[0].hypot(v[1]);
            if size <= CREEP_EXIT * self.tolerance(y) {
                continue;
            }
            let slowing = -(v[0] * (v2[0] - v[0]) + v[1] * (v2[1] - v[1])) / (d * size);
            if slowing > 0.0 {
                cap = cap.min(0.25 * size / slowing);
            }
        }
        cap
    }

    pub(crate) fn max_step(&self, phase: &Phase, y: &[f64; DIM]) -> f64 {
        let top = self.top;
        if phase.contacts.mask(top.parts.n) != 0 {
            // A part off the floor while others touch closes its gap smoothly (the step
            // control follows the motion); no limit, so a part that never touches changes
            // nothing.
            return f64::INFINITY;
        }
        // In flight: a tenth of the free-fall time through the reach, a quarter radian of
        // rotation, and a quarter of a bounce, so that a touchdown is not stepped over.
        let w = (y[4] * y[4] + y[5] * y[5] + y[6] * y[6]).sqrt();
        let mut h = (0.25 / w.max(1e-300)).min(phase.hop / 4.0);
        if top.g > 0.0 {
            h = h.min(0.1 * (top.reach() / top.g).sqrt());
        }
        h
    }

    /// The stick speed at `y`: the model's ([`PlayTop::stick_speed`]) where the integration
    /// resolves it, else the slip it resolves (ten times `rtol` of the speed scale). A slip
    /// below the integration's own error cannot be told from zero: a threshold below it
    /// leaves the parts sliding through that error in ever smaller steps (Euler's disk under
    /// point Coulomb friction, rtol 1e-6, threshold 1e-7: 488 594 steps and no stick phase,
    /// against 240 046 steps and 449 events with the threshold at 1e-5). At the default
    /// rtol (1e-10) and below, the threshold is the model's alone.
    pub(crate) fn tolerance(&self, y: &[f64; DIM]) -> f64 {
        self.top.stick.max(self.resolved.get()) * self.top.speed_scale(y)
    }

    pub(crate) fn row(&self, phase: &Phase, y: &[f64; DIM]) -> PlayRow {
        PlayRow {
            y: *y,
            contacts: phase.contacts,
        }
    }

    /// Integrates a phase: by DOP853, and where a part slides or the top has a resistance and
    /// the explicit steps turn out to be held by stability ([`STIFF_BOUND`]), the rest of the
    /// phase by Radau IIA. The observer sees one run. (A resistance's linear band relaxes its
    /// rate within `RESIST_TIME` of the top's time: a 1.4 g ball top rolling with its spin
    /// about the vertical inside the drilling resistance's band took 136 260 explicit steps
    /// and 645 299 rejections in 5 s at rtol 1e-6, its E + dissipated rising 7.4e-5 of E and
    /// its story wrong, upside down by 4.4 s: the floor campaign's case 1735 of seed 26.)
    pub(crate) fn integrate<O: Observer<DIM>>(
        &self,
        integrator: &Dop853,
        phase: &Phase,
        t: f64,
        y: [f64; DIM],
        t_end: f64,
        obs: &mut O,
    ) -> PhaseResult {
        let kernel = Kernel::of(self.top, &phase.contacts);
        let keep = Keep::of(self.top, &phase.contacts, &y, integrator.rtol);
        let slides = phase.contacts.mode.contains(&Mode::Slip);
        let explicit = Dop853 {
            stiff_stop: (slides || self.top.has_resistance()).then_some(STIFF_BOUND),
            ..*integrator
        };
        let slow = HELD_PACE * (self.top.reach() / self.top.g).sqrt();
        let rings = (0..self.top.parts.n).any(|i| self.ring_on(&phase.contacts, i));
        let held = (!phase.contacts.flat && (rings || slides && self.top.friction.can_stick()))
            .then_some(|y: &[f64; DIM], pace: f64| self.held_switch(phase, y, pace));
        // A restart at a resistance's kink after a phase that ended by Radau IIA goes on by
        // it from the start ([`Rules::stiff_end`]).
        let (t1, y1, st) = if self.stiff_end.replace(false) {
            obs.start(t, &y);
            (t, y, Stats::default())
        } else {
            let mut first = Watched::new(&mut *obs, held, slow, t, y, t_end, false);
            // A slide whose explicit steps fall below the held pace with no switch to end it on
            // goes on by Radau IIA too: the step-size test estimates the stiffness along the last
            // stages' difference and can miss it (a sharp rim under Coulomb-Contensou friction
            // with a drilling resistance, the spin about the figure axis relaxing at about
            // 1e10 /s, DOP853's steps stable at 2.6e-10 s and not at 3.7e-10 s, the test never
            // tripped; refused as stalled: the floor campaign's case 2831 of seed 10).
            first.stiff_when_slow = slides;
            let (t1, y1, st) =
                self.explicit(&explicit, phase, kernel, keep, t, y, t_end, &mut first)?;
            if let Some(sw) = first.found {
                self.forced.set(Some(sw));
                return Ok((t1, y1, st));
            }
            if (st.stiff_stops == 0 && !first.slowed) || t1 >= t_end {
                return Ok((t1, y1, st));
            }
            (t1, y1, st)
        };
        // Stiff (the explicit steps held by stability: a slip relaxing under friction, the
        // direction of a small slip turning): the rest of the phase by Radau IIA, the same
        // observer going on, held to DOP853's local error (with Radau5's own rule, 2e-8 at
        // rtol 1e-10, the energy of the floor campaign's sliding tops drifted by 1e-8).
        let radau = Radau5 {
            h_max: integrator.h_max,
            max_steps: integrator
                .max_steps
                .saturating_sub(st.steps + st.rejected)
                .max(1),
            ..Radau5::holding_local(integrator.rtol, integrator.atol)
        };
        let mut resumed = Resumed(obs);
        let mut tracked = Watched::new(&mut resumed, held, slow, t1, y1, t_end, true);
        // One integrator per sliding kernel, each with only that kernel inlined, as for DOP853.
        macro_rules! run {
            ($k:expr, $res:expr) => {
                radau.integrate(
                    &self.system::<{ $k }, { $res }>(phase, kernel, keep),
                    t1,
                    y1,
                    t_end,
                    &mut tracked,
                )
            };
        }
        let stiff = match (kernel.code(), self.top.has_resistance()) {
            (code::BALL, _) => run!(code::BALL, false),
            (code::ONE_SLIP, false) => run!(code::ONE_SLIP, false),
            (code::ONE_SLIP, true) => run!(code::ONE_SLIP, true),
            (code::CREEP, false) => run!(code::CREEP, false),
            (code::CREEP, true) => run!(code::CREEP, true),
            _ => run!(code::OTHER, false),
        };
        match stiff {
            Ok((t2, y2, more)) if tracked.found.is_some() || !tracked.crawled => {
                if let Some(sw) = tracked.found {
                    self.forced.set(Some(sw));
                }
                self.stiff_end.set(true);
                Ok((t2, y2, st.plus(&more)))
            }
            Ok(_)
            | Err(IntegrateError::StepSizeTooSmall { .. } | IntegrateError::NonFinite { .. }) => {
                // Radau IIA's Newton iteration fails where the right-hand side is not smooth
                // (the friction's direction turning at a slip of rounding size; a random floor
                // run of Coulomb-Contensou friction, its steps down to 1e-16 s), or crawls
                // (a patch whose slip and drilling have both fallen to a few stick speeds,
                // the law's direction turning at 1e9 /s: the finite-difference Jacobian
                // steps across that turn; case 3983 of the floor campaign's seed 1 took
                // 2.6e5 rejected steps of 1e-14 s there): DOP853 goes on from its last
                // accepted step, without the test.
                let (t2, y2) = tracked.last;
                // A sliding part whose measure is held within the creep's exit range (a few
                // stick speeds: the law's own equilibrium at the edge of its cone, just above
                // the speed its slip_to_roll is located at, so the stick and the creep are
                // never tried) ends the phase there, as at that event: a 1.2 g spheroid under
                // Coulomb-Contensou friction slid at 3.6 stick speeds, DOP853's steps held at
                // 1e-9 s by the law's turning, until the run was refused as stalled (the floor
                // campaign's case 4129 of seed 2).
                let done = match &stiff {
                    Ok((_, _, more)) => *more,
                    Err(_) => Stats {
                        steps: tracked.steps,
                        ..Stats::default()
                    },
                };
                // (Its steps crawl by the run's budget: a pace of none.)
                if let (Some(sw), true) = (held.and_then(|f| f(&y2, 0.0)), t2 > t1) {
                    self.forced.set(Some(sw));
                    return Ok((t2, y2, st.plus(&done)));
                }
                let plain = Dop853 {
                    stiff_stop: None,
                    max_steps: explicit
                        .max_steps
                        .saturating_sub(st.steps + st.rejected + tracked.steps)
                        .max(1),
                    ..*integrator
                };
                let mut rest = Watched::new(tracked.obs, held, slow, t2, y2, t_end, false);
                let (t3, y3, more) =
                    self.explicit(&plain, phase, kernel, keep, t2, y2, t_end, &mut rest)?;
                if let Some(sw) = rest.found {
                    self.forced.set(Some(sw));
                }
                Ok((t3, y3, st.plus(&done).plus(&more)))
            }
            Err(e) => Err(e),
        }
    }

    /// Whether part `i` is a ring (a torus) on the floor in `c`.
    fn ring_on(&self, c: &Contacts, i: usize) -> bool {
        c.mode[i] != Mode::Flight && matches!(self.top.parts.shape[i], Shape::Torus { .. })
    }

    /// The switch that ends `phase` at `y` where its steps crawl: the `slip_to_roll` of a
    /// part sliding (not creeping) with its sliding measure within the creep's exit range,
    /// [`CREEP_EXIT`] stick speeds; else the end of a creep, which hands the part to its
    /// law. A creep takes its friction's direction from the consistency of the contact,
    /// which beside a sliding part can have two roots; a 2.2 g top on a spheroid sliding
    /// and a sphere creeping under point Coulomb friction had its creep's friction jump
    /// between them (35 degrees apart) at every step, steps of 4e-11 s, until the run was
    /// refused as stalled (the floor campaign's case 3877 of seed 3).
    ///
    /// Where both methods crawl (`pace` 0: Radau IIA's steps too, the last resort before
    /// DOP853 goes on without a test), a part sliding alone under its law with its measure
    /// anywhere within the creep's range ([`Self::creep_exit`]) is tried sticking too, and
    /// creeps where it cannot stick: a 2.1 g fat torus rolling upside down and nearly flat
    /// under Coulomb-Contensou friction, its friction at 0.97 of the ellipse and hardly
    /// drilling, slid on at 27 stick speeds after its creep had ended, the law's direction
    /// turning at about 1e10 /s; steps of 6e-10 s until the run was refused as stalled (the
    /// floor campaign's case 188 of seed 27 at t_end 5 s).
    fn held_switch(&self, phase: &Phase, y: &[f64; DIM], pace: f64) -> Option<Switch> {
        let k = self.top.kin(y);
        let c = &phase.contacts;
        // A ring coming down nearly level, pressed by more than FLAT_HELD_FORCE weights: it
        // lands flat ([`FLAT_HELD`]).
        let tilt = (1.0 - k.e3[2] * k.e3[2]).max(0.0).sqrt();
        let ring = |i: usize| self.ring_on(c, i);
        let stalled = FLAT_PACE * (self.top.reach() / self.top.g).sqrt();
        if tilt <= FLAT_HELD && pace < stalled && (0..self.top.parts.n).any(ring) {
            let mut dy = [0.0; DIM];
            let f = self.top.dynamics(c, y, &mut dy);
            let pressed = FLAT_HELD_FORCE * self.top.m * self.top.g;
            // Flat (u = +-1) with ring i on the floor, every other part must be above it: a
            // part the turn would sink is the floor's next contact, not the ring's face.
            let u = k.e3[2].signum();
            let clear = |i: usize| {
                let (pi, fi) = (self.top.part(i), self.top.part(i).profile(u).0);
                (0..self.top.parts.n).filter(|&l| l != i).all(|l| {
                    let pl = self.top.part(l);
                    fi - pl.profile(u).0 + (pl.z() - pi.z()) * u >= 0.0
                })
            };
            if let Some(i) =
                (0..self.top.parts.n).find(|&i| ring(i) && f.n[i] >= pressed && clear(i))
            {
                return Some(Switch::Flat(i));
            }
        }
        if !self.top.friction.can_stick() {
            return None;
        }
        let eps = self.tolerance(y);
        let sliding = |i: usize| c.mode[i] == Mode::Slip;
        (0..self.top.parts.n)
            .find(|&i| {
                sliding(i) && c.creeping & (1 << i) == 0 && {
                    let slide = self.top.part_slide(&k, i);
                    slide <= CREEP_EXIT * eps
                        || (pace == 0.0
                            && c.mask(self.top.parts.n) == 1 << i
                            && slide <= self.creep_exit(y, eps))
                }
            })
            .map(Switch::SlipToRoll)
            .or_else(|| {
                // A patch that still drills, its slip held within that range: it rolls on
                // drilling where the slip its friction needs is within the drilling's exit
                // range (a 13 g top landing on a sphere under Coulomb-Contensou friction
                // slid on at 1.6e-9 m/s, the law's equilibrium just above the stick speed at
                // which that switch is located, its patch drilling at 5e-8 m/s; steps of
                // 2e-9 s until refused as stalled: the floor campaign's case 1858 of seed 5).
                (0..self.top.parts.n)
                    .find(|&i| {
                        self.may_drill(c, i) && {
                            let vp = self.top.parts.shape[i].point_velocity(k.v, k.w, k.e3);
                            vp[0].hypot(vp[1]) <= CREEP_EXIT * eps
                        }
                    })
                    .map(Switch::SlipToDrill)
            })
            .or_else(|| {
                (0..self.top.parts.n)
                    .find(|&i| sliding(i) && self.creeps(c, i))
                    .map(Switch::CreepEnd)
            })
    }

    /// The equations of `phase` with the kernel `K` inlined ([`PlayTop::rates_as`]), keeping
    /// `keep`'s ledger where nothing dissipates.
    fn system<const K: u8, const RES: bool>(
        &self,
        phase: &Phase,
        kernel: Kernel,
        keep: Option<Keep>,
    ) -> PhaseSystem<'_, K, RES> {
        PhaseSystem {
            top: self.top,
            contacts: phase.contacts,
            kernel,
            consts: self.consts(phase),
            last: &self.last,
            keep,
        }
    }

    /// The top's ratios with the sides of the resistances' kinks `phase` keeps to
    /// ([`PlayTop::resistance_on`]): those whose kink it watches ([`Rules::watched`]).
    pub(crate) fn consts(&self, phase: &Phase) -> Consts {
        let mut consts = Consts::of(self.top);
        let band = self.band.get();
        for j in (0..2).filter(|&j| self.watches_band(&phase.contacts, j)) {
            consts.side[j] = band[j];
        }
        consts
    }

    /// Whether a phase of `c` watches resistance `j`'s kink ([`Switch::Band`]; 0 rolling,
    /// 1 drilling): where a part presses on the floor (a ring lying flat: the drilling
    /// resistance's alone, the floor taking the rolling one's torque).
    fn watches_band(&self, c: &Contacts, j: usize) -> bool {
        let top = self.top;
        c.mask(top.parts.n) != 0
            && if j == 0 {
                top.rolling > 0.0 && !c.flat
            } else {
                top.drilling > 0.0
            }
    }

    /// A phase by DOP853, with one integrator per common kernel, each with only that kernel
    /// inlined ([`PlayTop::rates_as`]).
    #[allow(clippy::too_many_arguments)]
    fn explicit<O: Observer<DIM>>(
        &self,
        integrator: &Dop853,
        phase: &Phase,
        kernel: Kernel,
        keep: Option<Keep>,
        t: f64,
        y: [f64; DIM],
        t_end: f64,
        obs: &mut O,
    ) -> PhaseResult {
        macro_rules! run {
            ($k:expr, $res:expr) => {
                integrator.integrate(
                    &self.system::<{ $k }, { $res }>(phase, kernel, keep),
                    t,
                    y,
                    t_end,
                    obs,
                )
            };
        }
        match (kernel.code(), self.top.has_resistance()) {
            (code::FLIGHT, false) => run!(code::FLIGHT, false),
            (code::FLIGHT, true) => run!(code::FLIGHT, true),
            (code::BALL, _) => run!(code::BALL, false),
            (code::ONE_SLIP, false) => run!(code::ONE_SLIP, false),
            (code::ONE_SLIP, true) => run!(code::ONE_SLIP, true),
            (code::ONE_STICK, false) => run!(code::ONE_STICK, false),
            (code::ONE_STICK, true) => run!(code::ONE_STICK, true),
            (code::CREEP, false) => run!(code::CREEP, false),
            (code::CREEP, true) => run!(code::CREEP, true),
            _ => run!(code::OTHER, false),
        }
    }

    /// The right-hand side of a phase with `contacts` at `(t, y)`, evaluated as its
    /// integration evaluates it, the forces kept for the events: for runs that carry more than
    /// the state along (sensitivities), so that their trajectory is a plain run's.
    #[inline(always)]
    pub(crate) fn phase_rates(
        &self,
        contacts: &Contacts,
        kernel: Kernel,
        consts: &Consts,
        t: f64,
        y: &[f64; DIM],
        dy: &mut [f64; DIM],
    ) {
        let mut last = self.last.borrow_mut();
        last.t = t;
        last.q = [y[0], y[1], y[2], y[3]];
        self.top
            .rates(kernel, consts, contacts, y, dy, &mut last.forces);
    }

    pub(crate) fn mode_name(&self, phase: &Phase) -> &'static str {
        phase.contacts.overall(self.top.parts.n).name()
    }
}

/// The components of the state no right-hand side depends on: the horizontal position of
/// the centre of mass (the floor is the same everywhere) and the dissipated energy (a
/// quadrature). Radau IIA leaves them out of its Jacobian and its factorisations; every
/// other column it takes by forward differences. The stiffness is friction's response to
/// the velocities, but the attitude's columns matter to the simplified Newton iteration
/// too: with the velocities' alone it contracted at only 0.25 to 0.6 per iteration where
/// the top turns by a tenth of a radian in a step (T3's ball, forced: 992 of 3 198 attempts
/// rejected for it, against 168 of 1 669 with every column), and random floor runs of
/// Coulomb-Contensou friction stalled in slides of steps rejected one after another (floor
/// campaign, seed 1, cases 3983 and 7137).
const PASSIVE: [bool; DIM] = {
    let mut p = [false; DIM];
    p[7] = true;
    p[8] = true;
    p[13] = true;
    p
};

/// The several-part equations with the parts' modes fixed; every right-hand side's forces
/// are left in `last`.
struct PhaseSystem<'a, const K: u8, const RES: bool> {
    top: &'a PlayTop,
    contacts: Contacts,
    kernel: Kernel,
    consts: Consts,
    last: &'a RefCell<Solved>,
    keep: Option<Keep>,
}

/// The ledger `E + dissipated` of a phase in which nothing dissipates
/// ([`PlayTop::conserves`]: flight, or every touching part sticking, and no resistance),
/// put back after every accepted step.
///
/// There the ledger is a first integral of the phase's equations, and DOP853's local error
/// moves it both ways by about rtol of the energy a step; over tens of thousands of rolling
/// steps that drift had E + dissipated rise by 5.6e-8 of E at rtol 1e-10 (a sharp rim of
/// 12 mm rolling upside down nearly flat for 5 s, 61 303 rolling steps between 905 slides:
/// the floor campaign's case 839 of seed 27 at t_end 5 s). Putting the state back on the
/// first integral after each step is the projection method of Hairer, Lubich and Wanner
/// (Geometric Numerical Integration, 2nd ed., IV.4); the velocities are scaled, as the
/// constraints of sticking parts are homogeneous in them ([`PlayTop::keep_ledger`]).
///
/// Only a move within `band` (the integration's own error, [`KEEP_BAND`] rtol of the energy
/// scale) is taken back: a larger one is not drift, and is left for the energy checks to see.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Keep {
    /// E + dissipated at the phase's start (J).
    pub ledger: f64,
    /// The largest move taken back (J).
    pub band: f64,
}

/// The share of rtol of the energy scale (kinetic energy plus the weight times the top's
/// reach) that one step may move the ledger by and be put back ([`Keep`]).
pub(crate) const KEEP_BAND: f64 = 100.0;

impl Keep {
    /// The ledger to keep along a phase of `c` starting at `y` (integrated at `rtol`), or
    /// `None` where something in it dissipates.
    pub(crate) fn of(top: &PlayTop, c: &Contacts, y: &[f64; DIM], rtol: f64) -> Option<Self> {
        top.conserves(c).then(|| Keep {
            ledger: ledger(top, y),
            band: KEEP_BAND * rtol * (top.kinetic_energy(y) + top.m * top.g * top.reach()),
        })
    }

    /// The projection after every accepted step of a phase of `c`, a plain run's and a
    /// sensitivity run's alike: [`PlayTop::project`], then `keep`'s ledger put back
    /// ([`PlayTop::keep_ledger`]).
    #[inline]
    pub(crate) fn project(keep: Option<&Keep>, top: &PlayTop, c: &Contacts, y: &mut [f64; DIM]) {
        top.project(c, y);
        if let Some(k) = keep {
            top.keep_ledger(y, k.ledger - ledger(top, y), k.band);
        }
    }
}

impl<const K: u8, const RES: bool> OdeSystem<DIM> for PhaseSystem<'_, K, RES> {
    // Never inlined: DOP853 calls it from 13 places (its stages written out), and a copy of
    // the contact equations at each made the integrator 90-160 kB of code, past the
    // instruction cache (callgrind: 956 000 first-level misses on T1 against 3400 now; T3
    // 6.8 -> 6.3 ms for 4.6 % more instructions, the calls; T1 1.86 -> 1.75 ms).
    #[inline(never)]
    fn rhs(&self, t: f64, y: &[f64; DIM], dy: &mut [f64; DIM]) {
        let mut last = self.last.borrow_mut();
        last.t = t;
        last.q = [y[0], y[1], y[2], y[3]];
        self.top.rates_as::<K, RES>(
            self.kernel,
            &self.consts,
            &self.contacts,
            y,
            dy,
            &mut last.forces,
        );
    }
    fn project(&self, y: &mut [f64; DIM]) {
        Keep::project(self.keep.as_ref(), self.top, &self.contacts, y);
    }
    fn passive(&self) -> [bool; DIM] {
        PASSIVE
    }
}

/// How far a creeping part's slip (of length `size`, its component `along` the creep's
/// direction) is from having turned 60 degrees away from that direction, with the stick
/// speed `eps` as slack: at or below zero the creep's friction no longer opposes the slip
/// (it would feed in more than `2 mu N eps` of power).
fn creep_turn(size: f64, along: f64, eps: f64) -> f64 {
    along - 0.5 * size + 2.0 * eps
}

/// The record of a contact event of part `i` at `t` that the engine's rules make at a
/// switch (not a located event of the settings).
impl Switch {
    /// The record of this switch at `t`.
    pub(crate) fn event(self, t: f64) -> EventRecord {
        part_event(self.name(), t, self.part())
    }
}

/// The creeps that `c` ended (parts of `ends` that slide on: `creep_end`) and began (parts of
/// `starts`: `creep`) at `t`, against the creeping mask `before`.
fn push_creeps(
    events: &mut Vec<EventRecord>,
    t: f64,
    before: u8,
    c: &Contacts,
    ends: u8,
    starts: u8,
) {
    let ended = before & !c.creeping & ends;
    for i in (0..MAX_PARTS).filter(|&i| ended & (1 << i) != 0 && c.mode[i] == Mode::Slip) {
        events.push(part_event("creep_end", t, i));
    }
    let started = c.creeping & !before & starts;
    for i in (0..MAX_PARTS).filter(|&i| started & (1 << i) != 0) {
        events.push(part_event("creep", t, i));
    }
}

fn part_event(name: &'static str, t: f64, i: usize) -> EventRecord {
    EventRecord {
        index: None,
        name: name.into(),
        t,
        part: Some(i),
    }
}

/// `E + dissipated` at `y` (J): kinetic and potential energy and the energy dissipated so far,
/// conserved along a phase and never raised by a switch.
pub(crate) fn ledger(top: &PlayTop, y: &[f64; DIM]) -> f64 {
    top.kinetic_energy(y) + top.m * top.g * y[9] + y[13]
}

/// A switch keeps `E + dissipated`: it only turns energy into dissipated energy. The state
/// it leaves is put on the floor from the located state a hair below it
/// ([`PlayTop::touchdown_offset`]), which raises the potential energy by `m g offset`, and
/// its projections round: the difference from `before` is shed ([`PlayTop::shed_energy`]).
pub(crate) fn no_energy_from_a_switch(top: &PlayTop, y: &mut [f64; DIM], before: f64) {
    let now = ledger(top, y);
    top.shed_energy(y, now - before);
}

/// The jam event's level of sliding's own coefficient and cap of the normal force, per
/// part, where a phase starts clear of both ([`Switch::Jam`]): [`PlayTop::jam_level`] and
/// a hundred weights.
fn jam_arming(top: &PlayTop) -> [[f64; 2]; super::MAX_PARTS] {
    [[top.jam_level(), 1e2 * top.m * top.g]; super::MAX_PARTS]
}

/// Whether `contacts` at `y` have a touching part that the floor pulls by more than [`PULL`].
fn pulls(top: &PlayTop, contacts: &Contacts, y: &[f64; DIM]) -> bool {
    let mut dy = [0.0; DIM];
    pulled(top, contacts, &top.dynamics(contacts, y, &mut dy))
}

/// Whether the forces `f` of `contacts` pull a touching part by more than [`PULL`].
fn pulled(top: &PlayTop, contacts: &Contacts, f: &Forces) -> bool {
    (0..top.parts.n).any(|i| contacts.mode[i] != Mode::Flight && f.n[i] < -PULL * top.m * top.g)
}

/// A play top rests when its kinetic energy has fallen to this share of its start.
const REST: f64 = 1e-12;

/// The hybrid run of `top` under the rules `h` (see [`crate::simulate::Model::run`]).
pub(crate) fn drive(
    h: &Rules<'_>,
    top: &PlayTop,
    y0: &[f64; DIM],
    settings: &Settings,
    keep_going: &mut dyn FnMut(f64) -> bool,
    sink: Sink<'_, PlayRow>,
) -> Result<RunInfo> {
    let t_end = settings.t_end;
    let mut info = RunInfo::default();
    let mut y = *y0;
    let e_given = ledger(top, &y);
    let (mut phase, jam) = h.start(&mut y);
    // Putting the start on its contacts (or its impact at t = 0) keeps E + dissipated too.
    no_energy_from_a_switch(top, &mut y, e_given);
    if let Some(sw) = jam {
        info.events.push(sw.event(0.0));
    }
    let mut t = 0.0;
    let mut next_sample = 0usize;
    // Each inversion event fires once.
    let mut fired = vec![false; settings.events.len()];
    // The top rests once its kinetic energy falls below this.
    let rest_level = REST * top.kinetic_energy(&y);
    // The functions of the watched events (None: not watched by the play top).
    let value = move |kind: EventKind, y: &[f64; DIM]| match kind {
        EventKind::Inversion(level) => Some(top.kin(y).e3[2] - level),
        EventKind::Rest => Some(top.kinetic_energy(y) - rest_level),
        _ => None,
    };
    let mut first = true;
    let mut stopped = false;
    let mut n_switches = 0usize;
    // The last switch only restarted the integration ([`Switch::Band`]): no row after it.
    let mut restarted = false;
    loop {
        let h_max = h.max_step(&phase, &y);
        let eps = h.tolerance(&y);
        let creep_before = phase.contacts.creeping;
        let (slid, lifted, drilled) = h.prepare(&mut phase, &mut y, eps);
        let integrator = Dop853 {
            rtol: settings.rtol,
            atol: settings.atol,
            h_init: None,
            h_first_max: h.first_step(&phase, &y),
            h_max,
            max_steps: MAX_STEPS,
            stiff_stop: None,
        };
        if !first {
            for i in (0..top.parts.n).filter(|&i| drilled & (1 << i) != 0) {
                info.events.push(part_event("slip_to_roll", t, i));
            }
        }
        for i in (0..top.parts.n).filter(|&i| slid & (1 << i) != 0) {
            info.events.push(part_event("roll_to_slip", t, i));
            if phase.contacts.creeping & (1 << i) != 0 {
                info.events.push(part_event("creep", t, i));
            }
        }
        for i in (0..top.parts.n).filter(|&i| lifted & (1 << i) != 0) {
            info.events.push(part_event("lift_off", t, i));
        }
        // Parts whose creep the phase's start began (a slip the switch stopped, that cannot
        // stick) or ended (a creep turned back past its range: the law's slide).
        let own = !(slid | lifted | drilled);
        push_creeps(&mut info.events, t, creep_before, &phase.contacts, own, own);
        // The state after a switch at the same time (impacts make it jump), in the modes the
        // phase integrates (those the switch left, prepared).
        if !first && settings.t_eval.is_none() && !restarted {
            sink(t, &h.row(&phase, &y));
        }
        restarted = false;
        let ph = phase;
        // The contact switches of this phase (terminal), then the watched events.
        let switches = h.watched(&ph);
        let mut fns: Vec<RawEventFn<'_>> = Vec::with_capacity(switches.len() + 2);
        let mut specs = Vec::with_capacity(switches.len() + 2);
        for &sw in &switches {
            fns.push(Box::new(move |t: f64, y: &[f64; DIM]| {
                h.value(sw, &ph, t, y, eps)
            }));
            specs.push(EventSpec::new(-1, true));
        }
        let mut watched = Vec::with_capacity(settings.events.len());
        for (i, e) in settings.events.iter().enumerate() {
            if fired[i] || value(e.kind, &y).is_none() {
                continue;
            }
            let kind = e.kind;
            fns.push(Box::new(move |_t: f64, y: &[f64; DIM]| {
                value(kind, y).unwrap_or(0.0)
            }));
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
        // Every step's row, except a later phase's first: the switch already gave it. Each is
        // held until the next, so that the phase's last can be left out (below).
        let mut held: Option<(f64, PlayRow)> = None;
        let row = |ts: f64, yy: &[f64; DIM]| {
            if let Some((t0, r)) = held.replace((ts, h.row(&ph, yy))) {
                sink(t0, &r);
            }
        };
        let mut stream = Stream::new(seg_times, !first, Some(&mut *keep_going), row);
        let mut obs = WithEvents::new(locator, &mut stream);
        let y_start = y;
        let (t1, y1, st) = h
            .integrate(&integrator, &ph, t, y, t_end, &mut obs)
            .map_err(|e| match integrate_error(e, t_end) {
                KreiselError::Numerical(m) => {
                    KreiselError::Numerical(format!("play top, {} mode: {m}", h.mode_name(&ph)))
                }
                other => other,
            })?;
        let hits: Vec<(usize, f64)> = obs.locator.events.iter().map(|e| (e.index, e.t)).collect();
        let located = obs.locator.terminal_event().is_some();
        drop(obs);
        next_sample = offset + stream.taken;
        drop(fns);
        info.stats += st;
        first = false;
        let mut reason = None;
        for (idx, te) in hits {
            if let Some(&sw) = switches.get(idx) {
                // The switch's record, kept where it is in case the switch does not happen.
                reason = Some((sw, info.events.len()));
                info.events.push(sw.event(te));
            } else {
                let i = watched[idx - switches.len()];
                let e = &settings.events[i];
                info.events.push(EventRecord {
                    index: Some(i),
                    name: e.name.clone().into(),
                    t: te,
                    part: None,
                });
                if matches!(e.kind, EventKind::Inversion(_)) {
                    fired[i] = true;
                }
                stopped |= e.terminal;
            }
        }
        // A switch the integration ended the phase on, where no event was located.
        let forced = h.forced.take().filter(|_| reason.is_none() && !stopped);
        if let Some(sw) = forced {
            reason = Some((sw, info.events.len()));
            info.events.push(sw.event(t1));
        }
        t = t1;
        y = y1;
        if located {
            // A located event's state is the step's dense output: its row and the switch
            // start from it put on the phase's constraints ([`at_event`]).
            at_event(top, &ph.contacts, &mut y, &y_start);
            if let Some((ts, r)) = held.as_mut() {
                if *ts == t {
                    *r = h.row(&ph, &y);
                }
            }
        }
        let reason = reason.filter(|_| !stopped && t < t_end);
        if let Some((ts, r)) = held {
            // The row at a switch, located on the far side of it, in the modes before it: left
            // out where those modes have a touching part pulled beyond [`PULL`] (a normal
            // force that jumped through zero there); the row after the switch, at the same
            // time and state, follows.
            // (A requested output time is always kept.)
            if settings.t_eval.is_some()
                || reason.is_none()
                || ts != t
                || !pulls(top, &r.contacts, &r.y)
            {
                sink(ts, &r);
            }
        }
        let Some((switch, record)) = reason else {
            break;
        };
        let before_contacts = phase.contacts;
        let before = before_contacts.mode;
        let g_before: Vec<Option<f64>> =
            settings.events.iter().map(|e| value(e.kind, &y)).collect();
        let e_before = ledger(top, &y);
        h.unlocated.set(forced.is_some());
        h.now.set(t);
        phase = h.apply(switch, &phase, &mut y);
        h.unlocated.set(false);
        no_energy_from_a_switch(top, &mut y, e_before);
        // Other parts that the switch lifted off, put down, stuck or set sliding at the same
        // instant (an impulse, or parts that stick jointly).
        let after = phase.contacts.mode;
        let (own_name, mut own) = h.record(switch);
        n_switches += 1;
        if matches!(switch, Switch::Band(_)) {
            info.events.remove(record);
            restarted = true;
        } else {
            h.stiff_end.set(false);
        }
        if own_name == "creep_end" && phase.contacts.creeping != 0 {
            // The creep's slip was only turned back onto its direction: no event.
            info.events.remove(record);
        }
        if own_name == "lift_off" && own.is_some_and(|i| after[i] != Mode::Flight) {
            // The normal force jumped through zero as other parts' modes changed (see
            // [`PULL`]): the part stays on the floor; its change of mode, if any, and the
            // others' are recorded below.
            info.events.remove(record);
            own = None;
        }
        if own_name == "roll_to_slip" && own.is_some_and(|i| after[i] == Mode::Flight) {
            // The part could not slide (its normal force would pull): it lifted off.
            info.events[record].name = "lift_off".into();
        }
        if own_name == "slip_to_roll" && own.is_some_and(|i| after[i] == Mode::Slip) {
            // The part could not stick (its friction cannot hold it): it slides on, and no
            // slip_to_roll is recorded; where it starts to creep, that is.
            info.events.remove(record);
        }
        // Parts that stop creeping but slide on (the creep's own end records itself).
        // Parts that start to creep at the switch (a part that cannot stick, or that starts
        // to slide from rest, alone on the floor).
        let ends = if matches!(switch, Switch::CreepEnd(_)) {
            0
        } else {
            u8::MAX
        };
        push_creeps(
            &mut info.events,
            t,
            before_contacts.creeping,
            &phase.contacts,
            ends,
            u8::MAX,
        );
        for i in 0..top.parts.n {
            let name = match (before[i], after[i]) {
                (Mode::Flight, Mode::Flight)
                | (Mode::Slip, Mode::Slip)
                | (Mode::Roll, Mode::Roll) => continue,
                (Mode::Flight, _) => "touchdown",
                (_, Mode::Flight) => "lift_off",
                (Mode::Slip, Mode::Roll) => "slip_to_roll",
                (Mode::Roll, Mode::Slip) => "roll_to_slip",
            };
            if Some(i) != own {
                info.events.push(part_event(name, t, i));
            }
        }
        // A watched event whose function the switch carries across zero (an impulse or the
        // projection that ends the last slip or drilling stops the top: rest) happens at
        // the switch; no crossing in a later phase would show it.
        for (i, e) in settings.events.iter().enumerate() {
            let (Some(g0), Some(g1)) = (g_before[i], value(e.kind, &y)) else {
                continue;
            };
            if !fired[i] && EventSpec::new(e.direction, e.terminal).matches(g0, g1) {
                info.events.push(EventRecord {
                    index: Some(i),
                    name: e.name.clone().into(),
                    t,
                    part: None,
                });
                fired[i] = matches!(e.kind, EventKind::Inversion(_));
                stopped |= e.terminal;
            }
        }
        if stopped {
            // The state after the switch at the same time (impacts make it jump).
            if settings.t_eval.is_none() {
                sink(t, &h.row(&phase, &y));
            }
            break;
        }
        check_switches(n_switches, t)?;
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
