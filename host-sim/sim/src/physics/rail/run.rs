//! A train of 3-D high-speed cars ([`super::car`]) running over the guideway in the coupled
//! time loop: the left and right rails of a real track ([`super::irregularity`]) on the
//! layered support of [`super::track`], on the girder. docs/cars.md, "The 3-D car in a
//! run".
//!
//! # Coupling
//!
//! The car's contact is nonlinear (Hertz, Kalker, Shen–Hedrick–Elkins, the flange), so it is
//! not folded into the time loop's Newmark matrices: each car is integrated explicitly by
//! classical RK4 over the step from its committed state, in `substeps` equal sub-steps, while
//! the girder's motion under every wheel goes linearly from its committed value (t − Δt) to
//! the loop's current iterate (t). On a track, each car's state carries the rail mass under
//! each of its wheels ([`super::rail_mass`]), integrated with the car. At the end of the step
//! the girder is loaded at the wheels' rail points: laterally by the wheels' forces, and
//! vertically by the track's support force under each rail mass (by the wheels' forces on
//! rigid rails). The loop iterates, re-integrating the cars, until
//! the girder's motion under every wheel changes by at most the loop's tolerance between two
//! passes — the same fixed point as the Hertz contacts of the paper's wheel/rail car. The
//! first pass starts from the girder's motion extrapolated linearly from the last two steps.
//!
//! # The rails under a wheel
//!
//! Rail i's head at x is at y = y_i(x) + y_g, z = z_i(x) + z_g + v_w: the irregularity of
//! that rail, the girder's motion at the rail point (x, track_y ± b, rail_z) and, on a track,
//! the deflection v_w of the rail mass under the wheel, with ẏ = v·y_i'(x) + ẏ_g (the
//! derivative by central differences over ±1 mm).
//!
//! # The start
//!
//! Every car starts at rest in its static equilibrium on the rails as they lie at t = 0
//! ([`Running::settle`]), as the project's wheel/rail cars do (docs/cars.md, "The start on a
//! rough rail"), with each rail mass at rest under its wheel's force
//! ([`RailMass::rest`]): the car is settled on the rail masses where they lie, the masses
//! moved to their rest under the new forces, until they move by at most 1e−12 m.

use super::car::{HsrCar, Rails, Running, DOFS};
use super::irregularity::RailIrregularity;
use super::rail_mass::RailMass;
use super::spectrum::Component;
use super::track::TrackSupport;
use super::wheelset::{rk4, RailPoint, WheelForce};
use crate::physics::cars::wheel_rail::zhai_g;
use crate::physics::guideway::PointLoad;
use crate::{Error, Result};

/// The state of one car in a run: the car's (q, q̇), then (v, v̇) of the rail mass under
/// each of its 8 wheels.
pub const STATE: usize = 2 * DOFS + 16;

/// The largest h·ω of the wheel against the rail mass ([`RailMass::contact_frequency`] at
/// the static load) that a sub-step h may take: classical RK4 is stable to 2.83 on the
/// imaginary axis, and the Hertz stiffness grows as N^{1/3} (by 16 % at 2.5 times the static
/// load).
pub const MAX_CONTACT_STEP: f64 = 2.2;

/// The 3-D cars of a train and the track they run on.
#[derive(Clone, Debug)]
pub struct RailTrain {
    /// The car (every car of the train is this one).
    pub car: HsrCar,
    /// Number of cars.
    pub cars: usize,
    /// Distance between the centres of consecutive cars, m.
    pub pitch: f64,
    /// Y of the track centre on the guideway (from the beam axis), m.
    pub track_y: f64,
    /// Z of the rail heads on the guideway (from the beam axis), m.
    pub rail_z: f64,
    /// The layered support under the rails; `None`: rails rigid on the girder.
    pub support: Option<TrackSupport>,
    /// The rails' irregularity; `None`: smooth rails.
    pub irregularity: Option<RailIrregularity>,
    /// RK4 sub-steps per time step.
    pub substeps: usize,
}

impl RailTrain {
    /// The centre of car `i` (0 first) at t = 0: the leading wheelset of the train at x = 0.
    pub fn car_x0(&self, i: usize) -> f64 {
        -self.car.wheelset_x()[0] - i as f64 * self.pitch
    }

    /// How far the last wheelset lies behind the first, m.
    pub fn length(&self) -> f64 {
        let x = self.car.wheelset_x();
        x[0] - x[3] + self.cars.saturating_sub(1) as f64 * self.pitch
    }

    /// Number of wheels.
    pub fn wheels(&self) -> usize {
        8 * self.cars
    }

