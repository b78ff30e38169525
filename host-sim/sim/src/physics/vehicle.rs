//! Vehicles (docs/model.md §6, §9): lumped masses (Eq. 17), Kelvin–Voigt spring–dampers with
//! rigid links (Eq. 18), and maglev wheels — the nodes that carry the magnets.
//!
//! The vehicle is written in deviations from its static equilibrium: gravity, the spring
//! preload and the static magnet forces p0 cancel exactly, so its load vector holds only the
//! magnet force *changes* `G − p0` (and the guidance forces, zero at equilibrium). The
//! guideway, which starts undeformed, receives the full forces. Each magnet's p0 is its car's
//! exact static equilibrium ([`VehicleModel::static_wheel_loads`]), not a share of the weight
//! by assumption.
//!
//! A [`Train`] is a list of cars, each its own small [`VehicleModel`] (docs/model.md §10): the
//! cars share no spring, so the train's matrices are block-diagonal and each car is advanced
//! by its own prefactored Newmark solve; no matrix is ever assembled over the whole train.
//! One type serves every kind of car ([`CarKind`]): the Fig. 1 car (here), the Fig. 6
//! maglev carriage and the wheel/rail car (`crate::physics::cars`). A car meets the guideway through
//! maglev [`Wheel`]s (magnets, with their p0) and wheel–rail [`Contact`]s (Hertz springs,
//! with their P0); both loads come from the one static solution of
//! [`VehicleModel::static_loads`].

use crate::physics::cars::fig6::Fig6;
use crate::physics::cars::link::static_solution;
use crate::physics::cars::wheel_rail::WheelRail;
use crate::{Error, Result};
use nalgebra::{DMatrix, DVector};

/// A maglev wheel: a node of the vehicle with Y and Z DOFs, running along the target line.
#[derive(Clone, Debug, PartialEq)]
pub struct Wheel {
    /// X position at t = 0 (m).
    pub x0: f64,
    /// Offset of its target point from the beam axis (rigid link, docs/model.md §5), Y (m).
    pub ey: f64,
    /// Offset of its target point from the beam axis, Z (m).
    pub ez: f64,
    /// Index of its Y and Z DOFs in the vehicle system; no Y DOF for a magnet without
    /// guidance magnets (a `unit`: its guidance force, if computed, acts on nothing).
    pub dof_y: Option<usize>,
    pub dof_z: usize,
}

/// A wheel–rail contact: a linearised Hertz spring between the wheel DOF `dof_z` and the rail
/// target point at (x_w, ey, ez) (docs/model.md §5 rigid link; the contact law, its sign
/// convention and its coupling: docs/cars.md "Wheel–rail contact").
#[derive(Clone, Debug, PartialEq)]
pub struct Contact {
    /// X position at t = 0 (m), the leading contact of the car at 0.
    pub x0: f64,
    /// Offset of the rail target point from the beam axis, Y and Z (m).
    pub ey: f64,
    pub ez: f64,
    /// The wheel's vertical DOF in the car (its own DOF, coefficient 1).
    pub dof_z: usize,
    /// Static wheel load P0 (N, compressive), from the car's exact statics.
    pub p0: f64,
    /// Linearised Hertz stiffness at P0 (N/m), `cars::wheel_rail::hertz_stiffness`.
    pub k_h: f64,
    /// The contact spring between the wheel and the girder's rail point (N/m): the Hertz
    /// spring in series with the track (rail on its pads), `cars::wheel_rail::series`. The
    /// coupling and [`VehicleModel::k_on_rigid_rail`] use this one.
    pub k: f64,
}

