//! The vehicle's time integrator: the FE's average-acceleration Newmark ([`crate::fe::Newmark`],
//! γ = ½, β = ¼, docs/model.md §7) with a general damping matrix, wrapped in the coupling protocol
//! of [`crate::guideway::Guideway`]: `solve` restarts from the committed state at every call
//! (one Newton–Raphson iteration), `commit` accepts the trial. Zero-mass DOFs (massless
//! maglev wheels) are allowed as long as damping or stiffness holds each of them.

use crate::fe::{Newmark as Integrator, State};
use crate::{Error, Result};
use nalgebra::{DMatrix, DVector};

/// `M ü + C u̇ + K u = f` with a fixed step, committed and trial states.
pub struct Newmark {
    integrator: Integrator,
    committed: State,
    trial: State,
}

impl Newmark {
    /// Starts at rest (a system written in deviations from its static equilibrium).
    pub fn new(m: DMatrix<f64>, c: DMatrix<f64>, k: DMatrix<f64>, dt: f64) -> Result<Self> {
        let n = m.nrows();
        let integrator = Integrator::with_damping_matrix(&k, &m, Some(c), dt).map_err(|e| {
            Error::numerical(format!(
                "vehicle: {e} (a DOF with no mass, damping or stiffness?)"
            ))
        })?;
        Ok(Newmark {
            integrator,
            committed: State::zeros(n),
            trial: State::zeros(n),
        })
    }

    /// Committed displacement at t.
    pub fn u(&self) -> &DVector<f64> {
        &self.committed.d
    }

    /// Committed acceleration at t.
    pub fn a(&self) -> &DVector<f64> {
        &self.committed.a
    }

    /// Trial displacement at t + dt (valid after [`Newmark::solve`]).
    pub fn u1(&self) -> &DVector<f64> {
        &self.trial.d
    }

    /// Solves the step for the load `f` at t + dt, from the committed state.
    pub fn solve(&mut self, f: &DVector<f64>) {
        self.integrator
            .step_into(&self.committed, f, &mut self.trial);
    }

    /// Accepts the trial state.
    pub fn commit(&mut self) {
        self.committed.clone_from(&self.trial);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn single_oscillator_period_and_amplitude() {
        // m = 1, k = (2π)², free vibration from u(0) = 0, v(0) = 1: average acceleration
        // conserves the energy and its numerical frequency obeys tan(ω̄Δt/2) = ωΔt/2, so
        // u_n = sin(ω̄ t_n)/ω exactly (up to round-off).
        let w = 2.0 * std::f64::consts::PI;
        let dt = 1e-3;
        let mut s = Newmark::new(
            DMatrix::from_element(1, 1, 1.0),
            DMatrix::zeros(1, 1),
            DMatrix::from_element(1, 1, w * w),
            dt,
        )
        .unwrap();
        s.committed.v[0] = 1.0;
        let f = DVector::zeros(1);
        let steps = 1000;
        for _ in 0..steps {
            s.solve(&f);
            s.commit();
        }
        let (u, v) = (s.committed.d[0], s.committed.v[0]);
        let energy = 0.5 * v * v + 0.5 * w * w * u * u;
        assert!((energy - 0.5).abs() < 1e-12, "energy {energy}");
        let wbar = 2.0 * (w * dt / 2.0).atan() / dt;
        // Round-off over 1000 steps on an amplitude of 0.16 m: allow 1e-10.
        assert!(
            (u - (wbar * steps as f64 * dt).sin() / w).abs() < 1e-10,
            "{u}"
        );
    }

    #[test]
    fn massless_damped_dof_follows_its_force() {
        // A massless DOF on a damper c under a force F switched on at t = 0⁺ from rest:
        // u̇ = F/c. The trapezoidal rule starts from v(0) = 0, so the first step gains only
        // ½·Δt·F/c and every later step exactly Δt·F/c: u_n = (n − ½)·Δt·F/c.
        let c = 10.0;
        let mut s = Newmark::new(
            DMatrix::zeros(1, 1),
            DMatrix::from_element(1, 1, c),
            DMatrix::zeros(1, 1),
            0.01,
        )
        .unwrap();
        let f = DVector::from_element(1, 2.0);
        for _ in 0..100 {
            s.solve(&f);
            s.commit();
        }
        let want = (100.0 - 0.5) * 0.01 * 2.0 / c;
        assert!((s.u()[0] - want).abs() < 1e-12, "{} vs {want}", s.u()[0]);
    }
}
