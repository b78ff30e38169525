//! The library's one error type.
//!
//! Why one type: every failure a user can meet ends as one line on stderr and exit status 2
//! (`main`), so the library only has to say *what* went wrong, in words that name the key and
//! the limit. The variants separate what a caller may want to tell apart (bad input, files,
//! numerics, the firmware link); the message is the `Display`. `main` wraps it in `anyhow`.

use std::path::PathBuf;

/// Everything the host simulator can fail with.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A value of the case or an option outside its domain: `key: reason` (the reason states
    /// the limit, e.g. "must be > 0, got -1").
    #[error("{key}: {reason}")]
    Invalid { key: String, reason: String },
    /// A file or directory could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A text (scenario TOML, CSV, JSON) that does not parse: where, and the parser's words.
    #[error("{what}: {message}")]
    Parse { what: String, message: String },
    /// A numerical failure: a matrix that is not positive definite, an iteration that does not
    /// converge, a value that is no longer finite.
    #[error("{0}")]
    Numerical(String),
    /// The firmware link of a hardware-in-the-loop run failed (spawn, protocol, timeout).
    #[error("firmware: {0}")]
    Firmware(String),
}

impl Error {
    /// A bad value: `key` as the user wrote it, `reason` with the limit.
    pub fn invalid(key: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::Invalid {
            key: key.into(),
            reason: reason.into(),
        }
    }

    /// A failed file operation on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }

    /// A text that does not parse.
    pub fn parse(what: impl Into<String>, message: impl std::fmt::Display) -> Self {
        Error::Parse {
            what: what.into(),
            message: message.to_string(),
        }
    }

    /// A numerical failure, described.
    pub fn numerical(message: impl Into<String>) -> Self {
        Error::Numerical(message.into())
    }
}

/// `Result` with the library's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_are_one_line_naming_the_key() {
        let e = Error::invalid("run.dt_s", "must be > 0, got -1");
        assert_eq!(e.to_string(), "run.dt_s: must be > 0, got -1");
        let e = Error::io(
            "out/x.csv",
            std::io::Error::new(std::io::ErrorKind::NotFound, "gone"),
        );
        assert_eq!(e.to_string(), "out/x.csv: gone");
        assert_eq!(
            Error::Firmware("timed out".into()).to_string(),
            "firmware: timed out"
        );
    }
}
