//! The paper's validation (§4.3–4.5, Fig. 5): FE against the modal Timoshenko reference
//! (`maglev validate`), as a table, numbers and figures; the CLI writes them.
//!
//! FE runs use an internal-loop sub-step of about 1 µs (n_sub = Δt / 1 µs, the paper's 1000 at
//! Δt = 1 ms); the modal reference runs at Δt = 1e-5 s with n_sub = 1 (a 10 µs sub-step, far
//! below the controller's 0.16 s period) and 160 modes. Every case is derived from one base
//! [`Case`] with typed [`Changes`], so each is checked as a loaded case is.

use crate::input::case::{Case, Changes};
use crate::input::scenario::Model;
use crate::output::{gap_ranges, GapRange};
use crate::plot::{self, overrides, Plot, Series};
use crate::probes::{Probes, Rows};
use crate::setup::simulate;
use crate::simulation::magnets::CoreMagnets;
use crate::{Error, Result};
use maglev_core::Scheme;
use serde::Serialize;
use std::fmt::Write as _;

/// Keys each case sets itself.
pub const CASE_KEYS: [&str; 10] = [
    "speed",
    "run.speed_m_per_s",
    "model",
    "run.model",
    "elements",
    "run.elements_per_span",
    "dt",
    "run.dt_s",
    "nsub",
    "controller.nsub",
];

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
    /// Steps in which some magnet's gap reached zero, in the FE run and in its reference.
    pub collision_steps: usize,
    pub reference_collision_steps: usize,
    /// Wheel 1's levitation gap range in the FE run (m).
    pub wheel1_gap_min_m: f64,
    pub wheel1_gap_max_m: f64,
    /// The magnet whose gap came nearest the bounds (0, 2·h0) over the FE run and its
    /// reference, and its range (m).
    pub worst_gap: GapRange,
    /// Every gap of every magnet within (0, 2·h0) and no collision, FE and reference.
    pub gaps_within_bounds: bool,
    pub wall_seconds: f64,
    pub criterion: String,
    pub pass: bool,
}

/// One run's histories.
pub struct RunHistories {
    /// Its histories: the default columns (midspan and wheel 1), one row per step.
    rows: Rows,
    /// Mean and largest Newton–Raphson iterations per step.
    mean_iterations: f64,
    max_iterations: u32,
    /// Every magnet's gap range.
    gaps: Vec<GapRange>,
    collision_steps: usize,
    wall: f64,
}

fn run(base: &Case, changes: Changes) -> Result<RunHistories> {
    let case = crate::studies::design::with(base, &changes)?;
    let mut rows = Rows::new(Probes::default_columns());
    let r = simulate(&case, &mut CoreMagnets::new(), &mut rows, &mut ())?;
    let (o, wall) = (r.outcome, r.wall);
    if o.unconverged_steps > 0 {
        return Err(Error::numerical(format!(
            "{} steps did not converge in {changes:?}",
            o.unconverged_steps
        )));
    }
    Ok(RunHistories {
        gaps: gap_ranges(&o.gap_ranges, &o.guided),
        collision_steps: o.collision_steps,
        rows,
        mean_iterations: o.total_iterations as f64 / o.steps as f64,
        max_iterations: o.max_iterations,
        wall,
    })
}

/// The magnet gap nearest to leaving (0, 2·h0), by its distance to the nearer bound.
fn worst_gap<'a>(gaps: impl Iterator<Item = &'a GapRange>, h0: f64) -> Option<GapRange> {
    gaps.min_by(|a, b| {
        let m = |g: &GapRange| g.min_m.min(2.0 * h0 - g.max_m);
        m(a).total_cmp(&m(b))
    })
    .cloned()
}

fn fe(base: &Case, speed: f64, elements: usize, dt: f64) -> Result<(RunHistories, u32)> {
    let nsub = ((dt / 1e-6).round() as u32).max(1);
    let r = run(
        base,
        Changes {
            speed: Some(speed),
            model: Some(Model::Fe),
            elements: Some(elements),
            dt: Some(dt),
            n_sub: Some(nsub),
            ..Changes::default()
        },
    )?;
    Ok((r, nsub))
}

fn modal(base: &Case, speed: f64) -> Result<RunHistories> {
    run(
        base,
        Changes {
            speed: Some(speed),
            model: Some(Model::Modal),
            dt: Some(1e-5),
            n_sub: Some(1),
            ..Changes::default()
        },
    )
}

/// The history of default column `name` of run `r`.
fn history(r: &RunHistories, name: &str) -> Vec<f64> {
    r.rows
        .column(name)
        .expect("a validation run records the default columns")
}

