//! The contact forces and the equations of motion of a top on a floor, with any set of
//! parts touching, each sliding or sticking (theory: several parts).
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

use super::friction::rim_coulomb;
use super::parts::{Shape, MAX_PARTS};
use super::{add, scale, solve3, Contacts, Friction, Mode, PlayTop, DIM};
use crate::rotation::{cross, dot, Quat};

pub(super) const EX: [f64; 3] = [1.0, 0.0, 0.0];
pub(super) const EY: [f64; 3] = [0.0, 1.0, 0.0];
pub(super) const EZ: [f64; 3] = [0.0, 0.0, 1.0];
pub(super) const ZERO: [f64; 3] = [0.0; 3];

/// The matrix whose columns are `cols` (rows of `cols` as columns).
pub(super) fn transpose(cols: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    [
        [cols[0][0], cols[1][0], cols[2][0]],
        [cols[0][1], cols[1][1], cols[2][1]],
        [cols[0][2], cols[1][2], cols[2][2]],
    ]
}
/// The most unknowns of one system: four per part.
pub(super) const MAXU: usize = 4 * MAX_PARTS;

/// The equations a set of contacts is integrated with: the fast kernels of the common
/// phases (no part touching, one part sliding, one part sticking, a ring lying flat), else
/// the joint system of every touching part's unknowns (its size: each sliding part one, each
/// sticking part three, four under Coulomb-Contensou friction).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Kernel {
    /// No part touches.
    Flight,
    /// Part i alone touches, sliding.
    OneSlip(usize),
    /// A sphere alone touches, sliding under viscous, Coulomb or no friction and no
    /// resistance torque: the ball's own equations in the body frame (the classic play top's
    /// phase, its cheapest form).
    BallSlip {
        /// The part.
        i: usize,
        /// Its centre's distance below G along the figure axis (m).
        s: f64,
        /// Its radius (m).
        rho: f64,
    },
    /// Part i alone touches, sticking.
    OneStick(usize),
    /// Part i alone touches, creeping ([`Contacts::creeping`]).
    Creep(usize),
    /// Part i alone touches, its slip stopped while its patch drills
    /// ([`Contacts::drilling`]).
    Drill(usize),
    /// A ring lies flat.
    Flat,
    /// The joint system of this many unknowns.
    System(usize),
}

/// The kernels by code, for the integrator's compile-time choice ([`PlayTop::rates_as`]):
/// each common phase gets an integrator with only its own kernel inlined into its stages.
pub(crate) mod code {
    /// [`super::Kernel::Flight`].
    pub const FLIGHT: u8 = 0;
    /// [`super::Kernel::BallSlip`].
    pub const BALL: u8 = 1;
    /// [`super::Kernel::OneSlip`].
    pub const ONE_SLIP: u8 = 2;
    /// [`super::Kernel::OneStick`].
    pub const ONE_STICK: u8 = 3;
    /// Any other kernel (a ring lying flat, the joint systems): not inlined.
    pub const OTHER: u8 = 4;
    /// [`super::Kernel::Creep`].
    pub const CREEP: u8 = 5;
}

impl Kernel {
    /// The kernel's [`code`].
    pub(crate) fn code(self) -> u8 {
        match self {
            Kernel::Flight => code::FLIGHT,
            Kernel::BallSlip { .. } => code::BALL,
            Kernel::OneSlip(_) => code::ONE_SLIP,
            Kernel::OneStick(_) => code::ONE_STICK,
            Kernel::Creep(_) => code::CREEP,
            Kernel::Flat | Kernel::System(_) | Kernel::Drill(_) => code::OTHER,
        }
    }

    /// The kernel of the contacts `c` of `top`.
    pub(crate) fn of(top: &PlayTop, c: &Contacts) -> Kernel {
        if c.flat {
            return Kernel::Flat;
        }
        let n = top.parts.n;
        let per_stick = if top.friction.rbar() > 0.0 { 4 } else { 3 };
        let (mut touching, mut first, mut unknowns) = (0, 0, 0);
        for i in (0..n).rev() {
            match c.mode[i] {
                Mode::Flight => continue,
                Mode::Slip => unknowns += 1,
                Mode::Roll => unknowns += per_stick,
            }
            touching += 1;
            first = i;
        }
        match (touching, c.mode[first]) {
            (0, _) => Kernel::Flight,
            (1, Mode::Slip) if c.creeping & (1 << first) != 0 && top.friction.can_stick() => {
                Kernel::Creep(first)
            }
            (1, Mode::Slip) => match (top.parts.shape[first], top.friction) {
                (
                    Shape::Sphere { radius, z },
                    Friction::Viscous { .. } | Friction::Coulomb { .. } | Friction::Frictionless,
                ) if !top.has_resistance() => Kernel::BallSlip {
                    i: first,
                    s: -z,
                    rho: radius,
                },
                _ => Kernel::OneSlip(first),
            },
            (1, Mode::Roll) if c.drilling & (1 << first) != 0 => Kernel::Drill(first),
            (1, Mode::Roll) => Kernel::OneStick(first),
            _ => Kernel::System(unknowns),
        }
    }
}

/// A part's rows ([`PlayTop::stick_rows`]): each contact force component's row measure and
/// the angular acceleration it gives.
type Rows = ([[f64; 3]; 3], [[f64; 3]; 3]);

/// The ratios of a top's inertia the kernels use, computed once per phase (divisions in a
/// right-hand side's dependency chain cost more than their count says).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Consts {
    inv_m: f64,
    inv_a: f64,
    inv_c: f64,
    /// `1/C - 1/A`.
    kappa: f64,
    /// `(A - C) / A`.
    euler: f64,
    /// The side of each resistance's kink (0: rolling, 1: drilling) a phase's equations
    /// keep to ([`PlayTop::resistance_on`]): -1 the linear law, +1 the sharp law, each
    /// continued smoothly past the kink, where the phase ends ([`super::driver::Switch::Band`]);
    /// 0 the law the rate picks.
    pub(crate) side: [f64; 2],
}

impl Consts {
    /// The ratios of `top`.
    pub(crate) fn of(top: &PlayTop) -> Consts {
        Consts {
            inv_m: 1.0 / top.m,
            inv_a: 1.0 / top.a,
            inv_c: 1.0 / top.c,
            kappa: 1.0 / top.c - 1.0 / top.a,
            euler: (top.a - top.c) / top.a,
            side: [0.0; 2],
        }
    }

    /// `J^-1 t` in the space frame: the symmetric top's inverse inertia about G,
    /// `t / A + (1/C - 1/A) (e3 . t) e3` (no rotation to the body frame and back).
    #[inline(always)]
    fn inv_inertia(&self, k: &Kin, t: [f64; 3]) -> [f64; 3] {
        let kt = self.kappa * dot(k.e3, t);
        [
            self.inv_a * t[0] + kt * k.e3[0],
            self.inv_a * t[1] + kt * k.e3[1],
            self.inv_a * t[2] + kt * k.e3[2],
        ]
    }
}

