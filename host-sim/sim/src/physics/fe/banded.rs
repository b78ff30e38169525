//! [`SymBanded`]: a symmetric matrix stored by its lower band, for the span stiffness, mass
//! and damping.
//!
//! Why banded: a span's DOFs are numbered node by node, and an element couples only its two
//! nodes, so every non-zero of K, M (and a Rayleigh C) lies within 2·6 − 1 = 11 of the
//! diagonal. Band storage is O(n·b) memory and the products the Newmark right-hand side needs
//! cost O(n·b), where the dense matrices were O(n²) in both (2.9 TB at 100 000 elements).
//! The factorisation of the effective stiffness is not done here but by a sparse Cholesky
//! with a fill-reducing ordering ([`super::cholesky`]) or over the decoupled DOF families
//! ([`super::component_band`]).
//!
//! Within the band most entries are structural zeros (the axial, lateral, vertical and
//! torsion DOFs of a node are uncoupled): [`SymSparse`] keeps only the non-zeros, both
//! triangles row by row, for the product in the time loop, ≈ 4 per row instead of the band's
//! 23.

use nalgebra::{DMatrix, DVector};

/// A symmetric n×n matrix with half-bandwidth `b` (A[i][j] = 0 for |i − j| > b), stored as
/// its lower band column by column: entry (i, j), j ≤ i ≤ j + b, at `j·(b + 1) + (i − j)`.
#[derive(Clone, Debug, PartialEq)]
pub struct SymBanded {
    n: usize,
    b: usize,
    data: Vec<f64>,
}

/// The value of every entry outside the band.
static ZERO: f64 = 0.0;

impl SymBanded {
    /// The n×n zero matrix with half-bandwidth `b`.
    pub fn zeros(n: usize, b: usize) -> Self {
        SymBanded {
            n,
            b,
            data: vec![0.0; n * (b + 1)],
        }
    }

    /// Dimension n.
    pub fn nrows(&self) -> usize {
        self.n
    }

    /// Half-bandwidth b.
    pub fn bandwidth(&self) -> usize {
        self.b
    }

    fn slot(&self, i: usize, j: usize) -> Option<usize> {
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        (i < self.n && i - j <= self.b).then(|| j * (self.b + 1) + (i - j))
    }

    /// Entry (i, j) (zero outside the band).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.slot(i, j).map_or(0.0, |s| self.data[s])
    }

    /// Add `v` to entry (i, j) and, by symmetry, (j, i). Call it for the lower triangle
    /// (i ≥ j) only, or for both triangles with half the value; panics outside the band.
    pub fn add_lower(&mut self, i: usize, j: usize, v: f64) {
        assert!(i >= j, "add_lower({i}, {j}): not in the lower triangle");
        let s = self
            .slot(i, j)
            .unwrap_or_else(|| panic!("({i}, {j}) is outside the band {}", self.b));
        self.data[s] += v;
    }

    /// y ← y + α·A·x (symmetric band product, no allocation).
    pub fn mul_acc(&self, alpha: f64, x: &[f64], y: &mut [f64]) {
        let (n, b) = (self.n, self.b);
        assert!(x.len() == n && y.len() == n, "dimension mismatch");
        let w = b + 1;
        for j in 0..n {
            let col = &self.data[j * w..j * w + w];
            let xj = alpha * x[j];
            // Diagonal, then the lower entries (i > j) and their mirror (j, i).
            let mut acc = col[0] * xj;
            let end = (j + b).min(n - 1);
            for (k, i) in (j + 1..=end).enumerate() {
                let a = col[k + 1];
                y[i] += a * xj;
                acc += a * alpha * x[i];
            }
            y[j] += acc;
        }
    }

    /// α·self + β·other, both of the same size (the result has the larger bandwidth).
    pub fn combine(&self, alpha: f64, other: &SymBanded, beta: f64) -> SymBanded {
        assert_eq!(self.n, other.n, "dimension mismatch");
        let b = self.b.max(other.b);
        let mut out = SymBanded::zeros(self.n, b);
        for j in 0..self.n {
            for i in j..(j + b + 1).min(self.n) {
                let v = alpha * self.get(i, j) + beta * other.get(i, j);
                if v != 0.0 {
                    out.add_lower(i, j, v);
                }
            }
        }
        out
    }

    /// The structural non-zeros of the lower triangle, column by column: (i, j, value), i ≥ j.
    pub fn lower_entries(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        let w = self.b + 1;
        (0..self.n).flat_map(move |j| {
            (j..(j + w).min(self.n))
                .map(move |i| (i, j, self.data[j * w + i - j]))
                .filter(|&(_, _, v)| v != 0.0)
        })
    }

    /// The decoupled components of the matrix graph (union-find over the stored non-zeros).
    /// A straight span's axial, torsion and two bending families come out as four.
    pub fn components(&self) -> Components {
        let n = self.n;
        let mut parent: Vec<usize> = (0..n).collect();
        fn root(parent: &mut [usize], mut i: usize) -> usize {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        }
        for (i, j, _) in self.lower_entries() {
            let (ri, rj) = (root(&mut parent, i), root(&mut parent, j));
            if ri != rj {
                parent[ri.max(rj)] = ri.min(rj);
            }
        }
        let mut members: Vec<Vec<usize>> = Vec::new();
        let mut index_of_root = vec![usize::MAX; n];
        for i in 0..n {
            let r = root(&mut parent, i);
            if index_of_root[r] == usize::MAX {
                index_of_root[r] = members.len();
                members.push(Vec::new());
            }
            members[index_of_root[r]].push(i);
        }
        Components::from_members(members)
    }

    /// A dense copy (for small systems and checks only: O(n²) memory).
    pub fn to_dense(&self) -> DMatrix<f64> {
        DMatrix::from_fn(self.n, self.n, |i, j| self.get(i, j))
    }
}

