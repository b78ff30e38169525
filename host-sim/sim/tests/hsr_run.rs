//! The 3-D high-speed car in the coupled time loop (`physics::rail::run`; docs/cars.md, "The
//! 3-D car in a run"): at rest on smooth rigid rails, and over one FE span at low speed
//! against the static deflection of its wheel loads.

use maglev_core::gap::Geometry;
use maglev_core::levitation::GRAVITY;
use maglev_core::{LawKind, Params};
use maglev_sim::physics::fe::viaduct::paper5_viaduct;
use maglev_sim::physics::fe::FeGuideway;
use maglev_sim::physics::guideway::{Bridge, Guideway, RigidGuideway};
use maglev_sim::physics::rail::car::HsrCar;
use maglev_sim::physics::rail::run::{RailOutcome, RailTrain};
use maglev_sim::physics::rail::track::{SlabTrack, TrackSupport};
use maglev_sim::physics::train::Train;
use maglev_sim::probes::{Probe, Probes, Rows, SectionQ};
use maglev_sim::simulation::magnets::CoreMagnets;
use maglev_sim::simulation::{simulate, Load, Outcome, Profiles, Settings};

const DT: f64 = 2e-3;

fn settings(speed: f64, t_end: f64, midspans: Vec<f64>) -> Settings {
    Settings {
        speed,
        dt: DT,
        t_end,
        controller: Params::paper_wheel(DT),
        law: LawKind::Paper,
        guidance: None,
        geometry: Geometry::Paper,
        tolerance: 1e-9,
        max_iterations: 50,
        midspan_x: midspans.first().copied().unwrap_or(0.0),
        midspans,
        skid: maglev_sim::physics::skid::Skid::DEFAULT,
    }
}

fn spec(cars: usize, support: Option<TrackSupport>, substeps: usize) -> RailTrain {
    RailTrain {
        car: HsrCar::zhai_high_speed(),
        cars,
        pitch: 25.0,
        track_y: 2.25,
        rail_z: 1.0,
        support,
        irregularity: None,
        substeps,
    }
}

fn run(g: &mut impl Guideway, train: &Train, s: &Settings, rec: &mut Rows) -> Outcome {
    simulate(
        g,
        &Load::Vehicle(train.clone()),
        &Profiles::smooth(),
        s,
        &mut CoreMagnets::new(),
        rec,
        &mut (),
    )
    .unwrap()
}

fn midspan() -> Rows {
    let probes = vec![Probe::Midspan {
        span: 0,
        q: SectionQ::Z,
    }];
    let names = probes.iter().map(|p| format!("{p:?}")).collect();
    Rows::new(Probes { names, probes })
}

/// Two cars on smooth rigid rails, rigid on a rigid guideway: nothing moves, every wheel
/// carries the car's static wheel load and no lateral force, at every step.
#[test]
fn on_smooth_rigid_rails_the_cars_rest_on_their_static_loads() {
    let train = Train::rail_cars(spec(2, None, 2));
    let mut g = RigidGuideway::new(DT);
    let s = settings(83.33, 0.2, vec![15.0]);
    let out = run(&mut g, &train, &s, &mut midspan());
    let r: RailOutcome = out.rail.expect("the 3-D cars' record");
    let p0 = HsrCar::zhai_high_speed().wheel_load(GRAVITY);
    assert_eq!((r.lateral.len(), r.lateral[0].len()), (16, 101));
    for w in 0..16 {
        for (y, q) in r.lateral[w].iter().zip(&r.vertical[w]) {
            assert!(y.abs() < 1e-9 * p0, "wheel {w}: Y = {y}");
            assert!(
                (q - p0).abs() < 1e-9 * p0,
                "wheel {w}: Q = {q} against {p0}"
            );
        }
    }
    for a in r.body_az.iter().chain(&r.body_ay).flatten() {
        assert!(a.abs() < 1e-9, "{a}");
    }
    assert_eq!((r.lift_off_steps, out.unconverged_steps), (0, 0));
}

/// One car on its track over one 30 m span of paper-5's girder at 10 m/s: the midspan
/// deflection is the static one of its eight wheel loads where they stand (Euler beam with
/// shear, as `paper5_train.rs` checks the paper's wheel/rail car), within the dynamic
/// departure a moving load may show at that speed, α/(1 − α) of all the loads' static
/// deflection, α = v/(2 f1 L) (Frýba §1.3).
#[test]
fn one_car_over_one_span_deflects_as_its_static_wheel_loads() {
    let girder = paper5_viaduct().girder;
    let l = 30.0;
    let bridge = Bridge {
        section: girder.clone(),
        spans: vec![l],
    };
    let mut g = FeGuideway::new(&bridge, 16, DT).unwrap();
    let support = TrackSupport::new(&SlabTrack::crts2()).unwrap();
    let rail = spec(1, Some(support), 10);
    let train = Train::rail_cars(rail.clone());
    let v = 10.0;
    let t_end = (l + 22.0) / v;
    let s = settings(v, t_end, vec![l / 2.0]);
    let mut rec = midspan();
    let out = run(&mut g, &train, &s, &mut rec);
    assert_eq!((out.contact_loss_steps, out.unconverged_steps), (0, 0));
    let p0 = rail.car.wheel_load(GRAVITY);
    let ei = girder.youngs_modulus * girder.iy;
    let kga = girder.shear_modulus * girder.shear_area_z;
    let w_mid = |a: f64| -> f64 {
        if !(0.0..=l).contains(&a) {
            return 0.0;
        }
        let a = a.min(l - a);
        -(p0 * a * (3.0 * l * l - 4.0 * a * a) / (48.0 * ei) + p0 * a / (2.0 * kga))
    };
    let w_all = 8.0 * w_mid(l / 2.0);
    let f1_eb = std::f64::consts::PI / (2.0 * l * l) * (ei / girder.mass_per_length).sqrt();
    let f1 = f1_eb / (1.0 + std::f64::consts::PI.powi(2) * ei / (kga * l * l)).sqrt();
    let alpha = v / (2.0 * f1 * l);
    let tol = alpha / (1.0 - alpha) * w_all.abs();
    let xs = rail.car.wheelset_x();
    let x0 = rail.car_x0(0);
    let (mut worst, mut peak) = (0.0f64, 0.0f64);
    for (&t, row) in rec.t.iter().zip(&rec.rows) {
        let want: f64 = xs.iter().map(|xw| 2.0 * w_mid(x0 + xw + v * t)).sum();
        worst = worst.max((row[0] - want).abs());
        peak = peak.max(want.abs());
    }
    let its = &rec.iterations[1..];
    println!(
        "α {alpha:.2e}: max |w − w_static| {worst:.3e} m, tolerance {tol:.3e} m, peak static \
         {peak:.3e} m; iterations {}–{}",
        its.iter().min().unwrap(),
        its.iter().max().unwrap()
    );
    assert!(peak > 0.5 * w_all.abs());
    assert!(worst <= tol, "{worst} > {tol}");
}
