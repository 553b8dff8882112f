//! Semiclassical (Einstein-Brillouin-Keller) levels of the Lagrange top in a potential
//! `P cos(theta)`, from the actions of its exact classical solution.
//!
//! The classical top has three actions: `Mz` (conjugate to phi), `M3` (to psi) and the
//! nutation action `(1/2 pi) closed-integral p_theta d theta`. EBK quantisation sets
//! `Mz = M hbar`, `M3 = K hbar` (rotations: no Maslov phase) and the nutation action to
//! `(n + 1/2) hbar` (two simple turning points), and solves the last for the energy
//! (Keller, Ann. Phys. 4 (1958) 180; for the symmetric top, e.g. Child, "Semiclassical
//! Mechanics with Molecular Applications" (2014), ch. 5 and 9). For the free top it gives
//! `E = hbar^2 (J + 1/2)^2 / (2 I1) + ...` with J = n + max(|K|, |M|): quantum mechanics
//! shifted by `hbar^2 / (8 I1)`, relatively ~1/(4 J^2).
//!
//! The action is the exact classical solution's, in closed form. With `u = cos(theta)`,
//! energies in units of `B = hbar^2/(2 I1)` (`eps = (E - K^2 hbar^2/(2 I3)) / B`, `p = P / B`)
//! and momenta in units of hbar, the gyro function of theory: Lagrange top is
//! `f(u) = (1 - u^2)(eps - p u) - (M - K u)^2 = p (u - u1)(u - u2)(u - u3)` and
//!
//! ```text
//!     j = (1/pi) integral_{u1}^{u2} sqrt(f(u)) / (1 - u^2) du
//!       = (1/pi) integral_{u1}^{u2} [eps + K^2 - p u - (M-K)^2/(2(1-u)) - (M+K)^2/(2(1+u))] du / sqrt(f)
//! ```
//!
//! (partial fractions of `(M - K u)^2 / (1 - u^2)`). Along the exact solution
//! `u = u1 + (u2 - u1) sn^2(x | k^2)`, `k^2 = (u2 - u1)/(u3 - u1)`, `du / sqrt(f) = dx / w` with
//! `w = sqrt(p (u3 - u1)) / 2`, so the four terms are complete elliptic integrals K(k^2),
//! E(k^2) and Pi(n | k^2) with `n = (u2 - u1)/(1 - u1)` and `-(u2 - u1)/(1 + u1)`, from the
//! turning points (the roots of the cubic) and the elliptic integrals of [`crate::special`].
//! `dj/d eps = K(k^2) / (2 pi w)` is the nutation period over 2 pi (in these units), which makes
//! Newton's method for the energy cheap. `p < 0` is the mirror image `u -> -u`, `M -> -M`.

use super::SymmetricTop;
use crate::error::{finite, signed, KreiselError, Result};
use crate::special::{cubic::Poly3, ellipe, ellipk, ellippi};
use std::f64::consts::PI;

/// The dimensionless nutation action `j` (units of hbar) and `dj/d eps` at the scaled energy
/// `eps` and strength `p` (units of B) for axial and vertical quanta `k`, `m`.
pub fn action_scaled(k: f64, m: f64, eps: f64, p: f64) -> Result<(f64, f64)> {
    if p < 0.0 {
        return action_scaled(k, -m, eps, -p);
    }
    let l2 = eps + k * k;
    let edge = k.abs().max(m.abs());
    // Below round-off of the rotor's own terms the potential is no potential: the free top,
    // whose action is L - max(|K|, |M|) with L^2 = eps + K^2.
    if p <= f64::EPSILON * (eps.abs() + k * k + m * m + 1.0) {
        if l2 <= edge * edge {
            return Ok((0.0, 0.0));
        }
        let l = l2.sqrt();
        return Ok((l - edge, 0.5 / l));
    }
    let cubic = Poly3([eps - m * m, 2.0 * m * k - p, -l2, p]);
    let roots = cubic.real_roots()?;
    if roots.len() < 3 {
        return Ok((0.0, 0.0)); // one real root, beyond u = 1: no allowed nutation
    }
    let (u1, u2, u3) = (roots[0].max(-1.0), roots[1].min(1.0), roots[2]);
    if u2 <= u1 || roots[1] < -1.0 || roots[0] > 1.0 {
        return Ok((0.0, 0.0));
    }
    let delta = u2 - u1;
    let span = u3 - u1;
    let m_ell = (delta / span).min(1.0 - f64::EPSILON);
    let w = 0.5 * (p * span).sqrt();
    let kk = ellipk(m_ell)?;
    let ee = ellipe(m_ell)?;
    let mut integral = l2 * kk - p * (u1 * kk + span * (kk - ee));
    // The two pole terms vanish exactly where M = K (no barrier at theta = 0) or M = -K (none
    // at theta = pi); there the turning point sits on the pole and Pi would diverge.
    if m != k {
        let n = delta / (1.0 - u1);
        integral -= 0.5 * (m - k) * (m - k) * ellippi(n, m_ell)? / (1.0 - u1);
    }
    if m != -k {
        let n = -delta / (1.0 + u1);
        integral -= 0.5 * (m + k) * (m + k) * ellippi(n, m_ell)? / (1.0 + u1);
    }
    Ok(((integral / (PI * w)).max(0.0), kk / (2.0 * PI * w)))
}

/// The largest `|P| / B` of the semiclassical levels: in stronger potentials the turning points
/// of the low levels come within ~(B / |P|)^(1/2) of the poles u = +-1, and 1 -+ u loses its
/// digits in double precision (at 10^12, six of sixteen).
pub const EBK_STRENGTH_LIMIT: f64 = 1e12;

