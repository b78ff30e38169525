//! The flexible girder under the magnets, for the coupled analysis (issue 26 point 4): the
//! first vertical bending modes of the FE span that carries the magnets, each as one
//! mass–spring–damper in its modal coordinate, and what each magnet sees of it.
//!
//! # The model
//! The span is the FE model the runs use ([`crate::physics::fe::SpanModel`], the case's
//! `elements_per_span`), its modes from [`crate::physics::fe::natural_modes`] (only the `bending-z`
//! ones: a magnet on the beam axis, as the unit's, neither twists nor bends the span
//! sideways). Each mode `j` is scaled to a peak vertical displacement of 1 along the span, so
//! the girder under magnet `k` moves `z_g,k = Σ_j φ_j(x_k)·ξ_j` and the mode obeys
//!
//! ```text
//! m_j·(ξ̈_j + 2·ζ_j·ω_j·ξ̇_j + ω_j²·ξ_j) = Σ_k φ_j(x_k)·F_k        (girder eq. G1)
//! m_j = 1/peak_j²   (the mass-normalised FE shape has φᵀMφ = 1)
//! ζ_j = α/(2·ω_j) + β·ω_j/2   (the case's Rayleigh damping C = αM + βK; 0: undamped)
//! ```
//!
//! with `F_k` the load of magnet `k` on the girder (minus the force on the magnet: the magnet
//! pulls the rail as the rail pulls the magnet). The gap (Eq. 2) reads the girder through
//! `z_g`; the coupled closed loop is [`super::vehicle::VehiclePlant::on_girder`].
//!
//! # The check
//! For a simply supported Timoshenko span the closed form of mode `n` is the lower root of
//! the series term's frequency equation ([`crate::physics::modal::natural_frequencies`], docs/model.md
//! §8) with the shape `sin(nπx/L)`, modal mass `m·L/2` (rotary inertia aside). Each mode
//! reports that frequency and the FE's relative difference.

use crate::input::case::Case;
use crate::physics::fe::{natural_modes, ModeKind, SpanModel};
use crate::physics::vehicle::Wheel;
use serde::Serialize;

/// Sample points per span for a mode's peak (its vertical displacement at `L·i/PEAK_SAMPLES`).
const PEAK_SAMPLES: usize = 400;

/// One bending mode of the span under the magnets (SI).
#[derive(Clone, Debug, Serialize)]
pub struct GirderMode {
    /// Span (1-based) and the mode's rank among its vertical bending modes (half-waves).
    pub span: usize,
    pub n: usize,
    pub frequency_hz: f64,
    /// Modal mass for a unit peak displacement (kg, eq. G1).
    pub modal_mass_kg: f64,
    /// Modal damping ratio from the case's Rayleigh damping.
    pub damping_ratio: f64,
    /// The mode's vertical displacement under each magnet (wheel order), peak 1.
    pub at_magnets: Vec<f64>,
    /// The closed-form Timoshenko frequency (Hz) and the FE's relative difference from it.
    pub closed_form_hz: f64,
    pub fe_vs_closed_form: f64,
}

impl GirderMode {
    /// ω (rad/s).
    pub fn omega(&self) -> f64 {
        2.0 * std::f64::consts::PI * self.frequency_hz
    }
}

/// The first `count` vertical bending modes of every span of `case` that carries a magnet of
/// `wheels` (positions `x0`, at standstill), module docs. An error for a viaduct (its spans
/// are not on rigid supports) and for a magnet off the beam axis (torsion not modelled).
pub fn girder_modes(case: &Case, wheels: &[Wheel], count: usize) -> crate::Result<Vec<GirderMode>> {
    if case.viaduct.is_some() {
        return Err(crate::Error::invalid(
            "bridge.kind",
            "girder_modes needs simply supported spans on rigid supports, not a viaduct",
        ));
    }
    if wheels.iter().any(|w| w.ey != 0.0 || w.ez != 0.0) {
        return Err(crate::Error::invalid(
            "vehicle",
            "girder_modes models magnets on the beam axis only (no torsion)",
        ));
    }
    let bridge = &case.bridge;
    let mut out = Vec::new();
    let mut start = 0.0;
    for (s, &length) in bridge.spans.iter().enumerate() {
        let local: Vec<Option<f64>> = wheels
            .iter()
            .map(|w| Some(w.x0 - start).filter(|x| (0.0..=length).contains(x)))
            .collect();
        start += length;
        if local.iter().all(Option::is_none) {
            continue;
        }
        let model = SpanModel::new(&bridge.section, length, case.elements_per_span)?;
        let modes = natural_modes(&model)?;
        let z = |shape, x: f64| model.motion(shape, x, 0.0, 0.0).map_or(0.0, |m| m.z);
        for (rank, mode) in modes
            .iter()
            .filter(|m| m.kind == ModeKind::BendingZ)
            .take(count)
            .enumerate()
        {
            let peak = (0..=PEAK_SAMPLES)
                .map(|i| z(&mode.shape, length * i as f64 / PEAK_SAMPLES as f64))
                .fold(0.0, |p: f64, v| if v.abs() > p.abs() { v } else { p });
            if peak == 0.0 {
                return Err(crate::Error::numerical(
                    "a girder mode with no vertical motion",
                ));
            }
            let closed =
                crate::physics::modal::natural_frequencies(&bridge.section, length, rank + 1)
                    .vertical[0]
                    / (2.0 * std::f64::consts::PI);
            let (alpha, beta) = case.damping.map_or((0.0, 0.0), |r| (r.alpha, r.beta));
            out.push(GirderMode {
                span: s + 1,
                n: rank + 1,
                frequency_hz: mode.frequency_hz,
                modal_mass_kg: 1.0 / (peak * peak),
                damping_ratio: alpha / (2.0 * mode.omega) + beta * mode.omega / 2.0,
                at_magnets: local
                    .iter()
                    .map(|x| x.map_or(0.0, |x| z(&mode.shape, x) / peak))
                    .collect(),
                closed_form_hz: closed,
                fe_vs_closed_form: mode.frequency_hz / closed - 1.0,
            });
        }
    }
    Ok(out)
}
