//! Support motion in absolute coordinates (docs/seismic.md "Support motion"), each test named
//! after what it reproduces:
//!
//! - a mass on a spring and a dashpot to moving ground under harmonic ground acceleration,
//!   from rest, against the closed form derived here;
//! - the viaduct under uniform ground motion, absolute formulation (the code) against the
//!   relative one (M ÿ + C ẏ + K y = −M r ü_g, a dense Newmark written here);
//! - the viaduct under wave passage against a dense direct integration written here with a
//!   different split (quasi-static part K⁻¹ K_g u_g plus the dynamic rest) and the ground
//!   kinematics in closed form;
//! - a settled pier: the girders over it take their rigid-body tilt.

mod dense_newmark;

use dense_newmark::dense_newmark;
use maglev_sim::input::support::SupportSection;
use maglev_sim::physics::fe::newmark::{Rayleigh, SpanNewmark, State};
use maglev_sim::physics::fe::structure::{Builder, NodeKind};
use maglev_sim::physics::fe::{paper5_viaduct, Viaduct, ViaductSpec};
use maglev_sim::physics::guideway::Guideway;
use maglev_sim::physics::seismic::accelerogram::G;
use maglev_sim::physics::seismic::support::{
    add_ground_loads, GroundLink, GroundRecord, GroundState, SupportMotion,
};
use nalgebra::{DMatrix, DVector};
use std::f64::consts::PI;

/// Relative response y of ÿ + 2ζω ẏ + ω² y = −A sin Ωt from rest (closed form): the steady
/// state P sin Ωt + Q cos Ωt plus the free vibration that cancels its initial values.
fn sdof_relative(omega: f64, zeta: f64, a: f64, big_omega: f64, t: f64) -> f64 {
    let (w, z, o) = (omega, zeta, big_omega);
    let det = (w * w - o * o).powi(2) + (2.0 * z * w * o).powi(2);
    let p = -a * (w * w - o * o) / det;
    let q = a * 2.0 * z * w * o / det;
    let wd = w * (1.0 - z * z).sqrt();
    let b1 = -q;
    let b2 = (z * w * b1 - p * o) / wd;
    p * (o * t).sin()
        + q * (o * t).cos()
        + (-z * w * t).exp() * (b1 * (wd * t).cos() + b2 * (wd * t).sin())
}

/// A mass m on a spring k and a dashpot c to the ground in each direction (rotations held by
/// springs and inertias of their own), the ground accelerating as A_i sin Ωt from rest: the
/// relative motion u − u_g matches the closed form to 1e-6 of its peak, through the same
/// pieces the viaduct uses (trapezoid ground, loads k·u_g + c·v_g, the span Newmark).
#[test]
fn sdof_under_harmonic_support_motion_matches_closed_form() {
    let mass = 2.0e4;
    let omega = [2.0 * PI * 2.0, 2.0 * PI * 3.1, 2.0 * PI * 1.4];
    let zeta = [0.05, 0.02, 0.3];
    let amp = [1.0, -0.7, 0.4];
    let big_omega = 2.0 * PI * 1.3;
    let k: [f64; 6] = std::array::from_fn(|i| {
        if i < 3 {
            mass * omega[i] * omega[i]
        } else {
            1e6
        }
    });
    let c: [f64; 6] = std::array::from_fn(|i| {
        if i < 3 {
            2.0 * zeta[i] * mass * omega[i]
        } else {
            0.0
        }
    });
    let mut b = Builder::default();
    let node = b.node(NodeKind::Pier);
    b.ground(node, k, c);
    b.lumped(node, mass, [1e3; 3]);
    let s = b.finish();
    let dt = 2e-5;
    let steps = 150_000; // 3 s
    let record = GroundRecord::new(
        dt,
        (0..=steps)
            .map(|n| {
                let t = n as f64 * dt;
                std::array::from_fn(|i| amp[i] * (big_omega * t).sin())
            })
            .collect(),
    )
    .unwrap();
    let motion = SupportMotion::uniform(record, 1);
    let links: Vec<GroundLink> = (0..3)
        .map(|axis| GroundLink {
            dof: axis,
            support: 0,
            axis,
            k: k[axis],
            c: c[axis],
        })
        .collect();
    let nm = SpanNewmark::with_damping_matrix(&s.k, &s.m, Some(s.c.clone()), dt).unwrap();
    let mut committed = State::zeros(6);
    let mut trial = State::zeros(6);
    let mut pred = DVector::zeros(nm.pred_len());
    let mut rhs = DVector::zeros(6);
    let mut scratch = nm.factor().scratch();
    let mut ground = [GroundState::at([0.0; 3], motion.acceleration(0, 0.0))];
    let mut peak = [0.0f64; 3];
    let mut worst = [0.0f64; 3];
    for n in 1..=steps {
        let t = n as f64 * dt;
        ground[0] = ground[0].step(dt, motion.acceleration(0, t));
        nm.free_rhs(&committed, &mut pred, &mut rhs);
        add_ground_loads(&links, &ground, rhs.as_mut_slice());
        nm.solve_in_place(&mut rhs, &mut scratch);
        trial.d.copy_from(&rhs);
        nm.finish(&mut committed, &mut trial);
        for i in 0..3 {
            let y = committed.d[i] - ground[0].d[i];
            let exact = sdof_relative(omega[i], zeta[i], amp[i], big_omega, t);
            peak[i] = peak[i].max(exact.abs());
            worst[i] = worst[i].max((y - exact).abs());
        }
    }
    for i in 0..3 {
        let rel = worst[i] / peak[i];
        println!(
            "direction {i}: peak {:.6e} m, worst error / peak {rel:.3e}",
            peak[i]
        );
        assert!(rel < 1e-6, "direction {i}: {rel}");
    }
}

