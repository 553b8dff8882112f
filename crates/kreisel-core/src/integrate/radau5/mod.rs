//! RADAU5: the adaptive implicit Radau IIA method of order 5 (3 stages) for stiff systems.
//!
//! The method and its implementation follow E. Hairer, G. Wanner, *Solving Ordinary
//! Differential Equations II: Stiff and Differential-Algebraic Problems*, 2nd ed.,
//! Springer 1996, Sec. IV.8 ("Implementation of Implicit Runge–Kutta Methods"); the
//! coefficients of the Radau IIA tableau are those of Sec. IV.5 (Table 5.6).
//!
//! * **Method.** The 3-stage Radau IIA collocation method (nodes `c = (4 - √6)/10,
//!   (4 + √6)/10, 1`), of order 5 at the step ends, L-stable and stiffly accurate: the new
//!   state is the last stage, `y1 = y0 + z3`.
//! * **Newton iteration.** The stage increments `Z = (z1, z2, z3)`, `z_i = Y_i - y0`,
//!   solve `Z = h (A ⊗ I) F(Z)`. They are found by simplified Newton iterations with one
//!   Jacobian `J ≈ ∂f/∂y(t0, y0)` in the transformed variables `W = (T⁻¹ ⊗ I) Z`, where
//!   `T⁻¹ A⁻¹ T = diag(γ, [[α, -β], [β, α]])` (the real eigenvalue `γ` and the complex
//!   pair `α ± iβ` of `A⁻¹`). Each iteration solves one real system with
//!   `E1 = γ/h I - J` and one complex one with `E2 = (α + iβ)/h I - J` (Sec. IV.8, (8.11)
//!   to (8.16)); both are factorised by LU with partial pivoting, the complex one in a
//!   small local complex type. The starting values extrapolate the collocation polynomial
//!   of the previous step (zero on the first step). Convergence is monitored by the rate
//!   `θ_k = ‖ΔW_k‖ / ‖ΔW_{k-1}‖` (geometric mean of the last two from the third iteration
//!   on), `η = θ / (1 - θ)`: the iteration stops when `η ‖ΔW_k‖ <= κ` (scaled norm,
//!   `κ = max(10 ε / rtol', min(0.03, √rtol'))`, `η` of the first iteration from the
//!   previous step, `max(η_old, ε)^0.8`); it is abandoned when `θ >= 0.99`, when more
//!   than 7 iterations would be needed, or when `θ^(7-k) / (1 - θ) ‖ΔW_k‖ > κ` predicts
//!   that (then the step shrinks by `0.8 q^(-1/(4 + 7 - k))` with
//!   `q = clamp(θ^(7-k) / (1 - θ) ‖ΔW_k‖ / κ, 1e-4, 20)`, else it halves).
//! * **Error estimate** (Sec. IV.8, (8.19) to (8.21)): an embedded method of order 3,
//!   `ŷ1 - y1 = γ0 h f(t0, y0) + e1 z1 + e2 z2 + e3 z3` with `γ0 = 1/γ`, filtered as
//!   `err = (I - h γ0 J)⁻¹ (ŷ1 - y1)` (which costs one solve with `E1`, already
//!   factorised) so that it stays bounded for stiff components. On the first step and
//!   after a rejection, when `‖err‖ >= 1`, it is filtered a second time,
//!   `err = (I - h γ0 J)⁻¹ (γ0 h f(t0, y0 + err) + Σ e_i z_i)` (one more evaluation of
//!   `f`). The norm is the root mean square of `err_i / sk_i` with
//!   `sk_i = atol' + rtol' max(|y0_i|, |y1_i|, floor_i)` over the first
//!   [`OdeSystem::controlled`] components (the Newton norm uses all `N`, scaled at `y0`).
//! * **Tolerances.** The estimate is `O(h^4)` while the method has order 5, so the
//!   tolerances are transformed as in Hairer's code: `rtol' = 0.1 rtol^(2/3)`,
//!   `atol' = atol rtol' / rtol`. A run at `rtol` then has a global error of about `rtol`
//!   (a few times more or less), comparable to [`super::Dop853`] at the same settings.
//! * **Step-size control** (Sec. IV.8, (8.21) to (8.25)): `h_new = h / clamp(err^(1/4) / fac,
//!   1/8, 5)` with the safety factor `fac = min(0.9, 0.9 (1 + 2·7) / (k + 2·7))` lowered
//!   when Newton needed `k` many iterations; after an accepted step the predictive
//!   controller of Gustafsson, `h_new = fac h (1/err)^(1/4) (h/h_old) (err_old/err)^(1/4)`
//!   (clamped alike) is used when it gives the smaller step. No increase right after a
//!   rejection; a rejected first step shrinks by 10. Never larger than `h_max`; the last
//!   step is stretched by up to 1 % to land on `t_end` (as [`super::Dop853`]). Starting
//!   step: Hairer's `hinit` heuristic with the exponent 1/4 of this error estimate, unless
//!   `h_init` is given.
//! * **Jacobian and its reuse.** From [`OdeSystem::jacobian`] if the system provides it,
//!   else by forward differences: column `j` is `(f(t, y + δ_j e_j) - f(t, y)) / δ_j` with
//!   `δ_j = sqrt(ε max(|y_j|, floor_j, 1e-5))` (`ε` the machine epsilon, `floor` from
//!   [`OdeSystem::magnitude_floor`]), costing `N` evaluations of `f`. After an accepted
//!   step the Jacobian is kept when the Newton iteration converged fast (`θ <=`
//!   [`Radau5::theta_jac`], default 0.001 as in the book's code; `θ` is taken as that
//!   value when one iteration sufficed), else it is evaluated anew at the new state. When
//!   it is kept and the proposed step changed by a factor within `[1, 1.2]`, the step is
//!   kept too and so are the LU factors. After a rejection (error or Newton) the Jacobian
//!   is evaluated anew unless it already belongs to the step's initial state; the LU
//!   factors are renewed for every new step size.
//! * **Dense output.** The collocation polynomial of degree 3 through `(t0, y0)`,
//!   `(t0 + c_i h, y0 + z_i)` (with the accepted, projected `y1` in place of `y0 + z3`, so
//!   that it is continuous across steps and exact at both ends): error `O(h^4)` inside the
//!   step (order 3), exact at the step end. No extra evaluation of `f`.
//! * **Projection, observers, errors** as for [`super::Dop853`]: an accepted state is
//!   projected by [`OdeSystem::project`] before `f` is evaluated there; a non-finite
//!   stage, state or derivative rejects the step and halves it
//!   ([`IntegrateError::NonFinite`] when that reaches the minimal step size); a singular
//!   iteration matrix halves the step as well.
//!
//! Cost per step: 3 evaluations of `f` per Newton iteration, 1 at the new state, `N` per
//! finite-difference Jacobian, plus one real and one complex `N x N` LU per new step size.
#![allow(clippy::needless_range_loop)] // index loops mirror the formulas

