//! Frequency responses `F·(sI − A)⁻¹·B` at many points `s` through one Hessenberg reduction.
//!
//! Why: the margins ([`super::margins`]) and the disk margin ([`super::multiloop`]) evaluate a
//! loop at a thousand frequencies and more, and a dense LU of `sI − A` at each is `O(n³)`. With
//! `A = Q·H·Qᵀ` (`Q` orthogonal, `H` upper Hessenberg, once), `F·(sI − A)⁻¹·B =
//! (F·Q)·(sI − H)⁻¹·(Qᵀ·B)`, and `sI − H` is solved by Gaussian elimination with partial
//! pivoting between neighbouring rows in `O(n²)` (A.J. Laub, "Efficient multivariable
//! frequency response computations", IEEE Trans. Automatic Control 26(2) (1981) 407–408).
//! The tests hold it to the dense solve.

use nalgebra::{Complex, DMatrix};

/// The frequency grid (rad/s): 100 points a decade from 1e-2 to 1e6.
pub(super) fn grid() -> Vec<f64> {
    (0..=800)
        .map(|i| 10f64.powf(-2.0 + i as f64 / 100.0))
        .collect()
}

/// `F·(sI − A)⁻¹·B` for one `(A, B, F)` (module docs).
#[derive(Clone, Debug)]
pub struct Resolvent {
    /// `H`, upper Hessenberg (n × n).
    h: DMatrix<f64>,
    /// `Qᵀ·B` (n × k).
    qb: DMatrix<f64>,
    /// `F·Q` (m × n).
    fq: DMatrix<f64>,
}

impl Resolvent {
    /// The reduction of `a` (n × n) with `b` (n × k) and `f` (m × n).
    pub fn new(a: &DMatrix<f64>, b: &DMatrix<f64>, f: &DMatrix<f64>) -> Self {
        let (q, h) = a.clone().hessenberg().unpack();
        Resolvent {
            qb: q.transpose() * b,
            fq: f * &q,
            h,
        }
    }

    /// `F·(sI − A)⁻¹·B` (m × k); `None` where `sI − A` is singular to working precision.
    pub fn at(&self, s: Complex<f64>) -> Option<DMatrix<Complex<f64>>> {
        let n = self.h.nrows();
        let k = self.qb.ncols();
        let zero = Complex::new(0.0, 0.0);
        // Row-major sI − H on and above the subdiagonal.
        let mut m = vec![zero; n * n];
        for i in 0..n {
            for j in i.saturating_sub(1)..n {
                let d = if i == j { s } else { zero };
                m[i * n + j] = d - self.h[(i, j)];
            }
        }
        let mut x: Vec<Complex<f64>> = (0..n * k)
            .map(|r| Complex::new(self.qb[(r / k, r % k)], 0.0))
            .collect();
        for c in 0..n.saturating_sub(1) {
            if m[(c + 1) * n + c].norm() > m[c * n + c].norm() {
                for j in c..n {
                    m.swap(c * n + j, (c + 1) * n + j);
                }
                for j in 0..k {
                    x.swap(c * k + j, (c + 1) * k + j);
                }
            }
            let pivot = m[c * n + c];
            if pivot == zero {
                return None;
            }
            let l = m[(c + 1) * n + c] / pivot;
            for j in c..n {
                let v = m[c * n + j];
                m[(c + 1) * n + j] -= l * v;
            }
            for j in 0..k {
                let v = x[c * k + j];
                x[(c + 1) * k + j] -= l * v;
            }
        }
        for i in (0..n).rev() {
            let d = m[i * n + i];
            if d == zero {
                return None;
            }
            for j in 0..k {
                let mut acc = x[i * k + j];
                for c in i + 1..n {
                    acc -= m[i * n + c] * x[c * k + j];
                }
                x[i * k + j] = acc / d;
            }
        }
        let out: DMatrix<Complex<f64>> = DMatrix::from_fn(self.fq.nrows(), k, |r, j| {
            (0..n).map(|c| x[c * k + j] * self.fq[(r, c)]).sum()
        });
        out.iter()
            .all(|v: &Complex<f64>| v.re.is_finite() && v.im.is_finite())
            .then_some(out)
    }
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

    /// The reduction gives the dense solve's response to 1e-11 relative, at points on the
    /// imaginary axis and off it, for one input and for several.
    #[test]
    fn the_hessenberg_response_is_the_dense_solve() {
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
