//! Eigenvalues of a real symmetric tridiagonal matrix: the implicit QL algorithm with
//! Wilkinson's shift (Golub and Van Loan, "Matrix Computations", 4th ed., section 8.3) in the
//! root-free form of Pal, Walker and Kahan, which carries the squares of the off-diagonal
//! elements and needs no square root per rotation (Parlett, "The Symmetric Eigenvalue
//! Problem" (1998), section 8.15; LAPACK's dsterf).
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
    assert_eq!(
        e.len(),
        d.len(),
        "e needs the length of d (its last entry is scratch)"
    );
    let mut dl: Vec<[f64; 1]> = d.iter().map(|&x| [x]).collect();
    let mut el: Vec<[f64; 1]> = e.iter().map(|&x| [x]).collect();
    eigenvalues_lanes(&mut dl, &mut el)?;
    for (x, [y]) in d.iter_mut().zip(dl) {
        *x = y;
    }
    Ok(())
}

/// [`eigenvalues`] for `L` matrices of one size at once, in lock step: `d[i][lane]`,
/// `e[i][lane]` (the same layout as there, lane by lane). Each lane's eigenvalues end up in
/// `d[..][lane]`, ascending.
///
/// Why: one QL sweep is a chain of plane rotations, each waiting for the last (a square root
/// and a division deep), so a single matrix leaves the floating-point units idle most of the
/// time. Sweeping `L` independent matrices together turns the chain into `L` chains the
/// processor runs side by side (and in SIMD registers): several times the throughput. The
/// sweeps at row l go on until every lane's coupling there is negligible; a lane that is done
/// computes the sweep but keeps its matrix. So each lane goes through exactly the arithmetic
/// it would go through alone: the eigenvalues of a matrix do not depend on its neighbours,
/// bit for bit.
pub fn eigenvalues_lanes<const L: usize>(d: &mut [[f64; L]], e: &mut [[f64; L]]) -> Result<()> {
    let n = d.len();
    assert_eq!(
        e.len(),
        n,
        "e needs the length of d (its last entry is scratch)"
    );
    if n == 0 {
        return Ok(());
    }
    e[n - 1] = [0.0; L];
    let mut scale = [1.0f64; L];
    for lane in 0..L {
        let mut big = 0.0f64;
        for i in 0..n {
            let (a, b) = (d[i][lane], e[i][lane]);
            if !(a.is_finite() && b.is_finite()) {
                return Err(KreiselError::Numerical(
                    "a tridiagonal matrix with a non-finite entry".into(),
                ));
            }
            big = big.max(a.abs()).max(b.abs());
        }
        if big > 0.0 {
            scale[lane] = 2f64.powi(big.log2().ceil() as i32);
        }
    }
    // From here on e holds the squares of the (scaled) off-diagonal elements.
    let inv = scale.map(|s| 1.0 / s);
    for i in 0..n {
        for lane in 0..L {
            d[i][lane] *= inv[lane];
            let x = e[i][lane] * inv[lane];
            e[i][lane] = x * x;
        }
    }
    let m = n - 1;
    for l in 0..m {
        let mut sweeps = 0;
        loop {
            let mut done = [false; L];
            for lane in 0..L {
                let near = f64::EPSILON * (d[l][lane].abs() + d[l + 1][lane].abs());
                let e2 = e[l][lane];
                done[lane] = e2 <= near * near || e2 < f64::MIN_POSITIVE;
            }
            if done.iter().all(|&x| x) {
                break;
            }
            sweeps += 1;
            if sweeps > MAX_SWEEPS {
                return Err(KreiselError::Numerical(format!(
                    "the tridiagonal eigenvalue iteration did not converge at row {l} of {n}"
                )));
            }
            ql_sweep_lanes(d, e, l, m, &done);
        }
    }
    for lane in 0..L {
        let mut col: Vec<f64> = (0..n).map(|i| d[i][lane] * scale[lane]).collect();
        col.sort_unstable_by(f64::total_cmp);
        for (i, x) in col.into_iter().enumerate() {
            d[i][lane] = x;
        }
    }
    Ok(())
}

