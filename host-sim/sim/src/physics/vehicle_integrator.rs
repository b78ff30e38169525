//! The vehicle's time integrator: the FE's average-acceleration Newmark ([`crate::physics::fe::Newmark`],
//! γ = ½, β = ¼, docs/model.md §7) with a general damping matrix, wrapped in the coupling protocol
//! of [`crate::physics::guideway::Guideway`]: `solve` restarts from the committed state at every call
//! (one Newton–Raphson iteration), `commit` accepts the trial. Zero-mass DOFs (massless
//! maglev wheels) are allowed as long as damping or stiffness holds each of them.
//!
//! The step is linear in the load: `u₁ = Keff⁻¹ (r + f)` with `r` the load-free right-hand
//! side from the committed state (Eq. 19). So the load-free response `Keff⁻¹ r` is solved
//! once per step (on the first [`VehicleIntegrator::solve`] after a commit) and each further
//! Newton–Raphson iteration only adds `Keff⁻¹ f` from the precomputed columns of `Keff⁻¹` at
//! the loaded DOFs (the wheels and contacts: a few columns of n entries); velocity and
//! acceleration are completed once, on [`VehicleIntegrator::commit`]. Against one full step per
//! iteration this reorders sums only: round-off (test `split_step_matches_the_full_step`).
//!
//! The load-free response itself is [`FreeStep`]: the integrator's own operations
//! (`fe::Newmark::step_into` with a zero load: its predictors, its column-ordered gemv with M
//! and C, nalgebra's two triangular Cholesky solves with their 8-way unrolled dot) in the same
//! order, over the non-zero entries of M, C and the factor only, and without the velocity and
//! acceleration that the split step discards. For finite states the skipped terms are exact
//! zeros added to sums that are never −0, so the bits are the integrator's (test
//! `free_step_gives_the_integrators_bits`).

use crate::physics::fe::newmark::complete_step;
use crate::physics::fe::{Newmark as Integrator, State};
use crate::{Error, Result};
use nalgebra::{Cholesky, DMatrix, DVector};

/// The load-free displacement of the step, `Keff⁻¹ (M (a₀ d + a₂ v + a) + C (a₁ d + v))`, in
/// exactly the floating-point operations of [`Integrator::step_into`] under a zero load
/// (module docs), the zero entries of M, C and the Cholesky factor L skipped.
struct FreeStep {
    /// a₀ = 4/Δt², a₁ = 2/Δt, a₂ = 4/Δt as the integrator forms them.
    a0: f64,
    a1: f64,
    a2: f64,
    /// Non-zero `(row, column, value)` of M and of C, column by column (the gemv's order).
    m: Vec<(usize, usize, f64)>,
    c: Vec<(usize, usize, f64)>,
    /// `L[i, i]`.
    diag: Vec<f64>,
    /// Non-zero strict-lower entries of L, column by column: `(row k, L[k, i], slot)`, slot
    /// the accumulator of nalgebra's unrolled dot that the backward solve of row i puts the
    /// term in (`k − i − 1` mod 8 inside the whole chunks of 8, [`TAIL`] after them).
    lower: Vec<(usize, f64, usize)>,
    /// Per column i: `lower[start[i]..start[i + 1]]`, and the first tail entry `split[i]`.
    start: Vec<usize>,
    split: Vec<usize>,
    /// Scratch: the damping predictor `a₁ d + v` (the inertia one is built in place).
    pred: Vec<f64>,
    inertia: Vec<f64>,
}

/// The slot of a term of the backward dot outside the unrolled chunks.
const TAIL: usize = 8;

impl FreeStep {
    /// From the integrator's M, C, K and step (the factor recomputed as the integrator
    /// computes it: the same matrix, the same nalgebra Cholesky, so the same bits).
    fn new(m: &DMatrix<f64>, c: &DMatrix<f64>, k: &DMatrix<f64>, dt: f64) -> Option<Self> {
        let n = m.nrows();
        let mut keff = k + m * (4.0 / (dt * dt));
        keff += c * (2.0 / dt);
        let l = Cholesky::new(keff)?.l();
        let entries = |a: &DMatrix<f64>| {
            let mut e = Vec::new();
            for j in 0..n {
                for i in 0..n {
                    if a[(i, j)] != 0.0 {
                        e.push((i, j, a[(i, j)]));
                    }
                }
            }
            e
        };
        let (mut lower, mut start, mut split) = (Vec::new(), vec![0], Vec::with_capacity(n));
        for i in 0..n {
            // nalgebra's dot over L[i+1.., i] (length len): whole chunks of 8 first.
            let len = n - 1 - i;
            let chunked = len - len % 8;
            let mut first_tail = None;
            for kk in i + 1..n {
                let p = kk - i - 1;
                let slot = if p < chunked { p % 8 } else { TAIL };
                if l[(kk, i)] != 0.0 {
                    if slot == TAIL && first_tail.is_none() {
                        first_tail = Some(lower.len());
                    }
                    lower.push((kk, l[(kk, i)], slot));
                }
            }
            split.push(first_tail.unwrap_or(lower.len()));
            start.push(lower.len());
        }
        Some(FreeStep {
            a0: 4.0 / (dt * dt),
            a1: 2.0 / dt,
            a2: 4.0 / dt,
            m: entries(m),
            c: entries(c),
            diag: (0..n).map(|i| l[(i, i)]).collect(),
            lower,
            start,
            split,
            pred: vec![0.0; n],
            inertia: vec![0.0; n],
        })
    }

