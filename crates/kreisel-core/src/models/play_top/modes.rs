//! Which parts touch and how: the contact modes the complementarity conditions allow (every
//! touching part pushes, every part at zero gap that does not touch separates), sticking
//! where the friction can hold a part, a ring lying flat, and the projection of a state onto
//! its contacts' constraints (theory: several parts).

// Index loops: parts are addressed together by position.
#![allow(clippy::needless_range_loop)]

use super::parts::{Shape, MAX_PARTS};
use super::solve::{Forces, Kin, EZ};
use super::{add, scale, Friction, Mode, PlayTop, DIM};
use crate::rotation::{cross, dot, Quat};

/// Every part's contact mode (slip, roll = stick, flight = not touching) and the slip
/// direction (horizontal, space frame) a Coulomb force takes where the slip speed is zero.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contacts {
    /// Mode of each part.
    pub mode: [Mode; MAX_PARTS],
    /// Slip direction in force at zero slip speed, per part.
    pub dir: [[f64; 2]; MAX_PARTS],
    /// The one touching part is a ring lying flat: it touches along its whole circle
    /// ([`PlayTop::flat_dynamics`]).
    pub flat: bool,
    /// The creep speed (m/s): a part sliding under Coulomb-Contensou friction whose sliding
    /// measure is at or below it (it has stopped, to the phase's tolerance, but cannot stick:
    /// the force sticking needs is outside its ellipse) takes the full friction against that
    /// force (`dir`) instead of the direction of its round-off slip and drilling, so that it
    /// creeps off instead of chattering about zero in ever smaller steps
    /// ([`PlayTop::friction_per_n`]).
    pub creep: f64,
    /// The parts creeping (bit i: part i): a part alone on the floor whose slip and drilling
    /// have stopped, to the phase's tolerance, but whose friction cannot hold it (the force
    /// sticking would need lies outside its cone or ellipse) takes the full friction along
    /// that force instead of against its round-off slip ([`PlayTop::creep_friction`]): the
    /// direction comes from the contact's consistency, so the steps follow the motion instead
    /// of a slip relaxing at a rate that grows as 1/|slip|.
    pub creeping: u8,
    /// The parts rolling while their patch drills (bit i: part i; Coulomb-Contensou friction,
    /// a part alone on the floor, in [`Mode::Roll`]): the slip has stopped but the drilling
    /// has not, and the friction needs no more slip than the stick speed to carry the
    /// tangential force (`rbar |w_n| x / sqrt(1 - x^2)`, `x = |F| / (mu N)`): the slip is held
    /// at zero, the drilling torque is the law's on its ellipse (`PlayTop::drill_solve`),
    /// instead of integrating a slip that relaxes at a rate growing as `1 / (rbar |w_n|)`.
    pub drilling: u8,
}

impl Contacts {
    /// No part touches.
    pub const NONE: Contacts = Contacts {
        mode: [Mode::Flight; MAX_PARTS],
        dir: [[0.0; 2]; MAX_PARTS],
        flat: false,
        creep: 0.0,
        creeping: 0,
        drilling: 0,
    };

    /// The one mode that describes the whole top: slip if a part slides, else roll if a
    /// part sticks, else flight.
    pub fn overall(&self, n: usize) -> Mode {
        let m = &self.mode[..n];
        if m.contains(&Mode::Slip) {
            Mode::Slip
        } else if m.contains(&Mode::Roll) {
            Mode::Roll
        } else {
            Mode::Flight
        }
    }

    /// Part `i` slides against the friction force `f` says sticking would need.
    pub fn slide_against(&mut self, i: usize, f: &Forces) {
        let t = (f.ft[i][0] * f.ft[i][0] + f.ft[i][1] * f.ft[i][1]).sqrt();
        if t > 0.0 {
            self.dir[i] = [-f.ft[i][0] / t, -f.ft[i][1] / t];
        }
        self.mode[i] = Mode::Slip;
    }

    /// Whether every touching part pushes under the forces `f` (no normal force pulls).
    pub fn all_push(&self, f: &Forces, n: usize) -> bool {
        (0..n).all(|i| self.mode[i] == Mode::Flight || f.n[i] >= 0.0)
    }

