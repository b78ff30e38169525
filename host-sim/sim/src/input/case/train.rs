//! `[vehicle]` / `[train]` in SI: what runs over the guideway, by kind, each kind's keys
//! converted and checked once, and how far the train reaches (for t_end and the budget).

use super::checks::{bounded, finite, non_negative, positive, positive_within, within};
use crate::input::scenario::{
    Fig1Keys, ForcesKeys, HighSpeedKeys, MaglevKeys, MovingForceKeys, UnitKeys, VehicleSection,
    WheelRailKeys,
};
use crate::physics::cars::fig6::Fig6;
use crate::physics::rail::car::HsrCar;
use crate::physics::train::Train;
use crate::physics::vehicle::{Fig1, Unit, VehicleModel};
use crate::simulation::MovingLoad;
use crate::{Error, Result};
use maglev_core::gap::Geometry;
use maglev_core::levitation::GRAVITY;
use serde::Serialize;

/// The most loads a `forces` train may carry.
pub const MAX_LOADS: usize = 100_000;

/// The most cars a `fig1` train may have (12 magnets each).
pub const MAX_CARS: usize = 1000;

/// What runs over the guideway, in SI; summary.json's `case.train` is its serialisation
/// (`kind`, then each value under a key that names its unit).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum TrainCase {
    /// `cars` identical Fig. 1 cars, `car_length` apart (leading wheel to leading wheel).
    Fig1 {
        #[serde(flatten)]
        car: Fig1,
        cars: usize,
        #[serde(rename = "car_length_m")]
        car_length: f64,
    },
    /// `cars` Fig. 6 maglev carriages (docs/cars.md); `nodes` magnet wheels in all, the last
    /// `length` behind the leading one.
    Maglev {
        cars: usize,
        #[serde(rename = "magnets")]
        nodes: usize,
        #[serde(rename = "length_m")]
        length: f64,
        /// Mass of each magnet node (kg), `Fig6::magnet_mass`.
        #[serde(rename = "wheel_mass_kg")]
        magnet_mass: f64,
    },
    /// `cars` wheel/rail cars (docs/cars.md); `nodes` wheel–rail contacts in all.
    WheelRail {
        cars: usize,
        #[serde(rename = "contacts")]
        nodes: usize,
        #[serde(rename = "length_m")]
        length: f64,
    },
    /// `cars` 3-D high-speed cars (`crate::physics::rail::car`, docs/cars.md) on the case's
    /// track, `car_length` between centres; `wheels` wheels in all, the last `length`
    /// behind the leading one.
    HighSpeed {
        cars: usize,
        wheels: usize,
        #[serde(rename = "car_length_m")]
        pitch: f64,
        #[serde(rename = "length_m")]
        length: f64,
        conicity: f64,
        friction: f64,
        substeps: usize,
    },
    /// Constant vertical moving loads (a `forces` train or the single `moving-force`), the
    /// leading load at x = 0 at t = 0 and every other behind it.
    Forces(#[serde(serialize_with = "loads")] Vec<MovingLoad>),
    /// One levitation unit (`kind = "unit"`), at its position at t = 0.
    Unit(Unit),
}

/// The loads as `{"loads": […]}`: a tagged variant's content is a map.
fn loads<S: serde::Serializer>(loads: &[MovingLoad], s: S) -> std::result::Result<S::Ok, S::Error> {
    #[derive(Serialize)]
    struct Loads<'a> {
        loads: &'a [MovingLoad],
    }
    Loads { loads }.serialize(s)
}

/// The vehicle section in SI, and the magnets' geometry.
pub(super) fn train(v: &VehicleSection) -> Result<(TrainCase, Geometry)> {
    match v {
        VehicleSection::Fig1(k) => fig1(k),
        VehicleSection::Maglev(MaglevKeys {
            cars,
            wheel_mass_kg,
            geometry,
        }) => {
            bounded("train.cars", *cars, 1, MAX_CARS)?;
            let magnet_mass = non_negative("train.wheel_mass_kg", *wheel_mass_kg)?;
            let (nodes, length) = extent_of(&Train::fig6_with(&fig6(magnet_mass), *cars, GRAVITY)?);
            Ok((
                TrainCase::Maglev {
                    cars: *cars,
                    nodes,
                    length,
                    magnet_mass,
                },
                *geometry,
            ))
        }
        VehicleSection::WheelRail(WheelRailKeys { cars }) => {
            bounded("train.cars", *cars, 1, MAX_CARS)?;
            let (nodes, length) = extent_of(&Train::wheel_rail(*cars, GRAVITY)?);
            Ok((
                TrainCase::WheelRail {
                    cars: *cars,
                    nodes,
                    length,
                },
                Geometry::Paper,
            ))
        }
        VehicleSection::HighSpeed(k) => Ok((high_speed(k)?, Geometry::Paper)),
        VehicleSection::Unit(keys) => Ok((TrainCase::Unit(unit(keys)?), keys.geometry)),
        VehicleSection::MovingForce(MovingForceKeys {
            force_kN,
            offset_y_m,
            offset_z_m,
        }) => Ok((
            TrainCase::Forces(vec![MovingLoad {
                x0: 0.0,
                force: finite("vehicle.force_kN", *force_kN)? * 1e3,
                ey: finite("vehicle.offset_y_m", *offset_y_m)?,
                ez: finite("vehicle.offset_z_m", *offset_z_m)?,
            }]),
            Geometry::Paper,
        )),
        VehicleSection::Forces(ForcesKeys {
            loads_kN,
            offsets_m,
            repeat,
            car_length_m,
            offset_y_m,
            offset_z_m,
        }) => Ok((
            TrainCase::Forces(forces(
                loads_kN,
                offsets_m,
                *repeat,
                *car_length_m,
                (*offset_y_m, *offset_z_m),
            )?),
            Geometry::Paper,
        )),
    }
}

