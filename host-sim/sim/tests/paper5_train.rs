//! The §5 trains through the coupling loop (issue #10; docs/cars.md "How the cars join the
//! train"): Fig. 6 maglev carriages with a controller per magnet, wheel/rail cars on Hertz
//! contacts, over a rigid rail, one simply supported span and the paper-5 viaduct.

use maglev_core::gap::Geometry;
use maglev_core::levitation::GRAVITY;
use maglev_core::{LawKind, Params};
use maglev_sim::physics::cars::fig6::Fig6;
use maglev_sim::physics::cars::wheel_rail::WheelRail;
use maglev_sim::physics::fe::viaduct::{paper5_viaduct, Viaduct};
use maglev_sim::physics::fe::FeGuideway;
use maglev_sim::physics::guideway::RigidGuideway;
use maglev_sim::physics::guideway::{Bridge, Guideway};
use maglev_sim::physics::profile::Profile;
use maglev_sim::physics::train::Train;
use maglev_sim::probes::{BodyQ, PierQ, Probe, Probes, Rows, SectionQ, WheelQ};
use maglev_sim::simulation::magnets::CoreMagnets;
use maglev_sim::simulation::{simulate, Load, Outcome, Profiles, Settings};

const DT: f64 = 2e-3;
const SPEED: f64 = 83.33;

/// An in-memory recorder of `probes` (named by their `Debug` text).
fn collect(probes: Vec<Probe>) -> Rows {
    let names = probes.iter().map(|p| format!("{p:?}")).collect();
    Rows::new(Probes { names, probes })
}

fn settings(
    speed: f64,
    t_end: f64,
    law: LawKind,
    geometry: Geometry,
    midspans: Vec<f64>,
) -> Settings {
    Settings {
        speed,
        dt: DT,
        t_end,
        controller: Params::paper_wheel(DT),
        law,
        guidance: None,
        geometry,
        tolerance: 1e-9,
        max_iterations: 50,
        midspan_x: midspans.first().copied().unwrap_or(0.0),
        midspans,
        skid: maglev_sim::physics::skid::Skid::DEFAULT,
    }
}

/// The gap-loop gains designed for the Fig. 6 carriage (docs/gap-loop.md).
fn gap_loop(geometry: Geometry) -> LawKind {
    let car = Fig6::default().build(GRAVITY).unwrap();
    let d = maglev_sim::studies::stability::design::design(
        &car,
        &Params::paper_wheel(DT),
        geometry,
        None,
    )
    .unwrap();
    LawKind::GapLoop(d.gains)
}

/// The paper's Table 1 irregularity from x = −60 m over `length` (m), vertical and lateral.
fn table1(length: f64) -> Profiles {
    let (y, z) = Profile::table1_y_z(7, -60.0, length).unwrap();
    Profiles {
        y: Box::new(move |x| y.at(x)),
        z: Box::new(move |x| z.at(x)),
    }
}

fn run(g: &mut impl Guideway, t: &Train, p: &Profiles, s: &Settings, rec: &mut Rows) -> Outcome {
    simulate(
        g,
        &Load::Vehicle(t.clone()),
        p,
        s,
        &mut CoreMagnets::new(),
        rec,
        &mut (),
    )
    .unwrap()
}

fn body_probes(cars: usize) -> Vec<Probe> {
    (0..cars)
        .map(|car| Probe::Body { car, q: BodyQ::Z })
        .collect()
}

// ------------------------------------------------------------------ Fig. 6 on a rigid rail

