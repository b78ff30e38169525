//! The linearised stability of a whole case's vehicle (`maglev stability --scenario`): every
//! magnet under the case's law and geometry, the critical magnet mass, and for the gap loop
//! its designed gains with the per-magnet loop poles.

use crate::case::{Case, TrainCase};
use crate::stability::Complex;
use serde::Serialize;

/// The gap loop's gains as reported (per unit; SI seconds).
#[derive(Debug, Serialize)]
pub struct GainsReport {
    pub kp: f64,
    pub kd_s: f64,
    pub tf_s: f64,
    pub x_ref_max: f64,
    /// The reference delay the design assumed (s): the scenario's step, the outer loop's hold.
    pub design_delay_s: f64,
    /// The vehicle's spectral abscissa with that delay (first-order Padé, 1/s).
    pub sampled_max_real_part: f64,
    /// Wheel 1's per-magnet loops with these gains (levitation; guidance pair's differential
    /// mode), the plants the design works on (1/s).
    pub levitation_loop_poles: Vec<Complex>,
    pub guidance_loop_poles: Vec<Complex>,
}

/// `stability --scenario`: the scenario's vehicle, all magnets, rigid rail (SI, 1/s).
#[derive(Debug, Serialize)]
pub struct ScenarioReport {
    pub scenario: String,
    pub geometry: &'static str,
    pub law: &'static str,
    pub magnet_mass_kg: f64,
    pub states: usize,
    pub vehicle_poles: Vec<Complex>,
    pub zero_poles: usize,
    pub note: String,
    pub max_real_part: f64,
    pub stable: bool,
    pub critical_magnet_mass_kg: Option<f64>,
    pub gap_loop: Option<GainsReport>,
}

/// Computes the scenario report (no printing).
pub fn scenario_report(name: &str, sets: &[String]) -> crate::Result<ScenarioReport> {
    use crate::stability::gap_loop::GapLoopPlant;
    use crate::stability::vehicle::{critical_magnet_mass, VehiclePlant, ZERO_POLE};
    use maglev_core::LawKind;
    let case = Case::load(name, sets)?;
    let TrainCase::Fig1 { car: fig, .. } = &case.train else {
        return Err(crate::Error::invalid(
            "vehicle.kind",
            "stability --scenario needs a fig1 vehicle (magnets to analyse)",
        ));
    };
    let fig = fig.clone();
    let Some(inner) = case.controller else {
        return Err(crate::Error::invalid(
            "controller",
            "stability --scenario needs a [controller] section",
        ));
    };
    let law = case.law;
    let geometry = case.geometry;
    let v = crate::vehicle::VehicleModel::fig1(&fig, maglev_core::levitation::GRAVITY)?;
    let plant = VehiclePlant::new(&v, &inner, &law, geometry)?;
    let vd = plant.verdict()?;
    let critical = critical_magnet_mass(&fig, &inner, &law, geometry)?;
    let note = if vd.zero_poles > 0 {
        format!(
            "{} pole(s) with |s| < {ZERO_POLE:e} 1/s, expected: the paper's law holds each \
             magnet's flux g = i/h, hence its force, not its gap, so every rigid-body position \
             of the vehicle (v, w, θx, θy, θz) with the springs unstretched is an equilibrium; \
             they are left out of max_real_part",
            vd.zero_poles
        )
    } else {
        "no zero pole: the gap loop restores every gap to h0".to_string()
    };
    let gap_loop = match law {
        LawKind::Paper | LawKind::State(_) => None,
        LawKind::GapLoop(g) => {
            let loops = crate::stability::design::per_magnet_loops(&v, &inner);
            let (p, s, body) = loops
                .first()
                .ok_or_else(|| crate::Error::invalid("vehicle", "the vehicle has no wheel"))?;
            let lp = |pair| -> crate::Result<Vec<Complex>> {
                crate::stability::eigenvalues(
                    &GapLoopPlant::with_body(p, s, *body, &g, geometry, pair)?.a,
                )
            };
            let sampled =
                VehiclePlant::sampled(&v, &inner, &law, geometry, Some(case.dt))?.verdict()?;
            Some(GainsReport {
                design_delay_s: case.dt,
                sampled_max_real_part: sampled.max_real_part,
                kp: g.kp,
                kd_s: g.kd,
                tf_s: g.tf,
                x_ref_max: g.x_ref_max,
                levitation_loop_poles: lp(false)?,
                guidance_loop_poles: lp(true)?,
            })
        }
    };
    Ok(ScenarioReport {
        scenario: name.to_string(),
        geometry: geometry.as_str(),
        law: law.name().as_str(),
        magnet_mass_kg: fig.wheel_mass,
        states: plant.a.nrows(),
        vehicle_poles: vd.poles,
        zero_poles: vd.zero_poles,
        note,
        max_real_part: vd.max_real_part,
        stable: vd.stable,
        critical_magnet_mass_kg: critical,
        gap_loop,
    })
}
