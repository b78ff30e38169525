//! The guidance law under the state law: one controller for both magnets of a guidance pair
//! (`[controller.guidance]`), in its differential and common mode.
//!
//! # Why a law of its own
//! Run on each magnet of a pair alone (the levitation law's gains on the gaps `h0 ± d`,
//! [`super::Law::update_pair`]), the state law's two integrals see opposite gaps, so their sum
//! is fed by nothing: a closed-loop pole at exactly 0 on every guided vehicle, whatever the
//! gains. The pair has one mechanical coordinate to hold (the lateral offset `d`) and two
//! coils; this law feeds the five state-law gains back on the mode that moves `d` and holds
//! the other mode, the pair's bias, by current feedback alone.
//!
//! # The modes (per unit)
//! The gaps are `h_L = h0·(1 + η_L)`, `h_R = h0·(1 + η_R)` with `η_L = −η_R = d/h0`
//! ([`crate::gap::guidance_gaps`]); the coil currents `i_L = i0·(1 + Δi_L)`, likewise right.
//! ```text
//! η_d  = (η_L − η_R)/2        (= d/h0)        differential gap
//! Δi_d = (Δi_L − Δi_R)/2,     Δi_c = (Δi_L + Δi_R)/2        differential and common current
//! ```
//! # The law (SI, `V_b = R0·i0`)
//! ```text
//! ΔV_d = kp·d + kd·ḋ + ka·a_y + ki·∫d dt − kc·i0·Δi_d          differential mode (G1)
//! ΔV_c = −kc·i0·Δi_c                                            common mode       (G2)
//! V_L = V_b + ΔV_c + ΔV_d,    V_R = V_b + ΔV_c − ΔV_d,    each clamped to ±V_max   (G3)
//! ```
//! `a_y` is the magnet's absolute lateral acceleration along +Y (the direction that opens the
//! left gap; on a rigid rail `a_y = d̈`), where the pair has an accelerometer (`0` without).
//! Every gain is positive under the EMS geometry: a left gap that opens raises the left
//! voltage and lowers the right one, so the pair pulls the magnet back; this is the sign each
//! magnet's own law has in [`super::Law::update_pair`], restricted to the differential mode.
//! The integral acts on `d` alone, the mode the pair can hold, so it holds `d` at 0; the
//! common mode's equilibrium (`Δi_c = 0`, both currents at `i0`) is held by `kc` with the pole
//! `−(1 + Kc)/τ` of the linear model (τ the coil's time constant, `Kc = kc·i0/V_b`): no pole at
//! 0.
//!
//! # Timing, observer, anti-windup
//! As the levitation state law ([`super::state`], whose timing and supply — `vmax_V`,
//! `rate_Hz`, `observer_Hz` — the pair shares): `n` control periods per structural step, the
//! gaps (and acceleration) interpolated linearly across the step, the voltage held over each
//! period; `ḋ` from the second-order complementary observer on `η_d` and `a_y`
//! (`η̂' = v̂ + 2ω·(η_d − η̂)`, `v̂' = (g_n/h0)·α_y + ω²·(η_d − η̂)`); the integral frozen while
//! either coil's voltage is clamped ([`Status::VOLTAGE_SATURATED`]).
//!
//! # Per unit
//! `Kp = kp·h0/V_b`, `Kd = kd·h0/V_b` (s), `Ka = ka·g_n/V_b`, `Ki = ki·h0/V_b` (1/s),
//! `Kc = kc·i0/V_b`, `α_y = a_y/g_n`; the integral is kept as its voltage `u = Ki·∫η_d dt`.

use super::state::StateParams;
use super::{Field, LawName};
use crate::gap::Geometry;
use crate::guidance::PairOutput;
use crate::levitation::{
    convert, Levitation, Output, ParamError, Params, State, Status, DEFAULT_COEFFICIENT_TOLERANCE,
    GRAVITY,
};
use crate::scalar::Scalar;
use core::f64::consts::PI;

