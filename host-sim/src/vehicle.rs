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
    /// X of the body CoM ahead of the middle of the wheelbase (m); 0 for the paper's car.
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

/// One car: mass, damping and stiffness (its own small dense matrices) and its wheels.
#[derive(Clone, Debug)]
pub struct VehicleModel {
    pub m: DMatrix<f64>,
    pub c: DMatrix<f64>,
    pub k: DMatrix<f64>,
    /// The car's wheels, DOFs local to this car.
    pub wheels: Vec<Wheel>,
    /// Static load per wheel (N, up): the magnet force of the car's static equilibrium.
    pub p0: Vec<f64>,
    /// The body's heave DOF (the `car{N}.body` probes).
    pub body_z: usize,
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
                dof_y,
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
            body_z: BODY_W,
        };
        v.p0 = v.static_wheel_loads(&weight)?;
        Ok(v)
    }

    /// The magnet force (N, up) each wheel node needs for static equilibrium under the load
    /// `weight` (N per DOF; gravity on the bodies), the wheel nodes held at their targets:
    /// with f the free (non-wheel) DOFs, `K_ff u_f = weight_f` and the wheel rows give the
    /// magnet forces `K_wf u_f − weight_w`. The vertical ones are the p0; a lateral one
    /// would need a guidance preload the model does not have, so it is refused.
    pub fn static_wheel_loads(&self, weight: &DVector<f64>) -> Result<Vec<f64>> {
        let n = self.k.nrows();
        let held: Vec<usize> = self
            .wheels
            .iter()
            .flat_map(|w| [w.dof_y, w.dof_z])
            .collect();
        let free: Vec<usize> = (0..n).filter(|i| !held.contains(i)).collect();
        let kff = DMatrix::from_fn(free.len(), free.len(), |i, j| self.k[(free[i], free[j])]);
        let wf = DVector::from_fn(free.len(), |i, _| weight[free[i]]);
        let uf = kff.lu().solve(&wf).ok_or_else(|| {
            Error::numerical("vehicle: the body is not held by its springs (singular statics)")
        })?;
        let reaction = |dof: usize| -> f64 {
            free.iter()
                .zip(uf.iter())
                .map(|(&j, &u)| self.k[(dof, j)] * u)
                .sum::<f64>()
                - weight[dof]
        };
        let total: f64 = weight.iter().map(|w| w.abs()).sum();
        let mut p0 = Vec::with_capacity(self.wheels.len());
        for (i, w) in self.wheels.iter().enumerate() {
            let fy = reaction(w.dof_y);
            if fy.abs() > 1e-9 * total {
                return Err(Error::invalid(
                    "vehicle",
                    format!(
                        "wheel {} carries a static lateral load of {fy:.3e} N; the guidance magnets have no preload (|F_y| ≤ 1e-9 of the weight)",
                        i + 1
                    ),
                ));
            }
            let fz = reaction(w.dof_z);
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
        Ok(p0)
    }
}

/// A car of a train: its kind and where it runs.
///
/// Only the Fig. 1 car exists today; the Fig. 6 maglev carriage (four bogies of four magnets
/// a side at 1.5625 m, bodies and bogies joined by springs) and a wheel/rail car are further
/// kinds of the same list: each builds its own [`VehicleModel`] and gets its p0 from
/// [`VehicleModel::static_wheel_loads`].
#[derive(Clone, Debug, PartialEq)]
pub enum CarKind {
    /// The Fig. 1 car (docs/model.md §9).
    Fig1(Fig1),
}

/// One car of a train specification.
#[derive(Clone, Debug, PartialEq)]
pub struct CarSpec {
    pub kind: CarKind,
    /// Distance of the car's leading wheel behind the train's leading wheel (m, ≥ 0).
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
    /// The wheel's Y and Z DOFs in its car.
    pub dof_y: usize,
    pub dof_z: usize,
}

/// A train: cars one behind the other, block-diagonal (module docs). Wheels and cars are
/// numbered along the train from the front (car 1's wheels first), for the probes.
#[derive(Clone, Debug)]
pub struct Train {
    /// Each car's model, its wheels' `x0` along the train.
    pub cars: Vec<VehicleModel>,
    /// Every wheel of the train, in order.
    pub wheels: Vec<TrainWheel>,
    /// Each wheel's static load (N), in the same order.
    pub p0: Vec<f64>,
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
                        "offset must be zero or positive (behind the leading wheel), got {}",
                        s.offset
                    ),
                ));
            }
            let mut car = match &s.kind {
                CarKind::Fig1(p) => VehicleModel::fig1(p, gravity)?,
            };
            for w in &mut car.wheels {
                w.x0 -= s.offset;
            }
            cars.push(car);
        }
        Ok(Self::from_cars(cars))
    }

    /// `n` identical Fig. 1 cars `spacing` apart (leading wheel to leading wheel).
    pub fn fig1_repeated(p: &Fig1, n: usize, spacing: f64, gravity: f64) -> Result<Self> {
        let specs: Vec<CarSpec> = (0..n)
            .map(|i| CarSpec {
                kind: CarKind::Fig1(p.clone()),
                offset: i as f64 * spacing,
            })
            .collect();
        Self::new(&specs, gravity)
    }

    /// A train of the given car models, as they are.
    pub fn from_cars(cars: Vec<VehicleModel>) -> Self {
        let mut wheels = Vec::new();
        let mut p0 = Vec::new();
        for (c, car) in cars.iter().enumerate() {
            for (w, &p) in car.wheels.iter().zip(&car.p0) {
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
        }
        Train {
            cars,
            wheels,
            p0,
            parallel: false,
        }
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
}
