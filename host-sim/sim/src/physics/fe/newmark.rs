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
//! ([`SpanNewmark::free_rhs`], M and C products over the decoupled components as dense bands),
//! the solve of one right-hand side (per step with [`super::flexibility`], else per
//! Newton–Raphson iteration), and the velocity and acceleration update done once, on commit
//! ([`SpanNewmark::finish`]).
//!
//! The span's solve ([`SpanNewmark::solve_in_place`]) runs through [`ComponentBand`] (the
//! same matrix factorised as narrow bands over its decoupled components; round-off against
//! faer's) when it fits, else faer's factor through [`Simplicial`]: a plain loop over the
//! factor's columns, the permutation folded into the row indices and the diagonal's
//! reciprocals computed once, performing faer's simplicial solve's operations in faer's
//! order, so giving the same bits (test `simplicial_solve_gives_faers_bits`). A factor that
//! faer stores supernodally keeps faer's solve.

use super::banded::{ComponentProduct, Components, SymBanded, SymSparse, ToDense};
use super::cholesky::{Scratch, SparseCholesky};
use super::component_band::ComponentBand;

use crate::Error;
use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
use nalgebra::{Cholesky, DMatrix, DVector, Dyn};

/// The one-line error for a bad time step.
fn time_step_error(dt: f64) -> Error {
    Error::invalid("dt", format!("must be positive and finite, got {dt}"))
}

/// Rayleigh damping C = α M + β K.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Rayleigh {
    /// Mass-proportional coefficient α (1/s).
    #[serde(rename = "alpha_per_s")]
    pub alpha: f64,
    /// Stiffness-proportional coefficient β (s).
    #[serde(rename = "beta_s")]
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
    /// M (and C) as component bands, used for the products when they fit.
    bands: Option<ComponentProduct>,
    keff: SparseCholesky,
    /// The same factor as a plain column loop (`None` when faer stores it supernodally).
    fast: Option<Simplicial>,
    /// The banded factor of the decoupled components, used for every solve when it exists
    /// and is not larger than three times faer's (module docs).
    band: Option<ComponentBand>,
    /// Keff's decoupled components.
    components: Components,
}

/// A simplicial LLᵀ factor `P A Pᵀ = L Lᵀ` of faer's, for its solve in faer's order of
/// operations on the caller's vector, in the original numbering (no scratch).
#[derive(Debug)]
pub struct Simplicial {
    /// Per column j (in factor order): its original index, the reciprocal of `L[j, j]` and
    /// the range of its off-diagonal entries in `entries`.
    col: Vec<(usize, f64, usize, usize)>,
    /// Off-diagonal entries `(original row index, L[i, j])`, column by column, in faer's
    /// stored order.
    entries: Vec<(usize, f64)>,
}

impl Simplicial {
    /// The columns of `factor` (faer's own factor, read, not recomputed); `None` if faer chose
    /// a supernodal factor.
    pub fn new(factor: &SparseCholesky) -> Option<Self> {
        let (symbolic, values) = factor.parts();
        let n = symbolic.nrows();
        let SymbolicCholeskyRaw::Simplicial(simp) = symbolic.raw() else {
            return None;
        };
        // Factor index k is original index fwd[k] (faer: x[k] = rhs[fwd[k]]).
        let fwd: Vec<usize> = match symbolic.perm() {
            Some(p) => p.arrays().0.to_vec(),
            None => (0..n).collect(),
        };
        let (cp, ri) = (simp.col_ptr(), simp.row_idx());
        let mut col = Vec::with_capacity(n);
        let mut entries = Vec::with_capacity(values.len());
        for j in 0..n {
            let (start, end) = (cp[j], cp[j + 1]);
            // faer stores the diagonal first in each column.
            if start == end || ri[start] != j {
                return None;
            }
            let first = entries.len();
            for p in start + 1..end {
                entries.push((fwd[ri[p]], values[p]));
            }
            col.push((fwd[j], values[start].recip(), first, entries.len()));
        }
        Some(Simplicial { col, entries })
    }

