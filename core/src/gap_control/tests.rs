//! The outer loop's pieces against hand-derived values; closed-loop stability is tested
//! against the linearised analysis in `host-sim/sim/src/studies/stability/gap_loop.rs`.

extern crate std;
use super::*;
use crate::gap::Geometry;
use crate::levitation::Params;
use crate::scalar::{I32F32, I4F28};
use std::vec::Vec;

/// Eq. 14 as printed (SI), with `g0` in the error replaced by `g_ref` (Eq. 8 with a
/// reference): `B = KI·e_a + KI·(g_ref − g^t)·Δt/2 + (KP + KI·Δt/2)·g_ref`, one sub-step.
/// Returns `(g^{t+Δt}, e_a^{t+Δt})`.
fn eq14_with_reference(p: &Params, g: f64, e_a: f64, h1: f64, g_ref: f64) -> (f64, f64) {
    let (dt, g0c) = (p.dt, 2.0 * p.k0());
    let a = p.r0 * h1 + p.kp + p.ki * dt / 2.0;
    let b = p.ki * e_a + p.ki * (g_ref - g) * dt / 2.0 + (p.kp + p.ki * dt / 2.0) * g_ref;
    let g1 = (b + (g0c / dt - (1.0 - p.alpha) * a) * g) / (g0c / dt + a * p.alpha);
    (g1, e_a + ((g_ref - g) + (g_ref - g1)) * dt / 2.0)
}

#[test]
fn reference_form_is_eq14_with_g_ref() {
    let mut p = Params::paper_wheel(1e-3);
    for alpha in [0.0, 0.5, 1.0] {
        p.alpha = alpha;
        let ctrl = p.compile::<f64>().unwrap();
        let mut st = ctrl.equilibrium_state(0.0104);
        let (g0, vb) = (p.g0(), p.v_base());
        // Independent SI state: g = g0, KI·e_a = R0·h·g0.
        let (mut g, mut e_a) = (g0, p.r0 * 0.0104 * g0 / p.ki);
        for (k, x_ref) in [0.02, -0.05, 0.1, 0.0, 0.3].into_iter().enumerate() {
            let h1 = 0.0104 + 1e-4 * k as f64;
            ctrl.update_with_reference(&mut st, h1 / p.h0, x_ref);
            (g, e_a) = eq14_with_reference(&p, g, e_a, h1, g0 * (1.0 + x_ref));
            assert!(((1.0 + st.x) * g0 - g).abs() < 1e-9 * g0, "α={alpha} k={k}");
            assert!(((1.0 + st.y) * vb - p.ki * e_a).abs() < 1e-9 * vb);
        }
    }
}

#[test]
fn zero_reference_is_the_papers_update_bit_for_bit() {
    let ctrl = Params::paper_wheel(1e-3).compile::<f64>().unwrap();
    let (mut a, mut b) = (ctrl.initial_state(0.01), ctrl.initial_state(0.01));
    for k in 0..500 {
        let h = 1.0 + 0.1 * (k as f64 * 0.05).sin();
        let oa = ctrl.update(&mut a, h);
        let ob = ctrl.update_with_reference(&mut b, h, 0.0);
        assert_eq!(oa, ob);
        assert_eq!(a, b);
    }
}

#[test]
fn constant_gap_settles_at_the_reference_force() {
    // At a fixed gap the inner law is a stable linear loop (−2.51 ± 38.7j s⁻¹) whose integral
    // forces x → x_ref, so the force tends to (1 + x_ref)²; 10 s is 25 time constants.
    let ctrl = Params::paper_wheel(1e-3).compile::<f64>().unwrap();
    let mut st = ctrl.initial_state(0.01);
    let mut out = ctrl.output(&st);
    for _ in 0..10_000 {
        out = ctrl.update_with_reference(&mut st, 1.0, 0.05);
    }
    assert!((out.force - 1.05f64.powi(2)).abs() < 1e-9, "{out:?}");
}

#[test]
fn reference_is_proportional_plus_filtered_derivative() {
    let dt = 1e-3;
    let gp = GapParams::designed();
    let gl = gp.compile::<f64>(dt).unwrap();
    let inner = Params::paper_wheel(dt).compile::<f64>().unwrap();
    let mut st = gl.equilibrium_state(&inner, 0.01);
    // Constant gap: no derivative, x_ref = kp·η.
    st.inner.eta = 0.1;
    st.q = 0.1;
    let mut ov = false;
    assert_eq!(gl.reference(&mut st, &mut ov).0, gp.kp * 0.1);
    // A ramp η = s·t: the backward-Euler filter's derivative settles at exactly s (its
    // steady state solves q_k − q_{k−1} = s·Δt), so x_ref → kp·η + kd·s.
    let s = 2.0; // per unit per second = 20 mm/s
    st.q = 0.0;
    let mut r = 0.0;
    for k in 1..=200 {
        st.inner.eta = s * k as f64 * dt;
        r = gl.reference(&mut st, &mut ov).0;
    }
    let want = gp.kp * st.inner.eta + gp.kd * s;
    assert!((r - want).abs() < 1e-12, "{r} vs {want}");
    // A large error is limited and says so.
    st.inner.eta = 1e3;
    let (r, lim) = gl.reference(&mut st, &mut ov);
    assert!(lim && r == gp.x_ref_max);
    assert!(!ov);
}

