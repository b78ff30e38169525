//! Vehicle–guideway coupling in step-lockstep with the core's controllers (model.md §7).
//!
//! Each time step runs a Newton–Raphson (fixed-point) loop on the wheel forces:
//! (1) from the current displacement estimate compute every gap (Eq. 2, 16) and magnet force
//! (Eq. 14 with its internal loop, Eq. 1) — by calling the core, never a host copy of the law;
//! (2) load the guideway (Eq. 15) and the vehicle and solve both for t + Δt;
//! (3) repeat until the gaps the forces were computed from agree with the gaps the solution
//! gives. Controller states are copied from the committed ones at every iteration and
//! committed only on convergence. The iteration count of each step is recorded (Fig. 5).

use crate::guideway::{Guideway, PointLoad, SectionMotion};
use crate::newmark::Newmark;
use crate::vehicle::VehicleModel;
use maglev_core::gap_control::{GapLoop, GapPairState, GapParams, GapState};
use maglev_core::guidance;
use maglev_core::{Levitation, Params, Status};
use nalgebra::DVector;

/// What runs over the guideway.
pub enum Load {
    /// One constant force (N, positive downward) at a fixed offset from the beam axis; no
    /// controller, no irregularity (for verification against closed forms).
    MovingForce { force: f64, ey: f64, ez: f64 },
    /// A maglev vehicle with one levitation magnet and one guidance pair per wheel.
    Vehicle(VehicleModel),
}

/// Rail irregularity profiles r_y(x), r_z(x) (m), shared by every wheel (model.md §3).
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

/// Which levitation law each magnet runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Law {
    /// The paper's PI law on `g = i/h` alone (Eq. 8–14).
    Paper,
    /// The outer gap loop (`maglev_core::gap_control`) setting the paper's law's reference,
    /// on every levitation and guidance magnet.
    GapLoop(GapParams),
}

/// Run settings (SI).
pub struct Settings {
    pub speed: f64,
    pub dt: f64,
    pub t_end: f64,
    /// Controller parameters (p0 is replaced by each wheel's static load).
    pub controller: Params,
    /// Levitation law.
    pub law: Law,
    /// Convergence tolerance on the gaps between two iterations (m).
    pub tolerance: f64,
    pub max_iterations: u32,
    /// X of the section reported as "midspan".
    pub midspan_x: f64,
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
}

/// Result of a run.
pub struct Outcome {
    pub records: Vec<Record>,
    /// Steps whose iterations hit `max_iterations` without converging.
    pub unconverged_steps: usize,
}

struct WheelCtl {
    lev: Levitation<f64>,
    /// The outer gap loop, when selected.
    outer: Option<GapLoop<f64>>,
    /// Inner state (and the outer loop's filter, unused under the paper's law).
    lev_state: GapState<f64>,
    /// Guidance pair (the filters unused under the paper's law).
    pair: GapPairState<f64>,
}

