//! The flexible girder under the magnets, for the coupled analysis (issue 26 point 4, issue 39
//! point 3): the first modes of the FE span that carries the magnets, each as one
//! mass–spring–damper in its modal coordinate, and what each magnet sees of it.
//!
//! # The model
//! The span is the FE model the runs use ([`crate::physics::fe::SpanModel`], the case's
//! `elements_per_span`), its modes from [`crate::physics::fe::natural_modes`]. Which modes:
//!
//! * the first `count` vertical bending modes (`bending-z`), always;
//! * the first `count` torsion modes where a magnet on the span is off the beam axis
//!   (`ey ≠ 0`: its rail rises and falls as the span twists; `ez ≠ 0` with a guidance pair:
//!   its rail moves sideways as the span twists);
//! * the first `count` lateral bending modes (`bending-y`) where a wheel on the span has a
//!   guidance pair.
//!
//! A magnet on the axis without guidance (the `unit`) sees neither of the last two, so its
//! model holds the vertical modes only. Each mode `j` is scaled to a peak of 1 of its own
//! amplitude along the span (`bending-z`: the axis' vertical displacement, m; `bending-y`: the
//! axis' lateral displacement, m; `torsion`: the twist, rad), and the rail under magnet `k`
//! (the wheel's `(x, ey, ez)`, the rigid link of Eq. 16, as the runs read it) moves
//! `z_g,k = Σ_j φ_j(x_k)·ξ_j` vertically and `y_g,k = Σ_j ψ_j(x_k)·ξ_j` laterally. The mode
//! obeys
//!
//! ```text
//! m_j·(ξ̈_j + 2·ζ_j·ω_j·ξ̇_j + ω_j²·ξ_j) = Σ_k (φ_j(x_k)·F_z,k + ψ_j(x_k)·F_y,k)   (eq. G1)
//! m_j = 1/peak_j²   (the mass-normalised FE shape has φᵀMφ = 1)
//! ζ_j = α/(2·ω_j) + β·ω_j/2   (the case's Rayleigh damping C = αM + βK; 0: undamped)
//! ```
//!
//! with `F_k` the load of magnet `k` on the girder (minus the force on the magnet: the magnet
//! pulls the rail as the rail pulls the magnet). The levitation gap (Eq. 2) reads the girder
//! through `z_g`, the guidance pair's lateral offset through `y_g`; the coupled closed loop
//! is [`super::vehicle::VehiclePlant::on_girder`].
//!
//! # The check
//! For a simply supported Timoshenko span the closed form of mode `n` of each kind is the
//! series term's frequency ([`crate::physics::modal::natural_frequencies`], docs/model.md
//! §8: the lower bending root of its plane, or the torsion frequency). Each mode reports that
//! frequency and the FE's relative difference.

use crate::input::case::Case;
use crate::physics::fe::{natural_modes, ModeKind, SpanModel};
use crate::physics::vehicle::Wheel;
use serde::Serialize;

/// Sample points per span for a mode's peak (its vertical displacement at `L·i/PEAK_SAMPLES`).
const PEAK_SAMPLES: usize = 400;

/// One mode of the span under the magnets (SI).
#[derive(Clone, Debug, Serialize)]
pub struct GirderMode {
    /// Span (1-based) and the mode's rank among the modes of its kind (half-waves).
    pub span: usize,
    pub n: usize,
    /// `bending-z`, `torsion` or `bending-y` (module docs); omitted for `bending-z`.
    #[serde(skip_serializing_if = "is_bending_z")]
    pub kind: &'static str,
    pub frequency_hz: f64,
    /// Modal mass for a unit peak displacement (kg, eq. G1).
    pub modal_mass_kg: f64,
    /// Modal damping ratio from the case's Rayleigh damping.
    pub damping_ratio: f64,
    /// The rail's vertical displacement under each magnet (wheel order), per unit amplitude.
    pub at_magnets: Vec<f64>,
    /// The rail's lateral displacement under each magnet (wheel order), per unit amplitude;
    /// omitted where it is zero under every magnet.
    #[serde(skip_serializing_if = "all_zero")]
    pub lateral_at_magnets: Vec<f64>,
    /// The closed-form Timoshenko frequency (Hz) and the FE's relative difference from it.
    pub closed_form_hz: f64,
    pub fe_vs_closed_form: f64,
}

fn is_bending_z(kind: &&'static str) -> bool {
    *kind == ModeKind::BendingZ.as_str()
}

fn all_zero(v: &[f64]) -> bool {
    v.iter().all(|&x| x == 0.0)
}

impl GirderMode {
    /// ω (rad/s).
    pub fn omega(&self) -> f64 {
        2.0 * std::f64::consts::PI * self.frequency_hz
    }
}

