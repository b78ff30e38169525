//! The g-loop at fixed gap in continuous time: the coil (Eq. 9) driven by the PI law (Eq. 10).
//!
//! # Derivation
//! With `e = g0 − g` (Eq. 8), Eq. 9 + 10 read `G0·ġ + R0·h·g = KP·(g0 − g) + KI·e_a`,
//! `ė_a = g0 − g`. Divide by `V_b = R0·i0 = R0·h0·g0` and write `g = g0(1 + x)`,
//! `h = h0(1 + η)`, `KI·e_a = V_b(1 + y)`:
//!
//! ```text
//! τ·ẋ = y − η − x·(1 + kpv + η),    ẏ = −ki·x
//! τ = G0·g0/V_b = 2·K0·g0/V_b (s),   kpv = KP·g0/V_b,   ki = KI·g0/V_b (1/s)
//! ```
//!
//! At a fixed gap this is linear in `(x, y)` (exactly, not only to first order) with the
//! matrix `[[−p/τ, 1/τ], [−ki, 0]]`, `p = 1 + kpv + η`, whose characteristic polynomial is
//! `τ s² + p s + ki = 0`. At the paper's values (i0 = 43 A, h0 = 10 mm, R0 = 1 Ω, KP = 0.01,
//! KI = 6, p0 = 36.8 kN): τ = 0.398 s, kpv = 1, ki = 600 s⁻¹, poles −2.51 ± 38.7j s⁻¹
//! (6.2 Hz, damping ratio 0.065). Since τ, p, ki > 0 both poles are always in the left
//! half-plane: the g-loop alone is stable for every non-negative gain with KI > 0.
//!
//! This is also the system the paper's scheme converges to as `n_sub → ∞`: Eq. 13 with
//! `δ → 0` is `G0·ġ + (R0·h + KP)·g = KI·e_a + KP·g0`, i.e. Eq. 9 + 10 exactly, for every α
//! (the α-weighting only changes the O(δ) error).

use super::Complex;
use maglev_core::Params;
use nalgebra::Matrix2;

/// The per-unit loop constants at a fixed gap `h = h0(1 + eta)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Loop {
    /// Coil time constant τ = 2·K0·g0/(R0·i0) (s).
    pub tau: f64,
    /// `p = 1 + kpv + η`: coil resistance plus proportional gain, per unit.
    pub p: f64,
    /// Integral gain per unit, `ki = KI·g0/(R0·i0)` (1/s).
    pub ki: f64,
}

impl Loop {
    /// The loop of `params` at gap deviation `eta` (0 at the nominal gap).
    pub fn new(params: &Params, eta: f64) -> Self {
        let vb = params.v_base();
        let g0 = params.g0();
        Loop {
            tau: 2.0 * params.k0() * g0 / vb,
            p: 1.0 + params.kp * g0 / vb + eta,
            ki: params.ki * g0 / vb,
        }
    }

    /// The state matrix of `(x, y)`.
    pub fn matrix(&self) -> Matrix2<f64> {
        Matrix2::new(-self.p / self.tau, 1.0 / self.tau, -self.ki, 0.0)
    }

    /// Roots of `τ s² + p s + ki = 0` (closed form), sorted.
    pub fn poles(&self) -> [Complex; 2] {
        let (a, b, c) = (self.tau, self.p, self.ki);
        let disc = b * b - 4.0 * a * c;
        let mut out = if disc >= 0.0 {
            // Numerically stable real roots.
            let q = -0.5 * (b + b.signum() * disc.sqrt());
            let r1 = if q != 0.0 { c / q } else { 0.0 };
            [Complex { re: q / a, im: 0.0 }, Complex { re: r1, im: 0.0 }]
        } else {
            let re = -b / (2.0 * a);
            let im = (-disc).sqrt() / (2.0 * a);
            [Complex { re, im }, Complex { re, im: -im }]
        };
        super::sort_poles(&mut out);
        out
    }

    /// Eigenvalues of [`Loop::matrix`] by nalgebra (cross-check of [`Loop::poles`]), sorted.
    pub fn poles_numeric(&self) -> [Complex; 2] {
        let ev = self.matrix().complex_eigenvalues();
        let mut out = [ev[0].into(), ev[1].into()];
        super::sort_poles(&mut out);
        out
    }
}