    /// The track under a wheelset at x (m) at speed `v` (module docs, "The rails under a
    /// wheel").
    fn track_at(&self, x: f64, v: f64) -> TrackAt {
        let irr = match &self.irregularity {
            None => [0.0; 6],
            Some(r) => {
                let h = 1e-3;
                let rate = |k| v * (r.component(k, x + h) - r.component(k, x - h)) / (2.0 * h);
                let [vz, a, c, gauge] = r.all(x);
                [
                    vz,
                    a,
                    c,
                    gauge,
                    rate(Component::Alignment),
                    rate(Component::Gauge),
                ]
            }
        };
        let stiffness = self
            .support
            .as_ref()
            .map_or(0.0, |s| 1.0 / s.compliance_at(x));
        TrackAt { x, irr, stiffness }
    }

    /// The rail points (left, right) of a wheelset on the track `at` with the girder's
    /// motion `g` (y, z) under each rail and its rates `dg` (module docs; the rails as
    /// [`RailIrregularity::left`] and [`RailIrregularity::right`] combine the components).
    fn points(&self, at: &TrackAt, g: [[f64; 2]; 2], dg: [[f64; 2]; 2]) -> [RailPoint; 2] {
        let [vz, a, c, gauge, da, dgauge] = at.irr;
        let side = |s: f64, k: usize| RailPoint {
            y: a + s * 0.5 * gauge + g[k][0],
            z: vz + s * 0.5 * c + g[k][1],
            dy: da + s * 0.5 * dgauge + dg[k][0],
        };
        [side(1.0, 0), side(-1.0, 1)]
    }
}

/// The track under a wheelset at x: the irregularity (vertical, alignment, cross level,
/// gauge, and the rates of alignment and gauge) and the support's stiffness (0: rigid
/// rails).
#[derive(Clone, Copy, Debug)]
struct TrackAt {
    x: f64,
    irr: [f64; 6],
    stiffness: f64,
}

impl TrackAt {
    /// No point (matches no x).
    const NONE: TrackAt = TrackAt {
        x: f64::NAN,
        irr: [0.0; 6],
        stiffness: 0.0,
    };
}

/// What a run kept of the 3-D cars, every committed step (t = 0 included): per wheel
/// (car by car, wheelset by wheelset, left then right) the rail's lateral and vertical force
/// on it, per car the body's lateral and vertical acceleration.
#[derive(Clone, Debug, Default)]
pub struct RailOutcome {
    /// Step, s.
    pub dt: f64,
    /// Speed, m/s.
    pub speed: f64,
    /// Static wheel load, N.
    pub p0: f64,
    /// Y (N) per wheel, per step.
    pub lateral: Vec<Vec<f64>>,
    /// Q (N) per wheel, per step.
    pub vertical: Vec<Vec<f64>>,
    /// Body lateral and vertical acceleration (m/s²) per car, per step.
    pub body_ay: Vec<Vec<f64>>,
    /// See `body_ay`.
    pub body_az: Vec<Vec<f64>>,
    /// Steps (t = 0 included) with some wheel's normal force at zero.
    pub lift_off_steps: usize,
    /// The time of the first, s.
    pub first_lift_off_t: Option<f64>,
}

/// The rails under one car within a step: the girder's motion interpolated between the
/// committed and the current iterate (module docs).
struct StepRails<'a> {
    run: &'a RailRun,
    car: usize,
    /// The step's start, s.
    t0: f64,
    /// (v, v̇) of the rail mass under each wheel of the car.
    rail: &'a [f64],
}

impl Rails for StepRails<'_> {
    fn at(&self, x: f64, v: f64) -> [RailPoint; 2] {
        let r = self.run;
        let xc = r.spec.car_x0(self.car) + v * self.t0;
        // The wheelset whose path over the step holds x (they lie metres apart).
        let xs = r.spec.car.wheelset_x();
        let k = (0..4)
            .min_by(|&a, &b| {
                let da = (x - xc - xs[a] - 0.5 * v * r.dt).abs();
                let db = (x - xc - xs[b] - 0.5 * v * r.dt).abs();
                da.total_cmp(&db)
            })
            .unwrap_or(0);
        let tau = ((x - xc - xs[k]) / (v * r.dt)).clamp(0.0, 1.0);
        let w = 8 * self.car + 2 * k;
        let at = |side: usize| {
            let (g0, g1) = (r.girder0[w + side], r.girder1[w + side]);
            let g = [g0[0] + tau * (g1[0] - g0[0]), g0[1] + tau * (g1[1] - g0[1])];
            (g, [(g1[0] - g0[0]) / r.dt, (g1[1] - g0[1]) / r.dt])
        };
        let ((gl, dl), (gr, dr)) = (at(0), at(1));
        let mut p = r.spec.points(&r.track(self.car, k, x), [gl, gr], [dl, dr]);
        for (side, p) in p.iter_mut().enumerate() {
            p.z += self.rail[2 * (2 * k + side)];
        }
        p
    }
}

