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
//!    `(r, ζ, ρ) ∈ {1, 1.25, 1.5, 2, 2.5, 3, 4, 5, 6} × {0.7, 0.5, 0.9} × {0.2, 0.1, 0.3}`
//!    (a guided vehicle's design, [`design_guided`], adds ρ ∈ {0.05, 0.02} and the soft
//!    placements),
//!    in that order, is checked on the case's full linear model ([`VehiclePlant`]: body,
//!    spring, every magnet): every pole with real part ≤ −1 s⁻¹ (no zero pole; a suspension
//!    mode that is slower than that on held magnets is held to its own real part there,
//!    [`super::suspension`]), and at every
//!    magnet the margins with the delay of 1.5 control periods ([`super::margins`]): lower
//!    and upper gain margin ≥ 6 dB, phase margin ≥ 35°, `Ms ≤ 2`. The design is the first
//!    candidate that meets every target and keeps within the supply (a 10 % gap error asks
//!    for at most the headroom, `kp·0.1·h0 ≤ V_max − R0·i0`), else the first that meets every
//!    target (the supply then clamps large errors; the anti-windup holds the integral); none
//!    is an error naming the worst target of the best candidate.
//!
//! # Scope
//! [`design`]: magnets without guidance (`kind = "unit"`). On a guided vehicle (Fig. 1,
//! Fig. 6) under the levitation law alone the two magnets of each guidance pair see opposite
//! gaps, so the sum of their integrals is fed by nothing: a pole at exactly 0 whatever the
//! gains. [`design_guided`] gives the pairs the guidance law (`[controller.guidance]`), whose
//! common mode has no integral.

use super::margins::Margins;
use super::report::DELAY_PERIODS;
use super::targets::{
    GAIN_MARGIN_DB, MAX_HEADROOM_RATIO, MAX_REAL_PART, MAX_SENSITIVITY, MIN_DISK_ALPHA,
    PHASE_MARGIN_DEG,
};
use super::vehicle::VehiclePlant;
use crate::physics::vehicle::VehicleModel;
use maglev_core::gap::Geometry;
use maglev_core::law::guidance::GuidanceParams;
use maglev_core::law::state::StateParams;
use maglev_core::levitation::GRAVITY;
use maglev_core::{LawKind, Params};

/// The bandwidths tried, in units of the magnet's unstable pole `√c`, in order.
pub const CANDIDATE_R: [f64; 9] = [1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0];

/// The integral poles tried, in units of the bandwidth, in order. The slow ones (0.05,
/// 0.02) leave the suspension's low modes alone: an integral acting at a body mode's
/// frequency feeds it energy (a stiffness `Ki/(jω)` lags by 90°).
pub const CANDIDATE_RHO: [f64; 5] = [0.2, 0.1, 0.3, 0.05, 0.02];

/// The slow pairs' natural frequencies tried by [`Placement::Soft`] (rad/s, in order; each
/// pair's real part is `−0.7·ω_s`, left of −1 s⁻¹).
pub const CANDIDATE_SLOW: [f64; 4] = [1.5, 2.0, 3.0, 5.0];

/// The state law's gains from the pole placement on a bare magnet of mass `mass` (kg)
/// carrying `p0` (N), coil `inner`, at `(r, ζ, ρ)` (module docs); timing and supply from
/// `base`.
pub fn place(
    mass: f64,
    p0: f64,
    inner: &Params,
    base: &StateParams,
    placement: impl Into<Placement>,
) -> StateParams {
    let (h0, i0) = (inner.h0, inner.i0);
    let vb = inner.r0 * i0;
    let tau = 2.0 * p0 * h0 / (inner.r0 * i0 * i0);
    let c = 2.0 * p0 / (mass * h0);
    let [a3, a2, a1, a0] = placement.into().coefficients(c.sqrt());
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

/// Where a candidate puts the bare magnet's four poles (module docs, step 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Placement {
    /// `(r, ζ, ρ)`: a pair at `ω·(−ζ ± j·√(1 − ζ²))`, one at `−ω`, the integral's at `−ρ·ω`,
    /// `ω = r·√c`.
    Spread(f64, f64, f64),
    /// `(r, ζ, ω_s)`: a pair at `ω·(−ζ ± j·√(1 − ζ²))`, `ω = r·√c`, and a slow pair at
    /// `ω_s·(−0.7 ± j·0.71)` (`ω_s` in rad/s): the loop soft at the suspension's frequencies,
    /// where it damps the body on its springs instead of holding the springs' lower ends.
    Soft(f64, f64, f64),
}

impl From<(f64, f64, f64)> for Placement {
    fn from((r, zeta, rho): (f64, f64, f64)) -> Self {
        Placement::Spread(r, zeta, rho)
    }
}

