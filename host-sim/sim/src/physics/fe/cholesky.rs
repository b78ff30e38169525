//! [`SparseCholesky`]: a once-factorised symmetric positive definite matrix, through faer's
//! sparse Cholesky (LLᵀ) with an approximate-minimum-degree (AMD) fill-reducing ordering.
//!
//! Why sparse with AMD rather than banded: a span's axial, lateral-bending, vertical-bending
//! and torsion DOFs are uncoupled (see [`super::modes`]), so the ordering separates them and
//! the factor of the §4.2 span holds ≈ 2.5 non-zeros per row instead of the 12 of the band;
//! each solve is then O(n) with a small constant. Should a section couple the families, the
//! ordering simply keeps them together (the factor stays O(n·b)).
//!
//! The solve works in place on a caller-owned scratch ([`Scratch`]) so the time loop never
//! allocates and several spans can be solved at once (one scratch each).

use super::banded::SymBanded;
use crate::Error;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymmetricOrdering,
};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, MatMut, Par, Side};

/// LLᵀ of a symmetric positive definite matrix (faer, simplicial or supernodal as faer
/// chooses, AMD ordering).
#[derive(Debug)]
pub struct SparseCholesky {
    symbolic: SymbolicCholesky<usize>,
    values: Vec<f64>,
}

/// Scratch space for [`SparseCholesky::solve_in_place`], sized once.
pub struct Scratch(MemBuffer);

impl core::fmt::Debug for Scratch {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("Scratch")
    }
}

impl SparseCholesky {
    /// faer's symbolic factor and the factor's values (for [`super::newmark::Simplicial`]).
    pub fn parts(&self) -> (&SymbolicCholesky<usize>, &[f64]) {
        (&self.symbolic, &self.values)
    }

    /// Factorise `a`; fails if it is not positive definite.
    pub fn new(a: &SymBanded) -> crate::Result<Self> {
        let n = a.nrows();
        let triplets: Vec<Triplet<usize, usize, f64>> = a
            .lower_entries()
            .map(|(i, j, v)| Triplet::new(i, j, v))
            .collect();
        let csc = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &triplets)
            .map_err(|e| Error::numerical(format!("sparse matrix assembly failed: {e:?}")))?;
        let symbolic = factorize_symbolic_cholesky(
            csc.symbolic(),
            Side::Lower,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .map_err(|e| Error::numerical(format!("symbolic Cholesky failed: {e:?}")))?;
        let mut values = vec![0.0; symbolic.len_val()];
        let mut buf = MemBuffer::new(
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
        );
        symbolic
            .factorize_numeric_llt(
                &mut values,
                csc.as_ref(),
                Side::Lower,
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(&mut buf),
                Default::default(),
            )
            .map_err(|_| Error::numerical("matrix is not positive definite"))?;
        Ok(SparseCholesky { symbolic, values })
    }

    /// Dimension n.
    pub fn nrows(&self) -> usize {
        self.symbolic.nrows()
    }

    /// Stored non-zeros of the factor L.
    pub fn factor_nonzeros(&self) -> usize {
        self.values.len()
    }

    /// A scratch buffer for one right-hand side.
    pub fn scratch(&self) -> Scratch {
        Scratch(MemBuffer::new(
            self.symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
        ))
    }

    /// x ← A⁻¹ x, no allocation.
    pub fn solve_in_place(&self, x: &mut [f64], scratch: &mut Scratch) {
        let n = self.nrows();
        assert_eq!(x.len(), n, "dimension mismatch");
        let rhs = MatMut::from_column_major_slice_mut(x, n, 1);
        LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            rhs,
            Par::Seq,
            MemStack::new(&mut scratch.0),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DVector;

    /// The solve against a dense solve of the same SPD band matrix (block-decoupled, as a
    /// span is, so the ordering has something to do).
    #[test]
    fn solve_matches_dense() {
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
        let f = SparseCholesky::new(&a).unwrap();
        let b = DVector::from_fn(n, |i, _| (i as f64).cos());
        let want = a.to_dense().cholesky().unwrap().solve(&b);
        let mut x = b.clone();
        f.solve_in_place(x.as_mut_slice(), &mut f.scratch());
        assert!((x - &want).norm() <= 1e-13 * want.norm());
        let mut bad = SymBanded::zeros(2, 1);
        bad.add_lower(0, 0, 1.0);
        bad.add_lower(1, 0, 2.0);
        bad.add_lower(1, 1, 1.0);
        assert!(SparseCholesky::new(&bad).is_err());
    }
}
