//! `maglev control`'s engine (the core, driven by the host) against the independent
//! implementation of docs/model.md §4, and the fixed-point types against f64.

use maglev_core::{Interpolation, Params};
use maglev_sim::studies::control::{run_trace_as, Row, ScalarKind, Trace};
use maglev_tests::control_reference::{self as reference, RefParams};
use maglev_tests::traces;

fn params(dt: f64, n_sub: u32, interp: Interpolation) -> Params {
    let mut p = Params::paper_wheel(dt);
    p.n_sub = n_sub;
    p.interpolation = interp;
    p
}

fn ref_params(p: &Params) -> RefParams {
    RefParams {
        i0: p.i0,
        h0: p.h0,
        r0: p.r0,
        kp: p.kp,
        ki: p.ki,
        p0: p.p0,
        alpha: p.alpha,
        n_sub: p.n_sub,
        parabolic: p.interpolation == Interpolation::Parabolic,
    }
}

fn max_force_diff(a: &[Row], b: &[Row]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x.force - y.force).abs())
        .fold(0.0, f64::max)
}

#[test]
fn f64_matches_the_independent_implementation_to_a_micronewton() {
    for interp in [Interpolation::Linear, Interpolation::Parabolic] {
        for n_sub in [1, 10, 1000] {
            for (name, trace) in traces::all(1e-3) {
                let p = params(trace.dt, n_sub, interp);
                let rows = run_trace_as(ScalarKind::F64, &p, &trace).unwrap();
                let want = reference::run(&ref_params(&p), trace.dt, &trace.h);
                assert_eq!(rows.len(), want.len());
                for (k, (r, w)) in rows.iter().zip(&want).enumerate() {
                    let ctx = format!("{name} n_sub={n_sub} {interp:?} row {k}");
                    assert!(
                        (r.force - w.force).abs() <= 1e-6,
                        "{ctx}: force {} vs {}",
                        r.force,
                        w.force
                    );
                    assert!((r.g - w.g).abs() <= 1e-9 * w.g.abs().max(1.0), "{ctx}: g");
                    assert!((r.current - w.current).abs() <= 1e-9, "{ctx}: current");
                    assert!(
                        (r.voltage - w.voltage).abs() <= 1e-7,
                        "{ctx}: voltage {} vs {}",
                        r.voltage,
                        w.voltage
                    );
                }
            }
        }
    }
}

/// Budgets for the other types against f64 at n_sub = 10, Δt = 1 ms, as a fraction of p0
/// (36.8 kN), from a first-order error analysis (docs/theory.md, "Number formats"):
/// * coefficient quantisation: the sub-step gain c = 2.5e-4 is stored with relative error
///   ε_c ≤ ½·LSB/c, which scales the transient; its force effect is ≤ ε_c × (peak per-unit
///   force excursion ≤ 0.5) × (resonant amplification Q = 1/(2ζ) ≈ 8);
/// * state rounding: ½ LSB per operation on O(1) deviations, a random walk over ~10⁴
///   sub-steps (×100), doubled for F ∝ g².
///
/// | type   | LSB      | ε_c term | rounding term | budget |
/// |--------|----------|----------|---------------|--------|
/// | i32f32 | 2.3e-10  | 1.9e-6   | 4.7e-8        | 4e-6   |
/// | i4f28  | 3.7e-9   | 3.0e-5   | 7.5e-7        | 3e-5 (rounded down: ε_c bound is loose by Q) |
/// | f32    | 1.2e-7·x | 2.4e-7   | 6e-6          | 1e-5   |
const BUDGET_I32F32: f64 = 4e-6;
const BUDGET_I4F28: f64 = 3e-5;
const BUDGET_F32: f64 = 1e-5;

fn fixed_agreement(kind: ScalarKind, budget: f64) -> f64 {
    let mut worst = 0.0f64;
    for interp in [Interpolation::Linear, Interpolation::Parabolic] {
        for (name, trace) in traces::all(1e-3) {
            let p = params(trace.dt, 10, interp);
            let exact = run_trace_as(ScalarKind::F64, &p, &trace).unwrap();
            let fixed = run_trace_as(kind, &p, &trace).unwrap();
            let d = max_force_diff(&exact, &fixed) / p.p0;
            assert!(
                d <= budget,
                "{kind:?} {name} {interp:?}: {d:e} of p0 > budget {budget:e}"
            );
            worst = worst.max(d);
        }
    }
    worst
}

#[test]
fn fixed_point_and_f32_agree_with_f64_within_budget() {
    let w1 = fixed_agreement(ScalarKind::I32f32, BUDGET_I32F32);
    let w2 = fixed_agreement(ScalarKind::I4f28, BUDGET_I4F28);
    let w3 = fixed_agreement(ScalarKind::F32, BUDGET_F32);
    println!("worst |ΔF|/p0 at n_sub=10: i32f32 {w1:e}, i4f28 {w2:e}, f32 {w3:e}");
}

#[test]
fn i4f28_refuses_one_thousand_sub_steps() {
    let trace: Trace = traces::step(1e-3);
    let p = params(trace.dt, 1000, Interpolation::Linear);
    let err = run_trace_as(ScalarKind::I4f28, &p, &trace).unwrap_err();
    assert!(err.to_string().contains("i4f28 cannot represent"), "{err}");
}
