//! The design targets (issue 39 point 2) checked one by one on a report's numbers, so a user
//! reads "met" or "missed" with the value and the limit instead of comparing them by hand.
//!
//! The limits are the design's ([`super::state_design`]): every pole at or left of the pole
//! target (−1 s⁻¹, or a slower suspension mode on held magnets, [`super::suspension`]), no
//! zero pole; at every magnet, loop at a time, both gain margins ≥ 6 dB, the phase margin
//! ≥ 35° and `Ms ≤ 2`; all loops of the vehicle at once, the disk margin α ≥ 0.35; the supply
//! headroom `|V|/V_max ≤ 0.8` over the reference disturbances.

use super::headroom::Headroom;
use super::margins::Margins;
use super::multiloop::DiskMargin;
use serde::Serialize;

/// The control loops' own pole target (1/s; a slower suspension mode sets its own,
/// [`super::suspension::pole_target`]).
pub const MAX_REAL_PART: f64 = -1.0;
/// Both gain margins, loop at a time (dB).
pub const GAIN_MARGIN_DB: f64 = 6.0;
/// The phase margin, loop at a time (degrees).
pub const PHASE_MARGIN_DEG: f64 = 35.0;
/// The sensitivity peak `Ms`, loop at a time.
pub const MAX_SENSITIVITY: f64 = 2.0;
/// The smallest multi-loop disk margin α the design asks for (about ±3 dB with ±20°).
pub const MIN_DISK_ALPHA: f64 = 0.35;
/// The largest `|V|/V_max` the design allows over the reference disturbances.
pub const MAX_HEADROOM_RATIO: f64 = 0.8;

/// One target: the report's value (the worst over the magnets where it is per magnet; null:
/// not defined, e.g. the loop unstable with its delay, counted as missed), the limit, whether
/// it is met, and where the worst value is.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Target {
    pub name: &'static str,
    pub value: Option<f64>,
    /// `"<="` or `">="`.
    pub sense: &'static str,
    pub limit: f64,
    pub met: bool,
    pub at: String,
}

/// Every target as reported, and whether all are met.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Targets {
    pub all_met: bool,
    pub targets: Vec<Target>,
}

/// What the targets are read from (the report's own numbers).
pub struct Inputs<'a> {
    pub max_real_part: f64,
    pub pole_target: f64,
    pub zero_poles: usize,
    pub margins: &'a [Margins],
    pub disk: &'a DiskMargin,
    pub headroom: &'a Headroom,
}

fn at_most(name: &'static str, value: Option<f64>, limit: f64, at: String) -> Target {
    let met = value.is_some_and(|v| v <= limit);
    Target {
        name,
        value,
        sense: "<=",
        limit,
        met,
        at,
    }
}

fn at_least(name: &'static str, value: Option<f64>, limit: f64, at: String) -> Target {
    let met = value.is_some_and(|v| v >= limit);
    Target {
        name,
        value,
        sense: ">=",
        limit,
        met,
        at,
    }
}

/// The worst of one margin over the magnets (`key` reads it, `None` for a loop unstable with
/// its delay; a margin that never binds reads +∞), by `worse` (true when the first is worse).
fn worst(
    margins: &[Margins],
    key: impl Fn(&Margins) -> Option<f64>,
    worse: impl Fn(f64, f64) -> bool,
) -> (Option<f64>, String) {
    let mut out: Option<(Option<f64>, &str)> = None;
    for m in margins {
        let v = if m.stable_with_delay { key(m) } else { None };
        let replace = match out {
            None => true,
            Some((None, _)) => false,
            Some((Some(w), _)) => v.is_none_or(|v| worse(v, w)),
        };
        if replace {
            out = Some((v, &m.magnet));
        }
    }
    out.map_or((None, String::new()), |(v, at)| (v, at.to_string()))
}

/// The targets on `x` (module docs).
pub fn targets(x: &Inputs) -> Targets {
    let inf = |o: Option<f64>| Some(o.unwrap_or(f64::INFINITY));
    let lower = |a: f64, b: f64| a < b;
    let (low, low_at) = worst(x.margins, |m| inf(m.gain_low_db), lower);
    let (high, high_at) = worst(x.margins, |m| inf(m.gain_high_db), lower);
    let (phase, phase_at) = worst(x.margins, |m| inf(m.phase_deg), lower);
    let (ms, ms_at) = worst(x.margins, |m| inf(m.sensitivity_peak), |a, b| a > b);
    let targets = vec![
        at_most(
            "max_real_part",
            Some(x.max_real_part),
            x.pole_target,
            String::new(),
        ),
        at_most("zero_poles", Some(x.zero_poles as f64), 0.0, String::new()),
        at_least("gain_low_db", low, GAIN_MARGIN_DB, low_at),
        at_least("gain_high_db", high, GAIN_MARGIN_DB, high_at),
        at_least("phase_deg", phase, PHASE_MARGIN_DEG, phase_at),
        at_most("sensitivity_peak", ms, MAX_SENSITIVITY, ms_at),
        at_least(
            "disk_margin_alpha",
            x.disk.stable_with_delay.then_some(x.disk.alpha).flatten(),
            MIN_DISK_ALPHA,
            String::new(),
        ),
        at_most(
            "headroom_ratio",
            // No supply bound (V_max = ∞): no headroom is used.
            x.headroom
                .ratio
                .or(x.headroom.vmax_V.is_none().then_some(0.0)),
            MAX_HEADROOM_RATIO,
            String::new(),
        ),
    ];
    Targets {
        all_met: targets.iter().all(|t| t.met),
        targets,
    }
}