/// Two Fig. 6 carriages (64 magnets, each its own controller) on a rigid, smooth rail stay in
/// their static equilibrium to round-off, under both laws and the geometries they fly in;
/// over the paper's irregularity they fly without a collision.
#[test]
fn fig6_train_on_a_rigid_rail_rests_when_smooth_and_flies_over_the_irregularity() {
    let train = Train::fig6(2, GRAVITY).unwrap();
    let h0 = Params::paper_wheel(DT).h0;
    let cases = [
        ("paper law, paper geometry", LawKind::Paper, Geometry::Paper),
        (
            "gap loop, paper geometry",
            gap_loop(Geometry::Paper),
            Geometry::Paper,
        ),
        (
            "gap loop, EMS geometry",
            gap_loop(Geometry::Ems),
            Geometry::Ems,
        ),
    ];
    let mut probes = body_probes(2);
    for wheel in [0, 31, 32, 63] {
        probes.push(Probe::Wheel {
            wheel,
            q: WheelQ::GapZ,
        });
    }
    for (name, law, geometry) in cases {
        let s = settings(SPEED, 1.0, law, geometry, vec![]);
        let mut rec = collect(probes.clone());
        let out = run(
            &mut RigidGuideway::new(DT),
            &train,
            &Profiles::smooth(),
            &s,
            &mut rec,
        );
        assert_eq!(out.collision_steps, 0, "{name}");
        assert_eq!(out.unconverged_steps, 0, "{name}");
        let (mut body, mut gap) = (0.0f64, 0.0f64);
        for row in &rec.rows {
            body = body.max(row[0].abs()).max(row[1].abs());
            for g in &row[2..] {
                gap = gap.max((g - h0).abs());
            }
        }
        println!("{name}: smooth rigid rail, max |body z| {body:.2e} m, max |h − h0| {gap:.2e} m");
        // Round-off: the static state is exact, so every deviation is a few ulps of h0.
        assert!(body < 1e-13 && gap < 1e-15, "{name}: {body:e} {gap:e}");

        let mut rec = collect(probes.clone());
        let out = run(
            &mut RigidGuideway::new(DT),
            &train,
            &table1(SPEED * 1.0 + 60.0),
            &s,
            &mut rec,
        );
        let min_gap = out
            .gap_ranges
            .iter()
            .flat_map(|r| r.iter().map(|g| g.0))
            .fold(f64::INFINITY, f64::min);
        let its = out.max_iterations;
        println!("{name}: Table 1 rail, min gap {min_gap:.3e} m, max iterations {its}");
        assert_eq!(out.collision_steps, 0, "{name}: min gap {min_gap}");
        assert_eq!(out.unconverged_steps, 0, "{name}");
        assert!(rec.rows.iter().flatten().all(|v| v.is_finite()));
    }
}

// --------------------------------------------------------------- wheel/rail on a rigid rail

/// On a smooth rigid rail every contact force is the car's static axle-load share, by hand
/// statics of the symmetric car (lever rule): each wheel carries 1/8 of the body, 1/4 of its
/// bogie and 1/2 of its wheelset — to round-off, at every step, with no lift-off.
#[test]
fn wheel_rail_contact_forces_on_a_smooth_rigid_rail_are_the_hand_axle_loads() {
    let p = WheelRail::default();
    let share = GRAVITY * (p.body_mass / 8.0 + p.bogie_mass / 4.0 + p.wheelset_mass / 2.0);
    let train = Train::wheel_rail(2, GRAVITY).unwrap();
    let probes: Vec<Probe> = (0..16)
        .map(|wheel| Probe::Wheel {
            wheel,
            q: WheelQ::ForceZ,
        })
        .collect();
    let mut rec = collect(probes);
    let s = settings(SPEED, 1.0, LawKind::Paper, Geometry::Paper, vec![]);
    let out = run(
        &mut RigidGuideway::new(DT),
        &train,
        &Profiles::smooth(),
        &s,
        &mut rec,
    );
    assert_eq!(out.contact_loss_steps, 0);
    assert_eq!(rec.rows.len(), 501);
    let worst = rec
        .rows
        .iter()
        .flatten()
        .map(|f| (f - share).abs())
        .fold(0.0, f64::max);
    println!("hand share {share:.3} N, max deviation {worst:.2e} N");
    assert!(worst <= 1e-9 * share, "{worst}");
    // The same through the outcome's ranges.
    for &(lo, hi) in &out.contact_ranges {
        assert!((lo - share).abs() <= 1e-9 * share && (hi - share).abs() <= 1e-9 * share);
    }
}