use std::ops::{Add, ControlFlow, Div, Mul, Sub};

use super::{all_finite, initial_step, scaled, Dense, IntegrateError, Observer, OdeSystem, Stats};

#[cfg(test)]
mod tests;

/// Most Newton iterations per step (`NIT` of the book's code).
const MAX_NEWTON: u32 = 7;
/// Safety factor of the step-size controller.
const SAFETY: f64 = 0.9;
/// Largest increase `h_new / h` (as `1 / FAC_R`).
const FAC_R: f64 = 1.0 / 8.0;
/// Largest decrease `h / h_new`.
const FAC_L: f64 = 5.0;

/// Settings of the adaptive RADAU5 integrator (Hairer–Wanner, Sec. IV.8).
///
/// The fields and methods shared with [`super::Dop853`] mean the same; see the module
/// documentation for the method. Tolerances are scalar: the estimated local error of
/// component `i` is kept below `atol' + rtol' |y_i|` with the transformed tolerances
/// `rtol' = 0.1 rtol^(2/3)`, `atol' = atol rtol' / rtol` (a global error of about `rtol`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Radau5 {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
    /// First step size; `None` selects it with Hairer's `hinit` heuristic.
    pub h_init: Option<f64>,
    /// Largest step size (`f64::INFINITY` for no limit; never more than `t_end - t0`).
    pub h_max: f64,
    /// Largest number of step attempts (accepted + rejected).
    pub max_steps: u64,
    /// The Jacobian is kept for the next step when the Newton convergence rate `θ` of an
    /// accepted step was at most this (`THET` of the book's code, default 0.001; a larger
    /// value, e.g. 0.1, saves Jacobians when they are expensive).
    pub theta_jac: f64,
}

impl Default for Radau5 {
    /// `rtol = 1e-8`, `atol = 1e-10`, automatic first step, no `h_max`,
    /// `max_steps = 100_000`, `theta_jac = 0.001`.
    fn default() -> Self {
        Self {
            rtol: 1e-8,
            atol: 1e-10,
            h_init: None,
            h_max: f64::INFINITY,
            max_steps: 100_000,
            theta_jac: 0.001,
        }
    }
}

// ------------------------------------------------------------------ the tableau

/// The Radau IIA tableau and the quantities derived from it, computed once per run.
#[derive(Clone, Copy, Debug)]
struct Tableau {
    /// Nodes.
    c: [f64; 3],
    /// `T` (columns: the real eigenvector of `A⁻¹`, real and imaginary part of the complex one).
    t: [[f64; 3]; 3],
    /// `T⁻¹`.
    ti: [[f64; 3]; 3],
    /// Real eigenvalue of `A⁻¹`.
    gamma: f64,
    /// Complex eigenvalues `alpha ± i beta` of `A⁻¹`.
    alpha: f64,
    beta: f64,
    /// Error-estimate weights `e_i / γ0` (`ŷ1 - y1 = γ0 (h f0 + Σ dd_i z_i)`).
    dd: [f64; 3],
}

fn inv3(m: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    let mut r = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            // Cofactor of (j, i), divided by the determinant.
            let (a, b) = ((j + 1) % 3, (j + 2) % 3);
            let (c, d) = ((i + 1) % 3, (i + 2) % 3);
            r[i][j] = (m[a][c] * m[b][d] - m[a][d] * m[b][c]) / det;
        }
    }
    r
}

