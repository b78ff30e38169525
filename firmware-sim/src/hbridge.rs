//! The coil's H-bridge: a PWM channel (`embedded_hal::pwm::SetDutyCycle`) in locked
//! anti-phase, so one duty value spans both polarities:
//!
//! ```text
//! V = V_dc · (2·duty/max − 1),   max = 2^bits − 1
//! ```
//!
//! Duty `max/2` is (nearly) 0 V; the voltage resolution is `2·V_dc/max`. The firmware
//! quantises its commanded voltage with [`duty_for`]; the host reads the applied voltage back
//! with [`voltage`].

use core::convert::Infallible;
use embedded_hal::pwm::{ErrorType, SetDutyCycle};

/// One simulated H-bridge PWM channel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HBridge {
    max: u16,
    duty: u16,
}

impl HBridge {
    /// A bridge with `bits` of PWM resolution (1..=16), starting at 0 V (mid duty).
    pub fn new(bits: u8) -> Self {
        let max = ((1u32 << bits.clamp(1, 16)) - 1) as u16;
        HBridge { max, duty: max / 2 }
    }
    /// The duty last written.
    pub fn duty(&self) -> u16 {
        self.duty
    }
}

impl ErrorType for HBridge {
    type Error = Infallible;
}

impl SetDutyCycle for HBridge {
    fn max_duty_cycle(&self) -> u16 {
        self.max
    }
    fn set_duty_cycle(&mut self, duty: u16) -> Result<(), Infallible> {
        self.duty = duty.min(self.max);
        Ok(())
    }
}

/// Duty for a voltage given as a fraction `v/V_dc` of the DC link; clamped to the bridge's
/// range. Returns the duty and whether it clipped.
pub fn duty_for(fraction: f32, max: u16) -> (u16, bool) {
    let d = (fraction + 1.0) * 0.5 * max as f32;
    if d.is_nan() {
        return (max / 2, true);
    }
    if d <= 0.0 {
        return (0, d < -0.5);
    }
    if d >= max as f32 {
        return (max, d > max as f32 + 0.5);
    }
    ((d + 0.5) as u16, false)
}

/// Applied coil voltage (V) for a duty.
pub fn voltage(duty: u16, max: u16, v_dc: f64) -> f64 {
    v_dc * (2.0 * duty as f64 / max as f64 - 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn duty_voltage_round_trip() {
        let max = 4095;
        for frac in [-1.0f32, -0.5, 0.0, 0.25, 1.0] {
            let (d, clip) = duty_for(frac, max);
            assert!(!clip);
            let v = voltage(d, max, 100.0);
            assert!(
                (v - 100.0 * frac as f64).abs() <= 100.0 / max as f64 + 1e-9,
                "{v}"
            );
        }
        assert_eq!(duty_for(1.5, max), (max, true));
        assert_eq!(duty_for(-2.0, max), (0, true));
        let mut hb = HBridge::new(12);
        hb.set_duty_cycle(9999).unwrap();
        assert_eq!(hb.duty(), 4095);
    }
}
