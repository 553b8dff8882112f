//! The exact solution of the Lagrange top in Jacobi elliptic functions.
//!
//! With `u = cos(theta)` the nutation obeys `udot^2 = f(u)`, a cubic whose roots `uA`, `uB`
//! bound the motion (theory: Lagrange top). Writing
//!
//! `u(tau) = uA cn^2(tau | m) + uB sn^2(tau | m)`,  `tau = w t + tau0`,
//!
//! with `m = (uB - uA)/(u3 - uA)` and `4 w^2 = beta (u3 - uA)`, solves it for either sign of
//! `beta = 2 m g l / I1`: the anchor `uA` is the lower turning point for `l > 0` and the upper
//! one for `l < 0` (and `l = 0` gives `m = 0`, the free top). The same form gives
//! `1 - u = (1 - uA) cn^2 + (1 - uB) sn^2` and `1 + u` alike, so every quantity near the
//! vertical keeps full precision. The precession and spin angles are the integrals of
//! `phidot = (b - a u)/(1 - u^2) = [(b - a)/(1 - u) + (b + a)/(1 + u)] / 2` and
//! `psidot = (I1/I3 - 1) a - [(b - a)/(1 - u) - (b + a)/(1 + u)] / 2`, i.e. incomplete elliptic
//! integrals of the third kind in `am(tau)` with characteristics `n+ = (uB - uA)/(1 - uA)` and
//! `n- = -(uB - uA)/(1 + uA)`.
//!
//! Evaluation: all of theta, its rate, the periodic parts of phi and psi and their rates are
//! functions of `tau` on half a nutation period, `[0, K]`, extended by
//! symmetry (`u` is even in `tau`, the angle integrals odd) and by the period (`2K` in
//! `tau` adds a fixed advance). They are interpolated once per trajectory to round-off by
//! piecewise polynomials ([`Piecewise`]), which makes each further time cost a few tens of
//! nanoseconds; the direct evaluation with Jacobi functions and Carlson integrals is kept
//! for checks and for the separatrix, whose period is infinite.

use super::{EulerState, LagrangeTop};
use crate::error::{KreiselError, Result};
use crate::special::chebyshev::Piecewise;
use crate::special::cubic::Poly3;
use crate::special::elliptic::{ellipk_m1, pi_of_tau, rf};
use crate::special::jacobi;
use std::f64::consts::PI;

/// Below this complementary parameter 1 - k^2 a motion is taken to be on the separatrix:
/// its period would exceed 2 K / w with K > 17.7, and 1 - k^2 is then below what the
/// rounding of a state's invariants can resolve.
pub const SEPARATRIX_M1: f64 = 1e-13;

/// A nutation whose amplitude in theta is at most this (rad) is called a regular
/// precession: the rounding of a steady precession's rates leaves amplitudes near 1e-16.
pub const STEADY_AMPLITUDE: f64 = 1e-11;

/// A turning point whose distance to the vertical (1 - u or 1 + u) is below this fraction
/// of the other's is taken to be at the vertical: the axis then passes within 1e-16 rad of
/// it (relative to the nutation), and phi swings by pi within a time below the resolution
/// of t, so the passage is a crossing (phi and psi jump by pi, in the directions of that
/// swing) to round-off. Closer passages cannot be evaluated in floating point: the swing's
/// width in tau would be below the spacing of floats near K.
pub const VERTICAL_SNAP: f64 = f64::EPSILON * f64::EPSILON;

/// The kinds of motion of a Lagrange top.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotionKind {
    /// Spinning upright (theta = 0 for all time).
    Sleeping,
    /// Spinning hanging straight down (theta = pi for all time).
    Hanging,
    /// Steady precession: theta constant, 0 < theta < pi.
    RegularPrecession,
    /// Nutation with phidot of one sign throughout (wavy path of the axis).
    Waves,
    /// Nutation with phidot = 0 at one turning point (cusps).
    Cusps,
    /// Nutation with phidot changing sign (loops).
    Loops,
    /// The figure axis passes through the vertical (Mz = +-M3).
    ThroughVertical,
    /// The separatrix: the axis approaches the vertical asymptotically (infinite period).
    Asymptotic,
}

impl MotionKind {
    /// Every kind, in the order of their codes in a sweep.
    pub const ALL: [MotionKind; 8] = [
        MotionKind::Sleeping,
        MotionKind::Hanging,
        MotionKind::RegularPrecession,
        MotionKind::Waves,
        MotionKind::Cusps,
        MotionKind::Loops,
        MotionKind::ThroughVertical,
        MotionKind::Asymptotic,
    ];

    /// The public name of the kind.
    pub const fn name(&self) -> &'static str {
        match self {
            MotionKind::Sleeping => "sleeping",
            MotionKind::Hanging => "hanging",
            MotionKind::RegularPrecession => "regular_precession",
            MotionKind::Waves => "waves",
            MotionKind::Cusps => "cusps",
            MotionKind::Loops => "loops",
            MotionKind::ThroughVertical => "through_vertical",
            MotionKind::Asymptotic => "asymptotic",
        }
    }
}

