//! Trains of Fig. 1 cars (docs/model.md §10): block-diagonal cars, each in its own static
//! equilibrium, coupled only through the guideway and the rail.

use maglev_sim::input::case::{Case, TrainCase};
use maglev_sim::physics::train::{CarKind, CarSpec, Train};
use maglev_sim::physics::vehicle::Fig1;
use maglev_sim::probes::{BodyQ, Probe, Recorder, StepView, WheelQ};
use maglev_sim::setup::Passage;
use maglev_sim::simulation::magnets::CoreMagnets;
use maglev_sim::simulation::{simulate, Load, Profiles};

/// Records the given probes at every step.
struct Collect {
    probes: Vec<Probe>,
    rows: Vec<Vec<f64>>,
}

impl Collect {
    fn new(probes: Vec<Probe>) -> Self {
        Collect {
            probes,
            rows: Vec::new(),
        }
    }
}

impl Recorder for Collect {
    fn record(&mut self, step: &StepView) -> maglev_sim::Result<()> {
        self.rows
            .push(self.probes.iter().map(|p| step.value(p)).collect());
        Ok(())
    }
}

/// Car `car`'s body heave and its four wheels' gaps and displacements (0-based car index).
fn car_probes(car: usize) -> Vec<Probe> {
    let mut p = vec![Probe::Body { car, q: BodyQ::Z }];
    for w in 4 * car..4 * car + 4 {
        for q in [
            WheelQ::GapZ,
            WheelQ::GapY,
            WheelQ::Z,
            WheelQ::Y,
            WheelQ::ForceZ,
        ] {
            p.push(Probe::Wheel { wheel: w, q });
        }
    }
    p
}

/// A rail at rest for x < 0 and irregular beyond, C¹ at 0: a car standing behind x = 0 is in
/// its static equilibrium until its lead wheel gets there.
fn rail_from_zero() -> Profiles {
    Profiles {
        y: Box::new(|x: f64| {
            if x > 0.0 {
                1.5e-3 * (1.0 - (0.9 * x).cos())
            } else {
                0.0
            }
        }),
        z: Box::new(|x: f64| {
            if x > 0.0 {
                2e-3 * (1.0 - (0.37 * x).cos())
            } else {
                0.0
            }
        }),
    }
}

fn run(sets: &[&str], profiles: Option<Profiles>, probes: Vec<Probe>) -> Vec<Vec<f64>> {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let case = Case::load("paper-4.2", &sets).unwrap();
    let mut pa = Passage::new(&case).unwrap();
    if let Some(p) = profiles {
        pa.profiles = p;
    }
    let mut rec = Collect::new(probes);
    simulate(
        &mut pa.guideway,
        &pa.load,
        &pa.profiles,
        &pa.settings,
        &mut CoreMagnets::new(),
        &mut rec,
        &mut (),
    )
    .unwrap();
    rec.rows
}

/// The largest difference of any column of `b` from `a`, relative to that column's peak in
/// `a` (columns at rest: relative to 1), and the smallest such peak among moving columns.
fn max_abs_diff(a: &[Vec<f64>], b: &[Vec<f64>]) -> (f64, f64) {
    let cols = a[0].len();
    let mut worst: f64 = 0.0;
    let mut smallest = f64::INFINITY;
    for k in 0..cols {
        let base = a[0][k];
        let peak = a.iter().map(|r| (r[k] - base).abs()).fold(0.0, f64::max);
        let scale = if peak > 0.0 { peak } else { 1.0 };
        if peak > 0.0 {
            smallest = smallest.min(peak);
        }
        let d = a
            .iter()
            .zip(b)
            .map(|(ra, rb)| (ra[k] - rb[k]).abs())
            .fold(0.0, f64::max);
        worst = worst.max(d / scale);
    }
    (worst, smallest)
}

/// Two identical cars 40 m apart on a rigid guideway over an irregular rail: car 1 moves as
/// the car alone, and car 2 moves as car 1 did 40 m (400 steps) earlier.
#[test]
fn two_cars_on_a_rigid_guideway_each_move_like_one_car() {
    let common = [
        "model=rigid",
        "scheme=accurate",
        "t_end=0.8",
        "run.tolerance_m=1e-13",
    ];
    let one = run(&common, Some(rail_from_zero()), car_probes(0));
    let mut sets = common.to_vec();
    sets.extend(["vehicle.repeat=2", "vehicle.car_length_m=40.0"]);
    let mut both = car_probes(0);
    both.extend(car_probes(1));
    let two = run(&sets, Some(rail_from_zero()), both);
    assert_eq!(one.len(), 801);
    assert_eq!(two.len(), 801);
    let n = one[0].len();
    let car1: Vec<Vec<f64>> = two.iter().map(|r| r[..n].to_vec()).collect();
    let car2: Vec<Vec<f64>> = two.iter().map(|r| r[n..].to_vec()).collect();
    // Car 1 of the train against the car alone.
    let (d1, peak) = max_abs_diff(&one, &car1);
    // Car 2, 400 steps later, against the car alone (and it stands still until then).
    let (d2, _) = max_abs_diff(&one[..401], &car2[400..]);
    let (rest, _) = max_abs_diff(&car2[..400], &vec![car2[0].clone(); 400]);
    println!("car 1 vs alone {d1:.2e}, car 2 delayed vs alone {d2:.2e} of each column's swing, car 2 before the rail moves {rest:.2e} (smallest swing {peak:.3e})");
    // The wheels moved (the test has something to compare): gap changes of millimetres.
    let gap_swing = one
        .iter()
        .map(|r| (r[1] - one[0][1]).abs())
        .fold(0.0, f64::max);
    assert!(gap_swing > 1e-4, "{gap_swing}");
    // The Newton–Raphson tolerance (1e-13 m on gaps that swing by millimetres) sets the
    // agreement: each column within 1e-8 of its own swing.
    assert!(d1 <= 1e-8, "car 1: {d1:e}");
    assert!(d2 <= 1e-8, "car 2: {d2:e}");
    assert_eq!(
        rest, 0.0,
        "car 2 moved before its lead wheel reached the irregular rail"
    );
}