impl Tableau {
    fn new() -> Self {
        let s6 = 6f64.sqrt();
        let c = [(4.0 - s6) / 10.0, (4.0 + s6) / 10.0, 1.0];
        let a = [
            [
                (88.0 - 7.0 * s6) / 360.0,
                (296.0 - 169.0 * s6) / 1800.0,
                (-2.0 + 3.0 * s6) / 225.0,
            ],
            [
                (296.0 + 169.0 * s6) / 1800.0,
                (88.0 + 7.0 * s6) / 360.0,
                (-2.0 - 3.0 * s6) / 225.0,
            ],
            [(16.0 - s6) / 36.0, (16.0 + s6) / 36.0, 1.0 / 9.0],
        ];
        let ai = inv3(&a);
        // Eigenvalues of A⁻¹ (roots of 1 - 3x/5 + ... : closed forms, Sec. IV.8).
        let (c13, c23) = (3f64.cbrt(), 9f64.cbrt());
        let gamma = 3.0 + c23 - c13;
        let alpha = 3.0 + 0.5 * (c13 - c23);
        let beta = 0.5 * (3f64.powf(5.0 / 6.0) + 3f64.powf(7.0 / 6.0));
        // Null vectors of A⁻¹ - λ I as the cross product of two of its rows.
        let cross = |r0: [C64; 3], r1: [C64; 3]| -> [C64; 3] {
            [
                r0[1] * r1[2] - r0[2] * r1[1],
                r0[2] * r1[0] - r0[0] * r1[2],
                r0[0] * r1[1] - r0[1] * r1[0],
            ]
        };
        let row = |i: usize, lam: C64| -> [C64; 3] {
            let mut r = [C64::new(0.0, 0.0); 3];
            for j in 0..3 {
                r[j] = C64::new(ai[i][j], 0.0) - if i == j { lam } else { C64::new(0.0, 0.0) };
            }
            r
        };
        let lg = C64::new(gamma, 0.0);
        let v1 = cross(row(0, lg), row(1, lg));
        // Eigenvector of α - iβ: with T = [v1, Re v, Im v], T⁻¹ A⁻¹ T has the block
        // [[α, -β], [β, α]].
        let lc = C64::new(alpha, -beta);
        let v = cross(row(0, lc), row(1, lc));
        let mut t = [[0.0; 3]; 3];
        for i in 0..3 {
            t[i][0] = v1[i].re;
            t[i][1] = v[i].re;
            t[i][2] = v[i].im;
        }
        let ti = inv3(&t);
        // Embedded method: b̂0 = γ0 = 1/γ at c = 0, and b̂ of order 3 at the nodes:
        // γ0 + Σ b̂_i = 1, Σ b̂_i c_i = 1/2, Σ b̂_i c_i^2 = 1/3.
        let gamma0 = 1.0 / gamma;
        let v = [
            [1.0, 1.0, 1.0],
            [c[0], c[1], c[2]],
            [c[0] * c[0], c[1] * c[1], c[2] * c[2]],
        ];
        let vi = inv3(&v);
        let rhs = [1.0 - gamma0, 0.5, 1.0 / 3.0];
        let mut bhat = [0.0; 3];
        for i in 0..3 {
            bhat[i] = (0..3).map(|k| vi[i][k] * rhs[k]).sum();
        }
        // e = (b̂ - b)ᵀ A⁻¹ with b the last row of A (stiffly accurate); dd = e / γ0.
        let mut dd = [0.0; 3];
        for j in 0..3 {
            dd[j] = (0..3).map(|i| (bhat[i] - a[2][i]) * ai[i][j]).sum::<f64>() / gamma0;
        }
        Tableau {
            c,
            t,
            ti,
            gamma,
            alpha,
            beta,
            dd,
        }
    }
}

// ------------------------------------------------------------------ linear algebra

/// A complex number, just what the complex LU needs.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct C64 {
    re: f64,
    im: f64,
}

impl C64 {
    const fn new(re: f64, im: f64) -> Self {
        C64 { re, im }
    }
}

impl Add for C64 {
    type Output = C64;
    #[inline(always)]
    fn add(self, o: C64) -> C64 {
        C64::new(self.re + o.re, self.im + o.im)
    }
}

impl Sub for C64 {
    type Output = C64;
    #[inline(always)]
    fn sub(self, o: C64) -> C64 {
        C64::new(self.re - o.re, self.im - o.im)
    }
}

impl Mul for C64 {
    type Output = C64;
    #[inline(always)]
    fn mul(self, o: C64) -> C64 {
        C64::new(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
}

impl Div for C64 {
    type Output = C64;
    #[inline(always)]
    fn div(self, o: C64) -> C64 {
        // Smith's algorithm (no overflow for large |o|).
        if o.re.abs() >= o.im.abs() {
            let r = o.im / o.re;
            let d = o.re + o.im * r;
            C64::new((self.re + self.im * r) / d, (self.im - self.re * r) / d)
        } else {
            let r = o.re / o.im;
            let d = o.re * r + o.im;
            C64::new((self.re * r + self.im) / d, (self.im * r - self.re) / d)
        }
    }
}

/// The scalar of an LU factorisation: real or complex.
trait Scalar:
    Copy + Default + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    /// A magnitude for the choice of pivots (`|re| + |im|` for complex numbers).
    fn mag(self) -> f64;
}

impl Scalar for f64 {
    #[inline(always)]
    fn mag(self) -> f64 {
        self.abs()
    }
}

impl Scalar for C64 {
    #[inline(always)]
    fn mag(self) -> f64 {
        self.re.abs() + self.im.abs()
    }
}

/// An `N x N` LU factorisation with partial pivoting, in place (`L` unit lower, `U` upper),
/// of a matrix whose passive components (see [`OdeSystem::passive`]) have a diagonal
/// block: the matrix is held with its rows and columns in the order `perm` (the `nc` coupled
/// components first), only that leading `nc x nc` block is factorised, and the passive
/// unknowns follow by substitution in their rows (`E_pc x_c + d x_p = b_p`).
#[derive(Clone, Debug)]
struct Lu<T, const N: usize> {
    /// The matrix, rows and columns in the order `perm`.
    a: [[T; N]; N],
    piv: [usize; N],
    perm: [usize; N],
    nc: usize,
}

impl<T: Scalar, const N: usize> Lu<T, N> {
    #[cfg(test)]
    fn new() -> Self {
        Self::with_passive(&[false; N])
    }

