//! Plots of a sweep: each quantity against the first axis, one line per value of the others,
//! a marker at every run (a sweep has few points, and a line alone hides where they are),
//! each axis labelled with its unit: the quantity's from its probe's name
//! ([`crate::probes::si_unit`]), the axis key's from the scenario key's unit suffix.
//!
//! [`draw`] is the only place the sweep calls the plot module (crate::plot, plotters);
//! failed runs are NaN and leave a gap in their line.

use super::runs::Run;
use super::spec::Spec;
use super::store::{Record, Status};
use crate::plot::{self as svg, Series};
use crate::probes::si_unit;
use crate::Result;
use std::collections::BTreeMap;

/// One line: its label, x and y (NaN where a run failed or is absent).
pub struct Line {
    pub label: String,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
}

/// An SVG line plot of `lines`.
pub fn draw(title: &str, xlabel: &str, ylabel: &str, lines: &[Line]) -> Result<String> {
    let series: Vec<Series> = lines
        .iter()
        .map(|l| Series::new(l.label.clone(), l.x.clone(), l.y.clone()))
        .collect();
    svg::svg(&svg::Plot::new(title, xlabel, ylabel, series).markers())
}

/// `name (unit)`, or `name` alone when `unit` is empty.
fn with_unit(name: &str, unit: &str) -> String {
    if unit.is_empty() {
        name.to_string()
    } else {
        format!("{name} ({unit})")
    }
}

/// The unit of a `--set` key from the unit suffix of the scenario key it names
/// (`speed` → `run.speed_m_per_s` → m/s); empty for a key without one (seed, alpha).
pub fn key_unit(key: &str) -> &'static str {
    let full = crate::input::scenario::SHORT_KEYS
        .iter()
        .find(|(short, _)| *short == key)
        .map_or(key, |(_, full)| full);
    const SUFFIXES: [(&str, &str); 10] = [
        ("_m_per_s", "m/s"),
        ("_t_per_m3", "t/m³"),
        ("_t_per_m", "t/m"),
        ("_m4", "m⁴"),
        ("_m2", "m²"),
        ("_ohm", "Ω"),
        ("_hz", "Hz"),
        ("_m", "m"),
        ("_s", "s"),
        ("_t", "t"),
    ];
    SUFFIXES
        .iter()
        .find(|(suffix, _)| full.ends_with(suffix))
        .map_or("", |(_, unit)| unit)
}

/// The file name of quantity `name`'s plot (`peak:midspan_z` → `peak_midspan_z.svg`).
pub fn file_name(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("{s}.svg")
}

/// One plot per quantity: (file name, SVG text). The first axis is the abscissa (its index
/// when its values are not numbers); each combination of the other axes' values is a line.
pub fn plots(
    spec: &Spec,
    runs: &[Run],
    records: &BTreeMap<String, Record>,
) -> Result<Vec<(String, String)>> {
    let first = &spec.axes[0];
    let numeric = first.values.iter().all(|v| v.number().is_some());
    let xval = |run: &Run| {
        if numeric {
            run.values[0].number().unwrap_or(f64::NAN)
        } else {
            first
                .values
                .iter()
                .position(|v| *v == run.values[0])
                .unwrap_or(0) as f64
        }
    };
    let label = |run: &Run| {
        let rest: Vec<String> = spec.axes[1..]
            .iter()
            .zip(&run.values[1..])
            .map(|(a, v)| format!("{}={}", a.key, v.cell()))
            .collect();
        if rest.is_empty() {
            spec.scenario.clone()
        } else {
            rest.join(", ")
        }
    };
    let xlabel = if numeric {
        with_unit(&first.key, key_unit(&first.key))
    } else {
        format!("{} (index of its values)", first.key)
    };
    spec.quantities
        .iter()
        .enumerate()
        .map(|(k, q)| {
            let mut lines: Vec<Line> = Vec::new();
            for run in runs {
                let y = records
                    .get(&run.id)
                    .filter(|r| r.status != Status::Failed)
                    .and_then(|r| r.values.get(k).copied())
                    .unwrap_or(f64::NAN);
                let l = label(run);
                match lines.iter_mut().find(|line| line.label == l) {
                    Some(line) => {
                        line.x.push(xval(run));
                        line.y.push(y);
                    }
                    None => lines.push(Line {
                        label: l,
                        x: vec![xval(run)],
                        y: vec![y],
                    }),
                }
            }
            let title = format!("{} — {} against {}", spec.scenario, q.name(), first.key);
            Ok((
                file_name(&q.name()),
                draw(
                    &title,
                    &xlabel,
                    &with_unit(&q.name(), si_unit(&q.probe)),
                    &lines,
                )?,
            ))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Units from the scenario keys' suffixes, through the short keys; none for a key without
    /// one.
    #[test]
    fn key_units_come_from_the_scenario_key_names() {
        assert_eq!(key_unit("speed"), "m/s");
        assert_eq!(key_unit("dt"), "s");
        assert_eq!(key_unit("t_end"), "s");
        assert_eq!(key_unit("bridge.pier.height_m"), "m");
        assert_eq!(key_unit("seed"), "");
        assert_eq!(key_unit("alpha"), "");
        assert_eq!(
            with_unit("peak:midspan_z", si_unit("midspan_z")),
            "peak:midspan_z (m)"
        );
        assert_eq!(si_unit("car4.body.az"), "m/s²");
    }
}
