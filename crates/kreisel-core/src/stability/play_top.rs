//! The play top's stationary motions, their stability, and the (alpha, gamma) atlas.
//!
//! Conventions of theory: play top: `alpha = s/rho`, `gamma = A/C`, `u = cos
//! theta` (u = 1 upright), `J_beta = rho sqrt(C m g s)`, `N(u) = (alpha + u)^2 + gamma (1 -
//! u^2)`, `D(u) = alpha + (1 - gamma) u`. Source:
//! Rauch-Wojciechowski, Skoldstam and Glad, Regul. Chaotic Dyn. 10 (2005) 333 (regular
//! precession, stability of stationary motions, the division of the alpha-gamma plane).
//!
//! Derivations (checked here, and against a numerical minimisation in the Python tests):
//!
//! - At fixed Jellett integral J and inclination u, the energy is least when G is at rest
//!   and the top turns about GT: with `b = s e3 + rho ez`, minimising `omega.I omega / 2`
//!   subject to `omega.I b = J` gives `omega = lambda b`, `lambda = J / (b.I b)`, and
//!   `b.I b = rho^2 C N(u)`. So `V(u) = J^2 / (2 rho^2 C N(u)) + m g (rho + s u)` and every
//!   state has `E >= V(u)`. Writing `omega = Omega (ez + alpha e3)` gives
//!   `Omega = J / (rho C N(u))`, `psidot = alpha Omega`, `omega3 = Omega (u + alpha)`.
//! - `N' = 2 D`, so `V'(u) = m g s - J^2 D / (rho^2 C N^2) = m g s (1 - J^2 / J_R(u)^2)`
//!   where `D > 0`: the interior stationary points are the regular precessions,
//!   `|J| = J_R(u) = J_beta N / sqrt(D)`, and there `V'' = 2 m g s J_R' / J_R`. The same
//!   `Omega^2 = m g s / (C D)` follows from `dL/dt = Omega ez x L = a x (m g ez)`.
//! - `J_R'/J_R = (4 D^2 - (1 - gamma) N) / (2 N D)` and
//!   `4 D^2 - (1 - gamma) N = 3 D^2 - gamma (1 - alpha^2 - gamma)`: J_R is increasing
//!   wherever it is real if `gamma >= 1 - alpha^2`; otherwise its one minimum on the real
//!   line is where `D(u_m) = sqrt(gamma (1 - alpha^2 - gamma) / 3)`.
//! - At the vertical the energy as a function of theta has `E_thth = -u V'(u)`: the upright
//!   spin is a minimum iff `V'(1) < 0`, the hanging one iff `V'(-1) > 0` (the table of the
//!   notes).

use crate::error::{finite, KreiselError, Result};
use crate::models::play_top::{PlayTop, DIM};
use crate::rotation::{cross, Quat};
use crate::special::cubic::Poly3;
use crate::special::elliptic::ellipk_m1;
use crate::special::jacobi;

/// The stationary-motion theory of one play top: the top itself, with the theory's own
/// conditions checked (s > 0, g > 0); its friction law plays no part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlayStability {
    top: PlayTop,
}

/// The kinds of stationary motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StationaryKind {
    /// Spin about the vertical figure axis, G above Z (u = 1).
    Upright,
    /// Spin about the vertical figure axis, G below Z (u = -1).
    Hanging,
    /// Regular precession rolling without slip, G at rest (-1 < u < 1).
    Precession,
}

impl StationaryKind {
    /// The public name.
    pub fn name(&self) -> &'static str {
        match self {
            StationaryKind::Upright => "upright",
            StationaryKind::Hanging => "hanging",
            StationaryKind::Precession => "precession",
        }
    }
}

/// A regular precession (rolling without slip, G at rest).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RegularPrecession {
    /// Inclination u = cos(theta).
    pub u: f64,
    /// Precession rate about the vertical (rad/s), > 0.
    pub omega: f64,
    /// Axial spin omega . e3 (rad/s).
    pub omega3: f64,
    /// Spin rate psidot (rad/s).
    pub psi_dot: f64,
    /// Jellett's integral (kg m^2/s), = J_R(u).
    pub j: f64,
}

