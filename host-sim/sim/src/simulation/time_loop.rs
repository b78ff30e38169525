//! The time loop: one loop for every train kind, each step in three named parts.
//!
//! 1. [`TimeLoop::kinematics`]: where every wheel, contact and moving force is at t, the
//!    rail's irregularity under each wheel and contact, and the profile the run used.
//! 2. [`TimeLoop::iterate`]: the coupled iteration (module docs of [`super`]) — the magnets'
//!    forces, the loads, the vehicle's solve, the contact forces, the guideway's solve, the
//!    new gaps — until the gaps and the rail under the contacts agree between two passes.
//! 3. [`TimeLoop::bookkeeping`]: commit the step, update the gap and contact ranges and the
//!    counters, and hand the step to the [`Recorder`] (the run's one recording path).
//!
//! Why one loop: a train of constant moving forces (`Load::Forces`) is a train with no cars,
//! no magnets and no contacts whose loads are constant forces; it steps through the same
//! functions (one pass per step, as nothing can disagree), so the two kinds cannot drift
//! apart. Why the buffers live in one struct: the loop allocates nothing per step.

use super::train::TrainState;
use super::{
    contact_force, CoilRange, CoilRanges, GapRanges, Magnets, Monitor, MovingLoad, Outcome,
    Profiles, Settings, WheelGaps,
};
use crate::physics::guideway::{Guideway, PointLoad};
use crate::physics::rail::run::RailRun;
use crate::physics::skid::{Skids, WheelView};
use crate::physics::train::Train;
use crate::physics::vehicle::magnet_gaps;
use crate::probes::{written, Recorder, StepView, Wheels};
use crate::{Error, Result};

/// A gap farther than this many `h0` from `h0` (or not finite) ends the run as diverged: the
/// skids hold a landed magnet within a few `h0` of its rail (docs/contact.md), so such a gap
/// is no state the model describes (an undamped girder pumped by the loops, a supply far
/// beyond its coil), and its numbers would be garbage in summary.json.
const DIVERGED_GAP: f64 = 100.0;

/// The error of a run whose magnet wheel `i` (0-based, the train's order) reached gap `h`.
fn diverged_gap(t: f64, i: usize, h: f64, h0: f64) -> Error {
    Error::numerical(format!(
        "the run diverged at t = {t} s: magnet wheel {} has a gap of {h:e} m, beyond \
         {DIVERGED_GAP}·h0 = {:e} m of h0; no outputs are written (a loop feeding an undamped \
         girder, or a value of the case too extreme)",
        i + 1,
        DIVERGED_GAP * h0
    ))
}

/// What rides over the guideway: a train's magnet wheels and contacts, and constant moving
/// forces (one of the two is empty).
pub(super) struct Riders<'a> {
    pub train: &'a Train,
    pub forces: &'a [MovingLoad],
}

/// Runs `riders` from t = 0 to `s.t_end` with `magnets` over `guideway`, streaming every
/// committed step to `rec`; `monitor` hears the fraction done now and then and is asked
/// after every step whether to stop ([`Error::Cancelled`]).
pub(super) fn run<G: Guideway, M: Magnets + ?Sized>(
    guideway: &mut G,
    riders: Riders,
    profiles: &Profiles,
    s: &Settings,
    magnets: &mut M,
    rec: &mut dyn Recorder,
    monitor: &mut dyn Monitor,
) -> Result<Outcome> {
    if (guideway.time_step() - s.dt).abs() > 1e-15 * s.dt {
        return Err(Error::numerical(
            "internal: guideway step differs from the run's step",
        ));
    }
    let steps = (s.t_end / s.dt).round() as usize;
    let mut l = TimeLoop::new(guideway, magnets, riders, profiles, s, steps)?;
    l.record(0.0, 0, false, rec)?;
    for n in 1..=steps {
        let t = n as f64 * s.dt;
        l.kinematics(n, t);
        let it = l.iterate(n as u32, t)?;
        l.bookkeeping(n as u32, t, it, rec)?;
        if n % 200 == 0 {
            monitor.progress(n as f64 / steps as f64);
        }
        if monitor.cancelled() {
            return Err(Error::Cancelled { t_s: t });
        }
    }
    Ok(l.outcome(steps))
}

