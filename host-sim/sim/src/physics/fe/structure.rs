//! [`Structure`]: a general 3-D frame of beam elements, six-DOF springs and dashpots and
//! lumped masses, assembled into banded K, M and C (the dashpots), with its natural modes.
//!
//! Why a general frame beside [`super::SpanModel`]: a viaduct's girders, bearings, piers and
//! foundations are coupled (the spans interact through the piers), so the structure is no
//! longer block-diagonal over spans. Nodes are numbered along the track (pier, girder, pier,
//! …), so every coupling is between nearby nodes and the matrices stay banded; the
//! effective stiffness is factorised by the same sparse Cholesky ([`super::cholesky`]).
//!
//! Elements: [`element`]'s Timoshenko beam, either along X (girders) or along Z (piers: local
//! x = global Z, local y = global Y, local z = −X, so the section's `iz` bends the pier
//! laterally, in the Y–Z plane, and `iy` longitudinally, in the X–Z plane). Springs join two
//! nodes through a rigid offset on the first (a bearing below a girder's centroid), or a
//! node to the ground (a foundation).
//!
//! Modes: a dense solve for small models ([`dense_modes`]) and block subspace iteration with
//! Rayleigh–Ritz on the sparse factor of K for large ones ([`lowest_modes`]); both classify
//! a mode by the family with the largest kinetic-energy share, as [`super::modes`] does.

use super::assembly::DofFamily;
use super::banded::{SymBanded, SymSparse};
use super::cholesky::SparseCholesky;
use super::element;
use super::modes::{Mode, ModeKind};
use crate::physics::guideway::BeamSection;
use crate::Error;
use maglev_core::gap::{dof, DOFS_PER_NODE, ELEMENT_DOFS};
use nalgebra::{Cholesky, DMatrix, DVector, SymmetricEigen};

/// How a node's DOFs count for mode classification.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NodeKind {
    /// On a girder (axis along X): u axial, (v, θz) lateral, (w, θy) vertical, θx torsion.
    Girder,
    /// On a pier (axis along Z): (u, θy) longitudinal, (v, θx) lateral, w vertical, θz the
    /// pier's own twist.
    Pier,
}

impl NodeKind {
    fn family(self, d: usize) -> DofFamily {
        match self {
            NodeKind::Girder => DofFamily::of(d),
            NodeKind::Pier => match d {
                dof::U | dof::RY => DofFamily::Axial,
                dof::V | dof::RX => DofFamily::BendingY,
                dof::W => DofFamily::BendingZ,
                _ => DofFamily::Torsion,
            },
        }
    }
}

/// Orientation of a beam element.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// Along +X (first node at the smaller X).
    X,
    /// Along +Z (first node at the lower end).
    Z,
}

/// Collects the entries of K, M and C (lower triangles) node by node.
#[derive(Debug, Default)]
pub struct Builder {
    kinds: Vec<NodeKind>,
    k: Vec<(usize, usize, f64)>,
    m: Vec<(usize, usize, f64)>,
    c: Vec<(usize, usize, f64)>,
}

fn push(list: &mut Vec<(usize, usize, f64)>, i: usize, j: usize, v: f64) {
    if v != 0.0 && i >= j {
        list.push((i, j, v));
    }
}

/// The 3×3 rotation global → local of an element along `axis`.
fn rotation(axis: Axis) -> [[f64; 3]; 3] {
    match axis {
        Axis::X => [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        Axis::Z => [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]],
    }
}

impl Builder {
    /// A new node; returns its index.
    pub fn node(&mut self, kind: NodeKind) -> usize {
        self.kinds.push(kind);
        self.kinds.len() - 1
    }

