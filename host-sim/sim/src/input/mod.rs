//! Reading the user's input files (scenarios, sweep specs, traces, histories) with a size cap.
//!
//! Why a cap: an input is read whole (or a CSV line at a time) before anything checks it, so
//! `maglev run /dev/zero` or a scenario path that names a huge file would read until memory
//! runs out. Every input this project reads is far smaller than [`MAX_INPUT_BYTES`] (the
//! bundled scenarios are a few kB; a 10⁶-row history is about 40 MB), so a larger one is
//! refused with one line naming the file and the cap.

pub mod case;
pub mod scenario;
pub mod support;

use crate::{Error, Result};
use std::io::Read;
use std::path::Path;

/// The largest input file read: 64 MiB.
pub const MAX_INPUT_BYTES: u64 = 64 << 20;

/// The largest TOML text parsed (a scenario, a sweep spec): 4 MiB. TOML is parsed whole into a
/// tree before anything reads it, and the tree costs far more than its text: a value of two
/// bytes (`1,` in an array) takes a tree node of tens of bytes and a share of its array's
/// spare capacity, and the overrides' pass copies the tree once more: a 60 MB array of
/// integers took 4.5 GB of RSS and 65 s (docs/scenarios.md, "Input size"). At the measured
/// worst, [`TOML_COST`] bytes per byte of text, 4 MiB costs about 330 MB; the largest
/// bundled scenario is 2.7 kB.
pub const MAX_TOML_BYTES: usize = 4 << 20;

/// Peak memory per byte of TOML text, the worst measured (docs/scenarios.md, "Input size").
pub const TOML_COST: usize = 80;

/// `text` (the TOML of `what`) if it is at most [`MAX_TOML_BYTES`], checked before it is
/// parsed.
pub fn toml_within_cap<'a>(what: &str, text: &'a str) -> Result<&'a str> {
    if text.len() <= MAX_TOML_BYTES {
        return Ok(text);
    }
    Err(Error::invalid(
        what,
        format!(
            "has {} bytes of TOML, more than the {} MiB a TOML input may have (parsing costs \
             up to {TOML_COST}× the text in memory)",
            text.len(),
            MAX_TOML_BYTES >> 20
        ),
    ))
}

/// The error for an input larger than the cap.
fn too_large() -> std::io::Error {
    std::io::Error::new(
        std::io::ErrorKind::FileTooLarge,
        format!(
            "larger than the {} MiB an input file may have",
            MAX_INPUT_BYTES >> 20
        ),
    )
}

/// A reader that fails with [`std::io::ErrorKind::FileTooLarge`] once more than
/// [`MAX_INPUT_BYTES`] have been read (for inputs read as a stream, e.g. a CSV).
pub struct Capped<R> {
    inner: std::io::Take<R>,
}

impl<R: Read> Capped<R> {
    pub fn new(inner: R) -> Self {
        Capped {
            inner: inner.take(MAX_INPUT_BYTES + 1),
        }
    }
}

impl<R: Read> Read for Capped<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        if self.inner.limit() == 0 {
            return Err(too_large());
        }
        Ok(n)
    }
}

/// Opens `path` as a capped stream ([`Capped`]).
pub fn open(path: &Path) -> Result<Capped<std::fs::File>> {
    std::fs::File::open(path)
        .map(Capped::new)
        .map_err(|e| Error::io(path, e))
}

/// The whole text of `path` (UTF-8), at most [`MAX_INPUT_BYTES`].
pub fn read_text(path: &Path) -> Result<String> {
    let mut text = String::new();
    open(path)?
        .read_to_string(&mut text)
        .map_err(|e| Error::io(path, e))?;
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_endless_input_is_refused_at_the_cap() {
        let e = read_text(Path::new("/dev/zero")).unwrap_err().to_string();
        assert_eq!(
            e,
            "/dev/zero: larger than the 64 MiB an input file may have"
        );
    }

    #[test]
    fn a_file_at_the_cap_is_read_whole() {
        let mut r = Capped::new(std::io::repeat(b'a').take(MAX_INPUT_BYTES));
        let mut n = 0u64;
        let mut buf = vec![0u8; 1 << 20];
        loop {
            match r.read(&mut buf).unwrap() {
                0 => break,
                k => n += k as u64,
            }
        }
        assert_eq!(n, MAX_INPUT_BYTES);
        let mut over = Capped::new(std::io::repeat(b'a').take(MAX_INPUT_BYTES + 1));
        assert!(std::io::copy(&mut over, &mut std::io::sink()).is_err());
    }
}
