//! One simply supported span: node layout, supports, assembled stiffness and mass on the free
//! DOFs, load distribution (Eq. 15) and interpolation (Eq. 16).
//!
//! Why per span and banded: spans of a [`crate::physics::guideway::Bridge`] are separate beams, simply
//! supported at each end with their own end nodes, so the structure matrices are exactly
//! block-diagonal over spans and each span is solved on its own. Within a span the DOFs are
//! numbered node by node, so K and M are banded (half-bandwidth ≤ 11 on the free DOFs) and
//! are stored as such ([`SymBanded`]): memory and products O(n·b), never O(n²). Spans of
//! equal length share one model (see [`super::FeGuideway`]), so a long viaduct of equal spans
//! assembles and factorises once.
//!
//! Supports (fork bearings): v, w and θx fixed at both ends, u fixed at the left end only,
//! θy and θz free.

use super::banded::SymBanded;
use super::cholesky::SparseCholesky;
use super::element;
use crate::physics::guideway::{BeamSection, PointMotion, SectionMotion};
use crate::Error;
use maglev_core::gap::{dof, locate, ElementVector, WheelShape, DOFS_PER_NODE, ELEMENT_DOFS};
use nalgebra::DVector;

/// Family of a DOF, used to classify modes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum DofFamily {
    /// Bending with displacement in Z (vertical; w, θy; uses Iy).
    BendingZ,
    /// Bending with displacement in Y (lateral; v, θz; uses Iz).
    BendingY,
    /// Torsion θx.
    Torsion,
    /// Axial u.
    Axial,
}

impl DofFamily {
    /// The family of DOF `d` within a node (see [`dof`]).
    pub fn of(d: usize) -> Self {
        match d {
            dof::U => DofFamily::Axial,
            dof::V | dof::RZ => DofFamily::BendingY,
            dof::W | dof::RY => DofFamily::BendingZ,
            _ => DofFamily::Torsion,
        }
    }
}

/// Assembled model of one span, in span-local X (0 at its left support).
#[derive(Clone, Debug)]
pub struct SpanModel {
    /// Span length (m).
    pub length: f64,
    /// Node X coordinates from the left support (m), `elements + 1` of them.
    pub nodes: Vec<f64>,
    /// Full DOF index (`node * 6 + dof`) → free DOF index, `None` where supported.
    free_index: Vec<Option<usize>>,
    /// Free DOF index → full DOF index.
    full_index: Vec<usize>,
    /// Stiffness on the free DOFs (banded).
    pub k: SymBanded,
    /// Consistent mass on the free DOFs (banded).
    pub m: SymBanded,
    /// The inertia of each bearing's rigid-body shape, `M r_j` on the free DOFs with M the
    /// mass of every DOF (supported ones too, so the mass coupling to the bearings counts):
    /// j as in [`bearing_shape`] (docs/seismic.md Eq. S4).
    pub bearing_inertia: [DVector<f64>; BEARINGS],
}

pub use crate::physics::seismic::support::BEARINGS;