/// A turning point u, with 1 - u and 1 + u kept separately (full precision near +-1).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Turn {
    u: f64,
    om: f64,
    op: f64,
    /// u - u0
    delta: f64,
}

impl Turn {
    fn theta(&self) -> f64 {
        (self.om * self.op).max(0.0).sqrt().atan2(self.u)
    }
}

/// Values at one tau in [0, K]: theta, thetadot (tau increasing), Phi, Psi_periodic,
/// phidot, psidot.
type Row = [f64; 6];

#[derive(Debug, Clone)]
struct Nutation {
    a_: Turn,
    b_: Turn,
    m: f64,
    m1: f64,
    w: f64,
    /// Half-period in tau, K(m); infinite on the separatrix.
    kk: f64,
    /// 1 / (2 K)
    inv_period: f64,
    tau0: f64,
    /// (b - a)/(2 (1 - uA)) and (b + a)/(2 (1 + uA)), zero where the numerator is zero.
    cp: f64,
    cm: f64,
    np: f64,
    np1: f64,
    nm: f64,
    nm1: f64,
    db: f64,
    sb: f64,
    /// Phi and Psi_periodic at tau = K.
    phi_k: f64,
    psi_k: f64,
    /// Jumps of (phi, psi), in units of pi, at each vertical passage at tau = 0 (mod 2K)
    /// and at tau = K (mod 2K); zero where the axis does not pass there.
    jump_a: [f64; 2],
    jump_b: [f64; 2],
    interp: Option<Piecewise<6>>,
    /// Phi_total and Psi_total and the jumps of (phi, psi) (units of pi) at tau0.
    phi_tot0: f64,
    psi_tot0: f64,
    cross0: [f64; 2],
}

/// The exact motion of one Lagrange top from one state, ready to evaluate at any time.
#[derive(Debug, Clone)]
pub struct LagrangeExact {
    state: EulerState,
    kind: MotionKind,
    lo: Turn,
    hi: Turn,
    /// (I1/I3 - 1) a: the secular part of psidot.
    spin_lin: f64,
    /// sqrt(4 w^2) for small oscillations about a steady motion (0 if none).
    small_freq: f64,
    nut: Option<Nutation>,
}

