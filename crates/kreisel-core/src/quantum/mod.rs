//! The quantum symmetric top: the free rotor's levels, and the top in a potential
//! `P cos(theta)` (the heavy symmetric top with P = m g l; a symmetric-top molecule with a
//! dipole mu in a field E along z with P = -mu E, the Stark effect), block by block in the
//! |J K M> basis, and the semiclassical (EBK) levels of the classical Lagrange top.
//!
//! - [`SymmetricTop`]: the moments I1 (perpendicular), I3 (axial) and hbar, validated; free
//!   levels `E(J, K) = hbar^2 J(J+1)/(2 I1) + hbar^2 K^2 (1/(2 I3) - 1/(2 I1))`.
//! - [`SymmetricTop::levels`]: the eigenvalues of the tridiagonal (K, M) block up to J_max for
//!   many strengths at once, in parallel ([`matrix`] for the elements of cos(theta),
//!   [`tridiagonal`] for the eigenvalues).
//! - [`ebk`]: the nutation action of the classical top and the energies that quantise it.
//!
//! Conventions of theory: quantum top. Energies in joules, moments in
//! kg m^2, hbar in J s.

pub mod ebk;
pub mod matrix;
pub mod tridiagonal;

use crate::error::{positive, repr, signed, symmetric_moments, KreiselError, Result};
use rayon::prelude::*;

/// Strengths solved together on one thread ([`tridiagonal::eigenvalues_lanes`]): 8 keeps
/// the divider of an x86-64 core busiest (measured: 4 and 16 are 10-20 % slower).
const LANES: usize = 8;

/// The largest J_max of a block: the eigenvalues cost ~J_max^2 operations per strength (about
/// a second for each strength at this size), and a basis to J = 20000 already holds the
/// pendular states of strengths P ~ 10^7 B.
pub const J_MAX_LIMIT: i64 = 20_000;

/// The most levels one call may return (2^27 numbers, 1 GiB of float64).
pub const MAX_OUTPUT: usize = 1 << 27;

/// A rigid symmetric top (I1 = I2 about the centre of mass or the pivot) in quantum mechanics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SymmetricTop {
    i1: f64,
    i3: f64,
    hbar: f64,
}

impl SymmetricTop {
    /// A top with moments `I1` (about an axis perpendicular to the figure axis) and `I3`
    /// (about it), both in kg m^2, and Planck's reduced constant `hbar` (J s). A rigid body has
    /// `I3 <= 2 I1` (triangle inequality of principal moments).
    pub fn new(i1: f64, i3: f64, hbar: f64) -> Result<Self> {
        symmetric_moments(i1, i3)?;
        positive("hbar", hbar)?;
        let top = SymmetricTop { i1, i3, hbar };
        // hbar^2 / I must be a finite, normal energy scale.
        let b = top.b();
        if !(b.is_finite() && b >= f64::MIN_POSITIVE && (hbar * hbar / (2.0 * i3)).is_finite()) {
            return Err(KreiselError::invalid(
                "hbar",
                hbar,
                format!(
                    "hbar^2 / (2 I1) = {} J must be a finite, normal number for these moments",
                    repr(b)
                ),
            ));
        }
        Ok(top)
    }

    /// I1 (kg m^2).
    pub fn i1(&self) -> f64 {
        self.i1
    }

    /// I3 (kg m^2).
    pub fn i3(&self) -> f64 {
        self.i3
    }

    /// hbar (J s).
    pub fn hbar(&self) -> f64 {
        self.hbar
    }

    /// The energy scale `hbar^2 / (2 I1)` (J): the rotational constant B as an energy.
    pub fn b(&self) -> f64 {
        self.hbar * (self.hbar / (2.0 * self.i1))
    }

    /// `hbar^2 (1/(2 I3) - 1/(2 I1))` (J): the energy of K per K^2, (A - B) or (C - B).
    pub fn k_constant(&self) -> f64 {
        self.hbar * (self.hbar / (2.0 * self.i3)) - self.b()
    }

    /// Free rotor `E(J, K)` (J), for `|K| <= J`.
    pub fn free_energy(&self, j: i64, k: i64) -> Result<f64> {
        check_j("J", j, k, "K")?;
        let (jf, kf) = (j as f64, k as f64);
        Ok(self.b() * jf * (jf + 1.0) + self.k_constant() * kf * kf)
    }