/// A stationary motion at a given Jellett integral.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StationaryMotion {
    /// Its kind.
    pub kind: StationaryKind,
    /// Inclination u = cos(theta).
    pub u: f64,
    /// A minimum of the energy V at fixed J.
    pub stable: bool,
    /// Rate about the vertical in `omega = Omega (ez + alpha e3)` (rad/s), signed as J.
    pub omega: f64,
    /// Axial spin (rad/s).
    pub omega3: f64,
    /// Energy V(u) (J).
    pub energy: f64,
}

/// The top types of the atlas (theory: the atlas of play tops).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TopType {
    /// 1 - alpha^2 <= gamma < 1 + alpha.
    Ia,
    /// gamma >= 1 + alpha.
    Ib,
    /// 1 - alpha < gamma < 1 - alpha^2.
    IIa,
    /// gamma <= 1 - alpha (and gamma < 1 - alpha^2).
    IIb,
}

impl TopType {
    /// The public name.
    pub fn name(&self) -> &'static str {
        match self {
            TopType::Ia => "Ia",
            TopType::Ib => "Ib",
            TopType::IIa => "IIa",
            TopType::IIb => "IIb",
        }
    }
}

/// Where a top lies in the (alpha, gamma) plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Classification {
    /// Type Ia, Ib, IIa or IIb.
    pub top_type: TopType,
    /// Zone 1..8 (theory: play top).
    pub zone: u8,
    /// Area of the vertical-axis diagram (theory: the atlas of play tops): 'a', 'b' or 'c'.
    pub fig3: char,
}

/// The stationary motions open to a state and where it must end.
#[derive(Debug, Clone, PartialEq)]
pub struct Prediction {
    /// The state's Jellett integral.
    pub j: f64,
    /// Every stable stationary motion at this J, by ascending u.
    pub stable: Vec<StationaryMotion>,
    /// The stable motions the state can reach: those in the connected part of
    /// `{u : V(u) <= E}` that holds the state's u.
    pub reachable: Vec<StationaryMotion>,
    /// The one reachable stable motion, if there is exactly one.
    pub ending: Option<StationaryMotion>,
}

fn check_alpha_gamma(alpha: f64, gamma: f64) -> Result<()> {
    // Both are ratios of a top's parameters: say which, so a message about a top's
    // classification names what the user gave (s = 0 makes alpha = 0).
    if !(alpha.is_finite() && alpha > 0.0) {
        return Err(KreiselError::invalid(
            "alpha",
            alpha,
            "alpha = s/rho must be > 0: the classification is of tops whose centre of mass \
             lies off the centre of the tip sphere (s > 0)",
        ));
    }
    if !(gamma.is_finite() && gamma > 0.0) {
        return Err(KreiselError::invalid(
            "gamma",
            gamma,
            "gamma = A/C must be a finite number > 0",
        ));
    }
    Ok(())
}

/// u_m, the minimum of J_R on the real line; it exists only for `gamma < 1 - alpha^2`.
pub fn u_min(alpha: f64, gamma: f64) -> Option<f64> {
    let k = 1.0 - alpha * alpha - gamma;
    if k > 0.0 {
        let dm = (gamma * k / 3.0).sqrt();
        Some((dm - alpha) / (1.0 - gamma))
    } else {
        None
    }
}

/// `sign(J_R(-1) - J_R(1))` through `(1-alpha)^4 D(1) - (1+alpha)^4 D(-1)` (both D > 0).
fn ends_difference(alpha: f64, gamma: f64) -> f64 {
    (1.0 - alpha).powi(4) * (1.0 + alpha - gamma) - (1.0 + alpha).powi(4) * (alpha + gamma - 1.0)
}

/// Classifies a top by `alpha = s/rho > 0` and `gamma = A/C > 0` (theory: play top;
/// the atlas of play tops).
pub fn classify(alpha: f64, gamma: f64) -> Result<Classification> {
    check_alpha_gamma(alpha, gamma)?;
    let fig3 = if gamma >= 1.0 + alpha {
        'a'
    } else if gamma <= 1.0 - alpha {
        'b'
    } else {
        'c'
    };
    let (top_type, zone) = match u_min(alpha, gamma) {
        None if gamma < 1.0 + alpha => (TopType::Ia, 1),
        None => (TopType::Ib, 2),
        Some(um) if gamma > 1.0 - alpha => {
            let zone = if um > 1.0 {
                3
            } else if um < -1.0 {
                6
            } else if ends_difference(alpha, gamma) > 0.0 {
                4
            } else {
                5
            };
            (TopType::IIa, zone)
        }
        Some(um) => (TopType::IIb, if um > 1.0 { 8 } else { 7 }),
    };
    Ok(Classification {
        top_type,
        zone,
        fig3,
    })
}

