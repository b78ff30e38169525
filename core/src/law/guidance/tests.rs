extern crate std;
use super::*;
use crate::law::{LawKind, LawParams};

/// The paper's wheel magnet at the state law's own period, and levitation gains that hold it
/// (those of the state law's own tests).
fn setup() -> (Params, StateParams) {
    let mut m = Params::paper_wheel(1e-4);
    m.dt = 1e-4;
    let vb_h0 = m.v_base() / m.h0;
    let tau = 2.0 * m.p0 * m.h0 / (m.r0 * m.i0 * m.i0);
    let kp = 4.0 * vb_h0;
    let timing = StateParams {
        kp,
        kd: 2.0 * tau * (kp - vb_h0),
        ka: 0.0,
        ki: 0.5 * vb_h0,
        kc: 1.0,
        v_max: 1e6,
        rate_hz: StateParams::RATE_HZ,
        observer_hz: StateParams::OBSERVER_HZ,
        geometry: Geometry::Ems,
    };
    (m, timing)
}

fn same_gains(s: &StateParams) -> GuidanceParams {
    GuidanceParams {
        kp: s.kp,
        kd: s.kd,
        ka: 0.0,
        ki: s.ki,
        kc: s.kc,
    }
}

/// In equilibrium at any offset the pair stays there (without the integral, which moves the
/// pair back to `d = 0`): no net force, both coils at `g0`.
#[test]
fn equilibrium_holds_off_centre() {
    let (m, timing) = setup();
    let g = GuidanceParams {
        ki: 0.0,
        ..same_gains(&timing)
    };
    let law = g.compile::<f64>(&timing, &m).unwrap();
    for d in [0.0, 1.5e-3, -0.7e-3] {
        let mut st = law.equilibrium(d);
        for _ in 0..2000 {
            let o = law.update(
                &mut st,
                PairMeasurement {
                    d: d / m.h0,
                    accel: Some(0.0),
                },
                Geometry::Ems,
            );
            assert!(o.force_y.abs() < 1e-12, "d {d}: {o:?}");
            assert!((o.left.g - 1.0).abs() < 1e-12 && (o.right.g - 1.0).abs() < 1e-12);
            assert!(o.status.is_empty());
        }
    }
}

/// Unsaturated, with no accelerometer, the law's two voltages are those of the levitation
/// state law run on each magnet alone with the same gains ([`crate::Law::update_pair`]): the
/// per-magnet integrals are `±u_d` and their sum is the constant the pair law drops. A second
/// implementation, agreeing to rounding over 3000 steps of an arbitrary lateral motion.
#[test]
fn matches_the_per_magnet_state_law_in_the_linear_range() {
    let (m, timing) = setup();
    let law = same_gains(&timing).compile::<f64>(&timing, &m).unwrap();
    let per_magnet = LawParams {
        magnet: m,
        kind: LawKind::State(timing),
    }
    .compile::<f64>()
    .unwrap();
    let d0 = 2e-4;
    let mut st = law.equilibrium(d0);
    let mut pair = per_magnet.pair_equilibrium_state(d0);
    let mut moved = 0.0f64;
    for k in 0..3000 {
        let d = (d0 + 1e-3 * libm::sin(k as f64 * 0.01)) / m.h0;
        let a = law.update(&mut st, PairMeasurement { d, accel: None }, Geometry::Ems);
        let b = per_magnet.update_pair(Geometry::Ems, &mut pair, d);
        for (x, y) in [
            (a.force_y, b.force_y),
            (a.left.voltage, b.left.voltage),
            (a.right.voltage, b.right.voltage),
            (a.left.current, b.left.current),
        ] {
            assert!((x - y).abs() < 1e-9, "step {k}: {a:?} {b:?}");
        }
        moved = moved.max(a.force_y.abs());
    }
    assert!(moved > 1e-2, "the pair never pulled: {moved}");
}

/// The common mode is held by `kc` alone (G2): both coils' flux raised by the same amount at
/// `d = 0` decays as `exp(−(1 + Kc)·t/τ)` (its closed form), with no net force and the
/// integral untouched.
#[test]
fn the_common_mode_decays_at_its_closed_form_rate() {
    let (m, timing) = setup();
    let g = GuidanceParams {
        kc: 20.0,
        ..same_gains(&timing)
    };
    let law = g.compile::<f64>(&timing, &m).unwrap();
    let tau = 2.0 * m.p0 * m.h0 / (m.r0 * m.i0 * m.i0);
    let kc = g.kc * m.i0 / m.v_base();
    let rate = (1.0 + kc) / tau;
    let mut st = law.equilibrium(0.0);
    let x0 = 1e-3;
    st.left.x = x0;
    st.right.x = x0;
    let t = 0.5 / rate;
    let steps = (t / m.dt).round() as usize;
    let mut o = PairOutput::default();
    for _ in 0..steps {
        o = law.update(
            &mut st,
            PairMeasurement {
                d: 0.0,
                accel: None,
            },
            Geometry::Ems,
        );
        assert!(o.force_y.abs() < 1e-15);
    }
    let measured = -(st.left.x / x0).ln() / (steps as f64 * m.dt);
    assert!(
        (measured / rate - 1.0).abs() < 5e-3,
        "{measured} vs {rate} 1/s"
    );
    assert_eq!(st.integral, 0.0);
    assert_eq!(st.left.x, st.right.x);
    let _ = o;
}

/// A rigid lateral mass `M` between two EMS rails under a constant side force: with the
/// integral the offset returns to 0 (the mode the pair can hold); without it, it settles at
/// the offset the proportional gain leaves. Semi-implicit Euler at the law's period, the
/// exact lateral acceleration measured.
#[test]
fn the_integral_holds_the_offset_at_zero() {
    let (m, timing) = setup();
    let mass = 2000.0;
    let side = 0.05 * m.p0;
    let fly = |g: GuidanceParams| {
        let law = g.compile::<f64>(&timing, &m).unwrap();
        let mut st = law.equilibrium(0.0);
        let (mut y, mut v, mut a) = (0.0, 0.0, 0.0);
        for _ in 0..(40.0 / m.dt) as usize {
            let o = law.update(
                &mut st,
                PairMeasurement {
                    d: y / m.h0,
                    accel: Some(a / GRAVITY),
                },
                Geometry::Ems,
            );
            a = (o.force_y * m.p0 + side) / mass;
            v += a * m.dt;
            y += v * m.dt;
        }
        y
    };
    let g = GuidanceParams {
        ka: 10.0,
        ..same_gains(&timing)
    };
    let held = fly(g);
    let offset = fly(GuidanceParams { ki: 0.0, ..g });
    assert!(held.abs() < 1e-7, "{held}");
    assert!(offset.abs() > 1e-5, "{offset}");
}

#[test]
fn bad_gains_are_named() {
    let (m, timing) = setup();
    let g = same_gains(&timing);
    assert_eq!(
        GuidanceParams { kd: -1.0, ..g }
            .compile::<f64>(&timing, &m)
            .unwrap_err(),
        ParamError::Negative(fields::KD)
    );
    assert_eq!(
        GuidanceParams { ki: f64::NAN, ..g }
            .compile::<f64>(&timing, &m)
            .unwrap_err(),
        ParamError::NotFinite(fields::KI)
    );
}