/// Parameters of the Fig. 1 vehicle (SI), defaults from docs/model.md §9.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Fig1 {
    #[serde(rename = "body_mass_kg")]
    pub body_mass: f64,
    /// Body inertias about the CoM, X, Y, Z (kg·m²).
    #[serde(rename = "jx_kg_m2")]
    pub jx: f64,
    #[serde(rename = "jy_kg_m2")]
    pub jy: f64,
    #[serde(rename = "jz_kg_m2")]
    pub jz: f64,
    /// Body–wheel spring and damper, Y and Z.
    #[serde(rename = "spring_N_per_m")]
    pub k: f64,
    #[serde(rename = "damper_N_s_per_m")]
    pub c: f64,
    /// Half the wheel spacing along X (m): wheels at ±this from the body centre.
    #[serde(rename = "half_length_m")]
    pub half_length: f64,
    /// Half the wheel spacing along Y (m).
    #[serde(rename = "half_width_m")]
    pub half_width: f64,
    /// Y of the vehicle centre from the beam centre (m).
    #[serde(rename = "offset_y_m")]
    pub offset_y: f64,
    /// Height of the target line above the beam centroid (m).
    #[serde(rename = "target_height_m")]
    pub target_height: f64,
    /// Height of the body CoM above the target line (m).
    #[serde(rename = "body_height_m")]
    pub body_height: f64,
    /// Mass of each wheel node (kg); 0 allowed (damping keeps the system regular).
    #[serde(rename = "wheel_mass_kg")]
    pub wheel_mass: f64,
    /// X of the body CoM ahead of the middle of the wheelbase (m); 0 for the paper's car.
    #[serde(rename = "com_ahead_m")]
    pub com_ahead: f64,
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
            com_ahead: 0.0,
        }
    }
}

/// A levitation unit (`[vehicle] kind = "unit"`, docs/levitation.md): one magnet of
/// `magnet_mass` carrying a body of `body_mass` through a vertical spring `k` and damper `c`,
/// at `position` along the guideway at t = 0. It has no guidance magnets (no lateral DOF).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Unit {
    /// The magnet (kg), > 0.
    #[serde(rename = "magnet_mass_kg")]
    pub magnet_mass: f64,
    /// The body (kg), 0 for none.
    #[serde(rename = "body_mass_kg")]
    pub body_mass: f64,
    /// Magnet–body spring (N/m) and damper (N·s/m).
    #[serde(rename = "spring_N_per_m")]
    pub k: f64,
    #[serde(rename = "damper_N_s_per_m")]
    pub c: f64,
    /// X of the magnet at t = 0 (m).
    #[serde(rename = "position_m")]
    pub position: f64,
}

