//! The step between the case and the simulation: gains designed from the case's own plant.
//!
//! Why a step of its own: a design is a study (it linearises the vehicle and searches,
//! `crate::studies::stability`), and the input layer (`crate::input::case`) must not run one. A [`Case`]
//! holds what to design as data ([`LawChoice`]); [`resolve`] turns it into the law a run
//! uses. Every command that runs or analyses a case calls it after loading (`maglev run`,
//! `hil`, `sweep`, `validate`, `report`, `stability --scenario`); a case left unresolved is
//! refused by `Case::law`.

use crate::input::case::{Case, Changes, LawChoice, TrainCase};
use crate::physics::vehicle::{Train, VehicleModel};
use crate::{Error, Result};
use maglev_core::levitation::GRAVITY;
use maglev_core::LawKind;

/// The vehicle a design works on: the case's car (one of them: the cars of a train are
/// equal), or the unit.
fn design_vehicle(case: &Case) -> Result<VehicleModel> {
    match &case.train {
        TrainCase::Fig1 { car, .. } => VehicleModel::fig1(car, GRAVITY),
        TrainCase::Maglev { magnet_mass, .. } => {
            Ok(
                Train::fig6_with(&crate::input::case::fig6(*magnet_mass), 1, GRAVITY)?
                    .cars
                    .remove(0),
            )
        }
        TrainCase::Unit(u) => VehicleModel::unit(u, GRAVITY),
        TrainCase::Forces(_) | TrainCase::WheelRail { .. } => Err(Error::invalid(
            "controller.law",
            "a train without magnets has no gains to design",
        )),
    }
}

/// `case` with its law designed (module docs); a case whose law is given is returned as is.
pub fn resolve(mut case: Case) -> Result<Case> {
    let kind = match case.law {
        LawChoice::Given(_) => return Ok(case),
        LawChoice::DesignGapLoop | LawChoice::DesignState(_) => {
            let controller = case.controller.ok_or_else(|| {
                Error::invalid("controller", "a design needs a [controller] section")
            })?;
            let v = design_vehicle(&case)?;
            match case.law {
                LawChoice::DesignState(base) => {
                    LawKind::State(crate::studies::stability::state_design::design(
                        &v,
                        &controller,
                        &base,
                        case.geometry,
                        case.dt,
                    )?)
                }
                _ => LawKind::GapLoop(
                    crate::studies::stability::design::design(
                        &v,
                        &controller,
                        case.geometry,
                        Some(case.dt),
                    )
                    .map_err(|e| Error::invalid("controller.law", e.to_string()))?
                    .gains,
                ),
            }
        }
    };
    case.law = LawChoice::Given(kind);
    Ok(case)
}

/// [`Case::load`], then [`resolve`].
pub fn load(name_or_path: &str, sets: &[String]) -> Result<Case> {
    resolve(Case::load(name_or_path, sets)?)
}

/// [`Case::with`], then [`resolve`].
pub fn with(case: &Case, changes: &Changes) -> Result<Case> {
    resolve(case.with(changes)?)
}
