//! Ground levels and verdicts against values worked out by hand (docs/ground.md, "Levels",
//! "Verdicts"): the VdB of a sine of known amplitude, the maximum 1-s running rms of bursts
//! of known length, the PPV, and each verdict on both sides of its criterion.

use maglev_sim::ground::criteria::{din, din_guideline, fta};
use maglev_sim::ground::levels::{of_velocity, vdb};
use std::f64::consts::PI;

const DT: f64 = 1.0 / 1024.0;

/// `n` samples of `a·sin(2π·f·t)` between `t0` and `t1` (s), zero elsewhere.
fn burst(n: usize, a: f64, f: f64, t0: f64, t1: f64) -> Vec<f64> {
    (0..n)
        .map(|j| {
            let t = j as f64 * DT;
            if t >= t0 && t < t1 {
                a * (2.0 * PI * f * t).sin()
            } else {
                0.0
            }
        })
        .collect()
}

/// VdB = dB re 1e-9 m/s − 20·log10(25.4) = − 28.0967 dB (2.54e-8 / 1e-9 = 25.4).
#[test]
fn vdb_is_db_re_1e9_minus_28_0967() {
    assert!((vdb(100.0) - 71.9033).abs() < 1e-4);
}

/// A 32 Hz sine of 1 mm/s over 10 s (64 cycles a second: every 1-s window holds whole
/// cycles): rms 0.70711 mm/s, 116.9897 dB re 1e-9 m/s, 88.8930 VdB (by hand:
/// 20·log10(7.0711e-4/1e-9), 20·log10(7.0711e-4/2.54e-8)). The overall levels are these to
/// 1e-9 dB; the 31.5 Hz band (28.2–35.5 Hz) holds the sine to 0.05 dB (the rest of a
/// 10-s sine's spectrum lies outside it); the dominant band is 31.5 Hz.
#[test]
fn a_sine_of_known_amplitude() {
    let v = burst(10 * 1024, 1e-3, 32.0, 0.0, 10.0);
    let l = of_velocity(&v, DT).unwrap();
    let run = l.overall_max_running_db.unwrap();
    assert!((run - 116.9897).abs() < 1e-4, "{run}");
    assert!((vdb(run) - 88.8930).abs() < 1e-4);
    assert!((l.overall_record_db.unwrap() - 116.9897).abs() < 1e-4);
    let band = l
        .bands
        .iter()
        .find(|b| b.band.nominal_hz() == 31.5)
        .unwrap();
    assert!((band.record_db.unwrap() - 116.9897).abs() < 0.05);
    assert!((band.max_running_db.unwrap() - 116.9897).abs() < 0.05);
    assert_eq!(l.dominant_hz, Some(band.band.exact_hz()));
    assert!((l.ppv - 1e-3).abs() < 1e-9);
}

/// Bursts in a 10-s record: a 2-s burst's maximum 1-s rms is the sine's, A/√2, its
/// whole-record rms A/√10 (2 s of A²/2 in 10 s); a 0.5-s burst's maximum 1-s rms is A/2
/// (0.5 s of A²/2 in a 1-s window). The running window is 1 s, not a peak.
#[test]
fn running_rms_of_bursts() {
    let a = 2e-4;
    let l = of_velocity(&burst(10 * 1024, a, 32.0, 3.0, 5.0), DT).unwrap();
    let db = |x: f64| 20.0 * (x / 1e-9).log10();
    assert!((l.overall_max_running_db.unwrap() - db(a / 2f64.sqrt())).abs() < 1e-9);
    assert!((l.overall_record_db.unwrap() - db(a / 10f64.sqrt())).abs() < 1e-6);
    let l = of_velocity(&burst(10 * 1024, a, 32.0, 3.0, 3.5), DT).unwrap();
    assert!((l.overall_max_running_db.unwrap() - db(a / 2.0)).abs() < 1e-6);
    // The PPV and its time: the sine's first crest in the burst, 3 s + 1/(4·32) s.
    assert!((l.ppv - a).abs() < 1e-12);
    assert!((l.ppv_t - (3.0 + 1.0 / 128.0)).abs() < 0.5 * DT);
}

/// A record shorter than the 1-s window has no running levels (and says so by `None`).
#[test]
fn a_short_record_has_no_running_level() {
    let l = of_velocity(&burst(512, 1e-3, 32.0, 0.0, 1.0), DT).unwrap();
    assert_eq!(l.overall_max_running_db, None);
    assert!(l.bands.iter().all(|b| b.max_running_db.is_none()));
    assert!(l.overall_record_db.is_some());
}

/// FTA Table 6-3: category 2 (residences), frequent events, 72 VdB: 71.99 is no impact,
/// 72.01 is; category 1 is 65 for every event frequency; category 3 infrequent 83.
#[test]
fn fta_verdicts_on_both_sides() {
    assert!(!fta(71.99)[1][0].exceeds);
    assert!(fta(72.01)[1][0].exceeds);
    assert!(!fta(74.99)[1][1].exceeds && fta(75.01)[1][1].exceeds);
    assert!(!fta(79.99)[1][2].exceeds && fta(80.01)[1][2].exceeds);
    for e in 0..3 {
        assert_eq!(fta(0.0)[0][e].criterion, 65.0);
    }
    assert!(!fta(82.99)[2][2].exceeds && fta(83.01)[2][2].exceeds);
    assert_eq!(fta(0.0)[2][1].criterion, 78.0);
}

/// DIN 4150-3 Table 1 (foundation): type 2 (dwellings) 5 mm/s to 10 Hz, 5→15 mm/s over
/// 10–50 Hz (at 30 Hz: 10 mm/s), 15→20 over 50–100 Hz; type 3 at 75 Hz: 8 + 2·25/50 = 9 mm/s;
/// type 1 at 5 Hz: 20 mm/s, above 100 Hz: 50 mm/s.
#[test]
fn din_guidelines_and_verdicts_on_both_sides() {
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
    assert!(close(din_guideline(1, 5.0), 5e-3));
    assert!(close(din_guideline(1, 30.0), 10e-3));
    assert!(close(din_guideline(1, 50.0), 15e-3));
    assert!(close(din_guideline(1, 100.0), 20e-3));
    assert!(close(din_guideline(2, 75.0), 9e-3));
    assert!(close(din_guideline(0, 5.0), 20e-3));
    assert!(close(din_guideline(0, 200.0), 50e-3));
    assert!(!din(9.99e-3, 30.0)[1].exceeds);
    assert!(din(10.01e-3, 30.0)[1].exceeds);
    assert!(din(3.01e-3, 8.0)[2].exceeds && !din(2.99e-3, 8.0)[2].exceeds);
}
