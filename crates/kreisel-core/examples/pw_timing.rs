use kreisel_core::special::chebyshev::Piecewise;
use std::time::Instant;
fn main() {
    let p = Piecewise::<6>::build(
        0.0,
        2.0,
        |x| Ok([x.sin(), x.cos(), x.exp(), x, x * x, (2.0 * x).sin()]),
        1e-14,
        20,
    )
    .unwrap();
    println!("segs {}", p.segments());
    let n = 1_000_000;
    let xs: Vec<f64> = (0..n)
        .map(|i| 2.0 * ((i as f64 * 0.618034) % 1.0))
        .collect();
    for _ in 0..3 {
        let t0 = Instant::now();
        let mut acc = 0.0;
        for &x in &xs {
            let v = p.eval(x);
            acc += v[0] + v[3] + v[5];
        }
        println!("{:?} {}", t0.elapsed(), acc);
    }
}
