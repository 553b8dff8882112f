//! Forward sensitivities of a top on a floor: the derivatives of a run with respect to the
//! top's parameters and the fields of its initial state, integrated with the run by DOP853,
//! phase by phase, and carried across the contact switches by their saltation (theory:
//! sensitivities).
//!
//! Within a phase the contact set and each part's mode are fixed and the right-hand side
//! `f(y, p)` is smooth; the sensitivity `S = dy/dp` obeys the variational equation
//! `S' = (df/dy) S + df/dp` (Hairer, Norsett & Wanner, *Solving Ordinary Differential
//! Equations I*, Sec. I.14). The contact forces come out of the phase's kernels (solved
//! jointly for several parts), so `(df/dy) S` and `df/dp` are taken here as directional
//! derivatives of the phase's own right-hand side by central differences, the internal
//! numerical differentiation of Bock (1981): the difference is taken along the direction
//! `S` itself, so each costs two evaluations however many components the state has. The step
//! is `eps = H / |S|_w`, `H = 6e-6` (about the cube root of the rounding unit), with
//! `|S|_w` the largest component of `S` measured in the phase's scales (1 rad for the
//! orientation, `|omega| + sqrt(g / l)` for the rates, the reach `l` for positions, the speed
//! scale for velocities, the energy for the dissipated energy): the truncation error is
//! `H^2 / 6` of the third derivative along the unit direction and the rounding
//! `1e-16 / H` of the value, both about 1e-10 of the derivative's scale (measured against
//! analytic derivatives: 1e-9 to 1e-11 relative, see the tests). A parameter's own term is
//! the central difference of the right-hand sides of the tops with the parameter moved by
//! `H |p|` (`H` times a scale of its unit where it is zero).
//!
//! The orientation is perturbed on the rotation group through the exponential map in the
//! body frame, `q -> q exp(xi / 2)`, as the heavy top's ([`crate::models::heavy_top`]): its
//! sensitivity `xi` has three components, and its rate is the exact kinematics
//! `xi' = xi x omega + d_omega`. A sensitivity has 13 components, in the tangent coordinates
//! `(xi, d_omega, d_r, d_v, d_dissipated)`; the position's rate is `d_v` exactly.
//!
//! At a contact switch (a state event `g(y, p) = 0` located at `t*`, after which the state
//! may jump, `y+ = D(y-)`, and the right-hand side changes from `f-` to `f+`), the
//! sensitivity jumps by the saltation (Aizerman & Gantmacher 1958; Hiskens & Pai, IEEE
//! Trans. Circuits Syst. I 47 (2000) 204):
//! `S+ = DD S- + dD/dp + (f+ - DD f-) (g_y S- + g_p) / (g_y f-)`,
//! with `DD`, `dD/dp`, `g_y` and `g_p` again central differences of the engine's own switch
//! (the switch's projection and impulse, and the event function) along `S-` and `f-`;
//! `D` is differenced along `S- - f- th` (`th` the factor above), which stays on the event's
//! surface, so that the switch's own thresholds decide as at the located state. Crossed:
//! touchdowns. Lift-off, slip-to-stick and stick-to-slip switches, a slide from rest under
//! Coulomb friction, tangential impacts and lying flat end the run with an error naming the
//! event and its time: under Coulomb's law the slip direction's derivative grows as
//! 1/|slip| as a slip runs out or starts, a stiff mode of the variational equation that the
//! motion's steps do not see (measured across a slip-to-stick switch: errors of 1e-4 to
//! 0.4 of the sensitivity, against 1e-9 before it), so the saltation written here is not
//! taken there.
//!
//! The trajectory is the one a plain run takes, bit for bit: the sensitivities ride on its
//! steps, out of the step-size control, and the switches are those of the engine's
//! [`super::driver`] (its rules, each phase's kernel, its event functions). One exception: a
//! plain run continues a sliding phase whose explicit steps turn out to be held by stability
//! by Radau IIA (the driver's `Rules::integrate`); here the phase stays with DOP853, so
//! such a phase (a stiff viscous slide; Coulomb slides end the run anyway) agrees with the
//! plain run to the tolerance, not bit for bit.

// tangents are written component by component (their blocks mean different things)
#![allow(clippy::needless_range_loop)]

use super::driver::{ledger, no_energy_from_a_switch, Keep, Phase, Rules, Switch};
use super::simulate::PlayRow;
use super::solve::{Consts, Kernel};
use super::{Friction, PlayTop, Shape, DIM};
use crate::error::{KreiselError, Result};
use crate::integrate::{Dop853, EventSpec, Locator, OdeSystem, Stream, WithEvents};
use crate::rotation::{
    cross, dot, euler_from_quaternion, omega_body_from_euler, quaternion_from_euler, Quat,
};
use crate::simulate::{
    self, integrate_error, EventRecord, RunInfo, Settings, Status, MAX_ROWS, MAX_STEPS,
};
use std::cell::Cell;

/// A phase's event function on the state with its sensitivities.
type EventFnBox<'a, const N: usize> = Box<dyn FnMut(f64, &[f64; N]) -> f64 + 'a>;

/// Components of a sensitivity: `(xi, d_omega, d_r, d_v, d_dissipated)`.
pub const TAN: usize = 13;

/// The relative step of the internal differences (about the cube root of the rounding unit).
pub const STEP: f64 = 6e-6;

/// The parameters of a play top that have sensitivities, by their public names: mass,
/// moments, gravity, the friction law's coefficient `mu` (Coulomb, viscous or
/// Coulomb-Contensou) and the Coulomb-Contensou patch `radius`, the tip sphere's `s` and
/// `rho` (a top of one sphere), the restitution and the resistance torques' coefficients.
pub const PLAY_PARAMETERS: [&str; 12] = [
    "m",
    "A",
    "C",
    "g",
    "mu",
    "radius",
    "s",
    "rho",
    "restitution",
    "rolling_resistance",
    "drilling_resistance",
    "air_drag",
];

/// The fields of the initial state that have sensitivities. The state is the one
/// `PlayTop.state(theta, phi, psi, theta_dot, phi_dot, psi_dot, vx, vy, height)` builds: a
/// field is moved and the state built again, so that a top in contact stays in contact (the
/// height of G and its vertical velocity follow the orientation and the rates); "x" and "y"
/// move G horizontally; "orientation[i]" (body-frame rotation vector) and "omega[i]" (body
/// rates) are the same state's other coordinates, regular where the Euler angles are not
/// (theta = 0). "height" is the lowest part's gap of a dropped top (not of a top that starts
/// in contact).
pub const PLAY_FIELDS: [&str; 17] = [
    "theta",
    "phi",
    "psi",
    "theta_dot",
    "phi_dot",
    "psi_dot",
    "vx",
    "vy",
    "x",
    "y",
    "height",
    "orientation[0]",
    "orientation[1]",
    "orientation[2]",
    "omega[0]",
    "omega[1]",
    "omega[2]",
];

