//! The running-safety recorder (`safety.rs`, docs/safety.md): on hand-made step views whose
//! figures are worked out by hand here (smallest gaps and when, saturation time, ΔP/P from a
//! hand-computed contact force, lift-off, body acceleration), without allocating once sized;
//! and end to end through `maglev run`, where every figure that response.csv holds a column
//! for is recomputed from the file read back, and the coil figures are held against
//! summary.json's own coil figures (the time loop's tally, a separate path).

#[path = "../../sim/tests/counting_alloc/mod.rs"]
mod counting_alloc;

use counting_alloc::count;
use maglev_sim::physics::guideway::RigidGuideway;
use maglev_sim::physics::train::Node;
use maglev_sim::physics::vehicle::Coil;
use maglev_sim::probes::{Recorder, StepView, Wheels};
use maglev_sim::safety::{Safety, SafetyReport, BODY_ACCEL_LIMIT, UNLOADING_LIMIT};
use std::path::{Path, PathBuf};
use std::process::Command;

const H0: f64 = 0.01;
const DT: f64 = 0.002;

/// One hand-made step of a train of two magnet wheels (wheel 1 guided, wheel 2 not) and two
/// contacts, numbered magnet, contact, magnet, contact along the train, in two cars.
struct Hand {
    u: Vec<f64>,
    a: Vec<f64>,
    gaps: Vec<(f64, f64)>,
    forces: Vec<(f64, f64)>,
    contact_forces: Vec<f64>,
    coils: Vec<[Coil; 3]>,
}

const DOFS: [(Option<usize>, usize); 2] = [(Some(0), 1), (None, 2)];
const BODY_Z: [usize; 2] = [3, 4];
const NODES: [Node; 4] = [
    Node::Magnet(0),
    Node::Contact(0),
    Node::Magnet(1),
    Node::Contact(1),
];
const CONTACT_DOFS: [usize; 2] = [5, 6];
/// The wheel/rail car's hand statics (docs/cars.md): g·(5 500 + 600 + 1 200) kg.
const P0: f64 = 71_613.0;
const CONTACT_P0: [f64; 2] = [P0, P0];

fn coil(current: f64, voltage: f64, saturated: bool) -> Coil {
    Coil {
        current,
        voltage,
        saturated,
    }
}

impl Hand {
    fn new() -> Self {
        Hand {
            u: vec![0.0; 7],
            a: vec![0.0; 7],
            gaps: vec![(H0, 0.0); 2],
            forces: vec![(1e4, 0.0); 2],
            contact_forces: CONTACT_P0.to_vec(),
            coils: vec![[coil(43.0, 43.0, false); 3]; 2],
        }
    }

    fn record(&self, rec: &mut Safety, g: &RigidGuideway, t: f64, collision: bool) {
        rec.record(&StepView {
            t,
            guideway: g,
            midspans: &[],
            wheels: Wheels::Vehicle {
                u: &self.u,
                a: &self.a,
                dofs: &DOFS,
                gaps: &self.gaps,
                forces: &self.forces,
                h0: H0,
                body_z: &BODY_Z,
                nodes: &NODES,
                contact_dofs: &CONTACT_DOFS,
                contact_forces: &self.contact_forces,
                contact_p0: &CONTACT_P0,
                coils: &self.coils,
            },
            iterations: 1,
            collision,
        })
        .unwrap();
    }
}

