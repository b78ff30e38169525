//! What summary.json records of a case (`case`): the case serialised. Each SI type carries
//! its keys (`#[serde(rename = "youngs_modulus_Pa")]` on `BeamSection`, …), so no section's
//! fields are listed a second time here.

use super::Case;
use crate::probes::Probes;
use serde::Serialize;

impl Case {
    /// Every value the run uses, in SI with the unit in each key (summary.json `case`): the
    /// case's serialisation, each section by its SI type's keys; the controller is its
    /// section as written (its keys are SI already).
    pub fn record(&self) -> serde_json::Value {
        let mut record = serde_json::to_value(self).unwrap_or_else(unserialisable);
        record["controller"] =
            serde_json::to_value(&self.scenario.controller).unwrap_or_else(unserialisable);
        if let Some(s) = &self.scenario.support {
            record["support"] = serde_json::to_value(s).unwrap_or_else(unserialisable);
        }
        record
    }
}

/// Serialising a case to JSON cannot fail (no map has a non-string key, every enum is
/// representable; `record_holds_every_section_in_si` records every kind), so a failure is
/// a bug of this module.
fn unserialisable(e: serde_json::Error) -> serde_json::Value {
    unreachable!("a case serialises to JSON: {e}")
}

/// The probe names, in response.csv's order.
pub(super) fn probe_names<S: serde::Serializer>(
    p: &Probes,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    p.names.serialize(s)
}

#[cfg(test)]
mod tests {
    use super::super::Case;

    /// summary.json's `case` is the case in SI under keys that name the unit: the files'
    /// values converted by hand here (kN → N, t → kg), one check or more per section and
    /// per train kind, and a damped case's Rayleigh coefficients from their closed form.
    #[test]
    fn record_holds_every_section_in_si() {
        use serde_json::json;
        let r = Case::load("paper-4.2", &[]).unwrap().record();
        assert_eq!(r["bridge"]["spans_m"], json!([25.0]));
        assert_eq!(r["bridge"]["youngs_modulus_Pa"], 3.6e10);
        assert_eq!(r["bridge"]["shear_modulus_Pa"], 1.6e10);
        assert_eq!(r["bridge"]["mass_kg_per_m"], 3.5e3);
        assert!(r["bridge"]["polar_mass_kg_m2_per_m"].is_null());
        assert_eq!(r["train"]["kind"], "fig1");
        assert_eq!(r["train"]["body_mass_kg"], 15e3);
        assert_eq!(r["train"]["jz_kg_m2"], 1.6e6);
        assert_eq!(r["train"]["spring_N_per_m"], 2e5);
        assert_eq!(r["train"]["damper_N_s_per_m"], 1e4);
        assert_eq!(r["train"]["cars"], 1);
        assert_eq!(r["controller"]["i0_A"], 43.0);
        assert_eq!(r["controller"]["nsub"], 1000);
        assert_eq!(r["controller"]["interp"], "linear");
        assert!(r["controller"]["vmax_V"].is_null(), "inf is null in JSON");
        assert_eq!(r["law"], json!({"kind": "paper"}));
        assert_eq!(
            (r["model"].clone(), r["geometry"].clone()),
            (json!("fe"), json!("paper"))
        );
        assert_eq!(r["speed_m_per_s"], 100.0);
        assert!(r["viaduct"].is_null());
        for absent in ["soil", "damping", "ground_receivers_m", "scenario"] {
            assert!(r.get(absent).is_none(), "{absent}");
        }

        let r = Case::load("paper-5", &[]).unwrap().record();
        let v = &r["viaduct"];
        assert_eq!(v["pier"]["youngs_modulus_Pa"], 3.15e10);
        assert_eq!(v["pier"]["height_m"], 10.0);
        assert_eq!(v["pier"]["elements"], 4);
        assert_eq!(v["pier"]["cap_mass_kg"], 150e3);
        assert_eq!(v["bearings"]["vertical_N_per_m"], 1e9);
        assert_eq!(v["bearings"]["drop_m"], 2.1);
        // A rigid 9 × 12 × 2.5 m footing of 2.5 t/m³.
        assert_eq!(v["foundation"]["mass_kg"], 2500.0 * 9.0 * 12.0 * 2.5);
        assert_eq!(v["girder"]["youngs_modulus_Pa"], 3.55e10);
        assert_eq!(r["bridge"]["polar_mass_kg_m2_per_m"], 324.15 * 1e3);
        assert_eq!(r["soil"]["density_kg_per_m3"], 1.9 * 1e3);
        assert_eq!(r["soil"]["damping_ratio"], 0.03);
        assert_eq!(r["train"]["kind"], "maglev");
        assert_eq!(r["train"]["magnets"], 384);
        let r = Case::load("paper-5", &["train=wheel-rail".into()])
            .unwrap()
            .record();
        assert_eq!(
            (r["train"]["kind"].clone(), r["train"]["cars"].clone()),
            (json!("wheel-rail"), json!(12))
        );

        let r = Case::load("train-forces", &[]).unwrap().record();
        let loads = r["train"]["loads"].as_array().unwrap();
        assert_eq!(
            (r["train"]["kind"].clone(), loads.len()),
            (json!("forces"), 16 * 12)
        );
        assert_eq!(
            loads[1],
            json!({"x0_m": -1.5625, "force_N": 25e3, "ey_m": 0.0, "ez_m": 0.0})
        );
        assert_eq!(loads[16]["x0_m"], -25.0);
        assert!(r["controller"].is_null());

        let r = Case::load("unit", &[]).unwrap().record();
        assert_eq!(r["train"]["kind"], "unit");
        assert_eq!(r["train"]["magnet_mass_kg"], 600.0);
        assert_eq!(r["train"]["body_mass_kg"], 3750.0);
        assert_eq!(r["train"]["position_m"], 10.0);

        let damped = "bridge.damping={ratio=0.02, f1_Hz=5.0, f2_Hz=20.0}";
        let r = Case::load("moving-force", &[damped.into()])
            .unwrap()
            .record();
        let (w1, w2) = (
            2.0 * std::f64::consts::PI * 5.0,
            2.0 * std::f64::consts::PI * 20.0,
        );
        let alpha = r["damping"]["alpha_per_s"].as_f64().unwrap();
        let beta = r["damping"]["beta_s"].as_f64().unwrap();
        // ζ(ω) = α/(2ω) + β·ω/2 is the given ratio at both frequencies.
        for w in [w1, w2] {
            assert!(
                (alpha / (2.0 * w) + beta * w / 2.0 - 0.02).abs() < 1e-15,
                "{w}"
            );
        }
        assert_eq!(r["train"]["loads"][0]["force_N"], 36_790.0);
    }
}
