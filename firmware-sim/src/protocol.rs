//! The wire protocol between the host (plant, lockstep driver) and the firmware.
//!
//! Why this shape: the host couples the firmware into a Newton–Raphson loop that may run one
//! time step several times (docs/model.md §7). So a [`Request::Step`] always starts from the
//! firmware's *committed* state and is idempotent; only [`Request::Commit`] moves the
//! committed state forward. A retransmitted request (same `seq`) is answered from the
//! firmware's reply cache, never executed twice, so lost or corrupted frames can be retried
//! without changing the result.
//!
//! # Frame layout
//! ```text
//! wire  = COBS( body ‖ crc32_le(body) ) ‖ 0x00
//! body  = postcard( Envelope { version: u8, seq: u32 (varint), msg } )
//! ```
//! CRC-32 is ISO-HDLC (the zlib/Ethernet one). COBS guarantees the only zero byte on the wire
//! is the frame delimiter, so a receiver resynchronises on the next `0x00` after any damage.
//! Everything here is allocation-free (heapless, fixed buffers) and builds for bare metal.

use heapless::Vec;
/// The law types of [`Config::law`]: the core's own, serialised as they are.
pub use maglev_core::{
    gap::Geometry, gap_control::GapParams, law::guidance::GuidanceParams, law::state::StateParams,
    LawKind,
};
use serde::{Deserialize, Serialize};

/// Protocol version carried in every envelope; a mismatch is answered with [`Nack::Version`].
/// 2: [`Config::law`] added (postcard is not self-describing, so the layout changed).
/// 3: [`Config::watchdog_ticks`] added, and [`Nack::BadConfig`] carries a [`ConfigFault`].
/// 4: [`Config::geometry`] added (the state law's observer needs how the magnet faces its
/// rail, which `StateParams` does not serialise), [`Request::StepAccel`] and
/// [`ConfigKey::Accelerometer`] appended.
/// 5: [`Config::guidance`] added (the guidance pairs' own law), [`ConfigKey::Guidance`]
/// appended.
pub const VERSION: u8 = 5;
/// Most magnet channels one firmware serves (4 wheels × 3 magnets = 12 for the Fig. 1 car).
pub const MAX_CHANNELS: usize = 16;
/// Most ADC codes in one step request (channels × ticks per step).
pub const MAX_SAMPLES: usize = 1200;
/// Largest encoded frame (COBS overhead and delimiter included).
pub const MAX_FRAME: usize = 4096;
/// Largest frame body before COBS.
const MAX_BODY: usize = MAX_FRAME - MAX_FRAME / 254 - 2;

const CRC: crc::Crc<u32> = crc::Crc::<u32>::new(&crc::CRC_32_ISO_HDLC);

/// A message with its version and sequence number.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Envelope<M> {
    pub version: u8,
    /// Host requests count up from 1; a reply echoes the request's number.
    pub seq: u32,
    pub msg: M,
}

/// Which number type the firmware's control law runs in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum ScalarKind {
    /// 32-bit fixed point, 28 fraction bits: bit-identical on every target.
    I4F28,
    /// IEEE single precision (the Cortex-M4F FPU's type).
    F32,
}

