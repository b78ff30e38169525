//! Gap geometry and the wheel on its target nodes (docs/model.md §2, §5; paper Eq. 2, 15, 16).
//!
//! [`Geometry`] holds the one definition of the gap (Eq. 2, both readings) and of the
//! guidance pair's net force; every simulator, the firmware coupling, the stability analysis
//! and the tests call it.
//!
//! Why here, in the `no_std` core: the gap is what the levitation controller measures, and
//! the same interpolation that gives the guideway displacement under a wheel (Eq. 16) must
//! distribute the wheel force back onto the beam (Eq. 15, `f = Nᵀ G`). Keeping both in one
//! place makes them work-conjugate by construction: every quantity below is a *row* `N` over
//! the 12 DOFs of a two-node beam element, displacement is `N · d` and force is `Nᵀ G`.
//!
//! Element DOF order (per node, node 1 then node 3 in the paper's naming, here nodes 0 and 1):
//! `(u, v, w, θx, θy, θz)`, see [`dof`]. Axes (docs/model.md §0): X along the beam, Z up, Y
//! completing a right-handed set; rotations are right-handed about the axes, so for bending
//! θy = −∂w/∂x and θz = +∂v/∂x.
//!
//! Everything is generic over `nalgebra::RealField + Copy` (f32 and f64), uses fixed-size
//! types only (no alloc) and never panics: a position off the node list gives `None`.

use nalgebra::{RealField, SVector, Vector2, Vector4};

/// Degrees of freedom per beam node.
pub const DOFS_PER_NODE: usize = 6;
/// Degrees of freedom of a two-node beam element.
pub const ELEMENT_DOFS: usize = 2 * DOFS_PER_NODE;

/// A vector (or a row) over the 12 DOFs of one element.
pub type ElementVector<T> = SVector<T, ELEMENT_DOFS>;

/// Index of each DOF within a node's block of [`DOFS_PER_NODE`].
pub mod dof {
    /// Axial displacement along X.
    pub const U: usize = 0;
    /// Lateral displacement along Y.
    pub const V: usize = 1;
    /// Vertical displacement along Z.
    pub const W: usize = 2;
    /// Rotation about X (torsion).
    pub const RX: usize = 3;
    /// Rotation about Y (θy = −∂w/∂x).
    pub const RY: usize = 4;
    /// Rotation about Z (θz = +∂v/∂x).
    pub const RZ: usize = 5;
}

#[inline]
fn c<T: RealField + Copy>(x: f64) -> T {
    nalgebra::convert(x)
}

/// Cubic Hermite shape functions for `(w1, θy1, w3, θy3)` at `x2` from node 1 in an element of
/// length `l` (docs/model.md §5, used by Eq. 15 and 16). The minus signs on N2 and N4 come from
/// θy = −∂w/∂x.
pub fn hermite_z<T: RealField + Copy>(x2: T, l: T) -> Vector4<T> {
    let s = x2 / l;
    let s2 = s * s;
    let s3 = s2 * s;
    let one = T::one();
    let two: T = c(2.0);
    let three: T = c(3.0);
    Vector4::new(
        one - three * s2 + two * s3,
        -x2 * (one - two * s + s2),
        three * s2 - two * s3,
        -x2 * s2 + x2 * s,
    )
}

/// Cubic Hermite shape functions for `(v1, θz1, v3, θz3)`: as [`hermite_z`] with the
/// rotation functions sign-flipped, because θz = +∂v/∂x (docs/model.md §5).
pub fn hermite_y<T: RealField + Copy>(x2: T, l: T) -> Vector4<T> {
    let n = hermite_z(x2, l);
    Vector4::new(n[0], -n[1], n[2], -n[3])
}

/// Linear shape functions for torsion `(θx1, θx3)` (docs/model.md §5).
pub fn linear<T: RealField + Copy>(x2: T, l: T) -> Vector2<T> {
    let s = x2 / l;
    Vector2::new(T::one() - s, s)
}

/// Where a position falls in a line of nodes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Located<T> {
    /// Index of the element, i.e. of its first node.
    pub element: usize,
    /// Distance from the element's first node, `0 ≤ x2 ≤ length`.
    pub x2: T,
    /// Element length.
    pub length: T,
}

