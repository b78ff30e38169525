//! Run outputs: `response.csv`, `summary.json`, `profile.csv` and SVG plots of the histories
//! (drawn by [`crate::plot`]).

pub mod owned;
pub mod safety;
pub mod skid;
pub mod staging;

use crate::input::case::Case;
use crate::plot::{self, Plot, Series};
use crate::probes::CsvRecorder;
use crate::simulation::{voltage_limit, CoilRanges, GapRanges, Outcome};
use crate::{Error, Result};
use serde::Serialize;
pub use staging::{write_atomic, Staging};
use std::fmt::Write as _;

/// The largest magnitude of a history, signed, with its time.
#[derive(Serialize, Debug, Clone, Copy, PartialEq)]
pub struct Peak {
    pub value: f64,
    pub t: f64,
}

/// `summary.json` contents.
#[derive(Serialize, Debug)]
pub struct Summary {
    pub scenario: String,
    pub model: String,
    /// The resolved case: every value the run used, in SI, the unit in each key
    /// ([`Case::record`]).
    pub case: serde_json::Value,
    /// The magnets' nominal gap h0 (m); 0 for a train of forces (no gaps).
    #[serde(skip)]
    pub h0: f64,
    pub simulated_seconds: f64,
    pub wall_seconds: f64,
    pub real_time_factor: f64,
    pub steps: usize,
    pub mean_iterations: f64,
    pub max_iterations: u32,
    pub unconverged_steps: usize,
    /// Steps in which some magnet's gap was at or below zero.
    pub collision_steps: usize,
    /// Steps in which some wheel–rail contact lifted off (its force clamped at zero).
    pub contact_loss_steps: usize,
    /// Each magnet's gap range over the run (m).
    pub gaps: Vec<GapRange>,
    /// The smallest gap of any magnet over the run (m); null without magnets.
    pub min_gap_m: Option<f64>,
    /// The largest coil current `|i|` (A) and voltage `|V|` (V) of any magnet, as its law
    /// output them at the end of each step; null where no coil is reported.
    #[serde(rename = "peak_current_A")]
    pub peak_current: Option<f64>,
    #[serde(rename = "peak_voltage_V")]
    pub peak_voltage: Option<f64>,
    /// The law's voltage bound `V_max` (V); null when it has none (the paper's law with
    /// `vmax_V = inf`).
    #[serde(rename = "voltage_limit_V")]
    pub voltage_limit: Option<f64>,
    /// The longest time any one magnet spent saturated (s): Δt × the steps in which its law
    /// clamped the voltage at `±V_max` in at least one control period or sub-step; null when
    /// the law has no bound or no coil is reported.
    #[serde(rename = "saturated_s")]
    pub saturated: Option<f64>,
    /// Each magnet's coil over the run, in the order of `gaps`.
    pub coils: Vec<CoilSummary>,
    pub peaks: std::collections::BTreeMap<String, Option<Peak>>,
    /// The ground receivers' overall levels and verdicts (docs/ground.md); only with
    /// `[ground]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ground: Option<serde_json::Value>,
    /// The running-safety figures of a train (docs/safety.md); only for a run with a train.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub safety: Option<safety::SafetyReport>,
}

/// One magnet's gap range over a run.
#[derive(Serialize, Debug, Clone, PartialEq)]
pub struct GapRange {
    /// `wheel{N}.z` (levitation), `wheel{N}.left`, `wheel{N}.right` (guidance pair).
    pub magnet: String,
    pub min_m: f64,
    pub max_m: f64,
}

/// One magnet's coil over a run (summary.json `coils`; the run-wide figures of [`Summary`]
/// are the extremes of these).
#[derive(Serialize, Debug, Clone, PartialEq)]
pub struct CoilSummary {
    /// As in [`GapRange::magnet`].
    pub magnet: String,
    #[serde(rename = "peak_current_A")]
    pub peak_current: f64,
    #[serde(rename = "peak_voltage_V")]
    pub peak_voltage: f64,
    /// Null when the law has no voltage bound.
    #[serde(rename = "saturated_s")]
    pub saturated: Option<f64>,
}