/// The most sensitivities a run carries (every parameter and every field once).
pub const MAX_PLAY_SENSITIVITIES: usize = PLAY_PARAMETERS.len() + PLAY_FIELDS.len();

/// What a play top's sensitivity is taken with respect to: `Param(i)` the parameter
/// [`PLAY_PARAMETERS`]`[i]`, `Field(i)` the field [`PLAY_FIELDS`]`[i]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlayParam {
    /// A parameter, by its index in [`PLAY_PARAMETERS`].
    Param(usize),
    /// A field of the initial state, by its index in [`PLAY_FIELDS`].
    Field(usize),
}

/// The sensitivities a play-top run carries, by name.
#[derive(Debug, Clone, PartialEq)]
pub struct PlaySensitivities {
    /// The public names, in the caller's order.
    pub names: Vec<String>,
    /// What each name is.
    pub params: Vec<PlayParam>,
}

impl PlaySensitivities {
    /// The sensitivities of `names` for `top`: an unknown or repeated name, or a parameter
    /// the top does not have (`mu` without friction, `radius` without a Coulomb-Contensou
    /// law, `s` and `rho` of a top that is not one tip sphere), is an error naming it and the
    /// allowed ones.
    pub fn new(top: &PlayTop, names: &[String]) -> Result<Self> {
        let bad = |name: &str, allowed: String| KreiselError::InvalidParameter {
            name: "sensitivities".into(),
            value: format!("{name:?}"),
            allowed,
        };
        let mut params = Vec::with_capacity(names.len());
        for (i, name) in names.iter().enumerate() {
            if names[..i].contains(name) {
                return Err(bad(name, "each name at most once".into()));
            }
            let p = if let Some(j) = PLAY_PARAMETERS.iter().position(|p| p == name) {
                match (j, top.friction) {
                    (4, Friction::Frictionless) => {
                        return Err(bad(name, "a frictionless top has no coefficient mu".into()))
                    }
                    (5, f) if !matches!(f, Friction::CoulombContensou { .. }) => {
                        return Err(bad(
                            name,
                            "the patch radius is a parameter of Coulomb-Contensou friction only"
                                .into(),
                        ))
                    }
                    (6 | 7, _) if one_sphere(top).is_none() => {
                        return Err(bad(
                            name,
                            "s and rho are parameters of a top whose contact is one tip sphere \
                             below G (PlayTop(m, A, C, s, rho))"
                                .into(),
                        ))
                    }
                    _ => PlayParam::Param(j),
                }
            } else if let Some(j) = PLAY_FIELDS.iter().position(|f| f == name) {
                PlayParam::Field(j)
            } else {
                return Err(bad(
                    name,
                    format!(
                        "a play top has the parameters {} and its state the fields {}",
                        PLAY_PARAMETERS.join(", "),
                        PLAY_FIELDS.join(", ")
                    ),
                ));
            };
            params.push(p);
        }
        if params.is_empty() {
            return Err(bad(
                "[]",
                "name at least one parameter or field of the state (or give None)".into(),
            ));
        }
        Ok(PlaySensitivities {
            names: names.to_vec(),
            params,
        })
    }
}

/// `(s, rho)` of a top whose contact is one sphere below G.
fn one_sphere(top: &PlayTop) -> Option<(f64, f64)> {
    match (top.parts.n, top.parts.shape[0]) {
        (1, Shape::Sphere { radius, z }) if radius > 0.0 && z <= 0.0 => Some((-z, radius)),
        _ => None,
    }
}

/// The value of parameter `j` of `top`, and a scale of its unit for a step where it is 0.
fn parameter(top: &PlayTop, j: usize) -> (f64, f64) {
    let l = top.reach();
    let mu = match top.friction {
        Friction::Coulomb { mu } | Friction::Viscous { mu } => mu,
        Friction::CoulombContensou { mu, .. } => mu,
        Friction::Frictionless => 0.0,
    };
    match j {
        0 => (top.m, 1.0),
        1 => (top.a, 1.0),
        2 => (top.c, 1.0),
        3 => (top.g, 1.0),
        4 => (mu, 1.0),
        5 => match top.friction {
            Friction::CoulombContensou { radius, .. } => (radius, l),
            _ => (0.0, l),
        },
        6 => (top.s, l),
        7 => (top.rho, l),
        8 => (top.restitution, 1.0),
        9 => (top.rolling, l),
        10 => (top.drilling, l),
        _ => (top.air, top.a),
    }
}

/// `top` with parameter `j` moved by `d` (unchecked: a difference may step past a bound,
/// e.g. a restitution of 0 to -d; every law is smooth there).
fn moved(top: &PlayTop, j: usize, d: f64) -> PlayTop {
    let mut t = *top;
    match j {
        0 => t.m += d,
        1 => t.a += d,
        2 => t.c += d,
        3 => t.g += d,
        4 => {
            t.friction = match t.friction {
                Friction::Coulomb { mu } => Friction::Coulomb { mu: mu + d },
                Friction::Viscous { mu } => Friction::Viscous { mu: mu + d },
                Friction::CoulombContensou { mu, radius } => {
                    Friction::CoulombContensou { mu: mu + d, radius }
                }
                f => f,
            }
        }
        5 => {
            if let Friction::CoulombContensou { mu, radius } = t.friction {
                t.friction = Friction::CoulombContensou {
                    mu,
                    radius: radius + d,
                };
            }
        }
        6 | 7 => {
            let (s, rho) = one_sphere(top).unwrap_or((top.s, top.rho));
            let (s, rho) = if j == 6 { (s + d, rho) } else { (s, rho + d) };
            t.s = s;
            t.rho = rho;
            t.parts = super::Parts::one(Shape::Sphere { radius: rho, z: -s });
        }
        8 => t.restitution += d,
        9 => t.rolling += d,
        10 => t.drilling += d,
        _ => t.air += d,
    }
    t
}

/// The step of parameter `j` of `top`.
fn parameter_step(top: &PlayTop, j: usize) -> f64 {
    let (v, unit) = parameter(top, j);
    STEP * if v != 0.0 { v.abs() } else { unit }
}