    /// x ← A⁻¹ x: faer's `L` solve (x_j ← x_j·(1/L_jj), then x_i −= L_ij·x_j down column j)
    /// and its `Lᵀ` solve (from the last column, acc = Σ L_ij·x_i over the column's entries in
    /// reverse stored order, x_j ← (x_j − acc)·(1/L_jj)). No allocation.
    pub fn solve_in_place(&self, x: &mut [f64]) {
        assert_eq!(x.len(), self.col.len(), "dimension mismatch");
        for &(cj, dinv, start, end) in &self.col {
            let xj = x[cj] * dinv;
            x[cj] = xj;
            for &(i, l) in &self.entries[start..end] {
                x[i] -= l * xj;
            }
        }
        for &(cj, dinv, start, end) in self.col.iter().rev() {
            let mut acc = 0.0;
            for &(i, l) in self.entries[start..end].iter().rev() {
                acc += l * x[i];
            }
            x[cj] = (x[cj] - acc) * dinv;
        }
    }
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
        let c = damping.map(|r| rayleigh_matrix(k, m, r));
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
        let keff = effective_stiffness(k, m, c.as_ref(), dt);
        let components = keff.components();
        let band = ComponentBand::new(&keff);
        let keff = SparseCholesky::new(&keff)
            .map_err(|e| Error::numerical(format!("effective stiffness: {e}")))?;
        let fast = Simplicial::new(&keff);
        let band = band.filter(|b| b.stored() <= 3 * keff.factor_nonzeros());
        let bands = match &c {
            Some(c) => ComponentProduct::new(&components, &[m, c]),
            None => ComponentProduct::new(&components, &[m]),
        };
        Ok(SpanNewmark {
            dt,
            m: SymSparse::new(m),
            c: c.as_ref().map(SymSparse::new),
            bands,
            keff,
            fast,
            band,
            components,
        })
    }

    /// The fixed step (s).
    pub fn time_step(&self) -> f64 {
        self.dt
    }

    /// Stored values and indices of M, C and the factors, in words.
    pub fn storage_words(&self) -> usize {
        2 * (self.m.nonzeros() + self.c.as_ref().map_or(0, SymSparse::nonzeros))
            + self.bands.as_ref().map_or(0, ComponentProduct::stored)
            + self.keff.factor_nonzeros()
            + self.band.as_ref().map_or(0, ComponentBand::stored)
    }

    /// The effective stiffness factor.
    pub fn factor(&self) -> &SparseCholesky {
        &self.keff
    }

    /// Length of the scratch vector `pred` of [`Self::free_rhs`] (allocate it zeroed).
    pub fn pred_len(&self) -> usize {
        self.bands
            .as_ref()
            .map_or(self.m.nrows(), ComponentProduct::padded_len)
    }

    /// The load-free right-hand side of the step from `from` (state at t):
    /// `rhs = M (a₀ d + a₂ v + a) + C (a₁ d + v)`, a₀ = 4/Δt², a₁ = 2/Δt, a₂ = 4/Δt;
    /// `pred` is scratch of [`Self::pred_len`], zero when first given. The step's
    /// displacement is then `Keff⁻¹ (rhs + F)`. No allocation. Through the component bands
    /// when M and C fit them, else the row lists: the same sums either way.
    pub fn free_rhs(&self, from: &State, pred: &mut DVector<f64>, rhs: &mut DVector<f64>) {
        let dt = self.dt;
        let (a0, a1, a2) = (4.0 / (dt * dt), 2.0 / dt, 4.0 / dt);
        let (a, d, v) = (from.a.as_slice(), from.d.as_slice(), from.v.as_slice());
        let p = pred.as_mut_slice();
        assert_eq!(p.len(), self.pred_len(), "scratch of the wrong length");
        // nalgebra's `copy_from` and `axpy(·, ·, 1.0)` in one pass: the same operations.
        let inertia = |i: usize| a2 * v[i] + (a0 * d[i] + a[i]);
        let damping = |i: usize| a1 * d[i] + v[i];
        rhs.as_mut_slice().fill(0.0);
        let rhs = rhs.as_mut_slice();
        match &self.bands {
            Some(b) => {
                b.scatter(p, inertia);
                b.mul_acc(0, p, rhs);
                if self.c.is_some() {
                    b.scatter(p, damping);
                    b.mul_acc(1, p, rhs);
                }
            }
            None => {
                for (i, p) in p.iter_mut().enumerate() {
                    *p = inertia(i);
                }
                self.m.mul_acc(p, rhs);
                if let Some(c) = &self.c {
                    for (i, p) in p.iter_mut().enumerate() {
                        *p = damping(i);
                    }
                    c.mul_acc(p, rhs);
                }
            }
        }
    }

    /// x ← Keff⁻¹ x: through the [`ComponentBand`] factor when there is one (equal to faer's
    /// solve to round-off), else [`Simplicial`] when faer's factor is simplicial (the same
    /// bits as faer's solve), else faer's. No allocation.
    pub fn solve_in_place(&self, x: &mut DVector<f64>, scratch: &mut Scratch) {
        match (&self.band, &self.fast) {
            (Some(b), _) => b.solve_in_place(x.as_mut_slice()),
            (None, Some(f)) => f.solve_in_place(x.as_mut_slice()),
            (None, None) => self.keff.solve_in_place(x.as_mut_slice(), scratch),
        }
    }

    /// x ← Keff⁻¹ x through [`Simplicial`] or faer (the path without [`ComponentBand`]).
    pub fn solve_in_place_sparse(&self, x: &mut DVector<f64>, scratch: &mut Scratch) {
        self.solve_in_place_slice(x.as_mut_slice(), scratch);
    }

    /// As [`Self::solve_in_place_sparse`], on a slice.
    pub fn solve_in_place_slice(&self, x: &mut [f64], scratch: &mut Scratch) {
        match &self.fast {
            Some(f) => f.solve_in_place(x),
            None => self.keff.solve_in_place(x, scratch),
        }
    }

    /// The decoupled components of Keff ([`SymBanded::components`]).
    pub fn components(&self) -> &Components {
        &self.components
    }

    /// x ← Keff⁻¹ x by faer's own solve (the reference of the fast path's test).
    pub fn solve_in_place_faer(&self, x: &mut DVector<f64>, scratch: &mut Scratch) {
        self.keff.solve_in_place(x.as_mut_slice(), scratch);
    }

    /// The factor runs through [`Simplicial`].
    pub fn has_fast_solve(&self) -> bool {
        self.fast.is_some()
    }

    /// Complete the step ([`complete_step`] at this span's Δt). No allocation.
    pub fn finish(&self, committed: &mut State, trial: &mut State) {
        complete_step(self.dt, committed, trial);
    }
}