/// Every magnet's coil figures, wheel by wheel; saturation times only under a voltage bound.
pub fn coil_summaries(ranges: &CoilRanges, dt: f64, bounded: bool) -> Vec<CoilSummary> {
    ranges
        .iter()
        .enumerate()
        .flat_map(|(i, r)| {
            ["z", "left", "right"]
                .iter()
                .zip(r)
                .map(move |(m, c)| CoilSummary {
                    magnet: format!("wheel{}.{m}", i + 1),
                    peak_current: c.peak_current,
                    peak_voltage: c.peak_voltage,
                    saturated: bounded.then_some(c.saturated_steps as f64 * dt),
                })
        })
        .collect()
}

/// The largest of `xs`, `None` if empty.
fn largest(xs: impl Iterator<Item = f64>) -> Option<f64> {
    xs.reduce(f64::max)
}

/// Names and ranges of every magnet's gap, wheel by wheel.
pub fn gap_ranges(ranges: &GapRanges) -> Vec<GapRange> {
    ranges
        .iter()
        .enumerate()
        .flat_map(|(i, r)| {
            ["z", "left", "right"]
                .iter()
                .zip(r)
                .map(move |(m, &(min, max))| GapRange {
                    magnet: format!("wheel{}.{m}", i + 1),
                    min_m: min,
                    max_m: max,
                })
        })
        .collect()
}

impl Summary {
    /// `columns` are the run's response.csv read back ([`Columns::read`]): the peaks are of
    /// every history written there, the probes included.
    pub fn new(
        scenario: &str,
        case: &Case,
        outcome: &Outcome,
        wall: f64,
        columns: &Columns,
    ) -> Self {
        let (steps, simulated) = (outcome.steps, outcome.simulated_seconds);
        // The sum of the counts is exact in f64, as was the sum of each step's count.
        let mean = if steps == 0 {
            0.0
        } else {
            outcome.total_iterations as f64 / steps as f64
        };
        let peaks = columns
            .histories()
            .map(|(n, y)| (n.to_string(), columns.peak(y)))
            .collect();
        let gaps = gap_ranges(&outcome.gap_ranges);
        let limit = case
            .controller
            .as_ref()
            .and_then(|c| voltage_limit(&case.law().ok()?, c));
        let coils = coil_summaries(&outcome.coil_ranges, case.dt, limit.is_some());
        let min_gap = gaps.iter().map(|g| g.min_m).reduce(f64::min);
        Summary {
            scenario: scenario.to_string(),
            model: format!("{:?}", case.model).to_lowercase(),
            case: case.record(),
            h0: case.h0(),
            simulated_seconds: simulated,
            wall_seconds: wall,
            real_time_factor: if wall > 0.0 {
                simulated / wall
            } else {
                f64::INFINITY
            },
            steps,
            mean_iterations: mean,
            max_iterations: outcome.max_iterations,
            unconverged_steps: outcome.unconverged_steps,
            collision_steps: outcome.collision_steps,
            contact_loss_steps: outcome.contact_loss_steps,
            min_gap_m: min_gap,
            peak_current: largest(coils.iter().map(|c| c.peak_current)),
            peak_voltage: largest(coils.iter().map(|c| c.peak_voltage)),
            voltage_limit: limit,
            saturated: largest(coils.iter().filter_map(|c| c.saturated)),
            gaps,
            coils,
            peaks,
            ground: None,
            safety: None,
        }
    }
}

/// The histories of a run's response.csv, read back once it is complete: what summary.json's
/// peaks and the SVGs are made of, so they cover exactly the columns written (the probes) and
/// agree with the file to the bit (its numbers are shortest round-trip decimals). An empty
/// cell (a quantity that does not apply) reads as NaN.
pub struct Columns {
    names: Vec<String>,
    /// Column by column, every row.
    values: Vec<Vec<f64>>,
}

