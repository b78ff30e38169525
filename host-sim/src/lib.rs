//! Host-side simulators: the guideway (FE and modal reference), vehicles, coupling, CLI.
//!
//! Data flows one way: `cli/` parses arguments into a [`case::Case`], [`setup::simulate`] runs
//! it, [`output`] writes it. Nothing outside `cli/` imports from `cli/` (tests/layering.rs).
pub mod bands;
pub mod cars;
pub mod case;
pub mod cli;
pub mod control;
pub mod design;
pub mod error;
pub mod fe;
pub mod ground;
pub mod guideway;
pub mod hil;
pub mod input;
pub mod modal;
pub mod output;
pub mod paper5;
pub mod paper5_ground;
pub mod plot;
pub mod probes;
pub mod profile;
pub mod scenario;
pub mod seismic;
pub mod setup;
pub mod simulation;
pub mod stability;
pub mod sweep;
pub mod validation;
pub mod vehicle;
pub mod vehicle_integrator;

pub use error::{Error, Result};
