//! The rail the magnets see on the case's own flexible guideway at speed, for the supply
//! headroom ([`super::headroom`], issue 39 points 2 and 4): the guideway's vertical motion
//! under each levitation magnet while the whole train's static loads cross it at the case's
//! speed.
//!
//! # Why
//! On a rigid rail the headroom's disturbances are the irregularity and a load step. On a
//! viaduct the girders also move under the train, and where one girder ends and the next
//! begins the rail steps: the two girder ends at a pier stand on their own bearings, each
//! compressed by its own span's load. Ahead of the train's front (and behind its rear) one
//! span is loaded and the next is not, so each magnet of the first and last car crosses a
//! step of the bearings' compression difference; the cars between see loaded spans on both
//! sides. On `paper-5` at 83.33 m/s (no irregularity) the rail under car 1's front magnet
//! sinks about 1.0 mm across each loaded span and steps back by about 0.7 mm at each joint
//! (the loaded span's end on its bearings, pier and footing). With the Fig. 6 carriage's
//! rigid-rail design (300 Hz observer) the run saturates coils 104 ms on car 1 and 46 ms on
//! car 12, 4 ms on cars 2–11; the same run on 10× stiffer bearings saturates none (267 V,
//! the rigid rail's peak). A design that sees only the rigid rail cannot see that demand.
//!
//! # The model
//! One-way: the case's guideway ([`crate::setup::AnyGuideway`], without support motion:
//! an earthquake is not a reference disturbance), at rest and undeflected at t = 0 as a run
//! starts it, stepped at the case's `dt` under every magnet's static load `p0` (downward on
//! the girder at the magnet's rail point `(x0 + v·t, ey, ez)`, the loads a run applies at
//! equilibrium). The magnets' load variations about `p0` (a few per cent) are left out: they
//! are the response, not the disturbance. The rail input of magnet `k` is what the girder
//! and the rail's irregularity do to its gap (docs/model.md Eq. 2,
//! `h = h0 + dh·(z_w − z_g) + r`): `r_k = −dh·z_g + r(x_k) − r(x0_k)`, the rail as the run
//! meets it (the irregularity less its value at t = 0, as the headroom's `irregularity`).
//! Series are kept for the first and the last car of the train (one car: that one), each
//! mapped onto the design vehicle's wheels by its order within the car.

use crate::input::case::Case;
use crate::physics::guideway::{Guideway, PointLoad};
use crate::physics::vehicle::VehicleModel;
use crate::setup::AnyGuideway;

/// The rail inputs of the first and last car on the case's guideway (module docs).
#[derive(Clone, Debug)]
pub struct GuidewayRail {
    /// The guideway's step (s): sample `j` of a series is at `t = j·dt` (sample 0 is 0).
    pub dt: f64,
    /// Per car kept: its number in the train (1-based) and, per wheel of the design
    /// vehicle, the rail input `r` (m) at each step.
    pub cars: Vec<(usize, Vec<Vec<f64>>)>,
}

