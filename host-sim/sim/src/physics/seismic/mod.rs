//! Earthquake input for the guideway's supports (docs/seismic.md).
//!
//! Why a module of its own: ground motion is data that enters the structure at its supports
//! (pier bases, or span bearings where there are no piers); it is made or read here and then
//! handed to the guideway as an excitation, so the solver needs no special case for it.
//! [`accelerogram`] synthesises a seeded, reproducible record for a user without one;
//! [`support`] holds the motion of each support and the loads by which it enters a structure
//! on ground springs and dashpots.

pub mod accelerogram;
pub mod support;
