//! Times the exact Lagrange solution at 10^6 instants (benchmark case X1); prints the best
//! of 15 repetitions (this machine's timings are noisy).
use kreisel_core::models::lagrange::{EulerState, LagrangeExact, LagrangeTop};
use std::time::Instant;

fn main() {
    let top = LagrangeTop::new(1.0, 0.5, 1.0, 1.0, 1.0).unwrap();
    let s = EulerState::new(1.0, 0.0, 0.0, 0.3, 0.7, 9.0).unwrap();
    let n = 1_000_000;
    let t: Vec<f64> = (0..n).map(|i| 500.0 * i as f64 / (n - 1) as f64).collect();
    let mut buf: [Vec<f64>; 6] = std::array::from_fn(|_| vec![0.0; n]);
    let (mut build, mut many, mut warm) = (f64::MAX, f64::MAX, f64::MAX);
    let mut segs = 0;
    for _ in 0..15 {
        let t0 = Instant::now();
        let ex = LagrangeExact::new(&top, &s).unwrap();
        build = build.min(t0.elapsed().as_secs_f64());
        let t1 = Instant::now();
        let out = ex.eval_many(&t).unwrap();
        many = many.min(t1.elapsed().as_secs_f64());
        drop(out);
        let [a, b, c, d, e, f] = &mut buf;
        let t2 = Instant::now();
        ex.eval_into(&t, [a, b, c, d, e, f]).unwrap();
        warm = warm.min(t2.elapsed().as_secs_f64());
        segs = ex.segments();
    }
    println!(
        "best of 15: build {:.3} ms, eval_many (all cores, fresh output) {:.2} ms, \
         eval_into (1 thread, warm output) {:.2} ms, {segs} segments",
        build * 1e3,
        many * 1e3,
        warm * 1e3
    );
}
