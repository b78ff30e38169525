//! The magnet's accelerometer: a MEMS part on SPI (the firmware's driver, [`Accelerometer`]),
//! its simulated chip ([`AccelChip`]) and the analogue side ([`AccelModel`]).
//!
//! # The part
//! The register map is a subset modelled on ST's IIS3DWB (a three-axis industrial vibration
//! accelerometer, SPI, output data rate 26.7 kHz, so one fresh sample per 10 kHz tick). Only
//! what the firmware uses is modelled:
//!
//! | address | name | access | meaning here |
//! |---|---|---|---|
//! | `0x0F` | `WHO_AM_I` | r | `0x7B` |
//! | `0x10` | `CTRL1_XL` | r/w | bits 7:5 `XL_EN` (`101`: on; `000`: power-down, outputs read 0), bits 3:2 `FS_XL` (`00` ±2 g, `01` ±16 g, `10` ±4 g, `11` ±8 g) |
//! | `0x2C`, `0x2D` | `OUTZ_L_XL`, `OUTZ_H_XL` | r | Z acceleration, two's complement, little endian |
//!
//! SPI mode 0/3, one transaction per access: the first byte is the address with bit 7 set to
//! read (clear to write), then data; the address increments after each data byte (the part's
//! `IF_INC`, on by default). Other addresses read 0 and ignore writes.
//!
//! # Scale and units
//! The driver sets ±16 g (`CTRL1_XL = 0xA4`): 0.488 mg per LSB, 32 g of span — a magnet's
//! vertical acceleration over a rough rail stays well inside ±15 g. The part measures specific
//! force along its Z axis (Z up): `a + g_n`, so at rest it reads +1 g. The firmware takes the
//! magnet's absolute acceleration as `a/g_n = code · 0.488e-3 − 1`, which is what the core's
//! [`maglev_core::Measurement::accel`] wants. The host side ([`AccelModel`]) converts the
//! plant's acceleration (m/s², Z up) to that code, rounding to the nearest and saturating at
//! the 16-bit range; like the gap ADC's codes, the codes are integers, so every firmware mode
//! sees the same input.

use core::convert::Infallible;
use embedded_hal::spi::{ErrorType, Operation, SpiDevice};
use maglev_core::levitation::GRAVITY;

/// `WHO_AM_I` register and its value.
pub const WHO_AM_I: u8 = 0x0F;
pub const ID: u8 = 0x7B;
/// `CTRL1_XL` register, and the value the driver writes: on, ±16 g.
pub const CTRL1_XL: u8 = 0x10;
pub const CTRL1_ON_16G: u8 = 0xA4;
/// `OUTZ_L_XL` (`OUTZ_H_XL` follows).
pub const OUTZ_L_XL: u8 = 0x2C;
/// Sensitivity at ±16 g (g per LSB).
pub const LSB_G_16G: f64 = 0.488e-3;

/// Bit 7 of the address byte: read.
const READ: u8 = 0x80;

/// Sensitivity (g per LSB) of a `FS_XL` setting.
fn lsb_g(ctrl1: u8) -> f64 {
    match (ctrl1 >> 2) & 0b11 {
        0b00 => 0.061e-3,
        0b01 => LSB_G_16G,
        0b10 => 0.122e-3,
        _ => 0.244e-3,
    }
}

/// The analogue side: the plant's acceleration to the code the part outputs at ±16 g.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AccelModel;

impl AccelModel {
    /// Code for the absolute vertical acceleration `a` (m/s², Z up): the specific force
    /// `a/g_n + 1` in LSB, rounded, saturated to `i16`; NaN reads 0.
    pub fn code(&self, a: f64) -> i16 {
        saturate(libm::round((a / GRAVITY + 1.0) / LSB_G_16G))
    }

    /// Code of a part whose Z axis is horizontal, along +Y (a guidance magnet's,
    /// [`crate::guide`]), for the absolute lateral acceleration `a_y` (m/s²): `a_y/g_n` in
    /// LSB (no gravity along a horizontal axis), rounded, saturated; NaN reads 0.
    pub fn code_lateral(&self, a_y: f64) -> i16 {
        saturate(libm::round(a_y / GRAVITY / LSB_G_16G))
    }
}

