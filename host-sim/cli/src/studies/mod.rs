//! Studies that write reports or many runs: the paper's validation and §5 report, and sweeps
//! over a scenario's keys (the analyses they call are `maglev_sim::studies`').
pub mod paper5;
pub mod sweep;
pub mod validation;

pub use maglev_sim::studies::{control, design, stability};