/// The contact can only push: a car dropped onto a rail that falls away 1 mm under it (a
/// step of r_z, which opens the gap) loses contact and the force is zero, not negative.
#[test]
fn a_wheel_over_a_falling_rail_lifts_off_and_its_force_is_clamped_at_zero() {
    let train = Train::wheel_rail(1, GRAVITY).unwrap();
    let profiles = Profiles {
        y: Box::new(|_| 0.0),
        z: Box::new(|x: f64| if x > 1.0 { 1e-3 } else { 0.0 }),
    };
    let probes = vec![Probe::Wheel {
        wheel: 0,
        q: WheelQ::ForceZ,
    }];
    let mut rec = collect(probes);
    let s = settings(10.0, 0.5, LawKind::Paper, Geometry::Paper, vec![]);
    let out = run(&mut RigidGuideway::new(DT), &train, &profiles, &s, &mut rec);
    // The static compression is P0/k_h ≈ 60 µm ≪ 1 mm: the leading wheel leaves the rail.
    assert!(out.contact_loss_steps > 0);
    assert!(rec.rows.iter().all(|r| r[0] >= 0.0));
    assert!(rec.rows.iter().any(|r| r[0] == 0.0));
    assert_eq!(out.unconverged_steps, 0);
}

// ----------------------------------------------------- wheel/rail over one simply supported span

/// One wheel/rail car crossing one simply supported 30 m span of the paper-5 girder at
/// 2 m/s: the midspan deflection follows the closed-form static deflection of the eight
/// axle loads at their positions (Euler–Bernoulli bending plus Timoshenko shear, the loads the
/// hand statics' P0).
///
/// Tolerance from the speed: for a constant force crossing a simply supported beam, the
/// first mode's response is the quasi-static one times 1/(1 − α²) minus a free vibration of
/// relative amplitude α/(1 − α²), α = v/(2 f1 L) (Frýba, *Vibration of Solids and Structures
/// under Moving Loads*, §1.3). Even with every load's free vibration in phase, the departure
/// from the quasi-static value stays below α/(1 − α) times the static deflection of all the
/// loads at midspan. f1 is the Timoshenko beam's first frequency (shear lowers it, which
/// raises α).
#[test]
fn wheel_rail_car_over_one_span_at_low_speed_deflects_as_the_static_axle_loads() {
    let girder = paper5_viaduct().girder;
    let l = 30.0;
    let bridge = Bridge {
        section: girder.clone(),
        spans: vec![l],
    };
    let mut g = FeGuideway::new(&bridge, 16, DT).unwrap();
    let train = Train::wheel_rail(1, GRAVITY).unwrap();
    let p = WheelRail::default();
    let share = GRAVITY * (p.body_mass / 8.0 + p.bogie_mass / 4.0 + p.wheelset_mass / 2.0);
    let v = 2.0;
    // Long enough for the last axle (20 m behind) to leave the span.
    let t_end = (l + 22.0) / v;
    let s = settings(v, t_end, LawKind::Paper, Geometry::Paper, vec![l / 2.0]);
    let mut rec = collect(vec![Probe::Midspan {
        span: 0,
        q: SectionQ::Z,
    }]);
    let out = run(&mut g, &train, &Profiles::smooth(), &s, &mut rec);
    assert_eq!(out.contact_loss_steps, 0);
    assert_eq!(out.unconverged_steps, 0);

    let ei = girder.youngs_modulus * girder.iy;
    let kga = girder.shear_modulus * girder.shear_area_z;
    // Midspan deflection under P at a (0 ≤ a ≤ L; by symmetry a → L − a past the middle).
    let w_mid = |a: f64| -> f64 {
        if !(0.0..=l).contains(&a) {
            return 0.0;
        }
        let a = a.min(l - a);
        -(share * a * (3.0 * l * l - 4.0 * a * a) / (48.0 * ei) + share * a / (2.0 * kga))
    };
    let w_all = 8.0 * w_mid(l / 2.0);
    let f1_eb = std::f64::consts::PI / (2.0 * l * l) * (ei / girder.mass_per_length).sqrt();
    let f1 = f1_eb / (1.0 + std::f64::consts::PI.powi(2) * ei / (kga * l * l)).sqrt();
    let alpha = v / (2.0 * f1 * l);
    let tol = alpha / (1.0 - alpha) * w_all.abs();
    let mut worst = 0.0f64;
    let mut peak = 0.0f64;
    for (&t, row) in rec.t.iter().zip(&rec.rows) {
        let want: f64 = train.contacts.iter().map(|c| w_mid(c.x0 + v * t)).sum();
        worst = worst.max((row[0] - want).abs());
        peak = peak.max(want.abs());
    }
    let its = &rec.iterations[1..];
    println!(
        "f1 {f1:.3} Hz, α {alpha:.2e}: max |w − w_static| {worst:.3e} m, tolerance {tol:.3e} m, \
         peak static {peak:.3e} m; iterations {}–{}",
        its.iter().min().unwrap(),
        its.iter().max().unwrap()
    );
    assert!(peak > 0.5 * w_all.abs());
    assert!(worst <= tol, "{worst} > {tol}");
}

