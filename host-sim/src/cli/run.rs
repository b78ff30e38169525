//! `maglev run SCENARIO [--set key=value]... [--out DIR]`: one passage, FE or modal guideway.

use crate::fe::FeGuideway;
use crate::guideway::{Bridge, Guideway};
use crate::modal::ModalGuideway;
use crate::output::{write_run, Summary};
use crate::profile::Profile;
use crate::scenario::{self, Model, Scenario, VehicleSection};
use crate::simulation::{simulate, Load, Outcome, Profiles, Settings};
use crate::vehicle::VehicleModel;
use maglev_core::irregularity::Direction;
use std::path::PathBuf;
use std::time::Instant;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// A scenario TOML file, or a bundled name (paper-4.2, moving-force).
    pub scenario: String,
    /// Override a scenario value: speed, model, elements, modes, dt, t_end, nsub, alpha, scheme,
    /// law, seed, or section.key (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// Output directory.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
}

/// Runs a scenario; `progress` gets the fraction done. Returns the outcome and wall seconds.
pub fn execute(sc: &Scenario, progress: impl FnMut(f64)) -> Result<(Outcome, f64), String> {
    let bridge = sc.bridge();
    let dt = sc.run.dt_s;
    let load = match &sc.vehicle {
        VehicleSection::MovingForce {
            force_kN,
            offset_y_m,
            offset_z_m,
        } => Load::MovingForce {
            force: force_kN * 1e3,
            ey: *offset_y_m,
            ez: *offset_z_m,
        },
        VehicleSection::Fig1 { .. } => Load::Vehicle(VehicleModel::fig1(
            &sc.fig1()?,
            maglev_core::levitation::GRAVITY,
        )),
    };
    let profiles = profiles_for(sc, &load)?;
    let settings = Settings {
        speed: sc.run.speed_m_per_s,
        dt,
        t_end: sc.t_end(),
        controller: match &load {
            Load::Vehicle(_) => sc.controller_params()?,
            Load::MovingForce { .. } => maglev_core::Params::paper_wheel(dt),
        },
        law: sc.law()?,
        tolerance: sc.run.tolerance_m,
        max_iterations: sc.run.max_iterations,
        midspan_x: bridge.spans[0] / 2.0,
    };
    let start = Instant::now();
    let outcome = match sc.model()? {
        Model::Modal => {
            let mut g =
                ModalGuideway::from_bridge(&bridge, sc.run.modes, dt).map_err(|e| e.to_string())?;
            simulate(&mut g, &load, &profiles, &settings, progress)?
        }
        Model::Fe => {
            let mut g = fe_guideway(&bridge, sc.run.elements_per_span, dt)?;
            simulate(&mut g, &load, &profiles, &settings, progress)?
        }
    };
    Ok((outcome, start.elapsed().as_secs_f64()))
}

pub(crate) fn fe_guideway(
    bridge: &Bridge,
    elements: usize,
    dt: f64,
) -> Result<impl Guideway, String> {
    FeGuideway::new(bridge, elements, dt)
}

pub(crate) fn profiles_for(sc: &Scenario, load: &Load) -> Result<Profiles, String> {
    let enabled = sc.irregularity.as_ref().is_some_and(|i| i.enabled);
    if !enabled || matches!(load, Load::MovingForce { .. }) {
        return Ok(Profiles::smooth());
    }
    let seed = sc.irregularity.as_ref().map_or(0, |i| i.seed);
    let Load::Vehicle(v) = load else {
        unreachable!("moving force handled above")
    };
    let x0s = v.wheels.iter().map(|w| w.x0);
    let x_min = x0s.clone().fold(f64::INFINITY, f64::min) - 1.0;
    let x_max = x0s.fold(f64::NEG_INFINITY, f64::max) + sc.run.speed_m_per_s * sc.t_end() + 1.0;
    let y = Profile::table1(Direction::Y, seed, x_min, x_max)?;
    let z = Profile::table1(Direction::Z, seed, x_min, x_max)?;
    Ok(Profiles {
        y: Box::new(move |x| y.at(x)),
        z: Box::new(move |x| z.at(x)),
    })
}

pub fn run(args: Args) -> Result<(), String> {
    let sc = scenario::load(&args.scenario, &args.sets)?;
    let mut last = Instant::now();
    let (outcome, wall) = execute(&sc, |f| {
        if last.elapsed().as_secs_f64() > 2.0 {
            eprintln!("maglev: {:.0} % …", 100.0 * f);
            last = Instant::now();
        }
    })?;
    if outcome.unconverged_steps > 0 {
        eprintln!(
            "maglev: warning: {} step(s) hit max_iterations without converging",
            outcome.unconverged_steps
        );
    }
    let summary = Summary::new(
        &args.scenario,
        &sc.run.model,
        &outcome.records,
        wall,
        outcome.unconverged_steps,
    );
    write_run(&args.out, &outcome.records, &summary)?;
    eprintln!(
        "maglev: {} steps, {:.3} s simulated in {:.2} s wall; wrote {}",
        summary.steps,
        summary.simulated_seconds,
        wall,
        args.out.display()
    );
    Ok(())
}
