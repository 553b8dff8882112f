//! Steady precession of the Lagrange top, small nutations about it, and the sleeping top.
//!
//! Steady precession at theta0 with axial spin omega3 (theory: Lagrange top): the theta
//! equation with thetadot = 0 gives `m g l = Omega (I3 omega3 - I1 Omega cos theta0)`, a
//! quadratic in Omega. Small nutations about it have
//! `omega_n^2 = (a - 2 Omega cos theta0)^2 + Omega^2 sin^2 theta0`, `a = I3 omega3 / I1`.
//! The upright spin is stable iff `(I3 omega3)^2 > 4 I1 m g l`.

use crate::error::{rate, KreiselError, Result};
use crate::models::lagrange::LagrangeTop;
use crate::special::cubic::quadratic_roots;

fn check_theta0(theta0: f64) -> Result<f64> {
    if theta0.is_finite() && theta0 > 0.0 && theta0 < std::f64::consts::PI {
        Ok(theta0)
    } else {
        Err(KreiselError::invalid(
            "theta0",
            theta0,
            "steady precession needs 0 < theta0 < pi (at the vertical every split of the \
             spin is a sleeping or hanging top: see sleeping_threshold)",
        ))
    }
}

/// The steady precession rates at `theta0` for axial spin `omega3`, ascending; empty when
/// none exists.
pub fn steady_precession_rates(top: &LagrangeTop, theta0: f64, omega3: f64) -> Result<Vec<f64>> {
    check_theta0(theta0)?;
    rate("omega3", omega3)?;
    let (i1, i3, mgl) = (top.i1(), top.i3(), top.mgl());
    let c = theta0.cos();
    let m3 = i3 * omega3;
    // I1 cos(theta0) Omega^2 - M3 Omega + m g l = 0
    let (qa, qb, qc) = (i1 * c, -m3, mgl);
    if qa.abs() <= 1e-15 * (qb.abs() + qc.abs()).max(i1) {
        if m3 == 0.0 {
            if mgl == 0.0 {
                return Err(KreiselError::invalid(
                    "omega3",
                    omega3,
                    "with l = 0 (or g = 0), no spin and theta0 = pi/2 every rate is steady; \
                     give a non-zero spin",
                ));
            }
            return Ok(vec![]);
        }
        return Some(vec![mgl / m3])
            .filter(|r| r[0].is_finite())
            .ok_or_else(|| overflow(theta0, omega3));
    }
    quadratic_roots(qa, qb, qc).ok_or_else(|| overflow(theta0, omega3))
}

/// A steady precession rate beyond the range of f64.
fn overflow(theta0: f64, omega3: f64) -> KreiselError {
    KreiselError::invalid(
        "omega3",
        omega3,
        format!(
            "a steady precession rate at theta0 = {theta0} with this spin exceeds the range of \
             floating-point numbers"
        ),
    )
}

/// Angular frequency of small nutations about the steady precession at `theta0` with
/// spin `omega3` and rate `rate` (which must be one of the steady rates).
pub fn nutation_frequency(
    top: &LagrangeTop,
    theta0: f64,
    omega3: f64,
    precession: f64,
) -> Result<f64> {
    check_theta0(theta0)?;
    rate("omega3", omega3)?;
    let rate = rate("rate", precession)?;
    let (i1, i3, mgl) = (top.i1(), top.i3(), top.mgl());
    let (s, c) = theta0.sin_cos();
    let m3 = i3 * omega3;
    let residual = mgl - rate * (m3 - i1 * rate * c);
    let scale = mgl.abs() + (rate * m3).abs() + (i1 * rate * rate * c).abs();
    if residual.abs() > 1e-8 * scale.max(f64::MIN_POSITIVE) {
        return Err(KreiselError::invalid(
            "rate",
            rate,
            format!(
                "it is not a steady precession rate at theta0 = {theta0}, omega3 = {omega3} \
                 (those are {:?})",
                steady_precession_rates(top, theta0, omega3).unwrap_or_default()
            ),
        ));
    }
    let a = m3 / i1;
    let w2 = (a - 2.0 * rate * c).powi(2) + (rate * s).powi(2);
    Ok(w2.sqrt())
}

/// The axial spin omega3 above which the upright spin is stable: sqrt(4 I1 m g l) / I3
/// (0 when m g l <= 0: a top hanging below its pivot is stable without spin).
pub fn sleeping_threshold(top: &LagrangeTop) -> f64 {
    let mgl = top.mgl();
    if mgl <= 0.0 {
        0.0
    } else {
        (4.0 * top.i1() * mgl).sqrt() / top.i3()
    }
}
