//! Eq. 14 as the paper writes it, over one sub-step `δ = Δt/n_sub`, as a map of `(x, y)`.
//!
//! # The amplification matrix
//! At a fixed gap `η` the core's increment form of Eq. 14 (see `maglev_core::levitation`)
//!
//! ```text
//! Δx = c·(y − η − x·(1 + kpd + η)) / (1 + c·α·(1 + kph + η)),   y' = y − kih·(x + x')
//! c = δ/τ,  kpd = kpv + ki·δ,  kph = kpv + ki·δ/2,  kih = ki·δ/2
//! ```
//!
//! is affine in `(x, y)` — exactly, not only to first order — with the matrix
//!
//! ```text
//! M = [[1 − a, b], [−k·(2 − a), 1 − k·b]]
//! a = c·(p + ki·δ)/D,  b = c/D,  k = ki·δ/2,  D = 1 + c·α·(p + ki·δ/2),  p = 1 + kpv + η
//! tr M = 2 − a − k·b,   det M = 1 − a + k·b
//! ```
//!
//! `n_sub` sub-steps at a fixed gap multiply to `M^n_sub`, whose spectral radius is
//! `ρ(M)^n_sub`; the outer step is stable exactly when one sub-step is.
//!
//! # Stability region (proof)
//! By the Jury (Schur–Cohn) test a real 2×2 matrix has both eigenvalues inside the unit
//! circle iff `1 − tr + det > 0`, `1 + tr + det > 0` and `|det| < 1`. Here
//! `1 − tr + det = 2·k·b > 0` whenever `KI > 0`; `1 + tr + det = 4 − 2a`; `det < 1` iff
//! `k·b < a` iff `ki·δ/2 < p + ki·δ`, always true; `det > −1` follows from `a < 2`. So the
//! scheme is stable **iff `a < 2`**, and at `a = 2` one eigenvalue leaves through −1 (the
//! instability is a period-2 flip, the classic signature of a too-explicit step). With
//! `KI = 0` one eigenvalue is exactly 1 (the integrator holds) and the other is `1 − a`:
//! the radius exceeds 1 again iff `a > 2`. Multiplying `a < 2` out (D > 0):
//!
//! ```text
//! Q(δ) = (1 − α)·ki·δ² + (1 − 2α)·p·δ − 2τ < 0
//! ```
//!
//! `Q(0) = −2τ < 0`, so small steps are always stable, and
//! * `α = 1`: `Q = −p·δ − 2τ < 0` for every δ: **unconditionally stable** (with `p > 0`).
//! * `0 ≤ α < 1`, `KI > 0`: `Q` is an upward parabola: exactly one critical sub-step
//!   `δ* = (−(1 − 2α)p + √((1 − 2α)²p² + 8(1 − α)·ki·τ)) / (2(1 − α)·ki)`, unstable beyond.
//!   In particular **α = ½ is not unconditionally stable**, nor is any α < 1. The reason:
//!   Eq. 13 puts `KI·(g0 − g^t)·δ/2` into `B` and α-weights the other `KI·δ/2·g` (inside `A`),
//!   so the latest integral increment weighs `e^t` by `(2 − α)/2` and `e^{t+δ}` by only
//!   `α/2`; the resulting explicit `ki·δ²` term has the coefficient `1 − α` and wins at large δ.
//! * `KI = 0`: `δ* = 2τ/((1 − 2α)·p)` for α < ½, none for α ≥ ½.
//!
//! The critical outer step is `Δt* = n_sub·δ*`. At the paper's values (τ = 0.398 s, p = 2,
//! ki = 600 s⁻¹) and n_sub = 1: α = 0.5 → 51.5 ms, 0.6 → 58.4 ms, 0.75 → 76.2 ms,
//! 0.9 → 129 ms, 1.0 → none — far above the paper's Δt ≤ 10 ms.

use super::inner_loop::Loop;
use super::Complex;
use maglev_core::Params;
use nalgebra::Matrix2;

/// One sub-step of Eq. 14 at a fixed gap, in closed form.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Step {
    /// The continuous loop constants (τ, p, ki) at this gap.
    pub lp: Loop,
    /// α of the α-method.
    pub alpha: f64,
    /// Sub-step δ = Δt/n_sub (s).
    pub delta: f64,
}

impl Step {
    /// The sub-step of `params` at gap deviation `eta`.
    pub fn new(params: &Params, eta: f64) -> Self {
        Step {
            lp: Loop::new(params, eta),
            alpha: params.alpha,
            delta: params.dt / params.n_sub as f64,
        }
    }

    /// `(a, b, k)` of the module docs.
    fn abk(&self) -> (f64, f64, f64) {
        let Loop { tau, p, ki } = self.lp;
        let d = self.delta;
        let c = d / tau;
        let den = 1.0 + c * self.alpha * (p + ki * d / 2.0);
        (c * (p + ki * d) / den, c / den, ki * d / 2.0)
    }

