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

#[test]
fn heavy_ems_magnets_keep_their_gaps() {
    for (mass, speed) in [("200", "150"), ("2000", "100"), ("2000", "150")] {
        let d = out_dir(&format!("{mass}-{speed}"));
        let o = maglev(&[
            "run",
            "paper-4.2",
            "--set",
            "geometry=ems",
            "--set",
            "law=state",
            "--set",
            &format!("vehicle.wheel_mass_kg={mass}"),
            "--set",
            &format!("speed={speed}"),
            "--set",
            GAINS,
            "--strict",
            "--out",
            d.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(d.join("summary.json")).unwrap())
                .unwrap();
        assert_eq!(s["collision_steps"], 0);
        let h0 = 0.01;
        for g in s["gaps"].as_array().unwrap() {
            let (lo, hi) = (g["min_m"].as_f64().unwrap(), g["max_m"].as_f64().unwrap());
            assert!(
                lo > 0.5 * h0 && hi < 1.5 * h0,
                "{mass} kg at {speed} m/s: {g}"
            );
        }
        let _ = std::fs::remove_dir_all(&d);
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
