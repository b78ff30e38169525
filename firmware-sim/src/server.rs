//! The firmware's side of the protocol: executes requests on a [`Firmware`] wired to the
//! simulated board ([`AdcChip`], [`HBridge`]), with commit/restore and a reply cache.
//!
//! * `Step` restores the committed state, runs `ticks_per_step` ticks (latching each tick's
//!   codes into the ADC chip before the tick) and keeps the result as the *trial* state.
//! * `Commit{step}` promotes the trial state of that step; anything else is refused.
//! * A request whose `seq` equals the last one executed is answered from the cache without
//!   executing it again (the host retransmits after a lost or corrupted reply).
//! * A `Step`/`Commit` with a `seq` below the last one executed (a late duplicate) is not
//!   executed: `Nack(Stale)`. `Config` is always executed and restarts the numbering.
//! * A frame that fails COBS, CRC or decoding is answered with `Nack(Corrupt)` (seq 0).
//!
//! Used as is by the host in-process, by the `maglev-firmware` host process, and by the QEMU
//! image (feed it bytes with [`Server::push_byte`]). [`serve`] is the loop every byte-stream
//! board runs: a serial port (UART, USB CDC) behind the `embedded-io` traits.

use crate::accel::AccelChip;
use crate::adc::AdcChip;
use crate::firmware::{Firmware, FwState};
use crate::hbridge::HBridge;
use crate::protocol::{
    self, Config, ConfigFault, Envelope, FrameReader, Nack, Reply, Request, Response, ScalarKind,
    MAX_FRAME, VERSION,
};
use heapless::Vec;
use maglev_core::scalar::I4F28;
use maglev_core::Scalar;

/// A configured firmware in one scalar type, with its committed and trial states.
pub struct Node<S> {
    fw: Firmware<S, AdcChip, HBridge, AccelChip>,
    committed: FwState<S>,
    trial: Option<(u32, FwState<S>)>,
    ticks: u16,
    /// Link-loss watchdog: the limit (0 = off) and the timer periods since the last `Step`.
    watchdog: u16,
    idle: u32,
}

impl<S: Scalar> Node<S> {
    fn new(cfg: &Config) -> Result<Self, ConfigFault> {
        let mut pwm = Vec::new();
        for _ in 0..cfg.channels.len() {
            let _ = pwm.push(HBridge::new(cfg.pwm_bits));
        }
        let mut accels = Vec::new();
        for _ in 0..cfg.channels.len() {
            let _ = accels.push(AccelChip::default());
        }
        let fw = Firmware::new(cfg, AdcChip::default(), pwm, accels)?;
        Ok(Node {
            committed: fw.state(),
            fw,
            trial: None,
            ticks: cfg.ticks_per_step,
            watchdog: cfg.watchdog_ticks,
            idle: 0,
        })
    }

    /// One control-timer period (see [`Server::timer_tick`]).
    fn timer_tick(&mut self) -> u16 {
        if self.watchdog == 0 {
            return 0;
        }
        self.idle = self.idle.saturating_add(1);
        if self.idle <= self.watchdog as u32 {
            return 0;
        }
        // The link is lost: the fault reaction runs on the committed state, on the firmware's
        // own timer, with the last samples latched in the ADC; it stays latched.
        self.fw.restore(&self.committed);
        let events = self.fw.trip().0 | self.fw.tick().0;
        self.committed = self.fw.state();
        self.trial = None;
        events
    }

    /// `accel`: the wired channels (bit k: channel k) and their samples, tick by tick, in
    /// channel order ([`Request::StepAccel`]); `(0, [])` for a plain `Step`.
    fn step(&mut self, step: u32, codes: &[u16], (wired, accel): (u16, &[i16])) -> Response {
        let n = self.fw.channels();
        let per_tick = wired.count_ones() as usize;
        let ticks = self.ticks as usize;
        if codes.len() != n * ticks
            || accel.len() != per_tick * ticks
            || (n < 16 && wired >> n != 0)
        {
            return Response::Nack(Nack::BadRequest);
        }
        self.idle = 0;
        self.fw.restore(&self.committed);
        self.fw.wire_accelerometers(wired);
        let mut events = 0u16;
        for (j, tick) in codes.chunks_exact(n).enumerate() {
            for (k, &c) in tick.iter().enumerate() {
                self.fw.bus_mut().set_input(k, c);
            }
            let mut samples = accel[j * per_tick..(j + 1) * per_tick].iter();
            for k in (0..n).filter(|k| wired & (1 << k) != 0) {
                let z = samples.next().copied().unwrap_or(0);
                if let Some(chip) = self.fw.accel_mut(k) {
                    chip.set_sample(z);
                }
            }
            events |= self.fw.tick().0;
        }
        let st = self.fw.state();
        self.trial = Some((step, st));
        let mut reply = Reply {
            step,
            events,
            mode: st.mode as u8,
            channels: Vec::new(),
        };
        for k in 0..n {
            let _ = reply.channels.push(self.fw.output(k));
        }
        Response::Reply(reply)
    }

    fn commit(&mut self, step: u32) -> Response {
        match self.trial {
            Some((s, st)) if s == step => {
                self.committed = st;
                Response::Committed { step }
            }
            _ => Response::Nack(Nack::BadRequest),
        }
    }
}

enum Engine {
    None,
    Fixed(Node<I4F28>),
    Float(Node<f32>),
}

/// Protocol endpoint.
pub struct Server {
    engine: Engine,
    last: Option<Envelope<Response>>,
    last_seq: Option<u32>,
    reader: FrameReader,
}

