//! The ground section of `maglev report paper-5` (issue #27 point 5, docs/ground.md "The
//! paper-5 report"): each train's pier-base forces carried to receivers on the ground
//! ([`crate::ground::receivers`]), their levels and verdicts ([`crate::ground::levels`],
//! [`crate::ground::criteria`]), a figure of level against distance and a plan-view map of
//! peak surface velocity around piers 18–22 (the paper's Fig. 9 in this model's terms).
//!
//! Why a module of its own: [`crate::studies::paper5`] holds Fig. 8 (the carriage and the pier); the
//! ground is a second chain on the same runs, and every sentence of its section is evaluated
//! from the numbers here, never written in by hand.

use crate::bands::Band;
use crate::ground::criteria::{self, FTA_GENERAL_VDB};
use crate::ground::levels::{self, vdb, ReceiverLevels};
use crate::ground::receivers;
use crate::ground::table::Tables;
use crate::plot::{self, map, Plot, Series};
use crate::studies::paper5::TrainRun;
use crate::{Error, Result};
use std::fmt::Write as _;

/// Distances of the receivers from the viaduct's axis (m), across the line at [`PIER`].
pub const DISTANCES: [f64; 4] = [12.5, 25.0, 50.0, 100.0];
/// The pier (from 1) the receivers stand beside.
pub const PIER: usize = 20;
/// The map: piers 18 to 22, receivers every [`MAP_STEP`] m, from [`MAP_Y0`] to [`MAP_Y1`] m
/// off the axis (outside the footings' 7.5 m circumscribed circle; the half-space and the
/// vertical forces on the axis make the map symmetric in y, so one side is computed and
/// mirrored).
pub const MAP_PIERS: (usize, usize) = (18, 22);
pub const MAP_STEP: f64 = 5.0;
pub const MAP_Y0: f64 = 10.0;
pub const MAP_Y1: f64 = 60.0;

/// One train's ground results.
pub struct TrainGround {
    pub train: String,
    /// Levels at [`DISTANCES`].
    pub levels: Vec<ReceiverLevels>,
    /// Peak |vz| (m/s) on the map grid, `[j][i]` at (`map_x[i]`, `map_y[j]`), one side.
    pub map_x: Vec<f64>,
    pub map_y: Vec<f64>,
    pub peak: Vec<Vec<f64>>,
}

/// The receivers' velocities, levels and map of each run (the same soil and viaduct: one
/// table of the Green's function serves all, [`receivers::of_runs`]), the receivers shared
/// among `threads` threads (the same bits for every count).
pub fn analyse(runs: &[TrainRun], threads: usize) -> Result<Vec<TrainGround>> {
    let Some(first) = runs.first() else {
        return Ok(Vec::new());
    };
    let points = receivers_of(first.span);
    let bases: Vec<_> = runs.iter().map(|r| &r.base).collect();
    let mut tables = Tables::new();
    let v = receivers::of_runs(
        &mut tables,
        &first.soil,
        first.span,
        &bases,
        &points.0,
        threads,
    )?;
    runs.iter()
        .zip(v)
        .map(|(r, v)| train_ground(r, &points, v))
        .collect()
}

/// The receivers: [`DISTANCES`] beside [`PIER`], then the map grid row by row; with the
/// grid's x and y.
fn receivers_of(span: f64) -> (Vec<[f64; 2]>, Vec<f64>, Vec<f64>) {
    let x20 = (PIER - 1) as f64 * span;
    let mut points: Vec<[f64; 2]> = DISTANCES.iter().map(|&d| [x20, d]).collect();
    let (p0, p1) = MAP_PIERS;
    let (xa, xb) = ((p0 - 1) as f64 * span, (p1 - 1) as f64 * span);
    let nx = ((xb - xa) / MAP_STEP).round() as usize + 1;
    let ny = ((MAP_Y1 - MAP_Y0) / MAP_STEP).round() as usize + 1;
    let map_x: Vec<f64> = (0..nx).map(|i| xa + i as f64 * MAP_STEP).collect();
    let map_y: Vec<f64> = (0..ny).map(|j| MAP_Y0 + j as f64 * MAP_STEP).collect();
    for &y in &map_y {
        points.extend(map_x.iter().map(|&x| [x, y]));
    }
    (points, map_x, map_y)
}

