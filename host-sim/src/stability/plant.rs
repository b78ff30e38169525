//! One magnet carrying a body through the Fig. 1 suspension, under a rigid rail: the
//! closed-loop poles of the linearised magnet + law, including the gap's own mode.
//!
//! # The plant (a minimal, documented choice)
//! A body of mass `m_b` sits on a Kelvin–Voigt spring–damper (`k`, `c`; Fig. 1: 200 kN/m,
//! 10 kN·s/m) above a magnet of mass `m_m` (model.md §9 default 0); the magnet pulls itself
//! up towards a rigid rail with `F = K0·g²` (Eq. 1). The magnet carries everything:
//! `p0 = (m_b + m_m)·9.81`, so `m_b = p0/9.81 − m_m` (with `m_m = 0`, `m_b = p0/9.81`).
//! Z is up; the gap is `h = h0 − z_m` (model.md §2 with `z_g = r = 0`), so `η = −z_m/h0`.
//!
//! # Linearisation about the static equilibrium
//! `∂F/∂g = 2·K0·g0 = 2·p0/g0`, i.e. `ΔF = 2·p0·x` per unit of `x`. The force depends on the
//! gap only through the coil (Eq. 9): `τ·ẋ = y − η − p·x`, `ẏ = −ki·x` (see [`super::gloop`]).
//!
//! ```text
//! m_m·z̈_m = 2·p0·x − k·(z_m − z_b) − c·(ż_m − ż_b)
//! m_b·z̈_b =          k·(z_m − z_b) + c·(ż_m − ż_b)
//! τ·ẋ     = y + z_m/h0 − p·x,          ẏ = −ki·x
//! ```
//!
//! With `m_m = 0` the first line is an algebraic force balance that gives `ż_m` (needs
//! `c > 0`) and the state drops to `(z_m, z_b, ż_b, x, y)`.
//!
//! # What the law leaves of the gap mode
//! The law regulates `g`, i.e. the force (`F = K0·g²` has no `h` in it), not the gap. Two
//! consequences, both visible in the poles:
//! * **a pole at exactly 0**: every gap is an equilibrium (`x = 0`, `y = η`, springs
//!   unstretched): nothing restores the magnet to `h0`; the integral simply re-trims the
//!   voltage to `R0·h·g0`.
//! * **a real pole in the right half-plane**: a closing gap (`z_m` up, `η < 0`) raises `g`
//!   through the coil (`τ·ẋ = … − η`), the force rises and closes the gap further. For a
//!   rigid magnet + body of total mass `M` the characteristic polynomial (after the zero
//!   pole) is `M·τ·s³ + M·p·s² + M·ki·s − 2·p0/h0`; its constant term is negative and its
//!   leading one positive, so it has a positive real root for *every* choice of gains. A
//!   spring–damper suspension does not change that: at `s = 0` it is a rigid link, so the
//!   reduced polynomial still starts negative. At the paper's values the rigid root is
//!   ≈ +3.2 s⁻¹ (e-folding ≈ 0.3 s, the time a car needs to cross one 25 m span at 100 m/s).
//! * with the Fig. 1 suspension and a massless magnet (`maglev stability`) it is worse: the
//!   poles are +7.68 ± 22.3j, +3.99, 0, −44.4 s⁻¹ — the body's bounce on its spring couples
//!   with the g-loop into a growing 3.6 Hz oscillation besides the real divergence.
//!
//! The paper's vehicle therefore relies on the short passage time, not on the law, to keep
//! the gap; a gap (position) loop would be needed for a free-flying vehicle.

use super::gloop::Loop;
use super::Complex;
use maglev_core::levitation::GRAVITY;
use maglev_core::Params;
use nalgebra::DMatrix;

/// The suspension between magnet and body (SI).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Suspension {
    /// Magnet mass m_m (kg), ≥ 0.
    pub magnet_mass: f64,
    /// Spring stiffness k (N/m), > 0.
    pub k: f64,
    /// Damping c (N·s/m), ≥ 0 (> 0 when the magnet is massless).
    pub c: f64,
}

impl Suspension {
    /// Fig. 1: k = 200 kN/m, c = 10 kN·s/m, massless magnet (model.md §9 default).
    pub const FIG1: Suspension = Suspension {
        magnet_mass: 0.0,
        k: 200e3,
        c: 10e3,
    };
}