/// One car of any kind: mass, damping and stiffness (its own small dense matrices, in
/// deviations from its static equilibrium) and the nodes through which it meets the
/// guideway — maglev wheels, wheel–rail contacts, or (in principle) both.
#[derive(Clone, Debug)]
pub struct VehicleModel {
    pub m: DMatrix<f64>,
    pub c: DMatrix<f64>,
    /// Stiffness of the car's own springs (no contact spring: see [`Self::k_on_rigid_rail`]).
    pub k: DMatrix<f64>,
    /// The car's maglev wheels, DOFs local to this car (empty for a wheel/rail car).
    pub wheels: Vec<Wheel>,
    /// Static load per wheel (N, up): the magnet force of the car's static equilibrium.
    pub p0: Vec<f64>,
    /// The car's wheel–rail contacts (empty for a maglev car).
    pub contacts: Vec<Contact>,
    /// The body's heave DOF (the `car{N}.body` probes): the body's centre of mass, at the
    /// middle of the car.
    pub body_z: usize,
    /// The body's pitch (θy) DOF.
    pub body_pitch: usize,
    /// The car's own pitch along a train (m): the next car's leading node this far behind.
    pub length: f64,
    /// Total weight (N): the sum of the static loads.
    pub weight: f64,
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
    /// Each wheel's p0 is the car's static equilibrium under the body's weight.
    pub fn fig1(p: &Fig1, gravity: f64) -> Result<Self> {
        let n = 5 + 4 * 2;
        let mut m = DMatrix::zeros(n, n);
        let mut c = DMatrix::zeros(n, n);
        let mut k = DMatrix::zeros(n, n);
        m[(BODY_V, BODY_V)] = p.body_mass;
        m[(BODY_W, BODY_W)] = p.body_mass;
        m[(BODY_RX, BODY_RX)] = p.jx;
        m[(BODY_RY, BODY_RY)] = p.jy;
        m[(BODY_RZ, BODY_RZ)] = p.jz;
        // Wheels: (X from the middle of the wheelbase, Y from vehicle centre): 1 front-near,
        // 2 front-far, 3 rear-near, 4 rear-far. "Near" is the line closest to the beam axis.
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
            let delta = [p.com_ahead - wx, -wy, p.body_height];
            for dir in [Direction::Y, Direction::Z] {
                let dof = if dir == Direction::Y { dof_y } else { dof_z };
                add_link_spring(&mut k, p.k, dir, dof, delta);
                add_link_spring(&mut c, p.c, dir, dof, delta);
            }
            wheels.push(Wheel {
                x0: wx - p.half_length,
                ey: p.offset_y + wy,
                ez: p.target_height,
                dof_y: Some(dof_y),
                dof_z,
            });
        }
        let mut weight = DVector::zeros(n);
        weight[BODY_W] = -p.body_mass * gravity;
        let mut v = VehicleModel {
            m,
            c,
            k,
            wheels,
            p0: Vec::new(),
            contacts: Vec::new(),
            body_z: BODY_W,
            body_pitch: BODY_RY,
            length: 2.0 * p.half_length,
            weight: p.body_mass * gravity,
        };
        (v.p0, _) = v.static_loads(&weight)?;
        Ok(v)
    }

    /// The levitation unit `p` (DOF 0 the magnet's Z, DOF 1 the body's Z when it has one):
    /// `M = diag(m, m_b)`, the spring and damper between the two; the magnet carries
    /// (m + m_b)·g, the car's statics with the magnet held ([`Self::static_loads`]).
    pub fn unit(p: &Unit, gravity: f64) -> Result<Self> {
        let body = p.body_mass > 0.0;
        let n = 1 + usize::from(body);
        let mut m = DMatrix::zeros(n, n);
        let mut c = DMatrix::zeros(n, n);
        let mut k = DMatrix::zeros(n, n);
        let mut weight = DVector::zeros(n);
        m[(0, 0)] = p.magnet_mass;
        weight[0] = -p.magnet_mass * gravity;
        if body {
            m[(1, 1)] = p.body_mass;
            weight[1] = -p.body_mass * gravity;
            for (i, j, sign) in [(0, 0, 1.0), (0, 1, -1.0), (1, 0, -1.0), (1, 1, 1.0)] {
                k[(i, j)] = sign * p.k;
                c[(i, j)] = sign * p.c;
            }
        }
        let mut v = VehicleModel {
            m,
            c,
            k,
            wheels: vec![Wheel {
                x0: p.position,
                ey: 0.0,
                ez: 0.0,
                dof_y: None,
                dof_z: 0,
            }],
            p0: Vec::new(),
            contacts: Vec::new(),
            body_z: n - 1,
            body_pitch: n - 1,
            length: 0.0,
            weight: (p.magnet_mass + p.body_mass) * gravity,
        };
        (v.p0, _) = v.static_loads(&weight)?;
        Ok(v)
    }

    /// The stiffness with every contact spring tied to a fixed, smooth rail (`k` on each
    /// contact DOF): the car on a rigid rail, and the matrix the coupling integrates (the
    /// contact springs are implicit on the car's side, docs/cars.md). For a maglev car, `k`.
    pub fn k_on_rigid_rail(&self) -> DMatrix<f64> {
        let mut k = self.k.clone();
        for c in &self.contacts {
            k[(c.dof_z, c.dof_z)] += c.k;
        }
        k
    }

    /// The DOFs of the guideway nodes (wheels' Y and Z, contacts' Z), the ones the static
    /// solution holds.
    pub fn node_dofs(&self) -> Vec<usize> {
        let mut d: Vec<usize> = self
            .wheels
            .iter()
            .flat_map(|w| w.dof_y.into_iter().chain([w.dof_z]))
            .collect();
        d.extend(self.contacts.iter().map(|c| c.dof_z));
        d
    }

    /// The static load of every guideway node under the load `weight` (N per DOF; gravity on
    /// the bodies), the nodes held at their targets — the one static solution of every car
    /// kind ([`static_solution`]: `K_ff u_f = weight_f`, the reactions `(K u)_h − weight_h`).
    /// Returns the magnets' forces (N, up; the p0) and the contacts' loads (N, compressive;
    /// the P0), both in node order. A lateral reaction at a magnet would need a guidance
    /// preload the model does not have, so it is refused; a load that is not positive too
    /// (a magnet only pulls, a wheel only pushes).
    pub fn static_loads(&self, weight: &DVector<f64>) -> Result<(Vec<f64>, Vec<f64>)> {
        let (_, r) = static_solution(&self.k, weight, &self.node_dofs())?;
        let total: f64 = weight.iter().map(|w| w.abs()).sum();
        let mut p0 = Vec::with_capacity(self.wheels.len());
        for (i, w) in self.wheels.iter().enumerate() {
            let fy = w.dof_y.map_or(0.0, |y| r[y]);
            if fy.abs() > 1e-9 * total {
                return Err(Error::invalid(
                    "vehicle",
                    format!(
                        "wheel {} carries a static lateral load of {fy:.3e} N; the guidance magnets have no preload (|F_y| ≤ 1e-9 of the weight)",
                        i + 1
                    ),
                ));
            }
            let fz = r[w.dof_z];
            if !(fz.is_finite() && fz > 0.0) {
                return Err(Error::invalid(
                    "vehicle",
                    format!(
                        "wheel {} static load {fz:.3e} N: must be positive (a magnet only pulls)",
                        i + 1
                    ),
                ));
            }
            p0.push(fz);
        }
        let mut contact = Vec::with_capacity(self.contacts.len());
        for (i, c) in self.contacts.iter().enumerate() {
            let fz = r[c.dof_z];
            if !(fz.is_finite() && fz > 0.0) {
                return Err(Error::invalid(
                    "vehicle",
                    format!(
                        "contact {} static load {fz:.3e} N: must be positive (a wheel only pushes on its rail)",
                        i + 1
                    ),
                ));
            }
            contact.push(fz);
        }
        Ok((p0, contact))
    }
}

