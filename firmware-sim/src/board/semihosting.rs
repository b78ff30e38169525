//! Semihosting glue for the QEMU images: text output (QEMU's stdout with
//! `-semihosting-config enable=on,target=native`), exit with a status, and a panic report
//! that exits non-zero so a failing image fails CI instead of hanging.
use core::fmt::{self, Write};
use cortex_m_semihosting::{debug, hio};

/// Semihosting stdout as a `core::fmt::Write` sink.
pub struct Stdout(hio::HostStream);

impl Stdout {
    /// Opens the host's stdout (`None` if semihosting is not enabled).
    pub fn open() -> Option<Self> {
        hio::hstdout().ok().map(Stdout)
    }
}

impl Write for Stdout {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        self.0.write_all(s.as_bytes()).map_err(|_| fmt::Error)
    }
}

/// Ends the QEMU run with exit status 0 (`ok`) or 1.
pub fn exit(ok: bool) -> ! {
    debug::exit(if ok {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    #[allow(clippy::empty_loop)]
    loop {}
}

/// Body of the images' `#[panic_handler]` (each image declares its own, so linking this
/// library never imposes one): reports the panic and exits non-zero.
pub fn panic(info: &core::panic::PanicInfo) -> ! {
    if let Some(mut out) = Stdout::open() {
        let _ = writeln!(out, "panic: {info}");
    }
    exit(false)
}
