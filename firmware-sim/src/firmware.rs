//! The firmware's control loop: sample every gap sensor over SPI, supervise, run the core's
//! levitation law (`maglev_core::Law`: one update per tick, whichever law is configured), drive
//! each coil's H-bridge PWM.
//!
//! Generic over the embedded-hal 1.0 traits (`SpiDevice` for the ADC, `SetDutyCycle` per
//! coil) and over the core's [`Scalar`] (I4F28 for bit-identical fixed point, `f32` for the
//! Cortex-M4F FPU). It owns its bus and its PWM channels. The law is the core's, untouched;
//! this layer adds sampling, quantisation, scaling and supervision.
//!
//! # Timing
//! One [`Firmware::tick`] is one control period `1/rate` (default 10 kHz, 100 µs): per
//! channel one 3-byte SPI transaction, one law update with `n_sub = 1` and `dt = 1/rate`,
//! one duty write. With `delay`, the law at tick k uses the sample of tick k−1 (a one-sample
//! computation delay: sample, compute, apply at the next period).
//!
//! # Gap loop
//! With `LawKind::GapLoop` every channel (levitation and each guidance magnet, as
//! `maglev_core::gap_control::GapLoop::update_pair` treats a pair) runs the core's outer gap
//! loop once per tick, compiled for `Δt = 1/rate`: the reference from the channel's previous
//! sample (held over the tick, one tick of delay), the filter advanced by backward Euler over
//! one tick, then the inner update with the new sample. The outer loop thus runs at the
//! control rate, not once per host step: the sampling delay the continuous design neglects is
//! one tick (100 µs), not one host step (docs/gap-loop.md, "Firmware").
//!
//! The budget on a real part
//! is the period: 12 channels × (SPI + update) must finish in 100 µs; the instruction counts
//! per tick are measured on the QEMU image (see docs/hil.md).
//!
//! # Guidance
//! With `Config::guidance` the guidance pairs run the core's guidance law instead of each
//! magnet's own law ([`crate::guide`]): the tick's levitation channels as before, then one
//! guidance update per pair on its two samples of the same tick.
//!
//! # Snapshot and restore
//! The whole mutable state is one `Copy` value, [`FwState`]: the server restores the
//! committed one before every host step, so a step can be re-run (Newton iterations).
//!
//! # Coil model during a fault
//! The law's own coil equation (Eq. 9, the α-method with KP = KI = 0) carries the current
//! while the fault ramp drives the voltage; so the reported current stays physical.

use crate::accel::Accelerometer;
use crate::adc::read_channel;
use crate::guide::{Pairs, MAX_PAIRS};
use crate::hbridge::duty_for;
use crate::protocol::{ChannelOut, Config, ConfigFault, ConfigKey, Problem, MAX_CHANNELS};
use crate::supervision::{check, Event, Limits, Mode, SensorState};
use crate::validate::{check_config, law_fault};
use embedded_hal::pwm::SetDutyCycle;
use embedded_hal::spi::SpiDevice;
use heapless::Vec;
use maglev_core::law::guidance::GuidanceState;
use maglev_core::{
    Interpolation, Law, LawParams, LawState, Levitation, Measurement, Output, Params, Scalar,
    Status,
};

/// One channel's state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ChannelState<S> {
    /// The law's state ([`maglev_core::law`]).
    pub law: LawState<S>,
    pub sensor: SensorState,
    /// The previous tick's sample (for the one-sample delay).
    pub delayed: u16,
    /// The accelerometer sample the law reads this tick, and the previous tick's (the same
    /// delay); codes of [`crate::accel`].
    pub accel: i16,
    pub delayed_accel: i16,
    /// Voltage (per unit) when the fault ramp started.
    pub ramp_from: S,
    pub duty: u16,
}

/// The firmware's whole mutable state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FwState<S> {
    pub ch: [ChannelState<S>; MAX_CHANNELS],
    /// The guidance pairs' law states (with `Config::guidance`; their coils are copied into
    /// the channels' `law.inner` after every update, so outputs and the fault ramp read them
    /// there).
    pub pairs: [GuidanceState<S>; MAX_PAIRS],
    pub mode: Mode,
    pub ramp_left: u16,
    pub tick: u64,
}