/// A rounded LSB count as the part's 16-bit output (saturating; NaN reads 0).
fn saturate(v: f64) -> i16 {
    if v.is_nan() {
        0
    } else {
        v.clamp(i16::MIN as f64, i16::MAX as f64) as i16
    }
}

/// The part's digital side: registers and the latched Z sample (the board's side sets it
/// each tick at ±16 g; another range reads it rescaled, as the part would).
#[derive(Clone, Debug, Default)]
pub struct AccelChip {
    ctrl1: u8,
    /// The Z sample at ±16 g (LSB).
    z: i16,
}

impl AccelChip {
    /// Latches this tick's sample, a code of [`AccelModel::code`].
    pub fn set_sample(&mut self, code: i16) {
        self.z = code;
    }

    /// The output register pair's value at the configured range (0 in power-down).
    ///
    /// At ±16 g, the range the driver sets, the register is the sample itself: the rescale
    /// `round(z·lsb/lsb)` returns `z` for every `i16` (two roundings of relative 2⁻⁵³ move it
    /// by less than 32 768·2⁻⁵² ≪ ½; `tests::rescale_at_16g_is_the_sample`), so the chip
    /// skips it. In QEMU this chip runs on the simulated MCU and its `f64` arithmetic, in
    /// software there, would otherwise count in the firmware's tick (docs/hil.md).
    fn out_z(&self) -> i16 {
        if self.ctrl1 >> 5 != 0b101 {
            return 0;
        }
        if (self.ctrl1 >> 2) & 0b11 == 0b01 {
            return self.z;
        }
        rescale(self.z, self.ctrl1)
    }

    fn reg_read(&self, addr: u8) -> u8 {
        let [lo, hi] = self.out_z().to_le_bytes();
        match addr {
            WHO_AM_I => ID,
            CTRL1_XL => self.ctrl1,
            OUTZ_L_XL => lo,
            0x2D => hi,
            _ => 0,
        }
    }

    fn reg_write(&mut self, addr: u8, v: u8) {
        if addr == CTRL1_XL {
            self.ctrl1 = v;
        }
    }
}

/// A sample at ±16 g (LSB) as the register reads at the range of `ctrl1`.
fn rescale(z: i16, ctrl1: u8) -> i16 {
    let g = z as f64 * LSB_G_16G;
    libm::round(g / lsb_g(ctrl1)).clamp(i16::MIN as f64, i16::MAX as f64) as i16
}

impl ErrorType for AccelChip {
    type Error = Infallible;
}

impl SpiDevice<u8> for AccelChip {
    /// Chip select spans the transaction: the first byte clocked in is the address byte,
    /// each later byte reads (or writes) one register, the address incrementing.
    fn transaction(&mut self, operations: &mut [Operation<'_, u8>]) -> Result<(), Infallible> {
        let mut cmd: Option<u8> = None;
        let mut addr = 0u8;
        let mut clock = |inp: u8, chip: &mut AccelChip| -> u8 {
            match cmd {
                None => {
                    cmd = Some(inp);
                    addr = inp & !READ;
                    0
                }
                Some(c) => {
                    let out = if c & READ != 0 {
                        chip.reg_read(addr)
                    } else {
                        chip.reg_write(addr, inp);
                        0
                    };
                    addr = addr.wrapping_add(1) & !READ;
                    out
                }
            }
        };
        for op in operations.iter_mut() {
            match op {
                Operation::Write(w) => w.iter().for_each(|&b| {
                    clock(b, self);
                }),
                Operation::Read(r) => r.iter_mut().for_each(|b| *b = clock(0, self)),
                Operation::Transfer(r, w) => {
                    for i in 0..r.len().max(w.len()) {
                        let o = clock(w.get(i).copied().unwrap_or(0), self);
                        if let Some(b) = r.get_mut(i) {
                            *b = o;
                        }
                    }
                }
                Operation::TransferInPlace(buf) => {
                    for b in buf.iter_mut() {
                        *b = clock(*b, self);
                    }
                }
                Operation::DelayNs(_) => {}
            }
        }
        Ok(())
    }
}

/// Why the driver could not start the part.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AccelError<E> {
    /// The bus failed.
    Spi(E),
    /// `WHO_AM_I` read this instead of [`ID`].
    WrongId(u8),
}

/// The firmware's driver: owns its device (its chip select on the bus).
#[derive(Debug)]
pub struct Accelerometer<D> {
    dev: D,
}

