//! The gap loop's gains designed from the scenario's own linearised plant (issue 8, item 7).
//!
//! # Structure and sign
//! The gains are the core's PD with a filtered derivative (`GapParams`: `kp`, `kd`, `tf`;
//! `x_ref_max = 0.5`), the same on every magnet. The sign follows the geometry: a magnet must
//! ask for *more* force when its gap opens under "ems" (`kp, kd > 0`) and for *less* under
//! "paper", where an opening gap means the wheel rose above its rail (`kp, kd < 0`); so
//! `sign(kp) = sign(kd) = −levitation_sign` ([`Geometry::levitation_sign`]). The guidance pair
//! has the same sign in both geometries (docs/model.md §2).
//!
//! # Method: pole-region placement by search
//! Three gains cannot place the 6–7 poles of even one magnet's loop, so the design places the
//! region instead: it minimises the spectral abscissa `α` (largest real part; target `α < 0`,
//! as far left as the structure allows) of
//! 1. the per-magnet loops cut out of the scenario's vehicle ([`per_magnet_loops`]): for each
//!    wheel node its mass, the stiffness and damping of its own DOF (`K`, `C` diagonals) and
//!    the body share `p0/9.81` it carries, once as a levitation magnet (force gain 1) and once
//!    as the differential mode of its guidance pair (gain 2, `GapLoopPlant::guidance_pair`);
//!    the design value is the worse of the two: a 20 × 20 × 5 grid over `|kp| ∈ [1e-4, 1]`,
//!    `|kd| ∈ [1e-5, 0.1] s`, `tf ∈ {0.2, 0.5, 1, 2, 5} ms` (log-spaced);
//! 2. then the full vehicle with every magnet ([`super::vehicle::VehiclePlant::sampled`]), with
//!    the reference delayed by the scenario's step `Δt` (first-order Padé: the outer loop holds
//!    its reference over each step, formed from the gap at its start) and without it (the
//!    worse of the two abscissas; first on the continuous loop alone), by a compass
//!    search in `(log|kp|, log|kd|, log tf)` from the best grid point: ± the step on each
//!    axis, move on any improvement, halve the step when none, stop at 1/64; `tf` kept in
//!    [0.2, 5] ms.
//!
//! The search is deterministic; the abscissa is not smooth (it switches between modes), so a
//! local search from a grid is the honest tool. The result reports the poles it reached.

use super::gap_loop::GapLoopPlant;
use super::plant::Suspension;
use super::vehicle::VehiclePlant;
use crate::physics::vehicle::VehicleModel;
use maglev_core::gap::Geometry;
use maglev_core::gap_control::GapParams;
use maglev_core::levitation::GRAVITY;
use maglev_core::LawKind;
use maglev_core::Params;

/// The designed gains and the full vehicle's spectral abscissa with them (1/s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Design {
    pub gains: GapParams,
    pub abscissa: f64,
}

/// The range of the derivative filter's time constant (s).
pub const TF_MIN: f64 = 2e-4;
pub const TF_MAX: f64 = 5e-3;

/// Bound on the reference the designed loop may ask for (`|g_ref/g0 − 1|`).
pub const X_REF_MAX: f64 = 0.5;

fn gains(geometry: Geometry, u: [f64; 3]) -> GapParams {
    let s = -geometry.levitation_sign();
    GapParams {
        kp: s * u[0].exp(),
        kd: s * u[1].exp(),
        tf: u[2].exp(),
        x_ref_max: X_REF_MAX,
    }
}

/// One wheel node's loops as `(inner law with the wheel's p0, suspension, body mass)`.
pub fn per_magnet_loops(v: &VehicleModel, inner: &Params) -> Vec<(Params, Suspension, f64)> {
    v.wheels
        .iter()
        .zip(&v.p0)
        .map(|(w, &p0)| {
            let mut p = *inner;
            p.p0 = p0;
            let s = Suspension {
                magnet_mass: v.m[(w.dof_z, w.dof_z)],
                k: v.k[(w.dof_z, w.dof_z)],
                c: v.c[(w.dof_z, w.dof_z)],
            };
            (p, s, p0 / GRAVITY)
        })
        .collect()
}

