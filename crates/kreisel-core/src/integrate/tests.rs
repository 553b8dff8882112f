//! Convergence, accuracy, event and error-handling tests of the integrators.
//!
//! Run with `cargo test --release -- --nocapture` to see the measured orders.

use std::f64::consts::PI;
use std::ops::ControlFlow;

use super::*;

// ---------------------------------------------------------------- problems

/// Kepler two-body problem in the plane, `mu = 1`: `y = [x, y, vx, vy]`.
struct Kepler;

impl OdeSystem<4> for Kepler {
    fn rhs(&self, _t: f64, y: &[f64; 4], dy: &mut [f64; 4]) {
        let r2 = y[0] * y[0] + y[1] * y[1];
        let r3 = r2 * r2.sqrt();
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = -y[0] / r3;
        dy[3] = -y[1] / r3;
    }
}

/// Exact Kepler orbit with semi-major axis 1 and eccentricity `e`, at periapsis at `t = 0`
/// (period `2 pi`, energy `-1/2`).
fn kepler_exact(e: f64, t: f64) -> [f64; 4] {
    let m = t.rem_euclid(2.0 * PI);
    let mut ea = if e > 0.8 { PI } else { m };
    for _ in 0..50 {
        let d = (ea - e * ea.sin() - m) / (1.0 - e * ea.cos());
        ea -= d;
        if d.abs() < 1e-16 {
            break;
        }
    }
    let (s, c) = ea.sin_cos();
    let b = (1.0 - e * e).sqrt();
    let den = 1.0 - e * c;
    [c - e, b * s, -s / den, b * c / den]
}

fn kepler_energy(y: &[f64; 4]) -> f64 {
    0.5 * (y[2] * y[2] + y[3] * y[3]) - 1.0 / (y[0] * y[0] + y[1] * y[1]).sqrt()
}

/// Harmonic oscillator `x'' = -x`, `y = [x, v]`.
struct Oscillator;

impl OdeSystem<2> for Oscillator {
    fn rhs(&self, _t: f64, y: &[f64; 2], dy: &mut [f64; 2]) {
        dy[0] = y[1];
        dy[1] = -y[0];
    }
}

