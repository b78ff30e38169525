//! The skid contacts' figures of summary.json's `safety.maglev.skid_contact`
//! (docs/contact.md, docs/safety.md): per magnet that touched its rail, and in total, the
//! peak normal force and friction drag, the committed steps and the time in contact.

use super::{Figure, SafetyReport};
use crate::physics::skid::SkidOutcome;
use serde::Serialize;

const SKID_SOURCE: &str = "a magnet on its skid is not levitating: any contact at speed is a failure of levitation (docs/contact.md)";
const FORCE_SOURCE: &str = "no limit: the skid's load is reported, not judged (docs/contact.md)";

/// One magnet's contact with its rail over the run.
#[derive(Serialize, Debug, Clone, PartialEq)]
pub struct SkidMagnet {
    /// `wheel{N}.z`, `.left`, `.right` (the skids on the rail) or `.setdown` (the vehicle
    /// set down on the guideway).
    pub magnet: String,
    #[serde(rename = "peak_normal_N")]
    pub peak_normal: f64,
    #[serde(rename = "peak_drag_N")]
    pub peak_drag: f64,
    pub steps: usize,
    pub duration_s: f64,
    /// The end time of its first step in contact (s).
    pub first_t_s: Option<f64>,
}

/// Every magnet's contact with its rail.
#[derive(Serialize, Debug, Clone, PartialEq)]
pub struct SkidFigures {
    /// Steps with some magnet on its skid (limit 0), the first one's time.
    pub contact_steps: Figure,
    /// Their total duration (s).
    pub contact_duration_s: f64,
    /// The largest normal force of any skid (N).
    pub normal_peak: Figure,
    /// The largest friction drag of any skid along the rail (N).
    #[serde(rename = "drag_peak_N")]
    pub drag_peak: f64,
    /// Only the magnets that touched, along the train.
    pub per_magnet: Vec<SkidMagnet>,
}

const SIDES: [&str; crate::physics::skid::SIDES] = ["z", "left", "right", "setdown"];

/// The figures of `o` for a run of step `dt` (s); `wheel_names[i]` names magnet wheel `i`.
pub fn figures(o: &SkidOutcome, dt: f64, wheel_names: &[String]) -> SkidFigures {
    let per_magnet: Vec<SkidMagnet> = o
        .per_magnet
        .iter()
        .zip(wheel_names)
        .flat_map(|(r, w)| {
            r.iter()
                .zip(SIDES)
                .filter(|(r, _)| r.steps > 0)
                .map(move |(r, side)| SkidMagnet {
                    magnet: format!("{w}.{side}"),
                    peak_normal: r.peak_normal,
                    peak_drag: r.peak_drag,
                    steps: r.steps,
                    duration_s: r.steps as f64 * dt,
                    first_t_s: r.first_t,
                })
        })
        .collect();
    let worst = per_magnet.iter().fold(None::<&SkidMagnet>, |b, m| match b {
        Some(b) if b.peak_normal >= m.peak_normal => Some(b),
        _ => Some(m),
    });
    let normal_peak = Figure::judged(
        worst.map_or(0.0, |m| m.peak_normal),
        "N",
        worst.map(|m| m.magnet.clone()),
        None,
        None,
        FORCE_SOURCE,
    );
    let contact_steps = Figure::judged(
        o.steps as f64,
        "steps",
        None,
        o.first_t,
        Some(0.0),
        SKID_SOURCE,
    );
    SkidFigures {
        contact_steps,
        contact_duration_s: o.steps as f64 * dt,
        normal_peak,
        drag_peak: per_magnet.iter().map(|m| m.peak_drag).fold(0.0, f64::max),
        per_magnet,
    }
}

impl SafetyReport {
    /// The report with the skids' figures in `maglev` (a report without magnets is returned
    /// as it is), and its verdict again.
    pub fn with_skids(mut self, skids: SkidFigures) -> Self {
        if let Some(m) = &mut self.maglev {
            m.skid_contact = Some(skids);
        }
        self.pass = self.judged().iter().all(|(_, pass)| *pass);
        self
    }
}
