//! defmt logging demo for mps2-an386 (`thumbv7em-none-eabihf`): the f32 self-test trace of
//! `qemu-m4` (paper magnet, one sub-step), logged through defmt over semihosting — the core's
//! `defmt` feature formats each `Output` — and decoded on the host with `defmt-print`:
//!
//! ```sh
//! cargo build --release -p maglev-firmware-sim --target thumbv7em-none-eabihf --bin qemu-m4-defmt
//! qemu-system-arm -machine mps2-an386 -cpu cortex-m4 -nographic \
//!   -semihosting-config enable=on,target=native -kernel $ELF | defmt-print -e $ELF
//! ```
//!
//! Not part of CI's golden diff (installing defmt-print takes about 9 minutes on the CI
//! machine); CI decodes it only where `defmt-print` is already installed (docs/hil.md).
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(target_os = "none")]
#[cortex_m_rt::entry]
fn main() -> ! {
    use defmt_semihosting as _; // the global logger
    use maglev_core::Scalar;
    use maglev_firmware_sim::board::selftest::{gap, Config, STEPS};
    use maglev_firmware_sim::board::semihosting::exit;

    let p = Config::Paper.params();
    let Ok(ctrl) = p.compile::<f32>() else {
        defmt::error!("paper parameters do not compile for f32");
        exit(false)
    };
    defmt::info!(
        "maglev defmt demo: f32, n_sub = {=u32}, dt = {=f64} s",
        p.n_sub,
        p.dt
    );
    let mut st = ctrl.initial_state(p.h0);
    for k in 1..=STEPS {
        let mut ov = false;
        let h = f32::from_f64(gap(k), &mut ov);
        let out = ctrl.update(&mut st, h);
        defmt::info!("step {=usize} h/h0 = {=f32}: {}", k, h, out);
    }
    defmt::info!("done");
    exit(true)
}

#[cfg(target_os = "none")]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    defmt::error!("panic");
    maglev_firmware_sim::board::semihosting::exit(false)
}

maglev_firmware_sim::bare_metal_only!("qemu-m4-defmt");
