//! The paper's §5 comparison (its Fig. 8; docs/model.md §10): a 12-car maglev train and a
//! 12-car wheel/rail train cross the same viaduct at 83.33 m/s; the vertical acceleration at
//! the 4th carriage's centre and at the base of the 20th pier, as 1/3-octave band levels.
//!
//! Why a module of its own: `maglev report paper-5` is the one place that runs both trains,
//! turns their histories into band levels ([`crate::bands`]) and holds the result against
//! the paper's statements, so the report, its figure and the tests read the same numbers.
//! Every statement is evaluated from the levels, never written in by hand; where the model
//! disagrees with the paper the report says so (docs/paper5.md explains the disagreements).

pub mod ground;

use crate::bands::{self, Averaging, BandLevel, Level, Motion};
use crate::ground::receivers::BaseForces;
use crate::output::safety::{Figure, Safety, SafetyReport};
use crate::physics::fe::soil::Soil;
use crate::plot::{self, Plot, Series};
use crate::probes::{Rows, Tee};
use crate::setup::simulate;
use crate::simulation::magnets::CoreMagnets;
use crate::{Error, Result};
use std::fmt::Write as _;

/// The bundled scenario.
pub const SCENARIO: &str = "paper-5";
/// The probes of Fig. 8: the 4th carriage's centre and the base of the 20th pier.
pub const CARRIAGE: &str = "car4.body.az";
pub const PIER: &str = "pier20.base.az";
/// The two trains (`--set train=…`).
pub const TRAINS: [&str; 2] = ["maglev", "wheel-rail"];

/// One train's passage: the two histories of Fig. 8.
pub struct TrainRun {
    pub train: String,
    pub dt: f64,
    pub carriage: Vec<f64>,
    pub pier: Vec<f64>,
    pub steps: usize,
    pub collision_steps: usize,
    pub contact_loss_steps: usize,
    pub unconverged_steps: usize,
    pub wall: f64,
    /// Every pier's vertical base force, for the ground section ([`crate::studies::paper5::ground`]).
    pub base: BaseForces,
    /// The soil and the span length of the case (the ground section's half-space and piers).
    pub soil: Soil,
    pub span: f64,
    /// The running-safety figures (docs/safety.md).
    pub safety: Option<SafetyReport>,
}

/// One train's whole-record band levels (re 1e-6 m/s²) at the carriage and at the pier.
pub struct TrainLevels {
    pub carriage: Vec<BandLevel>,
    pub pier: Vec<BandLevel>,
}

/// One of the paper's statements, evaluated on the levels.
pub struct Statement {
    pub claim: String,
    pub holds: bool,
    pub measured: String,
}

/// Runs `train` over the paper-5 viaduct with `sets` (after the train and probe keys).
pub fn run_train(train: &str, sets: &[String], mut progress: impl FnMut(f64)) -> Result<TrainRun> {
    let mut all = vec![
        format!("train={train}"),
        format!("output.probes=[\"{CARRIAGE}\", \"{PIER}\"]"),
    ];
    all.extend_from_slice(sets);
    let case = crate::studies::design::load(SCENARIO, &all)?;
    let mut rows = Rows::new(case.probes.clone());
    let (Some(v), Some(soil)) = (&case.viaduct, &case.soil) else {
        return Err(Error::invalid(
            "report paper-5",
            "the case has no viaduct or no [soil]",
        ));
    };
    let f = &v.foundation;
    let mut base = BaseForces::new(v.spans + 1, f.stiffness[2], f.damping[2]);
    let mut safety = Safety::for_case(&case);
    let run = simulate(
        &case,
        &mut CoreMagnets::new(),
        &mut Tee(&mut Tee(&mut rows, &mut base), &mut safety),
        &mut progress,
    )?;
    let column = |name: &str| {
        rows.column(name)
            .ok_or_else(|| Error::numerical(format!("internal: no column {name}")))
    };
    Ok(TrainRun {
        train: train.to_string(),
        dt: case.dt,
        carriage: column(CARRIAGE)?,
        pier: column(PIER)?,
        steps: run.outcome.steps,
        collision_steps: run.outcome.collision_steps,
        contact_loss_steps: run.outcome.contact_loss_steps,
        unconverged_steps: run.outcome.unconverged_steps,
        wall: run.wall,
        base,
        soil: *soil,
        span: v.span_length,
        safety: safety.report(),
    })
}

/// The whole-record acceleration band levels of a run.
pub fn levels(run: &TrainRun) -> Result<TrainLevels> {
    let s = bands::Settings {
        input: Motion::Acceleration,
        level: Level::Acceleration,
        averaging: Averaging::WholeRecord,
    };
    let analyse = |v: &[f64], what: &str| {
        bands::analyse(v, run.dt, &s)
            .map_err(|e| Error::numerical(format!("{} {what}: {e}", run.train)))
    };
    Ok(TrainLevels {
        carriage: analyse(&run.carriage, CARRIAGE)?,
        pier: analyse(&run.pier, PIER)?,
    })
}