/// Four steps by hand. Every figure below is worked out from the numbers written here.
#[test]
fn hand_made_steps_give_the_hand_figures_without_allocating() {
    let g = RigidGuideway::new(DT);
    let mut rec = Safety::new(DT, Some(500.0));
    let mut s = Hand::new();
    // t = 0: at rest.
    s.record(&mut rec, &g, 0.0, false);
    let before = count();
    // t = 1Δt: wheel 2 (node 3, unguided) down to 6 mm; its guidance offset d = 9 mm would
    // make a 1 mm guidance gap, which must not count (it has no guidance magnets).
    // Wheel 1's left guidance gap h0 + d with d = −3 mm: 7 mm, its right 13 mm.
    // Contact 1 (node 2): the wheel 0.2 mm up on a still, smooth rail, k = 1.25e8 N/m:
    // P = P0 − k·z_w = 71 613 − 25 000 = 46 613 N.
    s.gaps[1] = (0.006, 0.009);
    s.gaps[0] = (0.0095, -0.003);
    s.contact_forces[0] = P0 - 1.25e8 * 2e-4;
    s.a[BODY_Z[0]] = 1.0;
    s.a[BODY_Z[1]] = -0.5;
    s.coils[0][1] = coil(-80.0, -500.0, true);
    s.record(&mut rec, &g, DT, false);
    // t = 2Δt: wheel 1 at 4 mm (the run's smallest levitation gap), contact 2 lifted off,
    // a collision flagged, wheel 1's left coil still saturated.
    s.gaps[0] = (0.004, -0.001);
    s.contact_forces[1] = 0.0;
    s.a[BODY_Z[0]] = -2.0;
    s.record(&mut rec, &g, 2.0 * DT, true);
    // t = 3Δt: everything back, a collision flagged again, the left coil still saturated.
    s.gaps.fill((H0, 0.0));
    s.contact_forces.copy_from_slice(&CONTACT_P0);
    s.a[BODY_Z[0]] = 0.5;
    s.a[BODY_Z[1]] = 0.0;
    s.record(&mut rec, &g, 3.0 * DT, true);
    assert_eq!(
        count(),
        before,
        "the recorder allocated after its first step"
    );

    let r: SafetyReport = rec.report().unwrap();
    let m = r.maglev.as_ref().unwrap();
    assert_eq!(m.levitation_gap_min.value, 0.004);
    assert_eq!(m.levitation_gap_min.at.as_deref(), Some("wheel1.z"));
    assert_eq!(m.levitation_gap_min.t_s, Some(2.0 * DT));
    assert_eq!(m.levitation_gap_min.pass, Some(true));
    let per: Vec<(&str, f64, f64)> = m
        .levitation_gap_per_magnet
        .iter()
        .map(|g| (g.magnet.as_str(), g.min_m, g.t_s))
        .collect();
    assert_eq!(
        per,
        [("wheel1.z", 0.004, 2.0 * DT), ("wheel3.z", 0.006, DT)]
    );
    let guide = m.guidance_gap_min.as_ref().unwrap();
    assert_eq!(guide.at.as_deref(), Some("wheel1.left"));
    assert!((guide.value - 0.007).abs() < 1e-15, "{}", guide.value);
    assert_eq!(guide.t_s, Some(DT));
    assert_eq!(m.collision_steps.value, 2.0);
    assert_eq!(m.collision_steps.t_s, Some(2.0 * DT));
    assert_eq!(m.collision_steps.pass, Some(false));
    let sat = m.saturated_longest.as_ref().unwrap();
    assert_eq!(sat.value, 3.0 * DT, "three steps, t = 0 not counted");
    assert_eq!(sat.at.as_deref(), Some("wheel1.left"));
    let i = m.current_peak.as_ref().unwrap();
    assert_eq!(
        (i.value, i.at.as_deref(), i.t_s),
        (80.0, Some("wheel1.left"), Some(DT))
    );
    assert_eq!(
        (i.limit, i.pass),
        (None, None),
        "no current limit in the model"
    );
    let v = m.voltage_peak.as_ref().unwrap();
    assert_eq!((v.value, v.limit, v.pass), (500.0, Some(500.0), Some(true)));

    let w = r.wheel_rail.as_ref().unwrap();
    // Contact 2 lifted off: ΔP/P = 1 at 2Δt; contact 1's largest is 25 000 / 71 613.
    assert_eq!(w.unloading_max.value, 1.0);
    assert_eq!(w.unloading_max.at.as_deref(), Some("wheel4"));
    assert_eq!(w.unloading_max.pass, Some(false));
    assert_eq!(w.unloading_max.limit, Some(UNLOADING_LIMIT));
    let c1 = &w.per_contact[0];
    assert_eq!(c1.wheel, "wheel2");
    assert!(
        (c1.unloading - 25_000.0 / 71_613.0).abs() < 1e-12,
        "{}",
        c1.unloading
    );
    assert_eq!(c1.t_s, DT);
    assert_eq!(w.lift_off_steps.value, 1.0);
    assert_eq!(w.lift_off_steps.at.as_deref(), Some("wheel4"));
    assert_eq!(w.lift_off_steps.t_s, Some(2.0 * DT));
    assert!(!w.derailment_quotient.computed);

    // Body: car 1 saw 0, 1, −2, 0.5 m/s²; car 2 0, −0.5, −0.5, 0.
    assert_eq!(r.body_acceleration_peak.value, 2.0);
    assert_eq!(r.body_acceleration_peak.at.as_deref(), Some("car1"));
    assert_eq!(r.body_acceleration_peak.t_s, Some(2.0 * DT));
    assert_eq!(r.body_acceleration_peak.limit, Some(BODY_ACCEL_LIMIT));
    assert_eq!(r.body_acceleration_peak.pass, Some(false));
    let rms1 = (5.25f64 / 4.0).sqrt();
    assert!((r.body_acceleration_rms.value - rms1).abs() < 1e-15);
    assert!((r.per_car[1].rms - (0.5f64 / 4.0).sqrt()).abs() < 1e-15);
    assert!(!r.pass);
}

