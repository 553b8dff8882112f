//! Times benchmark case T3 in the core alone (kreisel's side): MuJoCo's tutorial tippe top as
//! two spheres under Coulomb-Contensou friction, 7 s. `cargo run --release --example
//! t3_timing [rtol]`; under `valgrind --tool=callgrind` it counts instructions. With
//! `T3_EVENTS=1` it prints the events (name, part, time) before the counts.
use kreisel_core::models::play_top::{Friction, PlayTop, Shape};
use kreisel_core::rotation::{omega_body_from_euler, quaternion_from_euler};
use kreisel_core::simulate::{simulate, Settings};
use std::time::Instant;
fn main() {
    let rtol: f64 = std::env::args()
        .nth(1)
        .map_or(1e-10, |a| a.parse().unwrap());
    let (m, s, a, c) = (0.05574265, 0.005309281, 1.29335e-05, 1.28322e-05);
    let patch = 8.8e-5 * 16.0 / (3.0 * std::f64::consts::PI * 0.3);
    let parts = [
        Shape::Sphere {
            radius: 0.02,
            z: -s,
        },
        Shape::Sphere {
            radius: 0.004,
            z: -(s + 0.028),
        },
    ];
    let fr = Friction::coulomb_contensou(0.3, patch).unwrap();
    let top = PlayTop::with_parts(m, a, c, &parts, 9.81, fr, 0.0, 0.0, 0.0, 0.0).unwrap();
    let pi = std::f64::consts::PI;
    let q = quaternion_from_euler(pi / 2.0, pi, pi / 2.0);
    let w = omega_body_from_euler(pi, pi / 2.0, 1.0, 0.0, -200.0);
    let y = top.state(q, w, 0.0, 0.0, None).unwrap();
    let st = Settings {
        t_end: 7.0,
        rtol,
        atol: rtol * 1e-2,
        ..Settings::default()
    };
    let t0 = Instant::now();
    let out = simulate(&top, &y, &st, &mut [], &mut |_| true).unwrap();
    if std::env::var("T3_EVENTS").is_ok() {
        for e in &out.info.events {
            println!("{} {:?} {:.6}", e.name, e.part, e.t);
        }
    }
    println!(
        "{:?} steps {} rhs {} events {}",
        t0.elapsed(),
        out.info.stats.steps,
        out.info.stats.rhs_evals,
        out.info.events.len()
    );
}