/// The band of the highest level.
pub fn top_band(levels: &[BandLevel]) -> Option<&BandLevel> {
    levels
        .iter()
        .filter_map(|l| l.level_db.map(|db| (l, db)))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(l, _)| l)
}

/// Bands in which `a` lies below `b`, out of the bands both have a level in.
fn bands_below(a: &[BandLevel], b: &[BandLevel]) -> (usize, usize) {
    let pairs: Vec<(f64, f64)> = a
        .iter()
        .filter_map(|x| {
            let y = b.iter().find(|y| y.band == x.band)?;
            Some((x.level_db?, y.level_db?))
        })
        .collect();
    let below = pairs.iter().filter(|(x, y)| x < y).count();
    (below, pairs.len())
}

/// The paper's statements about Fig. 8, evaluated.
pub fn statements(maglev: &TrainLevels, wheel_rail: &TrainLevels) -> Vec<Statement> {
    let top = |l: &[BandLevel]| top_band(l).map_or(f64::NAN, |b| b.band.nominal_hz());
    let mut out = Vec::new();
    let at = |l: &[BandLevel], hz: f64| {
        l.iter()
            .find(|b| b.band.nominal_hz() == hz)
            .and_then(|b| b.level_db)
            .unwrap_or(f64::NAN)
    };
    let peak_db = |l: &[BandLevel]| top_band(l).and_then(|b| b.level_db).unwrap_or(f64::NAN);
    for (point, lv) in [("carriage", &maglev.carriage), ("pier", &maglev.pier)] {
        let f = top(lv);
        out.push(Statement {
            claim: format!(
                "the maglev train's top band at the {point} is the 50 Hz band (its magnets pass every 1.5625 m: 83.33/1.5625 = 53.3 Hz)"
            ),
            holds: f == 50.0,
            measured: format!(
                "top band {f} Hz at {:.1} dB; the 50 Hz band {:.1} dB",
                peak_db(lv),
                at(lv, 50.0)
            ),
        });
    }
    let f = top(&wheel_rail.pier);
    let low: Vec<BandLevel> = wheel_rail
        .pier
        .iter()
        .copied()
        .filter(|b| b.band.nominal_hz() <= 10.0)
        .collect();
    out.push(Statement {
        claim: "the wheel/rail train's pier energy lies in the 2.5–4 Hz bands (25 m cars: 83.33/25 = 3.3 Hz)".into(),
        holds: [2.5, 3.15, 4.0].contains(&f),
        measured: format!(
            "top band {f} Hz at {:.1} dB; up to 10 Hz the top band is {} Hz at {:.1} dB",
            peak_db(&wheel_rail.pier),
            top(&low),
            peak_db(&low)
        ),
    });
    for (point, a, b) in [
        ("carriage", &maglev.carriage, &wheel_rail.carriage),
        ("pier", &maglev.pier, &wheel_rail.pier),
    ] {
        let (below, of) = bands_below(a, b);
        out.push(Statement {
            claim: format!(
                "maglev levels lie below wheel/rail levels in most bands at the {point}"
            ),
            holds: 2 * below > of,
            measured: format!("below in {below} of {of} bands"),
        });
    }
    out
}

/// Fig. 8: both trains' band levels at the carriage and at the pier, level against the
/// band's nominal frequency on a logarithmic axis, a marker at each band.
pub fn figure(maglev: &TrainLevels, wheel_rail: &TrainLevels) -> Result<String> {
    let series = |label: &str, l: &[BandLevel]| {
        let (x, y) = l
            .iter()
            .filter_map(|b| Some((b.band.nominal_hz(), b.level_db?)))
            .unzip();
        Series::new(label, x, y)
    };
    let cell = |title: &str, a: &[BandLevel], b: &[BandLevel]| {
        Plot::new(
            title,
            "band centre frequency (Hz, log scale)",
            "level (dB re 1e-6 m/s²)",
            vec![series("maglev", a), series("wheel/rail", b)],
        )
        .log_x()
        .markers()
    };
    plot::panels(
        "Fig. 8: 1/3-octave vertical acceleration levels at 83.33 m/s",
        2,
        &[
            cell(
                "4th carriage (car4.body.az)",
                &maglev.carriage,
                &wheel_rail.carriage,
            ),
            cell(
                "20th pier base (pier20.base.az)",
                &maglev.pier,
                &wheel_rail.pier,
            ),
        ],
    )
}

/// `train,point,centre_hz,level_db_re_1e-6_m_per_s2` (1/3-octave band levels of the whole
/// record) for both trains and both points, under a plain header.
pub fn bands_csv(maglev: &TrainLevels, wheel_rail: &TrainLevels) -> String {
    let mut s = String::from("train,point,centre_hz,level_db_re_1e-6_m_per_s2\n");
    for (train, lv) in [("maglev", maglev), ("wheel-rail", wheel_rail)] {
        for (point, l) in [(CARRIAGE, &lv.carriage), (PIER, &lv.pier)] {
            for b in l {
                let db = b.level_db.map_or(String::new(), |db| db.to_string());
                let _ = writeln!(s, "{train},{point},{},{db}", b.band.nominal_hz());
            }
        }
    }
    s
}