/// Rayleigh damping's matrix C = α M + β K.
pub fn rayleigh_matrix(k: &SymBanded, m: &SymBanded, r: Rayleigh) -> SymBanded {
    m.combine(r.alpha, k, r.beta)
}

/// The effective stiffness of the step, Keff = K + (4/Δt²) M + (2/Δt) C (Eq. 19).
pub fn effective_stiffness(
    k: &SymBanded,
    m: &SymBanded,
    c: Option<&SymBanded>,
    dt: f64,
) -> SymBanded {
    let keff = k.combine(1.0, m, 4.0 / (dt * dt));
    match c {
        Some(c) => keff.combine(1.0, c, 2.0 / dt),
        None => keff,
    }
}

/// The end of an average-acceleration step, shared by the spans and the vehicle: with
/// `trial.d` the displacement at t + Δt and `committed` the state at t,
/// a₁ = a₀ (d₁ − d) − a₂ v − a (a₀ = 4/Δt², a₂ = 4/Δt) and v₁ = v + Δt (a + a₁)/2, written to
/// both `trial` and `committed` (which becomes the state at t + Δt). No allocation.
/// The acceleration at t + dt of a DOF at `d1` there, from its committed displacement `d0`,
/// velocity `v0` and acceleration `acc0` at t (Eq. 19, average acceleration).
pub fn acceleration_at_end(dt: f64, d0: f64, v0: f64, acc0: f64, d1: f64) -> f64 {
    let (a0, a2) = (4.0 / (dt * dt), 4.0 / dt);
    a0 * (d1 - d0) - a2 * v0 - acc0
}

