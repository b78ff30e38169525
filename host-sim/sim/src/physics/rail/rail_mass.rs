//! The rail's participating mass under each wheel: one vertical DOF per wheel between the
//! wheel's Hertz contact and the deck. docs/cars.md, "The track on the girder".
//!
//! Each wheel runs on a mass m_e (the rail's over 3/(2β), [`SlabTrack::rail_effective_mass`])
//! that travels with the wheel. It rests on the support of stiffness k(x) = 1/c(x) (the
//! discrete rail on its pads with the slab in series, [`TrackSupport::compliance_at`]) and
//! the damper c_e ([`SlabTrack::rail_damping`]), both on the deck. The irregularity lies on
//! the rail head, between the wheel and this mass, so the pads' damper sees the rail's motion,
//! not the irregularity's rate. The rail's deflection relative to the deck is u = v − Q0·c̄,
//! Q0 the wheel's static vertical force and c̄ the support's mean compliance over a bay, so
//! that v = 0 at rest on a uniform support:
//!
//! ```text
//! m_e v̈ = −(Q − Q0) − k(x)·v − c_e·v̇ + Q0·(k(x)·c̄ − 1)        (the rail mass)
//! F_deck = k(x)·(v − Q0·c̄) + c_e·v̇                              (up, on the deck)
//! ```
//!
//! with Q the rail's vertical force on the wheel (the wheel's on the rail is −Q). At rest
//! under Q, v = Q0·c̄ − Q·c(x) ([`RailMass::rest`]), so the rail sinks by Q·c(x), the
//! massless support's static deflection. Left out: the rail's own weight (carried by the deck
//! with the track's mass), the interaction of neighbouring wheels through the rail (2.4 m
//! apart: e^{−2.4β} ≈ 0.04 for the default track) and the moving load's effect on the
//! rail (the speed is a tenth of the rail's critical speed (4k·EI/m_r²)^{1/4}).

use super::track::{SlabTrack, TrackSupport};

/// The rail's participating mass under every wheel of a track (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct RailMass {
    /// The support along the track.
    pub support: TrackSupport,
    /// The participating mass m_e, kg.
    pub mass: f64,
    /// The damping c_e to the deck, N·s/m.
    pub damping: f64,
    /// The wheel's static vertical force Q0, N.
    pub q0: f64,
    /// The support's mean compliance c̄, m/N.
    c_mean: f64,
}

impl RailMass {
    /// The rail masses of `support` under wheels of static vertical force `q0` (N).
    pub fn new(support: &TrackSupport, q0: f64) -> Self {
        let track: &SlabTrack = &support.track;
        RailMass {
            support: support.clone(),
            mass: track.rail_effective_mass(),
            damping: track.rail_damping(),
            q0,
            c_mean: support.mean(),
        }
    }

    /// The support's stiffness k(x) = 1/c(x) under a wheel at x (m), N/m.
    pub fn stiffness_at(&self, x: f64) -> f64 {
        1.0 / self.support.compliance_at(x)
    }

    /// v̈ (m/s²) of the rail mass on the support stiffness `k` ([`RailMass::stiffness_at`]
    /// where it is) with deflection `v` (m) and rate `dv` (m/s) under the rail's vertical
    /// force `q` (N) on the wheel (module docs).
    pub fn acceleration(&self, k: f64, v: f64, dv: f64, q: f64) -> f64 {
        (-(q - self.q0) - k * v - self.damping * dv + self.q0 * (k * self.c_mean - 1.0)) / self.mass
    }

    /// The track's vertical force on the deck (up, N) under the rail mass on the support
    /// stiffness `k` (module docs).
    pub fn deck_force(&self, k: f64, v: f64, dv: f64) -> f64 {
        k * (v - self.q0 * self.c_mean) + self.damping * dv
    }

    /// The rail mass's deflection at rest at x under the vertical force `q` (N), m.
    pub fn rest(&self, x: f64, q: f64) -> f64 {
        self.q0 * self.c_mean - q * self.support.compliance_at(x)
    }

    /// The angular frequency (rad/s) of the wheel of mass `wheel` (kg) against the rail
    /// mass on the contact stiffness `contact` (N/m), the support neglected: √(k(1/m_e +
    /// 1/m_w)), the fastest mode an explicit integrator of the pair must resolve.
    pub fn contact_frequency(&self, wheel: f64, contact: f64) -> f64 {
        (contact * (1.0 / self.mass + 1.0 / wheel)).sqrt()
    }
}
