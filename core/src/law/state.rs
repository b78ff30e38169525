//! State feedback on gap, gap rate and acceleration: the law that holds the gap of an EMS
//! magnet (`controller.law = "state"`).
//!
//! # The law (SI)
//! ```text
//! ΔV = kp·Δh + kd·ḣ − ka·a + ki·∫Δh dt − kc·Δi,     V = R0·i0 + ΔV, clamped to ±V_max
//! Δh = h − h0,  ḣ the gap rate,  a the magnet's absolute vertical acceleration (Z up),
//! Δi = i − i0
//! ```
//! Under the EMS geometry every gain is positive: a gap that opens (the magnet falls away from
//! its rail) raises the voltage, hence the current and the force; an upward acceleration closes
//! the gap and lowers it; `kc` acts as an added resistance that speeds the current up.
//!
//! # The plant it drives
//! The coil of Eq. 9 in flux form, `G0·dg/dt + R0·h·g = V` (back-EMF of a moving gap included,
//! since `g = i/h` carries the gap), integrated as the paper's law integrates it: the
//! [`Levitation`] with `KP = KI = 0`, whose voltage is then `V_b·(1 + y)` (Eq. 11 with no
//! gains), one α-method step per control period. The force is Eq. 1, `K0·g²`.
//!
//! # Timing
//! The law runs at its own control rate inside the structural step Δt: `n = round(Δt·rate)`
//! periods of `δ = Δt/n`. At the start of each period it samples the gap (and acceleration),
//! interpolated linearly across the step from the last sample to the new measurement, computes
//! `V`, and holds it over the period (zero-order hold): causal, one period from sample to the
//! end of its effect.
//!
//! # Gap-rate estimate
//! No sensor gives `ḣ`. A second-order observer blends the gap (low frequencies) with the
//! acceleration (high frequencies), a complementary filter:
//! ```text
//! ĥ' = v̂ + 2ω·(h − ĥ),     v̂' = σ·a + ω²·(h − ĥ)      (σ: the gap's sign of the magnet's motion)
//! ```
//! With `a` measured the estimate of `ḣ` is exact for a rigid rail at every frequency (the
//! error obeys `ë + 2ω·ė + ω²·e = 0`); without it (`accel: None`, guidance magnets) it is a
//! derivative of the gap filtered at `ω` (critically damped). ω is `observer_hz·2π`
//! (default 300 Hz, well above the levitation loop's crossover of a few Hz to tens of Hz).
//! Forward Euler at δ, stable while `ω·δ < 1`: the compile step refuses a slower rate.
//!
//! # Anti-windup
//! While `V` is clamped the integral does not move (conditional integration), flagged
//! [`Status::VOLTAGE_SATURATED`].
//!
//! # Per unit
//! Internally, deviations from equilibrium per unit: `η = Δh/h0`, `α = a/g_n`, `Δi/i0`,
//! `v = V/V_b` with `V_b = R0·i0`. Gains: `Kp = kp·h0/V_b`, `Kd = kd·h0/V_b` (s),
//! `Ka = ka·g_n/V_b`, `Ki = ki·h0/V_b` (1/s), `Kc = kc·i0/V_b`. The integral is kept as its
//! voltage contribution `u = Ki·∫η dt`, so equilibrium at any gap is one value of `u`.

use super::{Field, LawName};
use crate::gap::Geometry;
use crate::levitation::{
    convert, Levitation, Output, ParamError, Params, State, Status, DEFAULT_COEFFICIENT_TOLERANCE,
    GRAVITY,
};
use crate::scalar::Scalar;
use core::f64::consts::PI;

pub mod batch;

