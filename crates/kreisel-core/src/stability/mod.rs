//! Stability of stationary motions.

pub mod steady_precession;