/// Decoupled components of a matrix's DOFs ([`SymBanded::components`]): each component's
/// members in ascending order, components in order of their first member, and for each DOF
/// its component and its index within it. The one description the component solvers and
/// products ([`super::component_band`], [`ComponentProduct`], [`super::flexibility`]) share.
#[derive(Clone, Debug, PartialEq)]
pub struct Components {
    pub members: Vec<Vec<usize>>,
    pub component: Vec<usize>,
    pub local: Vec<usize>,
}

impl Components {
    /// From the members of each component (together, every DOF `0..n` once).
    pub fn from_members(members: Vec<Vec<usize>>) -> Self {
        let n = members.iter().map(Vec::len).sum();
        let (mut component, mut local) = (vec![usize::MAX; n], vec![0; n]);
        for (c, m) in members.iter().enumerate() {
            for (k, &i) in m.iter().enumerate() {
                component[i] = c;
                local[i] = k;
            }
        }
        Components {
            members,
            component,
            local,
        }
    }

    /// Number of DOFs.
    pub fn dofs(&self) -> usize {
        self.component.len()
    }
}

/// The non-zeros of a symmetric matrix, both triangles, row by row (for products): each row
/// a dot product over `(column, value)` pairs, no scatter.
#[derive(Clone, Debug, PartialEq)]
pub struct SymSparse {
    n: usize,
    row_start: Vec<usize>,
    entries: Vec<(usize, f64)>,
}

impl SymSparse {
    /// The non-zeros of `a`.
    pub fn new(a: &SymBanded) -> Self {
        let mut rows: Vec<Vec<(usize, f64)>> = vec![Vec::new(); a.n];
        for (i, j, v) in a.lower_entries() {
            rows[i].push((j, v));
            if i != j {
                rows[j].push((i, v));
            }
        }
        let mut row_start = Vec::with_capacity(a.n + 1);
        let mut entries = Vec::new();
        row_start.push(0);
        for mut r in rows {
            r.sort_by_key(|&(j, _)| j);
            entries.extend(r);
            row_start.push(entries.len());
        }
        SymSparse {
            n: a.n,
            row_start,
            entries,
        }
    }

    /// Dimension n.
    pub fn nrows(&self) -> usize {
        self.n
    }

    /// Stored non-zeros (both triangles).
    pub fn nonzeros(&self) -> usize {
        self.entries.len()
    }

    /// y ← y + A·x (no allocation).
    pub fn mul_acc(&self, x: &[f64], y: &mut [f64]) {
        assert!(x.len() == self.n && y.len() == self.n, "dimension mismatch");
        for (yi, r) in y.iter_mut().zip(self.row_start.windows(2)) {
            let mut acc = 0.0;
            for &(j, a) in &self.entries[r[0]..r[1]] {
                acc += a * x[j];
            }
            *yi += acc;
        }
    }
}

/// The widest half-bandwidth (in a component's own numbering) [`ComponentProduct`] takes.
pub const PRODUCT_MAX_BAND: usize = 6;