/// A car of a train: its kind and its parameters.
#[derive(Clone, Debug, PartialEq)]
pub enum CarKind {
    /// The Fig. 1 car (docs/model.md §9).
    Fig1(Fig1),
    /// The Fig. 6 maglev carriage: 32 magnet wheels (docs/cars.md).
    Fig6Maglev(Fig6),
    /// The wheel/rail comparison car: 8 Hertz contacts (docs/cars.md).
    WheelRail(WheelRail),
    /// A levitation unit: one magnet under a body.
    Unit(Unit),
}

impl CarKind {
    /// Builds the car under `gravity`, its leading node at x = 0.
    pub fn build(&self, gravity: f64) -> Result<VehicleModel> {
        match self {
            CarKind::Fig1(p) => VehicleModel::fig1(p, gravity),
            CarKind::Fig6Maglev(p) => p.build(gravity),
            CarKind::WheelRail(p) => p.build(gravity),
            CarKind::Unit(p) => VehicleModel::unit(p, gravity),
        }
    }
}

/// One car of a train specification.
#[derive(Clone, Debug, PartialEq)]
pub struct CarSpec {
    pub kind: CarKind,
    /// Distance of the car's leading node behind the train's leading node (m, ≥ 0).
    pub offset: f64,
}

/// A wheel of a train: which car carries it, and the car's wheel (DOFs local to that car).
#[derive(Clone, Debug, PartialEq)]
pub struct TrainWheel {
    pub car: usize,
    /// X at t = 0 (m), along the train.
    pub x0: f64,
    pub ey: f64,
    pub ez: f64,
    /// The wheel's Y (if guided) and Z DOFs in its car.
    pub dof_y: Option<usize>,
    pub dof_z: usize,
}

/// A wheel–rail contact of a train: which car carries it, and the car's contact.
#[derive(Clone, Debug, PartialEq)]
pub struct TrainContact {
    pub car: usize,
    /// X at t = 0 (m), along the train.
    pub x0: f64,
    pub ey: f64,
    pub ez: f64,
    /// The wheel's Z DOF in its car.
    pub dof_z: usize,
    /// Static load (N, compressive) and the contact spring (N/m, [`Contact::k`]).
    pub p0: f64,
    pub k: f64,
}

/// A guideway node of a train as the probes number them (`wheel{N}`): a magnet wheel (index
/// into [`Train::wheels`]) or a wheel–rail contact (index into [`Train::contacts`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Node {
    Magnet(usize),
    Contact(usize),
}

