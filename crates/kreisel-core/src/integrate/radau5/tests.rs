//! Tests of RADAU5: the tableau, stiff reference problems, orders, dense output, the
//! driver contract shared with DOP853, and a measured comparison with DOP853.

use std::cell::Cell;
use std::ops::ControlFlow;
use std::time::Instant;

use super::*;
use crate::integrate::{Dop853, EveryStep, FnObserver, FnSystem, NullObserver, SampleAt};

fn slope(hs: &[f64], errs: &[f64]) -> f64 {
    // Least-squares slope of log(err) against log(h).
    let n = hs.len() as f64;
    let xs: Vec<f64> = hs.iter().map(|h| h.ln()).collect();
    let ys: Vec<f64> = errs.iter().map(|e| e.ln()).collect();
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

fn fmt_e(v: &[f64]) -> String {
    let parts: Vec<String> = v.iter().map(|x| format!("{x:.2e}")).collect();
    format!("[{}]", parts.join(", "))
}

// ---------------------------------------------------------------- the tableau

#[test]
fn radau5_tableau_transformation_and_error_weights() {
    let tab = Tableau::new();
    let s6 = 6f64.sqrt();
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
    // Collocation conditions: Σ_j a_ij c_j^(k-1) = c_i^k / k, k = 1..3.
    for i in 0..3 {
        for k in 1..=3 {
            let s: f64 = (0..3).map(|j| a[i][j] * tab.c[j].powi(k - 1)).sum();
            assert!((s - tab.c[i].powi(k) / k as f64).abs() < 1e-15, "{i} {k}");
        }
    }
    // T⁻¹ A⁻¹ T = diag(γ, [[α, -β], [β, α]]).
    let ai = inv3(&a);
    let mut m = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            m[i][j] = (0..3)
                .map(|k| {
                    (0..3)
                        .map(|l| tab.ti[i][k] * ai[k][l] * tab.t[l][j])
                        .sum::<f64>()
                })
                .sum();
        }
    }
    let want = [
        [tab.gamma, 0.0, 0.0],
        [0.0, tab.alpha, -tab.beta],
        [0.0, tab.beta, tab.alpha],
    ];
    for i in 0..3 {
        for j in 0..3 {
            assert!((m[i][j] - want[i][j]).abs() < 1e-12, "{m:?}");
        }
    }
    assert!((tab.gamma - 3.637834252744496).abs() < 1e-14);
    assert!((tab.alpha - 2.681082873627752).abs() < 1e-14);
    assert!((tab.beta - 3.050430199247411).abs() < 1e-14);
    // The closed forms of the error weights e_i / γ0 (Sec. IV.8).
    let dd = [
        (-13.0 - 7.0 * s6) / 3.0,
        (-13.0 + 7.0 * s6) / 3.0,
        -1.0 / 3.0,
    ];
    for i in 0..3 {
        assert!((tab.dd[i] - dd[i]).abs() < 1e-12, "{:?} {dd:?}", tab.dd);
    }
}

#[test]
fn radau5_lu_solves_real_and_complex_systems() {
    let mut lu = Lu::<C64, 3>::new();
    let m = [
        [C64::new(0.0, 1.0), C64::new(2.0, 0.0), C64::new(1.0, -1.0)],
        [C64::new(3.0, 0.0), C64::new(0.0, 0.0), C64::new(1.0, 2.0)],
        [C64::new(1.0, 1.0), C64::new(-1.0, 0.5), C64::new(4.0, 0.0)],
    ];
    lu.a = m;
    assert!(lu.factor());
    let x = [C64::new(1.0, -2.0), C64::new(0.5, 0.0), C64::new(-1.0, 3.0)];
    let mut b = [C64::default(); 3];
    for i in 0..3 {
        for j in 0..3 {
            b[i] = b[i] + m[i][j] * x[j];
        }
    }
    lu.solve(&mut b);
    for i in 0..3 {
        assert!((b[i] - x[i]).mag() < 1e-14, "{b:?}");
    }
    let mut lr = Lu::<f64, 2>::new();
    lr.a = [[1.0, 2.0], [2.0, 4.0]];
    assert!(!lr.factor(), "a singular matrix is reported");
}

// ---------------------------------------------------------------- stiff problems

/// Van der Pol `y1' = y2`, `y2' = mu (1 - y1^2) y2 - y1`.
fn vdp_mu(mu: f64) -> impl Fn(f64, &[f64; 2], &mut [f64; 2]) {
    move |_t, y, dy| {
        dy[0] = y[1];
        dy[1] = mu * (1.0 - y[0] * y[0]) * y[1] - y[0];
    }
}