    /// The parts touching, as a bit mask (bit i: part i).
    pub fn mask(&self, n: usize) -> u8 {
        (0..n).fold(0, |acc, i| {
            acc | (u8::from(self.mode[i] != Mode::Flight) << i)
        })
    }

    /// The parts in `mode`, as a bit mask.
    pub fn mask_of(&self, mode: Mode, n: usize) -> u8 {
        (0..n).fold(0, |acc, i| acc | (u8::from(self.mode[i] == mode) << i))
    }
}

impl PlayTop {
    /// The ring part lying flat at `y`, if one does: a torus touching (its gap within
    /// `tol`) whose plane is within [`super::driver::FLAT_LEVEL`] of the floor's, and no
    /// other part lower.
    pub fn lying_flat(&self, y: &[f64; DIM], tol: f64) -> Option<usize> {
        if self.g <= 0.0 {
            return None;
        }
        let k = self.kin(y);
        let tilt = k.e3[0].hypot(k.e3[1]);
        if tilt >= super::driver::FLAT_LEVEL {
            return None;
        }
        let gaps: Vec<f64> = (0..self.parts.n)
            .map(|i| self.part(i).gap(k.zg, k.e3))
            .collect();
        let lowest = gaps.iter().cloned().fold(f64::INFINITY, f64::min);
        (0..self.parts.n).find(|&i| {
            matches!(self.part(i), Shape::Torus { .. })
                && gaps[i] <= tol
                && gaps[i] <= lowest + 1e-12 * self.reach()
        })
    }

    /// The contacts of ring part `i` lying flat, sliding (or stuck where `stuck`).
    pub fn flat_contacts(&self, i: usize, stuck: bool) -> Contacts {
        let mut c = Contacts::NONE;
        c.mode[i] = if stuck { Mode::Roll } else { Mode::Slip };
        c.flat = true;
        c
    }

    /// The sliding measure of a ring lying flat: `sqrt(|v|^2 + (R w_z)^2)`, the largest
    /// speed of a point of its rim is at most this times sqrt 2 (R from
    /// [`Self::flat_radius`]).
    pub fn flat_slide(&self, i: usize, y: &[f64; DIM]) -> f64 {
        let k = self.kin(y);
        let r = self.flat_radius(i);
        (k.v[0] * k.v[0] + k.v[1] * k.v[1] + r * r * k.w[2] * k.w[2]).sqrt()
    }

    /// The radius over which part `i` touches when the top lies flat on it: a ring's
    /// circle; a part touching at its pole ([`Self::flat_support`]) touches over its
    /// Coulomb-Contensou patch (the drilling's mean radius `rbar`; 0 for a point contact).
    pub fn flat_radius(&self, i: usize) -> f64 {
        match *self.part(i) {
            Shape::Torus { major, .. } => major,
            _ => self.friction.rbar(),
        }
    }

    /// The height of G above the floor where the top lies flat (figure axis vertical, `u` =
    /// +1 upright, -1 upside down) with part `i`'s lowest point on the floor: a ring's
    /// circle, a sphere's or spheroid's pole.
    pub fn flat_height(&self, i: usize, u: f64) -> f64 {
        let p = self.part(i);
        match *p {
            Shape::Torus { z, minor, .. } => minor - z * u,
            _ => p.profile(u).0 - p.z() * u,
        }
    }

    /// The part the top rests on where ring part `i` comes down flat: the ring, unless a
    /// part on the axis reaches below the ring's plane (by less than the flat level over the
    /// ring's radius, else it would have touched first). Then the top lies flat on that
    /// part's pole, the ring's rim within the flat level of the floor (the state of a top
    /// resting on its pole and its rim at the tilt their levels fix, a tilt below the flat
    /// level, where the rim carries a share of the weight of the order of that tilt): so no
    /// part is put below the floor.
    pub fn flat_support(&self, i: usize, y: &[f64; DIM]) -> usize {
        let u = if self.kin(y).e3[2] >= 0.0 { 1.0 } else { -1.0 };
        let mut best = (i, self.flat_height(i, u));
        for l in 0..self.parts.n {
            let h = self.flat_height(l, u);
            if h > best.1 {
                best = (l, h);
            }
        }
        best.0
    }

