//! The levitation law of the core on a gap trace (`maglev control`, the stability checks).
//!
//! The host never re-implements the law: it converts SI to the core's per-unit run-time type
//! at the edge, calls `Levitation::update` once per trace row and converts back.

use crate::{Error, Result};
use maglev_core::scalar::{I32F32, I4F28};
use maglev_core::{Params, Scalar, Status};
use std::fmt::Write as _;

/// Scalar types selectable on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum ScalarKind {
    F64,
    F32,
    I32f32,
    I4f28,
}

/// A gap trace: uniform step `dt`, gaps in metres.
#[derive(Debug, Clone, PartialEq)]
pub struct Trace {
    pub t: Vec<f64>,
    pub h: Vec<f64>,
    pub dt: f64,
}

/// Parses a `t,h` CSV, checking the header, numbers and the uniformity of the step.
pub fn parse_trace(text: &str, name: &str) -> Result<Trace> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let (_, header) = lines
        .next()
        .ok_or_else(|| Error::parse(name, "empty file"))?;
    let cols: Vec<&str> = header.split(',').map(str::trim).collect();
    if cols != ["t", "h"] {
        return Err(Error::parse(
            name,
            format!("header must be exactly `t,h`, found `{}`", header.trim()),
        ));
    }
    let (mut t, mut h) = (Vec::new(), Vec::new());
    for (i, line) in lines {
        let row = i + 1;
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != 2 {
            return Err(Error::parse(
                name,
                format!(
                    "line {row}: expected 2 fields `t,h`, found {}",
                    fields.len()
                ),
            ));
        }
        let num = |s: &str, col: &str| -> Result<f64> {
            let v: f64 = s.parse().map_err(|_| {
                Error::parse(name, format!("line {row}: {col} = `{s}` is not a number"))
            })?;
            if !v.is_finite() {
                return Err(Error::parse(
                    name,
                    format!("line {row}: {col} = `{s}` is not finite"),
                ));
            }
            Ok(v)
        };
        t.push(num(fields[0], "t")?);
        h.push(num(fields[1], "h")?);
    }
    if t.len() < 2 {
        return Err(Error::parse(
            name,
            "needs at least two rows to define a time step",
        ));
    }
    let n = t.len();
    let dt = (t[n - 1] - t[0]) / (n - 1) as f64;
    if dt.is_nan() || dt <= 0.0 {
        return Err(Error::parse(
            name,
            format!("time must increase (t from {} to {})", t[0], t[n - 1]),
        ));
    }
    // Uniform to within what decimal text of the times can hold.
    let tol = 1e-6 * dt;
    for k in 1..n {
        let step = t[k] - t[k - 1];
        if (step - dt).abs() > tol {
            return Err(Error::parse(
                name,
                format!(
                    "non-uniform time step at line {}: {step} s where the mean step is {dt} s",
                    k + 2
                ),
            ));
        }
    }
    Ok(Trace { t, h, dt })
}

/// One output row in SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Row {
    pub t: f64,
    pub h: f64,
    pub g: f64,
    pub current: f64,
    pub force: f64,
    pub voltage: f64,
    pub status: Status,
}

/// Runs the core on a trace in scalar type `S`. Row 0 is the initial (equilibrium) state.
/// Arithmetic overflow is an error naming the time: the numbers would not be trustworthy.
pub fn run_trace<S: Scalar>(params: &Params, trace: &Trace) -> Result<Vec<Row>> {
    let ctrl = params
        .compile::<S>()
        .map_err(|e| Error::invalid("controller", e.to_string()))?;
    let mut st = ctrl.initial_state(trace.h[0]);
    let mut rows = Vec::with_capacity(trace.t.len());
    let mut out = ctrl.output(&st);
    for (k, (&t, &h)) in trace.t.iter().zip(&trace.h).enumerate() {
        if k > 0 {
            let mut ov = false;
            let h_pu = ctrl.gap_pu(h, &mut ov);
            out = ctrl.update(&mut st, h_pu);
            if ov || out.status.contains(Status::OVERFLOW) {
                return Err(Error::numerical(format!(
                    "{} overflowed at t = {t} s (h = {h} m): the type's range cannot carry this \
                     trace; use i32f32 or f64",
                    S::NAME
                )));
            }
        }
        let si = ctrl.to_si(&out);
        rows.push(Row {
            t,
            h,
            g: si.g,
            current: si.current,
            force: si.force,
            voltage: si.voltage,
            status: si.status,
        });
    }
    Ok(rows)
}

/// Runs the trace in the chosen scalar type.
pub fn run_trace_as(kind: ScalarKind, params: &Params, trace: &Trace) -> Result<Vec<Row>> {
    match kind {
        ScalarKind::F64 => run_trace::<f64>(params, trace),
        ScalarKind::F32 => run_trace::<f32>(params, trace),
        ScalarKind::I32f32 => run_trace::<I32F32>(params, trace),
        ScalarKind::I4f28 => run_trace::<I4F28>(params, trace),
    }
}

/// The CSV text with header `t,h,g,current,force,voltage` (shortest round-trip decimals).
pub fn to_csv(rows: &[Row]) -> String {
    let mut s = String::with_capacity(rows.len() * 80 + 32);
    s.push_str("t,h,g,current,force,voltage\n");
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{}",
            r.t, r.h, r.g, r.current, r.force, r.voltage
        );
    }
    s
}

/// The canned traces of `tests/src/traces.rs` (same definitions): 1 s at Δt = `dt`.
pub fn traces(dt: f64) -> [(&'static str, Trace); 2] {
    let make = |h: &dyn Fn(f64) -> f64| {
        let n = (1.0 / dt) as usize;
        let t: Vec<f64> = (0..=n).map(|k| k as f64 * dt).collect();
        let h = t.iter().map(|&t| h(t)).collect();
        Trace { t, h, dt }
    };
    [
        // The gap closes by 1 mm at t = 0.1 s.
        (
            "step",
            make(&|t| if t < 0.1 - 1e-12 { 0.01 } else { 0.009 }),
        ),
        // 1 mm at 5 Hz.
        (
            "sine",
            make(&|t| 0.01 + 0.001 * (2.0 * std::f64::consts::PI * 5.0 * t).sin()),
        ),
    ]
}

/// Largest |ΔF|/p0 between two runs of the same trace.
pub fn max_force_error(a: &[Row], b: &[Row], p0: f64) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x.force - y.force).abs() / p0)
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_and_uniformity_are_checked() {
        assert!(parse_trace("t,h\n0,0.01\n0.001,0.01\n", "x").is_ok());
        assert!(parse_trace("time,h\n0,0.01\n", "x")
            .unwrap_err()
            .to_string()
            .contains("header"));
        assert!(parse_trace("t,h\n0,0.01\n0.001,0.01\n0.003,0.01\n", "x")
            .unwrap_err()
            .to_string()
            .contains("non-uniform"));
        assert!(parse_trace("t,h\n0,0.01\n0.001,nan\n", "x")
            .unwrap_err()
            .to_string()
            .contains("not finite"));
        assert!(parse_trace("t,h\n0,0.01\n0.001,abc\n", "x")
            .unwrap_err()
            .to_string()
            .contains("not a number"));
        assert!(parse_trace("t,h\n0,0.01\n", "x")
            .unwrap_err()
            .to_string()
            .contains("two rows"));
    }
}
