//! `maglev control`: the levitation law of the core on a gap trace (a `t,h` CSV).
//!
//! The host never re-implements the law: it parses, converts SI to the core's per-unit run-time
//! type at the edge, calls `Levitation::update` once per trace row and converts back. Output
//! is buffered and written only when the whole trace ran, so a failure never leaves half a
//! CSV on stdout.

use maglev_core::scalar::{I32F32, I4F28};
use maglev_core::{Interpolation, Params, Scalar, Scheme, Status};
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;

/// Scalar types selectable on the command line.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ScalarKind {
    F64,
    F32,
    I32f32,
    I4f28,
}

/// Gap interpolation inside the outer step.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum InterpKind {
    Linear,
    Parabolic,
}

impl From<InterpKind> for Interpolation {
    fn from(k: InterpKind) -> Self {
        match k {
            InterpKind::Linear => Interpolation::Linear,
            InterpKind::Parabolic => Interpolation::Parabolic,
        }
    }
}

/// Integrator of the coil + PI equations (`maglev_core::Scheme`).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum SchemeKind {
    /// The paper's Eq. 14, `--nsub` times per step (first order).
    Paper,
    /// Gauss–Legendre on the limit system (order 4); ignores `--nsub` and `--alpha`.
    Accurate,
}

impl From<SchemeKind> for Scheme {
    fn from(k: SchemeKind) -> Self {
        match k {
            SchemeKind::Paper => Scheme::Paper,
            SchemeKind::Accurate => Scheme::Accurate,
        }
    }
}

/// Controller parameters shared by every subcommand that runs the law.
#[derive(clap::Args, Debug, Clone)]
pub struct ControllerArgs {
    /// Integrator: the paper's Eq. 14 with sub-steps, or the accurate Gauss–Legendre scheme.
    #[arg(long, value_enum, default_value_t = SchemeKind::Paper)]
    pub scheme: SchemeKind,
    /// α of the α-method, in [0, 1].
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.5)]
    pub alpha: f64,
    /// Internal-loop sub-steps per outer step.
    #[arg(long = "nsub", allow_negative_numbers = true, default_value_t = 1)]
    pub n_sub: u32,
    /// Gap interpolation inside the outer step.
    #[arg(long = "interp", value_enum, default_value_t = InterpKind::Linear)]
    pub interp: InterpKind,
    /// Nominal current i0 (A).
    #[arg(long, allow_negative_numbers = true, default_value_t = 43.0)]
    pub i0: f64,
    /// Nominal gap h0 (m).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.01)]
    pub h0: f64,
    /// Coil resistance R0 (Ω).
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0)]
    pub r0: f64,
    /// Proportional gain KP (V·m/A).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.01)]
    pub kp: f64,
    /// Integral gain KI (V·m/(A·s)).
    #[arg(long, allow_negative_numbers = true, default_value_t = 6.0)]
    pub ki: f64,
    /// Static load on the magnet p0 (N); default: a quarter of 15 t.
    #[arg(long, allow_negative_numbers = true, default_value_t = 15_000.0 * maglev_core::levitation::GRAVITY / 4.0)]
    pub p0: f64,
    /// Supply voltage bound ±V (V); `inf` for none (the paper has none).
    #[arg(long, allow_negative_numbers = true, default_value_t = f64::INFINITY)]
    pub vmax: f64,
}

impl ControllerArgs {
    /// The core's parameters for an outer step `dt`, validated (errors name the parameter).
    pub fn params(&self, dt: f64) -> Result<Params, String> {
        let p = Params {
            i0: self.i0,
            h0: self.h0,
            r0: self.r0,
            kp: self.kp,
            ki: self.ki,
            p0: self.p0,
            alpha: self.alpha,
            dt,
            n_sub: self.n_sub,
            interpolation: self.interp.into(),
            v_max: self.vmax,
            scheme: self.scheme.into(),
        };
        p.validate().map_err(|e| e.to_string())?;
        Ok(p)
    }
}

#[derive(clap::Args, Debug)]
pub struct Args {
    /// CSV with header `t,h` (seconds, metres) and a uniform time step.
    #[arg(long)]
    pub trace: PathBuf,
    /// Run-time number type of the controller.
    #[arg(long, value_enum, default_value_t = ScalarKind::F64)]
    pub scalar: ScalarKind,
    #[command(flatten)]
    pub controller: ControllerArgs,
}

/// A gap trace: uniform step `dt`, gaps in metres.
#[derive(Debug, Clone, PartialEq)]
pub struct Trace {
    pub t: Vec<f64>,
    pub h: Vec<f64>,
    pub dt: f64,
}

