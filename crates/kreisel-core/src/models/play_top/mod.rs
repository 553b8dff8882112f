//! Tops on a floor: a symmetric top whose contact geometry is a set of convex parts of
//! revolution (a tip sphere, spheroids, rings), on a horizontal plane, with friction
//! (theory: play top; theory: several parts; theory: bodies of revolution).
//!
//! Conventions: moments `A` (equatorial) and `C` (axial) about the centre of mass G, figure
//! axis `e3` (body 3-axis), `u = e3 . ez` (u = 1 upright). A classic play top is one tip
//! sphere of radius `rho` whose centre lies `s` below G on the figure axis.
//!
//! The state is `y = (q, omega, r, v, w)`: orientation, body angular velocity, position and
//! velocity of G (space frame), and the energy dissipated so far. Each part is in flight,
//! sliding or sticking; Newton-Euler about G with the contact forces solved jointly from the
//! touching parts' constraints.
//!
//! One engine, its files named by what they hold:
//! - this file: the top's parameters, its states, energies and Jellett's integral, and the
//!   contact thresholds scaled from its size;
//! - [`parts`]: the contact parts' geometry and the kinematics of their lowest points;
//! - [`friction`]: the friction laws and resistance torques, and the cone (ellipse) test;
//! - [`solve`]: the contact forces and the equations of motion (the fast kernels of one part
//!   sliding or sticking, and the joint system of several);
//! - [`impact`]: impacts (touchdowns, tangential impacts of jams, a ring landing flat);
//! - [`modes`]: which parts touch and how (complementarity, sticking, lying flat), and the
//!   projection onto the contact constraints;
//! - [`driver`]: the contact switches, their events and the hybrid run;
//! - [`simulate`]: the model behind `simulate::simulate`, its columns and summary.

pub mod driver;
pub mod friction;
pub mod impact;
pub mod modes;
pub mod parts;
#[cfg(test)]
mod reference;
pub mod sensitivity;
pub mod simulate;
pub mod solve;

pub use friction::Friction;
pub use modes::Contacts;
pub use parts::{Parts, Shape, MAX_PARTS};
pub use solve::{Forces, Kin};

use crate::error::{
    finite, non_negative, positive, rate, repr, KreiselError, Result, PARAMETER_RANGE, RATE_MAX,
};
use crate::rotation::{dot, Quat};

/// Length of the play-top state vector.
pub const DIM: usize = 14;

/// Contact mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Sliding contact.
    Slip,
    /// Rolling contact (no slip).
    Roll,
    /// Free flight.
    Flight,
}

impl Mode {
    /// Every mode, by code.
    pub const ALL: [Mode; 3] = [Mode::Slip, Mode::Roll, Mode::Flight];

    /// The public name.
    pub const fn name(&self) -> &'static str {
        match self {
            Mode::Slip => "slip",
            Mode::Roll => "roll",
            Mode::Flight => "flight",
        }
    }
    /// Small integer code (0 slip, 1 roll, 2 flight).
    pub const fn code(&self) -> u8 {
        match self {
            Mode::Slip => 0,
            Mode::Roll => 1,
            Mode::Flight => 2,
        }
    }

    /// The mode of a [`Mode::code`]; any other code is flight.
    #[inline(always)]
    pub const fn from_code(code: u8) -> Mode {
        match code {
            0 => Mode::Slip,
            1 => Mode::Roll,
            _ => Mode::Flight,
        }
    }
}

