//! Frequency responses `F·(sI − A)⁻¹·B` at many points `s` through one sparse LU per point.
//!
//! Why: the margins ([`super::margins`]) and the disk margin ([`super::multiloop`]) evaluate a
//! vehicle's loops at a thousand frequencies and more. A vehicle's state matrix is sparse (a
//! Fig. 6 carriage: 370 states, 2023 nonzeros: each magnet's coil touches its own node, each
//! node its frame), so `sI − A` is factorised as a sparse matrix, its pattern analysed once
//! (faer's column-ordered LU with partial pivoting, `faer::sparse::linalg::lu`), the values
//! refilled at each `s`. One factorisation serves every input column: all of a vehicle's
//! loops at one frequency cost one LU and one sparse solve each ([`Resolvent::diagonal_at`]).
//! The tests hold it to the dense solve.

use faer::c64;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, NumericLu, SymbolicLu};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, Par};
use nalgebra::{Complex, DMatrix};
use std::cell::RefCell;

/// The frequency grid (rad/s): 100 points a decade from 1e-2 to 1e6.
pub(super) fn grid() -> Vec<f64> {
    (0..=800)
        .map(|i| 10f64.powf(-2.0 + i as f64 / 100.0))
        .collect()
}

/// `F·(sI − A)⁻¹·B` for one `(A, B, F)` (module docs).
pub struct Resolvent {
    n: usize,
    /// `B` by columns and `F` by rows, their nonzeros as `(index, value)`.
    b: Vec<Vec<(usize, f64)>>,
    f: Vec<Vec<(usize, f64)>>,
    /// At each stored entry of `sI − A` (column-major, the pattern of `A` and the
    /// diagonal): `−A`'s value, and whether it is on the diagonal.
    neg_a: Vec<f64>,
    on_diagonal: Vec<bool>,
    symbolic: SymbolicLu<usize>,
    work: RefCell<Work>,
}

/// What one evaluation reuses: the matrix whose values are refilled, the numeric LU, the
/// right-hand sides and the scratch.
struct Work {
    matrix: SparseColMat<usize, c64>,
    numeric: NumericLu<usize, c64>,
    rhs: faer::Mat<c64>,
    scratch: MemBuffer,
}

impl std::fmt::Debug for Resolvent {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Resolvent")
            .field("states", &self.n)
            .field("inputs", &self.b.len())
            .field("outputs", &self.f.len())
            .finish()
    }
}

