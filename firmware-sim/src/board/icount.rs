//! Instructions per call, measured in QEMU.
//!
//! QEMU models no cycle counter (DWT.CYCCNT reads zero, and even timing-accurate cores would
//! not be modelled). Under `-icount shift=N` QEMU's virtual clock instead advances exactly
//! 2^N ns per executed guest instruction, and a device read (here SysTick's current value,
//! clocked from the core clock) is performed at an exact instruction boundary. So the SysTick
//! ticks elapsed between two reads are proportional to the instructions executed between them.
//!
//! The ratio is not taken on trust: [`Counter::calibrate`] times calls of a 1000-`nop` and a
//! 100-`nop` block (same call overhead, so the difference is exactly 900 instructions) and the
//! cost of an empty measurement window; every count is
//! `round((ticks − empty)·900 / (ticks_1000 − ticks_100))`. [`Counter::check`] then counts a
//! 500-`nop` block against the 100 one (must differ by 400). The board clocks differ (25 MHz
//! on mps2-an386: 25.6 ticks per instruction at `shift=10`); with ≥ 12 ticks per instruction
//! the ±1-tick quantisation of each read cannot change a rounded count. SysTick is 24-bit: one
//! measurement must stay below 2^24 ticks (over 600 000 instructions).
//!
//! A count is the instructions of the measured closure minus those of an empty one (whose
//! body is a bare return): for the controller, the closure's loads of its captures, argument
//! set-up, `bl`, the update's prologue, body and epilogue (docs/hil.md lists the few
//! instructions that are not the update itself).
use cortex_m::peripheral::{syst::SystClkSource, SYST};

/// SysTick-based instruction counter (see the module docs).
pub struct Counter {
    empty: u32,
    /// Ticks of 900 instructions.
    per_900: u32,
}

const MASK: u32 = 0x00FF_FFFF;

/// Ticks spent calling `f`. Every measurement — calibration, empty window, the controller —
/// goes through this one function, so the window around the call is the same code each time
/// (SysTick counts down; its 24-bit wrap-around is handled).
#[inline(never)]
fn ticks(f: &mut dyn FnMut()) -> u32 {
    let t0 = SYST::get_current();
    f();
    let t1 = SYST::get_current();
    t0.wrapping_sub(t1) & MASK
}

macro_rules! nop_block {
    ($name:ident, $n:literal) => {
        #[inline(never)]
        fn $name() {
            // SAFETY: no operands, no memory access, no stack use.
            unsafe {
                core::arch::asm!(
                    concat!(".rept ", $n),
                    "nop",
                    ".endr",
                    options(nomem, nostack)
                )
            }
        }
    };
}
nop_block!(nops_100, 100);
nop_block!(nops_500, 500);
nop_block!(nops_1000, 1000);

impl Counter {
    /// Starts SysTick on the core clock, free-running over its full 24-bit range, and
    /// calibrates against `nop` blocks.
    pub fn calibrate(mut syst: SYST) -> Self {
        syst.disable_interrupt();
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(MASK);
        syst.clear_current();
        syst.enable_counter();
        let empty = ticks(&mut || ());
        let t100 = ticks(&mut nops_100);
        let t1000 = ticks(&mut nops_1000);
        Counter {
            empty,
            per_900: t1000.saturating_sub(t100),
        }
    }

    /// SysTick ticks per 900 instructions (23 040 at 25 MHz with shift=10); 0 if not running
    /// under `-icount` (then no count is meaningful).
    pub fn ticks_per_900(&self) -> u32 {
        self.per_900
    }

    /// Instructions counted for a call of the 500-`nop` block minus those of the 100 one:
    /// 400 if the calibration holds.
    pub fn check(&self) -> Option<u32> {
        let a = self.count(&mut nops_500)?;
        let b = self.count(&mut nops_100)?;
        Some(a.wrapping_sub(b))
    }

    /// Instructions executed by `f` beyond an empty closure (`None` without a usable
    /// calibration). For a controller update `f` is a closure that calls the
    /// `#[inline(never)]` update on captured references and stores the result: the dynamic
    /// call keeps the compiler from moving work out of the measured window.
    pub fn count(&self, f: &mut dyn FnMut()) -> Option<u32> {
        let t = ticks(f);
        if self.per_900 == 0 {
            return None;
        }
        let n = (t.saturating_sub(self.empty) as u64 * 900 + self.per_900 as u64 / 2)
            / self.per_900 as u64;
        Some(n as u32)
    }
}

impl Counter {
    /// The calibration line of the images' output.
    pub fn header<W: core::fmt::Write>(&self, w: &mut W, check: Option<u32>) -> core::fmt::Result {
        match check {
            Some(n) => writeln!(
                w,
                "icount: {} SysTick ticks per 900 instructions; 500 nops - 100 nops = {n} (want 400)",
                self.per_900
            ),
            None => writeln!(w, "icount: SysTick did not advance; run QEMU with -icount shift=10"),
        }
    }
}

impl crate::board::selftest::Measure for Counter {
    fn count(&self, f: &mut dyn FnMut()) -> Option<u32> {
        Counter::count(self, f)
    }
}