impl LagrangeExact {
    /// Prepares the exact solution from a state (taken at t = 0).
    pub fn new(top: &LagrangeTop, state: &EulerState) -> Result<Self> {
        let s = normalise(state);
        let i1 = top.i1();
        let inv = top.invariants(&s);
        let a = inv.m3 / i1;
        let beta = 2.0 * top.mgl() / i1;
        // sin, cos, 1 - cos and 1 + cos of theta0, exact at the verticals.
        let (st, u0, om0, op0) = if s.theta == PI {
            (0.0, -1.0, 2.0, 0.0)
        } else {
            let (st, u0) = s.theta.sin_cos();
            let (sh, ch) = (0.5 * s.theta).sin_cos();
            (st, u0, 2.0 * sh * sh, 2.0 * ch * ch)
        };
        // The gyro function about u0 (delta = u - u0): c0 = udot0^2 exactly.
        let a0 = s.theta_dot * s.theta_dot + (s.phi_dot * st).powi(2);
        let b0 = s.phi_dot * st * st; // = b - a u0
        let c0 = (st * s.theta_dot).powi(2);
        let c1 = -st * st * beta - 2.0 * u0 * a0 + 2.0 * a * b0;
        let c2 = 2.0 * u0 * beta - a0 - a * a;
        let p = Poly3([c0, c1, c2, beta]);
        let mut db = b0 - a * om0; // b - a
        let mut sb = b0 + a * op0; // b + a

        let (dlo, dhi) = if c0 == 0.0 && c1 == 0.0 {
            (0.0, 0.0)
        } else if c0 == 0.0 {
            // u0 is a simple turning point; the other one is a root of the deflated quadratic.
            let q = Poly3([c1, c2, beta, 0.0]);
            if c1 > 0.0 {
                (0.0, q.root_in(0.0, om0))
            } else {
                (q.root_in(-op0, 0.0), 0.0)
            }
        } else {
            (p.root_in(-op0, 0.0), p.root_in(0.0, om0))
        };
        let mut lo = turn(u0, om0, op0, dlo, db, sb, beta, a, a0);
        let mut hi = turn(u0, om0, op0, dhi, db, sb, beta, a, a0);
        let (top_jump, bottom_jump) = snap_to_vertical(&mut lo, &mut hi, &mut db, &mut sb);
        let spin_lin = (i1 / top.i3() - 1.0) * a;

        let mut out = LagrangeExact {
            state: s,
            kind: MotionKind::RegularPrecession,
            lo,
            hi,
            spin_lin,
            small_freq: 0.0,
            nut: None,
        };
        // 4 w^2 = beta (u3 - uA), written without dividing by beta (so l = 0 is included).
        let (ta, mut tb) = if beta >= 0.0 { (lo, hi) } else { (hi, lo) };
        let w4 = -c2 - beta * (tb.delta + 2.0 * ta.delta);
        if hi.delta - lo.delta == 0.0 {
            out.kind = if s.theta == 0.0 {
                MotionKind::Sleeping
            } else if s.theta == PI {
                MotionKind::Hanging
            } else {
                MotionKind::RegularPrecession
            };
            out.small_freq = w4.max(0.0).sqrt();
            return Ok(out);
        }
        if w4.is_nan() || w4 <= 0.0 {
            return Err(KreiselError::Numerical(format!(
                "nutation frequency squared {w4} is not positive"
            )));
        }
        let dab = tb.delta - ta.delta; // uB - uA
        let (mut m, mut m1, w4) = if beta == 0.0 {
            (0.0, 1.0, w4)
        } else {
            // The third root in the distance to the vertical beyond which it lies (e3 < 0),
            // so that u3 - uB and u3 - uA have no cancellation even when uB is near it.
            let q = if beta > 0.0 {
                top_poly(db, a, beta, a0, om0)
            } else {
                bottom_poly(sb, a, beta, a0, op0)
            };
            let c = q.0;
            let x = 1.0 + (c[0].abs().max(c[1].abs()).max(c[2].abs())) / beta.abs();
            let (ea, eb) = if beta > 0.0 {
                (ta.om, tb.om)
            } else {
                (ta.op, tb.op)
            };
            let e3 = if x < 1e6 {
                q.root_in(-x, 0.0)
            } else {
                // beta is small against the other coefficients: the third root is far,
                // beyond the turning points by about x, and the sum of the roots gives it
                // without cancellation. (At the bracket's end -x the cubic's leading terms
                // cancel to round-off, so its sign there is not resolved.)
                -c[2] / c[3] - ea - eb
            };
            if e3.is_finite() {
                (
                    dab.abs() / (ea - e3),
                    (eb - e3) / (ea - e3),
                    beta.abs() * (ea - e3),
                )
            } else {
                // Beyond the range of f64: m = 0 to round-off, the limit of a free top.
                (0.0, 1.0, w4)
            }
        };
        if m1 < SEPARATRIX_M1 {
            // On the separatrix the far turning point is the vertical itself (Mz = +-M3).
            m = 1.0;
            m1 = 0.0;
            if beta > 0.0 {
                tb = Turn {
                    u: 1.0,
                    om: 0.0,
                    op: 2.0,
                    delta: tb.delta,
                };
                db = 0.0;
            } else {
                tb = Turn {
                    u: -1.0,
                    om: 2.0,
                    op: 0.0,
                    delta: tb.delta,
                };
                sb = 0.0;
            }
        }
        let w = 0.5 * w4.sqrt();
        out.small_freq = 2.0 * w;
        let kk = ellipk_m1(m1);

        // Phase: sn^2(tau0) = (u0 - uA)/(uB - uA), cn^2 = (uB - u0)/(uB - uA).
        let (sa, sbq) = (ta.delta.abs().sqrt(), tb.delta.abs().sqrt());
        let norm = (sa * sa + sbq * sbq).sqrt();
        let (sn0, cn0) = (sa / norm, sbq / norm);
        let dn0 = (cn0 * cn0 + m1 * sn0 * sn0).sqrt();
        let mut tau0 = if sn0 == 0.0 {
            0.0
        } else if cn0 == 0.0 {
            kk
        } else {
            sn0 * rf(cn0 * cn0, dn0 * dn0, 1.0)?
        };
        let udot0 = -st * s.theta_dot;
        if udot0 != 0.0 && (udot0 > 0.0) != (dab > 0.0) {
            tau0 = -tau0;
        }
        if !tau0.is_finite() {
            // At the vertical on the separatrix: the (unstable) equilibrium itself.
            out.kind = if u0 > 0.0 {
                MotionKind::Sleeping
            } else {
                MotionKind::Hanging
            };
            out.small_freq = 0.0;
            return Ok(out);
        }
        let half = |om: f64, num: f64| if num == 0.0 { 0.0 } else { num / (2.0 * om) };
        let cp = half(ta.om, db);
        let cm = half(ta.op, sb);
        let np = if ta.om == 0.0 { 0.0 } else { dab / ta.om };
        let np1 = if ta.om == 0.0 { 1.0 } else { tb.om / ta.om };
        let nm = if ta.op == 0.0 { 0.0 } else { -dab / ta.op };
        let nm1 = if ta.op == 0.0 { 1.0 } else { tb.op / ta.op };
        let mut nut = Nutation {
            a_: ta,
            b_: tb,
            m,
            m1,
            w,
            kk,
            inv_period: 0.5 / kk,
            tau0,
            cp,
            cm,
            np,
            np1,
            nm,
            nm1,
            db,
            sb,
            phi_k: 0.0,
            psi_k: 0.0,
            jump_a: passage(&ta, top_jump, bottom_jump),
            jump_b: passage(&tb, top_jump, bottom_jump),
            interp: None,
            phi_tot0: 0.0,
            psi_tot0: 0.0,
            cross0: [0.0; 2],
        };
        out.kind = if m1 == 0.0 {
            MotionKind::Asymptotic
        } else if lo.theta() - hi.theta() <= STEADY_AMPLITUDE {
            // A nutation this small is the round-off of a steady state's rates.
            MotionKind::RegularPrecession
        } else if nut.crosses() {
            MotionKind::ThroughVertical
        } else {
            let (ga, gb) = (b0 - a * lo.delta, b0 - a * hi.delta);
            let scale = 1e-12 * (a.abs() + (b0 + a * u0).abs());
            if ga.abs() <= scale || gb.abs() <= scale {
                MotionKind::Cusps
            } else if (ga > 0.0) != (gb > 0.0) {
                MotionKind::Loops
            } else {
                MotionKind::Waves
            }
        };
        if kk.is_finite() {
            let end = nut.row(kk, spin_lin)?;
            nut.phi_k = end[2];
            nut.psi_k = end[3];
            // Interpolate to round-off; fall back to direct evaluation if that fails.
            nut.interp = Piecewise::<6>::build(0.0, kk, |x| nut.row(x, spin_lin), 1e-14, 14)
                .ok()
                .filter(|p| p.accuracy() < 1e-11);
        }
        let (j0, sgn0, rho0) = nut.reduce(tau0);
        let v0 = nut.row(rho0, spin_lin)?;
        nut.phi_tot0 = 2.0 * j0 * nut.phi_k + sgn0 * v0[2];
        nut.psi_tot0 = 2.0 * j0 * nut.psi_k + sgn0 * v0[3];
        nut.cross0 = nut.crossings(tau0);
        out.nut = Some(nut);
        Ok(out)
    }