/// The state law's gains and timing, SI (module docs); serde names carry the units.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct StateParams {
    /// Gap gain `kp` (V/m).
    #[cfg_attr(feature = "serde", serde(rename = "kp_V_per_m"))]
    pub kp: f64,
    /// Gap-rate gain `kd` (V·s/m).
    #[cfg_attr(feature = "serde", serde(rename = "kd_V_s_per_m"))]
    pub kd: f64,
    /// Acceleration gain `ka` (V·s²/m).
    #[cfg_attr(feature = "serde", serde(rename = "ka_V_s2_per_m"))]
    pub ka: f64,
    /// Integral gain `ki` (V/(m·s)).
    #[cfg_attr(feature = "serde", serde(rename = "ki_V_per_m_s"))]
    pub ki: f64,
    /// Current gain `kc` (V/A).
    #[cfg_attr(feature = "serde", serde(rename = "kc_V_per_A"))]
    pub kc: f64,
    /// Supply bound `V_max` (V), > `R0·i0`.
    #[cfg_attr(feature = "serde", serde(rename = "vmax_V"))]
    pub v_max: f64,
    /// Control rate (Hz).
    #[cfg_attr(
        feature = "serde",
        serde(rename = "rate_Hz", default = "StateParams::default_rate")
    )]
    pub rate_hz: f64,
    /// Gap-rate observer bandwidth (Hz).
    #[cfg_attr(
        feature = "serde",
        serde(rename = "observer_Hz", default = "StateParams::default_observer")
    )]
    pub observer_hz: f64,
    /// How the magnet faces its rail: the sign by which the magnet's upward motion moves
    /// the gap (docs/model.md §2). Not serialised: it is the vehicle's, set where the law
    /// meets its magnet.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub geometry: Geometry,
}

/// The state law's parameters as errors name them ([`Field`]; keys as [`StateParams`]
/// serialises them).
pub mod fields {
    use crate::law::{Field, LawName::State};
    /// `kp`.
    pub const KP: Field = Field::of(State, "kp_V_per_m", "state kp");
    /// `kd`.
    pub const KD: Field = Field::of(State, "kd_V_s_per_m", "state kd");
    /// `ka`.
    pub const KA: Field = Field::of(State, "ka_V_s2_per_m", "state ka");
    /// `ki`.
    pub const KI: Field = Field::of(State, "ki_V_per_m_s", "state ki");
    /// `kc`.
    pub const KC: Field = Field::of(State, "kc_V_per_A", "state kc");
    /// `v_max`.
    pub const V_MAX: Field = Field::of(State, "vmax_V", "state v_max");
    /// `rate_hz`.
    pub const RATE: Field = Field::of(State, "rate_Hz", "state rate_hz");
    /// `observer_hz`.
    pub const OBSERVER: Field = Field::of(State, "observer_Hz", "state observer_hz");
}

/// The most control periods one update may run (rate_hz·dt): 1 s steps at 10 kHz.
pub const MAX_PERIODS: f64 = 10_000.0;

impl StateParams {
    /// Default control rate (Hz).
    pub const RATE_HZ: f64 = 10_000.0;
    /// Default observer bandwidth (Hz).
    pub const OBSERVER_HZ: f64 = 300.0;

    #[cfg(feature = "serde")]
    fn default_rate() -> f64 {
        Self::RATE_HZ
    }

    #[cfg(feature = "serde")]
    fn default_observer() -> f64 {
        Self::OBSERVER_HZ
    }

    /// Checks every value, naming the first bad one.
    pub fn validate(&self) -> Result<(), ParamError> {
        for (name, v) in [
            (fields::KP, self.kp),
            (fields::KD, self.kd),
            (fields::KA, self.ka),
            (fields::KI, self.ki),
            (fields::KC, self.kc),
        ] {
            if !v.is_finite() {
                return Err(ParamError::NotFinite(name));
            }
            if v < 0.0 {
                return Err(ParamError::Negative(name));
            }
        }
        for (name, v) in [
            (fields::V_MAX, self.v_max),
            (fields::RATE, self.rate_hz),
            (fields::OBSERVER, self.observer_hz),
        ] {
            if !v.is_finite() {
                return Err(ParamError::NotFinite(name));
            }
            if v <= 0.0 {
                return Err(ParamError::NotPositive(name));
            }
        }
        Ok(())
    }

