//! Natural modes of a span: K φ = ω² M φ on the free DOFs, sorted by frequency and classified.
//!
//! Why split into coupled blocks first: for a straight beam with coincident centroid and shear
//! centre, axial, lateral bending, vertical bending and torsion are uncoupled in K and M. With
//! Iy = Iz (the §4.2 beam) lateral and vertical bending frequencies coincide, and a solver on
//! the whole matrix may return any mixture of the two degenerate modes. Solving each connected
//! block of the DOF coupling graph (structural non-zeros of K or M) separately keeps each mode
//! within its family, and the result is the same spectrum (up to rounding). Should a future
//! section couple families, the blocks simply merge.
//!
//! Per block: M = L Lᵀ (Cholesky), then the symmetric eigenproblem of L⁻¹ K L⁻ᵀ, and
//! φ = L⁻ᵀ y (mass-normalised: φᵀ M φ = 1).
//!
//! Classification rule: the kinetic-energy share of each DOF family, `Σ_{i∈family} φ_i (M φ)_i`
//! (these sum to φᵀMφ = 1; for this element every share is 0 or 1, since M does not couple
//! families); the kind is the family with the largest share (ties go to the earlier of
//! bending-z, bending-y, torsion, axial). Modes of equal frequency (relative 1e-9) are listed
//! in that same order, so the output is deterministic.

use super::assembly::{DofFamily, SpanModel};
use crate::Error;
use nalgebra::{Cholesky, DMatrix, DVector, SymmetricEigen};

fn singular() -> Error {
    Error::numerical("singular mass factor")
}

/// Kind of a mode (see the module docs for the rule).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum ModeKind {
    /// Vertical bending: displacement in Z (w, θy).
    BendingZ,
    /// Lateral bending: displacement in Y (v, θz).
    BendingY,
    /// Torsion about X.
    Torsion,
    /// Axial, along X.
    Axial,
}

impl ModeKind {
    /// Name used in CLI output: `bending-z`, `bending-y`, `torsion`, `axial`.
    pub fn as_str(self) -> &'static str {
        match self {
            ModeKind::BendingZ => "bending-z",
            ModeKind::BendingY => "bending-y",
            ModeKind::Torsion => "torsion",
            ModeKind::Axial => "axial",
        }
    }

    fn from_family(f: DofFamily) -> Self {
        match f {
            DofFamily::BendingZ => ModeKind::BendingZ,
            DofFamily::BendingY => ModeKind::BendingY,
            DofFamily::Torsion => ModeKind::Torsion,
            DofFamily::Axial => ModeKind::Axial,
        }
    }
}

/// One natural mode.
#[derive(Clone, Debug)]
pub struct Mode {
    /// Circular frequency ω (rad/s).
    pub omega: f64,
    /// Frequency ω / 2π (Hz).
    pub frequency_hz: f64,
    /// Dominant DOF family.
    pub kind: ModeKind,
    /// Mass-normalised shape on the span's free DOFs.
    pub shape: DVector<f64>,
}

fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// Connected blocks of the coupling graph of K and M, each a sorted list of free DOFs.
fn blocks(model: &SpanModel) -> Vec<Vec<usize>> {
    let n = model.free_dofs();
    let mut parent: Vec<usize> = (0..n).collect();
    let band = model.k.bandwidth().max(model.m.bandwidth());
    for i in 0..n {
        for j in i.saturating_sub(band)..i {
            if model.k[(i, j)] != 0.0 || model.m[(i, j)] != 0.0 {
                let (a, b) = (find(&mut parent, i), find(&mut parent, j));
                parent[a.max(b)] = a.min(b);
            }
        }
    }
    let mut out: Vec<Vec<usize>> = Vec::new();
    let mut root_of_block: Vec<usize> = Vec::new();
    for i in 0..n {
        let r = find(&mut parent, i);
        match root_of_block.iter().position(|&x| x == r) {
            Some(b) => out[b].push(i),
            None => {
                root_of_block.push(r);
                out.push(vec![i]);
            }
        }
    }
    out
}

/// All natural modes of a span, ascending in frequency (see the module docs).
pub fn natural_modes(model: &SpanModel) -> crate::Result<Vec<Mode>> {
    let n = model.free_dofs();
    let families: Vec<DofFamily> = model.families().collect();
    let mut modes = Vec::with_capacity(n);
    for block in blocks(model) {
        let nb = block.len();
        let k = DMatrix::from_fn(nb, nb, |i, j| model.k[(block[i], block[j])]);
        let m = DMatrix::from_fn(nb, nb, |i, j| model.m[(block[i], block[j])]);
        let l = Cholesky::new(m.clone())
            .ok_or_else(|| Error::numerical("mass matrix is not positive definite"))?
            .l();
        // A = L⁻¹ K L⁻ᵀ
        let x = l.solve_lower_triangular(&k).ok_or_else(singular)?;
        let a = l
            .solve_lower_triangular(&x.transpose())
            .ok_or_else(singular)?;
        let a = (&a + a.transpose()) * 0.5;
        let eig = SymmetricEigen::new(a);
        let lt = l.transpose();
        for (col, &lambda) in eig.eigenvalues.iter().enumerate() {
            let y = eig.eigenvectors.column(col).into_owned();
            let phi_b = lt.solve_upper_triangular(&y).ok_or_else(singular)?;
            // Kinetic-energy shares within the block (M has no entries outside it).
            let mphi = &m * &phi_b;
            let mut share = [0.0f64; 4];
            let mut phi = DVector::zeros(n);
            for (i, &g) in block.iter().enumerate() {
                phi[g] = phi_b[i];
                share[families[g] as usize] += phi_b[i] * mphi[i];
            }
            let best = (0..4).fold(0, |b, f| if share[f] > share[b] { f } else { b });
            let family = [
                DofFamily::BendingZ,
                DofFamily::BendingY,
                DofFamily::Torsion,
                DofFamily::Axial,
            ][best];
            let omega = lambda.max(0.0).sqrt();
            modes.push(Mode {
                omega,
                frequency_hz: omega / (2.0 * std::f64::consts::PI),
                kind: ModeKind::from_family(family),
                shape: phi,
            });
        }
    }
    modes.sort_by(|a, b| a.omega.total_cmp(&b.omega));
    // Within runs of equal frequency, order by kind for determinism.
    let mut start = 0;
    while start < modes.len() {
        let mut end = start + 1;
        while end < modes.len() && modes[end].omega - modes[start].omega <= 1e-9 * modes[end].omega
        {
            end += 1;
        }
        modes[start..end].sort_by_key(|m| m.kind);
        start = end;
    }
    Ok(modes)
}
