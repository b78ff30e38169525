//! The host board: the physical side of the firmware's peripherals.
//!
//! * Gap sensors: each control tick's gap (interpolated inside the host step) goes through
//!   the converter model ([`AdcModel`]) and any injected sensor fault, giving the ADC codes
//!   the firmware reads over SPI.
//! * Magnets: the force is Eq. 1, `G = K0·g² = p0·(g/g0)²`, with `g = i/h` the flux variable
//!   of the coil equation (Eq. 9) as the firmware's law integrates it. As in the paper, the
//!   coil's electrical state lives in the law; sensor errors reach the force through it (the
//!   law integrates Eq. 9 with the *measured* gap). The flux, not the current, is the
//!   continuous state: at fixed flux the force does not jump when the gap does.

use maglev_firmware_sim::adc::AdcModel;
use std::collections::BTreeMap;

/// A sensor fault injected on one channel from a time on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SensorFaultKind {
    /// The code freezes at its first value at or after the start time.
    Stuck,
    /// The code reads full scale (open sensor / beyond range).
    OutOfRange,
    /// The code reads 0 (the magnet at the rail: a collision).
    Contact,
}

/// `kind:channel@t` on the command line, e.g. `stuck:0@0.2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SensorFault {
    pub kind: SensorFaultKind,
    pub channel: usize,
    pub from_s: f64,
}

/// A malformed fault is `Invalid` on `--set fault`, the one place it is written.
impl std::str::FromStr for SensorFault {
    type Err = maglev_sim::Error;
    fn from_str(s: &str) -> maglev_sim::Result<Self> {
        let err = || {
            maglev_sim::Error::invalid(
                "--set fault",
                format!("`{s}`: expected KIND:CHANNEL@SECONDS, KIND one of stuck, range, contact"),
            )
        };
        let (kind, rest) = s.split_once(':').ok_or_else(err)?;
        let (ch, t) = rest.split_once('@').ok_or_else(err)?;
        let kind = match kind {
            "stuck" => SensorFaultKind::Stuck,
            "range" => SensorFaultKind::OutOfRange,
            "contact" => SensorFaultKind::Contact,
            _ => return Err(err()),
        };
        Ok(SensorFault {
            kind,
            channel: ch.trim().parse().map_err(|_| err())?,
            from_s: t.trim().parse().map_err(|_| err())?,
        })
    }
}

/// Converter plus injected faults.
pub struct Sensors {
    pub adc: AdcModel,
    pub rate_hz: f64,
    pub faults: Vec<SensorFault>,
    frozen: BTreeMap<usize, u16>,
}

impl Sensors {
    pub fn new(adc: AdcModel, rate_hz: f64, faults: Vec<SensorFault>) -> Self {
        Sensors {
            adc,
            rate_hz,
            faults,
            frozen: BTreeMap::new(),
        }
    }

    /// The code channel `ch` reads at global control tick `tick` for true gap `h` (m).
    pub fn code(&mut self, h: f64, tick: u64, ch: usize) -> u16 {
        let t = tick as f64 / self.rate_hz;
        let code = self.adc.code(h, tick, ch as u32);
        for f in &self.faults {
            if f.channel != ch || t < f.from_s {
                continue;
            }
            return match f.kind {
                SensorFaultKind::Stuck => *self.frozen.entry(ch).or_insert(code),
                SensorFaultKind::OutOfRange => self.adc.full_scale(),
                SensorFaultKind::Contact => 0,
            };
        }
        code
    }
}

/// Magnet force (N) from the reported `g/g0` (Q4.28) for a magnet carrying `p0` (N).
pub fn force(g_q28: i32, p0: f64) -> f64 {
    let g = g_q28 as f64 / (1u64 << 28) as f64;
    p0 * g * g
}
