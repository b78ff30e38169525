//! The wire protocol (`maglev_firmware_sim::server::Server`) served over semihosting host files
//! on mps2-an386 (`thumbv7em-none-eabihf`): `maglev hil --firmware qemu --qemu-link semihosting`.
//!
//! The image opens `/dev/stdin` and `/dev/stdout` through semihosting (QEMU runs with
//! `-semihosting-config enable=on,target=native -serial null`, so only this image reads its
//! stdin) and moves whole buffers per trap: a request of ~220 bytes arrives in one `read`, a
//! reply leaves in one `write`. Over UART0 (`qemu-m4-server`) every byte costs a hand-over
//! between QEMU's I/O and vCPU threads, which bounds that link at ~150 exchanges/s here; this
//! one runs at the speed of the firmware under QEMU (docs/hil.md, "Link speed"). The host sees
//! the same byte stream on QEMU's stdin/stdout either way, carrying nothing but frames.
//!
//! Semihosting is a debugger feature: on a real board it is slow, and the UART image is the one
//! that would run there. At end of file on stdin (the host closed the link) the image exits.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(target_os = "none")]
#[cortex_m_rt::entry]
fn main() -> ! {
    use maglev_firmware_sim::board::semihosting::{exit, HostFile};
    use maglev_firmware_sim::protocol::MAX_FRAME;
    use maglev_firmware_sim::server::Server;
    let (Some(mut input), Some(mut output)) = (
        HostFile::open(c"/dev/stdin", false),
        HostFile::open(c"/dev/stdout", true),
    ) else {
        exit(false)
    };
    let mut server = Server::new();
    let mut frame = [0u8; MAX_FRAME];
    let mut buf = [0u8; MAX_FRAME];
    loop {
        let n = input.read(&mut buf);
        if n == 0 {
            exit(true);
        }
        for &b in &buf[..n] {
            if let Some(len) = server.push_byte(b, &mut frame) {
                if !output.write_all(&frame[..len]) {
                    exit(false);
                }
            }
        }
    }
}

maglev_firmware_sim::semihosting_panic_handler!();

maglev_firmware_sim::bare_metal_only!("qemu-m4-server-semi");
