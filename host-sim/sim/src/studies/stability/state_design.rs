//! The state law's gains designed from the case's linearised plant (issue 26 point 3,
//! docs/levitation.md "Design").
//!
//! # Method
//! 1. **Pole placement on the bare magnet.** One magnet of mass `M` carrying its static load
//!    `p0` under a rigid rail, the state law with ideal sensors, per unit
//!    (`c = 2·p0/(M·h0)`, τ the coil's time constant, `Kp = kp·h0/V_b`, `Kd = kd·h0/V_b`,
//!    `Ki = ki·h0/V_b`, `Kc = kc·i0/V_b`, `ka = 0`), has the characteristic polynomial
//!    ```text
//!    s⁴ + a3·s³ + a2·s² + a1·s + a0,
//!    a3 = (1 + Kc)/τ,  a2 = c·Kd/τ,  a1 = c·(Kp − Kc − 1)/τ,  a0 = c·Ki/τ
//!    ```
//!    (derived in docs/levitation.md; the rows are `super::magnet::write_state_rows`). Four
//!    gains place its four poles: a pair at `ω·(−ζ ± j·√(1 − ζ²))`, one at `−ω` and the
//!    integral's at `−ρ·ω`, with the bandwidth `ω = r·√c` scaled by the magnet's own unstable
//!    pole `√c`. The acceleration gain stays 0: on the bare magnet `a ∝ x`, so it would only
//!    duplicate `kc`.
//! 2. **Verification and a small search.** Every candidate
//!    `(r, ζ, ρ) ∈ {1, 1.25, 1.5, 2, 2.5, 3, 4, 5, 6} × {0.7, 0.5, 0.9} × {0.2, 0.1, 0.3}`,
//!    in that order, is checked on the case's full linear model ([`VehiclePlant`]: body,
//!    spring, every magnet): every pole with real part ≤ −1 s⁻¹ (no zero pole), and at every
//!    magnet the margins with the delay of 1.5 control periods ([`super::margins`]): lower
//!    and upper gain margin ≥ 6 dB, phase margin ≥ 35°, `Ms ≤ 2`. The design is the first
//!    candidate that meets every target and keeps within the supply (a 10 % gap error asks
//!    for at most the headroom, `kp·0.1·h0 ≤ V_max − R0·i0`), else the first that meets every
//!    target (the supply then clamps large errors; the anti-windup holds the integral); none
//!    is an error naming the worst target of the best candidate.
//!
//! # Scope
//! Magnets without guidance (`kind = "unit"`). On a guided vehicle (Fig. 1, Fig. 6) the two
//! magnets of each guidance pair see opposite gaps, so the sum of their integrals is fed by
//! nothing: a pole at exactly 0 whatever the gains, and the pole target cannot be met. The
//! design refuses such a vehicle; its gains are given (`[controller.state]`).

use super::margins::Margins;
use super::report::{all_margins, DELAY_PERIODS};
use super::vehicle::VehiclePlant;
use crate::physics::vehicle::VehicleModel;
use maglev_core::gap::Geometry;
use maglev_core::law::guidance::GuidanceParams;
use maglev_core::law::state::StateParams;
use maglev_core::levitation::GRAVITY;
use maglev_core::{LawKind, Params};

/// The targets (module docs).
pub const GAIN_MARGIN_DB: f64 = 6.0;
pub const PHASE_MARGIN_DEG: f64 = 35.0;
pub const MAX_SENSITIVITY: f64 = 2.0;
pub const MAX_REAL_PART: f64 = -1.0;

/// The bandwidths tried, in units of the magnet's unstable pole `√c`, in order.
pub const CANDIDATE_R: [f64; 9] = [1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0];

/// The state law's gains from the pole placement on a bare magnet of mass `mass` (kg)
/// carrying `p0` (N), coil `inner`, at `(r, ζ, ρ)` (module docs); timing and supply from
/// `base`.
pub fn place(
    mass: f64,
    p0: f64,
    inner: &Params,
    base: &StateParams,
    (r, zeta, rho): (f64, f64, f64),
) -> StateParams {
    let (h0, i0) = (inner.h0, inner.i0);
    let vb = inner.r0 * i0;
    let tau = 2.0 * p0 * h0 / (inner.r0 * i0 * i0);
    let c = 2.0 * p0 / (mass * h0);
    let w = r * c.sqrt();
    let wi = rho * w;
    let a3 = 2.0 * zeta * w + w + wi;
    let a2 = w * w + 2.0 * zeta * w * (w + wi) + w * wi;
    let a1 = w * w * (w + wi) + 2.0 * zeta * w * w * wi;
    let a0 = w * w * w * wi;
    let kc = (tau * a3 - 1.0).max(0.0);
    let kd = tau * a2 / c;
    let kp = tau * a1 / c + kc + 1.0;
    let ki = tau * a0 / c;
    StateParams {
        kp: kp * vb / h0,
        kd: kd * vb / h0,
        ka: 0.0,
        ki: ki * vb / h0,
        kc: kc * vb / i0,
        ..*base
    }
}

