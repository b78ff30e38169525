//! Hardware-in-the-loop: the firmware (`maglev-firmware-sim`) as the levitation controller
//! of a passage, in lockstep with the plant.
//!
//! * [`link`]: how the host talks to the firmware (in-process, a host process, QEMU, a
//!   serial device).
//! * [`realtime`]: pacing the exchanges to the wall clock (`--realtime`).
//! * [`board`]: the physical side of its peripherals (gap → ADC codes, current → force).
//! * [`coupling`]: the firmware as the magnets of the shared coupling loop
//!   ([`maglev_sim::simulation::couple`]): `Step` per Newton iteration, `Commit` per step.
//! * [`compare`]: the difference to the ideal in-process core run.
//!
//! A HIL passage ([`simulate`]) is [`maglev_sim::setup::simulate`] with
//! [`coupling::FirmwareMagnets`] as the magnets.
//!
//! See `docs/hil.md` for the timing model, the protocol and the fault reactions.

pub mod board;
pub mod compare;
pub mod coupling;
pub mod link;
pub mod realtime;
pub mod step_frame;

use board::SensorFault;
use coupling::{EventRecord, FirmwareMagnets};
use link::Link;
use maglev_firmware_sim::adc::AdcModel;
use maglev_firmware_sim::protocol::{ConfigKey, ScalarKind};
use maglev_firmware_sim::validate;
use maglev_sim::input::case::Case;
use maglev_sim::probes::Recorder;
use maglev_sim::simulation::{Monitor, Outcome};
use maglev_sim::{Error, Result};

/// A finished HIL passage.
pub struct HilPassage {
    /// The run's counters and ranges.
    pub outcome: Outcome,
    /// The firmware's events, one record per committed step that raised any.
    pub events: Vec<EventRecord>,
    /// Wall seconds of the time loop.
    pub wall: f64,
}

/// Runs `case` with the firmware behind `link` (settings `hs`) as the magnets: the library's
/// [`maglev_sim::setup::simulate`] with [`FirmwareMagnets`].
pub fn simulate(
    case: &Case,
    hs: &HilSettings,
    link: &mut dyn Link,
    rec: &mut dyn Recorder,
    monitor: &mut dyn Monitor,
) -> Result<HilPassage> {
    let mut firmware = FirmwareMagnets::new(hs, link);
    let run = maglev_sim::setup::simulate(case, &mut firmware, rec, monitor)?;
    Ok(HilPassage {
        outcome: run.outcome,
        events: firmware.events,
        wall: run.wall,
    })
}

/// Firmware, converter and supervision settings of a HIL run (SI).
#[derive(Clone, Debug, PartialEq)]
pub struct HilSettings {
    pub scalar: ScalarKind,
    pub rate_hz: u32,
    pub delay: bool,
    pub adc: AdcModel,
    pub pwm_bits: u8,
    pub v_dc: f64,
    pub hold_ticks: u16,
    pub stuck_ticks: u16,
    pub ramp_ticks: u16,
    /// Link-loss watchdog of the firmware (control periods; 0 = off). Only a board with a
    /// real-time control timer runs it; the lockstep modes never starve it.
    pub watchdog_ticks: u16,
    pub sensor_faults: Vec<SensorFault>,
}

impl Default for HilSettings {
    /// 10 kHz, I4F28, no delay; 16-bit ADC over 0–20 mm (0.305 µm per code) with 0.5 LSB
    /// noise; 12-bit PWM on a 200 V link; hold 2 ms, stuck after 10 ms, ramp 0.2 s.
    fn default() -> Self {
        HilSettings {
            scalar: ScalarKind::I4F28,
            rate_hz: 10_000,
            delay: false,
            adc: AdcModel {
                bits: 16,
                lsb_m: 0.02 / 65536.0,
                offset_m: 0.0,
                noise_lsb: 0.5,
                seed: 1,
            },
            pwm_bits: 12,
            v_dc: 200.0,
            hold_ticks: 20,
            stuck_ticks: 100,
            ramp_ticks: 2000,
            watchdog_ticks: 0,
            sensor_faults: Vec::new(),
        }
    }
}

/// `--set` keys that belong to the firmware, not the scenario.
pub const HIL_KEYS: [&str; 16] = [
    "rate",
    "delay",
    "scalar",
    "adc_bits",
    "adc_lsb",
    "adc_offset",
    "adc_noise",
    "adc_seed",
    "pwm_bits",
    "v_dc",
    "hold_ticks",
    "stuck_ticks",
    "ramp_ticks",
    "watchdog_ticks",
    "fault",
    "link_fault",
];

