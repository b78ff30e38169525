//! maglev-sim's errors as Python exceptions, worded as the CLI words them (one line, after
//! its `maglev: error: ` prefix).

use maglev_sim::Error;
use pyo3::exceptions::{PyKeyboardInterrupt, PyOSError, PyRuntimeError, PyValueError};
use pyo3::PyErr;

/// The CLI's one-line message of `e` (runs of white space made one space, as `maglev` prints
/// it).
pub fn message(e: &Error) -> String {
    e.to_string()
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}

/// `e` as the exception a Python caller expects: `ValueError` for bad input (a key outside
/// its domain, a text that does not parse), `OSError` for a file, `KeyboardInterrupt` for a
/// cancelled run, `RuntimeError` for the rest (numerics, a failed check).
pub fn to_py(e: Error) -> PyErr {
    let msg = message(&e);
    match e {
        Error::Invalid { .. } | Error::Parse { .. } => PyValueError::new_err(msg),
        Error::Io { .. } => PyOSError::new_err(msg),
        Error::Cancelled { .. } => PyKeyboardInterrupt::new_err(msg),
        _ => PyRuntimeError::new_err(msg),
    }
}
