//! The vehicle's time integrator: the FE's average-acceleration Newmark ([`crate::fe::Newmark`],
//! γ = ½, β = ¼, docs/model.md §7) with a general damping matrix, wrapped in the coupling protocol
//! of [`crate::guideway::Guideway`]: `solve` restarts from the committed state at every call
//! (one Newton–Raphson iteration), `commit` accepts the trial. Zero-mass DOFs (massless
//! maglev wheels) are allowed as long as damping or stiffness holds each of them.
//!
//! The step is linear in the load: `u₁ = Keff⁻¹ (r + f)` with `r` the load-free right-hand
//! side from the committed state (Eq. 19). So the load-free response `Keff⁻¹ r` is solved
//! once per step (on the first [`Newmark::solve`] after a commit) and each further
//! Newton–Raphson iteration only adds `Keff⁻¹ f` from the precomputed columns of `Keff⁻¹` at
//! the loaded DOFs (the wheels and contacts: a few columns of n entries); velocity and
//! acceleration are completed once, on [`Newmark::commit`]. Against one full step per
//! iteration this reorders sums only: round-off (test `split_step_matches_the_full_step`).

use crate::fe::newmark::complete_step;
use crate::fe::{Newmark as Integrator, State};
use crate::{Error, Result};
use nalgebra::{DMatrix, DVector};

/// `M ü + C u̇ + K u = f` with a fixed step, committed and trial states.
pub struct Newmark {
    integrator: Integrator,
    committed: State,
    trial: State,
    /// `Keff⁻¹`, column-major: column j is the step's displacement for a unit load on DOF j.
    flex: Vec<f64>,
    /// The step's load-free displacement `Keff⁻¹ r` (valid when `solved`).
    free: DVector<f64>,
    /// A zero load and a scratch state for the load-free step.
    zero: DVector<f64>,
    scratch: State,
    /// A solve since the last commit (and so `free` is this step's).
    solved: bool,
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
        // From rest the step is Keff⁻¹ f: a unit load per DOF gives Keff⁻¹'s columns.
        let rest = State::zeros(n);
        let mut scratch = State::zeros(n);
        let mut flex = Vec::with_capacity(n * n);
        let mut unit = DVector::zeros(n);
        for j in 0..n {
            unit[j] = 1.0;
            integrator.step_into(&rest, &unit, &mut scratch);
            flex.extend_from_slice(scratch.d.as_slice());
            unit[j] = 0.0;
        }
        Ok(Newmark {
            integrator,
            committed: State::zeros(n),
            trial: State::zeros(n),
            flex,
            free: DVector::zeros(n),
            zero: DVector::zeros(n),
            scratch,
            solved: false,
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

    /// Solves the step's displacement for the load `f` at t + dt, from the committed state:
    /// the load-free response (once per step) plus `Keff⁻¹ f` over the non-zero entries of
    /// `f` (module docs). No allocation.
    pub fn solve(&mut self, f: &DVector<f64>) {
        if !self.solved {
            self.integrator
                .step_into(&self.committed, &self.zero, &mut self.scratch);
            self.free.copy_from(&self.scratch.d);
        }
        let n = self.free.len();
        let d = self.trial.d.as_mut_slice();
        d.copy_from_slice(self.free.as_slice());
        for (j, &fj) in f.as_slice().iter().enumerate() {
            if fj != 0.0 {
                let col = &self.flex[j * n..(j + 1) * n];
                for (d, &k) in d.iter_mut().zip(col) {
                    *d += k * fj;
                }
            }
        }
        self.solved = true;
    }

    /// Accepts the trial state: completes its acceleration and velocity (Eq. 19, by
    /// [`complete_step`], the spans' completion).
    pub fn commit(&mut self) {
        if !self.solved {
            return;
        }
        complete_step(
            self.integrator.time_step(),
            &mut self.committed,
            &mut self.trial,
        );
        self.solved = false;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic pseudo-random number in [−1, 1) (xorshift).
    fn noise(s: &mut u64) -> f64 {
        *s ^= *s << 13;
        *s ^= *s >> 7;
        *s ^= *s << 17;
        (*s >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    /// The split step (load-free response once per step, `Keff⁻¹` columns per iteration,
    /// velocity and acceleration on commit) against the full step of `fe::Newmark` at every
    /// iteration: a 7-DOF chain with a massless, damped end DOF, three iterations a step with
    /// different loads on three DOFs, 400 steps; every trial and committed quantity within
    /// 1e-12 of its peak.
    #[test]
    fn split_step_matches_the_full_step() {
        let n = 7;
        let dt = 1e-3;
        let (mut m, mut c, mut k) = (
            DMatrix::zeros(n, n),
            DMatrix::zeros(n, n),
            DMatrix::zeros(n, n),
        );
        for i in 0..n {
            m[(i, i)] = if i == n - 1 {
                0.0
            } else {
                100.0 + 30.0 * i as f64
            };
        }
        for i in 0..n - 1 {
            let (kk, cc) = (1e6 * (1.0 + 0.2 * i as f64), 2e3 * (1.0 + 0.1 * i as f64));
            for (a, b, sgn) in [
                (i, i, 1.0),
                (i + 1, i + 1, 1.0),
                (i, i + 1, -1.0),
                (i + 1, i, -1.0),
            ] {
                k[(a, b)] += sgn * kk;
                c[(a, b)] += sgn * cc;
            }
        }
        k[(0, 0)] += 5e5;
        let full = Integrator::with_damping_matrix(&k, &m, Some(c.clone()), dt).unwrap();
        let mut split = Newmark::new(m, c, k, dt).unwrap();
        let (mut committed, mut trial) = (State::zeros(n), State::zeros(n));
        let mut f = DVector::zeros(n);
        let mut seed = 0x2545_F491_4F6C_DD1D_u64;
        let mut worst = [0.0f64; 3];
        let mut peak = [0.0f64; 3];
        for _ in 0..400 {
            for _ in 0..3 {
                f[1] = 1e3 * noise(&mut seed);
                f[4] = 2e3 * noise(&mut seed);
                f[n - 1] = 5e2 * noise(&mut seed);
                full.step_into(&committed, &f, &mut trial);
                split.solve(&f);
                for i in 0..n {
                    worst[0] = worst[0].max((split.u1()[i] - trial.d[i]).abs());
                    peak[0] = peak[0].max(trial.d[i].abs());
                }
            }
            committed.clone_from(&trial);
            split.commit();
            for i in 0..n {
                worst[1] = worst[1].max((split.u()[i] - committed.d[i]).abs());
                worst[2] = worst[2].max((split.a()[i] - committed.a[i]).abs());
                peak[1] = peak[1].max(committed.d[i].abs());
                peak[2] = peak[2].max(committed.a[i].abs());
            }
        }
        for q in 0..3 {
            assert!(peak[q] > 0.0);
            assert!(
                worst[q] <= 1e-12 * peak[q],
                "quantity {q}: {} of peak {}",
                worst[q],
                peak[q]
            );
        }
        // The chain was really excited (not a test of zeros).
        assert!(peak[0] > 1e-5, "peak displacement {}", peak[0]);
    }

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