/// Where the wheels, contacts and moving forces are at the step's time and the rail's
/// irregularity under them (docs/model.md §3).
struct Kinematics {
    /// Each magnet wheel's X and the irregularity `r_y`, `r_z` there (m).
    xs: Vec<f64>,
    ry: Vec<f64>,
    rz: Vec<f64>,
    /// Each contact's X and `r_z` there (m).
    cx: Vec<f64>,
    crz: Vec<f64>,
    /// Each moving force's point `(x, e_y, e_z)` (m) and its force (N, down), for the probes.
    points: Vec<(f64, f64, f64)>,
    magnitudes: Vec<f64>,
    /// `[x, r_y, r_z]` under every wheel and contact at every step, one ascending run of
    /// `steps + 1` rows per point (rows at equal x are equal, so the order of the runs does
    /// not show once sorted).
    profile: Vec<[f64; 3]>,
    /// Rows per point in `profile`.
    run: usize,
}

/// The coupled iteration's state within a step.
struct IterationState {
    /// Per magnet wheel: the committed gaps (t − Δt), those the last forces were computed
    /// from, and the current iterate (t).
    gaps_prev: Vec<WheelGaps>,
    gaps_used: Vec<WheelGaps>,
    current: Vec<WheelGaps>,
    /// Per magnet wheel: its vertical acceleration at the current iterate (m/s², Z up).
    accels: Vec<f64>,
    /// Per magnet wheel: its lateral acceleration there (m/s², +Y; 0 without a lateral DOF).
    accels_y: Vec<f64>,
    /// The magnets' forces `(G_z, G_y)` and the cars' wheel loads `(G_z − p0, G_y)` (N).
    forces: Vec<(f64, f64)>,
    f: Vec<(f64, f64)>,
    /// The guideway's loads: magnet wheels, then contacts, then moving forces.
    loads: Vec<PointLoad>,
    /// Per contact: the rail's motion under it (current iterate and the one the car was
    /// solved with), the car-side forcing, the loss-of-contact correction (current and used)
    /// and the contact force (N, compressive, clamped at zero).
    zg: Vec<f64>,
    zg_used: Vec<f64>,
    fc: Vec<f64>,
    lift: Vec<f64>,
    lift_used: Vec<f64>,
    contact_p: Vec<f64>,
}

/// What the coupled iteration of one step ended with.
#[derive(Clone, Copy)]
struct Iteration {
    iterations: u32,
    converged: bool,
    /// Some contact lifted off in the last pass.
    lost: bool,
}

/// The run's counters and ranges so far.
struct Tally {
    gap_ranges: GapRanges,
    coil_ranges: CoilRanges,
    contact_ranges: Vec<(f64, f64)>,
    unconverged_steps: usize,
    collision_steps: usize,
    contact_loss_steps: usize,
    total_iterations: u64,
    max_iterations: u32,
    first_collision_t: Option<f64>,
}

/// The train-wide DOF indices the probes read (cars concatenated in order), and each
/// contact's static load (the recorders' reference for its unloading).
struct ProbeDofs {
    /// Each magnet wheel's (Y, Z) DOFs (no Y: a magnet without guidance).
    wheels: Vec<(Option<usize>, usize)>,
    contacts: Vec<usize>,
    contact_p0: Vec<f64>,
    body_z: Vec<usize>,
}

