//! The exact Lagrange solution against an independent integration of the Euler-Lagrange
//! equations, its invariants, and its fast path against its direct evaluation.

use kreisel_core::models::lagrange::{EulerState, LagrangeExact, LagrangeTop, MotionKind};

/// RK4 on (theta, thetadot, phi, psi) with phidot, psidot from the conserved momenta:
/// I1 theta'' = I1 phidot^2 sin cos - M3 phidot sin + m g l sin.
fn integrate(top: &LagrangeTop, s: &EulerState, t_end: f64, steps: usize) -> [f64; 4] {
    let inv = top.invariants(s);
    let (i1, i3, mgl, mz, m3) = (top.i1(), top.i3(), top.mgl(), inv.mz, inv.m3);
    let rhs = |y: [f64; 4]| {
        let (st, ct) = y[0].sin_cos();
        let phid = (mz - m3 * ct) / (i1 * st * st);
        let psid = m3 / i3 - phid * ct;
        let thdd = phid * phid * st * ct - m3 * phid * st / i1 + mgl * st / i1;
        [y[1], thdd, phid, psid]
    };
    let mut y = [s.theta, s.theta_dot, s.phi, s.psi];
    let h = t_end / steps as f64;
    let add = |y: [f64; 4], k: [f64; 4], c: f64| std::array::from_fn(|i| y[i] + c * k[i]);
    for _ in 0..steps {
        let k1 = rhs(y);
        let k2 = rhs(add(y, k1, 0.5 * h));
        let k3 = rhs(add(y, k2, 0.5 * h));
        let k4 = rhs(add(y, k3, h));
        y = std::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
    }
    y
}

fn top() -> LagrangeTop {
    LagrangeTop::new(1.0, 0.5, 1.0, 1.0, 1.0).unwrap()
}

fn states() -> Vec<EulerState> {
    let s = |th, thd, phd, psd| EulerState::new(th, 0.3, -0.2, thd, phd, psd).unwrap();
    vec![
        s(1.0, 0.3, 0.7, 9.0), // the benchmark state, between turning points, moving down
        s(1.0, -0.3, 0.7, 9.0), // same, moving up
        s(1.2, 0.0, 0.0, 6.0), // at rest in theta and phi: cusps
        s(0.7, 0.0, -0.5, 6.0), // loops
        s(2.0, 0.4, 1.5, 3.0), // below the horizontal
    ]
}

#[test]
fn exact_matches_integration_of_euler_lagrange_equations() {
    let top = top();
    for s in states() {
        let ex = LagrangeExact::new(&top, &s).unwrap();
        let t_end = 10.0;
        let y = integrate(&top, &s, t_end, 200_000);
        let e = ex.at(t_end).unwrap();
        let err = [
            (e.theta - y[0]),
            (e.theta_dot - y[1]),
            (e.phi - y[2]),
            (e.psi - y[3]),
        ];
        for d in err {
            assert!(d.abs() < 1e-9, "{:?}: {err:?} ({:?})", s, ex.kind());
        }
    }
}

#[test]
fn fast_path_agrees_with_direct_evaluation() {
    let top = top();
    for s in states() {
        let ex = LagrangeExact::new(&top, &s).unwrap();
        assert!(ex.segments() > 0);
        for i in 0..400 {
            let t = -20.0 + 0.1 * i as f64 + 0.0123;
            let (f, d) = (ex.at(t).unwrap(), ex.at_direct(t).unwrap());
            let scale = 1.0 + d.phi.abs() + d.psi.abs();
            for (x, y) in [
                (f.theta, d.theta),
                (f.phi, d.phi),
                (f.psi, d.psi),
                (f.theta_dot, d.theta_dot),
                (f.phi_dot, d.phi_dot),
                (f.psi_dot, d.psi_dot),
            ] {
                assert!((x - y).abs() < 1e-12 * scale, "t={t}: {x} vs {y}");
            }
        }
    }
}

#[test]
fn invariants_are_kept_along_the_exact_motion() {
    let top = top();
    for s in states() {
        let ex = LagrangeExact::new(&top, &s).unwrap();
        let i0 = top.invariants(&s);
        for i in 0..500 {
            let e = ex.at(0.37 * i as f64).unwrap();
            let inv = top.invariants(&e);
            assert!((inv.energy - i0.energy).abs() < 1e-12 * i0.energy.abs().max(1.0));
            assert!((inv.mz - i0.mz).abs() < 1e-12 * i0.m3.abs());
            assert!((inv.m3 - i0.m3).abs() < 1e-12 * i0.m3.abs());
        }
    }
}

#[test]
fn state_at_zero_is_reproduced_and_kinds_are_classified() {
    let top = top();
    // Kinds from the signs of b - a u at the roots of f (computed independently with numpy:
    // the benchmark state has b - a u = +0.59 at u1 and -0.25 at u2, so loops).
    let kinds = [
        MotionKind::Loops,
        MotionKind::Loops,
        MotionKind::Cusps,
        MotionKind::Loops,
        MotionKind::Waves,
    ];
    for (s, k) in states().iter().zip(kinds) {
        let ex = LagrangeExact::new(&top, s).unwrap();
        let e = ex.at(0.0).unwrap();
        assert!((e.theta - s.theta).abs() < 1e-14 && (e.phi - s.phi).abs() < 1e-14);
        assert!((e.psi - s.psi).abs() < 1e-14 && (e.theta_dot - s.theta_dot).abs() < 1e-12);
        assert_eq!(ex.kind(), k, "{s:?}");
    }
}