#[test]
fn radau5_van_der_pol_mu_1e3_over_a_period() {
    let sys = FnSystem(vdp_mu(1e3));
    // The period of the relaxation oscillation is about (3 - 2 ln 2) mu = 1613.7 (plus
    // O(mu^(-1/3))): the samples lie on the slow branches, after the jumps at about 807 and
    // 1614 (near a jump the phase error of any run is amplified by the jump's slope).
    let times = [400.0, 1200.0, 1800.0];
    let y0 = [2.0, 0.0];
    let mut r = SampleAt::new(&times);
    let (_, _, sr) = Radau5::new(1e-12, 1e-12)
        .integrate(&sys, 0.0, y0, 1800.0, &mut r)
        .unwrap();
    for tol in [1e-6, 1e-8] {
        let mut s = SampleAt::new(&times);
        let (_, _, st) = Radau5::new(tol, tol)
            .integrate(&sys, 0.0, y0, 1800.0, &mut s)
            .unwrap();
        let errs: Vec<f64> = (0..3).map(|k| (s.out[k][0] - r.out[k][0]).abs()).collect();
        println!(
            "radau5 VdP mu=1e3 rtol {tol:e}: {} steps, {} rejected, {} f, {} J, {} LU; |y1 err| at {times:?} = {} (reference rtol 1e-12: {} steps)",
            st.steps, st.rejected, st.rhs_evals, st.jacobians, st.lu_decomps, fmt_e(&errs), sr.steps
        );
        // The global error grows through the jumps: a few tens of times the tolerance.
        for e in &errs {
            assert!(*e < 100.0 * tol, "{errs:?}");
        }
        assert!(st.steps < 2000, "{st:?}");
    }
    // The oscillation: a jump from y1 ≈ -2 back to y1 ≈ 2 within the period.
    assert!(r.out[1][0] < -1.0 && r.out[2][0] > 1.5, "{:?}", r.out);
}

/// Van der Pol in the scaled form of Hairer & Wanner II (Sec. IV.10, problem VDPOL):
/// `y1' = y2`, `y2' = ((1 - y1^2) y2 - y1) / eps`.
fn vdp_eps(eps: f64) -> impl Fn(f64, &[f64; 2], &mut [f64; 2]) {
    move |_t, y, dy| {
        dy[0] = y[1];
        dy[1] = ((1.0 - y[0] * y[0]) * y[1] - y[0]) / eps;
    }
}

#[test]
fn radau5_van_der_pol_eps_1e6_against_reference() {
    // Reference y(2) for eps = 1e-6, y(0) = (2, 0): the published reference solution of
    // problem VDPOL (F. Mazzia, C. Magherini, *Test Set for Initial Value Problem Solvers*,
    // Univ. of Bari, release 2.4, 2008), y1 = 1.706167732170483, y2 = -0.8928097010248125.
    // Confirmed by a one-off run of SciPy 1.17.1's `solve_ivp(method="Radau",
    // rtol=atol=1e-13, jac=exact)`: 1.706167732170492, -0.8928097010247877 (2.5e-14 off).
    // (With y(0) = (2, -0.66), the other initial value in use, SciPy gives
    // 1.7061674375431706, -0.8928100165511259: 3e-7 away, so the pairing matters.)
    const REF: [f64; 2] = [1.706167732170483, -0.8928097010248125];
    let sys = FnSystem(vdp_eps(1e-6));
    let mut last = f64::INFINITY;
    for tol in [1e-4, 1e-6, 1e-8, 1e-10] {
        let (_, y, st) = Radau5::new(tol, tol)
            .integrate(&sys, 0.0, [2.0, 0.0], 2.0, &mut NullObserver)
            .unwrap();
        let err = (y[0] - REF[0]).abs().max((y[1] - REF[1]).abs());
        println!(
            "radau5 VdP eps=1e-6 tol {tol:e}: y(2) = {y:?}, err {err:.2e}, {} steps, {} rejected, {} f, {} J, {} LU",
            st.steps, st.rejected, st.rhs_evals, st.jacobians, st.lu_decomps
        );
        assert!(err < 20.0 * tol, "tol {tol}: err {err}");
        assert!(err < last.max(1e-11));
        last = err;
    }
}

/// Robertson's chemical kinetics (Hairer & Wanner II, Sec. IV.1 and IV.10, problem ROBER).
fn robertson(_t: f64, y: &[f64; 3], dy: &mut [f64; 3]) {
    dy[0] = -0.04 * y[0] + 1e4 * y[1] * y[2];
    dy[2] = 3e7 * y[1] * y[1];
    dy[1] = -dy[0] - dy[2];
}