/// Controller, converter and supervision settings: SI values, converted once by the firmware.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Config {
    pub scalar: ScalarKind,
    /// Control rate (Hz).
    pub rate_hz: u32,
    /// Control ticks per host step (Δt × rate).
    pub ticks_per_step: u16,
    /// Use the sample of the previous tick (one-sample computation delay).
    pub delay: bool,
    /// Law parameters (paper §4.2): i0 (A), h0 (m), R0 (Ω), KP, KI, α, V_max (V).
    pub i0: f64,
    pub h0: f64,
    pub r0: f64,
    pub kp: f64,
    pub ki: f64,
    pub alpha: f64,
    pub v_max: f64,
    /// The levitation law of every channel (the core's own type: its postcard layout is the
    /// wire's). Gains per unit of the inner law, as `maglev_core::LawKind` documents; the gap
    /// loop runs once per control tick on the channel's sampled gap.
    pub law: LawKind,
    /// Per channel: static load p0 (N) and initial gap (m); the controller starts in
    /// equilibrium at that gap.
    pub channels: Vec<ChannelInit, MAX_CHANNELS>,
    /// ADC: resolution (bits), metres per code, gap at code 0 (m).
    pub adc_bits: u8,
    pub adc_lsb_m: f64,
    pub adc_offset_m: f64,
    /// H-bridge: PWM resolution (bits) and DC-link voltage (V).
    pub pwm_bits: u8,
    pub v_dc: f64,
    /// Supervision (ticks): hold a bad sample at most this long before the fault ramp.
    pub hold_ticks: u16,
    /// A code repeated this many ticks counts as a stuck sensor (0 = check off).
    pub stuck_ticks: u16,
    /// Length of the coil-voltage ramp to zero after a fault.
    pub ramp_ticks: u16,
    /// Link-loss watchdog: this many control-timer periods without a `Step` trigger the
    /// fault reaction (0 = off; otherwise more than `ticks_per_step`). See
    /// [`crate::server::Server::timer_tick`].
    pub watchdog_ticks: u16,
    /// How every magnet faces its rail (docs/model.md §2): the sign by which the magnet's
    /// upward motion moves its gap, which the state law's observer needs with the
    /// accelerometer (`maglev_core::law::state`); unused by the other laws.
    pub geometry: Geometry,
    /// The guidance pairs' own law (the core's `[controller.guidance]` gains, serialised as
    /// they are), with the timing and supply of the state law in [`Config::law`]: the
    /// channels then come in threes per wheel (levitation, guidance left at `h0 + d`,
    /// guidance right at `h0 − d`, as `maglev_core::guidance` orders them) and each pair
    /// runs `maglev_core::law::guidance` on its two gaps. `None`: every channel runs `law`.
    pub guidance: Option<GuidanceParams>,
}

/// One magnet channel's static load (N) and initial gap (m).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ChannelInit {
    pub p0: f64,
    pub gap: f64,
}

/// Host → firmware. Fixed-size by design (no allocator on the target): the enum is as large
/// as a full `Step`, which is what a receive buffer must hold anyway.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Request {
    /// Configure and reset to the initial equilibrium; answered with [`Response::Ready`].
    Config(Config),
    /// Run one host step from the committed state: ADC codes tick-major,
    /// `codes[tick · channels + channel]`, `ticks_per_step` ticks.
    Step {
        step: u32,
        codes: Vec<u16, MAX_SAMPLES>,
    },
    /// Make the state after the last `Step` the committed state.
    Commit { step: u32 },
    /// Liveness check.
    Ping,
    /// A [`Request::Step`] with accelerometer samples (the state law): `accel` holds, tick
    /// by tick, one code ([`crate::accel::AccelModel::code`]) for each channel whose bit is
    /// set in `wired` (bit k: channel k), in channel order. Appended last, so every earlier
    /// message keeps its bytes.
    StepAccel {
        step: u32,
        codes: Vec<u16, MAX_SAMPLES>,
        wired: u16,
        accel: Vec<i16, MAX_SAMPLES>,
    },
}

/// Firmware → host (fixed-size, see [`Request`]).
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Response {
    Ready {
        channels: u8,
    },
    Reply(Reply),
    Committed {
        step: u32,
    },
    Pong,
    /// The request was not executed.
    Nack(Nack),
}

/// Why a request was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Nack {
    /// Bad CRC, bad COBS, or undecodable body: retransmit.
    Corrupt,
    /// Unsupported protocol version.
    Version,
    /// `Step`/`Commit` before `Config`.
    NotConfigured,
    /// Wrong number of codes, or a commit for a step that was not run.
    BadRequest,
    /// A configuration value is out of its range, or the law cannot be compiled with it
    /// (e.g. fixed point cannot hold a coefficient): which one and why.
    BadConfig(ConfigFault),
    /// `seq` older than the last request executed (a late duplicate): not executed.
    Stale,
}

/// Why a [`Config`] was refused: the value ([`ConfigKey`], and the channel for per-channel
/// values) and what is wrong with it. [`core::fmt::Display`] names the key and its limit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ConfigFault {
    pub key: ConfigKey,
    /// The channel of a per-channel value (`p0`, `gap`).
    pub channel: Option<u8>,
    pub problem: Problem,
}

