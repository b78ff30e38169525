//! `maglev validate [--out DIR]`: the paper's validation (§4.3–4.5, Fig. 5) through
//! [`crate::studies::validation`]; writes report.md, validation.json and the figures, and exits
//! non-zero when a criterion fails.

use crate::cli::progress::Progress;
use crate::output::owned;
use crate::studies::validation::{validate, RUNS};
use crate::Error;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// File name of the report inside --out (`maglev validate --out docs --report
    /// validation.md` regenerates the committed docs/validation.md and its figures).
    #[arg(long, default_value = "report.md")]
    pub report: String,
    /// Output directory for the report, validation.json and the figures. Unlike `run`,
    /// validate writes only its own files into it and leaves the rest alone (so it can be
    /// docs/): a new or empty directory, or one whose .maglev-validation lists the files it
    /// replaces; nothing is written unless every case has run.
    #[arg(long, default_value = "validation")]
    pub out: PathBuf,
    /// Controller scheme of every run, FE and modal reference alike (`controller.scheme`).
    #[arg(long, value_parser = super::core_word::<maglev_core::Scheme>, default_value = "paper")]
    pub scheme: maglev_core::Scheme,
    /// Override a scenario value in every case, FE and modal reference alike (as `maglev run
    /// --set`; repeatable). The keys that define the cases (speed, model, elements, dt, nsub)
    /// are refused.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
}

pub fn run_cmd(args: Args) -> anyhow::Result<()> {
    crate::studies::validation::check_sets(&args.sets)?;
    owned::plain_name("--report", &args.report)?;
    owned::check(&args.out, &[&args.report, "validation.json"])?;
    let mut bar = Progress::steps("validate", RUNS);
    let out = validate(&args.sets, args.scheme, |what| bar.step(what))?;
    drop(bar);
    // Everything is in memory now: nothing is created before the validation has run, and
    // each file is written beside its place and renamed into it.
    let v = &out.validation;
    let mut files = out.figures.clone();
    files.push((args.report.clone(), out.report.clone()));
    files.push((
        "validation.json".to_string(),
        serde_json::to_string_pretty(v)? + "\n",
    ));
    owned::write(&args.out, &files)?;
    eprintln!(
        "maglev: validate: {} in {:.0} s; wrote {}",
        if v.pass { "PASS" } else { "FAIL" },
        v.wall_seconds,
        args.out.display()
    );
    if !v.pass {
        return Err(Error::CheckFailed(format!(
            "validation failed: see {}",
            args.out.join(&args.report).display()
        ))
        .into());
    }
    Ok(())
}
