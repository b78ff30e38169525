//! `[controller]` in SI: the magnets' parameters (checked by the core's own
//! `Params::validate`, its errors given under the scenario key), and the levitation law the
//! case asks for ([`LawChoice`]: given, or to be designed by `crate::studies::design::resolve`;
//! the input layer designs nothing).

use super::checks::{in_range, within};
use super::train::TrainCase;
use crate::error::guidance_error;
use crate::input::scenario::{GuidanceSection, Scenario, StateSection};
use crate::{Error, Result};
use maglev_core::gap::Geometry;
use maglev_core::gap_control::GapParams;
use maglev_core::law::guidance::GuidanceParams;
use maglev_core::law::state::StateParams;
use maglev_core::{LawKind, LawName, Params};

/// The levitation law as the input gives it: given, or to be designed from the case's plant
/// by the step between the case and the simulation (`crate::studies::design::resolve`; the input
/// layer runs no design).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LawChoice {
    Given(LawKind),
    /// The gap loop's gains, designed for the case's vehicle (docs/gap-loop.md).
    DesignGapLoop,
    /// The state law's gains, designed (docs/levitation.md); timing and supply as given.
    DesignState(StateParams),
}

impl LawChoice {
    /// The law as far as its properties go (its sensors, control period, supply bound:
    /// `maglev_core::law`'s questions), whether its gains are given or still to be designed
    /// (a design keeps the law, its timing and its supply; only the gains change).
    pub fn kind(&self) -> LawKind {
        match *self {
            LawChoice::Given(k) => k,
            LawChoice::DesignGapLoop => LawKind::GapLoop(GapParams::designed()),
            LawChoice::DesignState(s) => LawKind::State(s),
        }
    }
}

/// The guidance pairs' law as the input gives it (`[controller.guidance]`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum GuidanceChoice {
    /// No `[controller.guidance]`: each guidance magnet runs the levitation law on its own gap.
    #[default]
    None,
    /// The guidance law (`maglev_core::law::guidance`) with these gains.
    Given(GuidanceParams),
    /// Its gains designed for the case's vehicle (`crate::studies::design::resolve`).
    Design,
}

impl GuidanceChoice {
    /// Whether the case has no `[controller.guidance]`.
    pub fn is_none(&self) -> bool {
        matches!(self, GuidanceChoice::None)
    }
}

/// As summary.json records it: the gains under their serde names, or
/// `{"design": "pending"}`; absent without `[controller.guidance]`.
impl serde::Serialize for GuidanceChoice {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        match self {
            GuidanceChoice::Given(g) => g.serialize(s),
            GuidanceChoice::Design => serde_json::json!({"design": "pending"}).serialize(s),
            GuidanceChoice::None => s.serialize_none(),
        }
    }
}

/// `[controller.guidance]`: refused unless the levitation law is the state law (whose
/// timing and supply the guidance law shares); every gain finite, at most the scenario's
/// largest magnitude and not negative, each error naming its key.
pub(super) fn guidance(sc: &Scenario, law: &LawChoice) -> Result<GuidanceChoice> {
    let Some(section) = sc.controller.as_ref().and_then(|c| c.law.guidance) else {
        return Ok(GuidanceChoice::None);
    };
    if law.kind().state().is_none() {
        return Err(crate::error::guidance_needs_state_law());
    }
    match section {
        GuidanceSection::Design { .. } => Ok(GuidanceChoice::Design),
        GuidanceSection::Gains(g) => {
            for (field, v) in g.gains() {
                let key = format!("controller.guidance.{}", field.key.unwrap_or(field.name));
                if v.is_finite() {
                    in_range(&key, v)?;
                }
            }
            g.validate().map_err(guidance_error)?;
            Ok(GuidanceChoice::Given(g))
        }
    }
}