    /// Each part's gap rate at `y`, at least zero: the normal targets of an impulse that
    /// keeps every gap's rate (and stops a closing one).
    pub fn kept_gap_rates(&self, y: &[f64; DIM]) -> [f64; MAX_PARTS] {
        let k = self.kin(y);
        let mut target = [0.0; MAX_PARTS];
        for (j, t) in target.iter_mut().enumerate().take(self.parts.n) {
            *t = self.parts.shape[j].gap_rate(k.v[2], k.w, k.e3).max(0.0);
        }
        target
    }

    /// Puts a state on the flat contact of part `i` (a ring, or the pole of
    /// [`Self::flat_support`]): the figure axis exactly vertical (the orientation a turn
    /// about it from upright or from upside down, so that the integration keeps it exactly),
    /// no tilting rate, G at the part's resting height ([`Self::flat_height`]) with no
    /// vertical velocity, and where `stuck` no sliding and (over a ring or a patch) no spin.
    /// The kinetic energy removed (a plastic impact of the ring's face on the floor) is added
    /// to the dissipated energy; where the height's change would raise the energy, the
    /// velocities are scaled to keep it.
    pub fn flat_project(&self, i: usize, y: &mut [f64; DIM], stuck: bool) {
        let before = self.kinetic_energy(y) + self.m * self.g * y[9];
        let k = self.kin(y);
        let up = k.e3[2] >= 0.0;
        // A part stuck on a point (no patch) keeps its spin: a point contact takes no
        // moment about the normal.
        let wz = if stuck && self.flat_radius(i) > 0.0 {
            0.0
        } else {
            k.w[2]
        };
        let q = if up {
            // A turn by a about ez: q = (cos a/2, 0, 0, sin a/2), a the heading of body x.
            let a = k.r[1][0].atan2(k.r[0][0]);
            [(0.5 * a).cos(), 0.0, 0.0, (0.5 * a).sin()]
        } else {
            // A half turn about the horizontal (cos b, sin b, 0) maps body x to heading 2b.
            let b = 0.5 * k.r[1][0].atan2(k.r[0][0]);
            [0.0, b.cos(), b.sin(), 0.0]
        };
        // The sign of the quaternion kept (the heading's wrap at pi would flip it).
        let same = q.iter().zip(&y[..4]).map(|(a, b)| a * b).sum::<f64>() >= 0.0;
        y[..4].copy_from_slice(&q.map(|x| if same { x } else { -x }));
        let u = if up { 1.0 } else { -1.0 };
        y[4] = 0.0;
        y[5] = 0.0;
        y[6] = u * wz;
        y[9] = self.flat_height(i, u);
        if stuck {
            y[10] = 0.0;
            y[11] = 0.0;
        }
        y[12] = 0.0;
        let after = self.kinetic_energy(y) + self.m * self.g * y[9];
        self.shed_energy(y, after - before);
    }

    /// The contact modes of the parts in `cand` (touching, not separating) that the
    /// complementarity conditions allow: the largest set whose normal forces push and whose
    /// other candidates' gaps do not close; a part whose sliding measure is below `eps`
    /// sticks where its friction can hold it. `prev` gives the slip directions to keep.
    pub fn resolve(&self, y: &mut [f64; DIM], cand: u8, prev: &Contacts, eps: f64) -> Contacts {
        self.resolve_jam(y, cand, prev, eps).0
    }

