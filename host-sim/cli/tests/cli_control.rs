//! `maglev control` end to end through the binary: output shape, one row per input row, and
//! one-line errors with a non-zero exit for bad input.

use std::process::Command;

fn maglev(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_maglev"))
        .args(args)
        .output()
        .unwrap()
}

fn write_trace(name: &str, text: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("maglev-cli-control-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn csv_has_the_documented_header_and_one_row_per_input_row() {
    let mut text = String::from("t,h\n");
    for k in 0..=50 {
        let h = if k < 10 { 0.01 } else { 0.0095 };
        text.push_str(&format!("{},{}\n", k as f64 * 1e-3, h));
    }
    let p = write_trace("step.csv", &text);
    for scalar in ["f64", "f32", "i32f32", "i4f28"] {
        let out = maglev(&[
            "control",
            "--trace",
            p.to_str().unwrap(),
            "--nsub",
            "10",
            "--scalar",
            scalar,
        ]);
        assert!(
            out.status.success(),
            "{scalar}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let csv = String::from_utf8(out.stdout).unwrap();
        let mut lines = csv.lines();
        assert_eq!(lines.next(), Some("t,h,g,current,force,voltage"));
        let rows: Vec<Vec<f64>> = lines
            .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
            .collect();
        assert_eq!(rows.len(), 51);
        // Row 0 is the equilibrium: g0 = 4300 A/m, i0 = 43 A, p0 = 36787.5 N, V = R0·i0 = 43 V.
        let r0 = &rows[0];
        assert_eq!((r0[2], r0[3], r0[5]), (4300.0, 43.0, 43.0));
        assert!((r0[4] - 36_787.5).abs() < 1e-6);
        // The gap closed: g first rises above g0 (less voltage drop R0·h·g).
        assert!(rows[11][2] > 4300.0, "{scalar}: {:?}", rows[11]);
    }
}

#[test]
fn bad_input_gets_a_one_line_error_and_a_non_zero_exit() {
    let good = write_trace("ok.csv", "t,h\n0,0.01\n0.001,0.01\n");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec!["--trace".into(), "/nonexistent/trace.csv".into()],
            "cannot read trace",
        ),
        (
            vec![
                "--trace".into(),
                write_trace("hdr.csv", "time,gap\n0,0.01\n")
                    .to_string_lossy()
                    .into(),
            ],
            "header",
        ),
        (
            vec![
                "--trace".into(),
                write_trace("nu.csv", "t,h\n0,0.01\n0.001,0.01\n0.003,0.01\n")
                    .to_string_lossy()
                    .into(),
            ],
            "non-uniform",
        ),
        (
            vec![
                "--trace".into(),
                write_trace("nan.csv", "t,h\n0,0.01\n0.001,NaN\n")
                    .to_string_lossy()
                    .into(),
            ],
            "not finite",
        ),
        (
            vec![
                "--trace".into(),
                good.to_string_lossy().into(),
                "--h0".into(),
                "-0.01".into(),
            ],
            "h0",
        ),
        (
            vec![
                "--trace".into(),
                good.to_string_lossy().into(),
                "--scalar".into(),
                "q15".into(),
            ],
            "q15",
        ),
        (
            vec![
                "--trace".into(),
                good.to_string_lossy().into(),
                "--scalar".into(),
                "i4f28".into(),
                "--nsub".into(),
                "1000".into(),
            ],
            "cannot represent",
        ),
    ];
    for (args, want) in cases {
        let mut all = vec!["control"];
        all.extend(args.iter().map(String::as_str));
        let out = maglev(&all);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(err.contains(want), "{args:?}: stderr was {err}");
        assert!(out.stdout.is_empty(), "{args:?}: half-written output");
    }
}

/// The README's `maglev control` commands run as written on the trace the repo ships
/// (host-sim/cli/examples/data/gap.csv, 201 rows): exit 0, the header and one row per input row.
#[test]
fn the_readme_example_trace_runs() {
    let trace = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/gap.csv");
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../README.md")).unwrap();
    assert!(readme.contains("control --trace host-sim/cli/examples/data/gap.csv"));
    for extra in [
        ["--nsub", "10", "--scalar", "i4f28"],
        ["--scheme", "accurate", "--nsub", "1"],
    ] {
        let mut args = vec!["control", "--trace", trace];
        args.extend(extra);
        let out = maglev(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = String::from_utf8(out.stdout).unwrap();
        assert!(text.starts_with("t,h,"), "{text}");
        assert_eq!(text.lines().count(), 1 + 201);
    }
}