impl Resolvent {
    /// The analysis of `a` (n × n) with `b` (n × k) and `f` (m × n).
    pub fn new(a: &DMatrix<f64>, b: &DMatrix<f64>, f: &DMatrix<f64>) -> Self {
        let n = a.nrows();
        let mut triplets = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let v = a[(i, j)];
                if i == j || v != 0.0 {
                    triplets.push(Triplet::new(i, j, c64::new(-v, 0.0)));
                }
            }
        }
        let matrix = SparseColMat::try_new_from_triplets(n, n, &triplets)
            .expect("internal: distinct in-range triplets make a sparse matrix");
        let nonzeros = |v: &mut dyn Iterator<Item = f64>| -> Vec<(usize, f64)> {
            v.enumerate().filter(|(_, x)| *x != 0.0).collect()
        };
        let b = b
            .column_iter()
            .map(|c| nonzeros(&mut c.iter().copied()))
            .collect();
        let f = f
            .row_iter()
            .map(|r| nonzeros(&mut r.iter().copied()))
            .collect();
        Self::new_sparse(n, b, f, matrix)
    }

    /// [`Self::new`] from `sI − A` at `s = 0` as a sparse matrix.
    fn new_sparse(
        n: usize,
        b: Vec<Vec<(usize, f64)>>,
        f: Vec<Vec<(usize, f64)>>,
        matrix: SparseColMat<usize, c64>,
    ) -> Self {
        let (col_ptr, row_idx) = (matrix.symbolic().col_ptr(), matrix.symbolic().row_idx());
        let mut on_diagonal = vec![false; row_idx.len()];
        for j in 0..n {
            for e in col_ptr[j]..col_ptr[j + 1] {
                on_diagonal[e] = row_idx[e] == j;
            }
        }
        let neg_a = matrix.val().iter().map(|v| v.re).collect();
        let symbolic = factorize_symbolic_lu(matrix.symbolic(), Default::default())
            .expect("internal: the symbolic LU of a square pattern with its diagonal");
        let k = b.len();
        let scratch = MemBuffer::new(
            symbolic
                .factorize_numeric_lu_scratch::<c64>(Par::Seq, Default::default())
                .or(symbolic.solve_in_place_scratch::<c64>(k.max(1), Par::Seq)),
        );
        Resolvent {
            n,
            b,
            f,
            neg_a,
            on_diagonal,
            symbolic,
            work: RefCell::new(Work {
                matrix,
                numeric: NumericLu::new(),
                rhs: faer::Mat::zeros(n, k),
                scratch,
            }),
        }
    }

    /// `(sI − A)⁻¹·B` (n × k) into the work's right-hand sides, only the columns `cols`;
    /// false where `sI − A` is singular to working precision.
    fn solve(&self, work: &mut Work, s: Complex<f64>, cols: std::ops::Range<usize>) -> bool {
        let s = c64::new(s.re, s.im);
        for ((v, &a), &d) in work
            .matrix
            .val_mut()
            .iter_mut()
            .zip(&self.neg_a)
            .zip(&self.on_diagonal)
        {
            *v = if d { s + a } else { c64::new(a, 0.0) };
        }
        let Work {
            matrix,
            numeric,
            rhs,
            scratch,
        } = work;
        let Ok(lu) = self.symbolic.factorize_numeric_lu(
            numeric,
            matrix.as_ref(),
            Par::Seq,
            MemStack::new(scratch),
            Default::default(),
        ) else {
            return false;
        };
        for j in cols.clone() {
            rhs.col_mut(j).fill(c64::new(0.0, 0.0));
            for &(i, v) in &self.b[j] {
                rhs[(i, j)] = c64::new(v, 0.0);
            }
        }
        lu.solve_in_place_with_conj(
            Conj::No,
            rhs.as_mut().subcols_mut(cols.start, cols.len()),
            Par::Seq,
            MemStack::new(scratch),
        );
        true
    }

    /// `F·(sI − A)⁻¹·B` (m × k); `None` where `sI − A` is singular to working precision.
    pub fn at(&self, s: Complex<f64>) -> Option<DMatrix<Complex<f64>>> {
        let work = &mut *self.work.borrow_mut();
        let k = self.b.len();
        if !self.solve(work, s, 0..k) {
            return None;
        }
        let x = &work.rhs;
        let out = DMatrix::from_fn(self.f.len(), k, |r, j| self.output(x, r, j));
        finite(out)
    }

    /// The diagonal of `F·(sI − A)⁻¹·B` (square: m = k), or its entry `j` alone
    /// (`only = Some(j)`, a one-element vector); `None` where `sI − A` is singular to working
    /// precision.
    pub fn diagonal_at(&self, s: Complex<f64>, only: Option<usize>) -> Option<Vec<Complex<f64>>> {
        let work = &mut *self.work.borrow_mut();
        let cols = only.map_or(0..self.b.len(), |j| j..j + 1);
        if !self.solve(work, s, cols.clone()) {
            return None;
        }
        let x = &work.rhs;
        let out: Vec<Complex<f64>> = cols.map(|j| self.output(x, j, j)).collect();
        out.iter()
            .all(|v| v.re.is_finite() && v.im.is_finite())
            .then_some(out)
    }
}