/// Symmetric matrices over one set of decoupled components (as from
/// [`SymBanded::components`]), each row a dense band of `2b + 1` values in its component's
/// own ascending numbering, multiplied from a vector laid out component by component with
/// `b` zeros around each: the span's mass and damping products in the time loop.
///
/// Why: a row is then a fixed-length dot over contiguous memory with no index loads, where
/// [`SymSparse`] loads an index per entry. The terms are the row's non-zeros in ascending
/// column order (a component's members ascend), interleaved with exact zeros (padding and
/// zeros inside the band): the sum is [`SymSparse::mul_acc`]'s, bit for bit (the
/// accumulator starts at +0 and never becomes −0, so adding ±0 changes nothing).
#[derive(Clone, Debug, PartialEq)]
pub struct ComponentProduct {
    b: usize,
    /// Original index of each slot (the components' members in order).
    orig: Vec<usize>,
    /// Position of each slot in the padded layout.
    pos: Vec<usize>,
    /// Length of the padded layout.
    len: usize,
    /// Per matrix, per slot: the band row (local columns k − b ..= k + b).
    rows: Vec<Vec<f64>>,
}

impl ComponentProduct {
    /// The layout of `components` for `mats` (every matrix's non-zeros must lie within the
    /// components); `None` if some row is wider than [`PRODUCT_MAX_BAND`] in its component.
    pub fn new(components: &Components, mats: &[&SymBanded]) -> Option<Self> {
        let n = components.dofs();
        let (comp, local) = (&components.component, &components.local);
        let mut b = 1;
        for a in mats {
            assert_eq!(a.nrows(), n, "dimension mismatch");
            for (i, j, _) in a.lower_entries() {
                if comp[i] != comp[j] {
                    return None;
                }
                b = b.max(local[i].abs_diff(local[j]));
            }
        }
        if b > PRODUCT_MAX_BAND {
            return None;
        }
        let w = 2 * b + 1;
        let (mut orig, mut pos) = (Vec::with_capacity(n), Vec::with_capacity(n));
        let mut next = b;
        for members in &components.members {
            for &i in members {
                orig.push(i);
                pos.push(next);
                next += 1;
            }
            next += b;
        }
        let rows = mats
            .iter()
            .map(|a| {
                let mut r = vec![0.0; n * w];
                for (s, &i) in orig.iter().enumerate() {
                    let members = &components.members[comp[i]];
                    for t in 0..w {
                        let l = (local[i] + t).checked_sub(b);
                        if let Some(&j) = l.and_then(|l| members.get(l)) {
                            r[s * w + t] = a.get(i, j);
                        }
                    }
                }
                r
            })
            .collect();
        Some(ComponentProduct {
            b,
            orig,
            pos,
            len: next,
            rows,
        })
    }

    /// Length of the padded vectors [`Self::mul_acc`] reads.
    pub fn padded_len(&self) -> usize {
        self.len
    }

    /// Stored values.
    pub fn stored(&self) -> usize {
        self.rows.iter().map(Vec::len).sum()
    }

    /// `out[pos(s)] = f(orig(s))` for every slot: a vector into the padded layout (the padding
    /// is never written, so it stays as the caller made it: zero).
    pub fn scatter(&self, out: &mut [f64], mut f: impl FnMut(usize) -> f64) {
        for (&p, &i) in self.pos.iter().zip(&self.orig) {
            out[p] = f(i);
        }
    }

    /// y ← y + A_k·x for matrix `k` of [`Self::new`], x in the padded layout (no allocation).
    pub fn mul_acc(&self, k: usize, x: &[f64], y: &mut [f64]) {
        assert!(x.len() == self.len, "dimension mismatch");
        match self.b {
            1 => self.mul::<1>(k, x, y),
            2 => self.mul::<2>(k, x, y),
            3 => self.mul::<3>(k, x, y),
            4 => self.mul::<4>(k, x, y),
            5 => self.mul::<5>(k, x, y),
            _ => self.mul::<PRODUCT_MAX_BAND>(k, x, y),
        }
    }

    fn mul<const B: usize>(&self, k: usize, x: &[f64], y: &mut [f64]) {
        let w = 2 * B + 1;
        for ((&p, &i), row) in self
            .pos
            .iter()
            .zip(&self.orig)
            .zip(self.rows[k].chunks_exact(w))
        {
            let xs = &x[p - B..p + B + 1];
            let mut acc = 0.0;
            for t in 0..w {
                acc += row[t] * xs[t];
            }
            y[i] += acc;
        }
    }
}

impl core::ops::Index<(usize, usize)> for SymBanded {
    type Output = f64;
    fn index(&self, (i, j): (usize, usize)) -> &f64 {
        assert!(i < self.n && j < self.n, "index ({i}, {j}) out of range");
        self.slot(i, j).map_or(&ZERO, |s| &self.data[s])
    }
}

impl core::ops::Mul<&DVector<f64>> for &SymBanded {
    type Output = DVector<f64>;
    fn mul(self, x: &DVector<f64>) -> DVector<f64> {
        let mut y = DVector::zeros(self.n);
        self.mul_acc(1.0, x.as_slice(), y.as_mut_slice());
        y
    }
}

