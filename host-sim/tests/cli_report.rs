//! `maglev report paper-5` end to end: it writes its files, and its band levels agree with an
//! independent 1/3-octave analysis of the report's own histories within 0.5 dB (issue #10).
//!
//! The independent analyser here shares only the definition of docs/bands.md (IEC 61260-1
//! base-10 band edges, whole-record mean square, bins split at band edges by the fraction of
//! their width inside); it computes each bin by a direct DFT sum in its own code, not by the
//! FFT crate, and reads the histories from the written CSV.

use std::path::PathBuf;
use std::process::Command;

fn history(path: &PathBuf) -> (Vec<f64>, Vec<f64>, f64) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut t = Vec::new();
    let (mut car, mut pier) = (Vec::new(), Vec::new());
    for line in text.lines().skip(1) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        t.push(v[0]);
        car.push(v[1]);
        pier.push(v[2]);
    }
    let dt = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
    (car, pier, dt)
}

/// Band level (dB re 1e-6 m/s²) of band `hz_nominal` with exact centre `fm`, direct DFT.
fn level(x: &[f64], dt: f64, fm: f64) -> f64 {
    let n = x.len();
    let df = 1.0 / (n as f64 * dt);
    let (lo, hi) = (fm * 10f64.powf(-0.05), fm * 10f64.powf(0.05));
    let mut ms = 0.0;
    for k in 1..n.div_ceil(2) {
        let (a, b) = ((k as f64 - 0.5) * df, (k as f64 + 0.5) * df);
        let w = ((hi.min(b) - lo.max(a)) / df).clamp(0.0, 1.0);
        if w == 0.0 {
            continue;
        }
        let (mut re, mut im) = (0.0, 0.0);
        for (j, v) in x.iter().enumerate() {
            let ph = -2.0 * std::f64::consts::PI * ((j * k) % n) as f64 / n as f64;
            re += v * ph.cos();
            im += v * ph.sin();
        }
        ms += w * 2.0 * (re * re + im * im) / (n as f64 * n as f64);
    }
    10.0 * (ms / 1e-12).log10()
}

#[test]
fn report_levels_agree_with_an_independent_analyser() {
    let out = std::env::temp_dir().join(format!("maglev-report-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let o = Command::new(env!("CARGO_BIN_EXE_maglev"))
        .args(["report", "paper-5", "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in [
        "report.md",
        "fig8.svg",
        "bands.csv",
        "history-maglev.csv",
        "history-wheel-rail.csv",
    ] {
        assert!(out.join(f).is_file(), "missing {f}");
    }
    let bands = std::fs::read_to_string(out.join("bands.csv")).unwrap();
    let mut checked = 0;
    for train in ["maglev", "wheel-rail"] {
        let (car, pier, dt) = history(&out.join(format!("history-{train}.csv")));
        assert_eq!(car.len(), 5001, "5000 steps and t = 0");
        for line in bands
            .lines()
            .filter(|l| l.starts_with(&format!("{train},")))
        {
            let f: Vec<&str> = line.split(',').collect();
            let nominal: f64 = f[2].parse().unwrap();
            let ours: f64 = f[3].parse().unwrap();
            // The exact centre of the base-10 band nearest the nominal frequency.
            let x = (10.0 * (nominal / 1000.0).log10()).round();
            let fm = 1000.0 * 10f64.powf(x / 10.0);
            let series = if f[1] == "car4.body.az" { &car } else { &pier };
            let theirs = level(series, dt, fm);
            assert!(
                (ours - theirs).abs() <= 0.5,
                "{train} {} {nominal} Hz: {ours} dB vs {theirs} dB",
                f[1]
            );
            checked += 1;
        }
    }
    assert!(checked >= 100, "only {checked} bands checked");
    let _ = std::fs::remove_dir_all(&out);
}
