//! `maglev validate [--out DIR]`: the paper's validation (§4.3–4.5, Fig. 5), FE against the
//! modal Timoshenko reference, as tables (`report.md`), numbers (`validation.json`) and SVG
//! figures. Exits non-zero when a criterion fails.
//!
//! FE runs use an internal-loop sub-step of about 1 µs (n_sub = Δt / 1 µs, the paper's 1000 at
//! Δt = 1 ms); the modal reference runs at Δt = 1e-5 s with n_sub = 1 (a 10 µs sub-step, far
//! below the controller's 0.16 s period) and 160 modes.

use crate::cli::control::SchemeKind;
use crate::cli::run::execute;
use crate::output::{svg_plot, Series};
use crate::scenario::{self, Scenario};
use crate::simulation::Record;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// File name of the report inside --out (`maglev validate --out docs --report
    /// validation.md` regenerates the committed docs/validation.md and its figures).
    #[arg(long, default_value = "report.md")]
    pub report: String,
    /// Output directory for the report, validation.json and the figures.
    #[arg(long, default_value = "validation")]
    pub out: PathBuf,
    /// Controller scheme of every run, FE and modal reference alike (`controller.scheme`).
    #[arg(long, value_enum, default_value_t = SchemeKind::Paper)]
    pub scheme: SchemeKind,
}

/// One FE run compared with its modal reference.
#[derive(Serialize, Debug, Clone)]
pub struct Comparison {
    pub case: String,
    pub speed_m_per_s: f64,
    pub elements: usize,
    pub dt_s: f64,
    pub nsub: u32,
    pub midspan_z_peak_m: f64,
    pub midspan_z_max_diff_rel: f64,
    pub wheel1_z_peak_m: f64,
    pub wheel1_z_max_diff_rel: f64,
    pub mean_iterations: f64,
    pub max_iterations: u32,
    /// Steps in which some magnet's gap reached zero (the run goes on, flagged).
    pub collision_steps: usize,
    pub wall_seconds: f64,
    pub criterion: String,
    pub pass: bool,
}

struct Run {
    records: Vec<Record>,
    wall: f64,
}

fn run(sets: &[String], scheme: SchemeKind) -> Result<Run, String> {
    let mut sets = sets.to_vec();
    sets.push(format!("scheme={}", scheme_name(scheme)));
    let sc: Scenario = scenario::load("paper-4.2", &sets)?;
    let (o, wall) = execute(&sc, |_| {})?;
    if o.unconverged_steps > 0 {
        return Err(format!(
            "{} steps did not converge in {sets:?}",
            o.unconverged_steps
        ));
    }
    Ok(Run {
        records: o.records,
        wall,
    })
}

fn scheme_name(s: SchemeKind) -> &'static str {
    match s {
        SchemeKind::Paper => "paper",
        SchemeKind::Accurate => "accurate",
    }
}

fn fe(speed: f64, elements: usize, dt: f64, scheme: SchemeKind) -> Result<(Run, u32), String> {
    let nsub = ((dt / 1e-6).round() as u32).max(1);
    let r = run(
        &[
            format!("speed={speed}"),
            "model=fe".into(),
            format!("elements={elements}"),
            format!("dt={dt}"),
            format!("nsub={nsub}"),
        ],
        scheme,
    )?;
    Ok((r, nsub))
}

fn modal(speed: f64, scheme: SchemeKind) -> Result<Run, String> {
    run(
        &[
            format!("speed={speed}"),
            "model=modal".into(),
            "dt=1e-5".into(),
            "nsub=1".into(),
        ],
        scheme,
    )
}

/// Reference value at time t by linear interpolation in the (finer) reference history.
fn at(reference: &[Record], t: f64, get: fn(&Record) -> f64) -> f64 {
    let dt = reference[1].t - reference[0].t;
    let i = ((t / dt).floor() as usize).min(reference.len() - 2);
    let u = (t - reference[i].t) / dt;
    get(&reference[i]) * (1.0 - u) + get(&reference[i + 1]) * u
}