/// The 3-D cars in a run (module docs).
pub struct RailRun {
    spec: RailTrain,
    running: Running,
    /// The rail masses under the wheels; `None` on rigid rails.
    rail_mass: Option<RailMass>,
    dt: f64,
    /// Committed and trial state of every car ([`STATE`]).
    state: Vec<[f64; STATE]>,
    trial: Vec<[f64; STATE]>,
    /// The girder's (y, z) under every wheel: committed at t − 2Δt and t − Δt, the current
    /// iterate at t, and the iterate the cars were last integrated with.
    girder_old: Vec<[f64; 2]>,
    girder0: Vec<[f64; 2]>,
    girder1: Vec<[f64; 2]>,
    girder_used: Vec<[f64; 2]>,
    /// The rail's force on every wheel at the end of the step (trial).
    forces: Vec<WheelForce>,
    /// The track under every wheelset (car by car) at the RK4 stages of the step's
    /// sub-steps (τ = 0, h/2, h of each): the same points on every pass ([`RailRun::track`]).
    stages: Vec<TrackAt>,
    /// Time of the step being iterated (its end), s.
    t: f64,
    out: RailOutcome,
}

impl RailRun {
    /// The cars of `spec` at speed `v` (> 0), stepping by `dt`, each at rest in its static
    /// equilibrium on the rails at t = 0 over a girder at rest.
    pub fn new(spec: &RailTrain, v: f64, dt: f64, gravity: f64, steps: usize) -> Result<Self> {
        if spec.substeps == 0 {
            return Err(Error::invalid("train.substeps", "must be at least 1"));
        }
        let running = Running::new(&spec.car, v, gravity)?;
        let q0 = running.rest_wheel(0).vertical;
        let rail_mass = spec.support.as_ref().map(|s| RailMass::new(s, q0));
        if let Some(m) = &rail_mass {
            check_substeps(spec, m, dt, gravity)?;
        }
        let nw = spec.wheels();
        let mut run = RailRun {
            spec: spec.clone(),
            running,
            rail_mass,
            dt,
            state: vec![[0.0; STATE]; spec.cars],
            trial: vec![[0.0; STATE]; spec.cars],
            girder_old: vec![[0.0; 2]; nw],
            girder0: vec![[0.0; 2]; nw],
            girder1: vec![[0.0; 2]; nw],
            girder_used: vec![[0.0; 2]; nw],
            forces: vec![WheelForce::default(); nw],
            stages: vec![TrackAt::NONE; spec.cars * 4 * 3 * spec.substeps],
            t: 0.0,
            out: RailOutcome {
                dt,
                speed: v,
                p0: spec.car.wheel_load(gravity),
                lateral: vec![Vec::with_capacity(steps + 1); nw],
                vertical: vec![Vec::with_capacity(steps + 1); nw],
                body_ay: vec![Vec::with_capacity(steps + 1); spec.cars],
                body_az: vec![Vec::with_capacity(steps + 1); spec.cars],
                ..RailOutcome::default()
            },
        };
        for car in 0..spec.cars {
            run.state[car] = run.settle(car)?;
        }
        run.trial.clone_from(&run.state);
        run.end_forces();
        run.record();
        Ok(run)
    }

    /// Car `car` at rest at t = 0 (module docs, "The start").
    fn settle(&self, car: usize) -> Result<[f64; STATE]> {
        let mut s = [0.0; STATE];
        let x_car = self.spec.car_x0(car);
        for _ in 0..30 {
            let (q, rail) = s.split_at_mut(2 * DOFS);
            let rails = StepRails {
                run: self,
                car,
                t0: 0.0,
                rail,
            };
            let settled = self.running.settle(&rails, x_car)?;
            let Some(m) = &self.rail_mass else {
                q.copy_from_slice(&settled);
                return Ok(s);
            };
            let mut wheels = [WheelForce::default(); 8];
            self.running.rate_with(&settled, &rails, x_car, &mut wheels);
            let xs = self.spec.car.wheelset_x();
            let mut moved = 0.0f64;
            let mut next = [0.0; 16];
            for (w, f) in wheels.iter().enumerate() {
                next[2 * w] = m.rest(x_car + xs[w / 2], f.vertical);
                moved = moved.max((next[2 * w] - rail[2 * w]).abs());
            }
            q.copy_from_slice(&settled);
            rail.copy_from_slice(&next);
            if moved <= 1e-12 {
                return Ok(s);
            }
        }
        Err(Error::numerical(format!(
            "high-speed car {}: the rail masses' rest under the car at t = 0 did not converge in 30 passes",
            car + 1
        )))
    }

