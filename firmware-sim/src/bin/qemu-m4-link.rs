//! UART link skeleton for mps2-an386 (`thumbv7em-none-eabihf`): serves UART0 as a blocking
//! byte stream (`board::cmsdk_uart`, embedded-io `Read`/`Write`) and, until the wire protocol
//! is dropped in, echoes every byte back. A 0x04 (EOT) byte ends the session: the image
//! reports the bytes served over semihosting and exits. CI pipes a line through it.
//!
//! Run it with UART0 on a plain (non-multiplexed) channel, never `-nographic` alone (its
//! default `mon:stdio` mux eats 0x01 bytes); see docs/hil.md, "UART link":
//! `qemu-system-arm -machine mps2-an386 -cpu cortex-m4 -display none -monitor none
//!  -serial stdio -semihosting-config enable=on,target=native -kernel <elf>`.
#![cfg_attr(target_os = "none", no_std, no_main)]

/// Ends the echo session.
pub const EOT: u8 = 0x04;

#[cfg(target_os = "none")]
#[cortex_m_rt::entry]
fn main() -> ! {
    use core::fmt::Write;
    use embedded_io::{Read, Write as _};
    use maglev_firmware_sim::board::{cmsdk_uart::CmsdkUart, semihosting};
    // SAFETY: the only user of UART0 in this image.
    let mut uart = unsafe { CmsdkUart::uart0() };
    let mut served = 0usize;
    let mut buf = [0u8; 64];
    'session: loop {
        let Ok(n) = uart.read(&mut buf);
        for i in 0..n {
            if buf[i] == EOT {
                let _ = uart.write_all(&buf[..i]);
                served += i;
                break 'session;
            }
        }
        let _ = uart.write_all(&buf[..n]);
        served += n;
    }
    let ok = match semihosting::Stdout::open() {
        Some(mut out) => writeln!(out, "\nuart0: echoed {served} bytes").is_ok(),
        None => false,
    };
    semihosting::exit(ok)
}

maglev_firmware_sim::semihosting_panic_handler!();

maglev_firmware_sim::bare_metal_only!("qemu-m4-link");
