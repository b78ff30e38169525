//! Tests of the accurate scheme (`accurate.rs`) against closed forms written here, not taken
//! from the code under test.

extern crate std;

use super::*;
use crate::scalar::{I32F32, I4F28};

fn accurate(dt: f64, interp: Interpolation) -> Params {
    let mut p = Params::paper_wheel(dt);
    p.scheme = Scheme::Accurate;
    p.interpolation = interp;
    p
}

/// `(τ, p, ki)` of the per-unit loop at gap deviation `eta` (accurate.rs module docs), from
/// the SI parameters.
fn loop_of(p: &Params, eta: f64) -> (f64, f64, f64) {
    let vb = p.r0 * p.i0;
    let g0 = p.i0 / p.h0;
    let k0 = p.p0 * p.h0 * p.h0 / (p.i0 * p.i0);
    (
        2.0 * k0 * g0 / vb,
        1.0 + p.kp * g0 / vb + eta,
        p.ki * g0 / vb,
    )
}

/// Exact solution of `τ·ẋ = y − η − p·x`, `ẏ = −ki·x` at a constant gap from `(x0, y0)` after
/// time `t`: `z(t) = z_eq + e^{Jt}(z0 − z_eq)`, `z_eq = (0, η)`, and for `J` with eigenvalues
/// `σ ± iω`: `e^{Jt} = e^{σt}[cos(ωt)·I + sin(ωt)/ω·(J − σI)]`.
fn exact(p: &Params, eta: f64, x0: f64, y0: f64, t: f64) -> (f64, f64) {
    let (tau, pp, ki) = loop_of(p, eta);
    let j = [[-pp / tau, 1.0 / tau], [-ki, 0.0]];
    let sigma = -pp / (2.0 * tau);
    let disc = ki / tau - sigma * sigma;
    assert!(disc > 0.0, "the paper's loop is underdamped");
    let w = disc.sqrt();
    let (c, s) = ((w * t).cos(), (w * t).sin() / w);
    let e = (sigma * t).exp();
    let (dx, dy) = (x0, y0 - eta);
    let x = e * (c * dx + s * ((j[0][0] - sigma) * dx + j[0][1] * dy));
    let y = e * (c * dy + s * (j[1][0] * dx + (j[1][1] - sigma) * dy));
    (x, y + eta)
}

/// Runs from `(x0, y0)` at constant gap deviation `eta` for `t_end`; returns `(x, y)`.
fn run_fixed_gap(p: &Params, eta: f64, x0: f64, y0: f64, t_end: f64) -> (f64, f64) {
    let ctrl = p.compile::<f64>().unwrap();
    let mut st = ctrl.initial_state(p.h0 * (1.0 + eta));
    st.x = x0;
    st.y = y0;
    let steps = (t_end / p.dt).round() as usize;
    for _ in 0..steps {
        let out = ctrl.update(&mut st, 1.0 + eta);
        assert!(out.status.is_empty());
    }
    (st.x, st.y)
}

#[test]
fn interval_count_follows_the_documented_estimate() {
    // Paper values: ω = √(ki/τ) = 38.8 s⁻¹, h_max = (720·1e-6/ω⁵)^¼ = 1.69 ms (module docs).
    let (tau, _, ki) = loop_of(&Params::paper_wheel(1e-3), 0.0);
    let omega = (ki / tau).sqrt();
    let h_max = (720.0 * 1e-6 / omega.powi(5)).powf(0.25);
    assert!((h_max - 1.69e-3).abs() < 0.01e-3, "h_max = {h_max}");
    for (dt, m) in [(1e-4, 1), (1e-3, 1), (1.6e-3, 1), (1.8e-3, 2), (1e-2, 6)] {
        let p = accurate(dt, Interpolation::Linear);
        assert_eq!(accurate::intervals(&p), m, "dt = {dt}");
        let ctrl = p.compile::<f64>().unwrap();
        assert_eq!(ctrl.accurate_intervals(), m);
    }
    // Huge steps are capped, never a panic.
    assert_eq!(
        accurate::intervals(&accurate(1e3, Interpolation::Linear)),
        accurate::MAX_INTERVALS
    );
    assert_eq!(
        Params::paper_wheel(1e-3)
            .compile::<f64>()
            .unwrap()
            .accurate_intervals(),
        0
    );
}

