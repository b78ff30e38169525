//! A second levitation controller: an outer gap loop (PD with a filtered derivative) that
//! sets the reference `g_ref` of the paper's inner law (Eq. 8–14).
//!
//! # Why
//! The paper's law regulates `g = i/h`, i.e. the flux and so the force (Eq. 1), not the gap:
//! on a rigid rail a magnet carrying its body has a pole at 0 (every gap is an equilibrium)
//! and a real pole in the right half-plane (`docs/theory.md`, last section); a free-flying
//! vehicle drifts. Holding the gap needs gap feedback. This module adds the least: a loop
//! that measures the gap and moves the inner loop's reference, `e = g_ref − g` in place of
//! Eq. 8's `e = g0 − g`, leaving Eq. 9–14 as they are
//! ([`Levitation::update_with_reference`]). The paper's law stays the default everywhere.
//!
//! # Sensors
//! Only the gap `h`, sampled once per outer step Δt (what a gap sensor gives firmware). The
//! inner law already uses `g = i/h` (coil current and gap). No velocity or acceleration
//! sensor: the derivative is a filtered difference of the sampled gap.
//!
//! # The law (per unit, `η = h/h0 − 1`, `x_ref = g_ref/g0 − 1`)
//! ```text
//! continuous:  x_ref = kp·η + kd·s/(1 + tf·s)·η
//! discrete:    d_k = (η_k − q_{k−1})/(tf + Δt)              (backward Euler on tf·q̇ = η − q)
//!              q_k = q_{k−1} + Δt·d_k,   x_ref,k = kp·η_k + kd·d_k,  |x_ref| ≤ x_ref_max
//! ```
//! Under the EMS geometry (`kp, kd > 0`) a gap that opens (`η > 0`) raises the flux reference,
//! hence the force, and closes it; under the paper's geometry the gap opens when the wheel
//! rises, the force must fall, and the gains are negative (docs/gap-loop.md).
//! The reference for the step `[t_k, t_k + Δt]` is formed from the gap measured at `t_k`
//! (the last gap the inner state saw) and held over the step: causal, one sample of delay.
//! In steady state the inner integral makes `x = x_ref` and the force balance `x = 0`, so the
//! gap returns to `h0` exactly (no integral needed in the outer loop).
//!
//! # Gains
//! [`GapParams::designed`] gives `kp = 4.0e-3`, `kd = 4.2e-3 s`, `tf = 2 ms` per unit, found by
//! minimising the spectral abscissa of the linearised closed loop (inner law + outer PD + one
//! massless magnet carrying a quarter of the Fig. 1 body on its suspension, rigid rail):
//! poles −3.17 ± 2.51j, −3.41, −6.84 ± 64.7j, −502 s⁻¹ (`host-sim/sim/src/studies/stability/gap_loop.rs`,
//! `docs/gap-loop.md`). They are specific to that plant: with a 500 kg magnet mass the same
//! gains are unstable (the analysis and the simulation agree, tested there). The
//! gains are small because the inner integral (`ki = 600 s⁻¹` at the paper's values)
//! integrates the reference: a 1 mm gap error moves the coil voltage by `ki·kp·η` ≈ 24 % of
//! `V_b` per second. SI: `Δg_ref = kp·(g0/h0)·Δh` (A/m per m).
//!
//! # Guidance pairs
//! Each magnet of a guidance pair ([`crate::guidance`]) may run the same loop on its own gap
//! ([`GapLoop::update_pair`]). Linearised, the pair's differential mode
//! `x_d = (x_R − x_L)/2` sees `η_d = −d/h0` and gives `F_y = 4·p0·x_d`: the levitation plant
//! with twice the force gain; the common mode gives no force. With the designed gains and the
//! Fig. 1 suspension that plant is stable too (tested in `host-sim/sim/src/studies/stability/gap_loop`).
//!
//! Configuration ([`GapParams`], f64) is apart from state ([`GapState`]); [`GapParams::compile`]
//! converts once to the run-time type. No allocation, no panic.

use crate::guidance::PairOutput;
use crate::law::{Field, LawName};
use crate::levitation::{Levitation, Output, ParamError, State, Status};