/// Kinematics of a state in the space frame.
#[derive(Debug, Clone, Copy)]
pub struct Kin {
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

impl Kin {
    #[inline(always)]
    pub(super) fn to_space(self, v: [f64; 3]) -> [f64; 3] {
        super::to_space(&self.r, v)
    }
    #[inline(always)]
    pub(super) fn to_body(self, v: [f64; 3]) -> [f64; 3] {
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
pub(super) struct System<const U: usize> {
    pub(super) n: usize,
    pub(super) force: [[f64; 3]; U],
    pub(super) torque: [[f64; 3]; U],
    pub(super) jv: [[f64; 3]; U],
    pub(super) jw: [[f64; 3]; U],
    pub(super) rhs: [f64; U],
    /// The (dv, dw) each wrench makes ([`System::responses`]).
    pub(super) dv: [[f64; 3]; U],
    pub(super) dw: [[f64; 3]; U],
    /// The unknowns and the matrix's diagonal ([`System::solve`]).
    pub(super) x: [f64; U],
    pub(super) diag: [f64; U],
    /// Each unknown's weight in the norm a redundant system's solution minimises: 1 for a
    /// force, 1/rbar^2 for a drilling torque (the friction ellipse's metric).
    pub(super) weight: [f64; U],
    /// A redundant system's null space: `m` vectors (the solutions are `x + basis c`).
    pub(super) basis: [[f64; U]; U],
    pub(super) m: usize,
    /// A lower bound on the null space's dimension that the geometry gives (0: none known):
    /// two material points at rest leave a rigid body one freedom of the six their rows
    /// would fix, `(v_j - v_i) . (r_j - r_i) = 0` whatever the motion, so two sticking
    /// parts are always redundant ([`Self::solve`]).
    pub(super) structural: usize,
}

impl<const U: usize> System<U> {
    #[inline(always)]
    pub(super) fn new() -> System<U> {
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
            structural: 0,
        }
    }

    /// Adds an unknown (its wrench) with its row.
    #[inline(always)]
    pub(super) fn push(
        &mut self,
        force: [f64; 3],
        torque: [f64; 3],
        jv: [f64; 3],
        jw: [f64; 3],
        rhs: f64,
    ) {
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
    pub(super) fn responses(&mut self, resp: impl Fn([f64; 3], [f64; 3]) -> ([f64; 3], [f64; 3])) {
        for c in 0..self.n {
            (self.dv[c], self.dw[c]) = resp(self.force[c], self.torque[c]);
        }
    }

    /// The unknowns and the matrix's diagonal, from the wrenches' responses. A system whose
    /// smallest pivot lies between the rank test's 1e-13 and 1e-10 of the matrix's size, and
    /// that found fewer redundant rows there than it may have (at least [`Self::structural`],
    /// and one), is solved both ways, and the redundant solution (its least-norm split) is
    /// taken where the geometry says the system is redundant, or where the full-rank solution
    /// is more than [`NEAR_REDUNDANT`] times the least-norm one in size: its split then comes
    /// from the rounding of a structurally redundant system. (Two sticking parts always are:
    /// a top rolling steadily on its tip and a sphere was split by rounding, its tip's
    /// friction left its cone and the tip crept, its ledger rising 6.9e-9 of E over 5 s: the
    /// floor campaign's case 2129 of seed 23.)
    #[inline(always)]
    pub(super) fn solve(&mut self) {
        let least = self.solve_with(1e-13);
        if self.n > 1 && self.m < self.structural.max(1) && least <= 1e-10 {
            let (x, m, basis) = (self.x, self.m, self.basis);
            self.solve_with(1e-10);
            let size = |x: &[f64; U]| {
                (0..self.n)
                    .map(|r| self.weight[r] * x[r] * x[r])
                    .sum::<f64>()
            };
            let keep = self.m <= m
                || self.structural == 0
                    && size(&x) <= NEAR_REDUNDANT * NEAR_REDUNDANT * size(&self.x);
            if keep {
                (self.x, self.m, self.basis) = (x, m, basis);
            }
        }
    }

    /// [`Self::solve`] with the rank test at `tol` of the matrix's size: returns the smallest
    /// pivot taken, as a share of that size (infinite with one unknown).
    #[inline(always)]
    fn solve_with(&mut self, tol: f64) -> f64 {
        let n = self.n;
        let (dv, dw) = (&self.dv, &self.dw);
        if n == 1 {
            // One unknown (one part sliding): no elimination.
            let a = dot(self.jv[0], dv[0]) + dot(self.jw[0], dw[0]);
            self.diag[0] = a;
            self.x[0] = if a != 0.0 { self.rhs[0] / a } else { 0.0 };
            self.m = 0;
            return f64::INFINITY;
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
        // pivot (below 1e-10 of the matrix's size) belongs to a redundant constraint: two
        // sticking parts fix more than the body's freedoms (a cone rolling on its tip and its
        // rim), and the forces along the line between them are statically indeterminate.
        // The elimination's rounding can leave such a pivot above 1e-13 of the size (a top
        // sticking on its sphere and sharp rim: 9e-14 to 1e-12 where the needed friction
        // turned through an axis): the system taken as full rank there gave a split of
        // +-2835 N on a 3 g top and a false roll_to_slip located on it (the floor campaign's
        // case 3369 of seed 1); see [`Self::solve`].
        let mut least = f64::INFINITY;
        let mut pivot_col = [usize::MAX; U];
        let mut free = [false; U];
        let mut rows = 0;
        for k in 0..n {
            let p = (rows..n)
                .max_by(|&i, &j| a[i][k].abs().total_cmp(&a[j][k].abs()))
                .unwrap_or(rows);
            if rows == n || a[p][k].abs() <= tol * big {
                free[k] = true;
                continue;
            }
            least = least.min(a[p][k].abs() / big);
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
            self.m = 0;
            return least;
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
        least
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

/// Sliding parts' friction per unit normal force (tangential force, drilling torque) given
/// instead of their law's, part by part ([`PlayTop::joint_creep_friction`]).
type FrictionOver = [Option<([f64; 2], f64)>; MAX_PARTS];

/// No friction given: every sliding part's law.
const NO_OVER: FrictionOver = [None; MAX_PARTS];

/// How much larger than a near-redundant system's least-norm solution its full-rank one
/// may be and still be taken ([`System::solve`]).
const NEAR_REDUNDANT: f64 = 100.0;

/// The most Gauss-Seidel sweeps of the joint creep of several parts
/// ([`PlayTop::joint_creep_all`]).
const JOINT_SWEEPS: usize = 12;

impl PlayTop {
    /// The space-frame kinematics of a state.
    #[inline]
    pub fn kin(&self, y: &[f64; DIM]) -> Kin {
        let q = Quat([y[0], y[1], y[2], y[3]]);
        let r = q.unit_matrix();
        let wb = [y[4], y[5], y[6]];
        let w = super::to_space(&r, wb);
        Kin {
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
    pub(super) fn part(&self, i: usize) -> &Shape {
        &self.parts.shape[i]
    }

    /// The change of G's velocity and of the space angular velocity an impulse (or force)
    /// `f` with moment `t` about G makes (per unit time for a force).
    #[inline(always)]
    pub(super) fn response(&self, k: &Kin, f: [f64; 3], t: [f64; 3]) -> ([f64; 3], [f64; 3]) {
        (scale(1.0 / self.m, f), Consts::of(self).inv_inertia(k, t))
    }

    /// Contact forces and the state derivative with the parts in `c` (see the module's
    /// notes): the kernel [`Kernel::of`] chooses, run.
    pub fn dynamics(&self, c: &Contacts, y: &[f64; DIM], dy: &mut [f64; DIM]) -> Forces {
        let mut out = Forces::default();
        self.rates(Kernel::of(self, c), &Consts::of(self), c, y, dy, &mut out);
        out
    }

    /// [`Self::dynamics`] by the kernel `kernel` (chosen once per phase), the forces written
    /// to `out` (only the touching parts' entries: a phase's cache keeps the others at zero).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn rates(
        &self,
        kernel: Kernel,
        p: &Consts,
        c: &Contacts,
        y: &[f64; DIM],
        dy: &mut [f64; DIM],
        out: &mut Forces,
    ) {
        // The resistance torques compiled in or out once per call (not looked up at each use).
        let res = self.has_resistance();
        match (kernel, res) {
            (Kernel::Flight, false) => self.flight_rates::<false>(p, y, dy),
            (Kernel::Flight, true) => self.flight_rates::<true>(p, y, dy),
            (Kernel::BallSlip { i, s, rho }, _) => {
                self.ball_slip_rates(p, c, i, s, rho, y, dy, out)
            }
            (Kernel::OneSlip(i), false) => self.one_slip_rates::<false, false>(p, c, i, y, dy, out),
            (Kernel::OneSlip(i), true) => self.one_slip_rates::<true, false>(p, c, i, y, dy, out),
            (Kernel::OneStick(i), false) => self.one_stick_rates::<false, false>(p, i, y, dy, out),
            (Kernel::OneStick(i), true) => self.one_stick_rates::<true, false>(p, i, y, dy, out),
            (Kernel::Creep(i), false) => self.one_slip_rates::<false, true>(p, c, i, y, dy, out),
            (Kernel::Creep(i), true) => self.one_slip_rates::<true, true>(p, c, i, y, dy, out),
            (Kernel::Drill(i), false) => self.one_stick_rates::<false, true>(p, i, y, dy, out),
            (Kernel::Drill(i), true) => self.one_stick_rates::<true, true>(p, i, y, dy, out),
            (Kernel::Flat, _) => *out = self.flat_dynamics(c, y, dy),
            (Kernel::System(u), _) => match u {
                0..=2 => self.dynamics_of::<2>(p, c, y, dy, out),
                3 | 4 => self.dynamics_of::<4>(p, c, y, dy, out),
                5..=8 => self.dynamics_of::<8>(p, c, y, dy, out),
                _ => self.dynamics_of::<MAXU>(p, c, y, dy, out),
            },
        }
    }

    /// [`Self::rates`] with the kernel's code `K` ([`Kernel::code`]) and the resistance
    /// torques (`RES`, [`Self::has_resistance`]) fixed at compile time: the integrator of a
    /// phase inlines only its own kernel (every kernel inlined into every stage made the
    /// ball's phase 28 % dearer in instructions than on its own). A `kernel` of another code
    /// runs through [`Self::rates_of`], the same equations.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn rates_as<const K: u8, const RES: bool>(
        &self,
        kernel: Kernel,
        p: &Consts,
        c: &Contacts,
        y: &[f64; DIM],
        dy: &mut [f64; DIM],
        out: &mut Forces,
    ) {
        match (K, kernel) {
            (code::FLIGHT, Kernel::Flight) => self.flight_rates::<RES>(p, y, dy),
            (code::BALL, Kernel::BallSlip { i, s, rho }) => {
                self.ball_slip_rates(p, c, i, s, rho, y, dy, out)
            }
            (code::ONE_SLIP, Kernel::OneSlip(i)) => {
                self.one_slip_rates::<RES, false>(p, c, i, y, dy, out)
            }
            (code::ONE_STICK, Kernel::OneStick(i)) => {
                self.one_stick_rates::<RES, false>(p, i, y, dy, out)
            }
            (code::CREEP, Kernel::Creep(i)) => {
                self.one_slip_rates::<RES, true>(p, c, i, y, dy, out)
            }
            _ => self.rates_of(kernel, p, c, y, dy, out),
        }
    }

    /// [`Self::rates`], not inlined.
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn rates_of(
        &self,
        kernel: Kernel,
        p: &Consts,
        c: &Contacts,
        y: &[f64; DIM],
        dy: &mut [f64; DIM],
        out: &mut Forces,
    ) {
        self.rates(kernel, p, c, y, dy, out)
    }

    /// [`Self::dynamics`] with systems of at most `U` unknowns. Not inlined: the joint
    /// systems (and their indeterminate splits) are large code, and inlined into every
    /// stage of the integrator beside the one-part kernels they crowded the instruction
    /// cache of the common phases. A part creeping beside others takes the joint system's
    /// consistent creep ([`Self::joint_creep_friction`]).
    #[inline(never)]
    fn dynamics_of<const U: usize>(
        &self,
        p: &Consts,
        c: &Contacts,
        y: &[f64; DIM],
        dy: &mut [f64; DIM],
        out: &mut Forces,
    ) {
        let k = self.kin(y);
        let (wd0, res_n, res_0) = self.free_terms_any(p, &k);
        let vd0 = [0.0, 0.0, -self.g];
        let over = self.joint_creep_all::<U>(p, c, &k, res_n, vd0, wd0);
        let (vd, wd, p_friction, n_total) =
            self.joint_solve::<U>(c, &k, res_n, vd0, wd0, over, out);
        let p = p_friction + self.resistance_power::<true>(&k, n_total, res_n, res_0);
        Self::write_rates(&k, vd, wd, p, dy);
    }

    /// The creeping parts of `c` (sliding, marked creeping, not a ring lying flat), a mask.
    pub(crate) fn joint_creepers(c: &Contacts, n: usize) -> u8 {
        if c.flat || c.creeping == 0 {
            return 0;
        }
        c.creeping & c.mask_of(Mode::Slip, n)
    }

    /// The friction per unit normal force of every creeping part of `c`
    /// ([`Self::joint_creep_friction`]). Several parts creeping together (a top on two
    /// parts whose best split of the sticking forces reaches both cones' edges at once, so
    /// that both start to slide) each take the consistent creep given the others' friction,
    /// in Gauss-Seidel sweeps from the full friction against each one's direction `dir`,
    /// until no friction changes by more than 1e-12 of mu (at most [`JOINT_SWEEPS`]). A
    /// part creeping beside a part that slides under its law at a stopped slip instead (the
    /// law's direction at 1e-18 m/s chattered at every step: 460 000 steps in 4.4e-5 s, the
    /// floor campaign's case 3369 of seed 1).
    #[allow(clippy::too_many_arguments)]
    fn joint_creep_all<const U: usize>(
        &self,
        p: &Consts,
        c: &Contacts,
        k: &Kin,
        res_n: [f64; 3],
        vd0: [f64; 3],
        wd0: [f64; 3],
    ) -> FrictionOver {
        let n = self.parts.n;
        let creepers = Self::joint_creepers(c, n);
        let mut over = NO_OVER;
        if creepers == 0 {
            return over;
        }
        let each = || (0..n).filter(move |&i| creepers & (1 << i) != 0);
        if creepers.count_ones() == 1 {
            let i = creepers.trailing_zeros() as usize;
            over[i] = Some(self.joint_creep_friction::<U>(p, c, k, i, res_n, vd0, wd0, over));
            return over;
        }
        for i in each() {
            over[i] = Some(self.creep_along([0.0; 3], c.dir[i]));
        }
        let tol = 1e-12 * self.friction.mu();
        for _ in 0..JOINT_SWEEPS {
            let mut change = 0.0f64;
            for i in each() {
                let f = self.joint_creep_friction::<U>(p, c, k, i, res_n, vd0, wd0, over);
                if let Some((ft, mz)) = over[i] {
                    change = change
                        .max((f.0[0] - ft[0]).abs())
                        .max((f.0[1] - ft[1]).abs())
                        .max((f.1 - mz).abs());
                }
                over[i] = Some(f);
            }
            if change <= tol {
                break;
            }
        }
        over
    }

    /// The joint contact solve of the parts in `c` at the kinematics `k` with the free
    /// accelerations `(vd0, wd0)`: the forces written to `out`; returns G's acceleration,
    /// the angular acceleration (space), the friction's power and the total normal force.
    /// `over` gives one sliding part's friction per unit normal force instead of its law's.
    #[allow(clippy::too_many_arguments)]
    fn joint_solve<const U: usize>(
        &self,
        c: &Contacts,
        k: &Kin,
        res_n: [f64; 3],
        vd0: [f64; 3],
        wd0: [f64; 3],
        over: FrictionOver,
        out: &mut Forces,
    ) -> ([f64; 3], [f64; 3], f64, f64) {
        let mut sys = System::<U>::new();
        let mut what = [Unknown::StickN(0); U];
        self.contact_system(c, k, res_n, vd0, wd0, over, &mut sys, &mut what);
        sys.responses(|f, t| self.response(k, f, t));
        sys.solve();
        if sys.m > 0 {
            self.most_margin(&mut sys, &what);
        }
        let (x, diag, dvs, dws) = (&sys.x, &sys.diag, &sys.dv, &sys.dw);
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
        (vd, wd, p_friction, n_total)
    }

    /// The friction per unit normal force of part `i` creeping beside the other parts of
    /// `c` (theory: play top, "Creep: sliding at the edge of the cone"): the consistent
    /// sliding at zero slip of [`Self::creep_friction`], with the slip's acceleration taken
    /// from the joint system (the other parts sticking, sliding under their law or lying
    /// free as `c` has them). It is affine in the force at the part: the joint solve with the
    /// part sliding without friction gives the slip's free acceleration (its rate terms
    /// added) and normal force, and with a unit force (and, over a patch, a unit drilling
    /// torque per `rbar`) applied there the columns of the slip's response `W` and of the
    /// normal force's. The part slides in every one of those solves, so they have the
    /// unknowns of `c`'s own system (`U`). Other sliding parts' friction is `base`'s where
    /// given (other creeping parts), else their law's.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn joint_creep_friction<const U: usize>(
        &self,
        p: &Consts,
        c: &Contacts,
        k: &Kin,
        i: usize,
        res_n: [f64; 3],
        vd0: [f64; 3],
        wd0: [f64; 3],
        base: FrictionOver,
    ) -> ([f64; 2], f64) {
        let rb = self.friction.rbar();
        let part = self.part(i);
        let arm = part.arm(k.e3);
        let bias = part.slip_bias(k.w, k.e3);
        let accel = |vd: [f64; 3], wd: [f64; 3]| {
            let a = add(vd, cross(wd, arm));
            [a[0], a[1], rb * wd[2]]
        };
        let mut free = base;
        free[i] = Some(([0.0; 2], 0.0));
        let mut f0 = Forces::default();
        let (vd, wd, _, _) = self.joint_solve::<U>(c, k, res_n, vd0, wd0, free, &mut f0);
        let a0 = accel(vd, wd);
        let mut w = [[0.0; 3]; 3];
        let mut dn = [0.0; 3];
        for e in 0..if rb > 0.0 { 3 } else { 2 } {
            let (force, tz) = match e {
                0 => (EX, 0.0),
                1 => (EY, 0.0),
                _ => (ZERO, rb),
            };
            let torque = add(cross(arm, force), scale(tz, EZ));
            let vde = add(vd0, scale(1.0 / self.m, force));
            let wde = add(wd0, p.inv_inertia(k, torque));
            let mut fe = Forces::default();
            let (vd, wd, _, _) = self.joint_solve::<U>(c, k, res_n, vde, wde, free, &mut fe);
            let ae = accel(vd, wd);
            for r in 0..3 {
                w[r][e] = ae[r] - a0[r];
            }
            dn[e] = fe.n[i] - f0.n[i];
        }
        if rb <= 0.0 {
            w[2][2] = 1.0;
        }
        let size = w.iter().flatten().map(|v| v.abs()).fold(0.0, f64::max);
        if size <= 1e-9 / self.m || size.is_nan() {
            // The others hold the part's slip whatever its force (beside a part sticking
            // over a patch): no direction to take from the slip; the full friction against
            // `dir` (the force sticking needed where the part was set creeping).
            return self.creep_along([0.0; 3], c.dir[i]);
        }
        // The slip's acceleration without friction, its rate terms included.
        let wx = [-(a0[0] + bias[0]), -(a0[1] + bias[1]), -a0[2]];
        self.consistent_creep(wx, w, f0.n[i], dn, c.dir[i])
    }

    /// The angular acceleration with no contact force (space frame): Euler's term
    /// `J^-1 (-w x J w) = ((A - C) / A) (w . e3) (w x e3)` of the symmetric top, plus `J^-1`
    /// of the resistance torque that does not scale with N; and the resistance torques per
    /// unit N and not (space frame).
    #[inline(always)]
    fn free_terms<const RES: bool>(&self, p: &Consts, k: &Kin) -> ([f64; 3], [f64; 3], [f64; 3]) {
        let e = p.euler * dot(k.w, k.e3);
        let we = cross(k.w, k.e3);
        let euler = [e * we[0], e * we[1], e * we[2]];
        if !RES {
            return (euler, ZERO, ZERO);
        }
        let (res_n, res_0) = self.resistance_on(k.w, EZ, self.parts.reach(), p.side);
        (add(euler, p.inv_inertia(k, res_0)), res_n, res_0)
    }

    /// [`Self::free_terms`], the resistance torques looked up.
    fn free_terms_any(&self, p: &Consts, k: &Kin) -> ([f64; 3], [f64; 3], [f64; 3]) {
        if self.has_resistance() {
            self.free_terms::<true>(p, k)
        } else {
            self.free_terms::<false>(p, k)
        }
    }

    /// The power the resistance torques take (W) with the total normal force `n_total`.
    #[inline(always)]
    fn resistance_power<const RES: bool>(
        &self,
        k: &Kin,
        n_total: f64,
        res_n: [f64; 3],
        res_0: [f64; 3],
    ) -> f64 {
        if RES {
            dot(add(scale(n_total, res_n), res_0), k.w)
        } else {
            0.0
        }
    }

    /// Writes the state derivative from the accelerations of G (`vd`) and of the rotation
    /// (`wd`, space frame), and the dissipated power `p`.
    #[inline(always)]
    fn write_rates(k: &Kin, vd: [f64; 3], wd: [f64; 3], p: f64, dy: &mut [f64; DIM]) {
        dy[..4].copy_from_slice(&k.q.half_times_pure(k.wb));
        dy[4..7].copy_from_slice(&k.to_body(wd));
        dy[7..10].copy_from_slice(&k.v);
        dy[10..13].copy_from_slice(&vd);
        dy[13] = -p;
    }

    /// The kernel of no part touching: free flight.
    #[inline(always)]
    fn flight_rates<const RES: bool>(&self, p: &Consts, y: &[f64; DIM], dy: &mut [f64; DIM]) {
        let k = self.kin(y);
        let (wd0, res_n, res_0) = self.free_terms::<RES>(p, &k);
        let p = self.resistance_power::<RES>(&k, 0.0, res_n, res_0);
        Self::write_rates(&k, [0.0, 0.0, -self.g], wd0, p, dy);
    }

    /// The kernel of one part `i` touching and sliding (the common phase of every top on a
    /// floor): one unknown, its normal force, from the gap's acceleration being zero. With
    /// `CREEP`, the part creeps ([`Contacts::creeping`]): its friction is the consistent
    /// sliding's at zero slip ([`Self::creep_friction`]), not its slip's (theory: play top,
    /// "Creep: sliding at the edge of the cone").
    #[inline(always)]
    fn one_slip_rates<const RES: bool, const CREEP: bool>(
        &self,
        p: &Consts,
        c: &Contacts,
        i: usize,
        y: &[f64; DIM],
        dy: &mut [f64; DIM],
        out: &mut Forces,
    ) {
        let k = self.kin(y);
        let terms = self.free_terms::<RES>(p, &k);
        let arm = self.part(i).arm(k.e3);
        let vp = add(k.v, cross(k.w, arm));
        let fr = if CREEP {
            self.creep_friction(p, &k, i, terms.0, terms.1, c.dir[i])
        } else {
            self.friction_per_n(vp, k.w[2], c.dir[i], c.creep)
        };
        self.slide_rates::<RES>(p, &k, i, arm, vp, fr, terms, dy, out);
    }

    /// The friction per unit normal force of part `i` creeping alone on the floor: the
    /// sliding that is consistent at zero slip. In the ellipse's coordinates (the tangential
    /// force and `mz / rbar`, `mz` 0 under point Coulomb friction) let `x` be the force
    /// sticking needs and `W` the slip's response to the force (the contact's Delassus
    /// operator with the normal force eliminated), so that the slip accelerates at
    /// `W (F - x)`. Consistent sliding puts the full friction `F = -mu N s` against the slip
    /// direction `s` while the slip accelerates along `s`: `W (F - x) = -beta F` with
    /// `beta >= 0`, that is `F = (W + beta I)^-1 W x`, where `beta` is the root of
    /// `|F| = mu N(F)` (the normal force follows F through the gap's row). At the cone's edge
    /// `beta = 0` and `F = x`; `|F(beta)|` falls monotonically, so the root is bracketed
    /// and found by regula falsi. Where `x` lies inside the cone, `F = x` (the slip's
    /// acceleration is zero: the creep holds the slip until it ends in sticking, see
    /// [`super::driver::CREEP_STICK`]); where the normal force would pull, the full
    /// friction along `x`, or along `-dir` where `x` vanishes.
    #[inline(always)]
    fn creep_friction(
        &self,
        p: &Consts,
        k: &Kin,
        i: usize,
        wd0: [f64; 3],
        res_n: [f64; 3],
        dir: [f64; 2],
    ) -> ([f64; 2], f64) {
        let rows = self.stick_rows(p, k, i, res_n);
        let (xs, ns) = {
            let (x, mz) = self.stick_solve_with(p, k, i, wd0, rows);
            (self.ellipse_force(([x[0], x[1]], mz)), x[2])
        };
        // The slip's response, and the normal force as F moves off x.
        let Some((w, gn)) = self.slip_response(p, k, rows) else {
            return self.creep_along(xs, dir);
        };
        let dn = [-gn[0] / gn[3], -gn[1] / gn[3], -gn[2] / gn[3]];
        let wx = [dot(w[0], xs), dot(w[1], xs), dot(w[2], xs)];
        self.consistent_creep(wx, w, ns - dot(dn, xs), dn, dir)
    }

    /// The full friction along `f` (ellipse coordinates) per unit normal force, or against
    /// `dir` where `f` vanishes.
    #[inline(always)]
    fn creep_along(&self, f: [f64; 3], dir: [f64; 2]) -> ([f64; 2], f64) {
        let (mu, rb) = (self.friction.mu(), self.friction.rbar());
        let size = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
        if size > 0.0 {
            ([mu * f[0] / size, mu * f[1] / size], mu * rb * f[2] / size)
        } else {
            ([-mu * dir[0], -mu * dir[1]], 0.0)
        }
    }

    /// The consistent creep's friction per unit normal force ([`Self::creep_friction`]):
    /// the slip accelerates at `w F - wx` under the force `F` (ellipse coordinates; `wx =
    /// w x` with `x` the force sticking needs, where sticking is possible), the normal force
    /// is `N(F) = n0 + dn . F`. Consistent sliding: `w F - wx = -beta F`, `beta >= 0`, so
    /// `F(beta) = (w + beta I)^-1 wx` with `|F| = mu N(F)`. Where `w` is singular (a part
    /// beside a sticking one: the slip along the line between the contacts is tied to the
    /// other's, whatever the force) `F(0)` does not exist and `|F(beta)|` grows without
    /// bound as `beta` falls to 0; the root is bracketed all the same.
    #[inline(always)]
    fn consistent_creep(
        &self,
        wx: [f64; 3],
        w: [[f64; 3]; 3],
        n0: f64,
        dn: [f64; 3],
        dir: [f64; 2],
    ) -> ([f64; 2], f64) {
        let mu = self.friction.mu();
        let rb = self.friction.rbar();
        let along = |f: [f64; 3]| self.creep_along(f, dir);
        let normal = |f: [f64; 3]| n0 + dn[0] * f[0] + dn[1] * f[1] + dn[2] * f[2];
        let force = |beta: f64| {
            let mut m = w;
            for (a, row) in m.iter_mut().enumerate() {
                row[a] += beta;
            }
            solve3(m, wx)
        };
        let phi = |f: [f64; 3]| dot(f, f).sqrt() - mu * normal(f);
        let xs = force(0.0);
        let stick = xs.iter().all(|v| v.is_finite());
        let ns = normal(xs);
        if stick && ns <= 0.0 {
            return along(xs);
        }
        if stick && phi(xs) <= 0.0 {
            // Inside the cone: the force sticking needs, which holds the slip where it is
            // (of the order of the stick speed) until the creep ends in sticking.
            return ([xs[0] / ns, xs[1] / ns], rb * xs[2] / ns);
        }
        // Bracket: beta large enough that |F| has fallen below mu N.
        let scale = (w[0][0] + w[1][1] + w[2][2]).abs().max(f64::MIN_POSITIVE);
        let (mut lo, mut hi) = (0.0f64, scale);
        let f0 = if stick { phi(xs) } else { f64::INFINITY };
        let (mut f_lo, mut f_hi) = (f0, phi(force(hi)));
        let mut tries = 0;
        while f_hi > 0.0 && tries < 60 {
            lo = hi;
            f_lo = f_hi;
            hi *= 4.0;
            f_hi = phi(force(hi));
            tries += 1;
        }
        if f_hi > 0.0 || !f_hi.is_finite() {
            if normal([0.0; 3]) <= 0.0 {
                // No consistent creep: |F| - mu N(F) only grows as F shrinks from x (the
                // normal force falls faster than the friction), and without friction the
                // normal force would pull: lifting off is the consistent motion. No friction,
                // so the normal force is that pull and the lift-off's event function sees it
                // (the full friction along x instead would accelerate the slip along the
                // friction, feeding energy in; a random floor run chattered on it, turning the
                // creep back 180 000 times in 1.5 ms).
                return ([0.0; 2], 0.0);
            }
            return along(if stick { xs } else { wx });
        }
        // Regula falsi (Illinois) on phi(beta), to the rounding of beta.
        let mut side = 0i8;
        for _ in 0..60 {
            let b = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
            let b = if b > lo && b < hi { b } else { 0.5 * (lo + hi) };
            let fb = phi(force(b));
            if fb > 0.0 {
                lo = b;
                f_lo = fb;
                if side == 1 {
                    f_hi *= 0.5;
                }
                side = 1;
            } else {
                hi = b;
                f_hi = fb;
                if side == -1 {
                    f_lo *= 0.5;
                }
                side = -1;
            }
            if hi - lo <= 1e-14 * hi {
                break;
            }
        }
        let f = force(0.5 * (lo + hi));
        if normal(f) <= 0.0 {
            return along(if stick { xs } else { wx });
        }
        along(f)
    }

    /// Puts a creeping part `i`'s slip on the direction its creep's friction opposes: the
    /// slip's component across it, which the friction law would damp at the rate
    /// `mu N / (m* |slip|)` (the stiffness the creep steps over), is taken out by a tangential
    /// impulse at the contact (its normal part keeps the gap's rate). The slip kept is the
    /// projection onto the direction in the metric of the contact's inverse Delassus
    /// operator, so the impulse only takes kinetic energy (`-|s - s'|^2 / 2` in that metric);
    /// all of it where the slip points against the direction. At the creep's located turns
    /// ([`super::driver::Switch::CreepEnd`]). A part creeping beside others has its slip
    /// stopped instead, by the impulse there that keeps every gap's rate (it takes kinetic
    /// energy or is not applied, [`Self::stop_slips`]): the creep starts again from zero
    /// slip, along its consistent direction.
    pub(crate) fn creep_slave(&self, c: &Contacts, i: usize, y: &mut [f64; DIM]) {
        if c.mask(self.parts.n) != 1 << i {
            if let Some(out) = self.stop_slips(y, 1 << i, self.kept_gap_rates(y)) {
                *y = out;
            }
            return;
        }
        let dir = c.dir[i];
        let (p, k, wd0, res_n) = self.creep_terms(y);
        let f = self.ellipse_force(self.creep_friction(&p, &k, i, wd0, res_n, dir));
        let size = dot(f, f).sqrt();
        // (An impulse meets no resistance torque.)
        let rows = self.stick_rows(&p, &k, i, [0.0; 3]);
        let Some((w, gn)) = self.slip_response(&p, &k, rows).filter(|_| size > 0.0) else {
            return;
        };
        let d = scale(-1.0 / size, f);
        let s = self.ellipse_slip(&k, i);
        let wd = solve3(w, d);
        let along = dot(s, wd) / dot(d, wd);
        let keep = if along.is_finite() {
            along.max(0.0)
        } else {
            0.0
        };
        let pt = solve3(w, add(scale(keep, d), scale(-1.0, s)));
        if !pt.iter().all(|v| v.is_finite()) {
            return;
        }
        let imp = [
            pt[0],
            pt[1],
            -(gn[0] * pt[0] + gn[1] * pt[1] + gn[2] * pt[2]) / gn[3],
        ];
        let arm = self.part(i).arm(k.e3);
        let mut torque = cross(arm, imp);
        torque[2] += self.friction.rbar() * pt[2];
        self.kick(&k, y, imp, torque);
    }

    /// A creeping part's slip `s` (the contact point's horizontal velocity and, under
    /// Coulomb-Contensou friction, `rbar` times the drilling rate) and its projection on the
    /// direction the creep's friction opposes, `s . d` with `d = -F / |F|`, at `y`.
    pub(crate) fn creep_slip(&self, c: &Contacts, i: usize, y: &[f64; DIM]) -> (f64, f64) {
        let f = if c.mask(self.parts.n) == 1 << i {
            let (p, k, wd0, res_n) = self.creep_terms(y);
            self.ellipse_force(self.creep_friction(&p, &k, i, wd0, res_n, c.dir[i]))
        } else {
            let mut dy = [0.0; DIM];
            let f = self.dynamics(c, y, &mut dy);
            self.ellipse_force((f.ft[i], f.mz[i]))
        };
        let s = self.ellipse_slip(&self.kin(y), i);
        let size = dot(f, f).sqrt();
        let along = if size > 0.0 { -dot(s, f) / size } else { 0.0 };
        (dot(s, s).sqrt(), along)
    }

    /// How far the friction part `i` would need to stick at `y` lies inside its cone
    /// (ellipse) ([`Self::cone_margin`]), the other parts as `c` has them: negative while it
    /// creeps.
    pub(crate) fn creep_margin(&self, c: &Contacts, i: usize, y: &[f64; DIM]) -> f64 {
        if c.mask(self.parts.n) != 1 << i {
            let mut stuck = *c;
            stuck.mode[i] = Mode::Roll;
            stuck.creeping &= !(1 << i);
            stuck.drilling = 0;
            let mut dy = [0.0; DIM];
            return self.stick_margin(&self.dynamics(&stuck, y, &mut dy), i);
        }
        let (p, k, wd0, res_n) = self.creep_terms(y);
        let (x, mz) = self.stick_solve(&p, &k, i, wd0, res_n);
        self.cone_margin(x[2], [x[0], x[1]], mz)
    }

    /// The inertia ratios, kinematics, free angular acceleration and resistance torque per
    /// unit normal force at `y`, for the creep's functions outside a right-hand side.
    fn creep_terms(&self, y: &[f64; DIM]) -> (Consts, Kin, [f64; 3], [f64; 3]) {
        let p = Consts::of(self);
        let k = self.kin(y);
        let (wd0, res_n, _) = self.free_terms_any(&p, &k);
        (p, k, wd0, res_n)
    }

    /// A friction per unit normal force (tangential force, drilling torque) in the ellipse's
    /// coordinates `(f_x, f_y, mz / rbar)` (the third 0 under point Coulomb friction).
    fn ellipse_force(&self, (ft, mz): ([f64; 2], f64)) -> [f64; 3] {
        let rb = self.friction.rbar();
        [ft[0], ft[1], if rb > 0.0 { mz / rb } else { 0.0 }]
    }

    /// Part `i`'s slip in the ellipse's coordinates: the contact point's horizontal velocity
    /// and `rbar` times the drilling rate.
    fn ellipse_slip(&self, k: &Kin, i: usize) -> [f64; 3] {
        let vp = self.part(i).point_velocity(k.v, k.w, k.e3);
        [vp[0], vp[1], self.friction.rbar() * k.w[2]]
    }

    /// The state derivative with part `i` alone sliding under the friction `fr` per unit
    /// normal force (tangential force, drilling torque), the normal force from the gap's
    /// acceleration being zero; `terms` from [`Self::free_terms`].
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn slide_rates<const RES: bool>(
        &self,
        p: &Consts,
        k: &Kin,
        i: usize,
        arm: [f64; 3],
        vp: [f64; 3],
        fr: ([f64; 2], f64),
        terms: ([f64; 3], [f64; 3], [f64; 3]),
        dy: &mut [f64; DIM],
        out: &mut Forces,
    ) {
        let k = *k;
        let part = self.part(i);
        let ((ft, mz), (wd0, res_n, res_0)) = (fr, terms);
        let f = [ft[0], ft[1], 1.0];
        let t = add(add(cross(arm, f), [0.0, 0.0, mz]), res_n);
        let dw = p.inv_inertia(&k, t);
        let jw = cross(arm, EZ);
        let den = p.inv_m + dot(jw, dw);
        let rhs = self.g - dot(jw, wd0) - part.gap_bias(k.w, k.e3);
        let n = if den != 0.0 { rhs / den } else { 0.0 };
        let nm = n * p.inv_m;
        let vd = [nm * f[0], nm * f[1], nm - self.g];
        let wd = add(wd0, scale(n, dw));
        let power = ft[0] * vp[0] + ft[1] * vp[1] + mz * k.w[2];
        out.n[i] = n;
        out.ft[i] = [n * ft[0], n * ft[1]];
        out.mz[i] = n * mz;
        out.den[i] = den;
        let p_res = self.resistance_power::<RES>(&k, n, res_n, res_0);
        Self::write_rates(&k, vd, wd, n * power + p_res, dy);
    }

    /// The kernel of a sphere, part `i` (centre `s` below G, radius `rho`), sliding alone
    /// ([`Kernel::BallSlip`]), in the body frame (theory: play top): with the arm
    /// `a = -s e3 - rho gamma`, the normal force from the constraint
    /// `N/m - g - s d2u/dt2 = 0`, affine in N; the friction per unit N from the law. The same
    /// motion as [`Self::one_slip_rates`] (tested), in fewer operations.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn ball_slip_rates(
        &self,
        p: &Consts,
        c: &Contacts,
        i: usize,
        s: f64,
        rho: f64,
        y: &[f64; DIM],
        dy: &mut [f64; DIM],
        out: &mut Forces,
    ) {
        let q = Quat([y[0], y[1], y[2], y[3]]);
        let r = q.unit_matrix();
        let w = [y[4], y[5], y[6]];
        let v = [y[10], y[11], y[12]];
        let gamma = r[2];
        let a_b = [-rho * gamma[0], -rho * gamma[1], -s - rho * gamma[2]];
        // The slip velocity v + R (w x a), with w x a = rho gamma x w - s w x e3.
        let gdot = cross(gamma, w);
        let wa = [
            rho * gdot[0] - s * w[1],
            rho * gdot[1] + s * w[0],
            rho * gdot[2],
        ];
        let v_t = add(v, super::to_space(&r, wa));
        let (ft, _) = self.friction_per_n(v_t, 0.0, c.dir[i], 0.0);
        let f_s = [ft[0], ft[1], 1.0];
        let inv = |x: [f64; 3]| [x[0] * p.inv_a, x[1] * p.inv_a, x[2] * p.inv_c];
        let b0 = [p.euler * w[1] * w[2], -p.euler * w[0] * w[2], 0.0];
        let b1 = inv(cross(a_b, super::to_body(&r, f_s)));
        let k0 = cross(gdot, w)[2] + cross(gamma, b0)[2];
        let k1 = cross(gamma, b1)[2];
        let den = p.inv_m - s * k1;
        let n = if den != 0.0 {
            (self.g + s * k0) / den
        } else {
            0.0
        };
        let nm = n * p.inv_m;
        out.n[i] = n;
        out.ft[i] = [n * ft[0], n * ft[1]];
        out.den[i] = den;
        dy[..4].copy_from_slice(&q.half_times_pure(w));
        dy[4..7].copy_from_slice(&add(b0, scale(n, b1)));
        dy[7..10].copy_from_slice(&v);
        dy[10..13].copy_from_slice(&[nm * f_s[0], nm * f_s[1], nm - self.g]);
        dy[13] = -n * (ft[0] * v_t[0] + ft[1] * v_t[1]);
    }

    /// The kernel of one part `i` touching with its contact point at rest: its contact force
    /// and, under Coulomb-Contensou friction, its drilling torque. Sticking (`DRILL` false):
    /// the torque keeps the drilling rate, the 3 x 3 (4 x 4) system of the point's response
    /// solved directly. Drilling (`DRILL`, [`Contacts::drilling`]): the torque is the law's
    /// ([`Self::drill_solve`]) and takes `-M w_n` of power.
    #[inline(always)]
    fn one_stick_rates<const RES: bool, const DRILL: bool>(
        &self,
        p: &Consts,
        i: usize,
        y: &[f64; DIM],
        dy: &mut [f64; DIM],
        out: &mut Forces,
    ) {
        let k = self.kin(y);
        let (wd0, res_n, res_0) = self.free_terms::<RES>(p, &k);
        let rows = self.stick_rows(p, &k, i, res_n);
        let (x, mz) = if DRILL {
            self.drill_solve(p, &k, i, wd0, rows)
        } else {
            self.stick_solve_with(p, &k, i, wd0, rows)
        };
        let dw = rows.1;
        let mut wd = add(
            wd0,
            add(
                scale(x[0], dw[0]),
                add(scale(x[1], dw[1]), scale(x[2], dw[2])),
            ),
        );
        if self.friction.rbar() > 0.0 {
            wd = add(wd, scale(mz, p.inv_inertia(&k, EZ)));
        }
        let inv_m = p.inv_m;
        let vd = [inv_m * x[0], inv_m * x[1], inv_m * x[2] - self.g];
        out.n[i] = x[2];
        out.ft[i] = [x[0], x[1]];
        out.mz[i] = mz;
        let mut p_res = self.resistance_power::<RES>(&k, x[2], res_n, res_0);
        if DRILL {
            p_res += mz * k.w[2];
        }
        Self::write_rates(&k, vd, wd, p_res, dy);
    }

    /// Each contact force component's row measure at part `i` (`arm x e_j`, j = x, y, z) and
    /// the angular acceleration it gives (the normal one with the resistance torque per unit
    /// normal force `res_n`).
    #[inline(always)]
    fn stick_rows(
        &self,
        p: &Consts,
        k: &Kin,
        i: usize,
        res_n: [f64; 3],
    ) -> ([[f64; 3]; 3], [[f64; 3]; 3]) {
        let arm = self.part(i).arm(k.e3);
        let jw = [cross(arm, EX), cross(arm, EY), cross(arm, EZ)];
        let dw = [
            p.inv_inertia(k, jw[0]),
            p.inv_inertia(k, jw[1]),
            p.inv_inertia(k, add(jw[2], res_n)),
        ];
        (jw, dw)
    }

    /// The response of a part's slip, alone on the floor, in the ellipse's coordinates, from
    /// its rows ([`Self::stick_rows`]): with `g[r][j]` the acceleration of row r (slip
    /// x, slip y, `rbar` times the drilling rate's rate, the gap) per unit of force j (x, y,
    /// `mz / rbar`, normal), the slip's response `W` with the normal force eliminated (the
    /// Schur complement of `g[3][3]`) and the gap's row `g[3]`. Under point Coulomb friction
    /// the drilling row and column are the identity's. None where `g[3][3]` is not positive.
    #[inline(always)]
    fn slip_response(
        &self,
        p: &Consts,
        k: &Kin,
        (jw, dw): ([[f64; 3]; 3], [[f64; 3]; 3]),
    ) -> Option<([[f64; 3]; 3], [f64; 4])> {
        // Rows and columns in the order x, y, drilling, normal.
        const AT: [usize; 3] = [0, 1, 3];
        let mut g = [[0.0; 4]; 4];
        for r in 0..3 {
            for c in 0..3 {
                g[AT[r]][AT[c]] = dot(jw[r], dw[c]) + if r == c { p.inv_m } else { 0.0 };
            }
        }
        let rb = self.friction.rbar();
        if rb > 0.0 {
            let dwm = p.inv_inertia(k, EZ);
            for r in 0..3 {
                g[AT[r]][2] = rb * dot(jw[r], dwm);
                g[2][AT[r]] = rb * dw[r][2];
            }
            g[2][2] = rb * rb * dwm[2];
        } else {
            g[2][2] = 1.0;
        }
        let gnn = g[3][3];
        if gnn <= 0.0 || !gnn.is_finite() {
            return None;
        }
        let mut w = [[0.0; 3]; 3];
        for a in 0..3 {
            for b in 0..3 {
                w[a][b] = g[a][b] - g[a][3] * g[3][b] / gnn;
            }
        }
        Some((w, g[3]))
    }

    /// The contact force (x, y, normal) and drilling torque (0 but under Coulomb-Contensou
    /// friction) that keep part `i`, alone on the floor, at rest on it: the contact point's
    /// acceleration zero; the 3 x 3 (4 x 4) system of the point's response solved directly.
    /// `wd0` and `res_n` from [`Self::free_terms`].
    #[inline(always)]
    fn stick_solve(
        &self,
        p: &Consts,
        k: &Kin,
        i: usize,
        wd0: [f64; 3],
        res_n: [f64; 3],
    ) -> ([f64; 3], f64) {
        let rows = self.stick_rows(p, k, i, res_n);
        self.stick_solve_with(p, k, i, wd0, rows)
    }

    /// [`Self::stick_solve`] with the rows of [`Self::stick_rows`] given.
    #[inline(always)]
    fn stick_solve_with(
        &self,
        p: &Consts,
        k: &Kin,
        i: usize,
        wd0: [f64; 3],
        (jw, dw): ([[f64; 3]; 3], [[f64; 3]; 3]),
    ) -> ([f64; 3], f64) {
        let k = *k;
        let (a, rhs) = self.point_system(p, &k, i, wd0, (jw, dw));
        let rb = self.friction.rbar();
        let (x, mz) = if rb > 0.0 {
            // The drilling torque's column and row: the rotation's response to ez, and the
            // drilling rate's rate.
            let dwm = p.inv_inertia(&k, EZ);
            let col: [f64; 3] = core::array::from_fn(|r| dot(jw[r], dwm));
            let row: [f64; 3] = core::array::from_fn(|j| dw[j][2]);
            let (amm, rm) = (dwm[2], -wd0[2]);
            // Eliminate the torque: (a - col row / amm) x = rhs - col rm / amm.
            let mut s = a;
            let mut b = rhs;
            for r in 0..3 {
                for j in 0..3 {
                    s[r][j] -= col[r] * row[j] / amm;
                }
                b[r] -= col[r] * rm / amm;
            }
            let x = solve3(s, b);
            let mz = (rm - dot(row, x)) / amm;
            (x, mz)
        } else {
            (solve3(a, rhs), 0.0)
        };
        (x, mz)
    }

    /// The 3 x 3 system of the contact force (x, y, normal) that keeps part `i`'s material
    /// point at rest on the floor (its acceleration zero), from the rows of
    /// [`Self::stick_rows`]: the point's response per unit force, and what it must change by.
    #[inline(always)]
    fn point_system(
        &self,
        p: &Consts,
        k: &Kin,
        i: usize,
        wd0: [f64; 3],
        (jw, dw): ([[f64; 3]; 3], [[f64; 3]; 3]),
    ) -> ([[f64; 3]; 3], [f64; 3]) {
        let part = self.part(i);
        let bias = part.slip_bias(k.w, k.e3);
        let rhs = [
            -(dot(jw[0], wd0) + bias[0]),
            -(dot(jw[1], wd0) + bias[1]),
            self.g - dot(jw[2], wd0) - part.gap_bias(k.w, k.e3),
        ];
        let mut a = [[0.0; 3]; 3];
        for r in 0..3 {
            for col in 0..3 {
                a[r][col] = dot(jw[r], dw[col]) + if r == col { p.inv_m } else { 0.0 };
            }
        }
        (a, rhs)
    }

    /// Part `i` alone on the floor, its slip stopped while its contact patch drills
    /// (Coulomb-Contensou friction, [`Contacts::drilling`]): the contact force (x, y, normal)
    /// that keeps its material point at rest, and the drilling torque
    /// `M = -sign(w_n) mu rbar N sqrt(1 - x^2)`, `x = |F| / (mu N)`: the law's friction lies on
    /// its ellipse, the slip it takes to carry `F` being `rbar |w_n| x / sqrt(1 - x^2)`
    /// (neglected: the mode holds while that is below the stick speed). From the rows of
    /// [`Self::stick_rows`]: a torque `m N` about ez only adds `m (jw_r . J^-1 ez)` to the
    /// normal force's column, so the 3 x 3 system is built once. The torque depends on the
    /// force it helps set: a fixed point in `sqrt(1 - x^2)` (contracting: the torque moves `F`
    /// little where `x` is small, and the mode ends before `x` nears 1), iterated to rounding.
    /// Returns the force and the torque.
    #[inline(always)]
    pub(crate) fn drill_solve(
        &self,
        p: &Consts,
        k: &Kin,
        i: usize,
        wd0: [f64; 3],
        rows: Rows,
    ) -> ([f64; 3], f64) {
        let mu = self.friction.mu();
        let torque = -k.w[2].signum() * mu * self.friction.rbar();
        let (a0, rhs) = self.point_system(p, k, i, wd0, rows);
        let dwm = p.inv_inertia(k, EZ);
        let col: [f64; 3] = core::array::from_fn(|r| dot(rows.0[r], dwm));
        let (mut frac, mut x) = (1.0, [0.0; 3]);
        let mut m = torque;
        for _ in 0..12 {
            m = torque * frac;
            let mut a = a0;
            for r in 0..3 {
                a[r][2] += m * col[r];
            }
            x = solve3(a, rhs);
            let next = self.drill_share([x[0], x[1]], x[2]).1;
            let done = (next - frac).abs() <= 1e-15;
            frac = next;
            if done {
                break;
            }
        }
        (x, m * x[2])
    }

    /// The contact forces' system of the parts in `c` at the kinematics `k`, with the free
    /// accelerations (vd0, wd0) and the resistance torque per unit N `res_n` (space).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn contact_system<const U: usize>(
        &self,
        c: &Contacts,
        k: &Kin,
        res_n: [f64; 3],
        vd0: [f64; 3],
        wd0: [f64; 3],
        over: FrictionOver,
        sys: &mut System<U>,
        what: &mut [Unknown; U],
    ) {
        let contensou = self.friction.rbar() > 0.0;
        let free = |jv: [f64; 3], jw: [f64; 3]| dot(jv, vd0) + dot(jw, wd0);
        let mut sticking = 0;
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
                    let (ft, mz) = match over[i] {
                        Some(given) => given,
                        None => self.friction_per_n(vp, k.w[2], c.dir[i], c.creep),
                    };
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
                    sticking += 1;
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
        // Two sticking parts leave one of their rows redundant; rows beyond the body's six
        // freedoms are redundant too.
        sys.structural = usize::from(sticking >= 2).max(sys.n.saturating_sub(6));
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
        if m == 1 {
            // One free variable (two parts): solved directly ([`Self::split_1d`]).
            if let Some(c) = self.split_1d(sys, what) {
                let mut along = [0.0; U];
                along[0] = c;
                let x = at(&along);
                if worst(&x) > start {
                    sys.x = x;
                }
                return;
            }
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

    /// The split of largest smallest margin along a one-dimensional null space (`sys.m` =
    /// 1: the forces `x0 + c b`), solved directly: part i's margin
    /// `mu (a_i + b_i c) - sqrt(A_i c^2 + 2 B_i c + C_i)` (its normal force `a_i + b_i c`,
    /// the squared size of its friction in the ellipse's coordinates a quadratic in c) is
    /// concave, with its maximum, where `A_i > mu^2 b_i^2`, at
    /// `c_i = (-B_i + mu b_i sqrt((A_i C_i - B_i^2) / (A_i - mu^2 b_i^2))) / A_i` (the
    /// derivative's zero). The smallest margin is concave too, and its maximum lies between
    /// the smallest and the largest `c_i`: at some `c_i` where part i's margin is the
    /// smallest there, else where two margins cross (two parts: their difference changes
    /// sign between their maxima; the root by bisection to the rounding of c). `None` where
    /// a part's margin has no maximum (it grows without bound along the null vector).
    fn split_1d<const U: usize>(&self, sys: &System<U>, what: &[Unknown; U]) -> Option<f64> {
        let mu = self.friction.mu();
        let rb = self.friction.rbar();
        // Per part: its normal force, tangential force and moment, each as (the part at
        // x0, the part along b).
        let mut nf = [[0.0; 2]; MAX_PARTS];
        let mut comp = [[[0.0; 2]; 3]; MAX_PARTS];
        let (mut list, mut k) = ([0usize; MAX_PARTS], 0);
        for j in 0..sys.n {
            let v = [sys.x[j], sys.basis[0][j]];
            match what[j] {
                Unknown::StickN(i) => {
                    nf[i] = v;
                    list[k] = i;
                    k += 1;
                }
                Unknown::StickT(i, axis) => comp[i][axis] = v,
                Unknown::StickM(i) => comp[i][2] = v,
                Unknown::SlipN { .. } => {}
            }
        }
        let parts = &list[..k];
        if parts.is_empty() {
            return None;
        }
        let at = |e: [f64; 2], c: f64| e[0] + c * e[1];
        let margin = |i: usize, c: f64| {
            let [tx, ty, m] = comp[i].map(|e| at(e, c));
            self.cone_margin(at(nf[i], c), [tx, ty], m)
        };
        let smallest = |c: f64| {
            parts
                .iter()
                .map(|&i| margin(i, c))
                .fold(f64::INFINITY, f64::min)
        };
        let mut peaks = [0.0; MAX_PARTS];
        for &i in parts {
            // The friction's squared size in the ellipse's coordinates (the moment over
            // rbar; none for a point contact), A c^2 + 2 B c + C.
            let scale = [1.0, 1.0, if rb > 0.0 { 1.0 / rb } else { 0.0 }];
            let (a, b, cc) =
                comp[i]
                    .iter()
                    .zip(scale)
                    .fold((0.0, 0.0, 0.0), |(a, b, cc), (e, w)| {
                        let (e0, e1) = (w * e[0], w * e[1]);
                        (a + e1 * e1, b + e0 * e1, cc + e0 * e0)
                    });
            let nb = mu * nf[i][1];
            let d = a - nb * nb;
            if a <= 0.0 || d <= 0.0 {
                return None;
            }
            peaks[i] = (-b + nb * ((a * cc - b * b).max(0.0) / d).sqrt()) / a;
        }
        // A peak where its own margin is the smallest is the answer.
        if let Some(&i) = parts
            .iter()
            .find(|&&i| smallest(peaks[i]) >= margin(i, peaks[i]))
        {
            return Some(peaks[i]);
        }
        if parts.len() == 2 {
            // The crossing of the two margins, bracketed by their peaks.
            let (i, j) = (parts[0], parts[1]);
            let g = |c: f64| margin(i, c) - margin(j, c);
            let (mut a, mut b) = (peaks[i], peaks[j]);
            let ga = g(a);
            if ga.signum() == g(b).signum() {
                return None;
            }
            loop {
                let mid = 0.5 * (a + b);
                if mid <= a.min(b) || mid >= a.max(b) {
                    break;
                }
                let gm = g(mid);
                if gm == 0.0 {
                    return Some(mid);
                }
                if gm.signum() == ga.signum() {
                    a = mid;
                } else {
                    b = mid;
                }
            }
            return Some(if smallest(a) >= smallest(b) { a } else { b });
        }
        // More parts: the concave smallest margin's maximum between the outermost peaks by
        // golden sections.
        let r = 0.5 * (5f64.sqrt() - 1.0);
        let peak = |&i: &usize| peaks[i];
        let mut a = parts.iter().map(peak).fold(f64::INFINITY, f64::min);
        let mut b = parts.iter().map(peak).fold(f64::NEG_INFINITY, f64::max);
        for _ in 0..200 {
            if b - a <= 4.0 * f64::EPSILON * a.abs().max(b.abs()) {
                break;
            }
            let (c1, c2) = (b - r * (b - a), a + r * (b - a));
            if smallest(c1) >= smallest(c2) {
                b = c2;
            } else {
                a = c1;
            }
        }
        Some(0.5 * (a + b))
    }

    /// The gap's acceleration of part `i` from a state derivative `dy`.
    pub fn gap_acceleration(&self, i: usize, y: &[f64; DIM], dy: &[f64; DIM]) -> f64 {
        let k = self.kin(y);
        let p = self.part(i);
        let wd = k.to_space([dy[4], dy[5], dy[6]]);
        dy[12] + dot(wd, cross(p.arm(k.e3), EZ)) + p.gap_bias(k.w, k.e3)
    }

    /// The equations of a ring lying flat (part `i` of `c`, the one touching): its plane on
    /// the floor, it slides and spins about the vertical, `m dv/dt = F`, `C dw_z/dt = M_z`,
    /// the normal force `m g` spread evenly over the rim of radius R (the moment the friction
    /// makes about G is taken by the spread, which is not resolved). The friction law acts at
    /// every point of the rim (Coulomb-Contensou with its own patch there): its force and
    /// moment are closed forms for viscous friction (`F = -mu N v`, `M_z = -mu N R^2 w_z`) and
    /// point Coulomb friction ([`rim_coulomb`]), and under Coulomb-Contensou friction (smooth
    /// wherever the rim spins) the rim's mean over 64 points. A ring stuck flat (mode roll)
    /// rests. A top lying flat on a pole ([`Self::flat_support`]) takes the law at that one
    /// point (R = 0; its patch's drilling under Coulomb-Contensou friction); stuck, it spins
    /// on where the point has no patch.
    #[inline(never)]
    pub fn flat_dynamics(&self, c: &Contacts, y: &[f64; DIM], dy: &mut [f64; DIM]) -> Forces {
        let k = self.kin(y);
        let i = (0..self.parts.n)
            .find(|&j| c.mode[j] != Mode::Flight)
            .unwrap_or(0);
        let mut f = Forces::default();
        *dy = [0.0; DIM];
        let n = self.m * self.g;
        f.n[i] = n;
        f.den[i] = 1.0 / self.m;
        // The law acts over a ring's rim; on a pole at its one point.
        let r = match *self.part(i) {
            Shape::Torus { major, .. } => major,
            _ => 0.0,
        };
        // Resistance torques about the vertical (the horizontal ones are taken by the floor).
        let resistance = || {
            let (res_n, res_0) = self.resistance_on(k.wb, k.to_body(EZ), self.reach(), [0.0; 2]);
            k.to_space(add(scale(n, res_n), res_0))[2]
        };
        let u = k.e3[2].signum();
        if c.mode[i] == Mode::Roll {
            if self.flat_radius(i) == 0.0 {
                // Stuck on a point (a pole, no patch): it spins on, slowed by the resistance
                // torques alone.
                let res = resistance();
                dy[..4].copy_from_slice(&k.q.half_times_pure(k.wb));
                dy[6] = u * res / self.c;
                dy[13] = -res * k.w[2];
            }
            return f;
        }
        let (v, wz) = ([k.v[0], k.v[1]], k.w[2]);
        let (mut fx, mut fy, mut mz) = (0.0, 0.0, 0.0);
        match self.friction {
            Friction::Frictionless => {}
            Friction::Viscous { mu } => {
                fx = -mu * n * v[0];
                fy = -mu * n * v[1];
                mz = -mu * n * r * r * wz;
            }
            Friction::Coulomb { mu } => {
                let (ft, m) = rim_coulomb(v, r * wz);
                fx = mu * n * ft[0];
                fy = mu * n * ft[1];
                mz = mu * n * r * m;
            }
            Friction::CoulombContensou { .. } => {
                // A ring's rim by 64 points; a pole's patch at its one point.
                let nq = if r > 0.0 { 64 } else { 1 };
                let w = n / nq as f64;
                for j in 0..nq {
                    let phi = (j as f64 + 0.5) * std::f64::consts::TAU / nq as f64;
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
        let res = resistance();
        dy[..4].copy_from_slice(&k.q.half_times_pure(k.wb));
        dy[6] = u * (mz + res) / self.c;
        dy[7] = v[0];
        dy[8] = v[1];
        dy[10] = fx / self.m;
        dy[11] = fy / self.m;
        dy[13] = -(fx * v[0] + fy * v[1] + (mz + res) * wz);
        f
    }

    /// The gap's acceleration of part `i` at `y`, off the floor beside the other parts'
    /// contacts as `c` has them (in free flight where none touches).
    pub fn gap_acceleration_beside(&self, i: usize, y: &[f64; DIM], c: &Contacts) -> f64 {
        let mut others = *c;
        others.mode[i] = Mode::Flight;
        others.creeping &= !(1 << i);
        others.drilling &= !(1 << i);
        let mut dy = [0.0; DIM];
        self.dynamics(&others, y, &mut dy);
        self.gap_acceleration(i, y, &dy)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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

    /// The direct one-variable split against a scan: random two- and three-part splits
    /// (normal forces, friction and drilling moments all moving along the null vector, under
    /// Coulomb-Contensou friction): the smallest margin (each from [`PlayTop::cone_margin`])
    /// at the split's `c` is at least the best of 20001 points around it and of a golden
    /// search's refinement of the best one, to rounding.
    #[test]
    fn the_one_variable_split_is_the_best_of_a_scan() {
        let top = ball(
            Friction::coulomb_contensou(0.3, 2e-3).unwrap(),
            &[Shape::Sphere {
                radius: 0.01,
                z: 0.0,
            }],
        );
        let mut seed = 12345u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        let (mut solved, mut cases) = (0, 0);
        for parts in [2usize, 3] {
            for _ in 0..300 {
                let mut sys = System::<MAXU>::new();
                let mut what = [Unknown::StickN(0); MAXU];
                let kinds = |i: usize| {
                    [
                        Unknown::StickN(i),
                        Unknown::StickT(i, 0),
                        Unknown::StickT(i, 1),
                        Unknown::StickM(i),
                    ]
                };
                let mut j = 0;
                for i in 0..parts {
                    for kind in kinds(i) {
                        what[j] = kind;
                        let scale = if matches!(kind, Unknown::StickM(_)) {
                            1e-3
                        } else {
                            1.0
                        };
                        sys.x[j] = scale * rnd() + if j % 4 == 0 { 2.0 } else { 0.0 };
                        sys.basis[0][j] = scale * rnd();
                        j += 1;
                    }
                }
                sys.n = j;
                sys.m = 1;
                let smallest = |c: f64| {
                    (0..parts)
                        .map(|i| {
                            let at = |r: usize| sys.x[4 * i + r] + c * sys.basis[0][4 * i + r];
                            top.cone_margin(at(0), [at(1), at(2)], at(3))
                        })
                        .fold(f64::INFINITY, f64::min)
                };
                cases += 1;
                let Some(c) = top.split_1d(&sys, &what) else {
                    // Only where some part's margin grows without bound along the null
                    // vector (its normal force's cone outgrows its friction) is the split
                    // left to the search.
                    let margin = |i: usize, c: f64| {
                        let at = |r: usize| sys.x[4 * i + r] + c * sys.basis[0][4 * i + r];
                        top.cone_margin(at(0), [at(1), at(2)], at(3))
                    };
                    let unbounded = (0..parts).any(|i| {
                        [-1.0, 1.0].iter().any(|&d| {
                            let (m0, m1, m2) =
                                (margin(i, 0.0), margin(i, d * 1e4), margin(i, d * 1e8));
                            m2 > m1 && m1 > m0
                        })
                    });
                    assert!(
                        unbounded,
                        "parts {parts}: no split though every margin has a peak"
                    );
                    continue;
                };
                solved += 1;
                let span = 10.0 * (1.0 + c.abs());
                let mut best = (c, smallest(c));
                for k in 0..=20000 {
                    let ck = c - span + 2.0 * span * k as f64 / 20000.0;
                    let v = smallest(ck);
                    if v > best.1 {
                        best = (ck, v);
                    }
                }
                let h = 2.0 * span / 20000.0;
                let (mut a, mut b) = (best.0 - h, best.0 + h);
                for _ in 0..100 {
                    let (c1, c2) = (b - 0.618 * (b - a), a + 0.618 * (b - a));
                    if smallest(c1) >= smallest(c2) {
                        b = c2;
                    } else {
                        a = c1;
                    }
                }
                let refined = smallest(0.5 * (a + b)).max(best.1);
                assert!(
                    smallest(c) >= refined - 1e-12 * (1.0 + refined.abs()),
                    "parts {parts}: split at {c} gives {} against {refined}",
                    smallest(c)
                );
            }
        }
        // Most random splits have a bounded best (the friction grows faster than the cone).
        assert!(solved > cases / 2, "{solved} of {cases}");
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

    /// The creep's friction is the consistent sliding's: with it the slip (in the ellipse's
    /// coordinates) accelerates along minus the friction. The slip's rate is taken here by
    /// central differences of the contact point's velocity along the state's derivative (the
    /// kinematics alone), not from the contact system the friction was solved with. A sphere
    /// off the figure axis makes the contact's response anisotropic, so the naive choice,
    /// the full friction along the force sticking needs, fails the same check by 1e-3 rad and
    /// more (asserted, so that the check can tell the two apart).
    #[test]
    fn a_creeping_parts_slip_accelerates_against_its_friction() {
        use crate::rotation::quaternion_from_euler;
        let laws = [
            Friction::Coulomb { mu: 0.05 },
            Friction::coulomb_contensou(0.05, 2e-3).unwrap(),
        ];
        for fr in laws {
            let parts = [Shape::Sphere {
                radius: 0.008,
                z: -0.012,
            }];
            let top = ball(fr, &parts);
            let q = quaternion_from_euler(0.3, 0.9, -0.4);
            let mut y = top.state(q, [4.0, -9.0, 35.0], 0.0, 0.0, None).unwrap();
            // Put it on the floor, its slip (and drilling) stopped: the start of a creep.
            let mut stuck = Contacts::NONE;
            stuck.mode[0] = Mode::Roll;
            top.project(&stuck, &mut y);
            let p = Consts::of(&top);
            assert!(
                top.creep_margin(&stuck, 0, &y) < -1e-3,
                "the friction sticking needs is outside"
            );
            let slip_rate = |fr: ([f64; 2], f64)| {
                let rate = |y: &[f64; DIM]| {
                    let k = top.kin(y);
                    let (wd0, res_n, res_0) = top.free_terms::<false>(&p, &k);
                    let arm = top.part(0).arm(k.e3);
                    let vp = add(k.v, cross(k.w, arm));
                    let (mut dy, mut out) = ([0.0; DIM], Forces::default());
                    let terms = (wd0, res_n, res_0);
                    top.slide_rates::<false>(&p, &k, 0, arm, vp, fr, terms, &mut dy, &mut out);
                    (dy, out)
                };
                let (dy, out) = rate(&y);
                let h = 1e-7;
                let (mut yp, mut ym) = (y, y);
                for j in 0..DIM {
                    yp[j] += h * dy[j];
                    ym[j] -= h * dy[j];
                }
                let (sp, sm) = (
                    top.ellipse_slip(&top.kin(&yp), 0),
                    top.ellipse_slip(&top.kin(&ym), 0),
                );
                let a = scale(0.5 / h, add(sp, scale(-1.0, sm)));
                let f = top.ellipse_force((out.ft[0], out.mz[0]));
                let cos = -dot(a, f) / (dot(a, a).sqrt() * dot(f, f).sqrt());
                (
                    cos.clamp(-1.0, 1.0).acos(),
                    dot(f, f).sqrt() / (0.05 * out.n[0]),
                )
            };
            let k = top.kin(&y);
            let (wd0, res_n, _) = top.free_terms::<false>(&p, &k);
            let consistent = top.creep_friction(&p, &k, 0, wd0, res_n, [1.0, 0.0]);
            let (angle, full) = slip_rate(consistent);
            assert!(angle < 1e-5, "{fr:?}: the slip turns {angle} rad from -F");
            assert!((full - 1.0).abs() < 1e-9, "{fr:?}: |F| / (mu N) = {full}");
            // The naive direction: the full friction along the force sticking needs.
            let (x, mz) = top.stick_solve(&p, &k, 0, wd0, res_n);
            let g = top.ellipse_force(([x[0], x[1]], mz));
            let size = dot(g, g).sqrt();
            let rb = top.friction.rbar();
            let naive = (
                [0.05 * g[0] / size, 0.05 * g[1] / size],
                0.05 * rb * g[2] / size,
            );
            let (naive_angle, _) = slip_rate(naive);
            println!(
                "{}: consistent {angle:.1e} rad, naive {naive_angle:.1e} rad",
                fr.name()
            );
            assert!(
                naive_angle > 1e-3,
                "{fr:?}: the naive direction is off by {naive_angle}"
            );
        }
    }

    /// The two laws the creep tests run under: point Coulomb and Coulomb-Contensou.
    fn creep_laws(mu: f64) -> [Friction; 2] {
        [
            Friction::Coulomb { mu },
            Friction::coulomb_contensou(mu, 2e-3).unwrap(),
        ]
    }

    /// A tippe-top-like body (ball and peg) under `fr`, and a state tilted so that both
    /// spheres touch: where cos(theta) = (0.01 - 0.004) / (0.005 + 0.02). G lies between the
    /// two contacts, so both carry weight.
    fn ball_and_peg(fr: Friction) -> (PlayTop, [f64; DIM]) {
        use crate::rotation::quaternion_from_euler;
        let parts = [
            Shape::Sphere {
                radius: 0.01,
                z: 0.005,
            },
            Shape::Sphere {
                radius: 0.004,
                z: -0.02,
            },
        ];
        let top = ball(fr, &parts);
        let q = quaternion_from_euler(0.3, 0.24_f64.acos(), -0.4);
        let y = top.state(q, [4.0, -9.0, 35.0], 0.0, 0.0, None).unwrap();
        (top, y)
    }

    /// Part i's slip rate (ellipse coordinates) along the state's derivative `dy` at `y`,
    /// by central differences of its contact point's velocity (the kinematics alone).
    fn slip_rate(top: &PlayTop, y: &[f64; DIM], dy: &[f64; DIM], i: usize) -> [f64; 3] {
        let h = 1e-7;
        let (mut yp, mut ym) = (*y, *y);
        for j in 0..DIM {
            yp[j] += h * dy[j];
            ym[j] -= h * dy[j];
        }
        let (sp, sm) = (
            top.ellipse_slip(&top.kin(&yp), i),
            top.ellipse_slip(&top.kin(&ym), i),
        );
        scale(0.5 / h, add(sp, scale(-1.0, sm)))
    }

    /// Two parts creeping together ([`PlayTop::joint_creep_all`]): each one's slip
    /// accelerates along minus its friction, which lies on its cone (ellipse), the other's
    /// friction its own consistent creep's (Gauss-Seidel to a fixed point). The rates by
    /// central differences of the contact points' velocities along the state's derivative,
    /// as below; the same ball and peg.
    #[test]
    fn two_parts_creeping_together_each_slip_against_their_friction() {
        let mu = 0.05;
        for fr in creep_laws(mu) {
            let (top, mut y) = ball_and_peg(fr);
            let mut c = Contacts::NONE;
            c.mode = [Mode::Roll, Mode::Roll, Mode::Flight, Mode::Flight];
            top.project(&c, &mut y);
            c.mode[0] = Mode::Slip;
            c.mode[1] = Mode::Slip;
            c.creeping = 0b11;
            c.dir = [[1.0, 0.0], [0.0, 1.0], [0.0; 2], [0.0; 2]];
            let mut dy = [0.0; DIM];
            let out = top.dynamics(&c, &y, &mut dy);
            for i in 0..2 {
                let a = slip_rate(&top, &y, &dy, i);
                let f = top.ellipse_force((out.ft[i], out.mz[i]));
                let cos = -dot(a, f) / (dot(a, a).sqrt() * dot(f, f).sqrt());
                let angle = cos.clamp(-1.0, 1.0).acos();
                let full = dot(f, f).sqrt() / (mu * out.n[i]);
                println!(
                    "{} part {i}: {angle:.1e} rad, |F| / mu N = {full}",
                    fr.name()
                );
                assert!(out.n[i] > 0.0, "{fr:?}: part {i} pushes");
                assert!(
                    angle < 1e-5,
                    "{fr:?}: part {i}'s slip turns {angle} rad from -F"
                );
                assert!((full - 1.0).abs() < 1e-9, "{fr:?}: |F| / (mu N) = {full}");
            }
        }
    }

    /// A part creeping beside another ([`PlayTop::joint_creep_friction`]): with the joint
    /// system's consistent creep the creeping part's slip accelerates along minus its
    /// friction, which lies on the cone (ellipse), while the other part sticks (its contact
    /// point has no acceleration) or slides under its law. The rates are taken by central
    /// differences of the contact points' velocities along the state's derivative (the
    /// kinematics alone). A tippe-top-like body (ball and peg) tilted so that both touch.
    /// Two sticking parts' velocities put on their one freedom ([`PlayTop::two_sticking`]):
    /// both contact points at rest after it, and the change orthogonal to the result in the
    /// kinetic energy's metric, checked by Pythagoras, `T(u0) = T(u1) + T(u0 - u1)` (which
    /// only the kinetic energy's own projection meets), from spinning, tumbling states.
    #[test]
    fn two_sticking_parts_keep_the_energy_projection_of_their_one_freedom() {
        let top = ball_and_peg(Friction::Coulomb { mu: 0.5 }).0;
        let mut both = Contacts::NONE;
        both.mode[0] = Mode::Roll;
        both.mode[1] = Mode::Roll;
        let mut put = both;
        put.mode[1] = Mode::Slip;
        for (e, w) in [
            ((0.3, 0.24_f64.acos(), -0.4), [4.0, -9.0, 35.0]),
            ((1.1, 0.6_f64.acos(), 2.0), [-20.0, 3.0, -7.0]),
            ((-2.0, (-0.3_f64).acos(), 0.5), [0.5, 0.25, 60.0]),
        ] {
            use crate::rotation::quaternion_from_euler;
            let q = quaternion_from_euler(e.0, e.1, e.2);
            let mut y0 = top.state(q, w, 0.3, -0.2, None).unwrap();
            top.project(&put, &mut y0);
            y0[10..13].copy_from_slice(&[0.3, -0.2, 0.05]);
            let k = top.kin(&y0);
            let mut y1 = y0;
            assert!(top.two_sticking(&both, 0, &k, &mut y1));
            let k1 = top.kin(&y1);
            for i in 0..2 {
                let v = top.part(i).point_velocity(k1.v, k1.w, k1.e3);
                assert!(dot(v, v).sqrt() < 1e-12, "part {i} at rest: {v:?}");
            }
            let mut diff = y0;
            for c in (4..7).chain(10..13) {
                diff[c] = y0[c] - y1[c];
            }
            let (t0, t1, td) = (
                top.kinetic_energy(&y0),
                top.kinetic_energy(&y1),
                top.kinetic_energy(&diff),
            );
            assert!(((t1 + td) - t0).abs() < 1e-12 * t0, "{t0} {t1} {td}");
            assert!(t1 < t0 && td > 1e-6 * t0);
        }
    }

    #[test]
    fn a_part_creeping_beside_another_slips_against_its_friction() {
        let mu = 0.05;
        for fr in creep_laws(mu) {
            let (top, y0) = ball_and_peg(fr);
            // (Beside a part sticking over a patch, which stops the drilling too, the body
            // cannot move horizontally: the creeping part's slip is held whatever its force.)
            let others: &[Mode] = if fr.rbar() > 0.0 {
                &[Mode::Slip]
            } else {
                &[Mode::Roll, Mode::Slip]
            };
            for &other in others {
                let mut y = y0;
                // Both parts on the floor, the first sticking one's contact at rest (beside
                // part 0 sticking, part 1 is projected as sliding: two sticking parts would
                // leave the body only a turn about the line through them, and this state
                // spins about its figure axis).
                let mut put = Contacts::NONE;
                put.mode = [Mode::Roll; MAX_PARTS];
                put.mode[0] = other;
                put.mode[2] = Mode::Flight;
                put.mode[3] = Mode::Flight;
                if other == Mode::Roll {
                    put.mode[1] = Mode::Slip;
                }
                top.project(&put, &mut y);
                let k = top.kin(&y);
                for i in 0..2 {
                    assert!(
                        top.part(i).gap(k.zg, k.e3).abs() < 1e-12,
                        "part {i} touches"
                    );
                }
                let mut c = put;
                c.mode[1] = Mode::Slip;
                c.creeping = 1 << 1;
                c.dir[1] = [1.0, 0.0];
                assert!(
                    top.creep_margin(&c, 1, &y) < -1e-4,
                    "{fr:?}: the friction part 1 needs to stick is outside"
                );
                let mut dy = [0.0; DIM];
                let out = top.dynamics(&c, &y, &mut dy);
                let rate_along = |dy: &[f64; DIM], i: usize| slip_rate(&top, &y, dy, i);
                let rate = |i: usize| rate_along(&dy, i);
                let angle_to = |a: [f64; 3], f: [f64; 3]| {
                    let cos = -dot(a, f) / (dot(a, a).sqrt() * dot(f, f).sqrt());
                    cos.clamp(-1.0, 1.0).acos()
                };
                let a = rate(1);
                let f = top.ellipse_force((out.ft[1], out.mz[1]));
                let angle = angle_to(a, f);
                let full = dot(f, f).sqrt() / (mu * out.n[1]);
                println!("{} beside {other:?}: {angle:.1e} rad", fr.name());
                assert!(out.n[1] > 0.0 && out.n[0] > 0.0, "{fr:?}: both push");
                assert!(
                    angle < 1e-5,
                    "{fr:?} {other:?}: the slip turns {angle} rad from -F"
                );
                assert!((full - 1.0).abs() < 1e-9, "{fr:?}: |F| / (mu N) = {full}");
                // The naive direction, the full friction along the force the joint stick
                // solve needs at part 1, is not consistent: the check tells them apart.
                let mut stuck = c;
                stuck.mode[1] = Mode::Roll;
                stuck.creeping = 0;
                let fs = top.dynamics(&stuck, &y, &mut [0.0; DIM]);
                let g = top.ellipse_force((fs.ft[1], fs.mz[1]));
                let size = dot(g, g).sqrt();
                let naive = (
                    [mu * g[0] / size, mu * g[1] / size],
                    mu * top.friction.rbar() * g[2] / size,
                );
                let (p, k) = (Consts::of(&top), top.kin(&y));
                let (wd0, res_n, _) = top.free_terms_any(&p, &k);
                let mut fn_ = Forces::default();
                let mut over = NO_OVER;
                over[1] = Some(naive);
                let vd0 = [0.0, 0.0, -top.g];
                let (vd, wd, _, _) =
                    top.joint_solve::<MAXU>(&c, &k, res_n, vd0, wd0, over, &mut fn_);
                let mut dyn_ = [0.0; DIM];
                PlayTop::write_rates(&k, vd, wd, 0.0, &mut dyn_);
                let naive_angle = angle_to(rate_along(&dyn_, 1), top.ellipse_force(naive));
                println!("  naive {naive_angle:.1e} rad");
                assert!(
                    naive_angle > 1e-3,
                    "{fr:?} {other:?}: the naive direction is off by only {naive_angle}"
                );
                if other == Mode::Roll {
                    let a0 = rate(0);
                    let g = 9.81;
                    assert!(
                        dot(a0, a0).sqrt() < 1e-6 * g,
                        "{fr:?}: the sticking part's point accelerates at {a0:?}"
                    );
                }
            }
        }
    }

    /// Rolling while the patch drills ([`PlayTop::drill_solve`]): put on the
    /// Coulomb-Contensou law at the slip the mode neglects,
    /// `s = -rbar |w_n| x / sqrt(1 - x^2) F / |F|`, the law ([`PlayTop::friction_per_n`])
    /// gives back the kernel's tangential force and drilling torque; and the contact point's
    /// velocity has no rate (a central difference along the state's derivative). A light
    /// disk on a ball (floor campaign, seed 1, case 8645) with mu small enough that the
    /// tangential force takes half the cone, so that `sqrt(1 - x^2)` matters.
    #[test]
    fn a_drilling_part_s_forces_are_the_law_s_at_the_slip_it_needs() {
        let fr = Friction::coulomb_contensou(0.0035, 4.205991025432986e-05).unwrap();
        let top = PlayTop::new(
            0.006886063548669754,
            2.4174925518601564e-07,
            4.834985103720313e-07,
            0.016662910876893477,
            0.022864911441109897,
            9.81,
            fr,
            0.95,
            0.0,
            0.0,
            0.0,
        )
        .unwrap();
        let mut y: [f64; DIM] = [
            -0.9692980465936911,
            -0.000509827623923897,
            0.002070895154365805,
            0.2458795403011564,
            3.4920532782692653,
            -6.442688654484414,
            -7.738443046193315e-05,
            -0.00033088509766921457,
            2.7066561290216688e-08,
            0.03952767073447181,
            -0.28966709895890447,
            4.656477449975649e-05,
            -0.0005208385606208744,
            0.0,
        ];
        let mut c = Contacts::NONE;
        c.mode[0] = Mode::Roll;
        c.drilling = 1;
        top.project(&c, &mut y);
        let mut dy = [0.0; DIM];
        let f = top.dynamics(&c, &y, &mut dy);
        let (x, frac) = top.drill_share(f.ft[0], f.n[0]);
        assert!(x > 0.2 && x < 0.9, "x = {x}");
        let k = top.kin(&y);
        let size = top.friction.rbar() * k.w[2].abs() * x / frac;
        let ft = f.ft[0][0].hypot(f.ft[0][1]);
        let slip = [-size * f.ft[0][0] / ft, -size * f.ft[0][1] / ft, 0.0];
        let (law, m) = top.friction_per_n(slip, k.w[2], [0.0; 2], 0.0);
        for j in 0..2 {
            assert!(
                (law[j] * f.n[0] - f.ft[0][j]).abs() <= 1e-12 * ft,
                "{law:?} {:?}",
                f.ft[0]
            );
        }
        assert!(
            (m * f.n[0] - f.mz[0]).abs() <= 1e-12 * f.mz[0].abs(),
            "{m} {}",
            f.mz[0]
        );
        let h = 1e-7;
        let at = |s: f64| {
            let ys: [f64; DIM] = core::array::from_fn(|j| y[j] + s * h * dy[j]);
            let ks = top.kin(&ys);
            top.parts.shape[0].point_velocity(ks.v, ks.w, ks.e3)
        };
        let (a, b) = (at(1.0), at(-1.0));
        for j in 0..2 {
            assert!(
                ((a[j] - b[j]) / (2.0 * h)).abs() <= 1e-6 * top.g,
                "{a:?} {b:?}"
            );
        }
    }

    /// Phases in which nothing dissipates keep E + dissipated ([`super::super::driver::Keep`]):
    /// the floor campaign's case 839 of seed 27, a 14.6 g sharp rim of 12 mm under
    /// Coulomb-Contensou friction started upside down, nearly flat, spinning at 15 rad/s. It
    /// rolls for about 28 000 of its 64 000 steps in 5 s, between 905 slides. Over the rolling
    /// steps, the ledger's changes add up to 1.0e-10 of it, and it never rises above its
    /// start by more than 5.2e-10 (the floor campaign allows 50 rtol, 5e-9). Without the
    /// projection: 4.7e-8 and 4.8e-8.
    #[test]
    fn rolling_phases_keep_their_ledger() {
        use crate::rotation::{omega_body_from_euler, quaternion_from_euler};
        use crate::simulate::{simulate, Settings};
        let rim = [Shape::Torus {
            major: 0.012013670404018371,
            minor: 0.0,
            z: 0.0,
        }];
        let fr = Friction::coulomb_contensou(0.7831818872575849, 0.00011731277913321711).unwrap();
        let (m, a, c) = (
            0.01455116339919623,
            9.035541753326787e-7,
            1.8071083506653573e-6,
        );
        let top = PlayTop::with_parts(m, a, c, &rim, 9.81, fr, 0.95, 0.0, 0.0, 0.0).unwrap();
        let (th, phi, psi) = (3.133634075601824, 1.5618967743815402, 5.135259158944763);
        let q = quaternion_from_euler(phi, th, psi);
        let w = omega_body_from_euler(th, psi, -0.06054462790243988, 0.0, -15.451782471344176);
        let y0 = top.state(q, w, 0.0, 0.0, Some(0.0)).unwrap();
        let st = Settings {
            t_end: 5.0,
            ..Settings::default()
        };
        let out = simulate(&top, &y0, &st, &mut [], &mut |_| true).unwrap();
        let ledger = |y: &[f64; DIM]| top.kinetic_energy(y) + top.m * top.g * y[9] + y[13];
        let l0 = ledger(&out.rows[0].y);
        let (mut rolling, mut sum) = (0, 0.0);
        for (r0, r1) in out.rows.iter().zip(&out.rows[1..]) {
            if r0.contacts == r1.contacts && top.conserves(&r0.contacts) {
                rolling += usize::from(r0.contacts.mode[0] == Mode::Roll);
                sum += (ledger(&r1.y) - ledger(&r0.y)) / l0;
            }
        }
        let rise = out
            .rows
            .iter()
            .map(|r| (ledger(&r.y) - l0) / l0)
            .fold(f64::MIN, f64::max);
        println!("{rolling} rolling steps: the ledger moved by {sum:e}, rose at most {rise:e}");
        assert!(rolling > 20_000, "{rolling} rolling steps");
        assert!(
            sum.abs() <= 1e-9,
            "the rolling steps moved the ledger by {sum:e}"
        );
        assert!(rise <= 5e-9, "the ledger rose by {rise:e} of itself");
    }

    /// [`PlayTop::keep_ledger`] makes the change asked within its band, by the velocities
    /// alone, and none beyond it.
    #[test]
    fn keeping_the_ledger_moves_only_the_velocities_and_only_within_the_band() {
        let top = ball(
            Friction::Coulomb { mu: 0.5 },
            &[Shape::Sphere {
                radius: 0.01,
                z: -0.004,
            }],
        );
        let q = crate::rotation::quaternion_from_euler(0.2, 0.7, -0.1);
        let y = top.state(q, [3.0, -2.0, 40.0], 0.1, 0.0, None).unwrap();
        let energy = |y: &[f64; DIM]| top.kinetic_energy(y) + top.m * top.g * y[9];
        let ke = top.kinetic_energy(&y);
        for change in [1e-9 * ke, -1e-9 * ke] {
            let mut z = y;
            top.keep_ledger(&mut z, change, 1e-8 * ke);
            let moved = energy(&z) - energy(&y);
            assert!(
                (moved - change).abs() <= 1e-15 * ke,
                "{moved:e} for {change:e}"
            );
            for i in (0..4).chain(7..10).chain(13..14) {
                assert_eq!(z[i], y[i], "component {i}");
            }
        }
        let mut z = y;
        top.keep_ledger(&mut z, 1e-7 * ke, 1e-8 * ke);
        assert_eq!(z, y, "a change beyond the band is not made");
        top.keep_ledger(&mut z, -2.0 * ke, 10.0 * ke);
        assert_eq!(z, y, "a change the kinetic energy cannot give is not made");
    }
}