/// Parameters of a play top.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlayTop {
    /// Mass (kg).
    pub m: f64,
    /// Equatorial moment about G (kg m^2).
    pub a: f64,
    /// Axial moment about G (kg m^2).
    pub c: f64,
    /// Distance from the sphere centre to G along e3 (m).
    pub s: f64,
    /// Radius of the spherical tip (m).
    pub rho: f64,
    /// Gravitational acceleration (m/s^2).
    pub g: f64,
    /// Tangential force law.
    pub friction: Friction,
    /// Coefficient of restitution of impacts, in [0, 1].
    pub restitution: f64,
    /// Rolling resistance: a torque -rolling N omega_h/|omega_h| (m).
    pub rolling: f64,
    /// Drilling resistance: a torque -drilling N sign(omega_z) ez (m).
    pub drilling: f64,
    /// Air resistance: a torque -air omega (N m s).
    pub air: f64,
    /// The contact parts (the tip sphere `Sphere { radius: rho, z: -s }` for a top built by
    /// [`PlayTop::new`]).
    pub parts: Parts,
    /// The stick threshold (dimensionless, [`PlayTop::STICK`] unless set with
    /// [`PlayTop::with_stick_threshold`]): a sliding part sticks where its sliding measure
    /// falls to this share of the top's speed scale ([`PlayTop::stick_speed`]). A setting of
    /// the contact model, not of the integration: `rtol` changes only the integration error.
    pub stick: f64,
}

/// `r v`: a body-frame vector in space (`r` the row-major rotation body -> space).
#[inline(always)]
pub(crate) fn to_space(r: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [dot(r[0], v), dot(r[1], v), dot(r[2], v)]
}

/// `r^T v`: a space-frame vector in the body frame.
#[inline(always)]
pub(crate) fn to_body(r: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [
        dot([r[0][0], r[1][0], r[2][0]], v),
        dot([r[0][1], r[1][1], r[2][1]], v),
        dot([r[0][2], r[1][2], r[2][2]], v),
    ]
}

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn scale(k: f64, a: [f64; 3]) -> [f64; 3] {
    [k * a[0], k * a[1], k * a[2]]
}

/// Solves a 3x3 linear system by Cramer's rule (the matrices here are well conditioned:
/// the contact's inverse effective mass).
pub(crate) fn solve3(m: [[f64; 3]; 3], b: [f64; 3]) -> [f64; 3] {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(m);
    let mut x = [0.0; 3];
    for (j, xj) in x.iter_mut().enumerate() {
        let mut mj = m;
        for i in 0..3 {
            mj[i][j] = b[i];
        }
        *xj = det(mj) / d;
    }
    x
}