/// Parses a `t,h` CSV, checking the header, numbers and the uniformity of the step.
pub fn parse_trace(text: &str, name: &str) -> Result<Trace, String> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let (_, header) = lines.next().ok_or_else(|| format!("{name}: empty file"))?;
    let cols: Vec<&str> = header.split(',').map(str::trim).collect();
    if cols != ["t", "h"] {
        return Err(format!(
            "{name}: header must be exactly `t,h`, found `{}`",
            header.trim()
        ));
    }
    let (mut t, mut h) = (Vec::new(), Vec::new());
    for (i, line) in lines {
        let row = i + 1;
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != 2 {
            return Err(format!(
                "{name}: line {row}: expected 2 fields `t,h`, found {}",
                fields.len()
            ));
        }
        let num = |s: &str, col: &str| -> Result<f64, String> {
            let v: f64 = s
                .parse()
                .map_err(|_| format!("{name}: line {row}: {col} = `{s}` is not a number"))?;
            if !v.is_finite() {
                return Err(format!("{name}: line {row}: {col} = `{s}` is not finite"));
            }
            Ok(v)
        };
        t.push(num(fields[0], "t")?);
        h.push(num(fields[1], "h")?);
    }
    if t.len() < 2 {
        return Err(format!(
            "{name}: needs at least two rows to define a time step"
        ));
    }
    let n = t.len();
    let dt = (t[n - 1] - t[0]) / (n - 1) as f64;
    if dt.is_nan() || dt <= 0.0 {
        return Err(format!(
            "{name}: time must increase (t from {} to {})",
            t[0],
            t[n - 1]
        ));
    }
    // Uniform to within what decimal text of the times can hold.
    let tol = 1e-6 * dt;
    for k in 1..n {
        let step = t[k] - t[k - 1];
        if (step - dt).abs() > tol {
            return Err(format!(
                "{name}: non-uniform time step at line {}: {step} s where the mean step is {dt} s",
                k + 2
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
pub fn run_trace<S: Scalar>(params: &Params, trace: &Trace) -> Result<Vec<Row>, String> {
    let ctrl = params.compile::<S>().map_err(|e| e.to_string())?;
    let mut st = ctrl.initial_state(trace.h[0]);
    let mut rows = Vec::with_capacity(trace.t.len());
    let mut out = ctrl.output(&st);
    for (k, (&t, &h)) in trace.t.iter().zip(&trace.h).enumerate() {
        if k > 0 {
            let mut ov = false;
            let h_pu = ctrl.gap_pu(h, &mut ov);
            out = ctrl.update(&mut st, h_pu);
            if ov || out.status.contains(Status::OVERFLOW) {
                return Err(format!(
                    "{} overflowed at t = {t} s (h = {h} m): the type's range cannot carry this \
                     trace; use i32f32 or f64",
                    S::NAME
                ));
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
pub fn run_trace_as(kind: ScalarKind, params: &Params, trace: &Trace) -> Result<Vec<Row>, String> {
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

/// Notes on stderr about events (collisions, saturation) that are not errors.
fn report_events(rows: &[Row]) {
    let events = [
        (Status::COLLISION, "collision (gap <= 0)"),
        (Status::VOLTAGE_SATURATED, "voltage bound active"),
        (Status::CURRENT_CLAMPED, "current held at zero"),
        (
            Status::INVALID_INPUT,
            "gap beyond the accepted range, clamped",
        ),
    ];
    for (flag, what) in events {
        let hits: Vec<&Row> = rows.iter().filter(|r| r.status.contains(flag)).collect();
        if let Some(first) = hits.first() {
            eprintln!(
                "maglev: note: {what} in {} step(s), first at t = {} s",
                hits.len(),
                first.t
            );
        }
    }
}

pub fn run(args: Args) -> Result<(), String> {
    let name = args.trace.display().to_string();
    let text = std::fs::read_to_string(&args.trace)
        .map_err(|e| format!("cannot read trace {name}: {e}"))?;
    let trace = parse_trace(&text, &name)?;
    let params = args.controller.params(trace.dt)?;
    let rows = run_trace_as(args.scalar, &params, &trace)?;
    report_events(&rows);
    std::io::stdout()
        .lock()
        .write_all(to_csv(&rows).as_bytes())
        .map_err(|e| format!("cannot write output: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_and_uniformity_are_checked() {
        assert!(parse_trace("t,h\n0,0.01\n0.001,0.01\n", "x").is_ok());
        assert!(parse_trace("time,h\n0,0.01\n", "x")
            .unwrap_err()
            .contains("header"));
        assert!(parse_trace("t,h\n0,0.01\n0.001,0.01\n0.003,0.01\n", "x")
            .unwrap_err()
            .contains("non-uniform"));
        assert!(parse_trace("t,h\n0,0.01\n0.001,nan\n", "x")
            .unwrap_err()
            .contains("not finite"));
        assert!(parse_trace("t,h\n0,0.01\n0.001,abc\n", "x")
            .unwrap_err()
            .contains("not a number"));
        assert!(parse_trace("t,h\n0,0.01\n", "x")
            .unwrap_err()
            .contains("two rows"));
    }
}