/// The curves that bound the zones, as gamma(alpha) (NaN where a curve does not exist):
/// `u_m = 1` (two branches, lower and upper; they close at alpha = 7 - 4 sqrt(3)),
/// `u_m = -1`, and `J_R(1) = J_R(-1)` (the last two restricted to type IIa).
///
/// From `3 D(+-1)^2 = gamma (1 - alpha^2 - gamma)`:
/// `4 gamma^2 - (1 +- alpha)(7 -+ alpha) gamma + 3 (1 +- alpha)^2 = 0`; from
/// `(1 - alpha)^4 D(1) = (1 + alpha)^4 D(-1)`:
/// `gamma = (1 - alpha^2)(1 + 3 alpha^2) / (1 + 6 alpha^2 + alpha^4)`.
pub fn zone_boundaries(alpha: f64) -> [f64; 4] {
    let nan = f64::NAN;
    let (p, q) = (1.0 + alpha, 1.0 - alpha);
    let disc_p = (7.0 - alpha).powi(2) - 48.0;
    let (up_lo, up_hi) = if disc_p >= 0.0 {
        let r = disc_p.sqrt();
        // The smaller root without cancellation: product of roots = 3 p^2 / 4.
        let hi = p * ((7.0 - alpha) + r) / 8.0;
        (3.0 * p * p / (4.0 * hi), hi)
    } else {
        (nan, nan)
    };
    let disc_m = (7.0 + alpha).powi(2) - 48.0;
    let lower = |g: f64| g > q && g < 1.0 - alpha * alpha;
    let um_minus = q * ((7.0 + alpha) + disc_m.sqrt()) / 8.0;
    let um_minus = if lower(um_minus) { um_minus } else { nan };
    let a2 = alpha * alpha;
    let eq = (1.0 - a2) * (1.0 + 3.0 * a2) / (1.0 + 6.0 * a2 + a2 * a2);
    let eq = if lower(eq) { eq } else { nan };
    [up_lo, up_hi, um_minus, eq]
}

impl PlayStability {
    /// The theory of a play top (checked when it was made): it needs `s > 0` and `g > 0`
    /// (with s = 0 or g = 0 there is no torque and J_beta = 0).
    pub fn new(top: &PlayTop) -> Result<Self> {
        if top.s <= 0.0 {
            return Err(KreiselError::invalid(
                "s",
                top.s,
                "the stationary-motion theory needs s > 0 (with G at the sphere's centre \
                 gravity exerts no torque and J_beta = 0)",
            ));
        }
        if top.g <= 0.0 {
            return Err(KreiselError::invalid(
                "g",
                top.g,
                "the stationary-motion theory needs g > 0 (J_beta = rho sqrt(C m g s))",
            ));
        }
        Ok(PlayStability { top: *top })
    }

    /// The top whose theory this is.
    pub fn top(&self) -> &PlayTop {
        &self.top
    }

    /// s / rho.
    pub fn alpha(&self) -> f64 {
        self.top.s / self.top.rho
    }
    /// A / C.
    pub fn gamma(&self) -> f64 {
        self.top.a / self.top.c
    }
    /// J_beta = rho sqrt(C m g s) (kg m^2/s).
    pub fn j_beta(&self) -> f64 {
        self.top.rho * (self.top.c * self.top.m * self.top.g * self.top.s).sqrt()
    }
    fn mgs(&self) -> f64 {
        self.top.m * self.top.g * self.top.s
    }

    /// N(u) = (alpha + u)^2 + gamma (1 - u^2).
    pub fn n(&self, u: f64) -> f64 {
        let (al, ga) = (self.alpha(), self.gamma());
        (al + u) * (al + u) + ga * (1.0 - u) * (1.0 + u)
    }
    /// D(u) = alpha + (1 - gamma) u.
    pub fn d(&self, u: f64) -> f64 {
        self.alpha() + (1.0 - self.gamma()) * u
    }

