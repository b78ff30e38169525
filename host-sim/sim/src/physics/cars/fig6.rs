//! The Fig. 6 maglev carriage (docs/model.md §10): a car body on four bogies (levitation
//! frames), each bogie on four magnet wheels per side at an equal 1.5625 m pitch.
//!
//! Why this shape: §10's decisions read the 16 magnets per carriage as left/right pairs on
//! the two target lines (32 magnets, each its own controller), and Fig. 6's labels as a
//! bogie pitch of 6.25 m = 4 × 1.5625 m with the secondary suspension on the bogies. Every
//! reading, every value and its source are in docs/cars.md.
//!
//! DOF layout (89): body v, w, θx, θy, θz = 0..5 (its CoM at the car's middle, as Fig. 1's
//! body, docs/model.md §6); bogie b = 0..4 (front first) at 5 + 5b .. 10 + 5b in the same
//! order; magnet wheel n = 0..32 at 25 + 2n (Y) and 26 + 2n (Z). Wheel n = 8b + 2j + s: bogie
//! b, position j = 0..4 from the front of the bogie, s = 0 on the near line (Y = 1.25 m), 1 on
//! the far one (Y = 3.25 m). Wheel 1 (n = 0) leads on the near line at x0 = 0, as in
//! docs/model.md §9.

use super::link::{add_spring_damper, Axis, End, Rigid, RX, RY, RZ, UY, UZ};
use super::{VehicleModel, Wheel};
use crate::{Error, Result};
use nalgebra::{DMatrix, DVector};

/// Parameters of the Fig. 6 carriage (SI). Defaults: docs/cars.md.
#[derive(Clone, Debug, PartialEq)]
pub struct Fig6 {
    /// Car body mass (kg) and inertias about its CoM, X, Y, Z (kg·m²).
    pub body_mass: f64,
    pub body_inertia: [f64; 3],
    /// One bogie (levitation frame with its magnets' mass) and its inertias.
    pub bogie_mass: f64,
    pub bogie_inertia: [f64; 3],
    /// Mass of each magnet wheel node (kg); 0 by default (docs/model.md §2 item 3).
    pub magnet_mass: f64,
    /// Secondary spring–damper per station and side, vertical and lateral (N/m, N·s/m).
    pub k_sec_z: f64,
    pub c_sec_z: f64,
    pub k_sec_y: f64,
    pub c_sec_y: f64,
    /// Primary spring–damper per magnet, vertical and lateral.
    pub k_pri_z: f64,
    pub c_pri_z: f64,
    pub k_pri_y: f64,
    pub c_pri_y: f64,
    /// Magnet pitch along X (m): Fig. 6's "15 × 1.5625".
    pub pitch: f64,
    /// Half the distance of a bogie's two secondary stations (m): Fig. 6's 2.05 / 2.
    pub station_half: f64,
    /// Target lines' Y from the girder centre (m): near, far.
    pub lines_y: [f64; 2],
    /// Target lines' Z above the girder centroid (m).
    pub target_z: f64,
    /// Heights above the target line (m): bogie CoM, secondary elements, body CoM.
    pub bogie_height: f64,
    pub secondary_height: f64,
    pub body_height: f64,
}

impl Default for Fig6 {
    fn default() -> Self {
        Fig6 {
            body_mass: 40.0e3,
            body_inertia: [1.0e5, 2.14e6, 2.13e6],
            bogie_mass: 2.5e3,
            bogie_inertia: [2.5e3, 8.1e3, 1.06e4],
            magnet_mass: 0.0,
            k_sec_z: 1.0e5,
            c_sec_z: 6.0e3,
            k_sec_y: 1.0e5,
            c_sec_y: 6.0e3,
            k_pri_z: 1.0e6,
            c_pri_z: 1.0e4,
            k_pri_y: 1.0e6,
            c_pri_y: 1.0e4,
            pitch: 1.5625,
            station_half: 1.025,
            lines_y: [1.25, 3.25],
            target_z: 1.0,
            bogie_height: 0.28,
            secondary_height: 0.56,
            body_height: 2.0,
        }
    }
}

/// Bogies per carriage and magnet positions per bogie and side.
pub const BOGIES: usize = 4;
pub const PER_BOGIE: usize = 4;

impl Fig6 {
    /// Bogie pitch (m): 4 magnet pitches, so that the magnets of neighbouring bogies keep the
    /// equal spacing.
    pub fn bogie_pitch(&self) -> f64 {
        PER_BOGIE as f64 * self.pitch
    }

    /// Carriage pitch along the train (m): 16 magnet pitches, 25 m by default, so that the
    /// magnets of consecutive carriages keep the equal spacing.
    pub fn car_pitch(&self) -> f64 {
        (BOGIES * PER_BOGIE) as f64 * self.pitch
    }

    /// X of bogie b's centre from the body centre (front first).
    pub fn bogie_x(&self, b: usize) -> f64 {
        ((BOGIES as f64 - 1.0) / 2.0 - b as f64) * self.bogie_pitch()
    }

    /// X of magnet position j of bogie b from the body centre.
    pub fn magnet_x(&self, b: usize, j: usize) -> f64 {
        self.bogie_x(b) + ((PER_BOGIE as f64 - 1.0) / 2.0 - j as f64) * self.pitch
    }

