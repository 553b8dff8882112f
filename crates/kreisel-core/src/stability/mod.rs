//! Stability of stationary motions.

pub mod play_top;
pub mod steady_precession;
