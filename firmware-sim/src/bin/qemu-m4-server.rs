//! The wire protocol (`maglev_firmware_sim::server::Server`) served over UART0 of mps2-an386
//! (`thumbv7em-none-eabihf`): the image of `maglev hil --firmware qemu` (the default
//! `--qemu-link uart`). It runs the boards' serial loop (`maglev_firmware_sim::server::serve`)
//! on UART0: every received byte goes to `Server::push_byte`, every reply frame back out;
//! nothing else is ever written to the UART.
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
    use maglev_firmware_sim::board::cmsdk_uart::CmsdkUart;
    use maglev_firmware_sim::server::{serve, Server};
    // SAFETY: the only user of UART0 in this image, which has no interrupt handlers.
    let mut uart = unsafe { CmsdkUart::uart0_wfi() };
    let mut server = Server::new();
    // The boards' serial loop; the UART never fails and never ends.
    let Ok(()) = serve(&mut server, &mut uart);
    loop {
        cortex_m::asm::wfi();
    }
}

maglev_firmware_sim::semihosting_panic_handler!();

maglev_firmware_sim::bare_metal_only!("qemu-m4-server");
