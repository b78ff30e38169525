//! Semihosting glue for the QEMU images: text output (QEMU's stdout with
//! `-semihosting-config enable=on,target=native`), exit with a status, a panic report
//! that exits non-zero so a failing image fails CI instead of hanging, and host files as a
//! bulk byte stream ([`HostFile`], the fast link of `qemu-m4-server-semi`).
use core::fmt::{self, Write};
use cortex_m_semihosting::{debug, hio, syscall};

/// A host file opened through semihosting (`SYS_OPEN`; with `target=native` QEMU opens the
/// path on the host). Reads and writes move whole buffers in one trap, where a UART moves
/// one byte per device access.
pub struct HostFile(usize);

impl HostFile {
    /// Opens `path` (NUL-terminated) for reading (`write = false`, mode "rb") or writing
    /// (mode "wb"); `None` if semihosting refuses it.
    pub fn open(path: &core::ffi::CStr, write: bool) -> Option<Self> {
        let bytes = path.to_bytes();
        let mode = if write { 5 } else { 1 };
        // SAFETY: SYS_OPEN reads `len` bytes of the NUL-terminated name; no memory is written.
        let fd = unsafe { syscall!(OPEN, bytes.as_ptr(), mode, bytes.len()) };
        (fd as isize >= 0).then_some(HostFile(fd))
    }

    /// Reads at least one byte, blocking until some are there (the host's `read`); 0 at end
    /// of file or on an error.
    pub fn read(&mut self, buf: &mut [u8]) -> usize {
        // SAFETY: SYS_READ writes at most `buf.len()` bytes into `buf`.
        let left = unsafe { syscall!(READ, self.0, buf.as_mut_ptr(), buf.len()) };
        buf.len().saturating_sub(left)
    }

    /// Writes all of `buf`; false on an error.
    pub fn write_all(&mut self, buf: &[u8]) -> bool {
        // SAFETY: SYS_WRITE reads `buf.len()` bytes of `buf`.
        unsafe { syscall!(WRITE, self.0, buf.as_ptr(), buf.len()) == 0 }
    }
}

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