/// One implicit QL sweep on rows l..=m of every lane (e: squared off-diagonal), shifted by
/// the eigenvalue of the leading 2x2 block nearer d[l] (Wilkinson): a chain of plane
/// rotations from the bottom up that chases the bulge and leaves each lane's matrix similar to
/// what it was. Lanes marked `done` compute the sweep but keep their matrix.
///
/// In the root-free form a rotation is known by c^2 = p / (p + e^2) and s^2 = e^2 / (p + e^2),
/// and the next p is gamma^2 / c^2: both come from the one reciprocal 1 / ((p + e^2) p), so a
/// rotation costs a single division.
#[inline]
fn ql_sweep_lanes<const L: usize>(
    d: &mut [[f64; L]],
    e: &mut [[f64; L]],
    l: usize,
    m: usize,
    done: &[bool; L],
) {
    let mut sigma = [0.0f64; L];
    for lane in 0..L {
        sigma[lane] = if done[lane] {
            d[l][lane]
        } else {
            let root_e = e[l][lane].sqrt();
            let t = (d[l + 1][lane] - d[l][lane]) / (2.0 * root_e);
            let r = (t * t + 1.0).sqrt();
            d[l][lane] - root_e / (t + r.copysign(t))
        };
    }
    let mut gamma = [0.0f64; L];
    let mut p = [0.0f64; L];
    for lane in 0..L {
        gamma[lane] = d[m][lane] - sigma[lane];
        p[lane] = gamma[lane] * gamma[lane];
    }
    let (mut c, mut s) = ([1.0f64; L], [0.0f64; L]);
    for i in (l..m).rev() {
        let (ei, di) = (e[i], d[i]);
        let (mut e1, mut d1) = (e[i + 1], d[i + 1]);
        for lane in 0..L {
            let bb = ei[lane];
            let r = p[lane] + bb;
            // e[m] is scratch, so the first step may write it too.
            let new_e = s[lane] * r;
            let old_c = c[lane];
            let prod = r * p[lane];
            let ok = prod >= f64::MIN_POSITIVE;
            let inv = 1.0 / if ok { prod } else { 1.0 };
            // p = 0 (a zero bulge): c = 0, s = 1; p = e^2 = 0 as well: any rotation, take 1.
            let (c_new, s_new) = if ok {
                (p[lane] * p[lane] * inv, bb * p[lane] * inv)
            } else if r > 0.0 {
                (0.0, 1.0)
            } else {
                (1.0, 0.0)
            };
            c[lane] = c_new;
            s[lane] = s_new;
            let old_gamma = gamma[lane];
            let alpha = di[lane];
            let g = c_new * (alpha - sigma[lane]) - s_new * old_gamma;
            gamma[lane] = g;
            let new_d = old_gamma + (alpha - g);
            if !done[lane] {
                d1[lane] = new_d;
                e1[lane] = new_e;
            }
            p[lane] = if ok {
                g * g * (r * r * inv)
            } else if r > 0.0 {
                old_c * bb
            } else {
                g * g
            };
        }
        e[i + 1] = e1;
        d[i + 1] = d1;
    }
    for lane in 0..L {
        if !done[lane] {
            e[l][lane] = s[lane] * p[lane];
            d[l][lane] = sigma[lane] + gamma[lane];
        }
        e[m][lane] = 0.0;
    }
}

#[cfg(test)]
mod tests {
    use super::{eigenvalues, eigenvalues_lanes};

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

    /// Lanes solved together give each matrix's eigenvalues bit for bit as alone, although
    /// they need different numbers of sweeps (here one lane is already diagonal).
    #[test]
    fn lanes_do_not_disturb_one_another() {
        let n = 40;
        let mut d = vec![[0.0f64; 4]; n];
        let mut e = vec![[0.0f64; 4]; n];
        for i in 0..n {
            for (lane, p) in [0.0, 0.3, 7.0, -120.0].into_iter().enumerate() {
                d[i][lane] = (i * (i + 1)) as f64 + 0.1 * p;
                e[i][lane] = p * (1.0 + (i as f64).sin()) / 2.0;
            }
        }
        let alone: Vec<Vec<f64>> = (0..4)
            .map(|lane| {
                let mut dl: Vec<f64> = d.iter().map(|r| r[lane]).collect();
                let mut el: Vec<f64> = e.iter().map(|r| r[lane]).collect();
                eigenvalues(&mut dl, &mut el).unwrap();
                dl
            })
            .collect();
        eigenvalues_lanes(&mut d, &mut e).unwrap();
        for (lane, ref_lane) in alone.iter().enumerate() {
            for i in 0..n {
                assert_eq!(
                    d[i][lane].to_bits(),
                    ref_lane[i].to_bits(),
                    "lane {lane} row {i}"
                );
            }
        }
    }

    #[test]
    fn a_non_finite_entry_is_an_error() {
        let mut d = vec![1.0, f64::NAN];
        let mut e = vec![0.5, 0.0];
        assert!(eigenvalues(&mut d, &mut e).is_err());
    }
}
