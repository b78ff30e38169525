//! Rigid bodies and the spring–dampers between them (docs/model.md §6, Eq. 17, 18), for cars
//! made of several rigid bodies.
//!
//! Why a general form: [`crate::physics::vehicle::add_link_spring`] ties a node to *the* body at DOFs
//! 0..5. A carriage has a body, bogies and wheelsets, each a rigid body with its own DOFs, and
//! an element may join a point of any body to a point of any other. Here every body says how
//! its reference point moves — each of the six components (u_x, u_y, u_z, θx, θy, θz) as a
//! linear combination of car DOFs; an empty combination is a component held at zero — and a
//! point p of the body moves as `u(p) = t + θ × (p − r)` (small rotations). Along a global
//! axis e that is `e·t + (d × e)·θ` with `d = p − r`, which for Z gives Eq. 18's
//! (D1, D2) = (−ΔY, ΔX) on (θx, θy) with Δ = master − slave = −d, and likewise for X and Y.
//! A combination rather than one DOF per component lets a wheelset be written in its two
//! wheels' vertical displacements (see `wheel_rail`), so that each contact sits on a DOF of
//! its own.

use crate::{Error, Result};
use nalgebra::{DMatrix, DVector};

/// A global direction of an element.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    X,
    Y,
    Z,
}

impl Axis {
    fn unit(self) -> [f64; 3] {
        match self {
            Axis::X => [1.0, 0.0, 0.0],
            Axis::Y => [0.0, 1.0, 0.0],
            Axis::Z => [0.0, 0.0, 1.0],
        }
    }
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// A sparse row: (DOF, coefficient) pairs, repeated DOFs allowed (they add).
pub type Row = Vec<(usize, f64)>;

/// Translation components 0..3, rotation components 3..6 of [`Rigid::motion`].
pub const UX: usize = 0;
pub const UY: usize = 1;
pub const UZ: usize = 2;
pub const RX: usize = 3;
pub const RY: usize = 4;
pub const RZ: usize = 5;

/// One rigid body (or a node: a body with translations only), in the car's DOFs.
#[derive(Clone, Debug, PartialEq)]
pub struct Rigid {
    /// Reference point (the centre of mass), in the car's frame (m).
    pub at: [f64; 3],
    /// Each motion component of the reference point as a combination of car DOFs.
    pub motion: [Row; 6],
}

impl Rigid {
    /// A body at `at` with every component held.
    pub fn new(at: [f64; 3]) -> Self {
        Rigid {
            at,
            motion: Default::default(),
        }
    }

    /// Component `comp` is car DOF `dof` (coefficient 1).
    pub fn dof(mut self, comp: usize, dof: usize) -> Self {
        self.motion[comp].push((dof, 1.0));
        self
    }

    /// Component `comp` is the combination `row`.
    pub fn combo(mut self, comp: usize, row: Row) -> Self {
        self.motion[comp] = row;
        self
    }

    /// The displacement of point `p` of this body along `axis`, as a row over car DOFs.
    pub fn point_row(&self, p: [f64; 3], axis: Axis) -> Row {
        let e = axis.unit();
        let d = [p[0] - self.at[0], p[1] - self.at[1], p[2] - self.at[2]];
        let r = cross(d, e);
        let mut row = Row::new();
        for k in 0..3 {
            for &(dof, c) in &self.motion[k] {
                if e[k] != 0.0 {
                    row.push((dof, e[k] * c));
                }
            }
            for &(dof, c) in &self.motion[3 + k] {
                if r[k] != 0.0 {
                    row.push((dof, r[k] * c));
                }
            }
        }
        row
    }

    /// Adds the body's lumped mass (Eq. 17) `diag(m, m, m, Ix, Iy, Iz)` to `mat`, through its
    /// motion combinations: `M += Σ_k mass_k · a_kᵀ a_k`.
    pub fn add_mass(&self, mat: &mut DMatrix<f64>, m: f64, inertia: [f64; 3]) {
        let mass = [m, m, m, inertia[0], inertia[1], inertia[2]];
        for (row, &mk) in self.motion.iter().zip(&mass) {
            add_outer(mat, mk, row);
        }
    }

    /// Adds the body's weight `m·g` (along −Z at its reference point) to the load vector.
    pub fn add_weight(&self, f: &mut DVector<f64>, m: f64, gravity: f64) {
        for &(dof, c) in &self.motion[UZ] {
            f[dof] -= m * gravity * c;
        }
    }
}

/// `mat += s · rowᵀ row`.
pub fn add_outer(mat: &mut DMatrix<f64>, s: f64, row: &Row) {
    for &(i, a) in row {
        for &(j, b) in row {
            mat[(i, j)] += s * a * b;
        }
    }
}

/// One end of an element: a point `p` of body `body`.
#[derive(Clone, Copy, Debug)]
pub struct End<'a> {
    pub body: &'a Rigid,
    pub p: [f64; 3],
}

/// The elongation row of an element along `axis` from end `b` to end `a`:
/// `S·u = u_a(p_a)·e − u_b(p_b)·e` (Eq. 18's S).
///
/// The two ends must lie on one line along the element's direction (p_a − p_b ∥ e): only
/// then does a rigid rotation of the whole car leave the element unstrained (the relative
/// displacement of the ends under a rotation θ is θ × (p_a − p_b)). An element whose ends
/// are offset across its direction is refused.
pub fn elongation(axis: Axis, a: End, b: End) -> Result<Row> {
    let e = axis.unit();
    let gap = [a.p[0] - b.p[0], a.p[1] - b.p[1], a.p[2] - b.p[2]];
    let off = cross(gap, e);
    let scale = 1.0 + gap.iter().map(|g| g.abs()).fold(0.0, f64::max);
    if off.iter().any(|o| o.abs() > 1e-12 * scale) {
        return Err(Error::invalid(
            "car.element",
            format!(
                "the ends of a {axis:?} spring–damper must lie on a line along {axis:?}, got \
                 {:?} and {:?}",
                a.p, b.p
            ),
        ));
    }
    let mut row = a.body.point_row(a.p, axis);
    row.extend(
        b.body
            .point_row(b.p, axis)
            .into_iter()
            .map(|(d, c)| (d, -c)),
    );
    Ok(row)
}

/// A Kelvin–Voigt element (Eq. 18): adds `k·SᵀS` to `kmat` and `c·SᵀS` to `cmat`.
pub fn add_spring_damper(
    kmat: &mut DMatrix<f64>,
    cmat: &mut DMatrix<f64>,
    (k, c): (f64, f64),
    axis: Axis,
    a: End,
    b: End,
) -> Result<()> {
    let s = elongation(axis, a, b)?;
    add_outer(kmat, k, &s);
    add_outer(cmat, c, &s);
    Ok(())
}