/// The control loop over a bus `SPI` (the gap ADC), PWM channels `PWM` and, under the state
/// law, one accelerometer `ACC` per channel ([`crate::accel`]).
pub struct Firmware<S, SPI, PWM, ACC> {
    spi: SPI,
    pwm: Vec<PWM, MAX_CHANNELS>,
    /// One per channel under the state law (started by [`Firmware::new`]), none otherwise.
    accels: Vec<Accelerometer<ACC>, MAX_CHANNELS>,
    /// Channels whose law reads its accelerometer (bit k: channel k): the board's wiring,
    /// [`Firmware::wire_accelerometers`].
    accel_mask: u16,
    /// `a/g_n` of code −32768, and of the 16-bit span ([`crate::accel`]: `code·lsb − 1`).
    accel_offset: S,
    accel_span: S,
    /// Every channel runs the paper's law (called without the law type's dispatch).
    paper: bool,
    laws: Vec<Law<S>, MAX_CHANNELS>,
    /// The guidance pairs' law, with `Config::guidance`.
    pairs: Option<Pairs<S>>,
    coils: Vec<Levitation<S>, MAX_CHANNELS>,
    /// `h/h0` of code 0, and of the full 2^bits span.
    gap_offset: S,
    gap_span: S,
    adc_bits: u8,
    full_scale: u16,
    /// `V_b / V_dc`: per-unit voltage to a fraction of the DC link.
    v_to_frac: f32,
    delay: bool,
    limits: Limits,
    ramp_step: S,
    st: FwState<S>,
}