/// Reference value at time t by linear interpolation in the (finer) reference history
/// `(t_ref, y_ref)`.
fn at(t_ref: &[f64], y_ref: &[f64], t: f64) -> f64 {
    let dt = t_ref[1] - t_ref[0];
    let i = ((t / dt).floor() as usize).min(t_ref.len() - 2);
    let u = (t - t_ref[i]) / dt;
    y_ref[i] * (1.0 - u) + y_ref[i + 1] * u
}

/// Peak of the reference's history `name` and the largest difference of the run's over the
/// whole history relative to it.
fn max_rel_diff(run: &RunHistories, reference: &RunHistories, name: &str) -> (f64, f64) {
    let (y, y_ref) = (history(run, name), history(reference, name));
    let peak = y_ref.iter().map(|v| v.abs()).fold(0.0, f64::max);
    let d = run
        .rows
        .t
        .iter()
        .zip(&y)
        .map(|(&t, v)| (v - at(&reference.rows.t, &y_ref, t)).abs())
        .fold(0.0, f64::max);
    (peak, d / peak)
}

#[allow(clippy::too_many_arguments)]
fn compare(
    case: &str,
    speed: f64,
    elements: usize,
    dt: f64,
    reference: &RunHistories,
    lim_mid: Option<f64>,
    lim_w1: Option<f64>,
    base: &Case,
) -> Result<(Comparison, RunHistories)> {
    let h0 = base.h0();
    let (r, nsub) = fe(base, speed, elements, dt)?;
    let (mp, md) = max_rel_diff(&r, reference, "midspan_z");
    let (wp, wd) = max_rel_diff(&r, reference, "wheel1_z");
    let finite = ["midspan_z", "wheel1_z"]
        .iter()
        .all(|&name| history(&r, name).iter().all(|v| v.is_finite()));
    let worst = worst_gap(r.gaps.iter().chain(&reference.gaps), h0)
        .ok_or_else(|| Error::numerical("internal: a vehicle run without magnets"))?;
    let within = r.collision_steps == 0
        && reference.collision_steps == 0
        && worst.min_m > 0.0
        && worst.max_m < 2.0 * h0;
    let (criterion, pass) = match (lim_mid, lim_w1) {
        (Some(a), Some(b)) => (
            format!(
                "midspan ≤ {:.0} %, wheel 1 ≤ {:.0} %; gaps in (0, 2·h0)",
                a * 100.0,
                b * 100.0
            ),
            md <= a && wd <= b && finite && within,
        ),
        _ => (
            "gaps in (0, 2·h0) (differences reported only)".to_string(),
            finite && within,
        ),
    };
    let w1 = r
        .gaps
        .first()
        .ok_or_else(|| Error::numerical("internal: a vehicle run without magnets"))?;
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
            mean_iterations: r.mean_iterations,
            max_iterations: r.max_iterations,
            collision_steps: r.collision_steps,
            reference_collision_steps: reference.collision_steps,
            wheel1_gap_min_m: w1.min_m,
            wheel1_gap_max_m: w1.max_m,
            worst_gap: worst.clone(),
            gaps_within_bounds: within,
            wall_seconds: r.wall,
            criterion,
            pass,
        },
        r,
    ))
}

/// Everything validate found (validation.json).
#[derive(Serialize)]
pub struct Validation {
    pub pass: bool,
    pub comparisons: Vec<Comparison>,
    /// (Δt, mean, max) Newton–Raphson iterations per step (Fig. 5).
    pub iteration_study: Vec<(f64, f64, u32)>,
    pub iteration_study_pass: bool,
    pub wall_seconds: f64,
}

/// The validation's results, its figures `(file name, SVG)` and its report (Markdown).
pub struct Outcome {
    pub validation: Validation,
    pub figures: Vec<(String, String)>,
    pub report: String,
}

/// A displacement history `name` (m) of the FE `runs` against the modal `reference`, in mm.
fn plot_of(
    title: &str,
    reference: &RunHistories,
    runs: &[(String, &RunHistories)],
    name: &str,
    ylabel: &str,
) -> Plot {
    let t = |r: &RunHistories| r.rows.t.clone();
    let mm = |r: &RunHistories| history(r, name).iter().map(|v| v * 1e3).collect();
    let mut series = vec![Series::new(
        "modal (Δt = 1e-5)",
        t(reference),
        mm(reference),
    )];
    series.extend(
        runs.iter()
            .map(|(l, r)| Series::new(l.clone(), t(r), mm(r))),
    );
    Plot::new(title, "t (s)", ylabel, series)
}

