//! Heavy tops on a moving pivot, with friction at the pivot and air drag: the tops that are
//! no longer integrable (theory: driven and damped tops).
//!
//! The pivot O follows a prescribed path r_O(t). In the frame that translates with O (it
//! does not rotate) the body feels gravity and the inertial force `-m a_O(t)` at its centre
//! of mass, so Euler's equations about O keep their form with the torque
//! `m (g Gamma + A) x c`, A the pivot's acceleration seen in the body frame. The pivot's
//! force on the body is `R = m (a_G + g e_z)`; it works at the rate `R . v_O`. Damping
//! torques: viscous `-c omega`, air drag `-k |omega| omega`, and dry Coulomb friction in a
//! ball joint of radius r_p, a torque of magnitude up to `mu_p r_p |R|` against the rotation.
//!
//! The state integrated is `y = (q, omega, W, D)`: orientation, body angular velocity, the
//! work done by the pivot and the energy dissipated, so that `E + D - W` (E the lab-frame
//! energy) is a constant of every run, to the integration tolerance.
//!
//! Dry friction makes the top a hybrid system. While it turns, `|R|` depends on the angular
//! acceleration, which depends on the friction torque; with `R = R0 + s R1` affine in the
//! friction magnitude s (= |R|), `s = |R0 + s R1|` is a quadratic with exactly one root
//! s >= 0 when `|R1| < 1`, which the constructor ensures (else the friction force would be
//! ambiguous, as in Painleve's paradox). The top sticks when it comes to rest relative to the
//! pivot and the torque that keeps it there, `m (g Gamma + A) x c`, is within the bound,
//! i.e. `|(g Gamma + A) x c| <= mu_p r_p |g Gamma + A|`; it slips again when that fails.

use std::sync::Arc;

use super::equations::{normalize_quaternion, pack, unpack};
use super::simulate::{event_fns, fixed_info, HeavySummary};
use super::splitting::{Splitting, QM as SplitQM};
use super::{HeavyTop, RigidState};
use crate::error::{finite, non_negative, KreiselError, Result};
use crate::integrate::fixed::{self, FixedScheme};
use crate::integrate::implicit::{Gauss4, Midpoint};
use crate::integrate::rk4::Rk4Scheme;
use crate::integrate::{EventSpec, Locator, OdeSystem, Stream, WithEvents};
use crate::rotation::{cross, dot, euler_from_quaternion, norm, Quat};
use crate::simulate::{
    self, integrate_error, relative, Accumulate, EventKind, EventRecord, MethodInfo, Model,
    RunInfo, Settings, Sink, Stats, Status, Unwrapped, UserFn,
};

/// The dimension of the integrated state `(q, omega, W, D)`.
pub const DIM: usize = 9;

/// The degree of a sampled path's pieces (the septic spline with zero velocity, acceleration
/// and jerk at both ends).
pub const PATH_DEGREE: usize = 7;
const NCOEF: usize = PATH_DEGREE + 1;

/// A pivot path as a piecewise polynomial of degree [`PATH_DEGREE`] (built by the caller,
/// e.g. the septic spline with zero velocity, acceleration and jerk at both ends), constant
/// outside its breakpoints.
#[derive(Debug, Clone, PartialEq)]
pub struct PathSpline {
    breaks: Vec<f64>,
    /// Per interval and coordinate: the coefficients of `(t - t_i)^7 .. (t - t_i)^0`.
    coef: Vec<[[f64; NCOEF]; 3]>,
    /// Largest |acceleration| at the breakpoints and interval midpoints (a scale).
    a_max: f64,
    /// Largest |velocity| likewise.
    v_max: f64,
    vertical: bool,
}

/// Position, velocity and acceleration of the pivot (space frame).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PivotKin {
    /// Position (m).
    pub p: [f64; 3],
    /// Velocity (m/s).
    pub v: [f64; 3],
    /// Acceleration (m/s^2).
    pub a: [f64; 3],
}

impl PathSpline {
    /// A path from its breakpoints (strictly increasing, at least 2) and coefficients laid
    /// out as scipy's `PPoly.c` of a 3-vector path, shape (8, intervals, 3), in C order.
    pub fn new(breaks: Vec<f64>, coef: &[f64]) -> Result<Self> {
        if breaks.len() < 2 {
            return Err(KreiselError::invalid(
                "t",
                breaks.len() as f64,
                "a pivot path needs at least 2 samples",
            ));
        }
        for (i, &b) in breaks.iter().enumerate() {
            finite(&format!("t[{i}]"), b)?;
            if i > 0 && b <= breaks[i - 1] {
                return Err(KreiselError::invalid(
                    &format!("t[{i}]"),
                    b,
                    format!(
                        "sample times must increase strictly (t[{}] = {})",
                        i - 1,
                        breaks[i - 1]
                    ),
                ));
            }
        }
        let m = breaks.len() - 1;
        if coef.len() != NCOEF * m * 3 {
            return Err(KreiselError::invalid(
                "position",
                coef.len() as f64,
                format!("a path of {m} intervals has {NCOEF} x {m} x 3 coefficients"),
            ));
        }
        let mut c = vec![[[0.0; NCOEF]; 3]; m];
        for (k, &x) in coef.iter().enumerate() {
            finite("position", x)?;
            let (deg, rest) = (k / (3 * m), k % (3 * m));
            c[rest / 3][rest % 3][deg] = x;
        }
        let vertical = c.iter().all(|iv| {
            iv[0][..PATH_DEGREE]
                .iter()
                .chain(&iv[1][..PATH_DEGREE])
                .all(|&x| x == 0.0)
        });
        let mut path = PathSpline {
            breaks,
            coef: c,
            a_max: 0.0,
            v_max: 0.0,
            vertical,
        };
        let (mut a_max, mut v_max) = (0.0f64, 0.0f64);
        for i in 0..m {
            for f in [0.0, 0.5, 1.0] {
                let t = path.breaks[i] + f * (path.breaks[i + 1] - path.breaks[i]);
                let k = path.interval_kin(i, t);
                a_max = a_max.max(norm(k.a));
                v_max = v_max.max(norm(k.v));
            }
        }
        path.a_max = a_max;
        path.v_max = v_max;
        Ok(path)
    }

    fn interval_kin(&self, i: usize, t: f64) -> PivotKin {
        let x = t - self.breaks[i];
        let mut k = PivotKin::default();
        for d in 0..3 {
            // Horner on c_j (t - t_i)^(5 - j) and its first two derivatives.
            let (mut p, mut v, mut a) = (0.0, 0.0, 0.0);
            for (j, &cj) in self.coef[i][d].iter().enumerate() {
                let n = (PATH_DEGREE - j) as f64;
                p = p * x + cj;
                if j < PATH_DEGREE {
                    v = v * x + cj * n;
                }
                if j + 1 < PATH_DEGREE {
                    a = a * x + cj * n * (n - 1.0);
                }
            }
            k.p[d] = p;
            k.v[d] = v;
            k.a[d] = a;
        }
        k
    }

