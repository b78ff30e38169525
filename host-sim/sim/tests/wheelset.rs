//! One wheelset on rigid rails (`physics::rail::contact`, `wheelset`): the contact
//! mechanics against closed forms and hand values, and a free wheelset's kinematic
//! (Klingel) oscillation.

use maglev_sim::physics::rail::contact::{
    creep_forces, elliptic_ke, hertz_ellipse, kalker, she, Creepage, Ellipse, Material, KALKER,
};
use maglev_sim::physics::rail::wheelset::{rk4, Motion, RailPoint, Wheelset};
use std::f64::consts::{PI, TAU};

/// K and E at known points (Abramowitz & Stegun Table 17.1: k² = ½).
#[test]
fn elliptic_integrals_at_tabulated_points() {
    let (k, e) = elliptic_ke(0.0);
    assert!((k - PI / 2.0).abs() < 1e-15 && (e - PI / 2.0).abs() < 1e-15);
    let (k, e) = elliptic_ke(0.5f64.sqrt());
    assert!((k - 1.854_074_677_301_372).abs() < 1e-13, "{k}");
    assert!((e - 1.350_643_881_047_675).abs() < 1e-13, "{e}");
}

/// Hertz: equal curvatures give the circle a³ = 3NR/(4E*) (a sphere of radius R on a
/// plane, A = B = 1/(2R)); unequal ones satisfy the ellipse's two relations, written here
/// again from Johnson (4.39) in the load form P = (2/3)πab·p0.
#[test]
fn hertz_ellipse_against_closed_forms() {
    let m = Material::default();
    let (n, r) = (7.0e4, 0.45);
    let e = hertz_ellipse(n, 0.5 / r, 0.5 / r, &m);
    let a = (3.0 * n * r / (4.0 * m.e_star())).cbrt();
    assert!((e.a / a - 1.0).abs() < 1e-9 && (e.b / a - 1.0).abs() < 1e-9);
    let (ca, cb) = (0.5 / 0.4575, 0.5 / 0.3);
    let e = hertz_ellipse(n, ca, cb, &m);
    assert!(
        e.a > e.b,
        "the longer axis lies along the smaller curvature"
    );
    let ecc = (1.0 - (e.b / e.a).powi(2)).sqrt();
    let (k, el) = elliptic_ke(ecc);
    let p0 = 3.0 * n / (2.0 * PI * e.a * e.b);
    let common = p0 / m.e_star() * e.b / (ecc * ecc * e.a * e.a);
    assert!((common * (k - el) / ca - 1.0).abs() < 1e-9);
    assert!((common * ((e.a / e.b).powi(2) * el - k) / cb - 1.0).abs() < 1e-9);
}

/// Kalker at a/b = 1 is the table's row, scaled by G·c^n; between rows, linear.
#[test]
fn kalker_coefficients_from_the_table() {
    let m = Material::default();
    let c = 5e-3;
    let f = kalker(&Ellipse { a: c, b: c }, &m);
    let g = m.shear();
    let row = KALKER[9];
    assert_eq!(row[0], 1.0);
    let want = [
        g * c * c * row[1],
        g * c * c * row[2],
        g * c.powi(3) * row[3],
        g * c.powi(4) * row[4],
    ];
    for (f, w) in f.iter().zip(want) {
        assert!((f / w - 1.0).abs() < 1e-12);
    }
    let half = kalker(&Ellipse { a: 0.55 * c, b: c }, &m);
    let c11 = g * 0.55 * c * c * 0.5 * (3.862 + 3.958);
    assert!((half[0] / c11 - 1.0).abs() < 1e-12);
}

/// Shen–Hedrick–Elkins by hand: linear for small F0, 19/27 μN at F0 = μN, μN from 3μN on;
/// a creep force far beyond friction is μN along the linear force's direction.
#[test]
fn shen_hedrick_elkins_by_hand() {
    let limit = 1.0e4;
    assert!((she(1.0, limit) / (1.0 - 1.0 / 3e4) - 1.0).abs() < 1e-9);
    assert!((she(limit, limit) - 19.0 / 27.0 * limit).abs() < 1e-9);
    assert_eq!(she(3.0 * limit, limit), limit);
    assert_eq!(she(10.0 * limit, limit), limit);
    let f = [1e7, 8e6, 2e3, 30.0];
    let c = Creepage {
        x: 0.03,
        y: -0.04,
        spin: 0.0,
    };
    let out = creep_forces(&c, &f, 5e4, 0.3);
    assert!((out.fx.hypot(out.fy) - 0.3 * 5e4).abs() < 1e-6);
    assert!((out.fy / out.fx - (-8e6 * -0.04) / (-1e7 * 0.03)).abs() < 1e-12);
    assert_eq!(creep_forces(&c, &f, 0.0, 0.3).fx, 0.0);
}

const G: f64 = 9.81;

/// The static wheel load of the high-speed car (docs/cars.md): its 45.6 t over 8 wheels.
fn p0() -> f64 {
    (34_000.0 + 2.0 * 3_000.0 + 4.0 * 1_400.0) * G / 8.0
}

