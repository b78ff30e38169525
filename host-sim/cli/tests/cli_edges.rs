//! The CLI's input edges through the built binary (issue 38): a bad input is one line naming
//! the key and its limit with exit 2, before anything is written; no file outside `--out` is
//! touched; no analysis judges a case `run` refuses; a search over a range ends.

use std::path::PathBuf;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn maglev(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_maglev"))
        .args(args)
        .output()
        .unwrap()
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("maglev-cli-edges-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The one error line of a run that exited 2.
fn refused(o: &Output) -> String {
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(2), "{err}");
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "{err}");
    lines[0].to_string()
}

fn ok(o: &Output) -> String {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// `validate --report ../notes.md` would replace a file beside `--out`: refused naming
/// `--report`, the file untouched, nothing run.
#[test]
fn validate_writes_no_report_outside_out() {
    let d = scratch("validate");
    std::fs::write(d.join("notes.md"), "mine").unwrap();
    let out = d.join("v");
    let o = maglev(&[
        "validate",
        "--out",
        out.to_str().unwrap(),
        "--report",
        "../notes.md",
    ]);
    let e = refused(&o);
    assert!(
        e.contains("--report: must be a file name inside --out"),
        "{e}"
    );
    assert_eq!(std::fs::read_to_string(d.join("notes.md")).unwrap(), "mine");
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&d);
}

