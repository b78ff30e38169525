//! [`ModalBasis`]: a small span's Newmark step in the coordinates that make it diagonal, so
//! the load-free part of a step (Eq. 19) costs a few operations a mode instead of two sparse
//! products and a substitution.
//!
//! Why: with Φ the solutions of the generalised eigenproblem M φ = μ Keff φ, normalised so that
//! Φᵀ Keff Φ = I, also Φᵀ M Φ = diag(μ), and a Rayleigh C = α M + β K is diagonal as well
//! (K = Keff − a₀ M − a₁ C). Writing the span's state as d = Φ q, v = Φ q̇, a = Φ q̈, the step
//! Keff d₁ = M (a₀ d + a₂ v + a) + C (a₁ d + v) + F becomes, premultiplied by Φᵀ and written
//! as an increment, q₁ = q + μ (a₂ q̇ + q̈) + γ q̇ − κ q + Φᵀ F mode by mode
//! ([`ModalBasis::free_response`] says why the increment), and the end of the step
//! ([`super::newmark::complete_step`]) is the same linear formula in either coordinates. This
//! is a change of basis, not a truncation: every mode is kept, so the result equals the
//! direct step up to round-off (tests/fe_solver.rs holds it to 1e-12 of the peak against the
//! dense physical-coordinate step in double-double arithmetic). A massless DOF (μ = 0) is no
//! special case, since Φ is normalised on Keff, which is positive definite.
//!
//! Φ is block-diagonal over the decoupled DOF families (axial, torsion, lateral and vertical
//! bending), so the displacement at one DOF is a dot product over its family's modes and a
//! load at one DOF enters only its family's modes. Modal vectors have the span's length,
//! family after family (mode k of family c at `start[c] + k`), so that dot product runs over
//! contiguous memory, and the state type and step end of the physical DOFs serve them
//! unchanged.

use super::banded::{Components, SymBanded};
use super::newmark::State;
use nalgebra::{Cholesky, DMatrix, SymmetricEigen};

/// Φ, μ and γ of one span (module docs).
#[derive(Clone, Debug)]
pub struct ModalBasis {
    n: usize,
    /// Per DOF: where its row of Φ starts in `phi`, its family's first modal slot and its
    /// family's number of modes.
    rows: Vec<(usize, usize, usize)>,
    /// Φ's rows (over their family's modes), family after family.
    phi: Vec<f64>,
    /// Per slot: κ = φᵀ K φ, μ = φᵀ M φ and γ = φᵀ C φ of the mode stored there.
    kappa: Vec<f64>,
    mu: Vec<f64>,
    gamma: Vec<f64>,
}

impl ModalBasis {
    /// The basis of Keff, M and a damping matrix `c` over `components`; `None` if Keff is not
    /// positive definite on some component or `c` is not diagonal in the basis (not
    /// Rayleigh-like, to 1e-10 of its largest modal value).
    pub fn new(
        components: &Components,
        k: &SymBanded,
        keff: &SymBanded,
        m: &SymBanded,
        c: Option<&SymBanded>,
    ) -> Option<Self> {
        let n = components.dofs();
        let (mut kappa, mut mu, mut gamma) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let mut rows = vec![(0, 0, 0); n];
        let mut flat = Vec::new();
        let mut first = 0;
        for members in &components.members {
            let size = members.len();
            let dense =
                |a: &SymBanded| DMatrix::from_fn(size, size, |i, j| a.get(members[i], members[j]));
            let (kd, keffd, md) = (dense(k), dense(keff), dense(m));
            let cd = c.map(dense);
            let reduce = |a: &DMatrix<f64>, b: &DMatrix<f64>| {
                // S = L⁻¹ B L⁻ᵀ, symmetric; S = U Λ Uᵀ; Φ = L⁻ᵀ U.
                let l = Cholesky::new(a.clone())?.l();
                let lb = l.solve_lower_triangular(b)?;
                let s = l.solve_lower_triangular(&lb.transpose())?;
                let s = (&s + s.transpose()) * 0.5;
                let eig = SymmetricEigen::new(s);
                l.transpose().solve_upper_triangular(&eig.eigenvectors)
            };
            let phi0 = reduce(&keffd, &md)?;
            let a = phi0.transpose() * &keffd * &phi0;
            let b = phi0.transpose() * &md * &phi0;
            let mut phi = &phi0 * reduce(&a, &b)?;
            let quad = |phi: &DMatrix<f64>, x: &DMatrix<f64>, j: usize| {
                let col = phi.column(j);
                (col.transpose() * x * col)[(0, 0)]
            };
            for j in 0..size {
                let s = quad(&phi, &keffd, j);
                if !(s > 0.0 && s.is_finite()) {
                    return None;
                }
                let slot = first + j;
                kappa[slot] = quad(&phi, &kd, j) / s;
                mu[slot] = quad(&phi, &md, j) / s;
                if let Some(cd) = &cd {
                    gamma[slot] = quad(&phi, cd, j) / s;
                }
                phi.column_mut(j).scale_mut(1.0 / s.sqrt());
            }
            if let Some(cd) = &cd {
                let d = phi.transpose() * cd * &phi;
                let scale = d.diagonal().amax().max(f64::MIN_POSITIVE);
                for i in 0..size {
                    for j in 0..size {
                        if i != j && d[(i, j)].abs() > 1e-10 * scale {
                            return None;
                        }
                    }
                }
            }
            for (i, &dof) in members.iter().enumerate() {
                rows[dof] = (flat.len(), first, size);
                flat.extend(phi.row(i).iter());
            }
            first += size;
        }
        Some(ModalBasis {
            n,
            rows,
            phi: flat,
            kappa,
            mu,
            gamma,
        })
    }