#[test]
fn radau5_robertson_to_1e5() {
    // y(40) = (0.7158270687193, 0.9185534764529e-5, ...), the reference values quoted with
    // Hairer & Wanner II's ROBER; confirmed by a one-off run of SciPy 1.17.1's Radau at
    // rtol 1e-13, atol 1e-19: 0.7158270687194032, 9.185534764557798e-6 (1e-13 and 3e-12
    // relative).
    const Y40: [f64; 2] = [0.715_827_068_719_3, 0.918_553_476_452_9e-5];
    let sys = FnSystem(robertson);
    let times = [40.0, 1e5];
    let mut s = SampleAt::new(&times);
    let (t, y, st) = Radau5::new(1e-8, 1e-14)
        .integrate(&sys, 0.0, [1.0, 0.0, 0.0], 1e5, &mut s)
        .unwrap();
    assert_eq!(t, 1e5);
    let e1 = (s.out[0][0] - Y40[0]).abs() / Y40[0];
    let e2 = (s.out[0][1] - Y40[1]).abs() / Y40[1];
    let mass = (y[0] + y[1] + y[2] - 1.0).abs();
    println!(
        "radau5 Robertson rtol 1e-8: y(40) = {:?}, rel err y1 {e1:.1e} y2 {e2:.1e}; y(1e5) = {y:?}, |mass - 1| = {mass:.1e}; {} steps, {} rejected, {} f, {} J, {} LU",
        s.out[0], st.steps, st.rejected, st.rhs_evals, st.jacobians, st.lu_decomps
    );
    assert!(e1 < 1e-7 && e2 < 1e-6, "{e1} {e2}");
    assert!(mass < 1e-10, "{mass}");
    assert!(st.steps < 300, "{st:?}");
}

// ---------------------------------------------------------------- orders

fn oscillator(_t: f64, y: &[f64; 2], dy: &mut [f64; 2]) {
    dy[0] = y[1];
    dy[1] = -y[0];
}

#[test]
fn radau5_fixed_step_order_is_5() {
    let sys = FnSystem(oscillator);
    let t_end = 10.0;
    let ns = [20u64, 40, 80, 160];
    let (mut hs, mut errs) = (vec![], vec![]);
    for &n in &ns {
        let (t, y, st) = Radau5::new(1e-14, 1e-14)
            .integrate_fixed(&sys, 0.0, [1.0, 0.0], t_end, n, &mut NullObserver)
            .unwrap();
        assert_eq!(t, t_end);
        assert_eq!(st.steps, n);
        hs.push(t_end / n as f64);
        errs.push((y[0] - t_end.cos()).abs().max((y[1] + t_end.sin()).abs()));
    }
    let p = slope(&hs, &errs);
    println!(
        "radau5 fixed steps, oscillator: h = {hs:?}, err = {}, order {p:.3}",
        fmt_e(&errs)
    );
    assert!((4.6..=5.4).contains(&p), "order {p}");

    // Nonlinear: Kepler, e = 0.5, one period.
    let kepler = FnSystem(|_t: f64, y: &[f64; 4], dy: &mut [f64; 4]| {
        let r3 = (y[0] * y[0] + y[1] * y[1]).powf(1.5);
        *dy = [y[2], y[3], -y[0] / r3, -y[1] / r3];
    });
    let e: f64 = 0.5;
    let y0 = [1.0 - e, 0.0, 0.0, ((1.0 + e) / (1.0 - e)).sqrt()];
    let tp = 2.0 * std::f64::consts::PI;
    let (mut hs, mut errs) = (vec![], vec![]);
    for n in [50u64, 100, 200, 400] {
        let (_, y, _) = Radau5::new(1e-12, 1e-12)
            .integrate_fixed(&kepler, 0.0, y0, tp, n, &mut NullObserver)
            .unwrap();
        hs.push(tp / n as f64);
        errs.push((0..4).map(|i| (y[i] - y0[i]).abs()).fold(0.0, f64::max));
    }
    let p = slope(&hs, &errs);
    println!(
        "radau5 fixed steps, Kepler e=0.5: h = {hs:.4?}, err = {}, order {p:.3}",
        fmt_e(&errs)
    );
    assert!((4.6..=5.4).contains(&p), "order {p}");
}