    /// The third derivative at time t (zero outside the samples).
    pub fn jerk(&self, t: f64) -> [f64; 3] {
        let m = self.coef.len();
        // right-continuous: a run that starts where the path starts takes its first piece
        if t < self.breaks[0] || t >= self.breaks[m] {
            return [0.0; 3];
        }
        self.interval_jerk(self.interval(t), t)
    }

    /// The interval of t (clamped to the first and the last).
    fn interval(&self, t: f64) -> usize {
        self.breaks
            .partition_point(|&b| b <= t)
            .saturating_sub(1)
            .min(self.coef.len() - 1)
    }

    /// Motion and jerk at a time before the first sample continued smoothly from the first
    /// piece (else as [`PathSpline::kin`], [`PathSpline::jerk`]): for the inner stages of a
    /// composition method that step before a run's start, which is the path's start.
    pub fn continued(&self, t: f64) -> (PivotKin, [f64; 3]) {
        if t < self.breaks[0] {
            (self.interval_kin(0, t), self.interval_jerk(0, t))
        } else {
            (self.kin(t), self.jerk(t))
        }
    }

    fn interval_jerk(&self, i: usize, t: f64) -> [f64; 3] {
        let x = t - self.breaks[i];
        let mut j = [0.0; 3];
        for (d, jd) in j.iter_mut().enumerate() {
            for (k, &ck) in self.coef[i][d].iter().enumerate().take(PATH_DEGREE - 2) {
                let n = (PATH_DEGREE - k) as f64;
                *jd = *jd * x + ck * n * (n - 1.0) * (n - 2.0);
            }
        }
        j
    }

    /// The pivot's motion at time t: the polynomial's inside, at rest outside.
    pub fn kin(&self, t: f64) -> PivotKin {
        let m = self.coef.len();
        if t <= self.breaks[0] {
            let k = self.interval_kin(0, self.breaks[0]);
            return PivotKin {
                p: k.p,
                ..PivotKin::default()
            };
        }
        if t >= self.breaks[m] {
            let k = self.interval_kin(m - 1, self.breaks[m]);
            return PivotKin {
                p: k.p,
                ..PivotKin::default()
            };
        }
        self.interval_kin(self.interval(t), t)
    }
}

/// How the pivot moves.
#[derive(Debug, Clone, PartialEq)]
pub enum Pivot {
    /// At rest at the origin.
    Fixed,
    /// `r_O,i(t) = amplitude_i cos(omega t + phase_i)`: a straight stroke where the phases
    /// agree, an ellipse where they differ.
    Harmonic {
        /// Amplitude vector (m, space frame).
        amplitude: [f64; 3],
        /// Angular frequency (rad/s).
        omega: f64,
        /// Phase of each component (rad).
        phase: [f64; 3],
    },
    /// A sampled path.
    Path(Arc<PathSpline>),
}

impl Pivot {
    /// A harmonic pivot, validated.
    pub fn harmonic(amplitude: [f64; 3], omega: f64, phase: [f64; 3]) -> Result<Pivot> {
        for (i, &a) in amplitude.iter().enumerate() {
            finite(&format!("amplitude[{i}]"), a)?;
        }
        if !(0.0..=1e6).contains(&omega) {
            return Err(KreiselError::invalid(
                "omega",
                omega,
                "it must be a finite angular frequency in [0, 1e6] rad/s",
            ));
        }
        for (i, &p) in phase.iter().enumerate() {
            finite(&format!("phase[{i}]"), p)?;
        }
        Ok(Pivot::Harmonic {
            amplitude,
            omega,
            phase,
        })
    }

    /// Position, velocity and acceleration at time t.
    #[inline]
    pub fn kin(&self, t: f64) -> PivotKin {
        match self {
            Pivot::Fixed => PivotKin::default(),
            Pivot::Harmonic {
                amplitude,
                omega,
                phase,
            } => {
                let w2 = omega * omega;
                let mut k = PivotKin::default();
                for i in 0..3 {
                    if amplitude[i] != 0.0 {
                        let (s, c) = (omega * t + phase[i]).sin_cos();
                        k.p[i] = amplitude[i] * c;
                        k.v[i] = -amplitude[i] * omega * s;
                        k.a[i] = -amplitude[i] * w2 * c;
                    }
                }
                k
            }
            Pivot::Path(p) => p.kin(t),
        }
    }

    /// True when the pivot moves along the vertical only (or not at all): then Mz is kept.
    pub fn vertical(&self) -> bool {
        match self {
            Pivot::Fixed => true,
            Pivot::Harmonic { amplitude, .. } => amplitude[0] == 0.0 && amplitude[1] == 0.0,
            Pivot::Path(p) => p.vertical,
        }
    }

    /// True for a pivot at rest.
    pub fn fixed(&self) -> bool {
        match self {
            Pivot::Fixed => true,
            Pivot::Harmonic {
                amplitude, omega, ..
            } => *omega == 0.0 || amplitude.iter().all(|&a| a == 0.0),
            Pivot::Path(_) => false,
        }
    }

    /// The pivot's jerk (m/s^3) at time t: the rate of change of its acceleration.
    pub fn jerk(&self, t: f64) -> [f64; 3] {
        match self {
            Pivot::Fixed => [0.0; 3],
            Pivot::Harmonic {
                amplitude,
                omega,
                phase,
            } => {
                let w3 = omega * omega * omega;
                let mut j = [0.0; 3];
                for i in 0..3 {
                    if amplitude[i] != 0.0 {
                        j[i] = amplitude[i] * w3 * (omega * t + phase[i]).sin();
                    }
                }
                j
            }
            Pivot::Path(p) => p.jerk(t),
        }
    }

    /// The first breakpoint of a sampled path after time t (where its higher derivatives
    /// jump), if any.
    pub fn next_break(&self, t: f64) -> Option<f64> {
        match self {
            Pivot::Path(p) => {
                let i = p.breaks.partition_point(|&b| b <= t);
                p.breaks.get(i).copied()
            }
            _ => None,
        }
    }

    /// Scales of the pivot's acceleration and speed.
    fn scales(&self) -> (f64, f64) {
        match self {
            Pivot::Fixed => (0.0, 0.0),
            Pivot::Harmonic {
                amplitude, omega, ..
            } => {
                let a = norm(*amplitude);
                (a * omega * omega, a * omega)
            }
            Pivot::Path(p) => (p.a_max, p.v_max),
        }
    }
}

