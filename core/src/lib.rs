#![no_std]
#![doc = include_str!("../README.md")]

pub mod gap;
pub mod gap_control;
pub mod guidance;
pub mod irregularity;
pub mod irregularity_fast;
pub mod law;
pub mod levitation;
pub mod scalar;
mod trig;

pub use law::{Control, Field, Law, LawKind, LawName, LawParams, LawState, Measurement, Sensors};
pub use levitation::{
    Interpolation, Levitation, Output, ParamError, Params, Scheme, State, Status,
};
pub use scalar::Scalar;
