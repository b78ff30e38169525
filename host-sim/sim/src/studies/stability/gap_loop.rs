//! The magnet + body plant of [`super::plant`] closed by the outer gap loop
//! (`maglev_core::gap_control`): its poles, and the design of the loop's gains.
//!
//! # The closed loop
//! The inner law with a reference `x_ref` (Eq. 8 with `e = g_ref − g`, Eq. 9–10) is, per unit,
//!
//! ```text
//! τ·ẋ = y − η − p·x + kpv·x_ref,      ẏ = ki·(x_ref − x)
//! ```
//!
//! (the rows of [`super::plant`] plus the reference's two entries). The outer loop, continuous
//! form of the core's discrete one, adds the derivative filter's state `q`:
//!
//! ```text
//! tf·q̇ = η − q,      x_ref = kp·η + (kd/tf)·(η − q),      η = −z_m/h0
//! ```
//!
//! so the state is the plant's plus `q` (7×7 with a magnet mass, 6×6 without). The core
//! samples the gap once per outer step and holds `x_ref` (one step of delay); at the steps
//! used here (≤ 1 ms against poles ≤ ~100 s⁻¹) that shifts the poles by O(|s|·Δt), which the
//! tests' margin covers.
//!
//! # Gain design
//! Output feedback from the gap alone cannot place all poles, so the gains minimise the
//! spectral abscissa (largest real part of the closed-loop poles) of this matrix for one
//! magnet carrying a quarter of the Fig. 1 body (massless magnet) at the paper's inner gains,
//! `tf` fixed at 2 ms: a log grid refined by a compass search ([`design`]). It finds
//! `kp ≈ 3.98e-3`, `kd ≈ 4.22e-3 s`, abscissa ≈ −3.24 s⁻¹ (the abscissa is not smooth: other
//! local minima, e.g. −3.40 s⁻¹ near `kp = 2.6e-3`, `kd = 3.8e-3 s`, are as good and as
//! sensitive). [`GapParams::designed`] rounds to `kp = 4.0e-3`, `kd = 4.2e-3 s`: poles
//! −3.17 ± 2.51j, −3.41 (body bounce and gap mode), −6.84 ± 64.7j (the inner loop's pair,
//! from −2.51 ± 38.7j without the outer loop) and −502 s⁻¹ (filter). A test checks they are
//! within 10 % of the search's abscissa. With a magnet mass (500 kg) these gains are
//! unstable: gap-only PD output feedback is plant-specific; redesign for another plant.
//! the optimum abscissa.

use super::magnet::{self, Slots};
use super::plant::{Plant, Suspension};
use super::Complex;
use maglev_core::gap::{self, Geometry};
use maglev_core::gap_control::GapParams;
use maglev_core::levitation::GRAVITY;
use maglev_core::Params;
use nalgebra::DMatrix;

/// The closed loop with the gap loop: state matrix and names.
#[derive(Clone, Debug)]
pub struct GapLoopPlant {
    /// State matrix (the plant's states, then `q`).
    pub a: DMatrix<f64>,
    /// Names of the states, in order.
    pub states: Vec<&'static str>,
}

impl GapLoopPlant {
    /// Builds the closed loop for the inner `params`, suspension `s`, outer `gains`
    /// (`tf > 0`: the continuous model needs the filter) and gap geometry.
    pub fn new(
        params: &Params,
        s: &Suspension,
        gains: &GapParams,
        geometry: Geometry,
    ) -> crate::Result<Self> {
        Self::from_plant(
            params,
            Plant::new(params, s, geometry)?,
            gains,
            geometry.levitation_sign(),
        )
    }

    fn from_plant(
        params: &Params,
        plant: Plant,
        gains: &GapParams,
        eta_per_m: f64,
    ) -> crate::Result<Self> {
        gains
            .validate()
            .map_err(|e| crate::Error::invalid("gap_loop", e.to_string()))?;
        let lp = super::inner_loop::Loop::new(params, 0.0);
        let n = plant.a.nrows();
        let mut a = plant.a.clone().resize(n + 1, n + 1, 0.0);
        // z_m is state 0 in both plant variants.
        let at = Slots {
            x: n - 2,
            y: n - 1,
            q: Some(n),
            delay: None,
        };
        magnet::write_rows(&mut a, at, &[(0, eta_per_m / params.h0)], &lp, Some(gains))?;
        let mut states = plant.states.to_vec();
        states.push("q");
        Ok(GapLoopPlant { a, states })
    }