/// Three different cars (body CoM at 0, 1.5 m ahead, 1 m behind the middle of the wheelbase,
/// so three different sets of p0) start behind a 3-span FE viaduct on a smooth rail: each is
/// in its own static equilibrium, so nothing moves but what the viaduct under car 1 makes
/// move, and car 1 moves exactly as it would alone.
#[test]
fn a_three_car_train_starts_in_static_equilibrium_on_an_fe_viaduct() {
    let sets: Vec<String> = [
        "scheme=accurate",
        "t_end=0.2",
        "run.tolerance_m=1e-13",
        "bridge.spans_m=[25.0, 25.0, 25.0]",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let sc = Case::load("paper-4.2", &sets).unwrap();
    let TrainCase::Fig1 { car: fig, .. } = &sc.train else {
        panic!("paper-4.2 runs Fig. 1 cars")
    };
    let specs: Vec<CarSpec> = [0.0, 1.5, -1.0]
        .iter()
        .enumerate()
        .map(|(i, &e)| CarSpec {
            kind: CarKind::Fig1(Fig1 {
                com_ahead: e,
                ..fig.clone()
            }),
            offset: 25.0 * i as f64,
        })
        .collect();
    let train = Train::new(&specs, maglev_core::levitation::GRAVITY).unwrap();
    // Three different load sets.
    assert!(train.p0[4] > train.p0[6] && train.p0[8] < train.p0[10]);
    let p0 = train.p0.clone();
    let mut probes = Vec::new();
    for c in 0..3 {
        probes.extend(car_probes(c));
        probes.push(Probe::Body {
            car: c,
            q: BodyQ::Az,
        });
    }
    let run_train = |train: Train, probes: Vec<Probe>| {
        let mut pa = Passage::new(&sc).unwrap();
        pa.profiles = Profiles::smooth();
        pa.load = Load::Vehicle(train);
        let mut rec = Collect::new(probes);
        simulate(
            &mut pa.guideway,
            &pa.load,
            &pa.profiles,
            &pa.settings,
            &mut CoreMagnets::new(),
            &mut rec,
            &mut (),
        )
        .unwrap();
        rec.rows
    };
    let rows = run_train(train, probes.clone());
    let per_car = probes.len() / 3;
    // t = 0: every wheel at h0, every force its own car's p0.
    let h0 = sc.h0();
    for c in 0..3 {
        for w in 0..4 {
            let base = c * per_car + 1 + 5 * w;
            assert_eq!(rows[0][base], h0);
            assert_eq!(rows[0][base + 4], p0[4 * c + w]);
        }
    }
    // Cars 2 and 3 stand on rigid ground (x < 0) for the whole 0.2 s: exactly at rest, each
    // magnet holding its own p0 — a magnet given another car's p0 would move its car.
    for row in &rows {
        for c in 1..3 {
            let r = &row[c * per_car..(c + 1) * per_car];
            for w in 0..4 {
                let base = 1 + 5 * w;
                assert_eq!(r[base], h0, "car {} wheel {} gap", c + 1, w + 1);
                assert_eq!(
                    r[base + 4],
                    p0[4 * c + w],
                    "car {} wheel {} force",
                    c + 1,
                    w + 1
                );
            }
            assert_eq!(r[0], 0.0);
            assert_eq!(*r.last().unwrap(), 0.0);
        }
    }
    // No transient at t = 0: car 1 enters the viaduct at its support, where the beam does
    // not deflect, so its body's first-step acceleration is small against what the crossing
    // brings later (an unbalanced static force would show up at once, as ΔF/m).
    let az = |r: &Vec<f64>| r[per_car - 1].abs();
    let first = az(&rows[1]);
    let peak_az = rows.iter().map(az).fold(0.0, f64::max);
    println!(
        "car 1 body acceleration: first step {first:.2e}, largest over 0.2 s {peak_az:.2e} m/s²"
    );
    assert!(peak_az > 1e-3, "the viaduct should move car 1: {peak_az}");
    assert!(first <= 1e-3 * peak_az, "{first:e} vs {peak_az:e}");
    // Car 1 alone moves exactly as car 1 of the train until car 2 reaches the viaduct.
    let alone = Train::new(&specs[..1], maglev_core::levitation::GRAVITY).unwrap();
    let single = run_train(alone, probes[..per_car].to_vec());
    let car1: Vec<Vec<f64>> = rows.iter().map(|r| r[..per_car].to_vec()).collect();
    let (d, _) = max_abs_diff(&single, &car1);
    println!("car 1 in the train vs alone: {d:.2e} of each column's swing");
    assert!(d <= 1e-8, "{d:e}");
}