/// Torques at the pivot.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Damping {
    /// Viscous coefficient c (N m s): torque `-c omega`.
    pub viscous: f64,
    /// Air-drag coefficient k (N m s^2): torque `-k |omega| omega`.
    pub drag: f64,
    /// Dry friction coefficient of the ball joint (1).
    pub dry: f64,
    /// Radius of the ball joint (m).
    pub pivot_radius: f64,
}

impl Damping {
    /// Validated damping.
    pub fn new(viscous: f64, drag: f64, dry: f64, pivot_radius: f64) -> Result<Damping> {
        Ok(Damping {
            viscous: non_negative("viscous", viscous)?,
            drag: non_negative("drag", drag)?,
            dry: non_negative("dry", dry)?,
            pivot_radius: non_negative("pivot_radius", pivot_radius)?,
        })
    }

    /// Whether any damping acts.
    pub fn any(&self) -> bool {
        self.viscous > 0.0 || self.drag > 0.0 || self.dry * self.pivot_radius > 0.0
    }
}

/// A heavy top on a moving pivot, damped.
#[derive(Debug, Clone, PartialEq)]
pub struct DrivenTop {
    top: HeavyTop,
    pivot: Pivot,
    damping: Damping,
    /// mu_p r_p (m)
    kdry: f64,
    /// The pivot's time at the run's t = 0 (a run continued from a later time).
    t0: f64,
    /// The pivot moves along the vertical only: its motion seen in the body frame is along
    /// Gamma (no rotation of the pivot's vectors into the body frame).
    vertical: bool,
}

/// One output row of a driven top: time, `(q, omega, W, D)`, and whether it sticks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DrivenRow {
    /// Time of the row (s), from the run's start.
    pub t: f64,
    /// `(q, omega, W, D)`.
    pub y: [f64; DIM],
    /// True while dry friction holds the top at rest relative to the pivot.
    pub stuck: bool,
}

impl DrivenRow {
    /// The rigid state of the row.
    pub fn state(&self) -> RigidState {
        let mut q = [0.0; 7];
        q.copy_from_slice(&self.y[..7]);
        unpack(&q)
    }
}

/// What the equations give at one state.
#[derive(Debug, Clone, Copy, Default)]
struct Eval {
    dw: [f64; 3],
    /// The pivot's force on the body, body frame (N).
    r: [f64; 3],
    power_pivot: f64,
    power_dissipated: f64,
}

impl DrivenTop {
    /// A heavy top on `pivot` with `damping`.
    pub fn new(top: HeavyTop, pivot: Pivot, damping: Damping) -> Result<DrivenTop> {
        let kdry = damping.dry * damping.pivot_radius;
        if !kdry.is_finite() {
            return Err(KreiselError::invalid(
                "dry",
                damping.dry,
                "dry * pivot_radius must be finite",
            ));
        }
        let i = top.inertia();
        let i_min = i[0].min(i[1]).min(i[2]);
        let lever = kdry * top.m() * norm(top.com()) / i_min;
        if lever >= 1.0 {
            return Err(KreiselError::invalid(
                "dry",
                damping.dry,
                format!(
                    "dry * pivot_radius * m * |com| / min(I) = {lever:.6} must be < 1: with so \
                     large a joint the friction torque would not be determined by the motion \
                     (as in Painleve's paradox)"
                ),
            ));
        }
        let vertical = pivot.vertical();
        Ok(DrivenTop {
            top,
            pivot,
            damping,
            kdry,
            t0: 0.0,
            vertical,
        })
    }

    /// The same top with its pivot's clock started at `t0`: a run continued from time t0.
    pub fn later(&self, t0: f64) -> DrivenTop {
        DrivenTop {
            t0: self.t0 + t0,
            ..self.clone()
        }
    }

    /// The top on the pivot.
    pub fn top(&self) -> &HeavyTop {
        &self.top
    }
    /// The pivot.
    pub fn pivot(&self) -> &Pivot {
        &self.pivot
    }
    /// The damping.
    pub fn damping(&self) -> Damping {
        self.damping
    }
    /// The pivot's clock at the run's start.
    pub fn t0(&self) -> f64 {
        self.t0
    }

    /// Whether the top is Hamiltonian (no damping): the splittings apply.
    pub fn hamiltonian(&self) -> bool {
        !self.damping.any()
    }

    /// `g Gamma + A` in the body frame: the acceleration that gravity and the pivot's
    /// inertial force give, as felt in the pivot's frame.
    #[inline(always)]
    fn effective_gravity(&self, q: Quat, k: &PivotKin) -> [f64; 3] {
        self.in_body(q, q.up_in_body(), k).0
    }

    /// `g Gamma + A` and the pivot's velocity, in the body frame (Gamma = `q.up_in_body()`,
    /// given: it is computed once per evaluation). A pivot moving along the vertical only
    /// moves along Gamma there.
    #[inline(always)]
    fn in_body(&self, q: Quat, gamma: [f64; 3], k: &PivotKin) -> ([f64; 3], [f64; 3]) {
        let g = self.top.g();
        if self.vertical {
            return (gamma.map(|x| (g + k.a[2]) * x), gamma.map(|x| k.v[2] * x));
        }
        let a = q.rotate_inv(k.a);
        let ge = [
            g * gamma[0] + a[0],
            g * gamma[1] + a[1],
            g * gamma[2] + a[2],
        ];
        (ge, q.rotate_inv(k.v))
    }

    /// The sticking margin `|geff x c| - mu_p r_p |geff|` (per unit mass): <= 0 where dry
    /// friction holds a top at rest relative to the pivot.
    pub fn stick_margin(&self, t: f64, q: Quat) -> f64 {
        let k = self.pivot.kin(t + self.t0);
        let ge = self.effective_gravity(q, &k);
        norm(cross(ge, self.top.com())) - self.kdry * norm(ge)
    }