/// `y` moved by `e s` along the tangent `s`: the orientation through the exponential map.
fn retract(y: &[f64; DIM], s: &[f64; TAN], e: f64) -> [f64; DIM] {
    let mut out = *y;
    let q = Quat([y[0], y[1], y[2], y[3]]).hamilton(Quat::from_rotation_vector([
        e * s[0],
        e * s[1],
        e * s[2],
    ]));
    out[..4].copy_from_slice(&q.0);
    for i in 3..TAN {
        out[i + 1] += e * s[i];
    }
    out
}

/// The tangent `(a - b) / (2 e)` of two states about `y` (the orientation's through
/// `dq = q (0, xi) / 2`).
fn tangent(y: &[f64; DIM], a: &[f64; DIM], b: &[f64; DIM], e: f64) -> [f64; TAN] {
    let conj = Quat([y[0], -y[1], -y[2], -y[3]]);
    let dq = Quat(std::array::from_fn(|i| (a[i] - b[i]) / (2.0 * e)));
    let xi = conj.hamilton(dq);
    let mut out = [0.0; TAN];
    for i in 0..3 {
        out[i] = 2.0 * xi.0[1 + i];
    }
    for i in 3..TAN {
        out[i] = (a[i + 1] - b[i + 1]) / (2.0 * e);
    }
    out
}

/// The right-hand side in tangent coordinates: `(omega, omega', v, v', dissipated')`.
fn tangent_rates(y: &[f64; DIM], dy: &[f64; DIM]) -> [f64; TAN] {
    let mut out = [0.0; TAN];
    out[..3].copy_from_slice(&y[4..7]);
    out[3..].copy_from_slice(&dy[4..]);
    out
}

/// The scales a phase measures a tangent in (see the module's notes).
fn scales(top: &PlayTop, y: &[f64; DIM]) -> [f64; TAN] {
    let l = top.reach();
    let w = (y[4] * y[4] + y[5] * y[5] + y[6] * y[6]).sqrt() + (top.g / l).sqrt();
    let v = top.speed_scale(y);
    let e = top.kinetic_energy(y) + top.m * top.g * l + y[13].abs();
    let mut s = [1.0; TAN];
    s[3..6].fill(w);
    s[6..9].fill(l);
    s[9..12].fill(v);
    s[12] = e;
    s
}

/// The difference step along `s`: `STEP` over its largest scaled component (None: s = 0).
fn step_along(s: &[f64; TAN], scale: &[f64; TAN]) -> Option<f64> {
    let n = (0..TAN)
        .map(|i| (s[i] / scale[i]).abs())
        .fold(0.0, f64::max);
    (n > 0.0 && n.is_finite()).then(|| STEP / n)
}

/// A top with its phase's kernel and ratios.
#[derive(Clone, Copy)]
struct Kerneled {
    top: PlayTop,
    kernel: Kernel,
    consts: Consts,
}

impl Kerneled {
    /// `top` in `phase`, each resistance's law kept to the side of its kink `side` gives
    /// (the driver's [`Rules::consts`]), as in a plain run.
    fn of(top: PlayTop, phase: &Phase, side: [f64; 2]) -> Self {
        let mut consts = Consts::of(&top);
        consts.side = side;
        Kerneled {
            kernel: Kernel::of(&top, &phase.contacts),
            consts,
            top,
        }
    }
    fn rates(&self, phase: &Phase, y: &[f64; DIM]) -> [f64; DIM] {
        let mut dy = [0.0; DIM];
        let mut f = super::Forces::default();
        self.top.rates(
            self.kernel,
            &self.consts,
            &phase.contacts,
            y,
            &mut dy,
            &mut f,
        );
        dy
    }
}

/// A phase's system with the sensitivities after the state: `N = DIM + TAN K`.
struct PhaseWithSensitivities<'a> {
    rules: &'a Rules<'a>,
    phase: Phase,
    base: Kerneled,
    /// Per sensitivity, the tops with its parameter moved by `+d` and `-d`, and `1 / (2 d)`.
    moved: Vec<Option<(Kerneled, Kerneled, f64)>>,
    scale: [f64; TAN],
    /// The ledger kept where nothing dissipates, as in a plain run.
    keep: Option<Keep>,
}

impl PhaseWithSensitivities<'_> {
    /// The step `e` along `s`, shortened so that it moves each sliding part's slip measure
    /// vector by at most [`SLIP_STEP`] of its length: under Coulomb's law the force follows
    /// the slip's direction, whose derivative grows as 1/|slip| as a slip runs out, so the
    /// difference must stay small against the slip itself.
    fn slip_step(&self, y: &[f64; DIM], s: &[f64; TAN], e: f64) -> f64 {
        let top = &self.base.top;
        if !matches!(
            top.friction,
            Friction::Coulomb { .. } | Friction::CoulombContensou { .. }
        ) {
            return e;
        }
        let moved = retract(y, s, e);
        let (k0, k1) = (top.kin(y), top.kin(&moved));
        let rb = top.friction.rbar();
        let mut out = e;
        for i in 0..top.parts.n {
            if self.phase.contacts.mode[i] != super::Mode::Slip {
                continue;
            }
            let p = &top.parts.shape[i];
            let (a, b) = (
                p.point_velocity(k0.v, k0.w, k0.e3),
                p.point_velocity(k1.v, k1.w, k1.e3),
            );
            let v0 = [a[0], a[1], rb * k0.w[2]];
            let dv = [b[0] - a[0], b[1] - a[1], rb * (k1.w[2] - k0.w[2])];
            // (below the phase's creep tolerance the kernel slides along the phase's
            // direction: no shorter step)
            let n0 = dot(v0, v0).sqrt().max(self.phase.contacts.creep);
            let nd = dot(dv, dv).sqrt();
            if nd > SLIP_STEP * n0 {
                out = out.min(e * SLIP_STEP * n0 / nd);
            }
        }
        out
    }
}

/// The largest share of a sliding part's slip a difference step moves it by.
pub const SLIP_STEP: f64 = 1e-4;

