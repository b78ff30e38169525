//! UART0 of mps2-an386 (an ARM CMSDK APB UART at `0x4000_4000`) as a blocking byte stream:
//! the link the wire protocol runs over in QEMU (docs/hil.md, "UART link").
//!
//! Polled, no interrupts: `write` waits while the one-byte transmit holding register is full,
//! `read` waits for a received byte. In QEMU the UART is connected to the host by `-serial …`
//! (`-serial stdio`, or a socket chardev); its baud rate has no effect there, so the divider is
//! only set to the hardware minimum of 16.
use core::convert::Infallible;
use core::ptr::{read_volatile, write_volatile};

/// Base address of UART0 on mps2-an385/an386 (QEMU `hw/arm/mps2.c`).
pub const UART0_BASE: usize = 0x4000_4000;

const DATA: usize = 0x00;
const STATE: usize = 0x04;
const CTRL: usize = 0x08;
const BAUDDIV: usize = 0x10;
const STATE_TX_FULL: u32 = 1 << 0;
const STATE_RX_FULL: u32 = 1 << 1;
const CTRL_TX_EN: u32 = 1 << 0;
const CTRL_RX_EN: u32 = 1 << 1;

/// A CMSDK APB UART, polled.
pub struct CmsdkUart {
    base: usize,
}

impl CmsdkUart {
    /// UART0 of mps2-an386, enabled for transmit and receive.
    ///
    /// # Safety
    /// The caller owns UART0: no other code may touch its registers while this value lives.
    pub unsafe fn uart0() -> Self {
        let u = CmsdkUart { base: UART0_BASE };
        u.wr(BAUDDIV, 16);
        u.wr(CTRL, CTRL_TX_EN | CTRL_RX_EN);
        u
    }

    fn rd(&self, off: usize) -> u32 {
        // SAFETY: an aligned device register of the UART this value owns.
        unsafe { read_volatile((self.base + off) as *const u32) }
    }

    fn wr(&self, off: usize, v: u32) {
        // SAFETY: as in `rd`.
        unsafe { write_volatile((self.base + off) as *mut u32, v) }
    }

    /// Sends one byte, waiting for room.
    pub fn write_byte(&mut self, b: u8) {
        while self.rd(STATE) & STATE_TX_FULL != 0 {}
        self.wr(DATA, b as u32);
    }

    /// Receives one byte, waiting for it.
    pub fn read_byte(&mut self) -> u8 {
        while self.rd(STATE) & STATE_RX_FULL == 0 {}
        self.rd(DATA) as u8
    }

    /// A received byte, if one is waiting.
    pub fn try_read_byte(&mut self) -> Option<u8> {
        (self.rd(STATE) & STATE_RX_FULL != 0).then(|| self.rd(DATA) as u8)
    }
}

impl embedded_io::ErrorType for CmsdkUart {
    type Error = Infallible;
}

impl embedded_io::Read for CmsdkUart {
    /// Blocks for the first byte, then takes whatever else is already waiting.
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Infallible> {
        let Some((first, rest)) = buf.split_first_mut() else {
            return Ok(0);
        };
        *first = self.read_byte();
        let mut n = 1;
        for slot in rest {
            match self.try_read_byte() {
                Some(b) => *slot = b,
                None => break,
            }
            n += 1;
        }
        Ok(n)
    }
}

impl embedded_io::Write for CmsdkUart {
    fn write(&mut self, buf: &[u8]) -> Result<usize, Infallible> {
        for &b in buf {
            self.write_byte(b);
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> Result<(), Infallible> {
        Ok(())
    }
}
