//! `cos(2π·t)` for any [`Scalar`], built from the scalar's own saturating arithmetic.
//!
//! Used by fixed point, which has no trigonometry of its own. The argument is in turns so the
//! range reduction is an exact bit mask; the reduced angle `z ≤ π/4` goes into Taylor series
//! whose truncation error (< 1e-15) is far below every supported type's resolution.

use crate::scalar::Scalar;

const TWO_PI: f64 = 2.0 * core::f64::consts::PI;
/// cos z = Σ (−1)^k z^{2k} / (2k)!, k = 0..6, Horner in z².
const COS: [f64; 7] = [
    1.0,
    -1.0 / 2.0,
    1.0 / 24.0,
    -1.0 / 720.0,
    1.0 / 40_320.0,
    -1.0 / 3_628_800.0,
    1.0 / 479_001_600.0,
];
/// sin z / z = Σ (−1)^k z^{2k} / (2k+1)!, k = 0..6, Horner in z².
const SIN: [f64; 7] = [
    1.0,
    -1.0 / 6.0,
    1.0 / 120.0,
    -1.0 / 5_040.0,
    1.0 / 362_880.0,
    -1.0 / 39_916_800.0,
    1.0 / 6_227_020_800.0,
];

fn horner<S: Scalar>(coeffs: &[f64; 7], z2: S, ov: &mut bool) -> S {
    let mut acc = S::from_f64(coeffs[6], ov);
    for c in coeffs[..6].iter().rev() {
        acc = acc.smul(z2, ov).sadd(S::from_f64(*c, ov), ov);
    }
    acc
}

/// `cos(2π·t)` by range reduction in turns and a Taylor series on `[0, π/4]`.
pub fn cos_turns_generic<S: Scalar>(t: S, ov: &mut bool) -> S {
    let half = S::from_f64(0.5, ov);
    let quarter = S::from_f64(0.25, ov);
    let eighth = S::from_f64(0.125, ov);
    let mut u = t.fract();
    if u > half {
        u = S::ONE.ssub(u, ov); // cos is even and 1-periodic in turns
    }
    let negate = u > quarter;
    if negate {
        u = half.ssub(u, ov); // cos(π − z) = −cos z
    }
    let two_pi = S::from_f64(TWO_PI, ov);
    let value = if u <= eighth {
        let z = u.smul(two_pi, ov);
        horner(&COS, z.smul(z, ov), ov)
    } else {
        // cos z = sin(π/2 − z)
        let z = quarter.ssub(u, ov).smul(two_pi, ov);
        horner(&SIN, z.smul(z, ov), ov).smul(z, ov)
    };
    if negate {
        value.sneg(ov)
    } else {
        value
    }
}
