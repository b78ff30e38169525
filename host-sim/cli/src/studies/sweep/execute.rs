//! Running a sweep's runs: in parallel with rayon, each into its own record, skipping the
//! runs that already have one.
//!
//! Why a failed run does not stop the sweep: in a study of thousands of runs, one bad value
//! (a speed the controller cannot hold, a seed that collides) is a finding, not a reason to
//! lose the rest. Its error is recorded in its row; the sweep goes on.

use super::reduce::Reducer;
use super::runs::{self, Run, Shard};
use super::spec::Spec;
use super::store::{Header, Record, Status, Store};
use crate::output::safety::{Safety, SafetyReport};
use crate::probes::Tee;
use crate::{Error, Result};
use rayon::prelude::*;
use std::path::Path;
use std::time::Instant;

/// How to run a sweep.
#[derive(Clone, Debug)]
pub struct Options {
    /// Worker threads (≥ 1).
    pub jobs: usize,
    /// Only this shard's runs.
    pub shard: Option<Shard>,
    /// Run again the runs whose record says they failed.
    pub retry_failed: bool,
    /// Draw a progress bar on stderr.
    pub progress: bool,
}

/// What an invocation did.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// Runs of this invocation's share (all, or the shard's).
    pub runs: usize,
    /// Of those, already recorded before this invocation (skipped).
    pub skipped: usize,
    /// Run now.
    pub ran: usize,
    /// Recorded as failed, now or before.
    pub failed: usize,
    pub wall_s: f64,
}

/// The `--set` key that makes a run record exactly the probes the quantities need.
fn probe_set(spec: &Spec) -> String {
    let mut names: Vec<&str> = Vec::new();
    for q in &spec.quantities {
        if !names.contains(&q.probe.as_str()) {
            names.push(&q.probe);
        }
    }
    let list: Vec<String> = names
        .iter()
        .map(|n| toml::Value::String(n.to_string()).to_string())
        .collect();
    format!("output.probes=[{}]", list.join(","))
}

/// Resolves the case of a run (or the spec's base, with `run = None`) with its probes.
fn case(spec: &Spec, run: Option<&Run>) -> Result<(crate::input::case::Case, Reducer)> {
    let mut sets = match run {
        Some(r) => r.sets(spec),
        None => spec.sets.clone(),
    };
    sets.push(probe_set(spec));
    let case = crate::studies::design::load(&spec.scenario, &sets)?;
    let reducer = Reducer::new(&spec.quantities, &case.probes)?;
    Ok((case, reducer))
}

/// The hash of the files `run` reads now ([`super::inputs`]); `None` when they cannot be read
/// (the run is then run again, and its record says why it failed).
fn inputs(spec: &Spec, run: &Run) -> Option<String> {
    let sc = crate::input::scenario::load(&spec.scenario, &run.sets(spec)).ok()?;
    super::inputs::inputs_fnv1a(&sc).ok()
}

/// Runs one run to its record; never fails (a failure is the record's).
pub fn run_one(spec: &Spec, run: &Run) -> Record {
    let inputs_fnv1a = inputs(spec, run).unwrap_or_default();
    let record = run_uncaught(spec, run);
    Record {
        inputs_fnv1a,
        ..record
    }
}

/// [`run_one`] but for the inputs' hash.
fn run_uncaught(spec: &Spec, run: &Run) -> Record {
    let start = Instant::now();
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| -> Result<_> {
        let (case, mut reducer) = case(spec, Some(run))?;
        let mut safety = Safety::for_case(&case);
        let mut both = Tee(&mut reducer, &mut safety);
        let outcome = crate::setup::simulate(
            &case,
            &mut crate::simulation::magnets::CoreMagnets::new(),
            &mut both,
            &mut (),
        )?
        .outcome;
        let values = reducer.finish()?;
        let failing = failed_figures(safety.report());
        Ok((outcome.steps, outcome.collision_steps, values, failing))
    }));
    let wall_s = start.elapsed().as_secs_f64();
    let one_line = |s: String| s.split_whitespace().collect::<Vec<_>>().join(" ");
    match result {
        Ok(Ok((steps, collisions, values, failing))) => {
            let (status, error) = if collisions > 0 {
                (
                    Status::Collided,
                    format!("{collisions} step(s) with a collision (a magnet on its skid)"),
                )
            } else if !failing.is_empty() {
                (
                    Status::Unsafe,
                    format!("outside its safety limits: {}", failing.join(" ")),
                )
            } else {
                (Status::Ok, String::new())
            };
            Record {
                id: run.id.clone(),
                status,
                values,
                error,
                steps,
                wall_s,
                inputs_fnv1a: String::new(),
            }
        }
        Ok(Err(e)) => failed(run, one_line(e.to_string()), wall_s),
        Err(panic) => {
            let msg = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            failed(run, one_line(format!("the run panicked: {msg}")), wall_s)
        }
    }
}