/// A small viaduct for the dense checks: 2 spans of 30 m, 4 girder and 2 pier elements,
/// stiffness-proportional damping on top of the footing dashpots.
fn small_viaduct() -> ViaductSpec {
    let mut spec = paper5_viaduct().with_spans(2);
    spec.elements_per_span = 4;
    spec.pier.elements = 2;
    spec.damping = Some(Rayleigh {
        alpha: 0.0,
        beta: 1e-3,
    });
    spec
}

/// The viaduct's K, M and C = dashpots + β K, dense.
fn dense_matrices(v: &Viaduct) -> (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>) {
    let s = v.structure();
    let beta = v.spec().damping.map_or(0.0, |r| r.beta);
    let (k, m) = (s.k.to_dense(), s.m.to_dense());
    let c = s.c.to_dense() + &k * beta;
    (k, m, c)
}

/// A smooth three-component test record: a few sines under a sin² envelope over 1.5 s.
fn test_record(dt: f64, duration: f64) -> GroundRecord {
    let n = (duration / dt).round() as usize;
    GroundRecord::new(
        dt,
        (0..=n)
            .map(|i| {
                let t = i as f64 * dt;
                let e = if t < 1.5 {
                    (PI * t / 1.5).sin().powi(2)
                } else {
                    0.0
                };
                [
                    e * (1.5 * (2.0 * PI * 2.3 * t).sin() + 0.8 * (2.0 * PI * 5.1 * t).cos()),
                    e * 1.1 * (2.0 * PI * 3.7 * t).sin(),
                    e * (0.6 * (2.0 * PI * 4.4 * t).sin() - 0.3 * (2.0 * PI * 9.0 * t).sin()),
                ]
            })
            .collect(),
    )
    .unwrap()
}