impl core::ops::Mul<DVector<f64>> for &SymBanded {
    type Output = DVector<f64>;
    fn mul(self, x: DVector<f64>) -> DVector<f64> {
        self * &x
    }
}

/// A symmetric matrix that can be copied to dense storage, for the dense integrator
/// ([`super::Newmark`]) of small systems.
pub trait ToDense {
    fn to_dense_matrix(&self) -> DMatrix<f64>;
}

impl ToDense for DMatrix<f64> {
    fn to_dense_matrix(&self) -> DMatrix<f64> {
        self.clone()
    }
}

impl ToDense for SymBanded {
    fn to_dense_matrix(&self) -> DMatrix<f64> {
        self.to_dense()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The component-band product gives the row lists' bits, on the §4.2 span's M and a
    /// Rayleigh C (20 elements) for vectors over seven decades with exact zeros among them;
    /// a matrix coupling two components is refused.
    #[test]
    fn component_product_gives_the_bits_of_the_row_lists() {
        let model = crate::physics::fe::SpanModel::new(
            &crate::physics::guideway::BeamSection::paper_4_2(),
            25.0,
            20,
        )
        .unwrap();
        let c = model.m.combine(0.3, &model.k, 2e-4);
        let keff = model.k.combine(1.0, &model.m, 4e6);
        let components = keff.components();
        let bands = ComponentProduct::new(&components, &[&model.m, &c]).unwrap();
        let n = model.m.nrows();
        let mut seed = 0x2545_F491_4F6C_DD1Du64;
        for _ in 0..20 {
            let x: Vec<f64> = (0..n)
                .map(|_| {
                    seed ^= seed << 13;
                    seed ^= seed >> 7;
                    seed ^= seed << 17;
                    let u = (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                    if seed.is_multiple_of(5) {
                        0.0
                    } else {
                        u * 10f64.powi((seed % 7) as i32 - 3)
                    }
                })
                .collect();
            let mut padded = vec![0.0; bands.padded_len()];
            bands.scatter(&mut padded, |i| x[i]);
            for (k, a) in [&model.m, &c].into_iter().enumerate() {
                let (mut want, mut got) = (vec![0.0; n], vec![0.0; n]);
                SymSparse::new(a).mul_acc(&x, &mut want);
                bands.mul_acc(k, &padded, &mut got);
                for i in 0..n {
                    assert_eq!(got[i].to_bits(), want[i].to_bits(), "matrix {k}, row {i}");
                }
            }
        }
        let mut coupled = SymBanded::zeros(4, 1);
        for j in 0..4 {
            coupled.add_lower(j, j, 2.0);
        }
        coupled.add_lower(1, 0, 0.5);
        let split = Components::from_members(vec![vec![0, 2], vec![1, 3]]);
        assert!(ComponentProduct::new(&split, &[&coupled]).is_none());
    }

    /// The band product against the dense product of the same entries, for a band that is
    /// wider than, equal to and narrower than n.
    #[test]
    fn band_product_matches_dense() {
        for (n, b) in [(7, 2), (5, 4), (3, 6), (1, 0)] {
            let mut a = SymBanded::zeros(n, b.min(n.max(1) - 1));
            for j in 0..n {
                for i in j..(j + a.bandwidth() + 1).min(n) {
                    a.add_lower(i, j, 1.0 + (3 * i + 7 * j) as f64 * 0.1);
                }
            }
            let x = DVector::from_fn(n, |i, _| (i as f64 * 0.7).sin() + 0.2);
            let want = a.to_dense() * &x;
            let got = &a * &x;
            assert!((got - &want).norm() <= 1e-14 * want.norm(), "n={n} b={b}");
            let mut sparse = DVector::zeros(n);
            SymSparse::new(&a).mul_acc(x.as_slice(), sparse.as_mut_slice());
            assert!(
                (sparse - &want).norm() <= 1e-14 * want.norm(),
                "n={n} b={b}"
            );
            assert_eq!(a[(0, n - 1)], a[(n - 1, 0)]);
        }
    }

    #[test]
    fn combine_and_entries() {
        let mut a = SymBanded::zeros(4, 1);
        let mut c = SymBanded::zeros(4, 2);
        a.add_lower(1, 0, 2.0);
        c.add_lower(2, 0, 3.0);
        let s = a.combine(2.0, &c, 0.5);
        assert_eq!(s.bandwidth(), 2);
        assert_eq!((s.get(0, 1), s.get(0, 2), s.get(3, 0)), (4.0, 1.5, 0.0));
        let e: Vec<_> = s.lower_entries().collect();
        assert_eq!(e, vec![(1, 0, 4.0), (2, 0, 1.5)]);
    }
}
