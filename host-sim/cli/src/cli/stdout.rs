//! Standard output, for every command that prints: writes that fail are errors, never panics.
//!
//! Why one helper: `print!` panics when stdout is closed or full (`maglev stability >
//! /dev/full`, `maglev modes | (exec 0<&-; …)`). Every command writes through [`print`] or
//! [`writer`] and maps a failed write with [`error`] to [`Error::Io`] on `stdout`; `main`
//! then ends quietly when the reader went away ([`is_broken_pipe`]: the reader asked for no
//! more, as `head` does) and with one line and a non-zero status for any other failure.

use crate::{Error, Result};
use std::io::{BufWriter, StdoutLock, Write};

/// A failed write to stdout as the library's error.
pub fn error(e: std::io::Error) -> Error {
    Error::io("stdout", e)
}

/// Writes `text` to stdout and flushes it.
pub fn print(text: &str) -> Result<()> {
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(error)
}

/// Stdout buffered in writes of 64 KiB, for output streamed as it is made (map each write's
/// error with [`error`], and flush at the end).
pub fn writer() -> BufWriter<StdoutLock<'static>> {
    BufWriter::with_capacity(1 << 16, std::io::stdout().lock())
}

/// Whether `e` is (or was caused by) a write to a pipe whose reader has gone.
pub fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_broken_pipe_is_told_from_other_write_errors() {
        let broken = std::io::Error::from(std::io::ErrorKind::BrokenPipe);
        let full = std::io::Error::from_raw_os_error(28);
        assert!(is_broken_pipe(&anyhow::Error::from(error(broken))));
        let e = anyhow::Error::from(error(full));
        assert!(!is_broken_pipe(&e));
        assert!(e.to_string().starts_with("stdout: "), "{e}");
    }
}