impl<const N: usize> OdeSystem<N> for PhaseWithSensitivities<'_> {
    fn rhs(&self, t: f64, y: &[f64; N], dy: &mut [f64; N]) {
        let mut ym = [0.0; DIM];
        ym.copy_from_slice(&y[..DIM]);
        let mut dm = [0.0; DIM];
        let b = &self.base;
        self.rules
            .phase_rates(&self.phase.contacts, b.kernel, &b.consts, t, &ym, &mut dm);
        dy[..DIM].copy_from_slice(&dm);
        let omega = [ym[4], ym[5], ym[6]];
        for (j, moved) in self.moved.iter().enumerate() {
            let at = DIM + TAN * j;
            let mut s = [0.0; TAN];
            s.copy_from_slice(&y[at..at + TAN]);
            let mut d = [0.0; TAN];
            if let Some(e) = step_along(&s, &self.scale).map(|e| self.slip_step(&ym, &s, e)) {
                let fp = b.rates(&self.phase, &retract(&ym, &s, e));
                let fm = b.rates(&self.phase, &retract(&ym, &s, -e));
                for i in 3..TAN {
                    d[i] = (fp[i + 1] - fm[i + 1]) / (2.0 * e);
                }
                let xi = [s[0], s[1], s[2]];
                let c = cross(xi, omega);
                for i in 0..3 {
                    d[i] = c[i] + s[3 + i];
                    // the position's rate is the velocity: exactly its sensitivity
                    d[6 + i] = s[9 + i];
                }
            }
            if let Some((p, m, inv)) = moved {
                let (fp, fm) = (p.rates(&self.phase, &ym), m.rates(&self.phase, &ym));
                for i in 3..TAN {
                    if !(6..9).contains(&i) {
                        d[i] += (fp[i + 1] - fm[i + 1]) * inv;
                    }
                }
            }
            dy[at..at + TAN].copy_from_slice(&d);
        }
        for x in dy[DIM + TAN * self.moved.len()..].iter_mut() {
            *x = 0.0;
        }
    }

    fn project(&self, y: &mut [f64; N]) {
        let mut ym = [0.0; DIM];
        ym.copy_from_slice(&y[..DIM]);
        Keep::project(
            self.keep.as_ref(),
            &self.base.top,
            &self.phase.contacts,
            &mut ym,
        );
        y[..DIM].copy_from_slice(&ym);
    }

    #[inline(always)]
    fn controlled(&self) -> usize {
        DIM
    }
}

/// A run with sensitivities: times, rows, and per row and name the tangent
/// `(xi, d_omega, d_r, d_v, d_dissipated)`.
#[derive(Debug, Clone)]
pub struct PlaySensitivitySolution {
    /// Times (s).
    pub t: Vec<f64>,
    /// Rows at those times.
    pub rows: Vec<PlayRow>,
    /// Row-major: `sens[i * k + j]` for row i and name j of k.
    pub sens: Vec<[f64; TAN]>,
    /// Counters, the contact switches and status.
    pub info: RunInfo,
}

/// The coordinates the initial state is built from (see [`PLAY_FIELDS`]).
#[derive(Debug, Clone, Copy)]
struct Start {
    q: Quat,
    omega: [f64; 3],
    /// Euler angles and rates, None where theta is within 1e-6 of 0 or pi.
    euler: Option<[f64; 6]>,
    xy: [f64; 2],
    vxy: [f64; 2],
    height: Option<f64>,
}

impl Start {
    fn of(top: &PlayTop, y: &[f64; DIM]) -> Start {
        let q = Quat([y[0], y[1], y[2], y[3]]).normalized();
        let omega = [y[4], y[5], y[6]];
        let (phi, theta, psi) = euler_from_quaternion(q);
        let (st, ct) = theta.sin_cos();
        let euler = (st.abs() > 1e-6).then(|| {
            let (sp, cp) = psi.sin_cos();
            let theta_dot = omega[0] * cp - omega[1] * sp;
            let phi_dot = (omega[0] * sp + omega[1] * cp) / st;
            [theta, phi, psi, theta_dot, phi_dot, omega[2] - ct * phi_dot]
        });
        let k = top.kin(y);
        let gap = top
            .parts
            .iter()
            .map(|p| p.gap(k.zg, k.e3))
            .fold(f64::INFINITY, f64::min);
        Start {
            q,
            omega,
            euler,
            xy: [y[7], y[8]],
            vxy: [y[10], y[11]],
            height: (gap > 1e-9 * top.reach()).then_some(gap),
        }
    }

    /// The state of `top` with field `j` moved by `d` (none: `j` None).
    fn build(&self, top: &PlayTop, j: Option<usize>, d: f64) -> Result<[f64; DIM]> {
        let mut s = *self;
        match j {
            Some(j @ 0..=5) => {
                let mut e = self.euler.ok_or_else(|| KreiselError::InvalidParameter {
                    name: "sensitivities".into(),
                    value: format!("{:?}", PLAY_FIELDS[j]),
                    allowed: "the Euler angles are singular at theta = 0 or pi: take \
                              \"orientation[i]\" and \"omega[i]\" there"
                        .into(),
                })?;
                e[j] += d;
                s.q = quaternion_from_euler(e[1], e[0], e[2]);
                s.omega = omega_body_from_euler(e[0], e[2], e[3], e[4], e[5]);
            }
            Some(6) => s.vxy[0] += d,
            Some(7) => s.vxy[1] += d,
            Some(8) => s.xy[0] += d,
            Some(9) => s.xy[1] += d,
            Some(10) => {
                let h = self.height.ok_or_else(|| KreiselError::InvalidParameter {
                    name: "sensitivities".into(),
                    value: "\"height\"".into(),
                    allowed: "the height is a field of a dropped top (state(..., height=h) \
                              with h > 0); this one starts in contact"
                        .into(),
                })?;
                s.height = Some(h + d);
            }
            Some(j @ 11..=13) => {
                let mut v = [0.0; 3];
                v[j - 11] = d;
                s.q = self.q.hamilton(Quat::from_rotation_vector(v));
            }
            Some(j @ 14..=16) => s.omega[j - 14] += d,
            _ => {}
        }
        let mut y = top.state(s.q, s.omega, s.vxy[0], s.vxy[1], s.height)?;
        y[7] = s.xy[0];
        y[8] = s.xy[1];
        Ok(y)
    }

    /// A scale of field `j` for its difference step.
    fn field_scale(&self, top: &PlayTop, j: usize) -> f64 {
        let w = dot(self.omega, self.omega).sqrt() + (top.g / top.reach()).sqrt();
        match j {
            0..=2 | 11..=13 => 1.0,
            3..=5 | 14..=16 => w,
            6 | 7 => top.reach() * w,
            _ => top.reach(),
        }
    }
}

/// A part that slides from (nearly) zero slip under Coulomb's law (or Coulomb-Contensou's)
/// in `phase`: its slip direction's derivative grows as 1/|slip|, a stiff mode of the
/// variational equation that the steps of the motion (which does not see it) cannot follow.
fn slip_from_rest(top: &PlayTop, phase: &Phase, y: &[f64; DIM]) -> Option<usize> {
    if !matches!(
        top.friction,
        Friction::Coulomb { .. } | Friction::CoulombContensou { .. }
    ) {
        return None;
    }
    let k = top.kin(y);
    let level = 1e-6 * top.speed_scale(y);
    (0..top.parts.n)
        .find(|&i| phase.contacts.mode[i] == super::Mode::Slip && top.part_slide(&k, i) < level)
}