impl PlayTop {
    /// Validates and builds a play top.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        m: f64,
        a: f64,
        c: f64,
        s: f64,
        rho: f64,
        g: f64,
        friction: Friction,
        restitution: f64,
        rolling: f64,
        drilling: f64,
        air: f64,
    ) -> Result<Self> {
        positive("m", m)?;
        positive("A", a)?;
        positive("C", c)?;
        non_negative("s", s)?;
        positive("rho", rho)?;
        non_negative("g", g)?;
        if c > 2.0 * a * (1.0 + 1e-12) {
            return Err(KreiselError::invalid(
                "C",
                c,
                format!("no rigid body has C > 2*A = {} (0 < C/A < 2)", 2.0 * a),
            ));
        }
        friction.checked()?;
        finite("restitution", restitution)?;
        if !(0.0..=1.0).contains(&restitution) {
            return Err(KreiselError::invalid(
                "restitution",
                restitution,
                "it must lie in [0, 1]",
            ));
        }
        non_negative("rolling_resistance", rolling)?;
        non_negative("drilling_resistance", drilling)?;
        non_negative("air_drag", air)?;
        Ok(PlayTop {
            m,
            a,
            c,
            s,
            rho,
            g,
            friction,
            restitution,
            rolling,
            drilling,
            air,
            parts: Parts::one(Shape::Sphere { radius: rho, z: -s }),
            stick: Self::STICK,
        })
    }

    /// The default stick threshold: 1e-9 of the speed scale (the resolution of the default
    /// rtol, 1e-10: runs at it and looser are unchanged; at tighter tolerances the model
    /// stays the same instead of following rtol down).
    pub const STICK: f64 = 1e-9;

    /// This top with the stick threshold `stick` ([`PlayTop::stick_speed`]): a share of the
    /// speed scale in `(0, 1e-3]`.
    pub fn with_stick_threshold(mut self, stick: f64) -> Result<Self> {
        if !(stick > 0.0 && stick <= 1e-3) {
            return Err(KreiselError::InvalidParameter {
                name: "stick_threshold".into(),
                value: format!("{stick:?}"),
                allowed: "a share of the top's speed scale in (0, 1e-3]: a part sticks where its \
                          sliding measure falls to it"
                    .into(),
            });
        }
        self.stick = stick;
        Ok(self)
    }

    /// The stick speed at `y` (m/s): a sliding part sticks where its sliding measure
    /// ([`PlayTop::slide_measure`]) falls to it, and a part that starts or lands with a
    /// sliding measure below it starts sticking where its law lets it. The stick threshold
    /// times the speed scale ([`PlayTop::speed_scale`], `l |omega| + |v| + sqrt(g l)`): the
    /// model's own threshold, scaled from the top's reach and its motion. A run whose
    /// integration cannot resolve it (rtol above a tenth of the threshold) uses the slip it
    /// resolves instead, `10 rtol` of the speed scale.
    pub fn stick_speed(&self, y: &[f64; DIM]) -> f64 {
        self.stick * self.speed_scale(y)
    }

    /// A play top whose contact geometry is the union of `parts` (each checked, named
    /// `shape[i]` in errors). `s` and `rho` are the first part's when it is a sphere below G
    /// (what the atlas uses), else 0. A top of one sphere of positive radius whose centre
    /// is not above G is the same value [`PlayTop::new`] builds.
    #[allow(clippy::too_many_arguments)]
    pub fn with_parts(
        m: f64,
        a: f64,
        c: f64,
        parts: &[Shape],
        g: f64,
        friction: Friction,
        restitution: f64,
        rolling: f64,
        drilling: f64,
        air: f64,
    ) -> Result<Self> {
        let parts = Parts::new(parts)?;
        let (s, rho) = match parts.shape[0] {
            Shape::Sphere { radius, z } if radius > 0.0 && z <= 0.0 => (-z, radius),
            _ => (0.0, 0.0),
        };
        let rho_ok = if rho > 0.0 { rho } else { 1.0 };
        let mut top = PlayTop::new(
            m,
            a,
            c,
            s,
            rho_ok,
            g,
            friction,
            restitution,
            rolling,
            drilling,
            air,
        )?;
        top.rho = rho;
        top.parts = parts;
        Ok(top)
    }

    /// How far below the floor a part's touchdown is located (m): 1e-12 of the top's reach
    /// (the gap's rounding is about 1e-16 of it). A part that leaves the floor starts its
    /// flight at a gap of zero up to rounding; its touchdown event watches
    /// `gap + touchdown_offset`, which then starts positive, so the sign change of its return
    /// is seen however short the flight (an event function that starts at zero or below
    /// never changes sign downward, and the part would fall through the floor unseen). The
    /// impact puts the located state back on the floor.
    pub fn touchdown_offset(&self) -> f64 {
        1e-12 * self.parts.reach()
    }

    /// The bounce cut-off (m): a part that an impact sends up by less than this (its rise
    /// `vn^2 / 2a` under the gap's free deceleration `a`) stays on the floor (the impact is
    /// taken again without restitution). 1e-10 of the top's reach, a hundred times the
    /// [`PlayTop::touchdown_offset`]: every impact is located that far below the floor and
    /// lifted onto it, so without a cut-off a bouncing part's rise would settle at
    /// `e^2 / (1 - e^2)` offsets instead of shrinking to zero (a Zeno sequence of ever shorter
    /// flights, then chattering for ever). With it, bounces that shrink geometrically end
    /// in finite time, after about `ln(h0 / cut-off) / ln(1 / e^2)` of them, in persistent
    /// contact.
    pub fn bounce_height(&self) -> f64 {
        100.0 * self.touchdown_offset()
    }

    /// Whether part `i`, whose material point leaves the floor at the normal speed `vn` after
    /// an impact at state `y`, bounces: None where it stays (the bounce is below
    /// [`PlayTop::bounce_height`]); else its expected flight time (infinite where the motion
    /// itself lifts it off). Its gap's deceleration is taken beside the other parts'
    /// contacts `c` (part `i` off the floor): in free flight, a part that bounces while
    /// another rolls can seem to lift off of itself, while the contact beside it brings it
    /// back at once. A frictionless top lying on its side on two rings bounced so on one of
    /// them every 2.2e-7 s without end (its rise settled at the touchdown offsets, never
    /// below the cut-off), until the run was refused for chattering (the floor campaign's
    /// case 1120 of seed 3).
    pub fn bounce(&self, i: usize, y: &[f64; DIM], vn: f64, c: &Contacts) -> Option<f64> {
        if vn <= 0.0 {
            return None;
        }
        let a = -self.gap_acceleration_beside(i, y, c);
        if a <= 0.0 {
            return Some(f64::INFINITY);
        }
        (vn * vn / (2.0 * a) > self.bounce_height()).then(|| 2.0 * vn / a)
    }

    /// alpha = s / rho.
    pub fn alpha(&self) -> f64 {
        self.s / self.rho
    }
    /// gamma = A / C.
    pub fn gamma(&self) -> f64 {
        self.a / self.c
    }
    /// J_beta = rho sqrt(C m g s).
    pub fn j_beta(&self) -> f64 {
        self.rho * (self.c * self.m * self.g * self.s).sqrt()
    }

    /// Whether any resistance torque (rolling, drilling, air) acts.
    pub fn has_resistance(&self) -> bool {
        self.rolling > 0.0 || self.drilling > 0.0 || self.air > 0.0
    }

    /// Body angular momentum about G.
    #[inline(always)]
    pub fn momentum(&self, w: [f64; 3]) -> [f64; 3] {
        [self.a * w[0], self.a * w[1], self.c * w[2]]
    }

    /// Takes `excess` (J) of energy that a projection or switch made out of nothing back from
    /// the kinetic energy, by scaling the velocities (every contact constraint is homogeneous
    /// in them, so the contact modes hold); a negative `excess`, energy the change took
    /// without counting it, is counted as dissipated.
    pub(crate) fn shed_energy(&self, y: &mut [f64; DIM], excess: f64) {
        let ke = self.kinetic_energy(y);
        if excess > 0.0 {
            if ke > 0.0 {
                Self::scale_kinetic(y, ke, (ke - excess).max(0.0));
            }
        } else {
            y[13] -= excess;
        }
    }

    /// Scales the velocities of `y`, whose kinetic energy is `ke > 0`, so that it becomes `to`
    /// (J, at least 0): every contact constraint is homogeneous in them, so the modes hold.
    fn scale_kinetic(y: &mut [f64; DIM], ke: f64, to: f64) {
        let f = (to / ke).sqrt();
        for i in (4..7).chain(10..13) {
            y[i] *= f;
        }
    }

    /// Whether nothing dissipates along a phase of `c`: no resistance, and every part in
    /// flight or sticking (no patch drilling, none creeping, no ring lying flat). The contact
    /// forces then do no work, and E + dissipated is a first integral of the phase's
    /// equations ([`driver::Keep`]).
    pub fn conserves(&self, c: &Contacts) -> bool {
        !self.has_resistance()
            && !c.flat
            && c.drilling == 0
            && c.creeping == 0
            && c.mode[..self.parts.n]
                .iter()
                .all(|&m| matches!(m, Mode::Flight | Mode::Roll))
    }

    /// Moves the energy by `change` (J) where `|change| <= band`, by scaling the velocities
    /// ([`Self::scale_kinetic`]). A larger change, or one the kinetic energy cannot give, is
    /// not made ([`driver::Keep`]).
    pub(crate) fn keep_ledger(&self, y: &mut [f64; DIM], change: f64, band: f64) {
        let ke = self.kinetic_energy(y);
        if change != 0.0 && change.abs() <= band && ke + change > 0.0 {
            Self::scale_kinetic(y, ke, ke + change);
        }
    }

    /// Kinetic energy, translation + rotation (J).
    pub fn kinetic_energy(&self, y: &[f64; DIM]) -> f64 {
        let (tr, rot, _) = self.energy_parts(y);
        tr + rot
    }

    /// Total energy: translation + rotation + potential (J).
    pub fn energy_parts(&self, y: &[f64; DIM]) -> (f64, f64, f64) {
        let w = [y[4], y[5], y[6]];
        let v = [y[10], y[11], y[12]];
        let iw = self.momentum(w);
        (
            0.5 * self.m * dot(v, v),
            0.5 * dot(w, iw),
            self.m * self.g * y[9],
        )
    }

    /// Jellett's integral about the first part's lowest point, `-L . arm` (kg m^2/s): for a
    /// tip sphere below G, `L . (s e3 + rho ez)` (theory: play top).
    pub fn jellett(&self, y: &[f64; DIM]) -> f64 {
        let k = self.kin(y);
        let l = k.to_space(self.momentum(k.wb));
        -dot(l, self.part(0).arm(k.e3))
    }

    /// A length scale of the top: its parts' largest reach.
    pub fn reach(&self) -> f64 {
        self.parts.reach()
    }

    /// A speed scale of the motion: reach |omega| + |v| + sqrt(g reach).
    pub fn speed_scale(&self, y: &[f64; DIM]) -> f64 {
        let k = self.kin(y);
        let l = self.reach();
        l * dot(k.w, k.w).sqrt() + dot(k.v, k.v).sqrt() + (self.g * l).sqrt()
    }
}

