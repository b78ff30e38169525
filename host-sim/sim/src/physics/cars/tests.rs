//! Validation of the car models against independent truth: rigid motions, hand statics,
//! closed-form suspension frequencies, the Hertz formula (issue #10 item 3; docs/cars.md).

use super::fig6::{Fig6, BOGIES, PER_BOGIE};
use super::link::*;
use super::wheel_rail::{hertz_stiffness, zhai_g, WheelRail};
use super::*;
use crate::physics::vehicle::{add_link_spring, static_solution, Direction};
use nalgebra::{DMatrix, DVector};

const G: f64 = 9.81;

/// Displacement of point p under the rigid motion (t, θ) about the origin: t + θ × p.
fn rigid_at(t: [f64; 3], th: [f64; 3], p: [f64; 3]) -> [f64; 3] {
    [
        t[0] + th[1] * p[2] - th[2] * p[1],
        t[1] + th[2] * p[0] - th[0] * p[2],
        t[2] + th[0] * p[1] - th[1] * p[0],
    ]
}

/// `|K u|` relative to `max|K|·max|u|`.
fn rel_force(k: &DMatrix<f64>, u: &DVector<f64>) -> f64 {
    (k * u).amax() / (k.amax() * u.amax())
}

/// Symmetric generalized eigenvalues ω² of (K, M) on the DOFs `free` (M positive definite).
fn omega2(k: &DMatrix<f64>, m: &DMatrix<f64>, free: &[usize]) -> Vec<f64> {
    let sub =
        |a: &DMatrix<f64>| DMatrix::from_fn(free.len(), free.len(), |i, j| a[(free[i], free[j])]);
    let l = sub(m).cholesky().expect("mass positive definite").l();
    let li = l.clone().try_inverse().unwrap();
    let a = &li * sub(k) * li.transpose();
    let a = 0.5 * (&a + a.transpose());
    let mut ev: Vec<f64> = a.symmetric_eigen().eigenvalues.iter().copied().collect();
    ev.sort_by(f64::total_cmp);
    ev
}

/// Roots λ = ω² of det(K − λ M) = 0 for 2×2 K and diagonal M = diag(m1, m2): a hand quadratic.
fn two_dof(k11: f64, k12: f64, k22: f64, m1: f64, m2: f64) -> (f64, f64) {
    let (a, b, c) = (m1 * m2, -(m1 * k22 + m2 * k11), k11 * k22 - k12 * k12);
    let d = (b * b - 4.0 * a * c).sqrt();
    ((-b - d) / (2.0 * a), (-b + d) / (2.0 * a))
}

/// The eigenvalue of `ev` closest to `x`, relative distance.
fn nearest(ev: &[f64], x: f64) -> (f64, f64) {
    let e = ev
        .iter()
        .copied()
        .min_by(|a, b| (a - x).abs().total_cmp(&(b - x).abs()))
        .unwrap();
    (e, (e - x).abs() / x)
}

// ---------------------------------------------------------------- the link element (Eq. 18)

#[test]
fn link_element_is_eq18_of_the_fig1_vehicle() {
    // A Fig. 1-style body (v, w, θx, θy, θz = 0..5 at the origin) and a node (Y 5, Z 6):
    // the general element must give exactly vehicle::add_link_spring's matrix.
    let body = Rigid::new([0.0; 3])
        .dof(UY, 0)
        .dof(UZ, 1)
        .dof(RX, 2)
        .dof(RY, 3)
        .dof(RZ, 4);
    let p = [7.5, -1.5, -2.0];
    let node = Rigid::new(p).dof(UY, 5).dof(UZ, 6);
    for (axis, dir, dof) in [(Axis::Z, Direction::Z, 6), (Axis::Y, Direction::Y, 5)] {
        let (mut k, mut c) = (DMatrix::zeros(7, 7), DMatrix::zeros(7, 7));
        add_spring_damper(
            &mut k,
            &mut c,
            (2e5, 1e4),
            axis,
            End { body: &node, p },
            End { body: &body, p },
        )
        .unwrap();
        let mut want = DMatrix::zeros(7, 7);
        add_link_spring(&mut want, 2e5, dir, dof, [-p[0], -p[1], -p[2]]);
        assert!((&k - &want).amax() < 1e-9, "{axis:?}: {k} vs {want}");
        assert!((&c * 2e5 / 1e4 - &want).amax() < 1e-9);
    }
}

