//! `maglev run SCENARIO [--set key=value]... [--out DIR]`: one passage, FE or modal guideway.

use crate::output::{write_run, Summary};
use crate::scenario::{self, Scenario};
use crate::setup::Passage;
use crate::simulation::{simulate, Outcome};
use std::path::PathBuf;
use std::time::Instant;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// A scenario TOML file, or a bundled name (paper-4.2, moving-force).
    pub scenario: String,
    /// Override a scenario value: speed, model, elements, modes, dt, t_end, nsub, alpha, scheme,
    /// law, seed, or section.key (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// Output directory.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
}

/// Runs a scenario; `progress` gets the fraction done. Returns the outcome and wall seconds.
pub fn execute(sc: &Scenario, progress: impl FnMut(f64)) -> Result<(Outcome, f64), String> {
    let mut p = Passage::new(sc)?;
    let start = Instant::now();
    let outcome = simulate(&mut p.guideway, &p.load, &p.profiles, &p.settings, progress)?;
    Ok((outcome, start.elapsed().as_secs_f64()))
}

pub fn run(args: Args) -> Result<(), String> {
    let sc = scenario::load(&args.scenario, &args.sets)?;
    let mut last = Instant::now();
    let (outcome, wall) = execute(&sc, |f| {
        if last.elapsed().as_secs_f64() > 2.0 {
            eprintln!("maglev: {:.0} % …", 100.0 * f);
            last = Instant::now();
        }
    })?;
    if outcome.unconverged_steps > 0 {
        eprintln!(
            "maglev: warning: {} step(s) hit max_iterations without converging",
            outcome.unconverged_steps
        );
    }
    let summary = Summary::new(
        &args.scenario,
        &sc.run.model,
        &outcome.records,
        wall,
        outcome.unconverged_steps,
    );
    write_run(&args.out, &outcome.records, &summary)?;
    eprintln!(
        "maglev: {} steps, {:.3} s simulated in {:.2} s wall; wrote {}",
        summary.steps,
        summary.simulated_seconds,
        wall,
        args.out.display()
    );
    Ok(())
}
