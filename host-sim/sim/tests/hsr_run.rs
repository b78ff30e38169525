//! The 3-D high-speed car in the coupled time loop (`physics::rail::run`; docs/cars.md, "The
//! 3-D car in a run"): at rest on smooth rigid rails, and over one FE span at low speed
//! against the static deflection of its wheel loads.

use maglev_core::gap::Geometry;
use maglev_core::levitation::GRAVITY;
use maglev_core::{LawKind, Params};
use maglev_sim::physics::fe::viaduct::paper5_viaduct;
use maglev_sim::physics::fe::FeGuideway;
use maglev_sim::physics::guideway::{Bridge, Guideway, RigidGuideway};
use maglev_sim::physics::rail::car::{HsrCar, Running};
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
/// carries its static forces (a centred wheelset's, the lateral ones opposite on its two
/// wheels), at every step.
#[test]
fn on_smooth_rigid_rails_the_cars_rest_on_their_static_loads() {
    let train = Train::rail_cars(spec(2, None, 2));
    let mut g = RigidGuideway::new(DT);
    let s = settings(83.33, 0.2, vec![15.0]);
    let out = run(&mut g, &train, &s, &mut midspan());
    let r: RailOutcome = out.rail.expect("the 3-D cars' record");
    let car = HsrCar::zhai_high_speed();
    let p0 = car.wheel_load(GRAVITY);
    // A centred conical wheel at rest: the normal force's lateral lean and the spin creep
    // force leave each wheel a lateral force, equal and opposite on the two wheels.
    let rest = Running::new(&car, 83.33, GRAVITY).unwrap();
    let (y_left, q_rest) = (rest.rest_wheel(0).lateral, rest.rest_wheel(0).vertical);
    assert!((rest.rest_wheel(1).lateral + y_left).abs() < 1e-9 * p0);
    assert_eq!((r.lateral.len(), r.lateral[0].len()), (16, 101));
    for w in 0..16 {
        let y0 = if w % 2 == 0 { y_left } else { -y_left };
        for (y, q) in r.lateral[w].iter().zip(&r.vertical[w]) {
            assert!(
                (y - y0).abs() < 1e-9 * p0,
                "wheel {w}: Y = {y} against {y0}"
            );
            assert!(
                (q - q_rest).abs() < 1e-9 * p0,
                "wheel {w}: Q = {q} against {q_rest}"
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

/// One car on its track on a rigid guideway over one vertical cosine of both rails (5 µm at
/// the wavelength that drives the wheels at the P2 resonance, v/λ = 64 Hz): the amplitude of
/// every wheel's force at the drive frequency against the closed form of one wheel on the rail
/// mass, written here: the wheel (half the wheelset, M) on the primary spring and damper to
/// the bogie (held still: it moves by under 1 % of the wheel at 65 Hz), on the Hertz spring
/// linearised at the static load, k_H cos²δ, on the rail mass m_e with 1/c̄ and c_e to the
/// deck. With r the rail head's cosine and e^{iωt}:
///
/// ```text
/// −Mω² x = −(k1 + iωc1) x + k_H (u + r − x),   −m_e ω² u = −k_H (u + r − x) − (k_e + iωc_e) u
/// ```
///
/// and Q = k_H (u + r − x). The force less its mean is projected on the drive frequency over
/// the last 0.5 s (32 of its periods), after the start's transient (decay time
/// 1/(ζω) ≈ 0.02 s). Dense fastenings (a/16) make the support uniform.
#[test]
fn the_wheel_force_at_the_p2_resonance_is_the_rail_mass_models() {
    use maglev_core::irregularity::Term;
    use maglev_sim::physics::cars::wheel_rail::zhai_g;
    use maglev_sim::physics::rail::irregularity::RailIrregularity;
    use maglev_sim::physics::rail::rail_mass::RailMass;
    use nalgebra::{Complex, Matrix2, Vector2};
    let base = SlabTrack::crts2();
    let track = SlabTrack {
        pad_stiffness: base.pad_stiffness / 16.0,
        pad_damping: base.pad_damping / 16.0,
        pad_spacing: base.pad_spacing / 16.0,
        ..base
    };
    let support = TrackSupport::new(&track).unwrap();
    let car = HsrCar::zhai_high_speed();
    let p0 = car.wheel_load(GRAVITY);
    let rail = RailMass::new(&support, p0);
    let (v, amp) = (83.33, 5e-6);
    let w = &car.wheelset;
    let cone = w.conicity.atan();
    let k_h = 1.5 * (p0 / cone.cos()).cbrt() / zhai_g(w.r0) * cone.cos().powi(2);
    let (k1, c1) = (car.primary.k[2], car.primary.c[2]);
    let (ke, ce, me, mw) = (1.0 / support.mean(), rail.damping, rail.mass, 0.5 * w.mass);
    let q_amp = |omega: f64| -> f64 {
        let i = Complex::new(0.0, 1.0);
        let c = |x: f64| Complex::new(x, 0.0);
        let a = Matrix2::new(
            c(k1 + k_h - mw * omega * omega) + i * c1 * omega,
            c(-k_h),
            c(-k_h),
            c(k_h + ke - me * omega * omega) + i * ce * omega,
        );
        let rhs = Vector2::new(c(k_h * amp), c(-k_h * amp));
        let xu = a.lu().solve(&rhs).unwrap();
        (c(k_h) * (xu[1] + amp - xu[0])).norm()
    };
    let f = 64.0;
    let omega = 2.0 * std::f64::consts::PI * f;
    let vertical = vec![Term {
        freq: f / v,
        amp,
        phase: 0.0,
    }];
    let irregularity =
        RailIrregularity::from_terms(&[vertical, vec![], vec![], vec![]], -50.0, 200.0).unwrap();
    let mut spec = spec(1, Some(support), 4);
    spec.irregularity = Some(irregularity);
    let train = Train::rail_cars(spec);
    let mut g = RigidGuideway::new(DT);
    let t_end = 1.0;
    let s = settings(v, t_end, vec![15.0]);
    let out = run(&mut g, &train, &s, &mut midspan());
    let r: RailOutcome = out.rail.expect("the 3-D cars' record");
    assert_eq!(r.lift_off_steps, 0);
    let n = (0.5 / DT).round() as usize;
    let want = q_amp(omega);
    for (wheel, q) in r.vertical.iter().enumerate() {
        let tail = &q[q.len() - n..];
        let mean = tail.iter().sum::<f64>() / n as f64;
        let t0 = (q.len() - n) as f64 * DT;
        let (mut cs, mut sn) = (0.0, 0.0);
        for (j, q) in tail.iter().enumerate() {
            let phase = omega * (t0 + j as f64 * DT);
            cs += (q - mean) * phase.cos();
            sn += (q - mean) * phase.sin();
        }
        let got = 2.0 * (cs * cs + sn * sn).sqrt() / n as f64;
        println!("wheel {wheel}: |Q| at {f} Hz {got:.2} N, closed form {want:.2} N");
        assert!(
            (got / want - 1.0).abs() < 0.01,
            "wheel {wheel}: {got} against {want}"
        );
    }
}