#[test]
fn radau5_dense_output_order() {
    // y' = A y with a rotation and a decay: y = e^{-t/4} (cos t, -sin t).
    let sys = FnSystem(|_t: f64, y: &[f64; 2], dy: &mut [f64; 2]| {
        dy[0] = -0.25 * y[0] + y[1];
        dy[1] = -y[0] - 0.25 * y[1];
    });
    let exact = |t: f64| [(-0.25 * t).exp() * t.cos(), -(-0.25 * t).exp() * t.sin()];
    let t_end = 6.0;
    let (mut hs, mut errs) = (vec![], vec![]);
    for n in [12u64, 24, 48, 96] {
        let mut worst = 0.0f64;
        let mut obs = FnObserver(|t: f64, y: &[f64; 2], d: &dyn Dense<2>| {
            assert_eq!(d.t1(), t);
            let mut v = [0.0; 2];
            d.eval(d.t1(), &mut v);
            assert_eq!(&v, y, "exact at the step end");
            for k in 1..8 {
                let ts = d.t0() + (d.t1() - d.t0()) * k as f64 / 8.0;
                d.eval(ts, &mut v);
                let ex = exact(ts);
                worst = worst.max((v[0] - ex[0]).abs().max((v[1] - ex[1]).abs()));
            }
            ControlFlow::Continue(())
        });
        Radau5::new(1e-14, 1e-14)
            .integrate_fixed(&sys, 0.0, [1.0, 0.0], t_end, n, &mut obs)
            .unwrap();
        hs.push(t_end / n as f64);
        errs.push(worst);
    }
    let p = slope(&hs, &errs);
    println!(
        "radau5 dense output inside fixed steps: h = {hs:?}, max err = {}, order {p:.3}",
        fmt_e(&errs)
    );
    assert!(p > 3.5, "dense order {p}");

    // Adaptive: samples from the dense output at the tolerance.
    let times: Vec<f64> = (0..=60).map(|k| 0.1 * k as f64).collect();
    let mut s = SampleAt::new(&times);
    Radau5::new(1e-8, 1e-10)
        .integrate(&sys, 0.0, [1.0, 0.0], t_end, &mut s)
        .unwrap();
    let worst = times
        .iter()
        .zip(&s.out)
        .map(|(&t, v)| (v[0] - exact(t)[0]).abs().max((v[1] - exact(t)[1]).abs()))
        .fold(0.0, f64::max);
    println!("radau5 adaptive rtol 1e-8: dense samples max err {worst:.2e}");
    assert!(worst < 1e-7, "{worst}");
}

// ---------------------------------------------------------------- stiff linear

/// `y' = A y` with `A = V diag(-1e4, -1) V⁻¹`, `V = [[2, 1], [1, 1]]`.
struct StiffLinear {
    analytic: bool,
}

const L1: f64 = -1e4;
const L2: f64 = -1.0;
const STIFF_A: [[f64; 2]; 2] = [
    [2.0 * L1 - L2, -2.0 * L1 + 2.0 * L2],
    [L1 - L2, -L1 + 2.0 * L2],
];

impl OdeSystem<2> for StiffLinear {
    fn rhs(&self, _t: f64, y: &[f64; 2], dy: &mut [f64; 2]) {
        for i in 0..2 {
            dy[i] = STIFF_A[i][0] * y[0] + STIFF_A[i][1] * y[1];
        }
    }
    fn jacobian(&self, _t: f64, _y: &[f64; 2], jac: &mut [[f64; 2]; 2]) -> bool {
        *jac = STIFF_A;
        self.analytic
    }
}

fn stiff_exact(t: f64) -> [f64; 2] {
    // y(0) = (1, 0): V⁻¹ y0 = (1, -1).
    let (a, b) = ((L1 * t).exp(), (L2 * t).exp());
    [2.0 * a - b, a - b]
}

#[test]
fn radau5_stiff_linear_far_fewer_steps_than_dop853() {
    let (rtol, atol) = (1e-6, 1e-10);
    let t_end = 10.0;
    let mut rec = EveryStep::new();
    let (_, y, st) = Radau5::new(rtol, atol)
        .integrate(
            &StiffLinear { analytic: false },
            0.0,
            [1.0, 0.0],
            t_end,
            &mut rec,
        )
        .unwrap();
    let (_, yd, sd) = Dop853::new(rtol, atol)
        .integrate(
            &StiffLinear { analytic: false },
            0.0,
            [1.0, 0.0],
            t_end,
            &mut NullObserver,
        )
        .unwrap();
    let ex = stiff_exact(t_end);
    let err = (0..2)
        .map(|i| (y[i] - ex[i]).abs() / ex[i].abs())
        .fold(0.0, f64::max);
    let errd = (0..2)
        .map(|i| (yd[i] - ex[i]).abs() / ex[i].abs())
        .fold(0.0, f64::max);
    // The error along the way, relative to the slow solution's size.
    let worst = rec
        .ts
        .iter()
        .zip(&rec.ys)
        .skip(1)
        .map(|(&t, v)| {
            let e = stiff_exact(t);
            (0..2).map(|i| (v[i] - e[i]).abs()).fold(0.0, f64::max) / (L2 * t).exp()
        })
        .fold(0.0, f64::max);
    println!(
        "stiff 2x2 (-1e4, -1), rtol 1e-6: radau5 {} steps ({} rejected, {} f, {} J, {} LU), rel err {err:.1e}, worst along the way {worst:.1e}; dop853 {} steps ({} rejected, {} f), rel err {errd:.1e}",
        st.steps, st.rejected, st.rhs_evals, st.jacobians, st.lu_decomps, sd.steps, sd.rejected, sd.rhs_evals
    );
    assert!(err < 10.0 * rtol && worst < 10.0 * rtol, "{err} {worst}");
    assert!(st.steps * 20 < sd.steps, "{} vs {}", st.steps, sd.steps);
    assert!(st.steps < 100, "{st:?}");

    // The counter counts every evaluation of f (the finite-difference Jacobian's too), and
    // an analytic Jacobian spares those.
    for analytic in [false, true] {
        let calls = Cell::new(0u64);
        let sys = Counted(StiffLinear { analytic }, &calls);
        let (_, ya, sa) = Radau5::new(rtol, atol)
            .integrate(&sys, 0.0, [1.0, 0.0], t_end, &mut NullObserver)
            .unwrap();
        assert_eq!(sa.rhs_evals, calls.get(), "{sa:?}");
        if analytic {
            assert!(sa.rhs_evals < st.rhs_evals, "{sa:?} {st:?}");
            let err = (0..2)
                .map(|i| (ya[i] - ex[i]).abs() / ex[i].abs())
                .fold(0.0, f64::max);
            assert!(err < 10.0 * rtol, "{err}");
        } else {
            assert_eq!(sa, st);
        }
    }
}