    /// d/dt of car `car`'s state `s` at time `t` within the step from `t0` (module docs).
    fn rate(&self, car: usize, t0: f64, t: f64, s: &[f64; STATE]) -> [f64; STATE] {
        let (q, rail) = s.split_at(2 * DOFS);
        let rails = StepRails {
            run: self,
            car,
            t0,
            rail,
        };
        let mut car_state = [0.0; 2 * DOFS];
        car_state.copy_from_slice(q);
        let x_car = self.spec.car_x0(car) + self.running.v * t;
        let mut wheels = [WheelForce::default(); 8];
        let r = self
            .running
            .rate_with(&car_state, &rails, x_car, &mut wheels);
        let mut out = [0.0; STATE];
        out[..2 * DOFS].copy_from_slice(&r);
        if let Some(m) = &self.rail_mass {
            let xs = self.spec.car.wheelset_x();
            for (w, f) in wheels.iter().enumerate() {
                let (v, dv) = (rail[2 * w], rail[2 * w + 1]);
                out[2 * DOFS + 2 * w] = dv;
                let k = self.track(car, w / 2, x_car + xs[w / 2]).stiffness;
                out[2 * DOFS + 2 * w + 1] = m.acceleration(k, v, dv, f.vertical);
            }
        }
        out
    }

    /// The track under wheelset `k` of car `car` at x: the step's stage where x is one of
    /// them (bit for bit), computed otherwise.
    fn track(&self, car: usize, k: usize, x: f64) -> TrackAt {
        let n = 3 * self.spec.substeps;
        let base = (car * 4 + k) * n;
        self.stages[base..base + n]
            .iter()
            .find(|a| a.x == x)
            .copied()
            .unwrap_or_else(|| self.spec.track_at(x, self.running.v))
    }

    /// Number of wheels (guideway loads).
    pub fn wheels(&self) -> usize {
        self.spec.wheels()
    }

    /// The rail point (x, e_y, e_z) of wheel `w` at time `t`, m.
    pub fn point(&self, w: usize, t: f64) -> (f64, f64, f64) {
        let (car, k, side) = (w / 8, (w % 8) / 2, w % 2);
        let x = self.spec.car_x0(car) + self.spec.car.wheelset_x()[k] + self.running.v * t;
        let b = self.spec.car.wheelset.b;
        let ey = if side == 0 { b } else { -b };
        (x, self.spec.track_y + ey, self.spec.rail_z)
    }

    /// Starts the iteration of the step ending at `t`: the girder's motion under every wheel
    /// extrapolated from the last two committed steps.
    pub fn begin(&mut self, t: f64) {
        self.t = t;
        let (t0, n) = (self.t - self.dt, self.spec.substeps);
        let h = self.dt / n as f64;
        let (v, xs) = (self.running.v, self.spec.car.wheelset_x());
        for car in 0..self.spec.cars {
            for i in 0..n {
                let ti = t0 + i as f64 * h;
                for (j, tau) in [0.0, 0.5 * h, h].into_iter().enumerate() {
                    let x_car = self.spec.car_x0(car) + v * (ti + tau);
                    for (k, xw) in xs.iter().enumerate() {
                        let at = self.spec.track_at(x_car + xw, v);
                        self.stages[((car * 4 + k) * n + i) * 3 + j] = at;
                    }
                }
            }
        }
        for ((g1, g0), old) in self
            .girder1
            .iter_mut()
            .zip(&self.girder0)
            .zip(&self.girder_old)
        {
            *g1 = [2.0 * g0[0] - old[0], 2.0 * g0[1] - old[1]];
        }
    }

    /// Sets the girder's motion (y, z) under wheel `w` at the current iterate.
    pub fn set_girder(&mut self, w: usize, y: f64, z: f64) {
        self.girder1[w] = [y, z];
    }

