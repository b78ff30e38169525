//! The firmware as the magnets of the shared coupling loop ([`maglev_sim::simulation::couple`],
//! docs/model.md §7): [`FirmwareMagnets`] wraps the [`Link`], the ADC board and the tick
//! interpolation, and keeps the HIL-only record (firmware events).
//!
//! Per iteration of a host step t → t+Δt: for each of the `Δt·rate` control ticks the gap
//! interpolated linearly between the committed gap at t and the iterate's gap at t+Δt (the
//! firmware's version of the paper's internal loop), converted to ADC codes; one `Step`
//! request; forces from the reported flux. On convergence one `Commit`. Channels per wheel:
//! levitation (Z gap), guidance left (`h0 + d`), guidance right (`h0 − d`), as in
//! `maglev_core::guidance`.
//!
//! Under the state law each levitation magnet carries an accelerometer
//! (`maglev_firmware_sim::accel`): its acceleration, interpolated across the step as the gaps
//! are, goes to the firmware as the part's codes in a `StepAccel` request (the guidance
//! magnets' laws run on their gaps alone, as in `maglev run`). With `[controller.guidance]`
//! the firmware runs each wheel's guidance pair under the guidance law
//! (`maglev_firmware_sim::guide`), and the pair's left magnet carries a lateral accelerometer
//! too: the wheel's lateral acceleration ([`Magnets::lateral_accels`]), interpolated the same
//! way, as the codes of a part with its axis along +Y (`AccelModel::code_lateral`). The coil
//! current is the firmware's own: its law integrates the coil (Eq. 9), as the core's does in
//! `maglev run`.

use super::board::{force, SensorFault, Sensors};
use super::link::Link;
use super::HilSettings;
use maglev_core::gap::Geometry;
use maglev_core::Status;
use maglev_firmware_sim::accel::AccelModel;
use maglev_firmware_sim::protocol::{ChannelInit, Config, Nack, Reply, Request, Response};
use maglev_firmware_sim::supervision::Event;
use maglev_sim::physics::train::Train;
use maglev_sim::physics::vehicle::magnet_gaps;
use maglev_sim::simulation::{Magnets, Settings, Start, WheelGaps};
use maglev_sim::{Error, Result};

/// A logged firmware event.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EventRecord {
    pub t: f64,
    pub events: Event,
    pub mode: u8,
}

fn expect_reply(r: Response, step: u32) -> Result<Reply> {
    match r {
        Response::Reply(rep) if rep.step == step => Ok(rep),
        other => Err(Error::Firmware(format!(
            "answered step {step} with {other:?}"
        ))),
    }
}

/// The firmware behind a link, with the board's sensors and the per-wheel static loads.
/// [`FirmwareMagnets::new`] holds the link and the settings; [`Magnets::start`] configures
/// the firmware for the run's train.
pub struct FirmwareMagnets<'a> {
    link: &'a mut dyn Link,
    hs: &'a HilSettings,
    sensors: Sensors,
    ticks: usize,
    h0: f64,
    p0: Vec<f64>,
    geometry: Geometry,
    codes: maglev_firmware_sim::heapless::Vec<u16, { maglev_firmware_sim::protocol::MAX_SAMPLES }>,
    /// Under the state law: the levitation magnets' accelerations (m/s², Z up) at the
    /// committed step and at the last iterate, and the step's accelerometer codes.
    accel: Option<Accels>,
    /// The reply of the last `Step` (its events are logged on commit).
    last: Option<Reply>,
    /// Every committed step that raised an event.
    pub events: Vec<EventRecord>,
}

/// The accelerometers of the levitation magnets, and of the guidance pairs under the
/// guidance law (module docs).
struct Accels {
    committed: Vec<f64>,
    used: Vec<f64>,
    /// The wheels' lateral accelerations (m/s², +Y), under the guidance law; empty without.
    committed_y: Vec<f64>,
    used_y: Vec<f64>,
    codes: maglev_firmware_sim::heapless::Vec<i16, { maglev_firmware_sim::protocol::MAX_SAMPLES }>,
}

/// Bit k set for every levitation channel k (the first of each wheel's three).
fn levitation_channels(wheels: usize) -> u16 {
    (0..wheels).fold(0, |m, i| m | 1 << (3 * i))
}

/// The wired accelerometers: the levitation channels, and with `guided` the guidance pairs'
/// left channels (the second of each wheel's three).
fn wired_channels(wheels: usize, guided: bool) -> u16 {
    let lev = levitation_channels(wheels);
    if guided {
        lev | lev << 1
    } else {
        lev
    }
}