/// A `fig1` train in SI: `repeat` cars, `car_length_m` apart.
fn fig1(k: &Fig1Keys) -> Result<(TrainCase, Geometry)> {
    let kilo = |key: &str, v: f64| positive(key, v).map(|v| v * 1e3);
    // A body lighter than 1 kg (or an inertia under 1 kg·m²) leaves its effective
    // stiffness singular to f64 beside the suspension's.
    let body = |key: &str, v: f64, unit: &str| {
        positive_within(key, v, 1e-3, 1e6, &format!("{unit}: 1 kg to 1000 cars")).map(|v| v * 1e3)
    };
    let car = Fig1 {
        body_mass: body("vehicle.body_mass_t", k.body_mass_t, "t")?,
        jx: body("vehicle.jx_t_m2", k.jx_t_m2, "t·m²")?,
        jy: body("vehicle.jy_t_m2", k.jy_t_m2, "t·m²")?,
        jz: body("vehicle.jz_t_m2", k.jz_t_m2, "t·m²")?,
        k: kilo("vehicle.spring_kN_per_m", k.spring_kN_per_m)?,
        c: kilo("vehicle.damper_kN_s_per_m", k.damper_kN_s_per_m)?,
        half_length: positive_within(
            "vehicle.half_length_m",
            k.half_length_m,
            0.05,
            100.0,
            "m: a bogie's half wheelbase to a long car's",
        )?,
        half_width: within(
            "vehicle.half_width_m",
            finite("vehicle.half_width_m", k.half_width_m)?,
            0.05,
            10.0,
            "m: the magnets left and right of the centre; 0 leaves roll unsupported",
        )?,
        offset_y: finite("vehicle.offset_y_m", k.offset_y_m)?,
        target_height: finite("vehicle.target_height_m", k.target_height_m)?,
        body_height: within(
            "vehicle.body_height_m",
            finite("vehicle.body_height_m", k.body_height_m)?,
            -20.0,
            20.0,
            "m: within a car's height of the magnets",
        )?,
        wheel_mass: non_negative("vehicle.wheel_mass_kg", k.wheel_mass_kg)?,
        com_ahead: 0.0,
        position: within(
            "vehicle.position_m",
            finite("vehicle.position_m", k.position_m)?,
            -1e6,
            1e6,
            "m: within 1000 km of the first support",
        )?,
    };
    bounded("train.repeat", k.repeat, 1, MAX_CARS)?;
    let car_length = match k.car_length_m {
        Some(l) if !(l.is_finite() && l >= 2.0 * k.half_length_m) => {
            return Err(Error::invalid(
                "train.car_length_m",
                format!(
                "must be a finite number of at least the wheelbase 2·half_length_m = {} m, got {l}",
                2.0 * k.half_length_m
            ),
            ))
        }
        Some(l) => l,
        None if k.repeat == 1 => 0.0,
        None => {
            return Err(Error::invalid(
                "train.car_length_m",
                "is needed when train.repeat > 1",
            ))
        }
    };
    // The car must be buildable (a positive-definite block, magnets that lift).
    VehicleModel::fig1(&car, GRAVITY)?;
    Ok((
        TrainCase::Fig1 {
            car,
            cars: k.repeat,
            car_length,
        },
        k.geometry,
    ))
}