/// The linearised closed loop: state matrix and its eigenvalues.
#[derive(Clone, Debug)]
pub struct Plant {
    /// State matrix (6×6 with a magnet mass, 5×5 without).
    pub a: DMatrix<f64>,
    /// Names of the states, in order.
    pub states: &'static [&'static str],
    /// Body mass m_b (kg).
    pub body_mass: f64,
}

impl Plant {
    /// Builds the closed loop for `params` (only i0, h0, R0, KP, KI, p0 matter) and `s`.
    pub fn new(params: &Params, s: &Suspension) -> Result<Self, String> {
        let lp = Loop::new(params, 0.0);
        let body_mass = params.p0 / GRAVITY - s.magnet_mass;
        if !(s.magnet_mass >= 0.0 && s.magnet_mass.is_finite()) {
            return Err("magnet mass must be finite and >= 0".into());
        }
        if body_mass.is_nan() || body_mass <= 0.0 {
            return Err(format!(
                "magnet mass {} kg leaves no body mass: p0/9.81 = {} kg",
                s.magnet_mass,
                params.p0 / GRAVITY
            ));
        }
        if !(s.k > 0.0 && s.k.is_finite() && s.c >= 0.0 && s.c.is_finite()) {
            return Err("suspension needs k > 0 and c >= 0, finite".into());
        }
        let (fx, h0) = (2.0 * params.p0, params.h0);
        let (k, c, mb) = (s.k, s.c, body_mass);
        let (tau, p, ki) = (lp.tau, lp.p, lp.ki);
        if s.magnet_mass > 0.0 {
            let mm = s.magnet_mass;
            // z_m, v_m, z_b, v_b, x, y
            #[rustfmt::skip]
            let a = DMatrix::from_row_slice(6, 6, &[
                0.0, 1.0, 0.0, 0.0, 0.0, 0.0,
                -k / mm, -c / mm, k / mm, c / mm, fx / mm, 0.0,
                0.0, 0.0, 0.0, 1.0, 0.0, 0.0,
                k / mb, c / mb, -k / mb, -c / mb, 0.0, 0.0,
                1.0 / (h0 * tau), 0.0, 0.0, 0.0, -p / tau, 1.0 / tau,
                0.0, 0.0, 0.0, 0.0, -ki, 0.0,
            ]);
            Ok(Plant {
                a,
                states: &["z_m", "v_m", "z_b", "v_b", "x", "y"],
                body_mass,
            })
        } else {
            if c.is_nan() || c <= 0.0 {
                return Err("a massless magnet needs a damper c > 0".into());
            }
            // z_m, z_b, v_b, x, y;  ż_m = v_b + (2·p0·x − k(z_m − z_b))/c
            #[rustfmt::skip]
            let a = DMatrix::from_row_slice(5, 5, &[
                -k / c, k / c, 1.0, fx / c, 0.0,
                0.0, 0.0, 1.0, 0.0, 0.0,
                0.0, 0.0, 0.0, fx / mb, 0.0,
                1.0 / (h0 * tau), 0.0, 0.0, -p / tau, 1.0 / tau,
                0.0, 0.0, 0.0, -ki, 0.0,
            ]);
            Ok(Plant {
                a,
                states: &["z_m", "z_b", "v_b", "x", "y"],
                body_mass,
            })
        }
    }

    /// Closed-loop poles (1/s), sorted by descending real part.
    pub fn poles(&self) -> Vec<Complex> {
        super::sorted_poles(self.a.complex_eigenvalues().iter().copied())
    }
}

/// The positive real root of the rigid-mass cubic `M·τ·s³ + M·p·s² + M·ki·s − 2·p0/h0`
/// (magnet and body moving as one), by bisection: the gap mode's growth rate (1/s).
pub fn rigid_growth_rate(params: &Params) -> f64 {
    let lp = Loop::new(params, 0.0);
    let m = params.p0 / GRAVITY;
    let f =
        |s: f64| ((m * lp.tau * s + m * lp.p) * s + m * lp.ki) * s - 2.0 * params.p0 / params.h0;
    let (mut lo, mut hi) = (0.0, 1.0);
    while f(hi) < 0.0 {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}
