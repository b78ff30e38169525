//! The firmware as a host process: the protocol over stdin (requests) and stdout (replies).
//! The host's `maglev hil --firmware process` spawns it. Logs go to stderr only.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    use maglev_firmware_sim::protocol::MAX_FRAME;
    use maglev_firmware_sim::server::Server;
    use std::io::{Read, Write};

    let mut server = Server::new();
    let stdin = std::io::stdin();
    let stdout = std::io::stdout();
    let mut input = stdin.lock();
    let mut output = stdout.lock();
    let mut buf = [0u8; 8192];
    let mut frame = [0u8; MAX_FRAME];
    loop {
        let n = match input.read(&mut buf) {
            Ok(0) => return,
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => {
                eprintln!("maglev-firmware: read: {e}");
                std::process::exit(1);
            }
        };
        for &b in &buf[..n] {
            if let Some(len) = server.push_byte(b, &mut frame) {
                if output.write_all(&frame[..len]).is_err() {
                    return;
                }
            }
        }
        if output.flush().is_err() {
            return;
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