/// The loop's state: what it steps, its work buffers and its tally.
struct TimeLoop<'a, G, M: ?Sized> {
    guideway: &'a mut G,
    magnets: &'a mut M,
    train: &'a Train,
    forces: &'a [MovingLoad],
    profiles: &'a Profiles,
    s: &'a Settings,
    h0: f64,
    veh: TrainState,
    at: Kinematics,
    it: IterationState,
    dofs: ProbeDofs,
    tally: Tally,
    /// The magnets' skids (docs/contact.md).
    skids: Skids,
    /// The 3-D high-speed cars (`crate::physics::rail::run`), their loads the last in
    /// `it.loads` from `rail_first` on.
    rail: Option<RailRun>,
    rail_first: usize,
}

impl<'a, G: Guideway, M: Magnets + ?Sized> TimeLoop<'a, G, M> {
    /// Everything at rest at t = 0: the train in its static equilibrium under the static
    /// forces, the magnets at their initial gaps, each contact at its static load on the rail
    /// as it lies at t = 0 ([`TrainState::start_on_rail`]).
    fn new(
        guideway: &'a mut G,
        magnets: &'a mut M,
        riders: Riders<'a>,
        profiles: &'a Profiles,
        s: &'a Settings,
        steps: usize,
    ) -> Result<Self> {
        let v = riders.train;
        let h0 = s.controller.h0;
        let mut veh = TrainState::new(v, s.dt)?;
        // Every contact starts at its static load on the rail as it lies at t = 0 (the
        // irregularity under it and the guideway's initial motion), the car at rest in that
        // static equilibrium (docs/cars.md "The start on a rough rail").
        let forcing: Vec<f64> = v
            .contacts
            .iter()
            .map(|c| {
                let z_g = guideway.motion_at(c.x0, c.ey, c.ez).z;
                c.k * (z_g - (profiles.z)(c.x0))
            })
            .collect();
        let contact_p = veh.start_on_rail(v, &forcing)?;
        let gaps_prev = super::initial_gaps(v, profiles, h0);
        let dofs = ProbeDofs {
            wheels: v
                .wheels
                .iter()
                .map(|w| {
                    (
                        w.dof_y.map(|y| veh.global(w.car, y)),
                        veh.global(w.car, w.dof_z),
                    )
                })
                .collect(),
            contacts: v
                .contacts
                .iter()
                .map(|c| veh.global(c.car, c.dof_z))
                .collect(),
            contact_p0: v.contacts.iter().map(|c| c.p0).collect(),
            body_z: (0..v.cars.len())
                .map(|c| veh.global(c, v.cars[c].body_z))
                .collect(),
        };
        let tally = Tally {
            gap_ranges: gaps_prev
                .iter()
                .map(|&g| magnet_gaps(g, h0).map(|h| (h, h)))
                .collect(),
            coil_ranges: magnets
                .coils()
                .iter()
                .map(|c| c.each_ref().map(CoilRange::of))
                .collect(),
            contact_ranges: contact_p.iter().map(|&p| (p, p)).collect(),
            unconverged_steps: 0,
            collision_steps: 0,
            contact_loss_steps: 0,
            total_iterations: 0,
            max_iterations: 0,
            first_collision_t: None,
        };
        let rail = match &v.rail {
            Some(spec) => Some(RailRun::new(
                spec,
                s.speed,
                s.dt,
                maglev_core::levitation::GRAVITY,
                steps,
            )?),
            None => None,
        };
        let mut it = IterationState::at_rest(v, riders.forces, gaps_prev, contact_p);
        let rail_first = it.loads.len();
        if let Some(r) = &rail {
            it.loads
                .resize(rail_first + r.wheels(), PointLoad::default());
        }
        Ok(TimeLoop {
            skids: Skids::new(s.skid, v.wheels.len()),
            at: Kinematics::at_rest(v, riders.forces, profiles, steps),
            it,
            rail,
            rail_first,
            guideway,
            magnets,
            train: v,
            forces: riders.forces,
            profiles,
            s,
            h0,
            veh,
            dofs,
            tally,
        })
    }

