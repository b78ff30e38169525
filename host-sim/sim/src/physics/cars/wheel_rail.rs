//! The wheel/rail comparison car (docs/model.md §10 "The comparison train"): a 25 m car body
//! on two bogies (centres 17.5 m apart), each on two wheelsets 2.5 m apart, with primary
//! (axle box) and secondary (air spring) suspensions, and each wheel on its rail through a
//! Hertz contact spring linearised about its static load.
//!
//! Why vertical and roll only: the Z vibration of car and pier is what Fig. 8 compares, and
//! the vertical springs, the bodies' heave, pitch and roll and the Hertz contact are honest
//! linear elements. Lateral wheel–rail forces need creep and flange contact (Kalker), which a
//! spring would misrepresent; so the lateral, yaw and wheelset-pitch motions are held, and the
//! roll modes ride on the vertical springs alone (docs/cars.md).
//!
//! DOF layout (17): body z, θx, θy = 0, 1, 2 (CoM at the car's middle); bogie b = 0, 1 (front
//! first) z, θx, θy = 3 + 3b .. 6 + 3b; wheelset a = 0..4 (front first) as its two wheels'
//! vertical displacements, 9 + 2a (near rail, smaller Y) and 10 + 2a (far rail). A wheelset's
//! heave and roll are z = (z_near + z_far)/2 and θx = (z_far − z_near)/(2·b0), an exact change
//! of coordinates that gives each contact a DOF of its own.

use super::link::{add_spring_damper, Axis, End, Rigid, RX, RY, UZ};
use super::{Contact, VehicleModel};
use crate::{Error, Result};
use nalgebra::{DMatrix, DVector};

/// Zhai's Hertz constant for a conical tread (m/N^(2/3)), R the wheel radius (m):
/// G = 4.57·R^(−0.149)·1e−8, in P = (δ/G)^(3/2) (Zhai, Vehicle–Track Coupled Dynamics).
pub fn zhai_g(radius: f64) -> f64 {
    4.57 * radius.powf(-0.149) * 1e-8
}

/// The Hertz spring linearised at the static load `p0` (N): from P = (δ/G)^(3/2),
/// k_H = dP/dδ = (3/2)·(δ0/G)^(1/2)/G = (3/2)·P0^(1/3)/G (N/m).
pub fn hertz_stiffness(p0: f64, radius: f64) -> f64 {
    1.5 * p0.cbrt() / zhai_g(radius)
}

/// The track's point stiffness under a wheel (N/m): the rail as an infinite Euler beam
/// (bending stiffness `rail_ei`, N·m²) on its pads (`pad` N/m each, `spacing` m apart) smeared
/// into a Winkler foundation k_f = pad/spacing; a point load P deflects it by
/// w0 = P·β/(2·k_f), β = (k_f/(4·EI))^(1/4) (Hetényi, *Beams on Elastic Foundation*, 1946),
/// so k = 2·k_f/β.
pub fn track_stiffness(rail_ei: f64, pad: f64, spacing: f64) -> f64 {
    let kf = pad / spacing;
    let beta = (kf / (4.0 * rail_ei)).powf(0.25);
    2.0 * kf / beta
}

/// Two springs in series (N/m); an infinite one is rigid.
pub fn series(a: f64, b: f64) -> f64 {
    if a.is_infinite() {
        b
    } else if b.is_infinite() {
        a
    } else {
        a * b / (a + b)
    }
}

/// Parameters of the wheel/rail car (SI). Defaults and sources: docs/cars.md.
#[derive(Clone, Debug, PartialEq)]
pub struct WheelRail {
    /// Car body mass (kg), roll and pitch inertias (kg·m²).
    pub body_mass: f64,
    pub body_roll: f64,
    pub body_pitch: f64,
    /// One bogie frame.
    pub bogie_mass: f64,
    pub bogie_roll: f64,
    pub bogie_pitch: f64,
    /// One wheelset, mass and roll inertia.
    pub wheelset_mass: f64,
    pub wheelset_roll: f64,
    /// Secondary (air spring) per spring, two per bogie, vertical (N/m, N·s/m).
    pub k_sec: f64,
    pub c_sec: f64,
    /// Primary (axle box) per box, two per wheelset, vertical.
    pub k_pri: f64,
    pub c_pri: f64,
    /// Half the bogie-centre distance and half the wheelbase (m).
    pub half_bogie_spacing: f64,
    pub half_wheelbase: f64,
    /// Lateral half-distances (m): contact points, axle boxes, air springs.
    pub half_contact: f64,
    pub half_primary: f64,
    pub half_secondary: f64,
    /// Wheel radius (m), for the Hertz constant.
    pub wheel_radius: f64,
    /// Track centre Y from the girder centre, rail target points' Z above its centroid (m).
    pub track_y: f64,
    pub rail_z: f64,
    /// Car pitch along the train (m).
    pub car_length: f64,
    /// The track's point stiffness under each wheel (N/m), in series with the Hertz spring
    /// ([`track_stiffness`]; docs/cars.md "The track"); `f64::INFINITY` puts the wheel on the
    /// girder through the Hertz spring alone.
    pub track_stiffness: f64,
}

