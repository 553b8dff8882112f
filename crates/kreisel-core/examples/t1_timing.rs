//! Times benchmark case T1 in the core alone: the simulation, then the diagnostics columns.
//! With `T1_COULOMB=1`, the Coulomb ball: the same top under Coulomb(0.3) friction, started
//! sliding at vx = 0.2 m/s (its slip, stick and roll phases). With `T1_NO_COLUMNS=1` it
//! skips the columns (the integration alone, with its own allocations).
use kreisel_core::models::play_top::{Friction, PlayTop, DIM};
use kreisel_core::rotation::{omega_body_from_euler, quaternion_from_euler};
use kreisel_core::simulate::{simulate, Settings};
use std::time::Instant;
fn main() {
    let (m, rho, s) = (0.02, 0.02, 0.006);
    let c = 0.4 * m * rho * rho;
    let coulomb = std::env::var("T1_COULOMB").is_ok_and(|v| v == "1");
    let (friction, vx) = if coulomb {
        (Friction::Coulomb { mu: 0.3 }, 0.2)
    } else {
        (Friction::Viscous { mu: 1.0 }, 0.0)
    };
    let top = PlayTop::new(m, 0.8 * c, c, s, rho, 9.81, friction, 0.0, 0.0, 0.0, 0.0).unwrap();
    let th = std::f64::consts::PI - 0.1;
    let q = quaternion_from_euler(0.0, th, 0.0);
    let w = omega_body_from_euler(th, 0.0, 0.0, 0.0, 150.0);
    let y0 = top.state(q, w, vx, 0.0, None).unwrap();
    let st = Settings {
        t_end: 12.0,
        rtol: 1e-9,
        atol: 1e-12,
        ..Settings::default()
    };
    let reps: usize = std::env::var("REPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(20);
    let no_columns = std::env::var("T1_NO_COLUMNS").is_ok_and(|v| v == "1");
    let (mut a, mut b) = (f64::MAX, f64::MAX);
    let mut steps = 0;
    let mut last: [f64; DIM] = y0;
    for _ in 0..reps {
        let t0 = Instant::now();
        let out = simulate(&top, &y0, &st, &mut [], &mut |_| true).unwrap();
        let t1 = Instant::now();
        if !no_columns {
            let c = top.columns(&out.rows).unwrap();
            assert!(c.u.len() == out.t.len());
        }
        let t2 = Instant::now();
        a = a.min((t1 - t0).as_secs_f64());
        b = b.min((t2 - t1).as_secs_f64());
        steps = out.info.stats.steps;
        last = out.rows.last().unwrap().y;
    }
    println!(
        "integrate {:.3} ms, columns {:.3} ms, steps {steps}, final u {:.9}",
        a * 1e3,
        b * 1e3,
        top.kin(&last).e3[2]
    );
}
