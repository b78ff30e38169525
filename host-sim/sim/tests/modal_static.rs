//! (d), (e) Quasi-static limits: a force crossing the §4.2 span at 0.01 m/s, read when it is
//! at midspan, against the closed-form static Timoshenko solutions:
//!
//! - midspan deflection P L³/(48 E I) + P L/(4 G A_s) (bending + shear);
//! - support rotation P L²/(16 E I) (bending only), with the FE's signs (docs/model.md §5):
//!   θy = −∂w/∂x, θz = +∂v/∂x;
//! - midspan twist T L/(4 G J) for a central torque T = ey·Fz − ez·Fy, and the rigid-link
//!   point motion z = w + θ·ey, y = v − θ·ez.
//!
//! The N-term series reaches these with a truncation error that the tests compute exactly
//! (from the Fourier coefficients of the static solutions, not from the code): deflection and
//! twist tails ∝ Σ_{odd n > N} 1/n² (slow, ~1/N), bending tail ∝ Σ 1/n⁴. The dynamic part
//! at v = 0.01 m/s is a free vibration of relative size ≈ Ω₁/ω₁ = (πv/L)/ω₁ ≈ 3.3e-5
//! (bending) and ≈ 1e-5 (torsion), so the tolerance on top of the tail is 1e-4 of the static
//! value. Δt = 1e-2 s: quasi-static, Newmark is unconditionally stable and the slowly
//! varying load excites no term appreciably.
mod modal_common;

use maglev_sim::physics::guideway::{BeamSection, Guideway, PointLoad};
use maglev_sim::physics::modal::{ModalGuideway, DEFAULT_MODES};
use modal_common::{run_moving_load, L, P};
use std::f64::consts::PI;

const SPEED: f64 = 0.01;
const DT: f64 = 1e-2;
const DYNAMIC: f64 = 1e-4;

/// Σ_{odd n ≤ N} 1/n^p (pure arithmetic).
fn odd_sum(n_max: usize, p: i32) -> f64 {
    (1..=n_max)
        .filter(|n| n % 2 == 1)
        .map(|n| 1.0 / (n as f64).powi(p))
        .sum()
}

/// Quasi-static state with the load at midspan: (section motion, rotations at x = 0,
/// point motion at (ey, ez)).
struct AtMidspan {
    z: f64,
    y: f64,
    rx: f64,
    ry0: f64,
    rz0: f64,
    pz: f64,
    py: f64,
}

fn slow_crossing(modes: usize, load: PointLoad) -> AtMidspan {
    let mut g = ModalGuideway::new(BeamSection::paper_4_2(), L, modes, DT).unwrap();
    run_moving_load(&mut g, load, SPEED, L / 2.0, |_| 0.0);
    let s = g.section_at(L / 2.0);
    let (ry0, rz0) = g.rotations_at(0.0);
    let p = g.motion_at(L / 2.0, load.ey, load.ez);
    AtMidspan {
        z: s.z,
        y: s.y,
        rx: s.rx,
        ry0,
        rz0,
        pz: p.z,
        py: p.y,
    }
}

fn check(what: &str, got: f64, closed: f64, tail: f64) {
    let err = got - closed;
    println!(
        "{what:28} got {got:+.7e}  closed form {closed:+.7e}  rel. err {:+.3e}  (series tail {:+.3e})",
        err / closed.abs(),
        tail / closed.abs()
    );
    assert!(
        err.abs() <= tail.abs() + DYNAMIC * closed.abs(),
        "{what}: {got} vs {closed}, allowed tail {tail}"
    );
}

