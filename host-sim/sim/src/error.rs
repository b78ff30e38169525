//! The library's one error type.
//!
//! Why one type: every failure a user can meet ends as one line on stderr and an exit status
//! ([`Error::exit_code`]: the one place the statuses are decided), so the library only has to
//! say *what* went wrong, in words that name the key and the limit. The variants separate
//! what a caller may want to tell apart (bad input, files, numerics, the firmware link, a
//! result that fails a check); the message is the `Display`. `main` wraps it in `anyhow`.

use std::path::PathBuf;

/// Everything the host simulator can fail with.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A value of the case or an option outside its domain: `key: reason` (the reason states
    /// the limit, e.g. "must be > 0, got -1").
    #[error("{key}: {reason}")]
    Invalid {
        /// The key or option, as the user wrote it.
        key: String,
        /// What is wrong, with the limit.
        reason: String,
    },
    /// A file or directory could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// A text (scenario TOML, CSV, JSON) that does not parse: where, and the parser's words.
    #[error("{what}: {message}")]
    Parse {
        /// The text's name (a file, `--set`, a column).
        what: String,
        /// The parser's words, cut to an excerpt.
        message: String,
    },
    /// A numerical failure: a matrix that is not positive definite, an iteration that does not
    /// converge, a value that is no longer finite.
    #[error("{0}")]
    Numerical(String),
    /// The firmware link of a hardware-in-the-loop run failed (spawn, protocol, timeout).
    #[error("firmware: {0}")]
    Firmware(String),
    /// The command ran to its end and wrote its outputs, but the result fails a check of the
    /// physics or the numerics: a validation criterion, a statement of the paper, steps whose
    /// coupling iteration did not converge. Exit status 1.
    #[error("{0}")]
    CheckFailed(String),
    /// `run --strict` refused a run that completed (its outputs are written): a collision or a
    /// gap outside its bounds. Exit status 3.
    #[error("strict: {0}")]
    Strict(String),
    /// The caller stopped a run through its [`crate::simulation::Monitor`] (Ctrl-C in the
    /// `maglev` binary, `KeyboardInterrupt` in Python): the time of the last committed step.
    #[error("cancelled at t = {t_s} s")]
    Cancelled {
        /// The end time (s) of the last committed step.
        t_s: f64,
    },
}

/// The exit statuses of `maglev` (README "Exit codes", `maglev --help`).
pub mod exit {
    /// Done.
    pub const OK: u8 = 0;
    /// The outputs are written, but a check of the result failed ([`super::Error::CheckFailed`]).
    pub const CHECK_FAILED: u8 = 1;
    /// Bad input or usage, or a failure that left no result (I/O, numerics, firmware).
    pub const ERROR: u8 = 2;
    /// `run --strict` refused the run ([`super::Error::Strict`]).
    pub const STRICT: u8 = 3;
}

impl Error {
    /// A bad value: `key` as the user wrote it, `reason` with the limit. Line breaks in
    /// either (a user's text echoed back, e.g. a probe name) are written `\n`, so the error
    /// stays one line (the input fuzz target found a probe name with a newline in it).
    pub fn invalid(key: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::Invalid {
            // The key may echo what the user typed, which can be megabytes long.
            key: one_line(excerpt(&key.into())),
            reason: one_line(reason.into()),
        }
    }

    /// A failed file operation on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }

    /// A text that does not parse. The parser's message is cut to an excerpt
    /// ([`excerpt`]): it may quote the offending line, which can be megabytes long.
    pub fn parse(what: impl Into<String>, message: impl std::fmt::Display) -> Self {
        Error::Parse {
            what: excerpt(&what.into()),
            message: excerpt(&message.to_string()),
        }
    }

    /// The exit status for this error ([`exit`]).
    pub fn exit_code(&self) -> u8 {
        match self {
            Error::CheckFailed(_) => exit::CHECK_FAILED,
            Error::Strict(_) => exit::STRICT,
            _ => exit::ERROR,
        }
    }

    /// A numerical failure, described.
    pub fn numerical(message: impl Into<String>) -> Self {
        Error::Numerical(message.into())
    }
}

/// The longest word of a parser's message kept whole, and the longest message (characters).
pub const EXCERPT_WORD: usize = 60;
pub const EXCERPT_MESSAGE: usize = 600;

/// `message` with each word longer than [`EXCERPT_WORD`] characters cut to that length and
/// `…`, and, should it still be longer than [`EXCERPT_MESSAGE`], its middle left out: the
/// parser's words and the position stay, a quoted 10 MB line does not.
pub fn excerpt(message: &str) -> String {
    let words: Vec<String> = message
        .split(' ')
        .map(|w| match w.char_indices().nth(EXCERPT_WORD) {
            Some((i, _)) => format!("{}…", &w[..i]),
            None => w.to_string(),
        })
        .collect();
    let chars: Vec<char> = words.join(" ").chars().collect();
    let half = EXCERPT_MESSAGE / 2;
    if chars.len() <= EXCERPT_MESSAGE {
        return chars.into_iter().collect();
    }
    let head: String = chars[..half].iter().collect();
    let tail: String = chars[chars.len() - half..].iter().collect();
    format!("{head} … {tail}")
}

/// `Result` with the library's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// `s` with its line breaks escaped (`\n`, `\r`).
fn one_line(s: String) -> String {
    if s.contains(['\n', '\r']) {
        s.replace('\n', "\\n").replace('\r', "\\r")
    } else {
        s
    }
}

/// `v` for an error message: as written for ordinary magnitudes, in exponent form otherwise
/// (`{}` of 1e-300 is 300 digits: one line, but not a readable one).
pub fn shown(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e15).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// The refusal of `[controller.guidance]` without the state law.
pub fn guidance_needs_state_law() -> Error {
    Error::invalid(
        "controller.guidance",
        "needs law = \"state\" (the guidance law shares [controller.state]'s timing and supply)",
    )
}

/// A guidance law's parameter error under its scenario key.
pub fn guidance_error(e: maglev_core::ParamError) -> Error {
    match e.field().key {
        Some(k) if e.field().name.starts_with("guidance") => {
            Error::invalid(format!("controller.guidance.{k}"), e.to_string())
        }
        _ => Error::invalid("controller.guidance", e.to_string()),
    }
}

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

    #[test]
    fn a_parse_error_quotes_an_excerpt_not_a_whole_line() {
        let line = "x".repeat(10 << 20);
        let e = Error::parse(
            "scenario big.toml",
            format!("at line 1 | 1 | {line} | ^ expected `=`"),
        );
        let m = e.to_string();
        assert!(m.len() < 2 * EXCERPT_MESSAGE, "{} bytes", m.len());
        assert!(
            m.starts_with("scenario big.toml: at line 1 | 1 | xxx"),
            "{m}"
        );
        assert!(m.ends_with("| ^ expected `=`"), "{m}");
        let words = "word ".repeat(1000);
        let m = excerpt(&words);
        assert!(
            m.chars().count() <= EXCERPT_MESSAGE + 3 && m.contains(" … "),
            "{m}"
        );
        assert_eq!(excerpt("short message"), "short message");
    }

    #[test]
    fn exit_codes_tell_a_failed_check_and_strict_from_an_error() {
        let codes: Vec<u8> = [
            Error::CheckFailed("validation failed".into()),
            Error::Strict("a collision".into()),
            Error::invalid("k", "bad"),
            Error::numerical("diverged"),
        ]
        .iter()
        .map(Error::exit_code)
        .collect();
        assert_eq!(codes, [1, 3, 2, 2]);
    }
}