/// The worse abscissa of every per-magnet loop (levitation and guidance differential mode).
fn loops_abscissa(loops: &[(Params, Suspension, f64)], g: &GapParams, geometry: Geometry) -> f64 {
    let mut worst = f64::NEG_INFINITY;
    for (p, s, body) in loops {
        for pair in [false, true] {
            let x = GapLoopPlant::with_body(p, s, *body, g, geometry, pair)
                .ok()
                .and_then(|pl| super::eigenvalues(&pl.a).ok())
                .map_or(f64::INFINITY, |e| e[0].re);
            worst = worst.max(x);
        }
    }
    worst
}

/// The full vehicle's abscissa with gains `g`, +∞ if it cannot be built or solved.
fn vehicle_abscissa(
    v: &VehicleModel,
    inner: &Params,
    g: &GapParams,
    geometry: Geometry,
    delay: Option<f64>,
) -> f64 {
    // Both the continuous loop (what `stability --scenario` reports) and the delayed one
    // (what a run sampled at Δt does) must be stable: the worse of the two.
    [None, delay]
        .into_iter()
        .map(|d| {
            VehiclePlant::sampled(v, inner, &LawKind::GapLoop(*g), geometry, d)
                .and_then(|pl| pl.verdict())
                .map_or(f64::INFINITY, |vd| vd.max_real_part)
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

/// Designs the gap loop's gains for vehicle `v` with the inner law `inner`, the reference
/// delayed by `delay` (s; `None`: the continuous loop) in the final search (module docs).
pub fn design(
    v: &VehicleModel,
    inner: &Params,
    geometry: Geometry,
    delay: Option<f64>,
) -> crate::Result<Design> {
    let loops = per_magnet_loops(v, inner);
    let axis = |lo: f64, hi: f64, n: usize, i: usize| {
        lo.ln() + (hi.ln() - lo.ln()) * i as f64 / (n - 1) as f64
    };
    let mut best = ([0.0; 3], f64::INFINITY);
    for &tf in &[TF_MIN, 5e-4, 1e-3, 2e-3, TF_MAX] {
        for i in 0..20 {
            for j in 0..20 {
                let u = [axis(1e-4, 1.0, 20, i), axis(1e-5, 0.1, 20, j), f64::ln(tf)];
                let a = loops_abscissa(&loops, &gains(geometry, u), geometry);
                if a < best.1 {
                    best = (u, a);
                }
            }
        }
    }
    // First on the continuous loop alone, then from there on the worse of the continuous and
    // the delayed loop (a search from the grid point on the latter alone can stall in an
    // unstable region).
    let mut u = best.0;
    let mut fu = f64::INFINITY;
    for d in [None, delay] {
        fu = vehicle_abscissa(v, inner, &gains(geometry, u), geometry, d);
        let mut step = 0.5;
        while step > 1.0 / 64.0 {
            let mut moved = false;
            for k in 0..3 {
                for sgn in [1.0, -1.0] {
                    let mut w = u;
                    w[k] += sgn * step;
                    // The filter stays within the grid's range: below 0.2 ms (two firmware
                    // ticks) the continuous derivative no longer describes the sampled one.
                    w[2] = w[2].clamp(TF_MIN.ln(), TF_MAX.ln());
                    let fw = vehicle_abscissa(v, inner, &gains(geometry, w), geometry, d);
                    if fw < fu {
                        (u, fu, moved) = (w, fw, true);
                    }
                }
            }
            if !moved {
                step *= 0.5;
            }
        }
    }
    if !fu.is_finite() {
        return Err(crate::Error::numerical(
            "gap-loop design: no gains give a solvable closed loop",
        ));
    }
    Ok(Design {
        gains: gains(geometry, u),
        abscissa: fu,
    })
}
