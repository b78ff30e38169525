//! Host-side simulators: the guideway (FE and modal reference), vehicles, coupling, CLI.
pub mod cli;
pub mod guideway;
pub mod stability;