impl PlayTop {
    /// A state from orientation, body angular velocity and the horizontal velocity of G.
    /// In contact (`height` None) the lowest part touches the floor and G moves vertically
    /// with it (the gap's rate is zero); with `height` h >= 0 the lowest part is h above the
    /// floor and G has no vertical velocity (a dropped top).
    pub fn state(
        &self,
        q: Quat,
        omega: [f64; 3],
        vx: f64,
        vy: f64,
        height: Option<f64>,
    ) -> Result<[f64; DIM]> {
        for (name, v) in [("vx", vx), ("vy", vy)] {
            if !(v.is_finite() && v.abs() <= RATE_MAX) {
                return Err(KreiselError::invalid(
                    name,
                    v,
                    format!(
                        "it must be a finite speed of magnitude at most {} m/s",
                        repr(RATE_MAX)
                    ),
                ));
            }
        }
        for (i, &w) in omega.iter().enumerate() {
            rate(&format!("omega[{i}]"), w)?;
        }
        if !q.0.iter().all(|x| x.is_finite()) || q.0.iter().all(|&x| x == 0.0) {
            return Err(KreiselError::InvalidParameter {
                name: "q".into(),
                value: format!("{:?}", q.0),
                allowed: "a quaternion must be finite and non-zero (it is normalised)".into(),
            });
        }
        let q = q.normalized();
        let mut y = [0.0; DIM];
        y[..4].copy_from_slice(&q.0);
        y[4..7].copy_from_slice(&omega);
        y[10] = vx;
        y[11] = vy;
        // The lowest part touches (or is `height` above the floor).
        let k = self.kin(&y);
        y[9] = self.parts.resting_height(k.e3);
        if let Some(h) = height {
            self.check_height(h)?;
            y[9] += h;
        } else {
            let lowest = self
                .parts
                .iter()
                .min_by(|a, b| a.gap(y[9], k.e3).total_cmp(&b.gap(y[9], k.e3)));
            if let Some(p) = lowest {
                // (0 - rate: a state at rest moves at +0, not -0)
                y[12] = 0.0 - p.gap_rate(0.0, k.w, k.e3);
            }
        }
        Ok(y)
    }

    fn check_height(&self, h: f64) -> Result<()> {
        if !(h.is_finite() && (0.0..=PARAMETER_RANGE.1).contains(&h)) {
            return Err(KreiselError::invalid(
                "height",
                h,
                "the gap between the tip and the floor must lie in [0, 1e+100] m (a top \
                 cannot start below the floor)",
            ));
        }
        Ok(())
    }
}
