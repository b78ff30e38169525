//! `maglev bands`: one-third-octave band levels of a CSV time history (`crate::bands`,
//! docs/bands.md) as CSV `centre_hz,level_db_re_…` with a plain header (pandas reads it as it
//! is); the reference, the quantities and the method on stderr, or in the sidecar
//! `FILE.json` of `--out FILE`.

use std::io::BufReader;
use std::path::PathBuf;

use crate::bands::{self, Averaging, Level, Motion, Settings};
use crate::Error;

/// What the input column holds.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionArg {
    Acceleration,
    Velocity,
    Displacement,
}

/// What the level is of.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum LevelArg {
    Acceleration,
    Velocity,
}

#[derive(clap::Args, Debug)]
pub struct Args {
    /// CSV time history with a header row: column `t` (s, uniformly sampled) and --column.
    #[arg(long)]
    pub input: PathBuf,
    /// The column to analyse (SI units).
    #[arg(long)]
    pub column: String,
    /// What the column is.
    #[arg(long, value_enum, default_value_t = MotionArg::Acceleration)]
    pub quantity: MotionArg,
    /// What the level is of: acceleration (re 1e-6 m/s²) or velocity (re 1e-9 m/s).
    #[arg(long, value_enum, default_value_t = LevelArg::Acceleration)]
    pub output: LevelArg,
    /// Report the maximum running rms over a linear (rectangular) window of this many
    /// seconds instead of the whole-record rms (ISO 2631-1 MTVV: 1 s).
    #[arg(long, allow_negative_numbers = true)]
    pub running: Option<f64>,
    /// Write the CSV to this file instead of stdout.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

fn settings(a: &Args) -> Settings {
    Settings {
        input: match a.quantity {
            MotionArg::Acceleration => Motion::Acceleration,
            MotionArg::Velocity => Motion::Velocity,
            MotionArg::Displacement => Motion::Displacement,
        },
        level: match a.output {
            LevelArg::Acceleration => Level::Acceleration,
            LevelArg::Velocity => Level::Velocity,
        },
        averaging: a
            .running
            .map_or(Averaging::WholeRecord, |window_s| Averaging::MaxRunning {
                window_s,
            }),
    }
}

/// The method's sidecar of the CSV at `path`: `levels.csv` → `levels.csv.json`.
fn sidecar(path: &std::path::Path) -> PathBuf {
    let mut name = path.as_os_str().to_owned();
    name.push(".json");
    PathBuf::from(name)
}

/// Run the subcommand (the open error of `--input` is given as such).
pub fn run(a: Args) -> anyhow::Result<()> {
    use anyhow::Context as _;
    if let Some(w) = a.running {
        if !(w.is_finite() && w > 0.0) {
            return Err(Error::invalid(
                "--running",
                format!("must be a positive number of seconds, got {w}"),
            )
            .into());
        }
    }
    let s = settings(&a);
    let file = crate::input::open(&a.input).context("--input")?;
    let h = bands::read_history(BufReader::new(file), &a.column)
        .map_err(|e| Error::parse(format!("--input {}", a.input.display()), e))?;
    let levels = bands::analyse(&h.values, h.dt, &s).map_err(|e| match e {
        bands::BandsError::BadWindow { .. } => Error::invalid("--running", e.to_string()),
        _ => Error::invalid(format!("--input {}", a.input.display()), e.to_string()),
    })?;
    let method = bands::description(&a.column, h.values.len(), h.dt, &s);
    // Made in memory (a few kB), then written where it goes: a failed write keeps its
    // kind (a reader gone from stdout ends quietly, crate::cli::stdout).
    let mut text = Vec::new();
    bands::write_levels(&mut text, &bands::level_column(&s), &levels)
        .map_err(|e| Error::numerical(format!("internal: {e}")))?;
    match &a.out {
        Some(path) => {
            std::fs::write(path, &text).map_err(|e| Error::io(path, e))?;
            let side = sidecar(path);
            let json = serde_json::json!({ "csv": path.file_name().map(|n| n.to_string_lossy()), "method": method });
            std::fs::write(&side, json.to_string() + "\n").map_err(|e| Error::io(&side, e))?;
        }
        None => {
            eprintln!("maglev: bands: {method}");
            crate::cli::stdout::print(&String::from_utf8_lossy(&text))?
        }
    }
    Ok(())
}