/// The guidance law's five gains, SI (module docs, G1–G2); serde names carry the units, as
/// [`StateParams`]' do. Timing and supply are the levitation state law's.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct GuidanceParams {
    /// Lateral offset gain `kp` (V/m).
    #[cfg_attr(feature = "serde", serde(rename = "kp_V_per_m"))]
    pub kp: f64,
    /// Lateral rate gain `kd` (V·s/m).
    #[cfg_attr(feature = "serde", serde(rename = "kd_V_s_per_m"))]
    pub kd: f64,
    /// Lateral acceleration gain `ka` (V·s²/m).
    #[cfg_attr(feature = "serde", serde(rename = "ka_V_s2_per_m"))]
    pub ka: f64,
    /// Integral gain `ki` (V/(m·s)) on the lateral offset.
    #[cfg_attr(feature = "serde", serde(rename = "ki_V_per_m_s"))]
    pub ki: f64,
    /// Current gain `kc` (V/A), on both modes.
    #[cfg_attr(feature = "serde", serde(rename = "kc_V_per_A"))]
    pub kc: f64,
}

/// The guidance law's gains as errors name them ([`Field`]: the state law's family, the keys
/// of `[controller.guidance]`).
pub mod fields {
    use crate::law::{Field, LawName::State};
    /// `kp`.
    pub const KP: Field = Field::of(State, "kp_V_per_m", "guidance kp");
    /// `kd`.
    pub const KD: Field = Field::of(State, "kd_V_s_per_m", "guidance kd");
    /// `ka`.
    pub const KA: Field = Field::of(State, "ka_V_s2_per_m", "guidance ka");
    /// `ki`.
    pub const KI: Field = Field::of(State, "ki_V_per_m_s", "guidance ki");
    /// `kc`.
    pub const KC: Field = Field::of(State, "kc_V_per_A", "guidance kc");
}

impl GuidanceParams {
    /// The five gains of the levitation state law `s` on the differential mode (the pair
    /// then gives the levitation law's voltages to rounding in the linear range: module docs).
    pub fn same_as(s: &StateParams) -> Self {
        GuidanceParams {
            kp: s.kp,
            kd: s.kd,
            ka: s.ka,
            ki: s.ki,
            kc: s.kc,
        }
    }

    /// The gains in order `kp, kd, ka, ki, kc` with their fields.
    pub fn gains(&self) -> [(Field, f64); 5] {
        [
            (fields::KP, self.kp),
            (fields::KD, self.kd),
            (fields::KA, self.ka),
            (fields::KI, self.ki),
            (fields::KC, self.kc),
        ]
    }

    /// Checks every gain (finite, not negative), naming the first bad one.
    pub fn validate(&self) -> Result<(), ParamError> {
        for (name, v) in self.gains() {
            if !v.is_finite() {
                return Err(ParamError::NotFinite(name));
            }
            if v < 0.0 {
                return Err(ParamError::Negative(name));
            }
        }
        Ok(())
    }

    /// Converts once to the run-time type for one pair of magnets `m` (its `p0` each magnet's
    /// static load, its `dt` the structural step), with the timing and supply of the
    /// levitation law `timing` (checked as [`StateParams::compile`] checks them).
    pub fn compile<S: Scalar>(
        &self,
        timing: &StateParams,
        m: &Params,
    ) -> Result<GuidanceLaw<S>, ParamError> {
        self.validate()?;
        // The timing and supply checks are the levitation law's own.
        timing.compile::<S>(m)?;
        let n = timing.periods(m.dt);
        let delta = m.dt / n as f64;
        let omega = 2.0 * PI * timing.observer_hz;
        let vb = m.v_base();
        let coil = Params {
            kp: 0.0,
            ki: 0.0,
            alpha: 0.5,
            dt: delta,
            n_sub: 1,
            v_max: f64::INFINITY,
            scheme: crate::Scheme::Paper,
            ..*m
        }
        .compile::<S>()?;
        let c = |name, v| {
            convert::<S>(
                Field::derived(Some(LawName::State), name),
                v,
                DEFAULT_COEFFICIENT_TOLERANCE,
            )
        };
        let v_max = c("guidance v_max/Vb", timing.v_max / vb)?;
        Ok(GuidanceLaw {
            params: *self,
            timing: *timing,
            coil,
            n,
            kp: c("guidance kp·h0/Vb", self.kp * m.h0 / vb)?,
            kd: c("guidance kd·h0/Vb", self.kd * m.h0 / vb)?,
            ka: c("guidance ka·g/Vb", self.ka * GRAVITY / vb)?,
            ki_delta: c("guidance ki·h0·δ/Vb", self.ki * m.h0 * delta / vb)?,
            kc: c("guidance kc·i0/Vb", self.kc * m.i0 / vb)?,
            v_max,
            v_min: v_max.sneg(&mut false),
            half: c("1/2", 0.5)?,
            l1: c("guidance 2ω·δ", 2.0 * omega * delta)?,
            l2: c("guidance ω²·δ", omega * omega * delta)?,
            accel_gain: c("guidance g·δ/h0", GRAVITY * delta / m.h0)?,
            delta: c("guidance δ", delta)?,
            steps: c("guidance 1/n", 1.0 / n as f64)?,
        })
    }
}

