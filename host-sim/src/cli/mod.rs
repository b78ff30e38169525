//! One module per `maglev` subcommand. Each exposes `Args` (clap) and `run(Args)` returning
//! `crate::Result` or `anyhow::Result`;
//! errors are one line naming what is wrong.
pub mod bands;
pub mod control;
pub mod hil;
pub mod irregularity;
pub mod modes;
pub mod progress;
pub mod report;
pub mod run;
pub mod stability;
pub mod stdout;
pub mod sweep;
pub mod validate;
