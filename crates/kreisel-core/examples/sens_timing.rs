//! Times a heavy-top run with forward sensitivities against the same run without, in the
//! core alone: a general heavy top (asymmetric, centre of mass off every axis) over 100 s at
//! rtol = 1e-10, every step kept.
//!
//! `cargo run --release --example sens_timing` prints the best of `REPS` (default 20) runs
//! of each, their counters, and checks that the runs with sensitivities keep the plain run's
//! times and states bit for bit.
use kreisel_core::models::heavy_top::sensitivity::{simulate_with_sensitivities, Sensitivities};
use kreisel_core::models::heavy_top::{HeavyTop, RigidState};
use kreisel_core::rotation::{omega_body_from_euler, quaternion_from_euler};
use kreisel_core::simulate::{simulate, Settings};
use std::time::Instant;

fn main() {
    let top = HeavyTop::new(1.0, 0.75, 0.5, 1.0, [0.3, 0.2, 0.4], 9.81).unwrap();
    let (theta, phi, psi) = (0.8, 0.3, -0.4);
    let (theta_dot, phi_dot, psi_dot) = (0.5, 1.0, 8.0);
    let s0 = RigidState {
        q: quaternion_from_euler(phi, theta, psi),
        omega: omega_body_from_euler(theta, psi, theta_dot, phi_dot, psi_dot),
    };
    let euler = [theta, phi, psi, theta_dot, phi_dot, psi_dot];
    let st = Settings {
        method: "dop853".into(),
        t_end: 100.0,
        rtol: 1e-10,
        atol: 1e-12,
        ..Settings::default()
    };
    let reps: usize = std::env::var("REPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(20);
    let mut best = f64::MAX;
    let mut plain = None;
    for _ in 0..reps {
        let t0 = Instant::now();
        let out = simulate(&top, &s0, &st, &mut [], &mut |_| true).unwrap();
        best = best.min(t0.elapsed().as_secs_f64());
        plain = Some(out);
    }
    let plain = plain.unwrap();
    println!("plain: {:.3} ms, {:?}", best * 1e3, plain.info.stats);
    let all = [
        "I1",
        "I2",
        "I3",
        "m",
        "g",
        "com[0]",
        "com[1]",
        "com[2]",
        "theta",
        "phi",
        "psi",
        "theta_dot",
        "phi_dot",
        "psi_dot",
    ];
    for k in [1, 5, 14] {
        let names: Vec<String> = all[..k].iter().map(|s| s.to_string()).collect();
        let sens = Sensitivities::new(&names, false, false, Some(euler)).unwrap();
        let mut b = f64::MAX;
        let mut last = None;
        for _ in 0..reps {
            let t0 = Instant::now();
            let out = simulate_with_sensitivities(&top, &s0, &st, &sens, &mut |_| true).unwrap();
            b = b.min(t0.elapsed().as_secs_f64());
            last = Some(out);
        }
        let out = last.unwrap();
        let same = out.t == plain.t && out.rows == plain.rows;
        println!(
            "{k:2} sensitivities: {:.3} ms ({:.2} x plain), {:?}, same trajectory: {same}",
            b * 1e3,
            b / best,
            out.info.stats
        );
    }
}
