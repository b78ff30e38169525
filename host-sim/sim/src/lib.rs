//! `maglev-sim`: the EMS maglev simulator as a library — the guideway (finite elements or the
//! modal reference, a viaduct on piers), the vehicles and trains, the coupled time loop with
//! the levitation controllers in it, the scenarios and the checked case they resolve into, the
//! linear models (stability, gain design), ground-borne vibration, band levels and the safety
//! criteria (docs/architecture.md).
//!
//! Why a library of its own: the `maglev` command line, the hardware-in-the-loop crate
//! (`maglev-hil`) and a user's own program or Python study all run the same passage, so it
//! lives here, free of command-line, plotting, serial-port and signal-handling dependencies,
//! with no process-global side effects: a run is stopped through its [`Monitor`], never by a
//! signal handler installed here.
//!
//! # A run
//!
//! ```no_run
//! use maglev_sim::prelude::*;
//!
//! // A bundled scenario (or a file) with `--set`-style overrides, its designs resolved.
//! let case = maglev_sim::load("paper-4.2", &["speed=100".to_string()])?;
//! // The core's controllers as the magnets; every step's default probes kept in memory.
//! let mut rows = Rows::new(case.probes.clone());
//! let run = simulate(&case, &mut CoreMagnets::new(), &mut rows, &mut ())?;
//! println!("{} steps, {} rows", run.outcome.steps, rows.t.len());
//! # Ok::<(), maglev_sim::Error>(())
//! ```
//!
//! A controller written elsewhere implements [`Magnets`] (forces from gaps, a committed and a
//! trial state) and is passed instead of [`CoreMagnets`]; `maglev-hil`'s firmware magnets are
//! one. A caller that may stop a run passes a [`Monitor`] (an [`AtomicBool`] it sets, or its
//! own type); the run then ends with [`Error::Cancelled`].
//!
//! # The surface
//!
//! The items at this crate's root (and in [`prelude`]) are the library's interface: a case
//! from a scenario ([`load`], [`Case`], [`Scenario`]), a run ([`simulate`], [`Magnets`],
//! [`CoreMagnets`], [`Monitor`]), its records ([`Recorder`], [`Rows`], [`CsvRecorder`],
//! [`Safety`]), the linear models ([`scenario_report`], [`natural_modes`]), band levels
//! ([`band_levels`]) and the ground ([`ground_green`]).
//!
//! The module tree below them is public for the crates built on this one (`maglev-hil`, the
//! `maglev` binary) and for this crate's tests and benchmarks, which reach into every layer;
//! it is hidden from the documentation and carries no promise between versions. Its layers,
//! lowest first (tests/tests/layering.rs checks that no module names a higher one and that no
//! two modules name each other around a circle): `error` and `bands`; `physics`; `probes`;
//! `simulation`; `ground`; `input`; `setup` and `safety`; `studies`.
#![warn(missing_docs)]

#[doc(hidden)]
pub mod bands;
#[doc(hidden)]
pub mod error;
#[doc(hidden)]
pub mod ground;
#[doc(hidden)]
pub mod input;
#[doc(hidden)]
pub mod physics;
#[doc(hidden)]
pub mod probes;
#[doc(hidden)]
pub use safety::running as running_safety;
#[doc(hidden)]
pub mod safety;
#[doc(hidden)]
pub mod setup;
#[doc(hidden)]
pub mod simulation;
#[doc(hidden)]
pub mod studies;

pub use bands::{analyse as band_levels, BandLevel, Settings as BandSettings};
pub use error::{Error, Result};
pub use ground::green::displacement_per_newton as ground_green;
pub use input::case::Case;
pub use input::scenario::{Scenario, BUNDLED};
pub use physics::fe::{natural_modes, Mode, ModeKind, SpanModel};
pub use physics::train::Train;
pub use physics::vehicle::Coil;
pub use probes::{CsvRecorder, NoRecorder, Probe, Probes, Recorder, Rows, StepView, Tee};
pub use safety::{Safety, SafetyReport};
pub use setup::{simulate, FinishedPassage, Passage};
pub use simulation::magnets::CoreMagnets;
pub use simulation::{Magnets, Monitor, Outcome, Settings, Start, WheelGaps};
pub use std::sync::atomic::AtomicBool;
pub use studies::design::{load, resolve};
pub use studies::stability::report::{scenario_report, ScenarioReport};

/// What a run needs in one import: `use maglev_sim::prelude::*;`.
pub mod prelude {
    pub use crate::{
        load, simulate, Case, CoreMagnets, Error, Magnets, Monitor, Outcome, Recorder, Result,
        Rows, Start, StepView, WheelGaps,
    };
}
