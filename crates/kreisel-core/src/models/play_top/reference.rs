//! A second formulation of the one-sphere equations, for tests only: the classic play top
//! in the body frame (theory: play top), with the normal force from the constraint written
//! as `N/m - g - s d2u/dt2 = 0` and the rolling force from the differentiated rolling
//! constraint. The engine solves the same motion in the space frame from the parts' support
//! functions ([`super::solve`]); the two must agree to rounding.

use super::solve::{Consts, Kernel};
use super::{
    add, scale, solve3, to_body, to_space, Contacts, Forces, Friction, Mode, PlayTop, Shape, DIM,
};
use crate::rotation::{cross, dot, quaternion_from_euler, Quat};

/// The state derivative and the normal force of a tip sphere (radius `rho`, centre `s` below
/// G) in `mode`, `dir` the slip direction at zero slip (Coulomb).
fn classic(
    top: &PlayTop,
    (s, rho): (f64, f64),
    mode: Mode,
    y: &[f64; DIM],
    dir: [f64; 3],
    dy: &mut [f64; DIM],
) -> f64 {
    let q = Quat([y[0], y[1], y[2], y[3]]);
    let r = q.unit_matrix();
    let w = [y[4], y[5], y[6]];
    let gamma = r[2];
    let a_b = [-rho * gamma[0], -rho * gamma[1], -s - rho * gamma[2]];
    let v = [y[10], y[11], y[12]];
    let gdot = cross(gamma, w);
    let v_t = add(v, to_space(&r, cross(w, a_b)));
    let inv = |x: [f64; 3]| [x[0] / top.a, x[1] / top.a, x[2] / top.c];
    let e = (top.a - top.c) / top.a;
    let b0 = [e * w[1] * w[2], -e * w[0] * w[2], 0.0];
    let (n, ft, wdot, vdot) = match mode {
        Mode::Flight => (0.0, [0.0; 3], b0, [0.0, 0.0, -top.g]),
        Mode::Slip => {
            let sp = v_t[0].hypot(v_t[1]);
            let f_t = match top.friction {
                Friction::Viscous { mu } => [-mu * v_t[0], -mu * v_t[1], 0.0],
                Friction::Coulomb { mu } if sp > 0.0 => [-mu * v_t[0] / sp, -mu * v_t[1] / sp, 0.0],
                Friction::Coulomb { mu } => [-mu * dir[0], -mu * dir[1], 0.0],
                _ => [0.0; 3],
            };
            let f_s = [f_t[0], f_t[1], 1.0];
            let b1 = inv(cross(a_b, to_body(&r, f_s)));
            let k0 = cross(gdot, w)[2] + cross(gamma, b0)[2];
            let k1 = cross(gamma, b1)[2];
            let n = (top.g + s * k0) / (1.0 / top.m - s * k1);
            let vdot = [n * f_s[0] / top.m, n * f_s[1] / top.m, n / top.m - top.g];
            (n, scale(n, f_t), add(b0, scale(n, b1)), vdot)
        }
        Mode::Roll => {
            let map = |f: [f64; 3]| add(scale(1.0 / top.m, f), cross(inv(cross(a_b, f)), a_b));
            let cols = [
                map([1.0, 0.0, 0.0]),
                map([0.0, 1.0, 0.0]),
                map([0.0, 0.0, 1.0]),
            ];
            let mat = core::array::from_fn(|i| core::array::from_fn(|j| cols[j][i]));
            let wxe3 = cross(w, [0.0, 0.0, 1.0]);
            let rhs = add(
                add(scale(top.g, gamma), scale(-1.0, cross(b0, a_b))),
                scale(s, cross(w, wxe3)),
            );
            let f_b = solve3(mat, rhs);
            let f_s = to_space(&r, f_b);
            let vdot = [f_s[0] / top.m, f_s[1] / top.m, f_s[2] / top.m - top.g];
            (
                dot(f_b, gamma),
                [f_s[0], f_s[1], 0.0],
                add(inv(cross(a_b, f_b)), b0),
                vdot,
            )
        }
    };
    dy[..4].copy_from_slice(&q.half_times_pure(w));
    dy[4..7].copy_from_slice(&wdot);
    dy[7..10].copy_from_slice(&v);
    dy[10..13].copy_from_slice(&vdot);
    dy[13] = if mode == Mode::Slip {
        -(ft[0] * v_t[0] + ft[1] * v_t[1])
    } else {
        0.0
    };
    n
}