    /// Control periods per structural step `dt` (at least one).
    ///
    /// [`StateParams::compile`] refuses more than [`MAX_PERIODS`].
    pub fn periods(&self, dt: f64) -> u32 {
        let n = libm::round(dt * self.rate_hz);
        if n < 1.0 {
            1
        } else if n > u32::MAX as f64 {
            u32::MAX
        } else {
            n as u32
        }
    }

    /// Converts once to the run-time type for the magnet `m` (its `dt` is the structural step).
    pub fn compile<S: Scalar>(&self, m: &Params) -> Result<StateLaw<S>, ParamError> {
        self.validate()?;
        if m.dt * self.rate_hz > MAX_PERIODS {
            // One update would run that many periods: a configuration (e.g. a firmware tick
            // of 1 Hz with rate_hz = 1e9) that hangs the caller instead of controlling.
            return Err(ParamError::NotPositive(Field {
                name: "10 000 − state rate_hz·dt (control periods per step)",
                ..fields::RATE
            }));
        }
        let n = self.periods(m.dt);
        let delta = m.dt / n as f64;
        let omega = 2.0 * PI * self.observer_hz;
        if omega * delta >= 1.0 {
            return Err(ParamError::NotPositive(Field {
                name: "state rate_hz (at least 2π·observer_hz)",
                ..fields::RATE
            }));
        }
        let vb = m.v_base();
        if self.v_max <= vb {
            return Err(ParamError::NotPositive(Field {
                name: "state v_max − R0·i0",
                ..fields::V_MAX
            }));
        }
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
        let sigma = self.geometry.levitation_sign();
        let c = |name, v| {
            convert::<S>(
                Field::derived(Some(LawName::State), name),
                v,
                DEFAULT_COEFFICIENT_TOLERANCE,
            )
        };
        let v_max = c("state v_max/Vb", self.v_max / vb)?;
        Ok(StateLaw {
            params: *self,
            coil,
            n,
            kp: c("state kp·h0/Vb", self.kp * m.h0 / vb)?,
            kd: c("state kd·h0/Vb", self.kd * m.h0 / vb)?,
            ka: c("state ka·g/Vb", self.ka * GRAVITY / vb)?,
            ki_delta: c("state ki·h0·δ/Vb", self.ki * m.h0 * delta / vb)?,
            kc: c("state kc·i0/Vb", self.kc * m.i0 / vb)?,
            v_max,
            // The general path's `v_max.sneg` (exact in every type that has the value).
            v_min: v_max.sneg(&mut false),
            l1: c("state 2ω·δ", 2.0 * omega * delta)?,
            l2: c("state ω²·δ", omega * omega * delta)?,
            accel_gain: c("state σ·g·δ/h0", sigma * GRAVITY * delta / m.h0)?,
            delta: c("state δ", delta)?,
            steps: c("state 1/n", 1.0 / n as f64)?,
        })
    }
}

/// The compiled state law of one magnet.
#[derive(Clone, Copy, Debug)]
pub struct StateLaw<S> {
    params: StateParams,
    /// The coil (Eq. 9) at the control period, no gains: voltage `1 + y`.
    coil: Levitation<S>,
    /// Control periods per structural step.
    n: u32,
    kp: S,
    kd: S,
    ka: S,
    ki_delta: S,
    kc: S,
    v_max: S,
    /// `−v_max`, the lower clamp.
    v_min: S,
    /// Observer gains per period.
    l1: S,
    l2: S,
    /// `σ·g_n·δ/h0`: the gap's per-unit rate change per period per unit of `α`.
    accel_gain: S,
    delta: S,
    steps: S,
}

/// The state law's own states beside the coil's.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StateLawState<S> {
    /// The integral's voltage contribution `u = Ki·∫η dt` (per unit of `V_b`).
    pub integral: S,
    /// Observer: estimated gap `η̂` and gap rate `v̂` (per unit, 1/s).
    pub eta_est: S,
    pub rate_est: S,
    /// The acceleration `α = a/g_n` of the last sample.
    pub accel: S,
}

