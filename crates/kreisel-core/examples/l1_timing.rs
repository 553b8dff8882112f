//! Times benchmark case L1 in the core alone: integration, then the diagnostics columns.
//!
//! `cargo run --release --example l1_timing` prints the best of `REPS` (default 20) runs,
//! the run's counters and a checksum of every bit of its output (times, states, columns),
//! so that two builds can be compared for identical results; with `REPS=5` it is small
//! enough to profile under `valgrind --tool=callgrind`.
use kreisel_core::models::heavy_top::HeavyTop;
use kreisel_core::models::heavy_top::RigidState;
use kreisel_core::models::lagrange::LagrangeTop;
use kreisel_core::rotation::{omega_body_from_euler, quaternion_from_euler};
use kreisel_core::simulate::{simulate, Settings};
use std::time::Instant;

/// FNV-1a over the bits of a sequence of floats.
fn checksum<'a>(xs: impl IntoIterator<Item = &'a f64>) -> u64 {
    xs.into_iter().fold(0xcbf2_9ce4_8422_2325, |h, x| {
        (h ^ x.to_bits()).wrapping_mul(0x0100_0000_01b3)
    })
}

fn main() {
    let top = HeavyTop::from_lagrange(&LagrangeTop::new(1.0, 0.5, 1.0, 1.0, 1.0).unwrap());
    let s0 = RigidState {
        q: quaternion_from_euler(0.0, 1.0, 0.0),
        omega: omega_body_from_euler(1.0, 0.0, 0.3, 0.7, 9.0),
    };
    let st = Settings {
        method: "dop853".into(),
        t_end: 100.0,
        rtol: 1e-10,
        atol: 1e-12,
        ..Settings::default()
    };
    let (mut a, mut b) = (f64::MAX, f64::MAX);
    let reps: usize = std::env::var("REPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(20);
    let mut last = None;
    for _ in 0..reps {
        let t0 = Instant::now();
        let out = simulate(&top, &s0, &st, &mut [], &mut |_| true).unwrap();
        let t1 = Instant::now();
        let c = top.columns(&out.rows);
        let t2 = Instant::now();
        a = a.min((t1 - t0).as_secs_f64());
        b = b.min((t2 - t1).as_secs_f64());
        assert!(c.theta.len() == out.t.len());
        last = Some((out, c));
    }
    println!("integrate {:.3} ms, columns {:.3} ms", a * 1e3, b * 1e3);
    if let Some((out, c)) = last {
        let states = out.rows.iter().flat_map(|s| s.q.0.iter().chain(&s.omega));
        let cols = [&c.theta, &c.phi, &c.psi, &c.energy, &c.mz];
        let m3 = c.m3.iter().flatten();
        println!(
            "{:?}, checksum: states {:016x}, columns {:016x}",
            out.info.stats,
            checksum(out.t.iter().chain(states)),
            checksum(cols.into_iter().flatten().chain(m3)),
        );
    }
}