/// A [`Config`] value, by the name the host's `--set` uses where there is one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum ConfigKey {
    Channels,
    Rate,
    TicksPerStep,
    I0,
    H0,
    R0,
    Kp,
    Ki,
    Alpha,
    VMax,
    /// The gap loop's gains (`GapLoop { kp, kd, tf, x_ref_max }`).
    GapLoop,
    P0,
    Gap,
    AdcBits,
    AdcLsb,
    AdcOffset,
    PwmBits,
    VDc,
    HoldTicks,
    StuckTicks,
    RampTicks,
    WatchdogTicks,
    /// The state law's gains and timing (`LawKind::State`).
    StateLaw,
    /// A channel's accelerometer (state law): it did not answer with its id, or the number
    /// type cannot hold its scale.
    Accelerometer,
    /// The guidance law's gains ([`Config::guidance`]), or a channel layout it cannot pair.
    Guidance,
}

/// What is wrong with a [`Config`] value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Problem {
    /// NaN or infinite.
    NotFinite,
    /// Outside the range [`ConfigKey::limit`] gives.
    OutOfRange,
    /// The run-time number type cannot hold the law's coefficients with this value.
    Unrepresentable,
}

impl ConfigKey {
    /// The key of the parameters of `law` (the wire names each law's gains as one value).
    pub const fn of_law(law: maglev_core::LawName) -> Self {
        match law {
            maglev_core::LawName::GapLoop => ConfigKey::GapLoop,
            // The paper's law has no parameters of its own: a law field is the state law's.
            maglev_core::LawName::State | maglev_core::LawName::Paper => ConfigKey::StateLaw,
        }
    }

    /// The name (as `maglev hil --set` spells it where it is a key).
    pub fn name(self) -> &'static str {
        use ConfigKey::*;
        match self {
            Channels => "channels",
            Rate => "rate",
            TicksPerStep => "ticks_per_step",
            I0 => "i0",
            H0 => "h0",
            R0 => "r0",
            Kp => "kp",
            Ki => "ki",
            Alpha => "alpha",
            VMax => "v_max",
            GapLoop => "gap_loop",
            StateLaw => "state_law",
            P0 => "p0",
            Gap => "gap",
            AdcBits => "adc_bits",
            AdcLsb => "adc_lsb",
            AdcOffset => "adc_offset",
            PwmBits => "pwm_bits",
            VDc => "v_dc",
            HoldTicks => "hold_ticks",
            StuckTicks => "stuck_ticks",
            RampTicks => "ramp_ticks",
            WatchdogTicks => "watchdog_ticks",
            Accelerometer => "accelerometer",
            Guidance => "controller.guidance",
        }
    }

    /// The accepted values, in words (the limits of [`crate::validate`]).
    pub fn limit(self) -> &'static str {
        use ConfigKey::*;
        match self {
            Channels => "1..=16 channels, one PWM output each",
            Rate => "a positive whole number of Hz the law's coefficients fit at",
            TicksPerStep => "1 or more, channels × ticks_per_step ≤ 1200",
            I0 | H0 | R0 | P0 | AdcLsb | VDc => "a finite number > 0",
            Kp | Ki => "a finite number ≥ 0",
            Alpha => "0..=1",
            VMax => "a number > 0 (inf for none)",
            GapLoop => "finite gains ≥ 0, x_ref_max > 0",
            StateLaw => "finite gains ≥ 0, v_max > R0·i0, rate ≥ 2π·observer bandwidth",
            Gap => {
                "finite, inside the sensor's range (adc_offset, adc_offset + 2^adc_bits·adc_lsb)"
            }
            AdcBits => "2..=16",
            AdcOffset => "finite, with the sensor range representable in units of h0",
            PwmBits => "1..=16",
            HoldTicks => "0..=10000",
            StuckTicks => "0 (off) or 2..=65535",
            RampTicks => "1..=65535",
            WatchdogTicks => "0 (off) or more than ticks_per_step",
            Accelerometer => "one per channel answering WHO_AM_I = 0x7B, f32 firmware",
            Guidance => {
                "finite gains ≥ 0, under the state law, channels in threes (levitation, guidance \
                 left, guidance right)"
            }
        }
    }
}

impl core::fmt::Display for ConfigFault {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let what = match self.problem {
            Problem::NotFinite => "is not a finite number",
            Problem::OutOfRange => "is out of range",
            Problem::Unrepresentable => "cannot be represented by the firmware's number type",
        };
        write!(f, "{}", self.key.name())?;
        if let Some(c) = self.channel {
            write!(f, " of channel {c}")?;
        }
        write!(f, " {what} (accepted: {})", self.key.limit())
    }
}

