//! End-to-end: the `maglev bands` binary on CSV files it did not write: the `#` header, the
//! band list, analytic levels of a sine, `--out`, `--output velocity`, `--running`, and
//! one-line errors with exit code 2.

use std::f64::consts::{SQRT_2, TAU};
use std::path::PathBuf;
use std::process::{Command, Output};

fn maglev(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_maglev"))
        .args(args)
        .output()
        .expect("run maglev")
}

/// A file in Cargo's per-target temporary directory.
fn temp_file(name: &str, text: &str) -> PathBuf {
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// A response.csv-like history: 5000 steps of 2 ms, `a` = 1.5·sin(2π·50t) (500 whole periods
/// in the 50 Hz band), `z` = its displacement, `gap` with an empty cell (as response.csv
/// writes not-applicable values).
fn history() -> String {
    let mut s = String::from("t,a,z,gap\n");
    for j in 0..5000usize {
        let t = j as f64 * 0.002;
        let phase = TAU * ((j * 500) % 5000) as f64 / 5000.0;
        let w = TAU * 50.0;
        let gap = if j == 7 { String::new() } else { "0.01".into() };
        s += &format!(
            "{t},{},{},{gap}\n",
            1.5 * phase.sin(),
            -1.5 / (w * w) * phase.sin()
        );
    }
    s
}

fn parse(stdout: &[u8]) -> (String, Vec<(f64, f64)>) {
    let text = String::from_utf8(stdout.to_vec()).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().to_string();
    assert_eq!(lines.next(), Some("centre_hz,level_db"));
    let rows = lines
        .map(|l| {
            let (c, v) = l.split_once(',').unwrap();
            (c.parse().unwrap(), v.parse().unwrap())
        })
        .collect();
    (header, rows)
}

fn assert_ok(out: &Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn sine_levels_end_to_end() {
    let input = temp_file("bands_history.csv", &history());
    let input = input.to_str().unwrap();
    let out = maglev(&["bands", "--input", input, "--column", "a"]);
    assert_ok(&out);
    let (header, rows) = parse(&out.stdout);
    assert!(header.starts_with('#'));
    for needed in [
        "re 1e-6 m/s^2",
        "acceleration",
        "whole-record rms",
        "IEC 61260-1",
    ] {
        assert!(header.contains(needed), "{header}");
    }
    let centres: Vec<f64> = rows.iter().map(|r| r.0).collect();
    assert_eq!(centres.first(), Some(&0.5));
    assert_eq!(centres.last(), Some(&200.0));
    assert_eq!(centres.len(), 27, "0.5 … 200 Hz");
    assert!(centres.contains(&0.63) && centres.contains(&3.15) && centres.contains(&12.5));
    // 50 Hz lies in the 50 Hz band (44.7–56.2 Hz): 20·log10(1.5/√2 / 1e-6) = 120.5115 dB.
    let want = 20.0 * (1.5 / SQRT_2 / 1e-6).log10();
    for &(c, l) in &rows {
        if c == 50.0 {
            assert!((l - want).abs() <= 6e-5, "{l} vs {want}");
        } else {
            assert!(l < want - 150.0, "{c} Hz: {l}");
        }
    }

    // The displacement column gives the same acceleration levels; velocity re 1e-9 m/s.
    let out = maglev(&[
        "bands",
        "--input",
        input,
        "--column",
        "z",
        "--quantity",
        "displacement",
        "--output",
        "velocity",
    ]);
    assert_ok(&out);
    let (header, rows) = parse(&out.stdout);
    assert!(
        header.contains("re 1e-9 m/s;") && header.contains("displacement"),
        "{header}"
    );
    let want_v = 20.0 * (1.5 / (TAU * 50.0) / SQRT_2 / 1e-9).log10();
    let l50 = rows.iter().find(|r| r.0 == 50.0).unwrap().1;
    assert!((l50 - want_v).abs() <= 6e-5, "{l50} vs {want_v}");

    // --out writes the same text as stdout; --running 1 on a stationary sine changes nothing.
    let file = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("bands_out.csv");
    let f = file.to_str().unwrap();
    let out_file = maglev(&["bands", "--input", input, "--column", "a", "--out", f]);
    assert_ok(&out_file);
    assert!(out_file.stdout.is_empty());
    let (_, from_file) = parse(&std::fs::read(&file).unwrap());
    let running = maglev(&["bands", "--input", input, "--column", "a", "--running", "1"]);
    assert_ok(&running);
    let (header, rows_running) = parse(&running.stdout);
    assert!(header.contains("maximum running rms, linear (rectangular) window 1 s (500 samples)"));
    let from_stdout = parse(&maglev(&["bands", "--input", input, "--column", "a"]).stdout).1;
    assert_eq!(from_file, from_stdout);
    let r50 = rows_running.iter().find(|r| r.0 == 50.0).unwrap().1;
    assert!((r50 - want).abs() <= 6e-5, "{r50} vs {want}");
}

fn assert_input_error(args: &[&str], needle: &str) {
    let out = maglev(args);
    assert_eq!(out.status.code(), Some(2), "{args:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains(needle), "{args:?}: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(out.stdout.is_empty());
}

#[test]
fn bad_input_is_a_one_line_error_with_exit_2() {
    let input = temp_file("bands_history_errors.csv", &history());
    let input = input.to_str().unwrap();
    assert_input_error(
        &["bands", "--input", input, "--column", "nope"],
        "no column \"nope\"",
    );
    assert_input_error(
        &["bands", "--input", input, "--column", "gap"],
        "column \"gap\" line 9",
    );
    let nan = temp_file("bands_nan.csv", "t,a\n0,1\n0.1,NaN\n0.2,1\n");
    assert_input_error(
        &["bands", "--input", nan.to_str().unwrap(), "--column", "a"],
        "\"NaN\" is not a finite number",
    );
    let jitter = temp_file("bands_jitter.csv", "t,a\n0,1\n0.1,1\n0.2005,1\n0.3,1\n");
    assert_input_error(
        &[
            "bands",
            "--input",
            jitter.to_str().unwrap(),
            "--column",
            "a",
        ],
        "tolerance 0.001*dt",
    );
    let short = temp_file("bands_short.csv", "t,a\n0,1\n0.001,2\n0.002,3\n");
    assert_input_error(
        &["bands", "--input", short.to_str().unwrap(), "--column", "a"],
        "record too short",
    );
    assert_input_error(
        &[
            "bands",
            "--input",
            input,
            "--column",
            "a",
            "--running",
            "11",
        ],
        "--running",
    );
    assert_input_error(
        &[
            "bands",
            "--input",
            input,
            "--column",
            "a",
            "--running",
            "-1",
        ],
        "--running: must be a positive",
    );
    assert_input_error(
        &["bands", "--input", "/nonexistent/x.csv", "--column", "a"],
        "--input",
    );
    // Unknown enum values are clap usage errors: exit 2 as well.
    let out = maglev(&[
        "bands",
        "--input",
        input,
        "--column",
        "a",
        "--quantity",
        "jerk",
    ]);
    assert_eq!(out.status.code(), Some(2));
}
