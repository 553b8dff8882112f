//! Eigenvalues of a real symmetric tridiagonal matrix: the implicit QL algorithm with
//! Wilkinson's shift (Wilkinson and Reinsch, "Handbook for Automatic Computation II" (1971),
//! contribution II/3 (tql1); Golub and Van Loan, "Matrix Computations", 4th ed., section 8.3).
//!
//! Written here rather than taken from a crate: the maintained Rust linear-algebra crates
//! (nalgebra, faer, ndarray-linalg) either go through LAPACK (a system dependency the wheel
//! does not want) or solve one dense matrix at a time with allocations and a tridiagonal
//! reduction that a matrix already tridiagonal does not need. kreisel solves thousands of small
//! tridiagonal blocks, one per potential strength, each in a reused scratch buffer on its own
//! thread, which is all this routine does.

use crate::error::{KreiselError, Result};

/// Most QL sweeps spent on one eigenvalue (it converges cubically; 2-3 are usual).
const MAX_SWEEPS: u32 = 60;

/// Overwrites `d` (the diagonal, length n) with the eigenvalues in ascending order. `e` holds
/// the off-diagonal, `e[i]` coupling rows i and i+1; it must have length n (its last entry is
/// scratch) and is destroyed.
///
/// The matrix is scaled by a power of two (exact) so that squares of its entries neither
/// overflow nor lose the small ones. Errors: a non-finite entry, or no convergence (not seen
/// for finite input; it would name the row).
pub fn eigenvalues(d: &mut [f64], e: &mut [f64]) -> Result<()> {
    let n = d.len();
    assert_eq!(
        e.len(),
        n,
        "e needs the length of d (its last entry is scratch)"
    );
    if n == 0 {
        return Ok(());
    }
    e[n - 1] = 0.0;
    let mut big = 0.0f64;
    for (&a, &b) in d.iter().zip(e.iter()) {
        if !(a.is_finite() && b.is_finite()) {
            return Err(KreiselError::Numerical(
                "a tridiagonal matrix with a non-finite entry".into(),
            ));
        }
        big = big.max(a.abs()).max(b.abs());
    }
    if big == 0.0 {
        return Ok(());
    }
    // 2^-exponent(big): entries at most 1 in magnitude, exactly representable scaling.
    let scale = 2f64.powi(big.log2().ceil() as i32);
    let inv = 1.0 / scale;
    d.iter_mut().for_each(|x| *x *= inv);
    e.iter_mut().for_each(|x| *x *= inv);

    for l in 0..n {
        let mut sweeps = 0;
        loop {
            // The first negligible coupling at or below row l splits the matrix there.
            let mut m = l;
            while m + 1 < n {
                let near = d[m].abs() + d[m + 1].abs();
                if e[m].abs() <= f64::EPSILON * near || e[m].abs() < f64::MIN_POSITIVE {
                    break;
                }
                m += 1;
            }
            if m == l {
                break;
            }
            sweeps += 1;
            if sweeps > MAX_SWEEPS {
                return Err(KreiselError::Numerical(format!(
                    "the tridiagonal eigenvalue iteration did not converge at row {l} of {n}"
                )));
            }
            ql_sweep(d, e, l, m);
        }
    }
    d.iter_mut().for_each(|x| *x *= scale);
    d.sort_unstable_by(f64::total_cmp);
    Ok(())
}

/// One implicit QL sweep on the unreduced block l..=m, shifted by the eigenvalue of the
/// leading 2x2 block nearer d[l] (Wilkinson): a chain of plane rotations from the bottom up
/// that chases the bulge and leaves the block similar to the original.
#[inline]
fn ql_sweep(d: &mut [f64], e: &mut [f64], l: usize, m: usize) {
    let t = (d[l + 1] - d[l]) / (2.0 * e[l]);
    let root = (t * t + 1.0).sqrt();
    let shifted = e[l] / (t + root.copysign(t));
    let mut g = d[m] - d[l] + shifted;
    let (mut s, mut c, mut p) = (1.0f64, 1.0f64, 0.0f64);
    let mut i = m;
    while i > l {
        i -= 1;
        let f = s * e[i];
        let b = c * e[i];
        let r = (f * f + g * g).sqrt();
        e[i + 1] = r;
        if r == 0.0 {
            // The rotation is the identity: the block has split at row i+1.
            d[i + 1] -= p;
            e[m] = 0.0;
            return;
        }
        let inv = 1.0 / r;
        s = f * inv;
        c = g * inv;
        let h = d[i + 1] - p;
        let q = (d[i] - h) * s + 2.0 * c * b;
        p = s * q;
        d[i + 1] = h + p;
        g = c * q - b;
    }
    d[l] -= p;
    e[l] = g;
    e[m] = 0.0;
}

#[cfg(test)]
mod tests {
    use super::eigenvalues;

    /// The n x n matrix with 2 on the diagonal and -1 beside it has the eigenvalues
    /// 2 - 2 cos(k pi / (n+1)), k = 1..n (the discrete Laplacian).
    #[test]
    fn the_discrete_laplacian_has_its_known_eigenvalues() {
        for n in [1usize, 2, 3, 10, 200] {
            let mut d = vec![2.0; n];
            let mut e = vec![-1.0; n];
            eigenvalues(&mut d, &mut e).unwrap();
            for (k, &x) in d.iter().enumerate() {
                let exact =
                    2.0 - 2.0 * ((k + 1) as f64 * std::f64::consts::PI / (n + 1) as f64).cos();
                assert!((x - exact).abs() < 1e-13, "n {n} k {k}: {x} vs {exact}");
            }
        }
    }

    /// The Wilkinson matrix W21+ has a famous pair of eigenvalues equal to 14 digits
    /// (10.746194182903...), which a sloppy deflation merges or loses.
    #[test]
    fn wilkinsons_matrix_keeps_its_close_pair() {
        let mut d: Vec<f64> = (0..21).map(|i| (10i32 - i).abs() as f64).collect();
        let mut e = vec![1.0; 21];
        eigenvalues(&mut d, &mut e).unwrap();
        let top = d[20];
        let next = d[19];
        assert!((top - 10.746_194_182_903_4).abs() < 1e-12, "{top}");
        assert!((top - next).abs() < 1e-13 && top >= next, "{top} {next}");
        // trace is kept: sum of eigenvalues = sum of the diagonal = 110
        let trace: f64 = d.iter().sum();
        assert!((trace - 110.0).abs() < 1e-11, "{trace}");
    }

    #[test]
    fn huge_and_tiny_entries_neither_overflow_nor_vanish() {
        for scale in [1e-300, 1e-150, 1.0, 1e150, 1e300] {
            let mut d = vec![2.0 * scale; 5];
            let mut e = vec![-scale; 5];
            eigenvalues(&mut d, &mut e).unwrap();
            let lowest = 2.0 - 2.0 * (std::f64::consts::PI / 6.0).cos();
            assert!((d[0] / scale - lowest).abs() < 1e-13, "{scale}: {}", d[0]);
        }
    }

    #[test]
    fn a_non_finite_entry_is_an_error() {
        let mut d = vec![1.0, f64::NAN];
        let mut e = vec![0.5, 0.0];
        assert!(eigenvalues(&mut d, &mut e).is_err());
    }
}
