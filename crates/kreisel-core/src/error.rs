//! The one error type of the core. Every variant says what was wrong in words a user can act on.

use std::fmt;

/// An error from kreisel-core.
#[derive(Debug, Clone, PartialEq)]
pub enum KreiselError {
    /// A parameter or argument has a value outside what is allowed.
    InvalidParameter {
        /// The parameter's public name (as the Python API spells it).
        name: String,
        /// The offending value, formatted.
        value: String,
        /// What is allowed, in words.
        allowed: String,
    },
    /// A computation could not deliver a trustworthy result.
    Numerical(String),
}

impl KreiselError {
    /// An invalid-parameter error for a scalar value.
    pub fn invalid(name: &str, value: f64, allowed: impl Into<String>) -> Self {
        KreiselError::InvalidParameter {
            name: name.to_string(),
            value: number(value),
            allowed: allowed.into(),
        }
    }
}

/// A number as a message shows it: plain where that is short, else in exponent form (the
/// plain form of 1e-300 has 300 digits).
pub fn number(value: f64) -> String {
    let a = value.abs();
    if a != 0.0 && a.is_finite() && !(1e-4..1e16).contains(&a) {
        format!("{value:e}")
    } else {
        format!("{value}")
    }
}

impl fmt::Display for KreiselError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            KreiselError::InvalidParameter {
                name,
                value,
                allowed,
            } => write!(f, "{name} = {value} is not allowed: {allowed}"),
            KreiselError::Numerical(msg) => write!(f, "numerical failure: {msg}"),
        }
    }
}

impl std::error::Error for KreiselError {}

/// Result type of the core.
pub type Result<T> = std::result::Result<T, KreiselError>;

/// Checks that `value` is finite.
pub fn finite(name: &str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(KreiselError::invalid(
            name,
            value,
            "it must be a finite number",
        ))
    }
}

/// Checks that `value` is finite and strictly positive.
pub fn positive(name: &str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(KreiselError::invalid(
            name,
            value,
            "it must be a finite number > 0",
        ))
    }
}

/// Checks that `value` is finite and not negative.
pub fn non_negative(name: &str, value: f64) -> Result<f64> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(KreiselError::invalid(
            name,
            value,
            "it must be a finite number >= 0",
        ))
    }
}
