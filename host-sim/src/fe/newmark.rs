//! Newmark time integration, γ = ½, β = ¼ (average acceleration; docs/model.md §7, Eq. 19).
//!
//! Why average acceleration: it is what the paper uses for both the FE and the modal model,
//! it is unconditionally stable and, undamped, conserves the energy of a linear system exactly
//! (its only error is period elongation, ω̄Δt = 2 atan(ωΔt/2)). The effective stiffness
//! K + (4/Δt²) M + (2/Δt) C is factorised once per distinct matrix set and reused: the step is
//! fixed and the structure linear.
//!
//! Two integrators share the formulas: [`Newmark`], dense, for small systems (the vehicle);
//! [`SpanNewmark`], banded matrices and a sparse Cholesky factor, for the guideway spans. The
//! span integrator splits the step into its load-free part, computed once per step
//! ([`SpanNewmark::free_rhs`]), the solve of one right-hand side per Newton–Raphson
//! iteration, and the velocity and acceleration update done once, on commit
//! ([`SpanNewmark::finish`]).

use super::banded::{SymBanded, SymSparse, ToDense};
use super::cholesky::{Scratch, SparseCholesky};
use crate::Error;
use nalgebra::{Cholesky, DMatrix, DVector, Dyn};

/// The one-line error for a bad time step.
fn time_step_error(dt: f64) -> Error {
    Error::invalid("dt", format!("must be positive and finite, got {dt}"))
}

/// Rayleigh damping C = α M + β K.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rayleigh {
    /// Mass-proportional coefficient α (1/s).
    pub alpha: f64,
    /// Stiffness-proportional coefficient β (s).
    pub beta: f64,
}

/// Displacement, velocity and acceleration of a linear system.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    pub d: DVector<f64>,
    pub v: DVector<f64>,
    pub a: DVector<f64>,
}

impl State {
    /// At rest: zero displacement, velocity and acceleration (n DOFs).
    pub fn zeros(n: usize) -> Self {
        State {
            d: DVector::zeros(n),
            v: DVector::zeros(n),
            a: DVector::zeros(n),
        }
    }

    /// True if every entry is exactly zero.
    pub fn is_at_rest(&self) -> bool {
        let z = |x: &DVector<f64>| x.iter().all(|&e| e == 0.0);
        z(&self.d) && z(&self.v) && z(&self.a)
    }
}

/// A linear system M ẍ + C ẋ + K x = F advanced with average-acceleration Newmark at a
/// fixed step.
#[derive(Clone, Debug)]
pub struct Newmark {
    dt: f64,
    m: DMatrix<f64>,
    c: Option<DMatrix<f64>>,
    keff: Cholesky<f64, Dyn>,
}

impl Newmark {
    /// Factorise K + (4/Δt²) M + (2/Δt) C for the step `dt` (dense copies of `k`, `m`).
    pub fn new<A: ToDense>(
        k: &A,
        m: &A,
        damping: Option<Rayleigh>,
        dt: f64,
    ) -> crate::Result<Self> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(time_step_error(dt));
        }
        let (k, m) = (k.to_dense_matrix(), m.to_dense_matrix());
        let c = damping.map(|r| &m * r.alpha + &k * r.beta);
        Self::with_damping_matrix(&k, &m, c, dt)
    }

    /// As [`Newmark::new`] with an arbitrary (symmetric) damping matrix, e.g. a vehicle's
    /// discrete dampers. Zero-mass DOFs are fine as long as damping or stiffness holds them.
    pub fn with_damping_matrix(
        k: &DMatrix<f64>,
        m: &DMatrix<f64>,
        c: Option<DMatrix<f64>>,
        dt: f64,
    ) -> crate::Result<Self> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(time_step_error(dt));
        }
        let mut keff = k + m * (4.0 / (dt * dt));
        if let Some(c) = &c {
            keff += c * (2.0 / dt);
        }
        let keff = Cholesky::new(keff)
            .ok_or_else(|| Error::numerical("effective stiffness is not positive definite"))?;
        Ok(Newmark {
            dt,
            m: m.clone(),
            c,
            keff,
        })
    }

    /// The fixed step (s).
    pub fn time_step(&self) -> f64 {
        self.dt
    }

    /// Advance `from` (state at t) to `to` (state at t + Δt) under the load `f` at t + Δt:
    /// Keff d₁ = F + M (a₀ d + a₂ v + a) + C (a₁ d + v), a₀ = 4/Δt², a₁ = 2/Δt, a₂ = 4/Δt;
    /// then a₁ = a₀ (d₁ − d) − a₂ v − a and v₁ = v + Δt (a + a₁)/2. No allocation.
    pub fn step_into(&self, from: &State, f: &DVector<f64>, to: &mut State) {
        let dt = self.dt;
        let (a0, a1, a2) = (4.0 / (dt * dt), 2.0 / dt, 4.0 / dt);
        // to.v as scratch for the inertia predictor a0 d + a2 v + a.
        to.v.copy_from(&from.a);
        to.v.axpy(a0, &from.d, 1.0);
        to.v.axpy(a2, &from.v, 1.0);
        to.d.copy_from(f);
        to.d.gemv(1.0, &self.m, &to.v, 1.0);
        if let Some(c) = &self.c {
            to.v.copy_from(&from.v);
            to.v.axpy(a1, &from.d, 1.0);
            to.d.gemv(1.0, c, &to.v, 1.0);
        }
        self.keff.solve_mut(&mut to.d);
        // a_new = a0 (d1 - d) - a2 v - a
        to.a.copy_from(&to.d);
        to.a.axpy(-1.0, &from.d, 1.0);
        to.a *= a0;
        to.a.axpy(-a2, &from.v, 1.0);
        to.a.axpy(-1.0, &from.a, 1.0);
        // v_new = v + dt/2 (a + a_new)
        to.v.copy_from(&from.v);
        to.v.axpy(dt / 2.0, &from.a, 1.0);
        to.v.axpy(dt / 2.0, &to.a, 1.0);
    }
}

