//! The magnet–rail contact (docs/contact.md) against the closed form of a one-sided
//! Kelvin–Voigt contact: a rigid magnet with its coil off falls under gravity onto its skid
//! (the paper's geometry: the gap closes as the magnet falls), rebounds and settles. The truth
//! is the analytic solution of `m ẍ = m g − k x − c ẋ` from the first touch (x the
//! penetration) until the contact force `k x + c ẋ` reaches zero, then free flight: its peak
//! force, its lowest gap, the height of the first rebound, the static penetration `m g / k`
//! it settles at, and the friction drag `μ N` while the magnet slides at speed.
//!
//! The set-down stop (Eq. C3): an EMS magnet hanging under its rail with its coil off falls
//! away from the rail, its gap opening from h0 to the set-down gap `h_d` in the free-fall time
//! `√(2 (h_d − h0)/g)`, and comes to rest on the guideway, whose load is then the weight.

use maglev_core::gap::Geometry;
use maglev_core::{LawKind, Params, Status};
use maglev_sim::physics::guideway::{
    Guideway, PointLoad, PointMotion, RigidGuideway, SectionMotion,
};
use maglev_sim::physics::skid::Skid;
use maglev_sim::physics::train::Train;
use maglev_sim::physics::vehicle::{Unit, VehicleModel};
use maglev_sim::probes::{Recorder, StepView, Wheels};
use maglev_sim::simulation::{couple, Magnets, Outcome, Profiles, Settings, WheelGaps};
use maglev_sim::Result;

const G: f64 = 9.81;
const MASS: f64 = 600.0;
const H0: f64 = 0.01;
const DT: f64 = 1e-5;

/// A magnet whose coil is off: no force at any gap.
struct CoilOff;

impl Magnets for CoilOff {
    fn start(&mut self, _: &maglev_sim::simulation::Start<'_>) -> Result<()> {
        Ok(())
    }

    fn forces(
        &mut self,
        _: u32,
        _: f64,
        _: &[WheelGaps],
        _: &[WheelGaps],
        _: &[f64],
        out: &mut [(f64, f64)],
    ) -> Result<()> {
        out.fill((0.0, 0.0));
        Ok(())
    }
    fn commit(&mut self, _: u32, _: f64) -> Result<()> {
        Ok(())
    }
    fn status(&self) -> Status {
        Status::default()
    }
}

/// Every committed step's levitation gap.
struct Gaps(Vec<f64>);

impl Recorder for Gaps {
    fn record(&mut self, s: &StepView) -> Result<()> {
        if let Wheels::Vehicle { gaps, .. } = &s.wheels {
            self.0.push(gaps[0].0);
        }
        Ok(())
    }
}

fn skid() -> Skid {
    // ζ = 0.1 on the 600 kg magnet: c = 2ζ√(k m).
    let k = 1e8;
    Skid {
        gap: 0.002,
        setdown: 0.02,
        stiffness: k,
        damping: 2.0 * 0.1 * (k * MASS).sqrt(),
        friction: 0.3,
        slip: 0.01,
    }
}

/// The rigid guideway, keeping the loads of its last solved pass (what the magnets put on it).
struct Loads {
    rigid: RigidGuideway,
    last: Vec<PointLoad>,
}

impl Guideway for Loads {
    fn time_step(&self) -> f64 {
        self.rigid.time_step()
    }
    fn solve_step(&mut self, loads: &[PointLoad]) {
        self.last = loads.to_vec();
    }
    fn motion_at(&self, x: f64, ey: f64, ez: f64) -> PointMotion {
        self.rigid.motion_at(x, ey, ez)
    }
    fn section_at(&self, x: f64) -> SectionMotion {
        self.rigid.section_at(x)
    }
    fn commit(&mut self) {}
}

fn drop(skid: Skid, speed: f64, t_end: f64) -> (Outcome, Vec<f64>) {
    let (o, gaps, _) = drop_in(Geometry::Paper, skid, speed, t_end);
    (o, gaps)
}

/// The magnet released at h0 in `geometry`: the outcome, every committed gap, and the
/// guideway's load at the magnet in the last step (N, Z up).
fn drop_in(geometry: Geometry, skid: Skid, speed: f64, t_end: f64) -> (Outcome, Vec<f64>, f64) {
    let unit = Unit {
        magnet_mass: MASS,
        body_mass: 0.0,
        k: 0.0,
        c: 0.0,
        position: 0.0,
    };
    let train = Train::from_cars(vec![VehicleModel::unit(&unit, G).unwrap()]);
    let s = Settings {
        speed,
        dt: DT,
        t_end,
        controller: Params::paper(MASS * G, DT),
        law: LawKind::Paper,
        guidance: None,
        geometry,
        tolerance: 1e-13,
        max_iterations: 50,
        midspan_x: 0.0,
        midspans: Vec::new(),
        skid,
    };
    let mut g = Loads {
        rigid: RigidGuideway::new(DT),
        last: Vec::new(),
    };
    let mut rec = Gaps(Vec::new());
    let o = couple(
        &mut g,
        &train,
        &Profiles::smooth(),
        &s,
        &mut CoilOff,
        &mut rec,
        &mut (),
    )
    .unwrap();
    (o, rec.0, g.last[0].fz)
}