/// The error for an event the sensitivities do not cross.
fn unsupported(what: &str, t: f64) -> KreiselError {
    KreiselError::InvalidParameter {
        name: "sensitivities".into(),
        value: format!("a run with the event {what} at t = {t}"),
        allowed: "a play top's sensitivities cross touchdowns (not lift-off, slip_to_roll, \
                  roll_to_slip, a slide from rest under Coulomb friction, a tangential impact \
                  or lying flat); give a t_end before this event"
            .into(),
    }
}

/// The rules of a run with sensitivities: method "dop853", no user events, 1 to
/// [`MAX_PLAY_SENSITIVITIES`] names.
fn check(top: &PlayTop, settings: &Settings, sens: &PlaySensitivities) -> Result<()> {
    if settings.method != "dop853" {
        return Err(KreiselError::InvalidParameter {
            name: "method".into(),
            value: format!("{:?}", settings.method),
            allowed: "sensitivities are integrated with \"dop853\" only".into(),
        });
    }
    if !settings.events.is_empty() {
        return Err(KreiselError::InvalidParameter {
            name: "events".into(),
            value: format!("{} event(s)", settings.events.len()),
            allowed: "a run with sensitivities takes no events (their times would need \
                      sensitivities of their own)"
                .into(),
        });
    }
    simulate::check(top, settings, 0)?;
    let k = sens.params.len();
    if k == 0 || k > MAX_PLAY_SENSITIVITIES {
        return Err(KreiselError::invalid(
            "sensitivities",
            k as f64,
            format!("give 1 to {MAX_PLAY_SENSITIVITIES} names"),
        ));
    }
    Ok(())
}

