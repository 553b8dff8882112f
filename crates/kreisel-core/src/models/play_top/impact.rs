//! Impacts: a part reaching the floor (with restitution and friction, several parts at
//! once), the tangential impact that ends a Painleve jam (Darboux-Keller: integrated in the
//! normal impulse), and a ring landing flat on its whole rim (theory: several parts).

// Index loops: the impulses' rows, columns and parts are addressed together by position.
#![allow(clippy::needless_range_loop)]

use super::parts::MAX_PARTS;
use super::solve::{transpose, Kin, System, EX, EY, EZ, MAXU, ZERO};
use super::{add, scale, solve3, Friction, Mode, PlayTop, DIM};
use crate::rotation::{cross, dot};

impl PlayTop {
    /// `K`, the velocity change of the material point at `arm` (from G) per unit impulse
    /// there, as its columns (x, y, z impulse): the contact's inverse effective mass.
    pub(super) fn point_response(&self, k: &Kin, arm: [f64; 3]) -> [[f64; 3]; 3] {
        let col = |e: [f64; 3]| {
            let (dv, dw) = self.response(k, e, cross(arm, e));
            add(dv, cross(dw, arm))
        };
        [col(EX), col(EY), col(EZ)]
    }

    /// Adds to `y` the velocity change an impulse `imp` with moment `torque` about G makes
    /// (G's velocity, the body angular velocity), at the kinematics `k` of `y`.
    pub(super) fn kick(&self, k: &Kin, y: &mut [f64; DIM], imp: [f64; 3], torque: [f64; 3]) {
        let (dv, dw) = self.response(k, imp, torque);
        let dwb = k.to_body(dw);
        for a in 0..3 {
            y[4 + a] += dwb[a];
            y[10 + a] += dv[a];
        }
    }

    /// The impact of ring part `i` coming down flat (its plane within
    /// [`super::driver::FLAT_LEVEL`] of the floor's) with restitution `e`: the whole rim
    /// strikes at once. The orientation is put exactly flat and the tilting rate removed; G's
    /// vertical velocity is reversed times `e` (or stopped where the rise would be below the
    /// [`PlayTop::bounce_height`]); the rim's friction acts through the impact with the normal
    /// impulse `P = m (1 + e) |v_z|`, its force and moment per unit normal force those of
    /// [`Self::flat_dynamics`] at the impact, cut where they would reverse the sliding or the
    /// spin. Returns whether the ring bounces. The kinetic energy taken is added to the
    /// dissipated energy.
    pub fn flat_impact(&self, i: usize, y: &mut [f64; DIM], e: f64) -> bool {
        let vz = y[12].min(0.0);
        let ke0 = self.kinetic_energy(y);
        let d0 = y[13];
        self.flat_project(i, y, false);
        let up = self.m * self.g > 0.0 && e * e * vz * vz / (2.0 * self.g) > self.bounce_height();
        let e = if up { e } else { 0.0 };
        let pn = self.m * (1.0 + e) * -vz;
        let mut c = self.flat_contacts(i, false);
        c.mode[i] = Mode::Slip;
        let mut dy = [0.0; DIM];
        let f = self.flat_dynamics(&c, y, &mut dy);
        let n = self.m * self.g;
        if n > 0.0 && pn > 0.0 {
            let dv = [f.ft[i][0] / n * pn / self.m, f.ft[i][1] / n * pn / self.m];
            let dw = f.mz[i] / n * pn / self.c;
            let v = [y[10], y[11]];
            let k = self.kin(y);
            let mut lam: f64 = 1.0;
            let dvn = dv[0].hypot(dv[1]);
            if dvn > 0.0 {
                lam = lam.min(v[0].hypot(v[1]) / dvn);
            }
            if dw != 0.0 {
                lam = lam.min(k.w[2].abs() / dw.abs());
            }
            y[10] += lam * dv[0];
            y[11] += lam * dv[1];
            y[6] += k.e3[2].signum() * lam * dw;
        }
        y[12] = -e * vz;
        let loss = ke0 - self.kinetic_energy(y);
        y[13] = d0 + loss.max(0.0);
        up
    }

