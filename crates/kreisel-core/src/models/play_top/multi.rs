//! Tops with several contact parts, or with Coulomb-Contensou friction (theory: several parts): the
//! equations of motion with any set of parts touching, each sliding or sticking, and the
//! contact rules between them (touchdown and lift-off of a part, stick and slip of a part,
//! the tangential impact that ends a Painleve jam, impacts with several parts touching).
//!
//! Everything is in the space frame. The unknown contact forces are solved for jointly: each
//! touching part adds its normal force N_i (the gap's acceleration is zero), a sliding part
//! carries its friction per unit N_i (Coulomb, viscous, or Coulomb-Contensou with its drilling
//! torque), a sticking part adds its tangential force (the slip's rate is zero) and, under
//! Coulomb-Contensou friction, its drilling torque (the drilling rate's rate is zero). That is
//! one linear system of at most 4 unknowns per part, solved by Gaussian elimination. Which
//! parts touch is decided where it changes (at touchdown, after an impact, at the start) by
//! the complementarity conditions: every touching part pushes (N_i >= 0), every part at zero
//! gap that does not touch separates (its gap's acceleration >= 0).
//!
//! Hand-written: the systems are tiny (at most 16 unknowns, mostly 1 or 2) and solved at
//! every right-hand side; a general linear-algebra crate adds allocation and dispatch that
//! cost more than the arithmetic here.

// Index loops: the systems' rows, columns and parts are addressed together by position.
#![allow(clippy::needless_range_loop)]

use super::shapes::{Shape, MAX_PARTS};
use super::{add, scale, solve3, Friction, Mode, PlayTop, DIM};
use crate::rotation::{cross, dot, Quat};

const EX: [f64; 3] = [1.0, 0.0, 0.0];
const EY: [f64; 3] = [0.0, 1.0, 0.0];
const EZ: [f64; 3] = [0.0, 0.0, 1.0];
const ZERO: [f64; 3] = [0.0; 3];

/// The matrix whose columns are `cols` (rows of `cols` as columns).
fn transpose(cols: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    [
        [cols[0][0], cols[1][0], cols[2][0]],
        [cols[0][1], cols[1][1], cols[2][1]],
        [cols[0][2], cols[1][2], cols[2][2]],
    ]
}
/// The most unknowns of one system: four per part.
const MAXU: usize = 4 * MAX_PARTS;

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
}

impl Contacts {
    /// No part touches.
    pub const NONE: Contacts = Contacts {
        mode: [Mode::Flight; MAX_PARTS],
        dir: [[0.0; 2]; MAX_PARTS],
        flat: false,
        creep: 0.0,
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

/// Kinematics of a state in the space frame.
#[derive(Debug, Clone, Copy)]
pub struct MKin {
    /// Orientation as integrated.
    pub q: Quat,
    /// Rotation body -> space of `q / |q|` (row-major).
    pub r: [[f64; 3]; 3],
    /// Body angular velocity.
    pub wb: [f64; 3],
    /// Space angular velocity.
    pub w: [f64; 3],
    /// Figure axis (space).
    pub e3: [f64; 3],
    /// Velocity of G.
    pub v: [f64; 3],
    /// Height of G.
    pub zg: f64,
}

impl MKin {
    #[inline(always)]
    fn to_space(self, v: [f64; 3]) -> [f64; 3] {
        super::to_space(&self.r, v)
    }
    #[inline(always)]
    fn to_body(self, v: [f64; 3]) -> [f64; 3] {
        super::to_body(&self.r, v)
    }
}

/// The contact forces of a state in a [`Contacts`], per part.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Forces {
    /// Normal force (N); 0 for a part not touching.
    pub n: [f64; MAX_PARTS],
    /// Tangential force (space frame, horizontal; N).
    pub ft: [[f64; 2]; MAX_PARTS],
    /// Drilling torque about the vertical (N m).
    pub mz: [f64; MAX_PARTS],
    /// A sliding part's own coefficient: its gap's acceleration per unit of its normal
    /// force, friction included (1/kg). Zero or negative: the Painleve case (sliding has no
    /// consistent normal force).
    pub den: [f64; MAX_PARTS],
}

/// A linear system in contact forces (or impulses): columns are wrenches (force and torque
/// about G, space frame), rows measure the response of a material point's velocity
/// (`jv . dv + jw . dw`), the right-hand side what the row must change by.
struct System<const U: usize> {
    n: usize,
    force: [[f64; 3]; U],
    torque: [[f64; 3]; U],
    jv: [[f64; 3]; U],
    jw: [[f64; 3]; U],
    rhs: [f64; U],
    /// The (dv, dw) each wrench makes ([`System::responses`]).
    dv: [[f64; 3]; U],
    dw: [[f64; 3]; U],
    /// The unknowns and the matrix's diagonal ([`System::solve`]).
    x: [f64; U],
    diag: [f64; U],
    /// Each unknown's weight in the norm a redundant system's solution minimises: 1 for a
    /// force, 1/rbar^2 for a drilling torque (the friction ellipse's metric).
    weight: [f64; U],
    /// A redundant system's null space: `m` vectors (the solutions are `x + basis c`).
    basis: [[f64; U]; U],
    m: usize,
}

impl<const U: usize> System<U> {
    #[inline(always)]
    fn new() -> System<U> {
        System {
            n: 0,
            force: [ZERO; U],
            torque: [ZERO; U],
            jv: [ZERO; U],
            jw: [ZERO; U],
            rhs: [0.0; U],
            dv: [ZERO; U],
            dw: [ZERO; U],
            x: [0.0; U],
            diag: [0.0; U],
            weight: [1.0; U],
            basis: [[0.0; U]; U],
            m: 0,
        }
    }

    /// Adds an unknown (its wrench) with its row.
    #[inline(always)]
    fn push(&mut self, force: [f64; 3], torque: [f64; 3], jv: [f64; 3], jw: [f64; 3], rhs: f64) {
        let i = self.n;
        self.force[i] = force;
        self.torque[i] = torque;
        self.jv[i] = jv;
        self.jw[i] = jw;
        self.rhs[i] = rhs;
        self.n += 1;
    }

