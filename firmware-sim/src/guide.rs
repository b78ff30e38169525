//! The guidance pairs under the core's guidance law (`maglev_core::law::guidance`,
//! [`Config::guidance`]): one law per wheel's pair, run once per control tick on the pair's
//! two sampled gaps.
//!
//! # Channels
//! With [`Config::guidance`] the channels come in threes per wheel: levitation (`3w`),
//! guidance left (`3w + 1`, gap `h0 + d`), guidance right (`3w + 2`, gap `h0 − d`). The
//! levitation channel runs [`Config::law`] as without guidance; the pair's law reads the
//! lateral offset from both sensors, `d/h0 = (h_L/h0 − h_R/h0)/2`, and drives both coils.
//!
//! # Lateral accelerometer
//! Where the host wires the left guidance channel's accelerometer (`Request::StepAccel`,
//! bit `3w + 1`), the pair reads it as its lateral acceleration: the part sits on the
//! guidance magnet with its Z axis along +Y (the direction that opens the left gap), so it
//! reads `a_y` with no gravity in it, `a_y/g_n = code · 0.488e-3` ([`crate::accel`],
//! [`crate::accel::AccelModel::code_lateral`]). Unwired, the pair's law runs without it.
//!
//! # Timing
//! The pair's law is compiled as the channels' laws are, for one control period
//! (`dt = 1/rate`, one update per tick), with the state law's timing and supply.

use crate::protocol::{Config, ConfigFault, ConfigKey, Problem, MAX_CHANNELS};
use crate::validate::law_fault;
use heapless::Vec;
use maglev_core::gap::Geometry;
use maglev_core::guidance::PairOutput;
use maglev_core::law::guidance::{GuidanceLaw, GuidanceState, PairMeasurement};
use maglev_core::{Params, Scalar};

/// Most guidance pairs one firmware serves (three channels a wheel).
pub const MAX_PAIRS: usize = MAX_CHANNELS / 3;

/// The compiled guidance law of every pair.
pub struct Pairs<S> {
    laws: Vec<GuidanceLaw<S>, MAX_PAIRS>,
    geometry: Geometry,
    half: S,
    /// `a_y/g_n` of code −32768, and of the 16-bit span (no gravity: module docs).
    accel_offset: S,
    accel_span: S,
}

fn guidance_fault(problem: Problem) -> ConfigFault {
    ConfigFault {
        key: ConfigKey::Guidance,
        channel: None,
        problem,
    }
}

impl<S: Scalar> Pairs<S> {
    /// The pairs of `cfg` (`None` without [`Config::guidance`]), each compiled over its left
    /// channel's magnet `magnet(k)`, with their states in equilibrium at the channels'
    /// initial gaps written to `states`. A guidance law outside the state law, channels not
    /// in threes, or gains the core refuses, are refused as [`ConfigKey::Guidance`].
    #[inline(never)]
    pub fn compile(
        cfg: &Config,
        magnet: impl Fn(usize) -> Params,
        states: &mut [GuidanceState<S>; MAX_PAIRS],
    ) -> Result<Option<Self>, ConfigFault> {
        let Some(g) = cfg.guidance else {
            return Ok(None);
        };
        let n = cfg.channels.len();
        let timing = cfg.law.state().ok_or(guidance_fault(Problem::OutOfRange))?;
        if !n.is_multiple_of(3) {
            return Err(guidance_fault(Problem::OutOfRange));
        }
        let mut laws = Vec::new();
        for (w, st) in states.iter_mut().enumerate().take(n / 3) {
            let (l, r) = (3 * w + 1, 3 * w + 2);
            let law = g.compile::<S>(timing, &magnet(l)).map_err(|e| {
                let fault = law_fault(e, Some(l as u8));
                match fault.key {
                    // The gains; a magnet value is the channel's, named as without guidance.
                    ConfigKey::StateLaw => guidance_fault(fault.problem),
                    _ => fault,
                }
            })?;
            let d = 0.5 * (cfg.channels[l].gap - cfg.channels[r].gap);
            *st = law.equilibrium(d);
            let _ = laws.push(law);
        }
        let lsb = crate::accel::LSB_G_16G;
        let mut ov = false;
        let pairs = Pairs {
            laws,
            geometry: cfg.geometry,
            half: S::from_f64(0.5, &mut ov),
            accel_offset: S::from_f64(-32768.0 * lsb, &mut ov),
            accel_span: S::from_f64(65536.0 * lsb, &mut ov),
        };
        if ov {
            return Err(guidance_fault(Problem::Unrepresentable));
        }
        Ok(Some(pairs))
    }

    /// Number of pairs.
    pub fn len(&self) -> usize {
        self.laws.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.laws.is_empty()
    }

    /// `a_y/g_n` of a lateral accelerometer code (module docs), as offset binary through
    /// [`Scalar::from_code`] (no `f64`).
    pub fn accel_pu(&self, z: i16) -> S {
        let mut ov = false;
        let frac = S::from_code((z as u16) ^ 0x8000, 16);
        self.accel_offset
            .sadd(frac.smul(self.accel_span, &mut ov), &mut ov)
    }

    /// One control period of pair `w`: the law on the per-unit gaps `h_l`, `h_r` (`h/h0`)
    /// and the lateral acceleration `accel` (`a_y/g_n`, where wired).
    pub fn update(
        &self,
        w: usize,
        st: &mut GuidanceState<S>,
        (h_l, h_r): (S, S),
        accel: Option<S>,
    ) -> PairOutput<S> {
        let mut ov = false;
        let d = h_l.ssub(h_r, &mut ov).smul(self.half, &mut ov);
        let mut out = self.laws[w].update(st, PairMeasurement { d, accel }, self.geometry);
        if ov {
            out.status = out.status.union(maglev_core::Status::OVERFLOW);
        }
        out
    }
}