/// Uniform ground motion: the absolute displacements of the code minus the ground's rigid
/// translation r·u_g equal the relative formulation M ÿ + C ẏ + K y = −M r ü_g (a dense
/// Newmark here) to 1e-6 of the peak. Holds only if the damping does not act on the
/// rigid-body motion (C r = the ground dashpots' r): with C = dashpots + β K it does not.
#[test]
fn absolute_and_relative_formulations_agree() {
    let spec = small_viaduct();
    let dt = 2e-3;
    let steps = 1000;
    let record = test_record(dt, steps as f64 * dt);
    let piers = spec.spans + 1;
    let mut v =
        Viaduct::with_support_motion(&spec, dt, SupportMotion::uniform(record.clone(), piers))
            .unwrap();
    let (k, m, c) = dense_matrices(&v);
    let n = k.nrows();
    // r: unit rigid translation along each axis.
    let r: Vec<DVector<f64>> = (0..3)
        .map(|axis| DVector::from_fn(n, |i, _| if i % 6 == axis { 1.0 } else { 0.0 }))
        .collect();
    let mut relative = Vec::with_capacity(steps);
    dense_newmark(
        &k,
        &m,
        &c,
        dt,
        steps,
        |step| {
            let a = record.acceleration(step as f64 * dt);
            -(&m * (&r[0] * a[0] + &r[1] * a[1] + &r[2] * a[2]))
        },
        |_, y| relative.push(y.clone()),
    );
    let (mut peak, mut worst) = (0.0f64, 0.0f64);
    for y in &relative {
        v.solve_step(&[]);
        v.commit();
        let g = v.ground().unwrap()[0];
        let u = &v.state().d;
        for i in 0..n {
            let rigid = if i % 6 < 3 { g.d[i % 6] } else { 0.0 };
            peak = peak.max(y[i].abs());
            worst = worst.max((u[i] - rigid - y[i]).abs());
        }
    }
    println!(
        "peak relative displacement {peak:.6e} m, worst difference / peak {:.3e}",
        worst / peak
    );
    assert!(peak > 1e-4, "the test excites the viaduct: {peak}");
    assert!(worst < 1e-6 * peak, "{}", worst / peak);
}

/// Rigid-body motion meets no damping: for each axis, C r (C = dashpots + β K) is exactly the
/// ground dashpots' share, so a viaduct moving rigidly with the ground feels no damping force;
/// and mass-proportional damping, which would drag it, is refused.
#[test]
fn damping_does_not_drag_rigid_body_motion() {
    let spec = small_viaduct();
    let v = Viaduct::with_support_motion(&spec, 1e-3, SupportMotion::at_rest(3)).unwrap();
    let (k, _, c) = dense_matrices(&v);
    let n = k.nrows();
    let beta = spec.damping.unwrap().beta;
    for axis in 0..3 {
        let r = DVector::from_fn(n, |i, _| if i % 6 == axis { 1.0 } else { 0.0 });
        let (kr, cr) = (&k * &r, &c * &r);
        // Only the footing DOFs carry a force, and it is the ground spring's / dashpot's.
        let kg = spec.foundation.stiffness[axis];
        let cg = spec.foundation.damping[axis] + beta * kg;
        for i in 0..n {
            let base = v.layout().pier_base.iter().any(|&b| b * 6 + axis == i);
            let (ek, ec) = if base { (kg, cg) } else { (0.0, 0.0) };
            assert!(
                (kr[i] - ek).abs() <= 1e-9 * kg,
                "axis {axis} dof {i}: K r = {}",
                kr[i]
            );
            assert!(
                (cr[i] - ec).abs() <= 1e-9 * cg,
                "axis {axis} dof {i}: C r = {}",
                cr[i]
            );
        }
    }
    let mut bad = spec.clone();
    bad.damping = Some(Rayleigh {
        alpha: 0.1,
        beta: 1e-3,
    });
    let e = Viaduct::with_support_motion(&bad, 1e-3, SupportMotion::at_rest(3)).unwrap_err();
    assert!(e.to_string().contains("bridge.damping"), "{e}");
}

/// Ground kinematics in closed form for a = A sin Ωs over `cycles` whole periods from s = 0
/// (zero before and after): (u, v, a).
fn pulse(amp: f64, big_omega: f64, cycles: f64, s: f64) -> (f64, f64, f64) {
    let end = cycles * 2.0 * PI / big_omega;
    let o = big_omega;
    if s <= 0.0 {
        (0.0, 0.0, 0.0)
    } else if s <= end {
        (
            amp / o * (s - (o * s).sin() / o),
            amp / o * (1.0 - (o * s).cos()),
            amp * (o * s).sin(),
        )
    } else {
        (amp / o * end, 0.0, 0.0)
    }
}

