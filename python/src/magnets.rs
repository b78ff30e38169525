//! Controllers from outside the core: a Python object with the `Magnets` methods
//! ([`PyMagnets`]), driven step-lockstep by the coupling loop as `maglev hil` drives the
//! firmware, and the PD law the tests compare it with, in Rust ([`RustPd`]).

use maglev_core::Status;
use maglev_sim::simulation::{Magnets, Start, WheelGaps};
use maglev_sim::{Error, Result};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// A Python controller: an object with `start(info)`, `forces(step, t, gaps_prev, gaps_next,
/// accels)` returning per wheel `(G_z, G_y)` (N) as an `(n, 2)` array or a list of pairs,
/// `commit(step, t)`, and optionally `status()` (the core's status bits, an int). The loop
/// may call `forces` several times per step, always from the committed state (docs/python.md).
/// The GIL is taken for each call; the first exception raised is kept and ends the run.
pub struct PyMagnets {
    obj: Py<PyAny>,
    wheels: usize,
    status: Status,
    /// The exception a method raised, handed to the caller of the run.
    pub raised: Option<PyErr>,
}

impl PyMagnets {
    /// The controller `obj`.
    pub fn new(obj: Py<PyAny>) -> Self {
        PyMagnets {
            obj,
            wheels: 0,
            status: Status::default(),
            raised: None,
        }
    }

    /// Runs `f` with the GIL; a Python exception is kept and becomes the run's error.
    fn call<T>(
        &mut self,
        f: impl FnOnce(Python<'_>, &Bound<'_, PyAny>) -> PyResult<T>,
    ) -> Result<T> {
        let r = Python::attach(|py| f(py, self.obj.bind(py)));
        r.map_err(|e| {
            self.raised.get_or_insert(e);
            Error::numerical("the Python controller raised an exception")
        })
    }
}

/// Per wheel gaps as an `(n, 2)` array: `[h_z, d]` (m).
fn gaps_array<'py>(py: Python<'py>, gaps: &[WheelGaps]) -> PyResult<Bound<'py, PyAny>> {
    let flat = PyArray1::from_iter(py, gaps.iter().flat_map(|&(h, d)| [h, d]));
    Ok(flat.reshape([gaps.len(), 2])?.into_any())
}

/// Per wheel `(G_z, G_y)` from what `forces` returned, into `out`.
fn read_forces(ret: &Bound<'_, PyAny>, out: &mut [(f64, f64)]) -> PyResult<()> {
    let pairs: Vec<(f64, f64)> = match ret.extract::<PyReadonlyArray2<f64>>() {
        Ok(a) => a
            .as_array()
            .rows()
            .into_iter()
            .map(|r| (r[0], r.get(1).copied().unwrap_or(f64::NAN)))
            .collect(),
        Err(_) => ret.extract()?,
    };
    let shape_ok = match ret.extract::<PyReadonlyArray2<f64>>() {
        Ok(a) => a.shape() == [out.len(), 2],
        Err(_) => pairs.len() == out.len(),
    };
    if !shape_ok {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "controller.forces: must return {} (G_z, G_y) pairs, one per wheel",
            out.len()
        )));
    }
    out.copy_from_slice(&pairs);
    Ok(())
}

impl Magnets for PyMagnets {
    fn start(&mut self, start: &Start<'_>) -> Result<()> {
        self.wheels = start.gaps.len();
        self.call(|py, obj| {
            let info = PyDict::new(py);
            info.set_item("wheels", start.gaps.len())?;
            info.set_item("dt_s", start.settings.dt)?;
            info.set_item("h0_m", start.settings.controller.h0)?;
            info.set_item("p0_N", PyArray1::from_slice(py, &start.train.p0))?;
            info.set_item("gaps_m", gaps_array(py, start.gaps)?)?;
            obj.call_method1("start", (info,))?;
            Ok(())
        })
    }

    fn forces(
        &mut self,
        step: u32,
        t: f64,
        gaps_prev: &[WheelGaps],
        gaps_next: &[WheelGaps],
        accels: &[f64],
        out: &mut [(f64, f64)],
    ) -> Result<()> {
        let status = self.call(|py, obj| {
            let ret = obj.call_method1(
                "forces",
                (
                    step,
                    t,
                    gaps_array(py, gaps_prev)?,
                    gaps_array(py, gaps_next)?,
                    PyArray1::from_slice(py, accels),
                ),
            )?;
            read_forces(&ret, out)?;
            match obj.hasattr("status")? {
                true => obj.call_method0("status")?.extract::<u8>(),
                false => Ok(0),
            }
        })?;
        self.status = Status(status);
        Ok(())
    }

    fn commit(&mut self, step: u32, t: f64) -> Result<()> {
        self.call(|_, obj| obj.call_method1("commit", (step, t)).map(drop))
    }

    fn status(&self) -> Status {
        self.status
    }
}

/// A PD law with an integral term on each wheel, in Rust, to check a Python controller's
/// plumbing against (tests/test_controller.py writes the same law in Python):
///
/// `G_z = p0 + kp·e + kd·(h_z − h_z,prev)/Δt + ki·(I + e·Δt)`, `e = h_z − h0`, with `I` the
/// committed integral of `e` (it takes the step's `e·Δt` on commit), and
/// `G_y = −(ky·d + cy·(d − d_prev)/Δt)`.
#[pyclass(module = "maglev_sim._native", name = "_RustPd")]
#[derive(Clone, Default)]
pub struct RustPd {
    kp: f64,
    kd: f64,
    ki: f64,
    ky: f64,
    cy: f64,
    h0: f64,
    dt: f64,
    p0: Vec<f64>,
    /// Per wheel the committed integral and the last trial's.
    integral: Vec<f64>,
    trial: Vec<f64>,
}

#[pymethods]
impl RustPd {
    /// The law with its gains (SI: N/m, N·s/m, N/(m·s), N/m, N·s/m).
    #[new]
    #[pyo3(signature = (kp, kd, ki = 0.0, ky = 0.0, cy = 0.0))]
    fn py_new(kp: f64, kd: f64, ki: f64, ky: f64, cy: f64) -> Self {
        RustPd {
            kp,
            kd,
            ki,
            ky,
            cy,
            ..Default::default()
        }
    }
}

impl Magnets for RustPd {
    fn start(&mut self, start: &Start<'_>) -> Result<()> {
        self.h0 = start.settings.controller.h0;
        self.dt = start.settings.dt;
        self.p0 = start.train.p0.clone();
        self.integral = vec![0.0; self.p0.len()];
        self.trial = self.integral.clone();
        Ok(())
    }

    fn forces(
        &mut self,
        _step: u32,
        _t: f64,
        gaps_prev: &[WheelGaps],
        gaps_next: &[WheelGaps],
        _accels: &[f64],
        out: &mut [(f64, f64)],
    ) -> Result<()> {
        for (w, o) in out.iter_mut().enumerate() {
            let ((hp, dp), (h, d)) = (gaps_prev[w], gaps_next[w]);
            let e = h - self.h0;
            self.trial[w] = self.integral[w] + e * self.dt;
            let gz =
                self.p0[w] + self.kp * e + self.kd * (h - hp) / self.dt + self.ki * self.trial[w];
            let gy = -(self.ky * d + self.cy * (d - dp) / self.dt);
            *o = (gz, gy);
        }
        Ok(())
    }

    fn commit(&mut self, _step: u32, _t: f64) -> Result<()> {
        self.integral.clone_from(&self.trial);
        Ok(())
    }

    fn status(&self) -> Status {
        Status::default()
    }
}
