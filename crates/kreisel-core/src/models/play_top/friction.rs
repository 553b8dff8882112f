//! The friction laws at a contact and the resistance torques (theory: play top; theory:
//! several parts): each law's force (and drilling torque) per unit normal force while a part
//! slides, the cone (ellipse) a sticking part's force must lie in, and the Painleve case
//! where sliding has no consistent normal force.

use super::solve::{Forces, Kin};
use super::{add, scale, Contacts, Mode, PlayTop, DIM};
use crate::error::{non_negative, Result};
use crate::rotation::dot;

/// The relaxation time of the rolling and drilling resistances' linear law below their
/// regularisation rate, as a share of the top's time scale `sqrt(len / g)` (`len` the parts'
/// reach): 1e-4, 1.7 microseconds on a 3 mm top, 20 on a 4 cm disk
/// ([`PlayTop::resistance_on`]; theory: "Rolling and drilling resistance"). A setting of
/// the resistance law, not of the integration: the linear law ends a turning rate's last
/// stretch in about that time instead of at once, and holds explicit steps to a few times it.
pub const RESIST_TIME: f64 = 1e-4;

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

/// Point Coulomb friction spread evenly over a sharp rim of radius `R` lying flat, per unit
/// `mu N` (theory: play top, "A ring lying flat"): the rim's centre slides at `v` and it spins
/// at `w_z`, `a = R w_z`. The rim's mean force is `-G_F v / |v|` and its moment about the
/// centre `-R G_M sign(a)`, in closed form by complete elliptic integrals. With
/// `t = min(|v|, |a|) / max(|v|, |a|)`, `E(t)` and `B(t) = (E - (1 - t^2) K) / t^2` (Bulirsch's
/// `cel2`, no cancellation anywhere):
/// `|v| >= |a|`: `G_F = 2 E(t) / pi`, `G_M = 2 t B(t) / pi`; `|v| < |a|`: the two swapped.
/// (With v along x, the rim's point at angle `phi` slips at `s`, `|s|^2 = v^2 + a^2 -
/// 2 |v| a sin phi`; the means of `(|v| - a sin phi) / |s|` and `(a - |v| sin phi) / |s|` are Gauss-Landen
/// transforms of `K(k)` and `E(k)`, `k = 2 sqrt(|v| |a|) / (|v| + |a|)`.) Both are continuous
/// (`2/pi` at `|v| = |a|`, where a point of the rim stops), and smooth elsewhere: the 64-point
/// mean this replaces was not smooth near `|v| = |a|`, and a slide there took steps in
/// proportion to 1/rtol.
/// Returns the force per `mu N` (horizontal, space) and the moment per `mu N R`.
pub fn rim_coulomb(v: [f64; 2], a: f64) -> ([f64; 2], f64) {
    let sv = v[0].hypot(v[1]);
    let sa = a.abs();
    let big = sv.max(sa);
    if big == 0.0 {
        return ([0.0; 2], 0.0);
    }
    let t = sv.min(sa) / big;
    // kc = sqrt(1 - t^2) (never 0 for cel2: at t = 1 both E and B are 1 to rounding).
    let kc = ((1.0 - t) * (1.0 + t)).sqrt().max(1e-150);
    let e = ellip::cel2(kc, 1.0, kc * kc).unwrap_or(1.0);
    let b = ellip::cel2(kc, 1.0, 0.0).unwrap_or(1.0);
    let (gf, gm) = if sv >= sa { (e, t * b) } else { (t * b, e) };
    let (gf, gm) = (
        std::f64::consts::FRAC_2_PI * gf,
        std::f64::consts::FRAC_2_PI * gm,
    );
    let f = if sv > 0.0 {
        [-gf * v[0] / sv, -gf * v[1] / sv]
    } else {
        [0.0; 2]
    };
    (f, -gm * a.signum())
}