#[test]
fn an_element_with_ends_across_its_direction_is_refused() {
    let a = Rigid::new([0.0; 3]).dof(UY, 0).dof(RX, 1);
    let b = Rigid::new([0.0; 3]);
    let (mut k, mut c) = (DMatrix::zeros(2, 2), DMatrix::zeros(2, 2));
    // A Y spring between points 0.3 m apart in Z would be strained by a rigid roll.
    let e = add_spring_damper(
        &mut k,
        &mut c,
        (1.0, 1.0),
        Axis::Y,
        End {
            body: &a,
            p: [0.0, 0.0, 0.3],
        },
        End {
            body: &b,
            p: [0.0, 0.0, 0.0],
        },
    );
    assert!(e.unwrap_err().to_string().starts_with("car.element:"));
    // Ends apart along the direction are fine.
    add_spring_damper(
        &mut k,
        &mut c,
        (1.0, 1.0),
        Axis::Z,
        End {
            body: &a,
            p: [0.0, 0.0, 0.3],
        },
        End {
            body: &b,
            p: [0.0, 0.0, 0.0],
        },
    )
    .unwrap();
}

// ---------------------------------------------------------------- the Fig. 6 carriage

/// The rigid motion (t, θ) of the whole carriage as its DOF vector, from the geometry.
fn fig6_rigid(p: &Fig6, car: &VehicleModel, t: [f64; 3], th: [f64; 3]) -> DVector<f64> {
    let mut u = DVector::zeros(car.k.nrows());
    let (body, bogies) = p.bodies();
    for (base, at) in std::iter::once((0, body.at))
        .chain(bogies.iter().enumerate().map(|(b, g)| (5 + 5 * b, g.at)))
    {
        let d = rigid_at(t, th, at);
        u[base] = d[1];
        u[base + 1] = d[2];
        u[base + 2] = th[0];
        u[base + 3] = th[1];
        u[base + 4] = th[2];
    }
    let x_front = p.magnet_x(0, 0);
    for w in &car.wheels {
        let d = rigid_at(t, th, [w.x0 + x_front, w.ey, 0.0]);
        u[w.dof_y.unwrap()] = d[1];
        u[w.dof_z] = d[2];
    }
    u
}

#[test]
fn fig6_rigid_motions_strain_no_spring() {
    let p = Fig6::default();
    let car = p.build(G).unwrap();
    assert_eq!(car.k.nrows(), 5 + 5 * BOGIES + 4 * BOGIES * PER_BOGIE);
    let motions = [
        ([0.0, 0.01, 0.0], [0.0; 3]),
        ([0.0, 0.0, 0.02], [0.0; 3]),
        ([0.0; 3], [2e-3, 0.0, 0.0]),
        ([0.0; 3], [0.0, 1e-3, 0.0]),
        ([0.0; 3], [0.0, 0.0, 3e-3]),
        ([0.0, 0.01, -0.02], [2e-3, -1e-3, 3e-3]),
    ];
    for (t, th) in motions {
        let u = fig6_rigid(&p, &car, t, th);
        assert!(
            rel_force(&car.k, &u) < 1e-12,
            "{t:?} {th:?}: {}",
            rel_force(&car.k, &u)
        );
        assert!(rel_force(&car.c, &u) < 1e-12);
    }
    // The check can fail: one bogie lifted alone strains its springs.
    let mut u = DVector::zeros(car.k.nrows());
    u[5 + 1] = 0.01;
    assert!(rel_force(&car.k, &u) > 1e-3);
}