    /// Dimension n.
    pub fn nrows(&self) -> usize {
        self.n
    }

    /// Stored values.
    pub fn stored(&self) -> usize {
        self.phi.len() + 6 * self.n
    }

    /// The load-free modal response of the step from `from` (modal state at t), Eq. 19
    /// diagonalised and written as an increment, `q_free = q + μ (a₂ q̇ + q̈) + γ q̇ − κ q`
    /// (Keff (d₁ − d) = F − K d + M (a₂ v + a) + C v, the coefficients of
    /// [`super::SpanNewmark::free_rhs`]). The step's modal displacement is `q_free + Φᵀ F`.
    ///
    /// Why the increment: the direct form μ (a₀ q + …) reaches the quasi-static response
    /// through 1 − a₀ μ = κ + a₁ γ, which for the soft modes is ≈ ω²Δt²/4 (2.5e-4 for the
    /// §4.2 span's first bending mode at Δt = 1 ms) and so loses four digits; κ from its own
    /// quadratic form keeps them.
    pub fn free_response(&self, dt: f64, from: &State, out: &mut [f64]) {
        let a2 = 4.0 / dt;
        let n = self.n;
        let (d, v, a) = (
            &from.d.as_slice()[..n],
            &from.v.as_slice()[..n],
            &from.a.as_slice()[..n],
        );
        let (kappa, mu, gamma) = (&self.kappa[..n], &self.mu[..n], &self.gamma[..n]);
        let out = &mut out[..n];
        for i in 0..n {
            out[i] = d[i] + ((mu[i] * (a2 * v[i] + a[i]) + gamma[i] * v[i]) - kappa[i] * d[i]);
        }
    }

    /// Φ's row at DOF `i` and the modal slots it spans.
    fn row(&self, i: usize) -> (&[f64], std::ops::Range<usize>) {
        let (at, first, k) = self.rows[i];
        (&self.phi[at..at + k], first..first + k)
    }

    /// The physical value at DOF `i` of the modal vector `q`: (Φ q)ᵢ.
    ///
    /// In four partial sums, so the products do not wait on one chain of additions.
    pub fn value_at(&self, q: &[f64], i: usize) -> f64 {
        let (row, slots) = self.row(i);
        let q = &q[slots];
        let mut acc = [0.0; 4];
        let (rows, qs) = (row.chunks_exact(4), q.chunks_exact(4));
        let (row_tail, q_tail) = (rows.remainder(), qs.remainder());
        for (r, q) in rows.zip(qs) {
            for k in 0..4 {
                acc[k] += r[k] * q[k];
            }
        }
        for (k, (r, q)) in row_tail.iter().zip(q_tail).enumerate() {
            acc[k] += r * q;
        }
        (acc[0] + acc[1]) + (acc[2] + acc[3])
    }

