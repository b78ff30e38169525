//! `maglev stability`: the linearised analysis of the levitation law (issue 5) for one set of
//! controller parameters — continuous g-loop poles (Eq. 9 + 10), the spectral radius and
//! critical step of Eq. 14 as discretised (or of the accurate scheme, `--scheme accurate`), and
//! the poles of one magnet carrying its body.
//! The numbers come from `crate::studies::stability`; this file only parses and prints.

use super::control::ControllerArgs;
use crate::cli::stdout::print;
use crate::studies::stability::discrete::{self, Step};
use crate::studies::stability::gap_loop::GapLoopPlant;
use crate::studies::stability::gauss;
use crate::studies::stability::inner_loop::Loop;
use crate::studies::stability::marginal::{self, Kind};
use crate::studies::stability::plant::{rigid_growth_rate, Plant, Suspension};
use crate::studies::stability::report::{scenario_report, ScenarioReport};
use crate::studies::stability::targets::MAX_HEADROOM_RATIO;
use crate::studies::stability::Complex;
use maglev_core::gap::Geometry;
use maglev_core::gap_control::GapParams;
use serde::Serialize;

/// Output format.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Json,
    Table,
}

/// A study to print instead of the analysis.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Study {
    /// Convergence of the internal loop per n_sub, interpolation and type (docs/numerics.md).
    Numerics,
}

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Analyse a scenario's own vehicle with all its magnets on a rigid rail (a bundled name
    /// or a TOML file); the controller flags are then ignored (docs/gap-loop.md).
    #[arg(long)]
    pub scenario: Option<String>,
    /// Override a scenario value (as for `maglev run`), with `--scenario`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// Vertical bending modes per span in the coupled analysis (`girder_modes`, with
    /// `--scenario` on a flexible guideway at standstill).
    #[arg(long = "girder-modes", default_value_t = crate::studies::stability::coupled::GIRDER_MODES)]
    pub girder_modes: usize,
    /// With `--scenario`: find the value of this scenario key (e.g. `bridge.mass_t_per_m`)
    /// in `--range` where the coupled model's verdict turns unstable (a real part within the
    /// eigen-solver's error of zero is marginal, no crossing).
    #[arg(long, requires = "range", requires = "scenario")]
    pub critical: Option<String>,
    /// With `--scenario`: the speed envelope instead, one time run per speed, `A:B:N` (m/s,
    /// N speeds from A to B) or one speed; JSON on stdout (docs/levitation.md "Speed").
    #[arg(long, requires = "scenario", conflicts_with = "critical")]
    pub speeds: Option<String>,
    /// With `--speeds`: write the envelope's figure (SVG) to this file.
    #[arg(long, requires = "speeds")]
    pub plot: Option<std::path::PathBuf>,
    /// The search range of `--critical`: LO HI.
    #[arg(long, num_args = 2, value_names = ["LO", "HI"], allow_negative_numbers = true)]
    pub range: Option<Vec<f64>>,
    /// Print a study (Markdown) instead; the other flags are then ignored.
    #[arg(long, value_enum)]
    pub study: Option<Study>,
    /// Sub-steps of the converged f64 reference of the numerics study.
    #[arg(long = "ref-nsub", default_value_t = 100_000)]
    pub ref_nsub: u32,
    /// Outer time step Δt (s).
    #[arg(long, default_value_t = 1e-3)]
    pub dt: f64,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Json)]
    pub format: Format,
    /// Magnet mass m_m (kg) of the magnet + body plant; the body gets p0/9.81 − m_m.
    #[arg(long = "magnet-mass", default_value_t = 0.0)]
    pub magnet_mass: f64,
    /// Suspension stiffness k (N/m), Fig. 1.
    #[arg(long = "k-susp", default_value_t = 200e3)]
    pub k_susp: f64,
    /// Suspension damping c (N·s/m), Fig. 1.
    #[arg(long = "c-susp", default_value_t = 10e3)]
    pub c_susp: f64,
    #[command(flatten)]
    pub controller: ControllerArgs,
}

