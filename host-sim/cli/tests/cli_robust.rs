//! Hostile inputs through the binary (issue 25): each ends with one line on stderr and its
//! exit status (README "Exit codes"), within a time limit — no panic, no hang, no silent NaN.

use std::path::PathBuf;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Runs `maglev args`, killed (and the test failed) after `limit`.
fn maglev_within(args: &[&str], limit: Duration) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_maglev"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            child.kill().unwrap();
            panic!("{args:?} still running after {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

fn maglev(args: &[&str]) -> Output {
    maglev_within(args, Duration::from_secs(60))
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("maglev-robust-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// The one stderr line of a failed command, checked to start `maglev: error: `.
fn one_error_line(o: &Output, code: i32) -> String {
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert_eq!(o.status.code(), Some(code), "{err}");
    let lines: Vec<&str> = err
        .lines()
        .filter(|l| l.starts_with("maglev: error: "))
        .collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(!err.contains("panicked"), "{err}");
    lines[0].to_string()
}

#[test]
fn extreme_values_end_in_an_error_not_a_hang() {
    let limit = Duration::from_secs(30);
    let o = maglev_within(
        &[
            "stability",
            "--scenario",
            "paper-4.2",
            "--set",
            "vehicle.body_mass_t=1e200",
        ],
        limit,
    );
    // Refused at the input by the key's bound (`case::MAX_MAGNITUDE`); the eigenvalue
    // routine's own bound on a matrix entry (what hung here) is tested in stability::eig.
    let e = one_error_line(&o, 2);
    assert!(
        e.contains("vehicle.body_mass_t") && e.contains("1e9"),
        "{e}"
    );
    let out = scratch("kp");
    let o = maglev_within(
        &[
            "run",
            "paper-4.2",
            "--set",
            "law=gap-loop",
            "--set",
            "controller.kp_V_m_per_A=1e200",
            "--out",
            out.to_str().unwrap(),
        ],
        limit,
    );
    let e = one_error_line(&o, 2);
    assert!(e.contains("controller.kp_V_m_per_A"), "{e}");
    assert!(!out.exists());
}

/// The reproduction (a run that went NaN and exited 0 with peaks of 0) is refused at
/// its input now; a run that does diverge stops naming t and the quantity
/// (probes::tests::not_applicable_is_empty_and_diverged_is_an_error).
#[test]
fn an_extreme_value_is_refused_before_the_run() {
    let out = scratch("nan");
    let o = maglev(&[
        "run",
        "paper-4.2",
        "--set",
        "vehicle.half_width_m=1e300",
        "--strict",
        "--out",
        out.to_str().unwrap(),
    ]);
    let e = one_error_line(&o, 2);
    assert!(e.starts_with("maglev: error: vehicle.half_width_m"), "{e}");
    assert!(!out.exists(), "a refused run wrote its outputs");
}

#[test]
fn stability_refuses_a_step_whose_discretisation_overflows() {
    let o = maglev(&["stability", "--dt=1e300"]);
    let e = one_error_line(&o, 2);
    assert!(
        e.contains("--dt: must be at most 1.7") && e.contains("got 1e300"),
        "{e}"
    );
    // Up to the limit the radius is a number (and > 1: unstable), not a NaN read as 0.
    let o = maglev(&["stability", "--dt=1e150", "--format", "json"]);
    assert!(o.status.success());
    let r: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(r["discrete_spectral_radius"].as_f64().unwrap() > 1.0, "{r}");
}

#[test]
fn a_closed_or_full_stdout_is_no_panic() {
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_maglev"))
        .args(["stability"])
        .stdout(full)
        .output()
        .unwrap();
    let e = one_error_line(&o, 2);
    assert!(e.starts_with("maglev: error: stdout: No space left"), "{e}");
    // A reader that is gone: a quiet end, status 0, for every command that prints.
    for args in [
        &["modes", "--viaduct", "5"][..],
        &["stability"],
        &["irregularity", "--direction", "z", "--length", "1000"],
        &["accelerogram", "--pga-g", "0.1"],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_maglev"))
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        let o = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(0), "{args:?}: {err}");
        assert!(err.is_empty(), "{args:?}: {err}");
    }
}

#[test]
fn a_fault_on_a_channel_the_train_lacks_is_refused() {
    let out = scratch("hil");
    let o = maglev(&[
        "hil",
        "paper-4.2",
        "--set",
        "fault=stuck:99@0.1",
        "--out",
        out.to_str().unwrap(),
    ]);
    let e = one_error_line(&o, 2);
    assert!(
        e.contains("--set fault: channel 99 does not exist: this train has 12 channels"),
        "{e}"
    );
}

#[test]
fn usage_errors_are_one_line_and_help_is_unchanged() {
    for args in [
        &["run", "--bogus"][..],
        &["stability", "--dt", "abc"],
        &["nosuchcommand"],
    ] {
        let e = one_error_line(&maglev(args), 2);
        assert!(e.contains("--help"), "{args:?}: {e}");
    }
    let o = maglev(&["--help"]);
    assert!(o.status.success());
    let help = String::from_utf8_lossy(&o.stdout);
    assert!(
        help.contains("Usage: maglev") && help.contains("Exit codes:"),
        "{help}"
    );
    assert!(help.lines().count() > 10);
}

#[test]
fn a_huge_input_file_is_refused_at_the_cap() {
    let o = maglev(&["control", "--trace", "/dev/zero"]);
    let e = one_error_line(&o, 2);
    assert!(e.contains("larger than the 64 MiB"), "{e}");
    // A parse error quotes an excerpt, not a 1 MB line.
    let d = scratch("toml");
    std::fs::create_dir_all(&d).unwrap();
    let spec = d.join("spec.toml");
    std::fs::write(&spec, format!("x = {}\n", "9".repeat(1 << 20))).unwrap();
    let o = maglev(&[
        "sweep",
        spec.to_str().unwrap(),
        "--out",
        d.join("o").to_str().unwrap(),
    ]);
    let e = one_error_line(&o, 2);
    assert!(e.len() < 2000, "{} bytes", e.len());
}

#[test]
fn validate_writes_only_where_its_own_files_are() {
    let d = scratch("validate");
    std::fs::create_dir_all(&d).unwrap();
    std::fs::write(d.join("notes.md"), "mine").unwrap();
    let o = maglev(&["validate", "--out", d.to_str().unwrap()]);
    let e = one_error_line(&o, 2);
    assert!(e.contains("not a maglev validation output"), "{e}");
    // docs/ lists the files validate regenerates there.
    let docs = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/.maglev-validation");
    let listed = std::fs::read_to_string(docs).unwrap();
    for f in ["validation.md", "validation.json", "fig3.svg"] {
        assert!(listed.lines().any(|l| l == f), "{f}");
    }
}

#[test]
fn unconverged_steps_fail_the_check_with_the_outputs_written() {
    let out = scratch("unconverged");
    let o = maglev(&[
        "run",
        "paper-4.2",
        "--set",
        "run.max_iterations=1",
        "--out",
        out.to_str().unwrap(),
    ]);
    let e = one_error_line(&o, 1);
    assert!(
        e.contains("step(s) hit run.max_iterations without converging"),
        "{e}"
    );
    assert!(out.join("summary.json").is_file() && out.join("response.csv").is_file());
    // Converged, the same run exits 0.
    let o = maglev(&["run", "paper-4.2", "--out", out.to_str().unwrap()]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Values that pass the sign checks but broke the numerics under them: each failed naming no
/// key ("viaduct stiffness: matrix is not positive definite", "controller: f64 cannot
/// represent …"), or ran out of memory or time sampling the irregularity (speed 9e8 m/s ran
/// past 30 s; half_length_m = 9e8 aborted). Now each is one line naming its key, before the
/// run (docs/scenarios.md, "Plausible ranges"), and a tiny value prints as an exponent.
#[test]
fn implausible_values_are_refused_naming_their_key() {
    let cases: [(&str, &str, &str); 8] = [
        (
            "paper-4.2",
            "bridge.shear_modulus_kN_per_m2=1e-12",
            "bridge.shear_modulus_kN_per_m2",
        ),
        (
            "paper-4.2",
            "bridge.mass_t_per_m=1e-12",
            "bridge.mass_t_per_m",
        ),
        (
            "paper-4.2",
            "vehicle.half_width_m=0",
            "vehicle.half_width_m",
        ),
        ("paper-4.2", "controller.h0_m=1e-300", "controller.h0_m"),
        ("paper-4.2", "speed=9e8", "run.speed_m_per_s"),
        (
            "paper-4.2",
            "vehicle.half_length_m=9e8",
            "vehicle.half_length_m",
        ),
        (
            "paper-5",
            "bridge.bearings.lateral_kN_per_m=1e-12",
            "bridge.bearings.lateral_kN_per_m",
        ),
        (
            "paper-5",
            "bridge.footing.along_x_m=1e-300",
            "bridge.footing.along_x_m",
        ),
    ];
    for (scenario, set, key) in cases {
        let out = scratch("implausible");
        let o = maglev_within(
            &[
                "run",
                scenario,
                "--set",
                set,
                "--out",
                out.to_str().unwrap(),
            ],
            Duration::from_secs(30),
        );
        let e = one_error_line(&o, 2);
        assert!(
            e.starts_with(&format!("maglev: error: {key}")),
            "{set}: {e}"
        );
        assert!(e.len() < 300, "{set}: {e}");
        assert!(!out.exists(), "{set}: a refused run wrote its outputs");
    }
    let o = maglev(&["run", "paper-4.2", "--set", "speed=-1e-300"]);
    let e = one_error_line(&o, 2);
    assert!(e.ends_with("got -1e-300"), "{e}");
}
