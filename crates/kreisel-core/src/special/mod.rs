//! Special functions: Jacobi elliptic functions, elliptic integrals, cubic roots, and
//! piecewise Chebyshev interpolation.
//!
//! The Legendre and Carlson integrals come from the `ellip` crate (a careful port of Boost
//! Math). Jacobi's elliptic functions are not in any well-kept Rust crate, so they are
//! written here (arithmetic-geometric mean, descending Landen transformation), taking the
//! complementary parameter `m1 = 1 - m` as an input so that moduli near 1 keep full precision.

pub mod chebyshev;
pub mod cubic;
pub mod elliptic;
pub mod jacobi;

pub use elliptic::{ellipe, ellipf, ellipj, ellipk, ellippi, ellippiinc, rf, rj};
pub use jacobi::{jacobi, Jacobi};
