//! `maglev hil --firmware serial:PATH` end to end over pseudo-terminals: the `maglev-firmware`
//! process serves one serial device, `maglev hil` opens the other, and the outputs equal
//! `--firmware inproc` byte for byte. `--realtime` on a link that cannot keep the rate fails
//! with one line, exit 2 and no output directory.
//!
//! The "cable" is two pty pairs whose master ends this test joins (what `socat pty,raw
//! pty,raw` does): each program opens a slave end by its path, as it would a board's port.
//! Both slaves are put in raw mode here before either program starts, so no byte is echoed
//! or translated before a program sets raw mode itself (`serialport` does on open).
//!
//! `maglev-firmware` is another package's binary: `cargo test --workspace` builds it next to
//! `maglev` (`cargo build -p maglev-firmware-sim --bin maglev-firmware` otherwise).

use nix::pty::openpty;
use nix::sys::termios::{cfmakeraw, tcgetattr, tcsetattr, SetArg};
use std::fs::File;
use std::io::{Read, Write};
use std::os::fd::{FromRawFd, RawFd};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output};

const MAGLEV: &str = env!("CARGO_BIN_EXE_maglev");

/// One pty pair: the master end (for the cable), the raw slave kept open, its path.
struct Pty {
    master: File,
    _slave: File,
    path: PathBuf,
}

fn pty() -> Pty {
    let p = openpty(None, None).unwrap();
    let mut t = tcgetattr(p.slave).unwrap();
    cfmakeraw(&mut t);
    tcsetattr(p.slave, SetArg::TCSANOW, &t).unwrap();
    let path = std::fs::read_link(format!("/proc/self/fd/{}", p.slave)).unwrap();
    let file = |fd: RawFd| {
        // SAFETY: fresh descriptors from openpty, each owned by exactly one File from here on.
        unsafe { File::from_raw_fd(fd) }
    };
    Pty {
        master: file(p.master),
        _slave: file(p.slave),
        path,
    }
}

/// Copies everything from one master end to the other, until the test process ends.
fn pump(mut from: File, mut to: File) {
    std::thread::spawn(move || {
        let mut buf = [0u8; 4096];
        while let Ok(n) = from.read(&mut buf) {
            if n == 0 || to.write_all(&buf[..n]).is_err() {
                return;
            }
        }
    });
}

/// Two pty pairs joined master to master: a null-modem cable between their slave paths.
fn cable() -> (Pty, Pty) {
    let (a, b) = (pty(), pty());
    pump(a.master.try_clone().unwrap(), b.master.try_clone().unwrap());
    pump(b.master.try_clone().unwrap(), a.master.try_clone().unwrap());
    (a, b)
}

/// `maglev-firmware --serial PATH`, killed when dropped.
struct Firmware(Child);

impl Firmware {
    fn serve(path: &Path) -> Self {
        let prog = Path::new(MAGLEV).with_file_name("maglev-firmware");
        assert!(
            prog.exists(),
            "{} is missing: cargo build -p maglev-firmware-sim --bin maglev-firmware",
            prog.display()
        );
        let child = Command::new(prog)
            .arg("--serial")
            .arg(path)
            .args(["--baud", "115200"])
            .spawn()
            .unwrap();
        Firmware(child)
    }
}