/// A quiet passage passes every judged figure, and a moving-force run has no section.
#[test]
fn a_quiet_passage_passes_and_forces_have_no_section() {
    let g = RigidGuideway::new(DT);
    let mut rec = Safety::new(DT, None);
    let mut s = Hand::new();
    // A coil saturated at t = 0 only: t = 0 is the start, not a step, and is not counted (as
    // summary.json's `saturated_s`).
    s.coils[0][0].saturated = true;
    for n in 0..3 {
        s.record(&mut rec, &g, n as f64 * DT, false);
        s.coils[0][0].saturated = false;
    }
    let r = rec.report().unwrap();
    assert!(r.pass, "{r:?}");
    let m = r.maglev.unwrap();
    let sat = m.saturated_longest.unwrap();
    assert_eq!((sat.value, sat.at), (0.0, None));
    let v = m.voltage_peak.unwrap();
    assert_eq!((v.limit, v.pass), (None, None), "no V_max: not judged");

    let mut rec = Safety::new(DT, None);
    rec.record(&StepView {
        t: 0.0,
        guideway: &g,
        midspans: &[],
        wheels: Wheels::Forces {
            points: &[(0.0, 0.0, 0.0)],
            forces: &[1e4],
        },
        iterations: 0,
        collision: false,
    })
    .unwrap();
    assert!(rec.report().is_none());
}

// ------------------------------------------------------------------- end to end, `maglev run`

