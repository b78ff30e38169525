//! `maglev accelerogram`: a synthetic three-component ground-acceleration record (Clough–
//! Penzien noise under an envelope, ending at rest, scaled to a PGA) as CSV
//! `t_s,ax_m_per_s2,ay_m_per_s2,az_m_per_s2` on stdout; `crate::physics::seismic::accelerogram` has the
//! model, docs/seismic.md the parameters. The same arguments give the same bits.

use std::io::Write;

use crate::input::support::SyntheticSection;
use crate::physics::seismic::accelerogram::{flag, synthesize, GroundFilter, Spec};
use crate::Result;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// The record's values: the keys of a scenario's `[support.synthetic]`, as flags.
    #[command(flatten)]
    pub record: SyntheticSection,
    /// Override the ground class's Kanai–Tajimi frequency ω_g, rad/s.
    #[arg(long = "omega-g", allow_negative_numbers = true)]
    pub omega_g: Option<f64>,
    /// Override its damping ratio ζ_g.
    #[arg(long = "zeta-g", allow_negative_numbers = true)]
    pub zeta_g: Option<f64>,
    /// Override the Clough–Penzien high-pass frequency ω_f, rad/s.
    #[arg(long = "omega-f", allow_negative_numbers = true)]
    pub omega_f: Option<f64>,
    /// Override its damping ratio ζ_f.
    #[arg(long = "zeta-f", allow_negative_numbers = true)]
    pub zeta_f: Option<f64>,
}

/// The arguments as the model's SI spec: the record's values, then the filter's overrides.
fn spec(a: &Args) -> Result<Spec> {
    let mut spec = a.record.spec(&flag)?;
    let base = spec.filter;
    spec.filter = GroundFilter::new(
        a.omega_g.unwrap_or(base.omega_g),
        a.zeta_g.unwrap_or(base.zeta_g),
        a.omega_f.unwrap_or(base.omega_f),
        a.zeta_f.unwrap_or(base.zeta_f),
    );
    Ok(spec)
}

/// Run the subcommand: the CSV to stdout.
pub fn run(a: Args) -> Result<()> {
    let r = synthesize(&spec(&a)?, &flag)?;
    // t printed with Δt's decimals, as `irregularity` prints x.
    let prec = crate::cli::irregularity::decimals(a.record.dt_s);
    let mut w = crate::cli::stdout::writer();
    let io = crate::cli::stdout::error;
    writeln!(w, "t_s,ax_m_per_s2,ay_m_per_s2,az_m_per_s2").map_err(io)?;
    for j in 0..r.x.len() {
        let t = j as f64 * r.dt_s;
        writeln!(w, "{t:.prec$},{:e},{:e},{:e}", r.x[j], r.y[j], r.z[j]).map_err(io)?;
    }
    w.flush().map_err(io)
}