/// Largest difference over the whole history relative to the reference's peak.
fn max_rel_diff(run: &[Record], reference: &[Record], get: fn(&Record) -> f64) -> (f64, f64) {
    let peak = reference.iter().map(|r| get(r).abs()).fold(0.0, f64::max);
    let d = run
        .iter()
        .map(|r| (get(r) - at(reference, r.t, get)).abs())
        .fold(0.0, f64::max);
    (peak, d / peak)
}

fn midspan_z(r: &Record) -> f64 {
    r.midspan.z
}
fn wheel1_z(r: &Record) -> f64 {
    r.wheel1_z
}

#[allow(clippy::too_many_arguments)]
fn compare(
    case: &str,
    speed: f64,
    elements: usize,
    dt: f64,
    reference: &Run,
    lim_mid: Option<f64>,
    lim_w1: Option<f64>,
    scheme: SchemeKind,
) -> Result<(Comparison, Run), String> {
    let (r, nsub) = fe(speed, elements, dt, scheme)?;
    let (mp, md) = max_rel_diff(&r.records, &reference.records, midspan_z);
    let (wp, wd) = max_rel_diff(&r.records, &reference.records, wheel1_z);
    let its: Vec<u32> = r.records.iter().skip(1).map(|x| x.iterations).collect();
    let finite = r
        .records
        .iter()
        .all(|x| x.midspan.z.is_finite() && x.wheel1_z.is_finite());
    let (criterion, pass) = match (lim_mid, lim_w1) {
        (Some(a), Some(b)) => (
            format!("midspan ≤ {:.0} %, wheel 1 ≤ {:.0} %", a * 100.0, b * 100.0),
            md <= a && wd <= b && finite,
        ),
        _ => ("finite (reported only)".to_string(), finite),
    };
    Ok((
        Comparison {
            case: case.into(),
            speed_m_per_s: speed,
            elements,
            dt_s: dt,
            nsub,
            midspan_z_peak_m: mp,
            midspan_z_max_diff_rel: md,
            wheel1_z_peak_m: wp,
            wheel1_z_max_diff_rel: wd,
            mean_iterations: its.iter().map(|&i| i as f64).sum::<f64>() / its.len() as f64,
            max_iterations: its.iter().copied().max().unwrap_or(0),
            collision_steps: r
                .records
                .iter()
                .filter(|x| x.status.contains(maglev_core::Status::COLLISION))
                .count(),
            wall_seconds: r.wall,
            criterion,
            pass,
        },
        r,
    ))
}

#[derive(Serialize)]
struct Validation {
    pass: bool,
    comparisons: Vec<Comparison>,
    iteration_study: Vec<(f64, f64, u32)>,
    iteration_study_pass: bool,
    wall_seconds: f64,
}

fn figure(
    name: &str,
    title: &str,
    reference: &Run,
    runs: &[(String, &Run)],
    get: fn(&Record) -> f64,
    ylabel: &str,
) -> (String, String) {
    let t_ref: Vec<f64> = reference.records.iter().map(|r| r.t).collect();
    let mut series = vec![Series {
        label: "modal (Δt = 1e-5)".into(),
        x: &t_ref,
        y: reference.records.iter().map(get).collect(),
    }];
    let ts: Vec<Vec<f64>> = runs
        .iter()
        .map(|(_, r)| r.records.iter().map(|x| x.t).collect())
        .collect();
    for ((label, r), t) in runs.iter().zip(&ts) {
        series.push(Series {
            label: label.clone(),
            x: t,
            y: r.records.iter().map(get).collect(),
        });
    }
    (
        format!("{name}.svg"),
        svg_plot(title, "t (s)", ylabel, &series),
    )
}

