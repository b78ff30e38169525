//! The sweep directory: one record file per finished run, and the tables built from them.
//!
//! Why records, not one growing table: a sweep is resumable, so its directory is updated as
//! runs finish, from several threads (or, after a merge, from several machines). Each run's
//! record is its own small JSON file, written aside and renamed into place, so a record is
//! either complete or absent whatever interrupts the sweep; results.csv and costs.csv are
//! rebuilt from the records at the end of every invocation and also renamed into place, so
//! they are never half-written. `sweep.json` holds the spec the records belong to; a rerun
//! with another scenario, other fixed overrides, other quantities or other axis keys is
//! refused rather than mixed in.
//!
//! Layout: `.maglev-sweep` (the marker), `sweep.json`, `runs/<run>.json`, `results.csv`
//! (deterministic), `costs.csv` (wall seconds: differs from run to run), `plots/*.svg`.

use super::runs::{fnv1a, Run};
use super::spec::Spec;
use crate::{Error, Result};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The file that marks a directory as a sweep's.
pub use crate::output::staging::SWEEP_MARKER as MARKER;

/// What a sweep directory belongs to.
#[derive(Serialize, Deserialize, Debug, Clone, PartialEq)]
pub struct Header {
    pub spec: Spec,
    /// FNV-1a of the scenario's TOML text, so a changed scenario file is noticed.
    pub scenario_fnv1a: String,
}

impl Header {
    /// The header of `spec`, reading its scenario's text.
    pub fn of(spec: &Spec) -> Result<Self> {
        let text = match crate::input::scenario::BUNDLED
            .iter()
            .find(|(n, _)| *n == spec.scenario)
        {
            Some((_, t)) => t.to_string(),
            None => crate::input::read_text(std::path::Path::new(&spec.scenario))?,
        };
        Ok(Header {
            spec: spec.clone(),
            scenario_fnv1a: format!("{:016x}", fnv1a(text.as_bytes())),
        })
    }

    /// Why records made under `self` cannot be reused under `other`, if they cannot: the
    /// axes' values may differ (a sweep may grow), nothing else.
    fn conflict(&self, other: &Header) -> Option<&'static str> {
        let (a, b) = (&self.spec, &other.spec);
        if a.scenario != b.scenario {
            Some("scenario")
        } else if self.scenario_fnv1a != other.scenario_fnv1a {
            Some("scenario file's contents")
        } else if a.sets != b.sets {
            Some("[set]")
        } else if a.quantities != b.quantities {
            Some("reduce.quantities")
        } else if a
            .axes
            .iter()
            .map(|x| &x.key)
            .ne(b.axes.iter().map(|x| &x.key))
        {
            Some("axes (their keys or order)")
        } else {
            None
        }
    }
}

/// How a run ended.
#[derive(Serialize, Deserialize, Debug, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// Ran to its end.
    Ok,
    /// Ran to its end with some magnet's gap at or below zero in some step (the values are
    /// there, but the histories after the collision are not physical).
    Collided,
    /// Ran to its end without a collision, outside a running-safety limit of summary.json's
    /// `safety` (docs/safety.md): the error names the figures that failed.
    Unsafe,
    /// Could not run (a bad value, a numerical failure): no values, the error says why.
    Failed,
}

impl Status {
    pub fn name(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Collided => "collided",
            Status::Unsafe => "unsafe",
            Status::Failed => "failed",
        }
    }
}

/// One finished run.
#[derive(Serialize, Deserialize, Debug, Clone, PartialEq)]
pub struct Record {
    /// The run's identity (`key=value,…`).
    pub id: String,
    pub status: Status,
    /// One value per quantity (empty when failed).
    pub values: Vec<f64>,
    /// The error of a failed run, or the collision note.
    pub error: String,
    /// Time steps taken.
    pub steps: usize,
    /// Wall seconds, set-up included.
    pub wall_s: f64,
    /// FNV-1a of the files the run read besides the scenario (its `[support]` records,
    /// `super::inputs`); absent when it read none. A resumed sweep runs a run again when its
    /// files hash otherwise now.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub inputs_fnv1a: String,
}

pub use crate::output::write_atomic;

/// An open sweep directory.
pub struct Store {
    pub dir: PathBuf,
}

