//! The play top: a symmetric top with a spherical tip on a horizontal plane, with friction.
//!
//! Conventions of theory: play top: sphere radius `rho`, distance `s` from the
//! sphere centre Z to the centre of mass G along the figure axis e3 (pointing from Z to G),
//! moments `A` (equatorial) and `C` (axial) about G, `u = e3 . ez` (u = 1 upright, G above Z;
//! u = -1 hanging). The contact point is `T = Z - rho ez`; `a = GT = -s e3 - rho ez`.
//!
//! The state is `y = (q, omega, r, v, w)`: orientation (body 3-axis = e3), body angular
//! velocity, position and velocity of G (space frame), and the energy dissipated so far.
//! Three modes: sliding contact (the normal force N from the contact constraint, the
//! friction law giving the tangential force), rolling contact (the whole contact force
//! from the rolling constraint, while it stays in the Coulomb cone), and free flight.
//! Newton-Euler about G: `m dv/dt = F - m g ez`, `dL/dt = a x F` (+ optional resistance
//! torques), `L = A omega + (C - A)(omega . e3) e3`.
//!
//! - this file: the parameters, the kinematics and the equations of motion in each mode;
//! - [`contact`]: the contact rules (modes, switches and their events, impacts);
//! - [`simulate`]: the driver behind `simulate::simulate` for play tops, its diagnostics
//!   columns and its summary.

pub mod contact;
pub mod hybrid;
pub mod multi;
pub mod shapes;
pub mod simulate;

pub use shapes::{Parts, Shape, MAX_PARTS};

use crate::error::{
    finite, non_negative, positive, rate, repr, KreiselError, Result, PARAMETER_RANGE, RATE_MAX,
};
use crate::rotation::{cross, dot, Quat};

/// Length of the play-top state vector.
pub const DIM: usize = 14;

/// The tangential force law at the contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Friction {
    /// Coulomb: |F_t| = mu N against the slip while slipping; rolling without slip while
    /// the needed force stays within the cone |F_t| <= mu N.
    Coulomb {
        /// Friction coefficient.
        mu: f64,
    },
    /// Viscous: F_t = -mu N v_T (mu in s/m).
    Viscous {
        /// Coefficient (s/m).
        mu: f64,
    },
    /// No tangential force.
    Frictionless,
    /// Coulomb-Contensou friction over a circular patch (theory: several parts, Leine & Glocker
    /// 2003): sliding and drilling share the elliptic reservoir
    /// `|F|^2 + (M / rbar)^2 <= (mu N)^2`, `rbar = 3 pi R / 16`. Built with `radius > 0` only
    /// ([`Friction::coulomb_contensou`] makes radius 0 plain Coulomb).
    CoulombContensou {
        /// Friction coefficient.
        mu: f64,
        /// Radius R of the contact patch (m).
        radius: f64,
    },
}

impl Friction {
    /// The law's code in [`law`].
    pub const fn law(&self) -> u8 {
        match self {
            Friction::Coulomb { .. } => law::COULOMB,
            Friction::Viscous { .. } => law::VISCOUS,
            Friction::Frictionless => law::FRICTIONLESS,
            Friction::CoulombContensou { .. } => law::CONTENSOU,
        }
    }

    /// Coulomb-Contensou friction, checked; a patch of radius 0 is plain Coulomb (the same
    /// value, so the same results bit for bit).
    pub fn coulomb_contensou(mu: f64, radius: f64) -> Result<Friction> {
        non_negative("mu", mu)?;
        non_negative("radius", radius)?;
        Ok(if radius == 0.0 {
            Friction::Coulomb { mu }
        } else {
            Friction::CoulombContensou { mu, radius }
        })
    }

    /// Whether the law can stick (Coulomb and Coulomb-Contensou).
    pub const fn can_stick(&self) -> bool {
        matches!(
            self,
            Friction::Coulomb { .. } | Friction::CoulombContensou { .. }
        )
    }