/// Flange contact beyond the clearance, and loss of contact: a wheelset 10 mm to the left
/// (clearance 8 mm) has the left flange force −k_f·2 mm; lifted 1 mm off its rails it has
/// no force at all.
#[test]
fn flange_and_loss_of_contact() {
    let w = Wheelset::high_speed();
    let rails = [RailPoint::default(); 2];
    let m = Motion {
        q: [0.010, 0.0, 0.0, 0.0],
        dq: [0.0; 4],
    };
    let f = w.contact(p0()).forces(&m, 50.0, &rails);
    assert!((f.wheels[0].flange + w.flange_stiffness * 0.002).abs() < 1e-6);
    assert_eq!(f.wheels[1].flange, 0.0);
    let lifted = Motion {
        q: [0.0, 0.001, 0.0, 0.0],
        dq: [0.0; 4],
    };
    let f = w.contact(p0()).forces(&lifted, 50.0, &rails);
    assert!(f
        .wheels
        .iter()
        .all(|w| w.normal == 0.0 && w.creep.fy == 0.0));
    assert_eq!(f.generalised, [0.0; 4]);
}

/// At rest on smooth rails, centred, the static solution carries the car's wheel load: each
/// wheel's vertical force is p0 and they sum to the axle's share.
#[test]
fn centred_wheelset_settles_under_the_wheel_load() {
    let w = Wheelset::high_speed();
    let axle = 2.0 * p0() - w.mass * G;
    let c = w.contact(p0());
    let m = c.settle(0.0, 0.0, 50.0, axle, G).unwrap();
    let f = c.forces(&m, 50.0, &[RailPoint::default(); 2]);
    for wheel in f.wheels {
        assert!((wheel.vertical / p0() - 1.0).abs() < 1e-3, "{wheel:?}");
    }
    assert!((f.generalised[1] - 2.0 * p0()).abs() < 1e-3);
}

/// The wavelength of a free wheelset (no suspension) released `y0` off centre at `v`, from
/// the upward zero crossings of y(x) (linear interpolation between steps), and its peak |y|.
fn free_wavelength(w: &Wheelset, v: f64, y0: f64, waves: f64) -> (f64, f64) {
    let dt = 2e-4;
    let axle = 2.0 * p0() - w.mass * G;
    let c = w.contact(p0());
    let start = c.settle(y0, 0.0, v, axle, G).unwrap();
    let rails = [RailPoint::default(); 2];
    let mut x = [0.0; 8];
    x[..4].copy_from_slice(&start.q);
    let klingel = TAU * (w.r0 * w.b / w.conicity).sqrt();
    let steps = (waves * klingel / v / dt) as usize;
    let mut crossings = Vec::new();
    let mut peak = 0.0f64;
    for step in 0..steps {
        let before = x[0];
        rk4(&mut x, dt, |_, s| {
            let m = Motion {
                q: [s[0], s[1], s[2], s[3]],
                dq: [s[4], s[5], s[6], s[7]],
            };
            let a = c.accelerations(&m, v, &rails, axle, G);
            [s[4], s[5], s[6], s[7], a[0], a[1], a[2], a[3]]
        });
        peak = peak.max(x[0].abs());
        if before < 0.0 && x[0] >= 0.0 {
            crossings.push((step as f64 + before / (before - x[0])) * dt * v);
        }
    }
    assert!(crossings.len() >= 3, "{crossings:?}");
    let n = crossings.len() - 1;
    ((crossings[n] - crossings[0]) / n as f64, peak)
}

/// Klingel: a free wheelset released 1 mm off centre at 5 m/s rolls in the kinematic sine
/// wave.
///
/// Kinematic motion (no slip at the contacts) holds when the creep forces dominate the
/// inertial and gravitational ones. At the wavenumber k = 2π/L the inertia m v² k² is about
/// 5e3 N/m and the gravitational stiffness about 2Wλ/b ≈ 1.5e4 N/m, against the creep
/// stiffness 2 f22 k ≈ 6e6 N/m: at 5 m/s the creepages stay below 1e-3 of the kinematic
/// motion.
///
/// No lateral slip means ẏ + r0 φ̇ = vψ: the contact point lies r0 below the axle, and
/// the roll φ = λy/b that the radius difference imposes moves it by r0 φ̇. No longitudinal
/// slip gives ψ̇ = −vλy/(b r0). Together, L = 2π√(r0 b (1 + r0λ/b)/λ). Klingel's
/// 2π√(r0 b/λ) leaves out the roll term: it is the limit r0λ/b → 0, and it is short by
/// √(1 + r0λ/b) − 1, 1.5 % at λ = 0.05 and 0.6 % at λ = 0.02. So the run is checked
/// against the wavelength with the roll term, tightly, at λ = 0.05, and against Klingel's
/// formula within 1 % at λ = 0.02.
#[test]
fn free_wheelset_rolls_in_the_klingel_wavelength() {
    for (conicity, against_roll) in [(0.05, 1e-3), (0.02, 1e-3)] {
        let mut w = Wheelset::high_speed();
        w.conicity = conicity;
        let (wavelength, peak) = free_wavelength(&w, 5.0, 1e-3, 4.6);
        let klingel = TAU * (w.r0 * w.b / w.conicity).sqrt();
        let with_roll = klingel * (1.0 + w.r0 * w.conicity / w.b).sqrt();
        println!(
            "λ = {conicity}: Klingel {klingel:.4} m, with the roll term {with_roll:.4} m, measured \
             {wavelength:.4} m ({:+.3} % against Klingel, {:+.4} % against the roll term), peak |y| \
             {:.3} mm",
            100.0 * (wavelength / klingel - 1.0),
            100.0 * (wavelength / with_roll - 1.0),
            peak * 1e3
        );
        assert!(peak < w.flange_clearance, "the flange must not be reached");
        assert!((wavelength / with_roll - 1.0).abs() < against_roll);
        if conicity <= 0.02 {
            assert!((wavelength / klingel - 1.0).abs() < 0.01);
        }
    }
}