/// A train: cars one behind the other, block-diagonal (module docs). Cars and their guideway
/// nodes are numbered along the train from the front (car 1's nodes first, each car's magnets
/// before its contacts), for the probes.
#[derive(Clone, Debug)]
pub struct Train {
    /// Each car's model, its nodes' `x0` along the train.
    pub cars: Vec<VehicleModel>,
    /// Every magnet wheel of the train, in order.
    pub wheels: Vec<TrainWheel>,
    /// Each magnet wheel's static load (N), in the same order.
    pub p0: Vec<f64>,
    /// Every wheel–rail contact of the train, in order.
    pub contacts: Vec<TrainContact>,
    /// Every guideway node in probe order (`wheel{N}` is `nodes[N − 1]`).
    pub nodes: Vec<Node>,
    /// Advance the cars on rayon's pool (off by default; see docs/performance.md).
    pub parallel: bool,
}

impl Train {
    /// Builds the cars of `specs` under `gravity`.
    pub fn new(specs: &[CarSpec], gravity: f64) -> Result<Self> {
        if specs.is_empty() {
            return Err(Error::invalid("train", "needs at least one car"));
        }
        let mut cars = Vec::with_capacity(specs.len());
        for (i, s) in specs.iter().enumerate() {
            if !(s.offset.is_finite() && s.offset >= 0.0) {
                return Err(Error::invalid(
                    format!("train car {}", i + 1),
                    format!(
                        "offset must be zero or positive (behind the leading node), got {}",
                        s.offset
                    ),
                ));
            }
            let mut car = s.kind.build(gravity)?;
            for w in &mut car.wheels {
                w.x0 -= s.offset;
            }
            for c in &mut car.contacts {
                c.x0 -= s.offset;
            }
            cars.push(car);
        }
        Ok(Self::from_cars(cars))
    }

    /// `n` identical cars of `kind`, `spacing` apart (leading node to leading node); the
    /// train's leading node at x = 0 at t = 0.
    pub fn repeated(kind: &CarKind, n: usize, spacing: f64, gravity: f64) -> Result<Self> {
        if !(spacing.is_finite() && spacing > 0.0) && n > 1 {
            return Err(Error::invalid(
                "train.car_length_m",
                format!("must be > 0, got {spacing}"),
            ));
        }
        let specs: Vec<CarSpec> = (0..n)
            .map(|i| CarSpec {
                kind: kind.clone(),
                offset: i as f64 * spacing,
            })
            .collect();
        Self::new(&specs, gravity)
    }

    /// `n` identical Fig. 1 cars `spacing` apart (leading wheel to leading wheel).
    pub fn fig1_repeated(p: &Fig1, n: usize, spacing: f64, gravity: f64) -> Result<Self> {
        Self::repeated(&CarKind::Fig1(p.clone()), n, spacing, gravity)
    }

    /// `n` Fig. 6 maglev carriages (default parameters, docs/cars.md) at their own pitch,
    /// 16 × 1.5625 = 25 m, so every magnet of the train keeps the equal 1.5625 m spacing.
    pub fn fig6(n: usize, gravity: f64) -> Result<Self> {
        Self::fig6_with(&Fig6::default(), n, gravity)
    }

    /// `n` Fig. 6 carriages of parameters `p` at their own pitch.
    pub fn fig6_with(p: &Fig6, n: usize, gravity: f64) -> Result<Self> {
        Self::repeated(&CarKind::Fig6Maglev(p.clone()), n, p.car_pitch(), gravity)
    }

    /// `n` wheel/rail cars (default parameters, docs/cars.md) at their 25 m pitch.
    pub fn wheel_rail(n: usize, gravity: f64) -> Result<Self> {
        let p = WheelRail::default();
        let pitch = p.car_length;
        Self::repeated(&CarKind::WheelRail(p), n, pitch, gravity)
    }