    /// The eigenvalues (J, ascending) of the (K, M) block of `free rotor + P cos(theta)` in
    /// the basis |J K M>, J = max(|K|, |M|) ..= J_max, for every strength P (J) in
    /// `strengths`: row-major, one row of `J_max - max(|K|, |M|) + 1` levels per strength.
    /// Rows are computed in parallel on rayon's pool.
    pub fn levels(&self, k: i64, m: i64, j_max: i64, strengths: &[f64]) -> Result<Vec<f64>> {
        let block = Block::new(self, k, m, j_max, strengths.len())?;
        for (i, &p) in strengths.iter().enumerate() {
            signed(&format!("strength[{i}]"), p)?;
        }
        let n = block.len();
        let mut out = vec![0.0; n * strengths.len()];
        out.par_chunks_mut(n * LANES)
            .zip(strengths.par_chunks(LANES))
            .try_for_each_init(
                || (vec![[0.0; LANES]; n], vec![[0.0; LANES]; n]),
                |(d, e), (rows, ps)| block.eigenvalues_lanes(ps, rows, d, e),
            )?;
        Ok(out)
    }

    /// The dense-free description of one (K, M) block: its diagonal at P = 0 and the elements
    /// of cos(theta) (for checks and for users who want the matrix itself).
    pub fn block(&self, k: i64, m: i64, j_max: i64) -> Result<Block> {
        Block::new(self, k, m, j_max, 1)
    }
}

/// Checks a quantum number `J` against `|K| <= J` (named `k_name`).
fn check_j(j_name: &str, j: i64, k: i64, k_name: &str) -> Result<()> {
    if j < 0 || k.unsigned_abs() > j.unsigned_abs() {
        return Err(KreiselError::InvalidParameter {
            name: j_name.to_string(),
            value: j.to_string(),
            allowed: format!("it must be >= |{k_name}| = {} (and >= 0)", k.unsigned_abs()),
        });
    }
    Ok(())
}

/// One (K, M) block: `H(P) = diag(free) + P (diag(cos_diag) + offdiag(cos_off))`.
#[derive(Debug, Clone, PartialEq)]
pub struct Block {
    /// First J of the block, `max(|K|, |M|)`.
    pub j_min: i64,
    /// Free-rotor energies (J) at J = j_min ..= J_max.
    pub free: Vec<f64>,
    /// `<J K M| cos(theta) |J K M>` at each J.
    pub cos_diag: Vec<f64>,
    /// `<J+1 K M| cos(theta) |J K M>` for J = j_min ..< J_max (one fewer).
    pub cos_off: Vec<f64>,
}

impl Block {
    fn new(top: &SymmetricTop, k: i64, m: i64, j_max: i64, rows: usize) -> Result<Self> {
        let lim = (i64::MAX / 4) as u64;
        for (name, q) in [("K", k), ("M", m)] {
            if q.unsigned_abs() > lim.min(J_MAX_LIMIT as u64) {
                return Err(KreiselError::InvalidParameter {
                    name: name.into(),
                    value: q.to_string(),
                    allowed: format!("|{name}| must be at most J_max's limit {J_MAX_LIMIT}"),
                });
            }
        }
        let j_min = k.abs().max(m.abs());
        if j_max < j_min {
            return Err(KreiselError::InvalidParameter {
                name: "J_max".into(),
                value: j_max.to_string(),
                allowed: format!(
                    "it must be >= max(|K|, |M|) = {j_min}: the block (K = {k}, M = {m}) starts \
                     at J = {j_min}"
                ),
            });
        }
        if j_max > J_MAX_LIMIT {
            return Err(KreiselError::InvalidParameter {
                name: "J_max".into(),
                value: j_max.to_string(),
                allowed: format!(
                    "it must be at most {J_MAX_LIMIT} (the eigenvalues cost ~J_max^2 operations \
                     per strength)"
                ),
            });
        }
        let n = (j_max - j_min + 1) as usize;
        if n.saturating_mul(rows.max(1)) > MAX_OUTPUT {
            return Err(KreiselError::InvalidParameter {
                name: "J_max".into(),
                value: j_max.to_string(),
                allowed: format!(
                    "{rows} strengths x {n} levels = {} numbers do not fit in memory: at most \
                     {MAX_OUTPUT} (1 GiB) per call, so J_max <= {} for this many strengths",
                    (n as u128) * (rows as u128),
                    j_min + (MAX_OUTPUT / rows.max(1)) as i64 - 1
                ),
            });
        }
        let (b, kc, kf) = (top.b(), top.k_constant(), k as f64);
        let js = j_min..=j_max;
        Ok(Block {
            j_min,
            free: js
                .clone()
                .map(|j| b * (j as f64) * (j as f64 + 1.0) + kc * kf * kf)
                .collect(),
            cos_diag: js.clone().map(|j| matrix::cos_diagonal(j, k, m)).collect(),
            cos_off: (j_min..j_max)
                .map(|j| matrix::cos_off_diagonal(j, k, m))
                .collect(),
        })
    }

