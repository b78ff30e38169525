//! Vehicle–guideway coupling in step-lockstep with the magnets' controllers (docs/model.md §7):
//! the one Newton–Raphson loop of the project, shared by `maglev run` and `maglev hil`.
//!
//! Each time step runs a Newton–Raphson (fixed-point) loop on the wheel forces:
//! (1) from the current displacement estimate compute every gap (Eq. 2, 16) and ask the
//! [`Magnets`] for the forces over the step;
//! (2) load the guideway (Eq. 15) and the vehicle and solve both for t + Δt;
//! (3) repeat until the gaps the forces were computed from agree with the gaps the solution
//! gives. The magnets restart from their committed state at every iteration and commit only on
//! convergence. The iteration count of each step is recorded (Fig. 5).
//!
//! Wheel–rail contacts (Hertz springs, docs/cars.md "Wheel–rail contact") ride in the same
//! loop: their springs are implicit in the cars, the rail's motion is their forcing, and the
//! iteration runs until that motion agrees too.
//!
//! Two kinds of magnets plug into the loop: [`magnets::CoreMagnets`], the core's controllers
//! in f64 with exact gaps (both laws; `maglev run`), and `hil::coupling::FirmwareMagnets`,
//! the firmware behind a link with sampled, quantised gaps (`maglev hil`). One loop means the
//! two runs differ only in the controller, which is what `maglev hil --compare` measures.

pub mod magnets;
pub mod train;

use crate::guideway::{Guideway, PointLoad, SectionMotion};
use crate::probes::{Recorder, StepView, Wheels};
use crate::vehicle::{Node, Train};
use crate::{Error, Result};
use maglev_core::gap::{self, Geometry};
use maglev_core::{LawKind, Params, Status};
use train::TrainState;

/// What runs over the guideway.
pub enum Load {
    /// Constant vertical forces moving with the run's speed (a `forces` train, or the single
    /// moving force of the verification case); no controller, no irregularity. Record
    /// "wheel 1" is the first load.
    Forces(Vec<MovingLoad>),
    /// A train (one car or more): one levitation magnet and one guidance pair per maglev
    /// wheel, one Hertz spring per wheel–rail contact.
    Vehicle(Train),
}

/// One constant moving force.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MovingLoad {
    /// X at t = 0 (m).
    pub x0: f64,
    /// Force (N, positive downward).
    pub force: f64,
    /// Offset of its point from the beam axis, Y and Z (m).
    pub ey: f64,
    pub ez: f64,
}

/// Rail irregularity profiles r_y(x), r_z(x) (m), shared by every wheel (docs/model.md §3).
pub struct Profiles {
    pub y: Box<dyn Fn(f64) -> f64>,
    pub z: Box<dyn Fn(f64) -> f64>,
}

impl Profiles {
    /// A perfectly smooth rail.
    pub fn smooth() -> Self {
        Profiles {
            y: Box::new(|_| 0.0),
            z: Box::new(|_| 0.0),
        }
    }
}

/// Run settings (SI).
pub struct Settings {
    pub speed: f64,
    pub dt: f64,
    pub t_end: f64,
    /// Controller parameters (p0 is replaced by each wheel's static load).
    pub controller: Params,
    /// The law of every levitation and guidance magnet (`maglev_core::law`).
    pub law: LawKind,
    /// How the magnets face their rails (Eq. 2 and the guidance pair's sign, docs/model.md §2).
    pub geometry: Geometry,
    /// Convergence tolerance on the gaps between two iterations (m).
    pub tolerance: f64,
    pub max_iterations: u32,
    /// X of the section reported as "midspan".
    pub midspan_x: f64,
    /// X of the middle of every span (the `span{K}.midspan` probes).
    pub midspans: Vec<f64>,
}