    /// A train of the given car models, as they are.
    pub fn from_cars(cars: Vec<VehicleModel>) -> Self {
        let mut wheels = Vec::new();
        let mut p0 = Vec::new();
        let mut contacts = Vec::new();
        let mut nodes = Vec::new();
        for (c, car) in cars.iter().enumerate() {
            for (w, &p) in car.wheels.iter().zip(&car.p0) {
                nodes.push(Node::Magnet(wheels.len()));
                wheels.push(TrainWheel {
                    car: c,
                    x0: w.x0,
                    ey: w.ey,
                    ez: w.ez,
                    dof_y: w.dof_y,
                    dof_z: w.dof_z,
                });
                p0.push(p);
            }
            for k in &car.contacts {
                nodes.push(Node::Contact(contacts.len()));
                contacts.push(TrainContact {
                    car: c,
                    x0: k.x0,
                    ey: k.ey,
                    ez: k.ez,
                    dof_z: k.dof_z,
                    p0: k.p0,
                    k: k.k,
                });
            }
        }
        Train {
            cars,
            wheels,
            p0,
            contacts,
            nodes,
            parallel: false,
        }
    }

    /// X at t = 0 of every guideway node, in probe order.
    pub fn node_x0(&self) -> Vec<f64> {
        self.nodes
            .iter()
            .map(|n| match *n {
                Node::Magnet(i) => self.wheels[i].x0,
                Node::Contact(i) => self.contacts[i].x0,
            })
            .collect()
    }
}