#[test]
fn fig6_layout_is_the_equal_pitch_of_fig6() {
    let p = Fig6::default();
    let car = p.build(G).unwrap();
    assert_eq!(car.wheels.len(), 32);
    // Sixteen X positions, 1.5625 m apart over 15 × 1.5625 = 23.4375 m, each a near/far pair.
    let mut xs: Vec<f64> = car.wheels.iter().map(|w| w.x0).collect();
    xs.sort_by(|a, b| b.total_cmp(a));
    xs.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    assert_eq!(xs.len(), 16);
    for pair in xs.windows(2) {
        assert!((pair[0] - pair[1] - 1.5625).abs() < 1e-12);
    }
    assert!((xs[0] - 0.0).abs() < 1e-12 && (xs[15] + 23.4375).abs() < 1e-12);
    assert_eq!((car.wheels[0].ey, car.wheels[1].ey), (1.25, 3.25));
    assert!(car.wheels.iter().all(|w| w.ez == 1.0));
    // The next carriage's leading magnet follows at one more pitch: 16 × 1.5625 = 25 m.
    assert_eq!(car.length, 25.0);
    // Bogie centres at ±3.125 and ±9.375 m: Fig. 6's "6.25 3.125 3.125 6.25"; secondary
    // stations 2.05 m apart, 4.2 m between bogies: "2.05 4.2 2.05 …".
    assert_eq!([p.bogie_x(0), p.bogie_x(1)], [9.375, 3.125]);
    let gap = (p.bogie_x(0) - p.station_half) - (p.bogie_x(1) + p.station_half);
    assert!((gap - 4.2).abs() < 1e-12 && (2.0 * p.station_half - 2.05).abs() < 1e-12);
}

#[test]
fn fig6_static_loads_are_equal_shares_of_the_weight() {
    for magnet_mass in [0.0, 40.0] {
        let p = Fig6 {
            magnet_mass,
            ..Fig6::default()
        };
        let car = p.build(G).unwrap();
        // Hand statics: the layout is symmetric fore–aft and left–right, every load path the
        // same, so each of the 32 magnets carries 1/32 of the carriage's weight.
        let hand = G * (p.body_mass + 4.0 * p.bogie_mass + 32.0 * magnet_mass) / 32.0;
        let sum: f64 = car.p0.iter().sum();
        assert!((sum - car.weight).abs() < 1e-9 * car.weight);
        for &p0 in &car.p0 {
            assert!((p0 - hand).abs() < 1e-9 * hand, "{p0} vs {hand}");
        }
    }
    // Default carriage: 50 t, 15 328 N per magnet.
    let car = Fig6::default().build(G).unwrap();
    assert!((car.p0[0] - 50.0e3 * G / 32.0).abs() < 1e-6);
}

#[test]
fn fig6_static_solution_has_no_lateral_reaction_and_a_hand_deflection() {
    let p = Fig6::default();
    let car = p.build(G).unwrap();
    let n = car.k.nrows();
    let (body, bogies) = p.bodies();
    let mut f = DVector::zeros(n);
    body.add_weight(&mut f, p.body_mass, G);
    for b in &bogies {
        b.add_weight(&mut f, p.bogie_mass, G);
    }
    let (u, r) = static_solution(&car.k, &f, &car.node_dofs()).unwrap();
    for w in &car.wheels {
        assert!(r[w.dof_y.unwrap()].abs() < 1e-9 * car.p0[0]);
    }
    // Body sag = body weight through 16 secondary springs + carriage weight through 32
    // primary ones (series springs, hand calculation).
    let sag = p.body_mass * G / (16.0 * p.k_sec_z)
        + (p.body_mass + 4.0 * p.bogie_mass) * G / (32.0 * p.k_pri_z);
    assert!(
        (u[car.body_z] + sag).abs() < 1e-9 * sag,
        "{} vs {}",
        u[car.body_z],
        -sag
    );
}