pub fn complete_step(dt: f64, committed: &mut State, trial: &mut State) {
    let h = dt / 2.0;
    let n = committed.d.len();
    let (d, v, a) = (
        &mut committed.d.as_mut_slice()[..n],
        &mut committed.v.as_mut_slice()[..n],
        &mut committed.a.as_mut_slice()[..n],
    );
    let (d1s, tv, ta) = (
        &trial.d.as_slice()[..n],
        &mut trial.v.as_mut_slice()[..n],
        &mut trial.a.as_mut_slice()[..n],
    );
    for i in 0..n {
        let (d0, v0, acc0, d1) = (d[i], v[i], a[i], d1s[i]);
        let acc1 = acceleration_at_end(dt, d0, v0, acc0, d1);
        let v1 = v0 + h * acc0 + h * acc1;
        d[i] = d1;
        v[i] = v1;
        a[i] = acc1;
        tv[i] = v1;
        ta[i] = acc1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::fe::assembly::SpanModel;
    use crate::physics::guideway::BeamSection;

    /// A deterministic pseudo-random vector in [−1, 1) (xorshift), large and small entries.
    fn vector(n: usize, seed: u64) -> DVector<f64> {
        let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
        DVector::from_fn(n, |_, _| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            let u = (s >> 11) as f64 / (1u64 << 53) as f64;
            (2.0 * u - 1.0) * 10f64.powi((s % 7) as i32 - 3)
        })
    }

    /// The fast solve gives faer's bits, on the §4.2 span (undamped and Rayleigh-damped, 20
    /// and 80 elements) and on a block-coupled test matrix.
    #[test]
    fn simplicial_solve_gives_faers_bits() {
        let section = BeamSection::paper_4_2();
        let mut systems = Vec::new();
        for elements in [20, 80] {
            let model = SpanModel::new(&section, 25.0, elements).unwrap();
            for damping in [
                None,
                Some(Rayleigh {
                    alpha: 0.3,
                    beta: 1e-4,
                }),
            ] {
                systems.push(SpanNewmark::new(&model.k, &model.m, damping, 1e-3).unwrap());
            }
        }
        let n = 40;
        let mut a = SymBanded::zeros(n, 4);
        for j in 0..n {
            a.add_lower(j, j, 10.0 + j as f64 * 0.1);
            if j + 2 < n {
                a.add_lower(j + 2, j, -1.0 - 0.01 * j as f64);
            }
            if j + 4 < n && j % 2 == 0 {
                a.add_lower(j + 4, j, 0.5);
            }
        }
        let zero = SymBanded::zeros(n, 4);
        systems.push(SpanNewmark::with_damping_matrix(&a, &zero, None, 1e-3).unwrap());
        for (k, sys) in systems.iter().enumerate() {
            assert!(
                sys.has_fast_solve(),
                "system {k}: faer chose a supernodal factor"
            );
            let mut scratch = sys.factor().scratch();
            let n = sys.factor().nrows();
            for seed in 1..20 {
                let b = vector(n, seed + 100 * k as u64);
                let (mut fast, mut slow) = (b.clone(), b);
                sys.solve_in_place_sparse(&mut fast, &mut scratch);
                sys.solve_in_place_faer(&mut slow, &mut scratch);
                for i in 0..n {
                    assert_eq!(
                        fast[i].to_bits(),
                        slow[i].to_bits(),
                        "system {k}, seed {seed}, entry {i}"
                    );
                }
            }
        }
    }
}