// ------------------------------------------------------------------ over the paper-5 viaduct

fn viaduct_run(train: &Train, spans: usize, steps: usize, names: &[&str]) -> (Outcome, Rows, f64) {
    viaduct_run_on(train, spans, steps, names, &Profiles::smooth())
}

fn viaduct_run_on(
    train: &Train,
    spans: usize,
    steps: usize,
    names: &[&str],
    profiles: &Profiles,
) -> (Outcome, Rows, f64) {
    let spec = paper5_viaduct().with_spans(spans);
    let mut g = Viaduct::new(&spec, DT).unwrap();
    let midspans: Vec<f64> = (0..spans)
        .map(|k| (k as f64 + 0.5) * spec.span_length)
        .collect();
    let s = settings(
        SPEED,
        steps as f64 * DT,
        LawKind::Paper,
        Geometry::Paper,
        midspans,
    );
    let extent = maglev_sim::probes::Extent {
        spans,
        wheels: train.nodes.len(),
        cars: train.cars.len(),
        magnets: !train.wheels.is_empty(),
    };
    let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
    let probes = Probes::new(Some(&names), &extent).unwrap();
    probes.check_guideway(&g).unwrap();
    let mut rec = Rows::new(probes);
    let start = std::time::Instant::now();
    let out = run(&mut g, train, profiles, &s, &mut rec);
    (out, rec, start.elapsed().as_secs_f64())
}