/// The running-safety figures a run fails, by their summary.json names (docs/safety.md);
/// empty when it passes or has no figures (moving forces).
fn failed_figures(report: Option<SafetyReport>) -> Vec<&'static str> {
    report.map_or_else(Vec::new, |r| {
        r.judged()
            .into_iter()
            .filter(|(_, pass)| !pass)
            .map(|(name, _)| name)
            .collect()
    })
}

fn failed(run: &Run, error: String, wall_s: f64) -> Record {
    Record {
        id: run.id.clone(),
        status: Status::Failed,
        values: Vec::new(),
        error,
        steps: 0,
        wall_s,
        inputs_fnv1a: String::new(),
    }
}

/// The most runs a sweep runs at once: each is a whole simulation with its own memory, so
/// jobs beyond the cores only add memory and threads (10 000 threads stalled the machine).
pub const MAX_JOBS: usize = 256;

/// Runs the sweep `spec` into directory `out`: the runs of `opts.shard` (or all) that have no
/// record yet, then rebuilds results.csv, costs.csv and the plots from every record of the
/// share. An error is returned only for what stops the whole sweep (a bad spec, a base
/// scenario that does not load, an unwritable directory).
pub fn sweep(spec: &Spec, out: &Path, opts: &Options) -> Result<Report> {
    let start = Instant::now();
    if !(1..=MAX_JOBS).contains(&opts.jobs) {
        return Err(Error::invalid(
            "--jobs",
            format!("must be between 1 and {MAX_JOBS}, got {}", opts.jobs),
        ));
    }
    // The spec's base case and its probes must be sound before any run starts, and so must
    // every axis key and the type of every axis value: a misspelt key would fail every run
    // and still leave a sweep directory. Values the case refuses (speed = -10) stay failed
    // runs, recorded with their errors.
    case(spec, None)?;
    for axis in &spec.axes {
        for v in &axis.values {
            let mut sets = spec.sets.clone();
            sets.push(format!("{}={}", axis.key, v.toml()));
            crate::input::scenario::load(&spec.scenario, &sets)
                .map_err(|e| Error::invalid(format!("axes.{}", axis.key), e.to_string()))?;
        }
    }
    let store = Store::open(out, &Header::of(spec)?)?;
    let share: Vec<Run> = runs::all(spec)
        .into_iter()
        .filter(|r| opts.shard.is_none_or(|s| s.holds(r.index)))
        .collect();
    let before = store.records()?;
    let pending: Vec<&Run> = share
        .iter()
        .filter(|r| match before.get(&r.id) {
            None => true,
            Some(rec) => {
                (opts.retry_failed && rec.status == Status::Failed)
                    || inputs(spec, r).as_ref() != Some(&rec.inputs_fnv1a)
            }
        })
        .collect();
    let bar = if opts.progress {
        indicatif::ProgressBar::new(pending.len() as u64)
    } else {
        indicatif::ProgressBar::hidden()
    };
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{prefix} [{bar:40}] {pos}/{len} runs, {elapsed} elapsed, ~{eta} to go",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar.set_prefix("maglev sweep");
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.jobs)
        .build()
        .map_err(|e| Error::invalid("--jobs", e.to_string()))?;
    let written: Result<()> = pool.install(|| {
        pending.par_iter().try_for_each(|run| {
            let rec = run_one(spec, run);
            store.put(run, &rec)?;
            bar.inc(1);
            Ok(())
        })
    });
    bar.finish_and_clear();
    written?;
    let records = store.records()?;
    super::publish(&store.dir, spec, &share, &records)?;
    let failed = share
        .iter()
        .filter(|r| {
            records
                .get(&r.id)
                .is_some_and(|x| x.status == Status::Failed)
        })
        .count();
    Ok(Report {
        runs: share.len(),
        skipped: share.len() - pending.len(),
        ran: pending.len(),
        failed,
        wall_s: start.elapsed().as_secs_f64(),
    })
}
