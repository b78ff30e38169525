//! `maglev ground green --vs V --nu NU --rho-t-per-m3 RHO --xi XI --f F --r R [--format json|text]`:
//! the half-space Green's function at one frequency and distance (`crate::ground::green`,
//! docs/ground.md): vertical surface displacement per newton of a vertical point load,
//! load down, displacement positive down, time factor e^{+iωt}.

use crate::ground::green::{displacement_per_newton, Green};
use crate::input::case::MAX_MAGNITUDE;
use crate::physics::fe::soil::Soil;
use crate::Error;

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(subcommand)]
    pub what: What,
}

#[derive(clap::Subcommand, Debug)]
pub enum What {
    /// Vertical surface displacement per newton (m/N) of a vertical point load.
    Green(GreenArgs),
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Json,
    Text,
}

#[derive(clap::Args, Debug)]
pub struct GreenArgs {
    /// Shear-wave speed (m/s).
    #[arg(long, allow_negative_numbers = true)]
    pub vs: f64,
    /// Poisson's ratio, in [0, 0.49].
    #[arg(long, allow_negative_numbers = true)]
    pub nu: f64,
    /// Density in t/m³, as `[soil] density_t_per_m3` (0.5 to 5).
    #[arg(long = "rho-t-per-m3", allow_negative_numbers = true)]
    pub rho_t_per_m3: f64,
    /// Hysteretic damping ratio ξ (μ* = μ(1 + 2iξ)), in [0.001, 0.25].
    #[arg(long, allow_negative_numbers = true)]
    pub xi: f64,
    /// Frequency (Hz, ≥ 0).
    #[arg(long, allow_negative_numbers = true)]
    pub f: f64,
    /// Distance from the load (m, > 0).
    #[arg(long, allow_negative_numbers = true)]
    pub r: f64,
    #[arg(long, value_enum, default_value_t = Format::Json)]
    pub format: Format,
}

fn checked(key: &str, v: f64, zero_ok: bool) -> crate::Result<f64> {
    let ok = v.is_finite() && (v > 0.0 || (zero_ok && v == 0.0)) && v <= MAX_MAGNITUDE;
    if ok {
        Ok(v)
    } else {
        let lower = if zero_ok { ">= 0" } else { "> 0" };
        Err(Error::invalid(
            key,
            format!("must be finite, {lower} and at most {MAX_MAGNITUDE:e}, got {v}"),
        ))
    }
}

/// The displacement per newton for the arguments (checked).
pub fn green(a: &GreenArgs) -> crate::Result<[f64; 2]> {
    let soil = Soil {
        shear_wave_velocity: checked("--vs", a.vs, false)?,
        poisson: a.nu,
        density: crate::input::case::soil_density("--rho-t-per-m3", a.rho_t_per_m3)?,
        damping: a.xi,
    };
    let f = checked("--f", a.f, true)?;
    let r = checked("--r", a.r, false)?;
    let g = Green::new(a.nu, a.xi).map_err(|e| match e {
        Error::Invalid { key, reason } => {
            Error::invalid(if key == "poisson" { "--nu" } else { "--xi" }, reason)
        }
        e => e,
    })?;
    let w = displacement_per_newton(&soil, &g, f, r);
    if !(w.re.is_finite() && w.im.is_finite()) {
        return Err(Error::numerical(format!(
            "the Green's function is not finite at f = {f} Hz, r = {r} m"
        )));
    }
    Ok([w.re, w.im])
}

pub fn run(args: Args) -> anyhow::Result<()> {
    match args.what {
        What::Green(a) => {
            let w = green(&a)?;
            let text = match a.format {
                Format::Json => serde_json::json!({ "w_per_N": w }).to_string(),
                Format::Text => format!("{:e} {:e}", w[0], w[1]),
            };
            crate::cli::stdout::print(&(text + "\n"))?;
            Ok(())
        }
    }
}