/// Wave passage (each pier's ground delayed by its distance over 400 m/s): the code's
/// absolute displacements against a dense direct integration written here that splits the
/// motion into its quasi-static part u_s = K⁻¹ K_g u_g and the dynamic rest
/// (M ÿ + C ẏ + K y = −M ü_s − C u̇_s + C_g v_g), with the ground's motion in closed form.
/// Both the absolute motion and its dynamic part agree within 0.5 % of their peaks.
#[test]
fn viaduct_under_wave_passage_matches_dense_direct_integration() {
    let spec = small_viaduct();
    let dt = 1e-3;
    let steps = 1500;
    let (big_omega, cycles, speed) = (2.0 * PI * 2.5, 2.0, 400.0);
    let amp = [1.0, 0.8, 0.5];
    let record = GroundRecord::new(
        dt,
        (0..=steps)
            .map(|i| std::array::from_fn(|d| pulse(amp[d], big_omega, cycles, i as f64 * dt).2))
            .collect(),
    )
    .unwrap();
    let positions: Vec<f64> = (0..=spec.spans)
        .map(|k| k as f64 * spec.span_length)
        .collect();
    let motion = SupportMotion::wave_passage(record, &positions, speed).unwrap();
    let mut v = Viaduct::with_support_motion(&spec, dt, motion).unwrap();
    let (k, m, c) = dense_matrices(&v);
    let n = k.nrows();
    let beta = spec.damping.unwrap().beta;
    let f = &spec.foundation;
    // K_g u_g, C_g v_g as nodal vectors from the closed-form ground at time t.
    let ground = |t: f64, which: usize, damped: bool| {
        let mut g = DVector::zeros(n);
        for (p, &base) in v.layout().pier_base.iter().enumerate() {
            let s = t - positions[p] / speed;
            for axis in 0..3 {
                let (u, vel, a) = pulse(amp[axis], big_omega, cycles, s);
                let x = [u, vel, a][which];
                let coef = if damped {
                    f.damping[axis] + beta * f.stiffness[axis]
                } else {
                    f.stiffness[axis]
                };
                g[base * 6 + axis] = coef * x;
            }
        }
        g
    };
    let klu = k.clone().lu();
    let quasi = |t: f64, which: usize| klu.solve(&ground(t, which, false)).unwrap();
    let mut dynamic = Vec::with_capacity(steps);
    dense_newmark(
        &k,
        &m,
        &c,
        dt,
        steps,
        |step| {
            let t = step as f64 * dt;
            -(&m * quasi(t, 2)) - &c * quasi(t, 1) + ground(t, 1, true)
        },
        |step, y| dynamic.push((quasi(step as f64 * dt, 0), y.clone())),
    );
    let (mut peak_u, mut worst_u, mut peak_y, mut worst_y) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (us, y) in &dynamic {
        v.solve_step(&[]);
        v.commit();
        let u = &v.state().d;
        for i in 0..n {
            let exact = us[i] + y[i];
            peak_u = peak_u.max(exact.abs());
            worst_u = worst_u.max((u[i] - exact).abs());
            peak_y = peak_y.max(y[i].abs());
            worst_y = worst_y.max((u[i] - us[i] - y[i]).abs());
        }
    }
    println!(
        "absolute: peak {peak_u:.6e}, worst / peak {:.3e}; dynamic part: peak {peak_y:.6e}, worst / peak {:.3e}",
        worst_u / peak_u,
        worst_y / peak_y
    );
    assert!(
        peak_y > 1e-5,
        "the test excites the viaduct dynamically: {peak_y}"
    );
    assert!(worst_u < 5e-3 * peak_u, "{}", worst_u / peak_u);
    assert!(worst_y < 5e-3 * peak_y, "{}", worst_y / peak_y);
}

