//! The play top's contact rules, all of them: the modes (slip, roll, flight) and the
//! switches between them, the events that trigger each switch, the impacts at touchdown and
//! the bounce cut-off, and the projection of a state onto the contact constraint.
//!
//! Switches: slip -> roll when the slip speed falls to (numerically) zero and the rolling
//! force lies in the Coulomb cone; roll -> slip when the rolling force leaves the cone
//! (the slip then starts against the force that rolling would have needed); either contact
//! mode -> flight when the normal force falls to zero; flight -> contact at touchdown,
//! through an impact with restitution and a Coulomb friction impulse.

use super::{add, scale, solve3, Contact, Friction, Kin, Mode, PlayTop, DIM};
use crate::rotation::cross;

/// A switch of contact mode, each located as an event of the phase it ends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Switch {
    /// The normal force falls to zero: the top leaves the floor.
    LiftOff,
    /// The slip speed falls to (numerically) zero: rolling may begin.
    SlipToRoll,
    /// The rolling force leaves the Coulomb cone.
    RollToSlip,
    /// The sphere reaches the floor.
    Touchdown,
    /// Sliding's own coefficient (the gap's acceleration per unit normal force, friction
    /// included) falls towards zero: the Painleve case, ended by a tangential impact.
    Jam,
}

impl Switch {
    /// The event's public name.
    pub const fn name(self) -> &'static str {
        match self {
            Switch::LiftOff => "lift_off",
            Switch::SlipToRoll => "slip_to_roll",
            Switch::RollToSlip => "roll_to_slip",
            Switch::Touchdown => "touchdown",
            Switch::Jam => "tangential_impact",
        }
    }

    /// The switches watched in `mode`, in the order they are handed to the event locator
    /// (Coulomb friction alone can stick).
    pub fn watched(mode: Mode, coulomb: bool, jam: bool) -> &'static [Switch] {
        match (mode, coulomb) {
            (Mode::Slip, true) if jam => &[Switch::LiftOff, Switch::SlipToRoll, Switch::Jam],
            (Mode::Slip, true) => &[Switch::LiftOff, Switch::SlipToRoll],
            (Mode::Slip, false) => &[Switch::LiftOff],
            (Mode::Roll, _) => &[Switch::LiftOff, Switch::RollToSlip],
            (Mode::Flight, _) => &[Switch::Touchdown],
        }
    }
}

/// Where a contact phase stands: its mode, the slip direction taken where the slip speed is
/// zero (Coulomb friction), and the expected length of the current flight after a bounce
/// (infinite: unknown).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Phase {
    /// Contact mode.
    pub mode: Mode,
    /// Slip direction in force at zero slip speed (space frame).
    pub dir: [f64; 3],
    /// Expected flight time after a bounce (s).
    pub hop: f64,
}

impl PlayTop {
    /// The mode a state starts in, and the state put on its constraint; `rtol` is the
    /// integration's (it sets the [`PlayTop::slip_tolerance`]).
    pub fn initial_phase(&self, y: &mut [f64; DIM], rtol: f64) -> Phase {
        self.initial_phase_jam(y, rtol).0
    }

    /// [`Self::initial_phase`], and the switch the start needed, if any: a touchdown (the tip
    /// on the floor and moving into it: the impact of a touchdown at t = 0) or a tangential
    /// impact (sliding with no consistent normal force, the Painleve case).
    pub fn initial_phase_jam(&self, y: &mut [f64; DIM], rtol: f64) -> (Phase, Option<Switch>) {
        let flight = Phase {
            mode: Mode::Flight,
            dir: [0.0; 3],
            hop: f64::INFINITY,
        };
        if self.height(y) <= 1e-12 * self.rho {
            // The tip's normal velocity decides: into the floor, an impact; away from it,
            // a flight (putting either on the contact would change the energy unrecorded).
            let k = self.kin(y);
            let tol = 1e-12 * self.slip_scale(&k);
            if k.v_t[2] < -tol {
                return (
                    self.switch(Switch::Touchdown, &flight, y, rtol),
                    Some(Switch::Touchdown),
                );
            }
            if k.v_t[2] > tol {
                return (flight, None);
            }
        }
        let mode = self.settle(self.initial_mode(y), y, rtol);
        let phase = Phase {
            mode,
            dir: [0.0; 3],
            hop: f64::INFINITY,
        };
        if mode == Mode::Flight && self.height(y) <= 1e-12 * self.rho && self.jammed(y, [0.0; 3]) {
            // Sliding has no consistent normal force at the start (the Painleve case).
            return (self.switch(Switch::Jam, &phase, y, rtol), Some(Switch::Jam));
        }
        self.project(mode, y);
        (phase, None)
    }