    /// With the components marked `passive` ordered last.
    fn with_passive(passive: &[bool; N]) -> Self {
        let mut perm = [0; N];
        let mut n = 0;
        for want in [false, true] {
            for (i, &p) in passive.iter().enumerate() {
                if p == want {
                    perm[n] = i;
                    n += 1;
                }
            }
        }
        Lu {
            a: [[T::default(); N]; N],
            piv: [0; N],
            perm,
            nc: passive.iter().filter(|&&p| !p).count(),
        }
    }

    /// Sets entry `(i, j)` of the matrix (natural order) for every `i, j` from `f`.
    #[inline(always)]
    fn set(&mut self, f: impl Fn(usize, usize) -> T) {
        for (r, &i) in self.perm.iter().enumerate() {
            for (c, &j) in self.perm.iter().enumerate() {
                self.a[r][c] = f(i, j);
            }
        }
    }

    /// Factorises the matrix in place; `false` if a pivot is zero or not finite (singular).
    fn factor(&mut self) -> bool {
        let (a, nc) = (&mut self.a, self.nc);
        for k in 0..nc {
            let mut p = k;
            let mut best = a[k][k].mag();
            for i in k + 1..nc {
                let m = a[i][k].mag();
                if m > best {
                    best = m;
                    p = i;
                }
            }
            if best == 0.0 || !best.is_finite() {
                return false;
            }
            self.piv[k] = p;
            if p != k {
                a.swap(p, k);
            }
            let (done, rest) = a.split_at_mut(k + 1);
            let (pivot, urow) = (done[k][k], &done[k][k + 1..nc]);
            for row in &mut rest[..nc - k - 1] {
                let l = row[k] / pivot;
                row[k] = l;
                for (x, &u) in row[k + 1..nc].iter_mut().zip(urow) {
                    *x = *x - l * u;
                }
            }
        }
        (nc..N).all(|i| {
            let d = a[i][i].mag();
            d != 0.0 && d.is_finite()
        })
    }

    /// Solves `A x = b` in place with the factors.
    fn solve(&self, b: &mut [T; N]) {
        let (a, nc) = (&self.a, self.nc);
        let mut x = [T::default(); N];
        for (xr, &i) in x.iter_mut().zip(&self.perm) {
            *xr = b[i];
        }
        for k in 0..nc {
            let p = self.piv[k];
            if p != k {
                x.swap(p, k);
            }
        }
        let dot = |row: &[T], x: &[T]| {
            row.iter()
                .zip(x)
                .fold(T::default(), |s, (&r, &xj)| s + r * xj)
        };
        for i in 1..nc {
            x[i] = x[i] - dot(&a[i][..i], &x[..i]);
        }
        for i in (0..nc).rev() {
            x[i] = (x[i] - dot(&a[i][i + 1..nc], &x[i + 1..nc])) / a[i][i];
        }
        for i in nc..N {
            x[i] = (x[i] - dot(&a[i][..nc], &x[..nc])) / a[i][i];
        }
        for (xr, &i) in x.iter().zip(&self.perm) {
            b[i] = *xr;
        }
    }
}

// ------------------------------------------------------------------ dense output

/// Dense output of one RADAU5 step: the collocation polynomial (degree 3, order 3 inside
/// the step, exact at both ends).
///
/// `y(t0 + s h) = y0 + s (a1 + (s - c1) (a2 + (s - c2) a3))` in Newton form through
/// `(0, 0)`, `(c1, z1)`, `(c2, z2)`, `(1, y1 - y0)`.
#[derive(Clone, Debug)]
pub struct Radau5Dense<const N: usize> {
    t0: f64,
    t1: f64,
    h: f64,
    c: [f64; 2],
    y0: [f64; N],
    y1: [f64; N],
    a: [[f64; N]; 3],
}

impl<const N: usize> Radau5Dense<N> {
    fn new() -> Self {
        Radau5Dense {
            t0: 0.0,
            t1: 0.0,
            h: 0.0,
            c: [0.0; 2],
            y0: [0.0; N],
            y1: [0.0; N],
            a: [[0.0; N]; 3],
        }
    }

    /// Sets the polynomial of the step `[t0, t1]` of size `h` with the stage increments `z`.
    #[allow(clippy::too_many_arguments)]
    fn set(
        &mut self,
        t0: f64,
        t1: f64,
        h: f64,
        c: &[f64; 3],
        y0: &[f64; N],
        y1: &[f64; N],
        z: &[[f64; N]; 3],
    ) {
        let (c1, c2) = (c[0], c[1]);
        self.t0 = t0;
        self.t1 = t1;
        self.h = h;
        self.c = [c1, c2];
        self.y0 = *y0;
        self.y1 = *y1;
        for i in 0..N {
            let v3 = y1[i] - y0[i];
            let d01 = z[0][i] / c1;
            let d12 = (z[1][i] - z[0][i]) / (c2 - c1);
            let d23 = (v3 - z[1][i]) / (1.0 - c2);
            let d012 = (d12 - d01) / c2;
            let d123 = (d23 - d12) / (1.0 - c1);
            self.a[0][i] = d01;
            self.a[1][i] = d012;
            self.a[2][i] = d123 - d012;
        }
    }

