//! From a scenario to a ready-to-run passage: the one place `run`, `hil`, `validate` and the
//! tests build the guideway, the load, the irregularity profiles and the run settings.
//!
//! Why one place: `maglev run` and `maglev hil` must differ only in the magnets (that is what
//! `hil --compare` measures), so everything else is built here, once, from the scenario.

use crate::fe::FeGuideway;
use crate::guideway::{Bridge, Guideway, PointLoad, PointMotion, SectionMotion};
use crate::modal::ModalGuideway;
use crate::probes::{Extent, Probes, Recorder};
use crate::profile::Profile;
use crate::scenario::{Model, Scenario, VehicleSection};
use crate::simulation::{Load, MovingLoad, Profiles, Settings};
use crate::vehicle::Train;
use maglev_core::irregularity::Direction;

/// A guideway that never moves: `z_g = y_g = θ = 0` everywhere (`run.model = "rigid"`). The
/// vehicle and its magnets alone over the irregular rail, the first thing a control engineer
/// runs; the irregularity is still applied.
#[derive(Clone, Debug)]
pub struct RigidGuideway {
    dt: f64,
}

impl RigidGuideway {
    pub fn new(dt: f64) -> Self {
        RigidGuideway { dt }
    }
}

impl Guideway for RigidGuideway {
    fn time_step(&self) -> f64 {
        self.dt
    }
    fn solve_step(&mut self, _loads: &[PointLoad]) {}
    fn motion_at(&self, _x: f64, _ey: f64, _ez: f64) -> PointMotion {
        PointMotion::default()
    }
    fn section_at(&self, _x: f64) -> SectionMotion {
        SectionMotion::default()
    }
    fn commit(&mut self) {}
}

/// The scenario's guideway model, built (enum dispatch keeps the coupling loop monomorphic).
// One value per run: the size difference between the variants costs nothing.
#[allow(clippy::large_enum_variant)]
pub enum AnyGuideway {
    Fe(FeGuideway),
    Modal(ModalGuideway),
    Rigid(RigidGuideway),
}

impl AnyGuideway {
    /// Builds the guideway `model` of `bridge` with the scenario's discretisation.
    pub fn new(model: Model, bridge: &Bridge, sc: &Scenario) -> Result<Self, String> {
        let dt = sc.run.dt_s;
        Ok(match model {
            Model::Fe => AnyGuideway::Fe(
                FeGuideway::new(bridge, sc.run.elements_per_span, dt).map_err(|e| e.to_string())?,
            ),
            Model::Modal => AnyGuideway::Modal(
                ModalGuideway::from_bridge(bridge, sc.run.modes, dt).map_err(|e| e.to_string())?,
            ),
            Model::Rigid => AnyGuideway::Rigid(RigidGuideway::new(dt)),
        })
    }
}

macro_rules! each {
    ($self:ident, $g:ident => $e:expr) => {
        match $self {
            AnyGuideway::Fe($g) => $e,
            AnyGuideway::Modal($g) => $e,
            AnyGuideway::Rigid($g) => $e,
        }
    };
}

impl Guideway for AnyGuideway {
    fn time_step(&self) -> f64 {
        each!(self, g => g.time_step())
    }
    fn solve_step(&mut self, loads: &[PointLoad]) {
        each!(self, g => g.solve_step(loads))
    }
    fn motion_at(&self, x: f64, ey: f64, ez: f64) -> PointMotion {
        each!(self, g => g.motion_at(x, ey, ez))
    }
    fn section_at(&self, x: f64) -> SectionMotion {
        each!(self, g => g.section_at(x))
    }
    fn commit(&mut self) {
        each!(self, g => g.commit())
    }
}

/// Everything a passage needs, in SI.
pub struct Passage {
    pub guideway: AnyGuideway,
    pub load: Load,
    pub profiles: Profiles,
    pub settings: Settings,
}

