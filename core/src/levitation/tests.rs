use super::*;
use crate::scalar::{I32F32, I4F28};

fn paper(n_sub: u32, interp: Interpolation) -> Params {
    let mut p = Params::paper_wheel(1e-3);
    p.n_sub = n_sub;
    p.interpolation = interp;
    p
}

fn equilibrium_holds<S: Scalar>(n_sub: u32, interp: Interpolation) {
    let p = paper(n_sub, interp);
    let ctrl = p.compile::<S>().unwrap();
    let mut st = ctrl.initial_state(p.h0);
    let mut ov = false;
    let h = ctrl.gap_pu(p.h0, &mut ov);
    for _ in 0..200 {
        let out = ctrl.update(&mut st, h);
        assert!(out.status.is_empty());
        // Exactly: the deviation form makes equilibrium the zero state in every type.
        assert_eq!(st.x, S::ZERO, "{}", S::NAME);
        assert_eq!(st.y, S::ZERO, "{}", S::NAME);
        let si = ctrl.to_si(&out);
        assert!((si.force - p.p0).abs() <= 1e-9 * p.p0);
        assert!((si.voltage - p.v_base()).abs() <= 1e-9 * p.v_base());
    }
}

#[test]
fn equilibrium_at_constant_gap_all_types() {
    for interp in [Interpolation::Linear, Interpolation::Parabolic] {
        for n in [1, 10, 1000] {
            equilibrium_holds::<f64>(n, interp);
            equilibrium_holds::<f32>(n, interp);
            equilibrium_holds::<I32F32>(n, interp);
        }
        equilibrium_holds::<I4F28>(1, interp);
        equilibrium_holds::<I4F28>(10, interp);
    }
}

/// Linearised g-loop at fixed gap h0 (continuous time): τ·ẋ = y − (1 + kpv)·x − η,
/// ẏ = −ki·x, with τ = G0·g0/V_b and ki = KI·g0/V_b. Its poles are the roots of
/// τ s² + (1 + kpv) s + ki = 0.
fn continuous_poles(p: &Params) -> (f64, f64) {
    let vb = p.v_base();
    let tau = 2.0 * p.k0() * p.g0() / vb;
    let b = 1.0 + p.kp * p.g0() / vb;
    let ki = p.ki * p.g0() / vb;
    let disc = b * b - 4.0 * tau * ki;
    assert!(disc < 0.0, "the paper's loop is underdamped");
    (-b / (2.0 * tau), (-disc).sqrt() / (2.0 * tau))
}

#[test]
fn gap_step_settles_at_the_predicted_rate() {
    // Force regulation: after a gap step g returns to g0 with the envelope e^{σt}.
    let p = paper(10, Interpolation::Linear);
    let (sigma, omega) = continuous_poles(&p);
    let ctrl = p.compile::<f64>().unwrap();
    let mut st = ctrl.initial_state(p.h0);
    let h = 0.009 / p.h0; // the gap closes by 1 mm
    let mut peaks = [0.0f64; 2];
    let (t1, t2) = (1.0, 2.0);
    let mut max_window = |t: f64, x: f64| {
        // The largest |x| over one period after t1 and after t2.
        let period = 2.0 * core::f64::consts::PI / omega;
        if t >= t1 && t < t1 + period {
            peaks[0] = peaks[0].max(x.abs());
        }
        if t >= t2 && t < t2 + period {
            peaks[1] = peaks[1].max(x.abs());
        }
    };
    for k in 1..=4000 {
        let out = ctrl.update(&mut st, h);
        assert!(out.status.is_empty());
        max_window(k as f64 * p.dt, st.x);
    }
    // Settled: 4 s ≈ 10 time constants.
    assert!(st.x.abs() < 1e-4, "x = {}", st.x);
    // The decay over one second matches the continuous poles' real part to 2 %
    // (the α = ½ discretisation at Δt = 1 ms is close to the continuous system).
    let measured = (peaks[1] / peaks[0]).ln() / (t2 - t1);
    assert!(
        ((measured - sigma) / sigma).abs() < 0.02,
        "decay {measured} vs pole {sigma}"
    );
    // The steady voltage carries R0·h·g0 at the new gap.
    let si = ctrl.to_si(&ctrl.output(&st));
    assert!((si.voltage - p.r0 * 0.009 * p.g0()).abs() < 1e-3);
}

#[test]
fn voltage_bound_saturates_with_anti_windup() {
    let mut p = paper(10, Interpolation::Linear);
    p.v_max = 50.0; // 43 V nominal
    let ctrl = p.compile::<f64>().unwrap();
    let mut st = ctrl.initial_state(p.h0);
    let mut saw = false;
    // A gap that opens to 14 mm needs R0·h·g0 = 60 V in steady state, more than the supply.
    for k in 1..=2000 {
        let h = (p.h0 + 0.004 * (k as f64 / 20.0).min(1.0)) / p.h0;
        let out = ctrl.update(&mut st, h);
        let si = ctrl.to_si(&out);
        assert!(si.voltage <= p.v_max + 1e-9 && si.voltage >= -p.v_max - 1e-9);
        if out.status.contains(Status::VOLTAGE_SATURATED) {
            saw = true;
            assert!((si.voltage.abs() - p.v_max).abs() < 1e-9);
        }
    }
    assert!(saw, "the bound must have been reached");
    // Anti-windup: the integral did not run away while the bound held...
    assert!(1.0 + st.y <= p.v_max / p.v_base() + 1e-9, "y = {}", st.y);
    // ...so once the gap is back where 50 V suffice (11 mm: 47 V) the loop settles as fast
    // as from an ordinary step (envelope e^{-2.5 t}, see gap_step_settles_at_the_predicted_rate).
    for _ in 0..4000 {
        ctrl.update(&mut st, 0.011 / p.h0);
    }
    assert!(st.x.abs() < 1e-3, "x = {}", st.x);
}