/// The report's Markdown.
pub fn markdown(
    runs: &[TrainRun],
    maglev: &TrainLevels,
    wheel_rail: &TrainLevels,
    sets: &[String],
) -> String {
    let peak = |v: &[f64]| v.iter().map(|x| x.abs()).fold(0.0, f64::max);
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# The paper's §5: maglev and wheel/rail trains on a viaduct\n"
    );
    let _ = writeln!(
        md,
        "Generated by `maglev report paper-5{}`. Scenario `paper-5` (docs/viaduct.md, docs/cars.md): 35 spans of 30 m on 10 m piers and Gazetas footings, 83.33 m/s, Δt = 2 ms, 5000 steps. Levels: IEC 61260-1 base-10 1/3-octave bands of the whole record (`maglev bands`), vertical acceleration, dB re 1e-6 m/s².\n",
        sets.iter().map(|s| format!(" --set {s}")).collect::<String>()
    );
    let _ = writeln!(md, "## Runs\n\n| train | steps | wall (s) | collision / lift-off steps | unconverged steps | peak {CARRIAGE} (m/s²) | peak {PIER} (m/s²) |\n|---|---|---|---|---|---|---|");
    for r in runs {
        let _ = writeln!(
            md,
            "| {} | {} | {:.1} | {} / {} | {} | {:.4e} | {:.4e} |",
            r.train,
            r.steps,
            r.wall,
            r.collision_steps,
            r.contact_loss_steps,
            r.unconverged_steps,
            peak(&r.carriage),
            peak(&r.pier)
        );
    }
    md.push_str(&safety_markdown(runs));
    let _ = writeln!(
        md,
        "\n## The paper's statements\n\n| statement | measured | verdict |\n|---|---|---|"
    );
    for s in statements(maglev, wheel_rail) {
        let _ = writeln!(
            md,
            "| {} | {} | {} |",
            s.claim,
            s.measured,
            if s.holds {
                "holds"
            } else {
                "**does not hold**"
            }
        );
    }
    let _ = writeln!(
        md,
        "\nWhere a statement does not hold, docs/paper5.md gives the reason the model finds.\n"
    );
    let _ = writeln!(md, "## Band levels (dB)\n\n| band (Hz) | maglev carriage | wheel/rail carriage | maglev pier | wheel/rail pier |\n|---|---|---|---|---|");
    let find = |l: &[BandLevel], b: &BandLevel| {
        l.iter()
            .find(|x| x.band == b.band)
            .and_then(|x| x.level_db)
            .map_or("–".to_string(), |db| format!("{db:.1}"))
    };
    for b in &maglev.carriage {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} |",
            b.band.nominal_hz(),
            find(&maglev.carriage, b),
            find(&wheel_rail.carriage, b),
            find(&maglev.pier, b),
            find(&wheel_rail.pier, b)
        );
    }
    let _ = writeln!(md, "\n![Fig. 8](fig8.svg)\n");
    md
}

/// The running-safety table of the runs (docs/safety.md): each judged figure with its limit
/// and verdict, "–" where the train has no such figure.
fn safety_markdown(runs: &[TrainRun]) -> String {
    let cell = |f: Option<&Figure>, scale: f64| match f {
        None => "–".to_string(),
        Some(f) => {
            let verdict = match f.pass {
                Some(true) => "pass".to_string(),
                Some(false) => "**fail**".to_string(),
                None => "no limit".to_string(),
            };
            let limit = f
                .limit
                .map_or(String::new(), |l| format!(" / {}", l * scale));
            let value = match f.unit {
                "steps" => format!("{}", f.value),
                _ => format!("{:.4}", f.value * scale),
            };
            format!("{value}{limit} ({verdict})")
        }
    };
    let mut md = String::from("\n## Running safety (docs/safety.md)\n\n| train | body peak (m/s²) | smallest levitation gap (mm) | collision steps | largest ΔP/P | lift-off steps | overall |\n|---|---|---|---|---|---|---|\n");
    for r in runs {
        let Some(s) = &r.safety else { continue };
        let (m, w) = (s.maglev.as_ref(), s.wheel_rail.as_ref());
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} |",
            r.train,
            cell(Some(&s.body_acceleration_peak), 1.0),
            cell(m.map(|m| &m.levitation_gap_min), 1e3),
            cell(m.map(|m| &m.collision_steps), 1.0),
            cell(w.map(|w| &w.unloading_max), 1.0),
            cell(w.map(|w| &w.lift_off_steps), 1.0),
            if s.pass { "pass" } else { "**fail**" }
        );
    }
    md.push_str("\nValues / limits; the limits' sources are in summary.json's `safety` and docs/safety.md. Q/P is not computed (no lateral wheel–rail force in the model).\n");
    md
}
