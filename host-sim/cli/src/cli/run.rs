//! `maglev run SCENARIO [--set key=value]... [--out DIR] [--strict]`: one passage over an FE,
//! modal or rigid guideway.

use crate::cli::progress::Progress;
use crate::ground::receivers::{self, BaseForces};
use crate::ground::{criteria, levels};
use crate::input::case::Case;
use crate::output::safety::Safety;
use crate::output::{
    fill_response_columns, gap_ranges, response_recorder, write_run, Columns, Staging, Summary,
};
use crate::probes::Tee;
use crate::setup::simulate;
use crate::simulation::magnets::CoreMagnets;
use crate::simulation::Outcome;
use crate::Error;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// A scenario TOML file, or a bundled name (paper-4.2, paper-5, paper-5-quake,
    /// paper-5-settled, paper-5-hsr, train-forces, moving-force, unit). Every section and key, with its
    /// unit, default and accepted range: docs/scenarios.md.
    pub scenario: String,
    /// Override a scenario value: train, speed, model, elements, modes, dt, t_end, nsub, alpha,
    /// law, scheme, seed, geometry, or section.key (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// Output directory.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Exit with status 3 when any step collides or any magnet's gap leaves (0, 2·h0).
    #[arg(long)]
    pub strict: bool,
}

/// What `--strict` refuses: a collision, or a gap outside `(0, 2·h0)`. `None` when the run
/// is within bounds (a moving force has no gaps and always is).
pub fn strict_violation(outcome: &Outcome, h0: f64) -> Option<String> {
    if outcome.collision_steps > 0 {
        return Some(format!(
            "{} step(s) with a collision (a magnet on its skid, docs/contact.md)",
            outcome.collision_steps
        ));
    }
    gap_ranges(&outcome.gap_ranges, &outcome.guided)
        .into_iter()
        .find(|g| !(g.min_m > 0.0 && g.max_m < 2.0 * h0))
        .map(|g| {
            format!(
                "gap {} ranged over [{:.3}, {:.3}] mm, outside (0, 2·h0) = (0, {:.3}) mm",
                g.magnet,
                g.min_m * 1e3,
                g.max_m * 1e3,
                2e3 * h0
            )
        })
}

/// A run with steps whose coupling iteration hit `run.max_iterations` without converging
/// fails its check ([`Error::CheckFailed`], exit 1): it ran to its end and its outputs are
/// written, but those steps are not within `run.tolerance_m`, so the result is not the one
/// asked for (not a bad input: the same case may converge at a smaller `run.dt_s`).
pub fn check_converged(outcome: &Outcome) -> crate::Result<()> {
    match outcome.unconverged_steps {
        0 => Ok(()),
        n => Err(Error::CheckFailed(format!(
            "{n} step(s) hit run.max_iterations without converging to run.tolerance_m; the outputs are written, but those steps are not within the tolerance"
        ))),
    }
}

/// Warns on stderr about lifted wheels and collisions.
pub fn warn(outcome: &Outcome) {
    if outcome.contact_loss_steps > 0 {
        eprintln!(
            "maglev: warning: {} step(s) in which some wheel lifted off the rail (its contact force held at zero)",
            outcome.contact_loss_steps
        );
    }
    if outcome.collision_steps > 0 {
        eprintln!(
            "maglev: warning: {} step(s) with a collision (some magnet on its skid: levitation failed), the first at t = {} s; the magnets landed on their skids and slid (docs/contact.md)",
            outcome.collision_steps,
            outcome.first_collision_t.unwrap_or(f64::NAN)
        );
    }
}

