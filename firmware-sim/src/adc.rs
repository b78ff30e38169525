//! The gap-sensor ADC: a converter model (analogue gap → code) and the chip's SPI interface.
//!
//! embedded-hal 1.0 has no ADC trait, so the firmware reads the converter the way it would
//! read a real SPI ADC: one 3-byte full-duplex transaction per channel,
//!
//! ```text
//! MOSI: 0x80 | channel, 0x00, 0x00
//! MISO: 0x00,           code[15:8], code[7:0]
//! ```
//!
//! Why the split: the analogue side (gap, offset, noise, quantisation: [`AdcModel`]) belongs to
//! the physical world the host simulates, so the host converts and sends codes; the digital
//! side ([`AdcChip`]) runs beside the firmware and is what its `SpiDevice` talks to. The codes
//! are integers, so every mode (in-process, host process, QEMU) sees exactly the same input.
//! Noise comes from a counter-based PRNG keyed by (seed, tick, channel): the same sample
//! always gets the same noise, however often the host re-runs a step.

use crate::protocol::MAX_CHANNELS;
use core::convert::Infallible;
use embedded_hal::spi::{ErrorType, Operation, SpiDevice};

/// The converter's transfer function (SI at the edge).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdcModel {
    /// Resolution (bits, 1..=16).
    pub bits: u8,
    /// Gap per code (m).
    pub lsb_m: f64,
    /// Gap at code 0 (m).
    pub offset_m: f64,
    /// Gaussian-like noise, standard deviation in codes (0 = none).
    pub noise_lsb: f64,
    pub seed: u64,
}

impl AdcModel {
    /// Largest code.
    pub fn full_scale(&self) -> u16 {
        ((1u32 << self.bits.clamp(1, 16)) - 1) as u16
    }

    /// Code for gap `h` (m) at control tick `tick` on `channel`:
    /// `round((h − offset)/LSB + noise)`, clamped to `[0, full scale]`.
    pub fn code(&self, h: f64, tick: u64, channel: u32) -> u16 {
        let mut v = (h - self.offset_m) / self.lsb_m;
        if self.noise_lsb > 0.0 {
            v += self.noise_lsb * unit_noise(self.seed, tick, channel);
        }
        if v.is_nan() || v <= 0.0 {
            return 0;
        }
        let c = libm::round(v);
        let fs = self.full_scale();
        if c >= fs as f64 {
            fs
        } else {
            c as u16
        }
    }
}