impl Passage {
    /// Builds the passage of scenario `sc`.
    pub fn new(sc: &Scenario) -> Result<Self, String> {
        let bridge = sc.bridge();
        let dt = sc.run.dt_s;
        let load = match &sc.vehicle {
            VehicleSection::MovingForce {
                force_kN,
                offset_y_m,
                offset_z_m,
            } => Load::Forces(vec![MovingLoad {
                x0: 0.0,
                force: force_kN * 1e3,
                ey: *offset_y_m,
                ez: *offset_z_m,
            }]),
            VehicleSection::Forces { .. } => Load::Forces(sc.forces()?),
            VehicleSection::Fig1 { .. } => Load::Vehicle(fig1_train(sc)?),
        };
        let profiles = profiles_for(sc, &load)?;
        let settings = Settings {
            speed: sc.run.speed_m_per_s,
            dt,
            t_end: sc.t_end(),
            controller: match &load {
                Load::Vehicle(_) => sc.controller_params()?,
                Load::Forces(_) => maglev_core::Params::paper_wheel(dt),
            },
            law: sc.law()?,
            geometry: sc.geometry(),
            tolerance: sc.run.tolerance_m,
            max_iterations: sc.run.max_iterations,
            midspan_x: bridge.spans[0] / 2.0,
            midspans: bridge
                .spans
                .iter()
                .scan(0.0, |x0, &l| {
                    let mid = *x0 + l / 2.0;
                    *x0 += l;
                    Some(mid)
                })
                .collect(),
        };
        let guideway = AnyGuideway::new(sc.model()?, &bridge, sc)?;
        Ok(Passage {
            guideway,
            load,
            profiles,
            settings,
        })
    }
}

/// The scenario's train of `repeat` Fig. 1 cars `car_length_m` apart.
fn fig1_train(sc: &Scenario) -> Result<Train, String> {
    let (cars, length) = sc.fig1_cars()?;
    Train::fig1_repeated(&sc.fig1()?, cars, length, maglev_core::levitation::GRAVITY)
        .map_err(|e| e.to_string())
}

/// The Table 1 profiles of the scenario's irregularity section over every position a wheel
/// passes (smooth for a moving force or with the irregularity disabled).
fn profiles_for(sc: &Scenario, load: &Load) -> Result<Profiles, String> {
    let enabled = sc.irregularity.as_ref().is_some_and(|i| i.enabled);
    let Load::Vehicle(v) = load else {
        return Ok(Profiles::smooth());
    };
    if !enabled {
        return Ok(Profiles::smooth());
    }
    let seed = sc.irregularity.as_ref().map_or(0, |i| i.seed);
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

/// Runs scenario `sc` with the core's controllers; `progress` gets the fraction done. Returns
/// the outcome and the wall seconds of the time loop.
pub fn run_scenario(
    sc: &Scenario,
    rec: &mut dyn Recorder,
    progress: impl FnMut(f64),
) -> Result<(crate::simulation::Outcome, f64), String> {
    let mut p = Passage::new(sc)?;
    let start = std::time::Instant::now();
    let outcome = crate::simulation::simulate(
        &mut p.guideway,
        &p.load,
        &p.profiles,
        &p.settings,
        rec,
        progress,
    )
    .map_err(|e| e.to_string())?;
    Ok((outcome, start.elapsed().as_secs_f64()))
}

/// The scenario's probes (`[output] probes`, else the default columns), checked against it.
pub fn probes(sc: &Scenario) -> Result<Probes, String> {
    let spans = sc.bridge.spans_m.len();
    let extent = match &sc.vehicle {
        VehicleSection::Fig1 { .. } => {
            let v = fig1_train(sc)?;
            Extent {
                spans,
                wheels: v.wheels.len(),
                cars: v.cars.len(),
                magnets: true,
            }
        }
        VehicleSection::Forces { .. } => Extent {
            spans,
            wheels: sc.forces()?.len(),
            cars: 0,
            magnets: false,
        },
        VehicleSection::MovingForce { .. } => Extent {
            spans,
            wheels: 1,
            cars: 0,
            magnets: false,
        },
    };
    Probes::new(sc.output.as_ref().map(|o| o.probes.as_slice()), &extent)
}