/// Every `--set fault` names one of the train's `count` channels (three a wheel:
/// levitation, guidance left, guidance right); one beyond would be ignored in silence.
fn check_fault_channels(faults: &[SensorFault], count: usize) -> Result<()> {
    match faults.iter().find(|f| f.channel >= count) {
        Some(f) => Err(Error::invalid(
            "--set fault",
            format!(
                "channel {} does not exist: this train has {count} channels (0..={}, three a wheel)",
                f.channel,
                count.saturating_sub(1)
            ),
        )),
        None => Ok(()),
    }
}

impl<'a> FirmwareMagnets<'a> {
    /// The firmware behind `link`, with the converters and the supervision of `hs`; it is
    /// configured when the run [starts](Magnets::start) it.
    pub fn new(hs: &'a HilSettings, link: &'a mut dyn Link) -> Self {
        FirmwareMagnets {
            link,
            hs,
            sensors: Sensors::new(hs.adc, hs.rate_hz as f64, hs.sensor_faults.clone()),
            ticks: 0,
            h0: 0.0,
            p0: Vec::new(),
            geometry: Geometry::default(),
            codes: maglev_firmware_sim::heapless::Vec::new(),
            accel: None,
            last: None,
            events: Vec::new(),
        }
    }

    /// Configures the firmware (equilibrium at the initial gaps `gaps0`). A step that is not
    /// a whole number of control ticks is `Invalid` on `dt × rate`; the rest is
    /// [`Error::Firmware`].
    fn configure(&mut self, v: &Train, gaps0: &[WheelGaps], s: &Settings) -> Result<()> {
        let hs = self.hs;
        let ticks_f = s.dt * hs.rate_hz as f64;
        let ticks = ticks_f.round() as usize;
        if ticks == 0 || (ticks_f - ticks as f64).abs() > 1e-9 * ticks_f {
            return Err(Error::invalid(
                "dt × rate",
                format!("{ticks_f} control ticks per step, must be a whole number ≥ 1"),
            ));
        }
        let p = s.controller;
        let h0 = p.h0;
        let mut channels = maglev_firmware_sim::heapless::Vec::new();
        for (&p0, &(hz, d)) in v.p0.iter().zip(gaps0) {
            for gap in magnet_gaps((hz, d), h0) {
                channels.push(ChannelInit { p0, gap }).map_err(|_| {
                    Error::Firmware("too many magnet channels for the protocol".into())
                })?;
            }
        }
        check_fault_channels(&hs.sensor_faults, channels.len())?;
        let state_law = s.law.sensors().accel;
        let parts = if s.guidance.is_some() { 2 } else { 1 };
        super::step_frame::check(
            ticks,
            channels.len(),
            state_law.then_some(parts * v.p0.len()),
        )?;
        let cfg = Config {
            scalar: hs.scalar,
            rate_hz: hs.rate_hz,
            ticks_per_step: ticks as u16,
            delay: hs.delay,
            i0: p.i0,
            h0,
            r0: p.r0,
            kp: p.kp,
            ki: p.ki,
            alpha: p.alpha,
            v_max: p.v_max,
            // The gap loop runs in the firmware at the tick rate (docs/gap-loop.md).
            law: s.law,
            channels,
            adc_bits: hs.adc.bits,
            adc_lsb_m: hs.adc.lsb_m,
            adc_offset_m: hs.adc.offset_m,
            pwm_bits: hs.pwm_bits,
            v_dc: hs.v_dc,
            hold_ticks: hs.hold_ticks,
            stuck_ticks: hs.stuck_ticks,
            ramp_ticks: hs.ramp_ticks,
            watchdog_ticks: hs.watchdog_ticks,
            geometry: s.geometry,
            guidance: s.guidance,
        };
        match self.link.call(Request::Config(cfg))? {
            Response::Ready { .. } => {}
            Response::Nack(Nack::BadConfig(f)) => {
                return Err(Error::Firmware(format!("refused the configuration: {f}")))
            }
            other => {
                return Err(Error::Firmware(format!(
                    "refused the configuration: {other:?}"
                )))
            }
        }
        self.ticks = ticks;
        self.h0 = h0;
        self.p0 = v.p0.clone();
        self.geometry = s.geometry;
        let lateral = if s.guidance.is_some() { v.p0.len() } else { 0 };
        self.accel = s.law.sensors().accel.then(|| Accels {
            committed: vec![0.0; v.p0.len()],
            used: vec![0.0; v.p0.len()],
            committed_y: vec![0.0; lateral],
            used_y: vec![0.0; lateral],
            codes: maglev_firmware_sim::heapless::Vec::new(),
        });
        Ok(())
    }

    /// The three channel gaps (m) of a wheel: levitation, guidance left, guidance right.
    fn channel_gaps(&self, w: WheelGaps) -> [f64; 3] {
        magnet_gaps(w, self.h0)
    }
}

