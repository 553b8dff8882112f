//! kreisel-core: the physics and numerics of spinning tops, with no Python in sight.
//!
//! - [`special`]: Jacobi elliptic functions, elliptic integrals, polynomial roots and
//!   piecewise Chebyshev interpolation.
//! - [`models::lagrange`]: the heavy symmetric top on a fixed pivot, solved exactly.
//! - [`models::heavy_top`], [`models::play_top`]: every heavy top on a pivot, and the play
//!   top on a plane, each with all of its physics (equations, contact, its driver).
//! - [`stability`]: steady precession, small nutations and the sleeping top; the play top's
//!   stationary motions and the (alpha, gamma) atlas.
//! - [`simulate`]: one vocabulary for every model (settings, solution, events, summaries,
//!   the model trait) and the parallel batch.
//! - [`integrate`]: the general integrators (no model imported).
//! - [`quantum`]: the quantum symmetric top (free and in a potential P cos(theta)) and its
//!   semiclassical (EBK) levels.
//!
//! Conventions (SI units, radians, Euler angles z-x-z with theta from the upward vertical)
//! are those of the theory page.

pub mod chaos;
pub mod error;
pub mod integrate;
pub mod models;
pub mod quantum;
pub mod rotation;
pub mod simulate;
pub mod special;
pub mod stability;

pub use error::{KreiselError, Result};

/// `a * b + c`: one fused multiply-add (one rounding) where the build targets FMA
/// (x86-64-v3), else a product and a sum. Never the software `mul_add` of a CPU without it.
#[inline(always)]
pub(crate) fn fmadd(a: f64, b: f64, c: f64) -> f64 {
    #[cfg(target_feature = "fma")]
    {
        a.mul_add(b, c)
    }
    #[cfg(not(target_feature = "fma"))]
    {
        a * b + c
    }
}