/// A system that counts its evaluations of `f`.
struct Counted<'a, S>(S, &'a Cell<u64>);

impl<S: OdeSystem<2>> OdeSystem<2> for Counted<'_, S> {
    fn rhs(&self, t: f64, y: &[f64; 2], dy: &mut [f64; 2]) {
        self.1.set(self.1.get() + 1);
        self.0.rhs(t, y, dy)
    }
    fn jacobian(&self, t: f64, y: &[f64; 2], jac: &mut [[f64; 2]; 2]) -> bool {
        self.0.jacobian(t, y, jac)
    }
}

// ---------------------------------------------------------------- driver contract

/// Rotation in the plane, projected back to the unit circle after each step.
struct ProjectedRotation;

impl OdeSystem<2> for ProjectedRotation {
    fn rhs(&self, _t: f64, y: &[f64; 2], dy: &mut [f64; 2]) {
        dy[0] = -y[1];
        dy[1] = y[0];
    }
    fn project(&self, y: &mut [f64; 2]) {
        let r = (y[0] * y[0] + y[1] * y[1]).sqrt();
        y[0] /= r;
        y[1] /= r;
    }
}

#[test]
fn radau5_projection_is_applied_to_every_accepted_state() {
    let mut n = 0;
    let mut check = FnObserver(|t: f64, y: &[f64; 2], dense: &dyn Dense<2>| {
        n += 1;
        assert!(((y[0] * y[0] + y[1] * y[1]).sqrt() - 1.0).abs() < 4e-16);
        let mut ye = [0.0; 2];
        dense.eval(t, &mut ye);
        assert_eq!(&ye, y);
        ControlFlow::Continue(())
    });
    let (_, y, st) = Radau5::new(1e-3, 1e-3)
        .integrate(&ProjectedRotation, 0.0, [1.0, 0.0], 10.0, &mut check)
        .unwrap();
    assert!((y[0] - 10f64.cos()).abs() < 1e-2);
    assert_eq!(n, st.steps);
    // Without the projection the radius drifts (Radau IIA is dissipative): so the
    // projection was what kept it at 1.
    let free = FnSystem(|_t: f64, y: &[f64; 2], dy: &mut [f64; 2]| {
        dy[0] = -y[1];
        dy[1] = y[0];
    });
    let (_, y, _) = Radau5::new(1e-3, 1e-3)
        .integrate(&free, 0.0, [1.0, 0.0], 10.0, &mut NullObserver)
        .unwrap();
    assert!(((y[0] * y[0] + y[1] * y[1]).sqrt() - 1.0).abs() > 1e-12);
}

