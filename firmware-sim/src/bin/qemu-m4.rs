//! QEMU self-test image for mps2-an386 (Cortex-M4F, `thumbv7em-none-eabihf`): the canned gap
//! trace through the controller in f32 (hardware FPU) and in I4F28, instruction counts per
//! update, output over semihosting, then exit. Diffed against `golden/qemu-m4.txt` in CI.
//!
//! `cargo run --release --target thumbv7em-none-eabihf -p maglev-firmware-sim --bin qemu-m4`
//! (runner in `.cargo/config.toml`; docs/hil.md). On the host it prints the same trace lines
//! without counts.
#![cfg_attr(target_os = "none", no_std, no_main)]

use core::fmt::Write;
use maglev_core::scalar::I4F28;
use maglev_firmware_sim::board::selftest::{
    call_cost, law_type_cost, op_costs, report, run, Config, Measure,
};
use maglev_firmware_sim::board::{car_tick, lower_bound, state_law};
use maglev_firmware_sim::protocol::LawKind;

/// Instruction budgets per update without the internal loop (issue 4, item 5).
const BUDGET_F32: u32 = 60;
const BUDGET_FIXED: u32 = 250;
/// The state law's update, f32, net of the harness (issue 26, point 7).
const BUDGET_STATE_F32: u32 = 150;

fn selftest<W: Write, M: Measure>(w: &mut W, m: &M) -> core::fmt::Result {
    let mut counts = [None; 4];
    for (i, cfg) in Config::ALL.into_iter().enumerate() {
        counts[i] = run::<f32, _, _>(w, m, cfg)?;
        counts[2 + i] = run::<I4F28, _, _>(w, m, cfg)?;
    }
    for (i, cfg) in Config::ALL.into_iter().enumerate() {
        report::<f32, _>(w, cfg, counts[i], BUDGET_F32)?;
        report::<I4F28, _>(w, cfg, counts[2 + i], BUDGET_FIXED)?;
    }
    law_type_cost::<f32, _, _>(w, m, Config::Paper)?;
    law_type_cost::<I4F28, _, _>(w, m, Config::Paper)?;
    call_cost::<f32, _, _>(w, m)?;
    call_cost::<I4F28, _, _>(w, m)?;
    op_costs::<f32, _, _>(w, m)?;
    op_costs::<I4F28, _, _>(w, m)?;
    if !lower_bound::compare(w, m)? {
        return Err(core::fmt::Error); // fails the image: the experiment no longer matches
    }
    // The car on one MCU: a 168 MHz STM32F4-class Cortex-M4F, 2 cycles per instruction.
    let paper = (LawKind::Paper, None);
    car_tick::report::<f32, _, _>(w, m, f64::INFINITY, paper, "paper", 168, 200)?;
    car_tick::report::<I4F28, _, _>(w, m, f64::INFINITY, paper, "paper", 168, 200)?;
    car_tick::report::<f32, _, _>(w, m, 200.0, paper, "v_max=200V", 168, 200)?;
    // The state law (issue 26): one update, and the car's tick with 4 accelerometers.
    state_law::report::<f32, _, _>(w, m, BUDGET_STATE_F32)?;
    let state = LawKind::State(state_law::gains());
    car_tick::report::<f32, _, _>(w, m, f64::INFINITY, (state, None), "state", 168, 200)?;
    // The guidance law (issue 39): 4 levitation channels and 4 guidance pairs, 8 accelerometers.
    let guided = (state, Some(state_law::guidance_gains()));
    car_tick::report::<f32, _, _>(w, m, f64::INFINITY, guided, "state+guidance", 168, 200)?;
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
    let ok = writeln!(
        out,
        "maglev qemu self-test: mps2-an386, cortex-m4, f32 + i4f28"
    )
    .is_ok()
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
