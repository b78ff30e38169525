//! The checks every key of a scenario goes through, once: a value in the key's own unit
//! against its domain (sign, finiteness, [`MAX_MAGNITUDE`]) and, for the keys whose extremes
//! pass the sign but break the numerics below them, its plausible range ([`within`]). Each
//! returns the value, so a conversion reads `positive(key, v)? * 1e3`, and each error is one
//! line that starts with the key and says the limit (docs/scenarios.md, "How to read the
//! tables", quotes these functions).

use crate::error::shown;
use crate::physics::check as sign;
use crate::{Error, Result};

/// The largest magnitude any physical key may have, in its own unit (kN/m², t, m, m/s, …):
/// the stiffest material a guideway is built of (steel, 2.1e8 kN/m²) is under it, and so is
/// every bundled value (at most 3.6e7); a larger one is a slip of the exponent, and the bound
/// keeps every product of two inputs (≤ 1e18) far from overflow.
pub const MAX_MAGNITUDE: f64 = 1e9;

/// `v` within ±[`MAX_MAGNITUDE`], else the error naming `key`.
pub(super) fn in_range(key: &str, v: f64) -> Result<f64> {
    if v.abs() <= MAX_MAGNITUDE {
        Ok(v)
    } else {
        Err(Error::invalid(
            key,
            format!("must be at most {MAX_MAGNITUDE:e} in magnitude (in its unit), got {v:e}"),
        ))
    }
}

/// `v` a positive finite number (the physics' sign rule, [`sign::positive`]) within
/// ±[`MAX_MAGNITUDE`].
pub(super) fn positive(key: &str, v: f64) -> Result<f64> {
    in_range(key, sign::positive(key, v)?)
}

pub(super) fn finite(key: &str, v: f64) -> Result<f64> {
    if v.is_finite() {
        in_range(key, v)
    } else {
        Err(Error::invalid(
            key,
            format!("must be a finite number, got {}", shown(v)),
        ))
    }
}

/// `v` zero or a positive finite number ([`sign::non_negative`]) within ±[`MAX_MAGNITUDE`].
pub(super) fn non_negative(key: &str, v: f64) -> Result<f64> {
    in_range(key, sign::non_negative(key, v)?)
}

/// `v` (in the key's unit) within `[lo, hi]`: the plausible range of a key whose extremes pass
/// the sign checks but break the numerics below them (a stiffness that is singular to f64, a
/// Newmark matrix that loses every digit, statics with no solution); `why` says where the
/// range comes from. Found by driving every key to 1e-300, 1e-12, 9e8 and 0 through every
/// bundled scenario (docs/scenarios.md, "Plausible ranges").
pub(super) fn within(key: &str, v: f64, lo: f64, hi: f64, why: &str) -> Result<f64> {
    if (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(Error::invalid(
            key,
            format!(
                "must be between {} and {} ({why}), got {}",
                shown(lo),
                shown(hi),
                shown(v)
            ),
        ))
    }
}

/// [`positive`], then [`within`]: the two checks of a positive key with a plausible range, in
/// that order, naming `key` once.
pub(super) fn positive_within(key: &str, v: f64, lo: f64, hi: f64, why: &str) -> Result<f64> {
    within(key, positive(key, v)?, lo, hi, why)
}

pub(super) fn at_least(key: &str, v: usize, min: usize) -> Result<usize> {
    if v >= min {
        Ok(v)
    } else {
        Err(Error::invalid(
            key,
            format!("must be at least {min}, got {v}"),
        ))
    }
}

pub(super) fn bounded(key: &str, v: usize, min: usize, max: usize) -> Result<usize> {
    if (min..=max).contains(&v) {
        Ok(v)
    } else {
        Err(Error::invalid(
            key,
            format!("must be between {min} and {max}, got {v}"),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each check at its edges: the edge value passes, the next f64 beyond it (or a
    /// non-finite value) fails with one line that starts with the key.
    #[test]
    fn each_check_passes_its_edge_and_refuses_beyond_it() {
        let refused = |r: Result<f64>| {
            let m = r.unwrap_err().to_string();
            assert!(m.starts_with("k: ") && !m.contains('\n'), "{m}");
        };
        let above = |v: f64| f64::from_bits(v.to_bits() + 1);
        assert_eq!(positive("k", MAX_MAGNITUDE).unwrap(), MAX_MAGNITUDE);
        assert_eq!(positive("k", f64::MIN_POSITIVE).unwrap(), f64::MIN_POSITIVE);
        refused(positive("k", 0.0));
        refused(positive("k", above(MAX_MAGNITUDE)));
        refused(positive("k", f64::NAN));
        assert_eq!(non_negative("k", 0.0).unwrap(), 0.0);
        refused(non_negative("k", -f64::MIN_POSITIVE));
        refused(non_negative("k", f64::INFINITY));
        assert_eq!(finite("k", -MAX_MAGNITUDE).unwrap(), -MAX_MAGNITUDE);
        refused(finite("k", -above(MAX_MAGNITUDE)));
        refused(finite("k", f64::NEG_INFINITY));
        assert_eq!(within("k", 2.0, 1.0, 2.0, "why").unwrap(), 2.0);
        refused(within("k", above(2.0), 1.0, 2.0, "why"));
        refused(within("k", f64::NAN, 1.0, 2.0, "why"));
        assert!(within("k", 0.5, 1.0, 2.0, "because")
            .unwrap_err()
            .to_string()
            .contains("between 1 and 2 (because)"));
        assert_eq!(at_least("k", 3, 3).unwrap(), 3);
        assert!(at_least("k", 2, 3).is_err());
        assert_eq!(bounded("k", 5, 1, 5).unwrap(), 5);
        assert!(bounded("k", 6, 1, 5).is_err() && bounded("k", 0, 1, 5).is_err());
    }
}