    /// Step 1: positions at `t` (step `n`), the irregularity under the wheels and contacts,
    /// the profile rows, and the moving forces' loads.
    fn kinematics(&mut self, n: usize, t: f64) {
        let (s, p, a) = (self.s, self.profiles, &mut self.at);
        let nw = self.train.wheels.len();
        for (i, w) in self.train.wheels.iter().enumerate() {
            a.xs[i] = w.x0 + s.speed * t;
            a.rz[i] = (p.z)(a.xs[i]);
            a.ry[i] = (p.y)(a.xs[i]);
            a.profile[i * a.run + n] = [a.xs[i], a.ry[i], a.rz[i]];
        }
        for (j, c) in self.train.contacts.iter().enumerate() {
            a.cx[j] = c.x0 + s.speed * t;
            a.crz[j] = (p.z)(a.cx[j]);
            a.profile[(nw + j) * a.run + n] = [a.cx[j], (p.y)(a.cx[j]), a.crz[j]];
        }
        let first = nw + self.train.contacts.len();
        let loads = &mut self.it.loads[first..];
        for ((l, f), q) in loads.iter_mut().zip(self.forces).zip(&mut a.points) {
            l.x = f.x0 + s.speed * t;
            q.0 = l.x;
        }
    }

    /// Step 2: the coupled iteration of step `step` ending at `t`, from the committed
    /// displacements until two passes agree or `max_iterations` is reached.
    fn iterate(&mut self, step: u32, t: f64) -> Result<Iteration> {
        self.gaps(false);
        self.rail_under_contacts();
        if let Some(r) = &mut self.rail {
            r.begin(t);
        }
        self.it.lift.fill(0.0);
        let mut iterations = 0;
        loop {
            iterations += 1;
            let lost = self.pass(step, t)?;
            let converged = self.change() <= self.s.tolerance;
            if converged || iterations >= self.s.max_iterations {
                return Ok(Iteration {
                    iterations,
                    converged,
                    lost,
                });
            }
        }
    }

    /// One pass: the magnets' forces from the current gaps, the cars solved under them and
    /// the rail's motion, the contact forces from the cars' solution, the guideway solved
    /// under all loads, and the new gaps and rail motion. Whether some contact lifted off.
    fn pass(&mut self, step: u32, t: f64) -> Result<bool> {
        let it = &mut self.it;
        self.magnets.lateral_accels(&it.accels_y);
        self.magnets.forces(
            step,
            t,
            &it.gaps_prev,
            &it.current,
            &it.accels,
            &mut it.forces,
        )?;
        self.skid_forces();
        self.magnet_loads();
        // The car sees the rail's motion of this iterate (and the lift-off correction of the
        // last one); its contact forces follow from its solution.
        let it = &mut self.it;
        for (j, c) in self.train.contacts.iter().enumerate() {
            it.fc[j] = c.k * (it.zg[j] - self.at.crz[j]) + it.lift[j];
        }
        self.veh.solve(self.train, &it.f, &it.fc);
        it.zg_used.copy_from_slice(&it.zg);
        it.lift_used.copy_from_slice(&it.lift);
        let mut lost = self.contact_loads();
        if let Some(r) = &mut self.rail {
            r.advance(&mut self.it.loads[self.rail_first..]);
            lost |= r.lifted();
        }
        self.guideway.solve_step(&self.it.loads);
        self.it.gaps_used.copy_from_slice(&self.it.current);
        self.gaps(true);
        self.rail_under_contacts();
        self.rail_under_rail_cars(t);
        Ok(lost)
    }

