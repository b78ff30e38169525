//! From a case to a finished passage: the one place `run`, `hil`, `validate`, `sweep` and the
//! tests build the guideway, the load, the irregularity profiles and the run settings, and the
//! one [`simulate`] they all call.
//!
//! Why one place: `maglev run` and `maglev hil` must differ only in the magnets (that is what
//! `hil --compare` measures), so everything else is built here, once, from the [`Case`], and
//! the magnets come from the caller.

use crate::input::case::{Case, TrainCase};
use crate::input::scenario::Model;
use crate::physics::fe::{FeGuideway, Viaduct};
use crate::physics::guideway::{Guideway, PointLoad, PointMotion, RigidGuideway, SectionMotion};
use crate::physics::modal::{ModalGuideway, ModalSpans};
use crate::physics::profile::Profile;
use crate::probes::Recorder;
use crate::simulation::{Load, Magnets, Monitor, Outcome, Profiles, Settings};
use crate::{Error, Result};
use std::time::Instant;

/// The case's guideway model, built (enum dispatch keeps the coupling loop monomorphic).
// One value per run: the size difference between the variants costs nothing.
#[allow(clippy::large_enum_variant)]
pub enum AnyGuideway {
    Fe(FeGuideway),
    Modal(ModalGuideway),
    /// The modal reference over several simply supported spans, one series per span.
    ModalSpans(ModalSpans),
    /// The viaduct on bearings, piers and footings (`bridge.kind = "viaduct"`).
    Viaduct(Viaduct),
    Rigid(RigidGuideway),
}

impl AnyGuideway {
    /// Builds the case's guideway model with its discretisation.
    pub fn new(case: &Case) -> Result<Self> {
        let dt = case.dt;
        Ok(match (case.model, &case.viaduct) {
            (Model::Fe, Some(spec)) => AnyGuideway::Viaduct(match &case.support {
                Some(motion) => Viaduct::with_support_motion(spec, dt, motion.clone())?,
                None => Viaduct::new(spec, dt)?,
            }),
            (Model::Modal, Some(_)) => {
                return Err(Error::invalid(
                    "run.model",
                    "the modal reference has no viaduct on piers; use fe or rigid",
                ))
            }
            (Model::Fe, None) => AnyGuideway::Fe(match &case.support {
                Some(motion) => FeGuideway::with_support_motion(
                    &case.bridge,
                    case.elements_per_span,
                    dt,
                    case.damping,
                    motion.clone(),
                )?,
                None => FeGuideway::with_damping(
                    &case.bridge,
                    case.elements_per_span,
                    dt,
                    case.damping,
                )?,
            }),
            (Model::Modal, None) => match &case.support {
                Some(motion) => AnyGuideway::ModalSpans(ModalSpans::with_support_motion(
                    &case.bridge,
                    case.modes,
                    dt,
                    motion.clone(),
                )?),
                None if case.bridge.spans.len() == 1 => AnyGuideway::Modal(
                    ModalGuideway::from_bridge(&case.bridge, case.modes, dt)
                        .map_err(|e| Error::numerical(e.to_string()))?,
                ),
                None => AnyGuideway::ModalSpans(
                    ModalSpans::new(&case.bridge, case.modes, dt)
                        .map_err(|e| Error::numerical(e.to_string()))?,
                ),
            },
            (Model::Rigid, _) => AnyGuideway::Rigid(RigidGuideway::new(dt)),
        })
    }
}
macro_rules! each {
    ($self:ident, $g:ident => $e:expr) => {
        match $self {
            AnyGuideway::Fe($g) => $e,
            AnyGuideway::Modal($g) => $e,
            AnyGuideway::ModalSpans($g) => $e,
            AnyGuideway::Viaduct($g) => $e,
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
    fn pier_base(&self, k: usize) -> Option<crate::physics::guideway::BaseMotion> {
        each!(self, g => g.pier_base(k))
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
    /// Builds the passage of `case`.
    pub fn new(case: &Case) -> Result<Self> {
        let load = load_of(case)?;
        let profiles = profiles_for(case, &load)?;
        let midspans = case.midspans();
        let settings = Settings {
            speed: case.speed,
            dt: case.dt,
            t_end: case.t_end,
            // A train without magnets runs no controller: the paper's parameters stand in
            // (the coupling reads none of them for it).
            controller: case
                .controller
                .unwrap_or_else(|| maglev_core::levitation::Params::paper_wheel(case.dt)),
            law: case.law()?,
            guidance: case.guidance()?,
            geometry: case.geometry,
            tolerance: case.tolerance,
            max_iterations: case.max_iterations,
            midspan_x: midspans[0],
            midspans,
            skid: case.skid,
        };
        let guideway = AnyGuideway::new(case)?;
        Ok(Passage {
            guideway,
            load,
            profiles,
            settings,
        })
    }
}

/// The case's train, or its moving forces.
fn load_of(case: &Case) -> Result<Load> {
    Ok(match (&case.train, case.vehicle_train()?) {
        (_, Some(train)) => Load::Vehicle(train),
        (TrainCase::Forces(f), None) => Load::Forces(f.clone()),
        (_, None) => {
            return Err(Error::numerical(
                "internal: a train with cars built no train",
            ))
        }
    })
}

/// The rail irregularity profiles a passage of `case` runs over (as [`Passage::new`] builds
/// them), for the studies that need the rail without a run; the case's law need not be
/// resolved.
pub fn irregularity(case: &Case) -> Result<Profiles> {
    profiles_for(case, &load_of(case)?)
}

/// The Table 1 profiles of the case's irregularity over every position a wheel passes
/// (smooth for forces or with the irregularity off).
fn profiles_for(case: &Case, load: &Load) -> Result<Profiles> {
    let (Load::Vehicle(v), Some(seed)) = (load, case.irregularity_seed) else {
        return Ok(Profiles::smooth());
    };
    if v.nodes.is_empty() {
        // Only 3-D high-speed cars: their rails carry their own irregularity.
        return Ok(Profiles::smooth());
    }
    let x0s: Vec<f64> = v.node_x0();
    let x0s = x0s.iter().copied();
    let x_min = x0s.clone().fold(f64::INFINITY, f64::min) - 1.0;
    let x_max = x0s.fold(f64::NEG_INFINITY, f64::max) + case.speed * case.t_end + 1.0;
    let (y, z) = Profile::table1_y_z(seed, x_min, x_max)?;
    Ok(Profiles {
        y: Box::new(move |x| y.at(x)),
        z: Box::new(move |x| z.at(x)),
    })
}

/// A finished passage.
pub struct FinishedPassage {
    pub outcome: Outcome,
    /// Wall seconds of the time loop.
    pub wall: f64,
}

/// Runs `case` with `magnets` (the core's, [`crate::simulation::magnets::CoreMagnets`], or any
/// other [`Magnets`]: they are started on the case's train), streaming every step to `rec`;
/// `monitor` hears the fraction done now and then and may stop the run after any step.
pub fn simulate(
    case: &Case,
    magnets: &mut dyn Magnets,
    rec: &mut dyn Recorder,
    monitor: &mut dyn Monitor,
) -> Result<FinishedPassage> {
    let mut p = Passage::new(case)?;
    case.probes.check_guideway(&p.guideway)?;
    let start = Instant::now();
    let outcome = crate::simulation::simulate(
        &mut p.guideway,
        &p.load,
        &p.profiles,
        &p.settings,
        magnets,
        rec,
        monitor,
    )?;
    Ok(FinishedPassage {
        outcome,
        wall: start.elapsed().as_secs_f64(),
    })
}