    /// The unknowns, and the matrix's diagonal; `resp(f, t)` is the (dv, dw) a wrench makes.
    /// The (dv, dw) each unknown's wrench makes; `resp(f, t)` gives one.
    #[inline(always)]
    fn responses(&mut self, resp: impl Fn([f64; 3], [f64; 3]) -> ([f64; 3], [f64; 3])) {
        for c in 0..self.n {
            (self.dv[c], self.dw[c]) = resp(self.force[c], self.torque[c]);
        }
    }

    /// The unknowns and the matrix's diagonal, from the wrenches' responses.
    #[inline(always)]
    fn solve(&mut self) {
        let n = self.n;
        let (dv, dw) = (&self.dv, &self.dw);
        if n == 1 {
            // One unknown (one part sliding): no elimination.
            let a = dot(self.jv[0], dv[0]) + dot(self.jw[0], dw[0]);
            self.diag[0] = a;
            self.x[0] = if a != 0.0 { self.rhs[0] / a } else { 0.0 };
            return;
        }
        let (x, diag) = (&mut self.x, &mut self.diag);
        let mut a = [[0.0; U]; U];
        for c in 0..n {
            for r in 0..n {
                a[r][c] = dot(self.jv[r], dv[c]) + dot(self.jw[r], dw[c]);
            }
        }
        let mut big = 0.0f64;
        for i in 0..n {
            diag[i] = a[i][i];
            for j in 0..n {
                big = big.max(a[i][j].abs());
            }
        }
        let mut b = self.rhs;
        // Row echelon form by Gaussian elimination with partial pivoting. A column without a
        // pivot (below 1e-13 of the matrix's size) belongs to a redundant constraint: two
        // sticking parts fix more than the body's freedoms (a cone rolling on its tip and its
        // rim), and the forces along the line between them are statically indeterminate.
        let mut pivot_col = [usize::MAX; U];
        let mut free = [false; U];
        let mut rows = 0;
        for k in 0..n {
            let p = (rows..n)
                .max_by(|&i, &j| a[i][k].abs().total_cmp(&a[j][k].abs()))
                .unwrap_or(rows);
            if rows == n || a[p][k].abs() <= 1e-13 * big {
                free[k] = true;
                continue;
            }
            a.swap(rows, p);
            b.swap(rows, p);
            for i in rows + 1..n {
                let f = a[i][k] / a[rows][k];
                if f != 0.0 {
                    for j in k..n {
                        a[i][j] -= f * a[rows][j];
                    }
                    b[i] -= f * b[rows];
                }
            }
            pivot_col[rows] = k;
            rows += 1;
        }
        // The solution with the free unknowns at zero, by back substitution.
        let back = |x: &mut [f64; U], b: &[f64; U]| {
            for r in (0..rows).rev() {
                let k = pivot_col[r];
                let s: f64 = (k + 1..n).map(|j| a[r][j] * x[j]).sum();
                x[k] = (b[r] - s) / a[r][k];
            }
        };
        *x = [0.0; U];
        back(x, &b);
        if rows == n {
            return;
        }
        // Redundant: of all the solutions, the one of least sum_i w_i x_i^2 (the weights
        // make a drilling torque count as the force it takes of the friction ellipse). The
        // null space's basis: one vector per free unknown (it at 1, the other free ones at
        // 0, the pivots from the homogeneous rows).
        let basis = &mut self.basis;
        let mut m = 0;
        for f in 0..n {
            if free[f] {
                basis[m][f] = 1.0;
                back(&mut basis[m], &[0.0; U]);
                m += 1;
            }
        }
        self.m = m;
        let w = &self.weight;
        // (N^T W N) c = -N^T W x, then x += N c.
        let mut g = [[0.0; U]; U];
        let mut h = [0.0; U];
        for i in 0..m {
            for j in 0..m {
                g[i][j] = (0..n).map(|r| basis[i][r] * w[r] * basis[j][r]).sum();
            }
            h[i] = -(0..n).map(|r| basis[i][r] * w[r] * x[r]).sum::<f64>();
        }
        // A small symmetric positive definite system: elimination without pivoting.
        for k in 0..m {
            for i in k + 1..m {
                let f = g[i][k] / g[k][k];
                for j in k..m {
                    g[i][j] -= f * g[k][j];
                }
                h[i] -= f * h[k];
            }
        }
        let mut c = [0.0; U];
        for k in (0..m).rev() {
            let s: f64 = (k + 1..m).map(|j| g[k][j] * c[j]).sum();
            c[k] = (h[k] - s) / g[k][k];
        }
        for i in 0..m {
            for r in 0..n {
                x[r] += c[i] * basis[i][r];
            }
        }
    }
}

/// What each unknown of a contact system is.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Unknown {
    /// A sliding part's normal force, its friction per unit N given.
    SlipN {
        part: usize,
        ft: [f64; 2],
        mz: f64,
        /// The friction's power per unit N at the part's slip and drilling rates.
        power: f64,
    },
    /// A sticking part's normal force.
    StickN(usize),
    /// A sticking part's tangential force along x or y.
    StickT(usize, usize),
    /// A sticking part's drilling torque (Coulomb-Contensou).
    StickM(usize),
}

impl PlayTop {
    /// The space-frame kinematics of a state.
    #[inline]
    pub fn mkin(&self, y: &[f64; DIM]) -> MKin {
        let q = Quat([y[0], y[1], y[2], y[3]]);
        let r = q.unit_matrix();
        let wb = [y[4], y[5], y[6]];
        let w = super::to_space(&r, wb);
        MKin {
            q,
            r,
            wb,
            w,
            e3: [r[0][2], r[1][2], r[2][2]],
            v: [y[10], y[11], y[12]],
            zg: y[9],
        }
    }

    /// The parts in use.
    fn part(&self, i: usize) -> &Shape {
        &self.parts.shape[i]
    }