/// The compiled guidance law of one pair.
#[derive(Clone, Copy, Debug)]
pub struct GuidanceLaw<S> {
    params: GuidanceParams,
    timing: StateParams,
    /// Each coil (Eq. 9) at the control period, no gains: voltage `1 + y`.
    coil: Levitation<S>,
    n: u32,
    kp: S,
    kd: S,
    ka: S,
    ki_delta: S,
    kc: S,
    v_max: S,
    v_min: S,
    half: S,
    l1: S,
    l2: S,
    accel_gain: S,
    delta: S,
    steps: S,
}

/// State of one guidance pair: both coils and the differential mode's integral and observer.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GuidanceState<S> {
    /// Left coil (gap `h0 + d`); its `eta` is the last measured gap.
    pub left: State<S>,
    /// Right coil (gap `h0 − d`).
    pub right: State<S>,
    /// The integral's voltage `u = Ki·∫η_d dt` (per unit of `V_b`).
    pub integral: S,
    /// Observer: estimated `η_d` and its rate (1/s).
    pub eta_est: S,
    pub rate_est: S,
    /// The lateral acceleration `α_y = a_y/g_n` of the last sample.
    pub accel: S,
}

/// What the pair's law reads at the end of a step, per unit.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PairMeasurement<S> {
    /// `d/h0`, with `d = y_w − y_g + r_y` ([`crate::gap::lateral_offset`]).
    pub d: S,
    /// The magnet's absolute lateral acceleration `a_y/g_n` (+Y), where measured.
    pub accel: Option<S>,
}

impl<S: Scalar> GuidanceLaw<S> {
    /// The gains this law was compiled from.
    pub fn params(&self) -> &GuidanceParams {
        &self.params
    }

    /// The levitation law whose timing and supply it shares.
    pub fn timing(&self) -> &StateParams {
        &self.timing
    }

    /// The coil each magnet of the pair drives (per-unit outputs and their SI conversion).
    pub fn coil(&self) -> &Levitation<S> {
        &self.coil
    }

    /// Both magnets in equilibrium at lateral offset `d` (m): each coil at `g0` on its gap,
    /// the integral holding the differential voltage that keeps it there (G1 with `Δi_d = η_d`
    /// at `x = 0`: `u = η_d·(1 − Kp + Kc)`), the common mode at rest (`Δi_c = 0`).
    pub fn equilibrium(&self, d: f64) -> GuidanceState<S> {
        let h0 = self.coil.params().h0;
        let left = self.coil.equilibrium_state(h0 + d);
        let right = self.coil.equilibrium_state(h0 - d);
        let mut ov = false;
        let eta = left.eta.ssub(right.eta, &mut ov).smul(self.half, &mut ov);
        let u = eta
            .ssub(self.kp.smul(eta, &mut ov), &mut ov)
            .sadd(self.kc.smul(eta, &mut ov), &mut ov);
        GuidanceState {
            left,
            right,
            integral: u,
            eta_est: eta,
            rate_est: S::ZERO,
            accel: S::ZERO,
        }
    }

    /// One structural step of both magnets to the measurement at its end (module docs);
    /// the net lateral force per unit `p0` by `geometry` ([`Geometry::guidance_force`]).
    /// Never panics: events in the status. One control period in floating point (the
    /// firmware's case) takes a straight-line path with the same bits ([`fast`]).
    pub fn update(
        &self,
        st: &mut GuidanceState<S>,
        m: PairMeasurement<S>,
        geometry: Geometry,
    ) -> PairOutput<S> {
        if let Some(out) = self.fast_update(st, m, geometry) {
            return out;
        }
        self.general_update(st, m, geometry)
    }

