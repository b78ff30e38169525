//! `--compare`: the HIL run against the ideal in-process core run (the paper's scheme: the
//! law in f64 with its internal loop, exact gaps), step by step on the same time grid, so
//! the cost of sampling, quantisation, noise and delay is a number.

use maglev_sim::probes::{Probes, Rows};
use maglev_sim::{Error, Result};
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

/// An in-memory recorder of the histories `--compare` compares (the default columns), for
/// either run.
pub fn recorder() -> Rows {
    Rows::new(Probes::default_columns())
}

/// The history `name` of both runs, over their first `k` steps.
fn diff(hil: &Rows, ideal: &Rows, name: &str, k: usize) -> Result<Diff> {
    let column = |r: &Rows| {
        r.column(name)
            .ok_or_else(|| Error::numerical(format!("internal: no column {name} to compare")))
    };
    let (a, b) = (column(hil)?, column(ideal)?);
    let mut d = Diff {
        max_abs: 0.0,
        at_t: 0.0,
        ideal_peak: 0.0,
        relative: 0.0,
    };
    for ((a, b), &t) in a.iter().zip(&b).zip(&ideal.t).take(k) {
        let e = (a - b).abs();
        if e > d.max_abs || e.is_nan() {
            d.max_abs = e;
            d.at_t = t;
        }
        if b.abs() > d.ideal_peak.abs() {
            d.ideal_peak = *b;
        }
    }
    d.relative = d.max_abs / d.ideal_peak.abs();
    Ok(d)
}

/// Compares two runs on the same grid (both recorded by a [`recorder`]) over their steps
/// before `until` (s; all of them when `None`); runs of different lengths are
/// [`Error::Numerical`] (an internal failure: both runs step the same case).
pub fn compare(hil: &Rows, ideal: &Rows, until: Option<f64>) -> Result<Comparison> {
    if hil.t.len() != ideal.t.len() {
        return Err(Error::numerical(format!(
            "internal: HIL run has {} records, ideal run {}",
            hil.t.len(),
            ideal.t.len()
        )));
    }
    let k = match until {
        Some(tf) => hil.t.iter().take_while(|&&t| t < tf).count(),
        None => hil.t.len(),
    };
    Ok(Comparison {
        midspan_z: diff(hil, ideal, "midspan_z", k)?,
        wheel1_gap_z: diff(hil, ideal, "wheel1_gap_z", k)?,
        // The ideal run's force is total; compare deviations from the static load alike.
        wheel1_force_z: diff(hil, ideal, "wheel1_force_z", k)?,
    })
}