/// One run's levels and map from its receivers' velocities `v` (in [`receivers_of`]'s order).
fn train_ground(
    run: &TrainRun,
    (_, map_x, map_y): &(Vec<[f64; 2]>, Vec<f64>, Vec<f64>),
    v: Vec<Vec<f64>>,
) -> Result<TrainGround> {
    let nx = map_x.len();
    let levels = v[..DISTANCES.len()]
        .iter()
        .map(|v| levels::of_velocity(v, run.dt))
        .collect::<std::result::Result<Vec<_>, _>>()
        .map_err(|e| Error::numerical(format!("{} ground levels: {e}", run.train)))?;
    let peak_of = |v: &Vec<f64>| v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let peaks: Vec<f64> = v[DISTANCES.len()..].iter().map(peak_of).collect();
    let peak = peaks.chunks(nx).map(<[f64]>::to_vec).collect();
    Ok(TrainGround {
        train: run.train.clone(),
        levels,
        map_x: map_x.clone(),
        map_y: map_y.clone(),
        peak,
    })
}

/// The overall maximum 1-s level (VdB) of a receiver.
fn overall_vdb(l: &ReceiverLevels) -> f64 {
    l.overall_max_running_db.map_or(f64::NAN, vdb)
}

/// A band's maximum 1-s level (VdB), NaN where there is none.
fn band_vdb(l: &ReceiverLevels, band: Band) -> f64 {
    l.bands
        .iter()
        .find(|b| b.band == band)
        .and_then(|b| b.max_running_db)
        .map_or(f64::NAN, vdb)
}

/// The band of the highest maximum 1-s level.
fn top_band(l: &ReceiverLevels) -> Option<Band> {
    l.bands
        .iter()
        .filter_map(|b| Some((b.band, b.max_running_db?)))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(b, _)| b)
}

/// The figure: overall maximum 1-s level against distance for both trains, with the FTA
/// category 2 (residences) criteria for frequent and infrequent events.
pub fn figure(trains: &[TrainGround]) -> Result<String> {
    let mut series: Vec<Series> = trains
        .iter()
        .map(|g| {
            let y = g.levels.iter().map(overall_vdb).collect();
            Series::new(g.train.clone(), DISTANCES.to_vec(), y)
        })
        .collect();
    let ends = vec![DISTANCES[0], DISTANCES[DISTANCES.len() - 1]];
    for (events, col) in [("frequent", 0), ("infrequent", 2)] {
        let c = FTA_GENERAL_VDB[1][col];
        series.push(Series::new(
            format!("FTA category 2, {events} ({c} VdB)"),
            ends.clone(),
            vec![c, c],
        ));
    }
    plot::svg(
        &Plot::new(
            format!("Ground surface, beside pier {PIER}: overall maximum 1-s rms vertical velocity level"),
            "distance from the viaduct axis (m, log scale)",
            "level (VdB re 1 µin/s)",
            series,
        )
        .log_x()
        .markers(),
    )
}

/// The map of one train: peak |vz| in dB re 1e-9 m/s, mirrored to both sides of the axis.
pub fn map_svg(g: &TrainGround, span: f64) -> Result<String> {
    let mut y: Vec<f64> = g.map_y.iter().rev().map(|y| -y).collect();
    y.extend(&g.map_y);
    let db = |v: f64| levels::db_re_1e9(v).unwrap_or(f64::NAN);
    let mut z: Vec<Vec<f64>> = g
        .peak
        .iter()
        .rev()
        .map(|row| row.iter().map(|&v| db(v)).collect())
        .collect();
    z.extend(
        g.peak
            .iter()
            .map(|row| row.iter().map(|&v| db(v)).collect::<Vec<f64>>()),
    );
    let (p0, p1) = MAP_PIERS;
    let marks: Vec<(f64, f64)> = (p0..=p1).map(|k| ((k - 1) as f64 * span, 0.0)).collect();
    map::svg(
        &format!(
            "{}: peak vertical surface velocity around piers {p0}–{p1} (|y| ≥ {MAP_Y0} m; black: piers)",
            g.train
        ),
        "x along the line from pier 1 (m)",
        "y across the line (m)",
        "dB re 1e-9 m/s",
        &map::Grid {
            x: &g.map_x,
            y: &y,
            z: &z,
        },
        &marks,
    )
}

