//! `maglev report paper-5` end to end: it writes its files, and its band levels agree with an
//! independent 1/3-octave analysis of the report's own histories within 0.5 dB (issue #10).
//!
//! The independent analyser (tests/bands_reference) shares only the definition of
//! docs/bands.md (IEC 61260-1 base-10 band edges, the band mean square as the integral of the
//! record's spectrum over the band): it sums the spectrum directly at Gauss–Legendre nodes,
//! not by the FFT crate, and reads the histories from the written CSV.

use std::path::Path;
use std::process::Command;

#[path = "../../sim/tests/bands_reference/mod.rs"]
mod bands_reference;

/// report.md with the wall-time cell of the "## Runs" table blanked (it is a measurement).
fn without_wall_times(md: &str) -> String {
    let mut in_runs = false;
    md.lines()
        .map(|l| {
            if l.starts_with("## ") {
                in_runs = l == "## Runs";
            }
            let cells: Vec<&str> = l.split('|').collect();
            if in_runs && cells.len() > 4 && !l.starts_with("| train") && !l.starts_with("|---") {
                let mut c = cells.clone();
                c[3] = " ";
                c.join("|")
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Every file of two report directories, byte for byte (report.md without its wall times).
fn assert_same_reports(a: &Path, b: &Path) {
    let mut names: Vec<_> = std::fs::read_dir(a)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    names.sort();
    assert!(names.len() >= 10, "{names:?}");
    for name in names {
        let (x, y) = (
            std::fs::read(a.join(&name)).unwrap(),
            std::fs::read(b.join(&name)),
        );
        let y = y.unwrap_or_else(|_| panic!("{name:?} missing from {}", b.display()));
        if name == "report.md" {
            let (x, y) = (String::from_utf8(x).unwrap(), String::from_utf8(y).unwrap());
            assert_eq!(without_wall_times(&x), without_wall_times(&y), "report.md");
        } else {
            assert!(x == y, "{name:?} differs between 1 and 2 threads");
        }
    }
}

#[test]
fn report_levels_agree_with_an_independent_analyser() {
    let out = std::env::temp_dir().join(format!("maglev-report-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let o = Command::new(env!("CARGO_BIN_EXE_maglev"))
        .args(["report", "paper-5", "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // The two runs side by side and the receivers on two threads (the default) give the
    // same bytes as everything on one.
    let serial = out.with_extension("serial");
    let _ = std::fs::remove_dir_all(&serial);
    let o = Command::new(env!("CARGO_BIN_EXE_maglev"))
        .args(["report", "paper-5", "--threads", "1", "--out"])
        .arg(&serial)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_same_reports(&out, &serial);
    let _ = std::fs::remove_dir_all(&serial);
    for f in [
        "report.md",
        "fig8.svg",
        "bands.csv",
        "history-maglev.csv",
        "history-wheel-rail.csv",
        "ground-levels.csv",
        "ground-overall.csv",
        "ground-levels.svg",
        "ground-map-maglev.svg",
        "ground-map-wheel-rail.svg",
    ] {
        assert!(out.join(f).is_file(), "missing {f}");
    }
    // The ground section: levels for both trains at the four distances, falling with
    // distance, and the section's parts in report.md.
    let ground = std::fs::read_to_string(out.join("ground-overall.csv")).unwrap();
    for train in ["maglev", "wheel-rail"] {
        let overall: Vec<f64> = ground
            .lines()
            .filter(|l| l.starts_with(&format!("{train},")))
            .map(|l| l.split(',').nth(2).unwrap().parse().unwrap())
            .collect();
        assert_eq!(overall.len(), 4, "{train}");
        assert!(
            overall.windows(2).all(|w| w[0] > w[1]),
            "{train}: {overall:?}"
        );
    }
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    for part in [
        "## Ground-borne vibration",
        "### Verdicts",
        "### What the comparison says",
        "ground-map-maglev.svg",
    ] {
        assert!(md.contains(part), "report.md lacks {part}");
    }
    let bands = std::fs::read_to_string(out.join("bands.csv")).unwrap();
    let mut checked = 0;
    for train in ["maglev", "wheel-rail"] {
        let path = out.join(format!("history-{train}.csv"));
        let (car, dt) = bands_reference::read_csv_column(&path, "car4.body.az");
        let (pier, _) = bands_reference::read_csv_column(&path, "pier20.base.az");
        assert_eq!(car.len(), 5001, "5000 steps and t = 0");
        for line in bands
            .lines()
            .filter(|l| l.starts_with(&format!("{train},")))
        {
            let f: Vec<&str> = line.split(',').collect();
            let nominal: f64 = f[2].parse().unwrap();
            let ours: f64 = f[3].parse().unwrap();
            // The exact centre of the base-10 band nearest the nominal frequency.
            let x = (10.0 * (nominal / 1000.0).log10()).round() as i32;
            let series = if f[1] == "car4.body.az" { &car } else { &pier };
            let ms = bands_reference::band_mean_squares(series, dt, 0, &[x])[0];
            let theirs = 10.0 * (ms / 1e-12).log10();
            assert!(
                (ours - theirs).abs() <= 0.5,
                "{train} {} {nominal} Hz: {ours} dB vs {theirs} dB",
                f[1]
            );
            checked += 1;
        }
    }
    assert!(checked >= 100, "only {checked} bands checked");
    let _ = std::fs::remove_dir_all(&out);
}