impl Drop for Firmware {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn hil(firmware: &str, out: &Path, extra: &[&str]) -> Output {
    Command::new(MAGLEV)
        .args([
            "hil",
            "paper-4.2",
            "--firmware",
            firmware,
            "--set",
            "t_end=0.06",
        ])
        .args(extra)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

fn read(dir: &Path, name: &str) -> Vec<u8> {
    std::fs::read(dir.join(name)).unwrap()
}

#[test]
fn serial_link_over_a_pty_pair_equals_inproc_byte_for_byte() {
    let tmp = tempdir("equal");
    let inproc = tmp.join("inproc");
    let o = hil("inproc", &inproc, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (fw_end, host_end) = cable();
    let _fw = Firmware::serve(&fw_end.path);
    let serial = tmp.join("serial");
    let spec = format!("serial:{}", host_end.path.display());
    let o = hil(&spec, &serial, &["--baud", "115200"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for name in ["response.csv", "events.csv"] {
        assert!(read(&inproc, name) == read(&serial, name), "{name} differs");
    }
    let summary: serde_json::Value =
        serde_json::from_slice(&read(&serial, "summary.json")).unwrap();
    assert_eq!(summary["firmware"], "serial");
    assert_eq!(summary["link"]["retries"], 0);
    // Config, then a Step per Newton iteration and a Commit per step: 60 steps, ≥ 2 each.
    assert!(summary["link"]["exchanges"].as_u64().unwrap() > 120);
    assert!(summary.get("realtime").is_none());
}

#[test]
fn realtime_on_a_link_too_slow_for_the_rate_fails_without_output() {
    // Every request's first copy is dropped, so each exchange waits out the 20 ms reply timeout
    // before its retransmission is answered: a host step (≥ 2 exchanges) takes ≥ 40 ms against
    // its 1 ms period, and every period misses whatever the machine's load. The timeout is long
    // enough that a loaded machine's firmware process still answers the retransmission within
    // it (at 3 ms, five retries in a row once went unanswered under a parallel build).
    let tmp = tempdir("slow");
    let out = tmp.join("out");
    let (fw_end, host_end) = cable();
    let _fw = Firmware::serve(&fw_end.path);
    let spec = format!("serial:{}", host_end.path.display());
    let slow = [
        "--realtime",
        "--timeout-ms",
        "20",
        "--set",
        "link_fault=drop:1",
    ];
    let o = hil(&spec, &out, &slow);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    let last = err.lines().last().unwrap_or_default();
    assert!(
        last.starts_with("maglev: error: --realtime: 1000 Hz not kept: 40 of 40 periods after"),
        "{err}"
    );
    assert!(
        last.contains("; mean pace ") && last.contains("latency median"),
        "{err}"
    );
    assert!(!out.exists(), "a partial output directory was left");
}

#[test]
fn bad_serial_arguments_are_one_line_errors() {
    let tmp = tempdir("bad");
    let o = hil("serial:", &tmp.join("o"), &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("serial:PATH"));
    let o = hil("serial:/nonexistent/tty", &tmp.join("o"), &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("serial port /nonexistent/tty"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(!tmp.join("o").exists());
    let o = hil("inproc", &tmp.join("o"), &["--baud", "0"]);
    assert_eq!(o.status.code(), Some(2));
    // A baud rate with a mode that has no serial line is refused, not ignored.
    let o = hil("inproc", &tmp.join("o"), &["--baud", "9600"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("--baud: ") && err.lines().count() == 1,
        "{err}"
    );
    assert!(!tmp.join("o").exists());
}

fn tempdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("maglev-hil-serial-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The rate a pty achieves on this machine (docs/hil.md, "Connect a board"): the §4.3
/// passage (speed 100 m/s, 500 steps of 1 ms) over the pty cable, unpaced and with
/// `--realtime` at 1 kHz and at 500 Hz (Δt = 2 ms, 20 ticks per step). A measurement, not a check: it prints, and is run by hand with
/// `cargo test -p maglev --test hil_serial -- --ignored --nocapture pty_rate`.
#[test]
#[ignore = "a measurement; run by hand (docs/hil.md)"]
fn pty_rate() {
    let tmp = tempdir("rate");
    let (fw_end, host_end) = cable();
    let _fw = Firmware::serve(&fw_end.path);
    let spec = format!("serial:{}", host_end.path.display());
    let runs: [(&str, &[&str]); 3] = [
        ("unpaced", &[]),
        ("realtime 1 kHz", &["--realtime"]),
        ("realtime 500 Hz", &["--realtime", "--set", "dt=0.002"]),
    ];
    for (label, extra) in runs {
        let out = tmp.join(label.replace(' ', "-"));
        let o = Command::new(MAGLEV)
            .args([
                "hil",
                "paper-4.2",
                "--firmware",
                &spec,
                "--set",
                "speed=100",
            ])
            .args(extra)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        if !o.status.success() {
            println!("{label}: {}", String::from_utf8_lossy(&o.stderr).trim());
            continue;
        }
        let s: serde_json::Value = serde_json::from_slice(&read(&out, "summary.json")).unwrap();
        println!(
            "{label}: {} exchanges, {:.0}/s in the link, {:.0}/s of wall time; realtime {}",
            s["link"]["exchanges"],
            s["exchanges_per_second"],
            s["exchanges_per_wall_second"],
            s["realtime"]
        );
    }
}