    /// The polynomial less `y0` at `s = (t - t0) / h`, component `i`.
    #[inline(always)]
    fn rel(&self, s: f64, i: usize) -> f64 {
        let [c1, c2] = self.c;
        s * (self.a[0][i] + (s - c1) * (self.a[1][i] + (s - c2) * self.a[2][i]))
    }
}

impl<const N: usize> Dense<N> for Radau5Dense<N> {
    fn t0(&self) -> f64 {
        self.t0
    }

    fn t1(&self) -> f64 {
        self.t1
    }

    fn eval(&self, t: f64, out: &mut [f64; N]) {
        if t == self.t1 {
            *out = self.y1;
            return;
        }
        if t == self.t0 {
            *out = self.y0;
            return;
        }
        let s = (t - self.t0) / self.h;
        for i in 0..N {
            out[i] = self.y0[i] + self.rel(s, i);
        }
    }
}

// ------------------------------------------------------------------ the integrator

/// Why a Newton iteration was abandoned: the factor for the step size.
enum NewtonFail {
    /// Slow or diverging convergence, or too many iterations.
    Slow(f64),
    /// A non-finite stage value.
    NonFinite,
}

impl Radau5 {
    /// Settings with the given tolerances and the defaults of [`Radau5::default`] otherwise.
    pub fn new(rtol: f64, atol: f64) -> Self {
        Self {
            rtol,
            atol,
            ..Self::default()
        }
    }

    /// Settings whose error estimate is held to `rtol` and `atol` themselves (the local
    /// error an explicit method such as [`super::Dop853`] holds at those tolerances), the
    /// inverse of the transformation of [`Radau5`]'s tolerances (`rtol = (10 rtol')^(3/2)`),
    /// `rtol` no smaller than 1e-13, where the Newton iteration stalls. At tight tolerances
    /// the transformation is far looser than the tolerance itself (at rtol 1e-10 the local
    /// error is held to 2e-8): a caller that continues an explicit method's run by this one
    /// keeps its accuracy so.
    pub fn holding_local(rtol: f64, atol: f64) -> Self {
        let outer = (10.0 * rtol).powf(1.5).max(1e-13);
        Self::new(outer, atol * outer / rtol)
    }

    fn check_tolerances(&self) {
        assert!(
            self.rtol >= 0.0 && self.atol >= 0.0 && (self.rtol > 0.0 || self.atol > 0.0),
            "Radau5: tolerances must be >= 0 and not both zero (rtol = {}, atol = {})",
            self.rtol,
            self.atol
        );
    }

    /// The transformed tolerances `(rtol', atol')` the error estimate is held to.
    fn inner_tolerances(&self) -> (f64, f64) {
        if self.rtol > 0.0 {
            let r = 0.1 * self.rtol.powf(2.0 / 3.0);
            (r, self.atol * r / self.rtol)
        } else {
            (0.0, 0.1 * self.atol.powf(2.0 / 3.0))
        }
    }

    /// Integrates `sys` from `(t0, y0)` to `t_end`, reporting every accepted step to `obs`.
    ///
    /// The same contract as [`super::Dop853::integrate`]: returns the final time and state
    /// (`t_end`, or the stop point of the observer if it broke off) and the run's
    /// [`Stats`] (with [`Stats::jacobians`] and [`Stats::lu_decomps`]); `t_end == t0`
    /// returns `(t0, y0)` after calling `obs.start`; the last step lands exactly on
    /// `t_end`. Nothing is allocated; the work arrays live on the stack (about
    /// `3 N^2 + 20 N` floats).
    ///
    /// # Errors
    /// [`IntegrateError::NonFinite`] if `y0`, `f(t0, y0)` or a Jacobian is not finite, or
    /// if non-finite trial values persist down to the minimal step;
    /// [`IntegrateError::StepSizeTooSmall`] if the step size falls below
    /// `10 * f64::EPSILON * |t|`; [`IntegrateError::TooManySteps`] after `max_steps` step
    /// attempts.
    ///
    /// # Panics
    /// If `t0` or `t_end` is not finite, if `t_end < t0` (backward integration is not
    /// supported) or if the tolerances are negative or both zero.
    pub fn integrate<const N: usize, S, O>(
        &self,
        sys: &S,
        t0: f64,
        y0: [f64; N],
        t_end: f64,
        obs: &mut O,
    ) -> Result<(f64, [f64; N], Stats), IntegrateError>
    where
        S: OdeSystem<N> + ?Sized,
        O: Observer<N> + ?Sized,
    {
        self.run(sys, t0, y0, t_end, obs, None)
    }