    /// The motion kind.
    pub fn kind(&self) -> MotionKind {
        self.kind
    }

    /// (theta_min, theta_max): the turning points of the nutation.
    pub fn turning_points(&self) -> (f64, f64) {
        (self.hi.theta(), self.lo.theta())
    }

    /// (u_min, u_max) = (cos theta_max, cos theta_min).
    pub fn u_range(&self) -> (f64, f64) {
        (self.lo.u, self.hi.u)
    }

    /// Nutation period (s): infinite on the separatrix; for a steady motion the period of
    /// small nutations about it (infinite if it is unstable).
    pub fn nutation_period(&self) -> f64 {
        match &self.nut {
            Some(n) => 2.0 * n.kk / n.w,
            None if self.small_freq > 0.0 => 2.0 * PI / self.small_freq,
            None => f64::INFINITY,
        }
    }

    /// The mean of phidot over a nutation period (rad/s). On the separatrix, the limit rate
    /// at the vertical.
    pub fn mean_precession_rate(&self) -> f64 {
        match &self.nut {
            None => self.state.phi_dot,
            Some(n) if n.kk.is_infinite() => {
                // Time average over the infinite approach is the rate at the vertical.
                if n.b_.om == 0.0 {
                    n.sb / (2.0 * 2.0)
                } else {
                    n.db / (2.0 * 2.0)
                }
            }
            Some(n) => {
                let jumps = n.jump_a[0] + n.jump_b[0];
                (2.0 * n.phi_k + PI * jumps) / (2.0 * n.kk / n.w)
            }
        }
    }

    /// Number of interpolation segments (0 when evaluation is direct).
    pub fn segments(&self) -> usize {
        self.nut
            .as_ref()
            .and_then(|n| n.interp.as_ref())
            .map_or(0, |p| p.segments())
    }

    /// The state at time `t` (fast path: interpolation where available).
    pub fn at(&self, t: f64) -> Result<EulerState> {
        self.eval(t, true)
    }

    /// The state at time `t` by direct evaluation of the Jacobi functions and elliptic
    /// integrals (slow; for checks).
    pub fn at_direct(&self, t: f64) -> Result<EulerState> {
        self.eval(t, false)
    }

    fn eval(&self, t: f64, fast: bool) -> Result<EulerState> {
        let s = &self.state;
        let Some(n) = &self.nut else {
            return Ok(EulerState {
                phi: s.phi + s.phi_dot * t,
                psi: s.psi + s.psi_dot * t,
                ..*s
            });
        };
        let tau = n.w * t + n.tau0;
        let (j, sgn, rho) = n.reduce(tau);
        let v = match (&n.interp, fast) {
            (Some(p), true) => p.eval(rho),
            _ => n.row(rho, self.spin_lin)?,
        };
        Ok(self.assemble(n, t, tau, (j, sgn), &v))
    }