    /// [`Self::resolve`], and whether it took a tangential impact.
    pub fn resolve_jam(
        &self,
        y: &mut [f64; DIM],
        cand: u8,
        prev: &Contacts,
        eps: f64,
    ) -> (Contacts, bool) {
        if let Some(c) = self.resolve_at(y, cand, prev, eps) {
            return (c, false);
        }
        // No set is consistent (the Painleve case: sliding would need the floor to pull while
        // the contact is pressed into it): a tangential impact, the impulse that stops the
        // candidates' slip, then the modes again.
        if matches!(self.friction, Friction::Viscous { .. }) {
            // Viscous friction: each candidate's slip decays through its own impact.
            for i in 0..self.parts.n {
                if cand & (1 << i) != 0 {
                    if let Some(yi) = self.jam_impact(y, i) {
                        *y = yi;
                    }
                }
            }
        } else {
            let (yi, _) = self.impact(y, cand, [0.0; MAX_PARTS]);
            *y = yi;
        }
        let c = match self.resolve_at(y, cand, prev, eps) {
            Some(c) => c,
            None => self.never_pulling(y, cand, prev, eps),
        };
        (c, true)
    }

    /// The modes of the candidates `cand` where no set is consistent even after the
    /// tangential impact: sticking where the law can stick (a sticking contact does no
    /// work, so it adds no energy, though its friction may be outside the cone, and its
    /// normal force may pull, until the motion brings them back), the candidates locked first
    /// ([`Self::lock`]). Sliding with a pulling normal force feeds energy in through the
    /// friction: a prolate spheroid under Coulomb-Contensou friction landing from 1.4 mm
    /// gained 7 % of its energy so, and two tops of the floor campaign (cases 6388 and 9362
    /// of seed 1) 3e-4 and 6e-4 where sticking would have pulled as well. Viscous friction
    /// (which cannot stick) has the candidates locked too: at zero slip its force is zero and
    /// the modes are resolved afresh there (sliding only where that fails). Its viscous jam
    /// impact had left a spheroid landing on a disk's rim sliding with a pull of 9 N, its
    /// friction feeding the slip from 0.3 to 18 m/s in 2.4 ms (`Viscous(2.59)`, the floor
    /// campaign's case 8627 of seed 1).
    fn never_pulling(&self, y: &mut [f64; DIM], cand: u8, prev: &Contacts, eps: f64) -> Contacts {
        let n = self.parts.n;
        let with = |mode: Mode| {
            let mut c = Contacts::NONE;
            for i in 0..n {
                if cand & (1 << i) != 0 {
                    c.mode[i] = mode;
                }
            }
            c
        };
        self.lock(y, cand);
        if self.friction.can_stick() {
            return with(Mode::Roll);
        }
        self.resolve_at(y, cand, prev, eps)
            .unwrap_or_else(|| with(Mode::Slip))
    }

    /// Stops the material points of the parts in `set` (bit mask) by plastic impulses, one
    /// part at a time in sweeps until every point is at rest to rounding (Gauss-Seidel on the
    /// joint impulse problem): each impulse takes kinetic energy, which is added to the
    /// dissipated energy, whatever the friction cone allows. For contacts that stick where no
    /// mode is consistent ([`Self::never_pulling`]): a stuck contact whose point still moved
    /// would feed energy in through its constraint force (the floor campaign's case 83 of
    /// seed 1: a torus landing on its rim beside a resting spheroid, stuck at 0.048 m/s,
    /// gained 1.8e-5 of the energy in one step).
    pub(crate) fn lock(&self, y: &mut [f64; DIM], set: u8) {
        let before = self.kinetic_energy(y);
        let vs = self.speed_scale(y);
        for _ in 0..200 {
            let mut moving = 0.0f64;
            for i in (0..self.parts.n).filter(|&i| set & (1 << i) != 0) {
                let k = self.kin(y);
                let arm = self.part(i).arm(k.e3);
                let u = self.part(i).point_velocity(k.v, k.w, k.e3);
                let speed = dot(u, u).sqrt();
                moving = moving.max(speed);
                if speed <= 1e-15 * vs {
                    continue;
                }
                let kmat = super::solve::transpose(self.point_response(&k, arm));
                let p = super::solve3(kmat, scale(-1.0, u));
                if !p.iter().all(|v| v.is_finite()) {
                    continue;
                }
                self.kick(&k, y, p, cross(arm, p));
            }
            if moving <= 1e-13 * vs {
                break;
            }
        }
        let taken = before - self.kinetic_energy(y);
        self.shed_energy(y, -taken);
    }

