//! The analyses of the CLI's other commands, on a [`Scenario`], as dicts.

use crate::errors::to_py;
use crate::run::json_to_py;
use crate::scenario::Scenario;
use maglev_sim::studies::stability::coupled::GIRDER_MODES;
use maglev_sim::studies::stability::report::case_report;
use maglev_sim::Error;
use pyo3::prelude::*;

/// `maglev stability --scenario`: the scenario's linearised vehicle on a rigid rail and
/// coupled with `girder_modes` bending modes per span (poles, margins, critical magnet
/// mass), as the JSON the CLI prints, a dict. The GIL is released while it computes.
#[pyfunction]
#[pyo3(signature = (scenario, girder_modes = GIRDER_MODES))]
pub fn stability<'py>(
    py: Python<'py>,
    scenario: &Scenario,
    girder_modes: usize,
) -> PyResult<Bound<'py, PyAny>> {
    let report = py
        .detach(|| {
            let r = case_report(&scenario.name, &scenario.resolved()?, girder_modes)?;
            serde_json::to_value(&r).map_err(|e| Error::numerical(e.to_string()))
        })
        .map_err(to_py)?;
    json_to_py(py, &report)
}