/// `{name}.svg` and its text: one [`plot_of`].
fn figure(
    name: &str,
    title: &str,
    reference: &RunHistories,
    runs: &[(String, &RunHistories)],
    column: &str,
    ylabel: &str,
) -> crate::Result<(String, String)> {
    let svg = plot::svg(&plot_of(title, reference, runs, column, ylabel))?;
    Ok((format!("{name}.svg"), svg))
}

/// A 2 × 2 grid of plots under one title, as one SVG.
fn panels(title: &str, cells: &[Plot]) -> crate::Result<String> {
    plot::panels(title, 2, cells)
}

/// Refuses `--set` of the keys every case sets itself.
pub fn check_sets(sets: &[String]) -> Result<()> {
    for set in sets {
        let key = set.split_once('=').map_or(set.as_str(), |(k, _)| k).trim();
        if CASE_KEYS.contains(&key) {
            return Err(Error::invalid(
                format!("validate --set {key}"),
                "every case sets this key itself; override another key",
            ));
        }
    }
    Ok(())
}

/// The number of runs [`validate`] makes (one `step` call each).
pub const RUNS: u64 = 3 + 3 + 5 + 3 + 7;

/// Runs every case of the validation: `sets` apply to every case (checked by [`check_sets`]),
/// `scheme` is every run's controller scheme, `step` is told each run as it starts.
pub fn validate(sets: &[String], scheme: Scheme, mut step: impl FnMut(String)) -> Result<Outcome> {
    let start = std::time::Instant::now();
    check_sets(sets)?;
    let mut all = sets.to_vec();
    all.push(format!("scheme={}", scheme.as_str()));
    let base = crate::studies::design::load("paper-4.2", &all)?;
    let h0 = base.h0();
    let mut comps = Vec::new();
    let mut figs = Vec::new();
    let mut refs = std::collections::BTreeMap::new();
    for speed in [10.0, 100.0, 150.0] {
        step(format!("modal reference at {speed} m/s"));
        refs.insert(speed as u32, modal(&base, speed)?);
    }
    // §4.3 (Fig. 2): three speeds, 20 elements, Δt = 1 ms; the paper's four panels.
    for speed in [10.0, 100.0, 150.0] {
        let reference = &refs[&(speed as u32)];
        step(format!("§4.3 FE at {speed} m/s"));
        let (c, r) = compare(
            "4.3",
            speed,
            20,
            1e-3,
            reference,
            Some(0.01),
            Some(0.02),
            &base,
        )?;
        comps.push(c);
        let runs = [("FE, 20 el., Δt = 1 ms".to_string(), &r)];
        let cells: Vec<Plot> = [
            ("midspan Y", "midspan_y", "midspan_y (mm)"),
            ("midspan Z", "midspan_z", "midspan_z (mm)"),
            ("wheel 1 Y", "wheel1_y", "wheel1_y (mm)"),
            ("wheel 1 Z", "wheel1_z", "wheel1_z (mm)"),
        ]
        .iter()
        .map(|(what, column, ylabel)| plot_of(what, reference, &runs, column, ylabel))
        .collect();
        let title = format!("§4.3 (Fig. 2) at {speed} m/s{}", overrides(sets));
        let fig = panels(&title, &cells)?;
        figs.push((format!("fig2-{speed}.svg"), fig));
    }
    // §4.4: element counts at 100 m/s.
    let reference = &refs[&100];
    let mut el_runs = Vec::new();
    for el in [2usize, 4, 8, 16, 20] {
        step(format!("§4.4 FE with {el} elements"));
        let lim = if el >= 16 {
            (Some(0.01), Some(0.02))
        } else {
            (None, None)
        };
        let (c, r) = compare("4.4", 100.0, el, 1e-3, reference, lim.0, lim.1, &base)?;
        comps.push(c);
        el_runs.push((format!("FE, {el} elements"), r));
    }
    let el_refs: Vec<(String, &RunHistories)> =
        el_runs.iter().map(|(l, r)| (l.clone(), r)).collect();
    figs.push(figure(
        "fig3",
        &format!(
            "{}{}",
            "§4.4 midspan Z at 100 m/s, element count",
            overrides(sets)
        ),
        reference,
        &el_refs,
        "midspan_z",
        "midspan_z (mm)",
    )?);
    // §4.5: time steps at 100 m/s.
    let mut dt_runs = Vec::new();
    for dt in [1e-4, 5e-3, 1e-2] {
        step(format!("§4.5 FE with Δt = {dt} s"));
        let lim = if dt < 6e-3 {
            (Some(0.02), Some(0.04))
        } else {
            (None, None)
        };
        let (c, r) = compare("4.5", 100.0, 20, dt, reference, lim.0, lim.1, &base)?;
        comps.push(c);
        dt_runs.push((format!("FE, Δt = {dt} s"), r));
    }
    let dt_refs: Vec<(String, &RunHistories)> =
        dt_runs.iter().map(|(l, r)| (l.clone(), r)).collect();
    figs.push(figure(
        "fig4",
        &format!(
            "{}{}",
            "§4.5 midspan Z at 100 m/s, time step",
            overrides(sets)
        ),
        reference,
        &dt_refs,
        "midspan_z",
        "midspan_z (mm)",
    )?);
    figs.push(figure(
        "fig4-wheel1",
        &format!(
            "{}{}",
            "§4.5 wheel 1 Z at 100 m/s, time step",
            overrides(sets)
        ),
        reference,
        &dt_refs,
        "wheel1_z",
        "wheel1_z (mm)",
    )?);
    // Fig. 5: mean Newton–Raphson iterations per step against Δt.
    let mut study = Vec::new();
    for dt in [1e-5, 1e-4, 5e-4, 1e-3, 2e-3, 5e-3, 1e-2] {
        step(format!("Fig. 5 iterations at Δt = {dt} s"));
        let (r, _) = fe(&base, 100.0, 20, dt)?;
        study.push((dt, r.mean_iterations, r.max_iterations));
    }
    let study_pass = study.last().map(|l| l.1) > study.first().map(|f| f.1);
    let pass = comps.iter().all(|c| c.pass) && study_pass;
    // Report.
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# Validation: FE against the modal Timoshenko reference\n"
    );
    // The command that made this report: the committed docs/validation.md is the default one.
    let flags = match scheme {
        Scheme::Paper => String::new(),
        Scheme::Accurate => " --scheme accurate".to_string(),
    } + &sets
        .iter()
        .map(|s| format!(" --set {s}"))
        .collect::<String>();
    let again = if flags.is_empty() {
        "`cargo run --release -- validate --out docs --report validation.md` regenerates this page, its figures and docs/validation.json".to_string()
    } else {
        format!("`cargo run --release -- validate{flags} --out DIR` regenerates it")
    };
    let _ = writeln!(md, "Generated by `maglev validate{flags}` ({:.0} s wall; {again}). The paper-4.2 scenario (docs/model.md §9): 25 m Timoshenko beam, Fig. 1 vehicle, Table 1 irregularities (seed 1), magnet geometry `{}` (docs/model.md §2). Differences are the largest over the whole history, relative to the reference's peak. Reference: modal, 160 modes, Δt = 1e-5 s. Controller scheme (all runs): {} (n_sub applies to the paper scheme only).\n", start.elapsed().as_secs_f64(), base.geometry.as_str(), scheme.as_str());
    let _ = writeln!(md, "Every case must also fly: no collision step and every gap of every magnet (levitation and both guidance magnets of each wheel) within (0, 2·h0) = (0, {:.0}) mm, in the FE run and in its modal reference.\n", 2e3 * h0);
    let _ = writeln!(md, "Overall: **{}**\n", if pass { "PASS" } else { "FAIL" });
    let _ = writeln!(md, "| case | speed (m/s) | elements | Δt (s) | n_sub | midspan Z peak (mm) | max diff | wheel 1 Z peak (mm) | max diff | wheel 1 gap (mm) | nearest bound: magnet, gap (mm) | collision steps FE / ref. | mean NR it. | criterion | result |");
    let _ = writeln!(
        md,
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    );
    for c in &comps {
        let _ = writeln!(
            md,
            "| §{} | {} | {} | {} | {} | {:.4} | {:.3} % | {:.3} | {:.3} % | {:.2}–{:.2} | {} {:.2}–{:.2} | {} / {} | {:.2} | {} | {} |",
            c.case,
            c.speed_m_per_s,
            c.elements,
            c.dt_s,
            c.nsub,
            c.midspan_z_peak_m * 1e3,
            c.midspan_z_max_diff_rel * 100.0,
            c.wheel1_z_peak_m * 1e3,
            c.wheel1_z_max_diff_rel * 100.0,
            c.wheel1_gap_min_m * 1e3,
            c.wheel1_gap_max_m * 1e3,
            c.worst_gap.magnet,
            c.worst_gap.min_m * 1e3,
            c.worst_gap.max_m * 1e3,
            c.collision_steps,
            c.reference_collision_steps,
            c.mean_iterations,
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
    let _ = writeln!(md, "## Figures\n");
    for (name, _) in &figs {
        let _ = writeln!(md, "![{name}]({name})\n");
    }
    let validation = Validation {
        pass,
        comparisons: comps,
        iteration_study: study,
        iteration_study_pass: study_pass,
        wall_seconds: start.elapsed().as_secs_f64(),
    };
    Ok(Outcome {
        validation,
        figures: figs,
        report: md,
    })
}
