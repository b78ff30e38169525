//! Every [`Config`] value checked before the firmware uses it, so that a bad value is
//! refused with its name and limit ([`ConfigFault`], answered as `Nack::BadConfig`) instead of
//! panicking (an `adc_bits = 1` once made `clamp(1, 0)` panic) or silently disabling a
//! fail-safe (`hold_ticks = 65535` once turned fault escalation off). The host checks its
//! settings against the same limits before it sends them (`maglev hil --set`).
//!
//! The law's own parameters (`i0`, `h0`, …, `p0`, the gap loop's gains) are checked by the
//! core when the firmware compiles them; [`law_fault`] names the value a
//! [`maglev_core::ParamError`] is about.

use crate::protocol::{Config, ConfigFault, ConfigKey, Problem, MAX_CHANNELS, MAX_SAMPLES};
use core::ops::RangeInclusive;
use maglev_core::ParamError;

/// ADC resolutions accepted (bits). Codes 0 and full scale are fault codes, so one bit
/// would leave no valid code at all.
pub const ADC_BITS: RangeInclusive<u8> = 2..=16;
/// PWM resolutions accepted (bits).
pub const PWM_BITS: RangeInclusive<u8> = 1..=16;
/// Longest hold of a bad sample before escalation (ticks; 1 s at 10 kHz).
pub const MAX_HOLD_TICKS: u16 = 10_000;

fn fault(key: ConfigKey, problem: Problem) -> ConfigFault {
    ConfigFault {
        key,
        channel: None,
        problem,
    }
}

/// `v` finite and (if `positive`) > 0.
fn real(key: ConfigKey, v: f64, positive: bool) -> Result<(), ConfigFault> {
    if !v.is_finite() {
        return Err(fault(key, Problem::NotFinite));
    }
    if positive && v <= 0.0 {
        return Err(fault(key, Problem::OutOfRange));
    }
    Ok(())
}

/// Checks the values the firmware uses itself (channels, timing, converter, supervision,
/// initial gaps); the law's parameters are the core's to check.
pub fn check_config(cfg: &Config) -> Result<(), ConfigFault> {
    use ConfigKey::*;
    use Problem::OutOfRange;
    let n = cfg.channels.len();
    if n == 0 || n > MAX_CHANNELS {
        return Err(fault(Channels, OutOfRange));
    }
    if cfg.rate_hz == 0 {
        return Err(fault(Rate, OutOfRange));
    }
    if cfg.ticks_per_step == 0 || n * cfg.ticks_per_step as usize > MAX_SAMPLES {
        return Err(fault(TicksPerStep, OutOfRange));
    }
    if !ADC_BITS.contains(&cfg.adc_bits) {
        return Err(fault(AdcBits, OutOfRange));
    }
    real(AdcLsb, cfg.adc_lsb_m, true)?;
    real(AdcOffset, cfg.adc_offset_m, false)?;
    if !PWM_BITS.contains(&cfg.pwm_bits) {
        return Err(fault(PwmBits, OutOfRange));
    }
    real(VDc, cfg.v_dc, true)?;
    if cfg.hold_ticks > MAX_HOLD_TICKS {
        return Err(fault(HoldTicks, OutOfRange));
    }
    if cfg.stuck_ticks == 1 {
        return Err(fault(StuckTicks, OutOfRange));
    }
    if cfg.ramp_ticks == 0 {
        return Err(fault(RampTicks, OutOfRange));
    }
    if cfg.watchdog_ticks != 0 && cfg.watchdog_ticks <= cfg.ticks_per_step {
        return Err(fault(WatchdogTicks, OutOfRange));
    }
    // Initial gaps strictly inside the sensor's range (codes 0 and full scale are faults).
    let span = (1u32 << cfg.adc_bits) as f64 * cfg.adc_lsb_m;
    let (lo, hi) = (cfg.adc_offset_m, cfg.adc_offset_m + span);
    for (k, ch) in cfg.channels.iter().enumerate() {
        let bad = |problem| ConfigFault {
            key: Gap,
            channel: Some(k as u8),
            problem,
        };
        if !ch.gap.is_finite() {
            return Err(bad(Problem::NotFinite));
        }
        if ch.gap <= lo.max(0.0) || ch.gap >= hi {
            return Err(bad(OutOfRange));
        }
    }
    Ok(())
}

/// The [`Config`] value a compile error of the core is about (`channel` for `p0` and gaps).
pub fn law_fault(e: ParamError, channel: Option<u8>) -> ConfigFault {
    use maglev_core::levitation::fields as f;
    use ConfigKey::*;
    let problem = match e {
        ParamError::NotFinite(_) => Problem::NotFinite,
        ParamError::NotPositive(_)
        | ParamError::Negative(_)
        | ParamError::TooLarge { .. }
        | ParamError::AlphaOutOfRange => Problem::OutOfRange,
        ParamError::Unrepresentable { .. } => Problem::Unrepresentable,
    };
    let field = e.field();
    let magnet = [
        (f::I0, I0),
        (f::H0, H0),
        (f::R0, R0),
        (f::KP, Kp),
        (f::KI, Ki),
        (f::ALPHA, Alpha),
        (f::V_MAX, VMax),
        (f::P0, P0),
        (f::GAP, Gap),
    ];
    let key = match field.law {
        // A parameter of the configured law (its gains, or a coefficient made from them).
        Some(law) => ConfigKey::of_law(law),
        None => magnet
            .iter()
            .find(|(m, _)| field.is(*m))
            .map_or(Rate, |&(_, k)| k),
    };
    // The rest (the sub-step coefficients `c`, `kih`, …, and `dt`) depend on the rate.
    let per_channel = matches!(key, P0 | Gap);
    ConfigFault {
        key,
        channel: if per_channel { channel } else { None },
        problem,
    }
}