impl<S: Scalar> StateLaw<S> {
    /// The parameters this law was compiled from.
    pub fn params(&self) -> &StateParams {
        &self.params
    }

    /// Equilibrium at the coil state `coil` (gap `η`, `x = 0`): at rest, the integral holding
    /// the voltage `1 + η` that keeps `g = g0` at that gap.
    pub fn equilibrium(&self, coil: &State<S>) -> StateLawState<S> {
        let mut ov = false;
        let eta = coil.eta;
        // v − 1 = Kp·η + u − Kc·Δi with Δi = η (x = 0): u = η·(1 − Kp + Kc).
        let u = eta
            .ssub(self.kp.smul(eta, &mut ov), &mut ov)
            .sadd(self.kc.smul(eta, &mut ov), &mut ov);
        StateLawState {
            integral: u,
            eta_est: eta,
            rate_est: S::ZERO,
            accel: S::ZERO,
        }
    }

    /// One structural step: `n` control periods from the last sample to the measurement
    /// `(gap h/h0, accel a/g_n)` at the step's end. The current fed back is the coil's own
    /// (`i/i0 = (1 + x)·(1 + η)`): the coil is integrated here, so its current is the one a
    /// current sensor would read.
    pub fn update(
        &self,
        coil: &mut State<S>,
        st: &mut StateLawState<S>,
        gap: S,
        accel: Option<S>,
    ) -> Output<S> {
        if let Some(out) = self.fast_update(coil, st, gap, accel) {
            return out;
        }
        self.general_update(coil, st, gap, accel)
    }

    /// One control period per step in floating point (the firmware's case): the operations of
    /// [`StateLaw::general_update`] on unchecked arithmetic, with the finiteness of every
    /// value they flow into checked once before anything is stored. A float's checked
    /// operation differs from the plain one only where the result is not finite, and every
    /// intermediate here ends in one of the checked values (no operation maps a non-finite
    /// operand to a finite result before them), so when the checks pass the result is the
    /// general path's to the bit (`tests::fast_path_is_bit_identical`); otherwise `None` and
    /// the general path runs from the untouched state.
    #[inline(always)]
    fn fast_update(
        &self,
        coil: &mut State<S>,
        st: &mut StateLawState<S>,
        gap: S,
        accel: Option<S>,
    ) -> Option<Output<S>> {
        if !S::FLOAT || self.n != 1 {
            return None;
        }
        let one = S::ONE;
        let eta_end = gap.sub_raw(one);
        let acc_end = accel.unwrap_or(S::ZERO);
        let (eta, acc) = (coil.eta, st.accel);
        // One period: `1/n` is exactly 1 and `x·1 = x` for every float, so the general
        // path's increments `(end − start)·(1/n)` are the differences themselves.
        let d_eta = eta_end.sub_raw(eta);
        let d_acc = acc_end.sub_raw(acc);
        let i_pu = one.add_raw(coil.x).mul_raw(one.add_raw(eta));
        let di = i_pu.sub_raw(one);
        let dv = self
            .kp
            .mul_raw(eta)
            .add_raw(self.kd.mul_raw(st.rate_est))
            .sub_raw(self.ka.mul_raw(acc))
            .add_raw(st.integral)
            .sub_raw(self.kc.mul_raw(di));
        let v = one.add_raw(dv);
        // `clamp_to(−v_max, v_max)` for a value that is not NaN (a NaN `v` fails the check
        // below), with the comparisons that also say whether it clamped.
        let (vc, clamped) = if v > self.v_max {
            (self.v_max, true)
        } else if v < self.v_min {
            (self.v_min, true)
        } else {
            (v, false)
        };
        let integral = if clamped {
            st.integral
        } else {
            st.integral.add_raw(self.ki_delta.mul_raw(eta))
        };
        let e = eta.sub_raw(st.eta_est);
        let rate_change = self.accel_gain.mul_raw(acc).add_raw(self.l2.mul_raw(e));
        let eta_est = st
            .eta_est
            .add_raw(self.delta.mul_raw(st.rate_est))
            .add_raw(self.l1.mul_raw(e));
        let rate_est = st.rate_est.add_raw(rate_change);
        let eta1 = eta.add_raw(d_eta);
        let acc1 = acc.add_raw(d_acc);
        let h1 = one.add_raw(eta1);
        let all = v
            .add_raw(integral)
            .add_raw(eta_est)
            .add_raw(rate_est)
            .add_raw(h1)
            .add_raw(acc1)
            .add_raw(eta_end);
        // A sum of finite values can overflow; then the general path decides.
        if !all.is_finite_value() {
            return None;
        }
        // The coil's own fast path, on a copy: when it declines, so does this one, and the
        // general path runs from the untouched state (its coil step then takes the coil's
        // general path, which is the same computation).
        let mut c = *coil;
        c.y = vc.sub_raw(one);
        let out = self.coil.fast_update(&mut c, h1)?;
        st.integral = integral;
        st.eta_est = eta_est;
        st.rate_est = rate_est;
        st.accel = acc_end;
        *coil = State { eta: eta_end, ..c };
        Some(Output {
            status: if clamped {
                Status::VOLTAGE_SATURATED
            } else {
                Status::default()
            },
            ..out
        })
    }