/// The gap loop's gains as errors name them ([`Field`]; keys as [`GapParams`] serialises
/// them).
pub mod fields {
    use crate::law::{Field, LawName::GapLoop};
    /// `kp`.
    pub const KP: Field = Field::of(GapLoop, "kp", "gap kp");
    /// `kd`.
    pub const KD: Field = Field::of(GapLoop, "kd_s", "gap kd");
    /// `tf`.
    pub const TF: Field = Field::of(GapLoop, "tf_s", "gap tf");
    /// `x_ref_max`.
    pub const X_REF_MAX: Field = Field::of(GapLoop, "x_ref_max", "gap x_ref_max");
}

/// A coefficient derived from the gap loop's gains.
const fn derived(name: &'static str) -> Field {
    Field::derived(Some(LawName::GapLoop), name)
}
use crate::scalar::Scalar;

/// Outer-loop gains, per unit of the inner law's `(g0, h0)` (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct GapParams {
    /// Proportional gain `kp = (Δg_ref/g0)/(Δh/h0)`; > 0 holds the gap under "ems", < 0
    /// under "paper".
    pub kp: f64,
    /// Derivative gain `kd` (s), the sign of `kp`.
    #[cfg_attr(feature = "serde", serde(rename = "kd_s"))]
    pub kd: f64,
    /// Derivative filter time constant `tf` (s), ≥ 0 (0: plain backward difference).
    #[cfg_attr(feature = "serde", serde(rename = "tf_s"))]
    pub tf: f64,
    /// Bound on `|x_ref| = |g_ref/g0 − 1|`, > 0.
    pub x_ref_max: f64,
}

impl GapParams {
    /// The gains designed for the paper's inner law (§4.2) on one magnet carrying a quarter of
    /// the Fig. 1 body (module docs), reference bounded to ±50 % of `g0`.
    pub const fn designed() -> Self {
        GapParams {
            kp: 4.0e-3,
            kd: 4.2e-3,
            tf: 2e-3,
            x_ref_max: 0.5,
        }
    }

    /// Proportional gain in SI, `(A/m)/m`, for an inner law around `g0`, `h0`.
    pub fn kp_si(&self, inner: &crate::Params) -> f64 {
        self.kp * inner.g0() / inner.h0
    }

    /// Derivative gain in SI, `(A/m)/(m/s)`.
    pub fn kd_si(&self, inner: &crate::Params) -> f64 {
        self.kd * inner.g0() / inner.h0
    }

    /// Checks every gain, naming the first bad one. `kp` and `kd` may have either sign: the
    /// sign that holds the gap depends on the geometry (`-Geometry::levitation_sign()`:
    /// positive under "ems", negative under "paper", docs/gap-loop.md); `tf ≥ 0`.
    pub fn validate(&self) -> Result<(), ParamError> {
        for (name, v) in [
            (fields::KP, self.kp),
            (fields::KD, self.kd),
            (fields::TF, self.tf),
        ] {
            if !v.is_finite() {
                return Err(ParamError::NotFinite(name));
            }
        }
        if self.tf < 0.0 {
            return Err(ParamError::Negative(fields::TF));
        }
        if !self.x_ref_max.is_finite() {
            return Err(ParamError::NotFinite(fields::X_REF_MAX));
        }
        if self.x_ref_max <= 0.0 {
            return Err(ParamError::NotPositive(fields::X_REF_MAX));
        }
        Ok(())
    }

    /// Converts once to the run-time type for an outer step `dt` (s), the inner law's Δt.
    pub fn compile<S: Scalar>(&self, dt: f64) -> Result<GapLoop<S>, ParamError> {
        self.validate()?;
        if !(dt.is_finite() && dt > 0.0) {
            return Err(ParamError::NotPositive(crate::levitation::fields::DT));
        }
        let coeffs = [
            (fields::KP, self.kp),
            (derived("gap kd/(tf+dt)"), self.kd / (self.tf + dt)),
            (derived("gap dt/(tf+dt)"), dt / (self.tf + dt)),
            (fields::X_REF_MAX, self.x_ref_max.min(0.9)),
        ];
        let mut out = [S::ZERO; 4];
        for (slot, (name, value)) in out.iter_mut().zip(coeffs) {
            *slot = crate::levitation::convert(
                name,
                value,
                crate::levitation::DEFAULT_COEFFICIENT_TOLERANCE,
            )?;
        }
        let [kp, kdd, kq, x_max] = out;
        Ok(GapLoop {
            params: *self,
            kp,
            kdd,
            kq,
            x_max,
        })
    }
}