#[test]
fn fourth_order_at_a_fixed_gap_against_the_closed_form() {
    // A perturbed g-loop at a fixed gap (η = 0.05): the exact solution is a damped
    // oscillation (`exact`). Steps with m = 1 interval, so the order is in Δt itself.
    let (eta, x0, y0, t_end) = (0.05, 0.05, 0.02, 0.4);
    let mut errs = [0.0; 4];
    for (k, dt) in [1.6e-3, 8e-4, 4e-4, 2e-4].into_iter().enumerate() {
        let p = accurate(dt, Interpolation::Linear);
        assert_eq!(accurate::intervals(&p), 1);
        let (x, y) = run_fixed_gap(&p, eta, x0, y0, t_end);
        let (xe, ye) = exact(&p, eta, x0, y0, t_end);
        errs[k] = (x - xe).abs().max((y - ye).abs() / 15.0);
    }
    for w in errs.windows(2) {
        let order = (w[0] / w[1]).log2();
        std::eprintln!("error {:.3e} -> {:.3e}: order {order:.3}", w[0], w[1]);
        assert!(
            (3.8..4.3).contains(&order),
            "order {order}, errors {errs:?}"
        );
    }
    // The estimate of the module docs: local error ≤ ε = 1e-6 per second per unit of state at
    // h = 1.6 ms (ω⁵h⁴/720 = 0.8e-6); over 0.4 s on a state of size ≤ 0.1 (y/15 scaled),
    // ≤ 0.4·1e-6·0.1 = 4e-8.
    assert!(errs[0] < 4e-8, "{errs:?}");
}

fn equilibrium_holds<S: Scalar>(dt: f64, interp: Interpolation) {
    let p = accurate(dt, interp);
    let ctrl = p.compile::<S>().unwrap();
    let mut ov = false;
    for h in [p.h0, 0.0123] {
        let mut st = ctrl.equilibrium_state(h);
        let h_pu = ctrl.gap_pu(h, &mut ov);
        for _ in 0..100 {
            let out = ctrl.update(&mut st, h_pu);
            assert!(out.status.is_empty());
            // r = 0 at x = 0, y = η: the increments vanish exactly in every type.
            assert_eq!(st.x, S::ZERO, "{}", S::NAME);
        }
        assert_eq!(st, ctrl.equilibrium_state(h), "{}", S::NAME);
    }
}

#[test]
fn equilibrium_is_exact_in_every_type() {
    for interp in [Interpolation::Linear, Interpolation::Parabolic] {
        for dt in [1e-4, 1e-3, 1e-2] {
            equilibrium_holds::<f64>(dt, interp);
            equilibrium_holds::<f32>(dt, interp);
            equilibrium_holds::<I32F32>(dt, interp);
            equilibrium_holds::<I4F28>(dt, interp);
        }
    }
}

#[test]
fn n_sub_and_alpha_do_not_matter() {
    let base = accurate(1e-3, Interpolation::Parabolic);
    let mut other = base;
    other.n_sub = 1000;
    other.alpha = 1.0;
    let (a, b) = (
        base.compile::<f64>().unwrap(),
        other.compile::<f64>().unwrap(),
    );
    let (mut sa, mut sb) = (a.initial_state(base.h0), b.initial_state(base.h0));
    for k in 0..300 {
        let h = 1.0 + 0.1 * (k as f64 * 0.05).sin();
        assert_eq!(a.update(&mut sa, h), b.update(&mut sb, h));
    }
    // ...so i4f28 compiles it where the paper scheme's sub-step gain is unrepresentable.
    assert!(other.compile::<I4F28>().is_ok());
}