    /// The state at time t from the half-period values `v` at tau = w t + tau0.
    #[inline(always)]
    fn assemble(&self, n: &Nutation, t: f64, tau: f64, red: (f64, f64), v: &Row) -> EulerState {
        let s = &self.state;
        let (j, sgn) = red;
        let [jp, js] = n.crossings(tau);
        let (jp, js) = (jp - n.cross0[0], js - n.cross0[1]);
        EulerState {
            theta: v[0].clamp(0.0, PI),
            theta_dot: sgn * v[1],
            phi: s.phi + (2.0 * j * n.phi_k + sgn * v[2] - n.phi_tot0) + PI * jp,
            psi: s.psi
                + self.spin_lin * t
                + (2.0 * j * n.psi_k + sgn * v[3] - n.psi_tot0)
                + PI * js,
            phi_dot: v[4],
            psi_dot: v[5],
        }
    }

    /// Evaluates at many times into the six output slices (theta, phi, psi, theta_dot,
    /// phi_dot, psi_dot), each as long as `t`.
    pub fn eval_into(&self, t: &[f64], out: [&mut [f64]; 6]) -> Result<()> {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
        {
            // SAFETY: the CPU supports the features the function is compiled for.
            return unsafe { self.eval_into_avx2(t, out) };
        }
        self.eval_into_with::<false>(t, out)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn eval_into_avx2(&self, t: &[f64], out: [&mut [f64]; 6]) -> Result<()> {
        self.eval_into_with::<true>(t, out)
    }

    #[inline(always)]
    fn eval_into_with<const FMA: bool>(&self, t: &[f64], out: [&mut [f64]; 6]) -> Result<()> {
        let [th, ph, ps, thd, phd, psd] = out;
        if let Some(n) = self.nut.as_ref().filter(|n| n.interp.is_some()) {
            // Blocks in three passes: reduction to half a period and assembly are plain
            // loops the compiler vectorises; the interpolation runs four points at a time.
            const B: usize = 64;
            let interp = n.interp.as_ref().unwrap();
            let s = &self.state;
            let (p2, kk) = (2.0 * n.kk, n.kk);
            let phi_c = s.phi - n.phi_tot0 - PI * n.cross0[0];
            let psi_c = s.psi - n.psi_tot0 - PI * n.cross0[1];
            let mut rho = [0.0f64; B];
            let mut jj = [0.0f64; B];
            let mut sg = [0.0f64; B];
            let mut cr = [[0.0f64; 2]; B];
            let mut v = [[0.0f64; 6]; B];
            for (start, tb) in (0..t.len()).step_by(B).zip(t.chunks(B)) {
                let m = tb.len();
                for k in 0..m {
                    let tau = n.w * tb[k] + n.tau0;
                    let j = round_magic(tau * n.inv_period);
                    let r = tau - p2 * j;
                    jj[k] = j;
                    sg[k] = if r < 0.0 { -1.0 } else { 1.0 };
                    rho[k] = r.abs().min(kk);
                }
                if n.crosses() {
                    for k in 0..m {
                        cr[k] = n.crossings(n.w * tb[k] + n.tau0);
                    }
                }
                rho[m..].fill(0.0);
                for q in 0..m.div_ceil(4) {
                    let x = [rho[4 * q], rho[4 * q + 1], rho[4 * q + 2], rho[4 * q + 3]];
                    let r = interp.eval4::<FMA>(x);
                    v[4 * q..4 * q + 4].copy_from_slice(&r);
                }
                let range = start..start + m;
                let (th, ph, ps) = (
                    &mut th[range.clone()],
                    &mut ph[range.clone()],
                    &mut ps[range.clone()],
                );
                let (thd, phd, psd) = (
                    &mut thd[range.clone()],
                    &mut phd[range.clone()],
                    &mut psd[range],
                );
                for k in 0..m {
                    let (j, g) = (jj[k], sg[k]);
                    let [jp, js] = cr[k];
                    th[k] = v[k][0].clamp(0.0, PI);
                    thd[k] = g * v[k][1];
                    ph[k] = phi_c + 2.0 * j * n.phi_k + g * v[k][2] + PI * jp;
                    ps[k] =
                        psi_c + self.spin_lin * tb[k] + 2.0 * j * n.psi_k + g * v[k][3] + PI * js;
                    phd[k] = v[k][4];
                    psd[k] = v[k][5];
                }
            }
            return Ok(());
        }
        Self::each([th, ph, ps, thd, phd, psd], t, |ti| self.at(ti))
    }

    /// Fills the six outputs time by time from `state_at`.
    fn each(
        out: [&mut [f64]; 6],
        t: &[f64],
        state_at: impl Fn(f64) -> Result<EulerState>,
    ) -> Result<()> {
        let [th, ph, ps, thd, phd, psd] = out;
        for (i, &ti) in t.iter().enumerate() {
            let e = state_at(ti)?;
            th[i] = e.theta;
            ph[i] = e.phi;
            ps[i] = e.psi;
            thd[i] = e.theta_dot;
            phd[i] = e.phi_dot;
            psd[i] = e.psi_dot;
        }
        Ok(())
    }
}

impl Nutation {
    /// tau -> (periods j, sign, rho in [0, K]) with tau = 2 K j + sign rho.
    #[inline]
    fn reduce(&self, tau: f64) -> (f64, f64, f64) {
        if self.kk.is_infinite() {
            return (0.0, if tau < 0.0 { -1.0 } else { 1.0 }, tau.abs());
        }
        let j = round_fast(tau * self.inv_period);
        let r = tau - 2.0 * self.kk * j;
        let sgn = if r < 0.0 { -1.0 } else { 1.0 };
        (j, sgn, r.abs().min(self.kk))
    }

