//! UART0 of mps2-an386 (an ARM CMSDK APB UART at `0x4000_4000`) as a blocking byte stream:
//! the link the wire protocol runs over in QEMU (docs/hil.md, "UART link").
//!
//! `write` waits while the one-byte transmit holding register is full, `read` waits for a
//! received byte. In QEMU the UART is connected to the host by `-serial …` (`-serial stdio`, or
//! a socket chardev); its baud rate has no effect there, so the divider is only set to the
//! hardware minimum of 16.
//!
//! Two ways to wait for a received byte:
//!
//! * [`CmsdkUart::uart0`]: polled. The core spins on the STATE register.
//! * [`CmsdkUart::uart0_wfi`]: the core sleeps in `wfi` until the UART's RX interrupt is
//!   pending. Interrupts stay masked (PRIMASK), so no handler runs: the interrupt is only a
//!   wake-up. A spinning core keeps a host CPU busy in QEMU (and takes QEMU's big lock on every
//!   status read); a sleeping one costs nothing between requests and is woken by the byte
//!   itself. The link rate stays the same either way (measured, docs/hil.md "Link speed"): the
//!   UART holds one byte and QEMU hands over the next only after a round trip between its I/O
//!   thread and the vCPU thread, whoever reads DATA and however fast.
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
const CTRL_RX_INTEN: u32 = 1 << 3;
const INTSTATUS: usize = 0x0C;
const INTSTATUS_RX: u32 = 1 << 1;

/// UART0's receive interrupt on mps2-an385/an386 (QEMU `hw/arm/mps2.c`: RX = 0, TX = 1).
pub const UART0_RX_IRQ: u16 = 0;

/// An NVIC interrupt line by number (the images have no device crate).
#[derive(Clone, Copy)]
struct Irq(u16);

// SAFETY: `number` returns a valid external interrupt number of the board (below 32 on
// mps2-an386), always the same for a value.
unsafe impl cortex_m::interrupt::InterruptNumber for Irq {
    fn number(self) -> u16 {
        self.0
    }
}

/// A CMSDK APB UART.
pub struct CmsdkUart {
    base: usize,
    /// The RX interrupt that wakes `wfi` (None: polled).
    wake: Option<Irq>,
}

impl CmsdkUart {
    /// UART0 of mps2-an386, enabled for transmit and receive.
    ///
    /// # Safety
    /// The caller owns UART0: no other code may touch its registers while this value lives.
    pub unsafe fn uart0() -> Self {
        let u = CmsdkUart {
            base: UART0_BASE,
            wake: None,
        };
        u.wr(BAUDDIV, 16);
        u.wr(CTRL, CTRL_TX_EN | CTRL_RX_EN);
        u
    }

    /// UART0 of mps2-an386, receiving by sleeping in `wfi` until a byte is there.
    ///
    /// Masks interrupts (PRIMASK) for good and enables UART0's RX interrupt in the UART and the
    /// NVIC: a pending interrupt wakes `wfi` even while masked, and no handler ever runs.
    ///
    /// # Safety
    /// As [`CmsdkUart::uart0`]; besides, the image must not rely on interrupt handlers.
    pub unsafe fn uart0_wfi() -> Self {
        cortex_m::interrupt::disable();
        let irq = Irq(UART0_RX_IRQ);
        let u = CmsdkUart {
            base: UART0_BASE,
            wake: Some(irq),
        };
        u.wr(BAUDDIV, 16);
        u.wr(INTSTATUS, INTSTATUS_RX);
        cortex_m::peripheral::NVIC::unpend(irq);
        u.wr(CTRL, CTRL_TX_EN | CTRL_RX_EN | CTRL_RX_INTEN);
        // SAFETY: PRIMASK is set above and never cleared, so unmasking cannot start a handler.
        unsafe { cortex_m::peripheral::NVIC::unmask(irq) };
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

    /// Receives one byte, waiting for it (spinning, or asleep in `wfi`).
    pub fn read_byte(&mut self) -> u8 {
        loop {
            if let Some(b) = self.try_read_byte() {
                return b;
            }
            if self.wake.is_some() {
                // A byte that arrived since the check above left the interrupt pending, and a
                // pending interrupt ends `wfi` at once: no byte is slept through.
                cortex_m::asm::wfi();
            }
        }
    }

    /// A received byte, if one is waiting.
    pub fn try_read_byte(&mut self) -> Option<u8> {
        if self.rd(STATE) & STATE_RX_FULL == 0 {
            return None;
        }
        if let Some(irq) = self.wake {
            // Acknowledge before reading DATA: reading frees the holding register, and the
            // next byte (which QEMU may deliver at once) must raise the interrupt anew.
            self.wr(INTSTATUS, INTSTATUS_RX);
            cortex_m::peripheral::NVIC::unpend(irq);
        }
        Some(self.rd(DATA) as u8)
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