fn max_abs_diff<const N: usize>(a: &[f64; N], b: &[f64; N]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Least-squares slope of `log(err)` against `log(h)`.
fn slope(hs: &[f64], errs: &[f64]) -> f64 {
    let n = hs.len() as f64;
    let xs: Vec<f64> = hs.iter().map(|h| h.ln()).collect();
    let ys: Vec<f64> = errs.iter().map(|e| e.ln()).collect();
    let mx = xs.iter().sum::<f64>() / n;
    let my = ys.iter().sum::<f64>() / n;
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

fn report(name: &str, hs: &[f64], errs: &[f64]) -> f64 {
    let p = slope(hs, errs);
    println!("{name}:");
    for (h, e) in hs.iter().zip(errs) {
        println!("    h = {h:.6e}   err = {e:.3e}");
    }
    println!("    fitted slope = {p:.3}");
    p
}

const E: f64 = 0.5;

// ---------------------------------------------------------------- orders

#[test]
fn rk4_global_order_is_4() {
    let t_end = 2.0 * PI;
    let y0 = kepler_exact(E, 0.0);
    let (mut hs, mut errs) = (vec![], vec![]);
    for n in [200u32, 400, 800, 1600, 3200] {
        let dt = t_end / n as f64;
        let (t, y, stats) = Rk4::new(dt)
            .integrate(&Kepler, 0.0, y0, t_end, &mut NullObserver)
            .unwrap();
        assert_eq!(t, t_end);
        assert_eq!(stats.steps, n as u64);
        hs.push(dt);
        errs.push(max_abs_diff(&y, &kepler_exact(E, t_end)));
    }
    let p = report("RK4 global error, Kepler e=0.5, one period", &hs, &errs);
    assert!((p - 4.0).abs() <= 0.3, "RK4 order {p}");
}

#[test]
fn rk4_dense_output_order_is_3() {
    // One step from the exact state at periapsis; error of the Hermite interpolant at
    // mid-step and the largest error over interior points.
    let y0 = kepler_exact(E, 0.0);
    let (mut hs, mut mid_errs, mut any_errs) = (vec![], vec![], vec![]);
    for k in 0..5 {
        let h = 0.2 / 2f64.powi(k);
        let times = THETAS.map(|th| th * h);
        let mut obs = SampleAt::new(&times);
        Rk4::new(h)
            .integrate(&Kepler, 0.0, y0, h, &mut obs)
            .unwrap();
        let errs: Vec<f64> = times
            .iter()
            .zip(&obs.out)
            .map(|(&t, y)| max_abs_diff(y, &kepler_exact(E, t)))
            .collect();
        hs.push(h);
        mid_errs.push(errs[2]);
        any_errs.push(errs.iter().copied().fold(0.0, f64::max));
    }
    let pm = report(
        "RK4 Hermite dense output, local error at mid-step",
        &hs,
        &mid_errs,
    );
    let pa = report(
        &format!("RK4 Hermite dense output, local error, max over s in {THETAS:?}"),
        &hs,
        &any_errs,
    );
    println!(
        "    => dense-output order {:.3} (mid-step), {:.3} (max over s)",
        pm - 1.0,
        pa - 1.0
    );
    // Local error O(h^{q+1}) with q = 3.
    assert!(
        (pm - 1.0 - 3.0).abs() <= 0.3,
        "Hermite dense order {}",
        pm - 1.0
    );
    assert!(
        (pa - 1.0 - 3.0).abs() <= 0.3,
        "Hermite dense order {}",
        pa - 1.0
    );
}

/// Fixed-step DOP853 via [`Dop853::step`] on the Kepler orbit of eccentricity `e` over
/// `[0, t_end]` with `n` steps; returns the final error and the largest error of the dense
/// output at the mid-steps.
fn dop853_fixed(e: f64, t_end: f64, n: u32) -> (f64, f64) {
    let dop = Dop853::default();
    let h = t_end / n as f64;
    let mut work = Dop853Work::new();
    let mut y = kepler_exact(e, 0.0);
    let mut mid_err: f64 = 0.0;
    for k in 0..n {
        let t = k as f64 * h;
        let (y_new, _err) = dop.step(&Kepler, t, &y, h, &mut work);
        let mut ym = [0.0; 4];
        work.dense(&Kepler).eval(t + 0.5 * h, &mut ym);
        mid_err = mid_err.max(max_abs_diff(&ym, &kepler_exact(e, t + 0.5 * h)));
        y = y_new;
    }
    (max_abs_diff(&y, &kepler_exact(e, t_end)), mid_err)
}

fn dop853_global_case(name: &str, e: f64, t_end: f64, ns: &[u32]) {
    let (mut hs, mut errs, mut mids) = (vec![], vec![], vec![]);
    for &n in ns {
        let (err, mid) = dop853_fixed(e, t_end, n);
        hs.push(t_end / n as f64);
        errs.push(err);
        mids.push(mid);
    }
    let p = report(
        &format!("DOP853 fixed-step global error, {name}"),
        &hs,
        &errs,
    );
    let pm = report(
        &format!("DOP853 fixed-step dense output at mid-steps (max global error), {name}"),
        &hs,
        &mids,
    );
    assert!((p - 8.0).abs() <= 0.5, "DOP853 order {p}");
    // Globally the dense output is as accurate as the steps: order min(8, 7 + 1) = 8.
    assert!((pm - 8.0).abs() <= 0.7, "DOP853 global dense order {pm}");
}

#[test]
fn dop853_global_order_is_8_circular() {
    dop853_global_case(
        "Kepler e=0 (circular), one period",
        0.0,
        2.0 * PI,
        &[10, 14, 20, 28, 40],
    );
}

#[test]
fn dop853_global_order_is_8_eccentric() {
    dop853_global_case(
        "Kepler e=0.5, periapsis to apoapsis",
        0.5,
        PI,
        &[20, 28, 40, 56, 80],
    );
}

/// Interior points (fractions of a step) at which dense outputs are checked besides the
/// mid-step (which alone cannot tell `s` from `1 - s` in the interpolation formula).
const THETAS: [f64; 5] = [0.2, 0.35, 0.5, 0.65, 0.8];

/// One step of size `h` from the exact state at `t0`: local error of the step (`O(h^9)`,
/// order 8) and of the dense output at mid-step and at other interior points (`O(h^8)`,
/// order 7).
fn dop853_local_case(name: &str, e: f64, t0: f64, hs: &[f64]) {
    let dop = Dop853::default();
    let y0 = kepler_exact(e, t0);
    let (mut step_errs, mut mid_errs, mut any_errs) = (vec![], vec![], vec![]);
    let mut work = Dop853Work::new();
    for &h in hs {
        let (y1, _) = dop.step(&Kepler, t0, &y0, h, &mut work);
        step_errs.push(max_abs_diff(&y1, &kepler_exact(e, t0 + h)));
        let mut worst: f64 = 0.0;
        for th in THETAS {
            let mut ym = [0.0; 4];
            work.dense(&Kepler).eval(t0 + th * h, &mut ym);
            let err = max_abs_diff(&ym, &kepler_exact(e, t0 + th * h));
            if th == 0.5 {
                mid_errs.push(err);
            }
            worst = worst.max(err);
        }
        any_errs.push(worst);
    }
    let ps = report(
        &format!("DOP853 local error of one step, {name}"),
        hs,
        &step_errs,
    );
    let pd = report(
        &format!("DOP853 local error of the dense output at mid-step, {name}"),
        hs,
        &mid_errs,
    );
    let pa = report(
        &format!("DOP853 local error of the dense output, max over s in {THETAS:?}, {name}"),
        hs,
        &any_errs,
    );
    println!(
        "    => step order {:.3}, dense-output order {:.3} (mid-step), {:.3} (max over s)",
        ps - 1.0,
        pd - 1.0,
        pa - 1.0
    );
    assert!(
        (ps - 1.0 - 8.0).abs() <= 0.5,
        "DOP853 local step order {}",
        ps - 1.0
    );
    assert!(
        (pd - 1.0 - 7.0).abs() <= 0.7,
        "DOP853 dense order {}",
        pd - 1.0
    );
    assert!(
        (pa - 1.0 - 7.0).abs() <= 0.7,
        "DOP853 dense order {}",
        pa - 1.0
    );
}

#[test]
fn dop853_step_and_dense_match_scipy() {
    // Reference: scipy.integrate._ivp.rk.DOP853 (SciPy 1.17.1), one step h = 0.1 from
    // periapsis of the e = 0.5 Kepler orbit; `sol.y` and `sol.dense_output()(0.1 * s)`.
    // Agreement to rounding (the sums are evaluated in a different order).
    let reference: [(f64, [f64; 4]); 4] = [
        (
            1.0,
            [
                0.4803249729065918,
                0.17094505172953298,
                -0.38716324004300673,
                1.6652096160205934,
            ],
        ),
        (
            0.3,
            [
                0.4982026936729102,
                0.05189929359440426,
                -0.1196412521739403,
                1.7258359263702372,
            ],
        ),
        (
            0.5,
            [
                0.49502069926348846,
                0.08631544161994828,
                -0.19834933121578768,
                1.7148874682118898,
            ],
        ),
        (
            0.8,
            [
                0.4873343187258334,
                0.13739799516517012,
                -0.3133384307123308,
                1.6887243473496556,
            ],
        ),
    ];
    let mut work = Dop853Work::new();
    let (y1, _) = Dop853::default().step(&Kepler, 0.0, &kepler_exact(0.5, 0.0), 0.1, &mut work);
    for (s, yr) in reference {
        let mut y = [0.0; 4];
        work.dense(&Kepler).eval(0.1 * s, &mut y);
        if s == 1.0 {
            assert_eq!(y, y1);
        }
        assert!(max_abs_diff(&y, &yr) <= 2e-15, "s = {s}: {y:?} vs {yr:?}");
    }
}

#[test]
fn dop853_local_orders_circular() {
    dop853_local_case("Kepler e=0", 0.0, 0.0, &[0.5, 0.4, 0.32, 0.256, 0.2048]);
}

// ---------------------------------------------------------------- adaptive accuracy

#[test]
fn dop853_versions_agree_bit_for_bit() {
    // `integrate` may run a version compiled for a wider instruction set: the same
    // operations in the same order, so the same steps and values as the portable one.
    let (e, t_end) = (0.7, 6.0 * PI);
    let dop = Dop853::new(1e-11, 1e-12);
    let (mut a, mut b) = (EveryStep::new(), EveryStep::new());
    let ra = dop.integrate(&Kepler, 0.0, kepler_exact(e, 0.0), t_end, &mut a);
    let rb = dop.integrate_with(&Kepler, 0.0, kepler_exact(e, 0.0), t_end, &mut b);
    assert_eq!(ra.unwrap(), rb.unwrap());
    assert_eq!((a.ts, a.ys), (b.ts, b.ys));
}

#[test]
fn dop853_adaptive_kepler_ten_periods() {
    let e = 0.5;
    let t_end = 20.0 * PI;
    let dop = Dop853::new(1e-10, 1e-10);
    let mut rec = EveryStep::with_capacity(4096);
    let (t, y, stats) = dop
        .integrate(&Kepler, 0.0, kepler_exact(e, 0.0), t_end, &mut rec)
        .unwrap();
    assert_eq!(t, t_end);
    let final_err = max_abs_diff(&y, &kepler_exact(e, t_end));
    let max_err = rec
        .ts
        .iter()
        .zip(&rec.ys)
        .map(|(&t, y)| max_abs_diff(y, &kepler_exact(e, t)))
        .fold(0.0, f64::max);
    let max_energy_err = rec
        .ys
        .iter()
        .map(|y| (kepler_energy(y) + 0.5).abs())
        .fold(0.0, f64::max);
    println!(
        "DOP853 rtol=atol=1e-10, Kepler e=0.5, 10 periods: {} steps, {} rejected, {} rhs evals; \
         final error {final_err:.3e}, max error over steps {max_err:.3e}, max energy error {max_energy_err:.3e}",
        stats.steps, stats.rejected, stats.rhs_evals
    );
    assert_eq!(rec.ts.len() as u64, stats.steps + 1);
    // SciPy's DOP853 on the same run: 348 steps, 5774 evaluations, max error 8.4e-7, max
    // energy error 2.6e-9. The global error (mostly phase drift, growing linearly in time)
    // is ~1e4 x the per-step tolerance; see the tolerance sweep below for 1e-8.
    assert!(max_err < 1.5e-6, "global error {max_err:e}");
    assert!(max_energy_err < 4e-9, "energy error {max_energy_err:e}");
    assert!((300..400).contains(&stats.steps), "{}", stats.steps);
    // Evaluation count: f(t0) + hinit's Euler step + 11 per attempt + 1 per accepted step
    // (no dense output was evaluated by EveryStep).
    assert_eq!(
        stats.rhs_evals,
        2 + 11 * (stats.steps + stats.rejected) + stats.steps
    );
}

#[test]
fn dop853_adaptive_kepler_tolerance_sweep() {
    // Global error and energy error over 10 periods of the e = 0.5 orbit against tolerance.
    let e = 0.5;
    let t_end = 20.0 * PI;
    let mut errs = vec![];
    println!("DOP853, Kepler e=0.5, 10 periods, rtol = atol = tol:");
    for tol in [1e-8, 1e-10, 1e-12, 1e-13] {
        let mut rec = EveryStep::new();
        let (_, _, stats) = Dop853::new(tol, tol)
            .integrate(&Kepler, 0.0, kepler_exact(e, 0.0), t_end, &mut rec)
            .unwrap();
        let err = rec
            .ts
            .iter()
            .zip(&rec.ys)
            .map(|(&t, y)| max_abs_diff(y, &kepler_exact(e, t)))
            .fold(0.0, f64::max);
        let energy = rec
            .ys
            .iter()
            .map(|y| (kepler_energy(y) + 0.5).abs())
            .fold(0.0, f64::max);
        println!(
            "    tol {tol:.0e}: {:5} steps {:4} rejected, max error {err:.2e}, max energy error {energy:.2e}",
            stats.steps, stats.rejected
        );
        errs.push((tol, err, energy));
    }
    let (_, err12, energy12) = errs[2];
    assert!(err12 < 1e-8, "{err12:e}");
    assert!(energy12 < 1e-10, "{energy12:e}");
    // Tolerance proportionality: the error falls with the tolerance.
    assert!(errs.windows(2).all(|w| w[1].1 < w[0].1));
}

#[test]
fn dop853_dense_samples_match_exact() {
    let e = 0.5;
    let times: Vec<f64> = (0..=400).map(|k| k as f64 * 0.05).collect();
    let mut samples = SampleAt::new(&times);
    let y0 = kepler_exact(e, 0.0);
    let dop = Dop853::new(1e-11, 1e-11);
    let (t, y, stats) = dop.integrate(&Kepler, 0.0, y0, 20.0, &mut samples).unwrap();
    assert_eq!(t, 20.0);
    assert!(samples.is_complete());
    // Exact end points: t0 gives y0, t_end gives the returned state (bitwise).
    assert_eq!(samples.out[0], y0);
    assert_eq!(*samples.out.last().unwrap(), y);
    let err = times
        .iter()
        .zip(&samples.out)
        .map(|(&t, y)| max_abs_diff(y, &kepler_exact(e, t)))
        .fold(0.0, f64::max);
    // Same run, errors at the step ends (the steps do not depend on the observer).
    let mut rec = EveryStep::new();
    let (_, _, stats2) = dop.integrate(&Kepler, 0.0, y0, 20.0, &mut rec).unwrap();
    assert_eq!(stats.steps, stats2.steps);
    let step_err = rec
        .ts
        .iter()
        .zip(&rec.ys)
        .map(|(&t, y)| max_abs_diff(y, &kepler_exact(e, t)))
        .fold(0.0, f64::max);
    println!(
        "DOP853 rtol=atol=1e-11, Kepler e=0.5 on [0, 20]: max error of 401 dense samples \
         {err:.3e}, at the {} step ends {step_err:.3e}",
        stats.steps
    );
    assert!(err <= 1.5 * step_err, "{err:e} vs {step_err:e}");
    // Dense output was used: 3 extra evaluations in the steps that contain a sample.
    assert!(stats.rhs_evals > stats2.rhs_evals);
    assert_eq!((stats.rhs_evals - stats2.rhs_evals) % 3, 0);
}

#[test]
fn h_max_and_fixed_steps_via_h_init() {
    // Huge tolerances + h_init = h_max: DOP853 takes fixed steps of size h_max.
    let dop = Dop853 {
        rtol: 1e10,
        atol: 1e10,
        h_init: Some(0.1),
        h_first_max: f64::INFINITY,
        h_max: 0.1,
        max_steps: 1000,
        stiff_stop: None,
    };
    let mut rec = EveryStep::new();
    let (t, _, stats) = dop
        .integrate(&Oscillator, 0.0, [1.0, 0.0], 1.05, &mut rec)
        .unwrap();
    assert_eq!(t, 1.05);
    assert_eq!(stats.steps, 11);
    for w in rec.ts.windows(2) {
        assert!(w[1] - w[0] <= 0.1 + 1e-15);
    }
    // The adaptive run with tight tolerances also honours h_max.
    let dop = Dop853 {
        h_max: 0.3,
        ..Dop853::new(1e-6, 1e-6)
    };
    let mut rec = EveryStep::new();
    dop.integrate(&Oscillator, 0.0, [1.0, 0.0], 10.0, &mut rec)
        .unwrap();
    assert!(rec
        .ts
        .windows(2)
        .all(|w| w[1] - w[0] <= 0.3 * (1.0 + 1e-12)));
}

#[test]
fn the_first_step_is_capped_and_the_rest_grow_as_before() {
    // The heuristic's first step on the oscillator at rtol 1e-6 is well above 1e-4; capped,
    // the first step is 1e-4 and the controller grows the next ones from there.
    let free = Dop853::new(1e-6, 1e-6);
    let mut rec = EveryStep::new();
    free.integrate(&Oscillator, 0.0, [1.0, 0.0], 2.0, &mut rec)
        .unwrap();
    assert!(rec.ts[1] - rec.ts[0] > 1e-3);
    let capped = Dop853 {
        h_first_max: 1e-4,
        ..free
    };
    let mut rec = EveryStep::new();
    let (t, y, _) = capped
        .integrate(&Oscillator, 0.0, [1.0, 0.0], 2.0, &mut rec)
        .unwrap();
    assert_eq!(t, 2.0);
    assert!((rec.ts[1] - rec.ts[0] - 1e-4).abs() < 1e-18);
    assert!(rec.ts.windows(2).skip(1).any(|w| w[1] - w[0] > 1e-3));
    // the solution, cos t, to the tolerance
    assert!((y[0] - 2.0f64.cos()).abs() < 1e-5);
}

#[test]
fn rk4_lands_on_t_end_and_samples() {
    let times = [0.0, 0.25, 1.0, 1.05];
    let mut samples = SampleAt::new(&times);
    let y0 = [1.0, 0.0];
    let (t, y, stats) = Rk4::new(0.1)
        .integrate(&Oscillator, 0.0, y0, 1.05, &mut samples)
        .unwrap();
    assert_eq!(t, 1.05);
    assert_eq!(stats.steps, 11);
    assert_eq!(stats.rhs_evals, 1 + 4 * 11);
    assert_eq!(samples.out[0], y0);
    assert_eq!(samples.out[3], y);
    for (&ts, ys) in times.iter().zip(&samples.out) {
        assert!((ys[0] - ts.cos()).abs() < 1e-6);
    }
    // An exact multiple does not produce a sliver step.
    let (t, _, stats) = Rk4::new(0.1)
        .integrate(&Oscillator, 0.0, y0, 1.0, &mut NullObserver)
        .unwrap();
    assert_eq!((t, stats.steps), (1.0, 10));
}

#[test]
fn zero_length_interval_returns_initial_state() {
    let y0 = [0.3, -0.7];
    let times = [2.0, 2.0, 3.0];
    for run in 0..2 {
        let mut samples = SampleAt::new(&times);
        let mut rec = EveryStep::new();
        let res = if run == 0 {
            Dop853::default().integrate(&Oscillator, 2.0, y0, 2.0, &mut samples)
        } else {
            Rk4::new(0.1).integrate(&Oscillator, 2.0, y0, 2.0, &mut samples)
        };
        let (t, y, stats) = res.unwrap();
        assert_eq!((t, y), (2.0, y0));
        assert_eq!(stats, Stats::default());
        assert_eq!(samples.out, vec![y0, y0]);
        assert!(!samples.is_complete());
        Dop853::default()
            .integrate(&Oscillator, 2.0, y0, 2.0, &mut rec)
            .unwrap();
        assert_eq!(
            (rec.ts.as_slice(), rec.ys.as_slice()),
            (&[2.0][..], &[y0][..])
        );
    }
}

/// Rotation `y' = A y` in the plane, projected back to the unit circle after each step.
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
fn projection_is_applied_to_every_accepted_state() {
    let mut check = FnObserver(|t: f64, y: &[f64; 2], dense: &dyn Dense<2>| {
        assert!(((y[0] * y[0] + y[1] * y[1]).sqrt() - 1.0).abs() < 4e-16);
        let mut ye = [0.0; 2];
        dense.eval(t, &mut ye);
        assert_eq!(&ye, y);
        ControlFlow::Continue(())
    });
    let (_, y, _) = Dop853::new(1e-3, 1e-3)
        .integrate(&ProjectedRotation, 0.0, [1.0, 0.0], 10.0, &mut check)
        .unwrap();
    assert!((y[0] - 10f64.cos()).abs() < 1e-2);
    let (_, y, _) = Rk4::new(0.5)
        .integrate(&ProjectedRotation, 0.0, [1.0, 0.0], 10.0, &mut check)
        .unwrap();
    assert!((y[0] - 10f64.cos()).abs() < 1e-2);
}

#[test]
fn observer_break_stops_at_step_end() {
    let mut n = 0;
    let mut obs = FnObserver(|_t: f64, _y: &[f64; 2], _d: &dyn Dense<2>| {
        n += 1;
        if n == 3 {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    });
    let (t, _, stats) = Rk4::new(0.1)
        .integrate(&Oscillator, 0.0, [1.0, 0.0], 1.0, &mut obs)
        .unwrap();
    assert_eq!(stats.steps, 3);
    assert!((t - 0.3).abs() < 1e-15);
}

// ---------------------------------------------------------------- errors

#[test]
fn non_finite_rhs_is_reported() {
    let always_nan = FnSystem(|_t: f64, _y: &[f64; 2], dy: &mut [f64; 2]| {
        *dy = [f64::NAN, 0.0];
    });
    let r = Dop853::default().integrate(&always_nan, 0.0, [1.0, 0.0], 1.0, &mut NullObserver);
    assert_eq!(r.unwrap_err(), IntegrateError::NonFinite { t: 0.0 });
    let r = Rk4::new(0.1).integrate(&always_nan, 0.0, [1.0, 0.0], 1.0, &mut NullObserver);
    assert_eq!(r.unwrap_err(), IntegrateError::NonFinite { t: 0.0 });

    // Finite up to t = 1, NaN after: the step shrinks towards t = 1, then gives up.
    let nan_after_1 = FnSystem(|t: f64, y: &[f64; 2], dy: &mut [f64; 2]| {
        dy[0] = if t > 1.0 { f64::NAN } else { y[1] };
        dy[1] = -y[0];
    });
    let r = Dop853::default().integrate(&nan_after_1, 0.0, [1.0, 0.0], 3.0, &mut NullObserver);
    match r {
        Err(IntegrateError::NonFinite { t }) => assert!((t - 1.0).abs() < 1e-10 && t <= 1.0, "{t}"),
        other => panic!("{other:?}"),
    }
    let r = Rk4::new(0.3).integrate(&nan_after_1, 0.0, [1.0, 0.0], 3.0, &mut NullObserver);
    match r {
        Err(IntegrateError::NonFinite { t }) => assert!((t - 0.9).abs() < 1e-12, "{t}"),
        other => panic!("{other:?}"),
    }
    // Non-finite initial state.
    let r = Dop853::default().integrate(
        &Oscillator,
        0.0,
        [f64::INFINITY, 0.0],
        1.0,
        &mut NullObserver,
    );
    assert_eq!(r.unwrap_err(), IntegrateError::NonFinite { t: 0.0 });
}

#[test]
fn max_steps_is_honoured() {
    let dop = Dop853 {
        max_steps: 25,
        stiff_stop: None,
        ..Dop853::new(1e-12, 1e-12)
    };
    let mut rec = EveryStep::new();
    match dop.integrate(&Kepler, 0.0, kepler_exact(0.5, 0.0), 100.0, &mut rec) {
        Err(IntegrateError::TooManySteps { t, steps }) => {
            assert_eq!(steps, 25);
            assert_eq!(Some(&t), rec.ts.last());
            assert!(rec.ts.len() <= 26);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn step_size_too_small_at_blow_up() {
    // y' = y^2, y(0) = 1 blows up at t = 1.
    let sys = FnSystem(|_t: f64, y: &[f64; 1], dy: &mut [f64; 1]| dy[0] = y[0] * y[0]);
    let r = Dop853::new(1e-8, 1e-8).integrate(&sys, 0.0, [1.0], 2.0, &mut NullObserver);
    match r {
        Err(IntegrateError::StepSizeTooSmall { t, h }) => {
            assert!((t - 1.0).abs() < 1e-6 && h < 1e-14, "t = {t}, h = {h}");
        }
        other => panic!("{other:?}"),
    }
}

// ---------------------------------------------------------------- events

fn oscillator_zero_crossings(direction: i8, tol: f64) -> (Vec<Event<2>>, Stats) {
    let mut calls = 0u64;
    let mut x = |_t: f64, y: &[f64; 2]| {
        calls += 1;
        y[0]
    };
    let mut loc = Locator::new();
    loc.add(EventSpec::new(direction, false), &mut x);
    // x(t) = sin t: zeros at k pi (the one at t0 = 0 is not reported).
    let (_, _, stats) = Dop853::new(tol, tol)
        .integrate(&Oscillator, 0.0, [0.0, 1.0], 6.0 * PI + 1.0, &mut loc)
        .unwrap();
    let events = loc.events.clone();
    drop(loc);
    // One call at t0 and at every step end; the rest is root finding.
    let per_root = (calls - 1 - stats.steps) as f64 / events.len() as f64;
    println!("    direction {direction}: {per_root:.1} event-function calls per located root");
    assert!(per_root <= 20.0);
    (events, stats)
}

#[test]
fn events_locate_oscillator_zeros() {
    let (events, stats) = oscillator_zero_crossings(0, 1e-13);
    let ts: Vec<f64> = events.iter().map(|e| e.t).collect();
    println!("zero crossings of sin t ({} steps): {ts:?}", stats.steps);
    assert_eq!(events.len(), 6);
    let mut worst: f64 = 0.0;
    for (k, ev) in events.iter().enumerate() {
        let exact = (k + 1) as f64 * PI;
        worst = worst.max((ev.t - exact).abs());
        assert_eq!(ev.index, 0);
        assert!(
            (ev.t - exact).abs() <= 1e-12,
            "event {k}: {} vs {exact}",
            ev.t
        );
        assert!(ev.y[0].abs() <= 1e-12);
        let v = if k % 2 == 0 { -1.0 } else { 1.0 };
        assert!((ev.y[1] - v).abs() <= 1e-12);
    }
    println!("max |t_event - k pi| = {worst:.2e}");
}

#[test]
fn events_direction_filter() {
    let (up, _) = oscillator_zero_crossings(1, 1e-13);
    let (down, _) = oscillator_zero_crossings(-1, 1e-13);
    let up_t: Vec<f64> = up.iter().map(|e| (e.t / PI).round()).collect();
    let down_t: Vec<f64> = down.iter().map(|e| (e.t / PI).round()).collect();
    assert_eq!(up_t, vec![2.0, 4.0, 6.0]);
    assert_eq!(down_t, vec![1.0, 3.0, 5.0]);
    assert!(up.iter().all(|e| e.y[1] > 0.0));
    assert!(down.iter().all(|e| e.y[1] < 0.0));
}

/// An exact "interpolant" `y(t)` over the step `[t0, t1]`: the event locator alone.
struct Exact<F: Fn(f64) -> [f64; 2]>(f64, f64, F);

impl<F: Fn(f64) -> [f64; 2]> Dense<2> for Exact<F> {
    fn t0(&self) -> f64 {
        self.0
    }
    fn t1(&self) -> f64 {
        self.1
    }
    fn eval(&self, t: f64, out: &mut [f64; 2]) {
        *out = (self.2)(t);
    }
}

#[test]
fn locator_precision_on_exact_dense_output() {
    // The root finder alone, on an exact "interpolant" x = sin t over a long step.
    for k in [1.0, 10.0, 1000.0] {
        let (a, b) = (k * PI - 0.9, k * PI + 1.3);
        let mut g = |_t: f64, y: &[f64; 2]| y[0];
        let mut loc = Locator::new();
        loc.add(EventSpec::new(0, false), &mut g);
        loc.start(a, &[a.sin(), a.cos()]);
        let ev = loc.check(b, &[b.sin(), b.cos()], &Exact(a, b, |t| [t.sin(), t.cos()]));
        assert!(ev.is_none());
        let err = (loc.events[0].t - k * PI).abs();
        assert!(err <= 1e-12 * (k * PI).max(1.0), "k = {k}: {err:e}");
    }
}

#[test]
fn a_dip_through_zero_near_either_end_of_a_step_is_found() {
    // g = (t - c)^2 - 0.0025 on an exact "interpolant" y = (t, 0): zeros at c -+ 0.05, both
    // inside one long step, g > 0 at both of its ends; the dip lies within the first (or
    // last) eighth of the step, where the two interior points at 1/3 and 2/3 do not look.
    for (a, b, c) in [(0.145, 1.0, 0.2), (0.0, 0.855, 0.8)] {
        let mut g = |_t: f64, y: &[f64; 2]| (y[0] - c) * (y[0] - c) - 0.0025;
        let mut loc = Locator::new();
        loc.add(EventSpec::new(-1, false), &mut g);
        loc.start(a, &[a, 0.0]);
        assert!(loc
            .check(b, &[b, 0.0], &Exact(a, b, |t| [t, 0.0]))
            .is_none());
        assert_eq!(loc.events.len(), 1, "dip at {c}");
        let err = (loc.events[0].t - (c - 0.05)).abs();
        assert!(err <= 1e-12, "dip at {c}: {err:e}");
    }
}

#[test]
fn terminal_event_stops_at_event_state() {
    // Stop at the first falling zero of x (t = pi); count rising ones as non-terminal... none before.
    let mut x = |_t: f64, y: &[f64; 2]| y[0];
    let mut v = |_t: f64, y: &[f64; 2]| y[1];
    let mut loc = Locator::new();
    let iv = loc.add(EventSpec::new(0, false), &mut v); // v = cos t: zero at pi/2
    let ix = loc.add(EventSpec::new(-1, true), &mut x);
    let (t, y, _) = Dop853::new(1e-13, 1e-13)
        .integrate(&Oscillator, 0.0, [0.0, 1.0], 10.0, &mut loc)
        .unwrap();
    assert!((t - PI).abs() <= 1e-12, "{t}");
    assert!(y[0].abs() <= 1e-12 && (y[1] + 1.0).abs() <= 1e-12);
    assert_eq!(loc.events.len(), 2);
    assert_eq!(loc.events[0].index, iv);
    assert!((loc.events[0].t - 0.5 * PI).abs() <= 1e-12);
    assert_eq!(loc.events[1].index, ix);
    assert_eq!(loc.terminal_event().map(|e| (e.t, e.y)), Some((t, y)));
    // The stop point is on the far side of the crossing: x(t) <= 0.
    assert!(y[0] <= 0.0);
}

#[test]
fn terminal_event_with_inner_observer_and_rk4() {
    // Earliest terminal event wins when two occur in one step; the inner observer sees
    // the step truncated at the event.
    let mut g1 = |t: f64, _y: &[f64; 2]| t - 0.73;
    let mut g2 = |t: f64, _y: &[f64; 2]| t - 0.71;
    let mut loc = Locator::new();
    loc.add(EventSpec::new(1, true), &mut g1);
    loc.add(EventSpec::new(1, true), &mut g2);
    let times = [0.0, 0.5, 0.7, 0.72, 0.9];
    let mut obs = WithEvents::new(loc, SampleAt::new(&times));
    let (t, y, stats) = Rk4::new(0.25)
        .integrate(&Oscillator, 0.0, [1.0, 0.0], 2.0, &mut obs)
        .unwrap();
    assert_eq!(stats.steps, 3);
    assert!((t - 0.71).abs() <= 1e-12, "{t}");
    assert_eq!(obs.locator.events.len(), 1);
    assert_eq!(obs.locator.events[0].index, 1);
    assert_eq!(obs.inner.out.len(), 3); // 0.0, 0.5, 0.7 but not 0.72, 0.9
    assert!((y[0] - 0.71f64.cos()).abs() < 1e-4);
}

#[test]
fn restart_after_terminal_event_does_not_refire() {
    let mut x = |_t: f64, y: &[f64; 2]| y[0];
    let mut loc = Locator::new();
    loc.add(EventSpec::new(0, true), &mut x);
    let dop = Dop853::new(1e-12, 1e-12);
    let (t1, y1, _) = dop
        .integrate(&Oscillator, 0.0, [1.0, 0.0], 10.0, &mut loc)
        .unwrap();
    assert!((t1 - 0.5 * PI).abs() < 1e-11);
    let (t2, _, _) = dop.integrate(&Oscillator, t1, y1, 10.0, &mut loc).unwrap();
    assert!((t2 - 1.5 * PI).abs() < 1e-11, "{t2}");
}

#[test]
fn zero_atol_and_pure_relative_tolerance() {
    // y' = -y: with atol = 0 the relative criterion alone works for a nonzero solution.
    let decay = FnSystem(|_t: f64, y: &[f64; 1], dy: &mut [f64; 1]| dy[0] = -y[0]);
    let (_, y, _) = Dop853::new(1e-10, 0.0)
        .integrate(&decay, 0.0, [1.0], 10.0, &mut NullObserver)
        .unwrap();
    assert!((y[0] / (-10f64).exp() - 1.0).abs() < 1e-8);
    // A component that must stay exactly zero (here it does) does not upset the norm.
    let decay2 = FnSystem(|_t: f64, y: &[f64; 2], dy: &mut [f64; 2]| {
        dy[0] = -y[0];
        dy[1] = -y[1];
    });
    let (_, y, _) = Dop853::new(1e-10, 0.0)
        .integrate(&decay2, 0.0, [1.0, 0.0], 1.0, &mut NullObserver)
        .unwrap();
    assert_eq!(y[1], 0.0);
}

/// Kepler's orbit with a quadrature carried along that starts at 0 and oscillates about it
/// as a pivot's work does, `Q' = sin(40 t)`, its error measured against `floor` (0: its own
/// size, at most 1/20).
struct KeplerWithQuadrature {
    floor: f64,
}

impl OdeSystem<5> for KeplerWithQuadrature {
    fn rhs(&self, t: f64, y: &[f64; 5], dy: &mut [f64; 5]) {
        let mut d4 = [0.0; 4];
        Kepler.rhs(t, &[y[0], y[1], y[2], y[3]], &mut d4);
        dy[..4].copy_from_slice(&d4);
        dy[4] = (40.0 * t).sin();
    }
    fn magnitude_floor(&self) -> [f64; 5] {
        [0.0, 0.0, 0.0, 0.0, self.floor]
    }
}

#[test]
fn a_magnitude_floor_measures_a_quadrature_against_its_scale() {
    // atol far below the orbit's size: a quadrature starting at 0 is then held to atol
    let (rtol, atol) = (1e-10, 1e-16);
    let y0 = kepler_exact(0.5, 0.0);
    let dop = Dop853::new(rtol, atol);
    let steps = |floor: f64| {
        let sys = KeplerWithQuadrature { floor };
        let y = [y0[0], y0[1], y0[2], y0[3], 0.0];
        let (_, y1, st) = dop
            .integrate(&sys, 0.0, y, 2.0 * PI, &mut NullObserver)
            .unwrap();
        (st.steps, y1)
    };
    let (own, y_own) = steps(0.0);
    let (floored, y_floored) = steps(1.0); // the orbit's size
                                           // measured against its own size (<= 1/20, and near 0 against atol) the quadrature sets
                                           // the steps (measured: 546 against 327 with the floor)
    assert!(own as f64 > 1.3 * floored as f64, "{own} {floored}");
    // and both are right: Q(2 pi) = (1 - cos(80 pi)) / 40 = 0
    assert!(y_floored[4].abs() < 1e-9, "{}", y_floored[4]);
    assert!(y_own[4].abs() < 1e-10, "{}", y_own[4]);
}

/// Prothero and Robinson's stiff test, `y' = lambda (y - sin t) + cos t`, `y(0) = 0`: the
/// solution is `sin t` for every `lambda`; with `lambda = -1e4` the explicit steps are held
/// by stability (`h |lambda|` near the boundary) long after the transient.
struct ProtheroRobinson(f64);

impl OdeSystem<1> for ProtheroRobinson {
    fn rhs(&self, t: f64, y: &[f64; 1], dy: &mut [f64; 1]) {
        dy[0] = self.0 * (y[0] - t.sin()) + t.cos();
    }
}

#[test]
fn dop853_stops_where_a_problem_is_stiff_and_radau5_goes_on() {
    let dop = Dop853 {
        stiff_stop: Some(5.0),
        ..Dop853::new(1e-8, 1e-10)
    };
    // Not stiff: the oscillator at 8th order, h |lambda| = h below 5 (stops never).
    let mut rec = EveryStep::new();
    let (t, _, st) = dop
        .integrate(&Oscillator, 0.0, [0.0, 1.0], 50.0, &mut rec)
        .unwrap();
    assert_eq!((t, st.stiff_stops), (50.0, 0));
    // Stiff: stops after STIFF_STEPS steps over the bound, early in the run.
    let sys = ProtheroRobinson(-1e4);
    let mut rec = EveryStep::new();
    let (t1, y1, st) = dop.integrate(&sys, 0.0, [0.0], 10.0, &mut rec).unwrap();
    assert_eq!(st.stiff_stops, 1);
    assert!(
        t1 < 0.1 && st.steps >= u64::from(STIFF_STEPS),
        "{t1} {st:?}"
    );
    assert!((y1[0] - t1.sin()).abs() < 1e-8);
    // On a linear problem the estimate is h |lambda| itself: the last STIFF_STEPS steps all
    // had h |lambda| over the bound, the one before them (or the start) not necessarily.
    let h: Vec<f64> = rec.ts.windows(2).map(|w| w[1] - w[0]).collect();
    let last = &h[h.len() - STIFF_STEPS as usize..];
    assert!(last.iter().all(|&h| h * 1e4 > 5.0), "{last:?}");
    // and the explicit steps sit at DOP853's stability boundary (about 6 on the real axis)
    assert!(last.iter().all(|&h| h * 1e4 < 7.0), "{last:?}");
    // The rest by Radau5, the observer going on without a second start: its record is one
    // run, and the end is the exact solution's to the tolerance, in far fewer steps than the
    // explicit method takes for the whole interval.
    let n1 = rec.ts.len();
    let (t2, y2, more) = Radau5::new(1e-8, 1e-10)
        .integrate(&sys, t1, y1, 10.0, &mut Resumed(&mut rec))
        .unwrap();
    assert_eq!(t2, 10.0);
    assert!(
        (y2[0] - 10f64.sin()).abs() < 1e-7,
        "{}",
        y2[0] - 10f64.sin()
    );
    assert_eq!(rec.ts.len(), n1 + more.steps as usize);
    assert!(rec.ts.windows(2).all(|w| w[1] > w[0]));
    let explicit = Dop853::new(1e-8, 1e-10)
        .integrate(&sys, 0.0, [0.0], 10.0, &mut NullObserver)
        .unwrap()
        .2;
    assert!(
        more.steps * 20 < explicit.steps,
        "{} {}",
        more.steps,
        explicit.steps
    );
    let sum = st.plus(&more);
    assert_eq!(sum.steps, st.steps + more.steps);
    assert_eq!(sum.stiff_stops, 1);
}