/// One recorded step (SI; displacements positive along the axes).
#[derive(Clone, Copy, Debug, Default)]
pub struct Record {
    pub t: f64,
    pub midspan: SectionMotion,
    pub wheel1_y: f64,
    pub wheel1_z: f64,
    /// NaN for a moving force (no gap).
    pub wheel1_gap_z: f64,
    pub wheel1_force_z: f64,
    pub iterations: u32,
    pub status: Status,
    /// Some magnet's gap was at or below zero at the end of the step (a collision).
    pub collision: bool,
}

/// The range `(min, max)` (m) of each magnet's gap over a run, per wheel: levitation,
/// guidance left, guidance right.
pub type GapRanges = Vec<[(f64, f64); 3]>;

/// Result of a run.
pub struct Outcome {
    pub records: Vec<Record>,
    /// Steps whose iterations hit `max_iterations` without converging.
    pub unconverged_steps: usize,
    /// Steps in which some magnet's gap was at or below zero.
    pub collision_steps: usize,
    /// Each magnet's gap range over the run (empty for a moving force).
    pub gap_ranges: GapRanges,
    /// Steps in which some wheel–rail contact lifted off (its force clamped at zero).
    pub contact_loss_steps: usize,
    /// Each contact's force range `(min, max)` (N, compressive) over the run, clamped.
    pub contact_ranges: Vec<(f64, f64)>,
    /// The irregularity the run used, `[x, r_y, r_z]` (m) at every position a wheel occupied
    /// at a step, sorted by x, duplicates removed (empty for a moving force).
    pub profile: Vec<[f64; 3]>,
}

/// The three magnet gaps `[h_z, h_L, h_R]` (m) of a wheel's gaps (docs/model.md §2).
pub fn magnet_gaps((hz, d): WheelGaps, h0: f64) -> [f64; 3] {
    let (hl, hr) = gap::guidance_gaps(h0, d);
    [hz, hl, hr]
}

/// Per wheel: the levitation gap `h_z` (m, Eq. 2) and the relative lateral position
/// `d = y_w − y_g + r_y` (m, docs/model.md §2; the guidance magnets' gaps are `h0 ± d`).
pub type WheelGaps = (f64, f64);

/// The magnets of a vehicle as the coupling loop sees them: forces from gaps, with a
/// committed state and a trial state (docs/model.md §7).
pub trait Magnets {
    /// Per wheel `(G_z, G_y)` (N, magnet forces, positive up and along +Y) over step `step`
    /// ending at `t`, as the gaps move from `gaps_prev` (committed, at t − Δt) to `gaps_next`
    /// (the current iterate, at t). Always starts from the committed state, so the loop may
    /// call it several times per step.
    fn forces(
        &mut self,
        step: u32,
        t: f64,
        gaps_prev: &[WheelGaps],
        gaps_next: &[WheelGaps],
        out: &mut [(f64, f64)],
    ) -> Result<()>;

    /// Makes the state after the last [`Magnets::forces`] call of `step` the committed one.
    fn commit(&mut self, step: u32, t: f64) -> Result<()>;

    /// The core's status flags of the last [`Magnets::forces`] call (recorded per step).
    fn status(&self) -> Status;
}

/// Each wheel's gaps at t = 0 with the vehicle at rest at its static position:
/// `(h0 + r_z(x0), r_y(x0))`.
pub fn initial_gaps(v: &Train, profiles: &Profiles, h0: f64) -> Vec<WheelGaps> {
    v.wheels
        .iter()
        .map(|w| (h0 + (profiles.z)(w.x0), (profiles.y)(w.x0)))
        .collect()
}