impl PlayTop {
    /// The friction of a sliding part per unit normal force: the tangential force (space,
    /// horizontal) and the drilling torque, from the part's slip velocity `vp`, the drilling
    /// rate `wn` and the direction `dir` taken at zero slip.
    #[inline(always)]
    pub fn friction_per_n(
        &self,
        vp: [f64; 3],
        wn: f64,
        dir: [f64; 2],
        creep: f64,
    ) -> ([f64; 2], f64) {
        // Creeping (the measure at or below `creep`, a direction set): the full friction
        // against the force sticking would need.
        let creeping = |d: f64| creep > 0.0 && d <= creep && dir != [0.0; 2];
        match self.friction {
            Friction::Coulomb { mu } => {
                let sp = (vp[0] * vp[0] + vp[1] * vp[1]).sqrt();
                // (Point Coulomb friction keeps the direction of the slip above zero: its
                // creep at the cone's edge follows the slip, and a direction fixed at the
                // switch would make the force jump where the two part, at every step.)
                if sp > 0.0 {
                    ([-mu * vp[0] / sp, -mu * vp[1] / sp], 0.0)
                } else {
                    ([-mu * dir[0], -mu * dir[1]], 0.0)
                }
            }
            Friction::CoulombContensou { mu, radius } => {
                // (rbar from the arm's own radius: no call of the non-inlined `rbar`.)
                let rb = 3.0 * std::f64::consts::PI * radius / 16.0;
                let d = (vp[0] * vp[0] + vp[1] * vp[1] + rb * rb * wn * wn).sqrt();
                if d > 0.0 && !creeping(d) {
                    ([-mu * vp[0] / d, -mu * vp[1] / d], -mu * rb * rb * wn / d)
                } else if creep > 0.0 && rb * wn.abs() < creep {
                    // The law at the creep speed, its slip along `dir` (of the size that
                    // the drilling leaves to it): continuous in size where the measure
                    // crosses `creep` (a patch that drills at about the creep speed keeps
                    // its drilling torque; full sliding friction there made the normal
                    // forces of the other parts jump through zero).
                    let s = ((creep - rb * wn.abs()) * (creep + rb * wn.abs())).sqrt() / creep;
                    (
                        [-mu * s * dir[0], -mu * s * dir[1]],
                        -mu * rb * rb * wn / creep,
                    )
                } else {
                    ([-mu * dir[0], -mu * dir[1]], 0.0)
                }
            }
            Friction::Viscous { mu } => ([-mu * vp[0], -mu * vp[1]], 0.0),
            Friction::Frictionless => ([0.0; 2], 0.0),
        }
    }

    /// The measure of sliding that sticking ends at: the slip speed, and under
    /// Coulomb-Contensou friction `sqrt(|v|^2 + rbar^2 w_n^2)` (sliding and drilling).
    pub fn slide_measure(&self, vp: [f64; 3], wn: f64) -> f64 {
        let rb = self.friction.rbar();
        (vp[0] * vp[0] + vp[1] * vp[1] + rb * rb * wn * wn).sqrt()
    }

    /// Part `i`'s [`Self::slide_measure`] at the kinematics `k`.
    #[inline]
    pub fn part_slide(&self, k: &Kin, i: usize) -> f64 {
        let vp = self.parts.shape[i].point_velocity(k.v, k.w, k.e3);
        self.slide_measure(vp, k.w[2])
    }

    /// The cone test, the one place it is written: how far a normal force (or impulse) `n`,
    /// tangential `t` and drilling moment `m` lie inside the friction cone (Coulomb) or
    /// ellipse (Coulomb-Contensou, `|t|^2 + (m / rbar)^2 <= (mu n)^2`): `mu n - sqrt(|t|^2 +
    /// (m / rbar)^2)`, positive inside.
    pub fn cone_margin(&self, n: f64, t: [f64; 2], m: f64) -> f64 {
        let rb = self.friction.rbar();
        let m = if rb > 0.0 { m / rb } else { 0.0 };
        self.friction.mu() * n - (t[0] * t[0] + t[1] * t[1] + m * m).sqrt()
    }

    /// Whether the friction a sticking part needs lies in its cone (Coulomb) or ellipse
    /// (Coulomb-Contensou), with a pushing normal force ([`Self::cone_margin`]).
    pub fn stick_margin(&self, f: &Forces, i: usize) -> f64 {
        self.cone_margin(f.n[i], f.ft[i], f.mz[i])
    }

    /// A drilling part's share of its cone that its tangential force `ft` takes under the
    /// normal force `n`, `x = |F| / (mu N)`, and `sqrt(1 - x^2)` (0 at and beyond the cone's
    /// edge, or where the part does not push): the slip its friction needs is
    /// `rbar |w_n| x / sqrt(1 - x^2)` ([`super::Contacts::drilling`]).
    #[inline(always)]
    pub fn drill_share(&self, ft: [f64; 2], n: f64) -> (f64, f64) {
        let cap = self.friction.mu() * n;
        if cap <= 0.0 {
            return (1.0, 0.0);
        }
        let x = ft[0].hypot(ft[1]) / cap;
        (x, (1.0 - x * x).max(0.0).sqrt())
    }