    /// J_R(u) = J_beta N(u) / sqrt(D(u)) on the real line; NaN where D(u) <= 0.
    pub fn j_r(&self, u: f64) -> f64 {
        let d = self.d(u);
        if d > 0.0 {
            self.j_beta() * self.n(u) / d.sqrt()
        } else {
            f64::NAN
        }
    }

    /// J_R(u) for an inclination `u = cos(theta)` in [-1, 1] (an error outside, or for a
    /// non-finite u); NaN where no regular precession exists there (D(u) <= 0).
    pub fn j_r_at(&self, u: f64) -> Result<f64> {
        if !(-1.0..=1.0).contains(&u) {
            return Err(KreiselError::invalid(
                "u",
                u,
                "u = cos(theta) must lie in [-1, 1]",
            ));
        }
        Ok(self.j_r(u))
    }

    /// dJ_R/du; NaN where D(u) <= 0.
    pub fn j_r_prime(&self, u: f64) -> f64 {
        let d = self.d(u);
        if d > 0.0 {
            let p = 3.0 * d * d - self.gamma() * (1.0 - self.alpha().powi(2) - self.gamma());
            self.j_beta() * p / (2.0 * d * d.sqrt())
        } else {
            f64::NAN
        }
    }

    /// u_m: the minimum of J_R on the real line (None for type I tops).
    pub fn u_m(&self) -> Option<f64> {
        u_min(self.alpha(), self.gamma())
    }

    /// Where D > 0 within [-1, 1]: (lo, hi), lo < hi, or None.
    fn precession_range(&self) -> Option<(f64, f64)> {
        let (al, k) = (self.alpha(), 1.0 - self.gamma());
        let (mut lo, mut hi) = (-1.0f64, 1.0f64);
        if k > 0.0 {
            lo = lo.max(-al / k);
        } else if k < 0.0 {
            hi = hi.min(al / -k);
        }
        (lo < hi).then_some((lo, hi))
    }

    /// The regular precession at inclination `u` (J > 0 convention), or an error where none
    /// exists (|u| > 1 or D(u) <= 0).
    pub fn regular_precession(&self, u: f64) -> Result<RegularPrecession> {
        finite("u", u)?;
        if !(-1.0..=1.0).contains(&u) {
            return Err(KreiselError::invalid(
                "u",
                u,
                "u = cos(theta) must lie in [-1, 1]",
            ));
        }
        let d = self.d(u);
        if d <= 0.0 {
            let edge = self.alpha() / (self.gamma() - 1.0);
            let side = if self.gamma() > 1.0 { "below" } else { "above" };
            return Err(KreiselError::invalid(
                "u",
                u,
                format!(
                    "no regular precession exists there: alpha + (1 - gamma) u = {d} <= 0 \
                     (alpha = {}, gamma = {}); this top precesses only {side} u = {edge}",
                    self.alpha(),
                    self.gamma()
                ),
            ));
        }
        let omega = (self.mgs() / (self.top.c * d)).sqrt();
        Ok(RegularPrecession {
            u,
            omega,
            omega3: omega * (u + self.alpha()),
            psi_dot: self.alpha() * omega,
            j: self.j_r(u),
        })
    }

    /// The energy of the stationary motions at Jellett integral `j`:
    /// `V(u) = J^2 / (2 rho^2 C N(u)) + m g (rho + s u)` (J). Infinite where N = 0 and J != 0
    /// (alpha = 1, u = -1: G sits at the contact point and no spin about it carries J).
    pub fn energy(&self, j: f64, u: f64) -> f64 {
        let pot = self.top.m * self.top.g * (self.top.rho + self.top.s * u);
        if j == 0.0 {
            return pot;
        }
        let n = self.n(u);
        if n <= 0.0 {
            return f64::INFINITY;
        }
        j * j / (2.0 * self.top.rho * self.top.rho * self.top.c * n) + pot
    }

    /// dV/du at fixed J: `m g s - J^2 D / (rho^2 C N^2)`.
    pub fn energy_du(&self, j: f64, u: f64) -> f64 {
        if j == 0.0 {
            return self.mgs();
        }
        let n = self.n(u);
        self.mgs() - j * j * self.d(u) / (self.top.rho * self.top.rho * self.top.c * n * n)
    }

