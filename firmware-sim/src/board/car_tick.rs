//! The whole car on one controller: one control tick of the firmware with the 12 magnet
//! channels of the Fig. 1 car (4 wheels × levitation + guidance pair), measured in
//! instructions and compared with the clock budget of a 10 kHz loop (docs/hil.md, "A car on
//! one MCU").
//!
//! The tick is `Firmware::tick` as the server runs it: per channel one SPI transaction with
//! the simulated ADC chip, supervision, the law update (`n_sub = 1`, the core's fast path),
//! one PWM write. The gaps wobble by a few codes per tick so that no sensor looks stuck.
use crate::accel::{AccelChip, AccelModel};
use crate::adc::AdcChip;
use crate::board::selftest::Measure;
use crate::firmware::Firmware;
use crate::hbridge::HBridge;
use crate::protocol::{
    ChannelInit, Config, Geometry, GuidanceParams, LawKind, ScalarKind, MAX_CHANNELS,
};
use core::fmt::{self, Write};
use heapless::Vec;
use maglev_core::Scalar;

/// Channels of the Fig. 1 car.
pub const CHANNELS: usize = 12;
/// Ticks measured.
pub const TICKS: u32 = 20;

/// The car's configuration: `law` at 10 kHz, 16-bit ADC over 0–20 mm, 12-bit PWM on 200 V;
/// the paper's supply bound `v_max` (V, `INFINITY` for none). Under the state law the magnets
/// face their rails as EMS magnets do, and each levitation magnet carries an accelerometer;
/// with `guidance` the pairs run the guidance law (`Config::guidance`) and each pair's left
/// magnet carries a lateral accelerometer.
pub fn car_config(
    scalar: ScalarKind,
    v_max: f64,
    law: LawKind,
    guidance: Option<GuidanceParams>,
) -> Config {
    let mut channels = Vec::new();
    for _wheel in 0..4 {
        // Levitation (p0 of a Fig. 1 wheel) and the guidance pair at h0 ± 0.1 mm.
        for (p0, gap) in [(36_787.5, 0.01), (10_000.0, 0.0101), (10_000.0, 0.0099)] {
            let _ = channels.push(ChannelInit { p0, gap });
        }
    }
    Config {
        scalar,
        rate_hz: 10_000,
        ticks_per_step: 10,
        delay: false,
        i0: 43.0,
        h0: 0.01,
        r0: 1.0,
        kp: 0.01,
        ki: 6.0,
        alpha: 0.5,
        v_max,
        law,
        channels,
        adc_bits: 16,
        adc_lsb_m: 0.02 / 65536.0,
        adc_offset_m: 0.0,
        pwm_bits: 12,
        v_dc: 200.0,
        hold_ticks: 20,
        stuck_ticks: 100,
        ramp_ticks: 2000,
        watchdog_ticks: 0,
        // A law that reads the accelerometer holds EMS magnets (the state law).
        geometry: if law.sensors().accel {
            Geometry::Ems
        } else {
            Geometry::Paper
        },
        guidance,
    }
}

/// The levitation channels (the first of each wheel's three), which carry accelerometers.
pub const LEVITATION: u16 = 0b0010_0100_1001;
/// The guidance pairs' left channels (the second of each wheel's three), which carry the
/// pairs' lateral accelerometers under the guidance law.
pub const LATERAL: u16 = LEVITATION << 1;

/// Instructions of one 12-channel tick: (fewest, most) over [`TICKS`] ticks without events.
pub fn measure<S: Scalar, M: Measure>(
    m: &M,
    v_max: f64,
    law: LawKind,
    guidance: Option<GuidanceParams>,
) -> Option<(u32, u32)> {
    let kind = if S::FLOAT {
        ScalarKind::F32
    } else {
        ScalarKind::I4F28
    };
    let cfg = car_config(kind, v_max, law, guidance);
    let mut pwm: Vec<HBridge, MAX_CHANNELS> = Vec::new();
    for _ in 0..CHANNELS {
        let _ = pwm.push(HBridge::new(cfg.pwm_bits));
    }
    let mut accels = Vec::new();
    for _ in 0..CHANNELS {
        let _ = accels.push(AccelChip::default());
    }
    let mut fw = Firmware::<S, _, _, _>::new(&cfg, AdcChip::default(), pwm, accels).ok()?;
    let lateral = if guidance.is_some() { LATERAL } else { 0 };
    fw.wire_accelerometers(LEVITATION | lateral);
    let rest = |k: usize| match lateral & (1 << k) {
        0 => AccelModel.code(0.0),
        _ => AccelModel.code_lateral(0.0),
    };
    let (mut lo, mut hi) = (u32::MAX, 0);
    for t in 0..TICKS {
        for (k, ch) in cfg.channels.iter().enumerate() {
            let code = (ch.gap / cfg.adc_lsb_m) as u16 + ((t as usize + k) % 3) as u16;
            fw.bus_mut().set_input(k, code);
            if let Some(chip) = fw.accel_mut(k) {
                chip.set_sample(rest(k) + ((t as usize + k) % 3) as i16);
            }
        }
        let mut events = 0;
        let n = m.count(&mut || events = fw.tick().0);
        if events != 0 {
            return None; // not a nominal tick: the measurement would not be the budget's
        }
        let n = n?;
        (lo, hi) = (lo.min(n), hi.max(n));
    }
    Some((lo, hi))
}

/// Prints the 12-channel tick's count against a budget in instructions: the clock cycles of
/// one 100 µs period at `mhz`, divided by the assumed cycles per instruction (`cpi_x100`/100).
pub fn report<S: Scalar, W: Write, M: Measure>(
    w: &mut W,
    m: &M,
    v_max: f64,
    (law, guidance): (LawKind, Option<GuidanceParams>),
    tag: &str,
    mhz: u32,
    cpi_x100: u32,
) -> fmt::Result {
    let cycles = mhz * 100; // cycles per 100 µs
    let budget = cycles * 100 / cpi_x100;
    match measure::<S, M>(m, v_max, law, guidance) {
        Some((lo, hi)) => writeln!(
            w,
            "insns {}/car12 tick {tag}: {lo}..{hi} ({} per channel; budget {budget} = {mhz} MHz \
             x 100 us / {}.{:02} cycles per insn: {})",
            S::NAME,
            hi / CHANNELS as u32,
            cpi_x100 / 100,
            cpi_x100 % 100,
            if hi <= budget { "met" } else { "over" }
        ),
        None => writeln!(w, "insns {}/car12 tick {tag}: not measured", S::NAME),
    }
}