    /// The tangential impact of a jammed part (the Painleve case: sliding so that the
    /// friction's lever makes sliding's own coefficient negative, so that neither sliding nor
    /// flight is consistent). The impact is integrated in the normal impulse `lambda`
    /// (Darboux-Keller): the impulse grows as `dP = (ez + f(v_t)) dlambda` with `f` the
    /// friction per unit normal force of the law at the current slip (`-mu v_t` viscous,
    /// `-mu v_t / |v_t|` Coulomb and Coulomb-Contensou, whose drilling part is left out of
    /// the impulse), the contact point's velocity as `dv = K dP` with `K` the contact's
    /// inverse effective mass. The normal velocity first falls (compression) while the slip
    /// decays; the impact ends when it is back to zero (no rebound), with sliding consistent
    /// again. Where a Coulomb slip stops on the way, the rest of the impact is the impulse that
    /// stops the contact point (it sticks). Where the coefficient is still just positive (the
    /// dynamic jam: the normal force growing without bound), the impulse that stops the
    /// contact point where it lies in the cone, else the process at the law's friction until
    /// the slip stops or has turned the coefficient clear of zero. Returns the state after
    /// the impulse (the kinetic energy it takes added to the dissipated energy), or None where
    /// the part is not jammed, has no friction, or the process does not end.
    pub fn jam_impact(&self, y: &[f64; DIM], i: usize) -> Option<[f64; DIM]> {
        let (mu, viscous) = match self.friction {
            Friction::Viscous { mu } => (mu, true),
            Friction::Coulomb { mu } | Friction::CoulombContensou { mu, .. } => (mu, false),
            Friction::Frictionless => return None,
        };
        if mu <= 0.0 {
            return None;
        }
        let k = self.kin(y);
        let arm = self.part(i).arm(k.e3);
        let kc = self.point_response(&k, arm);
        let kmul = |p: [f64; 3]| {
            add(
                add(scale(p[0], kc[0]), scale(p[1], kc[1])),
                scale(p[2], kc[2]),
            )
        };
        let v0 = self.part(i).point_velocity(k.v, k.w, k.e3);
        let vs = self.speed_scale(y);
        let vstop = 1e-12 * vs;
        let slope = |v: [f64; 3]| {
            if viscous {
                [-mu * v[0], -mu * v[1], 1.0]
            } else {
                let sp = v[0].hypot(v[1]).max(vstop);
                [-mu * v[0] / sp, -mu * v[1] / sp, 1.0]
            }
        };
        let knorm = kc.iter().map(|c| dot(*c, *c).sqrt()).fold(0.0, f64::max);
        if knorm <= 0.0 {
            return None;
        }
        // Steps in lambda small against the slip's decay and the velocity's scale.
        let h_max = if viscous {
            0.02 / (mu * knorm)
        } else {
            1e-3 * v0[0].hypot(v0[1]).max(1e-3 * vs) / (mu * knorm)
        };
        let mut h = h_max.min(1e-3 * vs / knorm);
        let (mut v, mut p) = (v0, ZERO);
        let mut compressed = false;
        let mut jammed = false;
        let apply = |p: [f64; 3]| {
            let mut out = *y;
            self.kick(&k, &mut out, p, cross(arm, p));
            let ke = self.kinetic_energy(y);
            let loss = ke - self.kinetic_energy(&out);
            if loss < -1e-12 * ke {
                return None;
            }
            out[13] += loss.max(0.0);
            Some(out)
        };
        for _ in 0..200_000 {
            if jammed && kmul(slope(v))[2] > 10.0 * self.jam_level() {
                // The slip has turned so that sliding's own coefficient is clear of zero
                // again: the normal force it gives is bounded, the jam is over.
                return apply(p);
            }
            if !viscous && v[0].hypot(v[1]) <= 10.0 * vstop {
                // The slip has stopped: the rest of the impact stops the contact point.
                let stop = solve3(transpose(kc), scale(-1.0, v));
                return apply(add(p, stop));
            }
            // RK4 on dv/dlambda = K slope(v), dP/dlambda = slope(v).
            let s1 = slope(v);
            let s2 = slope(add(v, scale(0.5 * h, kmul(s1))));
            let s3 = slope(add(v, scale(0.5 * h, kmul(s2))));
            let s4 = slope(add(v, scale(h, kmul(s3))));
            let dp = scale(
                h / 6.0,
                add(add(s1, scale(2.0, s2)), add(scale(2.0, s3), s4)),
            );
            let vn = add(v, kmul(dp));
            if !viscous && dot([v[0], v[1], 0.0], [vn[0], vn[1], 0.0]) <= 0.0 {
                // The slip would reverse inside this step: a smaller one.
                h *= 0.25;
                if h < 1e-300 {
                    return None;
                }
                continue;
            }
            if compressed && vn[2] >= 0.0 {
                // The end of the impact inside this step: the fraction of it that brings the
                // normal velocity back to zero (linear in the step).
                let f = if vn[2] > v[2] {
                    -v[2] / (vn[2] - v[2])
                } else {
                    1.0
                };
                return apply(add(p, scale(f.clamp(0.0, 1.0), dp)));
            }
            if !compressed && !jammed && vn[2] >= v[2] {
                // Sliding's own coefficient is still (just) positive: the normal force is
                // growing without bound as it heads for zero (the dynamic jam), and its
                // friction stops the slip first. That is the impulse that stops the contact
                // point, where it lies in the friction cone.
                let stop = solve3(transpose(kc), scale(-1.0, v0));
                let inside =
                    stop[2] > 0.0 && self.cone_margin(stop[2], [stop[0], stop[1]], 0.0) >= 0.0;
                if inside && !viscous {
                    return apply(stop);
                }
                // Where that impulse leaves the cone (and under viscous friction, which
                // cannot stick), the normal force grows without bound while sliding's own
                // coefficient heads for zero, and its friction turns and slows the slip
                // faster than the motion moves: the process goes on, the law's friction
                // along the slip, the normal velocity changing by the coefficient times the
                // impulse (next to nothing at the jam), until the slip stops or has turned so
                // that the coefficient is clear of zero (ten jam levels); an impulse that
                // would feed energy in is refused by `apply`.
                // Without it the slip went on with its normal force growing past 300 weights
                // until the steps fell below 1e-16 s (floor campaign case 2387 of seed 1).
                jammed = true;
            }
            compressed |= vn[2] < 0.0;
            v = vn;
            p = add(p, dp);
            h = (h * 1.02).min(h_max);
        }
        None
    }