/// Find the element around `x` in the strictly increasing node coordinates `nodes`: the
/// element `i` with `nodes[i] ≤ x < nodes[i + 1]`; `x` equal to the last node belongs to the
/// last element. `None` off the line, with fewer than two nodes, for a non-positive element
/// length, or for a NaN position. Binary search: O(log n).
pub fn locate<T: RealField + Copy>(nodes: &[T], x: T) -> Option<Located<T>> {
    let first = *nodes.first()?;
    let last = *nodes.last()?;
    if nodes.len() < 2 || !(x >= first && x <= last) {
        return None;
    }
    // Invariant: nodes[lo] <= x, and x < nodes[hi] or hi == last index.
    let mut lo = 0usize;
    let mut hi = nodes.len() - 1;
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        match nodes.get(mid) {
            Some(&xm) if xm <= x => lo = mid,
            Some(_) => hi = mid,
            None => return None,
        }
    }
    let a = *nodes.get(lo)?;
    let b = *nodes.get(lo + 1)?;
    let length = b - a;
    if length <= T::zero() {
        return None;
    }
    Some(Located {
        element: lo,
        x2: x - a,
        length,
    })
}

/// The interpolation rows of a point on the element, offset from the beam axis by a rigid
/// link `(ΔY, ΔZ) = (ey, ez)` (docs/model.md §5, Eq. 15 and 16).
///
/// With `d` the element's 12 DOFs: `z_g = z · d`, `y_g = y · d`, `θx = rx · d`, and the rigid
/// link's rotation share is included (`z_g += θx ΔY`, `y_g −= θx ΔZ`: a rotation θx about X
/// moves the point `(ΔY, ΔZ)` by `θx x̂ × (ΔY ŷ + ΔZ ẑ)`). A force `(Fy, Fz)` applied at the
/// point becomes the nodal forces `f = yᵀ Fy + zᵀ Fz` (Eq. 15), which include the torque
/// `Mx = ΔY Fz − ΔZ Fy` (`r × F`) spread linearly over the two nodes. Being transposes of each
/// other, displacement and force are work-conjugate: `f · d = Fy y_g + Fz z_g` for any `d`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WheelShape<T: RealField + Copy> {
    /// Row giving the Z displacement of the point (Eq. 16).
    pub z: ElementVector<T>,
    /// Row giving the Y displacement of the point.
    pub y: ElementVector<T>,
    /// Row giving the axis rotation about X at the point (linear interpolation).
    pub rx: ElementVector<T>,
}

impl<T: RealField + Copy> WheelShape<T> {
    /// Rows at `x2` from the first node of an element of length `l`, for a point at offset
    /// `(ey, ez)` from the axis.
    pub fn new(x2: T, l: T, ey: T, ez: T) -> Self {
        let nz = hermite_z(x2, l);
        let ny = hermite_y(x2, l);
        let nx = linear(x2, l);
        let n1 = DOFS_PER_NODE;
        let mut rx = ElementVector::<T>::zeros();
        rx[dof::RX] = nx[0];
        rx[n1 + dof::RX] = nx[1];
        let mut z = rx * ey;
        z[dof::W] = nz[0];
        z[dof::RY] = nz[1];
        z[n1 + dof::W] = nz[2];
        z[n1 + dof::RY] = nz[3];
        let mut y = rx * (-ez);
        y[dof::V] = ny[0];
        y[dof::RZ] = ny[1];
        y[n1 + dof::V] = ny[2];
        y[n1 + dof::RZ] = ny[3];
        WheelShape { z, y, rx }
    }

    /// Z displacement of the point for element DOFs `d` (Eq. 16 with the rigid link).
    pub fn z_at(&self, d: &ElementVector<T>) -> T {
        self.z.dot(d)
    }

    /// Y displacement of the point for element DOFs `d`.
    pub fn y_at(&self, d: &ElementVector<T>) -> T {
        self.y.dot(d)
    }

    /// Axis rotation about X at the point for element DOFs `d`.
    pub fn rx_at(&self, d: &ElementVector<T>) -> T {
        self.rx.dot(d)
    }

    /// Nodal forces of a force `(fy, fz)` acting at the point (Eq. 15, `f = Nᵀ G`).
    pub fn nodal_forces(&self, fy: T, fz: T) -> ElementVector<T> {
        self.z * fz + self.y * fy
    }
}