/// Columns of response.csv that are not histories of a physical quantity.
const NOT_HISTORIES: [&str; 3] = ["t", "iterations", "collision"];

impl Columns {
    /// Reads `response.csv` from the run's staging directory.
    pub fn read(dir: &Staging) -> Result<Self> {
        let p = dir.path("response.csv");
        let mut r =
            csv::Reader::from_path(&p).map_err(|e| Error::parse(p.display().to_string(), e))?;
        let names: Vec<String> = r
            .headers()
            .map_err(|e| Error::parse(p.display().to_string(), e))?
            .iter()
            .map(str::to_string)
            .collect();
        let mut values = vec![Vec::new(); names.len()];
        for row in r.records() {
            let row = row.map_err(|e| Error::parse(p.display().to_string(), e))?;
            for (col, cell) in values.iter_mut().zip(row.iter()) {
                col.push(if cell.is_empty() {
                    f64::NAN
                } else {
                    cell.parse()
                        .map_err(|e| Error::parse(format!("{}: `{cell}`", p.display()), e))?
                });
            }
        }
        if names.first().map(String::as_str) != Some("t") {
            return Err(Error::numerical(format!(
                "internal: {} does not start with a t column",
                p.display()
            )));
        }
        Ok(Columns { names, values })
    }

    /// The time column (s).
    pub fn t(&self) -> &[f64] {
        &self.values[0]
    }

    /// Every history, by its column name, in the file's order.
    pub fn histories(&self) -> impl Iterator<Item = (&str, &[f64])> {
        self.names
            .iter()
            .zip(&self.values)
            .filter(|(n, _)| !NOT_HISTORIES.contains(&n.as_str()))
            .map(|(n, v)| (n.as_str(), v.as_slice()))
    }

    /// The largest magnitude of history `y`, signed, with its time (None when no value is
    /// finite: the quantity does not apply).
    pub fn peak(&self, y: &[f64]) -> Option<Peak> {
        self.t()
            .iter()
            .zip(y)
            .filter(|(_, v)| v.is_finite())
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            .map(|(&t, &value)| Peak { value, t })
    }
}

/// `profile.csv` text: the irregularity a run used, `x, r_y, r_z` (m), at every position a
/// wheel occupied at a step (docs/model.md §3), so the case can be rerun in another tool.
pub fn profile_csv(profile: &[[f64; 3]]) -> String {
    let mut s = String::with_capacity(profile.len() * 60 + 16);
    s.push_str("x,r_y,r_z\n");
    for [x, ry, rz] in profile {
        let _ = writeln!(s, "{x},{ry},{rz}");
    }
    s
}

/// Streams `response.csv` into the run's staging directory as the run goes, in writes of
/// [`CsvRecorder::CHUNK`] bytes (the recorder buffers; the file is written unbuffered).
pub fn response_recorder(
    dir: &Staging,
    probes: crate::probes::Probes,
) -> Result<CsvRecorder<std::fs::File>> {
    let p = dir.path("response.csv");
    let f = std::fs::File::create(&p).map_err(|e| Error::io(&p, e))?;
    CsvRecorder::new(probes, f).map_err(|e| match e {
        Error::Io { source, .. } => Error::io(&p, source),
        e => e,
    })
}