impl GuidewayRail {
    /// The series of `case` (module docs) for the design vehicle `v` (one car of the case's
    /// train); `None` on a rigid guideway, at standstill, or for a case without a train of
    /// magnets.
    pub fn of(case: &Case, v: &VehicleModel) -> crate::Result<Option<Self>> {
        if case.model == crate::input::scenario::Model::Rigid || case.speed == 0.0 {
            return Ok(None);
        }
        let Some(train) = case.vehicle_train()? else {
            return Ok(None);
        };
        let nw = v.wheels.len();
        if nw == 0 || train.wheels.len() % nw != 0 || !train.contacts.is_empty() {
            return Ok(None);
        }
        let ncars = train.wheels.len() / nw;
        let kept: Vec<usize> = if ncars == 1 {
            vec![0]
        } else {
            vec![0, ncars - 1]
        };
        for &c in &kept {
            let w = &train.wheels[c * nw..(c + 1) * nw];
            let off = w[0].x0 - v.wheels[0].x0;
            if w.iter().zip(&v.wheels).any(|(t, d)| {
                (t.x0 - d.x0 - off).abs() > 1e-9 * (1.0 + off.abs()) || t.ey != d.ey || t.ez != d.ez
            }) {
                return Err(crate::Error::numerical(
                    "internal: a car of the train is not the design vehicle's wheels shifted",
                ));
            }
        }
        let mut quiet = case.clone();
        quiet.support = None;
        let profiles = crate::setup::irregularity(&quiet)?;
        let z = &profiles.z;
        let mut g = AnyGuideway::new(&quiet)?;
        let dt = g.time_step();
        let steps = (case.t_end / dt).round() as usize;
        let dh = case.geometry.levitation_sign();
        // Every magnet's static load; each step moves them to `x0 + v·t`.
        let mut loads: Vec<PointLoad> = train
            .wheels
            .iter()
            .zip(&train.p0)
            .map(|(w, &p0)| PointLoad {
                x: w.x0,
                ey: w.ey,
                ez: w.ez,
                fy: 0.0,
                fz: -p0,
            })
            .collect();
        let mut cars: Vec<(usize, Vec<Vec<f64>>)> =
            kept.iter().map(|&c| (c + 1, vec![vec![0.0]; nw])).collect();
        for j in 1..=steps {
            let t = j as f64 * dt;
            for (l, w) in loads.iter_mut().zip(&train.wheels) {
                l.x = w.x0 + case.speed * t;
            }
            g.solve_step(&loads);
            for (c, (_, series)) in kept.iter().zip(cars.iter_mut()) {
                for (k, s) in series.iter_mut().enumerate() {
                    let l = &loads[c * nw + k];
                    let x0 = train.wheels[c * nw + k].x0;
                    s.push(-dh * g.motion_at(l.x, l.ey, l.ez).z + z(l.x) - z(x0));
                }
            }
            g.commit();
        }
        Ok(Some(GuidewayRail { dt, cars }))
    }

    /// Car `c`'s (index into [`GuidewayRail::cars`]) rail input under wheel `k` at time `t`
    /// (m), linear between steps (as a run's control periods read the structural steps);
    /// the last sample beyond the series.
    pub fn at(&self, c: usize, k: usize, t: f64) -> f64 {
        let s = &self.cars[c].1[k];
        let f = (t / self.dt).max(0.0);
        let j = f.floor() as usize;
        if j + 1 >= s.len() {
            return s[s.len() - 1];
        }
        let w = f - j as f64;
        s[j] + w * (s[j + 1] - s[j])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit crawling (1 mm/s) over its 25 m span, damped (20 % at its first mode, 6.2 Hz) so the
    /// sudden load's vibration has died out by 6 s: the rail under the magnet is the
    /// Timoshenko beam's static deflection under its own point load there,
    /// `w = P·a²·b²/(3·E·I·L) + P·a·b/(G·A_s·L)` (bending and shear), and the EMS magnet's
    /// gap reads it as `r = z_g = −w` (the rail drops towards the magnet).
    #[test]
    fn a_crawling_load_sees_the_static_timoshenko_deflection() {
        let sets: Vec<String> = [
            "speed=0.001",
            "t_end=6",
            "bridge.damping={ratio=0.2, f1_Hz=6.0, f2_Hz=6.0}",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        let case = Case::load("unit", &sets).unwrap();
        let (v, _, _) = crate::studies::stability::vehicle::vehicle_of(&case).unwrap();
        let rail = GuidewayRail::of(&case, &v).unwrap().unwrap();
        assert_eq!(rail.cars.len(), 1);
        let p: f64 = case.vehicle_train().unwrap().unwrap().p0.iter().sum();
        let b = &case.bridge;
        let l = b.spans[0];
        let a = v.wheels[0].x0 + case.speed * case.t_end;
        let bb = l - a;
        let (ei, gas) = (
            b.section.youngs_modulus * b.section.iy,
            b.section.shear_modulus * b.section.shear_area_z,
        );
        let w = p * a * a * bb * bb / (3.0 * ei * l) + p * a * bb / (gas * l);
        let r = rail.at(0, 0, case.t_end);
        assert!((r + w).abs() < 1e-4 * w, "r {r:e}, closed form −{w:e}");
    }
}