/// The report's ground section (Markdown).
pub fn markdown(trains: &[TrainGround]) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "## Ground-borne vibration beside pier {PIER}\n\nEach pier's vertical base force carried to the ground surface by the half-space Green's function of the scenario's `[soil]` (docs/ground.md). Levels: vertical velocity, overall (all frequencies) maximum 1-s running rms in VdB re 1 µin/s (= dB re 1e-9 m/s − 28.10); PPV: peak |vz|; dominant band: the 1/3-octave band of the highest whole-record level. Ground-surface values: no building, no coupling loss.\n"
    );
    let _ = writeln!(
        md,
        "| distance (m) | train | overall max 1-s (VdB) | dB re 1e-9 m/s | PPV (mm/s) | dominant band (Hz) | top max 1-s band (Hz, VdB) |\n|---|---|---|---|---|---|---|"
    );
    for (k, d) in DISTANCES.iter().enumerate() {
        for g in trains {
            let l = &g.levels[k];
            let top = top_band(l);
            let _ = writeln!(
                md,
                "| {d} | {} | {:.1} | {:.1} | {:.4} | {} | {} |",
                g.train,
                overall_vdb(l),
                l.overall_max_running_db.unwrap_or(f64::NAN),
                l.ppv * 1e3,
                l.dominant_hz
                    .map_or("–".into(), |f| format!("{}", nominal(f))),
                top.map_or("–".into(), |b| format!(
                    "{} ({:.1})",
                    b.nominal_hz(),
                    band_vdb(l, b)
                )),
            );
        }
    }
    let _ = writeln!(md, "\n![level against distance](ground-levels.svg)\n");
    md.push_str(&verdicts(trains));
    md.push_str(&comparison(trains));
    for g in trains {
        let _ = writeln!(md, "![{} map](ground-map-{}.svg)\n", g.train, g.train);
    }
    md
}

/// The nominal frequency of the band whose exact mid-band frequency is `f`.
fn nominal(f: f64) -> f64 {
    Band {
        index: (10.0 * (f / 1000.0).log10()).round() as i32,
    }
    .nominal_hz()
}

/// The verdict table: FTA Table 6-3 by land-use category and event frequency, DIN 4150-3
/// by building type.
fn verdicts(trains: &[TrainGround]) -> String {
    let mut md = String::from(
        "### Verdicts\n\nFTA (Report 0123, 2018, Table 6-3, general assessment): the overall maximum 1-s level against the criterion of land-use category 1 / 2 / 3 for frequent (F), occasional (O) and infrequent (I) events; DIN 4150-3 (Table 1, foundation, short-term): the PPV against the guideline value of building type 1 / 2 / 3 at the dominant band's frequency. \"impact\"/\"exceeded\" where above, \"–\" where not (docs/ground.md, \"Verdicts\").\n\n| distance (m) | train | VdB | cat. 1 F/O/I (65/65/65) | cat. 2 F/O/I (72/75/80) | cat. 3 F/O/I (75/78/83) | DIN type 1 / 2 / 3 (mm/s) |\n|---|---|---|---|---|---|---|\n",
    );
    for (k, d) in DISTANCES.iter().enumerate() {
        for g in trains {
            let l = &g.levels[k];
            let v = overall_vdb(l);
            let fta = criteria::fta(v);
            let cells: Vec<String> = fta
                .iter()
                .map(|row| {
                    row.iter()
                        .map(|x| if x.exceeds { "impact" } else { "–" })
                        .collect::<Vec<_>>()
                        .join(" / ")
                })
                .collect();
            let din = l.dominant_hz.map_or("–".to_string(), |f| {
                criteria::din(l.ppv, f)
                    .iter()
                    .map(|x| {
                        format!(
                            "{:.1}{}",
                            x.criterion * 1e3,
                            if x.exceeds { " exceeded" } else { "" }
                        )
                    })
                    .collect::<Vec<_>>()
                    .join(" / ")
            });
            let _ = writeln!(
                md,
                "| {d} | {} | {v:.1} | {} | {} | {} | {din} |",
                g.train, cells[0], cells[1], cells[2]
            );
        }
    }
    md.push('\n');
    md
}