    fn validate(&self) -> Result<()> {
        let positive = [
            ("body_mass", self.body_mass),
            ("bogie_mass", self.bogie_mass),
            ("pitch", self.pitch),
            ("k_sec_z", self.k_sec_z),
            ("k_sec_y", self.k_sec_y),
            ("k_pri_z", self.k_pri_z),
            ("k_pri_y", self.k_pri_y),
            (
                "body_inertia",
                self.body_inertia
                    .iter()
                    .cloned()
                    .fold(f64::INFINITY, f64::min),
            ),
            (
                "bogie_inertia",
                self.bogie_inertia
                    .iter()
                    .cloned()
                    .fold(f64::INFINITY, f64::min),
            ),
        ];
        for (key, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::invalid(
                    format!("fig6.{key}"),
                    format!("must be > 0, got {v}"),
                ));
            }
        }
        let nonneg = [
            ("magnet_mass", self.magnet_mass),
            ("c_sec_z", self.c_sec_z),
            ("c_sec_y", self.c_sec_y),
            ("c_pri_z", self.c_pri_z),
            ("c_pri_y", self.c_pri_y),
            ("station_half", self.station_half),
        ];
        for (key, v) in nonneg {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Error::invalid(
                    format!("fig6.{key}"),
                    format!("must be >= 0, got {v}"),
                ));
            }
        }
        if self.magnet_mass == 0.0 && (self.c_pri_z <= 0.0 || self.c_pri_y <= 0.0) {
            return Err(Error::invalid(
                "fig6.c_pri",
                "a massless magnet node needs a primary damper (> 0)",
            ));
        }
        Ok(())
    }

    /// The carriage's rigid bodies: body, then the bogies (front first).
    pub fn bodies(&self) -> (Rigid, Vec<Rigid>) {
        let yc = 0.5 * (self.lines_y[0] + self.lines_y[1]);
        let five = |base: usize, at: [f64; 3]| {
            Rigid::new(at)
                .dof(UY, base)
                .dof(UZ, base + 1)
                .dof(RX, base + 2)
                .dof(RY, base + 3)
                .dof(RZ, base + 4)
        };
        let body = five(0, [0.0, yc, self.body_height]);
        let bogies = (0..BOGIES)
            .map(|b| five(5 + 5 * b, [self.bogie_x(b), yc, self.bogie_height]))
            .collect();
        (body, bogies)
    }

    /// Builds the carriage (module docs), its static loads from its exact statics.
    pub fn build(&self, gravity: f64) -> Result<VehicleModel> {
        self.validate()?;
        let nw = 2 * BOGIES * PER_BOGIE;
        let n = 5 + 5 * BOGIES + 2 * nw;
        let (mut m, mut c, mut k) = (
            DMatrix::zeros(n, n),
            DMatrix::zeros(n, n),
            DMatrix::zeros(n, n),
        );
        let mut f = DVector::zeros(n);
        let (body, bogies) = self.bodies();
        body.add_mass(&mut m, self.body_mass, self.body_inertia);
        body.add_weight(&mut f, self.body_mass, gravity);
        let x_front = self.magnet_x(0, 0);
        let mut wheels = Vec::with_capacity(nw);
        for (b, bogie) in bogies.iter().enumerate() {
            bogie.add_mass(&mut m, self.bogie_mass, self.bogie_inertia);
            bogie.add_weight(&mut f, self.bogie_mass, gravity);
            // Secondary: at the bogie's two stations, on both lines, body ↔ bogie.
            for dx in [self.station_half, -self.station_half] {
                for &y in &self.lines_y {
                    let p = [self.bogie_x(b) + dx, y, self.secondary_height];
                    let (a, o) = (End { body: &body, p }, End { body: bogie, p });
                    add_spring_damper(&mut k, &mut c, (self.k_sec_z, self.c_sec_z), Axis::Z, a, o)?;
                    add_spring_damper(&mut k, &mut c, (self.k_sec_y, self.c_sec_y), Axis::Y, a, o)?;
                }
            }
            // Primary: each magnet node ↔ the bogie point at the magnet.
            for j in 0..PER_BOGIE {
                for (s, &y) in self.lines_y.iter().enumerate() {
                    let w = 2 * PER_BOGIE * b + 2 * j + s;
                    let (dof_y, dof_z) = (5 + 5 * BOGIES + 2 * w, 6 + 5 * BOGIES + 2 * w);
                    let p = [self.magnet_x(b, j), y, 0.0];
                    let node = Rigid::new(p).dof(UY, dof_y).dof(UZ, dof_z);
                    node.add_mass(&mut m, self.magnet_mass, [0.0; 3]);
                    node.add_weight(&mut f, self.magnet_mass, gravity);
                    let (a, o) = (End { body: &node, p }, End { body: bogie, p });
                    add_spring_damper(&mut k, &mut c, (self.k_pri_z, self.c_pri_z), Axis::Z, a, o)?;
                    add_spring_damper(&mut k, &mut c, (self.k_pri_y, self.c_pri_y), Axis::Y, a, o)?;
                    wheels.push(Wheel {
                        x0: p[0] - x_front,
                        ey: y,
                        ez: self.target_z,
                        dof_y: Some(dof_y),
                        dof_z,
                    });
                }
            }
        }
        let weight = gravity
            * (self.body_mass + BOGIES as f64 * self.bogie_mass + nw as f64 * self.magnet_mass);
        let mut car = VehicleModel {
            m,
            c,
            k,
            wheels,
            p0: Vec::new(),
            contacts: Vec::new(),
            body_z: 1,
            body_pitch: 3,
            length: self.car_pitch(),
            weight,
        };
        // Exact statics with every magnet node held: the reactions are the magnets' p0.
        (car.p0, _) = car.static_loads(&f)?;
        Ok(car)
    }
}
