//! Part of the numerics study (docs/numerics.md §5): the paper scheme at several n_sub against
//! the accurate scheme, error against cost, at Δt = 1e-4, 1e-3, 1e-2 s.
//!
//! The reference must be more accurate than anything judged, and independent of the accurate
//! scheme: the Richardson extrapolant `2·F(n = 2000) − F(n = 1000)` of the paper scheme (first
//! order with a smooth error expansion, so the extrapolant is second order). Its own error is
//! shown as the spread against the extrapolant from (500, 1000).

use crate::studies::control::{max_force_error, run_trace_as, traces, Row, ScalarKind, Trace};
use maglev_core::{Params, Scheme};
use std::fmt::Write as _;
use std::time::Instant;

fn params(dt: f64, scheme: Scheme, n_sub: u32) -> Params {
    let mut p = Params::paper_wheel(dt);
    p.scheme = scheme;
    p.n_sub = n_sub;
    p
}

/// Runs and times (best of `reps`, seconds per outer step).
fn timed(p: &Params, trace: &Trace, reps: usize) -> crate::Result<(Vec<Row>, f64)> {
    let mut best = f64::INFINITY;
    let mut rows = vec![];
    for _ in 0..reps {
        let t0 = Instant::now();
        rows = run_trace_as(ScalarKind::F64, p, trace)?;
        best = best.min(t0.elapsed().as_secs_f64());
    }
    Ok((rows, best / (trace.t.len() - 1) as f64))
}

fn extrapolate(coarse: &[Row], fine: &[Row]) -> Vec<Row> {
    coarse
        .iter()
        .zip(fine)
        .map(|(c, f)| Row {
            force: 2.0 * f.force - c.force,
            ..*f
        })
        .collect()
}

/// The Markdown tables of the comparison.
pub fn table() -> crate::Result<String> {
    let mut out = String::new();
    for dt in [1e-4, 1e-3, 1e-2] {
        for (name, trace) in traces(dt) {
            let p0 = Params::paper_wheel(dt).p0;
            let run = |n| run_trace_as(ScalarKind::F64, &params(dt, Scheme::Paper, n), &trace);
            let (f500, f1000, f2000) = (run(500)?, run(1000)?, run(2000)?);
            let reference = extrapolate(&f1000, &f2000);
            let spread = max_force_error(&reference, &extrapolate(&f500, &f1000), p0);
            let _ = writeln!(
                out,
                "\n### {name}, Δt = {dt} s: max |F − F_ref|/p0 (F_ref: Richardson from paper \
                 n_sub = 1000, 2000; its spread {spread:.1e})\n"
            );
            let _ = writeln!(
                out,
                "| scheme | work per step | error (f64) | time per update (f64) |"
            );
            let _ = writeln!(out, "|---|---|---|---|");
            for n in [1u32, 10, 100, 1000] {
                let p = params(dt, Scheme::Paper, n);
                let reps = if n == 1000 { 1 } else { 3 };
                let (rows, t) = timed(&p, &trace, reps)?;
                let e = max_force_error(&rows, &reference, p0);
                let _ = writeln!(
                    out,
                    "| paper, n_sub = {n} | {n} sub-step(s) | {e:.2e} | {:.0} ns |",
                    t * 1e9
                );
            }
            let p = params(dt, Scheme::Accurate, 1);
            let m = maglev_core::levitation::accurate::intervals(&p);
            let (rows, t) = timed(&p, &trace, 5)?;
            let e = max_force_error(&rows, &reference, p0);
            let _ = writeln!(
                out,
                "| accurate | {m} Gauss interval(s) | {e:.2e} | {:.0} ns |",
                t * 1e9
            );
        }
    }
    Ok(out)
}
