//! Measured orders of the fixed-step methods on the exact Lagrange solution, and the
//! invariants they are built to keep.

use kreisel_core::models::heavy_top::{HeavyTop, RigidState};
use kreisel_core::models::lagrange::{EulerState, LagrangeExact, LagrangeTop};
use kreisel_core::rotation::{omega_body_from_euler, quaternion_from_euler};
use kreisel_core::simulate::{simulate, Settings, Solution};

fn rigid(s: &EulerState) -> RigidState {
    RigidState {
        q: quaternion_from_euler(s.phi, s.theta, s.psi),
        omega: omega_body_from_euler(s.theta, s.psi, s.theta_dot, s.phi_dot, s.psi_dot),
    }
}

fn matrix_error(a: &RigidState, b: &RigidState) -> f64 {
    let (ma, mb) = (a.q.matrix(), b.q.matrix());
    let mut e: f64 = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            e = e.max((ma[i][j] - mb[i][j]).abs());
        }
    }
    e
}

fn settings(method: &str, t_end: f64, dt: f64) -> Settings {
    Settings {
        method: method.into(),
        t_end,
        rtol: 1e-10,
        atol: 1e-12,
        dt: Some(dt),
        t_eval: Some(vec![t_end]),
        ..Settings::default()
    }
}

fn simulate_fixed(
    top: &HeavyTop,
    s0: &RigidState,
    st: &Settings,
) -> kreisel_core::Result<Solution<RigidState>> {
    simulate(top, s0, st, &mut [], &mut |_| true)
}

#[test]
fn fixed_step_methods_have_their_declared_order() {
    let lt = LagrangeTop::new(1.0, 0.5, 1.0, 0.3, 1.0).unwrap();
    let top = HeavyTop::from_lagrange(&lt);
    let e0 = EulerState::new(1.0, 0.2, -0.1, 0.3, 0.7, 5.0).unwrap();
    let t_end = 2.0;
    let exact = rigid(&LagrangeExact::new(&lt, &e0).unwrap().at(t_end).unwrap());
    let s0 = rigid(&e0);
    for (method, order, dts) in [
        ("splitting", 2.0, [0.02, 0.01, 0.005]),
        ("verlet", 2.0, [0.02, 0.01, 0.005]),
        ("midpoint", 2.0, [0.02, 0.01, 0.005]),
        ("splitting4", 4.0, [0.04, 0.02, 0.01]),
        ("gauss4", 4.0, [0.04, 0.02, 0.01]),
        ("splitting6", 6.0, [0.1, 0.05, 0.025]),
    ] {
        let errs: Vec<f64> = dts
            .iter()
            .map(|&dt| {
                let out = simulate_fixed(&top, &s0, &settings(method, t_end, dt)).unwrap();
                matrix_error(out.rows.last().unwrap(), &exact)
            })
            .collect();
        let slope = (errs[0] / errs[2]).ln() / (dts[0] / dts[2]).ln();
        assert!(
            (slope - order).abs() < 0.35,
            "{method}: slope {slope}, errors {errs:?}"
        );
    }
}

#[test]
fn splitting_keeps_mz_and_m3_to_round_off() {
    let lt = LagrangeTop::new(1.0, 0.5, 1.0, 1.0, 1.0).unwrap();
    let top = HeavyTop::from_lagrange(&lt);
    let s0 = rigid(&EulerState::new(1.0, 0.0, 0.0, 0.3, 0.7, 9.0).unwrap());
    let st = Settings {
        t_eval: Some((0..=100).map(|i| i as f64 * 100.0).collect()),
        ..settings("splitting", 10_000.0, 0.01)
    };
    let out = simulate_fixed(&top, &s0, &st).unwrap();
    let (mz0, m30, e0) = (top.mz(&s0), top.m3(&s0).unwrap(), top.energy(&s0));
    let mut emax: f64 = 0.0;
    for s in &out.rows {
        assert!(
            (top.mz(s) - mz0).abs() < 1e-13 * m30.abs(),
            "Mz {} vs {mz0}: {:e}",
            top.mz(s),
            (top.mz(s) - mz0) / m30
        );
        assert!((top.m3(s).unwrap() - m30).abs() < 1e-13 * m30.abs());
        emax = emax.max((top.energy(s) - e0).abs() / e0.abs());
    }
    assert!(emax < 1e-3, "energy error {emax}");
}

#[test]
fn kovalevskaya_integral_is_kept() {
    let top = HeavyTop::new(2.0, 2.0, 1.0, 1.0, [0.4, 0.0, 0.0], 9.81).unwrap();
    let s0 = RigidState::new([0.9, 0.2, -0.3, 0.1], [1.0, -2.0, 3.0]).unwrap();
    let out = simulate_fixed(
        &top,
        &s0,
        &Settings {
            t_eval: Some((0..=50).map(|i| i as f64 * 0.2).collect()),
            ..settings("gauss4", 10.0, 1e-3)
        },
    )
    .unwrap();
    let k0 = top.kovalevskaya(&s0).unwrap();
    for s in &out.rows {
        let k = top.kovalevskaya(s).unwrap();
        assert!((k - k0).abs() < 1e-8 * k0, "K {k} vs {k0}");
    }
}