    /// Whether sliding at a contact state is in the Painleve case: its own coefficient at or
    /// below [`PlayTop::jam_level`] while a top that may jam ([`PlayTop::may_jam`]) slides.
    /// Under viscous friction no bound holds (the friction per unit N grows with the slip),
    /// so the coefficient is always looked at.
    fn jammed(&self, y: &[f64; DIM], dir: [f64; 3]) -> bool {
        (self.may_jam(-self.s, self.rho) || matches!(self.friction, Friction::Viscous { .. }))
            && self.slip_coefficient(y, dir) <= self.jam_level()
    }

    /// The mode a state starts in.
    pub fn initial_mode(&self, y: &[f64; DIM]) -> Mode {
        if self.height(y) > 1e-12 * self.rho {
            return Mode::Flight;
        }
        let k = self.kin(y);
        let sp = (k.v_t[0] * k.v_t[0] + k.v_t[1] * k.v_t[1]).sqrt();
        let mut dy = [0.0; DIM];
        let slip_n = self.dynamics(Mode::Slip, y, [0.0; 3], &mut dy).n;
        if slip_n < 0.0 {
            return Mode::Flight;
        }
        if sp <= 1e-12 * self.slip_scale(&k) && self.roll_admissible(y).0 {
            Mode::Roll
        } else {
            Mode::Slip
        }
    }

    /// The slip speed taken as zero in a phase from `y`: well above the integration error
    /// of the slip itself (`rtol` of the integration).
    pub fn slip_tolerance(&self, y: &[f64; DIM], rtol: f64) -> f64 {
        (10.0 * rtol).max(1e-10) * self.slip_scale(&self.kin(y))
    }

    /// The event function of `switch` in `phase` (a sign change downward triggers it);
    /// `eps` is the phase's [`PlayTop::slip_tolerance`].
    #[inline]
    pub fn switch_value(&self, switch: Switch, phase: &Phase, y: &[f64; DIM], eps: f64) -> f64 {
        match switch {
            Switch::LiftOff => {
                let mut dy = [0.0; DIM];
                self.dynamics(phase.mode, y, phase.dir, &mut dy).n
            }
            Switch::SlipToRoll => {
                let k = self.kin(y);
                (k.v_t[0] * k.v_t[0] + k.v_t[1] * k.v_t[1]).sqrt() - eps
            }
            Switch::RollToSlip => {
                let mu = match self.friction {
                    Friction::Coulomb { mu } => mu,
                    _ => 0.0,
                };
                let mut dy = [0.0; DIM];
                let c = self.dynamics(Mode::Roll, y, phase.dir, &mut dy);
                mu * c.n - (c.ft[0] * c.ft[0] + c.ft[1] * c.ft[1]).sqrt()
            }
            Switch::Touchdown => self.height(y) + self.touchdown_offset(),
            Switch::Jam => self.slip_coefficient(y, phase.dir) - self.jam_level(),
        }
    }

    /// The level of sliding's own coefficient (1/kg) at which a sliding contact is taken to
    /// jam: a hundredth of a free point mass's 1/m. The normal force grows as the coefficient's
    /// inverse on the way there.
    pub fn jam_level(&self) -> f64 {
        1e-2 / self.m
    }

    /// Whether sliding at a part centred at `z` with radius `r` can ever jam: its own
    /// coefficient is at least `1/m - mu |z| (|z| + r) / min(A, C)` (the normal part's
    /// contribution is positive, the friction's at most mu times the arms' product over the
    /// smallest moment), so below the jam level only when that bound is.
    pub fn may_jam(&self, z: f64, r: f64) -> bool {
        self.friction.can_stick()
            && 1.0 / self.m - self.friction.mu() * z.abs() * (z.abs() + r) / self.a.min(self.c)
                <= self.jam_level()
    }

    /// Sliding's own coefficient at a state: the acceleration of the contact's height per
    /// unit normal force, friction included (1/kg); the slip mode's denominator.
    pub fn slip_coefficient(&self, y: &[f64; DIM], dir: [f64; 3]) -> f64 {
        let mut dy = [0.0; DIM];
        let mut c = super::multi::Contacts::NONE;
        c.mode[0] = Mode::Slip;
        c.dir[0] = [dir[0], dir[1]];
        self.multi_dynamics(&c, y, &mut dy).den[0]
    }