    /// The impulses at the parts of `set` (bit mask) that make their material points'
    /// velocities what `target` gives (normal: the target normal velocity; tangential:
    /// zero where the part sticks), each part sticking, sliding against its slip (a Coulomb
    /// impulse) or taking no impulse: the first choice per part, in order of preference,
    /// that is consistent (pushing impulses in the friction cone, sliding not reversed, free
    /// parts separating) and takes no energy. Returns the state after the impulses (the
    /// kinetic energy they take added to the dissipated energy) and which parts stick.
    pub fn impact(&self, y: &[f64; DIM], set: u8, target: [f64; MAX_PARTS]) -> ([f64; DIM], u8) {
        self.impact_keeping(y, set, target, 0)
    }

    /// [`Self::impact`] where the parts of `keep` (bit mask) take an impulse (they may
    /// not separate).
    ///
    /// Where no choice is consistent with the targets (a part striking the floor while
    /// another rests on it: restitution at the one may need the other to pull), the impact
    /// is taken without restitution, and where that too fails, also without friction: the
    /// frictionless plastic impact always has a consistent choice (its impulses solve a
    /// linear complementarity problem with a positive semi-definite matrix) and takes energy.
    pub fn impact_keeping(
        &self,
        y: &[f64; DIM],
        set: u8,
        target: [f64; MAX_PARTS],
        keep: u8,
    ) -> ([f64; DIM], u8) {
        let plastic = target.map(|t| t.min(0.0));
        self.impact_search(y, set, target, keep, true, true)
            .or_else(|| self.impact_search(y, set, plastic, keep, true, true))
            .or_else(|| self.impact_search(y, set, plastic, keep, false, true))
            .unwrap_or((*y, 0))
    }

    /// The impulses at the parts of `set` that stop their slips (and drilling, over a patch)
    /// and give their gaps the rates `target`, whatever their size: not bounded by the
    /// friction cone (a slip far below the stick speed's scale that the friction would stop
    /// in a moment; [`super::driver`]'s end of a rocking). None where they would add kinetic
    /// energy. The state after them (the energy they take counted as dissipated).
    pub fn stop_slips(
        &self,
        y: &[f64; DIM],
        set: u8,
        target: [f64; MAX_PARTS],
    ) -> Option<[f64; DIM]> {
        self.impact_search(y, set, target, set, true, false)
            .filter(|&(_, stuck)| stuck == set)
            .map(|(out, _)| out)
    }

