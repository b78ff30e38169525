//! The firmware as a host process: the protocol over stdin (requests) and stdout (replies),
//! or over a serial device with `--serial PATH [--baud N]` (a pty, a USB-serial adapter).
//! The host's `maglev hil --firmware process` spawns it; `--firmware serial:PATH` talks to it
//! (or to a board) over a serial line. Either way it runs the boards' loop,
//! `maglev_firmware_sim::server::serve`. Logs go to stderr only.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(not(target_os = "none"))]
const USAGE: &str = "usage: maglev-firmware [--serial PATH [--baud N]]";

/// `--serial PATH` and `--baud N` (default 115200), or a one-line error.
#[cfg(not(target_os = "none"))]
fn parse(args: &[String]) -> Result<Option<(String, u32)>, String> {
    let (mut path, mut baud) = (None, None);
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut value = || it.next().ok_or(format!("{a} needs a value; {USAGE}"));
        match a.as_str() {
            "--serial" => path = Some(value()?.clone()),
            "--baud" => {
                let v = value()?;
                match v.parse::<u32>() {
                    Ok(b) if b > 0 => baud = Some(b),
                    _ => return Err(format!("--baud {v}: expected a whole number ≥ 1")),
                }
            }
            _ => return Err(format!("unknown argument `{a}`; {USAGE}")),
        }
    }
    match (path, baud) {
        (Some(p), b) => Ok(Some((p, b.unwrap_or(115_200)))),
        (None, Some(_)) => Err("--baud needs --serial PATH".into()),
        (None, None) => Ok(None),
    }
}

#[cfg(not(target_os = "none"))]
fn main() -> std::process::ExitCode {
    use maglev_firmware_sim::host_io::StdPort;
    use maglev_firmware_sim::server::{serve, Server};
    use std::process::ExitCode;
    use std::time::Duration;

    let fail = |msg: String| {
        eprintln!("maglev-firmware: error: {msg}");
        ExitCode::from(2)
    };
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut server = Box::new(Server::new());
    let served = match parse(&args) {
        Err(e) => return fail(e),
        Ok(None) => {
            let mut port = StdPort {
                reader: std::io::stdin().lock(),
                writer: std::io::stdout().lock(),
            };
            serve(&mut server, &mut port)
        }
        Ok(Some((path, baud))) => {
            // Raw mode (cfmakeraw: no echo, no CR/LF translation), 8N1, no flow control.
            let opened = serialport::new(&path, baud)
                .timeout(Duration::from_secs(1))
                .open()
                .and_then(|p| Ok((p.try_clone()?, p)));
            let (reader, writer) = match opened {
                Ok(p) => p,
                Err(e) => return fail(format!("--serial {path}: {e}")),
            };
            serve(&mut server, &mut StdPort { reader, writer })
        }
    };
    match served {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("maglev-firmware: link: {}", e.0);
            ExitCode::FAILURE
        }
    }
}

// On bare metal this program has nothing to run: the QEMU image has its own `main`.
#[cfg(target_os = "none")]
#[no_mangle]
pub extern "C" fn _start() -> ! {
    loop {}
}

#[cfg(target_os = "none")]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {}
}
