//! `--compare`: the HIL run against the ideal in-process core run (the paper's scheme: the
//! law in f64 with its internal loop, exact gaps), step by step on the same time grid, so
//! the cost of sampling, quantisation, noise and delay is a number.

use crate::simulation::Record;
use crate::{Error, Result};
use serde::Serialize;

/// Largest absolute difference of one history and the ideal run's peak of it.
#[derive(Serialize, Debug, Clone, Copy, PartialEq)]
pub struct Diff {
    pub max_abs: f64,
    pub at_t: f64,
    pub ideal_peak: f64,
    /// `max_abs / |ideal_peak|`.
    pub relative: f64,
}

/// The differences reported by `--compare`.
#[derive(Serialize, Debug, Clone, PartialEq)]
pub struct Comparison {
    pub midspan_z: Diff,
    pub wheel1_gap_z: Diff,
    pub wheel1_force_z: Diff,
}

fn diff(hil: &[Record], ideal: &[Record], get: fn(&Record) -> f64) -> Diff {
    let mut d = Diff {
        max_abs: 0.0,
        at_t: 0.0,
        ideal_peak: 0.0,
        relative: 0.0,
    };
    for (a, b) in hil.iter().zip(ideal) {
        let e = (get(a) - get(b)).abs();
        if e > d.max_abs || e.is_nan() {
            d.max_abs = e;
            d.at_t = b.t;
        }
        if get(b).abs() > d.ideal_peak.abs() {
            d.ideal_peak = get(b);
        }
    }
    d.relative = d.max_abs / d.ideal_peak.abs();
    d
}

/// Compares two runs on the same grid; runs of different lengths are
/// [`Error::Numerical`] (an internal failure: both runs step the same case).
pub fn compare(hil: &[Record], ideal: &[Record]) -> Result<Comparison> {
    if hil.len() != ideal.len() {
        return Err(Error::numerical(format!(
            "internal: HIL run has {} records, ideal run {}",
            hil.len(),
            ideal.len()
        )));
    }
    Ok(Comparison {
        midspan_z: diff(hil, ideal, |r| r.midspan.z),
        wheel1_gap_z: diff(hil, ideal, |r| r.wheel1_gap_z),
        // The ideal run's force is total; compare deviations from the static load alike.
        wheel1_force_z: diff(hil, ideal, |r| r.wheel1_force_z),
    })
}