/// The report printed as JSON (SI units: seconds, 1/s).
#[derive(Debug, Serialize)]
pub struct Report {
    /// `paper` or `accurate`: which discretisation the discrete figures describe.
    pub scheme: &'static str,
    /// Gauss intervals per outer step (accurate scheme only).
    pub intervals: Option<u32>,
    pub alpha: f64,
    pub dt_s: f64,
    pub n_sub: u32,
    /// Coil time constant τ = 2·K0·g0/(R0·i0) (s).
    pub tau_s: f64,
    /// Per-unit proportional gain `kpv = KP·g0/(R0·i0)`.
    pub kpv: f64,
    /// Per-unit integral gain `ki = KI·g0/(R0·i0)` (1/s).
    pub ki_per_s: f64,
    /// Roots of τ s² + (1 + kpv) s + ki = 0 (1/s).
    pub continuous_poles: Vec<Complex>,
    /// Eigenvalues of one sub-step's (paper) or one interval's (accurate) amplification matrix.
    pub substep_eigenvalues: Vec<Complex>,
    /// Spectral radius of one outer step (n_sub sub-steps).
    pub discrete_spectral_radius: f64,
    /// Largest stable outer step at this α and n_sub (s); null where every step is stable.
    pub critical_dt_s: Option<f64>,
    /// Closed-loop poles of one magnet carrying its body (1/s).
    pub plant_poles: Vec<Complex>,
    /// Names of the plant's states.
    pub plant_states: Vec<&'static str>,
    pub plant_body_mass_kg: f64,
    pub plant_magnet_mass_kg: f64,
    /// Growth rate of the gap mode if magnet and body were rigidly joined (1/s).
    pub rigid_gap_growth_per_s: f64,
    /// Closed-loop poles of the same plant with the outer gap loop at its designed gains
    /// (`maglev_core::gap_control`, docs/gap-loop.md) (1/s).
    pub gap_loop_poles: Vec<Complex>,
}

/// Computes the report (no printing).
pub fn report(args: &Args) -> crate::Result<Report> {
    if !(args.dt > 0.0 && args.dt.is_finite()) {
        return Err(crate::Error::invalid(
            "--dt",
            format!("must be a positive number of seconds, got {}", args.dt),
        ));
    }
    let p = args.controller.params(args.dt)?;
    let lp = Loop::new(&p, 0.0);
    let step = Step::new(&p, 0.0);
    let max_dt = discrete::max_substep(&lp) * p.n_sub as f64;
    if !(step.delta <= discrete::max_substep(&lp) && step.radius().is_finite()) {
        return Err(crate::Error::invalid(
            "--dt",
            format!(
                "must be at most {max_dt:e} s for this loop (n_sub = {}): beyond, one sub-step's amplification matrix overflows; got {:e}",
                p.n_sub, args.dt
            ),
        ));
    }
    let accurate = p.scheme == maglev_core::Scheme::Accurate;
    let (substep_eigenvalues, radius, critical) = if accurate {
        let (r, _) = gauss::interval_matrix(&p, 0.0);
        let ev = crate::studies::stability::sorted_poles(r.complex_eigenvalues().iter().copied());
        (ev, gauss::spectral_radius(&p, 0.0), None)
    } else {
        (
            step.eigenvalues().to_vec(),
            discrete::spectral_radius(&p, 0.0),
            discrete::critical_dt(&p, 0.0),
        )
    };
    let susp = Suspension {
        magnet_mass: args.magnet_mass,
        k: args.k_susp,
        c: args.c_susp,
    };
    // The quarter vehicle of issue 5 under the EMS reading (unchanged output; the scenario's
    // own vehicle and geometry are `--scenario`).
    let plant = Plant::new(&p, &susp, Geometry::Ems)?;
    Ok(Report {
        scheme: if accurate { "accurate" } else { "paper" },
        intervals: accurate.then(|| maglev_core::levitation::accurate::intervals(&p)),
        alpha: p.alpha,
        dt_s: p.dt,
        n_sub: p.n_sub,
        tau_s: lp.tau,
        kpv: lp.p - 1.0,
        ki_per_s: lp.ki,
        continuous_poles: lp.poles().to_vec(),
        substep_eigenvalues,
        discrete_spectral_radius: radius,
        critical_dt_s: critical,
        plant_poles: plant.poles(),
        plant_states: plant.states.to_vec(),
        plant_body_mass_kg: plant.body_mass,
        plant_magnet_mass_kg: args.magnet_mass,
        rigid_gap_growth_per_s: rigid_growth_rate(&p),
        gap_loop_poles: GapLoopPlant::new(&p, &susp, &GapParams::designed(), Geometry::Ems)?
            .poles(),
    })
}

