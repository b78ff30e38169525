//! The CLI's `accelerogram` and `bands` commands as functions returning numpy arrays in a
//! dict: the same library calls, the same numbers (python/tests/test_analyses.py compares
//! them with the commands' CSV).

use crate::errors::to_py;
use maglev_sim::bands::{self as band_levels, Averaging, Level, Motion, Settings};
use maglev_sim::input::support::SyntheticSection;
use maglev_sim::physics::seismic::accelerogram::synthesize;
use maglev_sim::Error;
use numpy::{IntoPyArray, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// How a Python keyword names a key in an error: as itself (`pga_g`).
fn keyword(key: &str) -> String {
    key.to_string()
}

/// `maglev accelerogram`: a synthetic three-component ground-acceleration record
/// (docs/seismic.md), as a dict of numpy arrays `t_s`, `ax_m_per_s2`, `ay_m_per_s2`,
/// `az_m_per_s2` (the command's CSV columns, the same bits). The keywords are the command's
/// flags (and `[support.synthetic]`'s keys); a value outside its limits raises `ValueError`
/// naming the keyword.
#[pyfunction]
#[pyo3(signature = (pga_g, ground = "medium".to_string(), vertical_ratio = 2.0 / 3.0,
    duration_s = 20.0, dt_s = 0.005, seed = 0, rise_s = 2.0, strong_end_s = 10.0,
    decay_per_s = 0.4))]
#[allow(clippy::too_many_arguments)]
pub fn accelerogram<'py>(
    py: Python<'py>,
    pga_g: f64,
    ground: String,
    vertical_ratio: f64,
    duration_s: f64,
    dt_s: f64,
    seed: u64,
    rise_s: f64,
    strong_end_s: f64,
    decay_per_s: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let section = SyntheticSection {
        pga_g,
        ground,
        vertical_ratio,
        duration_s,
        dt_s,
        seed,
        rise_s,
        strong_end_s,
        decay_per_s,
    };
    let r = py
        .detach(|| synthesize(&section.spec(&keyword)?, &keyword))
        .map_err(to_py)?;
    let t: Vec<f64> = (0..r.x.len()).map(|j| j as f64 * r.dt_s).collect();
    let d = PyDict::new(py);
    d.set_item("t_s", t.into_pyarray(py))?;
    d.set_item("ax_m_per_s2", r.x.into_pyarray(py))?;
    d.set_item("ay_m_per_s2", r.y.into_pyarray(py))?;
    d.set_item("az_m_per_s2", r.z.into_pyarray(py))?;
    Ok(d)
}

/// `quantity` and `output` as the command's `--quantity` and `--output` spell them.
fn settings(quantity: &str, output: &str, running: Option<f64>) -> Result<Settings, Error> {
    let input = match quantity {
        "acceleration" => Motion::Acceleration,
        "velocity" => Motion::Velocity,
        "displacement" => Motion::Displacement,
        q => {
            return Err(Error::invalid(
                "quantity",
                format!("expected acceleration, velocity or displacement, got {q:?}"),
            ))
        }
    };
    let level = match output {
        "acceleration" => Level::Acceleration,
        "velocity" => Level::Velocity,
        o => {
            return Err(Error::invalid(
                "output",
                format!("expected acceleration or velocity, got {o:?}"),
            ))
        }
    };
    let averaging = match running {
        None => Averaging::WholeRecord,
        Some(w) if w.is_finite() && w > 0.0 => Averaging::MaxRunning { window_s: w },
        Some(w) => {
            return Err(Error::invalid(
                "running",
                format!("must be a positive number of seconds, got {w}"),
            ))
        }
    };
    Ok(Settings {
        input,
        level,
        averaging,
    })
}

/// `maglev bands`: one-third-octave band levels (docs/bands.md) of `values`, sampled every
/// `dt_s` seconds (SI units of `quantity`), as a dict: `centre_hz` (the nominal centres),
/// the level column the command writes (e.g. `level_db_re_1e-6_m_per_s2`, NaN for a band
/// without energy; unrounded, where the CSV holds 0.0001 dB) and `rms` (SI), lowest band
/// first, and `method` (the description the command prints on stderr). Bad input raises
/// `ValueError`.
#[pyfunction]
#[pyo3(signature = (values, dt_s, quantity = "acceleration", output = "acceleration",
    running = None))]
pub fn bands<'py>(
    py: Python<'py>,
    values: PyReadonlyArray1<'py, f64>,
    dt_s: f64,
    quantity: &str,
    output: &str,
    running: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let s = settings(quantity, output, running).map_err(to_py)?;
    let samples = values.as_slice()?.to_vec();
    let levels = py
        .detach(|| band_levels::analyse(&samples, dt_s, &s))
        .map_err(|e| match e {
            band_levels::BandsError::BadWindow { .. } => Error::invalid("running", e.to_string()),
            _ => Error::invalid("values", e.to_string()),
        })
        .map_err(to_py)?;
    let centre: Vec<f64> = levels.iter().map(|l| l.band.nominal_hz()).collect();
    let db: Vec<f64> = levels
        .iter()
        .map(|l| l.level_db.unwrap_or(f64::NAN))
        .collect();
    let rms: Vec<f64> = levels.iter().map(|l| l.rms).collect();
    let d = PyDict::new(py);
    d.set_item("centre_hz", centre.into_pyarray(py))?;
    d.set_item(band_levels::level_column(&s), db.into_pyarray(py))?;
    d.set_item("rms", rms.into_pyarray(py))?;
    d.set_item(
        "method",
        band_levels::description("values", samples.len(), dt_s, &s),
    )?;
    Ok(d)
}
