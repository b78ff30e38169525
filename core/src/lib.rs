#![no_std]
pub mod irregularity;
pub mod scalar;
mod trig;
pub use scalar::Scalar;