impl Default for Server {
    fn default() -> Self {
        Self::new()
    }
}

impl Server {
    pub const fn new() -> Self {
        Server {
            engine: Engine::None,
            last: None,
            last_seq: None,
            reader: FrameReader::new(),
        }
    }

    /// Executes one request (or answers it from the cache).
    pub fn handle(&mut self, req: &Envelope<Request>) -> Envelope<Response> {
        let reply = |msg| Envelope {
            version: VERSION,
            seq: req.seq,
            msg,
        };
        if req.version != VERSION {
            return reply(Response::Nack(Nack::Version));
        }
        let is_config = matches!(req.msg, Request::Config(_));
        if !is_config {
            if self.last_seq == Some(req.seq) {
                if let Some(cached) = &self.last {
                    return cached.clone();
                }
            }
            if self.last_seq.is_some_and(|last| req.seq < last) {
                return reply(Response::Nack(Nack::Stale));
            }
        }
        let msg = match &req.msg {
            Request::Ping => Response::Pong,
            Request::Config(cfg) => self.configure(cfg),
            Request::Step { step, codes } => match &mut self.engine {
                Engine::None => Response::Nack(Nack::NotConfigured),
                Engine::Fixed(n) => n.step(*step, codes, (0, &[])),
                Engine::Float(n) => n.step(*step, codes, (0, &[])),
            },
            Request::StepAccel {
                step,
                codes,
                wired,
                accel,
            } => match &mut self.engine {
                Engine::None => Response::Nack(Nack::NotConfigured),
                Engine::Fixed(n) => n.step(*step, codes, (*wired, accel)),
                Engine::Float(n) => n.step(*step, codes, (*wired, accel)),
            },
            Request::Commit { step } => match &mut self.engine {
                Engine::None => Response::Nack(Nack::NotConfigured),
                Engine::Fixed(n) => n.commit(*step),
                Engine::Float(n) => n.commit(*step),
            },
        };
        let out = reply(msg);
        self.last_seq = Some(req.seq);
        self.last = Some(out.clone());
        out
    }

    fn configure(&mut self, cfg: &Config) -> Response {
        let engine = match cfg.scalar {
            ScalarKind::I4F28 => Node::new(cfg).map(Engine::Fixed),
            ScalarKind::F32 => Node::new(cfg).map(Engine::Float),
        };
        match engine {
            Ok(e) => {
                self.engine = e;
                Response::Ready {
                    channels: cfg.channels.len() as u8,
                }
            }
            Err(fault) => {
                self.engine = Engine::None;
                Response::Nack(Nack::BadConfig(fault))
            }
        }
    }

    /// The board's control timer, once per period `1/rate` in real time (not used in
    /// lockstep, where each `Step` carries its ticks): more than `watchdog_ticks` periods
    /// since the last `Step` trip the link-loss watchdog, which starts the fault reaction
    /// and then advances it one tick per call. Returns the events raised (`LINK_LOST`,
    /// `FAULT`, …; 0 while the link is alive, or unconfigured).
    pub fn timer_tick(&mut self) -> u16 {
        match &mut self.engine {
            Engine::None => 0,
            Engine::Fixed(n) => n.timer_tick(),
            Engine::Float(n) => n.timer_tick(),
        }
    }

    /// Handles one received frame (without delimiter); writes the reply frame into `out`
    /// and returns its length.
    pub fn handle_frame(&mut self, frame: &[u8], out: &mut [u8]) -> usize {
        let resp = match protocol::decode::<Request>(frame) {
            Ok(req) => self.handle(&req),
            Err(_) => Envelope {
                version: VERSION,
                seq: 0,
                msg: Response::Nack(Nack::Corrupt),
            },
        };
        protocol::encode(&resp, out).unwrap_or(0)
    }

    /// Byte-stream entry point: feed received bytes one at a time; when a frame completes,
    /// the reply frame is written into `out` and its length returned.
    pub fn push_byte(&mut self, b: u8, out: &mut [u8; MAX_FRAME]) -> Option<usize> {
        let frame = match self.reader.push(b)? {
            Ok(f) => {
                let mut copy = [0u8; MAX_FRAME];
                copy[..f.len()].copy_from_slice(f);
                (copy, f.len())
            }
            Err(_) => ([0u8; MAX_FRAME], 0),
        };
        Some(self.handle_frame(&frame.0[..frame.1], out))
    }
}

/// The serial server loop of a board: reads what `port` has, feeds it to
/// [`Server::push_byte`], writes each reply frame back and flushes after each read. Nothing
/// else is written to the port. Board-agnostic: `port` is any `embedded-io` byte stream (the
/// QEMU image's UART0, a board's UART or USB CDC driver, a host serial device or stdin/stdout
/// in `maglev-firmware`).
///
/// Returns `Ok(())` when the port reports its end (a read of 0 bytes), the port's error
/// otherwise. The control timer ([`Server::timer_tick`]) is the board's to drive, e.g. from
/// its timer interrupt.
pub fn serve<P: embedded_io::Read + embedded_io::Write>(
    server: &mut Server,
    port: &mut P,
) -> Result<(), P::Error> {
    let mut buf = [0u8; 64];
    let mut frame = [0u8; MAX_FRAME];
    loop {
        let n = port.read(&mut buf)?;
        if n == 0 {
            return Ok(());
        }
        for &b in &buf[..n] {
            if let Some(len) = server.push_byte(b, &mut frame) {
                port.write_all(&frame[..len])?;
            }
        }
        port.flush()?;
    }
}
