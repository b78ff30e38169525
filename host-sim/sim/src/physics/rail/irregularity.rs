//! The rail irregularity of a real track: vertical profile, alignment, cross level and gauge
//! from a published spectrum ([`super::spectrum`]), synthesised and tabulated as the Table 1
//! profile is ([`crate::physics::profile`]: the direct sum of Eq. 3 by the chirp-z transform,
//! read back by 4-point Lagrange), and combined into the left and right rails.
//!
//! # The cosine series
//!
//! Each component is r(x) = Σ a_k cos(Ω_k x + φ_k) over N terms, Ω_k = Ω_l + (k − ½)ΔΩ,
//! ΔΩ = (Ω_u − Ω_l)/N, with a_k = √(2 S(Ω_k) ΔΩ) for the one-sided density S: each term
//! carries the variance a_k²/2 = S(Ω_k)ΔΩ of its cell. (Eq. 4's a_k = 2√(G ΔΩ) is the same
//! rule for Table 1's two-sided G = S/2.) The phases φ_k = 2π p_k come from the core's
//! SplitMix64, one draw a term, from the state `mix(seed ^ stream)` with a stream constant
//! per component ([`STREAMS`]), so the four components of one seed are independent draws
//! (the argument of `maglev_core::irregularity`'s module docs) and independent of the Table 1
//! profiles of the same seed.
//!
//! # Left and right rails
//!
//! Left is the rail on +Y. Heights z are up, lateral positions y along +Y, both deviations of
//! the rail head from its nominal position (m):
//!
//! ```text
//! z_left  = z_v + c/2      z_right = z_v − c/2         (c: cross level)
//! y_left  = y_a + g/2      y_right = y_a − g/2         (g: gauge widening)
//! ```
//!
//! The project's vertical contact law (docs/cars.md) takes r_z > 0 as a rail *lower* than
//! nominal: there r_z = −z.

use super::spectrum::{Component, TrackSpectrum};
use crate::physics::profile::{grid, Profile};
use crate::{Error, Result};
use maglev_core::irregularity::{SplitMix64, Term};
use std::f64::consts::TAU;

/// Stream constants of the four components ([`Component::ALL`]'s order): ASCII "trk-V",
/// "trk-A", "trk-C", "trk-G".
pub const STREAMS: [u64; 4] = [
    0x7472_6B2D_5600_0000,
    0x7472_6B2D_4100_0000,
    0x7472_6B2D_4300_0000,
    0x7472_6B2D_4700_0000,
];

/// The wavelength band and the number of terms of a synthesis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Band {
    /// Shortest wavelength, m.
    pub wavelength_min: f64,
    /// Longest wavelength, m.
    pub wavelength_max: f64,
    /// Number of cosine terms N.
    pub terms: usize,
}

impl Default for Band {
    /// 1–120 m in 2000 terms (ΔΩ = 3.1e-3 rad/m: the profile repeats after 2π/ΔΩ = 2017 m).
    fn default() -> Self {
        Band {
            wavelength_min: 1.0,
            wavelength_max: 120.0,
            terms: 2000,
        }
    }
}

impl Band {
    /// Most terms a band may have (the core generator's capacity, Table 1's N).
    pub const MAX_TERMS: usize = maglev_core::irregularity::DEFAULT_CAPACITY;

    /// (Ω_l, Ω_u) in rad/m, or a one-line error naming the key and the limit.
    pub fn omegas(&self) -> Result<(f64, f64)> {
        let key = "rail_irregularity";
        let (lo, hi) = (self.wavelength_min, self.wavelength_max);
        if !(lo.is_finite() && lo > 0.0) {
            return Err(Error::invalid(
                format!("{key}.wavelength_min_m"),
                format!("must be finite and > 0, got {lo}"),
            ));
        }
        if !(hi.is_finite() && hi > lo) {
            return Err(Error::invalid(
                format!("{key}.wavelength_max_m"),
                format!("must be finite and > wavelength_min_m = {lo}, got {hi}"),
            ));
        }
        if self.terms == 0 || self.terms > Self::MAX_TERMS {
            return Err(Error::invalid(
                format!("{key}.terms"),
                format!("must be in 1..={}, got {}", Self::MAX_TERMS, self.terms),
            ));
        }
        Ok((TAU / hi, TAU / lo))
    }
}

