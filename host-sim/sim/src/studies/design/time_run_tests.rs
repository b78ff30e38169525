//! A designed guided vehicle's slowest closed-loop pole against a nonlinear time run
//! (issue 39: the measured decay within 5 % of the predicted real part).
//!
//! The gains are designed on the scenario as written (its rough rail at its speed in the
//! headroom); the time run then flies them on a rigid, smooth rail at 10 m/s (time-invariant:
//! the linear model's poles describe it), disturbed by a 0.1 mm step in both rail profiles at
//! x = 0.5 m. Long after every magnet has crossed it and the faster modes have died out, the
//! response is the slowest pole's mode alone, and the peaks of wheel 1's lateral motion per step (the lateral
//! motion: the slowest pole is the car's sway–roll mode) decay at its real part. The rate is
//! the least-squares slope of the log of those peaks, which for one damped oscillation is
//! its real part exactly (successive extrema are `π/ω` apart and in the ratio `e^{σπ/ω}`).
//!
//! Over a span the car stands still on the FE span (the case's `fe` model, Rayleigh damping
//! of 2 % at its first and third bending modes) and is kicked instead: a lateral and a
//! vertical force on wheel 1's magnet for the first 50 ms (the rail is smooth and the car
//! does not move, so a rail step would never reach it). The prediction is then the coupled
//! analysis' (`coupled`: the girder's bending and torsion modes under every magnet), whose
//! slowest pole the run must follow as on the rigid rail.

use crate::input::case::Case;
use crate::simulation::magnets::CoreMagnets;
use crate::simulation::{simulate, Magnets, Profiles, Start, WheelGaps};
use crate::studies::stability::report::scenario_report;
use crate::studies::stability::Complex;
use crate::Result;
use maglev_core::Status;

/// The Fig. 1 car of paper-4.2 on 2000 kg EMS magnets, both laws designed.
const DESIGNED_2000_KG: [&str; 5] = [
    "geometry=ems",
    "law=state",
    "vehicle.wheel_mass_kg=2000",
    "controller.state={design=true, vmax_V=500.0}",
    "controller.guidance={design=true}",
];

fn strings(s: &[&str]) -> Vec<String> {
    s.iter().map(|s| s.to_string()).collect()
}

/// `scenario` with `sets`, its laws designed, then with `run` added (the run's guideway),
/// keeping the designed gains.
fn designed_with(scenario: &str, sets: &[&str], run: &[&str]) -> Case {
    designed_onto(scenario, sets, scenario, run)
}

/// The laws `design` with `sets` designs, flown on `onto` with `sets` and `run`.
fn designed_onto(design: &str, sets: &[&str], onto: &str, run: &[&str]) -> Case {
    let designed = crate::studies::design::load(design, &strings(sets)).unwrap();
    let mut all = strings(sets);
    all.extend(strings(run));
    let mut case = Case::load(onto, &all).unwrap();
    case.law = designed.law;
    case.guidance = designed.guidance;
    case
}

/// The rigid smooth rail of the module docs (10 m/s, Δt = 0.2 ms, `t_end`).
fn rigid_designed(scenario: &str, sets: &[&str], t_end: f64) -> Case {
    let t_end = format!("t_end={t_end}");
    let run = [
        "model=rigid",
        "speed=10",
        "irregularity.enabled=false",
        "dt=2e-4",
        &t_end,
    ];
    designed_with(scenario, sets, &run)
}

/// The core's magnets with a force kick (N, vertical and lateral) until `until`, on wheel 1
/// or (`every`) on every wheel.
struct Kicked {
    inner: CoreMagnets,
    kick: (f64, f64),
    until: f64,
    every: bool,
}

impl Kicked {
    /// A kick of 1 % of `load` (N) both ways for the first 50 ms, on wheel 1 or every wheel.
    fn one_percent(load: f64, every: bool) -> Self {
        Kicked {
            inner: CoreMagnets::new(),
            kick: (0.01 * load, 0.01 * load),
            until: 0.05,
            every,
        }
    }
}

impl Magnets for Kicked {
    fn start(&mut self, start: &Start<'_>) -> Result<()> {
        self.inner.start(start)
    }

    fn forces(
        &mut self,
        step: u32,
        t: f64,
        gaps_prev: &[WheelGaps],
        gaps_next: &[WheelGaps],
        accels: &[f64],
        out: &mut [(f64, f64)],
    ) -> Result<()> {
        self.inner
            .forces(step, t, gaps_prev, gaps_next, accels, out)?;
        if t <= self.until {
            let n = if self.every { out.len() } else { 1 };
            for o in &mut out[..n] {
                o.0 += self.kick.0;
                o.1 += self.kick.1;
            }
        }
        Ok(())
    }

    fn lateral_accels(&mut self, accels_y: &[f64]) {
        self.inner.lateral_accels(accels_y);
    }

    fn commit(&mut self, step: u32, t: f64) -> Result<()> {
        self.inner.commit(step, t)
    }

    fn status(&self) -> Status {
        self.inner.status()
    }
}