    /// `out ← Keff⁻¹ r(from)`. No allocation.
    fn solve(&mut self, from: &State, out: &mut [f64]) {
        let (d, v, a) = (from.d.as_slice(), from.v.as_slice(), from.a.as_slice());
        let (a0, a1, a2) = (self.a0, self.a1, self.a2);
        // The predictors as the integrator's axpys form them (a product by 1 is exact).
        for i in 0..out.len() {
            self.inertia[i] = a2 * v[i] + (a0 * d[i] + a[i]);
            self.pred[i] = a1 * d[i] + v[i];
        }
        // r = 0 + M·inertia + C·pred, column by column (each `y + p` of the gemv and of the
        // axpys below written `y += p`: IEEE addition commutes bit for bit).
        out.fill(0.0);
        for &(i, j, x) in &self.m {
            out[i] += x * self.inertia[j];
        }
        for &(i, j, x) in &self.c {
            out[i] += x * self.pred[j];
        }
        // L y = r (nalgebra's column axpys).
        let n = out.len();
        for i in 0..n {
            let coeff = out[i] / self.diag[i];
            out[i] = coeff;
            for &(k, l, _) in &self.lower[self.start[i]..self.start[i + 1]] {
                out[k] += -coeff * l;
            }
        }
        // Lᵀ x = y (nalgebra's dot: 8 accumulators over whole chunks, then the tail).
        for i in (0..n).rev() {
            let mut acc = [0.0f64; 8];
            for &(k, l, slot) in &self.lower[self.start[i]..self.split[i]] {
                acc[slot] += l * out[k];
            }
            let mut res = 0.0;
            res += acc[0] + acc[4];
            res += acc[1] + acc[5];
            res += acc[2] + acc[6];
            res += acc[3] + acc[7];
            for &(k, l, _) in &self.lower[self.split[i]..self.start[i + 1]] {
                res += l * out[k];
            }
            out[i] = (out[i] - res) / self.diag[i];
        }
    }
}

/// `M ü + C u̇ + K u = f` with a fixed step, committed and trial states.
pub struct VehicleIntegrator {
    integrator: Integrator,
    committed: State,
    trial: State,
    /// `Keff⁻¹`, column-major: column j is the step's displacement for a unit load on DOF j.
    flex: Vec<f64>,
    /// The load-free step and its displacement `Keff⁻¹ r` (valid when `solved`).
    free_step: FreeStep,
    free: Vec<f64>,
    /// A solve since the last commit (and so `free` is this step's).
    solved: bool,
}

impl VehicleIntegrator {
    /// Starts at rest (a system written in deviations from its static equilibrium).
    pub fn new(m: DMatrix<f64>, c: DMatrix<f64>, k: DMatrix<f64>, dt: f64) -> Result<Self> {
        let n = m.nrows();
        let singular = |e: &dyn std::fmt::Display| {
            Error::numerical(format!(
                "vehicle: {e} (a DOF with no mass, damping or stiffness?)"
            ))
        };
        // The integrator first: its errors (a bad step, no factor) are the ones to report.
        let integrator = Integrator::with_damping_matrix(&k, &m, Some(c.clone()), dt)
            .map_err(|e| singular(&e))?;
        let free_step = FreeStep::new(&m, &c, &k, dt)
            .ok_or_else(|| singular(&"effective stiffness is not positive definite"))?;
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
        Ok(VehicleIntegrator {
            integrator,
            committed: State::zeros(n),
            trial: State::zeros(n),
            flex,
            free_step,
            free: vec![0.0; n],
            solved: false,
        })
    }

    /// Starts from rest at the displacement `d` instead of zero (velocity and acceleration
    /// zero): a static equilibrium of the load the first step starts from, `K d = f(0)`, which
    /// the caller has solved (`TrainState::start_on_rail`). Before the first step only.
    pub fn start_at(&mut self, d: &DVector<f64>) {
        self.committed.d.copy_from(d);
        self.committed.v.fill(0.0);
        self.committed.a.fill(0.0);
        self.solved = false;
    }

    /// Committed displacement at t.
    pub fn u(&self) -> &DVector<f64> {
        &self.committed.d
    }

    /// Committed acceleration at t.
    pub fn a(&self) -> &DVector<f64> {
        &self.committed.a
    }

    /// Trial displacement at t + dt (valid after [`VehicleIntegrator::solve`]).
    pub fn u1(&self) -> &DVector<f64> {
        &self.trial.d
    }

