//! Times the exact Lagrange solution at 10^6 instants (benchmark case X1).
use kreisel_core::models::lagrange::{EulerState, LagrangeExact, LagrangeTop};
use std::time::Instant;

fn main() {
    let top = LagrangeTop::new(1.0, 0.5, 1.0, 1.0, 1.0).unwrap();
    let s = EulerState::new(1.0, 0.0, 0.0, 0.3, 0.7, 9.0).unwrap();
    let n = 1_000_000;
    let t: Vec<f64> = (0..n).map(|i| 500.0 * i as f64 / (n - 1) as f64).collect();
    for _ in 0..3 {
        let t0 = Instant::now();
        let ex = LagrangeExact::new(&top, &s).unwrap();
        let t1 = Instant::now();
        let out = ex.eval_many(&t).unwrap();
        let t2 = Instant::now();
        let mut buf: [Vec<f64>; 6] = std::array::from_fn(|_| vec![0.0; n]);
        let [a, b, c, d, e, f] = &mut buf;
        ex.eval_into(&t, [a, b, c, d, e, f]).unwrap();
        let t3 = Instant::now();
        ex.eval_into(&t, [a, b, c, d, e, f]).unwrap();
        println!("warm buffers, 1 thread: {:?}", t3.elapsed());
        println!(
            "build {:?}  eval_many {:?}  eval_into(1 thread) {:?}  segs {} {}",
            t1 - t0,
            t2 - t1,
            t3 - t2,
            ex.segments(),
            out[1][n - 1]
        );
    }
}