/// The `unit` has one levitation magnet and no guidance pair: summary.json names no
/// `wheel1.left`/`right` (it listed both, at 10 mm, 43 A and 43 V).
#[test]
fn the_unit_lists_only_the_magnet_it_has() {
    let d = scratch("unit");
    let out = d.join("out");
    ok(&maglev(&[
        "run",
        "unit",
        "--set",
        "t_end=0.01",
        "--out",
        out.to_str().unwrap(),
    ]));
    let text = std::fs::read_to_string(out.join("summary.json")).unwrap();
    let s: serde_json::Value = serde_json::from_str(&text).unwrap();
    let names = |k: &str| -> Vec<String> {
        s[k].as_array()
            .unwrap()
            .iter()
            .map(|g| g["magnet"].as_str().unwrap().to_string())
            .collect()
    };
    assert_eq!(names("gaps"), ["wheel1.z"]);
    assert_eq!(names("coils"), ["wheel1.z"]);
    assert!(
        !text.contains("wheel1.left") && !text.contains("wheel1.right"),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// The unit's state gains as given (the designed ones, written out), so a law key can be set.
fn unit_given_gains() -> String {
    let r: serde_json::Value = serde_json::from_str(&ok(&maglev(&[
        "stability",
        "--scenario",
        "unit",
        "--format",
        "json",
    ])))
    .unwrap();
    let g = &r["gains"];
    let v = |k: &str| g[k].as_f64().unwrap();
    format!(
        "controller.state={{kp_V_per_m={:?}, kd_V_s_per_m={:?}, ki_V_per_m_s={:?}, kc_V_per_A={:?}, vmax_V={:?}}}",
        v("kp_V_per_m"),
        v("kd_V_s_per_m"),
        v("ki_V_per_m_s"),
        v("kc_V_per_A"),
        v("vmax_V"),
    )
}

fn stable(sets: &[&str]) -> bool {
    let mut args = vec![
        "stability",
        "--scenario",
        "unit",
        "--girder-modes",
        "1",
        "--format",
        "json",
    ];
    for s in sets {
        args.extend(["--set", s]);
    }
    let r: serde_json::Value = serde_json::from_str(&ok(&maglev(&args))).unwrap();
    r["coupled"]["stable"].as_bool().unwrap()
}

/// `stability --critical` over a key of the law analyses the law the key gives at each point
/// (it kept the scenario's law and answered "no crossing: stable"): ka = 1 is stable, ka =
/// 1000 alone is not, and the search finds the crossing between, where the analysis at either
/// side of it agrees. A range narrower than the floats can halve ends (it bisected for ever).
/// One girder mode: the undamped span's higher modes have nodes under the magnet and a real
/// part of zero to rounding (docs/levitation.md), which no sign test can judge.
#[test]
fn the_critical_search_over_a_law_key_finds_the_crossing_and_ends() {
    let gains = unit_given_gains();
    let ka = |v: f64| format!("controller.state.ka_V_s2_per_m={v:?}");
    assert!(stable(&[&gains, &ka(1.0)]));
    assert!(!stable(&[&gains, &ka(1000.0)]));
    let critical = |lo: f64, hi: f64| -> serde_json::Value {
        let args = [
            "stability",
            "--scenario",
            "unit",
            "--girder-modes",
            "1",
            "--set",
            &gains,
            "--set",
            "controller.state.ka_V_s2_per_m=1.0",
            "--critical",
            "controller.state.ka_V_s2_per_m",
            "--range",
            &format!("{lo:?}"),
            &format!("{hi:?}"),
        ];
        let mut child = Command::new(env!("CARGO_BIN_EXE_maglev"))
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let start = Instant::now();
        while child.try_wait().unwrap().is_none() {
            if start.elapsed() > Duration::from_secs(300) {
                let _ = child.kill();
                panic!("--critical over [{lo}, {hi}] did not end in 300 s");
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        serde_json::from_str(&ok(&child.wait_with_output().unwrap())).unwrap()
    };
    let r = critical(1.0, 1000.0);
    let x = r["critical"]
        .as_f64()
        .unwrap_or_else(|| panic!("no crossing: {r}"));
    assert!(x > 1.0 && x < 1000.0, "{r}");
    assert!(
        stable(&[&gains, &ka(x * 0.99)]) && !stable(&[&gains, &ka(x * 1.01)]),
        "{x}"
    );
    let narrow = critical(x * (1.0 - 4e-16), x * (1.0 + 4e-16));
    assert!(narrow["max_real_part_at_range"].is_array(), "{narrow}");
}

/// `stability --scenario` refuses what `run` refuses, with the same line: `vmax_V = 1e-300`
/// (below R0·i0) was judged "stable".
#[test]
fn stability_refuses_the_law_run_refuses() {
    let gains = unit_given_gains();
    let vmax = "controller.state.vmax_V=1e-300";
    let d = scratch("vmax");
    let run = refused(&maglev(&[
        "run",
        "unit",
        "--set",
        &gains,
        "--set",
        vmax,
        "--set",
        "t_end=0.01",
        "--out",
        d.join("out").to_str().unwrap(),
    ]));
    let stability = refused(&maglev(&[
        "stability",
        "--scenario",
        "unit",
        "--set",
        &gains,
        "--set",
        vmax,
    ]));
    assert_eq!(stability, run);
    assert!(run.contains("controller"), "{run}");
    let _ = std::fs::remove_dir_all(&d);
}

/// A record whose sample step is 1e-300 s is refused naming `support.record.dt` and its
/// limits, under `run` and `hil` alike (it panicked, exit 101).
#[test]
fn a_record_of_step_1e_300_is_refused_under_run_and_hil() {
    let d = scratch("dt");
    let rec = d.join("quake.csv");
    std::fs::write(
        &rec,
        "t_s,ax_m_per_s2,ay_m_per_s2,az_m_per_s2\n0,0,0,0\n1e-300,0,0,0\n2e-300,0,0,0\n",
    )
    .unwrap();
    let record = format!("support.record={:?}", rec.to_str().unwrap());
    for (cmd, extra) in [("run", &[][..]), ("hil", &["--firmware", "inproc"][..])] {
        let mut args = vec![cmd, "paper-5", "--set", "bridge.spans_m=[30.0, 30.0]"];
        args.extend(["--set", &record]);
        args.extend(extra);
        let out = d.join(cmd);
        args.extend(["--out", out.to_str().unwrap()]);
        let e = refused(&maglev(&args));
        assert!(
            e.contains("support.record.dt: must be within [0.000001, 0.1] s"),
            "{cmd}: {e}"
        );
        assert!(!out.exists());
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// `hil` under the state law at a rate whose step request no frame holds is refused up front
/// naming `--set rate` and the most ticks per step (it failed at the first step with
/// "cannot encode request 2: Encode").
#[test]
fn hil_refuses_a_rate_the_wire_cannot_carry() {
    let d = scratch("rate");
    let out = d.join("out");
    let st = "controller.state={kp_V_per_m=51600.0, kd_V_s_per_m=1600.0, ka_V_s2_per_m=40.0, ki_V_per_m_s=4300.0, kc_V_per_A=10.0, vmax_V=500.0}";
    let e = refused(&maglev(&[
        "hil",
        "paper-4.2",
        "--firmware",
        "inproc",
        "--set",
        "geometry=ems",
        "--set",
        "law=state",
        "--set",
        "vehicle.wheel_mass_kg=1000",
        "--set",
        st,
        "--set",
        "rate=100000",
        "--out",
        out.to_str().unwrap(),
    ]));
    assert!(
        e.contains("--set rate: gives 100 control ticks per step") && e.contains("at most"),
        "{e}"
    );
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&d);
}