    /// Trial acceleration of DOF `i` at t + dt (valid after [`VehicleIntegrator::solve`]; Eq. 19, as
    /// the commit completes it).
    pub fn a1(&self, i: usize) -> f64 {
        let c = &self.committed;
        crate::physics::fe::newmark::acceleration_at_end(
            self.integrator.time_step(),
            c.d[i],
            c.v[i],
            c.a[i],
            self.trial.d[i],
        )
    }

    /// `∂u_i/∂f_j` of a step (m/N): the displacement of DOF `i` at t + dt per unit load on
    /// DOF `j` (`Keff⁻¹`, the same for every step).
    pub fn flexibility(&self, i: usize, j: usize) -> f64 {
        self.flex[j * self.free.len() + i]
    }

    /// Solves the step's displacement for the load `f` at t + dt, from the committed state:
    /// the load-free response (once per step) plus `Keff⁻¹ f` over the non-zero entries of
    /// `f` (module docs). No allocation.
    pub fn solve(&mut self, f: &DVector<f64>) {
        if !self.solved {
            self.free_step.solve(&self.committed, &mut self.free);
        }
        let n = self.free.len();
        let d = self.trial.d.as_mut_slice();
        d.copy_from_slice(&self.free);
        for (col, &fj) in self.flex.chunks_exact(n.max(1)).zip(f.as_slice()) {
            if fj != 0.0 {
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
        let mut split = VehicleIntegrator::new(m, c, k, dt).unwrap();
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

    /// The load-free step gives the integrator's bits (`fe::Newmark::step_into` under a zero
    /// load): on the three car kinds (Fig. 1 with massless wheels, Fig. 6, wheel–rail) and on
    /// a dense 20-DOF system with a massless DOF (every slot of the unrolled dot used), from
    /// 200 pseudo-random states each (entries over eight decades, some exactly zero).
    #[test]
    fn free_step_gives_the_integrators_bits() {
        use crate::physics::train::Train;
        use crate::physics::vehicle::{Fig1, VehicleModel};
        let mut systems = Vec::new();
        let fig1 = VehicleModel::fig1(&Fig1::default(), 9.81).unwrap();
        systems.push((fig1.m.clone(), fig1.c.clone(), fig1.k_on_rigid_rail()));
        for train in [
            Train::fig6(1, 9.81).unwrap(),
            Train::wheel_rail(1, 9.81).unwrap(),
        ] {
            let car = &train.cars[0];
            systems.push((car.m.clone(), car.c.clone(), car.k_on_rigid_rail()));
        }
        let n = 20;
        let mut seed = 0x9E37_79B9_7F4A_7C15_u64;
        let b = DMatrix::from_fn(n, n, |_, _| noise(&mut seed));
        let k = &b * b.transpose() + DMatrix::identity(n, n) * 1e3;
        let cb = DMatrix::from_fn(n, n, |_, _| noise(&mut seed));
        let c = &cb * cb.transpose() * 10.0;
        let m = DMatrix::from_fn(n, n, |i, j| match (i == j, i) {
            (true, 7) => 0.0,
            (true, _) => 50.0 + i as f64,
            _ => 0.0,
        });
        systems.push((m, c, k));
        for (m, c, k) in systems {
            let n = m.nrows();
            let dt = 1e-3;
            let full = Integrator::with_damping_matrix(&k, &m, Some(c.clone()), dt).unwrap();
            let mut free = FreeStep::new(&m, &c, &k, dt).unwrap();
            let (zero, mut to) = (DVector::zeros(n), State::zeros(n));
            let mut out = vec![0.0; n];
            for _ in 0..200 {
                let mut from = State::zeros(n);
                for x in from
                    .d
                    .iter_mut()
                    .chain(from.v.iter_mut())
                    .chain(from.a.iter_mut())
                {
                    let r = noise(&mut seed);
                    *x = if r.abs() < 0.05 {
                        0.0
                    } else {
                        r * 10f64.powi((r * 1e6) as i32 % 8 - 6)
                    };
                }
                full.step_into(&from, &zero, &mut to);
                free.solve(&from, &mut out);
                for (i, (x, y)) in out.iter().zip(to.d.iter()).enumerate() {
                    assert_eq!(x.to_bits(), y.to_bits(), "DOF {i} of {n}");
                }
                assert!(out.iter().any(|&x| x != 0.0));
            }
        }
    }

    #[test]
    fn single_oscillator_period_and_amplitude() {
        // m = 1, k = (2π)², free vibration from u(0) = 0, v(0) = 1: average acceleration
        // conserves the energy and its numerical frequency obeys tan(ω̄Δt/2) = ωΔt/2, so
        // u_n = sin(ω̄ t_n)/ω exactly (up to round-off).
        let w = 2.0 * std::f64::consts::PI;
        let dt = 1e-3;
        let mut s = VehicleIntegrator::new(
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
        let mut s = VehicleIntegrator::new(
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
