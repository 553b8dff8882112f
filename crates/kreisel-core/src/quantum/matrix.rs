//! The matrix elements of cos(theta) between symmetric-top states |J K M>, in closed form.
//!
//! `cos(theta)` is the direction cosine of the figure axis with the space z axis, the
//! component `Phi_zz` of the direction-cosine matrix. Its elements diagonal in K and M are
//! (the direction-cosine matrix elements of the symmetric top: Townes and Schawlow, "Microwave
//! Spectroscopy" (1955), ch. 4; Gordy and Cook, "Microwave Molecular Spectra" (1984), ch. 2;
//! Zare, "Angular Momentum" (1988), ch. 3, as a product of two Clebsch-Gordan coefficients):
//!
//! ```text
//!     <J K M| cos(theta) |J K M>     = K M / (J (J+1))                       (J > 0; 0 for J = 0)
//!     <J+1 K M| cos(theta) |J K M>   = sqrt(((J+1)^2 - K^2) ((J+1)^2 - M^2))
//!                                      / ((J+1) sqrt((2J+1) (2J+3)))
//! ```
//!
//! and zero for |J' - J| > 1: cos(theta) = D^1_00 is a rank-one tensor, so a potential
//! `P cos(theta)` couples J only to J and J +- 1 at fixed K and M, and each (K, M) block of the
//! Hamiltonian is tridiagonal in J. The phase convention (the sign of the off-diagonal
//! element) does not change the eigenvalues of a tridiagonal matrix, which depend only on the
//! squares of its off-diagonal elements. `tests/test_quantum.py` checks both formulas against
//! a quadrature of Wigner's d-functions, with nothing shared with this file.

/// `<J K M| cos(theta) |J K M>` (0 at J = 0, where K = M = 0).
#[inline]
pub fn cos_diagonal(j: i64, k: i64, m: i64) -> f64 {
    if j == 0 {
        return 0.0;
    }
    let jf = j as f64;
    (k as f64) * (m as f64) / (jf * (jf + 1.0))
}

/// `<J+1 K M| cos(theta) |J K M>` for `J >= max(|K|, |M|)` (>= 0 in the usual phases).
#[inline]
pub fn cos_off_diagonal(j: i64, k: i64, m: i64) -> f64 {
    let j1 = (j + 1) as f64;
    let (kf, mf) = (k as f64, m as f64);
    let num = ((j1 * j1 - kf * kf) * (j1 * j1 - mf * mf)).max(0.0).sqrt();
    let jf = j as f64;
    num / (j1 * ((2.0 * jf + 1.0) * (2.0 * jf + 3.0)).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sum rule of a direction cosine: summed over the states it reaches,
    /// |<J' K M|cos|J K M>|^2 = <J K M|cos^2|J K M>, and averaged over M, cos^2 averages to 1/3
    /// (isotropy): sum over M and J' of the squares = (2J+1)/3.
    #[test]
    fn the_squares_of_the_elements_average_to_one_third_over_m() {
        for j in 0..12i64 {
            for k in -j..=j {
                let mut total = 0.0;
                for m in -j..=j {
                    let down = if j > k.abs().max(m.abs()) {
                        cos_off_diagonal(j - 1, k, m).powi(2)
                    } else {
                        0.0
                    };
                    total +=
                        cos_diagonal(j, k, m).powi(2) + cos_off_diagonal(j, k, m).powi(2) + down;
                }
                let expect = (2 * j + 1) as f64 / 3.0;
                assert!(
                    (total - expect).abs() < 1e-12 * expect,
                    "J {j} K {k}: {total} vs {expect}"
                );
            }
        }
    }

    #[test]
    fn the_element_vanishes_where_the_upper_state_does_not_exist() {
        // J = 2, K = 3: |J+1 K M> = |3 3 M> exists, |2 3 M> does not; the element from
        // J = |K| - 1 to |K| is zero (the block starts at J = max(|K|, |M|)).
        assert_eq!(cos_off_diagonal(2, 3, 0), 0.0);
        assert!(cos_off_diagonal(3, 3, 0) > 0.0);
    }
}
