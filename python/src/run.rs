//! `run`: one passage, as `maglev run` makes it, into numpy columns and a summary dict.

use crate::columns::Columns;
use crate::errors::to_py;
use crate::magnets::{PyMagnets, RustPd};
use crate::scenario::Scenario;
use maglev_sim::ground::receivers::{self, BaseForces};
use maglev_sim::input::case::Case;
use maglev_sim::probes::Tee;
use maglev_sim::simulation::magnets::CoreMagnets;
use maglev_sim::simulation::{Magnets, Monitor, Outcome};
use maglev_sim::{Error, Result};
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The monitor of a run without the GIL: every [`Interrupts::EVERY`] steps it takes the GIL
/// back and asks Python whether a signal is pending (`PyErr_CheckSignals`: Python's own
/// SIGINT handler set a flag; maglev-sim installs none). A pending `KeyboardInterrupt` (or
/// whatever a handler raised) is kept and stops the run.
#[derive(Default)]
pub struct Interrupts {
    steps: u32,
    pub raised: Option<PyErr>,
}

impl Interrupts {
    /// Steps between two checks: a check costs one GIL round trip (about a microsecond
    /// uncontended), a step of paper-5 some hundred; Ctrl-C answers within milliseconds.
    pub const EVERY: u32 = 16;
}

impl Monitor for Interrupts {
    fn cancelled(&mut self) -> bool {
        self.steps += 1;
        if !self.steps.is_multiple_of(Self::EVERY) {
            return false;
        }
        match Python::attach(|py| py.check_signals()) {
            Ok(()) => false,
            Err(e) => {
                self.raised = Some(e);
                true
            }
        }
    }
}

/// Which magnets drive the run.
pub enum Controller {
    /// The core's laws, as `maglev run` (`CoreMagnets`).
    Core,
    /// A Python object with the `Magnets` methods.
    Python(PyMagnets),
    /// The Rust PD law of the tests ([`RustPd`]).
    Pd(RustPd),
}

/// A finished run: the columns, the outcome, the loop's wall time.
pub struct Finished {
    pub columns: Columns,
    pub outcome: Outcome,
    pub wall: f64,
}

/// Runs `case` with `magnets`, without Python: the columns, with the `ground{N}.vz` probes
/// filled from the receivers after the run as `maglev run` fills them.
pub fn simulate(
    case: &Case,
    magnets: &mut dyn Magnets,
    monitor: &mut dyn Monitor,
) -> Result<Finished> {
    let mut columns = Columns::new(case.probes.clone());
    let mut base = BaseForces::for_case(case);
    let run = match &mut base {
        Some(b) => maglev_sim::setup::simulate(case, magnets, &mut Tee(&mut columns, b), monitor)?,
        None => maglev_sim::setup::simulate(case, magnets, &mut columns, monitor)?,
    };
    if let (Some(b), Some(v), Some(soil), Some(g)) =
        (&base, &case.viaduct, &case.soil, &case.ground)
    {
        let vel = receivers::of_run(soil, v.span_length, b, g)?;
        for (k, r) in case.probes.ground_columns() {
            if vel[r].len() != columns.t.len() {
                return Err(Error::numerical(format!(
                    "internal: ground receiver {} has {} values for {} rows",
                    r + 1,
                    vel[r].len(),
                    columns.t.len()
                )));
            }
            columns.values[k].clone_from(&vel[r]);
        }
    }
    Ok(Finished {
        columns,
        outcome: run.outcome,
        wall: run.wall,
    })
}

/// A JSON value as the Python object `json.loads` makes of it.
pub fn json_to_py<'py>(py: Python<'py>, v: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (v.to_string(),))
}