pub fn run_cmd(args: Args) -> Result<(), String> {
    let start = std::time::Instant::now();
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("cannot create {}: {e}", args.out.display()))?;
    let mut comps = Vec::new();
    let mut figs = Vec::new();
    let mut refs = std::collections::BTreeMap::new();
    for speed in [10.0, 100.0, 150.0] {
        eprintln!("maglev: validate: modal reference at {speed} m/s …");
        refs.insert(speed as u32, modal(speed, args.scheme)?);
    }
    // §4.3: three speeds, 20 elements, Δt = 1 ms.
    for speed in [10.0, 100.0, 150.0] {
        let reference = &refs[&(speed as u32)];
        eprintln!("maglev: validate: §4.3 FE at {speed} m/s …");
        let (c, r) = compare(
            "4.3",
            speed,
            20,
            1e-3,
            reference,
            Some(0.01),
            Some(0.02),
            args.scheme,
        )?;
        comps.push(c);
        figs.push(figure(
            &format!("fig2-{speed}"),
            &format!("§4.3 midspan Z at {speed} m/s"),
            reference,
            &[("FE, 20 el., Δt = 1 ms".into(), &r)],
            midspan_z,
            "midspan_z (m)",
        ));
    }
    // §4.4: element counts at 100 m/s.
    let reference = &refs[&100];
    let mut el_runs = Vec::new();
    for el in [2usize, 4, 8, 16, 20] {
        eprintln!("maglev: validate: §4.4 FE with {el} elements …");
        let lim = if el >= 16 {
            (Some(0.01), Some(0.02))
        } else {
            (None, None)
        };
        let (c, r) = compare("4.4", 100.0, el, 1e-3, reference, lim.0, lim.1, args.scheme)?;
        comps.push(c);
        el_runs.push((format!("FE, {el} elements"), r));
    }
    let el_refs: Vec<(String, &Run)> = el_runs.iter().map(|(l, r)| (l.clone(), r)).collect();
    figs.push(figure(
        "fig3",
        "§4.4 midspan Z at 100 m/s, element count",
        reference,
        &el_refs,
        midspan_z,
        "midspan_z (m)",
    ));
    // §4.5: time steps at 100 m/s.
    let mut dt_runs = Vec::new();
    for dt in [1e-4, 5e-3, 1e-2] {
        eprintln!("maglev: validate: §4.5 FE with Δt = {dt} s …");
        let lim = if dt < 6e-3 {
            (Some(0.02), Some(0.04))
        } else {
            (None, None)
        };
        let (c, r) = compare("4.5", 100.0, 20, dt, reference, lim.0, lim.1, args.scheme)?;
        comps.push(c);
        dt_runs.push((format!("FE, Δt = {dt} s"), r));
    }
    let dt_refs: Vec<(String, &Run)> = dt_runs.iter().map(|(l, r)| (l.clone(), r)).collect();
    figs.push(figure(
        "fig4",
        "§4.5 midspan Z at 100 m/s, time step",
        reference,
        &dt_refs,
        midspan_z,
        "midspan_z (m)",
    ));
    figs.push(figure(
        "fig4-wheel1",
        "§4.5 wheel 1 Z at 100 m/s, time step",
        reference,
        &dt_refs,
        wheel1_z,
        "wheel1_z (m)",
    ));
    // Fig. 5: mean Newton–Raphson iterations per step against Δt.
    let mut study = Vec::new();
    for dt in [1e-5, 1e-4, 5e-4, 1e-3, 2e-3, 5e-3, 1e-2] {
        eprintln!("maglev: validate: Fig. 5 iterations at Δt = {dt} s …");
        let (r, _) = fe(100.0, 20, dt, args.scheme)?;
        let its: Vec<u32> = r.records.iter().skip(1).map(|x| x.iterations).collect();
        study.push((
            dt,
            its.iter().map(|&i| i as f64).sum::<f64>() / its.len() as f64,
            its.iter().copied().max().unwrap_or(0),
        ));
    }
    let study_pass = study.last().map(|l| l.1) > study.first().map(|f| f.1);
    let pass = comps.iter().all(|c| c.pass) && study_pass;
    // Report.
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# Validation: FE against the modal Timoshenko reference\n"
    );
    let _ = writeln!(md, "Generated by `maglev validate` ({:.0} s wall; `cargo run --release -- validate --out docs --report validation.md` regenerates this page, its figures and docs/validation.json). The paper-4.2 scenario (model.md §9): 25 m Timoshenko beam, Fig. 1 vehicle, Table 1 irregularities (seed 1). Differences are the largest over the whole history, relative to the reference's peak. Reference: modal, 160 modes, Δt = 1e-5 s. Controller scheme (all runs): {} (n_sub applies to the paper scheme only).\n", start.elapsed().as_secs_f64(), scheme_name(args.scheme));
    let _ = writeln!(md, "Overall: **{}**\n", if pass { "PASS" } else { "FAIL" });
    let _ = writeln!(md, "| case | speed (m/s) | elements | Δt (s) | n_sub | midspan Z peak (mm) | max diff | wheel 1 Z peak (mm) | max diff | mean NR it. | collision steps | criterion | result |");
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for c in &comps {
        let _ = writeln!(
            md,
            "| §{} | {} | {} | {} | {} | {:.4} | {:.3} % | {:.3} | {:.3} % | {:.2} | {} | {} | {} |",
            c.case,
            c.speed_m_per_s,
            c.elements,
            c.dt_s,
            c.nsub,
            c.midspan_z_peak_m * 1e3,
            c.midspan_z_max_diff_rel * 100.0,
            c.wheel1_z_peak_m * 1e3,
            c.wheel1_z_max_diff_rel * 100.0,
            c.mean_iterations,
            c.collision_steps,
            c.criterion,
            if c.pass { "pass" } else { "FAIL" }
        );
    }
    let _ = writeln!(md, "\n## Fig. 5: Newton–Raphson iterations per step (100 m/s, 20 elements)\n\n| Δt (s) | mean | max |\n|---|---|---|");
    for (dt, mean, max) in &study {
        let _ = writeln!(md, "| {dt} | {mean:.2} | {max} |");
    }
    let _ = writeln!(
        md,
        "\nCriterion: iterations rise as Δt grows (mean at 1e-2 s above mean at 1e-5 s): **{}**.\n",
        if study_pass { "pass" } else { "FAIL" }
    );
    let _ = writeln!(md, "## Note: the vehicle drifts\n\nThe wheel-1 histories grow to tens of centimetres (metres in the 4 s passage at 10 m/s): with model.md's EMS sign convention the paper's law regulates the flux g = i/h, not the gap, and the linearised magnet + Fig. 1 vehicle on a rigid rail has unstable poles (see docs/theory.md). Once a gap reaches zero the run goes on with h = 0 in the law and the step flagged as a collision (column \"collision steps\"): past that point the wheel histories are not physical. FE and modal reproduce the same drift; the comparison is of the two guideway models, not a claim of a stable vehicle. `--set law=gap-loop` on `maglev run` adds the outer gap loop that holds the gap (docs/gap-loop.md).\n");
    let _ = writeln!(md, "## Figures\n");
    for (name, svg) in &figs {
        std::fs::write(args.out.join(name), svg)
            .map_err(|e| format!("cannot write figure {name}: {e}"))?;
        let _ = writeln!(md, "![{name}]({name})\n");
    }
    std::fs::write(args.out.join(&args.report), md)
        .map_err(|e| format!("cannot write {}: {e}", args.report))?;
    let v = Validation {
        pass,
        comparisons: comps,
        iteration_study: study,
        iteration_study_pass: study_pass,
        wall_seconds: start.elapsed().as_secs_f64(),
    };
    std::fs::write(
        args.out.join("validation.json"),
        serde_json::to_string_pretty(&v).map_err(|e| e.to_string())? + "\n",
    )
    .map_err(|e| format!("cannot write validation.json: {e}"))?;
    eprintln!(
        "maglev: validate: {} in {:.0} s; wrote {}",
        if pass { "PASS" } else { "FAIL" },
        start.elapsed().as_secs_f64(),
        args.out.display()
    );
    if pass {
        Ok(())
    } else {
        Err(format!(
            "validation failed: see {}",
            args.out.join(&args.report).display()
        ))
    }
}
