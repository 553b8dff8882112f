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
            value: repr(value),
            allowed: allowed.into(),
        }
    }
}

/// A float as Python's `repr` writes it (`1.0`, `2.5`, `1e-05`, `1e+300`, `5e-324`, `nan`):
/// the shortest form that reads back to the same number, as users of the Python API see
/// their values.
pub fn repr(x: f64) -> String {
    if x.is_nan() {
        return "nan".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf" } else { "-inf" }.into();
    }
    let a = x.abs();
    if a == 0.0 || (1e-4..1e16).contains(&a) {
        let s = format!("{x}");
        return if s.contains('.') { s } else { format!("{s}.0") };
    }
    let s = format!("{x:e}");
    let (mantissa, exp) = s.split_once('e').unwrap_or((&s, "0"));
    let (sign, digits) = match exp.strip_prefix('-') {
        Some(d) => ('-', d),
        None => ('+', exp),
    };
    format!("{mantissa}e{sign}{digits:0>2}")
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

/// The magnitudes a physical parameter of a model may have (in SI units): `[1e-100, 1e100]`,
/// or 0 where zero is allowed. Every physical top lies far inside, and within it the products
/// and ratios of a few parameters and rates (energies, `m g l / I1`, ...) stay far from the
/// overflow and underflow of f64 (1e308, 1e-308): a subnormal or a 1e300 parameter would turn
/// them into inf, 0 or NaN without a word.
pub const PARAMETER_RANGE: (f64, f64) = (1e-100, 1e100);

/// The largest magnitude of an angular rate (rad/s) or a rate-like argument: with moments
/// of inertia in [`PARAMETER_RANGE`], energies and momenta stay finite.
pub const RATE_MAX: f64 = 1e100;

fn in_range(value: f64) -> bool {
    (PARAMETER_RANGE.0..=PARAMETER_RANGE.1).contains(&value.abs())
}

/// Checks that `value` is a finite physical parameter > 0 within [`PARAMETER_RANGE`].
pub fn positive(name: &str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 && in_range(value) {
        Ok(value)
    } else {
        Err(KreiselError::invalid(
            name,
            value,
            format!(
                "it must be a finite number > 0 within [{}, {}]",
                repr(PARAMETER_RANGE.0),
                repr(PARAMETER_RANGE.1)
            ),
        ))
    }
}

/// Checks that `value` is a physical parameter >= 0: zero, or within [`PARAMETER_RANGE`].
pub fn non_negative(name: &str, value: f64) -> Result<f64> {
    if value == 0.0 || (value.is_finite() && value > 0.0 && in_range(value)) {
        Ok(value.abs())
    } else {
        Err(KreiselError::invalid(
            name,
            value,
            format!(
                "it must be 0 or a finite number within [{}, {}]",
                repr(PARAMETER_RANGE.0),
                repr(PARAMETER_RANGE.1)
            ),
        ))
    }
}

/// Checks that `value` is a signed physical parameter: zero, or of a magnitude within
/// [`PARAMETER_RANGE`].
pub fn signed(name: &str, value: f64) -> Result<f64> {
    if value == 0.0 || (value.is_finite() && in_range(value)) {
        Ok(value)
    } else {
        Err(KreiselError::invalid(
            name,
            value,
            format!(
                "it must be 0 or a finite number of magnitude within [{}, {}]",
                repr(PARAMETER_RANGE.0),
                repr(PARAMETER_RANGE.1)
            ),
        ))
    }
}

/// Checks the moments of a symmetric top: `I1` (perpendicular) and `I3` (axial) are
/// parameters > 0, and `I3 <= 2 I1`, the triangle inequality of principal moments that every
/// rigid body obeys (about its centre of mass, and so about any point on its figure axis).
pub fn symmetric_moments(i1: f64, i3: f64) -> Result<()> {
    positive("I1", i1)?;
    positive("I3", i3)?;
    if i3 > 2.0 * i1 {
        return Err(KreiselError::invalid(
            "I3",
            i3,
            format!(
                "no rigid body has I3 > 2*I1 = {} (triangle inequality of principal moments)",
                repr(2.0 * i1)
            ),
        ));
    }
    Ok(())
}

/// Checks that `value` is a finite rate (rad/s) of magnitude at most [`RATE_MAX`].
pub fn rate(name: &str, value: f64) -> Result<f64> {
    if value.is_finite() && value.abs() <= RATE_MAX {
        Ok(value)
    } else {
        Err(KreiselError::invalid(
            name,
            value,
            format!(
                "it must be a finite rate of magnitude at most {} rad/s",
                repr(RATE_MAX)
            ),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::repr;

    #[test]
    fn values_are_written_as_python_writes_them() {
        for (x, s) in [
            (1.0, "1.0"),
            (2.5, "2.5"),
            (-0.0, "-0.0"),
            (1e-5, "1e-05"),
            (1e300, "1e+300"),
            (5e-324, "5e-324"),
            (1.5e16, "1.5e+16"),
            (123456.789, "123456.789"),
            (f64::NAN, "nan"),
            (f64::NEG_INFINITY, "-inf"),
        ] {
            assert_eq!(repr(x), s);
        }
    }
}
