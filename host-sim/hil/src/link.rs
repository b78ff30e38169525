//! The host's end of the firmware link: one request, one reply, in lockstep.
//!
//! [`InProc`] calls the firmware's [`Server`] directly (no bytes). [`StreamLink`] speaks the
//! framed protocol over any byte stream (a child's stdin/stdout, a Unix socket, QEMU's
//! serial port, a serial device: [`StreamLink::serial`]) and is where link faults are handled:
//!
//! * corrupted request → the firmware answers `Nack(Corrupt)` → retransmit;
//! * corrupted reply (COBS/CRC/decode fails) → retransmit;
//! * lost request or reply → no reply within `timeout` → retransmit;
//! * late reply (after the timeout) → the retransmission is answered from the firmware's
//!   reply cache; the extra copy arrives with a stale `seq` and is dropped.
//!
//! A retransmission carries the same `seq`, so it never executes twice. After
//! `max_retries` the run stops with an error naming the request. [`LinkFaults`] injects
//! each fault deterministically (by request number) for the tests.

use maglev_firmware_sim::host_io::StdPort;
use maglev_firmware_sim::protocol::{
    self, Envelope, FrameReader, Nack, Request, Response, MAX_FRAME, VERSION,
};
use maglev_firmware_sim::server::{self, Server};
use maglev_sim::{Error, Result};
use std::io::{ErrorKind, Read, Write};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Counters of one link (summary.json).
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct LinkStats {
    /// Request/reply round trips completed.
    pub exchanges: u64,
    /// Retransmissions.
    pub retries: u64,
    pub timeouts: u64,
    pub corrupt_replies: u64,
    pub nacks: u64,
    /// Replies dropped for a stale sequence number (late duplicates).
    pub stale_replies: u64,
    /// Wall time spent inside `call` (s).
    pub seconds: f64,
}

/// A lockstep request/reply channel to the firmware.
/// Failures are [`Error::Firmware`].
pub trait Link {
    fn call(&mut self, req: Request) -> Result<Response>;
    fn stats(&self) -> LinkStats;
}

/// The firmware in this process.
pub struct InProc {
    server: Box<Server>,
    seq: u32,
    stats: LinkStats,
}

impl Default for InProc {
    fn default() -> Self {
        InProc {
            server: Box::new(Server::new()),
            seq: 0,
            stats: LinkStats::default(),
        }
    }
}

impl Link for InProc {
    fn call(&mut self, req: Request) -> Result<Response> {
        let t = Instant::now();
        self.seq += 1;
        let env = Envelope {
            version: VERSION,
            seq: self.seq,
            msg: req,
        };
        let out = self.server.handle(&env);
        self.stats.exchanges += 1;
        self.stats.seconds += t.elapsed().as_secs_f64();
        Ok(out.msg)
    }
    fn stats(&self) -> LinkStats {
        self.stats
    }
}

/// Deterministic link-fault injection: every n-th request (counting from 1, first
/// transmissions only; 0 = never).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LinkFaults {
    /// Flip one byte of the request frame.
    pub corrupt_request: u64,
    /// Flip one byte of the reply frame as received.
    pub corrupt_reply: u64,
    /// Do not send the request.
    pub drop_request: u64,
    /// Send the request only after 1.5 × the timeout (its reply is late).
    pub late_request: u64,
}

impl LinkFaults {
    fn hits(every: u64, n: u64) -> bool {
        n.checked_rem(every) == Some(0)
    }
}

type SharedWriter = Arc<Mutex<Box<dyn Write + Send>>>;

/// The framed protocol over a byte stream.
pub struct StreamLink {
    writer: SharedWriter,
    frames: Receiver<Vec<u8>>,
    child: Option<Child>,
    seq: u32,
    pub timeout: Duration,
    pub max_retries: u32,
    pub faults: LinkFaults,
    stats: LinkStats,
}