    /// [`StateLaw::update`] with every operation checked, any number of periods; out of line,
    /// so that the fast path's prologue stays small.
    #[inline(never)]
    fn general_update(
        &self,
        coil: &mut State<S>,
        st: &mut StateLawState<S>,
        gap: S,
        accel: Option<S>,
    ) -> Output<S> {
        let mut ov = false;
        let eta_end = gap.ssub(S::ONE, &mut ov);
        let acc_end = accel.unwrap_or(S::ZERO);
        let (eta0, acc0) = (coil.eta, st.accel);
        let d_eta = eta_end.ssub(eta0, &mut ov).smul(self.steps, &mut ov);
        let d_acc = acc_end.ssub(acc0, &mut ov).smul(self.steps, &mut ov);
        let mut status = Status::default();
        let mut out = Output::default();
        let (mut eta, mut acc) = (eta0, acc0);
        for _ in 0..self.n {
            let i_pu = S::ONE
                .sadd(coil.x, &mut ov)
                .smul(S::ONE.sadd(eta, &mut ov), &mut ov);
            let (v, clamped) = self.voltage(st, eta, acc, i_pu, &mut ov);
            if !clamped {
                st.integral = st.integral.sadd(self.ki_delta.smul(eta, &mut ov), &mut ov);
            }
            self.observe(st, eta, acc, &mut ov);
            eta = eta.sadd(d_eta, &mut ov);
            acc = acc.sadd(d_acc, &mut ov);
            coil.y = v.ssub(S::ONE, &mut ov);
            out = self.coil.update(coil, S::ONE.sadd(eta, &mut ov));
            if clamped {
                status = status.union(Status::VOLTAGE_SATURATED);
            }
            status = status.union(out.status);
        }
        // The last period ends on the measurement itself (no drift from the increments).
        coil.eta = eta_end;
        st.accel = acc_end;
        if ov {
            status = status.union(Status::OVERFLOW);
        }
        out.status = status;
        out
    }

    /// The per-unit voltage `v = 1 + Δv` from a sample, clamped to `±v_max`.
    fn voltage(&self, st: &StateLawState<S>, eta: S, acc: S, i_pu: S, ov: &mut bool) -> (S, bool) {
        let di = i_pu.ssub(S::ONE, ov);
        let dv = self
            .kp
            .smul(eta, ov)
            .sadd(self.kd.smul(st.rate_est, ov), ov)
            .ssub(self.ka.smul(acc, ov), ov)
            .sadd(st.integral, ov)
            .ssub(self.kc.smul(di, ov), ov);
        let v = S::ONE.sadd(dv, ov);
        let lo = self.v_min;
        (v.clamp_to(lo, self.v_max), v > self.v_max || v < lo)
    }