    /// The resistance torques of rolling, drilling and air (theory: play top), from the
    /// angular velocity `w` and the upward vertical `gamma` in any one frame (the torques are
    /// in that frame): the part proportional to N (per unit N) and the part that is not;
    /// `len` sets the regularisation's rate scale.
    ///
    /// Each law is kept to the side of its kink `side[j]` gives (-1 the linear law, +1 the
    /// sharp law, 0 the one the rate picks). A phase keeps to the side it starts on and ends
    /// where the rate crosses the kink ([`super::driver::Switch::Band`]): its equations are
    /// then smooth, and the step that crosses the kink, whose state at the crossing is taken
    /// from its dense output, sees no kink inside it. Where the law switched inside that
    /// step, its error estimate missed the kink: a step of 1e-3 s (a hundred times the steps
    /// before it, the first after a restart) across the drilling resistance's kink of a
    /// frictionless ball top spinning on its side at 201 rad/s raised E + dissipated by
    /// 1.3e-8 of E at rtol 1e-10 (the floor campaign's case 1032 of seed 29 at t_end 5 s).
    #[inline(always)]
    pub(crate) fn resistance_on(
        &self,
        w: [f64; 3],
        gamma: [f64; 3],
        len: f64,
        side: [f64; 2],
    ) -> ([f64; 3], [f64; 3]) {
        let mut per_n = [0.0; 3];
        if self.rolling > 0.0 || self.drilling > 0.0 {
            // Vertical and horizontal parts of omega, in the body frame.
            let wz = dot(w, gamma);
            let wh = add(w, scale(-wz, gamma));
            let h = dot(wh, wh).sqrt();
            // The sharp law down to a rate `reg`, linear in the rate below it, so the torque
            // vanishes continuously as the turning stops (a sharper switch makes the
            // equations stiff). Not h + reg: that would weaken the torque by reg / h at every
            // rate, and a ball rolling to a stop would take ln(h0 / h_end) reg / (dh/dt) longer.
            // `reg` is at least 1e-6 sqrt(g / len), and at least the rate at which the linear
            // law's relaxation time, at the top's weight and its smallest moment, is
            // RESIST_TIME sqrt(len / g): below it a resistance of radius `delta` relaxes the
            // rate at delta N / (I reg), and a drilling resistance of 1.9 mm on a 6 g top
            // resting on a 3 mm spheroid, its spin stopped, did so at 4e7 /s, holding the
            // explicit steps to 1e-7 s (3.6 million rows in 0.3 s: floor campaign case 2330 of
            // seed 2; 6756 and 4814 of seed 1 were refused at 4 million rows).
            let [rolling, drilling] = self.resist_bands(len);
            // The rate a law divides by: the band's edge on the linear side, the rate itself
            // on the sharp side (kept from zero: a stage may reach a little past the kink).
            let by = |rate: f64, band: f64, side: f64| {
                if side < 0.0 {
                    band
                } else if side > 0.0 {
                    rate.max(1e-3 * band)
                } else {
                    rate.max(band)
                }
            };
            per_n = add(
                scale(-self.rolling / by(h, rolling, side[0]), wh),
                scale(-self.drilling * wz / by(wz.abs(), drilling, side[1]), gamma),
            );
        }
        (per_n, scale(-self.air, w))
    }

