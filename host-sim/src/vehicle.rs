//! Vehicles (docs/model.md §6, §9): lumped masses (Eq. 17), Kelvin–Voigt spring–dampers with
//! rigid links (Eq. 18), and maglev wheels — the nodes that carry the magnets.
//!
//! The vehicle is written in deviations from its static equilibrium: gravity, the spring
//! preload and the static magnet forces p0 cancel exactly, so its load vector holds only the
//! magnet force *changes* `G − p0` (and the guidance forces, zero at equilibrium). The
//! guideway, which starts undeformed, receives the full forces.

use nalgebra::DMatrix;

/// A maglev wheel: a node of the vehicle with Y and Z DOFs, running along the target line.
#[derive(Clone, Debug, PartialEq)]
pub struct Wheel {
    /// X position at t = 0 (m).
    pub x0: f64,
    /// Offset of its target point from the beam axis (rigid link, docs/model.md §5), Y (m).
    pub ey: f64,
    /// Offset of its target point from the beam axis, Z (m).
    pub ez: f64,
    /// Index of its Y and Z DOFs in the vehicle system.
    pub dof_y: usize,
    pub dof_z: usize,
}

/// Parameters of the Fig. 1 vehicle (SI), defaults from docs/model.md §9.
#[derive(Clone, Debug, PartialEq)]
pub struct Fig1 {
    pub body_mass: f64,
    /// Body inertias about the CoM, X, Y, Z (kg·m²).
    pub jx: f64,
    pub jy: f64,
    pub jz: f64,
    /// Body–wheel spring and damper, Y and Z.
    pub k: f64,
    pub c: f64,
    /// Half the wheel spacing along X (m): wheels at ±this from the body centre.
    pub half_length: f64,
    /// Half the wheel spacing along Y (m).
    pub half_width: f64,
    /// Y of the vehicle centre from the beam centre (m).
    pub offset_y: f64,
    /// Height of the target line above the beam centroid (m).
    pub target_height: f64,
    /// Height of the body CoM above the target line (m).
    pub body_height: f64,
    /// Mass of each wheel node (kg); 0 allowed (damping keeps the system regular).
    pub wheel_mass: f64,
}

impl Default for Fig1 {
    fn default() -> Self {
        Fig1 {
            body_mass: 15_000.0,
            jx: 20e3,
            jy: 950e3,
            jz: 1600e3,
            k: 200e3,
            c: 10e3,
            half_length: 7.5,
            half_width: 1.5,
            offset_y: 1.5,
            target_height: 0.6,
            body_height: 2.0,
            wheel_mass: 0.0,
        }
    }
}

/// Mass, damping and stiffness of a vehicle and where its wheels are.
pub struct VehicleModel {
    pub m: DMatrix<f64>,
    pub c: DMatrix<f64>,
    pub k: DMatrix<f64>,
    pub wheels: Vec<Wheel>,
    /// Static load per wheel (N): the share of the weight each magnet carries.
    pub p0: Vec<f64>,
    /// The body heave DOF of each car (the `car{N}.body` probes).
    pub cars: Vec<usize>,
}

/// Body DOFs: v, w, θx, θy, θz (u along X carries no force and is left out).
const BODY_V: usize = 0;
const BODY_W: usize = 1;
const BODY_RX: usize = 2;
const BODY_RY: usize = 3;
const BODY_RZ: usize = 4;

/// Direction of a spring–damper element (Eq. 18).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    Y,
    Z,
}

/// Adds `s·S·Sᵀ` for a spring (or damper) of value `s` between a free node DOF `node_dof`
/// and a slave point of the body at offset Δ = master − slave (Eq. 18). For Z:
/// S = [1 at node, −1 at body w, −D1 at θx, −D2 at θy] with (D1, D2) = (−ΔY, ΔX); for Y:
/// (D1, D2) = (ΔZ, −ΔX) on (θx, θz). The slave point moves as master + θ × (slave − master).
pub fn add_link_spring(
    mat: &mut DMatrix<f64>,
    s: f64,
    dir: Direction,
    node_dof: usize,
    delta: [f64; 3],
) {
    let [dx, dy, dz] = delta;
    let entries: [(usize, f64); 4] = match dir {
        Direction::Z => [
            (node_dof, 1.0),
            (BODY_W, -1.0),
            (BODY_RX, dy),
            (BODY_RY, -dx),
        ],
        Direction::Y => [
            (node_dof, 1.0),
            (BODY_V, -1.0),
            (BODY_RX, -dz),
            (BODY_RZ, dx),
        ],
    };
    for &(i, si) in &entries {
        for &(j, sj) in &entries {
            mat[(i, j)] += s * si * sj;
        }
    }
}