/// Two-car trains of both kinds cross 3 spans of the paper-5 viaduct at 83.33 m/s, Δt = 2 ms,
/// on a smooth rail: no collision, every step converged, finite responses, and the piers'
/// bases move. The wheels keep contact everywhere except just past the two ends of the
/// viaduct, where the model's rail steps from the rigid embankment onto a girder end sunk on
/// its bearings, or back (docs/cars.md "Where a wheel lifts off"): there, and only there
/// (within 1.5 m, nine steps), a wheel may lift off briefly.
#[test]
fn two_car_trains_cross_three_viaduct_spans() {
    let base = [
        "car1.body.az",
        "car2.body.z",
        "pier2.base.z",
        "pier2.base.az",
        "pier3.base.az",
        "span2.midspan.z",
        "wheel9.z",
    ];
    // Leading node from x = 0 to beyond the last pier: 90 m + the train's 50 m.
    let steps = ((90.0 + 50.0) / SPEED / DT).ceil() as usize;
    for (kind, train) in [
        ("maglev", Train::fig6(2, GRAVITY).unwrap()),
        ("wheel-rail", Train::wheel_rail(2, GRAVITY).unwrap()),
    ] {
        let forces: Vec<String> = (1..=train.nodes.len())
            .map(|w| format!("wheel{w}.force_z"))
            .collect();
        let mut names: Vec<&str> = base.to_vec();
        names.extend(forces.iter().map(|s| s.as_str()));
        let (out, rec, wall) = viaduct_run(&train, 3, steps, &names);
        assert_eq!(out.collision_steps, 0, "{kind}");
        assert_eq!(out.unconverged_steps, 0, "{kind}");
        assert!(rec.rows.iter().flatten().all(|v| v.is_finite()), "{kind}");
        let max = |c: usize| rec.rows.iter().map(|r| r[c].abs()).fold(0.0, f64::max);
        let its = &rec.iterations[1..];
        let mean = its.iter().sum::<u32>() as f64 / its.len() as f64;
        // Where the contacts lifted off: distance past the nearest viaduct end.
        let mut lift_offs = Vec::new();
        for (i, r) in rec.rows.iter().enumerate() {
            for (j, c) in train.contacts.iter().enumerate() {
                if r[base.len() + j] == 0.0 {
                    lift_offs.push(c.x0 + SPEED * DT * i as f64);
                }
            }
        }
        println!(
            "{kind}: {steps} steps in {wall:.2} s; iterations mean {mean:.2}, max {}; \
             |pier2 base z| {:.3e} m, az {:.3e} m/s²; |span2 midspan z| {:.3e} m; \
             wheel1 force {:.4e}..{:.4e} N; lift-off steps {}, at x {:?}",
            its.iter().max().unwrap(),
            max(2),
            max(3),
            max(5),
            rec.rows.iter().map(|r| r[6]).fold(f64::INFINITY, f64::min),
            rec.rows.iter().map(|r| r[6]).fold(0.0, f64::max),
            out.contact_loss_steps,
            lift_offs
        );
        for x in &lift_offs {
            let past_end = [x - 0.0, x - 90.0]
                .into_iter()
                .any(|d| (0.0..=1.5).contains(&d));
            assert!(
                past_end,
                "{kind}: lift-off at x = {x} m, not just past a viaduct end"
            );
        }
        assert!(max(2) > 0.0 && max(3) > 0.0 && max(4) > 0.0, "{kind}");
        assert!(max(5) > 0.0, "{kind}");
    }
}

/// A pier probe beyond the viaduct is refused before the run, naming the limit.
#[test]
fn a_pier_probe_is_checked_against_the_guideway() {
    let g = Viaduct::new(&paper5_viaduct().with_spans(3), DT).unwrap();
    let e = maglev_sim::probes::Extent {
        spans: 3,
        wheels: 8,
        cars: 1,
        magnets: false,
    };
    let p = Probes::new(Some(&["pier5.base.z".to_string()]), &e).unwrap();
    let err = p.check_guideway(&g).unwrap_err();
    assert!(
        matches!(&err, maglev_sim::Error::Invalid { key, .. } if key == "output.probes"),
        "{err:?}"
    );
    assert_eq!(
        err.to_string(),
        "output.probes: `pier5.base.z`: the guideway has 4 pier(s), so K is at most 4"
    );
    let ok = Probes::new(Some(&["pier4.base.az".to_string()]), &e).unwrap();
    assert!(ok.check_guideway(&g).is_ok());
    assert_eq!(
        ok.probes[0],
        Probe::Pier {
            pier: 3,
            q: PierQ::Az
        }
    );
    // A guideway without piers has none.
    assert!(ok.check_guideway(&RigidGuideway::new(DT)).is_err());
}