/// The firmware's answer to one step.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Reply {
    pub step: u32,
    /// Supervision events raised during the step ([`crate::supervision::Event`] bits).
    pub events: u16,
    /// Supervision mode at the end of the step ([`crate::supervision::Mode`] as u8).
    pub mode: u8,
    /// Per channel at the end of the step.
    pub channels: Vec<ChannelOut, MAX_CHANNELS>,
}

/// One channel's outputs, per unit in Q4.28 (value × 2^28): `g/g0` (the flux variable of
/// Eq. 9; the force is `p0·(g/g0)²`, Eq. 1), the coil current `i/i0`, and the PWM duty
/// last written.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ChannelOut {
    pub g_q28: i32,
    pub current_q28: i32,
    pub duty: u16,
}

/// Why a frame could not be read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameError {
    /// COBS structure broken.
    Cobs,
    /// Shorter than a CRC, or CRC mismatch.
    Crc,
    /// Body does not decode to a message (or has trailing bytes).
    Decode,
    /// Frame longer than [`MAX_FRAME`].
    TooLong,
    /// Message too large to encode.
    Encode,
}

/// Encodes `env` into `out` as one delimited frame; returns its length.
pub fn encode<M: Serialize>(env: &Envelope<M>, out: &mut [u8]) -> Result<usize, FrameError> {
    let mut body = [0u8; MAX_BODY];
    let n = postcard::to_slice(env, &mut body[..MAX_BODY - 4])
        .map_err(|_| FrameError::Encode)?
        .len();
    let crc = CRC.checksum(&body[..n]);
    body[n..n + 4].copy_from_slice(&crc.to_le_bytes());
    let k = cobs::try_encode(&body[..n + 4], out).map_err(|_| FrameError::Encode)?;
    if k >= out.len() {
        return Err(FrameError::Encode);
    }
    out[k] = 0;
    Ok(k + 1)
}

/// Decodes one frame (without its `0x00` delimiter). Never panics on any input.
pub fn decode<M: for<'de> Deserialize<'de>>(frame: &[u8]) -> Result<Envelope<M>, FrameError> {
    let mut body = [0u8; MAX_FRAME];
    if frame.len() > MAX_FRAME {
        return Err(FrameError::TooLong);
    }
    let n = cobs::decode(frame, &mut body).map_err(|_| FrameError::Cobs)?;
    if n < 4 {
        return Err(FrameError::Crc);
    }
    let (payload, crc) = body[..n].split_at(n - 4);
    let want = u32::from_le_bytes([crc[0], crc[1], crc[2], crc[3]]);
    if CRC.checksum(payload) != want {
        return Err(FrameError::Crc);
    }
    match postcard::take_from_bytes::<Envelope<M>>(payload) {
        Ok((env, [])) => Ok(env),
        _ => Err(FrameError::Decode),
    }
}

/// Splits a byte stream into frames at `0x00`; an over-long frame is dropped whole.
pub struct FrameReader {
    buf: Vec<u8, MAX_FRAME>,
    overflow: bool,
    /// The buffer holds a frame already handed out: clear it before the next byte.
    done: bool,
}

impl Default for FrameReader {
    fn default() -> Self {
        Self::new()
    }
}

impl FrameReader {
    pub const fn new() -> Self {
        FrameReader {
            buf: Vec::new(),
            overflow: false,
            done: false,
        }
    }

    /// Feeds one byte; at a delimiter returns the frame collected since the last one
    /// (`Err(TooLong)` if it overflowed). Empty frames (two delimiters) are skipped.
    pub fn push(&mut self, b: u8) -> Option<Result<&[u8], FrameError>> {
        if core::mem::take(&mut self.done) {
            self.buf.clear();
        }
        if b != 0 {
            if self.buf.push(b).is_err() {
                self.overflow = true;
            }
            return None;
        }
        if core::mem::take(&mut self.overflow) {
            self.buf.clear();
            return Some(Err(FrameError::TooLong));
        }
        if self.buf.is_empty() {
            return None;
        }
        self.done = true;
        Some(Ok(self.buf.as_slice()))
    }
}