    /// A Timoshenko element of length `l` from node `a` to node `b` along `axis`.
    pub fn beam(&mut self, a: usize, b: usize, axis: Axis, section: &BeamSection, l: f64) {
        let kl = element::stiffness(section, l);
        let ml = element::mass(section, l);
        let r = rotation(axis);
        // T (12×12) = blockdiag(R, R, R, R); K = Tᵀ K_l T.
        let t = DMatrix::from_fn(ELEMENT_DOFS, ELEMENT_DOFS, |i, j| {
            if i / 3 == j / 3 {
                r[i % 3][j % 3]
            } else {
                0.0
            }
        });
        let kg = t.transpose() * DMatrix::from_fn(12, 12, |i, j| kl[(i, j)]) * &t;
        let mg = t.transpose() * DMatrix::from_fn(12, 12, |i, j| ml[(i, j)]) * &t;
        let global = |i: usize| {
            let node = if i < DOFS_PER_NODE { a } else { b };
            node * DOFS_PER_NODE + i % DOFS_PER_NODE
        };
        for i in 0..ELEMENT_DOFS {
            for j in 0..ELEMENT_DOFS {
                let (gi, gj) = (global(i), global(j));
                push(&mut self.k, gi, gj, kg[(i, j)]);
                push(&mut self.m, gi, gj, mg[(i, j)]);
            }
        }
    }

    /// A six-DOF spring (stiffness `k` along u, v, w, θx, θy, θz, N/m and N·m/rad) between a
    /// point rigidly attached to node `a` at offset `(0, 0, −drop)` and node `b`: the point
    /// moves by (u − drop·θy, v + drop·θx, w) and node `a`'s rotations.
    pub fn spring(&mut self, a: usize, b: usize, drop: f64, k: [f64; 6]) {
        // B: 6 relative displacements × 12 DOFs (a then b).
        let mut bm = [[0.0f64; 12]; 6];
        for (d, row) in bm.iter_mut().enumerate() {
            row[d] = 1.0;
            row[6 + d] = -1.0;
        }
        bm[0][dof::RY] = -drop;
        bm[1][dof::RX] = drop;
        let global = |i: usize| {
            let node = if i < 6 { a } else { b };
            node * DOFS_PER_NODE + i % 6
        };
        for i in 0..12 {
            for j in 0..12 {
                let v: f64 = (0..6).map(|d| bm[d][i] * k[d] * bm[d][j]).sum();
                push(&mut self.k, global(i), global(j), v);
            }
        }
    }

    /// Springs `k` and dashpots `c` from node `a` to the ground, per DOF (u … θz).
    pub fn ground(&mut self, a: usize, k: [f64; 6], c: [f64; 6]) {
        for d in 0..6 {
            let i = a * DOFS_PER_NODE + d;
            push(&mut self.k, i, i, k[d]);
            push(&mut self.c, i, i, c[d]);
        }
    }

    /// A lumped mass `m` (translations) and rotary inertias `j` (about X, Y, Z) at node `a`.
    pub fn lumped(&mut self, a: usize, m: f64, j: [f64; 3]) {
        for (d, &jd) in j.iter().enumerate() {
            let i = a * DOFS_PER_NODE + d;
            push(&mut self.m, i, i, m);
            push(&mut self.m, i + 3, i + 3, jd);
        }
    }

    /// The assembled structure.
    pub fn finish(self) -> Structure {
        let n = self.kinds.len() * DOFS_PER_NODE;
        let band = self
            .k
            .iter()
            .chain(&self.m)
            .chain(&self.c)
            .map(|&(i, j, _)| i - j)
            .max()
            .unwrap_or(0);
        let to_band = |list: &[(usize, usize, f64)]| {
            let mut a = SymBanded::zeros(n, band);
            for &(i, j, v) in list {
                a.add_lower(i, j, v);
            }
            a
        };
        let families = (0..n)
            .map(|i| self.kinds[i / DOFS_PER_NODE].family(i % DOFS_PER_NODE))
            .collect();
        Structure {
            k: to_band(&self.k),
            m: to_band(&self.m),
            c: to_band(&self.c),
            families,
        }
    }
}

/// An assembled frame: stiffness, mass and (dashpot) damping on all DOFs, node by node.
#[derive(Clone, Debug)]
pub struct Structure {
    pub k: SymBanded,
    pub m: SymBanded,
    /// Discrete dashpots only (Rayleigh damping is added by the integrator).
    pub c: SymBanded,
    /// Family of each DOF, for mode classification.
    pub families: Vec<DofFamily>,
}