    /// The rates (rad/s) below which the rolling and the drilling resistance's laws are
    /// linear ([`PlayTop::resistance_on`]), `len` setting the rate scale: each is at least
    /// 1e-6 sqrt(g / len), and at least the rate at which the linear law's relaxation time, at
    /// the top's weight and its smallest moment, is `RESIST_TIME sqrt(len / g)`. The law has a
    /// kink there, where a phase restarts ([`super::driver::Switch::Band`]).
    #[inline(always)]
    pub(crate) fn resist_bands(&self, len: f64) -> [f64; 2] {
        // (One square root: the top's time scale sqrt(len / g).)
        let time = (len / self.g).sqrt();
        let reg = (1e-6 / time).max(1e-9);
        let per_rate = RESIST_TIME * time * self.m * self.g / self.a.min(self.c);
        [
            reg.max(self.rolling * per_rate),
            reg.max(self.drilling * per_rate),
        ]
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
    /// smallest moment), so below the jam level only when that bound is. Viscous friction's
    /// force per unit normal force, `mu |v|`, has no bound: it may always jam (a spheroid
    /// sliding at 0.65 m/s under `Viscous(2.06)` did, its normal force growing past 280 N on
    /// a 37 g top until the steps fell below 1e-16 s: floor campaign case 500 of seed 1).
    pub fn may_jam(&self, z: f64, r: f64) -> bool {
        match self.friction {
            Friction::Viscous { mu } => mu > 0.0,
            _ => {
                self.friction.can_stick()
                    && 1.0 / self.m
                        - self.friction.mu() * z.abs() * (z.abs() + r) / self.a.min(self.c)
                        <= self.jam_level()
            }
        }
    }

    /// Sliding's own coefficient at a state for part 0: the acceleration of the contact's
    /// height per unit normal force, friction included (1/kg), with the friction against the
    /// slip (along `-dir` at zero slip); zero or negative is the Painleve case.
    pub fn slip_coefficient(&self, y: &[f64; DIM], dir: [f64; 3]) -> f64 {
        let mut dy = [0.0; DIM];
        let mut c = Contacts::NONE;
        c.mode[0] = Mode::Slip;
        c.dir[0] = [dir[0], dir[1]];
        self.dynamics(&c, y, &mut dy).den[0]
    }
}

#[cfg(test)]
mod tests {
    use super::super::parts::Shape;
    use super::super::{Friction, PlayTop};
    use super::rim_coulomb;

    /// The resistance laws kept to one side of their kinks (theory: "Contact thresholds",
    /// resistance rate): the linear law `-c w / r` continued above the kink rate `r`, the
    /// sharp law `-c w / |w|` continued below it, each the rate's own law on its own side, and
    /// the two equal at the kink.
    #[test]
    fn a_resistance_kept_to_a_side_of_its_kink_continues_that_sides_law() {
        let parts = [Shape::Sphere {
            radius: 0.01,
            z: -0.004,
        }];
        let (cr, cd) = (2e-4, 1e-4);
        let top = PlayTop::with_parts(
            0.02,
            4e-6,
            3e-6,
            &parts,
            9.81,
            Friction::Coulomb { mu: 0.3 },
            0.0,
            cr,
            cd,
            0.0,
        )
        .unwrap();
        let len = top.parts.reach();
        let [rr, rd] = top.resist_bands(len);
        let ez = [0.0, 0.0, 1.0];
        // Horizontal rate along x, vertical rate along z, each `k` times its kink's rate.
        let torque = |k: f64, side: [f64; 2]| {
            let w = [k * rr, 0.0, -k * rd];
            top.resistance_on(w, ez, len, side).0
        };
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1e-300);
        for k in [0.25, 0.5, 2.0, 4.0] {
            // [rolling (x), drilling (z)] per unit N, from the laws as written
            let linear = [-cr * k, cd * k];
            let sharp = [-cr, cd];
            let by_rate = if k < 1.0 { linear } else { sharp };
            for (side, want) in [
                ([-1.0, -1.0], linear),
                ([1.0, 1.0], sharp),
                ([0.0; 2], by_rate),
            ] {
                let t = torque(k, side);
                assert!(
                    close(t[0], want[0]) && close(t[2], want[1]),
                    "{k} {side:?}: {t:?}"
                );
                assert_eq!(t[1], 0.0);
            }
        }
        let (lin, sh) = (torque(1.0, [-1.0; 2]), torque(1.0, [1.0; 2]));
        assert!(
            close(lin[0], sh[0]) && close(lin[2], sh[2]),
            "{lin:?} {sh:?}"
        );
    }

