//! The speed envelope (issue 39 point 4): at speed the vehicle–girder system is time-varying,
//! so no pole describes it; instead one time run of the case per speed over its own guideway
//! (the law resolved once at the scenario's values, as `--critical` does), reduced to the
//! running-safety figures ([`crate::safety`]): the smallest levitation gap, the largest
//! `|V|/V_max`, the longest time a magnet spent at ±V_max, the body's peak vertical
//! acceleration and the collision steps.
//!
//! # Resonance speeds
//! A load crossing a span of length `L` at speed `v` repeats every `L/v`; a span mode of
//! frequency `f` is driven at resonance where a harmonic of that crossing rate meets it,
//! `k·v/L = f`, i.e. `v = f·L/k` (k = 1, 2, 3; L. Frýba, *Vibration of Solids and Structures
//! under Moving Loads*, 3rd ed., Telford 1999, §1.3, the critical speed of a span). The first
//! [`RESONANCE_MODES`] vertical bending modes of each span length use the closed-form
//! Timoshenko frequency of the simply supported span
//! ([`crate::physics::modal::natural_frequencies`], docs/model.md §8).

use crate::input::case::Case;
use crate::safety::Safety;
use serde::Serialize;

/// Vertical bending modes per span length whose resonance speeds are marked.
pub const RESONANCE_MODES: usize = 2;

/// One speed's figures (SI).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Point {
    pub speed_m_per_s: f64,
    /// The smallest levitation gap (m) and guidance gap (m; null: no guidance magnets).
    pub gap_min_m: f64,
    pub guidance_gap_min_m: Option<f64>,
    /// The largest |V| over V_max (null: no bound or no coils reported).
    pub voltage_ratio: Option<f64>,
    /// The longest time one magnet spent with its voltage at ±V_max (s).
    pub saturated_s: Option<f64>,
    pub body_acceleration_m_per_s2: f64,
    pub collision_steps: f64,
    /// The resonance speeds within half a step of this one (labels as in `resonances`).
    pub near_resonance: Vec<String>,
}

/// A resonance speed `v = f·L/k`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Resonance {
    pub span_m: f64,
    pub mode: usize,
    pub frequency_hz: f64,
    pub k: usize,
    pub speed_m_per_s: f64,
    /// `L25 f1 k2`: span length, mode, harmonic.
    pub label: String,
}

/// The envelope.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Envelope {
    pub scenario: String,
    pub points: Vec<Point>,
    /// The resonance speeds in the range of the speeds.
    pub resonances: Vec<Resonance>,
    pub method: &'static str,
}

const METHOD: &str = "one time run per speed over the case's guideway (its irregularity, its \
    law resolved once), reduced to summary.json's safety figures; resonance speeds v = f·L/k, \
    k = 1, 2, 3, for the first two vertical bending modes of each span length (closed-form \
    Timoshenko frequency)";

/// The resonance speeds of `case`'s spans in `[lo, hi]` (module docs).
pub fn resonances(case: &Case, lo: f64, hi: f64) -> Vec<Resonance> {
    let mut lengths: Vec<f64> = Vec::new();
    for &l in &case.bridge.spans {
        if !lengths.contains(&l) {
            lengths.push(l);
        }
    }
    let mut out = Vec::new();
    for l in lengths {
        for n in 1..=RESONANCE_MODES {
            let f = crate::physics::modal::natural_frequencies(&case.bridge.section, l, n).vertical
                [0]
                / (2.0 * std::f64::consts::PI);
            for k in 1..=3 {
                let v = f * l / k as f64;
                if (lo..=hi).contains(&v) {
                    out.push(Resonance {
                        span_m: l,
                        mode: n,
                        frequency_hz: f,
                        k,
                        speed_m_per_s: v,
                        label: format!("L{l} f{n} k{k}"),
                    });
                }
            }
        }
    }
    out.sort_by(|a, b| a.speed_m_per_s.total_cmp(&b.speed_m_per_s));
    out
}