    /// [`Self::resolve`] without the impact: None where no set (the empty one included) is
    /// consistent.
    pub(crate) fn resolve_at(
        &self,
        y: &[f64; DIM],
        cand: u8,
        prev: &Contacts,
        eps: f64,
    ) -> Option<Contacts> {
        let n = self.parts.n;
        let k = self.kin(y);
        let mut base = Contacts {
            mode: [Mode::Flight; MAX_PARTS],
            dir: prev.dir,
            flat: false,
            creep: prev.creep,
            creeping: 0,
            drilling: 0,
        };
        let mut want = [Mode::Flight; MAX_PARTS];
        for i in 0..n {
            if cand & (1 << i) == 0 {
                continue;
            }
            let p = self.part(i);
            let vp = p.point_velocity(k.v, k.w, k.e3);
            let sp = (vp[0] * vp[0] + vp[1] * vp[1]).sqrt();
            if sp > 0.0 {
                base.dir[i] = [vp[0] / sp, vp[1] / sp];
            }
            want[i] = if self.friction.can_stick() && self.slide_measure(vp, k.w[2]) <= eps {
                Mode::Roll
            } else {
                Mode::Slip
            };
        }
        // Subsets of the candidates, largest first.
        let mut subsets: Vec<u8> = (0..=cand).filter(|s| s & !cand == 0).collect();
        subsets.sort_by_key(|s| std::cmp::Reverse(s.count_ones()));
        let mut dy = [0.0; DIM];
        for s in subsets {
            let mut c = base;
            for i in 0..n {
                if s & (1 << i) != 0 {
                    c.mode[i] = want[i];
                }
            }
            let f = self.demote(&mut c, y, s, &mut dy);
            // A sliding part whose own coefficient is not positive (the Painleve case) is
            // not taken even where its normal force pushes: that is the branch whose force
            // grows without bound (a cone landing on its ball under Coulomb-Contensou
            // friction, mu 0.65, started sliding so at a coefficient of -245 /kg, its normal
            // force growing from 0.19 N to 3900 N in 1.3 ms until the steps fell below
            // 1e-16 s: floor campaign case 7116 of seed 1); flight, where the free motion
            // leaves the floor, or else the tangential impact, is taken instead.
            let push =
                c.all_push(&f, n) && (0..n).all(|i| c.mode[i] != Mode::Slip || f.den[i] > 0.0);
            let open = (0..n).all(|i| {
                cand & (1 << i) == 0
                    || c.mode[i] != Mode::Flight
                    || self.gap_acceleration(i, y, &dy) >= 0.0
            });
            if push && open {
                return Some(c);
            }
        }
        None
    }

    /// The sticking parts of `movable` (bit mask) whose friction leaves its cone or ellipse
    /// slide against it, one at a time, the furthest outside first (the forces change with
    /// every part set sliding), until every one left holds. The forces of the modes reached;
    /// `dy` their state derivative.
    pub fn demote(
        &self,
        c: &mut Contacts,
        y: &[f64; DIM],
        movable: u8,
        dy: &mut [f64; DIM],
    ) -> Forces {
        loop {
            let f = self.dynamics(c, y, dy);
            let worst = (0..self.parts.n)
                .filter(|&j| movable & (1 << j) != 0 && c.mode[j] == Mode::Roll)
                .map(|j| (j, self.stick_margin(&f, j)))
                .min_by(|a, b| a.1.total_cmp(&b.1));
            match worst {
                Some((j, margin)) if margin < 0.0 => c.slide_against(j, &f),
                _ => return f,
            }
        }
    }

    /// The parts touching the floor at a state (gap within `tol` of zero) and not
    /// separating (gap rate at most `vtol`), as a bit mask.
    pub fn touching(&self, y: &[f64; DIM], tol: f64, vtol: f64) -> u8 {
        let k = self.kin(y);
        (0..self.parts.n).fold(0, |acc, i| {
            let p = self.part(i);
            let on = p.gap(k.zg, k.e3) <= tol && p.gap_rate(k.v[2], k.w, k.e3) <= vtol;
            acc | (u8::from(on) << i)
        })
    }