#[test]
fn radau5_observer_break_stops_at_step_end_and_stop_point() {
    let sys = FnSystem(oscillator);
    let mut ends = vec![];
    let mut obs = FnObserver(|t: f64, _y: &[f64; 2], _d: &dyn Dense<2>| {
        ends.push(t);
        if ends.len() == 3 {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    });
    let (t, _, stats) = Radau5::new(1e-6, 1e-6)
        .integrate(&sys, 0.0, [1.0, 0.0], 100.0, &mut obs)
        .unwrap();
    assert_eq!(stats.steps, 3);
    assert_eq!(t, ends[2]);

    /// Breaks inside the second step, at its midpoint.
    struct MidStop(usize, Option<(f64, [f64; 2])>);
    impl Observer<2> for MidStop {
        fn step(&mut self, _t: f64, _y: &[f64; 2], d: &dyn Dense<2>) -> ControlFlow<()> {
            self.0 += 1;
            if self.0 == 2 {
                let tm = 0.5 * (d.t0() + d.t1());
                let mut v = [0.0; 2];
                d.eval(tm, &mut v);
                self.1 = Some((tm, v));
                return ControlFlow::Break(());
            }
            ControlFlow::Continue(())
        }
        fn stop_point(&self) -> Option<(f64, [f64; 2])> {
            self.1
        }
    }
    let mut mid = MidStop(0, None);
    let (t, y, stats) = Radau5::new(1e-8, 1e-8)
        .integrate(&sys, 0.0, [1.0, 0.0], 100.0, &mut mid)
        .unwrap();
    assert_eq!(stats.steps, 2);
    assert_eq!(Some((t, y)), mid.1);
    assert!((y[0] - t.cos()).abs() < 1e-6);
}

#[test]
fn radau5_errors_and_limits() {
    let always_nan = FnSystem(|_t: f64, _y: &[f64; 2], dy: &mut [f64; 2]| {
        *dy = [f64::NAN, 0.0];
    });
    let r = Radau5::default().integrate(&always_nan, 0.0, [1.0, 0.0], 1.0, &mut NullObserver);
    assert_eq!(r.unwrap_err(), IntegrateError::NonFinite { t: 0.0 });
    // Finite up to t = 1, NaN after: the step shrinks towards t = 1, then gives up.
    let nan_after_1 = FnSystem(|t: f64, y: &[f64; 2], dy: &mut [f64; 2]| {
        dy[0] = if t > 1.0 { f64::NAN } else { y[1] };
        dy[1] = -y[0];
    });
    match Radau5::default().integrate(&nan_after_1, 0.0, [1.0, 0.0], 3.0, &mut NullObserver) {
        Err(IntegrateError::NonFinite { t }) => assert!((t - 1.0).abs() < 1e-8 && t <= 1.0, "{t}"),
        other => panic!("{other:?}"),
    }
    // Zero-length interval.
    let mut rec = EveryStep::new();
    let (t, y, st) = Radau5::default()
        .integrate(&FnSystem(oscillator), 2.0, [1.0, 0.0], 2.0, &mut rec)
        .unwrap();
    assert_eq!((t, y, st), (2.0, [1.0, 0.0], Stats::default()));
    assert_eq!(rec.ts, vec![2.0]);
    // max_steps.
    let r = Radau5 {
        max_steps: 10,
        ..Radau5::new(1e-10, 1e-10)
    }
    .integrate(
        &FnSystem(oscillator),
        0.0,
        [1.0, 0.0],
        100.0,
        &mut NullObserver,
    );
    match r {
        Err(IntegrateError::TooManySteps { steps, .. }) => assert_eq!(steps, 10),
        other => panic!("{other:?}"),
    }
    // Blow-up of y' = y^2 at t = 1.
    let blow = FnSystem(|_t: f64, y: &[f64; 1], dy: &mut [f64; 1]| dy[0] = y[0] * y[0]);
    match Radau5::new(1e-8, 1e-8).integrate(&blow, 0.0, [1.0], 2.0, &mut NullObserver) {
        Err(IntegrateError::StepSizeTooSmall { t, .. }) | Err(IntegrateError::NonFinite { t }) => {
            assert!((t - 1.0).abs() < 1e-4, "{t}")
        }
        other => panic!("{other:?}"),
    }
    // h_max is honoured and the run lands on t_end.
    let mut rec = EveryStep::new();
    let (t, _, _) = Radau5 {
        h_max: 0.1,
        ..Radau5::new(1e-3, 1e-3)
    }
    .integrate(&FnSystem(oscillator), 0.0, [1.0, 0.0], 1.05, &mut rec)
    .unwrap();
    assert_eq!(t, 1.05);
    assert!(
        rec.ts.windows(2).all(|w| w[1] - w[0] <= 0.1 + 1e-15),
        "{:?}",
        rec.ts
    );
}

// ---------------------------------------------------------------- measured comparison

/// A 14-dimensional stiff model shaped like the play top in a sliding phase: a rigid body
/// (quaternion, body angular velocity) spinning at about 13 rad/s, its centre moving on the
/// floor, two tangential slip components relaxing to the contact-point velocity at
/// -1500 /s, Coulomb friction from the slip (regularised) acting on the body, and the
/// dissipated energy as a quadrature.
///
/// State: `q (4), ω (3), x, y, vx, vy, s1, s2, E`.
struct SlipTop;

const I_BODY: [f64; 3] = [1.0, 1.3, 1.7];
const RADIUS: f64 = 0.5;
const MU_G: f64 = 0.3 * 9.81;
const RELAX: f64 = 1500.0;

impl OdeSystem<14> for SlipTop {
    fn rhs(&self, _t: f64, y: &[f64; 14], dy: &mut [f64; 14]) {
        let q = [y[0], y[1], y[2], y[3]];
        let w = [y[4], y[5], y[6]];
        // q' = q ⊗ (0, ω) / 2.
        dy[0] = 0.5 * (-q[1] * w[0] - q[2] * w[1] - q[3] * w[2]);
        dy[1] = 0.5 * (q[0] * w[0] + q[2] * w[2] - q[3] * w[1]);
        dy[2] = 0.5 * (q[0] * w[1] + q[3] * w[0] - q[1] * w[2]);
        dy[3] = 0.5 * (q[0] * w[2] + q[1] * w[1] - q[2] * w[0]);
        // Rotation matrix body -> world.
        let (a, b, c, d) = (q[0], q[1], q[2], q[3]);
        let r = [
            [
                a * a + b * b - c * c - d * d,
                2.0 * (b * c - a * d),
                2.0 * (b * d + a * c),
            ],
            [
                2.0 * (b * c + a * d),
                a * a - b * b + c * c - d * d,
                2.0 * (c * d - a * b),
            ],
            [
                2.0 * (b * d - a * c),
                2.0 * (c * d + a * b),
                a * a - b * b - c * c + d * d,
            ],
        ];
        let mut ww = [0.0; 3];
        for i in 0..3 {
            ww[i] = r[i][0] * w[0] + r[i][1] * w[1] + r[i][2] * w[2];
        }
        // Contact point at -R e_z (world): its velocity v + ω × (-R e_z).
        let target = [y[9] - RADIUS * ww[1], y[10] + RADIUS * ww[0]];
        let s = [y[11], y[12]];
        let sn = (s[0] * s[0] + s[1] * s[1] + 1e-4).sqrt();
        let f = [-MU_G * s[0] / sn, -MU_G * s[1] / sn];
        // Torque of the friction force at the contact arm, in body axes.
        let tw = [RADIUS * f[1], -RADIUS * f[0], 0.0];
        let mut tb = [0.0; 3];
        for i in 0..3 {
            tb[i] = r[0][i] * tw[0] + r[1][i] * tw[1] + r[2][i] * tw[2];
        }
        let [i1, i2, i3] = I_BODY;
        dy[4] = ((i2 - i3) * w[1] * w[2] + tb[0]) / i1;
        dy[5] = ((i3 - i1) * w[2] * w[0] + tb[1]) / i2;
        dy[6] = ((i1 - i2) * w[0] * w[1] + tb[2]) / i3;
        dy[7] = y[9];
        dy[8] = y[10];
        dy[9] = f[0];
        dy[10] = f[1];
        dy[11] = -RELAX * (s[0] - target[0]);
        dy[12] = -RELAX * (s[1] - target[1]);
        dy[13] = -(f[0] * s[0] + f[1] * s[1]);
    }
    fn project(&self, y: &mut [f64; 14]) {
        let n = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3]).sqrt();
        for v in &mut y[..4] {
            *v /= n;
        }
    }
}