/// How a magnet faces its rail: the sign of Eq. 2 and of the guidance pair's net force
/// (docs/model.md §2). This is the one place either sign is written.
///
/// - [`Geometry::Paper`] (the default, every paper case): Eq. 2 read literally in the paper's
///   own Z-up axes, `h = h0 + (z_w − z_g) + r`. The wheel moving up *opens* the gap and, at
///   fixed current, lowers the force: the magnet acts as a soft spring, and the paper's law
///   gives a bounded ride. Guidance mirrors it: `F_y = G_L − G_R`, each magnet pushing the
///   wheel back towards the centre as its own gap closes.
/// - [`Geometry::Ems`]: a real EMS magnet hanging under its rail, `h = h0 − (z_w − z_g) + r`.
///   Closing the gap raises the force: open-loop unstable, so it needs a gap-feedback law
///   (`gap_control`). Guidance: `F_y = G_R − G_L`, each magnet pulling towards its own face.
///
/// In both, the pair's gaps are `h_L = h0 + d`, `h_R = h0 − d` with `d = y_w − y_g + r_y`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Geometry {
    /// The paper's literal Eq. 2 (default).
    #[default]
    Paper,
    /// The EMS magnet under its rail.
    Ems,
}

impl Geometry {
    /// The name as scenarios write it (`paper`, `ems`).
    pub const fn as_str(self) -> &'static str {
        match self {
            Geometry::Paper => "paper",
            Geometry::Ems => "ems",
        }
    }

    /// Levitation gap (Eq. 2): `h = h0 ± (z_w − z_g) + r`, `+` for [`Geometry::Paper`],
    /// `−` for [`Geometry::Ems`]. `z_w`: the magnet node's displacement, `z_g`: the
    /// guideway's at the wheel (Eq. 16), `r`: the rail irregularity at the wheel (Eq. 3).
    pub fn levitation_gap<T: RealField + Copy>(self, h0: T, z_w: T, z_g: T, r: T) -> T {
        match self {
            Geometry::Paper => h0 + (z_w - z_g) + r,
            Geometry::Ems => h0 - (z_w - z_g) + r,
        }
    }

    /// d(h)/d(z_w): `+1` (paper) or `−1` (EMS). For linearisations.
    pub fn levitation_sign(self) -> f64 {
        match self {
            Geometry::Paper => 1.0,
            Geometry::Ems => -1.0,
        }
    }

    /// Net lateral force on the wheel from the guidance pair's forces `(G_L, G_R)`:
    /// `G_L − G_R` (paper), `G_R − G_L` (EMS).
    pub fn guidance_force<T: core::ops::Sub<Output = T>>(self, left: T, right: T) -> T {
        match self {
            Geometry::Paper => left - right,
            Geometry::Ems => right - left,
        }
    }

    /// d(F_y)/d(G_L): `+1` (paper) or `−1` (EMS). For linearisations.
    pub fn guidance_sign(self) -> f64 {
        match self {
            Geometry::Paper => 1.0,
            Geometry::Ems => -1.0,
        }
    }
}

/// The guidance pair's relative lateral position `d = y_w − y_g + r_y` (docs/model.md §2),
/// the same in both geometries.
pub fn lateral_offset<T: RealField + Copy>(y_w: T, y_g: T, r_y: T) -> T {
    y_w - y_g + r_y
}

/// Guidance pair gaps `(h_L, h_R) = (h0 + d, h0 − d)` for the lateral offset `d`
/// ([`lateral_offset`]), the same in both geometries (docs/model.md §2).
pub fn guidance_gaps<T: RealField + Copy>(h0: T, d: T) -> (T, T) {
    (h0 + d, h0 - d)
}

#[cfg(test)]
mod tests {
    use super::*;

    const L: f64 = 1.7;