    /// Puts a state on the constraints of its touching parts: G's height and vertical
    /// velocity from the parts touching (their mean where several touch), and its whole
    /// velocity from the first sticking part. Normalises the quaternion.
    pub fn project(&self, c: &Contacts, y: &mut [f64; DIM]) {
        if c.flat {
            if let Some(i) = (0..self.parts.n).find(|&j| c.mode[j] != Mode::Flight) {
                self.flat_project(i, y, c.mode[i] == Mode::Roll);
                return;
            }
        }
        let nq = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3]).sqrt();
        for v in y.iter_mut().take(4) {
            *v /= nq;
        }
        self.fix_tilt(c, y);
        let on = (0..self.parts.n).filter(|&i| c.mode[i] != Mode::Flight);
        if on.clone().next().is_none() {
            return;
        }
        let stick = (0..self.parts.n).find(|&i| c.mode[i] == Mode::Roll);
        // The velocity's correction never creates energy: the kinetic energy it would add is
        // taken back by scaling the velocities (the constraints are homogeneous in them); the
        // kinetic energy it removes is counted as dissipated.
        let before = self.kinetic_energy(y);
        let mut k = self.kin(y);
        if stick.is_some_and(|i| c.drilling & (1 << i) == 0)
            && self.friction.rbar() > 0.0
            && k.w[2] != 0.0
        {
            // Sticking over a patch neither slides nor drills (D = 0): the drilling rate left
            // at the switch (below the tolerance over rbar) and its drift are removed.
            let wb = k.to_body([k.w[0], k.w[1], 0.0]);
            y[4..7].copy_from_slice(&wb);
            k = self.kin(y);
        }
        let (mut h, mut vz, mut count) = (0.0, 0.0, 0.0);
        for i in on {
            let p = self.part(i);
            h -= p.arm(k.e3)[2];
            vz -= p.gap_rate(0.0, k.w, k.e3);
            count += 1.0;
        }
        y[9] = h / count;
        y[12] = vz / count;
        if let Some(i) = stick.filter(|&i| !self.two_sticking(c, i, &k, y)) {
            let v = scale(-1.0, cross(k.w, self.part(i).arm(k.e3)));
            y[10] = v[0];
            y[11] = v[1];
        }
        let excess = self.kinetic_energy(y) - before;
        if stick.is_none() && excess > 0.0 {
            // Sliding parts leave G's horizontal velocity free: the excess is taken from the
            // rotation and the vertical velocity it fixes (both scaled alike, the sliding
            // constraints being linear in the rotation), so a frictionless top keeps its
            // horizontal momentum exactly.
            let free = 0.5 * self.m * (y[10] * y[10] + y[11] * y[11]);
            let rest = self.kinetic_energy(y) - free;
            if rest > excess {
                let f = ((rest - excess) / rest).sqrt();
                for i in [4, 5, 6, 12] {
                    y[i] *= f;
                }
                return;
            }
        }
        self.shed_energy(y, excess);
    }

    /// Two parts sticking, and no other touching: the top can only turn about the line
    /// through their contact points (a rigid body whose two points are at rest), so the
    /// velocities of `k` are put on that one freedom, `w = a d`, `v_G = -w x arm_i` with `d`
    /// the unit vector from contact `i` to the other. `a` is the projection in the kinetic
    /// energy's metric, `a = b.M u / b.M b` with `b = (-d x arm_i, d)`: it never adds kinetic
    /// energy (what it removes, the drift of the integration, [`Self::project`] counts as
    /// dissipated). Without it the second contact's slip, held at zero only through its
    /// acceleration, drifted: a top rolling on a ring and a sphere under a drilling
    /// resistance turned ever faster about the vertical (4e-5 rad/s after 5 s) and
    /// E + dissipated rose 7.5e-9 (rtol 1e-10) and 9e-6 (rtol 1e-8) of E. Returns whether it
    /// applied (else `y` is untouched).
    pub(crate) fn two_sticking(&self, c: &Contacts, i: usize, k: &Kin, y: &mut [f64; DIM]) -> bool {
        let mut on = (0..self.parts.n).filter(|&j| c.mode[j] != Mode::Flight);
        let (Some(a), Some(b), None) = (on.next(), on.next(), on.next()) else {
            return false;
        };
        if c.mode[a] != Mode::Roll || c.mode[b] != Mode::Roll || c.drilling != 0 {
            return false;
        }
        let j = if a == i { b } else { a };
        let arm_i = self.part(i).arm(k.e3);
        let d = add(self.part(j).arm(k.e3), scale(-1.0, arm_i));
        let len = dot(d, d).sqrt();
        if len <= 1e-9 * self.reach() || len.is_nan() {
            return false;
        }
        let d = scale(1.0 / len, d);
        let vb = cross(arm_i, d);
        // The rotational parts in the body frame, where the inertia is diagonal.
        let db = k.to_body(d);
        let num = self.m * dot(vb, k.v) + dot(db, self.momentum(k.wb));
        let den = self.m * dot(vb, vb) + dot(db, self.momentum(db));
        let alpha = num / den;
        y[4..7].copy_from_slice(&scale(alpha, db));
        y[10..13].copy_from_slice(&scale(alpha, vb));
        true
    }

    /// Two parts touching at once fix the tilt: their gaps `z_G + z u - phi(u)` are both zero,
    /// so `(z_i - z_j) u - phi_i(u) + phi_j(u) = 0` (for two spheres
    /// `u = (r_i - r_j) / (z_i - z_j)`), solved by Newton's method from the current tilt.
    /// Puts the orientation on that tilt (a rotation about the horizontal axis `ez x e3`) and
    /// removes the tilting rate (the angular velocity's component along that axis); the
    /// kinetic energy that removal takes, of the order of the integration's error, is added
    /// to the dissipated energy.
    fn fix_tilt(&self, c: &Contacts, y: &mut [f64; DIM]) {
        let mut on = (0..self.parts.n).filter(|&i| c.mode[i] != Mode::Flight);
        let (Some(i), Some(j)) = (on.next(), on.next()) else {
            return;
        };
        let w0 = self.kin(y).w;
        let Some(n) = self.tilt_both(i, j, y) else {
            return;
        };
        let before = self.kinetic_energy(y);
        let w = add(w0, scale(-dot(w0, n), n));
        let wb = self.kin(y).to_body(w);
        y[4..7].copy_from_slice(&wb);
        y[13] += (before - self.kinetic_energy(y)).max(0.0);
    }

    /// Turns the orientation of `y` (its body-frame angular velocity kept) about the
    /// horizontal axis `ez x e3` onto the tilt at which parts `i` and `j` are level, both at
    /// the height of the lowest point of one (see [`Self::fix_tilt`]); returns that axis, or
    /// None (`y` untouched) where the tilt is not fixed by the two (parts level at every
    /// tilt, an upright top, no root in (-1, 1)).
    pub(crate) fn tilt_both(&self, i: usize, j: usize, y: &mut [f64; DIM]) -> Option<[f64; 3]> {
        let (pi, pj) = (self.part(i), self.part(j));
        let k = self.kin(y);
        let mut u = k.e3[2].clamp(-1.0, 1.0);
        for _ in 0..8 {
            let ((fi, di, _), (fj, dj, _)) = (pi.profile(u), pj.profile(u));
            let slope = pi.z() - pj.z() - di + dj;
            if slope.abs() <= 1e-12 * self.reach() {
                return None;
            }
            let step = ((pi.z() - pj.z()) * u - fi + fj) / slope;
            u -= step;
            if u.is_nan() || u.abs() >= 1.0 {
                return None;
            }
            if step.abs() <= 1e-15 {
                break;
            }
        }
        let axis = cross(EZ, k.e3);
        let s = dot(axis, axis).sqrt();
        if s <= 1e-12 {
            return None;
        }
        let n = scale(1.0 / s, axis);
        let delta = u.acos() - k.e3[2].clamp(-1.0, 1.0).acos();
        let q = Quat::from_axis_angle(n, delta).hamilton(k.q).normalized();
        y[..4].copy_from_slice(&q.0);
        Some(n)
    }
}
