//! `maglev accelerogram`: a synthetic three-component ground-acceleration record (Clough–
//! Penzien noise under an envelope, ending at rest, scaled to a PGA) as CSV
//! `t_s,ax_m_per_s2,ay_m_per_s2,az_m_per_s2` on stdout; `crate::physics::seismic::accelerogram` has the
//! model, docs/seismic.md the parameters. The same arguments give the same bits.

use std::io::Write;

use crate::physics::seismic::accelerogram::{flag, synthesize, Envelope, GroundFilter, Spec, G};
use crate::{Error, Result};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Peak ground acceleration of each horizontal component, in g.
    #[arg(long = "pga-g", allow_negative_numbers = true)]
    pub pga_g: f64,
    /// Ground class for the filter: firm, medium or soft (Der Kiureghian & Neuenhofer 1992).
    #[arg(long, default_value = "medium")]
    pub ground: String,
    /// Vertical peak over horizontal peak.
    #[arg(long = "vertical-ratio", default_value_t = 2.0 / 3.0, allow_negative_numbers = true)]
    pub vertical_ratio: f64,
    /// Record length, s.
    #[arg(
        long = "duration-s",
        default_value_t = 20.0,
        allow_negative_numbers = true
    )]
    pub duration_s: f64,
    /// Sample step, s.
    #[arg(long = "dt-s", default_value_t = 0.005, allow_negative_numbers = true)]
    pub dt_s: f64,
    /// Seed of the phases (u64); x, y and z are independent streams of it.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Envelope: end of the quadratic rise, s.
    #[arg(long = "rise-s", default_value_t = 2.0, allow_negative_numbers = true)]
    pub rise_s: f64,
    /// Envelope: end of the strong motion, s.
    #[arg(
        long = "strong-end-s",
        default_value_t = 10.0,
        allow_negative_numbers = true
    )]
    pub strong_end_s: f64,
    /// Envelope: exponential decay rate after the strong motion, 1/s.
    #[arg(
        long = "decay-per-s",
        default_value_t = 0.4,
        allow_negative_numbers = true
    )]
    pub decay_per_s: f64,
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

/// The ground class by name (any case).
fn ground(name: &str) -> Result<GroundFilter> {
    GroundFilter::class(name).ok_or_else(|| {
        Error::invalid(
            "--ground",
            format!("unknown ground class {name:?}: expected firm, medium or soft"),
        )
    })
}

/// The arguments as the model's SI spec (g → m/s² here, at the edge).
fn spec(a: &Args) -> Result<Spec> {
    let base = ground(&a.ground)?;
    Ok(Spec {
        filter: GroundFilter::new(
            a.omega_g.unwrap_or(base.omega_g),
            a.zeta_g.unwrap_or(base.zeta_g),
            a.omega_f.unwrap_or(base.omega_f),
            a.zeta_f.unwrap_or(base.zeta_f),
        ),
        envelope: Envelope {
            rise_s: a.rise_s,
            strong_end_s: a.strong_end_s,
            decay_per_s: a.decay_per_s,
        },
        duration_s: a.duration_s,
        dt_s: a.dt_s,
        pga: a.pga_g * G,
        vertical_ratio: a.vertical_ratio,
        seed: a.seed,
    })
}

/// Run the subcommand: the CSV to stdout.
pub fn run(a: Args) -> Result<()> {
    let r = synthesize(&spec(&a)?, &flag)?;
    // t printed with Δt's decimals, as `irregularity` prints x.
    let prec = crate::cli::irregularity::decimals(a.dt_s);
    let mut w = crate::cli::stdout::writer();
    let io = crate::cli::stdout::error;
    writeln!(w, "t_s,ax_m_per_s2,ay_m_per_s2,az_m_per_s2").map_err(io)?;
    for j in 0..r.x.len() {
        let t = j as f64 * r.dt_s;
        writeln!(w, "{t:.prec$},{:e},{:e},{:e}", r.x[j], r.y[j], r.z[j]).map_err(io)?;
    }
    w.flush().map_err(io)
}