    /// Every magnet's skid force from the current gaps (docs/contact.md).
    fn skid_forces(&mut self) {
        let (it, veh, s) = (&self.it, &self.veh, self.s);
        self.skids.begin_pass();
        let sign = s.geometry.levitation_sign();
        for (i, w) in self.train.wheels.iter().enumerate() {
            let view = WheelView {
                prev: it.gaps_prev[i],
                now: it.current[i],
                h0: self.h0,
                sign,
                guided: w.dof_y.is_some(),
            };
            let flex = || {
                let y = w.dof_y.map_or(0.0, |y| veh.flexibility(w.car, y));
                (veh.flexibility(w.car, w.dof_z), y)
            };
            let touching = self.skids.wheel(i, &view, s.speed, s.dt, flex);
            self.skids.touched(touching);
        }
    }

    /// The cars' wheel loads and the guideway's magnet loads from the magnets' forces and the
    /// skids'.
    fn magnet_loads(&mut self) {
        let it = &mut self.it;
        for (i, w) in self.train.wheels.iter().enumerate() {
            let (gz, gy) = self.skids.add(i, it.forces[i]);
            it.f[i] = (gz - self.train.p0[i], gy);
            it.loads[i] = PointLoad {
                x: self.at.xs[i],
                ey: w.ey,
                ez: w.ez,
                fy: -gy,
                fz: -gz,
            };
        }
    }

    /// Each contact's force from the cars' trial solution, clamped at zero (the lift-off
    /// correction kept for the next pass), and its load on the guideway. Whether some
    /// contact lifted off.
    fn contact_loads(&mut self) -> bool {
        let (it, nw) = (&mut self.it, self.train.wheels.len());
        let mut lost = false;
        for (j, c) in self.train.contacts.iter().enumerate() {
            let z_w = self.veh.u1(c.car, c.dof_z);
            let p = contact_force(c.p0, c.k, z_w, it.zg[j], self.at.crz[j]);
            it.lift[j] = (-p).max(0.0);
            lost |= p < 0.0;
            it.contact_p[j] = p.max(0.0);
            it.loads[nw + j] = PointLoad {
                x: self.at.cx[j],
                ey: c.ey,
                ez: c.ez,
                fy: 0.0,
                fz: -it.contact_p[j],
            };
        }
        lost
    }

    /// Every magnet wheel's gaps at t (Eq. 2, 16) into the current iterate, from the cars'
    /// trial displacements (`trial`) or their committed ones (the first pass's estimate).
    fn gaps(&mut self, trial: bool) {
        let (s, at, veh) = (self.s, &self.at, &self.veh);
        for (i, w) in self.train.wheels.iter().enumerate() {
            let m = self.guideway.motion_at(at.xs[i], w.ey, w.ez);
            let (uy, uz, az, ay) = if trial {
                let (c, z) = (w.car, w.dof_z);
                (
                    w.dof_y.map_or(0.0, |y| veh.u1(c, y)),
                    veh.u1(c, z),
                    veh.a1(c, z),
                    w.dof_y.map_or(0.0, |y| veh.a1(c, y)),
                )
            } else {
                (
                    w.dof_y.map_or(0.0, |y| veh.u(w.car, y)),
                    veh.u(w.car, w.dof_z),
                    veh.a(w.car, w.dof_z),
                    w.dof_y.map_or(0.0, |y| veh.a(w.car, y)),
                )
            };
            self.it.accels[i] = az;
            self.it.accels_y[i] = ay;
            self.it.current[i] = (
                s.geometry.levitation_gap(self.h0, uz, m.z, at.rz[i]),
                maglev_core::gap::lateral_offset(uy, m.y, at.ry[i]),
            );
        }
    }

    /// The rail's vertical motion under every contact (the guideway's trial state).
    fn rail_under_contacts(&mut self) {
        for (j, c) in self.train.contacts.iter().enumerate() {
            self.it.zg[j] = self.guideway.motion_at(self.at.cx[j], c.ey, c.ez).z;
        }
    }