fn fmt_c(z: &Complex) -> String {
    if z.im == 0.0 {
        format!("{:.6}", z.re)
    } else {
        format!(
            "{:.6} {} {:.6}j",
            z.re,
            if z.im < 0.0 { '-' } else { '+' },
            z.im.abs()
        )
    }
}

/// The human-readable table.
pub fn table(r: &Report) -> String {
    let list = |v: &[Complex]| v.iter().map(fmt_c).collect::<Vec<_>>().join(", ");
    let crit = r
        .critical_dt_s
        .map_or("none (unconditionally stable)".to_string(), |d| {
            format!("{d:.6} s")
        });
    let scheme = match r.intervals {
        Some(m) => format!("accurate (Gauss–Legendre, {m} interval(s) per step)"),
        None => "paper (Eq. 14)".to_string(),
    };
    format!(
        "scheme                     {}\n\
         alpha                      {}\n\
         dt, n_sub or intervals     {} s, {}\n\
         tau, kpv, ki               {:.6} s, {:.6}, {:.6} 1/s\n\
         continuous poles (1/s)     {}\n\
         sub-step eigenvalues       {}\n\
         spectral radius (outer)    {:.9}\n\
         critical dt                {}\n\
         plant states               {}\n\
         plant poles (1/s)          {}\n\
         body / magnet mass (kg)    {:.3} / {:.3}\n\
         rigid gap growth (1/s)     {:.6}\n\
         gap-loop poles (1/s)       {}\n",
        scheme,
        r.alpha,
        r.dt_s,
        r.intervals.unwrap_or(r.n_sub),
        r.tau_s,
        r.kpv,
        r.ki_per_s,
        list(&r.continuous_poles),
        list(&r.substep_eigenvalues),
        r.discrete_spectral_radius,
        crit,
        r.plant_states.join(", "),
        list(&r.plant_poles),
        r.plant_body_mass_kg,
        r.plant_magnet_mass_kg,
        r.rigid_gap_growth_per_s,
        list(&r.gap_loop_poles),
    )
}

pub fn run(args: Args) -> crate::Result<()> {
    if let Some(Study::Numerics) = args.study {
        return print(&crate::studies::stability::numerics::study(
            args.ref_nsub.max(1),
        )?);
    }
    if let (Some(name), Some(speeds)) = (&args.scenario, &args.speeds) {
        return super::envelope::run(name, &args.sets, speeds, args.plot.as_deref());
    }
    if let (Some(name), Some(key), Some(range)) = (&args.scenario, &args.critical, &args.range) {
        let base = crate::studies::design::load(name, &args.sets)?;
        let r = crate::studies::stability::coupled::critical(
            name,
            &args.sets,
            &base,
            key,
            [range[0], range[1]],
            args.girder_modes,
            &crate::studies::design::resolve,
        )?;
        return print(
            &(serde_json::to_string_pretty(&r)
                .map_err(|e| crate::Error::numerical(e.to_string()))?
                + "\n"),
        );
    }
    if let Some(name) = &args.scenario {
        let case = crate::studies::design::load(name, &args.sets)?;
        let r = scenario_report(name, &case, args.girder_modes)?;
        let text = match args.format {
            Format::Json => {
                serde_json::to_string_pretty(&r)
                    .map_err(|e| crate::Error::numerical(e.to_string()))?
                    + "\n"
            }
            Format::Table => scenario_table(&r),
        };
        return print(&text);
    }
    let r = report(&args)?;
    let text = match args.format {
        Format::Json => {
            serde_json::to_string_pretty(&r).map_err(|e| crate::Error::numerical(e.to_string()))?
                + "\n"
        }
        Format::Table => table(&r),
    };
    print(&text)
}

