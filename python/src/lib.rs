//! `maglev_sim._native`: the Python binding of maglev-sim (pyo3 + numpy). The package
//! `maglev_sim` (python/maglev_sim/) wraps it; docs/python.md is the user's guide.
//!
//! What crosses the boundary: a [`scenario::Scenario`] (the scenario's text, its name and
//! the `--set` overrides, as the CLI takes them), a run's columns as numpy arrays and its
//! summary as a dict, and a controller written in Python ([`magnets::PyMagnets`]). A run
//! releases the GIL; its [`run::Interrupts`] monitor takes it back every few steps to let a
//! Ctrl-C through as `KeyboardInterrupt`.

use pyo3::prelude::*;

pub mod analyses;
pub mod columns;
pub mod errors;
pub mod magnets;
pub mod run;
pub mod scenario;
pub mod studies;

/// The extension module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<scenario::Scenario>()?;
    m.add_class::<magnets::RustPd>()?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_function(wrap_pyfunction!(studies::stability, m)?)?;
    m.add_function(wrap_pyfunction!(analyses::accelerogram, m)?)?;
    m.add_function(wrap_pyfunction!(analyses::bands, m)?)?;
    m.add("BUNDLED", scenario::bundled_names())?;
    Ok(())
}