    /// The mode a contact slides in, unless its slip is below the slip tolerance and rolling
    /// can hold it: then it rolls (the sticking impulse applied to `y`). A slip phase that
    /// starts below the tolerance would never see its slip_to_roll event, which watches the
    /// speed falling through it, and Coulomb friction would chatter about zero slip in ever
    /// smaller steps (an impact that does not quite stick leaves such a round-off slip; so
    /// may a start state).
    fn settle(&self, mode: Mode, y: &mut [f64; DIM], rtol: f64) -> Mode {
        if mode != Mode::Slip || !matches!(self.friction, Friction::Coulomb { .. }) {
            return mode;
        }
        let k = self.kin(y);
        let sp = (k.v_t[0] * k.v_t[0] + k.v_t[1] * k.v_t[1]).sqrt();
        if sp <= self.slip_tolerance(y, rtol) && self.roll_admissible(y).0 {
            *y = self.stick(y);
            Mode::Roll
        } else {
            mode
        }
    }

    /// The normal force sliding would need at a state (negative: the floor would have to
    /// pull).
    fn slip_normal(&self, y: &[f64; DIM], dir: [f64; 3]) -> f64 {
        let mut dy = [0.0; DIM];
        self.dynamics(Mode::Slip, y, dir, &mut dy).n
    }

    /// Carries out `switch` at the located state `y`: the new phase, and `y` after the
    /// impact (touchdown) or the sticking impulse (slip to roll), put on the new mode's
    /// constraint. `rtol` is the integration's (it sets the [`PlayTop::slip_tolerance`]).
    pub fn switch(&self, switch: Switch, phase: &Phase, y: &mut [f64; DIM], rtol: f64) -> Phase {
        let coulomb = matches!(self.friction, Friction::Coulomb { .. });
        let Phase {
            mut mode,
            mut dir,
            mut hop,
        } = *phase;
        match switch {
            Switch::LiftOff => {
                // The top leaves the floor from it: the located state (from the dense output,
                // off the contact by the local error) is put back on the contact first.
                self.project(mode, y);
                mode = Mode::Flight;
                hop = f64::INFINITY;
            }
            Switch::SlipToRoll => {
                let (ok, c) = self.roll_admissible(y);
                if ok {
                    mode = Mode::Roll;
                    *y = self.stick(y);
                } else {
                    let ft = (c.ft[0] * c.ft[0] + c.ft[1] * c.ft[1]).sqrt();
                    dir = if ft > 0.0 {
                        [-c.ft[0] / ft, -c.ft[1] / ft, 0.0]
                    } else {
                        dir
                    };
                }
            }
            Switch::RollToSlip => {
                let (_, c) = self.roll_admissible(y);
                let ft = (c.ft[0] * c.ft[0] + c.ft[1] * c.ft[1]).sqrt();
                if ft > 0.0 {
                    dir = [-c.ft[0] / ft, -c.ft[1] / ft, 0.0];
                }
                if self.slip_normal(y, dir) < 0.0 && self.jammed(y, dir) {
                    let jam = Phase {
                        mode: Mode::Slip,
                        dir,
                        hop,
                    };
                    return self.switch(Switch::Jam, &jam, y, rtol);
                }
                mode = if self.slip_normal(y, dir) < 0.0 {
                    hop = f64::INFINITY;
                    Mode::Flight
                } else {
                    Mode::Slip
                };
            }
            Switch::Jam => {
                // The tangential impact: an impulse that stops the slip, sticking if the
                // cone allows, else sliding until the slip along its direction is gone.
                let (yi, sticks) = match self.jam_impact(y, 0) {
                    Some(yi) => (yi, 0),
                    None => self.multi_impact(y, 1, [0.0; 4]),
                };
                *y = yi;
                mode = if sticks != 0 && self.roll_admissible(y).0 {
                    Mode::Roll
                } else {
                    let (_, c) = self.roll_admissible(y);
                    let ft = (c.ft[0] * c.ft[0] + c.ft[1] * c.ft[1]).sqrt();
                    if ft > 0.0 {
                        dir = [-c.ft[0] / ft, -c.ft[1] / ft, 0.0];
                    }
                    if self.slip_normal(y, dir) < 0.0 {
                        hop = f64::INFINITY;
                        Mode::Flight
                    } else {
                        Mode::Slip
                    }
                };
            }
            Switch::Touchdown => {
                let before = *y;
                let (yi, sticks) = self.impact(&before);
                *y = yi;
                let vn = self.kin(y).v_t[2];
                let flies = self.bounce(0, y, vn);
                hop = flies.unwrap_or(f64::INFINITY);
                let bounce = flies.is_some();
                let mut sticks = sticks;
                if !bounce && vn > 0.0 {
                    // A bounce below the cut-off: the impact without restitution instead.
                    let (yp, s2) = self.impact_with(&before, 0.0);
                    *y = yp;
                    sticks = s2;
                }
                mode = if bounce {
                    Mode::Flight
                } else if sticks && coulomb && self.roll_admissible(y).0 {
                    Mode::Roll
                } else {
                    Mode::Slip
                };
                if mode == Mode::Slip && self.slip_normal(y, dir) < 0.0 && self.jammed(y, dir) {
                    let jam = Phase {
                        mode: Mode::Slip,
                        dir,
                        hop,
                    };
                    return self.switch(Switch::Jam, &jam, y, rtol);
                }
                if mode == Mode::Slip && self.slip_normal(y, dir) < 0.0 {
                    // Sliding would need the floor to pull: the top leaves it again, with
                    // no normal speed, so the flight's length is not known in advance.
                    mode = Mode::Flight;
                    hop = f64::INFINITY;
                }
                mode = self.settle(mode, y, rtol);
                if mode != Mode::Flight {
                    let k = self.kin(y);
                    let sp = (k.v_t[0] * k.v_t[0] + k.v_t[1] * k.v_t[1]).sqrt();
                    if sp > 0.0 {
                        dir = [k.v_t[0] / sp, k.v_t[1] / sp, 0.0];
                    }
                }
            }
        }
        self.project(mode, y);
        Phase { mode, dir, hop }
    }

