//! `maglev`: the command-line front end. Each subcommand lives in `cli/<name>.rs`.

use clap::{Parser, Subcommand};
use maglev_host_sim::cli;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "maglev",
    version,
    about = "EMS maglev levitation control and guideway vibration (Ju, Ho & Leong 2012)"
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
}

/// Exit status: 0 done, 2 an error (one line on stderr), 3 `run --strict` refused the run.
fn main() -> ExitCode {
    let args = Cli::parse();
    let result: anyhow::Result<()> = match args.command {
        Command::Control(a) => cli::control::run(a),
        Command::Irregularity(a) => cli::irregularity::run(a).map_err(anyhow::Error::from),
        Command::Run(a) => match cli::run::run(a) {
            Ok(true) => Ok(()),
            Ok(false) => return ExitCode::from(3),
            Err(e) => Err(e),
        },
        Command::Modes(a) => cli::modes::run(a).map_err(anyhow::Error::from),
        Command::Validate(a) => cli::validate::run_cmd(a),
        Command::Stability(a) => cli::stability::run(a).map_err(anyhow::Error::from),
        Command::Hil(a) => cli::hil::run(a),
        Command::Bands(a) => cli::bands::run(a),
        Command::Report(a) => cli::report::run(a),
        Command::Sweep(a) => cli::sweep::run(a).map_err(anyhow::Error::from),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // One line: the causes joined, as the library words them (a cause the message
            // already ends with, such as an I/O error's, only once).
            let mut joined = String::new();
            for cause in e.chain().map(|c| c.to_string()) {
                if !joined.ends_with(&cause) {
                    if !joined.is_empty() {
                        joined.push_str(": ");
                    }
                    joined.push_str(&cause);
                }
            }
            let line = joined.split_whitespace().collect::<Vec<_>>().join(" ");
            eprintln!("maglev: error: {line}");
            ExitCode::from(2)
        }
    }
}