fn out_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("maglev-safety-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn run(name: &str, args: &[&str]) -> PathBuf {
    let d = out_dir(name);
    let o = Command::new(env!("CARGO_BIN_EXE_maglev"))
        .arg("run")
        .args(args)
        .args(["--out", d.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    d
}

/// response.csv read back: the header and the columns.
fn csv(dir: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(dir.join("response.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let mut cols = vec![Vec::new(); header.len()];
    for l in lines {
        for (c, cell) in cols.iter_mut().zip(l.split(',')) {
            c.push(cell.parse().unwrap_or(f64::NAN));
        }
    }
    (header, cols)
}

fn col<'a>(h: &[String], cols: &'a [Vec<f64>], name: &str) -> &'a [f64] {
    &cols[h.iter().position(|x| x == name).unwrap()]
}

fn safety(dir: &Path) -> (serde_json::Value, serde_json::Value) {
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    (s["safety"].clone(), s)
}

/// The row of the smallest (`lowest`) or largest value, its first occurrence.
fn arg(v: &[f64], lowest: bool) -> usize {
    let mut k = 0;
    for (i, &x) in v.iter().enumerate() {
        if (lowest && x < v[k]) || (!lowest && x > v[k]) {
            k = i;
        }
    }
    k
}

/// paper-4.2 (the Fig. 1 car, 4 magnet wheels) under the EMS geometry and the paper's law,
/// which collides: the gap figures equal the gap columns' minima, the collision count the
/// collision column's sum, the body figures car 1's acceleration column, and the coil
/// figures summary.json's coil figures.
#[test]
fn maglev_figures_are_the_response_columns() {
    for (name, sets) in [("paper", vec![]), ("ems", vec!["--set", "geometry=ems"])] {
        let mut args = vec![
            "paper-4.2",
            "--set",
            "output.probes=[\"wheel1.gap_z\",\"wheel2.gap_z\",\"wheel3.gap_z\",\"wheel4.gap_z\",\"wheel1.gap_y\",\"wheel2.gap_y\",\"wheel3.gap_y\",\"wheel4.gap_y\",\"car1.body.az\"]",
        ];
        args.extend(sets);
        let d = run(name, &args);
        let (h, cols) = csv(&d);
        let (s, summary) = safety(&d);
        let t = col(&h, &cols, "t");
        let m = &s["maglev"];
        // Levitation: each magnet's minimum, and the smallest with its magnet and time.
        let mut best = (f64::INFINITY, 0, 0);
        for w in 1..=4 {
            let g = col(&h, &cols, &format!("wheel{w}.gap_z"));
            let k = arg(g, true);
            let per = &m["levitation_gap_per_magnet"][w - 1];
            assert_eq!(per["magnet"], format!("wheel{w}.z"));
            assert_eq!(per["min_m"].as_f64().unwrap(), g[k], "{name} wheel{w}");
            assert_eq!(per["t_s"].as_f64().unwrap(), t[k]);
            if g[k] < best.0 {
                best = (g[k], w, k);
            }
        }
        let lev = &m["levitation_gap_min"];
        assert_eq!(lev["value"].as_f64().unwrap(), best.0);
        assert_eq!(lev["at"], format!("wheel{}.z", best.1));
        assert_eq!(lev["t_s"].as_f64().unwrap(), t[best.2]);
        assert_eq!(lev["pass"], best.0 > 0.0);
        // Guidance: gap_y is the left magnet's h0 + d; the right one's is h0 − d = 2h0 − gap_y.
        let guide = (1..=4)
            .flat_map(|w| {
                col(&h, &cols, &format!("wheel{w}.gap_y"))
                    .iter()
                    .flat_map(|&l| [l, 2.0 * H0 - l])
                    .collect::<Vec<_>>()
            })
            .fold(f64::INFINITY, f64::min);
        let g = m["guidance_gap_min"]["value"].as_f64().unwrap();
        assert!((g - guide).abs() <= 1e-15, "{name}: {g} vs {guide}");
        // Collisions: the collision column.
        let coll = col(&h, &cols, "collision");
        let steps = coll.iter().filter(|&&c| c == 1.0).count();
        let c = &m["collision_steps"];
        assert_eq!(c["value"].as_f64().unwrap(), steps as f64);
        assert_eq!(c["pass"], steps == 0);
        match coll.iter().position(|&c| c == 1.0) {
            Some(k) => assert_eq!(c["t_s"].as_f64().unwrap(), t[k]),
            None => assert!(c["t_s"].is_null()),
        }
        assert_eq!(name == "ems", steps > 0, "the EMS geometry collides");
        if steps > 0 {
            assert_eq!(s["pass"], false, "a collision fails the run");
        }
        // Coils: summary.json's run-wide coil figures, from the time loop's tally.
        assert_eq!(m["current_peak"]["value"], summary["peak_current_A"]);
        assert_eq!(m["voltage_peak"]["value"], summary["peak_voltage_V"]);
        assert!(m["current_peak"]["limit"].is_null());
        // Body: car 1's acceleration column.
        let az = col(&h, &cols, "car1.body.az");
        let abs: Vec<f64> = az.iter().map(|a| a.abs()).collect();
        let k = arg(&abs, false);
        let peak = &s["body_acceleration_peak"];
        assert_eq!(peak["value"].as_f64().unwrap(), abs[k]);
        assert_eq!(peak["t_s"].as_f64().unwrap(), t[k]);
        assert_eq!(peak["pass"], abs[k] <= BODY_ACCEL_LIMIT);
        let rms = (az.iter().map(|a| a * a).sum::<f64>() / az.len() as f64).sqrt();
        let got = s["body_acceleration_rms"]["value"].as_f64().unwrap();
        assert!((got - rms).abs() <= 1e-12 * rms, "{got} vs {rms}");
        assert!(s.get("wheel_rail").is_none());
    }
}

/// One paper-5 wheel/rail car over 3 spans: ΔP/P of every contact from its force column and
/// the hand static load 71 613 N, the lift-off count from the force columns.
#[test]
fn wheel_rail_figures_are_the_force_columns() {
    let probes: Vec<String> = (1..=8)
        .map(|w| format!("\"wheel{w}.force_z\""))
        .chain(["\"car1.body.az\"".to_string()])
        .collect();
    let probes = format!("output.probes=[{}]", probes.join(","));
    let d = run(
        "wheel-rail",
        &[
            "paper-5",
            "--set",
            "bridge.spans_m=[30.0, 30.0, 30.0]",
            "--set",
            "train=wheel-rail",
            "--set",
            "train.cars=1",
            "--set",
            "t_end=1.5",
            "--set",
            &probes,
        ],
    );
    let (h, cols) = csv(&d);
    let (s, _) = safety(&d);
    let t = col(&h, &cols, "t");
    let w = &s["wheel_rail"];
    let mut best = (f64::NEG_INFINITY, 0, 0);
    for k in 1..=8 {
        let p = col(&h, &cols, &format!("wheel{k}.force_z"));
        let dp: Vec<f64> = p.iter().map(|&p| (P0 - p) / P0).collect();
        let j = arg(&dp, false);
        let per = &w["per_contact"][k - 1];
        assert_eq!(per["wheel"], format!("wheel{k}"));
        let p0 = per["static_load_N"].as_f64().unwrap();
        assert!((p0 - P0).abs() <= 1e-9 * P0, "P0 {p0}");
        let got = per["unloading"].as_f64().unwrap();
        assert!((got - dp[j]).abs() <= 1e-9, "wheel{k}: {got} vs {}", dp[j]);
        if dp[j] > best.0 {
            best = (dp[j], k, j);
        }
    }
    let u = &w["unloading_max"];
    assert!((u["value"].as_f64().unwrap() - best.0).abs() <= 1e-9);
    assert_eq!(u["at"], format!("wheel{}", best.1));
    assert_eq!(u["t_s"].as_f64().unwrap(), t[best.2]);
    assert_eq!(u["pass"], best.0 <= UNLOADING_LIMIT);
    let lifted: Vec<usize> = (0..t.len())
        .filter(|&r| (1..=8).any(|k| col(&h, &cols, &format!("wheel{k}.force_z"))[r] <= 0.0))
        .collect();
    let l = &w["lift_off_steps"];
    assert_eq!(l["value"].as_f64().unwrap(), lifted.len() as f64);
    assert_eq!(l["pass"], lifted.is_empty());
    assert!(
        !lifted.is_empty(),
        "this passage lifts off past the viaduct's ends"
    );
    assert_eq!(l["t_s"].as_f64().unwrap(), t[lifted[0]]);
    assert_eq!(w["derailment_quotient"]["computed"], false);
    assert!(s.get("maglev").is_none());
}