#[test]
fn fixed_point_follows_f64() {
    fn run<S: Scalar>() -> Vec<f64> {
        let dt = 1e-3;
        let inner = Params::paper_wheel(dt).compile::<S>().unwrap();
        let gl = GapParams::designed().compile::<S>(dt).unwrap();
        let mut st = gl.equilibrium_state(&inner, 0.01);
        let mut ov = false;
        (0..300)
            .map(|k| {
                let h = 1.0 + 0.05 * (k as f64 * 0.03).sin();
                let o = gl.update(&inner, &mut st, S::from_f64(h, &mut ov));
                assert!(o.inner.status.is_empty());
                o.inner.force.to_f64()
            })
            .collect()
    }
    let r = run::<f64>();
    // Budgets as in `control_vs_reference` (same inner law; the outer loop adds three O(1)
    // products per step): f32 1e-5, I32F32 4e-6, I4F28 3e-5 of p0.
    for (name, got, tol) in [
        ("f32", run::<f32>(), 1e-5),
        ("I32F32", run::<I32F32>(), 4e-6),
        ("I4F28", run::<I4F28>(), 3e-5),
    ] {
        let worst = r
            .iter()
            .zip(&got)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(worst < tol, "{name}: {worst:e}");
    }
}

#[test]
fn bad_gains_are_named() {
    let mut gp = GapParams::designed();
    gp.kd = f64::NAN;
    assert_eq!(
        gp.compile::<f64>(1e-3).err(),
        Some(ParamError::NotFinite(fields::KD))
    );
    gp = GapParams::designed();
    gp.tf = -1e-3;
    assert_eq!(gp.validate(), Err(ParamError::Negative(fields::TF)));
    // Negative gains are the paper geometry's sign (docs/gap-loop.md): accepted.
    gp = GapParams {
        kp: -4e-3,
        kd: -4e-3,
        ..GapParams::designed()
    };
    assert!(gp.compile::<f64>(1e-3).is_ok());
    gp = GapParams::designed();
    gp.x_ref_max = 0.0;
    assert_eq!(
        gp.validate(),
        Err(ParamError::NotPositive(fields::X_REF_MAX))
    );
    assert!(GapParams::designed().compile::<f64>(0.0).is_err());
}

#[test]
fn pair_with_zero_gains_is_the_papers_pair() {
    let inner = Params::paper_wheel(1e-3).compile::<f64>().unwrap();
    let gl = GapParams {
        kp: 0.0,
        kd: 0.0,
        ..GapParams::designed()
    }
    .compile::<f64>(1e-3)
    .unwrap();
    let mut a = crate::guidance::initial_state(&inner, 2e-4);
    let mut b = gl.pair_equilibrium_state(&inner, 2e-4);
    for k in 0..200 {
        let d = 0.02 + 0.05 * (k as f64 * 0.07).sin();
        for g in [Geometry::Paper, Geometry::Ems] {
            let (mut a, mut b) = (a, b);
            let oa = crate::guidance::update(&inner, g, &mut a, d);
            let ob = gl.update_pair(&inner, g, &mut b, d);
            assert_eq!(oa, ob);
        }
        let oa = crate::guidance::update(&inner, Geometry::Paper, &mut a, d);
        let ob = gl.update_pair(&inner, Geometry::Paper, &mut b, d);
        assert_eq!(oa, ob);
    }
}

#[test]
fn pair_reference_pulls_towards_the_centre() {
    // Wheel 1 mm right of centre: the left gap is open (η_L = 0.1), so the left reference
    // rises and the right one falls: the loop pulls left, against the displacement.
    let inner = Params::paper_wheel(1e-3).compile::<f64>().unwrap();
    let gl = GapParams::designed().compile::<f64>(1e-3).unwrap();
    let mut st = gl.pair_equilibrium_state(&inner, 1e-3);
    let mut ov = false;
    let (rl, _) = gl.reference(&mut st.left, &mut ov);
    let (rr, _) = gl.reference(&mut st.right, &mut ov);
    assert!(rl > 0.0 && rr < 0.0 && (rl + rr).abs() < 1e-15);
}