    #[inline(always)]
    fn eval(&self, t: f64, q: Quat, w: [f64; 3], stuck: bool) -> Eval {
        let k = self.pivot.kin(t + self.t0);
        let (ge, v_b) = self.in_body(q, q.up_in_body(), &k);
        let (m, c) = (self.top.m(), self.top.com());
        if stuck {
            let r = ge.map(|x| m * x);
            return Eval {
                dw: [0.0; 3],
                r,
                power_pivot: dot(r, v_b),
                power_dissipated: 0.0,
            };
        }
        let inertia = self.top.inertia();
        let iw = self.top.momentum(w);
        let gyro = cross(iw, w);
        let tg = cross(ge, c);
        let wn = norm(w);
        let (cv, cd) = (self.damping.viscous, self.damping.drag);
        let drag = cv + cd * wn;
        let tau0 = [
            gyro[0] + m * tg[0] - drag * w[0],
            gyro[1] + m * tg[1] - drag * w[1],
            gyro[2] + m * tg[2] - drag * w[2],
        ];
        let alpha0 = self.top.omega(tau0);
        let cen = cross(w, cross(w, c));
        let ac = cross(alpha0, c);
        let base = [
            m * (ge[0] + ac[0] + cen[0]),
            m * (ge[1] + ac[1] + cen[1]),
            m * (ge[2] + ac[2] + cen[2]),
        ];
        let mut e = Eval {
            dw: alpha0,
            r: base,
            power_pivot: 0.0,
            power_dissipated: drag * wn * wn,
        };
        if self.kdry > 0.0 {
            // The direction the friction torque opposes: the rotation's, or at rest the
            // torque's that starts it (to leading order the same, see the module's notes).
            let dir = if wn > 0.0 { w } else { tau0 };
            let dn = norm(dir);
            if dn > 0.0 {
                let u = dir.map(|x| x / dn);
                let iu = [
                    self.kdry * u[0] / inertia[0],
                    self.kdry * u[1] / inertia[1],
                    self.kdry * u[2] / inertia[2],
                ];
                let r1 = cross(iu, c).map(|x| -m * x);
                let a = 1.0 - dot(r1, r1);
                let b = dot(base, r1);
                let s = (b + (b * b + a * dot(base, base)).sqrt()) / a;
                for i in 0..3 {
                    e.dw[i] -= s * iu[i];
                    e.r[i] += s * r1[i];
                }
                e.power_dissipated += s * self.kdry * wn;
            }
        }
        e.power_pivot = dot(e.r, v_b);
        e
    }

    /// Lab-frame energy: kinetic energy of the moving body and `m g z_G` (J).
    pub fn energy(&self, t: f64, s: &RigidState) -> f64 {
        let k = self.pivot.kin(t + self.t0);
        let (m, c) = (self.top.m(), self.top.com());
        let v_b = s.q.rotate_inv(k.v);
        let iw = self.top.momentum(s.omega);
        0.5 * dot(s.omega, iw)
            + m * dot(v_b, cross(s.omega, c))
            + 0.5 * m * dot(k.v, k.v)
            + m * self.top.g() * (k.p[2] + dot(c, s.q.up_in_body()))
    }

    /// The pivot frame's energy `H = T + m (g e_z + a_O(t)) . r_G` (J): the Hamiltonian of an
    /// undamped top on a moving pivot, with explicit time.
    pub fn pivot_frame_energy(&self, t: f64, s: &RigidState) -> f64 {
        let k = self.pivot.kin(t + self.t0);
        let iw = self.top.momentum(s.omega);
        let r = s.q.rotate(self.top.com());
        let m = self.top.m();
        0.5 * dot(s.omega, iw) + m * (self.top.g() * r[2] + dot(k.a, r))
    }

    /// The pivot's force on the body (space frame, N), the power it puts in and the power
    /// dissipated (W) at a state.
    pub fn forces(&self, t: f64, s: &RigidState, stuck: bool) -> ([f64; 3], f64, f64) {
        let e = self.eval(t, s.q, s.omega, stuck);
        (s.q.rotate(e.r), e.power_pivot, e.power_dissipated)
    }

    /// A rate scale of the motion from `s0` (rad/s): its own or the pendulum's.
    fn rate_scale(&self, s0: &RigidState) -> f64 {
        let i = self.top.inertia();
        let (a_max, _) = self.pivot.scales();
        let pend = (self.top.m() * (self.top.g() + a_max) * norm(self.top.com())
            / i[0].min(i[1]).min(i[2]))
        .sqrt();
        let s = norm(s0.omega).max(pend);
        if s > 0.0 && s.is_finite() {
            s
        } else {
            1.0
        }
    }

    /// The energy scale of the motion from `s0` (J): kinetic, potential and the pivot's.
    fn energy_scale(&self, s0: &RigidState) -> f64 {
        let (a_max, v_max) = self.pivot.scales();
        let m = self.top.m();
        let c = norm(self.top.com());
        let iw = self.top.momentum(s0.omega);
        0.5 * dot(s0.omega, iw) + m * (self.top.g() + a_max) * c + 0.5 * m * v_max * v_max
    }
}

/// The driven top as a first-order system on `(q, omega, W, D)` (or `(q, M, W, D)` with
/// `MOMENTUM`, the variables of the implicit Gauss methods), in one phase: turning, or
/// held by dry friction (`stuck`: the orientation stays, only the pivot's work grows).
pub struct Driven<'a, const MOMENTUM: bool, const STUCK: bool> {
    top: &'a DrivenTop,
    /// The energy scale W and D are measured against (J).
    energy: f64,
}

impl<const MOMENTUM: bool, const STUCK: bool> OdeSystem<DIM> for Driven<'_, MOMENTUM, STUCK> {
    /// W and D start at 0 and W crosses it: their errors are measured against the motion's
    /// energy scale, not against their own values (whose absolute tolerance near 0 set the
    /// steps: D1 took 7175 steps where the motion needs 4915).
    #[inline(always)]
    fn magnitude_floor(&self) -> [f64; DIM] {
        let mut f = [0.0; DIM];
        f[7] = self.energy;
        f[8] = self.energy;
        f
    }

    #[inline(always)]
    fn rhs(&self, t: f64, y: &[f64; DIM], dy: &mut [f64; DIM]) {
        let q = Quat([y[0], y[1], y[2], y[3]]);
        let raw = [y[4], y[5], y[6]];
        let w = if MOMENTUM {
            self.top.top.omega(raw)
        } else {
            raw
        };
        let e = self.top.eval(t, q, w, STUCK);
        if STUCK {
            dy[..7].fill(0.0);
        } else {
            dy[..4].copy_from_slice(&q.half_times_pure(w));
            let dw = if MOMENTUM {
                self.top.top.momentum(e.dw)
            } else {
                e.dw
            };
            dy[4..7].copy_from_slice(&dw);
        }
        dy[7] = e.power_pivot;
        dy[8] = e.power_dissipated;
    }

    fn project(&self, y: &mut [f64; DIM]) {
        // a stuck top's orientation does not change, not even by a rounding
        if !MOMENTUM && !STUCK {
            normalize_quaternion(y);
        }
    }
}

impl super::sensitivity::Carrier<DIM> for Driven<'_, false, false> {
    fn top(&self) -> &HeavyTop {
        &self.top.top
    }
    fn damping(&self) -> [f64; 2] {
        [self.top.damping.viscous, self.top.damping.drag]
    }
}

impl DrivenTop {
    /// The system a run from `s0` integrates while the top turns (not stuck), and its
    /// initial state `(q, omega, 0, 0)`.
    pub(super) fn smooth_system(&self, s0: &RigidState) -> (Driven<'_, false, false>, [f64; DIM]) {
        let sys = Driven::<false, false> {
            top: self,
            energy: self.energy_scale(s0),
        };
        (sys, pack9(s0))
    }
}