/// The closed form of the first contact: its peak force, its largest penetration, and the
/// penetration and velocity (m, m/s, into the rail positive) when the force reaches zero.
struct FirstContact {
    peak_force: f64,
    max_penetration: f64,
    apex_above_skid: f64,
}

fn closed_form(s: &Skid) -> FirstContact {
    let (k, c) = (s.stiffness, s.damping);
    let w0 = (k / MASS).sqrt();
    let zeta = c / (2.0 * (k * MASS).sqrt());
    let beta = zeta * w0;
    let wd = w0 * (1.0 - zeta * zeta).sqrt();
    let xs = G / (w0 * w0);
    // Free fall from h0 to the skid (Newmark's average acceleration is exact here).
    let v0 = (2.0 * G * (H0 - s.gap)).sqrt();
    let (a, b) = (-xs, (v0 - beta * xs) / wd);
    let x = |t: f64| xs + (-beta * t).exp() * (a * (wd * t).cos() + b * (wd * t).sin());
    let v = |t: f64| {
        (-beta * t).exp()
            * ((b * wd - beta * a) * (wd * t).cos() - (a * wd + beta * b) * (wd * t).sin())
    };
    let force = |t: f64| k * x(t) + c * v(t);
    // Dense sampling of the analytic solution until the force first returns to zero, then
    // the crossing by bisection.
    let (mut peak_force, mut max_pen, mut t) = (0.0f64, 0.0f64, 0.0);
    let h = 1e-3 / wd;
    while force(t + h) > 0.0 {
        t += h;
        peak_force = peak_force.max(force(t));
        max_pen = max_pen.max(x(t));
    }
    let (mut lo, mut hi) = (t, t + h);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if force(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let (x1, v1) = (x(hi), v(hi));
    FirstContact {
        peak_force,
        max_penetration: max_pen,
        // Leaving at penetration x1 with velocity v1 (< 0: out of the rail), the magnet rises
        // v1²/(2g) above where it left.
        apex_above_skid: v1 * v1 / (2.0 * G) - x1,
    }
}

/// The first contact (t < 0.1 s): the gaps around the first touch, and the apex of the
/// rebound after it.
fn first_bounce(s: &Skid, gaps: &[f64]) -> (f64, f64) {
    let touch = gaps
        .iter()
        .position(|&h| h < s.gap)
        .expect("the magnet lands");
    let leave = touch
        + gaps[touch..]
            .iter()
            .position(|&h| h >= s.gap)
            .expect("it rebounds");
    let lowest = gaps[touch..leave]
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    let back = leave
        + gaps[leave..]
            .iter()
            .position(|&h| h < s.gap)
            .expect("lands again");
    let apex = gaps[leave..back]
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    (lowest, apex)
}

#[test]
fn a_dropped_magnet_rebounds_and_settles_as_the_closed_form_says() {
    let s = skid();
    let truth = closed_form(&s);
    let (o, gaps) = drop(s, 0.0, 0.6);
    assert_eq!(o.unconverged_steps, 0);
    let (lowest, apex) = first_bounce(&s, &gaps);
    let pen = s.gap - lowest;
    let rel = |a: f64, b: f64| ((a - b) / b).abs();
    assert!(
        rel(pen, truth.max_penetration) < 1e-3,
        "largest penetration {pen:e} m, closed form {:e} m",
        truth.max_penetration
    );
    let rebound = apex - s.gap;
    assert!(
        rel(rebound, truth.apex_above_skid) < 3e-3,
        "rebound {rebound:e} m, closed form {:e} m (restitution)",
        truth.apex_above_skid
    );
    let peak = o.skids.per_magnet[0][0].peak_normal;
    assert!(
        rel(peak, truth.peak_force) < 3e-3,
        "peak force {peak} N, closed form {} N",
        truth.peak_force
    );
    // At rest on the skid: the static penetration m g / k.
    let last = *gaps.last().unwrap();
    let settled = s.gap - MASS * G / s.stiffness;
    assert!(
        (last - settled).abs() < 1e-3 * (MASS * G / s.stiffness),
        "settled at {last:e} m, static {settled:e} m"
    );
    // Every step on the skid is counted; the run collided.
    assert!(o.collision_steps > 0 && o.skids.steps == o.collision_steps);
}

#[test]
fn the_sliding_skid_drags_with_mu_n() {
    let s = skid();
    let (o, _) = drop(s, 50.0, 0.1);
    let r = o.skids.per_magnet[0][0];
    assert!(r.steps > 0);
    let want = s.friction * r.peak_normal;
    assert!(
        ((r.peak_drag - want) / want).abs() < 1e-6,
        "drag {} N, μ·N = {want} N",
        r.peak_drag
    );
    // The vertical motion does not depend on the speed (a unit has no lateral DOF).
    let (rest, _) = drop(s, 0.0, 0.1);
    assert_eq!(rest.skids.per_magnet[0][0].peak_normal, r.peak_normal);
}

/// The gap (m) of the released magnet at `t` ≥ Δt: the coil's force is `m g` at the committed
/// t = 0 and zero from t = Δt, which the step's trapezoid rule sees as a release ramped over
/// the first step. Exactly, the fall under that ramp is `g/2 (t − Δt/2)² + g Δt²/24`
/// (Newmark's average acceleration gives `g Δt²/8` for the constant: 1e-10 m here).
fn released(t: f64) -> f64 {
    H0 + 0.5 * G * (t - 0.5 * DT).powi(2) + G * DT * DT / 24.0
}

/// An EMS magnet with its coil off falls away from its rail onto the set-down stop: the gap
/// reaches `h_d` at the free-fall time `√(2 (h_d − h0)/g)` delayed by the half step of the
/// release ([`released`]), the first contact is in the step that crosses it, and at rest the
/// guideway carries the weight `m g` with the stop compressed by `m g / k`. The rail-side
/// skid never touches.
#[test]
fn a_released_ems_magnet_sets_down_on_the_guideway() {
    let s = skid();
    // 1.2 s: the bounces on the stop end by about 0.4 s (restitution 0.73 at ζ = 0.1), the
    // oscillation in contact decays as e^(−ζωt) after.
    let (o, gaps, load) = drop_in(Geometry::Ems, s, 0.0, 1.2);
    assert_eq!(o.unconverged_steps, 0);
    // The crossing of h_d, linear between the two committed gaps around it.
    let n = gaps
        .iter()
        .position(|&h| h > s.setdown)
        .expect("it sets down");
    let (a, b) = (gaps[n - 1], gaps[n]);
    // gaps[k] is the gap at t = k·Δt (the first record is the start, t = 0).
    let t_cross = ((n - 1) as f64 + (s.setdown - a) / (b - a)) * DT;
    // √(2s/g) after the half step of the release, s less the ramp's g Δt²/24.
    let s_fall = s.setdown - released(0.5 * DT);
    let t_fall = 0.5 * DT + (2.0 * s_fall / G).sqrt();
    assert!(
        ((t_cross - t_fall) / t_fall).abs() < 1e-6,
        "drop time {t_cross} s, free fall {t_fall} s (√(2s/g) = {} s)",
        (2.0 * (s.setdown - H0) / G).sqrt()
    );
    let r = o.skids.per_magnet[0];
    let first = r[3].first_t.expect("the set-down stop carried a force");
    assert!(
        first >= t_cross && first <= t_cross + DT,
        "first contact at {first} s, the gap crossed h_d at {t_cross} s"
    );
    assert_eq!(r[0].steps, 0, "the rail-side skid touched");
    // At rest: the guideway carries the weight through the stop.
    let weight = MASS * G;
    assert!(
        ((-load - weight) / weight).abs() < 1e-6,
        "the guideway's load {load} N, weight {weight} N"
    );
    let last = *gaps.last().unwrap();
    let settled = s.setdown + weight / s.stiffness;
    assert!(
        (last - settled).abs() < 1e-3 * (weight / s.stiffness),
        "settled at {last:e} m, static {settled:e} m"
    );
    assert!(o.collision_steps > 0 && o.skids.steps == o.collision_steps);
}

/// With the set-down stop out of reach (at 1 m) the same magnet falls freely: its gap at the
/// end is the parabola's, so the stop above is what held it.
#[test]
fn without_a_reachable_stop_the_magnet_falls_freely() {
    let s = Skid {
        setdown: 1.0,
        ..skid()
    };
    let t_end = 0.1;
    let (o, gaps, _) = drop_in(Geometry::Ems, s, 0.0, t_end);
    assert_eq!(o.skids.steps, 0);
    let want = released(t_end);
    let last = *gaps.last().unwrap();
    assert!(
        (last - want).abs() < 1e-9,
        "gap {last} m, free fall {want} m"
    );
}
