//! The tops: parameters, states, and what can be said of them exactly.

pub mod heavy_top;
pub mod lagrange;
pub mod play_top;
