//! The wire protocol (`maglev_firmware_sim::server::Server`) served over UART0 of mps2-an386
//! (`thumbv7em-none-eabihf`): the image of `maglev hil --firmware qemu` (the default
//! `--qemu-link uart`). Every received byte goes to `Server::push_byte`, every reply frame
//! back out; nothing else is ever written to the UART.
//!
//! The core sleeps in `wfi` between bytes (`CmsdkUart::uart0_wfi`) instead of spinning on the
//! status register, so QEMU idles at no CPU cost while the host computes the plant. The link
//! rate is bounded by QEMU, not by the image: the UART holds one byte, and QEMU hands over the
//! next one only after a round trip between its I/O thread and the vCPU thread (docs/hil.md,
//! "Link speed"). `qemu-m4-server-semi` is the same server over semihosting, which is faster.
//!
//! Run it with UART0 on a plain channel (`-monitor none -serial stdio`, never `-nographic`
//! alone: its `mon:stdio` mux eats 0x01 bytes).
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(target_os = "none")]
#[cortex_m_rt::entry]
fn main() -> ! {
    use embedded_io::Write as _;
    use maglev_firmware_sim::board::cmsdk_uart::CmsdkUart;
    use maglev_firmware_sim::protocol::MAX_FRAME;
    use maglev_firmware_sim::server::Server;
    // SAFETY: the only user of UART0 in this image, which has no interrupt handlers.
    let mut uart = unsafe { CmsdkUart::uart0_wfi() };
    let mut server = Server::new();
    let mut frame = [0u8; MAX_FRAME];
    loop {
        let b = uart.read_byte();
        if let Some(len) = server.push_byte(b, &mut frame) {
            let _ = uart.write_all(&frame[..len]);
        }
    }
}

maglev_firmware_sim::semihosting_panic_handler!();

maglev_firmware_sim::bare_metal_only!("qemu-m4-server");
