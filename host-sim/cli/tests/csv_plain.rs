//! Every CSV the project writes reads as it is in pandas and a spreadsheet: one plain header
//! row (no comment line before or after it, names unique, non-empty and without surrounding
//! spaces), rectangular rows, and every column numeric (or empty where not applicable) except
//! the label columns named below. Metadata lives in summary.json or a sidecar, never in the
//! CSV (README "Outputs"; docs/bands.md, docs/ground.md).
//!
//! Covered: `run` (response.csv, profile.csv; with `[ground]`: ground.csv, ground-levels.csv),
//! `hil` (its response.csv and events.csv, with an out-of-range sensor so that it has events), `sweep` (results.csv, costs.csv), `bands`,
//! `accelerogram`, `irregularity`, `control` and `modes --format csv` on stdout, `bands --out`,
//! and the report's CSVs as committed under docs/paper5 (`maglev report` wrote them).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Columns that hold words, not numbers: names of receivers, trains, points, modes, run
/// statuses and errors, firmware events.
const LABELS: [&str; 7] = [
    "receiver", "train", "point", "kind", "status", "error", "events",
];

fn maglev(args: &[&str]) -> Output {
    let o = Command::new(env!("CARGO_BIN_EXE_maglev"))
        .args(args)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    o
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("maglev-csv-plain-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `Err` saying what is wrong with `text` as a plain CSV (module docs).
fn plain(text: &str) -> Result<usize, String> {
    if text.lines().any(|l| l.starts_with('#')) {
        return Err("a comment line".into());
    }
    let mut r = csv::ReaderBuilder::new()
        .has_headers(true)
        .flexible(false)
        .from_reader(text.as_bytes());
    let header: Vec<String> = r
        .headers()
        .map_err(|e| e.to_string())?
        .iter()
        .map(str::to_string)
        .collect();
    for (i, h) in header.iter().enumerate() {
        if h.is_empty() || h.trim() != h || header[..i].contains(h) {
            return Err(format!("header name {h:?}"));
        }
    }
    let mut rows = 0;
    for rec in r.records() {
        let rec = rec.map_err(|e| format!("not rectangular: {e}"))?;
        for (h, cell) in header.iter().zip(rec.iter()) {
            if !LABELS.contains(&h.as_str()) && !cell.is_empty() && cell.parse::<f64>().is_err() {
                return Err(format!("row {}: column {h} holds {cell:?}", rows + 1));
            }
        }
        rows += 1;
    }
    if rows == 0 {
        return Err("no rows".into());
    }
    Ok(rows)
}

fn check(what: &str, text: &str) {
    match plain(text) {
        Ok(rows) => eprintln!("{what}: {rows} rows"),
        Err(e) => panic!(
            "{what}: {e}\n{}",
            text.lines().take(3).collect::<Vec<_>>().join("\n")
        ),
    }
}

fn check_file(p: &Path) {
    check(
        &p.display().to_string(),
        &std::fs::read_to_string(p).unwrap(),
    );
}

fn stdout(o: &Output) -> String {
    String::from_utf8(o.stdout.clone()).unwrap()
}

/// The checker refuses what pandas misreads: a comment line, a ragged row, a word in a
/// number column, a repeated name.
#[test]
fn the_checker_refuses_what_pandas_misreads() {
    assert!(plain("t,a\n0,1\n").is_ok());
    assert!(plain("# about\nt,a\n0,1\n").is_err());
    assert!(plain("t,a\n0,1,2\n").is_err());
    assert!(plain("t,a\n0,overall\n").is_err());
    assert!(plain("t,t\n0,1\n").is_err());
    assert!(plain("t,a\n0,\n").is_ok());
}

#[test]
fn every_csv_a_command_writes_is_plain() {
    let d = scratch("all");
    let s = |p: &Path| p.to_str().unwrap().to_string();
    // run: response.csv and profile.csv.
    let run = d.join("run");
    maglev(&["run", "paper-4.2", "--set", "t_end=0.02", "--out", &s(&run)]);
    for f in ["response.csv", "profile.csv"] {
        check_file(&run.join(f));
    }
    // run with ground receivers: ground.csv and ground-levels.csv.
    let ground = d.join("ground");
    maglev(&[
        "run",
        "paper-5",
        "--set",
        "bridge.spans_m=[30.0, 30.0, 30.0]",
        "--set",
        "train=wheel-rail",
        "--set",
        "train.cars=1",
        "--set",
        "t_end=1.0",
        "--set",
        "dt=0.004",
        "--set",
        "ground.distances_m=[12.5, 25.0]",
        "--set",
        "ground.pier=2",
        "--set",
        "output.probes=[\"pier2.base.az\", \"ground2.vz\"]",
        "--out",
        &s(&ground),
    ]);
    for f in ["response.csv", "ground.csv", "ground-levels.csv"] {
        check_file(&ground.join(f));
    }
    // hil: its response.csv and events.csv.
    let hil = d.join("hil");
    maglev(&[
        "hil",
        "paper-4.2",
        "--firmware",
        "inproc",
        "--set",
        "t_end=0.01",
        "--set",
        "fault=range:0@0.002",
        "--out",
        &s(&hil),
    ]);
    for f in ["response.csv", "events.csv"] {
        check_file(&hil.join(f));
    }
    // sweep: results.csv and costs.csv.
    let spec = d.join("spec.toml");
    std::fs::write(
        &spec,
        "scenario='moving-force'\n[set]\nt_end=0.02\ndt=0.001\n[axes]\nspeed=[10.0, -1.0]\n[reduce]\nquantities=['peak:midspan_z']\n",
    )
    .unwrap();
    let sweep = d.join("sweep");
    maglev(&["sweep", &s(&spec), "--out", &s(&sweep)]);
    for f in ["results.csv", "costs.csv"] {
        check_file(&sweep.join(f));
    }
    // The commands that print CSV.
    let history = d.join("history.csv");
    let mut h = String::from("t,a\n");
    for j in 0..5000 {
        let t = j as f64 * 0.002;
        h += &format!("{t},{}\n", (std::f64::consts::TAU * 50.0 * t).sin());
    }
    std::fs::write(&history, h).unwrap();
    let trace = d.join("trace.csv");
    std::fs::write(&trace, "t,h\n0,0.01\n0.001,0.0099\n0.002,0.0098\n").unwrap();
    let bands_file = d.join("bands.csv");
    maglev(&[
        "bands",
        "--input",
        &s(&history),
        "--column",
        "a",
        "--out",
        &s(&bands_file),
    ]);
    check_file(&bands_file);
    for args in [
        &["bands", "--input", &s(&history), "--column", "a"][..],
        &[
            "bands",
            "--input",
            &s(&history),
            "--column",
            "a",
            "--output",
            "velocity",
        ],
        &["accelerogram", "--pga-g", "0.1", "--duration-s", "12"],
        &[
            "irregularity",
            "--direction",
            "z",
            "--seed",
            "1",
            "--dx",
            "0.5",
            "--length",
            "20",
        ],
        &["control", "--trace", &s(&trace), "--nsub", "10"],
        &["modes", "--format", "csv"],
    ] {
        check(&args.join(" "), &stdout(&maglev(args)));
    }
    // The report's CSVs, as `maglev report paper-5 --out docs/paper5` wrote them.
    let docs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/paper5");
    for f in ["bands.csv", "ground-levels.csv", "ground-overall.csv"] {
        check_file(&docs.join(f));
    }
    let _ = std::fs::remove_dir_all(&d);
}