    /// Coulomb-Contensou friction at a patch whose sliding measure `d = |(v, rbar w_n)|`
    /// crosses the creep speed: the law above it (`-mu (v, rbar^2 w_n) / d`), the creep below
    /// (the slip put along `dir`). The tangential force's size and the drilling torque are
    /// continuous across, from a patch that only slips to one that only drills; the first
    /// build took the full sliding friction, no torque, at any drilling below the creep speed
    /// (a jump from 1e-3 mu to mu in the tangential force: the other parts' normal forces
    /// jumped through zero, floor campaign cases 2279 and 9925 of seed 1).
    #[test]
    fn the_contensou_creep_continues_the_law_at_the_creep_speed() {
        let parts = [Shape::Sphere {
            radius: 0.015,
            z: -0.003,
        }];
        let (mu, radius) = (0.4, 2e-4);
        let law = Friction::coulomb_contensou(mu, radius).unwrap();
        let rb = law.rbar();
        let top =
            PlayTop::with_parts(0.006, 8e-7, 7e-7, &parts, 9.81, law, 0.0, 0.0, 0.0, 0.0).unwrap();
        let creep = 1e-6;
        let dir = [0.6, -0.8];
        for share in [1.0, 0.9, 0.5, 1e-3, 0.0] {
            // |v| = share d, rbar |w_n| the rest of d; v along dir
            let at = |d: f64| {
                let sp = share * d;
                let wn = -((d * d - sp * sp).max(0.0)).sqrt() / rb;
                let v = [sp * dir[0], sp * dir[1], 0.0];
                let (ft, mz) = top.friction_per_n(v, wn, dir, creep);
                (ft, mz, -mu * rb * rb * wn / d)
            };
            let (above, m_above, law_m) = at(creep * (1.0 + 1e-12));
            let (below, m_below, _) = at(creep * (1.0 - 1e-12));
            let size = |f: [f64; 2]| f[0].hypot(f[1]);
            // the law above
            assert!((size(above) - mu * share).abs() <= 1e-9 * mu, "{share}");
            assert!((m_above - law_m).abs() <= 1e-9 * mu * rb, "{share}");
            // continuous across (the creep's size goes as the square root of the distance
            // to the creep speed where the patch only drills: 1.4e-6 here)
            assert!(
                (size(below) - size(above)).abs() <= 1e-5 * mu,
                "{share}: {below:?}"
            );
            assert!(
                (m_below - m_above).abs() <= 1e-9 * mu * rb,
                "{share}: {m_below}"
            );
            // against the slip's direction
            assert!(share == 0.0 || below[0] * dir[0] + below[1] * dir[1] < 0.0);
        }
    }

    /// The rim's closed forms against the mean over 2^16 points of the rim (the midpoint rule
    /// converges geometrically for a smooth periodic integrand; away from |v| = |a| the
    /// slip never vanishes on the rim), in both regimes and at t near 0 and near 1, in
    /// several directions of v and both senses of spin; and their common limit 2/pi at
    /// |v| = |a|, where the mean converges slowly (error ~ log n / n). 1e-10: the rounding of
    /// the 2^16 terms' sum.
    #[test]
    fn the_rim_s_coulomb_friction_is_the_mean_over_its_points() {
        let mean = |v: [f64; 2], a: f64, n: usize| {
            let (mut f, mut m) = ([0.0f64; 2], 0.0);
            for j in 0..n {
                let phi = (j as f64 + 0.5) * std::f64::consts::TAU / n as f64;
                let (s, c) = phi.sin_cos();
                let (rx, ry) = (c, s); // unit radius: the moment is per R
                let p = [v[0] - a * ry, v[1] + a * rx];
                let sp = p[0].hypot(p[1]);
                let ft = [-p[0] / sp, -p[1] / sp];
                f[0] += ft[0] / n as f64;
                f[1] += ft[1] / n as f64;
                m += (rx * ft[1] - ry * ft[0]) / n as f64;
            }
            (f, m)
        };
        for &(speed, a) in &[
            (1.0, 0.0),
            (1.0, 1e-6),
            (1.0, 0.1),
            (1.0, 0.5),
            (1.0, -0.9),
            (1.0, 0.99),
            (0.99, 1.0),
            (0.7, -1.0),
            (0.2, 1.0),
            (1e-6, -1.0),
            (0.0, 2.0),
        ] {
            for &dir in &[0.0, 1.0, -2.5] {
                let v = [speed * f64::cos(dir), speed * f64::sin(dir)];
                let (f, m) = rim_coulomb(v, a);
                let (fq, mq) = mean(v, a, 1 << 16);
                let err = (f[0] - fq[0]).abs() + (f[1] - fq[1]).abs() + (m - mq).abs();
                assert!(err < 1e-10, "v {v:?} a {a}: {f:?} {m} against {fq:?} {mq}");
            }
        }
        let (f, m) = rim_coulomb([0.3, 0.0], 0.3);
        let two_pi = std::f64::consts::FRAC_2_PI;
        assert!(
            (f[0] + two_pi).abs() < 1e-15 && (m + two_pi).abs() < 1e-15,
            "{f:?} {m}"
        );
        let (fq, mq) = mean([0.3, 0.0], 0.3, 1 << 20);
        assert!(
            (fq[0] - f[0]).abs() < 1e-4 && (mq - m).abs() < 1e-4,
            "{fq:?} {mq}"
        );
        assert_eq!(rim_coulomb([0.0; 2], 0.0), ([0.0; 2], 0.0));
    }
}