    fn motion(&self, kind: StationaryKind, j: f64, u: f64, stable: bool) -> StationaryMotion {
        let n = self.n(u);
        let omega = if j == 0.0 {
            0.0
        } else {
            j / (self.top.rho * self.top.c * n)
        };
        StationaryMotion {
            kind,
            u,
            stable,
            omega,
            omega3: omega * (u + self.alpha()),
            energy: self.energy(j, u),
        }
    }

    /// The inclinations of the regular precessions with |J| = J_R(u), -1 < u < 1,
    /// ascending (0, 1 or 2 of them).
    pub fn precession_inclinations(&self, j: f64) -> Vec<f64> {
        let target = j.abs();
        let mut out = Vec::new();
        let Some((lo, hi)) = self.precession_range() else {
            return out;
        };
        if target == 0.0 {
            return out;
        }
        // J_R is monotone between these break points.
        let mut pts = vec![lo];
        if let Some(um) = self.u_m() {
            if um > lo && um < hi {
                pts.push(um);
            }
        }
        pts.push(hi);
        let f = |u: f64| {
            let v = self.j_r(u);
            // At an end where D = 0, J_R is +infinity.
            if v.is_nan() {
                f64::INFINITY
            } else {
                v - target
            }
        };
        let um = self.u_m();
        for w in pts.windows(2) {
            let (a, b) = (w[0], w[1]);
            let (fa, fb) = (f(a), f(b));
            if fa == 0.0 && Some(a) == um {
                out.push(a);
                continue;
            }
            if fa == 0.0 || fb == 0.0 || (fa > 0.0) == (fb > 0.0) {
                continue;
            }
            // Bisection to the last bit: J_R is monotone on [a, b].
            let (mut neg, mut pos) = if fa < 0.0 { (a, b) } else { (b, a) };
            for _ in 0..200 {
                let mid = 0.5 * (neg + pos);
                if mid == neg || mid == pos {
                    break;
                }
                if f(mid) < 0.0 {
                    neg = mid;
                } else {
                    pos = mid;
                }
            }
            let r = if f(neg).abs() <= f(pos).abs() {
                neg
            } else {
                pos
            };
            if r > -1.0 && r < 1.0 {
                out.push(r);
            }
        }
        out.sort_by(|x, y| x.partial_cmp(y).expect("finite"));
        out.dedup();
        out
    }

    /// Whether the regular precession at u is stable: dJ_R/du > 0 there, i.e.
    /// gamma >= 1 - alpha^2 or u > u_m.
    pub fn precession_stable(&self, u: f64) -> bool {
        match self.u_m() {
            None => true,
            Some(um) => u > um,
        }
    }

    /// Whether the upright spin at `j` is stable: gamma < 1 + alpha and |J| > J_R(1).
    pub fn upright_stable(&self, j: f64) -> bool {
        self.gamma() < 1.0 + self.alpha() && j.abs() > self.j_r(1.0)
    }

    /// Whether the hanging spin at `j` is stable: gamma <= 1 - alpha or |J| < J_R(-1)
    /// (at rest, J = 0, it is stable also when J_R(-1) = 0, alpha = 1).
    pub fn hanging_stable(&self, j: f64) -> bool {
        let (al, ga) = (self.alpha(), self.gamma());
        ga <= 1.0 - al || j.abs() < self.j_r(-1.0) || j == 0.0
    }

    /// Every stationary motion at Jellett integral `j`, by ascending u: the hanging spin
    /// (unless alpha = 1 and J != 0, when none exists), the regular precessions, the upright
    /// spin.
    pub fn stationary_motions(&self, j: f64) -> Result<Vec<StationaryMotion>> {
        finite("J", j)?;
        let mut out = Vec::with_capacity(4);
        if self.n(-1.0) > 0.0 || j == 0.0 {
            out.push(self.motion(StationaryKind::Hanging, j, -1.0, self.hanging_stable(j)));
        }
        for u in self.precession_inclinations(j) {
            out.push(self.motion(StationaryKind::Precession, j, u, self.precession_stable(u)));
        }
        out.push(self.motion(StationaryKind::Upright, j, 1.0, self.upright_stable(j)));
        if out
            .iter()
            .any(|m| !(m.energy.is_finite() && m.omega.is_finite() && m.omega3.is_finite()))
        {
            return Err(KreiselError::invalid(
                "J",
                j,
                "the stationary motions at this Jellett integral have rates or energies \
                 beyond the floats (J^2 / (C rho^2) overflows): give a smaller |J|",
            ));
        }
        Ok(out)
    }

