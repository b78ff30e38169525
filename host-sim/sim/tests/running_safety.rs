//! The running-safety indices (`output::running_safety`) against values worked out by hand.

use maglev_sim::running_safety::{
    body_acceleration, derailment_quotient, low_pass, percentile, prudhomme_limit, sliding_mean,
    sperling, sperling_weight, unloading, wheelset_lateral_force, window, Direction,
};
use std::f64::consts::TAU;

#[test]
fn sliding_mean_and_percentile_by_hand() {
    assert_eq!(sliding_mean(&[1.0, 2.0, 3.0, 4.0], 2), vec![1.5, 2.5, 3.5]);
    assert!(sliding_mean(&[1.0], 2).is_empty());
    let x: Vec<f64> = (1..=10_000).map(f64::from).collect();
    // ceil(0.9985 · 10 000) = 9985th smallest.
    assert_eq!(percentile(&x, 99.85), 9985.0);
    assert_eq!(percentile(&x[..10], 99.85), 10.0);
    assert_eq!(window(0.1), 20);
}

/// Y/Q = 0.3 everywhere but one sample at 2.0: with 20 samples in 2 m, the 20 windows that
/// hold the spike average 0.3 + 1.7/20 = 0.385; they are 20 of 981 means (2 %, above the
/// 0.15 % the percentile leaves out), so the 99.85th percentile is 0.385, a pass. Without
/// the sliding mean the spike alone would fail 0.8.
#[test]
fn derailment_quotient_by_hand() {
    let q = vec![60e3; 1000];
    let mut y: Vec<f64> = q.iter().map(|q| 0.3 * q).collect();
    y[500] = -2.0 * q[500];
    let i = derailment_quotient(&y, &q, 0.1);
    assert!((i.value - 0.385).abs() < 1e-12, "{}", i.value);
    assert!(i.pass && i.limit == 0.8);
    // A wheel off its rail over a whole window fails.
    let mut q_off = q.clone();
    for v in &mut q_off[100..130] {
        *v = 0.0;
    }
    assert!(!derailment_quotient(&y, &q_off, 0.1).pass);
}

#[test]
fn unloading_and_body_acceleration_by_hand() {
    let p0 = 56e3;
    let i = unloading(&[p0, 0.5 * p0, 0.7 * p0], p0);
    assert!((i.value - 0.5).abs() < 1e-15 && i.pass);
    let i = unloading(&[p0, -10.0], p0);
    assert_eq!(i.value, 1.0);
    assert!(!i.pass);
    let i = body_acceleration(&[0.1, -3.0, 2.0]);
    assert_eq!(i.value, 3.0);
    assert!(!i.pass && i.limit == 2.5);
}

/// Prud'homme for a 140 kN axle: 10 + 140/3 kN = 56.667 kN; a constant ΣY of 50 kN passes,
/// 60 kN fails.
#[test]
fn wheelset_lateral_force_by_hand() {
    assert!((prudhomme_limit(140e3) - 56_666.666_666_666_67).abs() < 1e-6);
    assert!(wheelset_lateral_force(&[50e3; 100], 140e3, 0.1).pass);
    let i = wheelset_lateral_force(&[-60e3; 100], 140e3, 0.1);
    assert_eq!(i.value, 60e3);
    assert!(!i.pass);
}

/// A pure 2 Hz vertical sine of 0.5 m/s² (50 cm/s²) over 10 whole periods lies in one FFT
/// bin: W = 0.896 (50³ · 0.325·2² / 2)^{1/10} = 3.216; a lateral 8 Hz one of 0.2 m/s² has
/// F = 650/64 and W = 0.896 (20³ · 10.156 / 8)^{1/10}.
#[test]
fn sperling_of_pure_sines_by_hand() {
    let dt = 1e-3;
    let n = 5000;
    let sine = |amp: f64, f: f64| -> Vec<f64> {
        (0..n)
            .map(|i| amp * (TAU * f * i as f64 * dt + 0.3).sin())
            .collect()
    };
    let want = 0.896 * (50f64.powi(3) * 0.325 * 4.0 / 2.0).powf(0.1);
    let i = sperling(&sine(0.5, 2.0), dt, Direction::Vertical);
    assert!((i.value - want).abs() < 1e-9, "{} vs {want}", i.value);
    assert!(!i.pass, "{want} > 2.5");
    assert_eq!(sperling_weight(Direction::Lateral, 8.0), 650.0 / 64.0);
    let want = 0.896 * (20f64.powi(3) * 650.0 / 64.0 / 8.0).powf(0.1);
    let i = sperling(&sine(0.2, 8.0), dt, Direction::Lateral);
    assert!((i.value - want).abs() < 1e-9, "{} vs {want}", i.value);
}

/// The 20 Hz low-pass at the runs' 2 ms step: a sine's steady amplitude through it against
/// the 4th-order Butterworth's digital response written here, |H| = 1/√(1 + (tan(πf·dt)/
/// tan(πfc·dt))⁸) (−3 dB at fc), measured by projection over the last 200 periods' worth of
/// samples; a constant signal passes unchanged from its first sample. At the P2 resonance
/// (64 Hz) a wheel force swinging 90 % of its static value keeps under 1 % of it.
#[test]
fn low_pass_against_the_butterworth_response() {
    let (dt, fc) = (2e-3, 20.0);
    let n = 20_000;
    for f in [2.0, 10.0, 20.0, 40.0, 64.0] {
        let w = TAU * f;
        let x: Vec<f64> = (0..n).map(|i| (w * i as f64 * dt).sin()).collect();
        let y = low_pass(&x, dt, fc);
        let m = 10_000; // 20 s: an integer number of periods at every f here
        let (mut c, mut s) = (0.0, 0.0);
        for (i, v) in y.iter().enumerate().skip(n - m) {
            c += v * (w * i as f64 * dt).cos();
            s += v * (w * i as f64 * dt).sin();
        }
        let got = 2.0 * (c * c + s * s).sqrt() / m as f64;
        let ratio = (std::f64::consts::PI * f * dt).tan() / (std::f64::consts::PI * fc * dt).tan();
        let want = 1.0 / (1.0 + ratio.powi(8)).sqrt();
        println!("{f} Hz: gain {got:.6}, Butterworth {want:.6}");
        assert!((got - want).abs() < 1e-6, "{f} Hz: {got} against {want}");
    }
    let flat = low_pass(&[55.9e3; 100], dt, fc);
    assert!(flat.iter().all(|v| (v - 55.9e3).abs() < 1e-9), "{flat:?}");
    let p0 = 55.9e3;
    let q: Vec<f64> = (0..5000)
        .map(|i| p0 * (1.0 - 0.9 * (TAU * 64.0 * i as f64 * dt).sin()))
        .collect();
    assert!(unloading(&q, p0).value > 0.89);
    let filtered = unloading(&low_pass(&q, dt, fc)[500..], p0).value;
    assert!(filtered < 0.01, "{filtered}");
}