/// The modes of every span of `case` that carries a magnet of `wheels` (positions `x0`, at
/// standstill), `count` of each kind the magnets see (module docs). An error for a viaduct
/// (its spans are not on rigid supports).
pub fn girder_modes(case: &Case, wheels: &[Wheel], count: usize) -> crate::Result<Vec<GirderMode>> {
    if case.viaduct.is_some() {
        return Err(crate::Error::invalid(
            "bridge.kind",
            "girder_modes needs simply supported spans on rigid supports, not a viaduct",
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
        let on: Vec<&Wheel> = wheels
            .iter()
            .zip(&local)
            .filter_map(|(w, x)| x.map(|_| w))
            .collect();
        if on.is_empty() {
            continue;
        }
        let mut kinds = vec![ModeKind::BendingZ];
        if on
            .iter()
            .any(|w| w.ey != 0.0 || (w.dof_y.is_some() && w.ez != 0.0))
        {
            kinds.push(ModeKind::Torsion);
        }
        if on.iter().any(|w| w.dof_y.is_some()) {
            kinds.push(ModeKind::BendingY);
        }
        let model = SpanModel::new(&bridge.section, length, case.elements_per_span)?;
        let modes = natural_modes(&model)?;
        let at = |shape, x: f64, ey: f64, ez: f64| {
            model
                .motion(shape, x, ey, ez)
                .map_or((0.0, 0.0), |m| (m.y, m.z))
        };
        // A mode's own amplitude at x (module docs): the axis' displacement, or the twist
        // (the vertical motion of a point 1 m off the axis less the axis').
        let amplitude = |kind, shape, x: f64| match kind {
            ModeKind::BendingY => at(shape, x, 0.0, 0.0).0,
            ModeKind::Torsion => at(shape, x, 1.0, 0.0).1 - at(shape, x, 0.0, 0.0).1,
            _ => at(shape, x, 0.0, 0.0).1,
        };
        for kind in kinds {
            for (rank, mode) in modes
                .iter()
                .filter(|m| m.kind == kind)
                .take(count)
                .enumerate()
            {
                let peak = (0..=PEAK_SAMPLES)
                    .map(|i| amplitude(kind, &mode.shape, length * i as f64 / PEAK_SAMPLES as f64))
                    .fold(0.0, |p: f64, v| if v.abs() > p.abs() { v } else { p });
                if peak == 0.0 {
                    return Err(crate::Error::numerical(format!(
                        "a girder {} mode with no motion of its kind",
                        kind.as_str()
                    )));
                }
                let series =
                    crate::physics::modal::natural_frequencies(&bridge.section, length, rank + 1);
                let closed = match kind {
                    ModeKind::BendingY => series.lateral[0],
                    ModeKind::Torsion => series.torsion,
                    _ => series.vertical[0],
                } / (2.0 * std::f64::consts::PI);
                let (alpha, beta) = case.damping.map_or((0.0, 0.0), |r| (r.alpha, r.beta));
                let under: Vec<(f64, f64)> = wheels
                    .iter()
                    .zip(&local)
                    .map(|(w, x)| x.map_or((0.0, 0.0), |x| at(&mode.shape, x, w.ey, w.ez)))
                    .collect();
                out.push(GirderMode {
                    span: s + 1,
                    n: rank + 1,
                    kind: kind.as_str(),
                    frequency_hz: mode.frequency_hz,
                    modal_mass_kg: 1.0 / (peak * peak),
                    damping_ratio: alpha / (2.0 * mode.omega) + beta * mode.omega / 2.0,
                    at_magnets: under.iter().map(|m| m.1 / peak).collect(),
                    lateral_at_magnets: wheels
                        .iter()
                        .zip(&under)
                        .map(|(w, m)| if w.dof_y.is_some() { m.0 / peak } else { 0.0 })
                        .collect(),
                    closed_form_hz: closed,
                    fe_vs_closed_form: mode.frequency_hz / closed - 1.0,
                });
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn modes(scenario: &str, sets: &[&str]) -> Vec<GirderMode> {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let case = Case::load(scenario, &sets).unwrap();
        let (v, _, _) = crate::studies::stability::vehicle::vehicle_of(&case).unwrap();
        girder_modes(&case, &v.wheels, 3).unwrap()
    }

    #[test]
    fn a_magnet_on_the_axis_without_guidance_sees_the_vertical_modes_only() {
        let m = modes("unit", &[]);
        assert_eq!(m.len(), 3);
        assert!(m.iter().all(|m| m.kind == "bending-z"));
        assert!(m.iter().all(|m| all_zero(&m.lateral_at_magnets)));
    }

    #[test]
    fn off_axis_guided_magnets_see_the_twist_through_the_rigid_link() {
        // The Fig. 1 car standing with its wheels at 5 and 20 m of the 25 m §4.2 span: the
        // near magnets on the beam axis (ey = 0), the far ones at ey = 3 m, all at ez = 0.6 m.
        let m = modes(
            "paper-4.2",
            &["speed=0", "t_end=1", "vehicle.position_m=20"],
        );
        let kinds: Vec<&str> = m.iter().map(|m| m.kind).collect();
        assert_eq!(
            kinds,
            [["bending-z"; 3], ["torsion"; 3], ["bending-y"; 3]].concat()
        );
        let (l, x) = (25.0, [20.0, 20.0, 5.0, 5.0]);
        let (ey, ez) = ([0.0, 3.0, 0.0, 3.0], 0.6);
        for g in &m {
            // Every mode against its closed form (20 elements: within 1 % for n ≤ 3).
            assert!(g.fe_vs_closed_form.abs() < 1e-2, "{g:?}");
            // A simply supported span's mode n has the shape sin(nπx/L) at unit peak.
            let shape = |x: f64| (g.n as f64 * std::f64::consts::PI * x / l).sin();
            for w in 0..4 {
                let (z, y) = match g.kind {
                    "bending-z" => (shape(x[w]), 0.0),
                    "bending-y" => (0.0, shape(x[w])),
                    _ => (shape(x[w]) * ey[w], -shape(x[w]) * ez),
                };
                let tol = 2e-2 * ey[w].max(1.0);
                assert!(
                    (g.at_magnets[w].abs() - z.abs()).abs() < tol,
                    "{g:?}, wheel {w}"
                );
                assert!(
                    (g.lateral_at_magnets[w].abs() - y.abs()).abs() < tol,
                    "{g:?}, wheel {w}"
                );
                // The rigid link: the twist lifts a magnet by θ·ey and moves it by −θ·ez.
                if g.kind == "torsion" && ey[w] != 0.0 {
                    let ratio = g.lateral_at_magnets[w] / g.at_magnets[w];
                    assert!((ratio + ez / ey[w]).abs() < 1e-12, "{g:?}, wheel {w}");
                }
            }
        }
    }
}