impl VehicleModel {
    /// The Fig. 1 car: rigid body on four maglev wheels. Wheel 1 leads on the line nearest
    /// the beam axis; wheel 1 is at x = 0 at t = 0, the others behind it (docs/model.md §9).
    pub fn fig1(p: &Fig1, gravity: f64) -> Self {
        let n = 5 + 4 * 2;
        let mut m = DMatrix::zeros(n, n);
        let mut c = DMatrix::zeros(n, n);
        let mut k = DMatrix::zeros(n, n);
        m[(BODY_V, BODY_V)] = p.body_mass;
        m[(BODY_W, BODY_W)] = p.body_mass;
        m[(BODY_RX, BODY_RX)] = p.jx;
        m[(BODY_RY, BODY_RY)] = p.jy;
        m[(BODY_RZ, BODY_RZ)] = p.jz;
        // Wheels: (X from body centre, Y from vehicle centre): 1 front-near, 2 front-far,
        // 3 rear-near, 4 rear-far. "Near" is the line closest to the beam axis.
        let layout = [
            (p.half_length, -p.half_width),
            (p.half_length, p.half_width),
            (-p.half_length, -p.half_width),
            (-p.half_length, p.half_width),
        ];
        let mut wheels = Vec::new();
        for (i, &(wx, wy)) in layout.iter().enumerate() {
            let (dof_y, dof_z) = (5 + 2 * i, 6 + 2 * i);
            m[(dof_y, dof_y)] = p.wheel_mass;
            m[(dof_z, dof_z)] = p.wheel_mass;
            // Slave point on the body at the wheel; master = body CoM, Δ = master − slave.
            let delta = [-wx, -wy, p.body_height];
            for dir in [Direction::Y, Direction::Z] {
                let dof = if dir == Direction::Y { dof_y } else { dof_z };
                add_link_spring(&mut k, p.k, dir, dof, delta);
                add_link_spring(&mut c, p.c, dir, dof, delta);
            }
            wheels.push(Wheel {
                x0: wx - p.half_length,
                ey: p.offset_y + wy,
                ez: p.target_height,
                dof_y,
                dof_z,
            });
        }
        let p0 = vec![p.body_mass * gravity / 4.0; 4];
        VehicleModel {
            m,
            c,
            k,
            wheels,
            p0,
            cars: vec![BODY_W],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rigid_body_motion_strains_no_spring() {
        // Move the body and the wheels as one rigid body: K·u must vanish.
        let p = Fig1::default();
        let v = VehicleModel::fig1(&p, 9.81);
        let (ry, rx, rz) = (1e-3, 2e-3, 3e-3);
        let mut u = nalgebra::DVector::zeros(13);
        u[BODY_V] = 0.01;
        u[BODY_W] = 0.02;
        u[BODY_RX] = rx;
        u[BODY_RY] = ry;
        u[BODY_RZ] = rz;
        for (i, w) in v.wheels.iter().enumerate() {
            // Wheel position relative to the CoM: r = (wx, wy, −body_height).
            let wx = w.x0 + p.half_length;
            let wy = w.ey - p.offset_y;
            let r = [wx, wy, -p.body_height];
            // displacement = translation + θ × r
            u[w.dof_y] = 0.01 + (rz * r[0] - rx * r[2]);
            u[w.dof_z] = 0.02 + (rx * r[1] - ry * r[0]);
            let _ = i;
        }
        let f = &v.k * &u;
        assert!(f.amax() < 1e-9, "{f}");
    }

    #[test]
    fn heave_frequency_of_the_suspension() {
        // Body on four springs, massless wheels held (rigid rail): ω² = 4k/m.
        let p = Fig1 {
            wheel_mass: 0.0,
            ..Fig1::default()
        };
        let v = VehicleModel::fig1(&p, 9.81);
        let mut u = nalgebra::DVector::zeros(13);
        u[BODY_W] = 1.0;
        let f = &v.k * &u;
        assert!((f[BODY_W] - 4.0 * p.k).abs() < 1e-6);
        // A unit heave pulls each wheel up with k.
        for w in &v.wheels {
            assert!((f[w.dof_z] + p.k).abs() < 1e-6);
        }
    }
}