impl Structure {
    /// Number of DOFs.
    pub fn dofs(&self) -> usize {
        self.families.len()
    }

    /// Static displacements K d = f.
    pub fn solve_static(&self, f: &DVector<f64>) -> crate::Result<DVector<f64>> {
        let factor = SparseCholesky::new(&self.k)
            .map_err(|e| Error::numerical(format!("structure stiffness: {e}")))?;
        let mut d = f.clone();
        factor.solve_in_place(d.as_mut_slice(), &mut factor.scratch());
        Ok(d)
    }

    /// Classify and package a mass-normalised shape.
    fn mode(&self, omega: f64, phi: DVector<f64>, mphi: &DVector<f64>) -> Mode {
        let mut share = [0.0f64; 4];
        for (i, f) in self.families.iter().enumerate() {
            share[*f as usize] += phi[i] * mphi[i];
        }
        let best = (0..4).fold(0, |b, f| if share[f] > share[b] { f } else { b });
        let kind = [
            ModeKind::BendingZ,
            ModeKind::BendingY,
            ModeKind::Torsion,
            ModeKind::Axial,
        ][best];
        Mode {
            omega,
            frequency_hz: omega / (2.0 * std::f64::consts::PI),
            kind,
            shape: phi,
        }
    }
}

/// Largest model [`dense_modes`] accepts (the dense solve is O(n³)).
pub const MAX_DENSE_DOFS: usize = 3000;

/// All modes of a small structure by a dense generalized eigen-solve, ascending.
pub fn dense_modes(s: &Structure) -> crate::Result<Vec<Mode>> {
    let n = s.dofs();
    if n > MAX_DENSE_DOFS {
        return Err(Error::invalid(
            "structure",
            format!("the dense modal solve takes at most {MAX_DENSE_DOFS} DOFs, got {n}"),
        ));
    }
    let (k, m) = (s.k.to_dense(), s.m.to_dense());
    let (lambda, phi) = generalized(&k, &m)?;
    let mut modes: Vec<Mode> = (0..n)
        .map(|c| {
            let p = phi.column(c).into_owned();
            let mp = &m * &p;
            s.mode(lambda[c].max(0.0).sqrt(), p, &mp)
        })
        .collect();
    modes.sort_by(|a, b| a.omega.total_cmp(&b.omega));
    Ok(modes)
}

/// K φ = λ M φ, dense, M positive definite: eigenvalues and M-normalised vectors (columns).
fn generalized(k: &DMatrix<f64>, m: &DMatrix<f64>) -> crate::Result<(DVector<f64>, DMatrix<f64>)> {
    let l = Cholesky::new(m.clone())
        .ok_or_else(|| Error::numerical("mass matrix is not positive definite"))?
        .l();
    let singular = || Error::numerical("singular mass factor");
    let x = l.solve_lower_triangular(k).ok_or_else(singular)?;
    let a = l
        .solve_lower_triangular(&x.transpose())
        .ok_or_else(singular)?;
    let eig = SymmetricEigen::new((&a + a.transpose()) * 0.5);
    let phi = l
        .transpose()
        .solve_upper_triangular(&eig.eigenvectors)
        .ok_or_else(singular)?;
    Ok((eig.eigenvalues, phi))
}