fn pack9(s: &RigidState) -> [f64; DIM] {
    let p = pack(s);
    let mut y = [0.0; DIM];
    y[..7].copy_from_slice(&p);
    y
}

fn state_of(y: &[f64; DIM]) -> RigidState {
    let mut p = [0.0; 7];
    p.copy_from_slice(&y[..7]);
    unpack(&p)
}

/// The events a driven top has (those of the fixed heavy top).
const EVENTS: [EventKind; 3] = [
    EventKind::TurningPoints,
    EventKind::ThetaCrossing(0.0),
    EventKind::User,
];

/// The phase of a run with dry friction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    /// Turning relative to the pivot; watching for rest.
    Turning,
    /// Turning again after passing through rest without sticking; watching for the rate
    /// to rise clear of the rest threshold.
    Passing,
    /// Held at rest relative to the pivot.
    Stuck,
}

impl Model for DrivenTop {
    type State = RigidState;
    type Row = DrivenRow;
    type Summary = HeavySummary;
    type Acc<'a> = DrivenAcc<'a>;
    const NAME: &'static str = "driven heavy top";

    fn check(&self, settings: &Settings, info: &MethodInfo) -> Result<()> {
        settings.unsupported_event(Self::NAME, &EVENTS)?;
        if settings.reduced {
            return Err(KreiselError::InvalidParameter {
                name: "reduced".into(),
                value: "True".into(),
                allowed: "the reduced route uses the momenta p_phi and p_psi of a fixed, \
                          undamped Lagrange top; a moving pivot or damping does not keep them"
                    .into(),
            });
        }
        let refuse = |why: &str| {
            Err(KreiselError::InvalidParameter {
                name: "method".into(),
                value: format!("{:?}", info.name),
                allowed: why.into(),
            })
        };
        match info.name {
            "dop853" => Ok(()),
            "rk4" | "midpoint" | "gauss4" if self.kdry > 0.0 => refuse(
                "dry friction at the pivot sticks and slips; only \"dop853\" locates those \
                 switches (the fixed-step methods take moving pivots, viscous and drag damping)",
            ),
            "rk4" | "midpoint" | "gauss4" => Ok(()),
            "splitting" | "splitting4" | "splitting6" if !self.hamiltonian() => refuse(
                "the splittings are symplectic and a damped top is not Hamiltonian: use \
                 \"dop853\", or \"rk4\", \"midpoint\", \"gauss4\" without dry friction",
            ),
            "splitting" | "splitting4" | "splitting6" => Ok(()),
            "verlet" => refuse(
                "\"verlet\" works on the Euler-angle Hamiltonian of a fixed, undamped \
                 symmetric top; use \"splitting\" (moving pivot, no damping) or \"dop853\"",
            ),
            _ => refuse("a method of simulate::METHODS"),
        }
    }

    fn run(
        &self,
        s0: &RigidState,
        settings: &Settings,
        user: &mut [UserFn<'_, RigidState>],
        keep_going: &mut dyn FnMut(f64) -> bool,
        sink: Sink<'_, DrivenRow>,
    ) -> Result<RunInfo> {
        let info = simulate::method(&settings.method)?;
        if info.adaptive {
            return self.run_adaptive(s0, settings, user, keep_going, sink);
        }
        let dt = settings.dt.ok_or_else(|| {
            KreiselError::invalid("dt", f64::NAN, "a fixed-step method needs dt > 0")
        })?;
        let te = settings.t_eval.as_deref();
        let t_end = settings.t_end;
        let out = match info.name {
            "rk4" => {
                let sys = Driven::<false, false> {
                    top: self,
                    energy: 0.0,
                };
                let sch = Rk4Scheme::<_, DIM> { sys: &sys };
                let rec = |t: f64, y: &([f64; DIM], f64)| {
                    sink(
                        t,
                        &DrivenRow {
                            t,
                            y: y.0,
                            stuck: false,
                        },
                    )
                };
                (
                    fixed::run(&sch, (pack9(s0), 0.0), t_end, dt, te, rec, keep_going)?,
                    4,
                )
            }
            "midpoint" | "gauss4" => {
                let sys = Driven::<true, false> {
                    top: self,
                    energy: 0.0,
                };
                let mut y0 = pack9(s0);
                y0[4..7].copy_from_slice(&self.top.momentum(s0.omega));
                let top = &self.top;
                let rec = |t: f64, y: &([f64; DIM], f64)| {
                    let mut r = y.0;
                    let n = Quat([r[0], r[1], r[2], r[3]]).normalized();
                    r[..4].copy_from_slice(&n.0);
                    let w = top.omega([r[4], r[5], r[6]]);
                    r[4..7].copy_from_slice(&w);
                    sink(
                        t,
                        &DrivenRow {
                            t,
                            y: r,
                            stuck: false,
                        },
                    )
                };
                if info.name == "midpoint" {
                    let sch = Midpoint::<_, DIM> { sys: &sys };
                    (
                        fixed::run(&sch, (y0, 0.0), t_end, dt, te, rec, keep_going)?,
                        0,
                    )
                } else {
                    let sch = Gauss4::<_, DIM> { sys: &sys };
                    (
                        fixed::run(&sch, (y0, 0.0), t_end, dt, te, rec, keep_going)?,
                        0,
                    )
                }
            }
            _ => {
                let sch = DrivenSplitting::new(self, info.order)?;
                let y0 = sch.encode(s0);
                let rec = |t: f64, y: &SplitY| sink(t, &sch.decode(t, y));
                (fixed::run(&sch, y0, t_end, dt, te, rec, keep_going)?, 0)
            }
        };
        let (run, per_step) = out;
        fixed_info(run, per_step)
    }

    fn summary<'a>(&'a self, s0: &RigidState, _settings: &Settings) -> DrivenAcc<'a> {
        DrivenAcc::new(self, s0)
    }

    type Columns = DrivenColumns;

    fn column_names(&self) -> Vec<&'static str> {
        DRIVEN_COLUMNS.to_vec()
    }

    fn columns(&self, rows: &[DrivenRow]) -> DrivenColumns {
        DrivenTop::columns(self, rows)
    }
}