/// A `high-speed` train in SI, checked.
fn high_speed(k: &HighSpeedKeys) -> Result<TrainCase> {
    bounded("train.cars", k.cars, 1, MAX_CARS)?;
    bounded("train.substeps", k.substeps, 1, 100)?;
    let base = HsrCar::zhai_high_speed();
    let conicity = within(
        "train.conicity",
        finite(
            "train.conicity",
            k.conicity.unwrap_or(base.wheelset.conicity),
        )?,
        0.001,
        0.5,
        "(equivalent conicity of a wheel–rail pair)",
    )?;
    let friction = within(
        "train.friction",
        finite(
            "train.friction",
            k.friction.unwrap_or(base.wheelset.material.friction),
        )?,
        0.01,
        1.0,
        "(wheel–rail friction coefficient)",
    )?;
    let span = base.wheelset_x()[0] - base.wheelset_x()[3];
    let pitch = positive_within(
        "train.car_length_m",
        k.car_length_m,
        span,
        1000.0,
        "m: at least the car's outer wheelsets' distance",
    )?;
    Ok(TrainCase::HighSpeed {
        cars: k.cars,
        wheels: 8 * k.cars,
        pitch,
        length: span + (k.cars - 1) as f64 * pitch,
        conicity,
        friction,
        substeps: k.substeps,
    })
}

/// The high-speed car of a `high-speed` train: Zhai's car
/// ([`HsrCar::zhai_high_speed`]) with the case's conicity and friction.
pub fn high_speed_car(conicity: f64, friction: f64) -> HsrCar {
    let mut car = HsrCar::zhai_high_speed();
    car.wheelset.conicity = conicity;
    car.wheelset.material.friction = friction;
    car
}

/// The Fig. 6 carriage of a `maglev` train: the defaults of docs/cars.md with magnet nodes of
/// `magnet_mass` (kg).
pub fn fig6(magnet_mass: f64) -> Fig6 {
    Fig6 {
        magnet_mass,
        ..Fig6::default()
    }
}

/// The unit of `kind = "unit"` in SI: a magnet with mass; with a body, a spring and a damper.
fn unit(u: &UnitKeys) -> Result<Unit> {
    let unit = Unit {
        magnet_mass: positive("vehicle.magnet_mass_kg", u.magnet_mass_kg)?,
        body_mass: non_negative("vehicle.body_mass_t", u.body_mass_t)? * 1e3,
        k: non_negative("vehicle.spring_kN_per_m", u.spring_kN_per_m)? * 1e3,
        c: non_negative("vehicle.damper_kN_s_per_m", u.damper_kN_s_per_m)? * 1e3,
        position: finite("vehicle.position_m", u.position_m)?,
    };
    if unit.body_mass > 0.0 && unit.k == 0.0 {
        return Err(Error::invalid(
            "vehicle.spring_kN_per_m",
            "must be positive when the unit carries a body (body_mass_t > 0)",
        ));
    }
    VehicleModel::unit(&unit, GRAVITY)?;
    Ok(unit)
}

/// The loads of a `forces` train in SI, the leading load at x = 0 at t = 0 and every other
/// behind it (x0 = −offset − car·car_length).
fn forces(
    loads_kn: &[f64],
    offsets: &[f64],
    repeat: usize,
    car_length: Option<f64>,
    (ey, ez): (f64, f64),
) -> Result<Vec<MovingLoad>> {
    if loads_kn.is_empty() || loads_kn.len() != offsets.len() {
        return Err(Error::invalid(
            "train.loads_kN",
            format!(
                "train.loads_kN and train.offsets_m must be non-empty lists of equal length (got {} and {})",
                loads_kn.len(),
                offsets.len()
            ),
        ));
    }
    if repeat == 0 || repeat.saturating_mul(loads_kn.len()) > MAX_LOADS {
        return Err(Error::invalid(
            "train.repeat",
            format!(
                "repeat × {} loads must be between 1 and {MAX_LOADS}, got repeat = {repeat}",
                loads_kn.len()
            ),
        ));
    }
    let car = match car_length {
        Some(l) => positive("train.car_length_m", l)?,
        None if repeat == 1 => 0.0,
        None => {
            return Err(Error::invalid(
                "train.car_length_m",
                "is needed when train.repeat > 1",
            ))
        }
    };
    for (i, (&f, &o)) in loads_kn.iter().zip(offsets).enumerate() {
        finite(&format!("train.loads_kN[{i}]"), f)?;
        if !(o.is_finite() && o >= 0.0) {
            return Err(Error::invalid(
                format!("train.offsets_m[{i}]"),
                format!("must be zero or positive (behind the leading load), got {o}"),
            ));
        }
    }
    let ey = finite("train.offset_y_m", ey)?;
    let ez = finite("train.offset_z_m", ez)?;
    Ok((0..repeat)
        .flat_map(|c| {
            loads_kn
                .iter()
                .zip(offsets)
                .map(move |(&f, &o)| MovingLoad {
                    x0: -o - c as f64 * car,
                    force: f * 1e3,
                    ey,
                    ez,
                })
        })
        .collect())
}

