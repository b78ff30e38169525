//! Host-side simulators: the guideway (FE and modal reference), vehicles, coupling, CLI.
//!
//! Data flows one way: `cli/` parses arguments into an [`input::case::Case`],
//! [`setup::simulate`] runs it, [`output`] writes it. The module tree shows the layers, lowest
//! first (docs/architecture.md; `tests/layering.rs` checks that no module names a higher one):
//!
//! - [`physics`]: the guideway, the vehicles and cars, the irregularity, support motion;
//! - [`simulation`], [`probes`]: the coupled time loop and what it records;
//! - [`input`]: scenarios as written and the checked case in SI;
//! - [`setup`], [`output`], [`plot`], [`bands`], [`ground`]: one passage from a case to its output
//!   directory, and what is computed from its records (band levels, ground-borne vibration);
//! - [`studies`]: validation, the paper-5 report, stability, gain design, sweeps;
//! - [`hil`]: the firmware as the magnets; `cli/`: the commands.
pub mod bands;
pub mod error;
pub mod ground;
pub mod input;
pub mod physics;
pub mod probes;
pub mod safety;
pub mod setup;
pub mod simulation;
pub mod studies;

pub use error::{Error, Result};