/// Issue #10's runs: a 12-car train of each kind over the 35-span viaduct, 5000 steps of
/// 2 ms at 83.33 m/s. A timing print, not a timed assertion (run in release:
/// `cargo test --release -p maglev-sim --test paper5_train -- --ignored --nocapture`).
#[test]
#[ignore]
fn timing_of_12_car_trains_over_35_spans() {
    let names = ["car4.body.az", "pier20.base.az"];
    let hertz_only = WheelRail {
        track_stiffness: f64::INFINITY,
        ..WheelRail::default()
    };
    let hertz_only = Train::repeated(
        &maglev_sim::physics::train::CarKind::WheelRail(hertz_only),
        12,
        25.0,
        GRAVITY,
    )
    .unwrap();
    let smooth = Profiles::smooth();
    let rough = table1(1100.0);
    for (kind, train, profiles) in [
        ("maglev", Train::fig6(12, GRAVITY).unwrap(), &smooth),
        (
            "wheel-rail",
            Train::wheel_rail(12, GRAVITY).unwrap(),
            &smooth,
        ),
        (
            "wheel-rail, Hertz spring only (no track)",
            hertz_only,
            &smooth,
        ),
        (
            "maglev, Table 1 rail",
            Train::fig6(12, GRAVITY).unwrap(),
            &rough,
        ),
        (
            "wheel-rail, Table 1 rail",
            Train::wheel_rail(12, GRAVITY).unwrap(),
            &rough,
        ),
    ] {
        let (out, rec, wall) = viaduct_run_on(&train, 35, 5000, &names, profiles);
        let its = &rec.iterations[1..];
        let mean = its.iter().sum::<u32>() as f64 / its.len() as f64;
        println!(
            "{kind}: 12 cars, 35 spans, 5000 steps: {wall:.1} s wall; iterations mean {mean:.2}, \
             max {}; collisions {}, lift-offs {}, unconverged {}",
            its.iter().max().unwrap(),
            out.collision_steps,
            out.contact_loss_steps,
            out.unconverged_steps
        );
    }
}

// ------------------------------------------------------- the start on the paper-5 rough rail