impl SpanModel {
    /// Assemble `elements` equal Timoshenko elements over a span of `length`.
    pub fn new(section: &BeamSection, length: f64, elements: usize) -> crate::Result<Self> {
        if elements == 0 {
            return Err(Error::invalid(
                "elements_per_span",
                format!("must be at least 1, got {elements}"),
            ));
        }
        if !(length.is_finite() && length > 0.0) {
            return Err(Error::invalid(
                "span length",
                format!("must be positive and finite, got {length}"),
            ));
        }
        let n_nodes = elements + 1;
        let n_full = n_nodes * DOFS_PER_NODE;
        let le = length / elements as f64;
        let nodes: Vec<f64> = (0..n_nodes)
            .map(|i| if i == elements { length } else { i as f64 * le })
            .collect();
        let last = elements * DOFS_PER_NODE;
        let fixed = [
            dof::U,
            dof::V,
            dof::W,
            dof::RX,
            last + dof::V,
            last + dof::W,
            last + dof::RX,
        ];
        let mut free_index = vec![None; n_full];
        let mut full_index = Vec::with_capacity(n_full);
        for (i, slot) in free_index.iter_mut().enumerate() {
            if !fixed.contains(&i) {
                *slot = Some(full_index.len());
                full_index.push(i);
            }
        }
        let n = full_index.len();
        let ke = element::stiffness(section, le);
        let me = element::mass(section, le);
        // Half-bandwidth: the widest free-index distance within one element.
        let band = (0..elements)
            .map(|e| {
                let dofs = e * DOFS_PER_NODE..e * DOFS_PER_NODE + ELEMENT_DOFS;
                let f: Vec<usize> = dofs.filter_map(|i| free_index[i]).collect();
                f.iter().max().unwrap_or(&0) - f.iter().min().unwrap_or(&0)
            })
            .max()
            .unwrap_or(0);
        let mut k = SymBanded::zeros(n, band);
        let mut m = SymBanded::zeros(n, band);
        for e in 0..elements {
            let base = e * DOFS_PER_NODE;
            for i in 0..ELEMENT_DOFS {
                let Some(fi) = free_index[base + i] else {
                    continue;
                };
                for j in 0..ELEMENT_DOFS {
                    let Some(fj) = free_index[base + j] else {
                        continue;
                    };
                    if fi >= fj {
                        k.add_lower(fi, fj, ke[(i, j)]);
                        m.add_lower(fi, fj, me[(i, j)]);
                    }
                }
            }
        }
        let mut bearing_inertia: [DVector<f64>; BEARINGS] =
            std::array::from_fn(|_| DVector::zeros(n));
        for (j, f) in bearing_inertia.iter_mut().enumerate() {
            for e in 0..elements {
                let base = e * DOFS_PER_NODE;
                let r = ElementVector::from_fn(|i, _| {
                    let node = (base + i) / DOFS_PER_NODE;
                    bearing_shape(j, nodes[node] / length, length)[i % DOFS_PER_NODE]
                });
                let fe = me * r;
                for (i, v) in fe.iter().enumerate() {
                    if let Some(fi) = free_index[base + i] {
                        f[fi] += v;
                    }
                }
            }
        }
        Ok(SpanModel {
            length,
            nodes,
            free_index,
            full_index,
            k,
            m,
            bearing_inertia,
        })
    }

    /// Number of elements.
    pub fn elements(&self) -> usize {
        self.nodes.len() - 1
    }

    /// Number of free DOFs.
    pub fn free_dofs(&self) -> usize {
        self.full_index.len()
    }

    /// Free index of DOF `d` of node `node`, `None` if supported (or out of range).
    pub fn free(&self, node: usize, d: usize) -> Option<usize> {
        self.free_index
            .get(node * DOFS_PER_NODE + d)
            .copied()
            .flatten()
    }