/// Fills probe columns that are known only after the run (the `ground{N}.vz` probes,
/// [`crate::probes::Probes::ground_columns`]) into the staged response.csv: `fills` pairs a
/// probe's column among the probes (from 0; the file's column is one more, after `t`) with
/// its values, one per data row. The rows are numbers only ([`crate::probes::CsvRecorder`]),
/// so they are split at commas; the header is kept as it is.
pub fn fill_response_columns(dir: &Staging, fills: &[(usize, &[f64])]) -> Result<()> {
    if fills.is_empty() {
        return Ok(());
    }
    let p = dir.path("response.csv");
    let text = std::fs::read_to_string(&p).map_err(|e| Error::io(&p, e))?;
    let mut lines = text.lines();
    let mut out = Vec::with_capacity(text.len() + text.len() / 2);
    out.extend_from_slice(lines.next().unwrap_or("").as_bytes());
    out.push(b'\n');
    let mut rows = 0;
    for (j, line) in lines.enumerate() {
        let mut cells: Vec<&str> = line.split(',').collect();
        let mut cell = Vec::new();
        let mut filled: Vec<(usize, String)> = Vec::with_capacity(fills.len());
        for &(k, v) in fills {
            let value = *v.get(j).ok_or_else(|| {
                Error::numerical(format!(
                    "internal: response.csv has more rows than the {} values of probe column {k}",
                    v.len()
                ))
            })?;
            cell.clear();
            crate::probes::push_csv_f64(&mut cell, value);
            filled.push((k + 1, String::from_utf8_lossy(&cell).into_owned()));
        }
        for (c, text) in &filled {
            if let Some(slot) = cells.get_mut(*c) {
                *slot = text.as_str();
            }
        }
        out.extend_from_slice(cells.join(",").as_bytes());
        out.push(b'\n');
        rows += 1;
    }
    if let Some(&(k, v)) = fills.iter().find(|(_, v)| v.len() != rows) {
        return Err(Error::numerical(format!(
            "internal: probe column {k} has {} values for {rows} response.csv rows",
            v.len()
        )));
    }
    std::fs::write(&p, out).map_err(|e| Error::io(&p, e))
}

/// Writes `summary.json`, `profile.csv` and one SVG per history into the run's staging
/// directory (`response.csv` is streamed by [`response_recorder`]). `sets` are the run's
/// `--set` overrides, shown in the plot titles.
pub fn write_run(
    dir: &Staging,
    outcome: &Outcome,
    summary: &Summary,
    sets: &[String],
    columns: &Columns,
) -> Result<()> {
    let put = |name: &str, text: &str| dir.put(name, text);
    put("profile.csv", &profile_csv(&outcome.profile))?;
    put(
        "summary.json",
        &(serde_json::to_string_pretty(summary).map_err(|e| Error::numerical(e.to_string()))?
            + "\n"),
    )?;
    let h0 = (summary.h0 > 0.0).then_some(summary.h0);
    for (name, y) in columns.histories() {
        if y.iter().all(|v| !v.is_finite()) {
            continue;
        }
        let title = format!("{} — {name}{}", summary.scenario, plot::overrides(sets));
        let p = history_plot(name, &summary.model, columns.t(), y, h0);
        let p = Plot { title, ..p };
        put(&format!("{name}.svg"), &plot::svg(&p)?)?;
    }
    Ok(())
}

/// The plot of history `name` (a default column or a probe) in display units: displacements
/// in mm, forces in kN, accelerations in m/s², rotations in rad, the levitation gap as its
/// deviation from h0 in mm about a zero line (docs/model.md §2).
fn history_plot(name: &str, model: &str, t: &[f64], y: &[f64], h0: Option<f64>) -> Plot {
    let scaled = |k: f64, off: f64| y.iter().map(|v| (v - off) * k).collect::<Vec<_>>();
    let n = name;
    let (label, y, zero) = match (crate::probes::si_unit(name), h0) {
        ("m", Some(h0)) if n.ends_with("gap_z") => {
            (format!("{n} − h0 (mm)"), scaled(1e3, h0), true)
        }
        ("rad", _) => (format!("{n} (rad)"), y.to_vec(), false),
        ("m/s²", _) => (format!("{n} (m/s²)"), y.to_vec(), true),
        ("N", _) => (format!("{n} (kN)"), scaled(1e-3, 0.0), false),
        _ => (format!("{n} (mm)"), scaled(1e3, 0.0), false),
    };
    let p = Plot::new(
        name,
        "t (s)",
        label,
        vec![Series::new(model, t.to_vec(), y)],
    );
    if zero {
        p.zero_line()
    } else {
        p
    }
}
