//! The train's side of a coupled step: one prefactored Newmark solve per car
//! ([`crate::physics::vehicle_integrator::VehicleIntegrator`]), never a matrix over the whole train (docs/model.md §10).
//!
//! Why per car: cars share no spring, so the train's M, C, K are block-diagonal; a car of
//! 13 DOFs costs the same whether it runs alone or as car 12 of 12, and the train's cost grows
//! linearly in its cars. The cars may be advanced on rayon's pool ([`Train::parallel`]).

use crate::physics::train::Train;
use crate::physics::vehicle_integrator::VehicleIntegrator;
use crate::{Error, Result};
use nalgebra::{Cholesky, DVector};
use rayon::prelude::*;

/// One car's integrator and load vector.
struct Car {
    newmark: VehicleIntegrator,
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
                newmark: VehicleIntegrator::new(c.m.clone(), c.c.clone(), c.k_on_rigid_rail(), dt)?,
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

    /// Puts every car with contacts into its static equilibrium on the rail as it lies at
    /// t = 0 (docs/cars.md "The start on a rough rail"), and returns each contact's force at
    /// t = 0 (N, compressive, zero when lifted off). `forcing` is each contact's
    /// `k·(z_g − r_z)` at t = 0, the load the coupling puts on the car's contact DOF.
    ///
    /// The car's K here is [`crate::physics::vehicle::VehicleModel::k_on_rigid_rail`], the matrix the
    /// car integrates, so `K q0 = f(0)` makes the first step start with zero acceleration.
    /// A contact can only push: a contact whose spring would pull at q0 is dropped from the
    /// static problem (its spring and forcing out, its static load P0 taken off the car) and
    /// the problem solved again, until the
    /// contacts in and out agree (at most one pass per contact). Its load on the car is then
    /// the time loop's lift-off correction, so the car is still at rest. A car whose rail
    /// holds no contact has no equilibrium: refused. Cars with no forcing (a smooth rail, a
    /// maglev car) keep q0 = 0, bit for bit.
    pub fn start_on_rail(&mut self, train: &Train, forcing: &[f64]) -> Result<Vec<f64>> {
        let mut p: Vec<f64> = train.contacts.iter().map(|c| c.p0).collect();
        for (car, model) in train.cars.iter().enumerate() {
            let mine: Vec<usize> = (0..train.contacts.len())
                .filter(|&j| train.contacts[j].car == car)
                .collect();
            if mine.iter().all(|&j| forcing[j] == 0.0) {
                continue;
            }
            let n = model.m.nrows();
            let mut on = vec![true; mine.len()];
            let mut q = DVector::zeros(n);
            let mut settled = false;
            for _ in 0..=mine.len() {
                let mut k = model.k.clone();
                let mut f = DVector::zeros(n);
                for (&j, &o) in mine.iter().zip(&on) {
                    let c = &train.contacts[j];
                    if o {
                        k[(c.dof_z, c.dof_z)] += c.k;
                        f[c.dof_z] += forcing[j];
                    } else {
                        // Lifted off: the car loses its static load there (P − P0 = −P0).
                        f[c.dof_z] -= c.p0;
                    }
                }
                q = Cholesky::new(k)
                    .ok_or_else(|| {
                        Error::numerical(format!(
                            "car {}: no wheel touches the rail at t = 0, so it has no static                              equilibrium (rail irregularity beyond the static compression)",
                            car + 1
                        ))
                    })?
                    .solve(&f);
                // The linear force of every contact at q0: P0 − k·z_w + k·(z_g − r_z).
                let mut changed = false;
                for (&j, o) in mine.iter().zip(on.iter_mut()) {
                    let c = &train.contacts[j];
                    let pj = c.p0 - c.k * q[c.dof_z] + forcing[j];
                    p[j] = pj.max(0.0);
                    if (pj >= 0.0) != *o {
                        *o = pj >= 0.0;
                        changed = true;
                    }
                }
                if !changed {
                    settled = true;
                    break;
                }
            }
            if !settled {
                return Err(Error::numerical(format!(
                    "car {}: the contacts in touch at t = 0 do not settle",
                    car + 1
                )));
            }
            let o = self.offsets[car];
            self.u[o..o + n].copy_from_slice(q.as_slice());
            self.cars[car].newmark.start_at(&q);
        }
        Ok(p)
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
            if let Some(y) = w.dof_y {
                f[y] = fy;
            }
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

    /// The step's flexibility `∂u/∂f` (m/N) of car `car`'s DOF `dof` to a load on itself.
    pub fn flexibility(&self, car: usize, dof: usize) -> f64 {
        self.cars[car].newmark.flexibility(dof, dof)
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