    /// The change of G's velocity and of the space angular velocity an impulse (or force)
    /// `f` with moment `t` about G makes (per unit time for a force).
    fn response(&self, k: &MKin, f: [f64; 3], t: [f64; 3]) -> ([f64; 3], [f64; 3]) {
        let tb = k.to_body(t);
        let dwb = [tb[0] / self.a, tb[1] / self.a, tb[2] / self.c];
        (scale(1.0 / self.m, f), k.to_space(dwb))
    }

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
        let sp = (vp[0] * vp[0] + vp[1] * vp[1]).sqrt();
        // Creeping (the measure at or below `creep`, a direction set): the full friction
        // against the force sticking would need.
        let creeping = |d: f64| creep > 0.0 && d <= creep && dir != [0.0; 2];
        match self.friction {
            Friction::Coulomb { mu } => {
                // (Point Coulomb friction keeps the direction of the slip above zero: its
                // creep at the cone's edge follows the slip, and a direction fixed at the
                // switch would make the force jump where the two part, at every step.)
                if sp > 0.0 {
                    ([-mu * vp[0] / sp, -mu * vp[1] / sp], 0.0)
                } else {
                    ([-mu * dir[0], -mu * dir[1]], 0.0)
                }
            }
            Friction::CoulombContensou { mu, .. } => {
                let rb = self.friction.rbar();
                let d = (sp * sp + rb * rb * wn * wn).sqrt();
                if d > 0.0 && !creeping(d) {
                    ([-mu * vp[0] / d, -mu * vp[1] / d], -mu * rb * rb * wn / d)
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

    /// Contact forces and the state derivative with the parts in `c` (several-part
    /// equations; see the module's notes).
    pub fn multi_dynamics(&self, c: &Contacts, y: &[f64; DIM], dy: &mut [f64; DIM]) -> Forces {
        // All touching parts sliding: one unknown per part, a small system (one part sliding,
        // the common case: one unknown).
        let modes = &c.mode[..self.parts.n];
        if c.flat {
            return self.flat_dynamics(c, y, dy);
        }
        if modes.contains(&Mode::Roll) {
            self.dynamics_of::<MAXU>(c, y, dy)
        } else if modes.iter().filter(|&&m| m == Mode::Slip).count() <= 1 {
            self.dynamics_of::<1>(c, y, dy)
        } else {
            self.dynamics_of::<MAX_PARTS>(c, y, dy)
        }
    }

    /// [`Self::multi_dynamics`] with systems of at most `U` unknowns.
    #[inline(always)]
    fn dynamics_of<const U: usize>(
        &self,
        c: &Contacts,
        y: &[f64; DIM],
        dy: &mut [f64; DIM],
    ) -> Forces {
        let k = self.mkin(y);
        let (euler, res_n_b, res_0_b) = self.free_terms(&k);
        let wd0 = k.to_space(add(
            euler,
            [
                res_0_b[0] / self.a,
                res_0_b[1] / self.a,
                res_0_b[2] / self.c,
            ],
        ));
        let vd0 = [0.0, 0.0, -self.g];
        let res_n = k.to_space(res_n_b);
        let mut sys = System::<U>::new();
        let mut what = [Unknown::StickN(0); U];
        self.contact_system(c, &k, res_n, vd0, wd0, &mut sys, &mut what);
        sys.responses(|f, t| self.response(&k, f, t));
        sys.solve();
        if sys.m > 0 {
            self.most_margin(&mut sys, &what);
        }
        let (x, diag, dvs, dws) = (&sys.x, &sys.diag, &sys.dv, &sys.dw);
        let mut out = Forces::default();
        let (mut vd, mut wd) = (vd0, wd0);
        let mut n_total = 0.0;
        let mut p_friction = 0.0;
        for j in 0..sys.n {
            vd = add(vd, scale(x[j], dvs[j]));
            wd = add(wd, scale(x[j], dws[j]));
            match what[j] {
                Unknown::SlipN {
                    part,
                    ft,
                    mz,
                    power,
                } => {
                    let n = x[j];
                    out.n[part] = n;
                    out.ft[part] = [n * ft[0], n * ft[1]];
                    out.mz[part] = n * mz;
                    out.den[part] = diag[j];
                    n_total += n;
                    p_friction += n * power;
                }
                Unknown::StickN(part) => {
                    out.n[part] = x[j];
                    n_total += x[j];
                }
                Unknown::StickT(part, axis) => out.ft[part][axis] = x[j],
                Unknown::StickM(part) => out.mz[part] = x[j],
            }
        }
        let wdb = k.to_body(wd);
        dy[..4].copy_from_slice(&k.q.half_times_pure(k.wb));
        dy[4..7].copy_from_slice(&wdb);
        dy[7..10].copy_from_slice(&k.v);
        dy[10..13].copy_from_slice(&vd);
        let p_res = if self.has_resistance() {
            dot(add(scale(n_total, res_n_b), res_0_b), k.wb)
        } else {
            0.0
        };
        dy[13] = -(p_friction + p_res);
        out
    }

    /// Euler's term `I^-1 (-w x I w)` (body) and the resistance torques per unit N and not
    /// (body).
    fn free_terms(&self, k: &MKin) -> ([f64; 3], [f64; 3], [f64; 3]) {
        let e = (self.a - self.c) / self.a;
        let euler = [e * k.wb[1] * k.wb[2], -e * k.wb[0] * k.wb[2], 0.0];
        let (res_n, res_0) = if self.has_resistance() {
            self.resistance_at(k.wb, k.r[2], self.parts.reach())
        } else {
            (ZERO, ZERO)
        };
        (euler, res_n, res_0)
    }

    /// The contact forces' system of the parts in `c` at the kinematics `k`, with the free
    /// accelerations (vd0, wd0) and the resistance torque per unit N `res_n` (space).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn contact_system<const U: usize>(
        &self,
        c: &Contacts,
        k: &MKin,
        res_n: [f64; 3],
        vd0: [f64; 3],
        wd0: [f64; 3],
        sys: &mut System<U>,
        what: &mut [Unknown; U],
    ) {
        let contensou = self.friction.rbar() > 0.0;
        let free = |jv: [f64; 3], jw: [f64; 3]| dot(jv, vd0) + dot(jw, wd0);
        for i in 0..self.parts.n {
            let p = self.part(i);
            if c.mode[i] == Mode::Flight {
                continue;
            }
            let arm = p.arm(k.e3);
            let jw_n = cross(arm, EZ);
            let rhs_n = -(free(EZ, jw_n) + p.gap_bias(k.w, k.e3));
            match c.mode[i] {
                Mode::Flight => {}
                Mode::Slip => {
                    let vp = p.point_velocity(k.v, k.w, k.e3);
                    let (ft, mz) = self.friction_per_n(vp, k.w[2], c.dir[i], c.creep);
                    let f = [ft[0], ft[1], 1.0];
                    let t = add(add(cross(arm, f), scale(mz, EZ)), res_n);
                    let power = ft[0] * vp[0] + ft[1] * vp[1] + mz * k.w[2];
                    what[sys.n] = Unknown::SlipN {
                        part: i,
                        ft,
                        mz,
                        power,
                    };
                    sys.push(f, t, EZ, jw_n, rhs_n);
                }
                Mode::Roll => {
                    what[sys.n] = Unknown::StickN(i);
                    sys.push(EZ, add(jw_n, res_n), EZ, jw_n, rhs_n);
                    let bias = p.slip_bias(k.w, k.e3);
                    for (axis, e) in [EX, EY].into_iter().enumerate() {
                        let jw = cross(arm, e);
                        what[sys.n] = Unknown::StickT(i, axis);
                        sys.push(e, jw, e, jw, -(free(e, jw) + bias[axis]));
                    }
                    if contensou {
                        what[sys.n] = Unknown::StickM(i);
                        let rb = self.friction.rbar();
                        sys.weight[sys.n] = 1.0 / (rb * rb);
                        sys.push(ZERO, EZ, ZERO, EZ, -free(ZERO, EZ));
                    }
                }
            }
        }
    }

    /// A redundant system of sticking parts (two parts fix more than the body's freedoms,
    /// and the forces along the line between them are statically indeterminate): where the
    /// least-norm split leaves a part outside its cone, of the solutions, which all move the
    /// body alike, the one whose smallest friction margin ([`Self::stick_margin`]) is
    /// largest, so the parts stick wherever some split of the forces lets them. The margins are concave in the forces, their minimum too: a direct
    /// search (Nelder and Mead) over the null space from the least-norm solution finds it.
    fn most_margin<const U: usize>(&self, sys: &mut System<U>, what: &[Unknown; U]) {
        let n = sys.n;
        let worst = |x: &[f64; U]| -> f64 {
            let mut f = Forces::default();
            let mut sticks = [false; MAX_PARTS];
            for j in 0..n {
                match what[j] {
                    Unknown::StickN(i) => {
                        f.n[i] = x[j];
                        sticks[i] = true;
                    }
                    Unknown::StickT(i, axis) => f.ft[i][axis] = x[j],
                    Unknown::StickM(i) => f.mz[i] = x[j],
                    Unknown::SlipN { .. } => {}
                }
            }
            (0..MAX_PARTS)
                .filter(|&i| sticks[i])
                .map(|i| self.stick_margin(&f, i))
                .fold(f64::INFINITY, f64::min)
        };
        let m = sys.m;
        let x0 = sys.x;
        let at = |c: &[f64; U]| -> [f64; U] {
            let mut x = x0;
            for (i, ci) in c.iter().enumerate().take(m) {
                for r in 0..n {
                    x[r] += ci * sys.basis[i][r];
                }
            }
            x
        };
        // Where the least-norm split already holds every part, it is kept: the search is
        // for the splits that hold where that one does not (the margins then jump, but only
        // between positive values, so no event sees a false zero).
        let start = worst(&x0);
        if !start.is_finite() || start >= 0.0 {
            return;
        }
        // The simplex: the least-norm point and a step along each null vector, a tenth of
        // the forces' size in the weighted norm.
        let size = (0..n)
            .map(|r| sys.weight[r] * x0[r] * x0[r])
            .sum::<f64>()
            .sqrt()
            .max(f64::MIN_POSITIVE);
        let mut pts = [[0.0; U]; U];
        let mut val = [0.0; U];
        val[0] = -start;
        for i in 0..m {
            let len = (0..n)
                .map(|r| sys.weight[r] * sys.basis[i][r] * sys.basis[i][r])
                .sum::<f64>()
                .sqrt();
            pts[i + 1][i] = 0.1 * size / len.max(f64::MIN_POSITIVE);
            val[i + 1] = -worst(&at(&pts[i + 1]));
        }
        let k = m + 1;
        for _ in 0..200 * m {
            // order: best (least -margin) first
            let mut idx: [usize; U] = core::array::from_fn(|i| i);
            idx[..k].sort_by(|&a, &b| val[a].total_cmp(&val[b]));
            let (best, worst_i, second) = (idx[0], idx[k - 1], idx[k - 2]);
            if val[worst_i] - val[best] <= 1e-13 * size {
                break;
            }
            let mut cen = [0.0; U];
            for &p in &idx[..k - 1] {
                for d in 0..m {
                    cen[d] += pts[p][d] / m as f64;
                }
            }
            let towards = |f: f64| -> [f64; U] {
                core::array::from_fn(|d| cen[d] + f * (pts[worst_i][d] - cen[d]))
            };
            let r = towards(-1.0);
            let fr = -worst(&at(&r));
            if fr < val[best] {
                let e = towards(-2.0);
                let fe = -worst(&at(&e));
                (pts[worst_i], val[worst_i]) = if fe < fr { (e, fe) } else { (r, fr) };
            } else if fr < val[second] {
                (pts[worst_i], val[worst_i]) = (r, fr);
            } else {
                let cpt = towards(0.5);
                let fc = -worst(&at(&cpt));
                if fc < val[worst_i] {
                    (pts[worst_i], val[worst_i]) = (cpt, fc);
                } else {
                    for &p in &idx[1..k] {
                        for d in 0..m {
                            pts[p][d] = pts[best][d] + 0.5 * (pts[p][d] - pts[best][d]);
                        }
                        val[p] = -worst(&at(&pts[p]));
                    }
                }
            }
        }
        let best = (0..k)
            .min_by(|&a, &b| val[a].total_cmp(&val[b]))
            .unwrap_or(0);
        if val[best] < -start {
            sys.x = at(&pts[best]);
        }
    }

    /// The gap's acceleration of part `i` from a state derivative `dy`.
    pub fn gap_acceleration(&self, i: usize, y: &[f64; DIM], dy: &[f64; DIM]) -> f64 {
        let k = self.mkin(y);
        let p = self.part(i);
        let wd = k.to_space([dy[4], dy[5], dy[6]]);
        dy[12] + dot(wd, cross(p.arm(k.e3), EZ)) + p.gap_bias(k.w, k.e3)
    }

    /// The ring part lying flat at `y`, if one does: a torus touching (its gap within
    /// `tol`) whose plane is within [`super::hybrid::FLAT_LEVEL`] of the floor's, and no
    /// other part lower.
    pub fn lying_flat(&self, y: &[f64; DIM], tol: f64) -> Option<usize> {
        if self.g <= 0.0 {
            return None;
        }
        let k = self.mkin(y);
        let tilt = k.e3[0].hypot(k.e3[1]);
        if tilt >= super::hybrid::FLAT_LEVEL {
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
    /// speed of a point of its rim is at most this times sqrt 2.
    pub fn flat_slide(&self, i: usize, y: &[f64; DIM]) -> f64 {
        let k = self.mkin(y);
        let r = match *self.part(i) {
            Shape::Torus { major, .. } => major,
            _ => 0.0,
        };
        (k.v[0] * k.v[0] + k.v[1] * k.v[1] + r * r * k.w[2] * k.w[2]).sqrt()
    }

    /// Puts a state on the flat contact of ring part `i`: the figure axis exactly vertical
    /// (the orientation a turn about it from upright or from upside down, so that the
    /// integration keeps it exactly), no tilting rate, G at the ring's resting height with no
    /// vertical velocity, and where `stuck` no motion at all. The kinetic energy removed
    /// (a plastic impact of the ring's face on the floor) is added to the dissipated energy;
    /// where the height's change would raise the energy, the velocities are scaled to keep
    /// it.
    pub fn flat_project(&self, i: usize, y: &mut [f64; DIM], stuck: bool) {
        let before = self.kinetic_energy(y) + self.m * self.g * y[9];
        let k = self.mkin(y);
        let up = k.e3[2] >= 0.0;
        let wz = if stuck { 0.0 } else { k.w[2] };
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
        let (z, minor) = match *self.part(i) {
            Shape::Torus { z, minor, .. } => (z, minor),
            _ => (0.0, 0.0),
        };
        y[9] = minor - z * u;
        if stuck {
            y[10] = 0.0;
            y[11] = 0.0;
        }
        y[12] = 0.0;
        let after = self.kinetic_energy(y) + self.m * self.g * y[9];
        self.shed_energy(y, after - before);
    }

    /// The impact of ring part `i` coming down flat (its plane within
    /// [`super::hybrid::FLAT_LEVEL`] of the floor's) with restitution `e`: the whole rim
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
            let k = self.mkin(y);
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

    /// The equations of a ring lying flat (part `i` of `c`, the one touching): its plane on
    /// the floor, it slides and spins about the vertical, `m dv/dt = F`, `C dw_z/dt = M_z`,
    /// the normal force `m g` spread evenly over the rim of radius R (the moment the friction
    /// makes about G is taken by the spread, which is not resolved). The friction law acts at
    /// every point of the rim (Coulomb-Contensou with its own patch there): its force and
    /// moment are the rim's mean over 64 points (closed forms for viscous friction: `F = -mu
    /// N v`, `M_z = -mu N R^2 w_z`; for a rim spinning without sliding under Coulomb
    /// friction, `M_z = -mu N R sign(w_z)`). A ring stuck flat (mode roll) rests.
    pub fn flat_dynamics(&self, c: &Contacts, y: &[f64; DIM], dy: &mut [f64; DIM]) -> Forces {
        let k = self.mkin(y);
        let i = (0..self.parts.n)
            .find(|&j| c.mode[j] != Mode::Flight)
            .unwrap_or(0);
        let mut f = Forces::default();
        *dy = [0.0; DIM];
        let n = self.m * self.g;
        f.n[i] = n;
        f.den[i] = 1.0 / self.m;
        if c.mode[i] == Mode::Roll {
            return f;
        }
        let r = match *self.part(i) {
            Shape::Torus { major, .. } => major,
            _ => 0.0,
        };
        let (v, wz) = ([k.v[0], k.v[1]], k.w[2]);
        let (mut fx, mut fy, mut mz) = (0.0, 0.0, 0.0);
        match self.friction {
            Friction::Frictionless => {}
            Friction::Viscous { mu } => {
                fx = -mu * n * v[0];
                fy = -mu * n * v[1];
                mz = -mu * n * r * r * wz;
            }
            _ => {
                const NQ: usize = 64;
                let w = n / NQ as f64;
                for j in 0..NQ {
                    let phi = (j as f64 + 0.5) * std::f64::consts::TAU / NQ as f64;
                    let (sn, cs) = phi.sin_cos();
                    let (rx, ry) = (r * cs, r * sn);
                    let vp = [v[0] - wz * ry, v[1] + wz * rx, 0.0];
                    let (ft, md) = self.friction_per_n(vp, wz, [0.0; 2], 0.0);
                    fx += w * ft[0];
                    fy += w * ft[1];
                    mz += w * (rx * ft[1] - ry * ft[0] + md);
                }
            }
        }
        f.ft[i] = [fx, fy];
        f.mz[i] = mz;
        // Resistance torques about the vertical (the horizontal ones are taken by the floor).
        let (res_n, res_0) = self.resistance_at(k.wb, k.to_body(EZ), self.reach());
        let res = k.to_space(add(scale(n, res_n), res_0))[2];
        let u = k.e3[2].signum();
        dy[..4].copy_from_slice(&k.q.half_times_pure(k.wb));
        dy[6] = u * (mz + res) / self.c;
        dy[7] = v[0];
        dy[8] = v[1];
        dy[10] = fx / self.m;
        dy[11] = fy / self.m;
        dy[13] = -(fx * v[0] + fy * v[1] + (mz + res) * wz);
        f
    }

    /// The gap's acceleration of part `i` in free flight (no contact force) at `y`.
    pub fn free_gap_acceleration(&self, i: usize, y: &[f64; DIM]) -> f64 {
        let mut dy = [0.0; DIM];
        self.multi_dynamics(&Contacts::NONE, y, &mut dy);
        self.gap_acceleration(i, y, &dy)
    }

    /// Whether the friction a sticking part needs lies in its cone (Coulomb) or ellipse
    /// (Coulomb-Contensou), with a pushing normal force.
    pub fn stick_margin(&self, f: &Forces, i: usize) -> f64 {
        let rb = self.friction.rbar();
        let m = if rb > 0.0 { f.mz[i] / rb } else { 0.0 };
        let t = f.ft[i][0] * f.ft[i][0] + f.ft[i][1] * f.ft[i][1];
        self.friction.mu() * f.n[i] - (t + m * m).sqrt()
    }

    /// Jellett's integral about the first part's lowest point: `-L . arm` (the classic
    /// `L . (s e3 + rho ez)` for a tip sphere below G).
    pub fn multi_jellett(&self, y: &[f64; DIM]) -> f64 {
        let k = self.mkin(y);
        let l = k.to_space(self.momentum(k.wb));
        -dot(l, self.part(0).arm(k.e3))
    }

    /// A length scale of the top: its parts' largest reach.
    pub fn reach(&self) -> f64 {
        self.parts.reach()
    }

    /// A speed scale of the motion: reach |omega| + |v| + sqrt(g reach).
    pub fn multi_speed_scale(&self, y: &[f64; DIM]) -> f64 {
        let k = self.mkin(y);
        let l = self.reach();
        l * dot(k.w, k.w).sqrt() + dot(k.v, k.v).sqrt() + (self.g * l).sqrt()
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
            let (yi, _) = self.multi_impact(y, cand, [0.0; MAX_PARTS]);
            *y = yi;
        }
        let c = self.resolve_at(y, cand, prev, eps).unwrap_or_else(|| {
            let mut c = Contacts::NONE;
            for i in 0..self.parts.n {
                if cand & (1 << i) != 0 {
                    c.mode[i] = Mode::Slip;
                }
            }
            c
        });
        (c, true)
    }

    /// [`Self::resolve`] without the impact: None where no set (the empty one included) is
    /// consistent.
    fn resolve_at(&self, y: &[f64; DIM], cand: u8, prev: &Contacts, eps: f64) -> Option<Contacts> {
        let n = self.parts.n;
        let k = self.mkin(y);
        let mut base = Contacts {
            mode: [Mode::Flight; MAX_PARTS],
            dir: prev.dir,
            flat: false,
            creep: prev.creep,
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
            let push = (0..n).all(|i| c.mode[i] == Mode::Flight || f.n[i] >= 0.0);
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
            let f = self.multi_dynamics(c, y, dy);
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
        let k = self.mkin(y);
        (0..self.parts.n).fold(0, |acc, i| {
            let p = self.part(i);
            let on = p.gap(k.zg, k.e3) <= tol && p.gap_rate(k.v[2], k.w, k.e3) <= vtol;
            acc | (u8::from(on) << i)
        })
    }

    /// Puts a state on the constraints of its touching parts: G's height and vertical
    /// velocity from the parts touching (their mean where several touch), and its whole
    /// velocity from the first sticking part. Normalises the quaternion.
    pub fn multi_project(&self, c: &Contacts, y: &mut [f64; DIM]) {
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
        let mut k = self.mkin(y);
        if stick.is_some() && self.friction.rbar() > 0.0 && k.w[2] != 0.0 {
            // Sticking over a patch neither slides nor drills (D = 0): the drilling rate left
            // at the switch (below the tolerance over rbar) and its drift are removed.
            let wb = k.to_body([k.w[0], k.w[1], 0.0]);
            y[4..7].copy_from_slice(&wb);
            k = self.mkin(y);
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
        if let Some(i) = stick {
            let v = scale(-1.0, cross(k.w, self.part(i).arm(k.e3)));
            y[10] = v[0];
            y[11] = v[1];
        }
        self.shed_energy(y, self.kinetic_energy(y) - before);
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
        let (pi, pj) = (self.part(i), self.part(j));
        let k = self.mkin(y);
        let mut u = k.e3[2].clamp(-1.0, 1.0);
        for _ in 0..8 {
            let ((fi, di, _), (fj, dj, _)) = (pi.profile(u), pj.profile(u));
            let slope = pi.z() - pj.z() - di + dj;
            if slope.abs() <= 1e-12 * self.reach() {
                return;
            }
            let step = ((pi.z() - pj.z()) * u - fi + fj) / slope;
            u -= step;
            if u.is_nan() || u.abs() >= 1.0 {
                return;
            }
            if step.abs() <= 1e-15 {
                break;
            }
        }
        let axis = cross(EZ, k.e3);
        let s = dot(axis, axis).sqrt();
        if s <= 1e-12 {
            return;
        }
        let n = scale(1.0 / s, axis);
        let delta = u.acos() - k.e3[2].clamp(-1.0, 1.0).acos();
        let q = Quat::from_axis_angle(n, delta).hamilton(k.q).normalized();
        y[..4].copy_from_slice(&q.0);
        let before = self.kinetic_energy(y);
        let w = add(k.w, scale(-dot(k.w, n), n));
        let k1 = self.mkin(y);
        let wb = k1.to_body(w);
        y[4..7].copy_from_slice(&wb);
        y[13] += (before - self.kinetic_energy(y)).max(0.0);
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
    /// stops the contact point (it sticks). Returns the state after the impulse (the kinetic
    /// energy it takes added to the dissipated energy), or None where the part is not jammed,
    /// has no friction, or the process does not end.
    pub fn jam_impact(&self, y: &[f64; DIM], i: usize) -> Option<[f64; DIM]> {
        let (mu, viscous) = match self.friction {
            Friction::Viscous { mu } => (mu, true),
            Friction::Coulomb { mu } | Friction::CoulombContensou { mu, .. } => (mu, false),
            Friction::Frictionless => return None,
        };
        if mu <= 0.0 {
            return None;
        }
        let k = self.mkin(y);
        let arm = self.part(i).arm(k.e3);
        // K: the contact point's velocity change per unit impulse (columns).
        let col = |e: [f64; 3]| {
            let (dv, dw) = self.response(&k, e, cross(arm, e));
            add(dv, cross(dw, arm))
        };
        let kc = [col(EX), col(EY), col(EZ)];
        let kmul = |p: [f64; 3]| {
            add(
                add(scale(p[0], kc[0]), scale(p[1], kc[1])),
                scale(p[2], kc[2]),
            )
        };
        let v0 = self.part(i).point_velocity(k.v, k.w, k.e3);
        let vs = self.multi_speed_scale(y);
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
        let apply = |p: [f64; 3]| {
            let mut out = *y;
            let (dv, dw) = self.response(&k, p, cross(arm, p));
            let dwb = k.to_body(dw);
            for ax in 0..3 {
                out[4 + ax] += dwb[ax];
                out[10 + ax] += dv[ax];
            }
            let ke = self.kinetic_energy(y);
            let loss = ke - self.kinetic_energy(&out);
            if loss < -1e-12 * ke {
                return None;
            }
            out[13] += loss.max(0.0);
            Some(out)
        };
        for _ in 0..200_000 {
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
            if !compressed && vn[2] >= v[2] {
                // Sliding's own coefficient is still (just) positive: the normal force is
                // growing without bound as it heads for zero (the dynamic jam), and its
                // friction stops the slip first. That is the impulse that stops the contact
                // point, where it lies in the friction cone.
                let stop = solve3(transpose(kc), scale(-1.0, v0));
                let inside = stop[2] > 0.0 && stop[0].hypot(stop[1]) <= mu * stop[2];
                return if !viscous && inside {
                    apply(stop)
                } else {
                    None
                };
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
    pub fn multi_impact(
        &self,
        y: &[f64; DIM],
        set: u8,
        target: [f64; MAX_PARTS],
    ) -> ([f64; DIM], u8) {
        self.multi_impact_keeping(y, set, target, 0)
    }

    /// [`Self::multi_impact`] where the parts of `keep` (bit mask) take an impulse (they may
    /// not separate).
    ///
    /// Where no choice is consistent with the targets (a part striking the floor while
    /// another rests on it: restitution at the one may need the other to pull), the impact
    /// is taken without restitution, and where that too fails, also without friction: the
    /// frictionless plastic impact always has a consistent choice (its impulses solve a
    /// linear complementarity problem with a positive semi-definite matrix) and takes energy.
    pub fn multi_impact_keeping(
        &self,
        y: &[f64; DIM],
        set: u8,
        target: [f64; MAX_PARTS],
        keep: u8,
    ) -> ([f64; DIM], u8) {
        let plastic = target.map(|t| t.min(0.0));
        self.impact_search(y, set, target, keep, true)
            .or_else(|| self.impact_search(y, set, plastic, keep, true))
            .or_else(|| self.impact_search(y, set, plastic, keep, false))
            .unwrap_or((*y, 0))
    }

    /// [`Self::multi_impact_keeping`] with one set of targets, with or without friction:
    /// None where no choice is consistent.
    fn impact_search(
        &self,
        y: &[f64; DIM],
        set: u8,
        target: [f64; MAX_PARTS],
        keep: u8,
        friction: bool,
    ) -> Option<([f64; DIM], u8)> {
        let n = self.parts.n;
        let k = self.mkin(y);
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
        let tol_v = 1e-12 * self.multi_speed_scale(y);
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
            let (mut dv, mut dw) = (ZERO, ZERO);
            for &i in &parts {
                let torque = add(cross(self.part(i).arm(k.e3), imp[i]), scale(drill[i], EZ));
                let (a, b) = self.response(&k, imp[i], torque);
                dv = add(dv, a);
                dw = add(dw, b);
            }
            let dwb = k.to_body(dw);
            for ax in 0..3 {
                out[4 + ax] += dwb[ax];
                out[10 + ax] += dv[ax];
            }
            let k1 = self.mkin(&out);
            let ok = parts.iter().zip(&combo).all(|(&i, &choice)| {
                let pi = imp[i];
                let after = self.part(i).point_velocity(k1.v, k1.w, k1.e3);
                match choice {
                    0 => {
                        let m = if rb > 0.0 { drill[i] / rb } else { 0.0 };
                        pi[2] >= 0.0
                            && (pi[0] * pi[0] + pi[1] * pi[1] + m * m).sqrt()
                                <= mu * pi[2] * (1.0 + 1e-12)
                    }
                    1 => {
                        pi[2] >= 0.0 && vp[i][0] * after[0] + vp[i][1] * after[1] >= -tol_v * tol_v
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotation::quaternion_from_euler;

    fn ball(friction: Friction, parts: &[Shape]) -> PlayTop {
        PlayTop::with_parts(0.006, 8e-7, 7e-7, parts, 9.81, friction, 0.0, 0.0, 0.0, 0.0).unwrap()
    }

    /// A system whose matrix is `a` (unit wrenches, rows picking its entries), solved.
    fn solved<const U: usize>(a: &[[f64; 3]], rhs: &[f64], weight: &[f64]) -> [f64; U] {
        let mut sys = System::<U>::new();
        for (c, &b) in rhs.iter().enumerate() {
            let mut e = ZERO;
            e[c] = 1.0;
            sys.push(e, ZERO, ZERO, ZERO, b);
            sys.weight[c] = weight[c];
        }
        for (r, row) in a.iter().enumerate() {
            sys.jv[r] = *row; // a[r][c] = jv[r] . e_c
        }
        sys.responses(|f, t| (f, t));
        sys.solve();
        sys.x
    }

    /// A redundant column before a determined one: the pivot of the determined column is in
    /// the row the redundant column passed (the elimination used to skip that row and leave
    /// the determined unknown at 0).
    #[test]
    fn every_pivot_is_found_after_a_redundant_column() {
        let a = [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, 0.0]];
        let x: [f64; 3] = solved(&a, &[1.0, 2.0, 0.0], &[1.0; 3]);
        assert_eq!(x, [0.0, 1.0, 2.0]);
    }

    /// Of the solutions of a redundant system, the one of least weighted norm: x0 + x1 = 2
    /// with weights (1, 3) gives x0 = 3/2, x1 = 1/2 (the minimum of x0^2 + 3 x1^2 on it).
    #[test]
    fn a_redundant_system_takes_its_least_weighted_norm_solution() {
        let a = [[1.0, 1.0, 0.0], [1.0, 1.0, 0.0], [0.0, 0.0, 2.0]];
        let x: [f64; 3] = solved(&a, &[2.0, 2.0, 1.0], &[1.0, 3.0, 1.0]);
        assert!(
            (x[0] - 1.5).abs() < 1e-14 && (x[1] - 0.5).abs() < 1e-14,
            "{x:?}"
        );
        assert!((x[2] - 0.5).abs() < 1e-15);
    }

    /// Two sticking parts whose tangential forces along x only appear as their sum (the
    /// statically indeterminate split), mu = 0.3, normal forces `n0`, `n1`, the sum `t`:
    /// (the least-norm split, the null space's dimension, the split `most_margin` takes).
    fn split(n0: f64, n1: f64, t: f64) -> ([f64; MAXU], usize, [f64; MAXU]) {
        let top = ball(
            Friction::Coulomb { mu: 0.3 },
            &[Shape::Sphere {
                radius: 0.01,
                z: 0.0,
            }],
        );
        let mut sys = System::<MAXU>::new();
        let mut what = [Unknown::StickN(0); MAXU];
        // unknowns N0, T0x, T0y, N1, T1x, T1y: unit wrenches in force (0..3) and torque (3..6)
        let unit = |c: usize| {
            let mut e = ZERO;
            e[c % 3] = 1.0;
            if c < 3 {
                (e, ZERO)
            } else {
                (ZERO, e)
            }
        };
        let kinds = [
            Unknown::StickN(0),
            Unknown::StickT(0, 0),
            Unknown::StickT(0, 1),
            Unknown::StickN(1),
            Unknown::StickT(1, 0),
            Unknown::StickT(1, 1),
        ];
        // rows: N0 = n0, T0y = 0, N1 = n1, T1y = 0, T0x + T1x = t (twice: redundant)
        let rows: [(&[usize], f64); 6] = [
            (&[0], n0),
            (&[2], 0.0),
            (&[3], n1),
            (&[5], 0.0),
            (&[1, 4], t),
            (&[1, 4], t),
        ];
        for (c, kind) in kinds.into_iter().enumerate() {
            let (f, t) = unit(c);
            what[c] = kind;
            let (cols, b) = rows[c];
            let (mut jv, mut jw) = (ZERO, ZERO);
            for &k in cols {
                let (fk, tk) = unit(k);
                jv = add(jv, fk);
                jw = add(jw, tk);
            }
            sys.push(f, t, jv, jw, b);
        }
        sys.responses(|f, t| (f, t));
        sys.solve();
        let least_norm = sys.x;
        top.most_margin(&mut sys, &what);
        (least_norm, sys.m, sys.x)
    }

    /// Normal forces 1 and 3 N, the sum T = 1 N: the least-norm split, 0.5 N each, leaves
    /// part 0 outside its cone (margin 0.3 - 0.5 N). The split of largest smallest margin
    /// makes the margins equal, mu N0 - t0 = mu N1 - t1 with t0 + t1 = T: t0 = (T - mu (N1 -
    /// N0)) / 2 = 0.2 N, margins 0.1 N each.
    #[test]
    fn an_indeterminate_split_takes_the_largest_smallest_margin() {
        let (least_norm, m, x) = split(1.0, 3.0, 1.0);
        assert_eq!(m, 1);
        assert!((least_norm[1] - 0.5).abs() < 1e-14 && (least_norm[4] - 0.5).abs() < 1e-14);
        assert!(
            (x[1] - 0.2).abs() < 1e-9 && (x[4] - 0.8).abs() < 1e-9,
            "{x:?}"
        );
        assert!((x[0] - 1.0).abs() < 1e-12 && (x[3] - 3.0).abs() < 1e-12);
        assert!(x[2].abs() < 1e-12 && x[5].abs() < 1e-12);
    }

    /// Normal forces 2 and 3 N, T = 0.5 N: the least-norm split (0.25 N each, margins 0.35
    /// and 0.65 N) holds both parts and is kept (no search on such right-hand sides).
    #[test]
    fn a_split_that_holds_is_kept() {
        let (least_norm, m, x) = split(2.0, 3.0, 0.5);
        assert_eq!(m, 1);
        assert!((least_norm[1] - 0.25).abs() < 1e-14 && (least_norm[4] - 0.25).abs() < 1e-14);
        assert_eq!(x, least_norm);
    }

    /// One sphere under the several-part equations gives the one-sphere equations' right-hand
    /// side, in every mode and friction law.
    #[test]
    fn one_sphere_equals_the_classic_equations() {
        let parts = [Shape::Sphere {
            radius: 0.015,
            z: -0.003,
        }];
        let q = quaternion_from_euler(0.4, 2.1, -0.7);
        for friction in [
            Friction::Coulomb { mu: 0.3 },
            Friction::Viscous { mu: 1.0 },
            Friction::Frictionless,
        ] {
            let top = ball(friction, &parts);
            assert!(top.is_classic());
            let y = top.state(q, [3.0, -2.0, 150.0], 0.05, -0.03, None).unwrap();
            for mode in [Mode::Slip, Mode::Roll, Mode::Flight] {
                let (mut a, mut b) = ([0.0; DIM], [0.0; DIM]);
                let c = top.dynamics(mode, &y, [0.6, -0.8, 0.0], &mut a);
                let mut cs = Contacts::NONE;
                cs.mode[0] = mode;
                cs.dir[0] = [0.6, -0.8];
                let f = top.multi_dynamics(&cs, &y, &mut b);
                let scale = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                for i in 0..DIM {
                    assert!(
                        (a[i] - b[i]).abs() <= 1e-9 * a[i].abs() + 1e-14 * scale,
                        "{friction:?} {mode:?} {i}: {} {}",
                        a[i],
                        b[i]
                    );
                }
                assert!((c.n - f.n[0]).abs() <= 1e-10 * c.n.abs().max(1e-12));
            }
        }
    }
}
