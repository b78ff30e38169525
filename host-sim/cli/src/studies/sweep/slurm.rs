//! `sweep --emit slurm`: a Slurm job array with one task per shard, and a merge job that
//! waits for the whole array.
//!
//! Why scripts and not a scheduler client: the cluster's own `sbatch` is the interface users
//! trust and audit, and the same scripts run here without Slurm (`run-local.sh` executes each
//! array task with `SLURM_ARRAY_TASK_ID` set, as Slurm would). Every path in the scripts is
//! absolute, as a batch job starts in a directory of Slurm's choosing.
//!
//! Files: `sweep.sbatch` (`#SBATCH --array=1-N`; task I runs `--shard I/N` into `shard-I/`),
//! `merge.sbatch` (`sweep merge shard-1 … shard-N --out merged`), `submit.sh` (submits the
//! array, then the merge with `--dependency=afterok:<array job>`), `run-local.sh`.

use crate::{Error, Result};
use std::path::{Path, PathBuf};

/// The file that marks a directory as holding emitted Slurm scripts.
pub const MARKER: &str = ".maglev-slurm";

/// What to emit.
#[derive(Clone, Debug)]
pub struct Emit {
    /// The spec file (made absolute here).
    pub spec: PathBuf,
    /// The directory of the scripts, the shards and the merge (made absolute here).
    pub out: PathBuf,
    /// Array tasks (1 ≤ shards ≤ runs).
    pub shards: usize,
    /// CPUs per array task (each task runs its shard with as many jobs).
    pub cpus_per_task: usize,
    /// The `maglev` binary the jobs run (overridable at run time by `$MAGLEV`).
    pub maglev: PathBuf,
}

/// Single-quotes `s` for the shell.
fn sq(s: &Path) -> String {
    format!("'{}'", s.to_string_lossy().replace('\'', r"'\''"))
}

fn absolute(p: &Path, key: &str) -> Result<PathBuf> {
    std::path::absolute(p).map_err(|e| Error::invalid(key, format!("{}: {e}", p.display())))
}

/// The four files: (name, text).
pub fn scripts(e: &Emit) -> Vec<(&'static str, String)> {
    let n = e.shards;
    let out = &e.out;
    let logs = out.join("logs");
    let task_dir = format!("{}\"$SLURM_ARRAY_TASK_ID\"", sq(&out.join("shard-")));
    let sweep = format!(
        r#"#!/bin/bash
# maglev sweep as a Slurm job array: array task I runs shard I of {n} (written by
# `maglev sweep --emit slurm`; submit with submit.sh, or run here with run-local.sh).
#SBATCH --job-name=maglev-sweep
#SBATCH --array=1-{n}
#SBATCH --ntasks=1
#SBATCH --cpus-per-task={c}
#SBATCH --output={log}
set -euo pipefail
: "${{SLURM_ARRAY_TASK_ID:?is set by Slurm for each array task}}"
MAGLEV=${{MAGLEV:-{bin}}}
exec "$MAGLEV" sweep {spec} --shard "$SLURM_ARRAY_TASK_ID/{n}" \
  --jobs "${{SLURM_CPUS_PER_TASK:-{c}}}" --out {dir}
"#,
        c = e.cpus_per_task,
        log = logs.join("shard-%a.log").display(),
        bin = sq(&e.maglev),
        spec = sq(&e.spec),
        dir = task_dir,
    );
    let shards: Vec<String> = (1..=n)
        .map(|i| sq(&out.join(format!("shard-{i}"))))
        .collect();
    let merge = format!(
        r#"#!/bin/bash
# Merges the {n} shards of the sweep array into merged/ (submitted by submit.sh with
# --dependency=afterok on the array job, so it starts when every array task has succeeded).
#SBATCH --job-name=maglev-sweep-merge
#SBATCH --ntasks=1
#SBATCH --cpus-per-task=1
#SBATCH --output={log}
set -euo pipefail
MAGLEV=${{MAGLEV:-{bin}}}
exec "$MAGLEV" sweep merge \
  {shards} \
  --out {merged}
"#,
        log = logs.join("merge.log").display(),
        bin = sq(&e.maglev),
        shards = shards.join(" \\\n  "),
        merged = sq(&out.join("merged")),
    );
    let submit = format!(
        r#"#!/bin/bash
# Submits the sweep's job array, then the merge job depending on all of its tasks.
# Extra arguments go to both sbatch calls (e.g. --partition=short).
set -euo pipefail
array=$(sbatch --parsable "$@" {sweep})
array=${{array%%;*}}
merge=$(sbatch --parsable "$@" --dependency=afterok:"$array" {merge})
echo "array job $array ({n} tasks), merge job ${{merge%%;*}}"
"#,
        sweep = sq(&out.join("sweep.sbatch")),
        merge = sq(&out.join("merge.sbatch")),
    );
    let local = format!(
        r#"#!/bin/bash
# Runs the array tasks here, one after another, as Slurm would run them (each with
# SLURM_ARRAY_TASK_ID and the other array variables set), then the merge.
set -euo pipefail
for i in $(seq 1 {n}); do
  SLURM_JOB_ID=local-$i SLURM_ARRAY_JOB_ID=local SLURM_ARRAY_TASK_ID=$i \
    SLURM_ARRAY_TASK_COUNT={n} SLURM_ARRAY_TASK_MIN=1 SLURM_ARRAY_TASK_MAX={n} \
    SLURM_CPUS_PER_TASK={c} bash {sweep}
done
bash {merge}
"#,
        c = e.cpus_per_task,
        sweep = sq(&out.join("sweep.sbatch")),
        merge = sq(&out.join("merge.sbatch")),
    );
    vec![
        ("sweep.sbatch", sweep),
        ("merge.sbatch", merge),
        ("submit.sh", submit),
        ("run-local.sh", local),
    ]
}

/// Writes the scripts of `e` for a sweep of `runs` runs into `e.out` (and its `logs/`).
pub fn emit(e: &Emit, runs: usize) -> Result<Emit> {
    if e.shards == 0 || e.shards > runs {
        return Err(Error::invalid(
            "--shards",
            format!(
                "must be from 1 to the sweep's {runs} runs, got {}",
                e.shards
            ),
        ));
    }
    if e.cpus_per_task == 0 {
        return Err(Error::invalid(
            "--cpus-per-task",
            "must be at least 1, got 0",
        ));
    }
    let e = Emit {
        spec: absolute(&e.spec, "spec")?,
        out: absolute(&e.out, "--out")?,
        maglev: absolute(&e.maglev, "--maglev")?,
        ..e.clone()
    };
    if e.out.exists() && !e.out.join(MARKER).is_file() {
        let empty = std::fs::read_dir(&e.out)
            .map_err(|x| Error::io(&e.out, x))?
            .next()
            .is_none();
        if !empty {
            return Err(Error::invalid(
                "--out",
                format!(
                    "{}: the directory exists and holds no emitted sweep (no {MARKER} file); refusing to write into it",
                    e.out.display()
                ),
            ));
        }
    }
    let logs = e.out.join("logs");
    std::fs::create_dir_all(&logs).map_err(|x| Error::io(&logs, x))?;
    for (name, text) in scripts(&e) {
        let p = e.out.join(name);
        super::store::write_atomic(&p, text.as_bytes())?;
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o755))
                .map_err(|x| Error::io(&p, x))?;
        }
    }
    super::store::write_atomic(
        &e.out.join(MARKER),
        b"maglev sweep --emit slurm: job scripts; shard-*/ and merged/ are written by the jobs\n",
    )?;
    Ok(e)
}
