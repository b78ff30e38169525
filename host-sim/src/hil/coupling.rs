//! The HIL coupling loop: `simulation::simulate`'s Newton–Raphson structure with the
//! firmware as the controller (model.md §7).
//!
//! Per host step t → t+Δt and per iteration: the gaps at t+Δt from the current estimate;
//! for each of the `Δt·rate` control ticks the gap interpolated linearly between the
//! committed gap at t and that estimate (the firmware's version of the paper's internal
//! loop), converted to ADC codes; one `Step` request; forces from the reported currents;
//! solve. On convergence one `Commit`. Channels per wheel: levitation (Z gap), guidance left
//! (`h0 + d`), guidance right (`h0 − d`), as in `maglev_core::guidance`.

use super::board::{force, Sensors};
use super::link::Link;
use super::HilSettings;
use crate::guideway::{Guideway, PointLoad};
use crate::newmark::Newmark;
use crate::simulation::{Profiles, Record, Settings};
use crate::vehicle::VehicleModel;
use maglev_firmware_sim::protocol::{ChannelInit, Config, Reply, Request, Response};
use maglev_firmware_sim::supervision::Event;
use nalgebra::DVector;

/// A logged firmware event.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EventRecord {
    pub t: f64,
    pub events: Event,
    pub mode: u8,
}

/// Result of a HIL run.
pub struct HilOutcome {
    pub records: Vec<Record>,
    pub unconverged_steps: usize,
    pub events: Vec<EventRecord>,
}

fn expect_reply(r: Response, step: u32) -> Result<Reply, String> {
    match r {
        Response::Reply(rep) if rep.step == step => Ok(rep),
        other => Err(format!("firmware answered step {step} with {other:?}")),
    }
}