    /// The largest step of a phase: in flight [`PlayTop::flight_step`], and a quarter of
    /// a bounce's expected flight, so that its touchdown is not stepped over.
    pub fn phase_step(&self, phase: &Phase, y: &[f64; DIM]) -> f64 {
        if phase.mode == Mode::Flight {
            self.flight_step(y).min(phase.hop / 4.0)
        } else {
            f64::INFINITY
        }
    }
    /// The change of the velocity of the material point at T caused by an impulse `p` at
    /// T (space frame): `p/m + (I^-1 (a x p)) x a`.
    fn tip_velocity_change(&self, k: &Kin, p: [f64; 3]) -> [f64; 3] {
        let pb = k.to_body(p);
        let dw = self.inv_inertia(cross(k.a_b, pb));
        add(scale(1.0 / self.m, p), k.to_space(cross(dw, k.a_b)))
    }

    /// The contact's inverse effective mass: the matrix of [`Self::tip_velocity_change`].
    fn collision_matrix(&self, k: &Kin) -> [[f64; 3]; 3] {
        let cols = [
            self.tip_velocity_change(k, [1.0, 0.0, 0.0]),
            self.tip_velocity_change(k, [0.0, 1.0, 0.0]),
            self.tip_velocity_change(k, [0.0, 0.0, 1.0]),
        ];
        [
            [cols[0][0], cols[1][0], cols[2][0]],
            [cols[0][1], cols[1][1], cols[2][1]],
            [cols[0][2], cols[1][2], cols[2][2]],
        ]
    }

    /// The friction impulse that stops the remaining (numerically small) slip when rolling
    /// begins, with the energy it takes added to the dissipated energy. Unlike simply
    /// setting the velocity of G, it keeps Jellett's integral and never adds energy.
    pub fn stick(&self, y: &[f64; DIM]) -> [f64; DIM] {
        let k = self.kin(y);
        let mat = self.collision_matrix(&k);
        let p = solve3(mat, [-k.v_t[0], -k.v_t[1], -k.v_t[2]]);
        let (mut out, loss) = self.apply_impulse(y, &k, p);
        // Rounding may show a gain of ~1e-18 J: stopping a slip can only take energy.
        out[13] += loss.max(0.0);
        out
    }

