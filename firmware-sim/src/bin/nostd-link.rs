//! No-std link check: a bare-metal binary that uses the core, with its own panic handler.
//! Built for a thumb target in CI; any `std` dependency anywhere in the core's tree fails it.
//! On the host it builds as an ordinary program so `cargo test --workspace` stays green.
#![cfg_attr(target_os = "none", no_std, no_main)]

use maglev_core::scalar::I4F28;
use maglev_core::{Params, Scalar};

fn exercise() -> i64 {
    let mut p = Params::paper_wheel(1e-3);
    p.n_sub = 10;
    let Ok(ctrl) = p.compile::<I4F28>() else {
        return -1;
    };
    let mut st = ctrl.initial_state(p.h0);
    let mut ov = false;
    let out = ctrl.update(&mut st, I4F28::from_f64(1.05, &mut ov));
    out.force.to_bits() as i64
}

#[cfg(target_os = "none")]
#[no_mangle]
pub extern "C" fn _start() -> ! {
    let v = exercise();
    // Keep the result observable so the call is not optimised away.
    unsafe { core::ptr::write_volatile(core::ptr::addr_of_mut!(SINK), v) };
    loop {
        core::hint::spin_loop();
    }
}

#[cfg(target_os = "none")]
static mut SINK: i64 = 0;

#[cfg(target_os = "none")]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {
        core::hint::spin_loop();
    }
}

#[cfg(not(target_os = "none"))]
fn main() {
    println!("{}", exercise());
}