/// Issue #25: the paper-5 wheel/rail train (12 cars, the Table 1 irregularity of seed 1 as
/// the scenario builds it) starts in static equilibrium on its rough rail, on a rigid
/// guideway (so the rail's roughness is the only input).
///
/// At t = 0 every contact force is its static load P0, and consistent with the car's state:
/// P = P0 − k·(z_w + r_z(x0)). In this car both rails share r_z and the car is statically
/// determinate in the vertical plane (two axles per bogie on its heave and pitch, two bogies
/// on the body's), so the rough rail moves the car but redistributes no load: P = P0 up to
/// the solve's round-off, k·|δz_w| with |δz_w| ≤ cond(K)·ε·|z_w| (backward-stable Cholesky;
/// a factor 10 for the few operations around it).
///
/// The first step from rest at q0 (v = a = 0, K q0 = f0) is u1 = q0 + Keff⁻¹·Δf, Δf the change
/// of the contacts' forcing, −k·Δr_z on each contact DOF (Δr_z the irregularity's change under
/// the contact over v·Δt). Keff = K + 4M/Δt² + 2C/Δt ⪰ 4M/Δt², so
/// ‖Δz‖₂ ≤ Δt²/(4·λmin(M))·k·‖Δr_z‖₂ over the car, and each contact force changes by
/// |ΔP_j| = k·|Δz_wj + Δr_zj| ≤ k·(|Δr_zj| + ‖Δz‖₂). On today's code (the car at its
/// smooth-rail position) the first step jumps by about k·r_z(x0) instead, 270 kN at wheel 1.
#[test]
fn paper5_wheel_rail_train_starts_at_its_static_axle_loads_on_the_rough_rail() {
    use maglev_sim::input::case::Case;
    use maglev_sim::setup::Passage;
    let case = Case::load("paper-5", &["train=wheel-rail".into(), "t_end=0.02".into()]).unwrap();
    let p = Passage::new(&case).unwrap();
    let Load::Vehicle(train) = &p.load else {
        panic!("paper-5 wheel-rail is a train")
    };
    assert_eq!((train.cars.len(), train.contacts.len()), (12, 96));
    let nc = train.contacts.len();
    let mut probes = Vec::new();
    for wheel in 0..nc {
        probes.push(Probe::Wheel {
            wheel,
            q: WheelQ::ForceZ,
        });
        probes.push(Probe::Wheel {
            wheel,
            q: WheelQ::Z,
        });
    }
    let mut rec = collect(probes);
    let dt = p.settings.dt;
    let out = simulate(
        &mut RigidGuideway::new(dt),
        &p.load,
        &p.profiles,
        &p.settings,
        &mut CoreMagnets::new(),
        &mut rec,
        &mut (),
    )
    .unwrap();
    assert_eq!(out.unconverged_steps, 0);
    let car = &train.cars[0];
    let eps = f64::EPSILON;
    let eig = |m: &nalgebra::DMatrix<f64>| m.clone().symmetric_eigen().eigenvalues;
    let kr = eig(&car.k_on_rigid_rail());
    let cond = kr.max() / kr.min();
    let lambda_m = eig(&car.m).min();
    let rz = |x: f64| (p.profiles.z)(x);
    let (r0, r1) = (&rec.rows[0], &rec.rows[1]);
    let (mut worst0, mut worst1, mut worst_ratio) = (0.0f64, 0.0f64, 0.0f64);
    let mut first = Vec::new();
    for (ci, _) in train.cars.iter().enumerate() {
        let mine: Vec<usize> = (0..nc).filter(|&j| train.contacts[j].car == ci).collect();
        let dr: Vec<f64> = mine
            .iter()
            .map(|&j| {
                let x0 = train.contacts[j].x0;
                rz(x0 + p.settings.speed * dt) - rz(x0)
            })
            .collect();
        let dr_norm = dr.iter().map(|d| d * d).sum::<f64>().sqrt();
        for (&j, d) in mine.iter().zip(&dr) {
            let c = &train.contacts[j];
            let (f0, z0) = (r0[2 * j], r0[2 * j + 1]);
            // t = 0: the static load, and the force the car's state gives.
            let tol0 = 10.0 * cond * eps * c.k * z0.abs().max(rz(c.x0).abs()) + 4.0 * eps * c.p0;
            let from_state = c.p0 - c.k * (z0 + rz(c.x0));
            assert!(
                (f0 - c.p0).abs() <= tol0 && (from_state - c.p0).abs() <= tol0,
                "contact {}: P(0) {f0} N, from the state {from_state} N, P0 {} N, tol {tol0:e}",
                j + 1,
                c.p0
            );
            worst0 = worst0.max((f0 - c.p0).abs().max((from_state - c.p0).abs()));
            // The first step: the rail's roughness under it, and nothing more.
            let dz_bound = dt * dt / (4.0 * lambda_m) * c.k * dr_norm;
            let tol1 = c.k * (d.abs() + dz_bound);
            let df = (r1[2 * j] - f0).abs();
            assert!(
                df <= tol1,
                "contact {}: first step changes P by {df:.1} N > {tol1:.1} N",
                j + 1
            );
            worst1 = worst1.max(df);
            worst_ratio = worst_ratio.max(df / tol1);
            if j < 8 {
                first.push((r0[2 * j], r1[2 * j], rec.rows[10][2 * j]));
            }
        }
    }
    println!(
        "cond(K) {cond:.2e}, λmin(M) {lambda_m:.1} kg; max |P(0) − P0| {worst0:.2e} N; \
         max first-step change {worst1:.3e} N, at most {worst_ratio:.3} of its bound"
    );
    println!("car 1's contacts: (P at t = 0, Δt, 10Δt) N: {first:.1?}");
}