impl<D: SpiDevice<u8>> Accelerometer<D> {
    /// Checks `WHO_AM_I` and switches the part on at ±16 g.
    pub fn new(mut dev: D) -> Result<Self, (D, AccelError<D::Error>)> {
        let mut id = [READ | WHO_AM_I, 0];
        if let Err(e) = dev.transfer_in_place(&mut id) {
            return Err((dev, AccelError::Spi(e)));
        }
        if id[1] != ID {
            return Err((dev, AccelError::WrongId(id[1])));
        }
        if let Err(e) = dev.write(&[CTRL1_XL, CTRL1_ON_16G]) {
            return Err((dev, AccelError::Spi(e)));
        }
        Ok(Accelerometer { dev })
    }

    /// The Z sample (LSB at ±16 g): one 3-byte transaction.
    pub fn read_z(&mut self) -> Result<i16, D::Error> {
        let mut buf = [READ | OUTZ_L_XL, 0, 0];
        self.dev.transfer_in_place(&mut buf)?;
        Ok(i16::from_le_bytes([buf[1], buf[2]]))
    }

    /// The device (in simulation the board latches the analogue sample through it).
    pub fn device_mut(&mut self) -> &mut D {
        &mut self.dev
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_are_specific_force_at_16g() {
        let m = AccelModel;
        // At rest the part reads +1 g: 1/0.488e-3 = 2049.18 LSB.
        assert_eq!(m.code(0.0), 2049);
        // Free fall reads 0; −2 g of acceleration reads −1 g.
        assert_eq!(m.code(-GRAVITY), 0);
        assert_eq!(m.code(-2.0 * GRAVITY), -2049);
        assert_eq!(m.code(1e9), i16::MAX);
        assert_eq!(m.code(-1e9), i16::MIN);
        assert_eq!(m.code(f64::NAN), 0);
    }

    #[test]
    fn the_driver_starts_the_part_and_reads_z() {
        let mut chip = AccelChip::default();
        chip.set_sample(-1234);
        // Power-down reads 0 until the driver switches the part on.
        let mut buf = [READ | OUTZ_L_XL, 0, 0];
        chip.transfer_in_place(&mut buf).unwrap();
        assert_eq!(buf[1..], [0, 0]);
        let mut acc = Accelerometer::new(chip).unwrap();
        assert_eq!(acc.read_z().unwrap(), -1234);
        acc.device_mut().set_sample(i16::MAX);
        assert_eq!(acc.read_z().unwrap(), i16::MAX);
        // Split write/read transaction: the same bytes (address auto-increment).
        let mut r = [0u8; 3];
        acc.device_mut()
            .transaction(&mut [
                Operation::Write(&[READ | CTRL1_XL]),
                Operation::Read(&mut r),
            ])
            .unwrap();
        assert_eq!(r, [CTRL1_ON_16G, 0, 0]);
        // At ±2 g the same 15.99 g saturates.
        acc.device_mut().write(&[CTRL1_XL, 0xA0]).unwrap();
        assert_eq!(acc.read_z().unwrap(), i16::MAX);
    }

    /// The rescale that [`AccelChip::out_z`] skips at ±16 g is the identity on every code.
    #[test]
    fn rescale_at_16g_is_the_sample() {
        for z in i16::MIN..=i16::MAX {
            assert_eq!(rescale(z, CTRL1_ON_16G), z);
        }
        // and not at another range: ±2 g reads 8 times the LSB count, saturating.
        assert_eq!(rescale(1000, 0xA0), 8000);
        assert_eq!(rescale(5000, 0xA0), i16::MAX);
    }

    /// A part that is not there (all ones on MISO) is refused by its id.
    #[test]
    fn a_wrong_id_is_refused() {
        struct Absent;
        impl ErrorType for Absent {
            type Error = Infallible;
        }
        impl SpiDevice<u8> for Absent {
            fn transaction(&mut self, ops: &mut [Operation<'_, u8>]) -> Result<(), Infallible> {
                for op in ops.iter_mut() {
                    if let Operation::TransferInPlace(b) = op {
                        b.fill(0xFF);
                    }
                }
                Ok(())
            }
        }
        assert!(matches!(
            Accelerometer::new(Absent),
            Err((_, AccelError::WrongId(0xFF)))
        ));
    }
}