/// A compiled outer loop.
#[derive(Clone, Copy, Debug)]
pub struct GapLoop<S> {
    params: GapParams,
    kp: S,
    kdd: S,
    kq: S,
    x_max: S,
}

/// State of one magnet under the gap loop: the inner law's state and the derivative filter's.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GapState<S> {
    /// The inner law's state ([`State`]); its `eta` is the last measured gap.
    pub inner: State<S>,
    /// Derivative filter state `q` (per-unit gap, low-passed).
    pub q: S,
}

/// One step's result: the inner output and the reference that was applied.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GapOutput<S> {
    /// The inner law's output (force `G/p0`, events).
    pub inner: Output<S>,
    /// `x_ref = g_ref/g0 − 1` held over the step.
    pub x_ref: S,
    /// Whether `x_ref` was limited to `±x_ref_max`.
    pub reference_limited: bool,
}

impl<S: Scalar> GapLoop<S> {
    /// The gains this loop was compiled from.
    pub fn params(&self) -> &GapParams {
        &self.params
    }

    /// Inner equilibrium at gap `h` (m, [`Levitation::equilibrium_state`]) with the filter
    /// at rest there (the gap taken to have been `h` until now).
    pub fn equilibrium_state(&self, inner: &Levitation<S>, h: f64) -> GapState<S> {
        let st = inner.equilibrium_state(h);
        GapState {
            inner: st,
            q: st.eta,
        }
    }

    /// The reference for the next step from the last measured gap (`st.inner.eta`), and the
    /// filter advanced past that sample.
    pub fn reference(&self, st: &mut GapState<S>, ov: &mut bool) -> (S, bool) {
        let eta = st.inner.eta;
        let diff = eta.ssub(st.q, ov);
        let d = self.kdd.smul(diff, ov);
        st.q = st.q.sadd(self.kq.smul(diff, ov), ov);
        let r = self.kp.smul(eta, ov).sadd(d, ov);
        let lo = self.x_max.sneg(ov);
        let limited = r > self.x_max || r < lo;
        (r.clamp_to(lo, self.x_max), limited)
    }

    /// One outer step: the reference from the gap at the start of the step, then the inner
    /// law (Eq. 14 with `g_ref`, internal loop) as the gap moves to `h_next` (per unit,
    /// `h/h0`). Never panics; arithmetic saturation is flagged in the inner status.
    pub fn update(&self, inner: &Levitation<S>, st: &mut GapState<S>, h_next: S) -> GapOutput<S> {
        let mut ov = false;
        let (x_ref, reference_limited) = self.reference(st, &mut ov);
        let mut out = inner.update_with_reference(&mut st.inner, h_next, x_ref);
        if ov {
            out.status = out.status.union(Status::OVERFLOW);
        }
        GapOutput {
            inner: out,
            x_ref,
            reference_limited,
        }
    }
}

/// State of a guidance pair under the gap loop: one [`GapState`] per magnet.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GapPairState<S> {
    /// Left magnet (gap `h0 + d`).
    pub left: GapState<S>,
    /// Right magnet (gap `h0 − d`).
    pub right: GapState<S>,
}

impl<S: Scalar> GapLoop<S> {
    /// Both magnets in equilibrium at relative lateral position `d` (m), as
    /// [`crate::guidance::initial_state`].
    pub fn pair_equilibrium_state(&self, inner: &Levitation<S>, d: f64) -> GapPairState<S> {
        let h0 = inner.params().h0;
        GapPairState {
            left: self.equilibrium_state(inner, h0 + d),
            right: self.equilibrium_state(inner, h0 - d),
        }
    }

    /// One outer step of both magnets of a guidance pair, each under this loop on its own gap;
    /// `d_pu = (y_w − y_g + r_y)/h0` at the end of the step (as [`crate::guidance::update`]).
    pub fn update_pair(
        &self,
        inner: &Levitation<S>,
        geometry: crate::gap::Geometry,
        st: &mut GapPairState<S>,
        d_pu: S,
    ) -> PairOutput<S> {
        crate::guidance::update_with(geometry, &mut st.left, &mut st.right, d_pu, |s, h| {
            self.update(inner, s, h).inner
        })
    }
}

#[cfg(test)]
mod tests;