#[test]
fn fig6_body_bounce_and_pitch_on_held_magnets() {
    let p = Fig6::default();
    let car = p.build(G).unwrap();
    let free: Vec<usize> = (0..5 + 5 * BOGIES).collect();
    let ev = omega2(&car.k, &car.m, &free);
    // Bounce: body on 16 secondary springs, the 4 bogies on 32 primary ones — in the
    // symmetric heave the system is exactly this 2-DOF chain.
    let (k2, k1) = (16.0 * p.k_sec_z, 32.0 * p.k_pri_z);
    let (lo, hi) = two_dof(k2, -k2, k1 + k2, p.body_mass, 4.0 * p.bogie_mass);
    for x in [lo, hi] {
        let (_, rel) = nearest(&ev, x);
        assert!(rel < 1e-9, "bounce ω² {x}: {rel}");
    }
    // Body bounce 0.982 Hz (the same quadratic evaluated by hand).
    let f_bounce = lo.sqrt() / (2.0 * std::f64::consts::PI);
    assert!((f_bounce - 0.982).abs() < 0.001, "{f_bounce}");
    // Pitch: the body turning on its 4 × 2 × 2 secondary stations, each in series with its
    // bogie's primary support (bogie heave 4 k_p and pitch k_p Σξ² per side), condensed
    // statically — bogie inertia neglected, so this is a Rayleigh (upper) estimate, too high
    // by about (body-pitch / bogie frequency)² × (mass ratio), well under 2 %.
    let (ks, kp, a) = (p.k_sec_z, p.k_pri_z, p.station_half);
    let kh = 4.0 * kp;
    let kt = kp
        * [0.78125_f64, 2.34375, -0.78125, -2.34375]
            .iter()
            .map(|x| x * x)
            .sum::<f64>();
    let per_side =
        |x: f64| 2.0 * x * x / (1.0 / ks + 2.0 / kh) + 2.0 * a * a / (1.0 / ks + 2.0 * a * a / kt);
    let k_pitch: f64 = 2.0 * (0..BOGIES).map(|b| per_side(p.bogie_x(b))).sum::<f64>();
    let est = k_pitch / p.body_inertia[1];
    let (e, rel) = nearest(&ev, est);
    assert!(
        e <= est * (1.0 + 1e-12) && rel < 0.02,
        "pitch ω² {e} vs {est}"
    );
}

// ---------------------------------------------------------------- the wheel/rail car

/// The rigid motion (heave t_z, roll θx, pitch θy about the origin) as the car's DOF vector.
fn wr_rigid(p: &WheelRail, car: &VehicleModel, tz: f64, rx: f64, ry: f64) -> DVector<f64> {
    let mut u = DVector::zeros(17);
    let (t, th) = ([0.0, 0.0, tz], [rx, ry, 0.0]);
    let (body, bogies, _) = p.bodies();
    for (base, at) in std::iter::once((0, body.at))
        .chain(bogies.iter().enumerate().map(|(b, g)| (3 + 3 * b, g.at)))
    {
        u[base] = rigid_at(t, th, at)[2];
        u[base + 1] = rx;
        u[base + 2] = ry;
    }
    let x_front = p.wheelset_x(0);
    for c in &car.contacts {
        u[c.dof_z] = rigid_at(t, th, [c.x0 + x_front, c.ey, 0.0])[2];
    }
    u
}

#[test]
fn wheel_rail_rigid_motions_strain_no_spring() {
    let p = WheelRail::default();
    let car = p.build(G).unwrap();
    for (tz, rx, ry) in [
        (0.01, 0.0, 0.0),
        (0.0, 2e-3, 0.0),
        (0.0, 0.0, 1e-3),
        (0.01, -2e-3, 1e-3),
    ] {
        let u = wr_rigid(&p, &car, tz, rx, ry);
        assert!(rel_force(&car.k, &u) < 1e-12);
        assert!(rel_force(&car.c, &u) < 1e-12);
    }
    let mut u = DVector::zeros(17);
    u[9] = 1e-3; // one wheel up alone
    assert!(rel_force(&car.k, &u) > 1e-3);
}

#[test]
fn wheel_rail_mass_matrix_is_the_wheelsets_rigid_body() {
    // In (z_near, z_far) a wheelset's kinetic energy must be ½m ż² + ½I θ̇x² with
    // z = mean, θx = difference / (2 b0): check on a velocity pair by hand.
    let p = WheelRail::default();
    let car = p.build(G).unwrap();
    let mut v = DVector::zeros(17);
    v[9] = 0.3;
    v[10] = -0.1;
    let t = 0.5 * v.dot(&(&car.m * &v));
    let (z, th) = (0.1, 0.4 / (2.0 * p.half_contact));
    let hand = 0.5 * p.wheelset_mass * z * z + 0.5 * p.wheelset_roll * th * th;
    assert!((t - hand).abs() < 1e-12 * hand);
}