    /// The amplification matrix `M` of `(x, y)` over one sub-step.
    pub fn matrix(&self) -> Matrix2<f64> {
        let (a, b, k) = self.abk();
        Matrix2::new(1.0 - a, b, -k * (2.0 - a), 1.0 - k * b)
    }

    /// Eigenvalues of `M` (closed form from trace and determinant), sorted.
    pub fn eigenvalues(&self) -> [Complex; 2] {
        let (a, b, k) = self.abk();
        let half_tr = (2.0 - a - k * b) / 2.0;
        let det = 1.0 - a + k * b;
        let disc = half_tr * half_tr - det;
        let mut out = if disc >= 0.0 {
            let r = disc.sqrt();
            [
                Complex {
                    re: half_tr + r,
                    im: 0.0,
                },
                Complex {
                    re: half_tr - r,
                    im: 0.0,
                },
            ]
        } else {
            let r = (-disc).sqrt();
            [
                Complex { re: half_tr, im: r },
                Complex {
                    re: half_tr,
                    im: -r,
                },
            ]
        };
        super::sort_poles(&mut out);
        out
    }

    /// Spectral radius of one sub-step, `ρ(M)`, from nalgebra's eigenvalues; NaN when an
    /// eigenvalue is (a matrix that overflowed, [`max_substep`]), never a NaN dropped as 0.
    pub fn radius(&self) -> f64 {
        self.matrix()
            .complex_eigenvalues()
            .iter()
            .map(|z| z.norm())
            .fold(0.0, |r, n| if n.is_nan() { n } else { r.max(n) })
    }

    /// `Q(δ)` of the module docs: negative exactly where the sub-step is stable.
    pub fn q(&self) -> f64 {
        let Loop { tau, p, ki } = self.lp;
        let (al, d) = (self.alpha, self.delta);
        (1.0 - al) * ki * d * d + (1.0 - 2.0 * al) * p * d - 2.0 * tau
    }
}

/// The longest sub-step δ whose amplification matrix is finite, with a factor 2 to spare:
/// its largest terms grow as `ki·δ²/τ` ([`Step::matrix`]), which overflows f64 beyond
/// `√(τ·f64::MAX/ki)` (about 1e153 s for the paper's loop). A longer step made the matrix
/// NaN and the spectral radius 0 ("stable"; `stability --dt=1e300`).
pub fn max_substep(lp: &Loop) -> f64 {
    0.5 * (lp.tau * f64::MAX / lp.ki).sqrt()
}

/// Spectral radius of one outer step `Δt` (`n_sub` sub-steps at a fixed gap): `ρ(M)^n_sub`.
pub fn spectral_radius(params: &Params, eta: f64) -> f64 {
    Step::new(params, eta).radius().powi(params.n_sub as i32)
}

/// The critical sub-step δ* (closed form, root of `Q`), `None` where every δ is stable.
pub fn critical_substep(lp: &Loop, alpha: f64) -> Option<f64> {
    let (qa, qb, qc) = (
        (1.0 - alpha) * lp.ki,
        (1.0 - 2.0 * alpha) * lp.p,
        -2.0 * lp.tau,
    );
    if qa > 0.0 {
        // Q(0) < 0 and Q opens upwards: one positive root; the form avoids cancellation.
        let disc = qb * qb - 4.0 * qa * qc;
        let root = if qb <= 0.0 {
            (-qb + disc.sqrt()) / (2.0 * qa)
        } else {
            (2.0 * qc) / (-qb - disc.sqrt())
        };
        Some(root)
    } else if qb > 0.0 {
        Some(-qc / qb)
    } else {
        None
    }
}

/// The critical outer step `Δt* = n_sub·δ*` of `params` at gap deviation `eta` (s).
pub fn critical_dt(params: &Params, eta: f64) -> Option<f64> {
    critical_substep(&Loop::new(params, eta), params.alpha).map(|d| d * params.n_sub as f64)
}

/// The same by bisection on nalgebra's spectral radius (cross-check of [`critical_dt`]):
/// the smallest outer step with `ρ > 1 + 1e-9`, searched up to `dt_max`; `None` if the
/// radius stays below that up to `dt_max`.
pub fn critical_dt_bisect(params: &Params, eta: f64, dt_max: f64) -> Option<f64> {
    let unstable = |dt: f64| {
        let mut p = *params;
        p.dt = dt;
        Step::new(&p, eta).radius() > 1.0 + 1e-9
    };
    let mut hi = 1e-6 * Loop::new(params, eta).tau * params.n_sub as f64;
    let mut lo = 0.0;
    while !unstable(hi) {
        lo = hi;
        hi *= 2.0;
        // Also ends on a start that doubling cannot move (0, NaN: a degenerate τ).
        if !(hi <= dt_max && hi > lo) {
            return None;
        }
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if unstable(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(0.5 * (lo + hi))
}