/// The `count` lowest modes by block subspace iteration (Bathe's subspace method: Y = K⁻¹ M X,
/// Rayleigh–Ritz on span(Y)) with a block of `2·count + 8` vectors, iterated until every
/// wanted eigenvalue changes by less than `1e-12` relative. Never forms a dense n×n matrix:
/// memory O(n·block).
///
/// The iteration converges as (λ_count / λ_block+1)^k, so a cluster of nearly equal modes
/// wider than the block (a long viaduct: one mode of each family per span, 35 spans) barely
/// moves: with 12 modes of the 35-span paper-5 viaduct the change per iteration was still
/// 3e-8 after 1000 iterations. A block that has not converged in [`ITERATIONS_PER_BLOCK`]
/// iterations is therefore doubled (up to n, where Rayleigh–Ritz is exact) and the iteration
/// restarted; every case that converges in the first block is unchanged by this.
pub fn lowest_modes(s: &Structure, count: usize) -> crate::Result<Vec<Mode>> {
    let n = s.dofs();
    if count == 0 || count > n {
        return Err(Error::invalid(
            "count",
            format!("must be between 1 and {n} (DOFs), got {count}"),
        ));
    }
    let factor = SparseCholesky::new(&s.k)
        .map_err(|e| Error::numerical(format!("structure stiffness: {e}")))?;
    let (ks, ms) = (SymSparse::new(&s.k), SymSparse::new(&s.m));
    let mut p = (2 * count + 8).min(n);
    loop {
        if let Some(modes) = subspace(s, (&factor, &ks, &ms), count, p)? {
            return Ok(modes);
        }
        if p == n {
            return Err(Error::numerical(format!(
                "subspace iteration for {count} modes did not converge with a block of all {n} DOFs"
            )));
        }
        p = (2 * p).min(n);
    }
}

/// Iterations of one block size in [`lowest_modes`] before the block is doubled (the widest
/// case measured, 30 paper-5 spans at 12 modes, takes 91).
pub const ITERATIONS_PER_BLOCK: usize = 200;

/// One run of [`lowest_modes`] with a block of `p` vectors, given K's factor and the products
/// by K and M: `None` when it has not converged in [`ITERATIONS_PER_BLOCK`] iterations.
fn subspace(
    s: &Structure,
    (factor, ks, ms): (&SparseCholesky, &SymSparse, &SymSparse),
    count: usize,
    p: usize,
) -> crate::Result<Option<Vec<Mode>>> {
    let n = s.dofs();
    let mut scratch = factor.scratch();
    let mul = |a: &SymSparse, x: &DMatrix<f64>| {
        let mut y = DMatrix::zeros(x.nrows(), x.ncols());
        for c in 0..x.ncols() {
            let col = x.column(c).into_owned();
            let mut out = DVector::zeros(x.nrows());
            a.mul_acc(col.as_slice(), out.as_mut_slice());
            y.set_column(c, &out);
        }
        y
    };
    // Start: the diagonal of M, spread over the block by a deterministic pattern.
    let mut x = DMatrix::from_fn(n, p, |i, c| {
        let m = s.m.get(i, i);
        if c == 0 {
            m
        } else {
            m * (((i * (c + 1) * 7919) % 1009) as f64 / 1009.0 - 0.5)
        }
    });
    let mut previous = vec![f64::INFINITY; count];
    for _ in 0..ITERATIONS_PER_BLOCK {
        let mut y = mul(ms, &x);
        for c in 0..p {
            let mut col = y.column(c).into_owned();
            factor.solve_in_place(col.as_mut_slice(), &mut scratch);
            y.set_column(c, &col);
        }
        let kr = y.transpose() * mul(ks, &y);
        let mr = y.transpose() * mul(ms, &y);
        let (lambda, q) = generalized(
            &((&kr + kr.transpose()) * 0.5),
            &((&mr + mr.transpose()) * 0.5),
        )?;
        let mut order: Vec<usize> = (0..p).collect();
        order.sort_by(|&a, &b| lambda[a].total_cmp(&lambda[b]));
        let q = DMatrix::from_fn(p, p, |i, c| q[(i, order[c])]);
        x = y * q;
        let now: Vec<f64> = order[..count].iter().map(|&c| lambda[c]).collect();
        let done = now
            .iter()
            .zip(&previous)
            .all(|(a, b)| (a - b).abs() <= 1e-12 * a.abs());
        previous = now;
        if done {
            let mx = mul(ms, &x);
            return Ok(Some(
                (0..count)
                    .map(|c| {
                        s.mode(
                            previous[c].max(0.0).sqrt(),
                            x.column(c).into_owned(),
                            &mx.column(c).into_owned(),
                        )
                    })
                    .collect(),
            ));
        }
    }
    Ok(None)
}