/// How far the train reaches behind its leading wheel or load (m).
pub(super) fn train_length(t: &TrainCase) -> f64 {
    match t {
        TrainCase::Fig1 {
            car,
            cars,
            car_length,
        } => 2.0 * car.half_length + (cars - 1) as f64 * car_length,
        TrainCase::Maglev { length, .. }
        | TrainCase::WheelRail { length, .. }
        | TrainCase::HighSpeed { length, .. } => *length,
        TrainCase::Forces(f) => f.iter().map(|l| -l.x0).fold(0.0, f64::max),
        TrainCase::Unit(_) => 0.0,
    }
}

/// The guideway nodes of a §5 train and how far behind the leading one the last lies.
fn extent_of(t: &Train) -> (usize, f64) {
    let behind = t
        .wheels
        .iter()
        .map(|w| w.x0)
        .chain(t.contacts.iter().map(|c| c.x0))
        .fold(0.0, |m: f64, x| m.max(-x));
    (t.nodes.len(), behind)
}

#[cfg(test)]
mod tests {
    use super::super::Case;
    use super::*;
    use crate::input::scenario;

    /// The file's t, kN and t·m² are SI here; a moving force is one load at x = 0.
    #[test]
    fn vehicle_keys_are_converted_to_si() {
        let c = Case::load("paper-4.2", &[]).unwrap();
        let TrainCase::Fig1 { car, cars, .. } = &c.train else {
            panic!("paper-4.2 is a fig1 case")
        };
        assert_eq!((car.body_mass, car.jy, *cars), (15_000.0, 950e3, 1));
        // (25 m bridge + 15 m wheelbase) / 100 m/s + 0.1 s
        assert!((c.t_end - 0.5).abs() < 1e-12);
        let f = Case::load("moving-force", &[]).unwrap();
        assert_eq!(
            f.train,
            TrainCase::Forces(vec![MovingLoad {
                x0: 0.0,
                force: 36_790.0,
                ey: 0.0,
                ez: 0.0
            }])
        );
    }

    /// The unit stands still only for a given time; its keys are bounded and named.
    #[test]
    fn a_unit_at_standstill() {
        let c = Case::load("unit", &[]).unwrap();
        assert_eq!((c.speed, c.t_end), (0.0, 2.0));
        let TrainCase::Unit(u) = &c.train else {
            panic!("unit is a unit case")
        };
        assert_eq!(
            (u.magnet_mass, u.body_mass, u.position),
            (600.0, 3750.0, 10.0)
        );
        assert_eq!(c.vehicle_train().unwrap().unwrap().p0[0], 4350.0 * GRAVITY);
        for (set, key) in [
            ("run.t_end_s=nan", "run.t_end_s"),
            ("vehicle.magnet_mass_kg=0", "vehicle.magnet_mass_kg"),
            ("vehicle.body_mass_t=-1", "vehicle.body_mass_t"),
            ("vehicle.spring_kN_per_m=0", "vehicle.spring_kN_per_m"),
            ("vehicle.position_m=1e10", "vehicle.position_m"),
            ("speed=-1", "run.speed_m_per_s"),
        ] {
            let e = Case::load("unit", &[set.into()]).unwrap_err().to_string();
            assert!(e.starts_with(key), "{set}: {e}");
        }
        let mut sc = scenario::load("unit", &[]).unwrap();
        sc.run.t_end_s = None;
        let e = Case::new(sc).unwrap_err().to_string();
        assert!(e.starts_with("run.t_end_s") && e.contains("= 0"), "{e}");
    }

    /// `train.wheel_mass_kg` reaches the Fig. 6 carriages: each of the 384 magnets of the
    /// default train carries its share of body and bogies, 50 t/32, plus its own mass (the
    /// hand statics of docs/cars.md), and a negative mass is refused by its key.
    #[test]
    fn maglev_magnet_mass_reaches_the_train() {
        for m in [0.0, 500.0] {
            let c = Case::load("paper-5", &[format!("train.wheel_mass_kg={m}")]).unwrap();
            let t = c.vehicle_train().unwrap().unwrap();
            let want = (50_000.0 / 32.0 + m) * GRAVITY;
            assert_eq!(t.p0.len(), 384);
            for p in &t.p0 {
                assert!((p - want).abs() <= 1e-9 * want, "{p} against {want}");
            }
        }
        let e = Case::load("paper-5", &["train.wheel_mass_kg=-1".into()]).unwrap_err();
        assert!(e.to_string().contains("train.wheel_mass_kg"), "{e}");
    }
}