impl Magnets for FirmwareMagnets<'_> {
    /// Refuses a train of moving forces (no magnets to drive), then configures the firmware.
    fn start(&mut self, start: &Start<'_>) -> Result<()> {
        if start.train.cars.is_empty() {
            return Err(Error::invalid(
                "vehicle.kind",
                "hil needs a vehicle with magnets (\"fig1\"), not a train of forces",
            ));
        }
        self.configure(start.train, start.gaps, start.settings)
    }

    /// One `Step` request with every tick's ADC codes; forces `p0·(g/g0)²` from the reply.
    fn forces(
        &mut self,
        step: u32,
        _t: f64,
        gaps_prev: &[WheelGaps],
        gaps_next: &[WheelGaps],
        accels: &[f64],
        out: &mut [(f64, f64)],
    ) -> Result<()> {
        self.step_forces(step, gaps_prev, gaps_next, accels, out)
    }

    /// The wheels' lateral accelerations for the next step, read by the guidance pairs'
    /// accelerometers (module docs); ignored without the guidance law.
    fn lateral_accels(&mut self, accels_y: &[f64]) {
        if let Some(a) = &mut self.accel {
            let n = a.used_y.len();
            a.used_y.copy_from_slice(&accels_y[..n]);
        }
    }

    /// `Commit`; logs the step's events.
    fn commit(&mut self, step: u32, t: f64) -> Result<()> {
        self.step_commit(step, t)
    }

    /// The firmware reports through events, not the core's flags.
    fn status(&self) -> Status {
        Status::default()
    }
}

impl FirmwareMagnets<'_> {
    fn step_forces(
        &mut self,
        step: u32,
        gaps_prev: &[WheelGaps],
        gaps_next: &[WheelGaps],
        accels: &[f64],
        out: &mut [(f64, f64)],
    ) -> Result<()> {
        let chans = |g: &[WheelGaps]| -> Vec<f64> {
            g.iter().flat_map(|&w| self.channel_gaps(w)).collect()
        };
        let (h_prev, h_next) = (chans(gaps_prev), chans(gaps_next));
        let ticks = self.ticks;
        self.codes.clear();
        for j in 1..=ticks {
            let frac = j as f64 / ticks as f64;
            let tick = ((step as usize - 1) * ticks + j) as u64;
            for (ch, (&a, &b)) in h_prev.iter().zip(&h_next).enumerate() {
                let h = a + frac * (b - a);
                self.codes
                    .push(self.sensors.code(h, tick, ch))
                    .map_err(|_| {
                        Error::Firmware("too many samples per step for the protocol".into())
                    })?;
            }
        }
        let req = match &mut self.accel {
            None => Request::Step {
                step,
                codes: self.codes.clone(),
            },
            Some(a) => {
                a.used.copy_from_slice(accels);
                a.codes.clear();
                let guided = !a.used_y.is_empty();
                let lerp = |p: f64, q: f64, frac: f64| p + frac * (q - p);
                for j in 1..=ticks {
                    let frac = j as f64 / ticks as f64;
                    for (w, (&p, &q)) in a.committed.iter().zip(&a.used).enumerate() {
                        let mut codes = [AccelModel.code(lerp(p, q, frac)), 0];
                        if guided {
                            let y = lerp(a.committed_y[w], a.used_y[w], frac);
                            codes[1] = AccelModel.code_lateral(y);
                        }
                        for &c in &codes[..1 + guided as usize] {
                            a.codes.push(c).map_err(|_| {
                                Error::Firmware("too many samples per step for the protocol".into())
                            })?;
                        }
                    }
                }
                Request::StepAccel {
                    step,
                    codes: self.codes.clone(),
                    wired: wired_channels(a.used.len(), guided),
                    accel: a.codes.clone(),
                }
            }
        };
        let reply = expect_reply(self.link.call(req)?, step)?;
        for (i, o) in out.iter_mut().enumerate() {
            let c = &reply.channels[3 * i..3 * i + 3];
            let p0 = self.p0[i];
            let gz = force(c[0].g_q28, p0);
            let gl = force(c[1].g_q28, p0);
            let gr = force(c[2].g_q28, p0);
            *o = (gz, self.geometry.guidance_force(gl, gr));
        }
        self.last = Some(reply);
        Ok(())
    }

    fn step_commit(&mut self, step: u32, t: f64) -> Result<()> {
        match self.link.call(Request::Commit { step })? {
            Response::Committed { step: c } if c == step => {}
            other => {
                return Err(Error::Firmware(format!(
                    "refused to commit step {step}: {other:?}"
                )))
            }
        }
        let reply = self
            .last
            .take()
            .ok_or_else(|| Error::Firmware(format!("commit of step {step} without a step")))?;
        if let Some(a) = &mut self.accel {
            a.committed.copy_from_slice(&a.used);
            a.committed_y.copy_from_slice(&a.used_y);
        }
        if reply.events != 0 {
            self.events.push(EventRecord {
                t,
                events: Event(reply.events),
                mode: reply.mode,
            });
        }
        Ok(())
    }
}