    /// The stable stationary motions open to a state with Jellett integral `j`, energy
    /// `energy` and inclination `u0`, and the one it must end in where that is unique.
    ///
    /// Energy never increases and J is kept, and `E >= V(u)` always; so u stays in the
    /// connected part of `{u : V(u) <= E}` that holds u0, and the top ends in a stable
    /// stationary motion inside it. V is monotone between consecutive stationary points.
    pub fn predict(&self, j: f64, energy: f64, u0: f64) -> Result<Prediction> {
        finite("J", j)?;
        finite("energy", energy)?;
        finite("u", u0)?;
        if !(-1.0..=1.0).contains(&u0) {
            return Err(KreiselError::invalid(
                "u",
                u0,
                "u = cos(theta) must lie in [-1, 1]",
            ));
        }
        let all = self.stationary_motions(j)?;
        // Round-off may put a stationary state a hair below its own V.
        let e = energy.max(self.energy(j, u0));
        let tol = 1e-12 * e.abs().max(self.mgs() * self.top.rho);
        let ok = |m: &StationaryMotion| m.energy <= e + tol;
        let mut reachable = Vec::new();
        // Walk left from u0, then right, while the stationary points stay below E.
        let split = all.partition_point(|m| m.u < u0);
        for m in all[..split].iter().rev() {
            if !ok(m) {
                break;
            }
            reachable.push(*m);
        }
        reachable.reverse();
        for m in &all[split..] {
            if !ok(m) {
                break;
            }
            reachable.push(*m);
        }
        reachable.retain(|m| m.stable);
        let stable: Vec<StationaryMotion> = all.into_iter().filter(|m| m.stable).collect();
        let ending = (reachable.len() == 1).then(|| reachable[0]);
        Ok(Prediction {
            j,
            stable,
            reachable,
            ending,
        })
    }
}

/// Turning points and nutation period of the frictionless play top.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionlessNutation {
    /// Least and greatest u = cos(theta) of the nutation.
    pub u_range: (f64, f64),
    /// Nutation period (s); for a steady precession the period of small nutations about it,
    /// infinite on the separatrix.
    pub period: f64,
    /// The nutation period of the Lagrange top with the same gyro function (I1 = A about G,
    /// l = s): the play top's without the extra divisor.
    pub lagrange_period: f64,
}

