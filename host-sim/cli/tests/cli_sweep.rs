//! `maglev sweep` end to end through the binary: the issue's 6-run sweep gives one
//! results.csv for --jobs 1, --jobs 2 and two shards merged; a rerun skips finished runs; a
//! failing run is recorded and the rest run; the reductions equal the same reductions computed
//! here from an equivalent `maglev run`'s response.csv; the emitted Slurm scripts hold the
//! array and the merge dependency, and their local runner reproduces the in-process results.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn maglev(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_maglev"))
        .args(args)
        .output()
        .unwrap()
}

fn ok(o: &Output) -> String {
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{err}");
    err
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("maglev-cli-sweep-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The issue's spec, on 30 ms runs (30 steps) to keep the test short.
const ISSUE: &str = r#"
scenario = "paper-4.2"
[set]
scheme = "accurate"
t_end = 0.03
[axes]
speed = [50.0, 100.0, 150.0]
seed = [1, 2]
[reduce]
quantities = ["peak:midspan_z", "peak:wheel1_gap_z"]
"#;

fn spec(dir: &Path, text: &str) -> PathBuf {
    let p = dir.join("spec.toml");
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn the_issue_sweep_is_the_same_for_any_jobs_and_for_merged_shards() {
    let d = scratch("issue");
    let sp = spec(&d, ISSUE);
    let (j1, j2, s1, s2, m) = (
        d.join("j1"),
        d.join("j2"),
        d.join("s1"),
        d.join("s2"),
        d.join("merged"),
    );
    ok(&maglev(&["sweep", s(&sp), "--jobs", "1", "--out", s(&j1)]));
    ok(&maglev(&["sweep", s(&sp), "--jobs", "2", "--out", s(&j2)]));
    ok(&maglev(&[
        "sweep",
        s(&sp),
        "--shard",
        "1/2",
        "--out",
        s(&s1),
    ]));
    ok(&maglev(&[
        "sweep",
        s(&sp),
        "--shard",
        "2/2",
        "--out",
        s(&s2),
    ]));
    ok(&maglev(&["sweep", "merge", s(&s1), s(&s2), "--out", s(&m)]));
    let one = read(&j1.join("results.csv"));
    assert_eq!(one, read(&j2.join("results.csv")), "--jobs 1 vs --jobs 2");
    assert_eq!(one, read(&m.join("results.csv")), "shards merged");
    // The shards split the runs: 3 rows each, every other run.
    assert_eq!(read(&s1.join("results.csv")).lines().count(), 4);
    let lines: Vec<&str> = one.lines().collect();
    assert_eq!(
        lines[0],
        "speed,seed,peak:midspan_z,peak:wheel1_gap_z,status,error"
    );
    assert_eq!(lines.len(), 7);
    let keys: Vec<String> = lines[1..]
        .iter()
        .map(|l| l.split(',').take(2).collect::<Vec<_>>().join(","))
        .collect();
    assert_eq!(
        keys,
        ["50.0,1", "50.0,2", "100.0,1", "100.0,2", "150.0,1", "150.0,2"]
    );
    for l in &lines[1..] {
        let c: Vec<&str> = l.split(',').collect();
        assert_eq!(c[4], "ok", "{l}");
        let z: f64 = c[2].parse().unwrap();
        let gap: f64 = c[3].parse().unwrap();
        // The beam sags under the vehicle; the gap stays near h0 = 10 mm.
        assert!(z < 0.0 && z > -1e-3, "{l}");
        assert!(gap > 5e-3 && gap < 15e-3, "{l}");
    }
    // The seed changes the irregularity, hence the gap.
    assert_ne!(lines[1].split(',').nth(3), lines[2].split(',').nth(3));
    for q in ["peak_midspan_z.svg", "peak_wheel1_gap_z.svg"] {
        let svg = read(&j1.join("plots").join(q));
        assert!(svg.contains("seed=1") && svg.contains("seed=2"), "{q}");
    }
    // A merge of one shard alone is refused: runs are missing.
    let o = maglev(&["sweep", "merge", s(&s1), "--out", s(&d.join("half"))]);
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("3 of 6 runs have no record"), "{e}");
}

#[test]
fn a_rerun_skips_the_finished_runs_and_a_grown_axis_runs_only_the_new_ones() {
    let d = scratch("resume");
    let out = d.join("out");
    let base = |speeds: &str| {
        format!(
            "scenario='moving-force'\n[set]\nt_end=0.05\ndt=0.001\n[axes]\nspeed=[{speeds}]\n[reduce]\nquantities=['peak:midspan_z']\n"
        )
    };
    let sp = spec(&d, &base("10.0, 20.0"));
    let e = ok(&maglev(&["sweep", s(&sp), "--out", s(&out)]));
    assert!(e.contains("2 run now, 0 skipped"), "{e}");
    let first = read(&out.join("results.csv"));
    let records = || -> Vec<(String, String)> {
        let mut v: Vec<(String, String)> = std::fs::read_dir(out.join("runs"))
            .unwrap()
            .map(|e| {
                let p = e.unwrap().path();
                (
                    p.file_name().unwrap().to_string_lossy().into_owned(),
                    read(&p),
                )
            })
            .collect();
        v.sort();
        v
    };
    let before = records();
    let e = ok(&maglev(&["sweep", s(&sp), "--out", s(&out)]));
    assert!(e.contains("0 run now, 2 skipped"), "{e}");
    assert_eq!(
        records(),
        before,
        "the records of finished runs were rewritten"
    );
    assert_eq!(read(&out.join("results.csv")), first);
    // The axis grows: only the new run runs, the old records stay as they were.
    let sp = spec(&d, &base("10.0, 20.0, 30.0"));
    let e = ok(&maglev(&["sweep", s(&sp), "--out", s(&out)]));
    assert!(e.contains("1 run now, 2 skipped"), "{e}");
    let after = records();
    assert_eq!(after.len(), 3);
    assert!(before.iter().all(|r| after.contains(r)));
    assert!(read(&out.join("results.csv")).starts_with(&first));
    // Another spec in the same directory is refused, naming what differs.
    let other = spec(&d, &base("10.0").replace("peak:", "max:"));
    let o = maglev(&["sweep", s(&other), "--out", s(&out)]);
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("reduce.quantities differs"), "{e}");
    // A foreign directory is refused.
    std::fs::write(d.join("notes.txt"), "mine").unwrap();
    let o = maglev(&["sweep", s(&sp), "--out", s(&d)]);
    assert_eq!(o.status.code(), Some(2));
}

/// A record of one period of a sine on the bearings (ends at rest), amplitude `a` m/s².
fn sine_record(a: f64) -> String {
    let mut text = "t_s,ax_m_per_s2,ay_m_per_s2,az_m_per_s2\n".to_string();
    for j in 0..=50 {
        let t = j as f64 * 0.001;
        let z = a * (2.0 * std::f64::consts::PI * t / 0.05).sin();
        text += &format!("{t:.3},0,0,{z:e}\n");
    }
    text
}

/// A resumed sweep hashes the record files its runs read, not only the scenario: after the
/// record changes, every run that read it runs again and results.csv holds only the new
/// record's values; an unchanged record is skipped as before.
#[test]
fn a_changed_record_file_runs_again_the_runs_that_read_it() {
    let d = scratch("record");
    let out = d.join("out");
    let rec = d.join("quake.csv");
    std::fs::write(&rec, sine_record(1.0)).unwrap();
    let sp = spec(
        &d,
        &format!(
            "scenario='moving-force'\n[set]\nt_end=0.05\ndt=0.001\n\"support.record\"={:?}\n[axes]\nspeed=[10.0, 20.0]\n[reduce]\nquantities=['peak:midspan_z']\n",
            s(&rec)
        ),
    );
    let e = ok(&maglev(&["sweep", s(&sp), "--out", s(&out)]));
    assert!(e.contains("2 run now, 0 skipped"), "{e}");
    let first = read(&out.join("results.csv"));
    let e = ok(&maglev(&["sweep", s(&sp), "--out", s(&out)]));
    assert!(e.contains("0 run now, 2 skipped"), "{e}");
    std::fs::write(&rec, sine_record(3.0)).unwrap();
    let e = ok(&maglev(&["sweep", s(&sp), "--out", s(&out)]));
    assert!(e.contains("2 run now, 0 skipped"), "{e}");
    let second = read(&out.join("results.csv"));
    assert_ne!(first, second, "the new record's values");
    // The same as a fresh sweep of the new record.
    let fresh = d.join("fresh");
    ok(&maglev(&["sweep", s(&sp), "--out", s(&fresh)]));
    assert_eq!(read(&fresh.join("results.csv")), second);
}

#[test]
fn a_failing_run_is_recorded_with_its_error_and_the_others_run() {
    let d = scratch("fail");
    let out = d.join("out");
    let sp = spec(
        &d,
        "scenario='moving-force'\n[set]\nt_end=0.05\n[axes]\nspeed=[-10.0, 20.0]\nelements=[4, 8]\n[reduce]\nquantities=['peak:midspan_z']\n",
    );
    let e = ok(&maglev(&["sweep", s(&sp), "--jobs", "2", "--out", s(&out)]));
    assert!(e.contains("2 failed"), "{e}");
    let text = read(&out.join("results.csv"));
    let rows: Vec<csv::StringRecord> = csv::Reader::from_reader(text.as_bytes())
        .records()
        .map(|r| r.unwrap())
        .collect();
    assert_eq!(rows.len(), 4);
    for r in &rows[..2] {
        assert_eq!(&r[0], "-10.0");
        assert_eq!(&r[3], "failed");
        assert_eq!(&r[2], "");
        assert!(r[4].contains("run.speed_m_per_s"), "{:?}", r);
    }
    for r in &rows[2..] {
        assert_eq!(&r[3], "ok", "{:?}", r);
        assert!(r[2].parse::<f64>().unwrap() < 0.0);
    }
}

/// The column `name` of a `maglev run`'s response.csv.
fn column(dir: &Path, name: &str) -> Vec<f64> {
    let text = read(&dir.join("response.csv"));
    let mut r = csv::Reader::from_reader(text.as_bytes());
    let k = r.headers().unwrap().iter().position(|h| h == name).unwrap();
    r.records()
        .map(|x| x.unwrap()[k].parse().unwrap())
        .collect()
}

#[test]
fn reductions_equal_those_of_an_equivalent_run() {
    let d = scratch("reduce");
    let out = d.join("out");
    let sp = spec(
        &d,
        "scenario='paper-4.2'\n[set]\nscheme='accurate'\nt_end=0.08\n[axes]\nspeed=[100.0]\n[reduce]\nquantities=['peak:midspan_z','min:wheel1_gap_z','max:wheel1_gap_z','rms:wheel1_gap_z','rms:car1.body.az']\n",
    );
    ok(&maglev(&["sweep", s(&sp), "--out", s(&out)]));
    let run = d.join("run");
    ok(&maglev(&[
        "run",
        "paper-4.2",
        "--set",
        "scheme=accurate",
        "--set",
        "t_end=0.08",
        "--set",
        "speed=100.0",
        "--set",
        r#"output.probes=["midspan_z","wheel1_gap_z","car1.body.az"]"#,
        "--out",
        s(&run),
    ]));
    let z = column(&run, "midspan_z");
    let gap = column(&run, "wheel1_gap_z");
    let az = column(&run, "car1.body.az");
    assert_eq!(z.len(), 81);
    let peak = z
        .iter()
        .fold(0.0f64, |p, &v| if v.abs() > p.abs() { v } else { p });
    let rms = |v: &[f64]| (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt();
    let expected = [
        peak,
        gap.iter().copied().fold(f64::INFINITY, f64::min),
        gap.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        rms(&gap),
        rms(&az),
    ];
    let text = read(&out.join("results.csv"));
    let row: Vec<f64> = text
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .skip(1)
        .take(5)
        .map(|c| c.parse().unwrap())
        .collect();
    for (k, (got, want)) in row.iter().zip(expected).enumerate() {
        // response.csv holds the same f64s (shortest round-trip decimals); the sums are taken in
        // the same order, so the only difference allowed is none at all for peak/min/max and
        // round-off for rms.
        let tol = if k < 3 { 0.0 } else { 1e-14 * want.abs() };
        assert!((got - want).abs() <= tol, "quantity {k}: {got} vs {want}");
    }
    assert!(expected[4] > 0.0);
}

#[test]
fn the_slurm_scripts_hold_the_array_and_the_merge_dependency_and_run_locally() {
    let d = scratch("slurm");
    let sp = spec(&d, &ISSUE.replace("t_end = 0.03", "t_end = 0.02"));
    let jobs = d.join("jobs");
    ok(&maglev(&[
        "sweep",
        s(&sp),
        "--emit",
        "slurm",
        "--shards",
        "3",
        "--out",
        s(&jobs),
    ]));
    let array = read(&jobs.join("sweep.sbatch"));
    assert!(array.lines().any(|l| l == "#SBATCH --array=1-3"), "{array}");
    assert!(
        array.contains("--shard \"$SLURM_ARRAY_TASK_ID/3\""),
        "{array}"
    );
    let submit = read(&jobs.join("submit.sh"));
    assert!(
        submit.contains("--dependency=afterok:\"$array\""),
        "{submit}"
    );
    let merge = read(&jobs.join("merge.sbatch"));
    for i in 1..=3 {
        assert!(merge.contains(&format!("shard-{i}")), "{merge}");
    }
    let o = Command::new("bash")
        .arg(jobs.join("run-local.sh"))
        .env("MAGLEV", env!("CARGO_BIN_EXE_maglev"))
        .output()
        .unwrap();
    ok(&o);
    let inproc = d.join("inproc");
    ok(&maglev(&["sweep", s(&sp), "--out", s(&inproc)]));
    assert_eq!(
        read(&jobs.join("merged").join("results.csv")),
        read(&inproc.join("results.csv"))
    );
    // More shards than runs is refused.
    let o = maglev(&[
        "sweep",
        s(&sp),
        "--emit",
        "slurm",
        "--shards",
        "7",
        "--out",
        s(&d.join("x")),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--shards"));
}

#[test]
fn bad_specs_exit_2_with_one_line_naming_the_key() {
    let d = scratch("bad");
    for (text, key) in [
        ("scenario='moving-force'\n[axes]\nspeed={from=1.0,to=2.0,step=-1.0}\n[reduce]\nquantities=['peak:midspan_z']\n", "axes.speed.step"),
        ("scenario='moving-force'\n[axes]\nspeed=[1.0]\n[reduce]\nquantities=['peak:wheel1_gap_z']\n", "no gaps"),
        ("scenario='moving-force'\n[axes]\nspeed=[1.0]\n[reduce]\nquantities=['peak:span2.midspan.z']\n", "at most 1"),
        ("scenario='nowhere'\n[axes]\nspeed=[1.0]\n[reduce]\nquantities=['peak:midspan_z']\n", "nowhere"),
        ("scenario='moving-force'\n[axes]\nspeeed=[1.0]\n[reduce]\nquantities=['peak:midspan_z']\n", "axes.speeed"),
        ("scenario='moving-force'\n[axes]\n'run.speeed_m_per_s'=[1.0]\n[reduce]\nquantities=['peak:midspan_z']\n", "speeed_m_per_s"),
        ("scenario='moving-force'\n[axes]\nelements=[4, 8]\nseed=['one']\n[reduce]\nquantities=['peak:midspan_z']\n", "axes.seed"),
    ] {
        let sp = spec(&d, text);
        let o = maglev(&["sweep", s(&sp), "--out", s(&d.join("out"))]);
        assert_eq!(o.status.code(), Some(2), "{text}");
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(e.trim_end().lines().count(), 1, "{e}");
        assert!(e.contains(key), "{key}: {e}");
        assert!(!d.join("out").exists(), "{text}: a directory was left");
    }
    let sp = spec(&d, ISSUE);
    let o = maglev(&[
        "sweep",
        s(&sp),
        "--shard",
        "3/2",
        "--out",
        s(&d.join("out")),
    ]);
    assert_eq!(o.status.code(), Some(2));
}

/// `--jobs` beyond the limit is one line naming it (10 000 threads stalled the machine), and
/// nothing is written.
#[test]
fn too_many_jobs_are_refused() {
    let dir = scratch("jobs");
    let sp = spec(&dir, ISSUE);
    let out = dir.join("out");
    let o = maglev(&["sweep", s(&sp), "--jobs", "10000", "--out", s(&out)]);
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("--jobs") && e.contains("256"), "{e}");
    assert!(!out.exists());
}

/// A run outside a running-safety limit without a collision is `unsafe`, its error naming
/// the failed figures as summary.json's `safety` of the same `maglev run` names them
/// (paper-5's wheel/rail train lifts a wheel at 0.212 s, docs/safety.md).
#[test]
fn a_run_outside_its_safety_limits_is_unsafe_with_the_failed_figures() {
    let d = scratch("unsafe");
    let sp = spec(
        &d,
        "scenario = \"paper-5\"\n[set]\ntrain = \"wheel-rail\"\nt_end = 0.25\n\
         [axes]\nspeed = [83.33]\n[reduce]\nquantities = [\"peak:car4.body.az\"]\n",
    );
    let out = d.join("sweep");
    ok(&maglev(&["sweep", s(&sp), "--out", s(&out)]));
    let text = read(&out.join("results.csv"));
    let row: Vec<&str> = text.lines().nth(1).unwrap().split(',').collect();
    assert_eq!(row[2], "unsafe", "{text}");
    let run = d.join("run");
    ok(&maglev(&[
        "run",
        "paper-5",
        "--set",
        "train=wheel-rail",
        "--set",
        "t_end=0.25",
        "--set",
        "speed=83.33",
        "--out",
        s(&run),
    ]));
    let summary: serde_json::Value =
        serde_json::from_str(&read(&run.join("summary.json"))).unwrap();
    let safety = &summary["safety"];
    assert_eq!(safety["pass"], false);
    let mut failed = Vec::new();
    for (k, v) in safety["wheel_rail"].as_object().unwrap() {
        if v["pass"] == false {
            failed.push(format!("wheel_rail.{k}"));
        }
    }
    assert!(!failed.is_empty());
    for f in &failed {
        assert!(row[3].contains(f.as_str()), "{f} not in {}", row[3]);
    }
}