    /// The girder's motion under every wheel of the 3-D cars (the guideway's trial state).
    fn rail_under_rail_cars(&mut self, t: f64) {
        if let Some(r) = &mut self.rail {
            for w in 0..r.wheels() {
                let (x, ey, ez) = r.point(w, t);
                let m = self.guideway.motion_at(x, ey, ez);
                r.set_girder(w, m.y, m.z);
            }
        }
    }

    /// How far the last pass moved what the next one would start from: the largest change
    /// of a gap, of the rail under a contact, or of a lift-off correction (as a
    /// displacement), in m.
    fn change(&self) -> f64 {
        let it = &self.it;
        let gaps = it
            .current
            .iter()
            .zip(&it.gaps_used)
            .map(|(a, b)| (a.0 - b.0).abs().max((a.1 - b.1).abs()))
            .fold(0.0, f64::max);
        let contacts = (0..self.train.contacts.len())
            .map(|j| {
                let k_h = self.train.contacts[j].k;
                (it.zg[j] - it.zg_used[j])
                    .abs()
                    .max((it.lift[j] - it.lift_used[j]).abs() / k_h)
            })
            .fold(0.0, f64::max);
        match &self.rail {
            Some(r) => gaps.max(contacts).max(r.change()),
            None => gaps.max(contacts),
        }
    }

    /// Step 3: commit step `step` (ending at `t`), update the ranges and counters, record it.
    fn bookkeeping(
        &mut self,
        step: u32,
        t: f64,
        it: Iteration,
        rec: &mut dyn Recorder,
    ) -> Result<()> {
        self.magnets.commit(step, t)?;
        self.guideway.commit();
        self.veh.commit();
        if let Some(r) = &mut self.rail {
            r.commit();
        }
        let (buf, tally) = (&mut self.it, &mut self.tally);
        buf.gaps_prev.copy_from_slice(&buf.gaps_used);
        self.skids.commit(t);
        let mut collision = self.skids.touching();
        for (i, (r, &g)) in tally.gap_ranges.iter_mut().zip(&buf.gaps_used).enumerate() {
            for (r, h) in r.iter_mut().zip(magnet_gaps(g, self.h0)) {
                if !h.is_finite() || (h - self.h0).abs() > DIVERGED_GAP * self.h0 {
                    return Err(diverged_gap(t, i, h, self.h0));
                }
                *r = (r.0.min(h), r.1.max(h));
                collision |= h <= 0.0;
            }
        }
        for (r, c) in tally.coil_ranges.iter_mut().zip(self.magnets.coils()) {
            for (r, c) in r.iter_mut().zip(c) {
                r.add(c);
            }
        }
        for (r, &p) in tally.contact_ranges.iter_mut().zip(&buf.contact_p) {
            *r = (r.0.min(p), r.1.max(p));
        }
        tally.unconverged_steps += usize::from(!it.converged);
        tally.collision_steps += usize::from(collision);
        tally.contact_loss_steps += usize::from(it.lost);
        tally.total_iterations += u64::from(it.iterations);
        tally.max_iterations = tally.max_iterations.max(it.iterations);
        if collision && tally.first_collision_t.is_none() {
            tally.first_collision_t = Some(t);
        }
        self.record(t, it.iterations, collision, rec)
    }

    /// Hands the committed state at `t` to the recorder: the train's view, or, for a train
    /// with no guideway node (no magnet, no contact), the moving forces' view.
    fn record(
        &self,
        t: f64,
        iterations: u32,
        collision: bool,
        rec: &mut dyn Recorder,
    ) -> Result<()> {
        let wheels = if self.train.nodes.is_empty() {
            Wheels::Forces {
                points: &self.at.points,
                forces: &self.at.magnitudes,
            }
        } else {
            Wheels::Vehicle {
                u: self.veh.u_all(),
                a: self.veh.a_all(),
                dofs: &self.dofs.wheels,
                gaps: &self.it.gaps_prev,
                forces: &self.it.forces,
                h0: self.h0,
                body_z: &self.dofs.body_z,
                nodes: &self.train.nodes,
                contact_dofs: &self.dofs.contacts,
                contact_forces: &self.it.contact_p,
                contact_p0: &self.dofs.contact_p0,
                coils: self.magnets.coils(),
            }
        };
        rec.record(&StepView {
            t,
            guideway: &*self.guideway,
            midspans: &self.s.midspans,
            wheels,
            iterations,
            collision,
        })
    }