impl<S: Scalar, SPI: SpiDevice<u8>, PWM: SetDutyCycle, ACC: SpiDevice<u8>>
    Firmware<S, SPI, PWM, ACC>
{
    /// Builds the loop from a configuration; the state starts in equilibrium at each
    /// channel's initial gap. `pwm` must hold one channel per configured magnet, and under
    /// the state law `accels` one accelerometer per channel (each is started, its id
    /// checked; otherwise they are not used).
    /// Every value is checked first ([`crate::validate`]); a refusal names it.
    pub fn new(
        cfg: &Config,
        spi: SPI,
        pwm: Vec<PWM, MAX_CHANNELS>,
        accels: Vec<ACC, MAX_CHANNELS>,
    ) -> Result<Self, ConfigFault> {
        check_config(cfg)?;
        let n = cfg.channels.len();
        // The law says whether it reads the accelerometers.
        let state = cfg.law.sensors().accel;
        let mut drivers = Vec::new();
        if state {
            for (k, dev) in accels.into_iter().enumerate().take(n) {
                let fault = |_| ConfigFault {
                    key: ConfigKey::Accelerometer,
                    channel: Some(k as u8),
                    problem: Problem::OutOfRange,
                };
                let _ = drivers.push(Accelerometer::new(dev).map_err(fault)?);
            }
            if drivers.len() != n {
                return Err(ConfigFault {
                    key: ConfigKey::Accelerometer,
                    channel: None,
                    problem: Problem::OutOfRange,
                });
            }
        }
        if pwm.len() != n {
            return Err(ConfigFault {
                key: ConfigKey::Channels,
                channel: None,
                problem: Problem::OutOfRange,
            });
        }
        let full_scale = ((1u32 << cfg.adc_bits) - 1) as u16;
        let mut ov = false;
        let span_m = (1u32 << cfg.adc_bits) as f64 * cfg.adc_lsb_m;
        let gap_offset = S::from_f64(cfg.adc_offset_m / cfg.h0, &mut ov);
        let gap_span = S::from_f64(span_m / cfg.h0, &mut ov);
        let ramp_step = S::from_f64(1.0 / cfg.ramp_ticks as f64, &mut ov);
        let lsb = crate::accel::LSB_G_16G;
        let mut accel_ov = false;
        let accel_offset = S::from_f64(-32768.0 * lsb - 1.0, &mut accel_ov);
        let accel_span = S::from_f64(65536.0 * lsb, &mut accel_ov);
        // Built first and filled in place: one copy of the firmware on the stack (the
        // Cortex-M0 image's 64 KiB hold it and the harness).
        let mut fw = Firmware {
            spi,
            pwm,
            accels: drivers,
            accel_mask: 0,
            accel_offset,
            accel_span,
            paper: cfg.law.batches(),
            laws: Vec::new(),
            pairs: None,
            coils: Vec::new(),
            gap_offset,
            gap_span,
            adc_bits: cfg.adc_bits,
            full_scale,
            v_to_frac: (cfg.r0 * cfg.i0 / cfg.v_dc) as f32,
            delay: cfg.delay,
            limits: Limits {
                hold_ticks: cfg.hold_ticks,
                stuck_ticks: cfg.stuck_ticks,
                ramp_ticks: cfg.ramp_ticks,
            },
            ramp_step,
            st: FwState::default(),
        };
        for (k, ch) in cfg.channels.iter().enumerate() {
            let p = Params {
                i0: cfg.i0,
                h0: cfg.h0,
                r0: cfg.r0,
                kp: cfg.kp,
                ki: cfg.ki,
                p0: ch.p0,
                alpha: cfg.alpha,
                dt: 1.0 / cfg.rate_hz as f64,
                n_sub: 1,
                interpolation: Interpolation::Linear,
                v_max: cfg.v_max,
                // One control tick per update: the paper's Eq. 14 is the firmware's law.
                scheme: maglev_core::Scheme::Paper,
            };
            let channel = Some(k as u8);
            let kind = cfg.law.with_geometry(cfg.geometry);
            let law = LawParams { magnet: p, kind }
                .compile::<S>()
                .map_err(|e| law_fault(e, channel))?;
            let coil = Params {
                kp: 0.0,
                ki: 0.0,
                v_max: f64::INFINITY,
                ..p
            }
            .compile::<S>()
            .map_err(|e| law_fault(e, channel))?;
            let code = libm::round((ch.gap - cfg.adc_offset_m) / cfg.adc_lsb_m)
                .clamp(1.0, full_scale as f64 - 1.0) as u16;
            fw.st.ch[k] = ChannelState {
                law: law
                    .try_equilibrium_state(ch.gap)
                    .map_err(|e| law_fault(e, channel))?,
                sensor: SensorState {
                    last_good: code,
                    last_raw: code,
                    repeats: 0,
                    bad_run: 0,
                },
                delayed: code,
                // At rest the part reads +1 g ([`crate::accel`]).
                accel: crate::accel::AccelModel.code(0.0),
                delayed_accel: crate::accel::AccelModel.code(0.0),
                ramp_from: S::ONE,
                duty: 0,
            };
            let _ = fw.laws.push(law);
            let _ = fw.coils.push(coil);
        }
        if accel_ov && state {
            return Err(ConfigFault {
                key: ConfigKey::Accelerometer,
                channel: None,
                problem: Problem::Unrepresentable,
            });
        }
        if ov {
            return Err(ConfigFault {
                key: ConfigKey::AdcOffset,
                channel: None,
                problem: Problem::Unrepresentable,
            });
        }
        // The pairs after the rest, compiled into their place (no second copy on the stack:
        // the Cortex-M0 image's 64 KiB hold the whole firmware).
        fw.pairs = Pairs::compile(
            cfg,
            |k| Params {
                p0: cfg.channels[k].p0,
                kp: cfg.kp,
                ki: cfg.ki,
                v_max: cfg.v_max,
                ..*fw.coils[k].params()
            },
            &mut fw.st.pairs,
        )?;
        if let Some(pairs) = &fw.pairs {
            for (w, s) in fw.st.pairs.iter().enumerate().take(pairs.len()) {
                fw.st.ch[3 * w + 1].law.inner = s.left;
                fw.st.ch[3 * w + 2].law.inner = s.right;
            }
        }
        for k in 0..n {
            let v = fw.st.ch[k].law.inner.v;
            let _ = fw.apply(k, v);
        }
        Ok(fw)
    }

    /// Number of magnet channels.
    pub fn channels(&self) -> usize {
        self.laws.len()
    }

    /// The bus, for the board (in simulation the analogue world drives the ADC's inputs).
    pub fn bus_mut(&mut self) -> &mut SPI {
        &mut self.spi
    }

    /// Channel `k`'s accelerometer device, if the law uses one (for the board, as
    /// [`Firmware::bus_mut`]).
    pub fn accel_mut(&mut self, k: usize) -> Option<&mut ACC> {
        self.accels.get_mut(k).map(Accelerometer::device_mut)
    }

    /// Which channels' laws read their accelerometer (bit k: channel k; the board's wiring:
    /// a levitation magnet carries one, a guidance magnet's law runs on its gap alone).
    /// Ignored without the state law.
    pub fn wire_accelerometers(&mut self, mask: u16) {
        self.accel_mask = mask;
    }

    /// The whole mutable state (a snapshot).
    pub fn state(&self) -> FwState<S> {
        self.st
    }

    /// Restores a snapshot and re-applies its duties.
    pub fn restore(&mut self, st: &FwState<S>) {
        self.st = *st;
        for k in 0..self.channels() {
            let d = self.st.ch[k].duty;
            let _ = self.pwm[k].set_duty_cycle(d);
        }
    }

    /// Per-unit gap `h/h0` of a code (no `f64`: software floating point on the targets).
    fn gap_pu(&self, code: u16) -> S {
        let mut ov = false;
        let frac = S::from_code(code, self.adc_bits);
        self.gap_offset
            .sadd(frac.smul(self.gap_span, &mut ov), &mut ov)
    }

    /// A channel's law output to its H-bridge, its events raised.
    fn drive(&mut self, k: usize, out: &maglev_core::Output<S>, events: &mut Event) {
        events.raise(map_status(out.status));
        if self.apply(k, out.voltage) {
            events.raise(Event::PWM_CLIPPED);
        }
    }

    /// Reads every wired accelerometer into its channel's `accel` (the previous tick's sample
    /// with the one-sample delay).
    fn sample_accels(&mut self, n: usize) {
        for (k, a) in self.accels.iter_mut().enumerate().take(n) {
            if self.accel_mask & (1 << k) == 0 {
                continue;
            }
            let z = a.read_z().unwrap_or(0);
            let ch = &mut self.st.ch[k];
            ch.accel = if self.delay {
                core::mem::replace(&mut ch.delayed_accel, z)
            } else {
                z
            };
        }
    }

    /// `a/g_n` of an accelerometer code: `code·lsb − 1` ([`crate::accel`]), as offset binary
    /// through [`Scalar::from_code`] (no `f64`).
    fn accel_pu(&self, z: i16) -> S {
        let mut ov = false;
        let frac = S::from_code((z as u16) ^ 0x8000, 16);
        self.accel_offset
            .sadd(frac.smul(self.accel_span, &mut ov), &mut ov)
    }

    /// Quantises a per-unit voltage to a duty and writes it; returns whether it clipped.
    fn apply(&mut self, k: usize, v: S) -> bool {
        let max = self.pwm[k].max_duty_cycle();
        let (duty, clipped) = duty_for(v.to_f32() * self.v_to_frac, max);
        let _ = self.pwm[k].set_duty_cycle(duty);
        self.st.ch[k].duty = duty;
        clipped
    }

    /// Starts the fault reaction: every coil's voltage ramps from its value to 0.
    fn enter_fault(&mut self) {
        let n = self.channels();
        self.st.mode = Mode::Ramp;
        self.st.ramp_left = self.limits.ramp_ticks;
        for ch in self.st.ch.iter_mut().take(n) {
            ch.ramp_from = ch.law.inner.v;
        }
    }

    /// The link-loss watchdog fired: the fault reaction as for a sensor fault (latched until
    /// the next `Config`). Returns `LINK_LOST`, with `FAULT` if this started the reaction.
    pub fn trip(&mut self) -> Event {
        let mut events = Event::LINK_LOST;
        if self.st.mode == Mode::Normal {
            self.enter_fault();
            events.raise(Event::FAULT);
        }
        events
    }

    /// One control period; returns the events raised.
    pub fn tick(&mut self) -> Event {
        let n = self.channels();
        let mut events = Event::default();
        let mut fault = false;
        let mut codes = [0u16; MAX_CHANNELS];
        if self.accel_mask != 0 {
            self.sample_accels(n);
        }
        for (k, code) in codes.iter_mut().enumerate().take(n) {
            let raw = read_channel(&mut self.spi, k as u8).ok();
            let ch = &mut self.st.ch[k];
            let v = check(&mut ch.sensor, raw, self.full_scale, &self.limits);
            events.raise(v.events);
            fault |= v.fault;
            *code = if self.delay {
                core::mem::replace(&mut ch.delayed, v.code)
            } else {
                v.code
            };
        }
        if fault && self.st.mode == Mode::Normal {
            self.enter_fault();
            events.raise(Event::FAULT);
        }
        let mut ov = false;
        let ramp_factor = match self.st.mode {
            Mode::Normal => S::ONE,
            Mode::Ramp => {
                S::from_f64(self.st.ramp_left as f64, &mut ov).smul(self.ramp_step, &mut ov)
            }
            Mode::Off => S::ZERO,
        };
        // Every channel runs one law, so the choice is made once per tick, not per channel.
        if self.st.mode != Mode::Normal {
            for (k, &code) in codes.iter().enumerate().take(n) {
                let h = self.gap_pu(code);
                // Coil alone at the ramped voltage: with KP = KI = 0 the law's voltage is 1 + y.
                let ch = &mut self.st.ch[k];
                let target = ch.ramp_from.smul(ramp_factor, &mut ov);
                ch.law.inner.y = target.ssub(S::ONE, &mut ov);
                let out = self.coils[k].update(&mut ch.law.inner, h);
                self.drive(k, &out, &mut events);
            }
        } else if self.paper {
            for (k, &code) in codes.iter().enumerate().take(n) {
                let h = self.gap_pu(code);
                // `Law::update`'s paper arm is this call.
                let inner = &mut self.st.ch[k].law.inner;
                let out = self.laws[k].levitation().update(inner, h);
                self.drive(k, &out, &mut events);
            }
        } else {
            // With guidance pairs, the channels of a pair are the pair law's (below).
            let guided = self.pairs.is_some();
            for (k, &code) in codes.iter().enumerate().take(n) {
                if guided && !k.is_multiple_of(3) {
                    continue;
                }
                let h = self.gap_pu(code);
                let wired = self.accel_mask & (1 << k) != 0;
                let accel = wired.then(|| self.accel_pu(self.st.ch[k].accel));
                let m = Measurement {
                    gap: h,
                    accel,
                    current: None,
                };
                let out = law_update(&self.laws[k], &mut self.st.ch[k].law, m);
                self.drive(k, &out, &mut events);
            }
            if guided {
                self.guide(&codes, &mut events);
            }
        }
        if self.st.mode == Mode::Ramp {
            self.st.ramp_left -= 1;
            if self.st.ramp_left == 0 {
                self.st.mode = Mode::Off;
            }
        }
        if ov {
            events.raise(Event::OVERFLOW);
        }
        self.st.tick += 1;
        events
    }

    /// One period of every guidance pair on its channels' codes ([`crate::guide`]); out of
    /// line, as [`law_update`].
    #[inline(never)]
    fn guide(&mut self, codes: &[u16; MAX_CHANNELS], events: &mut Event) {
        let Some(pairs) = &self.pairs else {
            return;
        };
        let mut volts = [(S::ZERO, S::ZERO); MAX_PAIRS];
        for (w, v) in volts.iter_mut().enumerate().take(pairs.len()) {
            let (l, r) = (3 * w + 1, 3 * w + 2);
            let gaps = (self.gap_pu(codes[l]), self.gap_pu(codes[r]));
            let wired = self.accel_mask & (1 << l) != 0;
            let accel = wired.then(|| pairs.accel_pu(self.st.ch[l].accel));
            let out = pairs.update(w, &mut self.st.pairs[w], gaps, accel);
            self.st.ch[l].law.inner = self.st.pairs[w].left;
            self.st.ch[r].law.inner = self.st.pairs[w].right;
            events.raise(map_status(out.status));
            *v = (out.left.voltage, out.right.voltage);
        }
        for (w, &(v_l, v_r)) in volts.iter().enumerate().take(pairs.len()) {
            let clip_l = self.apply(3 * w + 1, v_l);
            let clip_r = self.apply(3 * w + 2, v_r);
            if clip_l || clip_r {
                events.raise(Event::PWM_CLIPPED);
            }
        }
    }

    /// Channel `k`'s `g/g0`, coil current `i/i0` (both Q4.28) and duty.
    pub fn output(&self, k: usize) -> ChannelOut {
        let ch = &self.st.ch[k];
        let out = self.laws[k].levitation().output(&ch.law.inner);
        ChannelOut {
            g_q28: q28(out.g),
            current_q28: q28(out.current),
            duty: ch.duty,
        }
    }
}