    /// Integrates with `n` equal steps, no error control (for convergence studies).
    ///
    /// Every step whose Newton iteration converges is accepted (the tolerances set only
    /// the Newton stopping criterion: use small ones, but not below about `1e-13`, where
    /// round-off stalls the iteration); the iteration runs while it contracts (up to 40
    /// iterations). The Jacobian is reused as in [`Radau5::integrate`]; a step whose
    /// Newton iteration fails with an old Jacobian is retried with a new one.
    ///
    /// # Errors
    /// [`IntegrateError::StepSizeTooSmall`] (with the fixed step) when a Newton iteration
    /// fails, [`IntegrateError::NonFinite`] for non-finite values, as well as
    /// [`IntegrateError::TooManySteps`] if `n > max_steps`.
    ///
    /// # Panics
    /// As [`Radau5::integrate`], and if `n == 0`.
    pub fn integrate_fixed<const N: usize, S, O>(
        &self,
        sys: &S,
        t0: f64,
        y0: [f64; N],
        t_end: f64,
        n: u64,
        obs: &mut O,
    ) -> Result<(f64, [f64; N], Stats), IntegrateError>
    where
        S: OdeSystem<N> + ?Sized,
        O: Observer<N> + ?Sized,
    {
        assert!(n > 0, "Radau5: integrate_fixed needs at least one step");
        self.run(sys, t0, y0, t_end, obs, Some(n))
    }

    /// The Jacobian at `(t, y)` (with `f0 = f(t, y)`) into `jac`; `false` if not finite.
    /// By forward differences where the system gives none, the `passive` columns zero.
    fn jacobian<const N: usize, S: OdeSystem<N> + ?Sized>(
        sys: &S,
        t: f64,
        y: &[f64; N],
        f0: &[f64; N],
        passive: &[bool; N],
        jac: &mut [[f64; N]; N],
        stats: &mut Stats,
    ) -> bool {
        stats.jacobians += 1;
        if !sys.jacobian(t, y, jac) {
            let floor = sys.magnitude_floor();
            let mut yj = *y;
            let mut fj = [0.0; N];
            for j in 0..N {
                if passive[j] {
                    for row in jac.iter_mut() {
                        row[j] = 0.0;
                    }
                    continue;
                }
                let d = (f64::EPSILON * y[j].abs().max(floor[j]).max(1e-5)).sqrt();
                yj[j] = y[j] + d;
                let d = yj[j] - y[j]; // the increment actually taken
                sys.rhs(t, &yj, &mut fj);
                stats.rhs_evals += 1;
                for i in 0..N {
                    jac[i][j] = (fj[i] - f0[i]) / d;
                }
                yj[j] = y[j];
            }
        }
        jac.iter().all(all_finite)
    }

