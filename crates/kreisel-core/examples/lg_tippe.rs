//! Leine and Glocker's tippe top (theory: bodies of revolution): a two-sphere top under
//! Coulomb-Contensou friction, printed as it turns over. `cargo run --release --example
//! lg_tippe [R] [t_end] [rtol]` (R the patch radius, 0: plain Coulomb).
use kreisel_core::models::play_top::{Friction, PlayTop, Shape};
use kreisel_core::rotation::{omega_body_from_euler, quaternion_from_euler, Quat};
use kreisel_core::simulate::{simulate, EventDef, EventKind, Settings};
fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse().unwrap())
        .collect();
    let radius = args.first().copied().unwrap_or(5e-4);
    let t_end = args.get(1).copied().unwrap_or(8.0);
    let rtol = args.get(2).copied().unwrap_or(1e-8);
    let parts = [
        Shape::Sphere {
            radius: 0.015,
            z: -0.003,
        },
        Shape::Sphere {
            radius: 0.005,
            z: -0.016,
        },
    ];
    let fr = Friction::coulomb_contensou(0.3, radius).unwrap();
    let top = PlayTop::with_parts(6e-3, 8e-7, 7e-7, &parts, 9.81, fr, 0.0, 0.0, 0.0, 0.0).unwrap();
    let th = std::f64::consts::PI - 0.1;
    let q: Quat = quaternion_from_euler(0.0, th, 0.0);
    let w = omega_body_from_euler(th, 0.0, 0.0, 0.0, 180.0);
    let y = top.state(q, w, 0.0, 0.0, None).unwrap();
    let st = Settings {
        t_end,
        rtol,
        atol: rtol * 1e-3,
        t_eval: Some(
            (0..=(t_end * 10.0) as usize)
                .map(|i| i as f64 * 0.1)
                .collect(),
        ),
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
    println!("time {:?} steps {}", t0.elapsed(), out.info.stats.steps);
    for e in out.info.events.iter().take(40) {
        println!("  {:>12} part {:?} t={:.6}", e.name, e.part, e.t);
    }
    println!("  ... {} events", out.info.events.len());
    let cols = top.columns(&out.rows).unwrap();
    for (i, t) in out.t.iter().enumerate() {
        let e = cols.energy_parts[i];
        println!(
            "{t:5.2} u={:+.5} E={:.9e} E+D={:.9e} parts={:?} N={:.3e},{:.3e} w3={:.2}",
            cols.u[i],
            e[0] + e[1] + e[2],
            e[0] + e[1] + e[2] + out.rows[i].y[13],
            cols.part_in_contact.row(i),
            cols.part_normal_force.row(i)[0],
            cols.part_normal_force.row(i)[1],
            out.rows[i].y[6],
        );
    }
}