    /// The effective patch radius `rbar = 3 pi R / 16` of Coulomb-Contensou friction (0 for
    /// every other law).
    ///
    /// Not inlined: inlined, the branch became a select that multiplied the `radius` slot
    /// for every law, and under `Coulomb { mu }` that slot is the enum's uninitialised payload
    /// (whatever the stack held); a subnormal there cost a microcode assist on every
    /// right-hand side (T4 under point Coulomb friction: 0.78 s against 0.36 s for the same
    /// steps, 5.3 s against 2.35 s at rtol 1e-8; the same run with the FPU's DAZ/FTZ flags
    /// set took 0.35 s).
    #[inline(never)]
    pub fn rbar(&self) -> f64 {
        match *self {
            Friction::CoulombContensou { radius, .. } => 3.0 * std::f64::consts::PI * radius / 16.0,
            _ => 0.0,
        }
    }

    /// The law, its coefficient checked (mu >= 0, finite).
    pub fn checked(self) -> Result<Friction> {
        match self {
            Friction::Coulomb { mu } | Friction::Viscous { mu } => {
                non_negative("mu", mu)?;
            }
            Friction::Frictionless => {}
            Friction::CoulombContensou { mu, radius } => {
                return Friction::coulomb_contensou(mu, radius);
            }
        }
        Ok(self)
    }

    /// The law's public name.
    pub const fn name(&self) -> &'static str {
        match self {
            Friction::Coulomb { .. } => "coulomb",
            Friction::Viscous { .. } => "viscous",
            Friction::Frictionless => "none",
            Friction::CoulombContensou { .. } => "coulomb_contensou",
        }
    }

    /// The coefficient mu (0 without friction).
    pub const fn mu(&self) -> f64 {
        match *self {
            Friction::Coulomb { mu }
            | Friction::Viscous { mu }
            | Friction::CoulombContensou { mu, .. } => mu,
            Friction::Frictionless => 0.0,
        }
    }
}

/// Codes of the friction laws, for right-hand sides compiled for one law
/// ([`PlayTop::dynamics_with`]).
pub mod law {
    /// Whichever law the top has (looked up on every call).
    pub const ANY: u8 = 0;
    /// [`super::Friction::Coulomb`].
    pub const COULOMB: u8 = 1;
    /// [`super::Friction::Viscous`].
    pub const VISCOUS: u8 = 2;
    /// [`super::Friction::Frictionless`].
    pub const FRICTIONLESS: u8 = 3;
    /// [`super::Friction::CoulombContensou`].
    pub const CONTENSOU: u8 = 4;
}

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
}

/// Contact force and its parts at one state in one mode.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Contact {
    /// Normal force (N); 0 in flight.
    pub n: f64,
    /// Tangential force (space frame, N).
    pub ft: [f64; 3],
}

/// The ratios of the parameters that the right-hand side uses, computed once for a whole
/// integration rather than on every call ([`PlayTop::rhs_consts`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RhsConsts {
    inv_a: f64,
    inv_c: f64,
    inv_m: f64,
    /// (A - C) / A.
    euler: f64,
    /// The friction coefficient.
    mu: f64,
}

impl RhsConsts {
    /// `I^-1 x` (body frame).
    #[inline(always)]
    fn inv_inertia(&self, x: [f64; 3]) -> [f64; 3] {
        [x[0] * self.inv_a, x[1] * self.inv_a, x[2] * self.inv_c]
    }
}

/// Kinematic quantities of a state.
#[derive(Debug, Clone, Copy)]
pub struct Kin {
    /// Orientation as integrated (of unit norm only up to the local error inside a step).
    pub q: Quat,
    /// Rotation matrix body -> space of `q / |q|` (row-major).
    pub r: [[f64; 3]; 3],
    /// Body angular velocity.
    pub w: [f64; 3],
    /// Upward vertical in the body frame.
    pub gamma: [f64; 3],
    /// Its rate of change in the body frame, `gamma x omega`.
    pub gdot: [f64; 3],
    /// G to T in the body frame.
    pub a_b: [f64; 3],
    /// G to T in space.
    pub a_s: [f64; 3],
    /// Velocity of G.
    pub v: [f64; 3],
    /// Velocity of the material point at T (the slip velocity while in contact).
    pub v_t: [f64; 3],
    /// u = cos(theta).
    pub u: f64,
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

impl Kin {
    /// A body-frame vector in space.
    #[inline(always)]
    pub fn to_space(&self, v: [f64; 3]) -> [f64; 3] {
        to_space(&self.r, v)
    }

