//! The sign rules of a physical value, written once for every layer: the physics' own
//! checks (a section's constants, a viaduct's stiffnesses, a footing's size) and the
//! scenario's keys (`input/case/checks.rs` adds its magnitude bound on top) say the same
//! thing in the same words. Each returns the value, so a check reads `positive(key, v)?`.

use crate::error::shown;
use crate::{Error, Result};

/// Whether `v` is a positive finite number.
pub fn is_positive(v: f64) -> bool {
    v.is_finite() && v > 0.0
}

/// The error of a value that must be a positive finite number and is not: `key` and `v` as
/// the caller names and was given them.
pub fn not_positive(key: impl Into<String>, v: f64) -> Error {
    Error::invalid(
        key,
        format!("must be a positive finite number, got {}", shown(v)),
    )
}

/// `v` if it is a positive finite number, else the error naming `key`.
pub fn positive(key: &str, v: f64) -> Result<f64> {
    if is_positive(v) {
        Ok(v)
    } else {
        Err(not_positive(key, v))
    }
}

/// `v` if it is zero or a positive finite number, else the error naming `key`.
pub fn non_negative(key: &str, v: f64) -> Result<f64> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(Error::invalid(
            key,
            format!("must be zero or a positive finite number, got {}", shown(v)),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The edges: the smallest positive number passes, zero does not; zero is non-negative,
    /// the largest negative number is not; neither passes NaN or infinity; no magnitude bound
    /// here (that is the scenario's, `input/case/checks.rs`).
    #[test]
    fn sign_checks_pass_their_edges_and_refuse_beyond() {
        assert_eq!(positive("k", f64::MIN_POSITIVE).unwrap(), f64::MIN_POSITIVE);
        assert_eq!(positive("k", f64::MAX).unwrap(), f64::MAX);
        assert_eq!(non_negative("k", 0.0).unwrap(), 0.0);
        for (r, says) in [
            (
                positive("k", 0.0),
                "k: must be a positive finite number, got 0",
            ),
            (
                positive("k", f64::NAN),
                "k: must be a positive finite number, got NaN",
            ),
            (
                positive("k", f64::INFINITY),
                "k: must be a positive finite number, got inf",
            ),
            (
                non_negative("k", -f64::MIN_POSITIVE),
                "k: must be zero or a positive finite number, got -2.2250738585072014e-308",
            ),
            (
                non_negative("k", f64::NAN),
                "k: must be zero or a positive finite number, got NaN",
            ),
        ] {
            assert_eq!(r.unwrap_err().to_string(), says);
        }
    }
}
