//! The reductions of a run: peak, min, max and rms of each probe, streamed step by step.
//!
//! Why a [`Recorder`]: a sweep keeps one number per quantity and run, so nothing of the
//! history is stored; the reducer reads each committed step through the same probes that
//! `maglev run` writes to response.csv, so a quantity equals the reduction of that column.

use super::spec::{ReducedProbe, Reduction};
use crate::probes::{Probe, Probes, Recorder, StepView};
use crate::{Error, Result};

/// Running statistics of one probe.
#[derive(Clone, Copy, Debug)]
struct Stats {
    /// The signed value of the largest magnitude so far (the first one on a tie).
    peak: f64,
    min: f64,
    max: f64,
    sum_sq: f64,
    n: usize,
    nonfinite: usize,
}

impl Stats {
    const EMPTY: Stats = Stats {
        peak: 0.0,
        min: f64::INFINITY,
        max: f64::NEG_INFINITY,
        sum_sq: 0.0,
        n: 0,
        nonfinite: 0,
    };

    fn add(&mut self, v: f64) {
        if !v.is_finite() {
            self.nonfinite += 1;
            return;
        }
        if self.n == 0 || v.abs() > self.peak.abs() {
            self.peak = v;
        }
        self.min = self.min.min(v);
        self.max = self.max.max(v);
        self.sum_sq += v * v;
        self.n += 1;
    }
}

/// Reduces the probes of `quantities` over a run.
pub struct Reducer {
    probes: Vec<Probe>,
    stats: Vec<Stats>,
    /// For each quantity, its reduction and the index of its probe.
    columns: Vec<(ReducedProbe, usize)>,
}

impl Reducer {
    /// `probes` must hold (at least) every probe named by `quantities`, by name.
    pub fn new(quantities: &[ReducedProbe], probes: &Probes) -> Result<Self> {
        let columns = quantities
            .iter()
            .map(|q| {
                probes
                    .names
                    .iter()
                    .position(|n| *n == q.probe)
                    .map(|k| (q.clone(), k))
                    .ok_or_else(|| {
                        Error::invalid("reduce.quantities", format!("no probe `{}`", q.probe))
                    })
            })
            .collect::<Result<Vec<_>>>()?;
        // A ground receiver's velocity exists only once the run is over (probes.rs).
        if let Some(&(k, _)) = probes.ground_columns().first() {
            return Err(Error::invalid(
                "reduce.quantities",
                format!(
                    "`{}` is computed after the run from the whole record; a sweep reduces rows as they stream",
                    probes.names[k]
                ),
            ));
        }
        Ok(Reducer {
            probes: probes.probes.clone(),
            stats: vec![Stats::EMPTY; probes.probes.len()],
            columns,
        })
    }

    /// The value of each quantity, in order; an error names the first quantity that has no
    /// value (a probe with no finite sample, or one that became NaN or infinite).
    pub fn finish(&self) -> Result<Vec<f64>> {
        self.columns
            .iter()
            .map(|(q, k)| {
                let s = &self.stats[*k];
                if s.nonfinite > 0 {
                    return Err(Error::numerical(format!(
                        "{}: {} non-finite value(s) in the history",
                        q.name(),
                        s.nonfinite
                    )));
                }
                if s.n == 0 {
                    return Err(Error::numerical(format!(
                        "{}: the run recorded no step",
                        q.name()
                    )));
                }
                Ok(match q.reduction {
                    Reduction::Peak => s.peak,
                    Reduction::Min => s.min,
                    Reduction::Max => s.max,
                    Reduction::Rms => (s.sum_sq / s.n as f64).sqrt(),
                })
            })
            .collect()
    }
}

impl Recorder for Reducer {
    fn record(&mut self, step: &StepView) -> Result<()> {
        for (p, s) in self.probes.iter().zip(&mut self.stats) {
            s.add(step.value(p));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statistics_of_a_known_sequence() {
        let mut s = Stats::EMPTY;
        for v in [1.0, -3.0, 2.0, 3.0] {
            s.add(v);
        }
        assert_eq!(s.peak, -3.0, "the first of equal magnitudes");
        assert_eq!((s.min, s.max, s.n), (-3.0, 3.0, 4));
        assert_eq!(s.sum_sq, 23.0);
        s.add(f64::NAN);
        assert_eq!(s.nonfinite, 1);
    }
}
