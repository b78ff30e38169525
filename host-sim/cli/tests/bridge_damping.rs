//! `[bridge.damping]`: Rayleigh damping of the FE spans, given as a damping ratio at two
//! frequencies. A moving force crosses the §4.2 span and leaves it ringing in its first bending
//! mode (6.13 Hz, `maglev modes`); with the damping ratio ζ set at that frequency the free
//! vibration decays by `exp(−2πζ/√(1 − ζ²))` a period (the damped oscillator's closed form),
//! and without damping it does not decay.
//!
//! Error budget of the measurement (why 1e-3 relative): the average-acceleration Newmark step changes the
//! decay per period by O((ω·Δt)²) ≈ 1.5e-5 at Δt = 1e-4 s; a peak read at a sample instead of
//! the true maximum by ≈ (ω·Δt)²/8 ≈ 2e-6; the next symmetric mode (≈ 52 Hz, ζ ≈ 0.086 under
//! this Rayleigh fit) has decayed by e^-28 one second after the force left.

use std::process::Command;

const F1: f64 = 6.13258140330599;

/// midspan_z after t = 1 s of a moving force over the §4.2 span (it leaves at 0.25 s).
fn ringing(damping: Option<f64>) -> (Vec<f64>, Vec<f64>) {
    let out = std::env::temp_dir().join(format!(
        "maglev-damping-{}-{}",
        std::process::id(),
        damping.is_some()
    ));
    let _ = std::fs::remove_dir_all(&out);
    let mut args = vec![
        "run".to_string(),
        "moving-force".into(),
        "--set".into(),
        "t_end=2.5".into(),
    ];
    if let Some(z) = damping {
        args.push("--set".into());
        args.push(format!(
            "bridge.damping={{ratio={z}, f1_Hz={F1}, f2_Hz={F1}}}"
        ));
    }
    args.extend(["--out".into(), out.to_str().unwrap().into()]);
    let o = Command::new(env!("CARGO_BIN_EXE_maglev"))
        .args(&args)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(out.join("response.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = header.iter().position(|h| *h == "midspan_z").unwrap();
    let (mut t, mut z) = (vec![], vec![]);
    for l in lines {
        let cells: Vec<&str> = l.split(',').collect();
        let ti: f64 = cells[0].parse().unwrap();
        if ti >= 1.0 {
            t.push(ti);
            z.push(cells[k].parse().unwrap());
        }
    }
    let _ = std::fs::remove_dir_all(&out);
    (t, z)
}

/// The damping ratio from the ratio of the first and last positive peaks in `z`.
fn measured_ratio(t: &[f64], z: &[f64]) -> f64 {
    let peaks: Vec<(f64, f64)> = (1..z.len() - 1)
        .filter(|&i| z[i] > 0.0 && z[i] >= z[i - 1] && z[i] > z[i + 1])
        .map(|i| (t[i], z[i]))
        .collect();
    assert!(peaks.len() >= 8, "{} peaks", peaks.len());
    let (first, last) = (peaks[0], peaks[peaks.len() - 1]);
    let periods = (peaks.len() - 1) as f64;
    // The peaks are one period of the first mode apart.
    let period = (last.0 - first.0) / periods;
    assert!((period * F1 - 1.0).abs() < 1e-3, "period {period} s");
    let delta = (first.1 / last.1).ln() / periods;
    delta / (4.0 * std::f64::consts::PI.powi(2) + delta * delta).sqrt()
}

#[test]
fn the_span_rings_down_at_the_damping_ratio_it_was_given() {
    let (t, z) = ringing(Some(0.02));
    let zeta = measured_ratio(&t, &z);
    eprintln!("damped: measured ζ = {zeta}");
    assert!((zeta / 0.02 - 1.0).abs() < 1e-3, "measured ζ = {zeta}");
    let (t, z) = ringing(None);
    let zeta = measured_ratio(&t, &z);
    eprintln!("undamped: measured ζ = {zeta}");
    assert!(zeta.abs() < 2e-4, "undamped span: measured ζ = {zeta}");
}
