//! `maglev report paper-5 --out DIR [--set key=value]...`: runs both trains of the paper's
//! §5 over the viaduct and writes report.md, fig8.svg, bands.csv and each train's histories
//! (history-maglev.csv, history-wheel-rail.csv), through [`crate::studies::paper5`]; and the ground
//! section (ground-levels.csv, ground-levels.svg, ground-map-{train}.svg, through
//! [`crate::studies::paper5::ground`]).

use crate::cli::progress::Progress;
use crate::output::Staging;
use crate::studies::paper5::ground;
use crate::studies::paper5::{self, CARRIAGE, PIER, TRAINS};
use std::fmt::Write as _;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// The report: `paper-5` (the paper's Fig. 8 comparison).
    #[arg(value_parser = ["paper-5"])]
    pub report: String,
    /// Output directory (replaced whole, as for `maglev run`).
    #[arg(long, default_value = "report-paper-5")]
    pub out: PathBuf,
    /// Override a scenario value in both runs (as `maglev run --set`; `train` is the report's).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// Threads: the two trains' runs side by side and the ground section's receivers shared
    /// (1 to 64; the same bytes for every count).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u16).range(1..=64))]
    pub threads: u16,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    if let Some(s) = args
        .sets
        .iter()
        .find(|s| s.trim_start().starts_with("train="))
    {
        anyhow::bail!("report --set {s}: the report runs both trains; override another key");
    }
    let out = Staging::new(&args.out)?;
    let threads = usize::from(args.threads);
    let runs = run_trains(&args.sets, threads)?;
    let maglev = paper5::levels(&runs[0])?;
    let wheel_rail = paper5::levels(&runs[1])?;
    for r in &runs {
        let mut csv = format!("t,{CARRIAGE},{PIER}\n");
        for (i, (c, p)) in r.carriage.iter().zip(&r.pier).enumerate() {
            let _ = writeln!(csv, "{},{c},{p}", i as f64 * r.dt);
        }
        out.put(&format!("history-{}.csv", r.train), &csv)?;
    }
    out.put("bands.csv", &paper5::bands_csv(&maglev, &wheel_rail))?;
    out.put("fig8.svg", &paper5::figure(&maglev, &wheel_rail)?)?;
    let mut md = paper5::markdown(&runs, &maglev, &wheel_rail, &args.sets);
    let start = std::time::Instant::now();
    let ground = ground::analyse(&runs, threads)?;
    eprintln!(
        "maglev: report: ground section in {:.1} s wall",
        start.elapsed().as_secs_f64()
    );
    out.put("ground-levels.csv", &ground::csv(&ground))?;
    out.put("ground-overall.csv", &ground::overall_csv(&ground))?;
    out.put("ground-levels.svg", &ground::figure(&ground)?)?;
    for (g, r) in ground.iter().zip(&runs) {
        out.put(
            &format!("ground-map-{}.svg", g.train),
            &ground::map_svg(g, r.span)?,
        )?;
    }
    md.push_str(&ground::markdown(&ground));
    out.put("report.md", &md)?;
    out.finish()?;
    for s in paper5::statements(&maglev, &wheel_rail) {
        eprintln!(
            "maglev: report: {} — {} ({})",
            if s.holds { "holds" } else { "DOES NOT HOLD" },
            s.claim,
            s.measured
        );
    }
    eprintln!("maglev: report: wrote {}", args.out.display());
    Ok(())
}

/// Both trains' runs: side by side on two threads when `threads` ≥ 2 (each run is the same
/// computation on its own data either way), one after the other otherwise; one bar for both.
fn run_trains(sets: &[String], threads: usize) -> anyhow::Result<Vec<paper5::TrainRun>> {
    let bar = std::sync::Mutex::new((Progress::run("report: both trains"), [0.0; 2]));
    let progress = |i: usize, f: f64| {
        if let Ok(mut b) = bar.lock() {
            b.1[i] = f;
            let mean = (b.1[0] + b.1[1]) / 2.0;
            b.0.fraction(mean);
        }
    };
    let one = |i: usize| paper5::run_train(TRAINS[i], sets, |f| progress(i, f));
    let runs = if threads >= 2 {
        std::thread::scope(|s| {
            let h = s.spawn(|| one(1));
            let first = one(0);
            let second = h
                .join()
                .unwrap_or_else(|_| Err(maglev_sim::Error::numerical("report: a run panicked")));
            vec![first, second]
        })
    } else {
        vec![one(0), one(1)]
    };
    Ok(runs.into_iter().collect::<Result<Vec<_>, _>>()?)
}