/// Average-acceleration Newmark for one span: banded M (and C), the effective stiffness
/// factorised once by a sparse Cholesky (see the module docs for the split of the step).
#[derive(Debug)]
pub struct SpanNewmark {
    dt: f64,
    m: SymSparse,
    c: Option<SymSparse>,
    keff: SparseCholesky,
}

impl SpanNewmark {
    /// Factorise K + (4/Δt²) M + (2/Δt) C, C = α M + β K if damped.
    pub fn new(
        k: &SymBanded,
        m: &SymBanded,
        damping: Option<Rayleigh>,
        dt: f64,
    ) -> crate::Result<Self> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(time_step_error(dt));
        }
        let c = damping.map(|r| m.combine(r.alpha, k, r.beta));
        Self::with_damping_matrix(k, m, c, dt)
    }

    /// As [`SpanNewmark::new`] with an arbitrary symmetric damping matrix `c` (e.g. discrete
    /// foundation dashpots plus Rayleigh damping).
    pub fn with_damping_matrix(
        k: &SymBanded,
        m: &SymBanded,
        c: Option<SymBanded>,
        dt: f64,
    ) -> crate::Result<Self> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(time_step_error(dt));
        }
        let mut keff = k.combine(1.0, m, 4.0 / (dt * dt));
        if let Some(c) = &c {
            keff = keff.combine(1.0, c, 2.0 / dt);
        }
        let keff = SparseCholesky::new(&keff)
            .map_err(|e| Error::numerical(format!("effective stiffness: {e}")))?;
        Ok(SpanNewmark {
            dt,
            m: SymSparse::new(m),
            c: c.as_ref().map(SymSparse::new),
            keff,
        })
    }

    /// The fixed step (s).
    pub fn time_step(&self) -> f64 {
        self.dt
    }

    /// Stored values and indices of M, C and the factor, in words.
    pub fn storage_words(&self) -> usize {
        2 * (self.m.nonzeros() + self.c.as_ref().map_or(0, SymSparse::nonzeros))
            + self.keff.factor_nonzeros()
    }

    /// The effective stiffness factor.
    pub fn factor(&self) -> &SparseCholesky {
        &self.keff
    }

    /// The load-free right-hand side of the step from `from` (state at t):
    /// `rhs = M (a₀ d + a₂ v + a) + C (a₁ d + v)`, a₀ = 4/Δt², a₁ = 2/Δt, a₂ = 4/Δt;
    /// `pred` is scratch. The step's displacement is then `Keff⁻¹ (rhs + F)`. No allocation.
    pub fn free_rhs(&self, from: &State, pred: &mut DVector<f64>, rhs: &mut DVector<f64>) {
        let dt = self.dt;
        let (a0, a1, a2) = (4.0 / (dt * dt), 2.0 / dt, 4.0 / dt);
        pred.copy_from(&from.a);
        pred.axpy(a0, &from.d, 1.0);
        pred.axpy(a2, &from.v, 1.0);
        rhs.fill(0.0);
        self.m.mul_acc(pred.as_slice(), rhs.as_mut_slice());
        if let Some(c) = &self.c {
            pred.copy_from(&from.v);
            pred.axpy(a1, &from.d, 1.0);
            c.mul_acc(pred.as_slice(), rhs.as_mut_slice());
        }
    }

    /// x ← Keff⁻¹ x. No allocation.
    pub fn solve_in_place(&self, x: &mut DVector<f64>, scratch: &mut Scratch) {
        self.keff.solve_in_place(x.as_mut_slice(), scratch);
    }

    /// Complete the step: with `trial.d` the displacement at t + Δt and `committed` the state
    /// at t, a₁ = a₀ (d₁ − d) − a₂ v − a and v₁ = v + Δt (a + a₁)/2, written to both `trial`
    /// and `committed` (which becomes the state at t + Δt). No allocation.
    pub fn finish(&self, committed: &mut State, trial: &mut State) {
        let dt = self.dt;
        let (a0, a2, h) = (4.0 / (dt * dt), 4.0 / dt, dt / 2.0);
        let n = committed.d.len();
        for i in 0..n {
            let (d0, v0, acc0, d1) = (committed.d[i], committed.v[i], committed.a[i], trial.d[i]);
            let acc1 = a0 * (d1 - d0) - a2 * v0 - acc0;
            let v1 = v0 + h * acc0 + h * acc1;
            committed.d[i] = d1;
            committed.v[i] = v1;
            committed.a[i] = acc1;
            trial.v[i] = v1;
            trial.a[i] = acc1;
        }
    }
}