/// A pier whose ground sinks by δ = 10 mm (settled before t = 0): the girders on either side
/// take their rigid-body tilt (w linear from 0 to −δ over each span, no twist, no lateral
/// motion) to 1e-9 δ, the third girder does not move, and stepping on without loads keeps
/// that shape.
#[test]
fn simply_supported_spans_over_a_settled_pier_take_their_rigid_body_tilt() {
    let spec = paper5_viaduct().with_spans(3);
    let delta = 0.01;
    let l = spec.span_length;
    let motion = SupportMotion::at_rest(4)
        .with_settlement(1, [0.0, 0.0, -delta])
        .unwrap();
    let mut v = Viaduct::with_support_motion(&spec, 1e-3, motion).unwrap();
    let expected = |x: f64| {
        if x < l {
            -delta * x / l
        } else if x < 2.0 * l {
            -delta * (2.0 * l - x) / l
        } else {
            0.0
        }
    };
    let check = |v: &Viaduct, when: &str| {
        let mut worst = 0.0f64;
        for i in 0..=300 {
            let x = i as f64 * 3.0 * l / 300.0 * (1.0 - 1e-12);
            let s = v.section_at(x);
            worst = worst
                .max((s.z - expected(x)).abs())
                .max(s.y.abs())
                .max(s.rx.abs() * l);
        }
        println!(
            "{when}: worst deviation from the rigid tilt {:.3e} of δ",
            worst / delta
        );
        assert!(worst <= 1e-9 * delta, "{when}: {}", worst / delta);
    };
    check(&v, "t = 0");
    for _ in 0..200 {
        v.solve_step(&[]);
        v.commit();
    }
    check(&v, "after 200 steps");
}