/// The frictionless play top from a contact state: `udot^2 = F(u) / (1 + (m s^2/A)(1-u^2))`
/// with F the gyro function of the Lagrange top with `I1 = A`, `I3 = C`, `l = s` (theory: play
/// top). The turning points are F's roots; with `u(tau) = uA cn^2 + uB sn^2`
/// the Lagrange solution in its own time tau, the play top's period is
/// `T = integral over one period of sqrt(1 + (m s^2/A)(1 - u(tau)^2)) dtau`: a smooth
/// periodic integrand, summed by the trapezoidal rule to round-off.
///
/// F is written about the state's u0 (as the exact Lagrange top does), where
/// `F(u0) = udot0^2 (1 + k (1 - u0^2))` is known without cancellation.
pub fn frictionless_nutation(top: &PlayTop, y: &[f64; DIM]) -> Result<FrictionlessNutation> {
    let (m, a, c, s, g) = (top.m, top.a, top.c, top.s, top.g);
    let gap = {
        let k = top.kin(y);
        top.parts.shape[0].gap(k.zg, k.e3)
    };
    if gap.abs() > 1e-9 * top.rho {
        return Err(KreiselError::invalid(
            "state",
            gap,
            "the gyro function holds while the top touches the floor; this state's tip is \
             that far (m) from it",
        ));
    }
    let q = Quat([y[0], y[1], y[2], y[3]]).normalized();
    let w = [y[4], y[5], y[6]];
    let gm = q.up_in_body();
    let u0 = gm[2];
    let st2 = gm[0] * gm[0] + gm[1] * gm[1]; // sin^2 theta
    let (om0, op0) = if u0 >= 0.0 {
        (st2 / (1.0 + u0), 1.0 + u0)
    } else {
        (1.0 - u0, st2 / (1.0 - u0))
    };
    let k = m * s * s / a;
    let beta = 2.0 * m * g * s / a;
    let aa = c * w[2] / a; // a = C omega3 / A
    let udot = cross(gm, w)[2];
    let edot2 = w[0] * w[0] + w[1] * w[1]; // |de3/dt|^2
    let b0 = w[0] * gm[0] + w[1] * gm[1]; // b - a u0 = (Lz - C omega3 u0)/A
    let a0 = edot2 + k * udot * udot; // 2E'/A - beta u0
    let c0 = udot * udot * (1.0 + k * st2);
    let c1 = -beta * st2 - 2.0 * u0 * a0 + 2.0 * aa * b0;
    let c2 = 2.0 * beta * u0 - a0 - aa * aa;
    let p = Poly3([c0, c1, c2, beta]);
    let (dlo, dhi) = if c0 == 0.0 && c1 == 0.0 {
        (0.0, 0.0)
    } else if c0 == 0.0 {
        let qd = Poly3([c1, c2, beta, 0.0]);
        if c1 > 0.0 {
            (0.0, qd.root_in(0.0, om0))
        } else {
            (qd.root_in(-op0, 0.0), 0.0)
        }
    } else {
        (p.root_in(-op0, 0.0), p.root_in(0.0, om0))
    };
    let (ua, ub) = ((u0 + dlo).max(-1.0), (u0 + dhi).min(1.0));
    // beta (u3 - uA) by Vieta, without dividing by beta.
    let w4 = -c2 - beta * (dhi + 2.0 * dlo);
    let divisor = |u: f64| (1.0 + k * (1.0 - u) * (1.0 + u)).sqrt();
    if dhi - dlo == 0.0 {
        let tl = if w4 > 0.0 {
            2.0 * std::f64::consts::PI / w4.sqrt()
        } else {
            f64::INFINITY
        };
        return Ok(FrictionlessNutation {
            u_range: (ua, ub),
            period: tl * divisor(u0),
            lagrange_period: tl,
        });
    }
    if w4.is_nan() || w4 <= 0.0 {
        return Err(KreiselError::Numerical(format!(
            "frictionless play top: the nutation from this state (u0 = {u0}, du/dt = {udot}, \
             u between {ua} and {ub}) could not be resolved: nutation frequency squared {w4} \
             is not positive"
        )));
    }
    let mm = (beta * (dhi - dlo) / w4).clamp(0.0, 1.0);
    let m1 = ((w4 - beta * (dhi - dlo)) / w4).clamp(0.0, 1.0);
    let ww = 0.5 * w4.sqrt();
    let kk = ellipk_m1(m1);
    if !kk.is_finite() {
        return Ok(FrictionlessNutation {
            u_range: (ua, ub),
            period: f64::INFINITY,
            lagrange_period: f64::INFINITY,
        });
    }
    let tl = 2.0 * kk / ww;
    // Mean of the divisor over one period of tau in [0, 2K): trapezoid rule, doubled until
    // it settles (exponential convergence for a smooth periodic integrand).
    let f = |tau: f64| {
        let jf = jacobi(tau, mm, m1);
        let u = ua * jf.cn * jf.cn + ub * jf.sn * jf.sn;
        divisor(u)
    };
    let mut n = 16usize;
    let mut sum: f64 = (0..n).map(|i| f(2.0 * kk * i as f64 / n as f64)).sum();
    let mut mean = sum / n as f64;
    for _ in 0..16 {
        let extra: f64 = (0..n)
            .map(|i| f(2.0 * kk * (i as f64 + 0.5) / n as f64))
            .sum();
        sum += extra;
        n *= 2;
        let next = sum / n as f64;
        let done = (next - mean).abs() <= 1e-15 * next;
        mean = next;
        if done {
            break;
        }
    }
    Ok(FrictionlessNutation {
        u_range: (ua, ub),
        period: tl * mean,
        lagrange_period: tl,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::play_top::Friction;

    fn top(alpha: f64, gamma: f64) -> PlayStability {
        let (m, rho, c) = (0.1, 0.02, 2e-5);
        let top = PlayTop::new(
            m,
            gamma * c,
            c,
            alpha * rho,
            rho,
            9.81,
            Friction::Frictionless,
            0.0,
            0.0,
            0.0,
            0.0,
        )
        .unwrap();
        PlayStability::new(&top).unwrap()
    }

    #[test]
    fn energy_is_stationary_at_every_regular_precession() {
        for &(al, ga) in &[(0.3, 0.8), (0.3, 1.2), (0.6, 1.9), (0.2, 0.7), (0.05, 0.9)] {
            let t = top(al, ga);
            for i in 1..40 {
                let u = -1.0 + i as f64 / 20.0;
                let Ok(rp) = t.regular_precession(u) else {
                    continue;
                };
                let scale = t.mgs();
                assert!(t.energy_du(rp.j, u).abs() < 1e-12 * scale, "{al} {ga} {u}");
                // Omega^2 = m g s / (C D) agrees with Omega = J / (rho C N).
                let om = rp.j / (t.top().rho * t.top().c * t.n(u));
                assert!((om / rp.omega - 1.0).abs() < 1e-14);
            }
        }
    }

    #[test]
    fn stability_table_matches_the_sign_of_the_energy_curvature() {
        for &(al, ga) in &[(0.3, 0.8), (0.3, 0.72), (0.3, 1.5), (0.5, 0.6), (0.02, 0.9)] {
            let t = top(al, ga);
            for i in 0..200 {
                let j = t.j_beta() * (0.05 + 0.05 * i as f64);
                for mo in t.stationary_motions(j).unwrap() {
                    let h = 1e-5;
                    let vpp = match mo.kind {
                        StationaryKind::Precession => {
                            (t.energy(j, mo.u + h) - 2.0 * t.energy(j, mo.u)
                                + t.energy(j, mo.u - h))
                                / (h * h)
                        }
                        StationaryKind::Upright => -t.energy_du(j, 1.0),
                        StationaryKind::Hanging => t.energy_du(j, -1.0),
                    };
                    let scale = t.mgs();
                    if vpp.abs() > 1e-6 * scale {
                        assert_eq!(mo.stable, vpp > 0.0, "{al} {ga} {j} {mo:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn zones_follow_the_boundary_curves() {
        // A point on each side of each boundary, at alpha = 0.3 and 0.03.
        let b = zone_boundaries(0.3);
        assert!(b[0].is_nan() && b[1].is_nan());
        assert_eq!(classify(0.3, b[2] + 1e-9).unwrap().zone, 6);
        assert_eq!(classify(0.3, b[2] - 1e-9).unwrap().zone, 5);
        assert_eq!(classify(0.3, b[3] + 1e-9).unwrap().zone, 5);
        assert_eq!(classify(0.3, b[3] - 1e-9).unwrap().zone, 4);
        let b = zone_boundaries(0.03);
        assert_eq!(classify(0.03, b[1] + 1e-9).unwrap().zone, 4);
        assert_eq!(classify(0.03, b[1] - 1e-9).unwrap().zone, 3);
        assert_eq!(classify(0.03, b[0] + 1e-9).unwrap().zone, 8);
        assert_eq!(classify(0.03, b[0] - 1e-9).unwrap().zone, 7);
        assert_eq!(classify(0.3, 1.3 - 1e-9).unwrap().zone, 1);
        assert_eq!(classify(0.3, 1.3).unwrap().zone, 2);
        assert_eq!(classify(0.3, 1.3).unwrap().fig3, 'a');
        assert_eq!(classify(0.3, 0.7).unwrap().fig3, 'b');
        assert!(classify(0.0, 0.9).is_err());
    }

    #[test]
    fn precessions_solve_jr_to_round_off() {
        let t = top(0.3, 0.75);
        let um = t.u_m().unwrap();
        let jm = t.j_r(um);
        for f in [1.0 + 1e-6, 1.001, 1.01, 1.1] {
            let us = t.precession_inclinations(f * jm);
            assert_eq!(us.len(), 2);
            for u in us {
                assert!((t.j_r(u) / (f * jm) - 1.0).abs() < 1e-14);
            }
        }
        assert!(t.precession_inclinations(0.999 * jm).is_empty());
    }
}
