//! Times benchmark case T4 in the core alone (kreisel's side): Euler's disk, a uniform steel
//! disk (radius 0.0375 m, thickness 0.0125 m) rolling with its centre at rest from 0.3 rad
//! under Coulomb friction 0.3, drilling 1e-4 m and rolling 2e-4 m, to flat. `cargo run
//! --release --example t4_timing [rtol] [t_end] [mu] [cc]`; with `cc`, Coulomb-Contensou
//! friction over the patch whose largest drilling torque per newton is 1e-4 m (no drilling
//! resistance), the benchmark's other law. Under `valgrind --tool=callgrind` it counts
//! instructions.
use kreisel_core::models::play_top::{Friction, PlayTop, Shape};
use kreisel_core::rotation::{omega_body_from_euler, quaternion_from_euler};
use kreisel_core::simulate::{simulate, Settings};
use std::time::Instant;
fn main() {
    let arg = |i: usize, default: f64| {
        std::env::args()
            .nth(i)
            .map_or(default, |a| a.parse().unwrap())
    };
    let (rtol, t_end, mu) = (arg(1, 1e-6), arg(2, 30.0), arg(3, 0.3));
    let (r, h, g) = (0.0375_f64, 0.0125_f64, 9.81);
    let m = 7850.0 * std::f64::consts::PI * r * r * h;
    let (a, c) = (m * (3.0 * r * r + h * h) / 12.0, m * r * r / 2.0);
    let parts = [
        Shape::Torus {
            major: r,
            minor: 0.0,
            z: h / 2.0,
        },
        Shape::Torus {
            major: r,
            minor: 0.0,
            z: -h / 2.0,
        },
    ];
    let cc = std::env::args().nth(4).is_some_and(|a| a == "cc");
    let (fr, drilling) = if cc {
        let patch = 1e-4 * 16.0 / (3.0 * std::f64::consts::PI * mu);
        (Friction::coulomb_contensou(mu, patch).unwrap(), 0.0)
    } else {
        (Friction::Coulomb { mu }, 1e-4)
    };
    let top = PlayTop::with_parts(m, a, c, &parts, g, fr, 0.0, 2e-4, drilling, 0.0).unwrap();
    // the thick disk's steady precession with G at rest (benchmarks/bench_euler_disk_mujoco.py)
    let (alpha, k) = (0.3_f64, h / (2.0 * r));
    let (ca, sa) = (alpha.cos(), alpha.sin());
    let omega = (m * g * r * (ca - k * sa) / (sa * (a * ca - c * k * sa))).sqrt();
    let psi_dot = -omega * (ca - k * sa);
    let q = quaternion_from_euler(0.0, alpha, 0.0);
    let w = omega_body_from_euler(alpha, 0.0, 0.0, omega, psi_dot);
    let y = top.state(q, w, 0.0, 0.0, None).unwrap();
    let st = Settings {
        t_end,
        rtol,
        atol: rtol * 1e-2,
        ..Settings::default()
    };
    let t0 = Instant::now();
    let out = simulate(&top, &y, &st, &mut [], &mut |_| true).unwrap();
    let flat = out.info.events.iter().find(|e| e.name == "flat");
    println!(
        "{:?} steps {} rejected {} rhs {} events {} flat {:.9}",
        t0.elapsed(),
        out.info.stats.steps,
        out.info.stats.rejected,
        out.info.stats.rhs_evals,
        out.info.events.len(),
        flat.map_or(f64::NAN, |e| e.t)
    );
}