#[test]
fn wheel_rail_static_loads_match_hand_statics() {
    let p = WheelRail::default();
    let car = p.build(G).unwrap();
    // Hand statics: 1/8 of the body, 1/4 of a bogie, 1/2 of a wheelset per wheel:
    // (5500 + 600 + 1200) kg · 9.81 = 71 613 N.
    let hand = 7300.0 * 9.81;
    assert_eq!(car.contacts.len(), 8);
    for c in &car.contacts {
        assert!((c.p0 - hand).abs() < 1e-9 * hand, "{}", c.p0);
    }
    let sum: f64 = car.contacts.iter().map(|c| c.p0).sum();
    assert!((sum - 58_400.0 * 9.81).abs() < 1e-6 * sum);
    assert!((car.weight - sum).abs() < 1e-6 * sum);
    // Layout: wheelsets at 10, 7.5, −7.5, −10 m from the body centre; contacts 1.493 m apart.
    let xs: Vec<f64> = car.contacts.iter().step_by(2).map(|c| c.x0).collect();
    assert_eq!(xs, vec![0.0, -2.5, -17.5, -20.0]);
    assert!((car.contacts[1].ey - car.contacts[0].ey - 1.493).abs() < 1e-12);
}

#[test]
fn hertz_stiffness_against_the_formula_and_a_derivative() {
    // Hand value at P0 = 71 613 N, R = 0.43 m: G = 4.57·0.43^−0.149·1e−8 = 5.1824e−8 m/N^(2/3),
    // k_H = 1.5·P0^(1/3)/G = 1.2020e9 N/m.
    assert!((zhai_g(0.43) - 5.1824e-8).abs() < 1e-12);
    let k = hertz_stiffness(71_613.0, 0.43);
    assert!((k - 1.2020e9).abs() < 1e5, "{k}");
    // Second method: the slope of P(δ) = (δ/G)^(3/2) at δ0 = G·P0^(2/3), central difference.
    let g = zhai_g(0.43);
    let d0 = g * 71_613f64.powf(2.0 / 3.0);
    let h = 1e-4 * d0;
    let pd = |d: f64| (d / g).powf(1.5);
    let slope = (pd(d0 + h) - pd(d0 - h)) / (2.0 * h);
    assert!((slope - k).abs() < 1e-6 * k);
    // And the car's contacts carry it.
    let car = WheelRail::default().build(G).unwrap();
    assert!((car.contacts[0].k_h - k).abs() < 1e-6 * k);
}

#[test]
fn wheel_rail_contact_forces_on_a_smooth_rigid_rail_are_the_static_loads() {
    // The car free on its 8 contact springs over a fixed rail: solve K_rail u = f (nothing
    // held); each contact force k·(−u) equals P0 and they sum to the weight.
    let p = WheelRail::default();
    let car = p.build(G).unwrap();
    let (body, bogies, wheelsets) = p.bodies();
    let mut f = DVector::zeros(17);
    body.add_weight(&mut f, p.body_mass, G);
    for b in &bogies {
        b.add_weight(&mut f, p.bogie_mass, G);
    }
    for w in &wheelsets {
        w.add_weight(&mut f, p.wheelset_mass, G);
    }
    let (u, _) = static_solution(&car.k_on_rigid_rail(), &f, &[]).unwrap();
    let mut sum = 0.0;
    for c in &car.contacts {
        let force = -c.k * u[c.dof_z];
        assert!((force - c.p0).abs() < 1e-9 * c.p0, "{force} vs {}", c.p0);
        sum += force;
    }
    assert!((sum - car.weight).abs() < 1e-9 * car.weight);
    // The contact compression is P0/k (Hertz and track in series); the body sags by the two
    // suspensions more.
    let sag = 44_000.0 * G / (4.0 * p.k_sec)
        + 48_800.0 * G / (8.0 * p.k_pri)
        + car.contacts[0].p0 / car.contacts[0].k;
    assert!((u[car.body_z] + sag).abs() < 1e-9 * sag);
}