impl Placement {
    /// The characteristic polynomial's `[a3, a2, a1, a0]` (monic quartic) for a magnet whose
    /// unstable pole is `√c` = `sqrt_c`.
    pub fn coefficients(self, sqrt_c: f64) -> [f64; 4] {
        match self {
            Placement::Spread(r, zeta, rho) => {
                let w = r * sqrt_c;
                let wi = rho * w;
                [
                    2.0 * zeta * w + w + wi,
                    w * w + 2.0 * zeta * w * (w + wi) + w * wi,
                    w * w * (w + wi) + 2.0 * zeta * w * w * wi,
                    w * w * w * wi,
                ]
            }
            Placement::Soft(r, zeta, slow) => {
                // (s² + b1·s + b0)(s² + d1·s + d0).
                let w = r * sqrt_c;
                let (b1, b0) = (2.0 * zeta * w, w * w);
                let (d1, d0) = (2.0 * 0.7 * slow, slow * slow);
                [b1 + d1, b0 + d0 + b1 * d1, b1 * d0 + b0 * d1, b0 * d0]
            }
        }
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
    candidate: impl Into<Placement>,
) -> GuidanceParams {
    GuidanceParams::same_as(&place(0.5 * mass, p0, inner, base, candidate))
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
    check_guided(v, inner, law, None, geometry, dt, |_| true, false)
}

/// [`check`] with the guidance pairs under `guidance` (when given), the margins of the
/// magnets `counted` names only (every pole counts). With `poles_first`, a candidate whose
/// poles miss their target is not asked for its margins (they are the costly part; the
/// check then holds none).
#[allow(clippy::too_many_arguments)]
pub fn check_guided(
    v: &VehicleModel,
    inner: &Params,
    law: &StateParams,
    guidance: Option<&GuidanceParams>,
    geometry: Geometry,
    dt: f64,
    counted: impl Fn(&str) -> bool,
    poles_first: bool,
) -> crate::Result<Check> {
    let kind = LawKind::State(*law);
    let plant = VehiclePlant::guided(v, inner, &kind, guidance, geometry)?;
    let poles = plant.poles()?;
    let max_re = poles.iter().map(|p| p.re).fold(f64::NEG_INFINITY, f64::max);
    let target = super::suspension::pole_target(v, MAX_REAL_PART)?;
    let mut worst = (
        (max_re - target) / -MAX_REAL_PART,
        format!("max_real_part: {max_re:.4} 1/s against {target:.4}"),
    );
    let delay = DELAY_PERIODS * dt / law.periods(dt) as f64;
    let margins = if poles_first && worst.0 > 0.0 {
        Vec::new()
    } else {
        let ks: Vec<usize> = (0..plant.magnets.len())
            .filter(|&k| counted(&plant.magnets[k].name))
            .collect();
        super::margins::margins_of(&plant, &ks, delay)?
    };
    let (x, what) = margins_shortfall(&margins);
    if x > worst.0 || x.is_nan() {
        worst = (if x.is_nan() { f64::INFINITY } else { x }, what);
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
    for candidate in unguided_candidates() {
        let law = place(mass, p0, &inner, base, candidate);
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

/// The supply headroom of a candidate pair (the largest `|V|/V_max` over the reference
/// disturbances, and the magnet where it is): the caller's, from its case
/// ([`super::headroom`]).
pub type Headroom<'a> = dyn Fn(&StateParams, &GuidanceParams) -> crate::Result<(f64, String)> + 'a;

/// What a vehicle design starts from: gains given, or to be designed (from `base`'s timing
/// and supply for the levitation law).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Want<T> {
    Given(T),
    Design,
}

/// The candidates of a vehicle without guidance ([`design`], module docs): the spread
/// placements with ρ ∈ {0.2, 0.1, 0.3}, the set the bundled `unit`'s design was made and
/// measured with (the guided design's wider set finds it a softer design within the supply;
/// docs/levitation.md keeps the unit's).
fn unguided_candidates() -> impl Iterator<Item = Placement> {
    spread().filter(|p| matches!(p, Placement::Spread(_, _, rho) if *rho >= 0.1))
}

/// The levitation candidates of a guided vehicle in the order they are tried: every
/// [`Placement::Spread`], then every [`Placement::Soft`].
fn candidates() -> impl Iterator<Item = Placement> {
    spread().chain(soft())
}

/// The guidance candidates in the order they are tried: the soft ones first. A guidance
/// pair holds the body's sway and yaw on its springs, the vehicle's slowest modes, which a
/// loop soft at their frequencies damps (measured on the Fig. 1 car at 200, 1000 and
/// 2000 kg: each design's guidance gains are a soft candidate).
fn guidance_candidates() -> impl Iterator<Item = Placement> {
    soft().chain(spread())
}

fn spread() -> impl Iterator<Item = Placement> {
    CANDIDATE_R.into_iter().flat_map(|r| {
        [0.7, 0.5, 0.9].into_iter().flat_map(move |z| {
            CANDIDATE_RHO
                .into_iter()
                .map(move |rho| Placement::Spread(r, z, rho))
        })
    })
}

fn soft() -> impl Iterator<Item = Placement> {
    CANDIDATE_R.into_iter().flat_map(|r| {
        [0.3, 0.5, 0.7].into_iter().flat_map(move |z| {
            CANDIDATE_SLOW
                .into_iter()
                .map(move |w| Placement::Soft(r, z, w))
        })
    })
}

/// The levitation and guidance gains of a guided vehicle `v` (docs/levitation.md, "Design
/// of a guided vehicle"): decentralised, one set per magnet kind, searched together.
///
/// For each levitation candidate in order ([`place`] on the first wheel's vertical mass and
/// load; only the given gains when they are given) that [`levitation_miss`] lets through,
/// each guidance candidate in order ([`place_guidance`] on the first guided wheel's lateral
/// mass; only the given ones when given; the soft placements first,
/// [`guidance_candidates`]) is checked on the whole vehicle: every pole left of the pole
/// target, then every magnet's margins, then the disk margin and the supply headroom
/// ([`whole_vehicle`]). The first pair meeting every target is the design, preferring within
/// one levitation candidate a guidance candidate within the supply. None found is an error
/// naming the worst target of the best candidate, under `controller.state.design` when no
/// levitation candidate met its margins, else `controller.guidance.design`.
#[allow(clippy::too_many_arguments)]
pub fn design_guided(
    v: &VehicleModel,
    inner: &Params,
    base: &StateParams,
    levitation: Want<StateParams>,
    guidance: Want<GuidanceParams>,
    geometry: Geometry,
    dt: f64,
    headroom: &Headroom<'_>,
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
        Want::Design => guidance_candidates()
            .map(|c| place_guidance(my, guide_inner.p0, &guide_inner, base, c))
            .collect(),
    };
    let first_guide = guide_candidates[0];
    let lev_candidates: Vec<StateParams> = match levitation {
        Want::Given(l) => vec![l],
        Want::Design => candidates()
            .map(|c| place(mz, lev_inner.p0, &lev_inner, base, c))
            .collect(),
    };
    let mut best: Option<Check> = None;
    let keep = |best: &mut Option<Check>, c: Check| {
        if best.as_ref().is_none_or(|b| c.shortfall < b.shortfall) {
            *best = Some(c);
        }
    };
    let mut levitation_met = false;
    for lev in lev_candidates {
        if levitation == Want::Design {
            let miss = levitation_miss(v, inner, &lev, &first_guide, geometry, dt, headroom)?;
            if let Some(miss) = miss {
                if !levitation_met {
                    keep(&mut best, miss);
                }
                continue;
            }
            if !levitation_met {
                best = None;
                levitation_met = true;
            }
        }
        let mut first_met = None;
        for g in &guide_candidates {
            let mut ch = check_guided(v, inner, &lev, Some(g), geometry, dt, |_| true, true)?;
            let mut levitation_spent = false;
            if ch.shortfall <= 0.0 {
                levitation_spent =
                    whole_vehicle(&mut ch, v, inner, &lev, g, geometry, dt, headroom)?;
            }
            if ch.shortfall <= 0.0 {
                if ch.within_supply {
                    return Ok((lev, *g));
                }
                first_met.get_or_insert(*g);
            }
            keep(&mut best, ch);
            if levitation_spent {
                // A levitation magnet spent the supply: no guidance gain changes that.
                break;
            }
        }
        if let Some(g) = first_met {
            return Ok((lev, g));
        }
    }
    let key = if levitation == Want::Design && !levitation_met {
        ("controller.state.design", mz, v.p0[0])
    } else {
        ("controller.guidance.design", my, v.p0[gw])
    };
    Err(no_candidate(key.0, best, key.1, key.2))
}

/// A levitation candidate's miss before it is paired (`None`: it may be paired), with the
/// pairs at the first guidance candidate `g`: the levitation loops' own margins, then the
/// supply headroom, which the rail's irregularity spends at the levitation magnets. The
/// headroom is asked only where `g` leaves the vehicle stable: an unstable response says
/// nothing.
fn levitation_miss(
    v: &VehicleModel,
    inner: &Params,
    lev: &StateParams,
    g: &GuidanceParams,
    geometry: Geometry,
    dt: f64,
    headroom: &Headroom<'_>,
) -> crate::Result<Option<Check>> {
    let is_lev = |n: &str| n.starts_with("lev");
    let ch = check_guided(v, inner, lev, Some(g), geometry, dt, is_lev, false)?;
    let (short, what) = margins_shortfall(&ch.margins);
    if short > 0.0 {
        return Ok(Some(Check {
            shortfall: short,
            worst: what,
            ..ch
        }));
    }
    if ch.max_real_part < 0.0 {
        let (ratio, _) = headroom(lev, g)?;
        if ratio > MAX_HEADROOM_RATIO {
            return Ok(Some(Check {
                shortfall: (ratio - MAX_HEADROOM_RATIO) / MAX_HEADROOM_RATIO,
                worst: format!("headroom_ratio: {ratio:.3} against {MAX_HEADROOM_RATIO}"),
                ..ch
            }));
        }
    }
    Ok(None)
}

/// The whole vehicle's targets on a candidate that meets every other (they cost more): the
/// multi-loop disk margin α ≥ [`MIN_DISK_ALPHA`] and the supply headroom (`headroom`: the
/// largest `|V|/V_max` over the reference disturbances, and the magnet) ≤
/// [`MAX_HEADROOM_RATIO`]; a miss becomes `ch`'s worst target. True when the headroom is
/// missed at a levitation magnet.
#[allow(clippy::too_many_arguments)]
fn whole_vehicle(
    ch: &mut Check,
    v: &VehicleModel,
    inner: &Params,
    lev: &StateParams,
    g: &GuidanceParams,
    geometry: Geometry,
    dt: f64,
    headroom: &Headroom<'_>,
) -> crate::Result<bool> {
    let plant = VehiclePlant::guided(v, inner, &LawKind::State(*lev), Some(g), geometry)?;
    let delay = DELAY_PERIODS * dt / lev.periods(dt) as f64;
    let disk = super::multiloop::vehicle_disk_margin(&plant, delay)?;
    let alpha = disk.alpha.filter(|_| disk.stable_with_delay).unwrap_or(0.0);
    if alpha < MIN_DISK_ALPHA {
        ch.shortfall = (MIN_DISK_ALPHA - alpha) / MIN_DISK_ALPHA;
        ch.worst = format!("disk_margin_alpha: {alpha:.3} against {MIN_DISK_ALPHA}");
        return Ok(false);
    }
    let (ratio, magnet) = headroom(lev, g)?;
    if ratio > MAX_HEADROOM_RATIO {
        ch.shortfall = (ratio - MAX_HEADROOM_RATIO) / MAX_HEADROOM_RATIO;
        ch.worst = format!("{magnet}: headroom_ratio {ratio:.3} against {MAX_HEADROOM_RATIO}");
        return Ok(magnet.starts_with("lev"));
    }
    Ok(false)
}

/// The worst margin shortfall over `margins` and which (the poles aside; `−∞` when there
/// are none).
fn margins_shortfall(margins: &[Margins]) -> (f64, String) {
    let mut worst = (f64::NEG_INFINITY, String::new());
    for m in margins {
        for (x, what) in shortfalls(m) {
            let x = if x.is_nan() { f64::INFINITY } else { x };
            if x > worst.0 {
                worst = (x, format!("{}: {what}", m.magnet));
            }
        }
    }
    worst
}

/// One magnet's shortfall on each margin target (> 0: missed, relative to the target; +∞ for
/// a loop unstable with its delay), with the target's name.
fn shortfalls(m: &Margins) -> [(f64, &'static str); 4] {
    if !m.stable_with_delay {
        return [(f64::INFINITY, "unstable with the delay"); 4];
    }
    let db = |x: Option<f64>| x.unwrap_or(f64::INFINITY);
    [
        (
            (GAIN_MARGIN_DB - db(m.gain_low_db)) / GAIN_MARGIN_DB,
            "gain_low_db",
        ),
        (
            (GAIN_MARGIN_DB - db(m.gain_high_db)) / GAIN_MARGIN_DB,
            "gain_high_db",
        ),
        (
            (PHASE_MARGIN_DEG - db(m.phase_deg)) / PHASE_MARGIN_DEG,
            "phase_deg",
        ),
        (
            (m.sensitivity_peak.unwrap_or(f64::INFINITY) - MAX_SENSITIVITY) / MAX_SENSITIVITY,
            "sensitivity_peak",
        ),
    ]
}

/// The refusal of a design that found no candidate, naming `key` and the best's worst target.
fn no_candidate(key: &str, best: Option<Check>, mass: f64, p0: f64) -> crate::Error {
    let worst = best.map_or(String::new(), |b| b.worst);
    crate::Error::invalid(
        key,
        format!(
            "no candidate meets every target (best misses {worst}); magnet {mass} kg, \
             load {p0:.0} N ({:.2}·its weight)",
            p0 / (mass * GRAVITY)
        ),
    )
}

#[cfg(test)]
mod guided_tests;