/// One sphere: the engine's kernels give the classic equations' right-hand side in every
/// mode and friction law (the space-frame kernel of one sliding part too, where the ball's
/// own body-frame kernel is the one a run takes).
#[test]
fn the_kernels_give_the_classic_one_sphere_equations() {
    let (s, rho) = (0.003, 0.015);
    let parts = [Shape::Sphere { radius: rho, z: -s }];
    let q = quaternion_from_euler(0.4, 2.1, -0.7);
    for friction in [
        Friction::Coulomb { mu: 0.3 },
        Friction::Viscous { mu: 1.0 },
        Friction::Frictionless,
    ] {
        let top = PlayTop::with_parts(
            0.006, 8e-7, 7e-7, &parts, 9.81, friction, 0.0, 0.0, 0.0, 0.0,
        )
        .unwrap();
        let y = top.state(q, [3.0, -2.0, 150.0], 0.05, -0.03, None).unwrap();
        for mode in [Mode::Slip, Mode::Roll, Mode::Flight] {
            for dir in [[0.6, -0.8, 0.0], [0.0; 3]] {
                let (mut a, mut b) = ([0.0; DIM], [0.0; DIM]);
                let n = classic(&top, (s, rho), mode, &y, dir, &mut a);
                let mut cs = Contacts::NONE;
                cs.mode[0] = mode;
                cs.dir[0] = [dir[0], dir[1]];
                let f = top.dynamics(&cs, &y, &mut b);
                let big = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                for i in 0..DIM {
                    assert!(
                        (a[i] - b[i]).abs() <= 1e-9 * a[i].abs() + 1e-14 * big,
                        "{friction:?} {mode:?} {i}: {} {}",
                        a[i],
                        b[i]
                    );
                }
                assert!((n - f.n[0]).abs() <= 1e-10 * n.abs().max(1e-12));
                if mode == Mode::Slip {
                    let (mut g, mut fo) = ([0.0; DIM], Forces::default());
                    let p = Consts::of(&top);
                    top.rates(Kernel::OneSlip(0), &p, &cs, &y, &mut g, &mut fo);
                    for i in 0..DIM {
                        assert!(
                            (a[i] - g[i]).abs() <= 1e-9 * a[i].abs() + 1e-14 * big,
                            "one-slip kernel {friction:?} {i}: {} {}",
                            a[i],
                            g[i]
                        );
                    }
                    assert!((fo.den[0] - f.den[0]).abs() <= 1e-9 * f.den[0].abs());
                }
            }
        }
    }
}

/// The ball's kernel serves a sphere that is not the first part and whose centre lies above
/// G (s < 0) as the general kernel of one sliding part does (the forces in that part's
/// slot).
#[test]
fn the_balls_kernel_is_the_one_part_kernel_for_any_sphere() {
    let parts = [
        Shape::Torus {
            major: 0.02,
            minor: 0.004,
            z: 0.03,
        },
        Shape::Sphere {
            radius: 0.026,
            z: 0.02,
        },
    ];
    let q = quaternion_from_euler(0.3, 1.9, 0.4);
    for friction in [Friction::Coulomb { mu: 0.3 }, Friction::Viscous { mu: 0.7 }] {
        let top = PlayTop::with_parts(0.15, 6e-5, 9e-5, &parts, 9.81, friction, 0.2, 0.0, 0.0, 0.0)
            .unwrap();
        let y = top.state(q, [4.0, -1.0, 30.0], 0.02, 0.01, None).unwrap();
        let mut cs = Contacts::NONE;
        cs.mode[1] = Mode::Slip;
        cs.dir[1] = [0.6, -0.8];
        assert!(matches!(
            Kernel::of(&top, &cs),
            Kernel::BallSlip { i: 1, .. }
        ));
        let (mut a, mut b, mut fb) = ([0.0; DIM], [0.0; DIM], Forces::default());
        let fa = top.dynamics(&cs, &y, &mut a);
        top.rates(
            Kernel::OneSlip(1),
            &Consts::of(&top),
            &cs,
            &y,
            &mut b,
            &mut fb,
        );
        let big = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for i in 0..DIM {
            assert!(
                (a[i] - b[i]).abs() <= 1e-9 * a[i].abs() + 1e-14 * big,
                "{friction:?} {i}"
            );
        }
        assert!(fa.n[0] == 0.0 && (fa.n[1] - fb.n[1]).abs() <= 1e-10 * fb.n[1].abs());
        assert!((fa.den[1] - fb.den[1]).abs() <= 1e-9 * fb.den[1].abs());
    }
}