impl From<VehicleModel> for Train {
    fn from(v: VehicleModel) -> Self {
        Train::from_cars(vec![v])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rigid_body_motion_strains_no_spring() {
        // Move the body and the wheels as one rigid body: K·u must vanish.
        let p = Fig1::default();
        let v = VehicleModel::fig1(&p, 9.81).unwrap();
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
            u[w.dof_y.unwrap()] = 0.01 + (rz * r[0] - rx * r[2]);
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
        let v = VehicleModel::fig1(&p, 9.81).unwrap();
        let mut u = nalgebra::DVector::zeros(13);
        u[BODY_W] = 1.0;
        let f = &v.k * &u;
        assert!((f[BODY_W] - 4.0 * p.k).abs() < 1e-6);
        // A unit heave pulls each wheel up with k.
        for w in &v.wheels {
            assert!((f[w.dof_z] + p.k).abs() < 1e-6);
        }
    }

    #[test]
    fn symmetric_car_carries_a_quarter_of_the_weight_per_wheel() {
        let p = Fig1::default();
        let v = VehicleModel::fig1(&p, 9.81).unwrap();
        let quarter = p.body_mass * 9.81 / 4.0;
        for &p0 in &v.p0 {
            assert!(
                (p0 - quarter).abs() <= 4.0 * f64::EPSILON * quarter,
                "{p0} vs {quarter}"
            );
        }
    }

    #[test]
    fn com_ahead_loads_the_front_wheels_as_the_lever_rule_says() {
        // Body CoM e ahead of the middle of the wheelbase 2h: moments about the CoM,
        // 2·F_f·(h − e) = 2·F_r·(h + e), and 2·F_f + 2·F_r = W, so
        // F_f = W (h + e)/(4h), F_r = W (h − e)/(4h) (lateral symmetry: near = far).
        for e in [0.9, -2.5, 6.0] {
            let p = Fig1 {
                com_ahead: e,
                wheel_mass: 300.0,
                ..Fig1::default()
            };
            let v = VehicleModel::fig1(&p, 9.81).unwrap();
            let (w, h) = (p.body_mass * 9.81, p.half_length);
            let want = [
                w * (h + e) / (4.0 * h),
                w * (h + e) / (4.0 * h),
                w * (h - e) / (4.0 * h),
                w * (h - e) / (4.0 * h),
            ];
            for (got, want) in v.p0.iter().zip(want) {
                assert!((got - want).abs() <= 1e-12 * w, "e = {e}: {got} vs {want}");
            }
        }
        // CoM beyond the front axle: the rear magnets would have to push.
        let p = Fig1 {
            com_ahead: 8.0,
            ..Fig1::default()
        };
        let e = VehicleModel::fig1(&p, 9.81).unwrap_err().to_string();
        assert!(e.contains("must be positive"), "{e}");
    }

    /// The unit's magnet carries (magnet + body)·g, with or without a body, and its model
    /// is the two-mass oscillator written out by hand.
    #[test]
    fn a_unit_carries_magnet_and_body() {
        for body in [0.0, 4000.0] {
            let p = Unit {
                magnet_mass: 600.0,
                body_mass: body,
                k: 3e5,
                c: 2e4,
                position: 10.0,
            };
            let v = VehicleModel::unit(&p, 9.81).unwrap();
            let want = (600.0 + body) * 9.81;
            assert!((v.p0[0] - want).abs() <= 1e-12 * want, "{:?}", v.p0);
            assert_eq!(v.wheels[0].x0, 10.0);
            assert_eq!(v.wheels[0].dof_y, None);
            if body > 0.0 {
                assert_eq!(v.k[(0, 1)], -3e5);
                assert_eq!(v.c[(1, 1)], 2e4);
                assert_eq!(v.m[(1, 1)], body);
                assert_eq!(v.body_z, 1);
            } else {
                assert_eq!(v.m.shape(), (1, 1));
            }
        }
    }

    #[test]
    fn a_train_numbers_its_wheels_along_the_train() {
        let p = Fig1::default();
        let t = Train::fig1_repeated(&p, 3, 25.0, 9.81).unwrap();
        assert_eq!(t.cars.len(), 3);
        assert_eq!(t.wheels.len(), 12);
        assert_eq!(t.p0.len(), 12);
        // Car 2's wheels are car 1's, 25 m further back, with the car's own DOFs.
        for i in 0..4 {
            assert_eq!(t.wheels[4 + i].car, 1);
            assert_eq!(t.wheels[4 + i].x0, t.wheels[i].x0 - 25.0);
            assert_eq!(t.wheels[4 + i].dof_z, t.wheels[i].dof_z);
        }
        assert_eq!(t.wheels[0].x0, 0.0);
        assert!(Train::new(&[], 9.81).is_err());
        let bad = CarSpec {
            kind: CarKind::Fig1(p),
            offset: f64::NAN,
        };
        assert!(Train::new(&[bad], 9.81).is_err());
    }

    #[test]
    fn fig6_and_wheel_rail_trains_place_their_cars_25_m_apart_from_x_0() {
        let t = Train::fig6(2, 9.81).unwrap();
        assert_eq!((t.cars.len(), t.wheels.len(), t.contacts.len()), (2, 64, 0));
        assert_eq!(t.wheels[0].x0, 0.0);
        // The magnet positions of the whole train: equal 1.5625 m steps across the cars.
        let mut xs: Vec<f64> = t.wheels.iter().map(|w| w.x0).collect();
        xs.sort_by(|a, b| b.total_cmp(a));
        xs.dedup();
        assert_eq!(xs.len(), 32);
        for (i, x) in xs.iter().enumerate() {
            assert!((x + 1.5625 * i as f64).abs() < 1e-12, "{i}: {x}");
        }
        for i in 0..32 {
            assert_eq!(t.wheels[32 + i].x0, t.wheels[i].x0 - 25.0);
            assert_eq!(t.nodes[32 + i], Node::Magnet(32 + i));
        }
        let t = Train::wheel_rail(2, 9.81).unwrap();
        assert_eq!(
            (t.wheels.len(), t.contacts.len(), t.nodes.len()),
            (0, 16, 16)
        );
        assert_eq!(t.contacts[0].x0, 0.0);
        for i in 0..8 {
            assert_eq!(t.contacts[8 + i].x0, t.contacts[i].x0 - 25.0);
            assert_eq!(t.contacts[8 + i].car, 1);
            assert_eq!(t.nodes[8 + i], Node::Contact(8 + i));
        }
        // Axles at 0, −2.5, −17.5, −20 m (bogie centres 17.5 m apart, wheelbase 2.5 m).
        let axles: Vec<f64> = t.contacts[..8].iter().step_by(2).map(|c| c.x0).collect();
        for (got, want) in axles.iter().zip([0.0, -2.5, -17.5, -20.0]) {
            assert!((got - want).abs() < 1e-12, "{got} vs {want}");
        }
        assert!(Train::repeated(&CarKind::WheelRail(WheelRail::default()), 2, 0.0, 9.81).is_err());
    }
}