#[test]
fn central_force_gives_static_timoshenko_deflection_and_rotation() {
    let s = BeamSection::paper_4_2();
    let ei = s.youngs_modulus * s.iy;
    let gas = s.shear_modulus * s.shear_area_z;
    let bending = P * L.powi(3) / (48.0 * ei);
    let shear = P * L / (4.0 * gas);
    for modes in [10, 40, 160] {
        let r = slow_crossing(
            modes,
            PointLoad {
                fz: -P,
                ..Default::default()
            },
        );
        // Static coefficient of term n (odd) under a central force: (2P/L)(1/(EI k⁴) + 1/(G A_s k²)).
        let series = 2.0 * P / L
            * ((L / PI).powi(4) / ei * odd_sum(modes, 4)
                + (L / PI).powi(2) / gas * odd_sum(modes, 2));
        let closed = -(bending + shear);
        println!(
            "N = {modes}: shear share of the static deflection {:.2} %",
            100.0 * shear / (bending + shear)
        );
        check(
            &format!("w(L/2), N = {modes}"),
            r.z,
            closed,
            -series - closed,
        );
        // φ(0) = Σ (2P/L) sin(nπ/2)/(EI k³): alternating, tail ≤ first omitted term.
        let first_omitted = 2.0 * P / L * (L / (PI * (modes + 1) as f64)).powi(3) / ei;
        check(
            &format!("θy(0), N = {modes}"),
            r.ry0,
            P * L * L / (16.0 * ei),
            first_omitted,
        );
        assert!(
            r.y.abs() < 1e-12 && r.rx.abs() < 1e-12,
            "no lateral/torsion response expected"
        );
    }
}

#[test]
fn eccentric_forces_give_static_twist_and_link_motion() {
    let s = BeamSection::paper_4_2();
    let gj = s.shear_modulus * s.torsion_constant;
    let eiz = s.youngs_modulus * s.iz;
    let gasy = s.shear_modulus * s.shear_area_y;
    // Downward P at 1.5 m off the axis (the §4.2 eccentricity) and 0.6 m above it, plus a
    // lateral H = 0.2 P at the same point.
    let h = 0.2 * P;
    let load = PointLoad {
        x: 0.0,
        ey: 1.5,
        ez: 0.6,
        fy: h,
        fz: -P,
    };
    let torque = load.ey * load.fz - load.ez * load.fy;
    // Twist under the torque: tail ≈ 0.4/N of the value (1 % at 40, 0.25 % at 160).
    for modes in [40, DEFAULT_MODES] {
        let r = slow_crossing(modes, load);

        let twist = torque * L / (4.0 * gj);
        let twist_series = 2.0 * torque / L * (L / PI).powi(2) / gj * odd_sum(modes, 2);
        check(
            &format!("θx(L/2), N = {modes}"),
            r.rx,
            twist,
            twist_series - twist,
        );

        let lateral = h * L.powi(3) / (48.0 * eiz) + h * L / (4.0 * gasy);
        let lateral_series = 2.0 * h / L
            * ((L / PI).powi(4) / eiz * odd_sum(modes, 4)
                + (L / PI).powi(2) / gasy * odd_sum(modes, 2));
        check(
            &format!("v(L/2), N = {modes}"),
            r.y,
            lateral,
            lateral_series - lateral,
        );
        let first_omitted = 2.0 * h / L * (L / (PI * (modes + 1) as f64)).powi(3) / eiz;
        check(
            &format!("θz(0), N = {modes}"),
            r.rz0,
            h * L * L / (16.0 * eiz),
            first_omitted,
        );

        // Rigid link (docs/model.md §5): exact relation on the same state, so only rounding allowed.
        assert!((r.pz - (r.z + r.rx * load.ey)).abs() < 1e-15);
        assert!((r.py - (r.y - r.rx * load.ez)).abs() < 1e-15);
        // Signs: the downward force at +ey twists the section negatively about X and the link
        // point goes down more than the axis.
        assert!(r.rx < 0.0 && r.pz < r.z);
        println!("link point at (ey, ez) = (1.5, 0.6): z {:+.6e} m (axis {:+.6e}), y {:+.6e} m (axis {:+.6e})", r.pz, r.z, r.py, r.y);
    }
}