impl Store {
    /// Opens (or creates) the sweep directory `dir` for `header`: refuses a directory that is
    /// neither empty nor a sweep's, and one whose records belong to another spec.
    pub fn open(dir: &Path, header: &Header) -> Result<Self> {
        if dir.exists() {
            let ours = dir.join(MARKER).is_file();
            let empty = std::fs::read_dir(dir)
                .map_err(|e| Error::io(dir, e))?
                .next()
                .is_none();
            if !ours && !empty {
                return Err(Error::invalid(
                    "--out",
                    format!(
                        "{}: the directory exists and is not a sweep's (no {MARKER} file); refusing to write into it",
                        dir.display()
                    ),
                ));
            }
            if ours {
                let old = read_header(dir)?;
                if let Some(what) = old.conflict(header) {
                    return Err(Error::invalid(
                        "--out",
                        format!(
                            "{}: holds a sweep whose {what} differs from this spec's; use another directory",
                            dir.display()
                        ),
                    ));
                }
            }
        }
        let runs = dir.join("runs");
        std::fs::create_dir_all(&runs).map_err(|e| Error::io(&runs, e))?;
        write_atomic(
            &dir.join(MARKER),
            b"maglev sweep: runs/ holds one record per finished run; results.csv is rebuilt from them\n",
        )?;
        let json =
            serde_json::to_string_pretty(header).map_err(|e| Error::parse("sweep.json", e))?;
        write_atomic(&dir.join("sweep.json"), (json + "\n").as_bytes())?;
        Ok(Store {
            dir: dir.to_path_buf(),
        })
    }

    /// Writes one run's record.
    pub fn put(&self, run: &Run, record: &Record) -> Result<()> {
        let json =
            serde_json::to_string_pretty(record).map_err(|e| Error::parse("run record", e))?;
        write_atomic(
            &self.dir.join("runs").join(run.file_name()),
            (json + "\n").as_bytes(),
        )
    }

    /// Every record in the directory, by run identity.
    pub fn records(&self) -> Result<BTreeMap<String, Record>> {
        read_records(&self.dir)
    }
}

/// The header of sweep directory `dir`.
pub fn read_header(dir: &Path) -> Result<Header> {
    if !dir.join(MARKER).is_file() {
        return Err(Error::invalid(
            "sweep directory",
            format!("{}: not a sweep's (no {MARKER} file)", dir.display()),
        ));
    }
    let p = dir.join("sweep.json");
    let text = std::fs::read_to_string(&p).map_err(|e| Error::io(&p, e))?;
    serde_json::from_str(&text).map_err(|e| Error::parse(p.display().to_string(), e))
}

/// The records of sweep directory `dir` (temporary files of an interrupted write skipped).
pub fn read_records(dir: &Path) -> Result<BTreeMap<String, Record>> {
    let runs = dir.join("runs");
    let mut out = BTreeMap::new();
    let Ok(entries) = std::fs::read_dir(&runs) else {
        return Ok(out);
    };
    for e in entries {
        let e = e.map_err(|e| Error::io(&runs, e))?;
        let name = e.file_name().to_string_lossy().into_owned();
        if name.starts_with('.') || !name.ends_with(".json") {
            continue;
        }
        let p = e.path();
        let text = std::fs::read_to_string(&p).map_err(|e| Error::io(&p, e))?;
        let r: Record =
            serde_json::from_str(&text).map_err(|e| Error::parse(p.display().to_string(), e))?;
        out.insert(r.id.clone(), r);
    }
    Ok(out)
}

/// results.csv: one row per run of `runs` that has a record, in product order: the axis
/// values, the quantities (shortest round-trip decimals, SI), the status and the error.
pub fn results_csv(
    spec: &Spec,
    runs: &[Run],
    records: &BTreeMap<String, Record>,
) -> Result<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut header: Vec<String> = spec.axes.iter().map(|a| a.key.clone()).collect();
    header.extend(spec.quantities.iter().map(|q| q.name()));
    header.push("status".into());
    header.push("error".into());
    w.write_record(&header)
        .map_err(|e| Error::parse("results.csv", e))?;
    for run in runs {
        let Some(r) = records.get(&run.id) else {
            continue;
        };
        let mut row: Vec<String> = run.values.iter().map(|v| v.cell()).collect();
        for k in 0..spec.quantities.len() {
            row.push(r.values.get(k).map_or(String::new(), |v| v.to_string()));
        }
        row.push(r.status.name().into());
        row.push(r.error.clone());
        w.write_record(&row)
            .map_err(|e| Error::parse("results.csv", e))?;
    }
    w.into_inner()
        .map_err(|e| Error::parse("results.csv", e.to_string()))
}

/// costs.csv: the steps and wall seconds of each run of `runs` that has a record (not
/// deterministic: the wall time is measured).
pub fn costs_csv(spec: &Spec, runs: &[Run], records: &BTreeMap<String, Record>) -> Result<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut header: Vec<String> = spec.axes.iter().map(|a| a.key.clone()).collect();
    header.extend(["status", "steps", "wall_s"].map(String::from));
    w.write_record(&header)
        .map_err(|e| Error::parse("costs.csv", e))?;
    for run in runs {
        let Some(r) = records.get(&run.id) else {
            continue;
        };
        let mut row: Vec<String> = run.values.iter().map(|v| v.cell()).collect();
        row.push(r.status.name().into());
        row.push(r.steps.to_string());
        row.push(format!("{:.4}", r.wall_s));
        w.write_record(&row)
            .map_err(|e| Error::parse("costs.csv", e))?;
    }
    w.into_inner()
        .map_err(|e| Error::parse("costs.csv", e.to_string()))
}