#[test]
fn radau5_vs_dop853_on_a_stiff_14_dim_top() {
    let (rtol, atol, t_end) = (1e-8, 1e-10, 4.5);
    let mut y0 = [0.0; 14];
    let h = 0.1f64; // tilt of the body's axis
    y0[0] = (0.5 * h).cos();
    y0[1] = (0.5 * h).sin();
    y0[4] = 0.3;
    y0[5] = 0.2;
    y0[6] = 13.0;
    y0[9] = 0.4;
    let sys = SlipTop;
    // Wall time: the fastest of 5 runs (the machine is shared).
    let clock = |f: &mut dyn FnMut() -> ([f64; 14], Stats)| {
        let mut best = f64::INFINITY;
        let mut out = ([0.0; 14], Stats::default());
        for _ in 0..5 {
            let start = Instant::now();
            out = f();
            best = best.min(start.elapsed().as_secs_f64());
        }
        (out.0, out.1, best)
    };
    let (yr, sr, tr) = clock(&mut || {
        let (_, y, s) = Radau5::new(rtol, atol)
            .integrate(&sys, 0.0, y0, t_end, &mut NullObserver)
            .unwrap();
        (y, s)
    });
    let (yr2, sr2, tr2) = clock(&mut || {
        let (_, y, s) = Radau5 {
            theta_jac: 0.1,
            ..Radau5::new(rtol, atol)
        }
        .integrate(&sys, 0.0, y0, t_end, &mut NullObserver)
        .unwrap();
        (y, s)
    });
    let (yd, sd, td) = clock(&mut || {
        let (_, y, s) = Dop853::new(rtol, atol)
            .integrate(&sys, 0.0, y0, t_end, &mut NullObserver)
            .unwrap();
        (y, s)
    });
    let (yref, _, _) = clock(&mut || {
        let (_, y, s) = Dop853::new(1e-13, 1e-15)
            .integrate(&sys, 0.0, y0, t_end, &mut NullObserver)
            .unwrap();
        (y, s)
    });
    let dev = |y: &[f64; 14]| (0..14).map(|i| (y[i] - yref[i]).abs()).fold(0.0, f64::max);
    println!("14-dim stiff top (slip relaxing at -1500/s, spin 13 rad/s), rtol {rtol:e}, atol {atol:e}, t_end {t_end}:");
    for (name, s, t, y) in [
        ("radau5 (theta_jac 0.001)", sr, tr, yr),
        ("radau5 (theta_jac 0.1)  ", sr2, tr2, yr2),
        ("dop853                  ", sd, td, yd),
    ] {
        println!(
            "  {name}: {:5} steps {:4} rejected {:7} f {:5} J {:5} LU  {:8.3} ms  max |y - y_ref| {:.1e}",
            s.steps,
            s.rejected,
            s.rhs_evals,
            s.jacobians,
            s.lu_decomps,
            1e3 * t,
            dev(&y)
        );
    }
    assert!(sr.steps * 5 < sd.steps, "{sr:?} vs {sd:?}");
    assert!(
        dev(&yr) < 1e-5 && dev(&yr2) < 1e-5,
        "{} {}",
        dev(&yr),
        dev(&yr2)
    );
}

