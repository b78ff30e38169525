//! `maglev control`: the levitation law of the core on a gap trace (a `t,h` CSV), through
//! [`crate::studies::control`]. Output is buffered and written only when the whole trace ran, so a
//! failure never leaves half a CSV on stdout.

use crate::studies::control::{parse_trace, run_trace_as, to_csv, Row, ScalarKind};
use crate::{Error, Result};
use anyhow::Context as _;
use maglev_core::{Interpolation, Params, Scheme, Status};
use std::path::PathBuf;

/// Controller parameters shared by every subcommand that runs the law.
#[derive(clap::Args, Debug, Clone)]
pub struct ControllerArgs {
    /// Integrator: the paper's Eq. 14 with sub-steps, or the accurate Gauss–Legendre scheme.
    #[arg(long, value_parser = super::core_word::<Scheme>, default_value = "paper")]
    pub scheme: Scheme,
    /// α of the α-method, in [0, 1].
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.5)]
    pub alpha: f64,
    /// Internal-loop sub-steps per outer step.
    #[arg(long = "nsub", allow_negative_numbers = true, default_value_t = 1)]
    pub n_sub: u32,
    /// Gap interpolation inside the outer step.
    #[arg(long = "interp", value_parser = super::core_word::<Interpolation>, default_value = "linear")]
    pub interp: Interpolation,
    /// Nominal current i0 (A).
    #[arg(long, allow_negative_numbers = true, default_value_t = 43.0)]
    pub i0: f64,
    /// Nominal gap h0 (m).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.01)]
    pub h0: f64,
    /// Coil resistance R0 (Ω).
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0)]
    pub r0: f64,
    /// Proportional gain KP (V·m/A).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.01)]
    pub kp: f64,
    /// Integral gain KI (V·m/(A·s)).
    #[arg(long, allow_negative_numbers = true, default_value_t = 6.0)]
    pub ki: f64,
    /// Static load on the magnet p0 (N); default: a quarter of 15 t.
    #[arg(long, allow_negative_numbers = true, default_value_t = 15_000.0 * maglev_core::levitation::GRAVITY / 4.0)]
    pub p0: f64,
    /// Supply voltage bound ±V (V); `inf` for none (the paper has none).
    #[arg(long, allow_negative_numbers = true, default_value_t = f64::INFINITY)]
    pub vmax: f64,
}

impl ControllerArgs {
    /// The core's parameters for an outer step `dt`, validated (errors name the parameter).
    pub fn params(&self, dt: f64) -> Result<Params> {
        let p = Params {
            i0: self.i0,
            h0: self.h0,
            r0: self.r0,
            kp: self.kp,
            ki: self.ki,
            p0: self.p0,
            alpha: self.alpha,
            dt,
            n_sub: self.n_sub,
            interpolation: self.interp,
            v_max: self.vmax,
            scheme: self.scheme,
        };
        p.validate()
            .map_err(|e| Error::invalid("controller", e.to_string()))?;
        Ok(p)
    }
}

#[derive(clap::Args, Debug)]
pub struct Args {
    /// CSV with header `t,h` (seconds, metres) and a uniform time step.
    #[arg(long)]
    pub trace: PathBuf,
    /// Run-time number type of the controller.
    #[arg(long, value_enum, default_value_t = ScalarKind::F64)]
    pub scalar: ScalarKind,
    #[command(flatten)]
    pub controller: ControllerArgs,
}

/// Notes on stderr about events (collisions, saturation) that are not errors.
fn report_events(rows: &[Row]) {
    let events = [
        (Status::COLLISION, "collision (gap <= 0)"),
        (Status::VOLTAGE_SATURATED, "voltage bound active"),
        (Status::CURRENT_CLAMPED, "current held at zero"),
        (
            Status::INVALID_INPUT,
            "gap beyond the accepted range, clamped",
        ),
    ];
    for (flag, what) in events {
        let hits: Vec<&Row> = rows.iter().filter(|r| r.status.contains(flag)).collect();
        if let Some(first) = hits.first() {
            eprintln!(
                "maglev: note: {what} in {} step(s), first at t = {} s",
                hits.len(),
                first.t
            );
        }
    }
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let name = args.trace.display().to_string();
    let text = crate::input::read_text(&args.trace).context("cannot read trace")?;
    let trace = parse_trace(&text, &name)?;
    let params = args.controller.params(trace.dt)?;
    let rows = run_trace_as(args.scalar, &params, &trace)?;
    report_events(&rows);
    Ok(crate::cli::stdout::print(&to_csv(&rows))?)
}
