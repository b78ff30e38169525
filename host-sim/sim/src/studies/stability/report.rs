//! The linearised stability of a whole case's vehicle (`maglev stability --scenario`): every
//! magnet under the case's law and geometry, the critical magnet mass, each magnet's plant
//! and margins (docs/levitation.md), and for the gap loop its designed gains with the
//! per-magnet loop poles.

use crate::input::case::Case;
use crate::studies::stability::coupled::{coupled, Coupled};
use crate::studies::stability::girder::GirderMode;
use crate::studies::stability::headroom::{headroom, Headroom};
use crate::studies::stability::marginal::{self, Honest, Kind};
use crate::studies::stability::margins::{margins_of, Margins};
use crate::studies::stability::multiloop::{vehicle_disk_margin, DiskMargin};
use crate::studies::stability::suspension::{held_poles, target_of};
use crate::studies::stability::targets::{targets, Inputs, Targets, MAX_REAL_PART};
use crate::studies::stability::vehicle::{min_damping, runnable, vehicle_of, VehiclePlant};
use crate::studies::stability::Complex;
use maglev_core::law::guidance::GuidanceParams;
use maglev_core::law::state::StateParams;
use serde::Serialize;

/// One magnet's plant as the analysis used it (SI).
#[derive(Debug, Serialize)]
#[allow(non_snake_case)]
pub struct PlantReport {
    pub magnet: String,
    /// Mass of the node the magnet acts on (kg) and its static load (N).
    pub mass_kg: f64,
    pub static_load_N: f64,
    /// Coil time constant `τ = 2·p0·h0/(R0·i0²)` (s, docs/model.md Eq. 9), nominal gap,
    /// current, resistance and voltage `R0·i0`.
    pub coil_tau_s: f64,
    pub h0_m: f64,
    pub i0_A: f64,
    pub r0_ohm: f64,
    pub v_base_V: f64,
    /// The supply bound of the law (V; the state law's, else the controller's; null: none).
    pub vmax_V: Option<f64>,
    /// The period at which the law updates the coil voltage (s).
    pub control_period_s: f64,
}

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
    /// The verdict is `stable` (no pole within its tolerance of zero or beyond).
    pub stable: bool,
    /// `stable`, `marginal` or `unstable`, with the marginal poles and the modes that cause
    /// them ([`crate::studies::stability::marginal`]).
    pub verdict: Kind,
    pub honest: Honest,
    pub critical_magnet_mass_kg: Option<f64>,
    pub gap_loop: Option<GainsReport>,
    /// Each magnet's plant.
    pub plant: Vec<PlantReport>,
    /// The state law's gains in scenario form (`[controller.state]`); null for other laws.
    pub gains: Option<StateParams>,
    /// The guidance law's gains in scenario form (`[controller.guidance]`); absent without
    /// one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub guidance_gains: Option<GuidanceParams>,
    /// Closed-loop poles of the continuous model with ideal sensors, `[re, im]` (1/s).
    pub ideal_poles: Vec<[f64; 2]>,
    /// Smallest `−re/|s|` over the poles other than the zero poles.
    pub min_damping_ratio: f64,
    /// What the delay of the margins stands for.
    pub delay_note: String,
    /// Each magnet's loop broken at its coil voltage, the others closed, the delay in series.
    pub margins: Vec<Margins>,
    /// Every magnet's loop broken at once: the multi-loop disk margin, the same delay
    /// ([`crate::studies::stability::multiloop`]).
    pub disk_margin: DiskMargin,
    /// The largest `|V|/V_max` in the linearised time response to the reference
    /// disturbances ([`crate::studies::stability::headroom`]).
    pub headroom: Headroom,
    /// The flexible span's bending modes under the magnets (null on a rigid guideway,
    /// [`crate::studies::stability::girder`]).
    pub girder_modes: Option<Vec<GirderMode>>,
    /// The closed loop with those modes coupled at the magnets, the same gains
    /// ([`crate::studies::stability::coupled`]).
    pub coupled: Option<Coupled>,
    /// The poles of the vehicle's suspension on held magnets (1/s, [`super::suspension`]):
    /// what no gain moves.
    pub suspension_poles: Vec<Complex>,
    /// The design targets read off this report ([`super::targets`]).
    pub targets: Targets,
}

/// The delay in series in the margins: 1.5 control periods (module docs of
/// [`crate::studies::stability::margins`]; docs/levitation.md "The delay").
pub const DELAY_PERIODS: f64 = 1.5;