/// The run's summary: summary.json's counters under its names (`steps`, `simulated_seconds`,
/// `wall_seconds`, `mean_iterations`, …), each magnet's gap range, and the case.
fn summary(name: &str, case: &Case, f: &Finished) -> serde_json::Value {
    let o = &f.outcome;
    let gaps: Vec<serde_json::Value> = o
        .gap_ranges
        .iter()
        .enumerate()
        .flat_map(|(w, ranges)| {
            ["z", "left", "right"]
                .iter()
                .zip(ranges)
                .map(move |(m, (lo, hi))| {
                    serde_json::json!({"wheel": w + 1, "magnet": m, "min_m": lo, "max_m": hi})
                })
        })
        .collect();
    let min_gap = o
        .gap_ranges
        .iter()
        .flat_map(|r| r.iter().map(|(lo, _)| *lo))
        .reduce(f64::min);
    serde_json::json!({
        "scenario": name,
        "case": case.record(),
        "steps": o.steps,
        "simulated_seconds": o.simulated_seconds,
        "wall_seconds": f.wall,
        "real_time_factor": o.simulated_seconds / f.wall,
        "mean_iterations": o.total_iterations as f64 / o.steps.max(1) as f64,
        "max_iterations": o.max_iterations,
        "unconverged_steps": o.unconverged_steps,
        "collision_steps": o.collision_steps,
        "first_collision_t_s": o.first_collision_t,
        "contact_loss_steps": o.contact_loss_steps,
        "gaps": gaps,
        "min_gap_m": min_gap,
    })
}

/// The columns as numpy arrays, in response.csv's order.
fn columns_to_py<'py>(py: Python<'py>, c: Columns) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("t", c.t.into_pyarray(py))?;
    for (name, v) in c.probes.names.iter().zip(c.values) {
        d.set_item(name, v.into_pyarray(py))?;
    }
    d.set_item("iterations", c.iterations.into_pyarray(py))?;
    d.set_item("collision", c.collision.into_pyarray(py))?;
    Ok(d)
}

/// Runs `scenario` (with `probes` as `--set output.probes=[…]`) with the core's laws, a
/// Python `controller`, or the test's Rust PD law: `(columns, summary)`. The GIL is released
/// for the run (a Python controller takes it back at each call); a Ctrl-C raises
/// `KeyboardInterrupt`; bad input raises `ValueError` with the CLI's message.
#[pyfunction]
#[pyo3(signature = (scenario, probes = None, controller = None))]
pub fn run<'py>(
    py: Python<'py>,
    scenario: &Scenario,
    probes: Option<Vec<String>>,
    controller: Option<Bound<'py, PyAny>>,
) -> PyResult<(Bound<'py, PyDict>, Bound<'py, PyAny>)> {
    let mut scenario = scenario.clone();
    if let Some(p) = probes {
        let list = serde_json::to_string(&p).map_err(|e| to_py(Error::numerical(e.to_string())))?;
        scenario.sets.push(format!("output.probes={list}"));
    }
    let mut ctl = match controller {
        None => Controller::Core,
        Some(c) => match c.extract::<PyRef<'_, RustPd>>() {
            Ok(pd) => Controller::Pd(pd.clone()),
            Err(_) => Controller::Python(PyMagnets::new(c.unbind())),
        },
    };
    let mut monitor = Interrupts::default();
    let outcome = py.detach(|| {
        let case = scenario.resolved()?;
        let magnets: &mut dyn Magnets = match &mut ctl {
            Controller::Core => &mut CoreMagnets::new(),
            Controller::Python(m) => m,
            Controller::Pd(m) => m,
        };
        let f = simulate(&case, magnets, &mut monitor)?;
        Ok::<_, Error>((summary(&scenario.name, &case, &f), f))
    });
    if let Some(e) = monitor.raised.take() {
        return Err(e);
    }
    if let Controller::Python(m) = &mut ctl {
        if let Some(e) = m.raised.take() {
            return Err(e);
        }
    }
    let (summary, finished) = outcome.map_err(to_py)?;
    Ok((
        columns_to_py(py, finished.columns)?,
        json_to_py(py, &summary)?,
    ))
}