#[test]
fn collision_is_an_event_not_a_nan() {
    let p = paper(10, Interpolation::Parabolic);
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
}

#[test]
fn nan_gap_holds_state() {
    let p = paper(1, Interpolation::Linear);
    let ctrl = p.compile::<f64>().unwrap();
    let mut st = ctrl.initial_state(p.h0);
    ctrl.update(&mut st, 0.95);
    let before = st;
    let out = ctrl.update(&mut st, f64::NAN);
    assert!(out.status.contains(Status::INVALID_INPUT));
    assert_eq!(st, before);
}

#[test]
fn bad_parameters_are_named() {
    let mut p = paper(1, Interpolation::Linear);
    p.h0 = -1.0;
    assert_eq!(p.validate(), Err(ParamError::NotPositive(fields::H0)));
    let mut p = paper(1, Interpolation::Linear);
    p.alpha = 1.5;
    assert_eq!(p.validate(), Err(ParamError::AlphaOutOfRange));
    let mut p = paper(1, Interpolation::Linear);
    p.kp = f64::NAN;
    assert_eq!(p.validate(), Err(ParamError::NotFinite(fields::KP)));
    let mut p = paper(1, Interpolation::Linear);
    p.n_sub = 0;
    assert_eq!(p.validate(), Err(ParamError::NotPositive(fields::N_SUB)));
}

#[test]
fn fixed_point_refuses_unrepresentable_sub_steps() {
    let p = paper(1000, Interpolation::Linear);
    match p.compile::<I4F28>() {
        Err(ParamError::Unrepresentable { field, .. }) => assert_eq!(field.name, "c"),
        other => panic!("expected Unrepresentable, got {other:?}"),
    }
    assert!(p.compile::<I32F32>().is_ok());
}

mod props {
    use super::*;
    use proptest::prelude::*;

    fn any_gap() -> impl Strategy<Value = f64> {
        prop_oneof![
            4 => 0.0f64..3.0,
            1 => prop::num::f64::ANY,
            1 => Just(0.0),
            1 => Just(f64::INFINITY),
            1 => Just(f64::NEG_INFINITY),
            1 => Just(f64::NAN),
        ]
    }

    fn any_params() -> impl Strategy<Value = Params> {
        (
            prop_oneof![Just(0.0), 1e-6f64..1e6],
            prop_oneof![Just(0.0), 1e-6f64..1e6],
            0.0f64..=1.0,
            1u32..50,
            prop_oneof![Just(f64::INFINITY), 1.0f64..1e4],
            prop::bool::ANY,
            1e-6f64..1e-1,
            prop::bool::ANY,
        )
            .prop_map(|(kp, ki, alpha, n_sub, v_max, parabolic, dt, accurate)| {
                let mut p = Params::paper_wheel(dt);
                p.kp = kp;
                p.ki = ki;
                p.alpha = alpha;
                p.n_sub = n_sub;
                p.v_max = v_max;
                p.scheme = if accurate {
                    Scheme::Accurate
                } else {
                    Scheme::Paper
                };
                p.interpolation = if parabolic {
                    Interpolation::Parabolic
                } else {
                    Interpolation::Linear
                };
                p
            })
    }

    fn never_nan<S: Scalar>(p: &Params, gaps: &[f64]) {
        let Ok(ctrl) = p.compile::<S>() else { return };
        let mut st = ctrl.initial_state(p.h0);
        for &h in gaps {
            let mut ov = false;
            let out = ctrl.update(&mut st, S::from_f64(h, &mut ov));
            for v in [out.g, out.force, out.current, out.voltage] {
                let f = v.to_f64();
                assert!(f.is_finite(), "{} gave {f} for h = {h}", S::NAME);
            }
            assert!(out.g.to_f64() >= 0.0, "negative g");
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig {
            cases: 300,
            rng_algorithm: proptest::test_runner::RngAlgorithm::ChaCha,
            rng_seed: proptest::test_runner::RngSeed::Fixed(0x5eed_0001),
            failure_persistence: None,
            ..ProptestConfig::default()
        })]
        #[test]
        fn no_input_panics_or_yields_nan(p in any_params(), gaps in prop::collection::vec(any_gap(), 1..40)) {
            never_nan::<f64>(&p, &gaps);
            never_nan::<f32>(&p, &gaps);
            never_nan::<I32F32>(&p, &gaps);
            never_nan::<I4F28>(&p, &gaps);
        }

        #[test]
        fn params_validation_never_panics(i0 in prop::num::f64::ANY, h0 in prop::num::f64::ANY, r0 in prop::num::f64::ANY, dt in prop::num::f64::ANY, n in 0u32..3) {
            let mut p = Params::paper_wheel(dt);
            p.i0 = i0; p.h0 = h0; p.r0 = r0; p.n_sub = n;
            let _ = p.compile::<f64>();
            let _ = p.compile::<I4F28>();
            p.scheme = Scheme::Accurate;
            let _ = p.compile::<f64>();
            let _ = p.compile::<I4F28>();
        }
    }
}

#[test]
fn equilibrium_state_holds_an_offset_gap_exactly() {
    let p = paper(10, Interpolation::Parabolic);
    let ctrl = p.compile::<f64>().unwrap();
    let h = 0.0123;
    let mut st = ctrl.equilibrium_state(h);
    for _ in 0..100 {
        let out = ctrl.update(&mut st, h / p.h0);
        assert!((ctrl.to_si(&out).force - p.p0).abs() < 1e-9 * p.p0);
        assert!((ctrl.to_si(&out).voltage - p.r0 * h * p.g0()).abs() < 1e-9);
    }
}
