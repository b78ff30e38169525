//! The DAF-against-speed study of docs/sweeps.md: two sweeps (host-sim/cli/sweeps/daf-*.toml),
//! each run's peak dynamic midspan deflection divided by the static midspan deflection from
//! an independent closed form (simply supported Timoshenko beam, docs/model.md §9), the plot,
//! and the cost of each run.
//!
//! `cargo run --release --example daf -- [--out DIR] [--jobs N] [--svg FILE]` (defaults
//! target/daf, all cores, DIR/daf.svg; `--svg docs/sweeps-daf.svg` refreshes the tracked
//! figure of docs/sweeps.md). The sweeps are resumable: a second call only redraws.

use maglev::studies::sweep::{self, plot, Options, Spec};
use std::path::{Path, PathBuf};

/// Midspan deflection (m, downward positive) of a simply supported span of length `l` under a
/// force `p` at distance `b ≤ l/2` from the nearer support: Euler–Bernoulli bending
/// `p b (3l² − 4b²) / (48 EI)` plus the Timoshenko shear term `M(l/2) / (G A_s) = p b / (2 G A_s)`.
fn midspan(p: f64, b: f64, l: f64, ei: f64, gas: f64) -> f64 {
    p * b * (3.0 * l * l - 4.0 * b * b) / (48.0 * ei) + p * b / (2.0 * gas)
}

/// The largest static midspan deflection (m) of each study over every position of its loads,
/// from the values of docs/model.md §9 (not read from the scenarios, so that a changed
/// scenario file shows up as a DAF away from 1 at low speed).
fn static_deflection(name: &str) -> f64 {
    // The §4.2 beam: L = 25 m, E = 3.6e10 Pa, I_Y = 0.6 m⁴ (vertical bending is about Y),
    // G = 1.6e10 Pa, A_Z = 0.7 m² (vertical shear).
    let (l, ei, gas) = (25.0, 3.6e10 * 0.6, 1.6e10 * 0.7);
    match name {
        // One constant 36.79 kN force (a quarter of the 15 t body's weight), worst at midspan.
        "moving-force" => midspan(36.79e3, l / 2.0, l, ei, gas),
        // The Fig. 1 vehicle: 15 t on two axles 15 m apart (wheels at ±7.5 m), each carrying
        // half the weight (g = 9.81, docs/model.md §0). The midspan influence line is concave,
        // so the worst position is symmetric about midspan (each axle 5 m from a support),
        // against 15625/17750 of that with one axle at midspan and the other off the span.
        "paper-4.2" => {
            let p = 15.0e3 * 9.81 / 2.0;
            let a = 7.5;
            (2.0 * midspan(p, l / 2.0 - a, l, ei, gas)).max(midspan(p, l / 2.0, l, ei, gas))
        }
        other => panic!("no closed form for {other}"),
    }
}

fn rows(dir: &Path) -> Vec<csv::StringRecord> {
    csv::Reader::from_path(dir)
        .unwrap()
        .records()
        .map(|r| r.unwrap())
        .collect()
}

fn main() {
    let mut args = std::env::args().skip(1);
    let mut out = PathBuf::from("target/daf");
    let mut svg = None;
    let mut jobs = std::thread::available_parallelism().map_or(1, |n| n.get());
    while let Some(a) = args.next() {
        let v = args.next().expect("a value after the option");
        match a.as_str() {
            "--out" => out = v.into(),
            "--svg" => svg = Some(PathBuf::from(v)),
            "--jobs" => jobs = v.parse().expect("--jobs N"),
            _ => panic!("unknown option {a}"),
        }
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("sweeps");
    let mut lines = Vec::new();
    println!("| scenario | static midspan deflection (closed form) |\n|---|---|");
    for (name, file) in [
        ("moving-force", "daf-moving-force.toml"),
        ("paper-4.2", "daf-paper-4.2.toml"),
    ] {
        let spec = Spec::load(&root.join(file)).unwrap();
        let dir = out.join(name);
        let opts = Options {
            jobs,
            shard: None,
            retry_failed: false,
            progress: false,
        };
        let r = sweep::sweep(&spec, &dir, &opts).unwrap();
        eprintln!(
            "{name}: {} runs ({} run now) in {:.1} s",
            r.runs, r.ran, r.wall_s
        );
        let stat = static_deflection(name);
        println!("| {name} | {:.4} mm |", stat * 1e3);
        let results = rows(&dir.join("results.csv"));
        let costs = rows(&dir.join("costs.csv"));
        for (row, cost) in results.iter().zip(&costs) {
            let speed: f64 = row[0].parse().unwrap();
            let label = if name == "paper-4.2" {
                format!("paper-4.2, seed {}", &row[1])
            } else {
                name.to_string()
            };
            let peak_col = spec.axes.len();
            let daf = row[peak_col]
                .parse::<f64>()
                .map_or(f64::NAN, |z| z.abs() / stat);
            let wall: f64 = cost[cost.len() - 1].parse().unwrap();
            let steps: usize = cost[cost.len() - 2].parse().unwrap();
            lines.push((
                label,
                speed,
                daf,
                steps,
                wall,
                row[row.len() - 2].to_string(),
            ));
        }
    }
    println!(
        "\n| run | speed (m/s) | DAF | steps | wall (s) | status |\n|---|---|---|---|---|---|"
    );
    for (label, speed, daf, steps, wall, status) in &lines {
        println!("| {label} | {speed} | {daf:.4} | {steps} | {wall:.3} | {status} |");
    }
    let mut curves: Vec<plot::Line> = Vec::new();
    for (label, speed, daf, ..) in &lines {
        match curves.iter_mut().find(|c| c.label == *label) {
            Some(c) => {
                c.x.push(*speed);
                c.y.push(*daf);
            }
            None => curves.push(plot::Line {
                label: label.clone(),
                x: vec![*speed],
                y: vec![*daf],
            }),
        }
    }
    let text = plot::draw(
        "DAF = peak midspan deflection / static (closed form)",
        "speed (m/s)",
        "DAF",
        &curves,
    )
    .expect("the DAF plot");
    let svg = svg.unwrap_or_else(|| out.join("daf.svg"));
    std::fs::write(&svg, text).unwrap();
    eprintln!("wrote {}", svg.display());
}
