//! Times benchmark case D1 in the core alone: the shaken, damped L1 top over 100 s.
use kreisel_core::models::heavy_top::driven::{Damping, DrivenTop, Pivot};
use kreisel_core::models::heavy_top::{HeavyTop, RigidState};
use kreisel_core::rotation::{omega_body_from_euler, quaternion_from_euler};
use kreisel_core::simulate::{simulate, Settings};
use std::time::Instant;
fn main() {
    let top = HeavyTop::new(1.0, 1.0, 0.5, 1.0, [0.0, 0.0, 1.0], 1.0).unwrap();
    // FIXED=1: the same top on a fixed pivot (the cost of the pivot's motion apart)
    let pivot = if std::env::var("FIXED").is_ok() {
        Pivot::Fixed
    } else {
        Pivot::harmonic([0.0, 0.0, 0.05], 20.0, [0.0; 3]).unwrap()
    };
    let d = DrivenTop::new(top, pivot, Damping::new(0.01, 0.0, 0.0, 0.0).unwrap()).unwrap();
    let (th, thd, phd, psd) = (1.0, 0.3, 0.7, 9.0);
    let s0 = RigidState::new(
        quaternion_from_euler(0.0, th, 0.0).0,
        omega_body_from_euler(th, 0.0, thd, phd, psd),
    )
    .unwrap();
    let st = Settings {
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
    let mut evals = 0;
    for _ in 0..reps {
        let t0 = Instant::now();
        let out = simulate(&d, &s0, &st, &mut [], &mut |_| true).unwrap();
        best = best.min(t0.elapsed().as_secs_f64());
        evals = out.info.stats.rhs_evals;
        std::hint::black_box(&out);
    }
    println!(
        "D1 core: {:.3} ms, {} rhs evals, {:.1} ns per evaluation",
        best * 1e3,
        evals,
        best * 1e9 / evals as f64
    );
}