/// Every magnet's margins in `plant` with the delay `delay` (s).
pub fn all_margins(plant: &VehiclePlant, delay: f64) -> crate::Result<Vec<Margins>> {
    let all: Vec<usize> = (0..plant.magnets.len()).collect();
    margins_of(plant, &all, delay)
}

/// Computes the report of scenario `name` as `case` (loaded with its law resolved,
/// [`crate::studies::design::load`]; no printing), with `girder_modes` bending modes per span
/// in the coupled analysis.
pub fn scenario_report(
    name: &str,
    case: &Case,
    girder_modes: usize,
) -> crate::Result<ScenarioReport> {
    case_report(name, case, girder_modes)
}

/// [`scenario_report`] of a case already loaded and resolved (`crate::studies::design`),
/// `name` the scenario's name in the report (the Python binding's scenarios from text).
pub fn case_report(
    name: &str,
    case: &crate::input::case::Case,
    girder_modes: usize,
) -> crate::Result<ScenarioReport> {
    use crate::studies::stability::gap_loop::GapLoopPlant;
    use crate::studies::stability::vehicle::{critical_mass, ZERO_POLE};
    let (v, magnet_mass, build) = vehicle_of(case)?;
    let Some(inner) = case.controller else {
        return Err(crate::Error::invalid(
            "controller",
            "stability --scenario needs a [controller] section",
        ));
    };
    let law = case.law()?;
    runnable(case, &v, &inner, law)?;
    let geometry = case.geometry;
    let (girder, coupled) = coupled(case, girder_modes)?.unzip();
    let guidance = case.guidance()?;
    let plant = VehiclePlant::guided(&v, &inner, &law, guidance.as_ref(), geometry)?;
    let vd = plant.verdict()?;
    let honest = marginal::honest(&plant.a, &plant.states, &vd.poles)?;
    let critical = critical_mass(magnet_mass, |m| {
        VehiclePlant::guided(&build(m)?, &inner, &law, guidance.as_ref(), geometry)
    })?;
    let period = law.control_period(&inner, case.dt);
    let delay = DELAY_PERIODS * period;
    let vmax = law.voltage_bound(&inner);
    let plant_report = plant
        .magnets
        .iter()
        .map(|m| PlantReport {
            magnet: m.name.clone(),
            mass_kg: m.mass,
            static_load_N: m.p0,
            coil_tau_s: m.tau,
            h0_m: inner.h0,
            i0_A: inner.i0,
            r0_ohm: inner.r0,
            v_base_V: inner.r0 * inner.i0,
            vmax_V: vmax,
            control_period_s: period,
        })
        .collect();
    let margins = all_margins(&plant, delay)?;
    let disk_margin = vehicle_disk_margin(&plant, delay)?;
    let rail = crate::studies::stability::guideway_rail::GuidewayRail::of(case, &v)?;
    let headroom = headroom(case, rail.as_ref())?;
    let suspension_poles = held_poles(&v)?;
    let targets = targets(&Inputs {
        max_real_part: vd.max_real_part,
        pole_target: target_of(&suspension_poles, MAX_REAL_PART),
        zero_poles: vd.zero_poles,
        margins: &margins,
        disk: &disk_margin,
        headroom: &headroom,
    });
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
    let gap_loop = match law.gap_loop().copied() {
        None => None,
        Some(g) => {
            let loops = crate::studies::stability::design::per_magnet_loops(&v, &inner);
            let (p, s, body) = loops
                .first()
                .ok_or_else(|| crate::Error::invalid("vehicle", "the vehicle has no wheel"))?;
            let lp = |pair| -> crate::Result<Vec<Complex>> {
                crate::studies::stability::eigenvalues(
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
        magnet_mass_kg: magnet_mass,
        plant: plant_report,
        gains: law.state().copied(),
        guidance_gains: guidance,
        ideal_poles: vd.poles.iter().map(|p| [p.re, p.im]).collect(),
        min_damping_ratio: min_damping(&vd.poles),
        delay_note: format!(
            "{DELAY_PERIODS} control periods of {period:e} s: the zero-order hold of the \
             sampled voltage (half a period on average) and one period of computation"
        ),
        margins,
        states: plant.a.nrows(),
        vehicle_poles: vd.poles,
        zero_poles: vd.zero_poles,
        note,
        max_real_part: vd.max_real_part,
        stable: honest.verdict == Kind::Stable,
        verdict: honest.verdict,
        honest,
        disk_margin,
        headroom,
        critical_magnet_mass_kg: critical,
        gap_loop,
        girder_modes: girder,
        coupled,
        suspension_poles,
        targets,
    })
}