/// A statically indeterminate car: a rigid beam (heave, pitch) on three wheels 5 m apart,
/// each on a stiff primary spring (1e8 N/m) and a contact spring (1e9 N/m). The middle
/// contact starts over a 3 mm dip. On three supports that dip unloads the middle one by
/// (2/3)·k_s·d = 1.8e5 N (k_s the two springs in series), more than its 1.08e5 N static
/// load. So the car starts on its two end wheels: the middle force 0, the ends W/2 each (the
/// hanging middle wheel's weight goes to the body), the car at rest. While the rail under
/// every contact stays as it was (10 m/s for 0.1 s: the dip spans ±2 m), nothing moves: the
/// middle force stays 0 and the others at W/2 within what the loop's lift-off correction
/// leaves. The loop stops when that correction changes by at most k·tolerance (1 N here)
/// between passes; with the clamp's contraction factor ρ = k·H_ww ≈ k/(k + k_p + 4m_w/Δt²) = 0.47 ≤ 1/2, its
/// remainder is at most ρ/(1 − ρ) ≤ 1 times that, so the car meets a force error of at most
/// 2·k·tolerance, and the end wheels' forces stay within it. Every step is a lift-off.
/// (The paper-5 car cannot start lifted off: both rails share r_z and it is statically
/// determinate in the vertical plane, docs/cars.md.)
#[test]
fn an_indeterminate_car_starting_over_a_dip_rests_on_its_other_wheels() {
    use maglev_sim::physics::vehicle::{Contact, VehicleModel};
    use nalgebra::{DMatrix, DVector};
    let (mb, jb, mw, kp, cp, kc, l, d) = (30e3, 2e5, 1e3, 1e8, 1e4, 1e9, 5.0, 3e-3);
    let n = 5;
    let (mut m, mut c, mut k) = (
        DMatrix::zeros(n, n),
        DMatrix::zeros(n, n),
        DMatrix::zeros(n, n),
    );
    m[(0, 0)] = mb;
    m[(1, 1)] = jb;
    let xs = [l, 0.0, -l];
    for (i, &x) in xs.iter().enumerate() {
        m[(2 + i, 2 + i)] = mw;
        // Spring between wheel i and the body point at x: z_w − (z_b + θ·x).
        let mut sv = DVector::zeros(n);
        sv[2 + i] = 1.0;
        sv[0] = -1.0;
        sv[1] = -x;
        k += &sv * sv.transpose() * kp;
        c += &sv * sv.transpose() * cp;
    }
    let mut weight = DVector::zeros(n);
    weight[0] = -mb * GRAVITY;
    for i in 0..3 {
        weight[2 + i] = -mw * GRAVITY;
    }
    let w = (mb + 3.0 * mw) * GRAVITY;
    let mut car = VehicleModel {
        m,
        c,
        k,
        wheels: Vec::new(),
        p0: Vec::new(),
        contacts: xs
            .iter()
            .enumerate()
            .map(|(i, &x)| Contact {
                x0: x - l,
                ey: 0.0,
                ez: 0.0,
                dof_z: 2 + i,
                p0: 0.0,
                k_h: kc,
                k: kc,
            })
            .collect(),
        body_z: 0,
        body_pitch: 1,
        length: 2.0 * l,
        weight: w,
    };
    let (_, p0) = car.static_loads(&weight).unwrap();
    for (ct, p) in car.contacts.iter_mut().zip(&p0) {
        ct.p0 = *p;
    }
    let train = Train::from_cars(vec![car]);
    let profiles = Profiles {
        y: Box::new(|_| 0.0),
        z: Box::new(move |x: f64| if (x + l).abs() < 2.0 { d } else { 0.0 }),
    };
    let probes = (0..3)
        .map(|wheel| Probe::Wheel {
            wheel,
            q: WheelQ::ForceZ,
        })
        .collect();
    let mut rec = collect(probes);
    let s = settings(10.0, 0.1, LawKind::Paper, Geometry::Paper, vec![]);
    let out = run(&mut RigidGuideway::new(DT), &train, &profiles, &s, &mut rec);
    let first = rec.rows[0].clone();
    println!("static loads {p0:.1?} N; start over the dip: {first:.1?} N");
    assert_eq!(first[1], 0.0, "{first:?}");
    for f in [first[0], first[2]] {
        assert!((f - w / 2.0).abs() <= 1e-9 * w, "{f} vs {}", w / 2.0);
    }
    let worst = rec
        .rows
        .iter()
        .flat_map(|r| r.iter().zip(&first).map(|(a, b)| (a - b).abs()))
        .fold(0.0, f64::max);
    let tol = 2.0 * kc * s.tolerance;
    println!("max change over 0.1 s {worst:.2e} N (tolerance {tol} N)");
    assert!(rec.rows.iter().all(|r| r[1] == 0.0));
    assert!(worst <= tol, "{worst}");
    assert_eq!(out.contact_loss_steps, 50);
    assert_eq!(out.unconverged_steps, 0);
}