/// Runs from t = 0 to `t_end`. `progress` is called with the fraction done now and then.
pub fn simulate<G: Guideway>(
    guideway: &mut G,
    load: &Load,
    profiles: &Profiles,
    s: &Settings,
    rec: &mut dyn Recorder,
    mut progress: impl FnMut(f64),
) -> Result<Outcome> {
    let dt = s.dt;
    if (guideway.time_step() - dt).abs() > 1e-15 * dt {
        return Err(Error::numerical(
            "internal: guideway step differs from the run's step",
        ));
    }
    match load {
        Load::Forces(forces) => {
            let steps = (s.t_end / dt).round() as usize;
            let first = forces
                .first()
                .ok_or_else(|| Error::invalid("train.loads_kN", "needs at least one load"))?;
            let mut records = written(steps + 1, Record::default());
            records.clear();
            records.push(Record {
                midspan: guideway.section_at(s.midspan_x),
                wheel1_gap_z: f64::NAN,
                ..Record::default()
            });
            let mut loads: Vec<PointLoad> = forces
                .iter()
                .map(|f| PointLoad {
                    x: f.x0,
                    ey: f.ey,
                    ez: f.ez,
                    fy: 0.0,
                    fz: -f.force,
                })
                .collect();
            let magnitudes: Vec<f64> = forces.iter().map(|f| f.force).collect();
            let mut points: Vec<(f64, f64, f64)> =
                loads.iter().map(|l| (l.x, l.ey, l.ez)).collect();
            let mut record = |t: f64, g: &G, points: &[(f64, f64, f64)], iterations| {
                rec.record(&StepView {
                    t,
                    guideway: g,
                    midspans: &s.midspans,
                    wheels: Wheels::Forces {
                        points,
                        forces: &magnitudes,
                    },
                    iterations,
                    collision: false,
                })
            };
            record(0.0, guideway, &points, 0)?;
            for n in 1..=steps {
                let t = n as f64 * dt;
                for ((l, f), p) in loads.iter_mut().zip(forces).zip(points.iter_mut()) {
                    l.x = f.x0 + s.speed * t;
                    p.0 = l.x;
                }
                guideway.solve_step(&loads);
                guideway.commit();
                record(t, guideway, &points, 1)?;
                let m = guideway.motion_at(loads[0].x, first.ey, first.ez);
                records.push(Record {
                    t,
                    midspan: guideway.section_at(s.midspan_x),
                    wheel1_y: m.y,
                    wheel1_z: m.z,
                    wheel1_gap_z: f64::NAN,
                    wheel1_force_z: first.force,
                    iterations: 1,
                    status: Status::default(),
                    collision: false,
                });
                if n % 1000 == 0 {
                    progress(n as f64 / steps as f64);
                }
            }
            Ok(Outcome {
                records,
                unconverged_steps: 0,
                collision_steps: 0,
                gap_ranges: Vec::new(),
                contact_loss_steps: 0,
                contact_ranges: Vec::new(),
                profile: Vec::new(),
            })
        }
        Load::Vehicle(v) => {
            let gaps0 = initial_gaps(v, profiles, s.controller.h0);
            let mut magnets = magnets::CoreMagnets::new(v, &gaps0, s)?;
            couple(guideway, v, profiles, s, &mut magnets, rec, progress)
        }
    }
}

