//! Run outputs: `response.csv`, `summary.json`, `profile.csv` and SVG plots of the histories.
//!
//! The SVG writer is a few dozen lines on purpose: polylines with axes, ticks and a legend are
//! all the figures need, and a plotting crate would double the clean build time.

pub mod staging;

use crate::probes::CsvRecorder;
use crate::scenario::Scenario;
use crate::simulation::{GapRanges, Outcome, Record};
use serde::Serialize;
pub use staging::Staging;
use std::fmt::Write as _;

/// Reads one value from a record.
pub type Getter = fn(&Record) -> f64;

/// The in-memory histories (summary peaks and plots), with how to read each from a record.
pub const COLUMNS: [(&str, Getter); 8] = [
    ("t", |r| r.t),
    ("midspan_y", |r| r.midspan.y),
    ("midspan_z", |r| r.midspan.z),
    ("midspan_rx", |r| r.midspan.rx),
    ("wheel1_y", |r| r.wheel1_y),
    ("wheel1_z", |r| r.wheel1_z),
    ("wheel1_gap_z", |r| r.wheel1_gap_z),
    ("wheel1_force_z", |r| r.wheel1_force_z),
];

/// The largest magnitude of a history, signed, with its time.
#[derive(Serialize, Debug, Clone, Copy, PartialEq)]
pub struct Peak {
    pub value: f64,
    pub t: f64,
}

/// Peak of column `get` over the records (None when the column is not applicable).
pub fn peak(records: &[Record], get: Getter) -> Option<Peak> {
    records
        .iter()
        .filter(|r| get(r).is_finite())
        .max_by(|a, b| get(a).abs().total_cmp(&get(b).abs()))
        .map(|r| Peak {
            value: get(r),
            t: r.t,
        })
}

/// `summary.json` contents.
#[derive(Serialize, Debug)]
pub struct Summary {
    pub scenario: String,
    pub model: String,
    /// The resolved case: every scenario value the run used, after the `--set` overrides
    /// (in the scenario file's units).
    pub case: Scenario,
    pub simulated_seconds: f64,
    pub wall_seconds: f64,
    pub real_time_factor: f64,
    pub steps: usize,
    pub mean_iterations: f64,
    pub max_iterations: u32,
    pub unconverged_steps: usize,
    /// Steps in which some magnet's gap was at or below zero.
    pub collision_steps: usize,
    /// Each magnet's gap range over the run (m).
    pub gaps: Vec<GapRange>,
    pub peaks: std::collections::BTreeMap<String, Option<Peak>>,
}

/// One magnet's gap range over a run.
#[derive(Serialize, Debug, Clone, PartialEq)]
pub struct GapRange {
    /// `wheel{N}.z` (levitation), `wheel{N}.left`, `wheel{N}.right` (guidance pair).
    pub magnet: String,
    pub min_m: f64,
    pub max_m: f64,
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
    pub fn new(scenario: &str, case: &Scenario, outcome: &Outcome, wall: f64) -> Self {
        let records = &outcome.records;
        let steps = records.len().saturating_sub(1);
        let simulated = records.last().map_or(0.0, |r| r.t);
        let iters: Vec<u32> = records.iter().skip(1).map(|r| r.iterations).collect();
        let mean = if iters.is_empty() {
            0.0
        } else {
            iters.iter().map(|&i| i as f64).sum::<f64>() / iters.len() as f64
        };
        let peaks = COLUMNS
            .iter()
            .skip(1)
            .map(|(n, get)| (n.to_string(), peak(records, *get)))
            .collect();
        Summary {
            scenario: scenario.to_string(),
            model: format!("{:?}", case.run.model).to_lowercase(),
            case: {
                let mut c = case.clone();
                c.run.t_end_s = Some(case.t_end());
                c
            },
            simulated_seconds: simulated,
            wall_seconds: wall,
            real_time_factor: if wall > 0.0 {
                simulated / wall
            } else {
                f64::INFINITY
            },
            steps,
            mean_iterations: mean,
            max_iterations: iters.iter().copied().max().unwrap_or(0),
            unconverged_steps: outcome.unconverged_steps,
            collision_steps: outcome.collision_steps,
            gaps: gap_ranges(&outcome.gap_ranges),
            peaks,
        }
    }
}

/// One curve of a plot.
pub struct Series<'a> {
    pub label: String,
    pub x: &'a [f64],
    pub y: Vec<f64>,
}

const COLOURS: [&str; 6] = [
    "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b",
];

fn nice_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let span = (hi - lo).max(1e-300);
    let raw = span / 5.0;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| span / s <= 6.0)
        .unwrap_or(10.0 * mag);
    let mut t = (lo / step).ceil() * step;
    let mut out = Vec::new();
    while t <= hi + 1e-9 * step {
        out.push(if t.abs() < 1e-12 * step { 0.0 } else { t });
        t += step;
    }
    out
}

