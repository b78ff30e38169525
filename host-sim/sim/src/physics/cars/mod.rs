//! Car models for the train on the viaduct (docs/model.md §10; issue #10 items 2 and 3): the
//! Fig. 6 maglev carriage ([`fig6`]) and the wheel/rail comparison car ([`wheel_rail`]).
//!
//! Why a block per car: the cars of a train share no spring, so the train's matrices are
//! block-diagonal, one small dense block per car (docs/model.md §7). Each model here builds
//! ONE car as such a block, a [`VehicleModel`] (the one per-car type of every kind) — mass, damping and stiffness in deviations from its static
//! equilibrium (docs/model.md §6), the nodes through which it meets the guideway, and each
//! node's exact static load — for the train to place along the track. The rigid bodies and
//! the spring–dampers between them are [`link`]'s; values and every reading of Fig. 6 are in
//! docs/cars.md.
//!
//! Two kinds of guideway node:
//! * a maglev [`Wheel`] (Y and Z DOFs, carrying a levitation magnet and a guidance pair,
//!   docs/model.md §2, §4) with its static load `p0`;
//! * a wheel–rail [`Contact`] (a Z DOF): a Hertz spring linearised about its static load P0,
//!   between the wheel's DOF and the rail's target point (docs/cars.md).

pub mod fig6;
pub mod link;
pub mod wheel_rail;

#[cfg(test)]
mod tests;

pub use crate::physics::vehicle::{Contact, VehicleModel, Wheel};