/// The coupling loop of a train with `magnets` over `guideway` (module docs). Wheel–rail
/// contacts join the same loop (docs/cars.md "Wheel–rail contact"): their Hertz springs are
/// in the cars' matrices, the rail's motion enters the car as the forcing `k_h·(z_g − r_z)`,
/// and the guideway receives the contact forces; the iteration also runs until the rail's
/// motion under every contact agrees between two iterations.
pub fn couple<G: Guideway, M: Magnets + ?Sized>(
    guideway: &mut G,
    v: &Train,
    profiles: &Profiles,
    s: &Settings,
    magnets: &mut M,
    rec: &mut dyn Recorder,
    mut progress: impl FnMut(f64),
) -> Result<Outcome> {
    let dt = s.dt;
    if (guideway.time_step() - dt).abs() > 1e-15 * dt {
        return Err(Error::numerical(
            "internal: guideway step differs from the run's step",
        ));
    }
    if v.nodes.is_empty() {
        return Err(Error::invalid(
            "train",
            "has no magnet and no wheel to meet the guideway",
        ));
    }
    let h0 = s.controller.h0;
    let steps = (s.t_end / dt).round() as usize;
    let nw = v.wheels.len();
    let nc = v.contacts.len();
    let mut gaps_prev = initial_gaps(v, profiles, h0);
    let mut ranges: GapRanges = gaps_prev
        .iter()
        .map(|&g| magnet_gaps(g, h0).map(|h| (h, h)))
        .collect();
    let mut contact_ranges: Vec<(f64, f64)> = v.contacts.iter().map(|c| (c.p0, c.p0)).collect();
    let mut collision_steps = 0;
    let mut contact_loss_steps = 0;
    // The irregularity under every wheel and contact, one ascending run per point (rows at
    // equal x are equal, so the order of the runs does not show after the sort).
    let run = steps + 1;
    let mut profile: Vec<[f64; 3]> = written(run * (nw + nc), [0.0; 3]);
    let x0s = v
        .wheels
        .iter()
        .map(|w| w.x0)
        .chain(v.contacts.iter().map(|c| c.x0));
    for (k, x0) in x0s.enumerate() {
        profile[k * run] = [x0, (profiles.y)(x0), (profiles.z)(x0)];
    }
    let mut veh = TrainState::new(v, dt)?;
    // Train-wide DOF indices for the probes (cars concatenated in order).
    let dofs: Vec<(usize, usize)> = v
        .wheels
        .iter()
        .map(|w| (veh.global(w.car, w.dof_y), veh.global(w.car, w.dof_z)))
        .collect();
    let contact_dofs: Vec<usize> = v
        .contacts
        .iter()
        .map(|c| veh.global(c.car, c.dof_z))
        .collect();
    let body_z: Vec<usize> = (0..v.cars.len())
        .map(|c| veh.global(c, v.cars[c].body_z))
        .collect();
    // The static forces at t = 0; every iteration overwrites them.
    let mut forces: Vec<(f64, f64)> = v.p0.iter().map(|&p0| (p0, 0.0)).collect();
    let mut contact_p: Vec<f64> = v.contacts.iter().map(|c| c.p0).collect();
    let first =
        |forces: &[(f64, f64)], contact_p: &[f64], gaps: &[WheelGaps], veh: &TrainState| match v
            .nodes[0]
        {
            Node::Magnet(i) => {
                let w = &v.wheels[i];
                (
                    veh.u(w.car, w.dof_y),
                    veh.u(w.car, w.dof_z),
                    gaps[i].0,
                    forces[i].0,
                )
            }
            Node::Contact(i) => {
                let c = &v.contacts[i];
                (f64::NAN, veh.u(c.car, c.dof_z), f64::NAN, contact_p[i])
            }
        };
    let mut records = written(steps + 1, Record::default());
    records.clear();
    {
        let (_, _, gap_z, force_z) = first(&forces, &contact_p, &gaps_prev, &veh);
        records.push(Record {
            midspan: guideway.section_at(s.midspan_x),
            wheel1_gap_z: gap_z,
            wheel1_force_z: force_z,
            ..Record::default()
        });
    }
    let mut unconverged = 0;
    rec.record(&StepView {
        t: 0.0,
        guideway: &*guideway,
        midspans: &s.midspans,
        wheels: Wheels::Vehicle {
            u: veh.u_all(),
            a: veh.a_all(),
            dofs: &dofs,
            gaps: &gaps_prev,
            forces: &forces,
            h0,
            body_z: &body_z,
            nodes: &v.nodes,
            contact_dofs: &contact_dofs,
            contact_forces: &contact_p,
        },
        iterations: 0,
        collision: false,
    })?;
    let mut f = vec![(0.0, 0.0); nw];
    let mut loads = vec![PointLoad::default(); nw + nc];
    let mut gaps_used = vec![(0.0, 0.0); nw];
    let mut current = vec![(0.0, 0.0); nw];
    let (mut xs, mut ry, mut rz) = (vec![0.0; nw], vec![0.0; nw], vec![0.0; nw]);
    // Contacts: position, irregularity, the rail's motion under them (current iterate and the
    // one the car was solved with), the car-side forcing and the loss-of-contact correction.
    let (mut cx, mut crz) = (vec![0.0; nc], vec![0.0; nc]);
    let (mut zg, mut zg_used) = (vec![0.0; nc], vec![0.0; nc]);
    let (mut fc, mut lift, mut lift_used) = (vec![0.0; nc], vec![0.0; nc], vec![0.0; nc]);
    for n in 1..=steps {
        let t = n as f64 * dt;
        let step = n as u32;
        for (i, w) in v.wheels.iter().enumerate() {
            xs[i] = w.x0 + s.speed * t;
            rz[i] = (profiles.z)(xs[i]);
            ry[i] = (profiles.y)(xs[i]);
            profile[i * run + n] = [xs[i], ry[i], rz[i]];
        }
        for (j, c) in v.contacts.iter().enumerate() {
            cx[j] = c.x0 + s.speed * t;
            crz[j] = (profiles.z)(cx[j]);
            profile[(nw + j) * run + n] = [cx[j], (profiles.y)(cx[j]), crz[j]];
        }
        // Gaps at t from a displacement estimate (the committed state on the first pass).
        let gaps = |trial: bool, veh: &TrainState, gw: &G, out: &mut [WheelGaps]| {
            for (i, w) in v.wheels.iter().enumerate() {
                let m = gw.motion_at(xs[i], w.ey, w.ez);
                let (uy, uz) = if trial {
                    (veh.u1(w.car, w.dof_y), veh.u1(w.car, w.dof_z))
                } else {
                    (veh.u(w.car, w.dof_y), veh.u(w.car, w.dof_z))
                };
                out[i] = (
                    s.geometry.levitation_gap(h0, uz, m.z, rz[i]),
                    gap::lateral_offset(uy, m.y, ry[i]),
                );
            }
        };
        let rail = |gw: &G, out: &mut [f64]| {
            for (j, c) in v.contacts.iter().enumerate() {
                out[j] = gw.motion_at(cx[j], c.ey, c.ez).z;
            }
        };
        gaps(false, &veh, guideway, &mut current);
        rail(guideway, &mut zg);
        lift.fill(0.0);
        let mut iterations = 0;
        let mut lost;
        loop {
            iterations += 1;
            magnets.forces(step, t, &gaps_prev, &current, &mut forces)?;
            for (i, w) in v.wheels.iter().enumerate() {
                let (gz, gy) = forces[i];
                f[i] = (gz - v.p0[i], gy);
                loads[i] = PointLoad {
                    x: xs[i],
                    ey: w.ey,
                    ez: w.ez,
                    fy: -gy,
                    fz: -gz,
                };
            }
            // The car sees the rail's motion of this iterate (and the lift-off correction of
            // the last one); its contact forces follow from its solution.
            for (j, c) in v.contacts.iter().enumerate() {
                fc[j] = c.k * (zg[j] - crz[j]) + lift[j];
            }
            veh.solve(v, &f, &fc);
            zg_used.copy_from_slice(&zg);
            lift_used.copy_from_slice(&lift);
            lost = false;
            for (j, c) in v.contacts.iter().enumerate() {
                let p = contact_force(c.p0, c.k, veh.u1(c.car, c.dof_z), zg[j], crz[j]);
                lift[j] = (-p).max(0.0);
                lost |= p < 0.0;
                contact_p[j] = p.max(0.0);
                loads[nw + j] = PointLoad {
                    x: cx[j],
                    ey: c.ey,
                    ez: c.ez,
                    fy: 0.0,
                    fz: -contact_p[j],
                };
            }
            guideway.solve_step(&loads);
            gaps_used.copy_from_slice(&current);
            gaps(true, &veh, guideway, &mut current);
            rail(guideway, &mut zg);
            let change = current
                .iter()
                .zip(&gaps_used)
                .map(|(a, b)| (a.0 - b.0).abs().max((a.1 - b.1).abs()))
                .fold(0.0, f64::max);
            let change_c = (0..nc)
                .map(|j| {
                    let k_h = v.contacts[j].k;
                    (zg[j] - zg_used[j])
                        .abs()
                        .max((lift[j] - lift_used[j]).abs() / k_h)
                })
                .fold(0.0, f64::max);
            if change.max(change_c) <= s.tolerance {
                break;
            }
            if iterations >= s.max_iterations {
                unconverged += 1;
                break;
            }
        }
        magnets.commit(step, t)?;
        guideway.commit();
        veh.commit();
        gaps_prev.copy_from_slice(&gaps_used);
        let mut collision = false;
        for (r, &g) in ranges.iter_mut().zip(&gaps_used) {
            for (r, h) in r.iter_mut().zip(magnet_gaps(g, h0)) {
                *r = (r.0.min(h), r.1.max(h));
                collision |= h <= 0.0;
            }
        }
        for (r, &p) in contact_ranges.iter_mut().zip(&contact_p) {
            *r = (r.0.min(p), r.1.max(p));
        }
        collision_steps += usize::from(collision);
        contact_loss_steps += usize::from(lost);
        rec.record(&StepView {
            t,
            guideway: &*guideway,
            midspans: &s.midspans,
            wheels: Wheels::Vehicle {
                u: veh.u_all(),
                a: veh.a_all(),
                dofs: &dofs,
                gaps: &gaps_used,
                forces: &forces,
                h0,
                body_z: &body_z,
                nodes: &v.nodes,
                contact_dofs: &contact_dofs,
                contact_forces: &contact_p,
            },
            iterations,
            collision,
        })?;
        let (wheel1_y, wheel1_z, wheel1_gap_z, wheel1_force_z) =
            first(&forces, &contact_p, &gaps_used, &veh);
        records.push(Record {
            t,
            midspan: guideway.section_at(s.midspan_x),
            wheel1_y,
            wheel1_z,
            wheel1_gap_z,
            wheel1_force_z,
            iterations,
            status: magnets.status(),
            collision,
        });
        if n % 200 == 0 {
            progress(n as f64 / steps as f64);
        }
    }
    profile.sort_by(|a, b| a[0].total_cmp(&b[0]));
    profile.dedup_by(|a, b| a[0] == b[0]);
    Ok(Outcome {
        records,
        unconverged_steps: unconverged,
        collision_steps,
        gap_ranges: ranges,
        contact_loss_steps,
        contact_ranges,
        profile,
    })
}

/// `n` copies of `value` in memory already written, so that the time loop, which fills it,
/// meets no page fault (the OS maps a fresh or zeroed allocation, `vec![0.0; n]`, only on
/// first touch). A vector cleared after this keeps its pages.
pub(crate) fn written<T: Clone>(n: usize, value: T) -> Vec<T> {
    let mut v = Vec::with_capacity(n);
    v.resize(n, value);
    v
}

/// The linearised contact force (N, compressive positive; docs/cars.md "Wheel–rail
/// contact"): `P = P0 − k·(z_w − z_g + r_z)`, k the contact spring ([`crate::vehicle::Contact::k`]), with z_w the wheel's and z_g the rail point's
/// displacement (m, up) and r_z the irregularity (m; r_z > 0 opens the gap, as in Eq. 2).
/// Negative means the wheel has lifted off: the caller clamps it at zero.
pub fn contact_force(p0: f64, k: f64, z_w: f64, z_g: f64, r_z: f64) -> f64 {
    p0 - k * (z_w - z_g + r_z)
}