    /// The state after an impulse `p` (space frame) at the contact point, and the kinetic
    /// energy the impulse took.
    fn apply_impulse(&self, y: &[f64; DIM], k: &Kin, p: [f64; 3]) -> ([f64; DIM], f64) {
        let pb = k.to_body(p);
        let dw = self.inv_inertia(cross(k.a_b, pb));
        let mut out = *y;
        for i in 0..3 {
            out[4 + i] += dw[i];
            out[10 + i] += p[i] / self.m;
        }
        (out, self.kinetic_energy(y) - self.kinetic_energy(&out))
    }

    /// Puts a contact state exactly on the constraint: height and vertical velocity of G
    /// from the orientation (and in rolling, the whole velocity of G from the no-slip
    /// condition). Normalises the quaternion.
    pub fn project(&self, mode: Mode, y: &mut [f64; DIM]) {
        let n = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3]).sqrt();
        for v in y.iter_mut().take(4) {
            *v /= n;
        }
        if mode == Mode::Flight {
            return;
        }
        let k = self.kin(y);
        y[9] = self.rho + self.s * k.u;
        if mode == Mode::Roll {
            let v = scale(-1.0, k.to_space(cross(k.w, k.a_b)));
            y[10..13].copy_from_slice(&v);
        } else {
            // d/dt (rho + s u) with du/dt = (Gamma x omega)_3.
            y[12] = self.s * cross(k.gamma, k.w)[2];
        }
    }

    /// The contact force rolling would need, and whether it lies in the Coulomb cone.
    pub fn roll_admissible(&self, y: &[f64; DIM]) -> (bool, Contact) {
        let mut dy = [0.0; DIM];
        let c = self.dynamics(Mode::Roll, y, [0.0; 3], &mut dy);
        let ok = match self.friction {
            Friction::Coulomb { mu } => {
                c.n >= 0.0 && (c.ft[0] * c.ft[0] + c.ft[1] * c.ft[1]).sqrt() <= mu * c.n
            }
            _ => false,
        };
        (ok, c)
    }

    /// The impact at touchdown with restitution and a Coulomb friction impulse: the impulse
    /// that stops the slip of T (and reverses its normal velocity times the restitution)
    /// if it lies in the friction cone, else a sliding impulse against the slip.
    /// Returns the new state and whether the contact sticks (no slip after the impact).
    pub fn impact(&self, y: &[f64; DIM]) -> ([f64; DIM], bool) {
        self.impact_with(y, self.restitution)
    }

    /// [`PlayTop::impact`] with a given coefficient of restitution.
    pub fn impact_with(&self, y: &[f64; DIM], e: f64) -> ([f64; DIM], bool) {
        let k = self.kin(y);
        let vn = k.v_t[2];
        // Velocity change of T per unit impulse P (space frame): P/m + (I^-1 (a x P)) x a.
        let kmat = |p: [f64; 3]| self.tip_velocity_change(&k, p);
        let mat = self.collision_matrix(&k);
        let target = [-k.v_t[0], -k.v_t[1], -(1.0 + e) * vn];
        let mut p = solve3(mat, target);
        let mut sticks = true;
        let mu = match self.friction {
            Friction::Coulomb { mu } => mu,
            _ => 0.0,
        };
        let pt = (p[0] * p[0] + p[1] * p[1]).sqrt();
        if matches!(self.friction, Friction::Coulomb { .. }) && pt <= mu * p[2] {
            // sticking impulse accepted
        } else {
            sticks = false;
            let sp = (k.v_t[0] * k.v_t[0] + k.v_t[1] * k.v_t[1]).sqrt();
            let dir = if sp > 0.0 {
                [k.v_t[0] / sp, k.v_t[1] / sp, 0.0]
            } else {
                [0.0; 3]
            };
            let d = [-mu * dir[0], -mu * dir[1], 1.0];
            let kd = kmat(d);
            let pn = -(1.0 + e) * vn / kd[2];
            p = scale(pn, d);
        }
        let (mut out, loss) = self.apply_impulse(y, &k, p);
        if loss < 0.0 {
            // A Coulomb impulse of one direction that reverses the slip gives energy: the
            // impact is the general one, whose every choice takes energy (and which falls back
            // to a plastic, then frictionless, impact).
            let (mut out, st) = self.multi_impact(y, 1, [-e * vn, 0.0, 0.0, 0.0]);
            out[9] = self.rho + self.s * k.u;
            return (out, st != 0);
        }
        out[13] += loss;
        // The impact happens on the floor.
        out[9] = self.rho + self.s * k.u;
        (out, sticks)
    }
}