    /// [`GuidanceLaw::update`] with every operation checked, any number of periods; out of
    /// line, so that the fast path's prologue stays small.
    #[inline(never)]
    pub(crate) fn general_update(
        &self,
        st: &mut GuidanceState<S>,
        m: PairMeasurement<S>,
        geometry: Geometry,
    ) -> PairOutput<S> {
        let mut ov = false;
        let one = S::ONE;
        let end_l = m.d;
        let end_r = m.d.sneg(&mut ov);
        let acc_end = m.accel.unwrap_or(S::ZERO);
        let step = |end: S, start: S, ov: &mut bool| end.ssub(start, ov).smul(self.steps, ov);
        let d_l = step(end_l, st.left.eta, &mut ov);
        let d_r = step(end_r, st.right.eta, &mut ov);
        let d_acc = step(acc_end, st.accel, &mut ov);
        let (mut eta_l, mut eta_r, mut acc) = (st.left.eta, st.right.eta, st.accel);
        let mut status = Status::default();
        let (mut out_l, mut out_r) = (Output::default(), Output::default());
        for _ in 0..self.n {
            let current = |x: S, eta: S, ov: &mut bool| {
                one.sadd(x, ov).smul(one.sadd(eta, ov), ov).ssub(one, ov)
            };
            let di_l = current(st.left.x, eta_l, &mut ov);
            let di_r = current(st.right.x, eta_r, &mut ov);
            let di_d = di_l.ssub(di_r, &mut ov).smul(self.half, &mut ov);
            let di_c = di_l.sadd(di_r, &mut ov).smul(self.half, &mut ov);
            let eta_d = eta_l.ssub(eta_r, &mut ov).smul(self.half, &mut ov);
            let dv_d = self
                .kp
                .smul(eta_d, &mut ov)
                .sadd(self.kd.smul(st.rate_est, &mut ov), &mut ov)
                .sadd(self.ka.smul(acc, &mut ov), &mut ov)
                .sadd(st.integral, &mut ov)
                .ssub(self.kc.smul(di_d, &mut ov), &mut ov);
            let dv_c = self.kc.smul(di_c, &mut ov).sneg(&mut ov);
            let base = one.sadd(dv_c, &mut ov);
            let v_l = base.sadd(dv_d, &mut ov);
            let v_r = base.ssub(dv_d, &mut ov);
            let clamped = [v_l, v_r].iter().any(|&v| v > self.v_max || v < self.v_min);
            if !clamped {
                st.integral = st
                    .integral
                    .sadd(self.ki_delta.smul(eta_d, &mut ov), &mut ov);
            }
            // The observer on (η_d, α_y), forward Euler over the period.
            let e = eta_d.ssub(st.eta_est, &mut ov);
            let rate_change = self
                .accel_gain
                .smul(acc, &mut ov)
                .sadd(self.l2.smul(e, &mut ov), &mut ov);
            st.eta_est = st
                .eta_est
                .sadd(self.delta.smul(st.rate_est, &mut ov), &mut ov)
                .sadd(self.l1.smul(e, &mut ov), &mut ov);
            st.rate_est = st.rate_est.sadd(rate_change, &mut ov);
            eta_l = eta_l.sadd(d_l, &mut ov);
            eta_r = eta_r.sadd(d_r, &mut ov);
            acc = acc.sadd(d_acc, &mut ov);
            st.left.y = v_l.clamp_to(self.v_min, self.v_max).ssub(one, &mut ov);
            st.right.y = v_r.clamp_to(self.v_min, self.v_max).ssub(one, &mut ov);
            out_l = self.coil.update(&mut st.left, one.sadd(eta_l, &mut ov));
            out_r = self.coil.update(&mut st.right, one.sadd(eta_r, &mut ov));
            if clamped {
                status = status.union(Status::VOLTAGE_SATURATED);
            }
            status = status.union(out_l.status).union(out_r.status);
        }
        // The last period ends on the measurement itself (no drift from the increments).
        st.left.eta = end_l;
        st.right.eta = end_r;
        st.accel = acc_end;
        let force_y = match geometry {
            Geometry::Paper => out_l.force.ssub(out_r.force, &mut ov),
            Geometry::Ems => out_r.force.ssub(out_l.force, &mut ov),
        };
        if ov {
            status = status.union(Status::OVERFLOW);
        }
        PairOutput {
            left: out_l,
            right: out_r,
            force_y,
            status,
        }
    }
}

mod fast;
#[cfg(test)]
mod tests;