impl HilSettings {
    /// Applies one `key=value` of [`HIL_KEYS`] (except `link_fault`, handled by the CLI). A
    /// bad value is `Invalid` on `--set KEY`, with the accepted range.
    pub fn set(&mut self, key: &str, value: &str) -> Result<()> {
        let bad = |reason: String| Error::invalid(format!("--set {key}"), reason);
        fn num<T: std::str::FromStr>(k: &str, v: &str) -> Result<T> {
            // The limit the type sets: `rate=-5` is refused for its sign, not its digits.
            let kind = match std::any::type_name::<T>() {
                "u8" | "u16" | "u32" | "u64" | "usize" => " (a whole number ≥ 0)",
                "i8" | "i16" | "i32" | "i64" | "isize" => " (a whole number)",
                _ => "",
            };
            v.parse().map_err(|_| {
                Error::invalid(
                    format!("--set {k}"),
                    format!("cannot read `{v}` as a number{kind}"),
                )
            })
        }
        match key {
            "rate" => self.rate_hz = num(key, value)?,
            "delay" => {
                self.delay = match value {
                    "1" | "true" | "on" => true,
                    "0" | "false" | "off" => false,
                    _ => return Err(bad(format!("expected true/false, got `{value}`"))),
                }
            }
            "scalar" => {
                self.scalar = match value {
                    "i4f28" => ScalarKind::I4F28,
                    "f32" => ScalarKind::F32,
                    _ => return Err(bad(format!("i4f28 or f32, got `{value}`"))),
                }
            }
            "adc_bits" => self.adc.bits = num(key, value)?,
            "adc_lsb" => self.adc.lsb_m = num(key, value)?,
            "adc_offset" => self.adc.offset_m = num(key, value)?,
            "adc_noise" => self.adc.noise_lsb = num(key, value)?,
            "adc_seed" => self.adc.seed = num(key, value)?,
            "pwm_bits" => self.pwm_bits = num(key, value)?,
            "v_dc" => self.v_dc = num(key, value)?,
            "hold_ticks" => self.hold_ticks = num(key, value)?,
            "stuck_ticks" => self.stuck_ticks = num(key, value)?,
            "ramp_ticks" => self.ramp_ticks = num(key, value)?,
            "watchdog_ticks" => self.watchdog_ticks = num(key, value)?,
            "fault" => self.sensor_faults.push(value.parse()?),
            _ => return Err(bad("not a firmware key".into())),
        }
        match self.check(key) {
            Some(limit) => Err(bad(format!(
                "`{value}` is out of range (accepted: {limit})"
            ))),
            None => Ok(()),
        }
    }

    /// The firmware's limits (`maglev_firmware_sim::validate`) for the value `key` set: the
    /// accepted range if it is outside, so a bad value is reported here, by name, before any
    /// firmware sees it.
    fn check(&self, key: &str) -> Option<&'static str> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        let (ok, limit) = match key {
            "rate" => (self.rate_hz > 0, ConfigKey::Rate.limit()),
            "adc_bits" => (
                validate::ADC_BITS.contains(&self.adc.bits),
                ConfigKey::AdcBits.limit(),
            ),
            "adc_lsb" => (positive(self.adc.lsb_m), ConfigKey::AdcLsb.limit()),
            "adc_offset" => (self.adc.offset_m.is_finite(), ConfigKey::AdcOffset.limit()),
            "adc_noise" => (
                self.adc.noise_lsb.is_finite() && self.adc.noise_lsb >= 0.0,
                "a finite number ≥ 0 (LSB rms)",
            ),
            "pwm_bits" => (
                validate::PWM_BITS.contains(&self.pwm_bits),
                ConfigKey::PwmBits.limit(),
            ),
            "v_dc" => (positive(self.v_dc), ConfigKey::VDc.limit()),
            "hold_ticks" => (
                self.hold_ticks <= validate::MAX_HOLD_TICKS,
                ConfigKey::HoldTicks.limit(),
            ),
            "stuck_ticks" => (self.stuck_ticks != 1, ConfigKey::StuckTicks.limit()),
            "ramp_ticks" => (self.ramp_ticks > 0, ConfigKey::RampTicks.limit()),
            _ => (true, ""),
        };
        (!ok).then_some(limit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The key and reason of a refused `--set`.
    fn refused(key: &str, value: &str) -> (String, String) {
        match HilSettings::default().set(key, value).unwrap_err() {
            Error::Invalid { key, reason } => (key, reason),
            other => panic!("{key}={value}: not an Invalid error: {other}"),
        }
    }

    #[test]
    fn bad_firmware_values_name_the_key_and_the_limit() {
        let (k, r) = refused("rate", "fast");
        assert_eq!(
            (k.as_str(), r.as_str()),
            (
                "--set rate",
                "cannot read `fast` as a number (a whole number ≥ 0)"
            )
        );
        let (_, r) = refused("rate", "-5");
        assert_eq!(r, "cannot read `-5` as a number (a whole number ≥ 0)");
        let (k, r) = refused("delay", "maybe");
        assert_eq!(k, "--set delay");
        assert!(r.contains("true/false") && r.contains("`maybe`"), "{r}");
        let (k, r) = refused("pwm_bits", "40");
        assert_eq!(k, "--set pwm_bits");
        assert!(
            r.starts_with("`40` is out of range (accepted: ")
                && r.contains(ConfigKey::PwmBits.limit()),
            "{r}"
        );
        let (k, r) = refused("fault", "stuck:x");
        assert_eq!(k, "--set fault");
        assert!(r.contains("KIND:CHANNEL@SECONDS"), "{r}");
        let mut hs = HilSettings::default();
        hs.set("fault", "stuck:2@0.25").unwrap();
        hs.set("rate", "20000").unwrap();
        assert_eq!(hs.rate_hz, 20_000);
        assert_eq!(hs.sensor_faults[0].channel, 2);
        assert_eq!(hs.sensor_faults[0].from_s, 0.25);
    }
}