    /// Number of levels, `J_max - j_min + 1`.
    pub fn len(&self) -> usize {
        self.free.len()
    }

    /// Never empty (J_max >= j_min).
    pub fn is_empty(&self) -> bool {
        self.free.is_empty()
    }

    /// Eigenvalues at up to [`LANES`] strengths `ps` into `rows` (one row of [`Block::len`]
    /// after the other), in lock step; `d`, `e` are scratch of [`Block::len`] lanes.
    fn eigenvalues_lanes(
        &self,
        ps: &[f64],
        rows: &mut [f64],
        d: &mut [[f64; LANES]],
        e: &mut [[f64; LANES]],
    ) -> Result<()> {
        let n = self.len();
        // Short batches repeat their last strength in the idle lanes.
        let lane_p: [f64; LANES] = std::array::from_fn(|j| ps[j.min(ps.len() - 1)]);
        for i in 0..n {
            let off = self.cos_off.get(i).copied().unwrap_or(0.0);
            d[i] = lane_p.map(|p| self.free[i] + p * self.cos_diag[i]);
            e[i] = lane_p.map(|p| p * off);
        }
        tridiagonal::eigenvalues_lanes(d, e)?;
        for (j, row) in rows.chunks_mut(n).enumerate() {
            for (i, x) in row.iter_mut().enumerate() {
                *x = d[i][j];
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const HBAR: f64 = 1.0;

    #[test]
    fn without_a_potential_the_levels_are_the_free_rotors() {
        let top = SymmetricTop::new(2.0, 1.5, HBAR).unwrap();
        let lv = top.levels(2, -1, 9, &[0.0]).unwrap();
        for (i, &e) in lv.iter().enumerate() {
            let j = 2 + i as i64;
            assert!((e - top.free_energy(j, 2).unwrap()).abs() < 1e-14 * e.abs().max(1.0));
        }
    }

    #[test]
    fn bad_input_names_the_parameter() {
        let err = SymmetricTop::new(1.0, 2.5, HBAR).unwrap_err().to_string();
        assert!(err.starts_with("I3 = 2.5 is not allowed"), "{err}");
        assert!(SymmetricTop::new(-1.0, 1.0, HBAR).is_err());
        let top = SymmetricTop::new(1.0, 1.0, HBAR).unwrap();
        let err = top.levels(3, 1, 2, &[0.0]).unwrap_err().to_string();
        assert!(err.starts_with("J_max = 2 is not allowed"), "{err}");
        let err = top
            .levels(0, 0, 3, &[1.0, f64::NAN])
            .unwrap_err()
            .to_string();
        assert!(err.starts_with("strength[1] = nan"), "{err}");
        let err = top.free_energy(2, 3).unwrap_err().to_string();
        assert!(err.starts_with("J = 2 is not allowed"), "{err}");
        let err = top
            .levels(0, 0, 19_000, &vec![0.0; 10_000])
            .unwrap_err()
            .to_string();
        assert!(err.contains("do not fit in memory"), "{err}");
    }

    #[test]
    fn blocks_with_opposite_signs_of_k_m_mirror_in_the_strength() {
        // cos(theta) -> its diagonal changes sign with K M; the spectrum of (K, -M) at P is
        // that of (K, M) at -P.
        let top = SymmetricTop::new(1.0, 0.7, HBAR).unwrap();
        let a = top.levels(2, 1, 30, &[3.0]).unwrap();
        let b = top.levels(2, -1, 30, &[-3.0]).unwrap();
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() < 1e-12 * x.abs().max(1.0));
        }
    }
}