/// The slowest pole of `case`'s closed loop (on a span: the coupled analysis') and the next
/// slower distinct real part.
fn slowest(case: &Case) -> (Complex, f64) {
    let r = scenario_report("designed", case, 8).unwrap();
    assert!(
        r.zero_poles == 0,
        "a designed guided vehicle has no zero pole"
    );
    let mut poles = match &r.coupled {
        Some(c) => {
            assert!(c.stable, "the coupled model is {}", c.verdict.as_str());
            c.poles
                .iter()
                .map(|p| Complex { re: p[0], im: p[1] })
                .collect()
        }
        None => r.vehicle_poles.clone(),
    };
    poles.sort_by(|a, b| b.re.total_cmp(&a.re));
    let first = poles[0];
    let next = poles
        .iter()
        .find(|p| p.re < first.re - 1e-9 * first.re.abs())
        .unwrap()
        .re;
    (first, next)
}

/// Wheel 1's lateral motion per step (m) of `case` with `magnets` over the rail of the
/// profile `step_m` at x > 0.5 m, at the end of each step: the increments remove the offset
/// a step leaves (the guidance pair follows the rail), and decay as the motion does.
fn lateral(case: &Case, step_m: f64, magnets: &mut dyn Magnets) -> (Vec<f64>, Vec<f64>) {
    let mut pa = crate::setup::Passage::new(case).unwrap();
    let step = move |x: f64| if x > 0.5 { step_m } else { 0.0 };
    pa.profiles = Profiles {
        y: Box::new(step),
        z: Box::new(step),
    };
    let mut rec = crate::probes::Rows::new(crate::probes::Probes::default_columns());
    let out = simulate(
        &mut pa.guideway,
        &pa.load,
        &pa.profiles,
        &pa.settings,
        magnets,
        &mut rec,
        &mut (),
    )
    .unwrap();
    assert_eq!(out.collision_steps, 0);
    assert_eq!(out.unconverged_steps, 0);
    let y = rec.column("wheel1_y").unwrap();
    (
        rec.t[1..].to_vec(),
        y.windows(2).map(|w| w[1] - w[0]).collect(),
    )
}

