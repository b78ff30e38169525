//! `maglev run` and `maglev validate` end to end through the binary: the paper geometry flies,
//! the EMS geometry under the paper's law collides and is reported as such (collision column,
//! summary.json, `--strict` exit 3, validate FAIL), and every run writes its profile.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn maglev(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_maglev"))
        .args(args)
        .output()
        .unwrap()
}

fn out_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("maglev-cli-run-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn column(dir: &Path, name: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(dir.join("response.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = header.iter().position(|h| *h == name).unwrap();
    lines
        .map(|l| l.split(',').nth(k).unwrap().parse().unwrap())
        .collect()
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

#[test]
fn paper_geometry_flies_and_strict_passes() {
    let d = out_dir("paper");
    let o = maglev(&["run", "paper-4.2", "--strict", "--out", d.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // stderr is not a terminal here: no progress bar, no percentages, only the closing line.
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.starts_with("maglev: ") && err.contains(" steps, "),
        "{err}"
    );
    assert!(
        !err.contains('\r') && !err.contains('\x1b') && !err.contains('%'),
        "{err:?}"
    );
    // The gap is plotted as its deviation from h0, in mm.
    let svg = std::fs::read_to_string(d.join("wheel1_gap_z.svg")).unwrap();
    assert!(svg.contains("wheel1_gap_z − h0 (mm)"));
    let gap = column(&d, "wheel1_gap_z");
    let h0 = 0.01;
    assert!(gap.iter().all(|&h| h > 0.5 * h0 && h < 1.5 * h0));
    assert!(column(&d, "collision").iter().all(|&c| c == 0.0));
    let s = summary(&d);
    assert_eq!(s["collision_steps"], 0);
    let gaps = s["gaps"].as_array().unwrap();
    assert_eq!(gaps.len(), 12, "4 wheels × (levitation + guidance pair)");
    let w1 = &gaps[0];
    assert_eq!(w1["magnet"], "wheel1.z");
    // The same bits as the CSV's minimum (serde_json parses with `float_roundtrip`).
    let min = gap.iter().cloned().fold(f64::INFINITY, f64::min);
    assert_eq!(w1["min_m"].as_f64().unwrap(), min);
}

#[test]
fn ems_geometry_under_the_papers_law_collides_and_strict_exits_3() {
    let d = out_dir("ems");
    let o = maglev(&[
        "run",
        "paper-4.2",
        "--set",
        "geometry=ems",
        "--strict",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(3));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("collision"), "{err}");
    let gap = column(&d, "wheel1_gap_z");
    let coll = column(&d, "collision");
    // The collision column marks (at least) every step whose wheel-1 gap is ≤ 0.
    assert!(gap.iter().zip(&coll).all(|(&h, &c)| h > 0.0 || c == 1.0));
    let n = coll.iter().filter(|&&c| c == 1.0).count() as u64;
    assert!(n > 0);
    assert_eq!(summary(&d)["collision_steps"].as_u64().unwrap(), n);
}

#[test]
fn profile_csv_covers_every_wheel_position() {
    let d = out_dir("profile");
    let o = maglev(&[
        "run",
        "paper-4.2",
        "--set",
        "model=rigid",
        "--set",
        "t_end=0.05",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // The plots carry the overrides in their titles.
    let svg = std::fs::read_to_string(d.join("wheel1_z.svg")).unwrap();
    assert!(svg.contains("paper-4.2 — wheel1_z [--set model=rigid, t_end=0.05]"));
    assert!(svg.contains("wheel1_z (mm)"));
    let text = std::fs::read_to_string(d.join("profile.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("x,r_y,r_z"));
    let xs: Vec<f64> = lines
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    // Wheels at x0 = 0 and −15 m, 100 m/s, Δt = 1 ms, 50 steps: x0 + 0.1·n for n = 0..=50.
    for x0 in [0.0, -15.0] {
        for n in 0..=50 {
            let x = x0 + 100.0 * (n as f64 * 1e-3);
            assert!(xs.contains(&x), "x = {x} missing");
        }
    }
    assert!(xs.windows(2).all(|w| w[0] < w[1]), "sorted, no duplicates");
    assert_eq!(xs.len(), 2 * 51);
}

#[test]
fn validate_fails_under_the_ems_geometry() {
    let d = out_dir("validate-ems");
    let o = maglev(&[
        "validate",
        "--set",
        "geometry=ems",
        "--out",
        d.to_str().unwrap(),
    ]);
    // A failed check with its outputs written: exit 1, not a usage error's 2.
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("validation failed"), "{err}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("validation.json")).unwrap()).unwrap();
    assert_eq!(v["pass"], false);
    // Every case fails on its collisions, not on a side issue.
    for c in v["comparisons"].as_array().unwrap() {
        assert!(c["collision_steps"].as_u64().unwrap() > 0, "{c}");
        assert_eq!(c["pass"], false);
    }
    // A key the cases set themselves is refused with a one-line error.
    let o = maglev(&[
        "validate",
        "--set",
        "speed=50",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("speed") && err.lines().count() == 1, "{err}");
    // A bad value or key is refused before anything is written: no directory is left.
    for (set, key) in [("foo=1", "foo"), ("alpha=2", "alpha"), ("seed=-1", "seed")] {
        let fresh = out_dir(&format!("validate-bad-{key}"));
        let o = maglev(&["validate", "--set", set, "--out", fresh.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{set}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains(key) && err.lines().count() == 1,
            "{set}: {err}"
        );
        assert!(!fresh.exists(), "{set}: validate left {}", fresh.display());
    }
}

#[test]
fn probes_name_their_columns_and_body_acceleration_is_newmarks() {
    let d = out_dir("probes");
    let o = maglev(&[
        "run",
        "paper-4.2",
        "--set",
        r#"output.probes=["car1.body.z","car1.body.az","span1.midspan.z","wheel2.gap_z"]"#,
        "--out",
        d.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let header = std::fs::read_to_string(d.join("response.csv")).unwrap();
    assert_eq!(
        header.lines().next().unwrap(),
        "t,car1.body.z,car1.body.az,span1.midspan.z,wheel2.gap_z,iterations,collision"
    );
    // Average-acceleration Newmark ties displacement and acceleration exactly:
    // (u₊ − 2u + u₋)/Δt² = (a₊ + 2a + a₋)/4. An independent check that `az` is the body's
    // acceleration, not a relabelled column.
    let (z, az) = (column(&d, "car1.body.z"), column(&d, "car1.body.az"));
    let dt = 1e-3;
    let peak = az.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    assert!(peak > 1e-3, "the body moves: {peak}");
    for k in 1..z.len() - 1 {
        let lhs = (z[k + 1] - 2.0 * z[k] + z[k - 1]) / (dt * dt);
        let rhs = (az[k + 1] + 2.0 * az[k] + az[k - 1]) / 4.0;
        assert!((lhs - rhs).abs() < 1e-6 * peak, "step {k}: {lhs} vs {rhs}");
    }
    // summary.json's peaks and the plots are of the probed columns, nothing else: each peak
    // is the column's largest magnitude (signed) and its time, read off response.csv here.
    let sum = summary(&d);
    let peaks = sum["peaks"].as_object().unwrap();
    let names = [
        "car1.body.z",
        "car1.body.az",
        "span1.midspan.z",
        "wheel2.gap_z",
    ];
    let mut keys: Vec<&str> = peaks.keys().map(String::as_str).collect();
    keys.sort_unstable();
    let mut want = names.to_vec();
    want.sort_unstable();
    assert_eq!(keys, want);
    let t = column(&d, "t");
    for name in names {
        let y = column(&d, name);
        let k = (0..y.len())
            .max_by(|&a, &b| y[a].abs().total_cmp(&y[b].abs()))
            .unwrap();
        assert_eq!(peaks[name]["value"].as_f64(), Some(y[k]), "{name}");
        assert_eq!(peaks[name]["t"].as_f64(), Some(t[k]), "{name}");
        let svg = std::fs::read_to_string(d.join(format!("{name}.svg"))).unwrap();
        assert!(svg.contains(name), "{name}.svg");
    }
    assert!(
        !d.join("midspan_z.svg").exists(),
        "a plot of a column not written"
    );
    // The same midspan as the default column, bit for bit.
    let d0 = out_dir("probes-default");
    assert!(maglev(&["run", "paper-4.2", "--out", d0.to_str().unwrap()])
        .status
        .success());
    assert_eq!(column(&d, "span1.midspan.z"), column(&d0, "midspan_z"));
    // A probe the case does not have is a one-line error naming the key and the limit.
    let o = maglev(&[
        "run",
        "paper-4.2",
        "--set",
        r#"output.probes=["wheel5.z"]"#,
        "--out",
        out_dir("probes-bad").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("output.probes") && err.contains("at most 4"),
        "{err}"
    );
}

#[test]
fn oversized_cases_are_refused_with_one_line_naming_the_key_and_limit() {
    for (set, key, limit) in [
        ("elements=100000", "run.elements_per_span", "1e10"),
        ("t_end=1e5", "run.t_end_s", "1e7"),
        ("t_end=1e12", "run.t_end_s", "1e9"),
        ("dt=1e-12", "run.dt_s", "1e7"),
        (
            "vehicle.target_height_m=nan",
            "vehicle.target_height_m",
            "finite",
        ),
        ("vehicle.offset_y_m=inf", "vehicle.offset_y_m", "finite"),
    ] {
        let d = out_dir("oversized");
        let o = maglev(&[
            "run",
            "paper-4.2",
            "--set",
            set,
            "--out",
            d.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2), "{set}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.lines().count(), 1, "{set}: {err}");
        assert!(err.contains(key) && err.contains(limit), "{set}: {err}");
        assert!(!d.exists(), "{set}: a refused run left an output directory");
    }
}

/// The paper's §5: the viaduct's first lateral, vertical and torsional frequencies lie
/// between 2 and 6.5 Hz (docs/model.md §10), as `maglev modes --scenario paper-5` lists them.
#[test]
fn paper5_first_frequencies_lie_in_the_papers_band() {
    let out = maglev(&[
        "modes",
        "--scenario",
        "paper-5",
        "--count",
        "1",
        "--format",
        "json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rows: Vec<serde_json::Value> = serde_json::from_slice(&out.stdout).unwrap();
    for kind in ["bending-y", "bending-z", "torsion"] {
        let f = rows
            .iter()
            .find(|r| r["kind"] == kind)
            .unwrap_or_else(|| panic!("no {kind} mode listed: {rows:?}"))["frequency_hz"]
            .as_f64()
            .unwrap();
        assert!((2.0..=6.5).contains(&f), "first {kind} mode at {f} Hz");
    }
}
