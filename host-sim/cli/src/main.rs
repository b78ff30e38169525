//! `maglev`: the command-line front end. Each subcommand lives in `cli/<name>.rs`.

use clap::{Parser, Subcommand};
use maglev::cli;
use maglev_sim::error::exit;
use std::process::ExitCode;

/// The exit statuses, as `maglev --help` shows them (README "Exit codes").
const EXIT_CODES: &str = "Exit codes:
  0  done (also when the reader of stdout went away, e.g. `| head`)
  1  the outputs are written, but a check of the result failed: validate FAIL, or a run
     (run, hil) with steps that did not converge to run.tolerance_m
  2  bad input or usage, or a failure that left no result (file, numerics, firmware);
     one line on stderr naming the key and the limit
  3  run --strict: the run collided or a gap left (0, 2·h0) (the outputs are written)";

#[derive(Parser)]
#[command(
    name = "maglev",
    version,
    about = "EMS maglev levitation control and guideway vibration (Ju, Ho & Leong 2012)",
    after_help = EXIT_CODES
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run the levitation controller (Eq. 8-14) on a gap trace; CSV to stdout.
    Control(cli::control::Args),
    /// Generate a rail irregularity profile (Eq. 3-5, Table 1); CSV to stdout.
    Irregularity(cli::irregularity::Args),
    /// Run one scenario (a vehicle passage over the guideway); CSV, JSON and SVG into --out.
    Run(cli::run::Args),
    /// Natural frequencies of the section 4.2 beam (FE, Timoshenko); JSON or CSV to stdout.
    Modes(cli::modes::Args),
    /// The paper's validation (§4.3-4.5, Fig. 5): FE against the modal reference; report.md.
    Validate(cli::validate::Args),
    /// Linearised stability of the levitation law: poles, spectral radius, critical dt.
    Stability(cli::stability::Args),
    /// A passage with the levitation firmware as the controller (in-process, host process
    /// or QEMU), in lockstep; --compare reports the difference to the ideal run.
    Hil(cli::hil::Args),
    /// IEC 61260-1 one-third-octave band levels of a CSV time history (docs/bands.md).
    Bands(cli::bands::Args),
    /// Many runs over the product of --set axes, reduced to peak/min/max/rms of probes;
    /// parallel, resumable, sharded, merged, or emitted as a Slurm job array (docs/sweeps.md).
    Sweep(cli::sweep::Args),
    /// The paper's §5 (Fig. 8): maglev and wheel/rail trains over the viaduct, band levels at
    /// a carriage and a pier, held against the paper's statements; report.md into --out.
    Report(cli::report::Args),
    /// Ground-borne vibration: `ground green` prints the half-space Green's function
    /// (vertical surface displacement per newton of a vertical point load; docs/ground.md).
    Ground(cli::ground::Args),
    /// A synthetic, seeded ground-acceleration record (Clough-Penzien noise under an
    /// envelope, ending at rest, scaled to a PGA); CSV to stdout (docs/seismic.md).
    Accelerogram(cli::accelerogram::Args),
}

/// Exit status: [`EXIT_CODES`], decided by [`maglev_sim::Error::exit_code`].
fn main() -> ExitCode {
    maglev::output::staging::interrupt::install();
    let args = match Cli::try_parse() {
        Ok(args) => args,
        Err(e) => return usage_error(e),
    };
    let result: anyhow::Result<()> = match args.command {
        Command::Control(a) => cli::control::run(a),
        Command::Irregularity(a) => cli::irregularity::run(a).map_err(anyhow::Error::from),
        Command::Run(a) => cli::run::run(a),
        Command::Modes(a) => cli::modes::run(a).map_err(anyhow::Error::from),
        Command::Validate(a) => cli::validate::run_cmd(a),
        Command::Stability(a) => cli::stability::run(a).map_err(anyhow::Error::from),
        Command::Hil(a) => cli::hil::run(a),
        Command::Bands(a) => cli::bands::run(a),
        Command::Report(a) => cli::report::run(a),
        Command::Ground(a) => cli::ground::run(a),
        Command::Accelerogram(a) => cli::accelerogram::run(a).map_err(anyhow::Error::from),
        Command::Sweep(a) => cli::sweep::run(a).map_err(anyhow::Error::from),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if cli::stdout::is_broken_pipe(&e) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!(
                "maglev: error: {}",
                one_line(e.chain().map(|c| c.to_string()))
            );
            let code = e
                .chain()
                .find_map(|c| c.downcast_ref::<maglev_sim::Error>())
                .map_or(exit::ERROR, maglev_sim::Error::exit_code);
            ExitCode::from(code)
        }
    }
}

/// One line of `causes` joined, as the library words them (a cause the message already ends
/// with, such as an I/O error's, only once).
fn one_line(causes: impl Iterator<Item = String>) -> String {
    let mut joined = String::new();
    for cause in causes {
        if !joined.ends_with(&cause) {
            if !joined.is_empty() {
                joined.push_str(": ");
            }
            joined.push_str(&cause);
        }
    }
    joined.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// Help and version as clap prints them; any other parse error as one line with the prefix
/// every error has (clap's lines, its usage and tip included, joined by `; `), exit 2.
fn usage_error(e: clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    if matches!(
        e.kind(),
        ErrorKind::DisplayHelp
            | ErrorKind::DisplayVersion
            | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    ) {
        e.exit();
    }
    let text = e.render().to_string();
    let mut line = String::new();
    for l in text.lines().map(str::trim).filter(|l| !l.is_empty()) {
        // A line that announces a list runs on into it; others are joined by `; `.
        if !line.is_empty() {
            line.push_str(if line.ends_with(':') { " " } else { "; " });
        }
        line.push_str(l.strip_prefix("error: ").unwrap_or(l));
    }
    eprintln!("maglev: error: {}", one_line(std::iter::once(line)));
    ExitCode::from(exit::ERROR)
}