/// What the comparison at 25 m says, from the numbers: which train is higher overall, and
/// where the maglev is not below, the bands that make the difference.
pub fn comparison(trains: &[TrainGround]) -> String {
    let (Some(m), Some(w)) = (
        trains.iter().find(|g| g.train == "maglev"),
        trains.iter().find(|g| g.train == "wheel-rail"),
    ) else {
        return String::new();
    };
    let k = DISTANCES.iter().position(|&d| d == 25.0).unwrap_or(1);
    let (lm, lw) = (&m.levels[k], &w.levels[k]);
    let (vm, vw) = (overall_vdb(lm), overall_vdb(lw));
    let mut md = String::from("### What the comparison says\n\n");
    let below_at: Vec<String> = DISTANCES
        .iter()
        .enumerate()
        .map(|(i, d)| {
            format!(
                "{d} m: {:+.1} dB",
                overall_vdb(&m.levels[i]) - overall_vdb(&w.levels[i])
            )
        })
        .collect();
    let _ = writeln!(
        md,
        "Maglev minus wheel/rail, overall maximum 1-s level: {}.",
        below_at.join(", ")
    );
    if vm < vw {
        let pairs: Vec<(f64, f64)> = lm
            .bands
            .iter()
            .map(|b| (band_vdb(lm, b.band), band_vdb(lw, b.band)))
            .filter(|(a, c)| a.is_finite() && c.is_finite())
            .collect();
        let below = pairs.iter().filter(|(a, c)| a < c).count();
        let _ = writeln!(
            md,
            "At 25 m the maglev train is below the wheel/rail train: {vm:.1} against {vw:.1} VdB, and below it in {below} of {} 1/3-octave bands (maximum 1-s levels).\n",
            pairs.len()
        );
        return md;
    }
    // The bands where the maglev is above, largest excess first.
    let mut above: Vec<(Band, f64, f64)> = lm
        .bands
        .iter()
        .filter_map(|b| {
            let (a, c) = (band_vdb(lm, b.band), band_vdb(lw, b.band));
            (a.is_finite() && c.is_finite() && a > c).then_some((b.band, a, c))
        })
        .collect();
    above.sort_by(|x, y| y.1.total_cmp(&x.1));
    let list: Vec<String> = above
        .iter()
        .take(3)
        .map(|(b, a, c)| format!("{} Hz ({a:.1} against {c:.1} VdB)", b.nominal_hz()))
        .collect();
    let _ = writeln!(
        md,
        "At 25 m the maglev train is **not below** the wheel/rail train: {vm:.1} against {vw:.1} VdB. Its strongest bands there lie above the wheel/rail train's: {}. The maglev's top band is {} Hz, the wheel/rail train's {} Hz; docs/ground.md (\"The paper-5 report\") explains where those bands come from.\n",
        if list.is_empty() { "none".to_string() } else { list.join(", ") },
        top_band(lm).map_or(f64::NAN, |b| b.nominal_hz()),
        top_band(lw).map_or(f64::NAN, |b| b.nominal_hz()),
    );
    md
}

/// `train,distance_m,centre_hz,max_1s_vdb,record_vdb` for the receivers at [`DISTANCES`]
/// (vertical velocity levels beside pier 20, VdB re 2.54e-8 m/s; max_1s = maximum 1-s running
/// rms, record = whole record), one row per band, under a plain header; the overall levels are
/// [`overall_csv`]'s.
pub fn csv(trains: &[TrainGround]) -> String {
    let mut s = String::from("train,distance_m,centre_hz,max_1s_vdb,record_vdb\n");
    for g in trains {
        for (d, l) in DISTANCES.iter().zip(&g.levels) {
            for b in &l.bands {
                let _ = writeln!(
                    s,
                    "{},{d},{},{},{}",
                    g.train,
                    b.band.nominal_hz(),
                    level_cell(b.max_running_db),
                    level_cell(b.record_db)
                );
            }
        }
    }
    s
}

/// `train,distance_m,max_1s_vdb,record_vdb`: the overall levels (all frequencies) of the
/// receivers at [`DISTANCES`], as [`csv`] writes the bands'.
pub fn overall_csv(trains: &[TrainGround]) -> String {
    let mut s = String::from("train,distance_m,max_1s_vdb,record_vdb\n");
    for g in trains {
        for (d, l) in DISTANCES.iter().zip(&g.levels) {
            let _ = writeln!(
                s,
                "{},{d},{},{}",
                g.train,
                level_cell(l.overall_max_running_db),
                level_cell(l.overall_record_db)
            );
        }
    }
    s
}

/// A level in VdB to 0.01 dB, empty where there is none.
fn level_cell(db: Option<f64>) -> String {
    db.map_or(String::new(), |d| format!("{:.2}", vdb(d)))
}
