//! The accurate scheme (`maglev_core::levitation::accurate`) at a fixed gap, as a map of
//! `(x, y)`: why it is stable for every step.
//!
//! At a fixed gap the limit system `ż = J·z + f` ([`super::inner_loop`]) has constant coefficients,
//! and any s-stage Gauss–Legendre method applied to a linear constant-coefficient system is
//! its (s, s) Padé approximant of the exponential. For s = 2, one interval `h = Δt/m` maps the
//! deviation from equilibrium by
//!
//! ```text
//! R(hJ) = (I − hJ/2 + (hJ)²/12)⁻¹ · (I + hJ/2 + (hJ)²/12)
//! ```
//!
//! and one outer step by `R^m`. `|R(z)| < 1` for every `Re z < 0` (A-stability), and the
//! eigenvalues of `J` are in the open left half-plane whenever τ, p, ki > 0 (inner_loop), so the
//! spectral radius is below 1 for every Δt: there is no critical step. The price of A- but
//! not L-stability is `R(z) → 1` as `z → −∞`: very stiff modes (far beyond this loop's) would be
//! damped slowly rather than wrongly.
//!
//! This module computes `R` independently of the core (nalgebra, from `J`); the tests check
//! that the core's update is exactly this map.

use super::inner_loop::Loop;
use maglev_core::levitation::accurate;
use maglev_core::Params;
use nalgebra::Matrix2;

/// The (2, 2) Padé map of one Gauss interval at gap deviation `eta`, and the interval count.
pub fn interval_matrix(params: &Params, eta: f64) -> (Matrix2<f64>, u32) {
    let m = accurate::intervals(params);
    let h = params.dt / m as f64;
    let hj = Loop::new(params, eta).matrix() * h;
    let hj2 = hj * hj / 12.0;
    let id = Matrix2::identity();
    let den = id - hj / 2.0 + hj2;
    let num = id + hj / 2.0 + hj2;
    // `den` is invertible for Re λ(hJ) < 0 (its eigenvalues are the Padé denominators).
    let r = den
        .try_inverse()
        .map_or(Matrix2::from_element(f64::NAN), |d| d * num);
    (r, m)
}

/// The map of one outer step, `R^m`.
pub fn outer_matrix(params: &Params, eta: f64) -> Matrix2<f64> {
    let (r, m) = interval_matrix(params, eta);
    r.pow(m)
}

/// Spectral radius of one outer step.
pub fn spectral_radius(params: &Params, eta: f64) -> f64 {
    outer_matrix(params, eta)
        .complex_eigenvalues()
        .iter()
        .map(|z| z.norm())
        .fold(0.0, f64::max)
}