    /// One forward-Euler period of the gap-rate observer on the sample `(η, α)`.
    fn observe(&self, st: &mut StateLawState<S>, eta: S, acc: S, ov: &mut bool) {
        let e = eta.ssub(st.eta_est, ov);
        let rate_change = self.accel_gain.smul(acc, ov).sadd(self.l2.smul(e, ov), ov);
        st.eta_est = st
            .eta_est
            .sadd(self.delta.smul(st.rate_est, ov), ov)
            .sadd(self.l1.smul(e, ov), ov);
        st.rate_est = st.rate_est.sadd(rate_change, ov);
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::law::{LawKind, LawParams, Measurement};
    use crate::scalar::I4F28;

    /// Vb/h0 (V/m) and τ = 2·p0·h0/(R0·i0²) (s) of the paper's magnet: the characteristic
    /// polynomial of a rigid magnet under `kp`, `kd` alone is
    /// `M·τ·s³ + M·s² + (2·p0·kd/Vb)·s + 2·p0·(kp/Vb − 1/h0)`, stable (Routh) iff
    /// `kp > Vb/h0`, `kd > 0` and `kd > τ·(kp − Vb/h0)`.
    fn paper_magnet(p0: f64) -> (Params, f64, f64) {
        let m = Params::paper(p0, 1e-4);
        let tau = 2.0 * p0 * m.h0 / (m.r0 * m.i0 * m.i0);
        (m, m.v_base() / m.h0, tau)
    }

    fn gains(kp: f64, kd: f64) -> StateParams {
        StateParams {
            kp,
            kd,
            ka: 0.0,
            ki: 0.0,
            kc: 0.0,
            v_max: 1e6,
            rate_hz: StateParams::RATE_HZ,
            observer_hz: StateParams::OBSERVER_HZ,
            geometry: Geometry::Ems,
        }
    }

    /// A rigid magnet of mass `mass` carrying its own weight under an EMS rail, started 1 mm
    /// below its nominal gap and left to the law for `seconds`; returns the gap error (m) at
    /// each step. Semi-implicit Euler at the law's own period, the gap measured at the end of
    /// each step (exact acceleration given).
    fn fly(kind: StateParams, mass: f64, seconds: f64) -> std::vec::Vec<f64> {
        let (mut m, _, _) = paper_magnet(mass * GRAVITY);
        m.dt = 1.0 / kind.rate_hz;
        let law = LawParams {
            magnet: m,
            kind: LawKind::State(kind),
        }
        .compile::<f64>()
        .unwrap();
        let h_start = m.h0 + 1e-3;
        let mut st = law.equilibrium_state(m.h0);
        // The magnet starts displaced and at rest; the law starts in equilibrium at h0.
        let (mut z, mut zd, mut acc) = (m.h0 - h_start, 0.0, 0.0);
        let mut out = std::vec::Vec::new();
        for _ in 0..(seconds * kind.rate_hz) as usize {
            let h = m.h0 - z; // EMS: the magnet moving up closes the gap
            let o = law.update(
                &mut st,
                Measurement {
                    gap: h / m.h0,
                    accel: Some(acc / GRAVITY),
                    current: None,
                },
            );
            acc = (o.force - 1.0) * GRAVITY; // (F − M·g)/M with F = p0·force
            zd += acc * m.dt;
            z += zd * m.dt;
            out.push(h - m.h0);
        }
        out
    }

    /// The largest gap error in `e` (m).
    fn peak(e: &[f64]) -> f64 {
        e.iter().fold(0.0f64, |a, v| a.max(v.abs()))
    }

    /// Routh's boundary `kd = τ·(kp − Vb/h0)` of the third-order polynomial (derived by hand,
    /// module tests' doc) separates decay from growth in the discrete law + magnet.
    #[test]
    fn routh_boundary_of_the_pd_law_on_a_rigid_magnet() {
        let mass = 1000.0;
        let (_, vb_h0, tau) = paper_magnet(mass * GRAVITY);
        let kp = 3.0 * vb_h0;
        let kd_crit = tau * (kp - vb_h0);
        // Poles −0.78 ± 68.5j, −7.9 s⁻¹ (decays ×0.002 in 8 s) and +1.13 ± 56.3j, −11.7 s⁻¹
        // (grows until the current clamps at zero and the motion settles on a limit cycle).
        let stable = fly(gains(kp, 1.2 * kd_crit), mass, 8.0);
        let unstable = fly(gains(kp, 0.8 * kd_crit), mass, 8.0);
        let n = stable.len();
        assert!(
            peak(&stable[n - n / 8..]) < 1e-5,
            "{}",
            peak(&stable[n - n / 8..])
        );
        assert!(
            peak(&unstable[n - n / 8..]) > 3e-3,
            "{}",
            peak(&unstable[n - n / 8..])
        );
        // Below kp = Vb/h0 nothing holds it, whatever kd.
        let weak = fly(gains(0.9 * vb_h0, 10.0 * kd_crit), mass, 8.0);
        assert!(weak.last().unwrap().abs() > 2e-3, "{:?}", weak.last());
    }

    /// With the integral the gap returns to h0 (no offset), and at h0 the equilibrium holds the
    /// force at p0 to the last bit.
    #[test]
    fn the_gap_is_held_at_h0() {
        let mass = 600.0;
        let (m, vb_h0, tau) = paper_magnet(mass * GRAVITY);
        let kp = 4.0 * vb_h0;
        let mut g = gains(kp, 2.0 * tau * (kp - vb_h0));
        g.ki = 0.5 * vb_h0;
        g.kc = 1.0;
        // Poles −13.1 ± 107j, −5.0, −0.26 s⁻¹: after 30 s the integral's slow mode has left
        // e^(−0.26·30) ≈ 4e-4 of the 1 mm start.
        let e = fly(g, mass, 30.0);
        assert!(e.last().unwrap().abs() < 1e-6, "{:?}", e.last());
        let law = LawParams {
            magnet: m,
            kind: LawKind::State(g),
        }
        .compile::<f64>()
        .unwrap();
        let mut st = law.equilibrium_state(m.h0);
        for _ in 0..1000 {
            let o = law.update(&mut st, Measurement::gap(1.0));
            assert_eq!(o.force, 1.0);
            assert!(o.status.is_empty());
        }
    }

    /// f32 flies the same magnet as f64; I4F28 cannot hold the observer's ω²·δ and says so.
    #[test]
    fn scalars() {
        let (m, vb_h0, tau) = paper_magnet(9810.0);
        let g = gains(3.0 * vb_h0, 2.0 * tau * 2.0 * vb_h0);
        let p = LawParams {
            magnet: m,
            kind: LawKind::State(g),
        };
        let (l64, l32) = (p.compile::<f64>().unwrap(), p.compile::<f32>().unwrap());
        let (mut s64, mut s32) = (l64.equilibrium_state(0.0101), l32.equilibrium_state(0.0101));
        for k in 0..2000 {
            let h = 1.0 + 0.05 * libm::sin(k as f64 * 0.01);
            let a = l64.update(&mut s64, Measurement::gap(h));
            let b = l32.update(&mut s32, Measurement::gap(h as f32));
            assert!(
                (a.force - b.force as f64).abs() < 1e-4,
                "step {k}: {a:?} {b:?}"
            );
        }
        assert!(matches!(
            p.compile::<I4F28>(),
            Err(ParamError::Unrepresentable { .. })
        ));
    }

    /// The float fast path (one period per step) gives the general path's bits, state and
    /// status, on 200 000 pseudo-random states and samples per type, from ordinary to absurd
    /// (saturating voltages, non-finite and huge values that make it decline).
    #[test]
    fn fast_path_is_bit_identical() {
        fn check<S: Scalar + core::fmt::Debug>(seed: u64) -> (u32, u32) {
            let (mut m, vb_h0, tau) = paper_magnet(9810.0);
            m.dt = 1e-4;
            let mut g = gains(3.0 * vb_h0, 2.0 * tau * 2.0 * vb_h0);
            (g.ka, g.ki, g.kc, g.v_max) = (40.0, 0.5 * vb_h0, 10.0, 500.0);
            let law = g.compile::<S>(&m).unwrap();
            let mut s = seed;
            let mut next = || {
                s ^= s << 13;
                s ^= s >> 7;
                s ^= s << 17;
                s
            };
            let (mut fast, mut declined) = (0, 0);
            for _ in 0..200_000 {
                let mut val = |scale: f64| {
                    let r = next();
                    let u = (r >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
                    let mut ov = false;
                    let big = S::from_f64(0.9 * S::MAX_ABS * u, &mut ov);
                    match r & 0xFF {
                        0 => big.add_raw(big),                           // ±inf
                        1 => big.add_raw(big).sub_raw(big.add_raw(big)), // NaN
                        2 | 3 => big,
                        4 => S::from_f64(1e6 * u, &mut ov),
                        _ => S::from_f64(scale * u, &mut ov),
                    }
                };
                let mut coil = State::<S>::default();
                (coil.x, coil.y, coil.eta) = (val(0.5), val(0.5), val(0.5));
                let mut st = StateLawState {
                    integral: val(3.0),
                    eta_est: val(0.5),
                    rate_est: val(50.0),
                    accel: val(2.0),
                };
                let (gap, acc) = (S::ONE.sadd(val(0.5), &mut false), val(2.0));
                let accel = (next() & 1 == 0).then_some(acc);
                let (mut c1, mut s1) = (coil, st);
                let want = law.general_update(&mut c1, &mut s1, gap, accel);
                match law.fast_update(&mut coil, &mut st, gap, accel) {
                    Some(out) => {
                        fast += 1;
                        assert_eq!(std::format!("{out:?}"), std::format!("{want:?}"));
                        assert_eq!(std::format!("{coil:?}"), std::format!("{c1:?}"));
                        assert_eq!(std::format!("{st:?}"), std::format!("{s1:?}"));
                    }
                    None => declined += 1,
                }
            }
            (fast, declined)
        }
        let (f32_fast, f32_declined) = check::<f32>(0x9E37_79B9_7F4A_7C15);
        let (f64_fast, f64_declined) = check::<f64>(0x2545_F491_4F6C_DD1D);
        // Both paths are exercised.
        for (f, d) in [(f32_fast, f32_declined), (f64_fast, f64_declined)] {
            assert!(f > 150_000 && d > 1_000, "fast {f}, declined {d}");
        }
    }

    #[test]
    fn bad_values_are_named() {
        let (mut m, vb_h0, _) = paper_magnet(9810.0);
        m.dt = 1e-3;
        let compile = |g: StateParams| {
            LawParams {
                magnet: m,
                kind: LawKind::State(g),
            }
            .compile::<f64>()
            .unwrap_err()
        };
        let g = gains(2.0 * vb_h0, 100.0);
        assert_eq!(
            compile(StateParams { kd: -1.0, ..g }),
            ParamError::Negative(fields::KD)
        );
        assert_eq!(
            compile(StateParams { v_max: 40.0, ..g }),
            ParamError::NotPositive(Field {
                name: "state v_max − R0·i0",
                ..fields::V_MAX
            })
        );
        assert_eq!(
            compile(StateParams {
                rate_hz: 1000.0,
                ..g
            }),
            ParamError::NotPositive(Field {
                name: "state rate_hz (at least 2π·observer_hz)",
                ..fields::RATE
            })
        );
        // 1e8 periods in one update would hang the caller (a firmware tick far slower than
        // the control rate): refused.
        assert_eq!(
            compile(StateParams { rate_hz: 1e11, ..g }),
            ParamError::NotPositive(Field {
                name: "10 000 − state rate_hz·dt (control periods per step)",
                ..fields::RATE
            })
        );
    }
}
