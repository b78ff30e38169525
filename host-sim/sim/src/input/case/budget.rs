//! Whole-case limits, checked after every key and before anything is allocated: the time
//! steps, the rail and response.csv a run records, the rail its irregularity is sampled on
//! and the law's sub-steps, each error naming the keys that make it large
//! (docs/scenarios.md, "Whole-case limits").

use super::controller::LawChoice;
use super::train::TrainCase;
use crate::{Error, Result};
use maglev_core::Params;

/// The most time steps a case may take (t_end / dt): 10⁷ steps is hours of wall time for a
/// vehicle passage; a larger count is a typo in dt or t_end far more often than intent.
pub const MAX_STEPS: f64 = 1e7;

/// The time steps of `t_end` at `dt`, at most [`MAX_STEPS`].
pub(super) fn steps(t_end: f64, dt: f64) -> Result<f64> {
    let steps = t_end / dt;
    // A run takes t_end / dt rounded steps: below one it would write a run of none.
    if steps.round() < 1.0 {
        return Err(Error::invalid(
            "run.t_end_s",
            format!("must be at least one step, run.dt_s = {dt:e} s, got {t_end:e}"),
        ));
    }
    if steps.is_nan() || steps > MAX_STEPS {
        return Err(Error::invalid(
            "run.t_end_s",
            format!(
                "t_end / run.dt_s = {steps:.3e} steps exceeds the limit of {MAX_STEPS:.0e} steps"
            ),
        ));
    }
    Ok(steps)
}

/// The most memory a case may ask of its run's per-step records (bytes): 4 GiB, a quarter of a
/// 16 GiB workstation; every bundled case needs under 0.1 GiB.
pub const MAX_RECORD_BYTES: f64 = 4.0 * 1024.0 * 1024.0 * 1024.0;

/// The most magnet law sub-steps a run may take (steps × magnets × sub-steps per update):
/// at about 30 ns a sub-step, 10¹¹ is close to an hour; the paper's n_sub = 1000 passage at
/// 10 m/s needs 5·10⁷.
pub const MAX_SUB_STEPS: f64 = 1e11;

/// The most rail a run may sample its irregularity on (m): 500 km, 10⁸ points of
/// [`crate::physics::profile::GRID`] in each of two tables (1.6 GB) and about 10 s of synthesis; the
/// paper-5 train at 150 m/s passes about 3 km. The extent is what the wheels pass: the train's
/// length plus speed × t_end (a speed of 9e8 m/s asked for 3.6e6 km and ran out of memory).
pub const MAX_PROFILE_M: f64 = 5e5;

/// What a run will record and compute per step, known before anything is allocated.
pub(super) struct Budget<'a> {
    /// Time steps, the t = 0 row included.
    pub steps: f64,
    pub train: &'a TrainCase,
    /// Law sub-steps per magnet update (0 without magnets).
    pub sub_steps: f64,
    /// Columns `output.probes` asks for (0: the default seven).
    pub columns: usize,
    /// Rail the irregularity is sampled on (m): speed × t_end and the train's length; 0
    /// without irregularity.
    pub profile: (f64, f64),
}

/// The train's size key, its wheels and contacts (rail points recorded per step), and its
/// magnets.
fn train_size(t: &TrainCase) -> (&'static str, f64, f64) {
    match t {
        TrainCase::Fig1 { cars, .. } => ("train.repeat", 4.0 * *cars as f64, 12.0 * *cars as f64),
        TrainCase::Maglev { nodes, .. } => ("train.cars", *nodes as f64, 3.0 * *nodes as f64),
        TrainCase::WheelRail { nodes, .. } => ("train.cars", *nodes as f64, 0.0),
        TrainCase::HighSpeed { wheels, .. } => ("train.cars", *wheels as f64, 0.0),
        TrainCase::Unit(_) => ("vehicle.kind", 1.0, 1.0),
        TrainCase::Forces(_) => ("train.loads_kN", 0.0, 0.0),
    }
}

/// Sub-steps of one magnet update: the law's control periods per step
/// (`maglev_core::LawKind::sub_steps`).
pub(super) fn sub_steps(p: &Params, law: &LawChoice, dt: f64) -> f64 {
    law.kind().sub_steps(p, dt) as f64
}