    /// The run's outcome after `steps` steps.
    fn outcome(self, steps: usize) -> Outcome {
        let mut profile = self.at.profile;
        profile.sort_by(|a, b| a[0].total_cmp(&b[0]));
        profile.dedup_by(|a, b| a[0] == b[0]);
        let t = self.tally;
        Outcome {
            steps,
            simulated_seconds: steps as f64 * self.s.dt,
            total_iterations: t.total_iterations,
            max_iterations: t.max_iterations,
            unconverged_steps: t.unconverged_steps,
            collision_steps: t.collision_steps,
            first_collision_t: t.first_collision_t,
            gap_ranges: t.gap_ranges,
            guided: self
                .train
                .wheels
                .iter()
                .map(|w| w.dof_y.is_some())
                .collect(),
            coil_ranges: t.coil_ranges,
            contact_loss_steps: t.contact_loss_steps,
            contact_ranges: t.contact_ranges,
            skids: self.skids.outcome(),
            rail: self.rail.map(RailRun::outcome),
            profile,
        }
    }
}

impl Kinematics {
    /// Everything at its place at t = 0, the profile's first rows written.
    fn at_rest(v: &Train, forces: &[MovingLoad], profiles: &Profiles, steps: usize) -> Self {
        let (nw, nc) = (v.wheels.len(), v.contacts.len());
        let run = steps + 1;
        let mut profile = written(run * (nw + nc), [0.0; 3]);
        let x0s = v.wheels.iter().map(|w| w.x0);
        for (k, x0) in x0s.chain(v.contacts.iter().map(|c| c.x0)).enumerate() {
            profile[k * run] = [x0, (profiles.y)(x0), (profiles.z)(x0)];
        }
        Kinematics {
            xs: vec![0.0; nw],
            ry: vec![0.0; nw],
            rz: vec![0.0; nw],
            cx: vec![0.0; nc],
            crz: vec![0.0; nc],
            points: forces.iter().map(|f| (f.x0, f.ey, f.ez)).collect(),
            magnitudes: forces.iter().map(|f| f.force).collect(),
            profile,
            run,
        }
    }
}

impl IterationState {
    /// The buffers at t = 0: the magnets at `gaps_prev` with their static forces, every
    /// contact at its force `contact_p` (its static load on the rail at t = 0), each moving
    /// force's load at its start.
    fn at_rest(
        v: &Train,
        forces: &[MovingLoad],
        gaps_prev: Vec<WheelGaps>,
        contact_p: Vec<f64>,
    ) -> Self {
        let (nw, nc) = (v.wheels.len(), v.contacts.len());
        let mut loads = vec![PointLoad::default(); nw + nc];
        loads.extend(forces.iter().map(|f| PointLoad {
            x: f.x0,
            ey: f.ey,
            ez: f.ez,
            fy: 0.0,
            fz: -f.force,
        }));
        IterationState {
            gaps_used: vec![(0.0, 0.0); nw],
            current: vec![(0.0, 0.0); nw],
            accels: vec![0.0; nw],
            accels_y: vec![0.0; nw],
            gaps_prev,
            forces: v.p0.iter().map(|&p0| (p0, 0.0)).collect(),
            f: vec![(0.0, 0.0); nw],
            loads,
            zg: vec![0.0; nc],
            zg_used: vec![0.0; nc],
            fc: vec![0.0; nc],
            lift: vec![0.0; nc],
            lift_used: vec![0.0; nc],
            contact_p,
        }
    }
}