impl Default for WheelRail {
    fn default() -> Self {
        WheelRail {
            body_mass: 44.0e3,
            body_roll: 9.0e4,
            body_pitch: 2.7e6,
            bogie_mass: 2.4e3,
            bogie_roll: 1.6e3,
            bogie_pitch: 2.2e3,
            wheelset_mass: 2.4e3,
            wheelset_roll: 1.2e3,
            k_sec: 6.0e5,
            c_sec: 8.0e4,
            k_pri: 1.4e6,
            c_pri: 8.0e4,
            half_bogie_spacing: 8.75,
            half_wheelbase: 1.25,
            half_contact: 0.7465,
            half_primary: 1.0,
            half_secondary: 1.0,
            wheel_radius: 0.43,
            track_y: 2.25,
            rail_z: 1.0,
            car_length: 25.0,
            // UIC60 rail (E·I = 2.06e11 × 3.217e-5 m⁴) on 60 kN/mm pads every 0.625 m.
            track_stiffness: track_stiffness(2.06e11 * 3.217e-5, 6.0e7, 0.625),
        }
    }
}

impl WheelRail {
    fn validate(&self) -> Result<()> {
        let positive = [
            ("body_mass", self.body_mass),
            ("body_roll", self.body_roll),
            ("body_pitch", self.body_pitch),
            ("bogie_mass", self.bogie_mass),
            ("bogie_roll", self.bogie_roll),
            ("bogie_pitch", self.bogie_pitch),
            ("wheelset_mass", self.wheelset_mass),
            ("wheelset_roll", self.wheelset_roll),
            ("k_sec", self.k_sec),
            ("k_pri", self.k_pri),
            ("half_wheelbase", self.half_wheelbase),
            ("half_contact", self.half_contact),
            ("half_primary", self.half_primary),
            ("half_secondary", self.half_secondary),
            ("wheel_radius", self.wheel_radius),
            ("car_length", self.car_length),
        ];
        if self.track_stiffness.is_nan() || self.track_stiffness <= 0.0 {
            return Err(Error::invalid(
                "wheel_rail.track_stiffness",
                format!(
                    "must be > 0 (infinite: no track), got {}",
                    self.track_stiffness
                ),
            ));
        }
        for (key, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::invalid(
                    format!("wheel_rail.{key}"),
                    format!("must be > 0, got {v}"),
                ));
            }
        }
        for (key, v) in [("c_sec", self.c_sec), ("c_pri", self.c_pri)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Error::invalid(
                    format!("wheel_rail.{key}"),
                    format!("must be >= 0, got {v}"),
                ));
            }
        }
        let reach = self.half_bogie_spacing + self.half_wheelbase;
        if !(self.half_bogie_spacing > self.half_wheelbase && 2.0 * reach < self.car_length) {
            return Err(Error::invalid(
                "wheel_rail.half_bogie_spacing",
                format!(
                    "must exceed half_wheelbase and keep the wheelsets within car_length \
                     ({} m), got {}",
                    self.car_length, self.half_bogie_spacing
                ),
            ));
        }
        Ok(())
    }

    /// X of bogie b's centre and of wheelset a from the body centre (front first).
    pub fn bogie_x(&self, b: usize) -> f64 {
        [self.half_bogie_spacing, -self.half_bogie_spacing][b]
    }
    pub fn wheelset_x(&self, a: usize) -> f64 {
        self.bogie_x(a / 2) + [self.half_wheelbase, -self.half_wheelbase][a % 2]
    }

    /// The car's rigid bodies: body, bogies, wheelsets (module docs). Heights play no part
    /// (every element is vertical, lateral motion held), so all sit at Z = 0.
    pub fn bodies(&self) -> (Rigid, Vec<Rigid>, Vec<Rigid>) {
        let yc = self.track_y;
        let three = |base: usize, x: f64| {
            Rigid::new([x, yc, 0.0])
                .dof(UZ, base)
                .dof(RX, base + 1)
                .dof(RY, base + 2)
        };
        let body = three(0, 0.0);
        let bogies = (0..2).map(|b| three(3 + 3 * b, self.bogie_x(b))).collect();
        let h = 0.5 / self.half_contact;
        let wheelsets = (0..4)
            .map(|a| {
                let (near, far) = (9 + 2 * a, 10 + 2 * a);
                Rigid::new([self.wheelset_x(a), yc, 0.0])
                    .combo(UZ, vec![(near, 0.5), (far, 0.5)])
                    .combo(RX, vec![(near, -h), (far, h)])
            })
            .collect();
        (body, bogies, wheelsets)
    }

    /// Builds the car (module docs); contact loads from its exact statics on held wheels.
    pub fn build(&self, gravity: f64) -> Result<VehicleModel> {
        self.validate()?;
        let n = 17;
        let (mut m, mut c, mut k) = (
            DMatrix::zeros(n, n),
            DMatrix::zeros(n, n),
            DMatrix::zeros(n, n),
        );
        let mut f = DVector::zeros(n);
        let (body, bogies, wheelsets) = self.bodies();
        let yc = self.track_y;
        body.add_mass(
            &mut m,
            self.body_mass,
            [self.body_roll, self.body_pitch, 0.0],
        );
        body.add_weight(&mut f, self.body_mass, gravity);
        for (b, bogie) in bogies.iter().enumerate() {
            bogie.add_mass(
                &mut m,
                self.bogie_mass,
                [self.bogie_roll, self.bogie_pitch, 0.0],
            );
            bogie.add_weight(&mut f, self.bogie_mass, gravity);
            for dy in [-self.half_secondary, self.half_secondary] {
                let p = [self.bogie_x(b), yc + dy, 0.0];
                let (a, o) = (End { body: &body, p }, End { body: bogie, p });
                add_spring_damper(&mut k, &mut c, (self.k_sec, self.c_sec), Axis::Z, a, o)?;
            }
        }
        for (a, ws) in wheelsets.iter().enumerate() {
            ws.add_mass(&mut m, self.wheelset_mass, [self.wheelset_roll, 0.0, 0.0]);
            ws.add_weight(&mut f, self.wheelset_mass, gravity);
            for dy in [-self.half_primary, self.half_primary] {
                let p = [self.wheelset_x(a), yc + dy, 0.0];
                let (w, o) = (
                    End {
                        body: &bogies[a / 2],
                        p,
                    },
                    End { body: ws, p },
                );
                add_spring_damper(&mut k, &mut c, (self.k_pri, self.c_pri), Axis::Z, w, o)?;
            }
        }
        let x_front = self.wheelset_x(0);
        let mut contacts = Vec::with_capacity(8);
        for a in 0..4 {
            for (s, dy) in [-self.half_contact, self.half_contact]
                .into_iter()
                .enumerate()
            {
                contacts.push(Contact {
                    x0: self.wheelset_x(a) - x_front,
                    ey: yc + dy,
                    ez: self.rail_z,
                    dof_z: 9 + 2 * a + s,
                    p0: 0.0,
                    k_h: 0.0,
                    k: 0.0,
                });
            }
        }
        let weight = gravity * (self.body_mass + 2.0 * self.bogie_mass + 4.0 * self.wheelset_mass);
        let mut car = VehicleModel {
            m,
            c,
            k,
            wheels: Vec::new(),
            p0: Vec::new(),
            contacts,
            body_z: 0,
            body_pitch: 2,
            length: self.car_length,
            weight,
        };
        // Exact statics with every wheel held: the reactions are the contacts' P0.
        let (_, loads) = car.static_loads(&f)?;
        for (c, p0) in car.contacts.iter_mut().zip(loads) {
            c.p0 = p0;
            c.k_h = hertz_stiffness(p0, self.wheel_radius);
            c.k = series(c.k_h, self.track_stiffness);
        }
        Ok(car)
    }
}
