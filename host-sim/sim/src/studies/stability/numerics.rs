//! The numerics study of docs/numerics.md: how the paper's internal loop (Eq. 14 applied
//! `n_sub` times per outer step) converges, per interpolation and per number type.
//!
//! Why: the paper recommends n_sub = 1000 without saying what it buys. At a fixed gap Eq. 14
//! is a consistent one-step method for Eq. 9 + 10 (see [`super::inner_loop`]); this study measures
//! its error against a converged solution on the canned traces, the observed order, and where
//! fixed point stops carrying the sub-step increments. Everything runs through the core via
//! `control::run_trace_as` (the same path as `maglev control`).

use crate::studies::control::{max_force_error, run_trace_as, traces, ScalarKind};
use maglev_core::{Interpolation, ParamError, Params};
use std::fmt::Write as _;

/// The sub-step counts of the study.
pub const N_SUBS: [u32; 6] = [1, 2, 5, 10, 100, 1000];

/// The types of the study.
pub const TYPES: [ScalarKind; 4] = [
    ScalarKind::F64,
    ScalarKind::F32,
    ScalarKind::I32f32,
    ScalarKind::I4f28,
];

fn params(dt: f64, n_sub: u32, interp: Interpolation) -> Params {
    let mut p = Params::paper_wheel(dt);
    p.n_sub = n_sub;
    p.interpolation = interp;
    p
}

/// The relative quantisation error of the sub-step gain `c = δ/τ` in a type with least
/// significant bit `lsb` (what `Params::compile` checks against 1e-4).
fn c_error(p: &Params, lsb: f64) -> f64 {
    let c = p.dt / p.n_sub as f64 / (2.0 * p.k0() * p.g0() / p.v_base());
    let q = (c / lsb).round() * lsb;
    ((q - c) / c).abs()
}

/// Runs the whole study and returns its report (Markdown tables). `ref_n_sub` is the f64
/// run taken as converged (its own error is ≈ the n_sub = 1000 error × 1000/ref_n_sub, the
/// scheme being first order).
pub fn study(ref_n_sub: u32) -> crate::Result<String> {
    let dt = 1e-3;
    let mut out = String::new();
    let mut refs = vec![];
    for (name, trace) in traces(dt) {
        for interp in [Interpolation::Linear, Interpolation::Parabolic] {
            let p = params(dt, ref_n_sub, interp);
            let reference = run_trace_as(ScalarKind::F64, &p, &trace)?;
            let _ = writeln!(
                out,
                "\n### {name}, {interp:?} interpolation: max |F − F_ref|/p0 (F_ref: f64, n_sub = {ref_n_sub})\n"
            );
            let _ = writeln!(out, "| n_sub | f64 | order | f32 | i32f32 | i4f28 |");
            let _ = writeln!(out, "|---|---|---|---|---|---|");
            let mut prev: Option<(u32, f64)> = None;
            for n in N_SUBS {
                let p = params(dt, n, interp);
                let mut cells = vec![];
                let mut e64 = f64::NAN;
                for kind in TYPES {
                    match run_trace_as(kind, &p, &trace) {
                        Ok(rows) => {
                            let e = max_force_error(&rows, &reference, p.p0);
                            if kind == ScalarKind::F64 {
                                e64 = e;
                            }
                            cells.push(format!("{e:.2e}"));
                        }
                        Err(_) => cells.push("refused".into()),
                    }
                }
                let order = prev.map_or("".to_string(), |(n0, e0)| {
                    format!("{:.2}", (e0 / e64).ln() / (n as f64 / n0 as f64).ln())
                });
                prev = Some((n, e64));
                let _ = writeln!(
                    out,
                    "| {n} | {} | {order} | {} | {} | {} |",
                    cells[0], cells[1], cells[2], cells[3]
                );
            }
            refs.push((name, interp, reference));
        }
    }
    let _ = writeln!(
        out,
        "\n### Linear vs parabolic interpolation: max |F_lin − F_par|/p0, both converged\n"
    );
    for pair in refs.chunks(2) {
        let p0 = Params::paper_wheel(dt).p0;
        let _ = writeln!(
            out,
            "- {}: {:.2e}",
            pair[0].0,
            max_force_error(&pair[0].2, &pair[1].2, p0)
        );
    }
    let _ = writeln!(
        out,
        "\n### Fixed point: the sub-step gain c = δ/τ in each type (Δt = 1 ms)\n"
    );
    let _ = writeln!(
        out,
        "| n_sub | c | rel. error i32f32 | rel. error i4f28 | i4f28 compiles |"
    );
    let _ = writeln!(out, "|---|---|---|---|---|");
    for n in [1u32, 10, 100, 134, 135, 1000, 2000] {
        let p = params(dt, n, Interpolation::Linear);
        let c = dt / n as f64 / (2.0 * p.k0() * p.g0() / p.v_base());
        let ok = match p.compile::<maglev_core::scalar::I4F28>() {
            Ok(_) => "yes".to_string(),
            Err(ParamError::Unrepresentable { field, .. }) => format!("no ({field})"),
            Err(e) => format!("no ({e})"),
        };
        let _ = writeln!(
            out,
            "| {n} | {c:.3e} | {:.1e} | {:.1e} | {ok} |",
            c_error(&p, 2f64.powi(-32)),
            c_error(&p, 2f64.powi(-28)),
        );
    }
    let _ = writeln!(
        out,
        "\n### Paper scheme vs accurate scheme: error against cost (f64, linear interpolation)"
    );
    out.push_str(&super::schemes::table()?);
    Ok(out)
}