/// The guidance law's gains from the same pole placement on the differential mode of a
/// guidance pair on a bare lateral mass `mass` (kg), each magnet at `p0` (N): its lateral
/// force is `−4·p0·x_d` (`x_d = (x_L − x_R)/2`, EMS) where a levitation magnet's is
/// `2·p0·x`, so the mode is the bare levitation magnet of mass `mass/2`
/// (`maglev_core::law::guidance`, docs/levitation.md).
pub fn place_guidance(
    mass: f64,
    p0: f64,
    inner: &Params,
    base: &StateParams,
    candidate: (f64, f64, f64),
) -> GuidanceParams {
    let s = place(0.5 * mass, p0, inner, base, candidate);
    GuidanceParams {
        kp: s.kp,
        kd: s.kd,
        ka: s.ka,
        ki: s.ki,
        kc: s.kc,
    }
}

/// How a candidate fares: its worst target's shortfall (≤ 0: every target met) and which.
#[derive(Clone, Debug)]
pub struct Check {
    /// A 10 % gap error asks for no more than the headroom: `kp·0.1·h0 ≤ V_max − R0·i0`.
    pub within_supply: bool,
    pub shortfall: f64,
    pub worst: String,
    pub max_real_part: f64,
    pub margins: Vec<Margins>,
}

/// Checks `law` on vehicle `v` (module docs, step 2).
pub fn check(
    v: &VehicleModel,
    inner: &Params,
    law: &StateParams,
    geometry: Geometry,
    dt: f64,
) -> crate::Result<Check> {
    check_guided(v, inner, law, None, geometry, dt, |_| true)
}

/// [`check`] with the guidance pairs under `guidance` (when given), counting the margins of
/// the magnets `counted` names only (every pole counts).
pub fn check_guided(
    v: &VehicleModel,
    inner: &Params,
    law: &StateParams,
    guidance: Option<&GuidanceParams>,
    geometry: Geometry,
    dt: f64,
    counted: impl Fn(&str) -> bool,
) -> crate::Result<Check> {
    let kind = LawKind::State(*law);
    let plant = VehiclePlant::guided(v, inner, &kind, guidance, geometry)?;
    let poles = plant.poles()?;
    let max_re = poles.iter().map(|p| p.re).fold(f64::NEG_INFINITY, f64::max);
    let delay = DELAY_PERIODS * dt / law.periods(dt) as f64;
    let margins = all_margins(&plant, delay)?;
    let mut worst = (max_re - MAX_REAL_PART, "max_real_part".to_string());
    let mut consider = |x: f64, what: String| {
        if x > worst.0 || x.is_nan() {
            worst = (if x.is_nan() { f64::INFINITY } else { x }, what);
        }
    };
    for m in margins.iter().filter(|m| counted(&m.magnet)) {
        let n = &m.magnet;
        if !m.stable_with_delay {
            consider(f64::INFINITY, format!("{n}: unstable with the delay"));
            continue;
        }
        let db = |x: Option<f64>| x.unwrap_or(f64::INFINITY);
        consider(
            (GAIN_MARGIN_DB - db(m.gain_low_db)) / GAIN_MARGIN_DB,
            format!("{n}: gain_low_db"),
        );
        consider(
            (GAIN_MARGIN_DB - db(m.gain_high_db)) / GAIN_MARGIN_DB,
            format!("{n}: gain_high_db"),
        );
        consider(
            (PHASE_MARGIN_DEG - db(m.phase_deg)) / PHASE_MARGIN_DEG,
            format!("{n}: phase_deg"),
        );
        consider(
            (m.sensitivity_peak.unwrap_or(f64::INFINITY) - MAX_SENSITIVITY) / MAX_SENSITIVITY,
            format!("{n}: sensitivity_peak"),
        );
    }
    let headroom = law.v_max - inner.r0 * inner.i0;
    let kp_max = guidance.map_or(law.kp, |g| g.kp.max(law.kp));
    Ok(Check {
        within_supply: kp_max * 0.1 * inner.h0 <= headroom,
        shortfall: worst.0,
        worst: worst.1,
        max_real_part: max_re,
        margins,
    })
}

