//! Bare-metal boards for the QEMU images (`src/bin/qemu-*.rs`; docs/hil.md).
//!
//! * [`selftest`]: the canned gap trace run through the core controller and printed
//!   deterministically (exact bits in hex); platform-neutral, so it builds on the host too.
//! * [`car_tick`]: one control tick of the 12 channels of a Fig. 1 car, against a clock budget.
//! * [`lower_bound`]: the f32 step without the core's checks, to show what bounds the count.
//! * [`state_law`]: one update of the state law (gap + accelerometer), counted.
//! * `icount` (bare metal only): instructions per call, measured with SysTick under QEMU's
//!   `-icount` (QEMU models no cycle counter).
//! * `cmsdk_uart` (bare metal only): UART0 of mps2-an386 as a blocking byte stream
//!   (embedded-io `Read`/`Write`), the link the wire protocol runs over.
//! * `semihosting` (bare metal only): text output, exit codes and the panic handler.
pub mod car_tick;
pub mod lower_bound;
pub mod selftest;
pub mod state_law;

#[cfg(target_os = "none")]
pub mod cmsdk_uart;
#[cfg(target_os = "none")]
pub mod icount;
#[cfg(target_os = "none")]
pub mod semihosting;

/// The panic handler of the QEMU images: report over semihosting and exit with failure.
#[macro_export]
macro_rules! semihosting_panic_handler {
    () => {
        #[cfg(target_os = "none")]
        #[panic_handler]
        fn panic(info: &core::panic::PanicInfo) -> ! {
            $crate::board::semihosting::panic(info)
        }
    };
}

/// The host `main` of an image that only makes sense on bare metal (so `cargo build` and
/// `cargo test --workspace` on the host still compile every binary).
#[macro_export]
macro_rules! bare_metal_only {
    ($name:literal) => {
        #[cfg(not(target_os = "none"))]
        fn main() {
            println!(concat!(
                $name,
                " is a bare-metal image: build it for thumbv7em-none-eabihf (docs/hil.md)"
            ));
        }
    };
}
