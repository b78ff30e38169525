//! Sweeps: many runs of one scenario over the cartesian product of `--set` axes, each reduced
//! to a few numbers (peak, min, max, rms of named probes), in parallel, resumable, sharded
//! across machines and merged back (docs/sweeps.md).
//!
//! Why a library module and not a shell loop over `maglev run`: the runs share nothing but
//! the spec, so they parallelise perfectly, but a study must also be reproducible to the byte
//! (any `--jobs`, any sharding), survive interruptions, and keep a failed run's error next to
//! the others' numbers. Each file does one of these:
//!
//! - [`spec`]: the TOML spec, typed and checked;
//! - [`runs`]: the product, each run's identity, the shards;
//! - [`reduce`]: the streaming reductions (a `Recorder`);
//! - [`store`]: the sweep directory, its records and tables;
//! - [`execute`]: running the pending runs with rayon;
//! - [`merge`]: combining shards;
//! - [`plot`]: the plots against the first axis;
//! - [`slurm`]: the job-array scripts for a cluster.

pub mod execute;
pub mod inputs;
pub mod merge;
pub mod plot;
pub mod reduce;
pub mod runs;
pub mod slurm;
pub mod spec;
pub mod store;

pub use execute::{sweep, Options, Report};
pub use merge::merge;
pub use spec::Spec;

use crate::{Error, Result};
use std::collections::BTreeMap;
use std::path::Path;

/// Writes results.csv, costs.csv and the plots of `runs` into `dir`, each file renamed into
/// place when complete.
pub fn publish(
    dir: &Path,
    spec: &Spec,
    runs: &[runs::Run],
    records: &BTreeMap<String, store::Record>,
) -> Result<()> {
    store::write_atomic(
        &dir.join("results.csv"),
        &store::results_csv(spec, runs, records)?,
    )?;
    store::write_atomic(
        &dir.join("costs.csv"),
        &store::costs_csv(spec, runs, records)?,
    )?;
    let plots = dir.join("plots");
    std::fs::create_dir_all(&plots).map_err(|e| Error::io(&plots, e))?;
    for (name, svg) in plot::plots(spec, runs, records)? {
        store::write_atomic(&plots.join(name), svg.as_bytes())?;
    }
    Ok(())
}