    /// [`Self::impact_keeping`] with one set of targets, with or without friction:
    /// None where no choice is consistent.
    fn impact_search(
        &self,
        y: &[f64; DIM],
        set: u8,
        target: [f64; MAX_PARTS],
        keep: u8,
        friction: bool,
        cone: bool,
    ) -> Option<([f64; DIM], u8)> {
        let n = self.parts.n;
        let k = self.kin(y);
        let parts: Vec<usize> = (0..n).filter(|i| set & (1 << i) != 0).collect();
        let mu = if friction && self.friction.can_stick() {
            self.friction.mu()
        } else {
            0.0
        };
        let vp: Vec<[f64; 3]> = (0..n)
            .map(|i| self.part(i).point_velocity(k.v, k.w, k.e3))
            .collect();
        let ke = self.kinetic_energy(y);
        // choice per part: 0 stick, 1 slide, 2 free; combinations ordered by preference
        let m = parts.len() as u32;
        let mut combos: Vec<Vec<u8>> = (0..3u32.pow(m))
            .map(|mut c| {
                (0..m)
                    .map(|_| {
                        let d = (c % 3) as u8;
                        c /= 3;
                        d
                    })
                    .collect()
            })
            .collect();
        combos.sort_by_key(|c| {
            let free = c.iter().filter(|&&x| x == 2).count();
            let slide = c.iter().filter(|&&x| x == 1).count();
            (free, slide)
        });
        let tol_v = 1e-12 * self.speed_scale(y);
        let rb = if mu > 0.0 { self.friction.rbar() } else { 0.0 };
        for combo in combos {
            if mu == 0.0 && combo.contains(&0) {
                continue;
            }
            if parts
                .iter()
                .zip(&combo)
                .any(|(&i, &ch)| ch == 2 && keep & (1 << i) != 0)
            {
                continue;
            }
            let mut sys = System::<MAXU>::new();
            let mut owner = [(0usize, 0usize); MAXU];
            for (&i, &choice) in parts.iter().zip(&combo) {
                let p = self.part(i);
                let arm = p.arm(k.e3);
                let v = vp[i];
                match choice {
                    0 => {
                        for (axis, e) in [EX, EY, EZ].into_iter().enumerate() {
                            let goal = if axis == 2 { target[i] } else { 0.0 };
                            owner[sys.n] = (i, axis);
                            let jw = cross(arm, e);
                            sys.push(e, jw, e, jw, goal - dot(e, v));
                        }
                        if rb > 0.0 {
                            // Sticking over a patch stops the drilling too (D = 0).
                            owner[sys.n] = (i, 4);
                            sys.weight[sys.n] = 1.0 / (rb * rb);
                            sys.push(ZERO, EZ, ZERO, EZ, -k.w[2]);
                        }
                    }
                    1 => {
                        let sp = (v[0] * v[0] + v[1] * v[1]).sqrt();
                        let d = if sp > 0.0 {
                            [v[0] / sp, v[1] / sp]
                        } else {
                            [0.0; 2]
                        };
                        let f = [-mu * d[0], -mu * d[1], 1.0];
                        owner[sys.n] = (i, 3);
                        sys.push(f, cross(arm, f), EZ, cross(arm, EZ), target[i] - v[2]);
                    }
                    _ => {}
                }
            }
            sys.responses(|f, t| self.response(&k, f, t));
            sys.solve();
            let x = sys.x;
            // the impulse at each part, and its drilling impulse about ez
            let mut imp = [[0.0; 3]; MAX_PARTS];
            let mut drill = [0.0; MAX_PARTS];
            for j in 0..sys.n {
                let (i, axis) = owner[j];
                let f = sys.force[j];
                match axis {
                    3 => imp[i] = add(imp[i], scale(x[j], f)),
                    4 => drill[i] += x[j],
                    _ => imp[i][axis] += x[j],
                }
            }
            let mut out = *y;
            let (mut total, mut moment) = (ZERO, ZERO);
            for &i in &parts {
                total = add(total, imp[i]);
                moment = add(
                    moment,
                    add(cross(self.part(i).arm(k.e3), imp[i]), scale(drill[i], EZ)),
                );
            }
            self.kick(&k, &mut out, total, moment);
            let k1 = self.kin(&out);
            let ok = parts.iter().zip(&combo).all(|(&i, &choice)| {
                let pi = imp[i];
                let after = self.part(i).point_velocity(k1.v, k1.w, k1.e3);
                match choice {
                    0 => {
                        !cone
                            || pi[2] >= 0.0
                                && self.cone_margin(pi[2] * (1.0 + 1e-12), [pi[0], pi[1]], drill[i])
                                    >= 0.0
                    }
                    // (Without friction a normal impulse may turn the slip any way: nothing
                    // to reverse. Checked, the frictionless plastic impact of a tilted ring
                    // striking at 2.2 m/s had no consistent choice, was not taken, and the
                    // touchdown was found again 2e-14 s later, 195 000 times.)
                    1 => {
                        pi[2] >= 0.0
                            && (mu == 0.0
                                || vp[i][0] * after[0] + vp[i][1] * after[1] >= -tol_v * tol_v)
                    }
                    _ => after[2] >= target[i].min(0.0) - tol_v,
                }
            });
            let loss = ke - self.kinetic_energy(&out);
            if !ok {
                continue;
            }
            if loss < -1e-12 * ke {
                continue;
            }
            out[13] += loss.max(0.0);
            let sticks = parts
                .iter()
                .zip(&combo)
                .fold(0u8, |acc, (&i, &ch)| acc | (u8::from(ch == 0) << i));
            return Some((out, sticks));
        }
        None
    }
}