impl StreamLink {
    /// A link over `reader`/`writer`; a thread splits the incoming bytes into frames.
    pub fn new(reader: impl Read + Send + 'static, writer: impl Write + Send + 'static) -> Self {
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            let mut reader = reader;
            let mut fr = FrameReader::new();
            let mut buf = [0u8; 8192];
            loop {
                let n = match reader.read(&mut buf) {
                    // A serial port's read timeout, or a signal: nothing yet.
                    Err(e) if matches!(e.kind(), ErrorKind::TimedOut | ErrorKind::Interrupted) => {
                        continue
                    }
                    Ok(0) | Err(_) => return,
                    Ok(n) => n,
                };
                for &b in &buf[..n] {
                    if let Some(Ok(f)) = fr.push(b) {
                        if tx.send(f.to_vec()).is_err() {
                            return;
                        }
                    }
                }
            }
        });
        StreamLink {
            writer: Arc::new(Mutex::new(Box::new(writer))),
            frames: rx,
            child: None,
            seq: 0,
            timeout: Duration::from_secs(5),
            max_retries: 5,
            faults: LinkFaults::default(),
            stats: LinkStats::default(),
        }
    }

    /// Spawns `cmd` and talks to it over its stdin/stdout (stderr is passed through).
    pub fn spawn(mut cmd: Command) -> Result<Self> {
        let what = format!("{:?}", cmd.get_program());
        let mut child = cmd
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .map_err(|e| Error::Firmware(format!("cannot start {what}: {e}")))?;
        let pipe = |p: &str| Error::Firmware(format!("{what} has no {p} pipe"));
        let stdin = child.stdin.take().ok_or_else(|| pipe("stdin"))?;
        let stdout = child.stdout.take().ok_or_else(|| pipe("stdout"))?;
        let mut link = StreamLink::new(stdout, stdin);
        link.child = Some(child);
        Ok(link)
    }

    /// Opens a serial device (a board's UART or USB CDC port, a pty) at `baud`, 8N1, raw
    /// (no echo, no CR/LF translation), exclusive, with stale input discarded.
    pub fn serial(path: &str, baud: u32) -> Result<Self> {
        let fail = |e: serialport::Error| Error::Firmware(format!("serial port {path}: {e}"));
        let port = serialport::new(path, baud)
            .timeout(Duration::from_secs(1))
            .open()
            .map_err(fail)?;
        port.clear(serialport::ClearBuffer::All).map_err(fail)?;
        let writer = port.try_clone().map_err(fail)?;
        Ok(StreamLink::new(port, writer))
    }

    fn send(&self, frame: &[u8], late: bool) -> Result<()> {
        if late {
            let w = Arc::clone(&self.writer);
            let frame = frame.to_vec();
            let delay = self.timeout.mul_f64(1.5);
            std::thread::spawn(move || {
                std::thread::sleep(delay);
                if let Ok(mut w) = w.lock() {
                    let _ = w.write_all(&frame).and_then(|_| w.flush());
                }
            });
            return Ok(());
        }
        let mut w = self
            .writer
            .lock()
            .map_err(|_| Error::Firmware("the link's writer is poisoned".into()))?;
        w.write_all(frame)
            .and_then(|_| w.flush())
            .map_err(|e| Error::Firmware(format!("link write failed: {e}")))
    }

    fn exchange(&mut self, req: &Request) -> Result<Response> {
        self.seq += 1;
        let seq = self.seq;
        let env = Envelope {
            version: VERSION,
            seq,
            msg: req.clone(),
        };
        let mut frame = [0u8; MAX_FRAME];
        let len = protocol::encode(&env, &mut frame)
            .map_err(|e| Error::Firmware(format!("cannot encode request {seq}: {e:?}")))?;
        let n = seq as u64;
        let f = self.faults;
        for attempt in 0..=self.max_retries {
            if attempt > 0 {
                self.stats.retries += 1;
            }
            let first = attempt == 0;
            if first && LinkFaults::hits(f.drop_request, n) {
                // Lost on the way.
            } else if first && LinkFaults::hits(f.corrupt_request, n) {
                let mut bad = frame[..len].to_vec();
                bad[len / 2] ^= if bad[len / 2] == 0x55 { 0xAA } else { 0x55 };
                if bad[len / 2] == 0 {
                    bad[len / 2] = 0x01;
                }
                self.send(&bad, false)?;
            } else {
                self.send(&frame[..len], first && LinkFaults::hits(f.late_request, n))?;
            }
            let deadline = Instant::now() + self.timeout;
            loop {
                let left = deadline.saturating_duration_since(Instant::now());
                let mut bytes = match self.frames.recv_timeout(left) {
                    Ok(b) => b,
                    Err(RecvTimeoutError::Timeout) => {
                        self.stats.timeouts += 1;
                        break;
                    }
                    Err(RecvTimeoutError::Disconnected) => {
                        return Err(Error::Firmware(format!("the link closed (request {seq})")))
                    }
                };
                if first && LinkFaults::hits(f.corrupt_reply, n) && !bytes.is_empty() {
                    let k = bytes.len() / 2;
                    bytes[k] ^= 0x10;
                }
                match protocol::decode::<Response>(&bytes) {
                    Err(_) => {
                        self.stats.corrupt_replies += 1;
                        break;
                    }
                    Ok(r) if r.msg == Response::Nack(Nack::Corrupt) => {
                        self.stats.nacks += 1;
                        break;
                    }
                    Ok(r) if r.seq == seq => {
                        self.stats.exchanges += 1;
                        return Ok(r.msg);
                    }
                    Ok(_) => self.stats.stale_replies += 1,
                }
            }
        }
        Err(Error::Firmware(format!(
            "no valid reply to request {seq} after {} retries",
            self.max_retries
        )))
    }
}

impl Link for StreamLink {
    fn call(&mut self, req: Request) -> Result<Response> {
        let t = Instant::now();
        let r = self.exchange(&req);
        self.stats.seconds += t.elapsed().as_secs_f64();
        r
    }
    fn stats(&self) -> LinkStats {
        self.stats
    }
}

impl Drop for StreamLink {
    fn drop(&mut self) {
        if let Some(mut c) = self.child.take() {
            // Closing stdin ends the firmware process; QEMU needs to be stopped.
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

/// Serves the protocol over a byte stream until it closes or fails: the boards' serial loop
/// ([`maglev_firmware_sim::server::serve`]), for tests that run the firmware on a thread
/// behind a socket.
pub fn serve(reader: impl Read, writer: impl Write) {
    let mut server = Box::new(Server::new());
    let _ = server::serve(&mut server, &mut StdPort { reader, writer });
}