    /// `q += Φᵀ e_j f`: a load `f` at DOF `j` into its family's modes.
    pub fn add_load(&self, j: usize, f: f64, q: &mut [f64]) {
        let (row, slots) = self.row(j);
        for (phi, q) in row.iter().zip(&mut q[slots]) {
            *q += phi * f;
        }
    }

    /// `q += Φᵀ load` over the non-zero loads, DOF by DOF in order.
    pub fn add_loads(&self, load: &[f64], q: &mut [f64]) {
        for (j, &f) in load[..self.n].iter().enumerate() {
            if f != 0.0 {
                self.add_load(j, f, q);
            }
        }
    }

    /// `out = Φ q` (every DOF).
    pub fn to_physical(&self, q: &[f64], out: &mut [f64]) {
        for (i, o) in out[..self.n].iter_mut().enumerate() {
            *o = self.value_at(q, i);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::fe::assembly::SpanModel;
    use crate::physics::fe::newmark::{effective_stiffness, rayleigh_matrix, Rayleigh};
    use crate::physics::guideway::BeamSection;

    /// Φᵀ Keff Φ = I and Φᵀ M Φ = diag(μ) to round-off, μ in [0, 1/a₀], and a Rayleigh C
    /// diagonal, on the §4.2 span: the identities the modal step rests on.
    #[test]
    fn basis_diagonalises_keff_m_and_rayleigh_c() {
        let model = SpanModel::new(&BeamSection::paper_4_2(), 25.0, 20).unwrap();
        let dt = 1e-3;
        let damping = Rayleigh {
            alpha: 0.3,
            beta: 1e-4,
        };
        let c = rayleigh_matrix(&model.k, &model.m, damping);
        let keff = effective_stiffness(&model.k, &model.m, Some(&c), dt);
        let comps = keff.components();
        let basis = ModalBasis::new(&comps, &model.k, &keff, &model.m, Some(&c)).unwrap();
        let n = basis.nrows();
        // Φ column by column, as physical vectors.
        let phi: Vec<Vec<f64>> = (0..n)
            .map(|slot| {
                let mut q = vec![0.0; n];
                q[slot] = 1.0;
                let mut x = vec![0.0; n];
                basis.to_physical(&q, &mut x);
                x
            })
            .collect();
        let quad = |a: &SymBanded, x: &[f64], y: &[f64]| {
            let mut ay = vec![0.0; n];
            a.mul_acc(1.0, y, &mut ay);
            x.iter().zip(&ay).map(|(x, y)| x * y).sum::<f64>()
        };
        let (a0, a1) = (4.0 / (dt * dt), 2.0 / dt);
        let gmax = basis.gamma.iter().fold(0.0f64, |m, g| m.max(g.abs()));
        assert!(gmax > 0.0);
        for i in 0..n {
            for j in 0..n {
                let (k, kk, m, cc) = (
                    quad(&keff, &phi[i], &phi[j]),
                    quad(&model.k, &phi[i], &phi[j]),
                    quad(&model.m, &phi[i], &phi[j]),
                    quad(&c, &phi[i], &phi[j]),
                );
                let (want_k, want_kk, want_m, want_c) = if i == j {
                    (1.0, basis.kappa[i], basis.mu[i], basis.gamma[i])
                } else {
                    (0.0, 0.0, 0.0, 0.0)
                };
                assert!((k - want_k).abs() < 1e-12, "Keff ({i}, {j}): {k}");
                assert!((kk - want_kk).abs() < 1e-12, "K ({i}, {j}): {kk}");
                assert!((m - want_m).abs() < 1e-12 / a0, "M ({i}, {j}): {m}");
                assert!((cc - want_c).abs() < 1e-12 * gmax, "C ({i}, {j}): {cc}");
            }
            let (kappa, mu, gamma) = (basis.kappa[i], basis.mu[i], basis.gamma[i]);
            assert!(kappa > 0.0 && mu >= 0.0 && gamma > 0.0, "mode {i}");
            // Keff = K + a₀ M + a₁ C in the basis: the three parts of each mode sum to 1.
            let sum = kappa + a0 * mu + a1 * gamma;
            assert!((sum - 1.0).abs() < 1e-13, "mode {i}: {sum}");
        }
    }
}
