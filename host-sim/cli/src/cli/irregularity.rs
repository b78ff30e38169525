//! `maglev irregularity`: a rail irregularity profile (Eq. 3–5, Table 1) as CSV `x,r` in m.
//!
//! The profile is `maglev_core::irregularity::Irregularity<f64>`; the phases depend only on
//! `--seed` and `--direction` (see the core module docs), so the CSV is reproducible on any
//! machine (to round-off). Evaluating the 2000-term sum with one cosine per term and sample
//! would take minutes for a 26 km profile, so `profile::sweep` evaluates the same direct sum
//! on the uniform grid by the chirp-z transform (see there for the accuracy).

use std::io::Write;

use crate::physics::profile::sweep;
use crate::{Error, Result};
use maglev_core::irregularity::{Direction, Irregularity, PsdParams};

/// Largest number of rows the command will write (10⁸ rows is ~3 GB of CSV).
pub const MAX_SAMPLES: u64 = 100_000_000;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Profile direction: y (lateral, guidance) or z (vertical, levitation); selects Table 1's
    /// row and the random stream.
    #[arg(long)]
    pub direction: String,
    /// Seed of the phase generator (u64).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Sample spacing, m (> 0).
    #[arg(long, default_value_t = 0.1, allow_negative_numbers = true)]
    pub dx: f64,
    /// Profile length, m (> 0); rows x = 0, dx, 2 dx, … ≤ length.
    #[arg(long, default_value_t = 1000.0, allow_negative_numbers = true)]
    pub length: f64,
    /// Override Table 1's A_r, m²·rad/m.
    #[arg(long, allow_negative_numbers = true)]
    pub ar: Option<f64>,
    /// Override Table 1's ω1, rad/m.
    #[arg(long, allow_negative_numbers = true)]
    pub omega1: Option<f64>,
    /// Override Table 1's ω2, rad/m.
    #[arg(long, allow_negative_numbers = true)]
    pub omega2: Option<f64>,
    /// Override Table 1's ω_l, rad/m.
    #[arg(long = "omega-l", allow_negative_numbers = true)]
    pub omega_l: Option<f64>,
    /// Override Table 1's ω_u, rad/m.
    #[arg(long = "omega-u", allow_negative_numbers = true)]
    pub omega_u: Option<f64>,
    /// Override Table 1's number of terms N (at most 2000).
    #[arg(long)]
    pub n: Option<usize>,
}

/// Parse `y`/`z` (any case).
pub fn parse_direction(s: &str) -> Result<Direction> {
    match s.trim().to_ascii_lowercase().as_str() {
        "y" => Ok(Direction::Y),
        "z" => Ok(Direction::Z),
        _ => Err(Error::invalid(
            "--direction",
            format!("unknown direction {s:?}: expected y or z"),
        )),
    }
}

/// Number of rows: x_j = j·dx for j = 0..count with x_j ≤ length (to a relative 1e-9 of dx,
/// so that `--length 1000 --dx 0.1` ends at x = 1000 despite 0.1 not being exact in binary).
pub fn sample_count(dx: f64, length: f64) -> Result<usize> {
    if !dx.is_finite() || dx <= 0.0 {
        return Err(Error::invalid(
            "--dx",
            format!("must be a positive finite number of metres, got {dx}"),
        ));
    }
    if !length.is_finite() || length <= 0.0 {
        return Err(Error::invalid(
            "--length",
            format!("must be a positive finite number of metres, got {length}"),
        ));
    }
    let last = (length / dx + 1e-9).floor();
    if last + 1.0 > MAX_SAMPLES as f64 {
        return Err(Error::invalid(
            "--length/--dx",
            format!(
                "gives {} samples, more than the limit {MAX_SAMPLES}",
                last + 1.0
            ),
        ));
    }
    Ok(last as usize + 1)
}

/// Decimal places of `dx`'s shortest representation (capped at 17): x is printed with these
/// so that `--dx 0.1` prints `0.3`, not `0.30000000000000004`. The profile is evaluated at
/// j·dx exactly; the printed x differs from it by less than 1e-15 relative.
pub(crate) fn decimals(dx: f64) -> usize {
    let s = format!("{dx}");
    s.split_once('.').map_or(0, |(_, f)| f.len()).min(17)
}

fn params_from(a: &Args, direction: Direction) -> PsdParams {
    let mut p = PsdParams::table1(direction);
    if let Some(v) = a.ar {
        p.a_r = v;
    }
    if let Some(v) = a.omega1 {
        p.omega1 = v;
    }
    if let Some(v) = a.omega2 {
        p.omega2 = v;
    }
    if let Some(v) = a.omega_l {
        p.omega_l = v;
    }
    if let Some(v) = a.omega_u {
        p.omega_u = v;
    }
    if let Some(v) = a.n {
        p.n = v;
    }
    p
}

/// Run the subcommand: CSV with header `x,r` to stdout.
pub fn run(a: Args) -> Result<()> {
    let direction = parse_direction(&a.direction)?;
    let count = sample_count(a.dx, a.length)?;
    let params = params_from(&a, direction);
    // The generator holds 2000 terms of 24 bytes; keep it off the stack.
    let mut g: Box<Irregularity<f64>> = Box::default();
    g.rebuild(&params, direction, a.seed, 0.0)
        .map_err(|e| Error::invalid("irregularity parameters", e.to_string()))?;
    let prec = decimals(a.dx);
    let mut w = crate::cli::stdout::writer();
    let io = crate::cli::stdout::error;
    writeln!(w, "x,r").map_err(io)?;
    sweep(&g, a.dx, count, |_, x, r| writeln!(w, "{x:.prec$},{r:e}")).map_err(io)?;
    w.flush().map_err(io)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_and_validation() {
        assert_eq!(sample_count(0.1, 1000.0).unwrap(), 10_001);
        assert_eq!(sample_count(0.3, 1.0).unwrap(), 4);
        assert_eq!(sample_count(2.0, 1.0).unwrap(), 1);
        for (dx, len) in [
            (0.0, 1.0),
            (-0.1, 1.0),
            (f64::NAN, 1.0),
            (0.1, -1.0),
            (0.1, 0.0),
            (0.1, f64::INFINITY),
            (1e-9, 1e3),
        ] {
            let e = sample_count(dx, len).unwrap_err().to_string();
            assert!(!e.contains('\n') && e.starts_with("--"), "{e}");
        }
        assert_eq!(parse_direction("Y").unwrap(), Direction::Y);
        assert_eq!(parse_direction("z").unwrap(), Direction::Z);
        assert!(parse_direction("x")
            .unwrap_err()
            .to_string()
            .starts_with("--direction: "));
        assert_eq!(decimals(0.1), 1);
        assert_eq!(decimals(0.25), 2);
        assert_eq!(decimals(1.0), 0);
    }
}