/// Refuses a case whose per-step records or law work exceed the limits, naming the keys that
/// make them large: the rail under every wheel and contact (24 bytes a point a step, the
/// profile the run writes), response.csv's rows (read back whole for the summary, about 24
/// bytes a cell), and the magnets' law sub-steps.
pub(super) fn check_budget(b: &Budget) -> Result<()> {
    let (size_key, points, magnets) = train_size(b.train);
    let gib = |x: f64| x / (1024.0 * 1024.0 * 1024.0);
    let rail = b.steps * points * 24.0;
    if rail > MAX_RECORD_BYTES {
        return Err(Error::invalid(
            format!("{size_key} (with run.t_end_s)"),
            format!(
                "the run would record the rail under {points} wheels and contacts for {} steps: \
                 {:.1} GiB, above the limit of {:.0} GiB",
                b.steps,
                gib(rail),
                gib(MAX_RECORD_BYTES)
            ),
        ));
    }
    let rows = b.steps * (b.columns.max(7) + 3) as f64 * 24.0;
    if rows > MAX_RECORD_BYTES {
        return Err(Error::invalid(
            "output.probes (with run.t_end_s)",
            format!(
                "{} columns for {} steps make a response.csv of about {:.1} GiB, above the \
                 limit of {:.0} GiB",
                b.columns,
                b.steps,
                gib(rows),
                gib(MAX_RECORD_BYTES)
            ),
        ));
    }
    let (travel, length) = b.profile;
    let rail = travel + length;
    if rail.is_nan() || rail > MAX_PROFILE_M {
        let key = match b.train {
            _ if travel >= length => "run.speed_m_per_s (with run.t_end_s)",
            TrainCase::Fig1 { .. } => "vehicle.half_length_m (with car_length_m and repeat)",
            TrainCase::Forces(_) => "train.offsets_m",
            _ => size_key,
        };
        return Err(Error::invalid(
            key,
            format!(
                "the irregularity would be sampled on {rail:.3e} m of rail (speed × t_end \
                 {travel:.3e} m, train {length:.3e} m), above the limit of {MAX_PROFILE_M:.0e} m"
            ),
        ));
    }
    let work = b.steps * magnets * b.sub_steps;
    if work > MAX_SUB_STEPS {
        return Err(Error::invalid(
            "controller.nsub (or controller.state.rate_Hz; with run.t_end_s and the train's size)",
            format!(
                "{} steps × {magnets} magnets × {} sub-steps = {work:.1e} law sub-steps, above \
                 the limit of {MAX_SUB_STEPS:.0e} (about an hour)",
                b.steps, b.sub_steps
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::Case;

    /// Every bad value is refused with the key that holds it; nothing is allocated first.
    #[test]
    fn oversized_runs_are_refused_before_they_allocate() {
        let refused = |sets: &[&str], key: &str| {
            let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
            match Case::load("paper-4.2", &sets) {
                Ok(_) => panic!("accepted: {}", sets[0].len().min(80)),
                Err(e) => assert!(e.to_string().contains(key), "{e}"),
            }
        };
        // 1000 cars 15 m apart: 4000 wheels for 150 k steps, 14.4 GB of rail record.
        refused(
            &[
                "vehicle.repeat=1000",
                "vehicle.car_length_m=15",
                "speed=100",
            ],
            "train.repeat",
        );
        // 4·10⁹ sub-steps a magnet update.
        refused(&["nsub=4000000000"], "controller.nsub");
        // 2·10⁴ columns for 10⁴ steps: 4.8 GB of response.csv.
        let probes: Vec<String> = (0..20_000).map(|_| "\"wheel1.z\"".to_string()).collect();
        refused(
            &[&format!("output.probes=[{}]", probes.join(",")), "t_end=10"],
            "output.probes",
        );
        for (scenario, sets) in [("paper-4.2", vec!["model=modal"]), ("paper-5", vec![])] {
            let mut sets: Vec<String> = sets.into_iter().map(String::from).collect();
            sets.push("bridge.damping={ratio=0.02, f1_Hz=5.0, f2_Hz=20.0}".into());
            match Case::load(scenario, &sets) {
                Ok(_) => panic!("{scenario}: damping accepted where no model takes it"),
                Err(e) => assert!(e.to_string().starts_with("bridge.damping"), "{e}"),
            }
        }
        match Case::load("paper-5", &["bridge.pier.elements=1000".into()]) {
            Ok(_) => panic!("1000 pier elements accepted"),
            Err(e) => assert!(e.to_string().contains("bridge.pier.elements"), "{e}"),
        }
        // The bundled cases are far inside every limit.
        for (name, _) in crate::input::scenario::BUNDLED {
            Case::load(name, &[]).unwrap();
        }
    }
}