    /// Family of each free DOF.
    pub fn families(&self) -> impl Iterator<Item = DofFamily> + '_ {
        self.full_index
            .iter()
            .map(|&i| DofFamily::of(i % DOFS_PER_NODE))
    }

    /// Element `e`'s 12 DOFs gathered from a free-DOF vector (supported DOFs are zero).
    pub fn gather(&self, d: &DVector<f64>, e: usize) -> ElementVector<f64> {
        let d = d.as_slice();
        self.gather_with(e, |f| d[f])
    }

    /// The wheel shape at span-local `x` with offset `(ey, ez)`: element index and rows.
    /// `None` off the span.
    pub fn shape_at(&self, x: f64, ey: f64, ez: f64) -> Option<(usize, WheelShape<f64>)> {
        let at = locate(&self.nodes, x)?;
        Some((at.element, WheelShape::new(at.x2, at.length, ey, ez)))
    }

    /// Add the nodal forces of a point force `(fy, fz)` at span-local `x`, offset `(ey, ez)`,
    /// to the free-DOF load vector `f` (Eq. 15, `f = Nᵀ G`). Ignored off the span; the share
    /// on supported DOFs goes to the supports.
    pub fn add_point_force(
        &self,
        x: f64,
        ey: f64,
        ez: f64,
        fy: f64,
        fz: f64,
        f: &mut DVector<f64>,
    ) {
        if let Some((e, shape)) = self.shape_at(x, ey, ez) {
            self.add_shaped_force(e, &shape, fy, fz, f.as_mut_slice(), |_| {});
        }
    }

    /// As [`Self::add_point_force`] for a point already located (element `e`, `shape` from
    /// [`Self::shape_at`]) into a slice, calling `on_dof` with each free DOF it adds to.
    pub fn add_shaped_force(
        &self,
        e: usize,
        shape: &WheelShape<f64>,
        fy: f64,
        fz: f64,
        f: &mut [f64],
        mut on_dof: impl FnMut(usize),
    ) {
        let fe = shape.nodal_forces(fy, fz);
        let base = e * DOFS_PER_NODE;
        let idx = &self.free_index[base..base + ELEMENT_DOFS];
        for (i, fe) in idx.iter().zip(fe.iter()) {
            if let Some(fi) = *i {
                f[fi] += fe;
                on_dof(fi);
            }
        }
    }

    /// Free index of each of element `e`'s 12 DOFs (`None` where supported).
    pub fn element_free(&self, e: usize) -> &[Option<usize>] {
        &self.free_index[e * DOFS_PER_NODE..e * DOFS_PER_NODE + ELEMENT_DOFS]
    }

    /// Element `e`'s 12 DOFs with `value(free index)` (supported DOFs are zero).
    pub fn gather_with(&self, e: usize, value: impl FnMut(usize) -> f64) -> ElementVector<f64> {
        self.gather_where(e, |_| true, value)
    }

    /// As [`Self::gather_with`] on the element DOFs `k` (0..12) with `keep(k)` only; the
    /// others are zero.
    pub fn gather_where(
        &self,
        e: usize,
        keep: impl Fn(usize) -> bool,
        mut value: impl FnMut(usize) -> f64,
    ) -> ElementVector<f64> {
        let base = e * DOFS_PER_NODE;
        let mut out = ElementVector::zeros();
        for (k, (o, i)) in out
            .iter_mut()
            .zip(&self.free_index[base..base + ELEMENT_DOFS])
            .enumerate()
        {
            if let (Some(f), true) = (*i, keep(k)) {
                *o = value(f);
            }
        }
        out
    }

    /// Displacement of a point at span-local `x`, offset `(ey, ez)`, for free DOFs `d`
    /// (Eq. 16 with the rigid-link rotation share). `None` off the span.
    pub fn motion(&self, d: &DVector<f64>, x: f64, ey: f64, ez: f64) -> Option<PointMotion> {
        self.motion_with(x, ey, ez, |e| self.gather(d, e))
    }

    /// As [`Self::motion`], with element `e`'s DOFs from `element(e)`.
    pub fn motion_with(
        &self,
        x: f64,
        ey: f64,
        ez: f64,
        element: impl FnOnce(usize) -> ElementVector<f64>,
    ) -> Option<PointMotion> {
        let (e, s) = self.shape_at(x, ey, ez)?;
        let de = element(e);
        Some(PointMotion {
            y: s.y_at(&de),
            z: s.z_at(&de),
        })
    }

    /// Axis displacement at span-local `x` for free DOFs `d`. `None` off the span.
    pub fn section(&self, d: &DVector<f64>, x: f64) -> Option<SectionMotion> {
        self.section_with(x, |e| self.gather(d, e))
    }

    /// As [`Self::section`], with element `e`'s DOFs from `element(e)`.
    pub fn section_with(
        &self,
        x: f64,
        element: impl FnOnce(usize) -> ElementVector<f64>,
    ) -> Option<SectionMotion> {
        let (e, s) = self.shape_at(x, 0.0, 0.0)?;
        let de = element(e);
        Some(SectionMotion {
            y: s.y_at(&de),
            z: s.z_at(&de),
            rx: s.rx_at(&de),
        })
    }

    /// Cholesky factor of the stiffness (for static solves); fails if K is not positive
    /// definite (it is, for a supported span with positive properties).
    pub fn stiffness_factor(&self) -> crate::Result<SparseCholesky> {
        SparseCholesky::new(&self.k).map_err(|e| Error::numerical(format!("span stiffness: {e}")))
    }
}

/// The six DOFs of a node at ξ = x/L of a span of `length` under bearing motion j
/// ([`BEARINGS`]): the quasi-static rigid-body motion of Eq. S3 (docs/seismic.md), the span's
/// displacement when that bearing moves by 1 m and the others stay (w or v linear between the
/// bearings, θy = −∂w/∂x, θz = ∂v/∂x; no strain, so no force).
fn bearing_shape(j: usize, xi: f64, length: f64) -> [f64; DOFS_PER_NODE] {
    let mut d = [0.0; DOFS_PER_NODE];
    let (value, slope) = match j % 2 {
        0 => (1.0 - xi, -1.0 / length),
        _ => (xi, 1.0 / length),
    };
    if j < 2 {
        d[dof::W] = value;
        d[dof::RY] = -slope;
    } else {
        d[dof::V] = value;
        d[dof::RZ] = slope;
    }
    d
}