#[test]
fn voltage_bound_saturates_with_anti_windup() {
    // The paper-scheme test's scenario (tests.rs), same expectations.
    let mut p = accurate(1e-3, Interpolation::Linear);
    p.v_max = 50.0;
    let ctrl = p.compile::<f64>().unwrap();
    let mut st = ctrl.initial_state(p.h0);
    let mut saw = false;
    for k in 1..=2000 {
        let h = (p.h0 + 0.004 * (k as f64 / 20.0).min(1.0)) / p.h0;
        let out = ctrl.update(&mut st, h);
        let si = ctrl.to_si(&out);
        assert!(si.voltage.abs() <= p.v_max + 1e-9);
        if out.status.contains(Status::VOLTAGE_SATURATED) {
            saw = true;
            assert!((si.voltage.abs() - p.v_max).abs() < 1e-9);
        }
    }
    assert!(saw, "the bound must have been reached");
    assert!(1.0 + st.y <= p.v_max / p.v_base() + 1e-9, "y = {}", st.y);
    // Saturated at 14 mm the coil alone settles where R0·h·g = V_max: g/g0 = 50/(1.4·43),
    // at the rate (1 + η)/τ = 3.5 s⁻¹: after ~2 s within e^{−7}·0.17 ≈ 1.6e-4 of it.
    let g_sat = 50.0 / (1.4 * 43.0);
    assert!((1.0 + st.x - g_sat).abs() < 3e-4, "x = {}", st.x);
    for _ in 0..4000 {
        ctrl.update(&mut st, 0.011 / p.h0);
    }
    assert!(st.x.abs() < 1e-3, "x = {}", st.x);
}

#[test]
fn current_clamp_holds_g_at_zero() {
    // An integral wound to V = −19·V_b: x falls at 19/τ ≈ 48 per second over a quarter of the
    // 0.16-s loop period, far below −1, so the clamp must act; g never goes negative.
    let p = accurate(1e-3, Interpolation::Linear);
    let ctrl = p.compile::<f64>().unwrap();
    let mut st = ctrl.initial_state(p.h0);
    st.y = -20.0;
    let mut saw = false;
    for _ in 0..1000 {
        let out = ctrl.update(&mut st, 1.0);
        assert!(out.g >= 0.0 && out.force.is_finite());
        saw |= out.status.contains(Status::CURRENT_CLAMPED);
    }
    assert!(saw, "the clamp must have acted");
    assert!(st.x.abs() < 0.1, "and the loop recovers: x = {}", st.x);
}

#[test]
fn collision_and_nan_like_the_paper_scheme() {
    let p = accurate(1e-3, Interpolation::Parabolic);
    let ctrl = p.compile::<f64>().unwrap();
    let mut st = ctrl.initial_state(p.h0);
    for h in [0.5, 0.0, -1.0, -1e300] {
        let out = ctrl.update(&mut st, h);
        assert!(out.force.is_finite() && out.g.is_finite() && out.voltage.is_finite());
        if h <= 0.0 {
            assert!(out.status.contains(Status::COLLISION));
            assert_eq!(out.current, 0.0);
        }
    }
    let before = st;
    let out = ctrl.update(&mut st, f64::NAN);
    assert!(out.status.contains(Status::INVALID_INPUT));
    assert_eq!(st, before);
}

#[test]
fn the_reference_of_an_outer_loop_is_honoured() {
    // With g_ref = g0·(1 + r) held over each step (an outer gap loop's output), the accurate
    // scheme must agree with the paper scheme at many sub-steps (a first-order, independent
    // discretisation of the same ODE): error of the paper scheme ~ δ·(rate) ≈ 1e-6 here.
    let mut paper = Params::paper_wheel(1e-3);
    paper.n_sub = 4000;
    let acc = accurate(1e-3, Interpolation::Linear);
    let (cp, ca) = (
        paper.compile::<f64>().unwrap(),
        acc.compile::<f64>().unwrap(),
    );
    let (mut sp, mut sa) = (cp.initial_state(paper.h0), ca.initial_state(acc.h0));
    let mut worst = 0.0f64;
    for k in 1..=400 {
        let h = 1.0 + 0.05 * ((k as f64) * 0.02).sin();
        let r = 0.03 * ((k as f64) * 0.013).cos();
        let op = cp.update_with_reference(&mut sp, h, r);
        let oa = ca.update_with_reference(&mut sa, h, r);
        worst = worst.max((op.force - oa.force).abs());
    }
    assert!(worst < 5e-6, "max |ΔF|/p0 = {worst:e}");
    // And the reference matters: the same run with r = 0 differs by far more.
    let mut s0 = ca.initial_state(acc.h0);
    let mut sr = ca.initial_state(acc.h0);
    let mut diff = 0.0f64;
    for _ in 0..100 {
        let a = ca.update_with_reference(&mut s0, 1.0, 0.0);
        let b = ca.update_with_reference(&mut sr, 1.0, 0.03);
        diff = diff.max((a.force - b.force).abs());
    }
    assert!(diff > 1e-2, "{diff}");
}