/// Simulates `top` from `y0` with the sensitivities `sens` (method "dop853", no events): the
/// rows are those of [`simulate::simulate`] with the same settings, bit for bit. A run that
/// reaches an event the sensitivities do not cross (see the module's notes) ends with an
/// error naming it and its time.
pub fn simulate_with_sensitivities(
    top: &PlayTop,
    y0: &[f64; DIM],
    settings: &Settings,
    sens: &PlaySensitivities,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<PlaySensitivitySolution> {
    check(top, settings, sens)?;
    macro_rules! widths {
        ($($k:literal),*) => {
            match sens.params.len() {
                $(k if k <= $k => run::<{ DIM + TAN * $k }>(top, y0, settings, sens, keep_going),)*
                _ => run::<{ DIM + TAN * MAX_PLAY_SENSITIVITIES }>(
                    top, y0, settings, sens, keep_going,
                ),
            }
        };
    }
    widths!(1, 2, 4, 8, 14)
}

/// The parameter tops of a phase: per sensitivity the moved tops and `1 / (2 d)`.
fn moved_tops(
    top: &PlayTop,
    sens: &PlaySensitivities,
    phase: &Phase,
    side: [f64; 2],
) -> Vec<Option<(Kerneled, Kerneled, f64)>> {
    sens.params
        .iter()
        .map(|p| match *p {
            PlayParam::Param(j) => {
                let d = parameter_step(top, j);
                Some((
                    Kerneled::of(moved(top, j, d), phase, side),
                    Kerneled::of(moved(top, j, -d), phase, side),
                    0.5 / d,
                ))
            }
            PlayParam::Field(_) => None,
        })
        .collect()
}

/// The start of a run of `top` from `y`: the driver's start and the energy it keeps.
fn started(top: &PlayTop, y: &[f64; DIM], rtol: f64) -> (Phase, Option<Switch>, [f64; DIM]) {
    let rules = Rules::for_run(top, rtol);
    let mut y = *y;
    let e = ledger(top, &y);
    let (phase, jam) = rules.start(&mut y);
    no_energy_from_a_switch(top, &mut y, e);
    (phase, jam, y)
}

/// The initial sensitivities: central differences of the start (the state built from its
/// fields, then put on its contacts as the driver does) in each field or parameter.
fn initial(
    top: &PlayTop,
    y0: &[f64; DIM],
    y: &[f64; DIM],
    phase: &Phase,
    sens: &PlaySensitivities,
    rtol: f64,
) -> Result<Vec<[f64; TAN]>> {
    let start = Start::of(top, y0);
    // The start as given differs from the one its fields build by how far the given state
    // is from a built one: the differences are taken about the built one, which is what the
    // fields describe.
    let mut out = Vec::with_capacity(sens.params.len());
    for (name, p) in sens.names.iter().zip(&sens.params) {
        let (a, b, d) = match *p {
            PlayParam::Field(j) => {
                let d = STEP * start.field_scale(top, j);
                (
                    start.build(top, Some(j), d)?,
                    start.build(top, Some(j), -d)?,
                    d,
                )
            }
            PlayParam::Param(j) => {
                let d = parameter_step(top, j);
                let (tp, tm) = (moved(top, j, d), moved(top, j, -d));
                (
                    start.build(&tp, None, 0.0)?,
                    start.build(&tm, None, 0.0)?,
                    d,
                )
            }
        };
        let (ta, tb) = match *p {
            PlayParam::Param(j) => (moved(top, j, d), moved(top, j, -d)),
            PlayParam::Field(_) => (*top, *top),
        };
        let (pa, _, ya) = started(&ta, &a, rtol);
        let (pb, _, yb) = started(&tb, &b, rtol);
        if pa.contacts.mode != phase.contacts.mode || pb.contacts.mode != phase.contacts.mode {
            return Err(KreiselError::InvalidParameter {
                name: "sensitivities".into(),
                value: format!("{name:?}"),
                allowed: "the initial state is at a contact switch (moving it changes how the \
                          run starts); start it away from the switch"
                    .into(),
            });
        }
        out.push(tangent(y, &ya, &yb, d));
    }
    Ok(out)
}

/// The saltation of the sensitivities `s` at the switch `sw` of `phase` located at `y`
/// (before it): returns the sensitivities after the switch, given the state after it `y1`
/// and the phase after it `next` (prepared).
#[allow(clippy::too_many_arguments)]
fn saltation(
    rules: &Rules<'_>,
    sens: &PlaySensitivities,
    sw: Switch,
    phase: &Phase,
    eps: f64,
    y: &[f64; DIM],
    s: &[[f64; TAN]],
    t: f64,
    rtol: f64,
) -> Result<(Vec<[f64; TAN]>, Vec<f64>)> {
    let top = rules.top;
    let scale = scales(top, y);
    let base = Kerneled::of(*top, phase, rules.consts(phase).side);
    let f_minus = tangent_rates(y, &base.rates(phase, y));
    let g = |r: &Rules<'_>, yy: &[f64; DIM]| r.value(sw, phase, f64::NAN, yy, eps);
    // The switch's map, the driver's: the switch, then E + dissipated kept.
    let jump = |r: &Rules<'_>, yy: &[f64; DIM]| {
        let mut yy = *yy;
        let e = ledger(r.top, &yy);
        let next = r.apply(sw, phase, &mut yy);
        no_energy_from_a_switch(r.top, &mut yy, e);
        (next, yy)
    };
    let (next, y1) = jump(rules, y);
    let same = |n: &Phase| {
        if n.contacts.mode[..top.parts.n] == next.contacts.mode[..top.parts.n] {
            Ok(())
        } else {
            Err(KreiselError::Numerical(format!(
                "play top sensitivities: the switch {} at t = {t} ends in other contact modes \
                 when the state is moved by its sensitivities (a switch at the edge of two \
                 outcomes has no derivative: {:?} against {:?})",
                sw.name(),
                &n.contacts.mode[..top.parts.n],
                &next.contacts.mode[..top.parts.n]
            )))
        }
    };
    // A slip's end is located where its measure |(v_slip, rbar w_n)| falls to the creep
    // tolerance, 1e-10 of the speed scale: a difference step would cross that kink, so its
    // derivative is the unit slip's dot product with the slip vector's (smooth) derivative.
    let slip = match sw {
        Switch::SlipToRoll(i) if !phase.contacts.flat => Some(i),
        _ => None,
    };
    let slip_vector = |tp: &PlayTop, yy: &[f64; DIM]| -> [f64; 3] {
        let i = slip.unwrap_or(0);
        let k = tp.kin(yy);
        let vp = tp.parts.shape[i].point_velocity(k.v, k.w, k.e3);
        [vp[0], vp[1], tp.friction.rbar() * k.w[2]]
    };
    let unit = {
        let v = slip_vector(top, y);
        let n = dot(v, v).sqrt();
        [v[0] / n, v[1] / n, v[2] / n]
    };
    // The event function's derivative along a direction v.
    let dg = |v: &[f64; TAN]| -> f64 {
        let Some(e) = step_along(v, &scale) else {
            return 0.0;
        };
        let (yp, ym) = (retract(y, v, e), retract(y, v, -e));
        if slip.is_some() {
            let (a, b) = (slip_vector(top, &yp), slip_vector(top, &ym));
            (0..3).map(|c| unit[c] * (a[c] - b[c])).sum::<f64>() / (2.0 * e)
        } else {
            (g(rules, &yp) - g(rules, &ym)) / (2.0 * e)
        }
    };
    let gf = dg(&f_minus);
    if gf == 0.0 || !gf.is_finite() {
        return Err(KreiselError::Numerical(format!(
            "play top sensitivities: the switch {} at t = {t} is crossed tangentially (its \
             event function's rate is {gf}): its time has no derivative",
            sw.name()
        )));
    }
    let floor = rules.floor.get();
    let mut out = Vec::with_capacity(s.len());
    let mut theta = Vec::with_capacity(s.len());
    for (sj, p) in s.iter().zip(&sens.params) {
        // The switch's time moves by -th: the state moved along w = S- - f- th (and the
        // parameter along 1) stays on the event's surface, where the switch's own thresholds
        // (a gap or a slip of 1e-9 of the top's scales) decide as they do at y; DD w is then
        // the difference of the switch along it.
        let mut gs = dg(sj);
        let param = match *p {
            PlayParam::Param(j) => {
                let d = parameter_step(top, j);
                let (tp, tm) = (moved(top, j, d), moved(top, j, -d));
                let (rp, rm) = (Rules::for_run(&tp, rtol), Rules::for_run(&tm, rtol));
                rp.floor.set(floor);
                rm.floor.set(floor);
                gs += if slip.is_some() {
                    let (a, b) = (slip_vector(&tp, y), slip_vector(&tm, y));
                    (0..3).map(|c| unit[c] * (a[c] - b[c])).sum::<f64>() / (2.0 * d)
                } else {
                    (g(&rp, y) - g(&rm, y)) / (2.0 * d)
                };
                Some((j, d))
            }
            PlayParam::Field(_) => None,
        };
        let th = gs / gf;
        let mut w = [0.0; TAN];
        for i in 0..TAN {
            w[i] = sj[i] - f_minus[i] * th;
        }
        let e_w = step_along(&w, &scale).unwrap_or(f64::INFINITY);
        let e = match param {
            Some((_, d)) => e_w.min(d),
            None => e_w,
        };
        let v = if e.is_finite() {
            let (yp, ym) = (retract(y, &w, e), retract(y, &w, -e));
            let ((np, jp), (nm, jm)) = match param {
                Some((j, _)) => {
                    let (tp, tm) = (moved(top, j, e), moved(top, j, -e));
                    let (rp, rm) = (Rules::for_run(&tp, rtol), Rules::for_run(&tm, rtol));
                    rp.floor.set(floor);
                    rm.floor.set(floor);
                    (jump(&rp, &yp), jump(&rm, &ym))
                }
                None => (jump(rules, &yp), jump(rules, &ym)),
            };
            same(&np)?;
            same(&nm)?;
            tangent(&y1, &jp, &jm, e)
        } else {
            [0.0; TAN]
        };
        out.push(v);
        // f+ th is added once the next phase is prepared (its right-hand side)
        theta.push(th);
    }
    let _ = next;
    Ok((out, theta))
}