    /// Whether the axis passes through the vertical.
    fn crosses(&self) -> bool {
        self.jump_a != [0.0; 2] || self.jump_b != [0.0; 2]
    }

    /// The jumps of (phi, psi), in units of pi, of the vertical passages counted from
    /// tau = 0 (step functions of tau).
    #[inline]
    fn crossings(&self, tau: f64) -> [f64; 2] {
        if self.kk.is_infinite() {
            return [0.0; 2];
        }
        let p = 2.0 * self.kk;
        let mut c = [0.0; 2];
        if self.jump_a != [0.0; 2] {
            let k = floor_fast(tau / p);
            c = [c[0] + k * self.jump_a[0], c[1] + k * self.jump_a[1]];
        }
        if self.jump_b != [0.0; 2] {
            let k = floor_fast((tau - self.kk) / p);
            c = [c[0] + k * self.jump_b[0], c[1] + k * self.jump_b[1]];
        }
        c
    }

    /// Direct evaluation at rho in [0, K] (any rho >= 0 on the separatrix).
    fn row(&self, rho: f64, spin_lin: f64) -> Result<Row> {
        let (sn, cn, dn) = if rho >= self.kk {
            // The turning point itself, exactly (the complete integrals).
            (1.0, 0.0, self.m1.sqrt())
        } else {
            let jf = jacobi(rho, self.m, self.m1);
            (jf.sn.max(0.0), jf.cn.max(0.0), jf.dn)
        };
        let (s2, c2) = (sn * sn, cn * cn);
        let (ta, tb) = (&self.a_, &self.b_);
        let u = ta.u * c2 + tb.u * s2;
        let om = ta.om * c2 + tb.om * s2;
        let op = ta.op * c2 + tb.op * s2;
        let theta = (om * op).max(0.0).sqrt().atan2(u);
        // thetadot = -udot / sin(theta), udot = 2 w (uB - uA) sn cn dn; where sin(theta)
        // vanishes at a vertical passage the factor sn or cn cancels analytically.
        let mut num = [sn, cn];
        let mut den = 1.0;
        for (x_a, x_b, x) in [(ta.om, tb.om, om), (ta.op, tb.op, op)] {
            if x_a == 0.0 {
                num[0] = 1.0;
                den *= x_b.sqrt();
            } else if x_b == 0.0 {
                num[1] = 1.0;
                den *= x_a.sqrt();
            } else {
                den *= x.sqrt();
            }
        }
        let dab = tb.u - ta.u;
        let theta_dot = if den == 0.0 {
            0.0
        } else {
            -2.0 * self.w * dab * num[0] * num[1] * dn / den
        };
        let ratio = |c: f64, x: f64| if c == 0.0 { 0.0 } else { c / x };
        let tp = ratio(self.db, om) * 0.5;
        let tm = ratio(self.sb, op) * 0.5;
        let phi_dot = tp + tm;
        let psi_dot = spin_lin - tp + tm;
        let third = |n: f64, n1: f64| {
            if self.m1 == 0.0 {
                Ok(pi_separatrix(rho, sn, n, n1))
            } else {
                pi_of_tau(rho.min(self.kk), [sn, cn, dn], n, n1, self.m, self.m1)
            }
        };
        let ip = if self.cp == 0.0 {
            0.0
        } else {
            self.cp * third(self.np, self.np1)?
        };
        let im = if self.cm == 0.0 {
            0.0
        } else {
            self.cm * third(self.nm, self.nm1)?
        };
        Ok([
            theta,
            theta_dot,
            (ip + im) / self.w,
            (im - ip) / self.w,
            phi_dot,
            psi_dot,
        ])
    }
}

/// `int_0^tau ds / (1 - n tanh^2 s)` (the third-kind integral at k = 1), elementary:
/// `[tau - sqrt(n) atanh(sqrt(n) tanh tau)] / (1 - n)` for 0 < n < 1 and
/// `[tau + sqrt(-n) atan(sqrt(-n) tanh tau)] / (1 - n)` for n < 0. `th` is tanh(tau).
fn pi_separatrix(tau: f64, th: f64, n: f64, n1: f64) -> f64 {
    if n == 0.0 {
        tau
    } else if n > 0.0 {
        let r = n.sqrt();
        (tau - r * (r * th).atanh()) / n1
    } else {
        let r = (-n).sqrt();
        (tau + r * (r * th).atan()) / n1
    }
}

/// Nearest integer (ties to even) by the 1.5 * 2^52 trick: branch-free, so loops over it
/// vectorise. Exact for |x| < 2^51; beyond that x is returned.
#[inline(always)]
fn round_magic(x: f64) -> f64 {
    const M: f64 = 6_755_399_441_055_744.0;
    if x.abs() < 2_251_799_813_685_248.0 {
        (x + M) - M
    } else {
        x
    }
}

/// Nearest integer, by truncating conversion (the libm call behind `f64::round` costs more
/// than the rest of an evaluation on baseline x86-64). Exact for |x| < 2^52.
#[inline]
fn round_fast(x: f64) -> f64 {
    let y = x.abs() + 0.5;
    let r = if y < 4.5e15 {
        (y as i64) as f64
    } else {
        x.abs()
    };
    r.copysign(x)
}

/// Floor by truncating conversion, exact for |x| < 2^52.
#[inline]
fn floor_fast(x: f64) -> f64 {
    if x.abs() >= 4.5e15 {
        return x;
    }
    let t = (x as i64) as f64;
    if t > x {
        t - 1.0
    } else {
        t
    }
}

/// A state with theta at 0 or pi moving out of [0, pi] is rewritten as the same orientation
/// seen from the other side: (phi + pi, theta, psi - pi) with the rate of theta reversed.
fn normalise(s: &EulerState) -> EulerState {
    if (s.theta == 0.0 && s.theta_dot < 0.0) || (s.theta == PI && s.theta_dot > 0.0) {
        EulerState {
            phi: s.phi + PI,
            psi: s.psi - PI,
            theta_dot: -s.theta_dot,
            ..*s
        }
    } else {
        *s
    }
}

/// Puts a turning point that lies closer to a vertical than [`VERTICAL_SNAP`] allows onto
/// it, with `b - a` (top) or `b + a` (bottom) zero as there. Returns the jumps of (phi, psi),
/// in units of pi, at a passage through the top and the bottom vertical: those of the swing
/// the near passage makes (phi by the sign of `b -+ a`, psi opposite at the top and along at
/// the bottom), and +1, -1 for an exact passage.
fn snap_to_vertical(
    lo: &mut Turn,
    hi: &mut Turn,
    db: &mut f64,
    sb: &mut f64,
) -> ([f64; 2], [f64; 2]) {
    let sign = |x: f64| if x < 0.0 { -1.0 } else { 1.0 };
    let top = [sign(*db), -sign(*db)];
    let bottom = if *sb == 0.0 {
        [1.0, -1.0]
    } else {
        [sign(*sb), sign(*sb)]
    };
    if hi.om <= VERTICAL_SNAP * lo.om {
        *hi = Turn {
            u: 1.0,
            om: 0.0,
            op: 2.0,
            delta: hi.delta,
        };
        *db = 0.0;
    }
    if lo.op <= VERTICAL_SNAP * hi.op {
        *lo = Turn {
            u: -1.0,
            om: 2.0,
            op: 0.0,
            delta: lo.delta,
        };
        *sb = 0.0;
    }
    (top, bottom)
}

/// The jumps of (phi, psi) at a passage of the axis through the vertical at turning point
/// `t`, or zero where `t` is not at a vertical.
fn passage(t: &Turn, top: [f64; 2], bottom: [f64; 2]) -> [f64; 2] {
    if t.om == 0.0 {
        top
    } else if t.op == 0.0 {
        bottom
    } else {
        [0.0; 2]
    }
}

/// Builds a turning point from its offset `delta = u - u0`, refining it in the variable
/// 1 - u or 1 + u when it lies closer to the vertical than to u0 (so that the distance to
/// the vertical keeps full relative precision).
#[allow(clippy::too_many_arguments)]
fn turn(
    u0: f64,
    om0: f64,
    op0: f64,
    delta: f64,
    db: f64,
    sb: f64,
    beta: f64,
    a: f64,
    a0: f64,
) -> Turn {
    let mut om = om0 - delta;
    let mut op = op0 + delta;
    if delta > 0.0 && om < delta {
        // f(1 - e) = -db^2 + e (2 D - 2 a db) + e^2 (2 beta - D - a^2) - beta e^3,
        // D = alpha - beta = a0 - beta (1 - u0).
        let d = a0 - beta * om0;
        let q = Poly3([
            -db * db,
            2.0 * d - 2.0 * a * db,
            2.0 * beta - d - a * a,
            -beta,
        ]);
        om = refine(&q, om, om0);
        op = 2.0 - om;
    } else if delta < 0.0 && op < -delta {
        // f(-1 + e) = -sb^2 + e (2 S + 2 a sb) + e^2 (-2 beta - S - a^2) + beta e^3,
        // S = alpha + beta = a0 + beta (1 + u0).
        let s = a0 + beta * op0;
        let q = Poly3([
            -sb * sb,
            2.0 * s + 2.0 * a * sb,
            -2.0 * beta - s - a * a,
            beta,
        ]);
        op = refine(&q, op, op0);
        om = 2.0 - op;
    }
    let u = if u0 + delta >= 0.0 {
        1.0 - om
    } else {
        op - 1.0
    };
    Turn {
        u,
        om: om.max(0.0),
        op: op.max(0.0),
        delta,
    }
}

/// The gyro function in e = 1 - u: f(1 - e) = -db^2 + e (2 D - 2 a db)
/// + e^2 (2 beta - D - a^2) - beta e^3, with D = alpha - beta = a0 - beta (1 - u0).
fn top_poly(db: f64, a: f64, beta: f64, a0: f64, om0: f64) -> Poly3 {
    let d = a0 - beta * om0;
    Poly3([
        -db * db,
        2.0 * d - 2.0 * a * db,
        2.0 * beta - d - a * a,
        -beta,
    ])
}

/// The gyro function in e = 1 + u: f(-1 + e) = -sb^2 + e (2 S + 2 a sb)
/// + e^2 (-2 beta - S - a^2) + beta e^3, with S = alpha + beta = a0 + beta (1 + u0).
fn bottom_poly(sb: f64, a: f64, beta: f64, a0: f64, op0: f64) -> Poly3 {
    let s = a0 + beta * op0;
    Poly3([
        -sb * sb,
        2.0 * s + 2.0 * a * sb,
        -2.0 * beta - s - a * a,
        beta,
    ])
}

/// Refines a root `e` in [0, e_max] of `q` (q(0) <= 0 <= q(e_max)) near the guess.
fn refine(q: &Poly3, guess: f64, e_max: f64) -> f64 {
    if q.eval(0.0) == 0.0 && guess <= 4.0 * f64::EPSILON {
        return 0.0;
    }
    let width = 64.0 * f64::EPSILON * e_max.max(1e-300);
    let lo = (guess - width).max(0.0);
    let hi = (guess + width).min(e_max);
    let (qa, qb) = (q.eval(lo), q.eval(hi));
    if qa <= 0.0 && qb >= 0.0 {
        q.root_in(lo, hi)
    } else if q.eval(0.0) <= 0.0 && q.eval(e_max) >= 0.0 {
        q.root_in(0.0, e_max)
    } else {
        guess
    }
}

impl LagrangeExact {
    /// Evaluates at many times, in parallel over the machine's cores for long inputs.
    /// Returns (theta, phi, psi, theta_dot, phi_dot, psi_dot), each as long as `t`.
    pub fn eval_many(&self, t: &[f64]) -> Result<[Vec<f64>; 6]> {
        let mut out: [Vec<f64>; 6] = std::array::from_fn(|_| vec![0.0; t.len()]);
        let [a, b, c, d, e, f] = &mut out;
        self.eval_par_into(t, [a, b, c, d, e, f])?;
        Ok(out)
    }

    /// Like [`LagrangeExact::eval_into`] but every time by direct evaluation of the elliptic
    /// functions (slow; for checks).
    pub fn eval_direct_into(&self, t: &[f64], out: [&mut [f64]; 6]) -> Result<()> {
        Self::each(out, t, |ti| self.at_direct(ti))
    }

    /// [`LagrangeExact::eval_into`] spread over the machine's cores in chunks.
    pub fn eval_par_into(&self, t: &[f64], out: [&mut [f64]; 6]) -> Result<()> {
        use rayon::prelude::*;
        const CHUNK: usize = 16_384;
        let [a, b, c, d, e, f] = out;
        a.par_chunks_mut(CHUNK)
            .zip(b.par_chunks_mut(CHUNK))
            .zip(c.par_chunks_mut(CHUNK))
            .zip(d.par_chunks_mut(CHUNK))
            .zip(e.par_chunks_mut(CHUNK))
            .zip(f.par_chunks_mut(CHUNK))
            .zip(t.par_chunks(CHUNK))
            .try_for_each(|((((((a, b), c), d), e), f), t)| self.eval_into(t, [a, b, c, d, e, f]))
    }
}