/// The least-squares slope of `ln|s|` at the local maxima of `|s|` with `t0 ≤ t ≤ t1`.
fn peak_rate(t: &[f64], s: &[f64], t0: f64, t1: f64) -> (f64, usize) {
    let peaks: Vec<(f64, f64)> = (1..s.len() - 1)
        .filter(|&k| t[k] >= t0 && t[k] <= t1)
        .filter(|&k| s[k].abs() > s[k - 1].abs() && s[k].abs() >= s[k + 1].abs())
        .map(|k| (t[k], s[k].abs().ln()))
        .collect();
    let n = peaks.len() as f64;
    let (mt, ml) = (
        peaks.iter().map(|p| p.0).sum::<f64>() / n,
        peaks.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxy: f64 = peaks.iter().map(|p| (p.0 - mt) * (p.1 - ml)).sum();
    let sxx: f64 = peaks.iter().map(|p| (p.0 - mt).powi(2)).sum();
    (sxy / sxx, peaks.len())
}

/// The decay rate of `s` over `(t0, t1)` ([`peak_rate`], at least 10 peaks), asserted
/// within 5 % of `pole`'s real part; returned.
fn within_5_percent(t: &[f64], s: &[f64], (t0, t1): (f64, f64), pole: Complex) -> f64 {
    let (got, peaks) = peak_rate(t, s, t0, t1);
    assert!(peaks >= 10, "{peaks} peaks");
    assert!(
        (got - pole.re).abs() < 0.05 * pole.re.abs(),
        "predicted {}, measured {got} over {peaks} peaks",
        pole.re
    );
    got
}

#[test]
fn designed_fig1_car_decays_at_its_slowest_pole_on_a_rigid_rail() {
    // The 2000 kg design (docs/levitation.md "Design of a guided vehicle"): slowest pole
    // −0.426 ± 3.95j (sway–roll), the next −0.94. From t0 = 8 s the next mode is below
    // e^{−0.51·8} ≈ 2 % of its start relative to the slowest; the fit spans 8–20 s.
    let sets = DESIGNED_2000_KG;
    let (t0, t1) = (8.0, 20.0);
    let case = rigid_designed("paper-4.2", &sets, t1);
    let (pole, next) = slowest(&case);
    assert!(
        next < 1.5 * pole.re,
        "{pole:?}: the next pole {next} is too close for one mode to dominate"
    );
    let (t, y) = lateral(&case, 1e-4, &mut CoreMagnets::new());
    let got = within_5_percent(&t, &y, (t0, t1), pole);
    eprintln!("predicted {pole:?} (next {next}), measured {got}");
}

#[test]
fn designed_fig1_car_decays_at_its_coupled_slowest_pole_over_a_span() {
    // The same design, the car standing still with its wheels at 5 and 20 m on the 25 m §4.2
    // span; 2 % Rayleigh damping at the first and third bending modes (6.13 and 49.0 Hz,
    // `maglev modes`), so that no girder mode is marginal. A kick of 1 % of a wheel's load.
    let sets = DESIGNED_2000_KG;
    let (t0, t1) = (8.0, 20.0);
    let t_end = format!("t_end={t1}");
    let run = [
        "model=fe",
        "speed=0",
        "irregularity.enabled=false",
        "dt=2e-4",
        "vehicle.position_m=20",
        "bridge.damping={ratio=0.02, f1_Hz=6.13, f2_Hz=49.0}",
        &t_end,
    ];
    let case = designed_with("paper-4.2", &sets, &run);
    let (pole, next) = slowest(&case);
    assert!(
        next < 1.5 * pole.re,
        "{pole:?}: the next pole {next} is too close for one mode to dominate"
    );
    let load = (15_000.0 / 4.0 + 2000.0) * maglev_core::levitation::GRAVITY;
    let (t, y) = lateral(&case, 0.0, &mut Kicked::one_percent(load, false));
    let got = within_5_percent(&t, &y, (t0, t1), pole);
    // The same gains on a rigid rail: the girder moves the slowest pole (−0.4263 to −0.4243
    // 1/s), and the run must follow the coupled model, not the rigid one.
    let (rigid, _) = slowest(&rigid_designed("paper-4.2", &sets, t1));
    eprintln!(
        "predicted {pole:?} (next {next}; rigid rail {}), measured {got}",
        rigid.re
    );
    assert!(
        (got - pole.re).abs() < (got - rigid.re).abs(),
        "measured {got} is nearer the rigid rail's {} than the coupled {}",
        rigid.re,
        pole.re
    );
}

/// The §5 train's Fig. 6 carriage on 500 kg EMS magnets, both laws designed (docs/levitation.md
/// "Design of a guided vehicle").
const DESIGNED_CARRIAGE: [&str; 5] = [
    "geometry=ems",
    "law=state",
    "train.wheel_mass_kg=500",
    "controller.state={design=true, vmax_V=500.0}",
    "controller.guidance={design=true}",
];

#[test]
fn designed_fig6_carriage_decays_at_its_slowest_pole_on_a_rigid_rail() {
    // One carriage (slowest pole −0.211 ± 2.69j, the body on its secondary suspension; then
    // 24 real poles at −0.236 and oscillating ones from −1.0). The real ones are too close
    // for the slowest to dominate the motion, but the per-step increments the rate is read
    // from scale each mode by its |s|: the real modes' share falls by 2.69/0.236 ≈ 11 against
    // the oscillation, and from t0 = 8 s the modes from −1.0 are below e^{−0.79·8} ≈ 0.2 %.
    let (t0, t1) = (8.0, 25.0);
    let sets = DESIGNED_CARRIAGE;
    let t_end = format!("t_end={t1}");
    let run = [
        "model=rigid",
        "train.cars=1",
        "speed=10",
        "irregularity.enabled=false",
        "dt=2e-4",
        "output.probes=[\"wheel1.z\"]",
        &t_end,
    ];
    let case = designed_with("paper-5", &sets, &run);
    let (pole, next) = slowest(&case);
    let (t, y) = lateral(&case, 1e-4, &mut CoreMagnets::new());
    let got = within_5_percent(&t, &y, (t0, t1), pole);
    eprintln!("predicted {pole:?} (next {next}), measured {got}");
}

#[test]
fn designed_fig6_carriage_decays_at_its_coupled_slowest_pole_over_a_span() {
    // The design of the rigid-rail test, one carriage standing still at the start of the
    // light-girder case (docs/cases/light-girder-train.toml: the §4.2 girder, 25 m spans) with
    // 2 % Rayleigh damping at its first and third bending modes; a 50 ms kick of 1 % of a
    // wheel's load on every magnet (the body's sway, as the rail step of the rigid test; a
    // kick on one wheel excites the carriage's other slow modes as much). Measured: coupled
    // prediction −0.211089, the run −0.21053 over 15 peaks. This girder moves the slowest
    // pole by 2e-13 only (the body's sway on its secondary suspension, far below the span's
    // 6.13 Hz), so the test holds the prediction on a span, not a girder effect.
    let case_file = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../docs/cases/light-girder-train.toml"
    );
    let (t0, t1) = (8.0, 25.0);
    let t_end = format!("t_end={t1}");
    let run = [
        "model=fe",
        "train.cars=1",
        "speed=0",
        "irregularity.enabled=false",
        "dt=2e-4",
        "bridge.damping={ratio=0.02, f1_Hz=6.13, f2_Hz=49.0}",
        &t_end,
    ];
    let case = designed_onto("paper-5", &DESIGNED_CARRIAGE, case_file, &run);
    let (pole, next) = slowest(&case);
    let load = (50_000.0 / 32.0 + 500.0) * maglev_core::levitation::GRAVITY;
    let (t, y) = lateral(&case, 0.0, &mut Kicked::one_percent(load, true));
    let got = within_5_percent(&t, &y, (t0, t1), pole);
    eprintln!("predicted {pole:?} (next {next}), measured {got}");
}