/// The designed gains for vehicle `v` (module docs): timing and supply from `base`, the
/// bandwidth from the first magnet (every magnet of the bundled vehicles has the same mass).
pub fn design(
    v: &VehicleModel,
    inner: &Params,
    base: &StateParams,
    geometry: Geometry,
    dt: f64,
) -> crate::Result<StateParams> {
    let w = v
        .wheels
        .first()
        .ok_or_else(|| crate::Error::invalid("vehicle", "the state law's design needs a magnet"))?;
    if v.wheels.iter().any(|w| w.dof_y.is_some()) {
        // Measured: paper-4.2 under ems at 1000 kg, every candidate keeps 4 poles at 0.
        return Err(crate::Error::invalid(
            "controller.state.design",
            "on a guided vehicle each guidance pair's common-mode integral under the \
             levitation law is a pole at 0 that no gain moves: give the pairs their own law, \
             [controller.guidance] design = true (or its gains), docs/levitation.md",
        ));
    }
    let mass = v.m[(w.dof_z, w.dof_z)];
    if mass <= 0.0 {
        return Err(crate::Error::invalid(
            "vehicle.wheel_mass_kg",
            "the state law's design needs a magnet with mass (> 0)",
        ));
    }
    let p0 = v.p0[0];
    let mut inner = *inner;
    inner.p0 = p0;
    let mut best: Option<(Check, StateParams)> = None;
    let mut first_met = None;
    for r in CANDIDATE_R {
        for zeta in [0.7, 0.5, 0.9] {
            for rho in [0.2, 0.1, 0.3] {
                let law = place(mass, p0, &inner, base, (r, zeta, rho));
                let c = check(v, &inner, &law, geometry, dt)?;
                if c.shortfall <= 0.0 {
                    if c.within_supply {
                        return Ok(law);
                    }
                    first_met.get_or_insert(law);
                }
                if best.as_ref().is_none_or(|b| c.shortfall < b.0.shortfall) {
                    best = Some((c, law));
                }
            }
        }
    }
    if let Some(law) = first_met {
        return Ok(law);
    }
    let worst = best.map_or(String::new(), |b| b.0.worst);
    Err(crate::Error::invalid(
        "controller.state.design",
        format!(
            "no candidate meets every target (best misses {worst}); magnet {mass} kg, \
             load {:.0} N ({:.2}·its weight)",
            p0,
            p0 / (mass * GRAVITY)
        ),
    ))
}

/// What a vehicle design starts from: gains given, or to be designed (from `base`'s timing
/// and supply for the levitation law).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Want<T> {
    Given(T),
    Design,
}

/// The (r, ζ, ρ) candidates in the order they are tried (module docs).
fn candidates() -> impl Iterator<Item = (f64, f64, f64)> {
    CANDIDATE_R.into_iter().flat_map(|r| {
        [0.7, 0.5, 0.9]
            .into_iter()
            .flat_map(move |z| [0.2, 0.1, 0.3].into_iter().map(move |rho| (r, z, rho)))
    })
}

