//! `maglev`: the command-line front end. Each subcommand lives in `cli/<name>.rs`.

use clap::{Parser, Subcommand};
use maglev_host_sim::cli;

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
    /// Linearised stability of the levitation law: poles, spectral radius, critical dt.
    Stability(cli::stability::Args),
}

fn main() {
    let args = Cli::parse();
    let result = match args.command {
        Command::Control(a) => cli::control::run(a),
        Command::Irregularity(a) => cli::irregularity::run(a),
        Command::Stability(a) => cli::stability::run(a),
    };
    if let Err(e) = result {
        eprintln!("maglev: error: {e}");
        std::process::exit(2);
    }
}
