#![no_std]
pub mod gap;
pub mod scalar;
mod trig;
pub use scalar::Scalar;