/// ground.csv and ground-levels.csv of the case's receivers from the recorded base forces,
/// the `ground{N}.vz` probe columns filled into response.csv, and summary.json's `ground`
/// section, returned (docs/ground.md).
pub fn write_ground(
    out: &Staging,
    case: &Case,
    b: &BaseForces,
) -> crate::Result<Option<serde_json::Value>> {
    let (Some(v), Some(soil), Some(g)) = (&case.viaduct, &case.soil, &case.ground) else {
        return Ok(None);
    };
    let (start, cpu) = (std::time::Instant::now(), process_cpu_seconds());
    let vel = receivers::of_run(soil, v.span_length, b, g)?;
    eprintln!(
        "maglev: ground: {} receiver(s) from {} piers in {:.2} s wall, {:.2} s CPU",
        g.len(),
        b.forces.len(),
        start.elapsed().as_secs_f64(),
        process_cpu_seconds() - cpu
    );
    out.put("ground.csv", &receivers::csv(&b.t, &vel))?;
    let fills: Vec<(usize, &[f64])> = case
        .probes
        .ground_columns()
        .into_iter()
        .map(|(k, r)| (k, vel[r].as_slice()))
        .collect();
    fill_response_columns(out, &fills)?;
    // The records' spacing, as the receivers used it (`of_run` checked n ≥ 2).
    let dt = (b.t[b.t.len() - 1] - b.t[0]) / (b.t.len() - 1) as f64;
    let levels = vel
        .iter()
        .map(|v| levels::of_velocity(v, dt))
        .collect::<std::result::Result<Vec<_>, _>>()
        .map_err(|e| Error::numerical(format!("ground levels: {e}")))?;
    let names: Vec<String> = (1..=g.len()).map(|i| format!("ground{i}.vz")).collect();
    out.put("ground-levels.csv", &levels::csv(&names, &levels))?;
    Ok(Some(criteria::summary(&names, g, &levels)))
}

/// CPU seconds used by the whole process so far (all threads), for the ground step's report
/// on a shared machine (docs/ground.md, "Cost").
fn process_cpu_seconds() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; the clock id is a constant of the platform.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
    if rc == 0 {
        ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
    } else {
        f64::NAN
    }
}

/// Runs the command. Once the outputs are written: [`Error::Strict`] when `--strict` and the
/// run collided or left its gap bounds (exit 3), else [`check_converged`].
pub fn run(args: Args) -> anyhow::Result<()> {
    let case = crate::studies::design::load(&args.scenario, &args.sets)?;
    let out = Staging::new(&args.out)?;
    let mut rec = response_recorder(&out, case.probes.clone())?;
    let mut safety = Safety::for_case(&case);
    let mut bar = Progress::run("run");
    let mut base = BaseForces::for_case(&case);
    let mut with_safety = Tee(&mut rec, &mut safety);
    let run = match &mut base {
        Some(b) => simulate(
            &case,
            &mut CoreMagnets::new(),
            &mut Tee(&mut with_safety, b),
            &mut |f| bar.fraction(f),
        )?,
        None => simulate(&case, &mut CoreMagnets::new(), &mut with_safety, &mut |f| {
            bar.fraction(f)
        })?,
    };
    drop(bar);
    rec.finish()?;
    let ground = match &base {
        Some(b) => write_ground(&out, &case, b)?,
        None => None,
    };
    let (outcome, wall) = (run.outcome, run.wall);
    warn(&outcome);
    let columns = Columns::read(&out)?;
    let mut summary = Summary::new(&args.scenario, &case, &outcome, wall, &columns);
    summary.ground = ground;
    let skids =
        maglev_sim::safety::skid::figures(&outcome.skids, case.dt, &safety.magnet_wheel_names());
    summary.safety = match &outcome.rail {
        // The 3-D high-speed cars keep their own record (docs/cars.md, "The 3-D car in a run").
        Some(r) => Some(maglev_sim::Safety::of_rail_cars(r)),
        None => safety.report().map(|r| r.with_skids(skids)),
    };
    write_run(&out, &outcome, &summary, &args.sets, &columns)?;
    out.finish()?;
    eprintln!(
        "maglev: {} steps, {:.3} s simulated in {:.2} s wall; wrote {}",
        summary.steps,
        summary.simulated_seconds,
        wall,
        args.out.display()
    );
    if args.strict {
        if let Some(v) = strict_violation(&outcome, case.h0()) {
            return Err(Error::Strict(v).into());
        }
    }
    Ok(check_converged(&outcome)?)
}

#[cfg(test)]
mod tests {
    use super::Args;
    use crate::input::scenario::BUNDLED;
    use clap::Args as _;

    /// `maglev run --help` names every bundled scenario (the list is written by hand in the
    /// argument's doc comment, so a new scenario must be added there too).
    #[test]
    fn the_help_names_every_bundled_scenario() {
        let cmd = Args::augment_args(clap::Command::new("run"));
        let help = cmd
            .get_arguments()
            .find(|a| a.get_id() == "scenario")
            .and_then(|a| a.get_help())
            .map(|h| h.to_string())
            .unwrap_or_default();
        let words: Vec<&str> = help
            .split(|c: char| c.is_whitespace() || ",()".contains(c))
            .collect();
        for (name, _) in BUNDLED {
            assert!(words.contains(&name), "`{name}` missing from: {help}");
        }
    }
}