impl Resolvent {
    /// Output `r` of the solved column `j`: `F_r·x_j`.
    fn output(&self, x: &faer::Mat<c64>, r: usize, j: usize) -> Complex<f64> {
        let v = self.f[r]
            .iter()
            .fold(c64::new(0.0, 0.0), |a, &(c, f)| a + x[(c, j)] * f);
        Complex::new(v.re, v.im)
    }
}

/// `m` where every entry is finite.
fn finite(m: DMatrix<Complex<f64>>) -> Option<DMatrix<Complex<f64>>> {
    m.iter()
        .all(|v: &Complex<f64>| v.re.is_finite() && v.im.is_finite())
        .then_some(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fixed, non-symmetric test system (deterministic entries).
    fn system(n: usize, k: usize, m: usize) -> (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>) {
        let v = |i: usize, j: usize, seed: f64| ((i * 7 + j * 13) as f64 * seed).sin();
        (
            DMatrix::from_fn(n, n, |i, j| v(i, j, 0.37) * if i == j { 5.0 } else { 1.0 }),
            DMatrix::from_fn(n, k, |i, j| v(i, j, 1.91)),
            DMatrix::from_fn(m, n, |i, j| v(i, j, 0.73)),
        )
    }

    /// The sparse LU gives the dense solve's response to 1e-11 relative, at points on the
    /// imaginary axis and off it, for one input and for several.
    #[test]
    fn the_sparse_response_is_the_dense_solve() {
        for (n, k, m) in [(1, 1, 1), (6, 1, 1), (23, 4, 3)] {
            let (a, b, f) = system(n, k, m);
            let r = Resolvent::new(&a, &b, &f);
            for s in [
                Complex::new(0.0, 0.01),
                Complex::new(0.0, 3.0),
                Complex::new(0.0, 1e4),
                Complex::new(-0.5, 2.0),
            ] {
                let dense = DMatrix::from_fn(n, n, |i, j| {
                    let d = if i == j { s } else { Complex::new(0.0, 0.0) };
                    d - a[(i, j)]
                });
                let x = dense.lu().solve(&b.map(|v| Complex::new(v, 0.0))).unwrap();
                let want = f.map(|v| Complex::new(v, 0.0)) * x;
                let got = r.at(s).unwrap();
                let scale = want.iter().map(|v| v.norm()).fold(0.0, f64::max);
                let err = (&got - &want).iter().map(|v| v.norm()).fold(0.0, f64::max);
                assert!(err <= 1e-11 * scale, "n {n}, s {s}: {err:e} of {scale:e}");
            }
        }
    }

    /// The diagonal, whole and one entry at a time, is the full response's diagonal to
    /// 1e-13 relative (the same factorisation; one column solved or all).
    #[test]
    fn the_diagonal_is_the_full_response_s_diagonal() {
        let (a, b, f) = system(17, 5, 5);
        let r = Resolvent::new(&a, &b, &f);
        for s in [Complex::new(0.0, 0.3), Complex::new(0.0, 40.0)] {
            let full = r.at(s).unwrap();
            let diag = r.diagonal_at(s, None).unwrap();
            for (j, d) in diag.iter().enumerate() {
                let one = r.diagonal_at(s, Some(j)).unwrap()[0];
                let want = full[(j, j)];
                assert!(
                    (d - want).norm() <= 1e-13 * want.norm(),
                    "{j}: {d} vs {want}"
                );
                assert!(
                    (one - want).norm() <= 1e-13 * want.norm(),
                    "{j}: {one} vs {want}"
                );
            }
        }
    }

    /// At an eigenvalue of `A` the response is singular: `None`, not a huge number.
    #[test]
    fn at_a_pole_there_is_no_response() {
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, -2.0]);
        let r = Resolvent::new(&a, &DMatrix::identity(2, 1), &DMatrix::identity(1, 2));
        assert!(r.at(Complex::new(0.0, 0.0)).is_none());
        assert!(r.at(Complex::new(-2.0, 0.0)).is_none());
        assert!(r.at(Complex::new(0.0, 1.0)).is_some());
    }
}
