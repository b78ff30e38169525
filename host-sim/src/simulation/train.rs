//! The train's side of a coupled step: one prefactored Newmark solve per car
//! ([`crate::newmark::Newmark`]), never a matrix over the whole train (docs/model.md §10).
//!
//! Why per car: cars share no spring, so the train's M, C, K are block-diagonal; a car of
//! 13 DOFs costs the same whether it runs alone or as car 12 of 12, and the train's cost grows
//! linearly in its cars. The cars may be advanced on rayon's pool ([`Train::parallel`]).

use crate::newmark::Newmark;
use crate::vehicle::Train;
use crate::Result;
use nalgebra::DVector;
use rayon::prelude::*;

/// One car's integrator and load vector.
struct Car {
    newmark: Newmark,
    f: DVector<f64>,
}

/// The committed and trial states of every car of a train.
pub struct TrainState {
    cars: Vec<Car>,
    parallel: bool,
    /// Where each car's DOFs start in the train-wide vectors of the probes.
    offsets: Vec<usize>,
    /// Train-wide committed displacement and acceleration (gathered on commit).
    u: Vec<f64>,
    a: Vec<f64>,
}

impl TrainState {
    /// Every car at rest in its static equilibrium, stepping by `dt`.
    pub fn new(train: &Train, dt: f64) -> Result<Self> {
        let mut cars = Vec::with_capacity(train.cars.len());
        let mut offsets = Vec::with_capacity(train.cars.len());
        let mut n = 0;
        for c in &train.cars {
            offsets.push(n);
            n += c.m.nrows();
            cars.push(Car {
                // The contact springs are implicit on the car's side (docs/cars.md).
                newmark: Newmark::new(c.m.clone(), c.c.clone(), c.k_on_rigid_rail(), dt)?,
                f: DVector::zeros(c.m.nrows()),
            });
        }
        Ok(TrainState {
            cars,
            parallel: train.parallel,
            offsets,
            u: vec![0.0; n],
            a: vec![0.0; n],
        })
    }

    /// Train-wide index of DOF `dof` of car `car`.
    pub fn global(&self, car: usize, dof: usize) -> usize {
        self.offsets[car] + dof
    }

    /// Committed displacement of DOF `dof` of car `car`.
    pub fn u(&self, car: usize, dof: usize) -> f64 {
        self.cars[car].newmark.u()[dof]
    }

    /// Trial displacement (after [`TrainState::solve`]).
    pub fn u1(&self, car: usize, dof: usize) -> f64 {
        self.cars[car].newmark.u1()[dof]
    }

    /// Committed acceleration of DOF `dof` of car `car`.
    pub fn a(&self, car: usize, dof: usize) -> f64 {
        self.cars[car].newmark.a()[dof]
    }

    /// Trial acceleration (after [`TrainState::solve`]).
    pub fn a1(&self, car: usize, dof: usize) -> f64 {
        self.cars[car].newmark.a1(dof)
    }

    /// Solves every car for the wheel forces `(Δf_z, f_y)` (`G − p0` and the guidance
    /// force), one entry per magnet wheel of the train in order, and the contacts' forcing
    /// `contact` (N, one per contact: `k·(z_g − r_z)` plus any loss-of-contact correction,
    /// docs/cars.md "Wheel–rail contact").
    pub fn solve(&mut self, train: &Train, forces: &[(f64, f64)], contact: &[f64]) {
        for c in &mut self.cars {
            c.f.as_mut_slice().fill(0.0);
        }
        for (w, &(fz, fy)) in train.wheels.iter().zip(forces) {
            let f = self.cars[w.car].f.as_mut_slice();
            f[w.dof_z] = fz;
            f[w.dof_y] = fy;
        }
        for (k, &fz) in train.contacts.iter().zip(contact) {
            self.cars[k.car].f.as_mut_slice()[k.dof_z] += fz;
        }
        if self.parallel {
            self.cars.par_iter_mut().for_each(|c| c.newmark.solve(&c.f));
        } else {
            for c in &mut self.cars {
                c.newmark.solve(&c.f);
            }
        }
    }

    /// Accepts every car's trial state and gathers the train-wide vectors.
    pub fn commit(&mut self) {
        for (c, &o) in self.cars.iter_mut().zip(&self.offsets) {
            c.newmark.commit();
            let n = c.newmark.u().len();
            self.u[o..o + n].copy_from_slice(c.newmark.u().as_slice());
            self.a[o..o + n].copy_from_slice(c.newmark.a().as_slice());
        }
    }

    /// Train-wide committed displacements (the probes' view).
    pub fn u_all(&self) -> &[f64] {
        &self.u
    }

    /// Train-wide committed accelerations.
    pub fn a_all(&self) -> &[f64] {
        &self.a
    }
}
