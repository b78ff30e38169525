//! A train (docs/model.md §10): cars one behind the other, each its own small
//! [`VehicleModel`]. The cars share no spring, so the train's matrices are block-diagonal and
//! each car is advanced by its own prefactored Newmark solve; no matrix is ever assembled over
//! the whole train. Every kind of car ([`CarKind`]) builds its block: the Fig. 1 car and the
//! unit (`crate::physics::vehicle`), the Fig. 6 maglev carriage and the wheel/rail car
//! (`crate::physics::cars`).

use crate::physics::cars::fig6::Fig6;
use crate::physics::cars::wheel_rail::WheelRail;
use crate::physics::rail::run::RailTrain;
use crate::physics::vehicle::{Fig1, Unit, VehicleModel};
use crate::{Error, Result};

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
    /// Static load (N, compressive) and the contact spring (N/m, [`crate::physics::vehicle::Contact::k`]).
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
    /// The 3-D high-speed cars and their track (`crate::physics::rail::run`), which run
    /// beside `cars`: their own integrator, their own loads on the guideway.
    pub rail: Option<RailTrain>,
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
            rail: None,
        }
    }

    /// A train of 3-D high-speed cars on their track, and nothing else.
    pub fn rail_cars(spec: RailTrain) -> Self {
        Train {
            rail: Some(spec),
            ..Self::from_cars(Vec::new())
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