/// Runs from t = 0 to `t_end`. `progress` is called with the fraction done now and then.
pub fn simulate<G: Guideway>(
    guideway: &mut G,
    load: &Load,
    profiles: &Profiles,
    s: &Settings,
    mut progress: impl FnMut(f64),
) -> Result<Outcome, String> {
    let dt = s.dt;
    if (guideway.time_step() - dt).abs() > 1e-15 * dt {
        return Err("internal: guideway step differs from the run's step".into());
    }
    let steps = (s.t_end / dt).round() as usize;
    let mut records = Vec::with_capacity(steps + 1);
    records.push(Record {
        midspan: guideway.section_at(s.midspan_x),
        ..Record::default()
    });
    let mut unconverged = 0;
    match load {
        Load::MovingForce { force, ey, ez } => {
            records[0].wheel1_gap_z = f64::NAN;
            for n in 1..=steps {
                let t = n as f64 * dt;
                let x = s.speed * t;
                guideway.solve_step(&[PointLoad {
                    x,
                    ey: *ey,
                    ez: *ez,
                    fy: 0.0,
                    fz: -force,
                }]);
                guideway.commit();
                let m = guideway.motion_at(x, *ey, *ez);
                records.push(Record {
                    t,
                    midspan: guideway.section_at(s.midspan_x),
                    wheel1_y: m.y,
                    wheel1_z: m.z,
                    wheel1_gap_z: f64::NAN,
                    wheel1_force_z: *force,
                    iterations: 1,
                    status: Status::default(),
                });
                if n % 1000 == 0 {
                    progress(n as f64 / steps as f64);
                }
            }
        }
        Load::Vehicle(v) => {
            let mut veh = Newmark::new(v.m.clone(), v.c.clone(), v.k.clone(), dt)?;
            let mut ctl = Vec::new();
            for (w, &p0) in v.wheels.iter().zip(&v.p0) {
                let mut p = s.controller;
                p.p0 = p0;
                p.dt = dt;
                let lev = p.compile::<f64>().map_err(|e| e.to_string())?;
                let outer = match s.law {
                    Law::Paper => None,
                    Law::GapLoop(g) => Some(g.compile::<f64>(dt).map_err(|e| e.to_string())?),
                };
                let (gy, gz) = ((profiles.y)(w.x0), (profiles.z)(w.x0));
                let h_init = p.h0 + gz;
                let inner = lev.equilibrium_state(h_init);
                ctl.push(WheelCtl {
                    lev_state: GapState {
                        inner,
                        q: inner.eta,
                    },
                    outer,
                    pair: {
                        let p = guidance::initial_state(&lev, gy);
                        GapPairState {
                            left: GapState {
                                inner: p.left,
                                q: p.left.eta,
                            },
                            right: GapState {
                                inner: p.right,
                                q: p.right.eta,
                            },
                        }
                    },
                    lev,
                });
            }
            records[0].wheel1_gap_z = ctl[0].lev.params().h0 + (profiles.z)(v.wheels[0].x0);
            records[0].wheel1_force_z = v.p0[0];
            let nw = v.wheels.len();
            let mut f = DVector::zeros(v.m.nrows());
            let mut loads = vec![PointLoad::default(); nw];
            let mut gaps_used = vec![(0.0, 0.0); nw];
            let mut forces = vec![(0.0, 0.0); nw];
            let mut trial: Vec<(GapState<f64>, GapPairState<f64>)> = Vec::with_capacity(nw);
            for n in 1..=steps {
                let t = n as f64 * dt;
                let xs: Vec<f64> = v.wheels.iter().map(|w| w.x0 + s.speed * t).collect();
                let rz: Vec<f64> = xs.iter().map(|&x| (profiles.z)(x)).collect();
                let ry: Vec<f64> = xs.iter().map(|&x| (profiles.y)(x)).collect();
                // Gaps from the current estimate (the committed state on the first pass).
                let gaps = |veh: &Newmark, gw: &G, first: bool| -> Vec<(f64, f64)> {
                    v.wheels
                        .iter()
                        .enumerate()
                        .map(|(i, w)| {
                            let u = if first { veh.u() } else { veh.u1() };
                            let m = gw.motion_at(xs[i], w.ey, w.ez);
                            let h0 = ctl[i].lev.params().h0;
                            // Eq. 2 (Z) and model.md §2 (Y, relative lateral position).
                            (h0 - (u[w.dof_z] - m.z) + rz[i], u[w.dof_y] - m.y + ry[i])
                        })
                        .collect()
                };
                let mut current = gaps(&veh, guideway, true);
                let mut iterations = 0;
                let mut status;
                loop {
                    iterations += 1;
                    trial.clear();
                    status = Status::default();
                    for (i, c) in ctl.iter().enumerate() {
                        let (hz, dy) = current[i];
                        let h0 = c.lev.params().h0;
                        let mut st = c.lev_state;
                        let out = match &c.outer {
                            Some(o) => o.update(&c.lev, &mut st, hz / h0).inner,
                            None => c.lev.update(&mut st.inner, hz / h0),
                        };
                        let mut pair = c.pair;
                        let pout = match &c.outer {
                            Some(o) => o.update_pair(&c.lev, &mut pair, dy / h0),
                            None => {
                                let mut ps = guidance::PairState {
                                    left: pair.left.inner,
                                    right: pair.right.inner,
                                };
                                let out = guidance::update(&c.lev, &mut ps, dy / h0);
                                (pair.left.inner, pair.right.inner) = (ps.left, ps.right);
                                out
                            }
                        };
                        status = status.union(out.status).union(pout.status);
                        let p0 = c.lev.params().p0;
                        forces[i] = (out.force * p0, pout.force_y * p0);
                        trial.push((st, pair));
                    }
                    f.fill(0.0);
                    for (i, w) in v.wheels.iter().enumerate() {
                        let (gz, gy) = forces[i];
                        f[w.dof_z] = gz - v.p0[i];
                        f[w.dof_y] = gy;
                        loads[i] = PointLoad {
                            x: xs[i],
                            ey: w.ey,
                            ez: w.ez,
                            fy: -gy,
                            fz: -gz,
                        };
                    }
                    guideway.solve_step(&loads);
                    veh.solve(&f);
                    gaps_used.copy_from_slice(&current);
                    current = gaps(&veh, guideway, false);
                    let change = current
                        .iter()
                        .zip(&gaps_used)
                        .map(|(a, b)| (a.0 - b.0).abs().max((a.1 - b.1).abs()))
                        .fold(0.0, f64::max);
                    if change <= s.tolerance {
                        break;
                    }
                    if iterations >= s.max_iterations {
                        unconverged += 1;
                        break;
                    }
                }
                guideway.commit();
                veh.commit();
                for (c, (st, pair)) in ctl.iter_mut().zip(trial.drain(..)) {
                    c.lev_state = st;
                    c.pair = pair;
                }
                let w1 = &v.wheels[0];
                records.push(Record {
                    t,
                    midspan: guideway.section_at(s.midspan_x),
                    wheel1_y: veh.u()[w1.dof_y],
                    wheel1_z: veh.u()[w1.dof_z],
                    wheel1_gap_z: gaps_used[0].0,
                    wheel1_force_z: forces[0].0,
                    iterations,
                    status,
                });
                if n % 200 == 0 {
                    progress(n as f64 / steps as f64);
                }
            }
        }
    }
    Ok(Outcome {
        records,
        unconverged_steps: unconverged,
    })
}