impl DrivenTop {
    /// The adaptive run (DOP853), phase by phase where dry friction sticks and slips.
    fn run_adaptive(
        &self,
        s0: &RigidState,
        settings: &Settings,
        user: &mut [UserFn<'_, RigidState>],
        keep_going: &mut dyn FnMut(f64) -> bool,
        sink: Sink<'_, DrivenRow>,
    ) -> Result<RunInfo> {
        let integrator = settings.dop853();
        let t_end = settings.t_end;
        let dry = self.kdry > 0.0;
        // The rate below which a turning top counts as at rest relative to the pivot.
        let w_rest = 1e-9 * self.rate_scale(s0);
        let energy = self.energy_scale(s0);
        let mut y = pack9(s0);
        let mut t = 0.0;
        let mut phase = if dry && norm(s0.omega) == 0.0 && self.stick_margin(0.0, s0.q) <= 0.0 {
            Phase::Stuck
        } else {
            Phase::Turning
        };
        let mut stats = Stats::default();
        let mut events = Vec::new();
        let mut taken = 0usize;
        let mut first = true;
        let status = loop {
            let stuck = phase == Phase::Stuck;
            let mut out = |ti: f64, yy: &[f64; DIM]| {
                sink(
                    ti,
                    &DrivenRow {
                        t: ti,
                        y: *yy,
                        stuck,
                    },
                )
            };
            let mut stream = Stream::new(
                settings.t_eval.as_deref(),
                !first,
                Some(&mut *keep_going),
                &mut out,
            );
            stream.taken = taken;
            let mut fns = event_fns(settings, &mut *user, &state_of)?;
            let n_user = fns.len();
            if dry {
                fns.push(match phase {
                    Phase::Stuck => {
                        Box::new(|tt: f64, yy: &[f64; DIM]| self.stick_margin(tt, state_of(yy).q))
                    }
                    Phase::Turning => Box::new(move |_t: f64, yy: &[f64; DIM]| {
                        norm([yy[4], yy[5], yy[6]]) - w_rest
                    }),
                    Phase::Passing => Box::new(move |_t: f64, yy: &[f64; DIM]| {
                        norm([yy[4], yy[5], yy[6]]) - 2.0 * w_rest
                    }),
                });
            }
            let mut locator = Locator::new();
            for (i, f) in fns.iter_mut().enumerate() {
                let spec = if i < n_user {
                    let e = &settings.events[i];
                    EventSpec::new(e.direction, e.terminal)
                } else {
                    EventSpec::new(if phase == Phase::Turning { -1 } else { 1 }, true)
                };
                locator.add(spec, f.as_mut());
            }
            let mut obs = WithEvents::new(locator, &mut stream);
            // A sampled path is a piecewise polynomial: its breakpoints end the integrator's
            // segments, so that no step straddles a jump of its higher derivatives.
            let seg_end = self
                .pivot
                .next_break(t + self.t0)
                .map_or(t_end, |b| (b - self.t0).min(t_end));
            let result = if stuck {
                let sys = Driven::<false, true> { top: self, energy };
                integrator.integrate(&sys, t, y, seg_end, &mut obs)
            } else {
                let sys = Driven::<false, false> { top: self, energy };
                integrator.integrate(&sys, t, y, seg_end, &mut obs)
            };
            let (t1, y1, st) = result.map_err(|e| integrate_error(e, t_end))?;
            stats += st;
            let mut switched = false;
            let mut terminal = false;
            for e in &obs.locator.events {
                if e.index >= n_user {
                    switched = true;
                    continue;
                }
                terminal |= settings.events[e.index].terminal;
                events.push(EventRecord {
                    index: Some(e.index),
                    name: settings.events[e.index].name.clone().into(),
                    t: e.t,
                    part: None,
                });
            }
            drop(obs);
            taken = stream.taken;
            if terminal {
                break Status::Event;
            }
            if !switched {
                if t1 < seg_end {
                    break Status::Interrupted;
                }
                if seg_end >= t_end {
                    break Status::Completed;
                }
                // the next piece of the pivot's path, in the same phase
                t = t1;
                y = y1;
                first = false;
                continue;
            }
            t = t1;
            y = y1;
            first = false;
            phase = match phase {
                Phase::Stuck | Phase::Passing => Phase::Turning,
                Phase::Turning => {
                    let s = state_of(&y);
                    if self.stick_margin(t, s.q) <= 0.0 {
                        // Held: the friction's impulse takes the rest of the rotation relative
                        // to the pivot, its kinetic energy (1/2 w.I w, of the order of
                        // w_rest^2) dissipated; the pivot's impulse, which stops the centre of
                        // mass's motion relative to the pivot, m w x r_G, does the work
                        // -m v_O . (w x r_G). E + D - W stays what it was.
                        let k = self.pivot.kin(t + self.t0);
                        let w = s.omega;
                        let v_b = self.in_body(s.q, s.q.up_in_body(), &k).1;
                        y[8] += 0.5 * dot(w, self.top.momentum(w));
                        y[7] -= self.top.m() * dot(v_b, cross(w, self.top.com()));
                        y[4..7].fill(0.0);
                        Phase::Stuck
                    } else {
                        Phase::Passing
                    }
                }
            };
            if t >= t_end {
                break Status::Completed;
            }
        };
        Ok(RunInfo {
            stats,
            events,
            status,
        })
    }
}

/// The splittings' state for a driven top: the splitting's own, the time t and its
/// conjugate momentum p_t (extended phase space), and `E_lab - H` at the start.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SplitY {
    qm: SplitQM,
    t: f64,
    pt: f64,
    lag0: f64,
}

/// The splittings of [`Splitting`] on a moving pivot, undamped: in extended phase space the
/// Hamiltonian `K = T(M) + V(q, t) + p_t`, `V = m (g e_z + a_O(t)) . r_G`, splits into the
/// free rotation with `p_t` (which also advances the time) and the kick of V at frozen time
/// (M takes the torque's impulse, `p_t` takes `-h dV/dt = -h m j_O(t) . r_G`, j the pivot's
/// jerk), both exact, so every composition stays symplectic and keeps `H + p_t` to its
/// order. The pivot's work follows from it: along the motion `dE/dt = R . v_O` and
/// `d(H + p_t)/dt = 0`, so `W = (E - H)(t) - (E - H)(0) - (p_t(t) - p_t(0))`, and the drift of
/// `E - W` is that of `H + p_t`: the method's own error, at its order. Mz is restored after
/// each step only where the pivot moves vertically.
pub struct DrivenSplitting<'a> {
    top: &'a DrivenTop,
    split: Splitting<'a>,
}

impl<'a> DrivenSplitting<'a> {
    fn new(top: &'a DrivenTop, order: u32) -> Result<Self> {
        Ok(DrivenSplitting {
            top,
            split: Splitting::new(&top.top, order)?,
        })
    }

    fn encode(&self, s: &RigidState) -> SplitY {
        SplitY {
            qm: self.split.encode(s),
            t: 0.0,
            pt: 0.0,
            lag0: self.top.energy(0.0, s) - self.top.pivot_frame_energy(0.0, s),
        }
    }

    fn decode(&self, t: f64, y: &SplitY) -> DrivenRow {
        let s = self.split.decode(&y.qm);
        let mut r = pack9(&s);
        let lag = self.top.energy(t, &s) - self.top.pivot_frame_energy(t, &s);
        r[7] = lag - y.lag0 - y.pt;
        DrivenRow {
            t,
            y: r,
            stuck: false,
        }
    }