/// The cosine terms of `component` of `spectrum` over `band` for `seed`, shifted so that
/// evaluating at ξ gives r(origin + ξ) (as `Irregularity::with_origin`). Frequencies in
/// turns/m, amplitudes in m, phases in turns.
pub fn terms(
    spectrum: &TrackSpectrum,
    component: Component,
    band: &Band,
    seed: u64,
    origin: f64,
) -> Result<Vec<Term<f64>>> {
    let (lo, hi) = band.omegas()?;
    let n = band.terms;
    let step = (hi - lo) / n as f64;
    let stream = STREAMS[component.index()];
    let mut rng = SplitMix64::new(SplitMix64::mix(seed ^ stream));
    (1..=n)
        .map(|k| {
            let omega = lo + (k as f64 - 0.5) * step;
            let freq = omega / TAU;
            let amp = (2.0 * spectrum.density(component, omega) * step).sqrt();
            let p = rng.next_unit();
            let shift = freq * origin;
            let phase = fract(p + fract(shift));
            if amp.is_finite() && phase.is_finite() {
                Ok(Term { freq, amp, phase })
            } else {
                Err(Error::invalid(
                    "rail_irregularity",
                    format!("term {k} is not finite (origin {origin} m)"),
                ))
            }
        })
        .collect()
}

/// v − ⌊v⌋ in [0, 1).
fn fract(v: f64) -> f64 {
    let r = v - v.floor();
    if r >= 1.0 {
        0.0
    } else {
        r
    }
}

/// The four components of a track's irregularity, tabulated over a stretch of track.
#[derive(Clone, Debug)]
pub struct RailIrregularity {
    profiles: Vec<Profile>,
}

impl RailIrregularity {
    /// The irregularity of `spectrum` over `band` for `seed`, sampled over
    /// `[x_min, x_max]` (0 outside).
    pub fn new(
        spectrum: &TrackSpectrum,
        band: &Band,
        seed: u64,
        x_min: f64,
        x_max: f64,
    ) -> Result<Self> {
        if !(x_min.is_finite() && x_max.is_finite() && x_max > x_min) {
            return Err(Error::invalid(
                "rail_irregularity",
                format!("the extent [{x_min}, {x_max}] m is empty or not finite"),
            ));
        }
        let (x0, _) = grid(x_min, x_max);
        let all = Component::ALL
            .iter()
            .map(|&c| terms(spectrum, c, band, seed, x0))
            .collect::<Result<Vec<_>>>()?;
        Self::from_terms(&all, x_min, x_max)
    }

    /// The irregularity of given cosine terms, one list per component in
    /// [`Component::ALL`]'s order, each shifted to the grid's origin as [`terms`] shifts
    /// them (the origin of `profile::grid(x_min, x_max)`), sampled over `[x_min, x_max]`.
    pub fn from_terms(components: &[Vec<Term<f64>>], x_min: f64, x_max: f64) -> Result<Self> {
        if !(x_min.is_finite() && x_max.is_finite() && x_max > x_min) || components.len() != 4 {
            return Err(Error::invalid(
                "rail_irregularity",
                format!(
                    "needs 4 components over a finite extent, got {} over [{x_min}, {x_max}] m",
                    components.len()
                ),
            ));
        }
        let (x0, n) = grid(x_min, x_max);
        let profiles = components
            .iter()
            .map(|t| Profile::from_terms(t, x0, n))
            .collect::<Result<_>>()?;
        Ok(RailIrregularity { profiles })
    }

    /// One component at x (m): a height or lateral deviation in m.
    pub fn component(&self, component: Component, x: f64) -> f64 {
        self.profiles[component.index()].at(x)
    }

    /// The left rail's deviation (y, z) at x (module docs).
    pub fn left(&self, x: f64) -> (f64, f64) {
        let [v, a, c, g] = self.all(x);
        (a + 0.5 * g, v + 0.5 * c)
    }

    /// The right rail's deviation (y, z) at x (module docs).
    pub fn right(&self, x: f64) -> (f64, f64) {
        let [v, a, c, g] = self.all(x);
        (a - 0.5 * g, v - 0.5 * c)
    }

    /// The four components at x, in [`Component::ALL`]'s order (m).
    pub fn all(&self, x: f64) -> [f64; 4] {
        Component::ALL.map(|c| self.component(c, x))
    }
}