    /// A space-frame vector in the body frame.
    #[inline(always)]
    pub fn to_body(&self, v: [f64; 3]) -> [f64; 3] {
        to_body(&self.r, v)
    }
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
        })
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

    /// Whether the top runs on the one-sphere equations of this file (one spherical part of
    /// positive radius below G, and a friction law other than Coulomb-Contensou); every other
    /// top runs on the equations of several parts ([`multi`]).
    pub fn is_classic(&self) -> bool {
        self.parts.n == 1
            && self.rho > 0.0
            && !matches!(self.friction, Friction::CoulombContensou { .. })
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
    /// [`PlayTop::bounce_height`]); else its expected flight time (infinite where the free
    /// motion itself lifts it off).
    pub fn bounce(&self, i: usize, y: &[f64; DIM], vn: f64) -> Option<f64> {
        if vn <= 0.0 {
            return None;
        }
        let a = -self.free_gap_acceleration(i, y);
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

    #[inline(always)]
    fn inv_inertia(&self, x: [f64; 3]) -> [f64; 3] {
        self.rhs_consts().inv_inertia(x)
    }

    /// The ratios the right-hand side needs (see [`PlayTop::dynamics_with`]).
    #[inline(always)]
    pub fn rhs_consts(&self) -> RhsConsts {
        RhsConsts {
            inv_a: 1.0 / self.a,
            inv_c: 1.0 / self.c,
            inv_m: 1.0 / self.m,
            euler: (self.a - self.c) / self.a,
            mu: self.friction.mu(),
        }
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

    /// Kinematics of a state vector. The orientation is that of `q / |q|`: inside a step
    /// the integrated quaternion leaves the unit sphere by its local error, and a right-hand
    /// side that ignores the norm keeps that error out of the dynamics (with `|q|^2` in the
    /// rotations, it roughly doubles the number of steps a fast spin needs).
    #[inline(always)]
    pub fn kin(&self, y: &[f64; DIM]) -> Kin {
        let q = Quat([y[0], y[1], y[2], y[3]]);
        let r = q.unit_matrix();
        let w = [y[4], y[5], y[6]];
        let gamma = r[2];
        let a_b = [
            -self.rho * gamma[0],
            -self.rho * gamma[1],
            -self.s - self.rho * gamma[2],
        ];
        let a_s = [
            -self.s * r[0][2],
            -self.s * r[1][2],
            -self.s * r[2][2] - self.rho,
        ];
        let v = [y[10], y[11], y[12]];
        // omega x a = rho gdot - s omega x e3, with a = -rho gamma - s e3.
        let gdot = cross(gamma, w);
        let wa = [
            self.rho * gdot[0] - self.s * w[1],
            self.rho * gdot[1] + self.s * w[0],
            self.rho * gdot[2],
        ];
        let v_t = add(v, [dot(r[0], wa), dot(r[1], wa), dot(r[2], wa)]);
        Kin {
            q,
            r,
            w,
            gamma,
            gdot,
            a_b,
            a_s,
            v,
            v_t,
            u: gamma[2],
        }
    }

    /// Height of the lowest point of the sphere above the floor (m).
    #[inline(always)]
    pub fn height(&self, y: &[f64; DIM]) -> f64 {
        let q = Quat([y[0], y[1], y[2], y[3]]);
        y[9] - self.s * q.up_in_body()[2] - self.rho
    }

    /// Resistance torques (body frame): the part proportional to N (per unit N) and the
    /// part that is not.
    #[inline(always)]
    fn resistance(&self, k: &Kin) -> ([f64; 3], [f64; 3]) {
        self.resistance_at(k.w, k.gamma, self.rho)
    }

    /// [`Self::resistance`] from the body angular velocity `w` and the upward vertical
    /// `gamma` in the body frame; `len` sets the regularisation's rate scale.
    #[inline(always)]
    pub(crate) fn resistance_at(
        &self,
        w: [f64; 3],
        gamma: [f64; 3],
        len: f64,
    ) -> ([f64; 3], [f64; 3]) {
        let mut per_n = [0.0; 3];
        if self.rolling > 0.0 || self.drilling > 0.0 {
            // Vertical and horizontal parts of omega, in the body frame.
            let wz = dot(w, gamma);
            let wh = add(w, scale(-wz, gamma));
            let h = dot(wh, wh).sqrt();
            // The sharp law down to reg ~ 1e-6 sqrt(g / rho), linear in the rate below it, so
            // the torque vanishes continuously as the rolling stops (a sharper switch makes the
            // equations stiff). Not h + reg: that would weaken the torque by reg / h at every
            // rate, and a ball rolling to a stop would take ln(h0 / h_end) reg / (dh/dt) longer.
            let reg = 1e-6 * (self.g / len).sqrt().max(1e-3);
            per_n = add(
                scale(-self.rolling / h.max(reg), wh),
                scale(-self.drilling * wz / wz.abs().max(reg), gamma),
            );
        }
        (per_n, scale(-self.air, w))
    }

    /// The tangential force per unit N while slipping (space frame), by the friction law
    /// `LAW` (see [`PlayTop::dynamics_with`]).
    #[inline(always)]
    fn slip_force_per_n<const LAW: u8>(&self, p: &RhsConsts, k: &Kin, dir: [f64; 3]) -> [f64; 3] {
        let law = if LAW == law::ANY {
            self.friction.law()
        } else {
            LAW
        };
        let mu = p.mu;
        match law {
            law::VISCOUS => [-mu * k.v_t[0], -mu * k.v_t[1], 0.0],
            law::COULOMB => {
                let sp = (k.v_t[0] * k.v_t[0] + k.v_t[1] * k.v_t[1]).sqrt();
                if sp > 0.0 {
                    [-mu * k.v_t[0] / sp, -mu * k.v_t[1] / sp, 0.0]
                } else {
                    // At (numerically) zero slip the direction is the one the mode began
                    // with: the friction opposes the slip that is starting.
                    [-mu * dir[0], -mu * dir[1], 0.0]
                }
            }
            _ => [0.0; 3],
        }
    }

    /// Largest step in flight: a tenth of the time to fall through the tip's radius, and a
    /// quarter radian of rotation, so that the touchdown of a short hop is never stepped
    /// over (an event inside one step is located only if the sign differs at its ends).
    pub fn flight_step(&self, y: &[f64; DIM]) -> f64 {
        let w = (y[4] * y[4] + y[5] * y[5] + y[6] * y[6]).sqrt();
        let fall = if self.g > 0.0 {
            0.1 * (self.rho / self.g).sqrt()
        } else {
            f64::INFINITY
        };
        fall.min(0.25 / w.max(1e-300))
    }

    /// A speed scale of the motion: rho |omega| + |v| + sqrt(g rho).
    pub fn slip_scale(&self, k: &Kin) -> f64 {
        self.rho * dot(k.w, k.w).sqrt() + dot(k.v, k.v).sqrt() + (self.g * self.rho).sqrt()
    }

    /// Contact force and state derivative in a mode. `dir` is the slip direction used when
    /// the slip speed is zero (Coulomb friction only).
    #[inline(always)]
    pub fn dynamics(
        &self,
        mode: Mode,
        y: &[f64; DIM],
        dir: [f64; 3],
        dy: &mut [f64; DIM],
    ) -> Contact {
        self.dynamics_with::<true, { law::ANY }>(&self.rhs_consts(), mode, y, dir, dy)
    }

    /// [`PlayTop::dynamics`] with the ratios `p` of [`PlayTop::rhs_consts`] given, the
    /// resistance torques left out of the code when `RES` is false (for a top without them,
    /// [`PlayTop::has_resistance`] false) and the friction law `LAW` ([`law`]) compiled in
    /// (the top's own, or [`law::ANY`]). The result is the same as [`PlayTop::dynamics`]'s.
    #[inline(always)]
    pub fn dynamics_with<const RES: bool, const LAW: u8>(
        &self,
        p: &RhsConsts,
        mode: Mode,
        y: &[f64; DIM],
        dir: [f64; 3],
        dy: &mut [f64; DIM],
    ) -> Contact {
        debug_assert!(RES || !self.has_resistance());
        debug_assert!(LAW == law::ANY || LAW == self.friction.law());
        let k = self.kin(y);
        // I^-1 of the torque without the contact force: -omega x I omega, which for a
        // symmetric top (Euler's equations) is ((A - C) w2 w3, (C - A) w1 w3, 0), plus the
        // resistance torque that does not scale with N; `res_n` is the part per unit N.
        // (Its axial part -0.0: adding it is the identity, which the compiler drops.)
        let euler = [p.euler * k.w[1] * k.w[2], -p.euler * k.w[0] * k.w[2], -0.0];
        let (res_n, res_0) = if RES {
            self.resistance(&k)
        } else {
            ([0.0; 3], [0.0; 3])
        };
        let b0 = if RES {
            add(p.inv_inertia(res_0), euler)
        } else {
            euler
        };
        // The torque about G of a contact force f (body frame), with the resistance torque
        // per unit N of its normal part `fn_`.
        let contact_torque = |f: [f64; 3], fn_: f64| {
            let t = cross(k.a_b, f);
            if RES {
                add(t, scale(fn_, res_n))
            } else {
                t
            }
        };
        let (contact, wdot, vdot) = match mode {
            Mode::Flight => (Contact::default(), b0, [0.0, 0.0, -self.g]),
            Mode::Slip => {
                // F = N f with f = ez + (tangential force per unit N); N from the constraint
                // that T stays on the floor: N/m - g - s d2u/dt2 = 0, affine in N.
                let f_t = self.slip_force_per_n::<LAW>(p, &k, dir);
                let f_s = [f_t[0], f_t[1], 1.0];
                let f_b = k.to_body(f_s);
                let t1 = contact_torque(f_b, 1.0);
                let b1 = p.inv_inertia(t1);
                let k0 = cross(k.gdot, k.w)[2] + cross(k.gamma, b0)[2];
                let k1 = cross(k.gamma, b1)[2];
                let n = (self.g + self.s * k0) / (p.inv_m - self.s * k1);
                let wdot = add(b0, scale(n, b1));
                let n_m = n * p.inv_m;
                let vdot = [n_m * f_s[0], n_m * f_s[1], n_m * f_s[2] - self.g];
                (
                    Contact {
                        n,
                        ft: [n * (f_s[0]), n * (f_s[1]), 0.0],
                    },
                    wdot,
                    vdot,
                )
            }
            Mode::Roll => {
                // The rolling constraint v_T = 0 differentiated (body frame):
                // F/m - g Gamma + wdot x a - s omega x (omega x e3) = 0, with
                // wdot = I^-1 (a x F + (F.Gamma) res_n) + b0: linear in F.
                let map = |f: [f64; 3]| {
                    let t = contact_torque(f, dot(f, k.gamma));
                    add(scale(p.inv_m, f), cross(p.inv_inertia(t), k.a_b))
                };
                let cols = [
                    map([1.0, 0.0, 0.0]),
                    map([0.0, 1.0, 0.0]),
                    map([0.0, 0.0, 1.0]),
                ];
                let mat = [
                    [cols[0][0], cols[1][0], cols[2][0]],
                    [cols[0][1], cols[1][1], cols[2][1]],
                    [cols[0][2], cols[1][2], cols[2][2]],
                ];
                let wxe3 = cross(k.w, [0.0, 0.0, 1.0]);
                let rhs = add(
                    add(scale(self.g, k.gamma), scale(-1.0, cross(b0, k.a_b))),
                    scale(self.s, cross(k.w, wxe3)),
                );
                let f_b = solve3(mat, rhs);
                let n = dot(f_b, k.gamma);
                let f_s = k.to_space(f_b);
                let t = contact_torque(f_b, n);
                let wdot = add(p.inv_inertia(t), b0);
                let vdot = [
                    p.inv_m * f_s[0],
                    p.inv_m * f_s[1],
                    p.inv_m * f_s[2] - self.g,
                ];
                (
                    Contact {
                        n,
                        ft: [f_s[0], f_s[1], 0.0],
                    },
                    wdot,
                    vdot,
                )
            }
        };
        dy[..4].copy_from_slice(&k.q.half_times_pure(k.w));
        dy[4..7].copy_from_slice(&wdot);
        dy[7..10].copy_from_slice(&k.v);
        dy[10..13].copy_from_slice(&vdot);
        // Dissipated power: minus the power of the tangential contact force at T and of the
        // resistance torques.
        let p_friction = if mode == Mode::Slip {
            // The friction force is horizontal.
            contact.ft[0] * k.v_t[0] + contact.ft[1] * k.v_t[1]
        } else {
            0.0
        };
        dy[13] = if RES && self.has_resistance() {
            -(p_friction + dot(add(scale(contact.n, res_n), res_0), k.w))
        } else {
            -p_friction
        };
        contact
    }

    /// Takes `excess` (J) of energy that a projection or switch made out of nothing back from
    /// the kinetic energy, by scaling the velocities (every contact constraint is homogeneous
    /// in them, so the contact modes hold); a negative `excess`, energy the change took
    /// without counting it, is counted as dissipated.
    pub(crate) fn shed_energy(&self, y: &mut [f64; DIM], excess: f64) {
        let ke = self.kinetic_energy(y);
        if excess > 0.0 {
            if ke > 0.0 {
                let f = ((ke - excess).max(0.0) / ke).sqrt();
                for i in (4..7).chain(10..13) {
                    y[i] *= f;
                }
            }
        } else {
            y[13] -= excess;
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

    /// Jellett's integral J = L . (s e3 + rho ez) (kg m^2/s).
    pub fn jellett(&self, y: &[f64; DIM]) -> f64 {
        let q = Quat([y[0], y[1], y[2], y[3]]);
        let l = self.momentum([y[4], y[5], y[6]]);
        self.s * l[2] + self.rho * dot(l, q.up_in_body())
    }
}

impl PlayTop {
    /// A state from orientation, body angular velocity and the horizontal velocity of G.
    /// In contact (`height` None) G is at `rho + s u` and moves vertically with the
    /// constraint; with `height` h >= 0 the sphere's lowest point is h above the floor and
    /// G has no vertical velocity (a dropped top).
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
        let u = q.up_in_body()[2];
        if !self.is_classic() {
            // Several parts: the lowest part touches (or is `height` above the floor).
            let k = self.mkin(&y);
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
                    y[12] = -p.gap_rate(0.0, k.w, k.e3);
                }
            }
            return Ok(y);
        }
        match height {
            None => {
                y[9] = self.rho + self.s * u;
                let g = q.up_in_body();
                y[12] = self.s * cross(g, omega)[2];
            }
            Some(h) => {
                self.check_height(h)?;
                y[9] = h + self.rho + self.s * u;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotation::quaternion_from_euler;

    /// The right-hand sides compiled for one friction law and without resistance torques
    /// (what the simulation integrates) are the general one's, in every mode.
    #[test]
    fn compiled_right_hand_sides_are_the_general_one() {
        let (m, rho, s) = (0.02, 0.02, 0.006);
        let c = 0.4 * m * rho * rho;
        let q = quaternion_from_euler(0.4, 2.1, -0.7);
        for friction in [
            Friction::Coulomb { mu: 0.3 },
            Friction::Viscous { mu: 1.0 },
            Friction::Frictionless,
        ] {
            let top =
                PlayTop::new(m, 0.8 * c, c, s, rho, 9.81, friction, 0.0, 0.0, 0.0, 0.0).unwrap();
            let y = top.state(q, [3.0, -2.0, 150.0], 0.05, -0.03, None).unwrap();
            let p = top.rhs_consts();
            let dir = [0.6, -0.8, 0.0];
            for mode in [Mode::Slip, Mode::Roll, Mode::Flight] {
                let (mut general, mut any, mut own) = ([0.0; DIM], [0.0; DIM], [0.0; DIM]);
                let c0 = top.dynamics(mode, &y, dir, &mut general);
                let c1 = top.dynamics_with::<false, { law::ANY }>(&p, mode, &y, dir, &mut any);
                let c2 = match friction.law() {
                    law::COULOMB => {
                        top.dynamics_with::<false, { law::COULOMB }>(&p, mode, &y, dir, &mut own)
                    }
                    law::VISCOUS => {
                        top.dynamics_with::<false, { law::VISCOUS }>(&p, mode, &y, dir, &mut own)
                    }
                    _ => top
                        .dynamics_with::<false, { law::FRICTIONLESS }>(&p, mode, &y, dir, &mut own),
                };
                assert_eq!(general, any, "{friction:?} {mode:?}");
                assert_eq!(general, own, "{friction:?} {mode:?}");
                assert_eq!((c0.n, c0.ft), (c1.n, c1.ft));
                assert_eq!((c0.n, c0.ft), (c2.n, c2.ft));
                // the state moves: a slip, a spin, a normal force
                assert!(general.iter().all(|v| v.is_finite()));
                if mode != Mode::Flight {
                    assert!(c0.n.abs() > 0.0);
                }
            }
        }
    }
}