/// `[support.synthetic]` is `maglev accelerogram` with the same values: its defaults are
/// the command's, so a section giving only `pga_g` and `seed` reproduces the command's CSV
/// (printed with `{:e}`, which reads back to the same f64) sample for sample.
#[test]
fn a_synthetic_record_is_the_accelerogram_commands_record() {
    let exe = env!("CARGO_BIN_EXE_maglev");
    let out = std::process::Command::new(exe)
        .args(["accelerogram", "--pga-g", "0.15", "--seed", "7"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let csv = String::from_utf8(out.stdout).unwrap();
    let command = GroundRecord::from_csv("cli", &csv).unwrap();
    let s: SupportSection = toml::from_str("[synthetic]\npga_g = 0.15\nseed = 7\n").unwrap();
    let ours = s.synthetic.as_ref().unwrap().record().unwrap();
    assert_eq!(ours.time_step(), 0.005);
    assert_eq!(ours.samples().len(), 4001);
    assert_eq!(ours.samples(), command.samples());
    let peak = ours
        .samples()
        .iter()
        .map(|a| a[0].abs())
        .fold(0.0, f64::max);
    assert!((peak - 0.15 * G).abs() < 1e-12 * G, "x peak {peak}");
    let m = s.to_motion(2, 30.0, |_| unreachable!()).unwrap();
    assert_eq!(m.acceleration(1, 1.0), m.acceleration(0, 1.0));
}

/// `[[support.settlement]]` in a scenario reaches the viaduct of `maglev run`: over three
/// 30 m spans with pier 2 settled 10 mm, the run starts on the settled shape — pier 2's base
/// 10 mm down and span 1's girder tilted rigidly through half of it at midspan (a 1 N load
/// at the start of span 1 adds under 1e-9 m) — and a rigid guideway refuses the section naming it
/// (support motion drives an FE viaduct only).
#[test]
fn a_settled_pier_from_a_scenario_reaches_the_run() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../sim/scenarios/paper-5.toml"
    ))
    .unwrap();
    let text = text
        .replace(
            "[train]\nkind = \"maglev\"\ncars = 12\n",
            "[train]\nkind = \"forces\"\nloads_kN = [0.001]\noffsets_m = [0.0]\n",
        )
        .replace(
            "probes = [\"car4.body.az\", \"pier20.base.az\", \"span20.midspan.z\", \"wheel1.z\", \"wheel1.force_z\"]",
            "probes = [\"pier2.base.z\", \"span1.midspan.z\", \"span3.midspan.z\"]",
        );
    let spans_35 = format!("spans_m = [{}]", vec!["30.0"; 35].join(", "));
    assert!(text.contains(&spans_35) && text.contains("pier2.base.z"));
    let text = text.replace(&spans_35, "spans_m = [30.0, 30.0, 30.0]")
        + "\n[[support.settlement]]\npier = 2\ndz_m = -0.01\n";
    let dir = std::env::temp_dir().join(format!("maglev-settled-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scenario = dir.join("settled.toml");
    std::fs::write(&scenario, &text).unwrap();
    let exe = env!("CARGO_BIN_EXE_maglev");
    let out = std::process::Command::new(exe)
        .args(["run", scenario.to_str().unwrap(), "--set", "t_end=0.01"])
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(dir.join("out/response.csv")).unwrap();
    let row: Vec<f64> = csv
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    // t, pier2.base.z, span1.midspan.z, span3.midspan.z
    assert!((row[1] + 0.01).abs() < 1e-11, "pier 2 base {}", row[1]);
    assert!((row[2] + 0.005).abs() < 1e-9, "span 1 midspan {}", row[2]);
    assert!(row[3].abs() < 1e-9, "span 3 midspan {}", row[3]);
    let summary = std::fs::read_to_string(dir.join("out/summary.json")).unwrap();
    assert!(
        summary.contains("\"settlement\""),
        "summary.json records [support]"
    );

    let out = std::process::Command::new(exe)
        .args([
            "run",
            scenario.to_str().unwrap(),
            "--set",
            "model=rigid",
            "--out",
        ])
        .arg(dir.join("out2"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("support"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Nothing drifts after a record ends: the small viaduct under `paper-5-quake`'s synthetic
/// record (10 s, Δt 5 ms) stepped at 1 ms to 11 s, uniformly and with wave passage at
/// 333 m/s (delays of 0.09 s and 0.18 s, not multiples of the run's step). From the first
/// step past each pier's record its ground velocity is exactly zero and its displacement
/// constant; uniformly, where the run's step divides the record's, the ground ends where it
/// started (to 1e-9 of its peak displacement: the record ends at rest under the trapezoid
/// rule, and a last sample of zero adds nothing after it). Before, the last sample a_N ≠ 0
/// left each pier's ground moving at Δt·a_N/2 (1.2e-4 m/s at 1 ms) for ever.
#[test]
fn nothing_drifts_after_the_record_ends() {
    let s: SupportSection = toml::from_str(
        "[synthetic]\npga_g = 0.1\nground = \"medium\"\nduration_s = 10.0\nseed = 1\n",
    )
    .unwrap();
    let record = s.synthetic.as_ref().unwrap().record().unwrap();
    let end = record.end();
    assert_eq!(end, 10.0);
    let spec = small_viaduct();
    let dt = 1e-3;
    let piers = spec.spans + 1;
    let positions: Vec<f64> = (0..piers).map(|k| k as f64 * 30.0).collect();
    for (what, motion) in [
        ("uniform", SupportMotion::uniform(record.clone(), piers)),
        (
            "wave passage",
            SupportMotion::wave_passage(record.clone(), &positions, 333.0).unwrap(),
        ),
    ] {
        let delays: Vec<f64> = positions.iter().map(|x| x / 333.0).collect();
        let uniform = what == "uniform";
        let mut v = Viaduct::with_support_motion(&spec, dt, motion).unwrap();
        let mut peak = [0.0f64; 3];
        let mut held: Vec<Option<GroundState>> = vec![None; piers];
        for n in 1..=11_000usize {
            v.solve_step(&[]);
            v.commit();
            let t = n as f64 * dt;
            for (k, g) in v.ground().unwrap().iter().enumerate() {
                for (p, d) in peak.iter_mut().zip(g.d) {
                    *p = p.max(d.abs());
                }
                let past = t - if uniform { 0.0 } else { delays[k] } > end + dt;
                match (&held[k], past) {
                    (None, true) => {
                        assert_eq!(g.v, [0.0; 3], "{what} pier {k} at {t} s");
                        held[k] = Some(*g);
                    }
                    (Some(h), _) => {
                        assert_eq!((g.v, g.d), ([0.0; 3], h.d), "{what} pier {k} at {t} s")
                    }
                    _ => {}
                }
            }
        }
        let last = v.ground().unwrap()[0];
        println!(
            "{what}: peak ground displacement {peak:?} m; pier 1's ground ends at {:?} m",
            last.d
        );
        assert!(
            held.iter().all(Option::is_some),
            "{what}: every record ended"
        );
        if uniform {
            for (axis, (d, p)) in last.d.iter().zip(peak).enumerate() {
                assert!(d.abs() <= 1e-9 * p, "axis {axis}: {d} of {p}");
            }
        }
    }
}