/// The human-readable scenario table.
pub fn scenario_table(r: &ScenarioReport) -> String {
    let list = |v: &[Complex]| v.iter().map(fmt_c).collect::<Vec<_>>().join(", ");
    let mut out = format!(
        "scenario                   {} (geometry {}, law {}, magnet node mass {} kg)\n\
         states                     {}\n\
         verdict                    {} (max real part {:.6} 1/s)\n\
         zero poles                 {}\n\
         critical magnet mass       {}\n\
         vehicle poles (1/s)        {}\n",
        r.scenario,
        r.geometry,
        r.law,
        r.magnet_mass_kg,
        r.states,
        r.verdict.as_str(),
        r.max_real_part,
        r.zero_poles,
        r.critical_magnet_mass_kg
            .map_or("none up to 10 t".to_string(), |m| format!("{m:.3} kg")),
        list(&r.vehicle_poles),
    );
    if let Some(g) = &r.gains {
        out += &format!(
            "state gains (scenario)     controller.state={{kp_V_per_m={:e}, kd_V_s_per_m={:e}, \
             ka_V_s2_per_m={:e}, ki_V_per_m_s={:e}, kc_V_per_A={:e}, vmax_V={:e}, rate_Hz={:e}, \
             observer_Hz={:e}}}\n",
            g.kp, g.kd, g.ka, g.ki, g.kc, g.v_max, g.rate_hz, g.observer_hz
        );
    }
    out += &format!(
        "min damping ratio          {:.6}\n{:<27}{}\n",
        r.min_damping_ratio, "margins delay", r.delay_note
    );
    let db = |x: Option<f64>| x.map_or("none".to_string(), |v| format!("{v:.3}"));
    for m in &r.margins {
        out += &format!(
            "margins {:<19}gain −{} / +{} dB, phase {} deg, Ms {}{}\n",
            m.magnet,
            db(m.gain_low_db),
            db(m.gain_high_db),
            db(m.phase_deg),
            db(m.sensitivity_peak),
            if m.stable_with_delay {
                ""
            } else {
                " (unstable with the delay)"
            }
        );
    }
    if r.verdict == Kind::Marginal {
        out += &format!(
            "marginal poles             {}\n",
            marginal::describe(&r.honest)
        );
    }
    let d = &r.disk_margin;
    out += &match d.alpha {
        Some(a) => format!(
            "disk margin (all loops)    α {:.4}: ±{} dB with ±{} deg (at {} rad/s, {} loops)\n",
            a,
            db(d.gain_db),
            db(d.phase_deg),
            db(d.peak_rad_per_s),
            d.loops.len()
        ),
        None => "disk margin (all loops)    none (unstable with the delay)\n".to_string(),
    };
    let h = &r.headroom;
    for p in &h.disturbances {
        out += &format!(
            "headroom {:<18}peak |V| {:.1} V at {}{} ({:.3} s){}\n",
            p.disturbance,
            p.peak_V,
            p.magnet,
            p.car.map_or(String::new(), |c| format!(" of car {c}")),
            p.t_s,
            p.ratio
                .map_or(String::new(), |x| format!(", |V|/V_max {x:.3}"))
        );
    }
    if let Some(g) = h.guideway_ratio.filter(|&g| g > MAX_HEADROOM_RATIO) {
        out += &format!(
            "warning: on this guideway the supply is asked for {g:.3} of V_max (guideway \
             headroom above {MAX_HEADROOM_RATIO}): a run is likely to saturate; the design's \
             targets are on a rigid guideway (docs/levitation.md, \"Supply headroom\")\n"
        );
    }
    if let Some(g) = &r.gap_loop {
        out += &format!(
            "gap-loop gains             kp {:e}, kd {:e} s, tf {:e} s (sampled abscissa {:.6} 1/s at a {} s delay)\n\
             levitation loop (1/s)      {}\n\
             guidance loop (1/s)        {}\n",
            g.kp,
            g.kd_s,
            g.tf_s,
            g.sampled_max_real_part,
            g.design_delay_s,
            list(&g.levitation_loop_poles),
            list(&g.guidance_loop_poles)
        );
    }
    for m in r.girder_modes.iter().flatten() {
        out += &format!(
            "girder span {} mode {:<8}{:.4} Hz (closed form {:.4}), modal mass {:.1} kg, ζ {:.4}, at magnets {:?}\n",
            m.span,
            match m.kind {
                "bending-z" => m.n.to_string(),
                kind => format!("{} {kind}", m.n),
            },
            m.frequency_hz,
            m.closed_form_hz,
            m.modal_mass_kg,
            m.damping_ratio,
            m.at_magnets
        );
    }
    if let Some(c) = &r.coupled {
        out += &format!(
            "coupled max real part      {:.6} 1/s (min damping ratio {:.6}, {})\n",
            c.max_real_part,
            c.min_damping_ratio,
            c.verdict.as_str()
        );
        if c.verdict == Kind::Marginal {
            out += &format!(
                "coupled marginal poles     {}\n",
                marginal::describe(&c.honest)
            );
        }
    }
    out
}