#[test]
fn wheel_rail_body_bounce_and_pitch_on_held_wheels() {
    let p = WheelRail::default();
    let car = p.build(G).unwrap();
    let ev = omega2(&car.k, &car.m, &(0..9).collect::<Vec<_>>());
    // Bounce: body on 4 air springs, 2 bogies on 8 axle boxes (exact 2-DOF chain).
    let (k2, k1) = (4.0 * p.k_sec, 8.0 * p.k_pri);
    let (lo, hi) = two_dof(k2, -k2, k1 + k2, p.body_mass, 2.0 * p.bogie_mass);
    for x in [lo, hi] {
        assert!(nearest(&ev, x).1 < 1e-9, "bounce {x}");
    }
    // Closed-form estimate of the brief: sqrt(k_sec_total/m) with the primary in series.
    let series = 1.0 / (1.0 / k2 + 1.0 / k1);
    let est = series / p.body_mass;
    assert!(lo < est && (lo - est).abs() / est < 0.01, "{lo} vs {est}");
    let f = lo.sqrt() / (2.0 * std::f64::consts::PI);
    assert!((f - 1.065).abs() < 0.001, "{f}");
    // Pitch: body pitch φ with the bogies' antisymmetric heave z_b (front up, rear down), an
    // exact 2-DOF system: V = k_s (z_b − l φ)² + k_p z_b² with k_s, k_p per bogie,
    // T = ½ I_y φ̇² + ½ (2 m_b) ż_b².
    let l = p.half_bogie_spacing;
    let (ks, kp) = (2.0 * p.k_sec, 4.0 * p.k_pri); // per bogie: 2 air springs, 4 boxes
    let (plo, phi) = two_dof(
        2.0 * ks * l * l,
        -2.0 * ks * l,
        2.0 * ks + 2.0 * kp,
        p.body_pitch,
        2.0 * p.bogie_mass,
    );
    for x in [plo, phi] {
        assert!(nearest(&ev, x).1 < 1e-9, "pitch {x}");
    }
    let fp = plo.sqrt() / (2.0 * std::f64::consts::PI);
    assert!((fp - 1.189).abs() < 0.001, "{fp}");
}

#[test]
fn bad_parameters_are_refused_with_the_key() {
    let e = Fig6 {
        body_mass: -1.0,
        ..Fig6::default()
    }
    .build(G)
    .unwrap_err();
    assert_eq!(e.to_string(), "fig6.body_mass: must be > 0, got -1");
    let e = WheelRail {
        half_bogie_spacing: 20.0,
        ..WheelRail::default()
    }
    .build(G)
    .unwrap_err();
    assert!(e.to_string().starts_with("wheel_rail.half_bogie_spacing:"));
}

#[test]
fn static_reactions_follow_the_lever_rule_off_centre() {
    // A body (heave, pitch) whose CoM sits 3 m from one support and 1 m from the other, on
    // two springs of different stiffness, nodes held: statically determinate, so the lever
    // rule gives the reactions W·1/4 and W·3/4 whatever the springs.
    let body = Rigid::new([0.0; 3]).dof(UZ, 0).dof(RY, 1);
    let (pa, pb) = ([3.0, 0.0, 0.0], [-1.0, 0.0, 0.0]);
    let (na, nb) = (Rigid::new(pa).dof(UZ, 2), Rigid::new(pb).dof(UZ, 3));
    let (mut k, mut c) = (DMatrix::zeros(4, 4), DMatrix::zeros(4, 4));
    add_spring_damper(
        &mut k,
        &mut c,
        (1e5, 0.0),
        Axis::Z,
        End { body: &na, p: pa },
        End { body: &body, p: pa },
    )
    .unwrap();
    add_spring_damper(
        &mut k,
        &mut c,
        (7e5, 0.0),
        Axis::Z,
        End { body: &nb, p: pb },
        End { body: &body, p: pb },
    )
    .unwrap();
    let mut f = DVector::zeros(4);
    body.add_weight(&mut f, 1000.0, G);
    let (_, r) = static_solution(&k, &f, &[2, 3]).unwrap();
    assert!((r[2] - 0.25 * 1000.0 * G).abs() < 1e-9);
    assert!((r[3] - 0.75 * 1000.0 * G).abs() < 1e-9);
}
