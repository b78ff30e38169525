//! QEMU self-test image for lm3s6965evb run as a Cortex-M0 (`thumbv6m-none-eabi`, no FPU, no
//! 64-bit multiply): the canned gap trace through the controller in I4F28 only, instruction
//! counts per update, output over semihosting, then exit. Diffed against `golden/qemu-m0.txt`.
//!
//! `cargo run --release --target thumbv6m-none-eabi -p maglev-firmware-sim --bin qemu-m0`
//! (runner in `.cargo/config.toml`; docs/hil.md). On the host it prints the same trace lines
//! without counts.
#![cfg_attr(target_os = "none", no_std, no_main)]

use core::fmt::Write;
use maglev_core::scalar::I4F28;
use maglev_firmware_sim::board::car_tick;
use maglev_firmware_sim::board::selftest::{call_cost, op_costs, report, run, Config, Measure};
use maglev_firmware_sim::protocol::LawKind;

/// Instruction budget per fixed-point update without the internal loop (issue 4, item 5).
const BUDGET_FIXED: u32 = 250;

fn selftest<W: Write, M: Measure>(w: &mut W, m: &M) -> core::fmt::Result {
    let mut counts = [None; 2];
    for (i, cfg) in Config::ALL.into_iter().enumerate() {
        counts[i] = run::<I4F28, _, _>(w, m, cfg)?;
    }
    for (i, cfg) in Config::ALL.into_iter().enumerate() {
        report::<I4F28, _>(w, cfg, counts[i], BUDGET_FIXED)?;
    }
    call_cost::<I4F28, _, _>(w, m)?;
    op_costs::<I4F28, _, _>(w, m)?;
    // The car on a 48 MHz Cortex-M0 (STM32F0-class: 1 flash wait state, 2-cycle loads, 3-cycle taken branches: 1.5 cycles per insn assumed).
    car_tick::report::<I4F28, _, _>(
        w,
        m,
        f64::INFINITY,
        (LawKind::Paper, None),
        "paper",
        48,
        150,
    )?;
    Ok(())
}

#[cfg(target_os = "none")]
#[cortex_m_rt::entry]
fn main() -> ! {
    use maglev_firmware_sim::board::{icount::Counter, semihosting};
    let Some(mut out) = semihosting::Stdout::open() else {
        semihosting::exit(false)
    };
    let cp = cortex_m::Peripherals::take().expect("first take");
    let counter = Counter::calibrate(cp.SYST);
    let check = counter.check();
    let ok = writeln!(out, "maglev qemu self-test: lm3s6965evb, cortex-m0, i4f28").is_ok()
        && counter.header(&mut out, check).is_ok()
        && selftest(&mut out, &counter).is_ok();
    semihosting::exit(ok && check == Some(400))
}

maglev_firmware_sim::semihosting_panic_handler!();

#[cfg(not(target_os = "none"))]
fn main() {
    let mut s = String::new();
    selftest(&mut s, &maglev_firmware_sim::board::selftest::NoCount).expect("format");
    print!("{s}");
}