/// The levitation and guidance gains of a guided vehicle `v` (docs/levitation.md, "Design
/// of a guided vehicle"): decentralised, one set per magnet kind.
///
/// 1. Levitation (when to be designed): each levitation candidate in order ([`place`] on
///    the first wheel's vertical mass and load), with the guidance pairs under the first
///    guidance candidate (or the given gains); the first whose levitation magnets meet every
///    margin target and whose poles are left of the target is taken (preferring one within
///    the supply).
/// 2. Guidance (when to be designed): with those levitation gains, each guidance candidate
///    in order ([`place_guidance`] on the first guided wheel's lateral mass); the first that
///    meets every target on the whole vehicle — every pole, every magnet's margins — is the
///    design (preferring one within the supply).
///
/// Every check is on the full linear vehicle ([`VehiclePlant::guided`]) with the delay of the
/// margins; none found is an error naming the worst target of the best candidate.
pub fn design_guided(
    v: &VehicleModel,
    inner: &Params,
    base: &StateParams,
    levitation: Want<StateParams>,
    guidance: Want<GuidanceParams>,
    geometry: Geometry,
    dt: f64,
) -> crate::Result<(StateParams, GuidanceParams)> {
    let lev_wheel = v
        .wheels
        .first()
        .ok_or_else(|| crate::Error::invalid("vehicle", "the state law's design needs a magnet"))?;
    let (gw, guided) = v
        .wheels
        .iter()
        .enumerate()
        .find_map(|(i, w)| w.dof_y.map(|y| (i, y)))
        .ok_or_else(|| {
            crate::Error::invalid(
                "controller.guidance",
                "the vehicle has no guidance magnets (no lateral DOF)",
            )
        })?;
    let (mz, my) = (
        v.m[(lev_wheel.dof_z, lev_wheel.dof_z)],
        v.m[(guided, guided)],
    );
    if mz <= 0.0 || my <= 0.0 {
        return Err(crate::Error::invalid(
            "vehicle.wheel_mass_kg",
            "the state law's design needs magnets with mass (> 0)",
        ));
    }
    let with_p0 = |p0: f64| Params { p0, ..*inner };
    let (lev_inner, guide_inner) = (with_p0(v.p0[0]), with_p0(v.p0[gw]));
    let guide_candidates: Vec<GuidanceParams> = match guidance {
        Want::Given(g) => vec![g],
        Want::Design => candidates()
            .map(|c| place_guidance(my, guide_inner.p0, &guide_inner, base, c))
            .collect(),
    };
    let first_guide = guide_candidates[0];
    let is_lev = |n: &str| n.starts_with("lev");
    let lev = match levitation {
        Want::Given(l) => l,
        Want::Design => {
            let mut best: Option<(Check, StateParams)> = None;
            let mut first_met = None;
            let mut found = None;
            for c in candidates() {
                let law = place(mz, lev_inner.p0, &lev_inner, base, c);
                let ch = check_guided(v, inner, &law, Some(&first_guide), geometry, dt, is_lev)?;
                // Only the levitation loops' own margins decide here; the guidance gains
                // (and with them the lateral poles) are chosen next.
                let lev_short = ch.margins_shortfall(is_lev);
                if lev_short <= 0.0 {
                    if ch.within_supply {
                        found = Some(law);
                        break;
                    }
                    first_met.get_or_insert(law);
                }
                if best.as_ref().is_none_or(|b| lev_short < b.0.shortfall) {
                    best = Some((
                        Check {
                            shortfall: lev_short,
                            ..ch
                        },
                        law,
                    ));
                }
            }
            match found.or(first_met) {
                Some(l) => l,
                None => return Err(no_candidate("controller.state.design", best, mz, v.p0[0])),
            }
        }
    };
    let mut best: Option<(Check, GuidanceParams)> = None;
    let mut first_met = None;
    for g in guide_candidates {
        let ch = check_guided(v, inner, &lev, Some(&g), geometry, dt, |_| true)?;
        if ch.shortfall <= 0.0 {
            if ch.within_supply {
                return Ok((lev, g));
            }
            first_met.get_or_insert(g);
        }
        if best.as_ref().is_none_or(|b| ch.shortfall < b.0.shortfall) {
            best = Some((ch, g));
        }
    }
    match first_met {
        Some(g) => Ok((lev, g)),
        None => Err(no_candidate(
            "controller.guidance.design",
            best,
            my,
            v.p0[gw],
        )),
    }
}

impl Check {
    /// The worst margin shortfall among the magnets `counted` names (the poles aside).
    fn margins_shortfall(&self, counted: impl Fn(&str) -> bool) -> f64 {
        let mut worst = f64::NEG_INFINITY;
        for m in self.margins.iter().filter(|m| counted(&m.magnet)) {
            if !m.stable_with_delay {
                return f64::INFINITY;
            }
            let db = |x: Option<f64>| x.unwrap_or(f64::INFINITY);
            for x in [
                (GAIN_MARGIN_DB - db(m.gain_low_db)) / GAIN_MARGIN_DB,
                (GAIN_MARGIN_DB - db(m.gain_high_db)) / GAIN_MARGIN_DB,
                (PHASE_MARGIN_DEG - db(m.phase_deg)) / PHASE_MARGIN_DEG,
                (m.sensitivity_peak.unwrap_or(f64::INFINITY) - MAX_SENSITIVITY) / MAX_SENSITIVITY,
            ] {
                worst = worst.max(if x.is_nan() { f64::INFINITY } else { x });
            }
        }
        worst
    }
}

/// The refusal of a design that found no candidate, naming `key` and the best's worst target.
fn no_candidate<T>(key: &str, best: Option<(Check, T)>, mass: f64, p0: f64) -> crate::Error {
    let worst = best.map_or(String::new(), |b| b.0.worst);
    crate::Error::invalid(
        key,
        format!(
            "no candidate meets every target (best misses {worst}); magnet {mass} kg, \
             load {p0:.0} N ({:.2}·its weight)",
            p0 / (mass * GRAVITY)
        ),
    )
}