fn run<const N: usize>(
    top: &PlayTop,
    y0: &[f64; DIM],
    settings: &Settings,
    sens: &PlaySensitivities,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<PlaySensitivitySolution> {
    let k = sens.params.len();
    debug_assert!(DIM + TAN * k <= N);
    let h = Rules::for_run(top, settings.rtol);
    let t_end = settings.t_end;
    let rtol = settings.rtol;
    let mut info = RunInfo::default();
    let mut y = *y0;
    let e_given = ledger(top, &y);
    let (mut phase, jam) = h.start(&mut y);
    no_energy_from_a_switch(top, &mut y, e_given);
    if let Some(sw) = jam {
        return Err(unsupported(sw.name(), 0.0));
    }
    if phase.contacts.flat {
        return Err(unsupported("flat (the start lies flat)", 0.0));
    }
    if let Some(i) = slip_from_rest(top, &phase, &y) {
        return Err(unsupported(
            &format!("start (part {i} slides from rest)"),
            0.0,
        ));
    }
    let mut s = initial(top, y0, &y, &phase, sens, rtol)?;
    // After a switch: the factor of f+ still to add to each sensitivity.
    let mut pending: Option<Vec<f64>> = None;
    let (mut ts, mut rows, mut out) = (Vec::new(), Vec::new(), Vec::new());
    let full = Cell::new(false);
    let mut t = 0.0;
    let mut next_sample = 0usize;
    let mut first = true;
    let mut n_switches = 0usize;
    loop {
        // (Checked here, after every switch: a band's restart included.)
        super::driver::check_switches(n_switches, t)?;
        let integrator = Dop853 {
            rtol,
            atol: settings.atol,
            h_init: None,
            h_first_max: f64::INFINITY,
            h_max: h.max_step(&phase, &y),
            max_steps: MAX_STEPS,
            stiff_stop: None,
        };
        let eps = h.tolerance(&y);
        match h.prepare(&mut phase, &mut y, eps) {
            (0, 0, 0) => {}
            // Drilling from the start (a top sleeping upright): the kernel is the phase's.
            (0, 0, _) if first => {}
            (0, 0, _) => return Err(unsupported("slip_to_roll", t)),
            _ => return Err(unsupported("roll_to_slip", t)),
        }
        // The row after a switch is in the phase's modes, prepared, as the driver's.
        let row_after = pending.as_ref().map(|_| h.row(&phase, &y));
        let ph = phase;
        let side = h.consts(&ph).side;
        let base = Kerneled::of(*top, &ph, side);
        if let Some(th) = pending.take() {
            let f_plus = tangent_rates(&y, &base.rates(&ph, &y));
            for (sj, th) in s.iter_mut().zip(th) {
                for i in 0..TAN {
                    sj[i] += f_plus[i] * th;
                }
            }
            // the state after the switch at the same time
            if let (None, Some(r)) = (&settings.t_eval, row_after) {
                if ts.len() >= MAX_ROWS {
                    full.set(true);
                } else {
                    ts.push(t);
                    rows.push(r);
                    out.extend_from_slice(&s);
                }
            }
        }
        let switches = h.watched(&ph);
        let mut fns: Vec<EventFnBox<'_, N>> = Vec::with_capacity(switches.len());
        let hr = &h;
        for &sw in &switches {
            fns.push(Box::new(move |t: f64, yy: &[f64; N]| {
                let mut ym = [0.0; DIM];
                ym.copy_from_slice(&yy[..DIM]);
                hr.value(sw, &ph, t, &ym, eps)
            }));
        }
        let mut locator = Locator::new();
        for f in fns.iter_mut() {
            locator.add(EventSpec::new(-1, true), f.as_mut());
        }
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
        let mut go = |ti: f64| !full.get() && keep_going(ti);
        let (mut t_row, mut r_row, mut s_row) = (Vec::new(), Vec::new(), Vec::new());
        let row = |ti: f64, yy: &[f64; N]| {
            let mut ym = [0.0; DIM];
            ym.copy_from_slice(&yy[..DIM]);
            t_row.push(ti);
            r_row.push(h.row(&ph, &ym));
            for j in 0..k {
                let mut v = [0.0; TAN];
                v.copy_from_slice(&yy[DIM + TAN * j..DIM + TAN * (j + 1)]);
                s_row.push(v);
            }
        };
        let mut stream = Stream::new(seg_times, !first, Some(&mut go), row);
        let mut obs = WithEvents::new(locator, &mut stream);
        let sys = PhaseWithSensitivities {
            rules: &h,
            phase: ph,
            base,
            moved: moved_tops(top, sens, &ph, side),
            scale: scales(top, &y),
            keep: Keep::of(top, &ph.contacts, &y, integrator.rtol),
        };
        let mut yn = [0.0; N];
        yn[..DIM].copy_from_slice(&y);
        for (j, sj) in s.iter().enumerate() {
            yn[DIM + TAN * j..DIM + TAN * (j + 1)].copy_from_slice(sj);
        }
        let (t1, y1, st) = integrator
            .integrate(&sys, t, yn, t_end, &mut obs)
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
        let mut y1 = y1;
        if located {
            // As the plain run: a located event's state is put on the phase's constraints
            // (the tangents are left as the dense output gives them).
            let mut ym = [0.0; DIM];
            ym.copy_from_slice(&y1[..DIM]);
            super::driver::at_event(top, &ph.contacts, &mut ym, &y);
            y1[..DIM].copy_from_slice(&ym);
            if let (Some(&tl), Some(r)) = (t_row.last(), r_row.last_mut()) {
                if tl == t1 {
                    *r = h.row(&ph, &ym);
                }
            }
        }
        for (i, ti) in t_row.into_iter().enumerate() {
            if ts.len() >= MAX_ROWS {
                full.set(true);
                break;
            }
            ts.push(ti);
            rows.push(r_row[i]);
            out.extend_from_slice(&s_row[k * i..k * (i + 1)]);
        }
        info.stats += st;
        first = false;
        let mut reason = None;
        for (idx, te) in hits {
            if let Some(&sw) = switches.get(idx) {
                reason = Some((sw, info.events.len()));
                info.events.push(sw.event(te));
            }
        }
        t = t1;
        y.copy_from_slice(&y1[..DIM]);
        for (j, sj) in s.iter_mut().enumerate() {
            sj.copy_from_slice(&y1[DIM + TAN * j..DIM + TAN * (j + 1)]);
        }
        if s.iter().flatten().any(|x| !x.is_finite()) {
            return Err(KreiselError::Numerical(format!(
                "play top sensitivities: not finite at t = {t} ({} mode)",
                h.mode_name(&ph)
            )));
        }
        if full.get() {
            return Err(KreiselError::invalid(
                "t_end",
                t_end,
                format!(
                    "the run keeps a row per step and reached the {MAX_ROWS} rows: give \
                     t_eval or a shorter t_end"
                ),
            ));
        }
        let Some((switch, record)) = reason.filter(|_| t < t_end) else {
            break;
        };
        if matches!(switch, Switch::Band(_)) {
            // A resistance's kink: the right-hand side is continuous there, so the tangents
            // go on unchanged (no saltation); only the integration restarts.
            info.events.remove(record);
            phase = h.apply(switch, &phase, &mut y);
            n_switches += 1;
            continue;
        }
        if matches!(
            switch,
            Switch::Jam(_)
                | Switch::Flat(_)
                | Switch::LiftOff(_)
                | Switch::RollToSlip(_)
                | Switch::SlipToRoll(_)
                | Switch::CreepEnd(_)
                | Switch::SlipToDrill(_)
                | Switch::DrillEnd(_)
        ) {
            return Err(unsupported(switch.name(), t));
        }
        let (s_jump, theta) = saltation(&h, sens, switch, &ph, eps, &y, &s, t, rtol)?;
        let before = h.row(&phase, &y).contacts.mode;
        let e_before = ledger(top, &y);
        phase = h.apply(switch, &phase, &mut y);
        no_energy_from_a_switch(top, &mut y, e_before);
        if let Some(i) = slip_from_rest(top, &phase, &y) {
            return Err(unsupported(
                &format!("{} (part {i} starts sliding from rest)", switch.name()),
                t,
            ));
        }
        s = s_jump;
        pending = Some(theta);
        let after = h.row(&phase, &y).contacts.mode;
        let (own_name, own) = h.record(switch);
        n_switches += 1;
        if own_name == "slip_to_roll" && own.is_some_and(|i| after[i] == super::Mode::Slip) {
            info.events.remove(record);
        }
        for i in 0..top.parts.n {
            use super::Mode::*;
            let name = match (before[i], after[i]) {
                (Flight, Flight) | (Slip, Slip) | (Roll, Roll) => continue,
                (Flight, _) => "touchdown",
                (_, Flight) => "lift_off",
                (Slip, Roll) => "slip_to_roll",
                (Roll, Slip) => "roll_to_slip",
            };
            if Some(i) != own {
                info.events.push(EventRecord {
                    index: None,
                    name: name.into(),
                    t,
                    part: Some(i),
                });
            }
        }
    }
    info.status = if t < t_end {
        Status::Interrupted
    } else {
        Status::Completed
    };
    Ok(PlaySensitivitySolution {
        t: ts,
        rows,
        sens: out,
        info,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotation::quaternion_from_euler;

    fn names(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| s.to_string()).collect()
    }

    fn coulomb_top() -> PlayTop {
        PlayTop::new(
            0.1,
            1.6e-5,
            2e-5,
            0.03,
            0.005,
            9.81,
            Friction::Coulomb { mu: 0.3 },
            0.0,
            0.0,
            0.0,
            0.0,
        )
        .unwrap()
    }

    fn settings(t_end: f64) -> Settings {
        Settings {
            t_end,
            rtol: 1e-10,
            atol: 1e-12,
            ..Settings::default()
        }
    }

    /// A top sliding on Coulomb friction (mu = 1) that comes to stick at 3.8 ms and slides
    /// again at 0.115 s.
    fn stick_slip() -> (PlayTop, [f64; DIM]) {
        let mut top = coulomb_top();
        top.friction = Friction::Coulomb { mu: 1.0 };
        let q = quaternion_from_euler(0.1, 0.3, 0.2);
        let w = omega_body_from_euler(0.3, 0.2, 0.0, 3.0, 60.0);
        let y0 = top.state(q, w, 0.2, 0.0, None).unwrap();
        (top, y0)
    }

    #[test]
    fn play_sensitivities_leave_the_trajectory_bit_for_bit() {
        // across a touchdown, every step's row and every event as a plain run's
        let mut top = coulomb_top();
        top.friction = Friction::Viscous { mu: 0.5 };
        let q = quaternion_from_euler(0.0, 0.3, 0.0);
        let w = omega_body_from_euler(0.3, 0.0, 0.0, 3.0, 60.0);
        let y0 = top.state(q, w, 0.0, 0.0, Some(0.002)).unwrap();
        let st = settings(0.1);
        let plain = simulate::simulate(&top, &y0, &st, &mut [], &mut |_| true).unwrap();
        let sens = PlaySensitivities::new(&top, &names(&["m", "mu", "theta"])).unwrap();
        let out = simulate_with_sensitivities(&top, &y0, &st, &sens, &mut |_| true).unwrap();
        assert_eq!(plain.info.events.len(), 1, "{:?}", plain.info.events);
        assert_eq!(out.t, plain.t);
        assert_eq!(out.rows, plain.rows);
        assert_eq!(out.info.events, plain.info.events);
        assert_eq!(out.info.stats, plain.info.stats);
        assert_eq!(out.sens.len(), 3 * out.t.len());
        // with t_eval too
        let st = Settings {
            t_eval: Some(vec![0.0, 0.002, 0.05, 0.1]),
            ..st
        };
        let plain = simulate::simulate(&top, &y0, &st, &mut [], &mut |_| true).unwrap();
        let out = simulate_with_sensitivities(&top, &y0, &st, &sens, &mut |_| true).unwrap();
        assert_eq!(out.t, plain.t);
        assert_eq!(out.rows, plain.rows);
        assert_eq!(out.info.events[0].name, "touchdown");
        // a slip-to-stick switch (at 3.8 ms) ends them with an error naming it
        let (top, y0) = stick_slip();
        let e = simulate_with_sensitivities(&top, &y0, &settings(0.01), &sens, &mut |_| true)
            .unwrap_err()
            .to_string();
        assert!(e.contains("slip_to_roll at t = 0.003"), "{e}");
    }

    #[test]
    fn play_sensitivity_names_are_checked() {
        let top = coulomb_top();
        let e = PlaySensitivities::new(&top, &names(&["I1"])).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("\"I1\""), "{msg}");
        assert!(msg.contains("m, A, C, g, mu"), "{msg}");
        assert!(msg.contains("theta, phi, psi"), "{msg}");
        let e = PlaySensitivities::new(&top, &names(&["m", "m"])).unwrap_err();
        assert!(e.to_string().contains("at most once"), "{e}");
        let e = PlaySensitivities::new(&top, &names(&["radius"])).unwrap_err();
        assert!(e.to_string().contains("Coulomb-Contensou"), "{e}");
        let parts = [
            Shape::Sphere {
                radius: 0.015,
                z: -0.003,
            },
            Shape::Sphere {
                radius: 0.005,
                z: -0.016,
            },
        ];
        let two = PlayTop::with_parts(
            6e-3,
            8e-7,
            7e-7,
            &parts,
            9.81,
            Friction::Coulomb { mu: 0.3 },
            0.0,
            0.0,
            0.0,
            0.0,
        )
        .unwrap();
        let e = PlaySensitivities::new(&two, &names(&["rho"])).unwrap_err();
        assert!(e.to_string().contains("one tip sphere"), "{e}");
        assert!(PlaySensitivities::new(&two, &names(&["mu", "theta"])).is_ok());
        // "height" of a top that starts in contact
        let y0 = top
            .state(
                quaternion_from_euler(0.0, 0.3, 0.0),
                [0.0, 0.0, 50.0],
                0.0,
                0.0,
                None,
            )
            .unwrap();
        let sens = PlaySensitivities::new(&top, &names(&["height"])).unwrap();
        let e = simulate_with_sensitivities(&top, &y0, &settings(0.01), &sens, &mut |_| true)
            .unwrap_err();
        assert!(e.to_string().contains("starts in contact"), "{e}");
    }
}
