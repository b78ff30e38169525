//! End-to-end: the `maglev irregularity` binary writes the core's profile as CSV and rejects
//! bad input with exit code 2 and a one-line message.

use std::process::Command;

use maglev_core::irregularity::{Direction, Irregularity, PsdParams};

fn maglev(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_maglev"))
        .args(args)
        .output()
        .expect("run maglev")
}

#[test]
fn csv_matches_core_profile() {
    let out = maglev(&[
        "irregularity",
        "--direction",
        "y",
        "--seed",
        "9",
        "--dx",
        "0.25",
        "--length",
        "100",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("x,r"));
    let g = Irregularity::<f64>::new(&PsdParams::TABLE1_Y, Direction::Y, 9).unwrap();
    let mut rows = 0;
    for (j, line) in lines.enumerate() {
        let (x, r) = line.split_once(',').expect("two columns");
        let (x, r): (f64, f64) = (x.parse().unwrap(), r.parse().unwrap());
        assert_eq!(x, j as f64 * 0.25);
        let mut ov = false;
        let want = g.eval(x, &mut ov);
        // The CLI sums by the chirp-z transform (round-off, `profile::Synthesis`): ≤ 1e-12 of
        // the profile scale.
        assert!((r - want).abs() <= 1e-12 * 5e-3, "x={x}: {r} vs {want}");
        rows += 1;
    }
    assert_eq!(rows, 401, "x = 0, 0.25, …, 100");
}

#[test]
fn overrides_change_the_profile() {
    let base = maglev(&[
        "irregularity",
        "--direction",
        "z",
        "--length",
        "2",
        "--dx",
        "1",
    ]);
    let over = maglev(&[
        "irregularity",
        "--direction",
        "z",
        "--length",
        "2",
        "--dx",
        "1",
        "--ar",
        "3.2e-7",
        "--n",
        "2000",
    ]);
    assert!(base.status.success() && over.status.success());
    let col = |o: &std::process::Output| -> Vec<f64> {
        String::from_utf8_lossy(&o.stdout)
            .lines()
            .skip(1)
            .map(|l| l.split_once(',').unwrap().1.parse().unwrap())
            .collect()
    };
    // A_r four times larger: every sample exactly (to rounding) twice as large.
    for (a, b) in col(&base).iter().zip(col(&over)) {
        assert!((2.0 * a - b).abs() <= 1e-14 * a.abs().max(1e-6), "{a} {b}");
    }
}

#[test]
fn bad_input_exits_2_with_one_line() {
    for args in [
        &["irregularity", "--direction", "x"][..],
        &["irregularity", "--direction", "z", "--dx", "0"],
        &["irregularity", "--direction", "z", "--dx", "-0.1"],
        &["irregularity", "--direction", "z", "--length", "NaN"],
        &["irregularity", "--direction", "z", "--n", "0"],
        &["irregularity", "--direction", "z", "--n", "5000"],
        &["irregularity", "--direction", "z", "--omega-u", "0.05"],
        &["irregularity", "--direction", "z", "--ar", "-1"],
        &["irregularity", "--direction", "z", "--length", "-5"],
        &["irregularity", "--direction", "z", "--omega-l", "-0.1"],
        &["irregularity", "--direction", "z", "--omega2", "inf"],
    ] {
        let out = maglev(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
        assert!(out.stdout.is_empty(), "{args:?}");
    }
}
