use kreisel_core::models::play_top::{Friction, PlayTop, DIM};
use kreisel_core::rotation::{omega_body_from_euler, quaternion_from_euler};
use kreisel_core::simulate::{simulate, EventDef, EventKind, Settings};
fn main() {
    let (m, rho, s) = (0.02, 0.02, 0.006);
    let c = 0.4 * m * rho * rho;
    let args: Vec<String> = std::env::args().collect();
    let fr = if args.len() > 1 && args[1] == "coulomb" {
        Friction::Coulomb { mu: 0.3 }
    } else {
        Friction::Viscous { mu: 1.0 }
    };
    let top = PlayTop::new(m, 0.8 * c, c, s, rho, 9.81, fr, 0.0, 0.0, 0.0, 0.0).unwrap();
    let th = std::f64::consts::PI - 0.1;
    let q = quaternion_from_euler(0.0, th, 0.0);
    let w = omega_body_from_euler(th, 0.0, 0.0, 0.0, 150.0);
    let mut y = [0.0; DIM];
    y[..4].copy_from_slice(&q.0);
    y[4..7].copy_from_slice(&w);
    y[9] = rho + s * th.cos();
    let st = Settings {
        t_end: 12.0,
        rtol: 1e-9,
        atol: 1e-12,
        t_eval: Some((0..=24).map(|i| i as f64 * 0.5).collect()),
        events: vec![EventDef {
            name: "inversion".into(),
            kind: EventKind::Inversion(0.9),
            direction: 1,
            terminal: false,
        }],
        ..Settings::default()
    };
    let t0 = std::time::Instant::now();
    let out = simulate(&top, &y, &st, &mut [], &mut |_| true).unwrap();
    println!(
        "time {:?} steps {} events {:?}",
        t0.elapsed(),
        out.info.stats.steps,
        &out.info.events[..out.info.events.len().min(12)]
    );
    let j0 = top.jellett(&out.rows[0].y);
    for (t, row) in out.t.iter().zip(&out.rows) {
        let (yy, md) = (&row.y, &row.mode());
        let (a, b, cc) = top.energy_parts(yy);
        println!(
            "{t:5.2} u={:+.5} J rel={:+.2e} E+D={:.12e} mode={:?} N={:.4e}",
            top.kin(yy).e3[2],
            (top.jellett(yy) - j0) / j0,
            a + b + cc + yy[13],
            md,
            {
                let mut dy = [0.0; DIM];
                top.dynamics(&row.contacts, yy, &mut dy)
                    .n
                    .iter()
                    .sum::<f64>()
            }
        );
    }
}
