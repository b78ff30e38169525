//! A recorder that keeps response.csv's columns in memory: `t`, the probes, `iterations`,
//! `collision`, one value per committed step, the same values through the same checks
//! ([`finite_t`], [`finite_reading`]) as the CLI's `CsvRecorder`.

use maglev_sim::probes::{finite_reading, finite_t, Probes, Recorder, StepView};
use maglev_sim::Result;

/// response.csv's columns, by column.
pub struct Columns {
    pub probes: Probes,
    pub t: Vec<f64>,
    /// One vector per probe (NaN where the probe does not apply, an empty cell in the CSV).
    pub values: Vec<Vec<f64>>,
    pub iterations: Vec<u32>,
    pub collision: Vec<bool>,
}

impl Columns {
    /// Empty columns of `probes`.
    pub fn new(probes: Probes) -> Self {
        let values = vec![Vec::new(); probes.probes.len()];
        Columns {
            probes,
            t: Vec::new(),
            values,
            iterations: Vec::new(),
            collision: Vec::new(),
        }
    }
}

impl Recorder for Columns {
    fn record(&mut self, step: &StepView) -> Result<()> {
        let t = finite_t(step)?;
        let mut memo = None;
        for (k, column) in self.values.iter_mut().enumerate() {
            column.push(finite_reading(step, &self.probes, k, &mut memo)?.unwrap_or(f64::NAN));
        }
        self.t.push(t);
        self.iterations.push(step.iterations);
        self.collision.push(step.collision);
        Ok(())
    }
}