    fn samples() -> impl Iterator<Item = f64> {
        (0..=16).map(|k| L * k as f64 / 16.0)
    }

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs()))
    }

    #[test]
    fn hermite_partition_of_unity() {
        for x2 in samples() {
            let n = hermite_z(x2, L);
            assert!(close(n[0] + n[2], 1.0, 1e-15), "x2={x2}");
            let n = hermite_y(x2, L);
            assert!(close(n[0] + n[2], 1.0, 1e-15), "x2={x2}");
            let n = linear(x2, L);
            assert!(close(n[0] + n[1], 1.0, 1e-15), "x2={x2}");
        }
        // Nodal values: N = (1, 0, 0, 0) at node 1 and (0, 0, 1, 0) at node 3.
        assert_eq!(hermite_z(0.0, L), Vector4::new(1.0, 0.0, 0.0, 0.0));
        let n = hermite_z(L, L);
        assert!(n[0].abs() < 1e-15 && n[1].abs() < 1e-15 && (n[2] - 1.0).abs() < 1e-15);
        assert!(n[3].abs() < 1e-15);
    }

    /// A rigid rotation θy about node 1 moves a point at distance x2 by θy ŷ × x2 x̂ = −θy x2 ẑ.
    #[test]
    fn rigid_rotation_about_y_moves_point_down() {
        let th = 1e-3;
        for x2 in samples() {
            let n = hermite_z(x2, L);
            // Nodal DOFs of the rigid rotation: w1 = 0, θy1 = θ, w3 = −θ L, θy3 = θ.
            let w = n.dot(&Vector4::new(0.0, th, -th * L, th));
            assert!(close(w, -th * x2, 1e-14), "x2={x2}: {w} vs {}", -th * x2);
        }
    }

    /// A rigid rotation θz about node 1 moves a point by θz ẑ × x2 x̂ = +θz x2 ŷ.
    #[test]
    fn rigid_rotation_about_z_moves_point_sideways() {
        let th = 1e-3;
        for x2 in samples() {
            let n = hermite_y(x2, L);
            let v = n.dot(&Vector4::new(0.0, th, th * L, th));
            assert!(close(v, th * x2, 1e-14), "x2={x2}");
        }
    }

    /// The same through the 12-DOF rows, with a rigid translation added.
    #[test]
    fn rigid_body_motion_of_element_rows() {
        let (ty, tz, ry, rz) = (2e-3, -3e-3, 4e-4, -5e-4);
        let mut d = ElementVector::<f64>::zeros();
        for (node, x) in [(0usize, 0.0), (1, L)] {
            let o = node * DOFS_PER_NODE;
            d[o + dof::V] = ty + rz * x;
            d[o + dof::W] = tz - ry * x;
            d[o + dof::RY] = ry;
            d[o + dof::RZ] = rz;
        }
        for x2 in samples() {
            let s = WheelShape::new(x2, L, 0.0, 0.0);
            assert!(close(s.z_at(&d), tz - ry * x2, 1e-14));
            assert!(close(s.y_at(&d), ty + rz * x2, 1e-14));
        }
    }

    /// Cubic fields are reproduced exactly (Hermite interpolation is exact on cubics).
    #[test]
    fn reproduces_cubic_fields() {
        let w = |x: f64| 0.3 - 1.2 * x + 0.7 * x * x - 0.4 * x * x * x;
        let dw = |x: f64| -1.2 + 1.4 * x - 1.2 * x * x;
        let nodal_z = Vector4::new(w(0.0), -dw(0.0), w(L), -dw(L));
        let nodal_y = Vector4::new(w(0.0), dw(0.0), w(L), dw(L));
        for x2 in samples() {
            assert!(close(hermite_z(x2, L).dot(&nodal_z), w(x2), 1e-14));
            assert!(close(hermite_y(x2, L).dot(&nodal_y), w(x2), 1e-14));
        }
    }

    #[test]
    fn works_in_f32() {
        let n = hermite_z(0.5f32, 1.0f32);
        assert!((n[0] + n[2] - 1.0).abs() < 1e-6);
        let s = WheelShape::new(0.25f32, 1.0, 1.5, 0.6);
        assert!((s.rx[dof::RX] - 0.75).abs() < 1e-6);
    }

    /// A Z force at +Y arm gives Mx = ΔY·Fz; a Y force at +Z arm gives Mx = −ΔZ·Fy (r × F).
    #[test]
    fn rigid_link_torque() {
        let (ey, ez) = (1.5, 0.6);
        for x2 in samples() {
            let s = WheelShape::new(x2, L, ey, ez);
            let f = s.nodal_forces(0.0, -1000.0);
            let mx = f[dof::RX] + f[DOFS_PER_NODE + dof::RX];
            assert!(close(mx, ey * -1000.0, 1e-14));
            let fz = f[dof::W] + f[DOFS_PER_NODE + dof::W];
            assert!(close(fz, -1000.0, 1e-14));
            let f = s.nodal_forces(200.0, 0.0);
            let mx = f[dof::RX] + f[DOFS_PER_NODE + dof::RX];
            assert!(close(mx, -ez * 200.0, 1e-14));
            let fy = f[dof::V] + f[DOFS_PER_NODE + dof::V];
            assert!(close(fy, 200.0, 1e-14));
        }
        // A pure axis twist moves the offset point by θ x̂ × (ey ŷ + ez ẑ) = θ (−ez ŷ + ey ẑ).
        let th = 2e-3;
        let mut d = ElementVector::<f64>::zeros();
        d[dof::RX] = th;
        d[DOFS_PER_NODE + dof::RX] = th;
        let s = WheelShape::new(0.4, L, ey, ez);
        assert!(close(s.z_at(&d), th * ey, 1e-15));
        assert!(close(s.y_at(&d), -th * ez, 1e-15));
    }

    /// Virtual work: f · d = Fy y_g + Fz z_g for arbitrary element DOFs d.
    #[test]
    fn force_and_displacement_are_work_conjugate() {
        // Deterministic pseudo-random DOFs (LCG), no extra dependency.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        for _ in 0..50 {
            let d = ElementVector::<f64>::from_fn(|_, _| rnd());
            let (x2, ey, ez, fy, fz) = ((rnd() + 1.0) * L / 2.0, rnd(), rnd(), rnd(), rnd());
            let s = WheelShape::new(x2, L, ey, ez);
            let f = s.nodal_forces(fy, fz);
            let lhs = f.dot(&d);
            let rhs = fy * s.y_at(&d) + fz * s.z_at(&d);
            assert!(close(lhs, rhs, 1e-13), "{lhs} vs {rhs}");
        }
    }

    #[test]
    fn locate_finds_element() {
        let nodes = [0.0, 1.0, 2.5, 4.0];
        assert_eq!(locate(&nodes, -0.1), None);
        assert_eq!(locate(&nodes, 4.1), None);
        assert_eq!(locate(&nodes, f64::NAN), None);
        assert_eq!(locate(&[1.0], 1.0), None);
        let l = locate(&nodes, 0.0).unwrap();
        assert_eq!((l.element, l.x2, l.length), (0, 0.0, 1.0));
        let l = locate(&nodes, 1.0).unwrap();
        assert_eq!((l.element, l.x2, l.length), (1, 0.0, 1.5));
        let l = locate(&nodes, 3.0).unwrap();
        assert_eq!((l.element, l.x2, l.length), (2, 0.5, 1.5));
        let l = locate(&nodes, 4.0).unwrap();
        assert_eq!((l.element, l.x2, l.length), (2, 1.5, 1.5));
        assert_eq!(locate(&[0.0, 0.0], 0.0), None);
    }

    #[test]
    fn gap_formulas() {
        let h0 = 0.01;
        let (p, e) = (Geometry::Paper, Geometry::Ems);
        // Paper (literal Eq. 2): the magnet moving up 1 mm over a still rail opens the gap.
        assert!(close(p.levitation_gap(h0, 1e-3, 0.0, 0.0), 0.011, 1e-15));
        // EMS (magnet under its rail): the same motion closes it.
        assert!(close(e.levitation_gap(h0, 1e-3, 0.0, 0.0), 0.009, 1e-15));
        // The rail moving down 2 mm (z_g = −2e-3) under a still magnet: paper opens, EMS
        // closes the gap by as much.
        assert!(close(p.levitation_gap(h0, 0.0, -2e-3, 0.0), 0.012, 1e-15));
        assert!(close(e.levitation_gap(h0, 0.0, -2e-3, 0.0), 0.008, 1e-15));
        // The irregularity adds to the gap in both.
        assert!(close(p.levitation_gap(h0, 0.0, 0.0, 5e-4), 0.0105, 1e-15));
        assert!(close(e.levitation_gap(h0, 0.0, 0.0, 5e-4), 0.0105, 1e-15));
        // The signs used by linearisations agree with the formulas.
        for g in [p, e] {
            let dh = g.levitation_gap(h0, 1e-6, 0.0, 0.0) - h0;
            assert!(close(dh, g.levitation_sign() * 1e-6, 1e-9));
            assert_eq!(g.guidance_force(1.0, 0.0), g.guidance_sign());
        }
        let d = lateral_offset(1e-3, 4e-4, 1e-4);
        assert!(close(d, 7e-4, 1e-15));
        let (hl, hr) = guidance_gaps(h0, d);
        assert!(close(hl, h0 + 7e-4, 1e-15) && close(hr, h0 - 7e-4, 1e-15));
        assert!(close(hl + hr, 2.0 * h0, 1e-15));
        // Wheel to the right (d > 0): the right gap closes, its magnet pulls harder (G_R > G_L).
        // Paper: the net force is G_L − G_R < 0, back to the centre; EMS: G_R − G_L > 0.
        assert!(p.guidance_force(1.0, 2.0) < 0.0);
        assert!(e.guidance_force(1.0, 2.0) > 0.0);
    }
}