/// The strength in units of B, checked against [`EBK_STRENGTH_LIMIT`].
fn scaled_strength(top: &SymmetricTop, strength: f64) -> Result<f64> {
    signed("strength", strength)?;
    let p = strength / top.b();
    if p.abs() > EBK_STRENGTH_LIMIT || p.is_nan() {
        return Err(KreiselError::invalid(
            "strength",
            strength,
            format!(
                "the semiclassical levels need |strength| <= {} B = {} J (B = hbar^2 / (2 I1)): \
                 beyond, the turning points come within round-off of the poles",
                crate::error::repr(EBK_STRENGTH_LIMIT),
                crate::error::repr(EBK_STRENGTH_LIMIT * top.b())
            ),
        ));
    }
    Ok(p)
}

/// The nutation action `(1/2 pi) closed-integral p_theta d theta` (J s) of the classical
/// top with `Mz = M hbar`, `M3 = K hbar` at total energy `energy` (J) in the potential
/// `strength cos(theta)` (strength in J); 0 below the bottom of the well.
pub fn nutation_action(
    top: &SymmetricTop,
    k: i64,
    m: i64,
    energy: f64,
    strength: f64,
) -> Result<f64> {
    finite("energy", energy)?;
    let p = scaled_strength(top, strength)?;
    let (b, kf) = (top.b(), k as f64);
    let eps = (energy - top.hbar() * top.hbar() * kf * kf / (2.0 * top.i3())) / b;
    finite("energy", eps)?;
    Ok(top.hbar() * action_scaled(kf, m as f64, eps, p)?.0)
}

/// The EBK energy (J) of the level with `n` nutation quanta (n = 0, 1, ...), `M3 = K hbar`,
/// `Mz = M hbar`, in the potential `strength cos(theta)`: the root of `action = (n + 1/2) hbar`.
/// It correlates with the quantum level `J = n + max(|K|, |M|)` of the (K, M) block.
pub fn energy(top: &SymmetricTop, k: i64, m: i64, n: i64, strength: f64) -> Result<f64> {
    if n < 0 {
        return Err(KreiselError::InvalidParameter {
            name: "n".into(),
            value: n.to_string(),
            allowed: "it must be an integer >= 0 (the number of nutation quanta)".into(),
        });
    }
    let p = scaled_strength(top, strength)?;
    let (kf, mf) = (k as f64, m as f64);
    let b = top.b();
    let target = n as f64 + 0.5;
    let j = n as f64 + kf.abs().max(mf.abs());
    let free = (j + 0.5) * (j + 0.5) - kf * kf;
    let eps = if p == 0.0 {
        free
    } else {
        // The potential moves the well by at most |p| either way, so the free top's energy
        // +- |p| brackets the root (the action is monotone: its slope is a period).
        let (mut lo, mut hi) = (free - p.abs(), free + p.abs());
        let mut x = free;
        let mut found = None;
        for _ in 0..200 {
            let (a, slope) = action_scaled(kf, mf, x, p)?;
            let g = a - target;
            if g == 0.0 {
                found = Some(x);
                break;
            }
            if g < 0.0 {
                lo = x;
            } else {
                hi = x;
            }
            let newton = if slope > 0.0 { x - g / slope } else { f64::NAN };
            let next = if newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
            let tol = 4.0 * f64::EPSILON * (x.abs() + p.abs() + 1.0);
            if (next - x).abs() <= tol || hi - lo <= tol {
                found = Some(next);
                break;
            }
            x = next;
        }
        found.ok_or_else(|| {
            KreiselError::Numerical(format!(
                "the EBK energy (K = {k}, M = {m}, n = {n}, strength = {strength}) did not \
                 converge"
            ))
        })?
    };
    Ok(b * eps + top.hbar() * top.hbar() * kf * kf / (2.0 * top.i3()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Free top: EBK gives J(J+1) + 1/4 in units of B (Langer's (J + 1/2)^2).
    #[test]
    fn the_free_top_is_quantum_mechanics_plus_a_quarter() {
        let top = SymmetricTop::new(1.0, 0.5, 1.0).unwrap();
        for (k, m, n) in [(0, 0, 0), (1, 2, 3), (-2, 1, 0), (3, 3, 5)] {
            let e = energy(&top, k, m, n, 0.0).unwrap();
            let j = n + k.abs().max(m.abs());
            let q = top.free_energy(j, k).unwrap();
            assert!(
                (e - q - 0.25 * top.b()).abs() < 1e-12 * q.max(1.0),
                "{k} {m} {n}"
            );
        }
    }

    /// The closed form and a tiny potential agree with the free action (continuity at p = 0).
    #[test]
    fn the_action_is_continuous_at_zero_strength() {
        for (k, m) in [(0.0, 0.0), (1.0, 2.0), (2.0, 2.0), (2.0, -2.0), (-1.0, 3.0)] {
            let eps = 40.0;
            let (free, _) = action_scaled(k, m, eps, 0.0).unwrap();
            let (near, _) = action_scaled(k, m, eps, 1e-7).unwrap();
            assert!((free - near).abs() < 1e-6, "K {k} M {m}: {free} vs {near}");
        }
    }

    /// The slope returned is the derivative of the action (finite differences).
    #[test]
    fn the_slope_is_the_derivative_of_the_action() {
        let (k, m, p) = (1.0, 2.0, 15.0);
        let eps = 30.0;
        let h = 1e-5;
        let (_, slope) = action_scaled(k, m, eps, p).unwrap();
        let up = action_scaled(k, m, eps + h, p).unwrap().0;
        let down = action_scaled(k, m, eps - h, p).unwrap().0;
        let fd = (up - down) / (2.0 * h);
        assert!((slope - fd).abs() < 1e-7 * slope, "{slope} vs {fd}");
    }
}