    #[inline(always)]
    fn kick(&self, y: &mut SplitY, t: f64, h: f64) {
        let tt = t + self.top.t0;
        // A composition's inner stages may step before the run's start (Yoshida's negative
        // weights): a path that starts there is continued smoothly, not held at rest.
        let (k, jerk) = match &self.top.pivot {
            Pivot::Path(p) => p.continued(tt),
            other => (other.kin(tt), other.jerk(tt)),
        };
        let ge = self.top.effective_gravity(y.qm.q, &k);
        let c = self.top.top.com();
        let tq = cross(ge, c);
        let m = self.top.top.m();
        for (mi, ti) in y.qm.m.iter_mut().zip(tq) {
            *mi += h * m * ti;
        }
        y.pt -= h * m * dot(jerk, y.qm.q.rotate(c));
    }
}

impl FixedScheme for DrivenSplitting<'_> {
    type Y = SplitY;
    fn step(&self, y: &mut SplitY, h: f64) -> Result<()> {
        let t0 = y.t;
        self.split
            .compose(y, h, |y| &mut y.qm, |y, tau, dt| self.kick(y, t0 + tau, dt));
        y.t = t0 + h;
        if self.top.vertical {
            self.split.restore_mz(&mut y.qm);
        } else {
            y.qm.mz = dot(y.qm.m, y.qm.q.up_in_body());
        }
        if !(y.qm.m.iter().all(|x| x.is_finite()) && y.qm.q.0.iter().all(|x| x.is_finite())) {
            return Err(KreiselError::Numerical(format!(
                "splitting: the state became non-finite at t = {}",
                y.t
            )));
        }
        Ok(())
    }
}

/// The names of a driven top's diagnostics columns.
pub const DRIVEN_COLUMNS: [&str; 15] = [
    "theta",
    "phi",
    "psi",
    "energy",
    "potential",
    "Mz",
    "pivot_position",
    "pivot_velocity",
    "reaction_force",
    "power_pivot",
    "power_dissipated",
    "work_by_pivot",
    "dissipated",
    "balance",
    "stuck",
];

/// Diagnostics of a driven top's run, as columns.
#[derive(Debug, Clone, Default)]
pub struct DrivenColumns {
    /// Nutation angle (rad).
    pub theta: Vec<f64>,
    /// Precession angle, unwrapped (rad).
    pub phi: Vec<f64>,
    /// Spin angle, unwrapped (rad).
    pub psi: Vec<f64>,
    /// Lab-frame energy (J).
    pub energy: Vec<f64>,
    /// m g z_G (J).
    pub potential: Vec<f64>,
    /// Vertical angular momentum about the pivot (kg m^2/s).
    pub mz: Vec<f64>,
    /// Pivot position (m).
    pub pivot_position: Vec<[f64; 3]>,
    /// Pivot velocity (m/s).
    pub pivot_velocity: Vec<[f64; 3]>,
    /// The pivot's force on the top, space frame (N).
    pub reaction_force: Vec<[f64; 3]>,
    /// R . v_O (W).
    pub power_pivot: Vec<f64>,
    /// Power dissipated at the pivot (W).
    pub power_dissipated: Vec<f64>,
    /// Work done by the pivot since the start (J).
    pub work_by_pivot: Vec<f64>,
    /// Energy dissipated since the start (J).
    pub dissipated: Vec<f64>,
    /// energy + dissipated - work_by_pivot (J): constant.
    pub balance: Vec<f64>,
    /// Held by dry friction.
    pub stuck: Vec<bool>,
}

impl DrivenTop {
    /// The diagnostics of every row.
    pub fn columns(&self, rows: &[DrivenRow]) -> DrivenColumns {
        let n = rows.len();
        let mut c = DrivenColumns::default();
        c.theta.reserve(n);
        let mut angles = Unwrapped::default();
        let (m, g) = (self.top.m(), self.top.g());
        for r in rows {
            let s = r.state();
            let (phi, theta, psi) = euler_from_quaternion(s.q);
            let (phi, psi) = angles.next(phi, psi);
            c.theta.push(theta);
            c.phi.push(phi);
            c.psi.push(psi);
            let k = self.pivot.kin(r.t + self.t0);
            let e = self.energy(r.t, &s);
            c.energy.push(e);
            c.potential
                .push(m * g * (k.p[2] + dot(self.top.com(), s.q.up_in_body())));
            c.mz.push(self.top.mz(&s));
            c.pivot_position.push(k.p);
            c.pivot_velocity.push(k.v);
            let (force, pp, pd) = self.forces(r.t, &s, r.stuck);
            c.reaction_force.push(force);
            c.power_pivot.push(pp);
            c.power_dissipated.push(pd);
            c.work_by_pivot.push(r.y[7]);
            c.dissipated.push(r.y[8]);
            c.balance.push(e + r.y[8] - r.y[7]);
            c.stuck.push(r.stuck);
        }
        c
    }
}

/// The running summary of a driven top's run: the heavy top's summary, with
/// `energy_drift` the drift of `E + D - W`, and Mz's and M3's drifts where they are kept.
pub struct DrivenAcc<'a> {
    top: &'a DrivenTop,
    b0: f64,
    mz0: f64,
    m30: Option<f64>,
    m_norm: f64,
    e_scale: f64,
    theta: f64,
    th_min: f64,
    th_max: f64,
    db: f64,
    dmz: f64,
    dm3: f64,
    mz_kept: bool,
}

impl<'a> DrivenAcc<'a> {
    fn new(top: &'a DrivenTop, s0: &RigidState) -> Self {
        let mom = top.top.momentum(s0.omega);
        let undamped = top.hamiltonian();
        // M3 is kept by an axial top (no torque about its axis from any force at G) and by a
        // symmetric top on a vertically moving pivot, when undamped.
        let m3 = top
            .top
            .m3(s0)
            .filter(|_| undamped && (top.top.axial() || top.pivot.vertical()));
        DrivenAcc {
            top,
            b0: top.energy(0.0, s0),
            mz0: top.top.mz(s0),
            m30: m3,
            m_norm: norm(mom),
            e_scale: top.energy_scale(s0),
            theta: f64::NAN,
            th_min: f64::INFINITY,
            th_max: f64::NEG_INFINITY,
            db: 0.0,
            dmz: 0.0,
            dm3: 0.0,
            mz_kept: undamped && top.pivot.vertical(),
        }
    }
}