/// The controller parameters in SI (p0 is set per magnet by the simulation).
pub(super) fn controller(sc: &Scenario, dt: f64) -> Result<Params> {
    let Some(c) = &sc.controller else {
        return Err(Error::invalid(
            "controller",
            "the scenario has no [controller] section",
        ));
    };
    // The core's own type as read; the static load is set per magnet by the simulation.
    let p = Params {
        p0: 1.0,
        dt,
        ..c.magnet
    };
    for (key, v) in [
        ("controller.i0_A", p.i0),
        ("controller.h0_m", p.h0),
        ("controller.r0_ohm", p.r0),
        ("controller.kp_V_m_per_A", p.kp),
        ("controller.ki_V_m_per_A_s", p.ki),
        ("controller.vmax_V", p.v_max),
    ] {
        if v.is_finite() {
            in_range(key, v)?;
        }
    }
    if p.h0 > 0.0 && p.h0.is_finite() {
        // Smaller gaps make the sub-step coefficients of Eq. 14 overflow (h/τ = inf at 1e-300).
        within(
            "controller.h0_m",
            p.h0,
            1e-4,
            1.0,
            "m: a tenth of a millimetre to a metre; EMS gaps are 8–10 mm",
        )?;
    }
    p.validate().map_err(controller_error)?;
    Ok(p)
}

/// A core parameter error under the scenario key that holds the value: the core names the
/// field by its key in `[controller]` ([`maglev_core::Field`]); the step is `run.dt_s`.
fn controller_error(e: maglev_core::ParamError) -> Error {
    let field = e.field();
    let key = match field.key {
        _ if field.is(maglev_core::levitation::fields::DT) => "run.dt_s".to_string(),
        Some(k) if field.law.is_none() => format!("controller.{k}"),
        _ => "controller".to_string(),
    };
    Error::invalid(key, e.to_string())
}

/// The levitation law (`controller.law`); the paper's without a controller section. Designs
/// are left to `crate::studies::design::resolve`.
pub(super) fn law(
    sc: &Scenario,
    train: &TrainCase,
    controller: Option<&Params>,
    geometry: Geometry,
) -> Result<LawChoice> {
    let Some((c, Some(_))) = sc.controller.as_ref().map(|c| (c, controller)) else {
        return Ok(LawChoice::Given(LawKind::Paper));
    };
    match c.law.law {
        LawName::Paper => Ok(LawChoice::Given(LawKind::Paper)),
        LawName::State => state_law(c.law.state.as_ref(), geometry),
        LawName::GapLoop => Ok(match train {
            // Designed for this case's vehicle; a train without magnets runs none.
            TrainCase::Fig1 { .. } | TrainCase::Maglev { .. } | TrainCase::Unit(_) => {
                LawChoice::DesignGapLoop
            }
            TrainCase::Forces(_) | TrainCase::WheelRail { .. } | TrainCase::HighSpeed { .. } => {
                LawChoice::Given(LawKind::GapLoop(GapParams::designed()))
            }
        }),
    }
}

/// `[controller.state]`: its gains, or `design = true` (then no gain may be given).
/// The state law holds a magnet with mass (it feeds back the magnet's own acceleration, and
/// its gains are made for a plant with that mass, docs/levitation.md). The paper's magnet
/// nodes are massless (`wheel_mass_kg = 0`): there the law has nothing to hold and every
/// step of paper-5 collides, so the case is refused naming the key that gives the magnets
/// their mass.
pub(super) fn state_law_magnets(train: &TrainCase) -> Result<()> {
    let (key, mass) = match train {
        TrainCase::Fig1 { car, .. } => ("vehicle.wheel_mass_kg", car.wheel_mass),
        TrainCase::Maglev { magnet_mass, .. } => ("train.wheel_mass_kg", *magnet_mass),
        _ => return Ok(()),
    };
    if mass > 0.0 {
        return Ok(());
    }
    Err(Error::invalid(
        key,
        "is 0 (the paper's massless magnet nodes), and law = \"state\" holds magnets with mass: \
         give them one, e.g. 500 (docs/levitation.md)",
    ))
}