/// The stiff 2x2 system with two quadratures riding on it, `q0' = y0 + y1` and `q1' = y0`,
/// which no right-hand side reads. Declared passive, Radau IIA factorises the coupled 2x2
/// block only and solves for the quadratures by substitution; undeclared, the full 4x4
/// matrices. Both against the exact integrals of `stiff_exact`.
struct WithQuadratures {
    passive: bool,
}

impl OdeSystem<4> for WithQuadratures {
    fn rhs(&self, _t: f64, y: &[f64; 4], dy: &mut [f64; 4]) {
        // The passive components sit between and after the coupled ones (indices 1 and 3), so
        // that the reordering of the matrices is exercised.
        let (u0, u1) = (y[0], y[2]);
        dy[0] = STIFF_A[0][0] * u0 + STIFF_A[0][1] * u1;
        dy[2] = STIFF_A[1][0] * u0 + STIFF_A[1][1] * u1;
        dy[1] = u0 + u1;
        dy[3] = u0;
    }
    fn passive(&self) -> [bool; 4] {
        [false, self.passive, false, self.passive]
    }
}

#[test]
fn radau5_passive_components_are_solved_by_substitution() {
    // Exact: y0 = 2a - b, y1 = a - b (a = e^{L1 t}, b = e^{L2 t}); the integrals from 0 of
    // a and b are (a - 1)/L1 and (b - 1)/L2.
    let exact = |t: f64| {
        let ia = ((L1 * t).exp() - 1.0) / L1;
        let ib = ((L2 * t).exp() - 1.0) / L2;
        let e = stiff_exact(t);
        [e[0], 3.0 * ia - 2.0 * ib, e[1], 2.0 * ia - ib]
    };
    let (rtol, atol) = (1e-8, 1e-12);
    let t_end = 3.0;
    let mut runs = Vec::new();
    for passive in [true, false] {
        let (_, y, st) = Radau5::new(rtol, atol)
            .integrate(
                &WithQuadratures { passive },
                0.0,
                [1.0, 0.0, 0.0, 0.0],
                t_end,
                &mut NullObserver,
            )
            .unwrap();
        let ex = exact(t_end);
        let err = (0..4)
            .map(|i| (y[i] - ex[i]).abs() / ex[i].abs().max(1e-2))
            .fold(0.0, f64::max);
        println!(
            "passive {passive}: {} steps, {} f, rel err {err:.2e}",
            st.steps, st.rhs_evals
        );
        assert!(
            err < 100.0 * rtol,
            "passive {passive}: {y:?} against {ex:?}"
        );
        runs.push((y, st));
    }
    // The same steps: the substitution is the elimination the full factorisation does
    // (with diagonal pivots), up to rounding; the Jacobian skips the passive columns.
    let ((yp, sp), (yf, sf)) = (&runs[0], &runs[1]);
    assert_eq!(sp.steps, sf.steps);
    for i in 0..4 {
        assert!(
            (yp[i] - yf[i]).abs() <= 1e-12 * yf[i].abs().max(1e-2),
            "{yp:?} {yf:?}"
        );
    }
    assert_eq!(sf.rhs_evals - sp.rhs_evals, 2 * sf.jacobians);
}
