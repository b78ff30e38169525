//! `maglev sweep SPEC.toml --out DIR [--jobs N] [--shard I/N]`, `maglev sweep merge DIR…
//! --out DIR` and `maglev sweep SPEC --emit slurm --out DIR`: parses, calls `crate::studies::sweep`,
//! reports on stderr.

use crate::studies::sweep::{self, runs::Shard, slurm, Options, Spec};
use crate::{Error, Result};
use std::io::IsTerminal;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct Args {
    #[command(subcommand)]
    pub command: Option<Sub>,
    /// The sweep spec (TOML: scenario, [set], [axes], [reduce]; docs/sweeps.md).
    #[arg(required = true)]
    pub spec: Option<PathBuf>,
    /// The sweep directory (resumable: a rerun skips the runs recorded there), or with
    /// --emit the directory of the job scripts.
    #[arg(long, required = true)]
    pub out: Option<PathBuf>,
    /// Runs at once (default: the machine's cores).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Run only shard I of N (every N-th run, from run I).
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// Run again the runs recorded as failed.
    #[arg(long)]
    pub retry_failed: bool,
    /// Write job scripts for a scheduler instead of running.
    #[arg(long, value_enum)]
    pub emit: Option<Scheduler>,
    /// With --emit: array tasks (shards).
    #[arg(long, default_value_t = 4)]
    pub shards: usize,
    /// With --emit: CPUs per array task.
    #[arg(long, default_value_t = 1)]
    pub cpus_per_task: usize,
    /// With --emit: the maglev binary the jobs run (default: this one).
    #[arg(long)]
    pub maglev: Option<PathBuf>,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug)]
pub enum Scheduler {
    Slurm,
}

#[derive(clap::Subcommand, Debug)]
pub enum Sub {
    /// Combine shard directories into one whose results.csv equals the unsharded sweep's.
    Merge {
        /// The shards' sweep directories.
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// The merged sweep directory.
        #[arg(long)]
        out: PathBuf,
    },
}

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    if let Some(Sub::Merge { dirs, out }) = args.command {
        let n = sweep::merge(&dirs, &out)?;
        eprintln!(
            "maglev: sweep merge: {n} runs from {} directories; wrote {}",
            dirs.len(),
            out.join("results.csv").display()
        );
        return Ok(());
    }
    let (Some(spec_path), Some(out)) = (args.spec, args.out) else {
        return Err(Error::invalid("sweep", "needs SPEC and --out"));
    };
    let spec = Spec::load(&spec_path)?;
    if let Some(Scheduler::Slurm) = args.emit {
        let maglev = match args.maglev {
            Some(m) => m,
            None => std::env::current_exe().map_err(|e| Error::io("maglev", e))?,
        };
        let e = slurm::emit(
            &slurm::Emit {
                spec: spec_path,
                out,
                shards: args.shards,
                cpus_per_task: args.cpus_per_task,
                maglev,
            },
            spec.runs(),
        )?;
        eprintln!(
            "maglev: sweep: {} runs in {} array tasks; submit with {}, or run here with {}",
            spec.runs(),
            e.shards,
            e.out.join("submit.sh").display(),
            e.out.join("run-local.sh").display()
        );
        return Ok(());
    }
    let jobs = match args.jobs {
        Some(j) => j,
        None => std::thread::available_parallelism().map_or(1, |n| n.get()),
    };
    let opts = Options {
        jobs,
        shard: args.shard.as_deref().map(Shard::parse).transpose()?,
        retry_failed: args.retry_failed,
        progress: std::io::stderr().is_terminal(),
    };
    let r = sweep::sweep(&spec, &out, &opts)?;
    eprintln!(
        "maglev: sweep: {} runs: {} run now, {} skipped (recorded before), {} failed; {:.2} s wall with {jobs} job(s); wrote {}",
        r.runs,
        r.ran,
        r.skipped,
        r.failed,
        r.wall_s,
        out.join("results.csv").display()
    );
    if r.failed > 0 {
        eprintln!("maglev: sweep: the failed runs' errors are in results.csv (status, error)");
    }
    Ok(())
}