/// SplitMix64 finaliser: a good 64-bit mix of a counter.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Zero-mean, unit-variance noise (Irwin–Hall of four uniforms, rescaled), deterministic in
/// its arguments.
pub fn unit_noise(seed: u64, tick: u64, channel: u32) -> f64 {
    let mut z = mix(seed ^ mix(tick ^ ((channel as u64) << 48)));
    let mut sum = 0.0;
    for _ in 0..4 {
        z = mix(z);
        sum += (z >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
    }
    // Var(sum) = 4/12; scale to 1.
    sum * 1.732_050_807_568_877_2
}

/// The ADC chip's digital side: latched codes per channel, served over SPI.
#[derive(Clone, Debug, Default)]
pub struct AdcChip {
    inputs: [u16; MAX_CHANNELS],
    /// Transactions with a malformed command (answered with all ones).
    pub bad_commands: u32,
}

impl AdcChip {
    /// Latches the code the converter produced for `channel` this tick (the board's side).
    pub fn set_input(&mut self, channel: usize, code: u16) {
        if let Some(slot) = self.inputs.get_mut(channel) {
            *slot = code;
        }
    }

    /// The 3 response bytes for a command byte.
    fn response(&mut self, cmd: u8) -> [u8; 3] {
        let ch = (cmd & 0x7F) as usize;
        if cmd & 0x80 == 0 || ch >= MAX_CHANNELS {
            self.bad_commands += 1;
            return [0xFF; 3];
        }
        let [hi, lo] = self.inputs[ch].to_be_bytes();
        [0x00, hi, lo]
    }
}

impl ErrorType for AdcChip {
    type Error = Infallible;
}

impl SpiDevice<u8> for AdcChip {
    /// Chip select spans the whole transaction; the first byte written is the command and
    /// the bytes clocked out are the response, byte for byte.
    fn transaction(&mut self, operations: &mut [Operation<'_, u8>]) -> Result<(), Infallible> {
        let mut cmd: Option<u8> = None;
        let mut resp = [0xFFu8; 3];
        let mut pos = 0usize;
        let mut clock = |out: Option<&mut u8>, inp: Option<u8>, chip: &mut AdcChip| {
            if pos == 0 {
                if let Some(c) = inp {
                    cmd = Some(c);
                    resp = chip.response(c);
                }
            }
            if let Some(o) = out {
                *o = if pos < 3 && cmd.is_some() || pos == 0 {
                    resp[pos.min(2)]
                } else {
                    0xFF
                };
            }
            pos += 1;
        };
        for op in operations.iter_mut() {
            match op {
                Operation::Write(w) => w.iter().for_each(|&b| clock(None, Some(b), self)),
                Operation::Read(r) => r.iter_mut().for_each(|b| clock(Some(b), None, self)),
                Operation::Transfer(r, w) => {
                    for i in 0..r.len().max(w.len()) {
                        let inp = w.get(i).copied();
                        clock(r.get_mut(i), inp, self);
                    }
                }
                Operation::TransferInPlace(buf) => {
                    for b in buf.iter_mut() {
                        let inp = *b;
                        clock(Some(b), Some(inp), self);
                    }
                }
                Operation::DelayNs(_) => {}
            }
        }
        Ok(())
    }
}

/// Reads one channel's code through any SPI device speaking this chip's protocol.
pub fn read_channel<D: SpiDevice<u8>>(spi: &mut D, channel: u8) -> Result<u16, D::Error> {
    let mut buf = [0x80 | channel, 0, 0];
    spi.transfer_in_place(&mut buf)?;
    Ok(u16::from_be_bytes([buf[1], buf[2]]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model() -> AdcModel {
        AdcModel {
            bits: 12,
            lsb_m: 1e-5,
            offset_m: 0.0,
            noise_lsb: 0.0,
            seed: 1,
        }
    }

    #[test]
    fn code_rounds_and_clamps() {
        let m = model();
        assert_eq!(m.code(0.01, 0, 0), 1000);
        assert_eq!(m.code(0.010_004_9, 0, 0), 1000);
        assert_eq!(m.code(0.010_005_1, 0, 0), 1001);
        assert_eq!(m.code(-0.001, 0, 0), 0);
        assert_eq!(m.code(1.0, 0, 0), 4095);
        assert_eq!(m.code(f64::NAN, 0, 0), 0);
    }

    #[test]
    fn noise_is_deterministic_and_roughly_unit_variance() {
        let n = 20_000;
        let xs: std::vec::Vec<f64> = (0..n).map(|k| unit_noise(7, k, 3)).collect();
        assert_eq!(xs[123], unit_noise(7, 123, 3));
        assert_ne!(unit_noise(7, 123, 3), unit_noise(7, 123, 4));
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
        assert!(mean.abs() < 0.03, "{mean}");
        assert!((var - 1.0).abs() < 0.05, "{var}");
    }

    #[test]
    fn spi_round_trip_and_bad_command() {
        let mut chip = AdcChip::default();
        chip.set_input(5, 0xBEEF);
        assert_eq!(read_channel(&mut chip, 5).unwrap(), 0xBEEF);
        // Split write/read transaction gives the same bytes.
        let mut r = [0u8; 2];
        chip.transaction(&mut [Operation::Write(&[0x85]), Operation::Read(&mut r)])
            .unwrap();
        assert_eq!(r, [0xBE, 0xEF]);
        let mut buf = [0x05, 0, 0];
        chip.transfer_in_place(&mut buf).unwrap();
        assert_eq!(buf, [0xFF; 3]);
        assert_eq!(chip.bad_commands, 1);
    }
}
