//! `Scenario`: a scenario's text, its name and its `--set` overrides, exactly what
//! `maglev run SCENARIO --set …` takes; every check is the CLI's (`Case::new`).

use crate::errors::to_py;
use maglev_sim::input::case::Case;
use maglev_sim::input::scenario::{self, BUNDLED};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyFloat, PyInt, PyString};

/// The names `Scenario.bundled` knows.
pub fn bundled_names() -> Vec<&'static str> {
    BUNDLED.iter().map(|(n, _)| *n).collect()
}

/// A scenario: a bundled one, a TOML text or a file, with `key=value` overrides as
/// `maglev run --set` takes them (docs/scenarios.md names every key).
#[pyclass(module = "maglev_sim")]
#[derive(Clone)]
pub struct Scenario {
    /// The TOML text.
    pub text: String,
    /// The name errors give (the bundled name or the path, as the CLI names it).
    #[pyo3(get)]
    pub name: String,
    /// The overrides, `key=value`, in order.
    pub sets: Vec<String>,
}

impl Scenario {
    /// The checked case, its law not yet designed (what `--set` errors come from).
    pub fn parse(&self) -> maglev_sim::Result<Case> {
        Case::new(scenario::parse(&self.text, &self.name, &self.sets)?)
    }

    /// The case a run uses: checked, and its law designed when it asks for a design.
    pub fn resolved(&self) -> maglev_sim::Result<Case> {
        maglev_sim::studies::design::resolve(self.parse()?)
    }

    /// A checked scenario: `Ok` only if the case it makes passes the CLI's checks.
    fn checked(self) -> PyResult<Self> {
        self.parse().map_err(to_py)?;
        Ok(self)
    }
}

/// A Python value as the text after `--set key=`: booleans `true`/`false`, numbers by
/// `repr` (the shortest text that reads back to the same float), strings as they are.
fn set_value(value: &Bound<'_, PyAny>) -> PyResult<String> {
    if value.is_instance_of::<PyBool>() {
        return Ok(if value.extract::<bool>()? {
            "true"
        } else {
            "false"
        }
        .into());
    }
    if value.is_instance_of::<PyInt>() || value.is_instance_of::<PyFloat>() {
        return Ok(value.repr()?.to_string());
    }
    if value.is_instance_of::<PyString>() {
        return value.extract::<String>();
    }
    Err(PyValueError::new_err(format!(
        "a --set value is a bool, a number or a str, got {}",
        value.get_type().name()?
    )))
}

#[pymethods]
impl Scenario {
    /// A scenario bundled with the simulator (`maglev_sim.BUNDLED` lists them).
    #[staticmethod]
    fn bundled(name: &str) -> PyResult<Self> {
        let Some((_, text)) = BUNDLED.iter().find(|(n, _)| *n == name) else {
            return Err(PyValueError::new_err(format!(
                "scenario: `{name}` is not a bundled name ({})",
                bundled_names().join(", ")
            )));
        };
        Scenario {
            text: text.to_string(),
            name: name.into(),
            sets: Vec::new(),
        }
        .checked()
    }

    /// A scenario from its TOML text; `name` is what errors call it.
    #[staticmethod]
    #[pyo3(signature = (text, name = "<text>"))]
    fn from_toml(text: String, name: &str) -> PyResult<Self> {
        Scenario {
            text,
            name: name.into(),
            sets: Vec::new(),
        }
        .checked()
    }

    /// A scenario from a TOML file.
    #[staticmethod]
    fn from_file(path: std::path::PathBuf) -> PyResult<Self> {
        let text = maglev_sim::input::read_text(&path).map_err(|e| {
            PyValueError::new_err(format!(
                "scenario: `{}` is not a readable file: {}",
                path.display(),
                crate::errors::message(&e)
            ))
        })?;
        Scenario {
            text,
            name: path.display().to_string(),
            sets: Vec::new(),
        }
        .checked()
    }

    /// Overrides `key` with `value` as `maglev run --set key=value` does (the same short
    /// keys, `section.key`, and errors); raises `ValueError` naming the key on a bad one and
    /// leaves the scenario as it was. Returns the scenario, so calls chain.
    fn set<'py>(
        mut slf: PyRefMut<'py, Self>,
        key: &str,
        value: &Bound<'py, PyAny>,
    ) -> PyResult<PyRefMut<'py, Self>> {
        let set = format!("{key}={}", set_value(value)?);
        let mut next = slf.clone();
        next.sets.push(set);
        *slf = next.checked()?;
        Ok(slf)
    }

    /// The overrides so far, `key=value`, as the CLI's `--set` arguments.
    #[getter]
    fn sets(&self) -> Vec<String> {
        self.sets.clone()
    }

    /// The scenario's TOML text (before the overrides).
    #[getter]
    fn text(&self) -> String {
        self.text.clone()
    }

    /// The case a run uses, as a dict: every value in SI with its unit in the key
    /// (summary.json's `case`), the law designed where the scenario asks for a design.
    fn case<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let case = py.detach(|| self.resolved()).map_err(to_py)?;
        crate::run::json_to_py(py, &case.record())
    }

    fn __repr__(&self) -> String {
        format!("Scenario({:?}, sets={:?})", self.name, self.sets)
    }
}