/// Runs the passage with the firmware behind `link`.
pub fn simulate_hil<G: Guideway>(
    guideway: &mut G,
    v: &VehicleModel,
    profiles: &Profiles,
    s: &Settings,
    hs: &HilSettings,
    link: &mut dyn Link,
    mut progress: impl FnMut(f64),
) -> Result<HilOutcome, String> {
    let dt = s.dt;
    let ticks_f = dt * hs.rate_hz as f64;
    let ticks = ticks_f.round() as usize;
    if ticks == 0 || (ticks_f - ticks as f64).abs() > 1e-9 * ticks_f {
        return Err(format!(
            "dt × rate = {ticks_f} control ticks per step: must be a whole number ≥ 1"
        ));
    }
    let p = s.controller;
    let (h0, i0) = (p.h0, p.i0);
    let nw = v.wheels.len();
    let nch = 3 * nw;
    // Initial gaps and loads per channel.
    let mut channels = maglev_firmware_sim::heapless::Vec::new();
    let mut h_prev = Vec::with_capacity(nch);
    for (w, &p0) in v.wheels.iter().zip(&v.p0) {
        let (gy, gz) = ((profiles.y)(w.x0), (profiles.z)(w.x0));
        for gap in [h0 + gz, h0 + gy, h0 - gy] {
            channels
                .push(ChannelInit { p0, gap })
                .map_err(|_| "too many magnet channels for the protocol")?;
            h_prev.push(gap);
        }
    }
    let cfg = Config {
        scalar: hs.scalar,
        rate_hz: hs.rate_hz,
        ticks_per_step: ticks as u16,
        delay: hs.delay,
        i0,
        h0,
        r0: p.r0,
        kp: p.kp,
        ki: p.ki,
        alpha: p.alpha,
        v_max: p.v_max,
        channels,
        adc_bits: hs.adc.bits,
        adc_lsb_m: hs.adc.lsb_m,
        adc_offset_m: hs.adc.offset_m,
        pwm_bits: hs.pwm_bits,
        v_dc: hs.v_dc,
        hold_ticks: hs.hold_ticks,
        stuck_ticks: hs.stuck_ticks,
        ramp_ticks: hs.ramp_ticks,
    };
    match link.call(Request::Config(cfg))? {
        Response::Ready { .. } => {}
        other => return Err(format!("firmware refused the configuration: {other:?}")),
    }
    let mut sensors = Sensors::new(hs.adc, hs.rate_hz as f64, hs.sensor_faults.clone());
    let steps = (s.t_end / dt).round() as usize;
    let mut records = Vec::with_capacity(steps + 1);
    records.push(Record {
        midspan: guideway.section_at(s.midspan_x),
        wheel1_gap_z: h_prev[0],
        wheel1_force_z: v.p0[0],
        ..Record::default()
    });
    let mut events = Vec::new();
    let mut unconverged = 0;
    let mut veh = Newmark::new(v.m.clone(), v.c.clone(), v.k.clone(), dt)?;
    let mut f = DVector::zeros(v.m.nrows());
    let mut loads = vec![PointLoad::default(); nw];
    let mut forces = vec![(0.0, 0.0); nw];
    let mut h_next = vec![0.0; nch];
    let mut codes = maglev_firmware_sim::heapless::Vec::new();
    for n in 1..=steps {
        let t = n as f64 * dt;
        let step = n as u32;
        let xs: Vec<f64> = v.wheels.iter().map(|w| w.x0 + s.speed * t).collect();
        let rz: Vec<f64> = xs.iter().map(|&x| (profiles.z)(x)).collect();
        let ry: Vec<f64> = xs.iter().map(|&x| (profiles.y)(x)).collect();
        let gaps = |u: &DVector<f64>, gw: &G, out: &mut [f64]| {
            for (i, w) in v.wheels.iter().enumerate() {
                let m = gw.motion_at(xs[i], w.ey, w.ez);
                let hz = h0 - (u[w.dof_z] - m.z) + rz[i];
                let d = u[w.dof_y] - m.y + ry[i];
                out[3 * i..3 * i + 3].copy_from_slice(&[hz, h0 + d, h0 - d]);
            }
        };
        gaps(veh.u(), guideway, &mut h_next);
        let mut iterations = 0;
        let mut used = vec![0.0; nch];
        let reply = loop {
            iterations += 1;
            codes.clear();
            for j in 1..=ticks {
                let frac = j as f64 / ticks as f64;
                let tick = ((n - 1) * ticks + j) as u64;
                for ch in 0..nch {
                    let h = h_prev[ch] + frac * (h_next[ch] - h_prev[ch]);
                    codes
                        .push(sensors.code(h, tick, ch))
                        .map_err(|_| "too many samples per step for the protocol")?;
                }
            }
            let reply = expect_reply(
                link.call(Request::Step {
                    step,
                    codes: codes.clone(),
                })?,
                step,
            )?;
            f.fill(0.0);
            for (i, w) in v.wheels.iter().enumerate() {
                let c = &reply.channels[3 * i..3 * i + 3];
                let p0 = v.p0[i];
                let gz = force(c[0].g_q28, p0);
                let gl = force(c[1].g_q28, p0);
                let gr = force(c[2].g_q28, p0);
                let gy = gr - gl;
                forces[i] = (gz, gy);
                f[w.dof_z] = gz - p0;
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
            used.copy_from_slice(&h_next);
            gaps(veh.u1(), guideway, &mut h_next);
            let change = h_next
                .iter()
                .zip(&used)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            if change <= s.tolerance {
                break reply;
            }
            if iterations >= s.max_iterations {
                unconverged += 1;
                break reply;
            }
        };
        match link.call(Request::Commit { step })? {
            Response::Committed { step: c } if c == step => {}
            other => return Err(format!("firmware refused to commit step {step}: {other:?}")),
        }
        guideway.commit();
        veh.commit();
        h_prev.copy_from_slice(&used);
        if reply.events != 0 {
            events.push(EventRecord {
                t,
                events: Event(reply.events),
                mode: reply.mode,
            });
        }
        let w1 = &v.wheels[0];
        records.push(Record {
            t,
            midspan: guideway.section_at(s.midspan_x),
            wheel1_y: veh.u()[w1.dof_y],
            wheel1_z: veh.u()[w1.dof_z],
            wheel1_gap_z: used[0],
            wheel1_force_z: forces[0].0,
            iterations,
            status: Default::default(),
        });
        if n % 200 == 0 {
            progress(n as f64 / steps as f64);
        }
    }
    Ok(HilOutcome {
        records,
        unconverged_steps: unconverged,
        events,
    })
}