/// One channel's update under a law other than the paper's: the state law called directly
/// (`Law::update`'s state arm, without its dispatch: the instruction count of
/// `board::state_law` is this call's), any other law through the law type. Out of line, so
/// that [`Firmware::tick`]'s paper path compiles as it did without it.
#[inline(never)]
fn law_update<S: Scalar>(law: &Law<S>, st: &mut LawState<S>, m: Measurement<S>) -> Output<S> {
    match law.state_law() {
        Some(l) => l.update(&mut st.inner, &mut st.state, m.gap, m.accel),
        None => law.update(st, m),
    }
}

/// A per-unit value in Q4.28 (exact for I4F28), saturating.
fn q28<S: Scalar>(x: S) -> i32 {
    let q = libm::round(x.to_f64() * (1u64 << 28) as f64);
    q.clamp(i32::MIN as f64, i32::MAX as f64) as i32
}

/// The law's events as firmware events (none in a quiet tick: one test, not five).
fn map_status(s: Status) -> Event {
    let mut e = Event::default();
    if s.is_empty() {
        return e;
    }
    for (from, to) in [
        (Status::COLLISION, Event::CONTACT),
        (Status::VOLTAGE_SATURATED, Event::VOLTAGE_SATURATED),
        (Status::CURRENT_CLAMPED, Event::CURRENT_CLAMPED),
        (Status::OVERFLOW, Event::OVERFLOW),
        (Status::REFERENCE_LIMITED, Event::REFERENCE_LIMITED),
    ] {
        if s.contains(from) {
            e.raise(to);
        }
    }
    e
}