    /// The differential mode of a guidance pair under the same loop (docs/model.md §2): each
    /// magnet runs the loop on its own gap; with `d` in place of `z_m`, the suspension's
    /// lateral spring–damper and the same body mass, `x_d = σ_g·(x_L − x_R)/2` (σ_g the
    /// geometry's `guidance_sign`) sees `η_d = σ_g·(∂h_L/∂d)·d/h0` and gives the net force
    /// `F_y = 4·p0·x_d`: this plant with the force column doubled.
    pub fn guidance_pair(
        params: &Params,
        s: &Suspension,
        gains: &GapParams,
        geometry: Geometry,
    ) -> crate::Result<Self> {
        Self::with_body(
            params,
            s,
            params.p0 / GRAVITY - s.magnet_mass,
            gains,
            geometry,
            true,
        )
    }

    /// One magnet's loop with an explicit body mass (kg): the levitation magnet
    /// (`pair = false`, as [`GapLoopPlant::new`]) or a guidance pair's differential mode
    /// (`pair = true`, as [`GapLoopPlant::guidance_pair`]).
    pub fn with_body(
        params: &Params,
        s: &Suspension,
        body_mass: f64,
        gains: &GapParams,
        geometry: Geometry,
        pair: bool,
    ) -> crate::Result<Self> {
        let (sign, gain) = if pair {
            (
                geometry.guidance_sign() * gap::guidance_gaps(0.0, 1.0).0,
                2.0,
            )
        } else {
            (geometry.levitation_sign(), 1.0)
        };
        let plant = Plant::with_body(params, s, body_mass, sign, gain)?;
        Self::from_plant(params, plant, gains, sign)
    }

    /// Closed-loop poles (1/s), sorted by descending real part.
    pub fn poles(&self) -> Vec<Complex> {
        super::sorted_poles(self.a.complex_eigenvalues().iter().copied())
    }

    /// Spectral abscissa: the largest real part of the poles (1/s); < 0 is stable.
    pub fn abscissa(&self) -> f64 {
        self.poles()[0].re
    }
}

/// Spectral abscissa for gains `(kp, kd)` with `tf`, or +∞ if the loop cannot be built.
fn abscissa(params: &Params, s: &Suspension, kp: f64, kd: f64, tf: f64) -> f64 {
    let g = GapParams {
        kp,
        kd,
        tf,
        ..GapParams::designed()
    };
    GapLoopPlant::new(params, s, &g, Geometry::Ems).map_or(f64::INFINITY, |p| p.abscissa())
}

/// Gains `(kp, kd)` minimising the spectral abscissa at filter `tf`, and that abscissa:
/// the best point of a 25 × 25 grid over `kp, kd ∈ [1e-4, 1e-1]` (log-spaced; the abscissa
/// is not smooth and has local minima), refined by a compass search in `(log kp, log kd)`:
/// try ± the step on each axis, move to any improvement, halve the step when none, stop at
/// a relative step of 1e-4. Deterministic.
pub fn design(params: &Params, s: &Suspension, tf: f64) -> (f64, f64, f64) {
    let f = |u: [f64; 2]| abscissa(params, s, u[0].exp(), u[1].exp(), tf);
    let (lo, hi) = (1e-4f64.ln(), 1e-1f64.ln());
    let at = |i: usize| lo + (hi - lo) * i as f64 / 24.0;
    let (mut u, mut best) = ([at(0), at(0)], f64::INFINITY);
    for i in 0..25 {
        for j in 0..25 {
            let v = [at(i), at(j)];
            let fv = f(v);
            if fv < best {
                (u, best) = (v, fv);
            }
        }
    }
    let mut step = 1.0;
    while step > 1e-4 {
        let mut moved = false;
        for axis in 0..2 {
            for sign in [1.0, -1.0] {
                let mut v = u;
                v[axis] += sign * step;
                let fv = f(v);
                if fv < best {
                    (u, best, moved) = (v, fv, true);
                }
            }
        }
        if !moved {
            step *= 0.5;
        }
    }
    (u[0].exp(), u[1].exp(), best)
}

#[cfg(test)]
mod tests;