/// An SVG line plot of several series.
pub fn svg_plot(title: &str, xlabel: &str, ylabel: &str, series: &[Series]) -> String {
    let (w, h) = (720.0, 360.0);
    let (ml, mr, mt, mb) = (80.0, 20.0, 30.0, 45.0);
    let pts = series
        .iter()
        .flat_map(|s| s.x.iter().zip(&s.y))
        .filter(|(x, y)| x.is_finite() && y.is_finite());
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for (x, y) in pts {
        x0 = x0.min(*x);
        x1 = x1.max(*x);
        y0 = y0.min(*y);
        y1 = y1.max(*y);
    }
    if !x0.is_finite() {
        (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
    }
    if y1 - y0 < 1e-30 {
        y0 -= 1.0_f64.max(y0.abs() * 0.1);
        y1 += 1.0_f64.max(y1.abs() * 0.1);
    }
    if x1 - x0 < 1e-30 {
        x1 = x0 + 1.0;
    }
    let pad = 0.05 * (y1 - y0);
    let (y0, y1) = (y0 - pad, y1 + pad);
    let sx = |x: f64| ml + (x - x0) / (x1 - x0) * (w - ml - mr);
    let sy = |y: f64| h - mb - (y - y0) / (y1 - y0) * (h - mt - mb);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{}" y="18" text-anchor="middle" font-size="14">{}</text>"#,
        w / 2.0,
        esc(title)
    );
    for t in nice_ticks(x0, x1) {
        let x = sx(t);
        let _ = writeln!(
            s,
            r##"<line x1="{x:.1}" y1="{mt}" x2="{x:.1}" y2="{}" stroke="#ddd"/><text x="{x:.1}" y="{}" text-anchor="middle">{}</text>"##,
            h - mb,
            h - mb + 15.0,
            fmt_tick(t)
        );
    }
    for t in nice_ticks(y0, y1) {
        let y = sy(t);
        let _ = writeln!(
            s,
            r##"<line x1="{ml}" y1="{y:.1}" x2="{}" y2="{y:.1}" stroke="#ddd"/><text x="{}" y="{:.1}" text-anchor="end">{}</text>"##,
            w - mr,
            ml - 5.0,
            y + 4.0,
            fmt_tick(t)
        );
    }
    let _ = writeln!(
        s,
        r#"<rect x="{ml}" y="{mt}" width="{}" height="{}" fill="none" stroke="black"/>"#,
        w - ml - mr,
        h - mt - mb
    );
    let _ = writeln!(
        s,
        r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#,
        (ml + w - mr) / 2.0,
        h - 8.0,
        esc(xlabel)
    );
    let _ = writeln!(
        s,
        r#"<text x="15" y="{}" text-anchor="middle" transform="rotate(-90 15 {})">{}</text>"#,
        h / 2.0,
        h / 2.0,
        esc(ylabel)
    );
    // Legend, drawn after the curves on a background so curves never run through it.
    let mut legend = String::new();
    let _ = writeln!(
        legend,
        r##"<rect x="{}" y="{}" width="155" height="{}" fill="white" fill-opacity="0.85" stroke="#bbb"/>"##,
        w - mr - 158.0,
        mt + 4.0,
        16.0 * series.len() as f64 + 6.0
    );
    for (i, se) in series.iter().enumerate() {
        let c = COLOURS[i % COLOURS.len()];
        // Thin the polyline to about two points per pixel column.
        let stride = (se.x.len() / 1400).max(1);
        let mut d = String::new();
        for (k, (x, y)) in se.x.iter().zip(&se.y).enumerate() {
            if (k % stride == 0 || k + 1 == se.x.len()) && x.is_finite() && y.is_finite() {
                let _ = write!(d, "{:.1},{:.1} ", sx(*x), sy(*y));
            }
        }
        let dash = if i % 2 == 1 {
            r#" stroke-dasharray="6,3""#
        } else {
            ""
        };
        let _ = writeln!(
            s,
            r#"<polyline fill="none" stroke="{c}" stroke-width="1.3"{dash} points="{d}"/>"#
        );
        let ly = mt + 15.0 + 16.0 * i as f64;
        let _ = writeln!(
            legend,
            r#"<line x1="{}" y1="{ly}" x2="{}" y2="{ly}" stroke="{c}" stroke-width="2"{dash}/><text x="{}" y="{}">{}</text>"#,
            w - mr - 150.0,
            w - mr - 125.0,
            w - mr - 120.0,
            ly + 4.0,
            esc(&se.label)
        );
    }
    s.push_str(&legend);
    s.push_str("</svg>\n");
    s
}

fn fmt_tick(t: f64) -> String {
    if t == 0.0 {
        "0".into()
    } else if t.abs() >= 1e4 || t.abs() < 1e-2 {
        format!("{t:.2e}")
    } else {
        format!("{}", (t * 1e6).round() / 1e6)
    }
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
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

/// Streams `response.csv` into the run's staging directory as the run goes.
pub fn response_recorder(
    dir: &Staging,
    probes: crate::probes::Probes,
) -> Result<CsvRecorder<std::io::BufWriter<std::fs::File>>, String> {
    let p = dir.path("response.csv");
    let f = std::fs::File::create(&p).map_err(|e| format!("cannot write {}: {e}", p.display()))?;
    CsvRecorder::new(probes, std::io::BufWriter::new(f))
}

/// Writes `summary.json`, `profile.csv` and one SVG per history into the run's staging
/// directory (`response.csv` is streamed by [`response_recorder`]).
pub fn write_run(dir: &Staging, outcome: &Outcome, summary: &Summary) -> Result<(), String> {
    let records = &outcome.records;
    let put = |name: &str, text: &str| dir.put(name, text);
    put("profile.csv", &profile_csv(&outcome.profile))?;
    put(
        "summary.json",
        &(serde_json::to_string_pretty(summary).map_err(|e| e.to_string())? + "\n"),
    )?;
    let t: Vec<f64> = records.iter().map(|r| r.t).collect();
    for (name, get) in COLUMNS.iter().skip(1) {
        let y: Vec<f64> = records.iter().map(get).collect();
        if y.iter().all(|v| !v.is_finite()) {
            continue;
        }
        let unit = if name.ends_with("_rx") {
            "rad"
        } else if name.ends_with("force_z") {
            "N"
        } else {
            "m"
        };
        let svg = svg_plot(
            &format!("{} — {}", summary.scenario, name),
            "t (s)",
            &format!("{name} ({unit})"),
            &[Series {
                label: summary.model.clone(),
                x: &t,
                y,
            }],
        );
        put(&format!("{name}.svg"), &svg)?;
    }
    Ok(())
}