/// The envelope of scenario `name` with `sets` over `speeds` (m/s, > 0), the law of `base`
/// (`name` with `sets`, its law resolved) at every speed.
pub fn envelope(
    name: &str,
    sets: &[String],
    base: &Case,
    speeds: &[f64],
) -> crate::Result<Envelope> {
    if speeds.is_empty() || speeds.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
        return Err(crate::Error::invalid(
            "--speeds",
            "needs speeds above 0 m/s (a standstill is `stability --scenario` itself)",
        ));
    }
    let (lo, hi) = speeds
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let res = resonances(base, lo, hi);
    let half = if speeds.len() > 1 {
        0.5 * (hi - lo) / (speeds.len() - 1) as f64
    } else {
        0.0
    };
    let mut points = Vec::with_capacity(speeds.len());
    for &v in speeds {
        let mut s = sets.to_vec();
        s.push(format!("speed={v:?}"));
        let mut case = Case::load(name, &s)?;
        case.law = base.law;
        points.push(point(&case, v, &res, half)?);
    }
    Ok(Envelope {
        scenario: name.to_string(),
        points,
        resonances: res,
        method: METHOD,
    })
}

/// One run at speed `v`, reduced.
fn point(case: &Case, v: f64, res: &[Resonance], half: f64) -> crate::Result<Point> {
    let mut safety = Safety::for_case(case);
    crate::setup::simulate(
        case,
        &mut crate::simulation::magnets::CoreMagnets::new(),
        &mut safety,
        &mut (),
    )
    .map_err(|e| crate::Error::numerical(format!("the run at {v} m/s: {e}")))?;
    let r = safety.report().ok_or_else(|| {
        crate::Error::invalid(
            "vehicle.kind",
            "the speed envelope needs a vehicle with magnets",
        )
    })?;
    let m = r.maglev.as_ref().ok_or_else(|| {
        crate::Error::invalid(
            "vehicle.kind",
            "the speed envelope needs a vehicle with magnets",
        )
    })?;
    Ok(Point {
        speed_m_per_s: v,
        gap_min_m: m.levitation_gap_min.value,
        guidance_gap_min_m: m.guidance_gap_min.as_ref().map(|f| f.value),
        voltage_ratio: m
            .voltage_peak
            .as_ref()
            .and_then(|f| f.limit.map(|l| f.value / l)),
        saturated_s: m.saturated_longest.as_ref().map(|f| f.value),
        body_acceleration_m_per_s2: r.body_acceleration_peak.value,
        collision_steps: m.collision_steps.value,
        near_resonance: res
            .iter()
            .filter(|x| (x.speed_m_per_s - v).abs() <= half)
            .map(|x| x.label.clone())
            .collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The §4.2 span (25 m): the first mode's resonance speeds are its frequency times L/k,
    /// and the frequency is below the Euler–Bernoulli one, `f1 = (π/2L²)·√(EI/m)`, by the
    /// shear and rotary inertia of this stocky span (L/r = 40: 1.8 %, under 3 %).
    #[test]
    fn resonance_speeds_are_f_l_over_k() {
        let case = crate::studies::design::load("paper-4.2", &[]).unwrap();
        let res = resonances(&case, 1.0, 1e4);
        let s = &case.bridge.section;
        let l = 25.0;
        let eb = std::f64::consts::PI / (2.0 * l * l)
            * (s.youngs_modulus * s.iy / s.mass_per_length).sqrt();
        let first: Vec<&Resonance> = res.iter().filter(|r| r.mode == 1).collect();
        assert_eq!(first.len(), 3, "{res:?}");
        for r in first {
            let ratio = r.frequency_hz / eb;
            assert!(ratio < 1.0 && ratio > 0.97, "{r:?} {eb}");
            assert!((r.speed_m_per_s - r.frequency_hz * l / r.k as f64).abs() < 1e-9);
        }
    }

    #[test]
    fn speeds_at_or_below_zero_are_refused() {
        let case = crate::studies::design::load("paper-4.2", &[]).unwrap();
        let e = envelope("paper-4.2", &[], &case, &[0.0, 10.0]).unwrap_err();
        assert!(e.to_string().contains("--speeds"), "{e}");
    }
}
