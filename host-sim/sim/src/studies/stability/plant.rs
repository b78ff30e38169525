//! One magnet carrying a body through the Fig. 1 suspension, under a rigid rail: the
//! closed-loop poles of the linearised magnet + law, including the gap's own mode.
//!
//! # The plant (a minimal, documented choice)
//! A body of mass `m_b` sits on a Kelvin–Voigt spring–damper (`k`, `c`; Fig. 1: 200 kN/m,
//! 10 kN·s/m) above a magnet of mass `m_m` (docs/model.md §9 default 0); the magnet pulls itself
//! up towards a rigid rail with `F = K0·g²` (Eq. 1). The magnet carries everything:
//! `p0 = (m_b + m_m)·9.81`, so `m_b = p0/9.81 − m_m` (with `m_m = 0`, `m_b = p0/9.81`).
//! Z is up; the gap is `h = h0 + σ·z_m` with `σ = Geometry::levitation_sign()` (docs/model.md §2
//! with `z_g = r = 0`: `σ = −1` for "ems", `+1` for "paper"), so `η = σ·z_m/h0`.
//!
//! # Linearisation about the static equilibrium
//! `∂F/∂g = 2·K0·g0 = 2·p0/g0`, i.e. `ΔF = 2·p0·x` per unit of `x`. The force depends on the
//! gap only through the coil (Eq. 9): `τ·ẋ = y − η − p·x`, `ẏ = −ki·x` (see [`super::inner_loop`];
//! the rows are written once, in [`super::magnet`]).
//!
//! ```text
//! m_m·z̈_m = 2·p0·x − k·(z_m − z_b) − c·(ż_m − ż_b)
//! m_b·z̈_b =          k·(z_m − z_b) + c·(ż_m − ż_b)
//! τ·ẋ     = y − σ·z_m/h0 − p·x,          ẏ = −ki·x
//! ```
//!
//! With `m_m = 0` the first line is an algebraic force balance that gives `ż_m` (needs
//! `c > 0`) and the state drops to `(z_m, z_b, ż_b, x, y)`.
//!
//! The rest of this section is the EMS reading (`σ = −1`, the plant of issue 5 that
//! `maglev stability` without `--scenario` still reports); under the paper's reading the same
//! quarter vehicle is stable apart from the zero pole (docs/model.md §2, item 1).
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

use super::inner_loop::Loop;
use super::magnet::{self, Slots};
use super::Complex;
use maglev_core::gap::Geometry;
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
    /// Fig. 1: k = 200 kN/m, c = 10 kN·s/m, massless magnet (docs/model.md §9 default).
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
    /// Builds the closed loop for `params` (only i0, h0, R0, KP, KI, p0 matter), `s` and the
    /// gap geometry (`h − h0 = levitation_sign·z_m`, docs/model.md §2); the magnet carries
    /// everything, `m_b = p0/9.81 − m_m`.
    pub fn new(params: &Params, s: &Suspension, geometry: Geometry) -> crate::Result<Self> {
        let body_mass = params.p0 / GRAVITY - s.magnet_mass;
        if body_mass.is_nan() || body_mass <= 0.0 {
            return Err(crate::Error::invalid(
                "magnet_mass",
                format!(
                    "{} kg leaves no body mass: must be < p0/9.81 = {} kg",
                    s.magnet_mass,
                    params.p0 / GRAVITY
                ),
            ));
        }
        Self::with_body(params, s, body_mass, geometry.levitation_sign(), 1.0)
    }

    /// The same plant with an explicit body mass `m_b` (kg), gap `η = eta_per_m·z_m/h0` and
    /// force change `force_gain·2·p0·x` (1 for a levitation magnet; 2 for the differential
    /// mode of a guidance pair, [`super::gap_loop::GapLoopPlant::guidance_pair`]).
    pub fn with_body(
        params: &Params,
        s: &Suspension,
        body_mass: f64,
        eta_per_m: f64,
        force_gain: f64,
    ) -> crate::Result<Self> {
        let lp = Loop::new(params, 0.0);
        if !(s.magnet_mass >= 0.0 && s.magnet_mass.is_finite()) {
            return Err(crate::Error::invalid(
                "magnet_mass",
                format!("must be finite and >= 0, got {} kg", s.magnet_mass),
            ));
        }
        if !(body_mass > 0.0 && body_mass.is_finite()) {
            return Err(crate::Error::invalid(
                "body_mass",
                format!("must be positive, got {body_mass} kg"),
            ));
        }
        if !(s.k > 0.0 && s.k.is_finite() && s.c >= 0.0 && s.c.is_finite()) {
            return Err(crate::Error::invalid(
                "suspension",
                format!(
                    "needs k > 0 and c >= 0, finite, got k = {}, c = {}",
                    s.k, s.c
                ),
            ));
        }
        let fx = force_gain * 2.0 * params.p0;
        let (k, c, mb) = (s.k, s.c, body_mass);
        let eta = [(0, eta_per_m / params.h0)];
        if s.magnet_mass > 0.0 {
            let mm = s.magnet_mass;
            // z_m, v_m, z_b, v_b, x, y
            #[rustfmt::skip]
            let mut a = DMatrix::from_row_slice(6, 6, &[
                0.0, 1.0, 0.0, 0.0, 0.0, 0.0,
                -k / mm, -c / mm, k / mm, c / mm, fx / mm, 0.0,
                0.0, 0.0, 0.0, 1.0, 0.0, 0.0,
                k / mb, c / mb, -k / mb, -c / mb, 0.0, 0.0,
                0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
                0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
            ]);
            magnet::write_rows(
                &mut a,
                Slots {
                    x: 4,
                    y: 5,
                    q: None,
                    delay: None,
                },
                &eta,
                &lp,
                None,
            )?;
            Ok(Plant {
                a,
                states: &["z_m", "v_m", "z_b", "v_b", "x", "y"],
                body_mass,
            })
        } else {
            if c.is_nan() || c <= 0.0 {
                return Err(crate::Error::invalid(
                    "suspension.c",
                    format!("a massless magnet needs a damper c > 0, got {c}"),
                ));
            }
            // z_m, z_b, v_b, x, y;  ż_m = v_b + (2·p0·x − k(z_m − z_b))/c
            #[rustfmt::skip]
            let mut a = DMatrix::from_row_slice(5, 5, &[
                -k / c, k / c, 1.0, fx / c, 0.0,
                0.0, 0.0, 1.0, 0.0, 0.0,
                0.0, 0.0, 0.0, fx / mb, 0.0,
                0.0, 0.0, 0.0, 0.0, 0.0,
                0.0, 0.0, 0.0, 0.0, 0.0,
            ]);
            magnet::write_rows(
                &mut a,
                Slots {
                    x: 3,
                    y: 4,
                    q: None,
                    delay: None,
                },
                &eta,
                &lp,
                None,
            )?;
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
    // Ends at the latest when `hi` overflows (a cubic negative for every finite s: NaN out).
    while f(hi) < 0.0 && hi.is_finite() {
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