impl Accumulate<DrivenRow> for DrivenAcc<'_> {
    type Summary = HeavySummary;

    fn push(&mut self, _t: f64, r: &DrivenRow) {
        let s = r.state();
        self.theta = euler_from_quaternion(s.q).1;
        self.th_min = self.th_min.min(self.theta);
        self.th_max = self.th_max.max(self.theta);
        let b = self.top.energy(r.t, &s) + r.y[8] - r.y[7];
        self.db = self.db.max((b - self.b0).abs());
        self.dmz = self.dmz.max((self.top.top.mz(&s) - self.mz0).abs());
        if let Some(a) = self.m30 {
            let m3 = self.top.top.inertia()[2] * s.omega[2];
            self.dm3 = self.dm3.max((m3 - a).abs());
        }
    }

    fn finish(self, info: &RunInfo) -> HeavySummary {
        HeavySummary {
            final_theta: self.theta,
            theta_min: self.th_min,
            theta_max: self.th_max,
            energy_drift: relative(self.db, self.e_scale),
            mz_drift: if self.mz_kept {
                relative(self.dmz, self.m_norm)
            } else {
                f64::NAN
            },
            m3_drift: self
                .m30
                .map_or(f64::NAN, |_| relative(self.dm3, self.m_norm)),
            kovalevskaya_drift: f64::NAN,
            steps: info.stats.steps,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotation::quaternion_from_euler;

    fn lagrange() -> HeavyTop {
        HeavyTop::new(1.0, 1.0, 0.5, 1.0, [0.0, 0.0, 1.0], 1.0).unwrap()
    }

    fn run(top: &DrivenTop, s0: &RigidState, t_end: f64) -> Vec<DrivenRow> {
        let st = Settings {
            method: "dop853".into(),
            t_end,
            rtol: 1e-11,
            atol: 1e-13,
            ..Settings::default()
        };
        simulate::simulate(top, s0, &st, &mut [], &mut |_| true)
            .unwrap()
            .rows
    }

    #[test]
    fn balance_holds_on_a_shaken_damped_top() {
        let top = HeavyTop::new(1.0, 0.8, 0.5, 1.0, [0.1, 0.05, 0.6], 1.0).unwrap();
        let pivot = Pivot::harmonic([0.03, -0.02, 0.05], 20.0, [0.3, 1.2, 0.0]).unwrap();
        let d = DrivenTop::new(top, pivot, Damping::new(0.01, 0.005, 0.0, 0.0).unwrap()).unwrap();
        let s0 = RigidState::new(quaternion_from_euler(0.2, 0.7, 0.1).0, [0.5, -0.3, 3.0]).unwrap();
        let rows = run(&d, &s0, 5.0);
        let c = d.columns(&rows);
        let b0 = c.balance[0];
        let worst = c.balance.iter().map(|b| (b - b0).abs()).fold(0.0, f64::max);
        assert!(worst < 1e-8, "balance drift {worst}");
        assert!(c.dissipated.last().unwrap() > &0.0);
        assert!(c.power_dissipated.iter().all(|&p| p >= 0.0));
    }

    #[test]
    fn viscous_spin_decays_exponentially() {
        let pivot = Pivot::harmonic([0.0, 0.02, 0.04], 15.0, [0.0; 3]).unwrap();
        let d = DrivenTop::new(
            lagrange(),
            pivot,
            Damping::new(0.02, 0.0, 0.0, 0.0).unwrap(),
        )
        .unwrap();
        let s0 = RigidState::new(quaternion_from_euler(0.0, 0.4, 0.0).0, [0.1, 0.0, 8.0]).unwrap();
        let rows = run(&d, &s0, 3.0);
        for r in &rows {
            let want = 8.0 * (-0.02 * r.t / 0.5f64).exp();
            assert!((r.y[6] - want).abs() < 1e-9 * 8.0, "{} {}", r.y[6], want);
        }
    }

    #[test]
    fn dry_friction_holds_a_hanging_top_and_stops_a_swinging_one() {
        // A pendulum-like top (com below the pivot) released at 0.3 rad: swings, stops.
        let top = HeavyTop::new(1.0, 1.0, 0.5, 1.0, [0.0, 0.0, -0.8], 9.81).unwrap();
        let damp = Damping::new(0.0, 0.0, 0.5, 0.1).unwrap();
        let d = DrivenTop::new(top, Pivot::Fixed, damp).unwrap();
        let s0 = RigidState::new(quaternion_from_euler(0.0, 0.3, 0.0).0, [0.0; 3]).unwrap();
        let rows = run(&d, &s0, 20.0);
        let c = d.columns(&rows);
        assert!(*c.stuck.last().unwrap(), "the top never came to rest");
        let b0 = c.balance[0];
        let worst = c.balance.iter().map(|b| (b - b0).abs()).fold(0.0, f64::max);
        assert!(worst < 1e-8, "balance drift {worst}");
        // At rest within the friction circle: |c| sin(tilt from down) <= mu r_p.
        let s = rows.last().unwrap().state();
        assert!(d.stick_margin(rows.last().unwrap().t, s.q) <= 1e-12);
        // Released inside the circle, it never moves.
        let s1 = RigidState::new(quaternion_from_euler(0.0, 0.05, 0.0).0, [0.0; 3]).unwrap();
        let rows = run(&d, &s1, 2.0);
        assert!(rows.iter().all(|r| r.stuck && r.y[..7] == rows[0].y[..7]));
    }

    #[test]
    fn painleve_joints_are_refused() {
        let e = DrivenTop::new(
            lagrange(),
            Pivot::Fixed,
            Damping::new(0.0, 0.0, 2.0, 1.0).unwrap(),
        )
        .unwrap_err();
        assert!(e.to_string().starts_with("dry = 2"), "{e}");
    }

    #[test]
    fn path_is_evaluated_with_its_derivatives() {
        // One interval: p(t) = t^5 + 2 t^2 in x, 3 in z (coefficients highest first, of
        // t^7 .. t^0).
        let mut coef = vec![0.0; 24];
        coef[2 * 3] = 1.0; // t^5, x
        coef[5 * 3] = 2.0; // t^2, x
        coef[7 * 3 + 2] = 3.0; // t^0, z
        let p = PathSpline::new(vec![0.0, 1.0], &coef).unwrap();
        let k = p.kin(0.5);
        assert!((k.p[0] - (0.5f64.powi(5) + 0.5)).abs() < 1e-15);
        assert!((k.v[0] - (5.0 * 0.5f64.powi(4) + 2.0)).abs() < 1e-15);
        assert!((k.a[0] - (20.0 * 0.5f64.powi(3) + 4.0)).abs() < 1e-15);
        assert_eq!(k.p[2], 3.0);
        assert!((p.jerk(0.5)[0] - 60.0 * 0.25).abs() < 1e-14);
        let after = p.kin(2.0);
        assert_eq!(after.v, [0.0; 3]);
        assert!((after.p[0] - 3.0).abs() < 1e-15);
        assert!(PathSpline::new(vec![0.0, 0.0], &coef).is_err());
    }
}
