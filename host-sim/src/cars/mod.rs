//! Car models for the train on the viaduct (docs/model.md §10; issue #10 items 2 and 3): the
//! Fig. 6 maglev carriage ([`fig6`]) and the wheel/rail comparison car ([`wheel_rail`]).
//!
//! Why a block per car: the cars of a train share no spring, so the train's matrices are
//! block-diagonal, one small dense block per car (docs/model.md §7). Each model here builds
//! ONE car as such a block — mass, damping and stiffness in deviations from its static
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
mod stability_check;
#[cfg(test)]
mod tests;

pub use crate::vehicle::Wheel;
use nalgebra::DMatrix;

/// A wheel–rail contact: a linearised Hertz spring between the wheel DOF `dof_z` and the rail
/// target point at (x_w, ey, ez) (docs/model.md §5 rigid link).
#[derive(Clone, Debug, PartialEq)]
pub struct Contact {
    /// X position at t = 0 (m), the leading contact of the car at 0.
    pub x0: f64,
    /// Offset of the rail target point from the beam axis, Y and Z (m).
    pub ey: f64,
    pub ez: f64,
    /// The wheel's vertical DOF in the car block (its own DOF, coefficient 1).
    pub dof_z: usize,
    /// Static wheel load P0 (N, compressive), from the car's exact statics.
    pub p0: f64,
    /// Linearised Hertz stiffness at P0 (N/m), [`wheel_rail::hertz_stiffness`].
    pub k_h: f64,
}

/// What kind of car a block is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CarKind {
    /// The Fig. 6 maglev carriage: 32 magnet wheels.
    Fig6Maglev,
    /// The wheel/rail car: 8 Hertz contacts.
    WheelRail,
}

/// One car: a block of the train's matrices and its guideway nodes.
#[derive(Clone, Debug)]
pub struct CarBlock {
    pub kind: CarKind,
    /// Mass, damping, stiffness (deviations from static equilibrium).
    pub m: DMatrix<f64>,
    pub c: DMatrix<f64>,
    pub k: DMatrix<f64>,
    /// Maglev wheels (empty for a wheel/rail car).
    pub wheels: Vec<Wheel>,
    /// Static load of each maglev wheel (N), same order as `wheels`.
    pub p0: Vec<f64>,
    /// Wheel–rail contacts (empty for a maglev car).
    pub contacts: Vec<Contact>,
    /// The car body's heave (Z) DOF, for `car{N}.body.{z,az}`; the body's reference point is
    /// its centre of mass, at the middle of the car.
    pub body_z: usize,
    /// The car body's pitch (θy) DOF.
    pub body_pitch: usize,
    /// Car pitch along the train (m): the next car's leading node is this far behind.
    pub length: f64,
    /// Total weight (N): the sum of the static loads.
    pub weight: f64,
}

impl CarBlock {
    /// The stiffness with every contact spring tied to a fixed, smooth rail (`k_h` on each
    /// contact DOF): the car on a rigid rail. For a maglev car, `k` itself.
    pub fn k_on_rigid_rail(&self) -> DMatrix<f64> {
        let mut k = self.k.clone();
        for c in &self.contacts {
            k[(c.dof_z, c.dof_z)] += c.k_h;
        }
        k
    }

    /// The DOFs of the guideway nodes (wheels' Y and Z, contacts' Z), the ones a static
    /// solution "with the wheels held" fixes.
    pub fn node_dofs(&self) -> Vec<usize> {
        let mut d: Vec<usize> = self
            .wheels
            .iter()
            .flat_map(|w| [w.dof_y, w.dof_z])
            .collect();
        d.extend(self.contacts.iter().map(|c| c.dof_z));
        d
    }
}