    /// Integrates every car over the step from its committed state under the current
    /// iterate of the girder's motion, and writes the loads on the guideway into `loads`:
    /// at every wheel's rail point, the wheel's lateral force on the rail and the track's
    /// vertical force on the deck (module docs).
    pub fn advance(&mut self, loads: &mut [PointLoad]) {
        self.girder_used.clone_from(&self.girder1);
        let (t0, h) = (self.t - self.dt, self.dt / self.spec.substeps as f64);
        for car in 0..self.spec.cars {
            let mut s = self.state[car];
            for i in 0..self.spec.substeps {
                let ti = t0 + i as f64 * h;
                rk4(&mut s, h, |tau, x| self.rate(car, t0, ti + tau, x));
            }
            self.trial[car] = s;
        }
        self.end_forces();
        for (w, (l, f)) in loads.iter_mut().zip(&self.forces).enumerate() {
            let (x, ey, ez) = self.point(w, self.t);
            let fz = match &self.rail_mass {
                None => -f.vertical,
                Some(m) => {
                    let rail = &self.trial[w / 8][2 * DOFS + 2 * (w % 8)..];
                    m.deck_force(m.stiffness_at(x), rail[0], rail[1])
                }
            };
            *l = PointLoad {
                x,
                ey,
                ez,
                fy: -f.lateral,
                fz,
            };
        }
    }

    /// The contact forces at the end of the step of every wheel, from the trial states.
    fn end_forces(&mut self) {
        let t0 = self.t - self.dt;
        let v = self.running.v;
        for car in 0..self.spec.cars {
            let (q, rail) = self.trial[car].split_at(2 * DOFS);
            let rails = StepRails {
                run: self,
                car,
                t0,
                rail,
            };
            let (q, dq) = q.split_at(DOFS);
            let xc = self.spec.car_x0(car) + v * self.t;
            let xs = self.spec.car.wheelset_x();
            let mut f = [WheelForce::default(); 8];
            for k in 0..4 {
                let c = self.running.wheelset_forces(k, q, dq, &rails, xc + xs[k]);
                f[2 * k] = c.wheels[0];
                f[2 * k + 1] = c.wheels[1];
            }
            self.forces[8 * car..8 * car + 8].copy_from_slice(&f);
        }
    }

    /// The largest change of the girder's motion under a wheel between the iterate the
    /// cars were integrated with and the current one, m.
    pub fn change(&self) -> f64 {
        self.girder1
            .iter()
            .zip(&self.girder_used)
            .map(|(a, b)| (a[0] - b[0]).abs().max((a[1] - b[1]).abs()))
            .fold(0.0, f64::max)
    }

    /// Whether some wheel's normal force is zero at the trial state.
    pub fn lifted(&self) -> bool {
        self.forces.iter().any(|f| f.normal <= 0.0)
    }

    /// Accepts the trial states and records the step.
    pub fn commit(&mut self) {
        self.state.clone_from(&self.trial);
        self.girder_old.clone_from(&self.girder0);
        self.girder0.clone_from(&self.girder_used);
        self.record();
    }

    /// Records the committed step: wheel forces and body accelerations.
    fn record(&mut self) {
        for (w, f) in self.forces.iter().enumerate() {
            self.out.lateral[w].push(f.lateral);
            self.out.vertical[w].push(f.vertical);
        }
        if self.lifted() {
            self.out.lift_off_steps += 1;
            self.out.first_lift_off_t.get_or_insert(self.t);
        }
        let t0 = self.t - self.dt;
        for car in 0..self.spec.cars {
            let r = self.rate(car, t0, self.t, &self.state[car]);
            self.out.body_ay[car].push(r[DOFS + HsrCar::BODY[0]]);
            self.out.body_az[car].push(r[DOFS + HsrCar::BODY[1]]);
        }
    }

    /// What the run kept.
    pub fn outcome(self) -> RailOutcome {
        self.out
    }
}

/// Refuses a sub-step too long for the wheel on the rail mass ([`MAX_CONTACT_STEP`]),
/// naming `train.substeps` and the fewest that will do.
fn check_substeps(spec: &RailTrain, m: &RailMass, dt: f64, gravity: f64) -> Result<()> {
    let w = &spec.car.wheelset;
    let p = spec.car.wheel_load(gravity) / w.conicity.atan().cos();
    let hertz = 1.5 * p.cbrt() / zhai_g(w.r0);
    let omega = m.contact_frequency(0.5 * w.mass, hertz);
    let fewest = (dt * omega / MAX_CONTACT_STEP).ceil() as usize;
    if spec.substeps < fewest {
        return Err(Error::invalid(
            "train.substeps",
            format!(
                "must be at least {fewest} at dt = {dt} s on this track: the wheel on the rail's mass rings at {omega:.0} rad/s, and RK4 needs dt/substeps ≤ {MAX_CONTACT_STEP}/ω; got {}",
                spec.substeps
            ),
        ));
    }
    Ok(())
}
