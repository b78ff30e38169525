//! The `maglev` command line over the library crates: the commands (`cli/`), output
//! directories and their staging (`output/`, with the signal handling only a binary may
//! install), plots (`plot`), and the studies that write reports or many runs (`studies/`:
//! validation, the paper's §5 report, sweeps and Slurm). The physics, the simulation, the
//! input path and the linear models are `maglev-sim`'s; the firmware coupling `maglev-hil`'s.
pub mod cli;
pub mod output;
pub mod plot;
pub mod studies;

// The library's modules at this crate's root, so that the commands name them as
// `crate::input::…` wherever they live.
use maglev_hil as hil;
use maglev_sim::{bands, ground, input, physics, probes, setup, simulation, Error, Result};
