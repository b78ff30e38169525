//! `maglev ground green` through the built binary: the JSON shape, the library's value, and
//! one-line errors with exit status 2.

use maglev_host_sim::fe::soil::Soil;
use maglev_host_sim::ground::green::{displacement_per_newton, Green};
use std::process::Command;

fn maglev(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_maglev"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn green_prints_the_displacement_per_newton() {
    let out = maglev(&[
        "ground", "green", "--vs", "250", "--nu", "0.33", "--rho", "1900", "--xi", "0.03", "--f",
        "10", "--r", "25", "--format", "json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let w = v["w_per_N"].as_array().unwrap();
    let soil = Soil {
        shear_wave_velocity: 250.0,
        poisson: 0.33,
        density: 1900.0,
        damping: 0.03,
    };
    let lib = displacement_per_newton(&soil, &Green::new(0.33, 0.03).unwrap(), 10.0, 25.0);
    assert_eq!(w[0].as_f64().unwrap(), lib.re);
    assert_eq!(w[1].as_f64().unwrap(), lib.im);
    // At 0 Hz: Boussinesq, P(1 − ν)/(2πμ*r).
    let out = maglev(&[
        "ground", "green", "--vs", "250", "--nu", "0.33", "--rho", "1900", "--xi", "0.03", "--f",
        "0", "--r", "25",
    ]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let mu =
        rustfft::num_complex::Complex64::new(1900.0 * 250.0 * 250.0, 1900.0 * 250.0 * 250.0 * 0.06);
    let b = 0.67 / (2.0 * std::f64::consts::PI * 25.0 * mu);
    let w = &v["w_per_N"];
    assert!((w[0].as_f64().unwrap() - b.re).abs() < 1e-15 * b.norm());
    assert!((w[1].as_f64().unwrap() - b.im).abs() < 1e-15 * b.norm());
}

#[test]
fn bad_values_are_one_line_errors() {
    for (key, bad) in [
        ("--vs", "-1"),
        ("--nu", "0.5"),
        ("--rho", "0"),
        ("--xi", "0"),
        ("--f", "nan"),
        ("--r", "0"),
        ("--r", "1e300"),
    ] {
        let mut args = vec![
            "ground", "green", "--vs", "250", "--nu", "0.33", "--rho", "1900", "--xi", "0.03",
            "--f", "10", "--r", "25",
        ];
        let i = args.iter().position(|a| *a == key).unwrap();
        args[i + 1] = bad;
        let out = maglev(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{key}={bad}: {err}");
        assert!(
            err.contains(key) && err.trim().lines().count() == 1,
            "{err}"
        );
    }
}