fn state_law(s: Option<&StateSection>, geometry: Geometry) -> Result<LawChoice> {
    let s = s.ok_or_else(|| {
        Error::invalid(
            "controller.state",
            "law = \"state\" needs its gains: kp_V_per_m, kd_V_s_per_m, ka_V_s2_per_m, \
             ki_V_per_m_s, kc_V_per_A, vmax_V, or design = true (docs/scenarios.md)",
        )
    })?;
    let gains = [
        ("kp_V_per_m", s.kp_V_per_m),
        ("kd_V_s_per_m", s.kd_V_s_per_m),
        ("ka_V_s2_per_m", s.ka_V_s2_per_m),
        ("ki_V_per_m_s", s.ki_V_per_m_s),
        ("kc_V_per_A", s.kc_V_per_A),
    ];
    for (key, v) in gains.iter().chain(&[
        ("vmax_V", Some(s.vmax_V)),
        ("rate_Hz", Some(s.rate_Hz)),
        ("observer_Hz", Some(s.observer_Hz)),
    ]) {
        if let Some(v) = v.filter(|v| v.is_finite()) {
            in_range(&format!("controller.state.{key}"), v)?;
        }
    }
    let given = |k: &str, v: Option<f64>| {
        v.ok_or_else(|| {
            Error::invalid(
                format!("controller.state.{k}"),
                "is needed unless design = true (docs/scenarios.md)",
            )
        })
    };
    let gain = |i: usize| match s.design {
        true => Ok(0.0),
        false => given(gains[i].0, gains[i].1),
    };
    let law = StateParams {
        kp: gain(0)?,
        kd: gain(1)?,
        ka: gain(2)?,
        ki: gain(3)?,
        kc: gain(4)?,
        v_max: s.vmax_V,
        rate_hz: s.rate_Hz,
        observer_hz: s.observer_Hz,
        geometry,
    };
    if s.design {
        if let Some((k, _)) = gains.iter().find(|(_, v)| v.is_some()) {
            return Err(Error::invalid(
                format!("controller.state.{k}"),
                "is designed with design = true; give the gains or design, not both",
            ));
        }
    }
    law.validate()
        .map_err(|e| Error::invalid("controller.state", e.to_string()))?;
    Ok(if s.design {
        LawChoice::DesignState(law)
    } else {
        LawChoice::Given(LawKind::State(law))
    })
}

/// The law as summary.json records it: `kind` (its name) and the law's own parameters under
/// their serde names (`maglev_core::law`), whichever law it is; a law still to be designed is
/// `{"kind": …, "design": "pending"}`.
impl serde::Serialize for LawChoice {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde_json::{json, Value};
        let record = match self {
            LawChoice::Given(law) => {
                let mut record = serde_json::Map::new();
                record.insert("kind".into(), law.name().as_str().into());
                // Externally tagged: a unit variant is its name, a variant with parameters
                // `{name: {…}}`.
                if let Ok(Value::Object(tagged)) = serde_json::to_value(law) {
                    for (_, params) in tagged {
                        if let Value::Object(p) = params {
                            record.extend(p);
                        }
                    }
                }
                Value::Object(record)
            }
            LawChoice::DesignGapLoop => json!({"kind": "gap-loop", "design": "pending"}),
            LawChoice::DesignState(_) => json!({"kind": "state", "design": "pending"}),
        };
        record.serialize(s)
    }
}

#[cfg(test)]
mod tests {
    use super::super::Case;
    use super::*;
    use maglev_core::Scheme;

    #[test]
    fn laws_and_schemes_resolve() {
        // The input layer leaves the gap loop's design to crate::studies::design::resolve.
        let c = Case::load("paper-4.2", &["law=gap-loop".into()]).unwrap();
        assert_eq!(c.law, LawChoice::DesignGapLoop);
        assert!(c.law().is_err());
        let c = Case::load("paper-4.2", &["scheme=accurate".into()]).unwrap();
        assert_eq!(c.controller.unwrap().scheme, Scheme::Accurate);
    }

    /// `law = "state"` on the paper's massless magnet nodes is refused naming the mass key
    /// (paper-5 under it collided at 4 994 of 5 000 steps); with a mass it resolves.
    #[test]
    fn the_state_law_needs_magnets_with_mass() {
        const GAINS: &str = "controller.state={kp_V_per_m=51600.0, kd_V_s_per_m=1600.0, \
            ka_V_s2_per_m=40.0, ki_V_per_m_s=4300.0, kc_V_per_A=10.0, vmax_V=500.0}";
        for (scenario, key) in [
            ("paper-5", "train.wheel_mass_kg"),
            ("paper-4.2", "vehicle.wheel_mass_kg"),
        ] {
            let mut sets = vec!["law=state".to_string(), "geometry=ems".to_string()];
            if scenario == "paper-4.2" {
                sets.push(GAINS.to_string());
            }
            let e = Case::load(scenario, &sets).unwrap_err().to_string();
            assert!(e.starts_with(&format!("{key}: is 0")), "{e}");
            sets.push(format!("{key}=500"));
            Case::load(scenario, &sets).unwrap();
        }
    }
}
