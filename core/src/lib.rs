#![no_std]
pub mod scalar;
mod trig;
pub use scalar::Scalar;