    fn run<const N: usize, S, O>(
        &self,
        sys: &S,
        t0: f64,
        y0: [f64; N],
        t_end: f64,
        obs: &mut O,
        fixed: Option<u64>,
    ) -> Result<(f64, [f64; N], Stats), IntegrateError>
    where
        S: OdeSystem<N> + ?Sized,
        O: Observer<N> + ?Sized,
    {
        assert!(
            t0.is_finite() && t_end.is_finite(),
            "Radau5: t0 and t_end must be finite"
        );
        assert!(
            t_end >= t0,
            "Radau5: backward integration (t_end < t0) is not supported"
        );
        self.check_tolerances();

        let mut stats = Stats::default();
        obs.start(t0, &y0);
        if t_end == t0 {
            return Ok((t0, y0, stats));
        }

        let tab = Tableau::new();
        let (rtol, atol) = self.inner_tolerances();
        let rt_newton = if rtol > 0.0 { rtol } else { atol };
        let kappa = (10.0 * f64::EPSILON / rt_newton).max(0.03f64.min(rt_newton.sqrt()));
        let floor = sys.magnitude_floor();
        let nc = sys.controlled().min(N);

        let mut t = t0;
        let mut y = y0;
        let mut f0 = [0.0; N];
        sys.rhs(t, &y, &mut f0);
        stats.rhs_evals += 1;
        if !all_finite(&y) || !all_finite(&f0) {
            return Err(IntegrateError::NonFinite { t });
        }

        let span = t_end - t0;
        let h_max = if self.h_max > 0.0 {
            self.h_max.min(span)
        } else {
            span
        };
        let mut h = match (fixed, self.h_init) {
            (Some(n), _) => span / n as f64,
            (None, Some(h)) if h > 0.0 && h.is_finite() => h.min(h_max),
            _ => initial_step(sys, t, &y, &f0, h_max, (rtol, atol), 0.25, &mut stats),
        };

        let mut jac = [[0.0; N]; N];
        let passive = sys.passive();
        let mut e1 = Lu::<f64, N>::with_passive(&passive);
        let mut e2 = Lu::<C64, N>::with_passive(&passive);
        let mut dense = Radau5Dense::<N>::new();
        let mut z = [[0.0; N]; 3];
        let mut w = [[0.0; N]; 3];
        let mut fz = [[0.0; N]; 3];

        let mut have_jac = false;
        let mut jac_current = false; // the Jacobian belongs to the current (t, y)
        let mut want_new_jac = false;
        let mut lu_h = f64::NAN; // step size of the current factors
        let mut first = true;
        let mut rejected_last = false;
        let mut nonfinite_last = false;
        let mut eta = 1.0f64; // η of the last Newton iteration
        let (mut h_acc, mut err_acc) = (0.0, 0.0); // Gustafsson's controller
        let mut done_fixed = 0u64;

        loop {
            let attempts = stats.steps + stats.rejected;
            if attempts >= self.max_steps {
                return Err(IntegrateError::TooManySteps { t, steps: attempts });
            }
            if h.is_nan() || h <= 10.0 * f64::EPSILON * t.abs() {
                return Err(if nonfinite_last {
                    IntegrateError::NonFinite { t }
                } else {
                    IntegrateError::StepSizeTooSmall { t, h }
                });
            }
            let (last, h_step, t_new) = match fixed {
                Some(n) => {
                    let last = done_fixed + 1 == n;
                    let t_new = if last {
                        t_end
                    } else {
                        t0 + (done_fixed + 1) as f64 * h
                    };
                    (last, t_new - t, t_new)
                }
                None => {
                    // Stretch the step by up to 1 % to land on t_end, never beyond h_max.
                    if t_end - t <= (1.01 * h).min(h_max) {
                        (true, t_end - t, t_end)
                    } else {
                        (false, h, t + h)
                    }
                }
            };

            // Jacobian and iteration matrices.
            if !have_jac || (want_new_jac && !jac_current) {
                if !Self::jacobian(sys, t, &y, &f0, &passive, &mut jac, &mut stats) {
                    return Err(IntegrateError::NonFinite { t });
                }
                have_jac = true;
                jac_current = true;
                want_new_jac = false;
                lu_h = f64::NAN;
            }
            if h_step != lu_h {
                let (g, al, be) = (tab.gamma / h_step, tab.alpha / h_step, tab.beta / h_step);
                e1.set(|i, j| if i == j { g - jac[i][j] } else { -jac[i][j] });
                e2.set(|i, j| {
                    if i == j {
                        C64::new(al - jac[i][j], be)
                    } else {
                        C64::new(-jac[i][j], 0.0)
                    }
                });
                stats.lu_decomps += 1;
                let ok = e1.factor() & e2.factor();
                if !ok {
                    if fixed.is_some() {
                        return Err(IntegrateError::StepSizeTooSmall { t, h: h_step });
                    }
                    lu_h = f64::NAN;
                    stats.rejected += 1;
                    rejected_last = true;
                    h = 0.5 * h_step;
                    continue;
                }
                lu_h = h_step;
            }

            // Starting values: extrapolate the last collocation polynomial.
            if first {
                z = [[0.0; N]; 3];
            } else {
                let r = h_step / dense.h;
                for k in 0..3 {
                    let s = 1.0 + tab.c[k] * r;
                    for i in 0..N {
                        z[k][i] = dense.rel(s, i) - (dense.y1[i] - dense.y0[i]);
                    }
                }
            }
            for i in 0..N {
                for k in 0..3 {
                    w[k][i] =
                        tab.ti[k][0] * z[0][i] + tab.ti[k][1] * z[1][i] + tab.ti[k][2] * z[2][i];
                }
            }

            // Simplified Newton iterations on W.
            let mut sc = [0.0; N];
            for i in 0..N {
                sc[i] = atol + rtol * y[i].abs().max(floor[i]);
            }
            eta = eta.max(f64::EPSILON).powf(0.8);
            let mut theta = self.theta_jac;
            let mut newt = 0u32;
            let (mut dnorm_old, mut thq_old) = (0.0f64, 0.0f64);
            let (g, al, be) = (tab.gamma / h_step, tab.alpha / h_step, tab.beta / h_step);
            // Fixed steps cannot shrink: iterate as long as the iteration contracts.
            let max_newton = if fixed.is_some() { 40 } else { MAX_NEWTON };
            let outcome = loop {
                if newt >= max_newton {
                    break Err(NewtonFail::Slow(0.5));
                }
                let mut finite = true;
                for k in 0..3 {
                    let mut ys = [0.0; N];
                    for i in 0..N {
                        ys[i] = y[i] + z[k][i];
                    }
                    sys.rhs(t + tab.c[k] * h_step, &ys, &mut fz[k]);
                    finite &= all_finite(&fz[k]);
                }
                stats.rhs_evals += 3;
                if !finite {
                    break Err(NewtonFail::NonFinite);
                }
                let mut r1 = [0.0; N];
                let mut r2 = [C64::default(); N];
                for i in 0..N {
                    let gk = |k: usize| {
                        tab.ti[k][0] * fz[0][i] + tab.ti[k][1] * fz[1][i] + tab.ti[k][2] * fz[2][i]
                    };
                    r1[i] = gk(0) - g * w[0][i];
                    r2[i] = C64::new(
                        gk(1) - (al * w[1][i] - be * w[2][i]),
                        gk(2) - (be * w[1][i] + al * w[2][i]),
                    );
                }
                e1.solve(&mut r1);
                e2.solve(&mut r2);
                newt += 1;
                let mut dn = 0.0;
                for i in 0..N {
                    dn += (r1[i] / sc[i]).powi(2)
                        + (r2[i].re / sc[i]).powi(2)
                        + (r2[i].im / sc[i]).powi(2);
                }
                let dnorm = (dn / (3 * N) as f64).sqrt();
                if !dnorm.is_finite() {
                    break Err(NewtonFail::NonFinite);
                }
                if newt > 1 && newt < max_newton {
                    let thq = dnorm / dnorm_old;
                    theta = if newt == 2 {
                        thq
                    } else {
                        (thq * thq_old).sqrt()
                    };
                    thq_old = thq;
                    if theta >= 0.99 {
                        break Err(NewtonFail::Slow(0.5));
                    }
                    eta = theta / (1.0 - theta);
                    let left = (max_newton - 1 - newt) as i32;
                    let pred = eta * dnorm * theta.powi(left) / kappa;
                    if pred >= 1.0 && fixed.is_none() {
                        let q = pred.clamp(1e-4, 20.0);
                        break Err(NewtonFail::Slow(0.8 * q.powf(-1.0 / (4.0 + left as f64))));
                    }
                }
                dnorm_old = dnorm.max(f64::EPSILON);
                for i in 0..N {
                    w[0][i] += r1[i];
                    w[1][i] += r2[i].re;
                    w[2][i] += r2[i].im;
                    for k in 0..3 {
                        z[k][i] =
                            tab.t[k][0] * w[0][i] + tab.t[k][1] * w[1][i] + tab.t[k][2] * w[2][i];
                    }
                }
                if eta * dnorm <= kappa {
                    break Ok(());
                }
            };
            if let Err(fail) = outcome {
                if fixed.is_some() && !jac_current && matches!(fail, NewtonFail::Slow(_)) {
                    // Fixed steps: retry once with a Jacobian at the step's initial state.
                    want_new_jac = true;
                    continue;
                }
                if fixed.is_some() {
                    return Err(match fail {
                        NewtonFail::NonFinite => IntegrateError::NonFinite { t },
                        NewtonFail::Slow(_) => IntegrateError::StepSizeTooSmall { t, h: h_step },
                    });
                }
                stats.rejected += 1;
                rejected_last = true;
                let fac = match fail {
                    NewtonFail::Slow(f) => {
                        nonfinite_last = false;
                        f
                    }
                    NewtonFail::NonFinite => {
                        nonfinite_last = true;
                        0.5
                    }
                };
                h = fac * h_step;
                if !jac_current {
                    want_new_jac = true;
                }
                continue;
            }

            // Error estimate, filtered through (I - h γ0 J)⁻¹ = E1⁻¹ / (h γ0).
            let mut y_new = [0.0; N];
            let mut dz = [0.0; N];
            let mut ev = [0.0; N];
            for i in 0..N {
                y_new[i] = y[i] + z[2][i];
                dz[i] = (tab.dd[0] * z[0][i] + tab.dd[1] * z[1][i] + tab.dd[2] * z[2][i]) / h_step;
                ev[i] = f0[i] + dz[i];
            }
            e1.solve(&mut ev);
            let norm = |ev: &[f64; N]| -> f64 {
                let mut s = 0.0;
                for i in 0..nc {
                    let sk = atol + rtol * y[i].abs().max(y_new[i].abs()).max(floor[i]);
                    s += scaled(ev[i], sk).powi(2);
                }
                let e = (s / nc.max(1) as f64).sqrt();
                if e.is_nan() {
                    f64::INFINITY
                } else {
                    e
                }
            };
            let mut err = norm(&ev);
            if fixed.is_none() && err >= 1.0 && (first || rejected_last) {
                let mut ye = [0.0; N];
                for i in 0..N {
                    ye[i] = y[i] + ev[i];
                }
                let mut fe = [0.0; N];
                sys.rhs(t, &ye, &mut fe);
                stats.rhs_evals += 1;
                for i in 0..N {
                    ev[i] = fe[i] + dz[i];
                }
                e1.solve(&mut ev);
                err = norm(&ev);
            }
            let err = err.max(1e-10);

            let fac =
                SAFETY.min(SAFETY * (1 + 2 * MAX_NEWTON) as f64 / (newt + 2 * MAX_NEWTON) as f64);
            let mut quot = (err.sqrt().sqrt() / fac).clamp(FAC_R, FAC_L);
            if err >= 1.0 && fixed.is_none() {
                stats.rejected += 1;
                rejected_last = true;
                nonfinite_last = false;
                h = if first { 0.1 * h_step } else { h_step / quot };
                if !jac_current {
                    want_new_jac = true;
                }
                continue;
            }

            // Accepted: project, then evaluate f at the (projected) new state.
            sys.project(&mut y_new);
            let mut f_new = [0.0; N];
            sys.rhs(t_new, &y_new, &mut f_new);
            stats.rhs_evals += 1;
            if !all_finite(&y_new) || !all_finite(&f_new) {
                if fixed.is_some() {
                    return Err(IntegrateError::NonFinite { t });
                }
                stats.rejected += 1;
                rejected_last = true;
                nonfinite_last = true;
                h = 0.5 * h_step;
                continue;
            }
            if !first {
                // Gustafsson's predictive controller, when it proposes the smaller step.
                let gus = (h_acc / h_step) * (err * err / err_acc).sqrt().sqrt() / SAFETY;
                quot = quot.max(gus.clamp(FAC_R, FAC_L));
            }
            h_acc = h_step;
            err_acc = err.max(1e-2);
            let mut h_new = (h_step / quot).min(h_max);
            if rejected_last {
                h_new = h_new.min(h_step);
            }

            dense.set(t, t_new, h_step, &tab.c, &y, &y_new, &z);
            stats.steps += 1;
            done_fixed += 1;
            let flow = obs.step(t_new, &y_new, &dense);
            if let ControlFlow::Break(()) = flow {
                let (ts, ys) = obs.stop_point().unwrap_or((t_new, y_new));
                return Ok((ts, ys, stats));
            }
            if last {
                return Ok((t_new, y_new, stats));
            }
            t = t_new;
            y = y_new;
            f0 = f_new;
            first = false;
            rejected_last = false;
            nonfinite_last = false;
            jac_current = false;
            // Jacobian reuse after fast convergence; then also the step and the LU, if
            // the step would change little.
            let keep_jac = theta <= self.theta_jac;
            want_new_jac = !keep_jac;
            let qt = h_new / h_step;
            if fixed.is_none() {
                h = if keep_jac && (1.0..=1.2).contains(&qt) && h_step <= h_max {
                    h_step
                } else {
                    h_new
                };
            }
        }
    }
}
