//! The state law (`controller.law = "state"`) holds EMS magnets that the paper's law cannot:
//! the Fig. 1 car under its rails (`geometry = "ems"`) on heavy magnets crosses the paper-4.2
//! span over the rough rail with every gap inside (0.5, 1.5)·h0, no collision, and
//! `maglev stability` finds every pole of the same linear model in the left half-plane. The
//! same run under the paper's law collides (tests/cli_run.rs), so these checks fail when the
//! law stops holding the gap.

use std::path::PathBuf;
use std::process::{Command, Output};

const GAINS: &str = "controller.state={kp_V_per_m=51600.0, kd_V_s_per_m=1600.0, \
                     ka_V_s2_per_m=40.0, ki_V_per_m_s=4300.0, kc_V_per_A=10.0, vmax_V=500.0}";

fn maglev(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_maglev"))
        .args(args)
        .output()
        .unwrap()
}

fn out_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("maglev-state-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Runs `maglev run SCENARIO --set geometry=ems --set law=state --set GAINS` with `sets`,
/// expecting success; returns summary.json.
fn run_state(scenario: &str, name: &str, sets: &[String]) -> serde_json::Value {
    let sets: Vec<String> = std::iter::once(GAINS.to_string())
        .chain(sets.iter().cloned())
        .collect();
    run_ems_state(scenario, name, &sets)
}

/// Runs `maglev run SCENARIO --set geometry=ems --set law=state` with `sets` (the gains
/// among them), expecting success; returns summary.json.
fn run_ems_state(scenario: &str, name: &str, sets: &[String]) -> serde_json::Value {
    let d = out_dir(name);
    let o = ems_state(scenario, &d, sets);
    assert!(
        o.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let s = summary(&d);
    let _ = std::fs::remove_dir_all(&d);
    s
}

/// `maglev run SCENARIO --set geometry=ems --set law=state` with `sets`, into `d`.
fn ems_state(scenario: &str, d: &std::path::Path, sets: &[String]) -> Output {
    let mut args = vec![
        "run",
        scenario,
        "--set",
        "geometry=ems",
        "--set",
        "law=state",
        "--out",
        d.to_str().unwrap(),
    ];
    for s in sets {
        args.extend(["--set", s]);
    }
    maglev(&args)
}

/// `maglev run SCENARIO` of a train under the state law on 500 kg EMS magnets (the
/// scenario's own gains) into `d`.
fn run_train_500kg(scenario: &str, d: &std::path::Path) -> Output {
    ems_state(scenario, d, &["train.wheel_mass_kg=500".to_string()])
}

fn summary(d: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(d.join("summary.json")).unwrap()).unwrap()
}

fn f(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// Issue 26's limits on one run: no collision, every gap inside (0.5, 1.5)·h0, every coil's
/// |V| within the law's V_max (from summary.json's coil figures, which must be there).
fn within_limits(s: &serde_json::Value, what: &str) {
    let h0 = 0.01;
    assert_eq!(s["collision_steps"], 0, "{what}");
    for g in s["gaps"].as_array().unwrap() {
        let (lo, hi) = (f(&g["min_m"]), f(&g["max_m"]));
        assert!(lo > 0.5 * h0 && hi < 1.5 * h0, "{what}: {g}");
    }
    let v_max = f(&s["voltage_limit_V"]);
    assert_eq!(v_max, 500.0, "{what}: the GAINS' vmax_V");
    let coils = s["coils"].as_array().unwrap();
    assert_eq!(coils.len(), s["gaps"].as_array().unwrap().len(), "{what}");
    for c in coils {
        assert!(f(&c["peak_voltage_V"]) <= v_max, "{what}: {c}");
        assert!(f(&c["peak_current_A"]) > 0.0, "{what}: {c}");
    }
    assert!(f(&s["peak_voltage_V"]) <= v_max, "{what}");
    assert!(f(&s["min_gap_m"]) > 0.5 * h0, "{what}");
}

/// Issue 26 point 6: the Fig. 1 car under its rails with magnets of 200, 1000 and 2000 kg at
/// 10, 100 and 150 m/s over the rough paper-4.2 span. (About 1 s of the test profile a run;
/// the 10 m/s runs are 4100 steps.)
#[test]
fn heavy_ems_magnets_keep_their_gaps() {
    for mass in [200, 1000, 2000] {
        for speed in [10, 100, 150] {
            let what = format!("{mass} kg at {speed} m/s");
            let s = run_state(
                "paper-4.2",
                &format!("{mass}-{speed}"),
                &[
                    format!("vehicle.wheel_mass_kg={mass}"),
                    format!("speed={speed}"),
                ],
            );
            within_limits(&s, &what);
        }
    }
}

/// The `targets` block of a `stability --format json` report `r`: all eight, each value
/// against its limit (not only its `met` flag), and `all_met`.
fn every_target_met(r: &serde_json::Value, what: &str) {
    let targets = r["targets"]["targets"].as_array().unwrap();
    assert_eq!(targets.len(), 8, "{what}");
    for t in targets {
        let (v, limit) = (f(&t["value"]), f(&t["limit"]));
        let met = if t["sense"] == "<=" {
            v <= limit
        } else {
            v >= limit
        };
        assert!(met && t["met"] == true, "{what}: {t}");
    }
    assert_eq!(r["targets"]["all_met"], true, "{what}");
}

/// Issue 39: the designed gains of a guided vehicle. For the Fig. 1 car on 1000 kg magnets
/// (200 and 2000 kg: docs/levitation.md, by the same commands), designed at its top speed
/// (`speed=150`: the headroom is the irregularity at the case's speed), `maglev stability`
/// with `design = true` for both laws reports every target met (its `targets` block, each
/// value against its limit), and the car under those gains crosses the rough paper-4.2 span
/// at 10, 100 and 150 m/s with no collision, every gap inside (0.5, 1.5)·h0, every |V|
/// within V_max and at most 10 ms saturated. The design works on a rigid rail; the runs are
/// on the flexible span.
#[test]
fn designed_guided_gains_hold_the_fig1_car() {
    let mass = 1000;
    let m = format!("vehicle.wheel_mass_kg={mass}");
    let o = maglev(&[
        "stability",
        "--scenario",
        "paper-4.2",
        "--set",
        "geometry=ems",
        "--set",
        "law=state",
        "--set",
        &m,
        "--set",
        "controller.state={design=true, vmax_V=500.0}",
        "--set",
        "controller.guidance={design=true}",
        "--set",
        "speed=150",
        "--format",
        "json",
    ]);
    assert!(
        o.status.success(),
        "{mass} kg: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let r: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    every_target_met(&r, &format!("{mass} kg"));
    let gains = |key: &str, extra: &str| {
        let g = r[key].as_object().unwrap();
        let kv: Vec<String> = [
            "kp_V_per_m",
            "kd_V_s_per_m",
            "ka_V_s2_per_m",
            "ki_V_per_m_s",
            "kc_V_per_A",
        ]
        .iter()
        .map(|k| format!("{k}={:?}", f(&g[*k])))
        .collect();
        format!("{{{}{extra}}}", kv.join(", "))
    };
    let state = format!("controller.state={}", gains("gains", ", vmax_V=500.0"));
    let guidance = format!("controller.guidance={}", gains("guidance_gains", ""));
    for speed in [10, 100, 150] {
        let what = format!("designed, {mass} kg at {speed} m/s");
        let sets = [
            m.clone(),
            format!("speed={speed}"),
            state.clone(),
            guidance.clone(),
        ];
        let s = run_ems_state("paper-4.2", &format!("designed-{mass}-{speed}"), &sets);
        within_limits(&s, &what);
        let saturated = s["saturated_s"].as_f64().unwrap_or(0.0);
        assert!(saturated <= 0.010, "{what}: {saturated} s saturated");
    }
}

/// Issue 39 on the Fig. 6 carriage of the §5 train (32 magnet wheels, 96 loops: a levitation
/// magnet and a guidance pair each; 338 states with the designed laws) on 500 kg magnets:
/// `maglev stability --scenario paper-5` with `design = true` for both laws reports every
/// target met (each value against its limit, every loop's margins), no zero pole. About two
/// minutes. The same gains in the §5 run (83.33 m/s over the viaduct's rough rail) keep every
/// gap above 6.8 mm but saturate 184 of the 1152 coils, the longest for 104 ms, where on a
/// rigid guideway they peak at 267 V (docs/levitation.md, "The §5 train"): the design's
/// targets are on a rigid guideway, so no run is asserted here. What the report must show is
/// that demand: the `guideway` disturbance (the viaduct's girders under the train, the steps
/// at their joints) asks for more than the supply (`guideway_ratio` 1.47, car 1), where the
/// design's `ratio` is 0.57.
#[test]
fn designed_guided_gains_meet_every_target_on_the_fig6_carriage() {
    let o = maglev(&[
        "stability",
        "--scenario",
        "paper-5",
        "--set",
        "geometry=ems",
        "--set",
        "law=state",
        "--set",
        "train.wheel_mass_kg=500",
        "--set",
        "controller.state={design=true, vmax_V=500.0}",
        "--set",
        "controller.guidance={design=true}",
        "--format",
        "json",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(r["zero_poles"], 0);
    assert_eq!(r["margins"].as_array().unwrap().len(), 96);
    for m in r["margins"].as_array().unwrap() {
        assert!(m["stable_with_delay"] == true, "{m}");
    }
    every_target_met(&r, "the Fig. 6 carriage");
    let h = &r["headroom"];
    assert!(f(&h["ratio"]) <= 0.8, "{h}");
    assert!(f(&h["guideway_ratio"]) > 1.0, "{h}");
}

/// Issue 26 point 6 on the §5 train (12 Fig. 6 carriages, 384 magnets, 35 spans, the Table 1
/// rail at 83.33 m/s; 5000 steps, about 25 s in release) with the scenario's own
/// `[controller.state]` and magnets of 500 kg: `maglev run paper-5 --set geometry=ems --set
/// law=state --set train.wheel_mass_kg=500`. On the paper's massless magnet nodes
/// (`wheel_mass_kg = 0`) the same run collided at every step and is now refused
/// (docs/levitation.md, "The §5 train"), so this fails when the magnets' mass stops reaching
/// the train.
#[test]
fn the_paper_5_train_keeps_its_gaps() {
    let d = out_dir("paper-5");
    let o = run_train_500kg("paper-5", &d);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = summary(&d);
    let _ = std::fs::remove_dir_all(&d);
    // 384 magnet wheels, each a levitation gap and a guidance pair.
    assert_eq!(s["gaps"].as_array().unwrap().len(), 3 * 384);
    within_limits(&s, "paper-5");
}

/// summary.json's coil figures against closed forms: on a smooth rigid rail every magnet
/// stays in its equilibrium, where `i = i0` and `V = R0·i0` (i0 = 43 A, R0 = 1 Ω) under any
/// law; with no voltage bound there is no saturation time.
#[test]
fn coil_figures_at_equilibrium() {
    let d = out_dir("equilibrium");
    let o = maglev(&[
        "run",
        "paper-4.2",
        "--set",
        "model=rigid",
        "--set",
        "irregularity.enabled=false",
        "--set",
        "t_end=0.05",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = summary(&d);
    let _ = std::fs::remove_dir_all(&d);
    let close = |v: f64, want: f64| (v - want).abs() <= 1e-9 * want;
    assert!(close(f(&s["peak_current_A"]), 43.0), "{s}");
    assert!(close(f(&s["peak_voltage_V"]), 43.0), "{s}");
    assert!(close(f(&s["min_gap_m"]), 0.01), "{s}");
    assert!(s["voltage_limit_V"].is_null() && s["saturated_s"].is_null());
    let coils = s["coils"].as_array().unwrap();
    assert_eq!(coils.len(), 12);
    assert_eq!(coils[0]["magnet"], "wheel1.z");
    assert_eq!(coils[11]["magnet"], "wheel4.right");
    for c in coils {
        assert!(close(f(&c["peak_current_A"]), 43.0), "{c}");
        assert!(c["saturated_s"].is_null(), "{c}");
    }
}

/// A tight bound (60 V: the static voltages are R0·i0·h/h0, 43–52 V at the guidance magnets'
/// initial gaps) is hit on the rough rail: the time saturated is a positive whole number of
/// steps within the run, and no coil's |V| exceeds the bound; the same under the paper's law
/// with `controller.vmax_V` (which collides under this geometry, but clamps its voltage).
#[test]
fn a_tight_voltage_bound_saturates() {
    let tight = GAINS.replace("vmax_V=500.0", "vmax_V=60.0");
    for (law, bound) in [("state", tight.as_str()), ("paper", "controller.vmax_V=60")] {
        let d = out_dir(&format!("tight-{law}"));
        let o = maglev(&[
            "run",
            "paper-4.2",
            "--set",
            &format!("law={law}"),
            "--set",
            bound,
            "--set",
            "vehicle.wheel_mass_kg=1000",
            "--set",
            "geometry=ems",
            "--set",
            "t_end=0.2",
            "--out",
            d.to_str().unwrap(),
        ]);
        let s = summary(&d);
        let _ = std::fs::remove_dir_all(&d);
        assert!(o.status.code().is_some(), "{law}");
        assert_eq!(f(&s["voltage_limit_V"]), 60.0, "{law}");
        let sat = f(&s["saturated_s"]);
        let steps = sat / 1e-3;
        assert!(
            sat > 0.0 && sat <= 0.2 + 1e-12 && (steps - steps.round()).abs() < 1e-6,
            "{law}: {sat}"
        );
        for c in s["coils"].as_array().unwrap() {
            assert!(
                f(&c["peak_voltage_V"]) <= 60.0 * (1.0 + 1e-12),
                "{law}: {c}"
            );
        }
    }
}

#[test]
fn the_linear_model_is_stable_with_the_same_gains() {
    let o = maglev(&[
        "stability",
        "--scenario",
        "paper-4.2",
        "--set",
        "geometry=ems",
        "--set",
        "law=state",
        "--set",
        "vehicle.wheel_mass_kg=1000",
        "--set",
        GAINS,
        "--format",
        "json",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(r["law"], "state");
    assert_eq!(r["stable"], true);
    assert!(r["max_real_part"].as_f64().unwrap() < -0.5, "{r}");
}

#[test]
fn state_without_its_gains_names_the_table() {
    let o = maglev(&["run", "paper-4.2", "--set", "law=state"]);
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("controller.state"), "{e}");
    assert_eq!(e.trim().lines().count(), 1, "{e}");
}

/// The headroom's `guideway` disturbance against a run, two methods: the designed `unit`
/// crossing its flexible span at 50 m/s (smooth rail, so the girder's motion under its own
/// load is the only disturbance). The headroom predicts the peak coil voltage from the
/// linear closed loop driven one way by the girder's response to the magnet's static load
/// (ideal gap rate); the run couples the nonlinear magnet, its 300 Hz observer and the
/// girder both ways. Compared: the excess over the static 43 V. Measured: 22.25 V against
/// 21.08 V (5.5 %; at 20 m/s 21.0 against 19.1 V).
#[test]
fn the_guideway_headroom_predicts_the_unit_s_peak_voltage_over_its_span() {
    let sets = ["speed=50", "t_end=0.2"];
    let mut args = vec!["stability", "--scenario", "unit", "--format", "json"];
    for s in sets {
        args.extend(["--set", s]);
    }
    let o = maglev(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let guideway: Vec<&serde_json::Value> = r["headroom"]["disturbances"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|d| d["disturbance"] == "guideway")
        .collect();
    assert_eq!(guideway.len(), 1, "{r}");
    let predicted = f(&guideway[0]["peak_V"]);
    let d = out_dir("unit-guideway");
    let mut args = vec!["run", "unit", "--out", d.to_str().unwrap()];
    for s in sets {
        args.extend(["--set", s]);
    }
    let o = maglev(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let measured = f(&summary(&d)["peak_voltage_V"]);
    let _ = std::fs::remove_dir_all(&d);
    let v_static = 43.0; // R0·i0
    let (p, m) = (predicted - v_static, measured - v_static);
    assert!(
        m > 0.3 * v_static,
        "the girder moved the coil too little to compare: {m} V"
    );
    assert!(
        (p - m).abs() < 0.1 * m,
        "headroom {predicted} V, run {measured} V"
    );
}

/// A run that leaves every state the model describes is refused, not summarised: the README's
/// gains on three Fig. 6 carriages over the undamped light girder (docs/levitation.md, "Trains
/// on a light girder") pump the girder until a gap reaches 1.25e15 m at 3.0 s. Exit 2, one
/// line naming the time, the magnet and the bound, and no output directory (summary.json
/// used to report a smallest gap of −3.28e133 m).
#[test]
fn a_run_whose_gap_diverges_writes_nothing() {
    let case_file = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../docs/cases/light-girder-train.toml"
    );
    let d = out_dir("diverged-gap");
    let o = run_train_500kg(case_file, &d);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    let last = err.lines().last().unwrap_or("");
    assert!(
        last.contains("the run diverged at t = ") && last.contains("beyond 100·h0"),
        "{err}"
    );
    assert!(!d.exists(), "{} was written", d.display());
}
