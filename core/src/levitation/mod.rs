//! Levitation control: the paper's α-method PI law on `g = i/h` (Eq. 8–14) with its internal loop.
//!
//! Configuration ([`Params`], designed in `f64`; [`Levitation`], the compiled run-time form) is
//! kept apart from state ([`State`]): one compiled controller can drive many magnets, and
//! `update(&self, &mut State, gap)` is a pure function of its arguments (idsp style).
//!
//! # Per-unit deviation form
//! Internally every quantity is a per-unit *deviation from equilibrium*:
//!
//! | symbol | meaning                           | equilibrium |
//! |--------|-----------------------------------|-------------|
//! | `x`    | `g/g0 − 1`                        | 0           |
//! | `y`    | `KI·e_a/(R0·i0) − 1` (integral V) | 0           |
//! | `η`    | `h/h0 − 1`                        | 0           |
//!
//! Eq. 14 is evaluated in its increment form. With `δ = Δt/n_sub`, `V_b = R0·i0`,
//! `G0 = 2·K0` (Eq. 9), dividing Eq. 13 by `V_b` gives
//!
//! ```text
//! Δx = c·N / (1 + c·α·(1 + kph + η))          (Eq. 14, increment form)
//! N  = y − η − x·(1 + kpd + η)                ((B − A·g^t)/V_b)
//! c  = V_b·δ/(G0·g0),  kpd = (KP + KI·δ)·g0/V_b,  kph = (KP + KI·δ/2)·g0/V_b
//! y ← y − kih·(x^t + x^{t+δ}),  kih = KI·g0·δ/(2·V_b)       (Eq. 12, trapezoidal)
//! v = 1 + y − kpv·x^{t+δ},     kpv = KP·g0/V_b              (Eq. 10/11, per unit of V_b)
//! ```
//!
//! This is algebraically identical to the paper's Eq. 14 (`A`, `B` expanded), but the
//! equilibrium is exactly zero in every type (so constant gap holds to the last bit), no
//! large numbers cancel, and all run-time coefficients are O(1) or small — which is what lets
//! a 32-bit fixed-point format ([`crate::scalar::I4F28`]) run it. Outputs are per unit:
//! force `F/p0 = (1+x)²` (Eq. 1, 7), current `i/i0 = (1+x)(1+η)`, voltage `V/V_b`.
//!
//! # What the paper leaves open (docs/model.md §4)
//! * Current never negative: `g ≥ 0` is enforced (`x ≥ −1`), flagged [`Status::CURRENT_CLAMPED`].
//! * Supply voltage bounded by `±v_max`: if the unconstrained step would end beyond it, the
//!   step is recomputed with the coil (Eq. 9, same α-weighting) driven at `±v_max` and the
//!   integral is frozen (conditional-integration anti-windup), flagged
//!   [`Status::VOLTAGE_SATURATED`]. In fixed point the limit is additionally capped to the
//!   type's range.
//! * A gap `h ≤ 0` is a collision: the update runs with `h = 0` and flags
//!   [`Status::COLLISION`]; never a NaN. A NaN gap is rejected ([`Status::INVALID_INPUT`]) and
//!   the state is held.
//! * Arithmetic overflow saturates and flags [`Status::OVERFLOW`] (see [`crate::scalar`]).
//! * Parabolic interpolation needs `h^{t−Δt}`; before the first step the gap is taken to
//!   have been constant.
//!
//! # Cost on small cores (docs/hil.md, "Instruction budget")
//! * `n_sub = 1`, paper scheme, no voltage bound (the firmware's law): [`Levitation::update`]
//!   first runs a straight-line path with one check per update instead of one per operation;
//!   it gives the general path's bits exactly or declines.
//! * Fixed point evaluates the quotient of Eq. 14 division-free, `c·N/den ≈ N·(cr − cru·η)`
//!   ([`Params`]' `reciprocal`, exact to about one LSB of I4F28); floats keep the division.
//!
//! # Two schemes ([`Scheme`])
//! [`Scheme::Paper`] (the default) is Eq. 14 applied `n_sub` times per outer step, as above: a
//! first-order method for the coil + PI equations (docs/numerics.md). [`Scheme::Accurate`]
//! integrates the same continuous system — the limit of the paper scheme as `n_sub → ∞` — by
//! the 2-stage Gauss–Legendre method (order 4), see [`accurate`]; it ignores `n_sub` and `α`.

use crate::law::Field;
use crate::scalar::Scalar;

pub mod accurate;
pub mod batch;

/// How the gap is interpolated inside one outer step for the internal loop (docs/model.md §4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Interpolation {
    /// Linear between `h^t` and `h^{t+Δt}`.
    Linear,
    /// The parabola through `h^{t−Δt}`, `h^t`, `h^{t+Δt}`.
    Parabolic,
}

/// Which integrator advances the coil + PI equations over one outer step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Scheme {
    /// The paper's Eq. 14, `n_sub` times per outer step (first order in `Δt/n_sub`).
    #[default]
    Paper,
    /// 2-stage Gauss–Legendre on the limit system of Eq. 9 + 10 (order 4), see [`accurate`].
    Accurate,
}

impl Interpolation {
    /// The name as scenarios write it (`linear`, `parabolic`).
    pub const fn as_str(self) -> &'static str {
        match self {
            Interpolation::Linear => "linear",
            Interpolation::Parabolic => "parabolic",
        }
    }
}

impl Scheme {
    /// The name as scenarios write it (`paper`, `accurate`).
    pub const fn as_str(self) -> &'static str {
        match self {
            Scheme::Paper => "paper",
            Scheme::Accurate => "accurate",
        }
    }
}

/// Controller parameters in SI units, designed in `f64` (paper §4.2 values from [`Params::paper`]).
///
/// Its serde names carry the units and are the scenario's `[controller]` keys ([`fields`]);
/// unknown keys are refused. `p0` and `dt` are not serialised (read back as 1 N and 0 s):
/// they are the magnet's static load and the run's step, set where the law meets its magnet.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Params {
    /// Nominal current i0 (A).
    #[cfg_attr(feature = "serde", serde(rename = "i0_A"))]
    pub i0: f64,
    /// Nominal gap h0 (m).
    #[cfg_attr(feature = "serde", serde(rename = "h0_m"))]
    pub h0: f64,
    /// Coil resistance R0 (Ω).
    #[cfg_attr(feature = "serde", serde(rename = "r0_ohm"))]
    pub r0: f64,
    /// Proportional gain KP (V per A/m).
    #[cfg_attr(feature = "serde", serde(rename = "kp_V_m_per_A"))]
    pub kp: f64,
    /// Integral gain KI (V per A/m·s).
    #[cfg_attr(feature = "serde", serde(rename = "ki_V_m_per_A_s"))]
    pub ki: f64,
    /// Static load carried by the magnet p0 (N); fixes K0 (Eq. 7).
    #[cfg_attr(feature = "serde", serde(skip, default = "one"))]
    pub p0: f64,
    /// α of the α-method, in [0, 1].
    pub alpha: f64,
    /// Outer time step Δt (s).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub dt: f64,
    /// Number of internal-loop sub-steps per outer step (≥ 1).
    #[cfg_attr(feature = "serde", serde(rename = "nsub"))]
    pub n_sub: u32,
    /// Gap interpolation inside the outer step.
    #[cfg_attr(feature = "serde", serde(rename = "interp"))]
    pub interpolation: Interpolation,
    /// Supply voltage bound (V), `f64::INFINITY` for none.
    #[cfg_attr(feature = "serde", serde(rename = "vmax_V"))]
    pub v_max: f64,
    /// Integrator of the coil + PI equations (the paper's by default).
    #[cfg_attr(feature = "serde", serde(default))]
    pub scheme: Scheme,
}

/// The static load a deserialised [`Params`] starts with (set per magnet).
#[cfg(feature = "serde")]
const fn one() -> f64 {
    1.0
}

/// Standard gravity used for the paper's loads (m/s²).
pub const GRAVITY: f64 = 9.81;

/// The most internal-loop sub-steps one update may run (`n_sub`), from the control period
/// budget: an update must fit in its control period, and the paper's period is Δt = 1 ms.
/// One sub-step of Eq. 14 takes 10–25 ns on a desktop host (docs/numerics.md; `n_sub =
/// 4294967295` took 49 s), the fastest target this core runs on, so 10⁵ sub-steps fill that
/// millisecond there; on a Cortex-M4 (about 150 instructions per f32 sub-step,
/// docs/c-api.md) the same millisecond holds about 10³. Above the bound no target keeps a
/// 1 kHz loop: a firmware's update would never return in time (docs/c-api.md, "Bounds").
pub const MAX_N_SUB: u32 = 100_000;

impl Params {
    /// The paper's §4.2 values (i0 = 43 A, h0 = 0.01 m, R0 = 1 Ω, KP = 0.01, KI = 6.0) for a
    /// magnet carrying `p0` newtons, α = 0.5, one sub-step, linear interpolation, no
    /// voltage bound, the paper's scheme.
    pub const fn paper(p0: f64, dt: f64) -> Self {
        Params {
            i0: 43.0,
            h0: 0.01,
            r0: 1.0,
            kp: 0.01,
            ki: 6.0,
            p0,
            alpha: 0.5,
            dt,
            n_sub: 1,
            interpolation: Interpolation::Linear,
            v_max: f64::INFINITY,
            scheme: Scheme::Paper,
        }
    }

    /// One of the four maglev wheels of the 15 t car body of Fig. 1: p0 = 15000·9.81/4 N.
    pub const fn paper_wheel(dt: f64) -> Self {
        Self::paper(15_000.0 * GRAVITY / 4.0, dt)
    }

    /// Equilibrium value of the controlled variable, g0 = i0/h0 (A/m).
    pub fn g0(&self) -> f64 {
        self.i0 / self.h0
    }

    /// Magnet constant K0 = p0·h0²/i0² (N·m²/A², Eq. 7), so that K0·g0² = p0.
    pub fn k0(&self) -> f64 {
        self.p0 * self.h0 * self.h0 / (self.i0 * self.i0)
    }

    /// Base voltage V_b = R0·i0 (V): the coil voltage at equilibrium.
    pub fn v_base(&self) -> f64 {
        self.r0 * self.i0
    }

    /// Magnet force G = K0·g² (N, Eq. 1).
    pub fn force(&self, g: f64) -> f64 {
        self.k0() * g * g
    }

    /// Checks every parameter, naming the first bad one.
    pub fn validate(&self) -> Result<(), ParamError> {
        let positive = [
            (fields::I0, self.i0),
            (fields::H0, self.h0),
            (fields::R0, self.r0),
            (fields::P0, self.p0),
            (fields::DT, self.dt),
        ];
        for (name, v) in positive {
            if !v.is_finite() {
                return Err(ParamError::NotFinite(name));
            }
            if v <= 0.0 {
                return Err(ParamError::NotPositive(name));
            }
        }
        for (name, v) in [
            (fields::KP, self.kp),
            (fields::KI, self.ki),
            (fields::ALPHA, self.alpha),
        ] {
            if !v.is_finite() {
                return Err(ParamError::NotFinite(name));
            }
            if v < 0.0 {
                return Err(ParamError::Negative(name));
            }
        }
        if self.alpha > 1.0 {
            return Err(ParamError::AlphaOutOfRange);
        }
        if self.n_sub == 0 {
            return Err(ParamError::NotPositive(fields::N_SUB));
        }
        if self.n_sub > MAX_N_SUB {
            return Err(ParamError::TooLarge {
                field: fields::N_SUB,
                max: MAX_N_SUB as f64,
            });
        }
        if self.v_max.is_nan() {
            return Err(ParamError::NotFinite(fields::V_MAX));
        }
        if self.v_max <= 0.0 {
            return Err(ParamError::NotPositive(fields::V_MAX));
        }
        Ok(())
    }

    /// The per-unit run-time coefficients in f64, before conversion (see the module docs).
    fn coefficients(&self) -> [(&'static str, f64); 7] {
        let delta = self.dt / self.n_sub as f64;
        let vb = self.v_base();
        let g0 = self.g0();
        let c = vb * delta / (2.0 * self.k0() * g0);
        let kph = (self.kp + self.ki * delta / 2.0) * g0 / vb;
        [
            ("c", c),
            ("kpd", (self.kp + self.ki * delta) * g0 / vb),
            ("c*alpha", c * self.alpha),
            ("c*alpha*(1+kph)", c * self.alpha * (1.0 + kph)),
            ("kih", self.ki * g0 * delta / (2.0 * vb)),
            ("kpv", self.kp * g0 / vb),
            ("1/n_sub", 1.0 / self.n_sub as f64),
        ]
    }

    /// The division-free form of Eq. 14's quotient for fixed point, with the magnitude each
    /// coefficient's conversion error is measured against.
    ///
    /// `c·N/den` with `den = d0 + cα·η`, `d0 = 1 + cα(1 + kph)`: with `u = cα·η/d0`,
    /// `1/den = (1/d0)(1 − u + u² − …)`, so `c·N/den ≈ N·(cr − cru·η)`, `cr = c/d0`,
    /// `cru = c·cα/d0²`. The omitted terms are `cr·u²/(1 + u)`: at Δt = 1 ms and `|η| ≤ 1`
    /// (`cα = 1.3e-3`) 4e-9·η² absolute on a coefficient of 2.5e-3, i.e. about one LSB of
    /// I4F28 (3.7e-9), the coefficient's own quantisation; at the firmware's 0.1 ms, 100×
    /// less. The saturated branch's coil step (`den = 1 + cα(1 + η)`) is expanded the same
    /// way around `d0 = 1 + cα` (`crs`, `crsu`). `cru`, `crsu` are far below one LSB's
    /// relative resolution on their own; what matters is their error next to `cr` (`crs`).
    fn reciprocal(&self) -> [(&'static str, f64, f64); 4] {
        let [(_, c), _, (_, ca), (_, ca1), ..] = self.coefficients();
        let d0 = 1.0 + ca1;
        let ds = 1.0 + ca;
        let (cr, crs) = (c / d0, c / ds);
        [
            ("c/den0", cr, cr),
            ("c*ca/den0^2", c * ca / (d0 * d0), cr),
            ("c/(1+c*alpha)", crs, crs),
            ("c*ca/(1+c*alpha)^2", c * ca / (ds * ds), crs),
        ]
    }

    /// Fixed point, `n_sub = 1`: the largest bound `B` (1, ½, ¼ or ⅛) such that with
    /// `|x|, |y| ≤ B` and a gap accepted without event (`−1 < η ≤ h_max − 1`), no operation of
    /// the update can leave 0.9 × the type's range — worst case of every intermediate,
    /// operation by operation, in f64. Then the fast path needs no per-operation saturation.
    fn fast_bound<S: Scalar>(&self, h_max_pu: f64) -> Option<S> {
        let [_, (_, kpd), _, _, (_, kih), (_, kpv), _] = self.coefficients();
        let [(_, cr, _), (_, cru, _), ..] = self.reciprocal();
        let e = (h_max_pu - 1.0).max(1.0);
        let lim = 0.9 * S::MAX_ABS;
        // Every factor of a product also below the bound that makes `mul_raw` exact.
        let lim_factor = lim.min(crate::scalar::RAW_OPERAND_MAX);
        [1.0, 0.5, 0.25, 0.125].into_iter().find_map(|b: f64| {
            let fac = 1.0 + kpd + e;
            let num = b + e + b * fac;
            let coef = cr + cru * e;
            let dx = num * coef;
            let x1 = b + dx;
            let y1 = b + kih * (b + x1);
            let v1 = 1.0 + y1 + kpv * x1;
            let g = 1.0 + x1;
            let worst = [
                fac,
                b * fac,
                b + e,
                num,
                coef,
                cru * e,
                dx,
                x1,
                b + x1,
                kih * (b + x1),
                y1,
                1.0 + y1,
                kpv * x1,
                v1,
                g,
                g * g,
                g * (1.0 + e),
            ];
            // The factors of the seven products (x·fac, cru·η, num·coef, kih·(x + x1),
            // kpv·x1, g·g, g·(1 + η)).
            let factors = [b, fac, cru, e, num, coef, kih, b + x1, kpv, x1, g, 1.0 + e];
            let ok = worst.iter().all(|w| w.is_finite() && *w <= lim)
                && factors.iter().all(|w| *w <= lim_factor);
            let mut ov = false;
            let s = S::from_f64(b, &mut ov);
            (ok && !ov).then_some(s)
        })
    }

    /// Converts to the run-time type once, with the default tolerance
    /// [`DEFAULT_COEFFICIENT_TOLERANCE`].
    pub fn compile<S: Scalar>(&self) -> Result<Levitation<S>, ParamError> {
        self.compile_with_tolerance(DEFAULT_COEFFICIENT_TOLERANCE)
    }

    /// Converts to the run-time type once. Each run-time coefficient must be representable
    /// with a relative error of at most `tolerance`; otherwise the type cannot carry this
    /// configuration's sub-step increments and [`ParamError::Unrepresentable`] names the
    /// coefficient (typically `c` for fixed point with many sub-steps).
    pub fn compile_with_tolerance<S: Scalar>(
        &self,
        tolerance: f64,
    ) -> Result<Levitation<S>, ParamError> {
        self.validate()?;
        // Only the coefficients of the selected scheme must be representable.
        let mut paper = [S::ZERO; 7];
        let mut gauss = accurate::Gauss::default();
        match self.scheme {
            Scheme::Paper => {
                for (slot, (name, value)) in paper.iter_mut().zip(self.coefficients().iter()) {
                    *slot = convert(Field::derived(None, name), *value, tolerance)?;
                }
            }
            Scheme::Accurate => gauss = accurate::Gauss::compile(self, tolerance)?,
        }
        let [c, kpd, ca, ca1, kih, kpv, inv_n] = paper;
        // Division-free Eq. 14 (fixed point): the reciprocal's coefficients.
        let mut recip = [S::ZERO; 4];
        if !S::FLOAT && self.scheme == Scheme::Paper {
            for (slot, (name, value, scale)) in recip.iter_mut().zip(self.reciprocal().iter()) {
                *slot = convert_scaled(Field::derived(None, name), *value, *scale, tolerance)?;
            }
        }
        let [cr, cru, crs, crsu] = recip;
        // The voltage bound in per unit, capped inside the type's range so that the
        // saturated branch itself cannot overflow.
        let v_max_pu = (self.v_max / self.v_base()).min(0.9 * S::MAX_ABS);
        let mut ov = false;
        let v_max = S::from_f64(v_max_pu, &mut ov);
        let half = S::from_f64(0.5, &mut ov);
        // Largest per-unit gap accepted: 100·h0, or what the type holds with headroom.
        let h_max_pu = (0.45 * S::MAX_ABS).min(100.0);
        let h_max = S::from_f64(h_max_pu, &mut ov);
        if ov {
            return Err(ParamError::Unrepresentable {
                field: fields::V_MAX,
                value: v_max_pu,
                relative_error: f64::INFINITY,
                scalar: S::NAME,
            });
        }
        // 1 + kpd and 1 + cα(1 + kph) exactly as the general path adds them.
        let one_kpd = S::ONE.sadd(kpd, &mut ov);
        let one_ca1 = S::ONE.sadd(ca1, &mut ov);
        // The fast path takes gaps up to 2·h0 (|η| ≤ 1); larger ones go the general way.
        let fast_h_pu = h_max_pu.min(FAST_H_MAX);
        let fast_xy = match (self.n_sub, self.scheme) {
            (1, Scheme::Paper) if S::FLOAT => Some(S::ZERO), // floats check the results instead
            (1, Scheme::Paper) => self.fast_bound::<S>(fast_h_pu),
            _ => None,
        };
        // A voltage bound would cost the fast path two compares per update: bounded
        // configurations take the general path.
        let fast = fast_xy.is_some() && !ov && self.v_max == f64::INFINITY;
        let fast_h = if fast {
            S::from_f64(fast_h_pu, &mut ov)
        } else {
            S::ZERO // no gap passes `0 < h ≤ 0`: the fast path always declines
        };
        Ok(Levitation {
            params: *self,
            c,
            kpd,
            ca,
            kih,
            kpv,
            inv_n,
            v_max,
            half,
            h_max,
            one_kpd,
            one_ca1,
            cr,
            cru,
            crs,
            crsu,
            fast_h,
            fast_xy: fast_xy.unwrap_or(S::ZERO),
            gauss,
        })
    }
}

/// `value` in the run-time type, within relative error `tolerance` (else
/// [`ParamError::Unrepresentable`] naming it).
pub(crate) fn convert<S: Scalar>(
    field: Field,
    value: f64,
    tolerance: f64,
) -> Result<S, ParamError> {
    convert_scaled(field, value, value, tolerance)
}

/// `value` in the run-time type with an absolute error of at most `tolerance·scale` (else
/// [`ParamError::Unrepresentable`], the error given relative to `scale`): for a coefficient
/// that only ever corrects a larger one of magnitude `scale`.
fn convert_scaled<S: Scalar>(
    field: Field,
    value: f64,
    scale: f64,
    tolerance: f64,
) -> Result<S, ParamError> {
    let mut ov = false;
    let s = S::from_f64(value, &mut ov);
    let rel = if scale == 0.0 {
        0.0
    } else {
        ((s.to_f64() - value) / scale).abs()
    };
    if ov || rel.is_nan() || rel > tolerance {
        return Err(ParamError::Unrepresentable {
            field,
            value,
            relative_error: rel,
            scalar: S::NAME,
        });
    }
    Ok(s)
}

/// Largest per-unit gap `h/h0` the `n_sub = 1` fast path takes (docs/hil.md).
const FAST_H_MAX: f64 = 2.0;

/// Largest relative error accepted when converting a run-time coefficient to its type.
pub const DEFAULT_COEFFICIENT_TOLERANCE: f64 = 1e-4;

/// A parameter that cannot be used, named as data ([`Field`]: its law and key).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ParamError {
    /// NaN or infinite.
    NotFinite(Field),
    /// Must be > 0.
    NotPositive(Field),
    /// Must be ≥ 0.
    Negative(Field),
    /// α outside [0, 1].
    AlphaOutOfRange,
    /// Above its upper bound `max` (e.g. [`MAX_N_SUB`]).
    TooLarge {
        /// The parameter.
        field: Field,
        /// Its bound.
        max: f64,
    },
    /// The run-time type cannot represent a coefficient accurately enough.
    Unrepresentable {
        /// The coefficient (a parameter, the gap, or one derived from several).
        field: Field,
        value: f64,
        relative_error: f64,
        scalar: &'static str,
    },
}

impl ParamError {
    /// The parameter (or coefficient) this error is about.
    pub fn field(&self) -> Field {
        match *self {
            ParamError::NotFinite(f) | ParamError::NotPositive(f) | ParamError::Negative(f) => f,
            ParamError::AlphaOutOfRange => fields::ALPHA,
            ParamError::TooLarge { field, .. } => field,
            ParamError::Unrepresentable { field, .. } => field,
        }
    }
}

/// The parameters of [`Params`] (and the gap) as errors name them, keys as `[controller]`
/// spells them (units in the names).
pub mod fields {
    use crate::law::Field;
    /// `i0`.
    pub const I0: Field = Field::magnet("i0_A", "i0");
    /// `h0`.
    pub const H0: Field = Field::magnet("h0_m", "h0");
    /// `r0`.
    pub const R0: Field = Field::magnet("r0_ohm", "r0");
    /// `kp`.
    pub const KP: Field = Field::magnet("kp_V_m_per_A", "kp");
    /// `ki`.
    pub const KI: Field = Field::magnet("ki_V_m_per_A_s", "ki");
    /// `p0`.
    pub const P0: Field = Field::magnet("p0_N", "p0");
    /// `alpha`.
    pub const ALPHA: Field = Field::magnet("alpha", "alpha");
    /// `dt`, the structural step.
    pub const DT: Field = Field::magnet("dt_s", "dt");
    /// `n_sub`.
    pub const N_SUB: Field = Field::magnet("nsub", "n_sub");
    /// `v_max`, the paper's law's supply bound.
    pub const V_MAX: Field = Field::magnet("vmax_V", "v_max");
    /// The gap a state starts from (an argument, not a parameter).
    pub const GAP: Field = Field::magnet("gap_m", "h");
}

impl core::fmt::Display for ParamError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ParamError::NotFinite(n) => write!(f, "parameter {n} is not a finite number"),
            ParamError::NotPositive(n) => write!(f, "parameter {n} must be positive"),
            ParamError::Negative(n) => write!(f, "parameter {n} must not be negative"),
            ParamError::AlphaOutOfRange => write!(f, "parameter alpha must lie in [0, 1]"),
            ParamError::TooLarge { field, max } => {
                write!(f, "parameter {field} must be at most {max}")
            }
            ParamError::Unrepresentable {
                field: name,
                value,
                relative_error,
                scalar,
            } if name.law == Some(crate::law::LawName::State) => write!(
                f,
                "{scalar} cannot represent the state law's coefficient {name} = {value:e} \
                 (relative error {relative_error:.1e}): a gain or filter coefficient per unit \
                 outside the type's range or below its resolution; use a wider type or \
                 gains of smaller per-unit size"
            ),
            ParamError::Unrepresentable {
                field: name,
                value,
                relative_error,
                scalar,
            } => write!(
                f,
                "{scalar} cannot represent the sub-step coefficient {name} = {value:e} \
                 (relative error {relative_error:.1e}); use fewer sub-steps, a longer step \
                 or a wider type"
            ),
        }
    }
}

/// Events raised by an update (bit set; several may be raised at once).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Status(pub u8);

impl Status {
    /// The gap reached zero or below: the magnet touches the rail.
    pub const COLLISION: Status = Status(1);
    /// The supply voltage bound was active during the step.
    pub const VOLTAGE_SATURATED: Status = Status(2);
    /// The current would have gone negative and was held at zero.
    pub const CURRENT_CLAMPED: Status = Status(4);
    /// Arithmetic saturated at the type's range: the numbers of this step are not trustworthy.
    pub const OVERFLOW: Status = Status(8);
    /// The gap input was NaN or beyond the accepted range; state held or gap clamped.
    pub const INVALID_INPUT: Status = Status(16);
    /// A law's own reference or command reached its bound (the gap loop's `x_ref_max`,
    /// [`crate::law`]); never raised by the paper's law.
    pub const REFERENCE_LIMITED: Status = Status(32);

    /// No event.
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }
    /// Whether every event of `other` is raised here.
    pub const fn contains(self, other: Status) -> bool {
        self.0 & other.0 == other.0
    }
    /// Union of two sets of events.
    pub const fn union(self, other: Status) -> Status {
        Status(self.0 | other.0)
    }
    fn raise_if(&mut self, cond: bool, what: Status) {
        if cond {
            self.0 |= what.0;
        }
    }
}

/// Controller state: per-unit deviations from equilibrium (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct State<S> {
    /// `g/g0 − 1`.
    pub x: S,
    /// `KI·e_a/(R0·i0) − 1`.
    pub y: S,
    /// `h/h0 − 1` at the end of the last step.
    pub eta: S,
    /// `h/h0 − 1` one outer step earlier (for parabolic interpolation).
    pub eta_prev: S,
    /// Per-unit voltage at the end of the last step.
    pub v: S,
}

/// One update's result, per unit (multiply by `g0`, `p0`, `i0`, `V_b` for SI; see [`Levitation::to_si`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Output<S> {
    /// `g/g0`.
    pub g: S,
    /// `G/p0 = (g/g0)²` (Eq. 1).
    pub force: S,
    /// `i/i0 = (g/g0)·(h/h0)`.
    pub current: S,
    /// `V/(R0·i0)`.
    pub voltage: S,
    /// Events of this step.
    pub status: Status,
}

/// The same output in SI units.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SiOutput {
    /// g (A/m).
    pub g: f64,
    /// Magnet force G (N), upward on the magnet.
    pub force: f64,
    /// Coil current i (A).
    pub current: f64,
    /// Coil voltage V (V).
    pub voltage: f64,
    /// Events of this step.
    pub status: Status,
}

/// A compiled controller: parameters converted once to the run-time type `S`.
#[derive(Clone, Copy, Debug)]
pub struct Levitation<S> {
    params: Params,
    c: S,
    kpd: S,
    ca: S,
    kih: S,
    kpv: S,
    inv_n: S,
    v_max: S,
    half: S,
    h_max: S,
    /// `1 + kpd`, `1 + cα(1 + kph)` (as the general path adds them).
    one_kpd: S,
    one_ca1: S,
    /// Division-free Eq. 14 for fixed point ([`Params::reciprocal`]); zero for floats.
    cr: S,
    cru: S,
    crs: S,
    crsu: S,
    /// `n_sub = 1` under the paper's scheme without a voltage bound: [`Levitation::update`]
    /// tries the straight-line path first for gaps `0 < h ≤ fast_h` (zero otherwise: never); for fixed point it
    /// requires `|x|, |y| ≤ fast_xy` ([`Params::fast_bound`]).
    fast_h: S,
    fast_xy: S,
    gauss: accurate::Gauss<S>,
}

impl<S: Scalar> Levitation<S> {
    /// The parameters this controller was compiled from.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// Gauss intervals per outer step under [`Scheme::Accurate`] ([`accurate::intervals`]);
    /// 0 under the paper scheme.
    pub fn accurate_intervals(&self) -> u32 {
        self.gauss.m()
    }

    /// Per-unit gap `h/h0` of a gap in metres, in the run-time type (saturating, flagged).
    pub fn gap_pu(&self, h: f64, overflow: &mut bool) -> S {
        S::from_f64(h / self.params.h0, overflow)
    }

    /// [`Levitation::initial_state`], refusing a gap that is not a finite positive number of
    /// metres the type can hold (`NotFinite("h")`, `NotPositive("h")`, `Unrepresentable`):
    /// an unchecked NaN would start in a collision state.
    pub fn try_initial_state(&self, h: f64) -> Result<State<S>, ParamError> {
        self.check_gap(h)?;
        Ok(self.initial_state(h))
    }

    /// [`Levitation::equilibrium_state`] with the checks of [`Levitation::try_initial_state`].
    pub fn try_equilibrium_state(&self, h: f64) -> Result<State<S>, ParamError> {
        self.check_gap(h)?;
        Ok(self.equilibrium_state(h))
    }

    fn check_gap(&self, h: f64) -> Result<(), ParamError> {
        if !h.is_finite() {
            return Err(ParamError::NotFinite(fields::GAP));
        }
        if h <= 0.0 {
            return Err(ParamError::NotPositive(fields::GAP));
        }
        let mut ov = false;
        let pu = self.gap_pu(h, &mut ov);
        if ov || pu > self.h_max {
            return Err(ParamError::Unrepresentable {
                field: fields::GAP,
                value: h / self.params.h0,
                relative_error: f64::INFINITY,
                scalar: S::NAME,
            });
        }
        Ok(())
    }

    /// The state at equilibrium (docs/model.md §4): `g = g0`, `KI·e_a = R0·i0`, the gap taken to
    /// have been `h` (m) until now. Use [`Levitation::try_initial_state`] where `h` may be
    /// bad: here a NaN gap is taken as 0 (a collision state) without a flag.
    pub fn initial_state(&self, h: f64) -> State<S> {
        let mut ov = false;
        let eta = self.gap_pu(h, &mut ov).ssub(S::ONE, &mut ov);
        State {
            x: S::ZERO,
            y: S::ZERO,
            eta,
            eta_prev: eta,
            v: S::ONE,
        }
    }

    /// The state in equilibrium *at gap `h`* (m): `g = g0` and the integral holding
    /// `V = R0·h·g0`, so a constant gap `h` is held exactly. Equal to
    /// [`Levitation::initial_state`] at `h = h0`; a vehicle that starts in static equilibrium
    /// over an irregular rail (docs/model.md §9) starts here.
    pub fn equilibrium_state(&self, h: f64) -> State<S> {
        let mut st = self.initial_state(h);
        st.y = st.eta;
        let mut ov = false;
        st.v = S::ONE.sadd(st.eta, &mut ov);
        st
    }

    /// Output describing a state (no step taken): used for the row at t = 0.
    pub fn output(&self, st: &State<S>) -> Output<S> {
        let mut ov = false;
        let g = S::ONE.sadd(st.x, &mut ov);
        let h = S::ONE.sadd(st.eta, &mut ov);
        let mut status = Status::default();
        status.raise_if(ov, Status::OVERFLOW);
        Output {
            g,
            force: g.smul(g, &mut ov),
            current: g.smul(h, &mut ov),
            voltage: st.v,
            status,
        }
    }

    /// Converts an output to SI units (f64). Never non-finite: a product beyond f64's range
    /// (only an `f64` controller's saturated output can get there) saturates at ±`f64::MAX`
    /// and raises [`Status::OVERFLOW`].
    pub fn to_si(&self, o: &Output<S>) -> SiOutput {
        let p = &self.params;
        let mut ov = false;
        let mut si = |v: S, scale: f64| (v.to_f64()).smul(scale, &mut ov);
        let (g, force) = (si(o.g, p.g0()), si(o.force, p.p0));
        let (current, voltage) = (si(o.current, p.i0), si(o.voltage, p.v_base()));
        let mut status = o.status;
        status.raise_if(ov, Status::OVERFLOW);
        SiOutput {
            g,
            force,
            current,
            voltage,
            status,
        }
    }

    /// One outer step Δt: the gap moves from the state's last gap to `h_next` (per unit,
    /// `h/h0`), interpolated inside the step (docs/model.md §4), and the selected [`Scheme`] advances
    /// the coil + PI equations: Eq. 14 `n_sub` times, or the Gauss–Legendre intervals of
    /// [`accurate`]. Never panics; every anomaly is reported in [`Output::status`].
    ///
    /// With `n_sub = 1` under the paper's scheme and no voltage bound (the firmware's law) it runs
    /// a straight-line fast path (`fast_update`) first, which gives the same bits or declines.
    #[inline]
    pub fn update(&self, st: &mut State<S>, h_next: S) -> Output<S> {
        if let Some(out) = self.fast_update(st, h_next) {
            return out;
        }
        self.general_update(st, h_next)
    }

    /// The general path of [`Levitation::update`], out of line so that the fast path's
    /// prologue stays small.
    #[inline(never)]
    fn general_update(&self, st: &mut State<S>, h_next: S) -> Output<S> {
        // Without a reference the reference terms are compiled out: the paper's law costs
        // no more than before the gap loop existed (instruction counts in docs/hil.md).
        self.advance::<false>(st, h_next, S::ZERO)
    }

    /// The paper's law for `n_sub = 1` in one straight line (docs/hil.md, "Instruction
    /// budget"): [`Levitation::substep`]'s operations in its order, unchecked, with one check
    /// for the whole update instead of one per operation. Fixed point: `|x|, |y|` within the
    /// bound proven at compile time ([`Params::fast_bound`]) keeps every intermediate in
    /// range. Floats: an overflow anywhere propagates an infinity or NaN into `Δx`, `v` or
    /// the force or the voltage (`x ≥ −1` and the gap are bounded, the denominator is ≥ 1; a
    /// `Δx` of −∞ ends below the current floor, which declines), so the sum of the force
    /// and the voltage is checked once. Declines (`None`, state untouched) on any event —
    /// collision, gap beyond 2·h0 or NaN, inputs beyond the bound, current floor,
    /// non-finite result — and the general path runs; so the outcome is
    /// bit-identical to the general path's either way.
    #[inline(always)]
    pub(crate) fn fast_update(&self, st: &mut State<S>, h1: S) -> Option<Output<S>> {
        if !h1.positive_up_to(self.fast_h) {
            return None;
        }
        let (x, y) = (st.x, st.y);
        if !S::FLOAT {
            let b = self.fast_xy;
            let nb = S::ZERO.sub_raw(b);
            if !(x >= nb && x <= b && y >= nb && y <= b) {
                return None;
            }
        }
        let one = S::ONE;
        let eta = h1.sub_raw(one);
        let num = y.sub_raw(eta).sub_raw(x.mul_raw(self.one_kpd.add_raw(eta)));
        let dx = if S::FLOAT {
            let den = self.one_ca1.add_raw(self.ca.mul_raw(eta));
            self.c.mul_raw(num).div_raw(den)
        } else {
            num.mul_raw(self.cr.sub_raw(self.cru.mul_raw(eta)))
        };
        let x1 = x.add_raw(dx);
        let g = one.add_raw(x1);
        // `1 + x1 < 0` is `x1 < −1`: exact in fixed point, and in floats by Sterbenz's lemma
        // on [−2, −½] (outside it both sides have the same sign).
        if g < S::ZERO {
            return None;
        }
        let y1 = y.sub_raw(self.kih.mul_raw(x.add_raw(x1)));
        let v1 = one.add_raw(y1).sub_raw(self.kpv.mul_raw(x1));
        let force = g.mul_raw(g);
        let current = g.mul_raw(one.add_raw(eta));
        if S::FLOAT && !v1.add_raw(force).is_finite_value() {
            return None;
        }
        st.eta_prev = st.eta;
        st.eta = eta;
        st.x = x1;
        st.y = y1;
        st.v = v1;
        Some(Output {
            g,
            force,
            current,
            voltage: v1,
            status: Status::default(),
        })
    }

    /// [`Levitation::update`] with the reference `g_ref = g0·(1 + x_ref)` in place of `g0`
    /// in the error (Eq. 8: `e = g_ref − g`), held over the step: the inner loop of an outer
    /// (gap) loop such as [`crate::gap_control`]. Per unit this adds `kpd·x_ref` to `N`,
    /// `2·kih·x_ref` to the integral's increment and `kpv·x_ref` to the voltage (module docs);
    /// `x_ref = 0` is exactly [`Levitation::update`].
    pub fn update_with_reference(&self, st: &mut State<S>, h_next: S, x_ref: S) -> Output<S> {
        self.advance::<true>(st, h_next, x_ref)
    }

    /// The outer step; `REF = false` ignores `x_ref` (treated as zero) at compile time.
    #[inline]
    fn advance<const REF: bool>(&self, st: &mut State<S>, h_next: S, x_ref: S) -> Output<S> {
        let mut ov = false;
        let mut status = Status::default();
        // NaN (floats only) is the one input that cannot be clamped meaningfully.
        if is_nan(h_next) {
            let mut out = self.output(st);
            out.status = out.status.union(Status::INVALID_INPUT);
            return out;
        }
        let h1 = if h_next <= S::ZERO {
            status = status.union(Status::COLLISION);
            S::ZERO
        } else if h_next > self.h_max {
            status = status.union(Status::INVALID_INPUT);
            self.h_max
        } else {
            h_next
        };
        let eta1 = h1.ssub(S::ONE, &mut ov);
        let eta0 = st.eta;
        // Interpolation of η inside the step: η(s) = η0 + s·b1 + s²·b2, s = k/n.
        let (b1, b2) = match self.params.interpolation {
            Interpolation::Linear => (eta1.ssub(eta0, &mut ov), S::ZERO),
            Interpolation::Parabolic => {
                let m = st.eta_prev;
                let b1 = eta1.ssub(m, &mut ov).smul(self.half, &mut ov);
                let two_eta0 = eta0.sadd(eta0, &mut ov);
                let b2 = eta1
                    .ssub(two_eta0, &mut ov)
                    .sadd(m, &mut ov)
                    .smul(self.half, &mut ov);
                (b1, b2)
            }
        };
        let (x, y, v) = match self.params.scheme {
            Scheme::Paper => {
                self.paper_steps::<REF>(st, eta0, eta1, b1, b2, x_ref, &mut status, &mut ov)
            }
            Scheme::Accurate => {
                let eta = accurate::Gap { eta0, b1, b2 };
                self.gauss.step(
                    st.x,
                    st.y,
                    st.v,
                    &eta,
                    x_ref,
                    self.v_max,
                    &mut status,
                    &mut ov,
                )
            }
        };
        st.x = x;
        st.y = y;
        st.v = v;
        st.eta_prev = eta0;
        st.eta = eta1;
        let mut out = self.output(st);
        status.raise_if(ov, Status::OVERFLOW);
        out.status = out.status.union(status);
        out
    }

    /// Eq. 14 `n_sub` times over the outer step, the gap interpolated (docs/model.md §4), with
    /// the reference `g0·(1 + x_ref)`: returns the new `(x, y, v)`.
    #[allow(clippy::too_many_arguments)]
    fn paper_steps<const REF: bool>(
        &self,
        st: &State<S>,
        eta0: S,
        eta1: S,
        b1: S,
        b2: S,
        x_ref: S,
        status: &mut Status,
        ov: &mut bool,
    ) -> (S, S, S) {
        let n = self.params.n_sub;
        let mut s = S::ZERO;
        let (mut x, mut y, mut v) = (st.x, st.y, st.v);
        for k in 1..=n {
            let eta = if k == n {
                eta1
            } else {
                s = s.sadd(self.inv_n, ov);
                let quad = s.smul(b2, ov);
                eta0.sadd(s.smul(b1.sadd(quad, ov), ov), ov)
            };
            let (x1, y1, v1, sub) = self.substep::<REF>(x, y, eta, x_ref, ov);
            *status = status.union(sub);
            x = x1;
            y = y1;
            v = v1;
        }
        (x, y, v)
    }

    /// One application of Eq. 14 over a sub-step ending at gap deviation `eta`, with the
    /// reference `g0·(1 + r)` (`r = 0`: the paper's law).
    #[inline]
    fn substep<const REF: bool>(
        &self,
        x: S,
        y: S,
        eta: S,
        r: S,
        ov: &mut bool,
    ) -> (S, S, S, Status) {
        let mut status = Status::default();
        let one = S::ONE;
        // N = y − η − x·(1 + kpd + η) + kpd·r
        let factor = self.one_kpd.sadd(eta, ov);
        let mut num = y.ssub(eta, ov).ssub(x.smul(factor, ov), ov);
        if REF {
            num = num.sadd(self.kpd.smul(r, ov), ov);
        }
        // Δx = c·N / (1 + cα(1 + kph) + cα·η); fixed point division-free (Params::reciprocal).
        let dx = if S::FLOAT {
            let den = self.one_ca1.sadd(self.ca.smul(eta, ov), ov);
            self.c.smul(num, ov).sdiv(den, ov)
        } else {
            num.smul(self.cr.ssub(self.cru.smul(eta, ov), ov), ov)
        };
        let mut x1 = x.sadd(dx, ov);
        let x_floor = one.sneg(ov);
        if x1 < x_floor {
            x1 = x_floor;
            status = status.union(Status::CURRENT_CLAMPED);
        }
        // Trapezoidal integral (Eq. 12) and the voltage at the end of the sub-step (Eq. 11).
        let (y1, v1) = if REF {
            let two_r = r.sadd(r, ov);
            let y1 = y.ssub(self.kih.smul(x.sadd(x1, ov).ssub(two_r, ov), ov), ov);
            (
                y1,
                one.sadd(y1, ov).ssub(self.kpv.smul(x1.ssub(r, ov), ov), ov),
            )
        } else {
            let y1 = y.ssub(self.kih.smul(x.sadd(x1, ov), ov), ov);
            (y1, one.sadd(y1, ov).ssub(self.kpv.smul(x1, ov), ov))
        };
        let v_lim = self.v_max;
        if v1 > v_lim || v1 < v_lim.sneg(ov) {
            status = status.union(Status::VOLTAGE_SATURATED);
            let vs = if v1 > v_lim { v_lim } else { v_lim.sneg(ov) };
            // Coil alone (Eq. 9, α-method) at V = vs: Δx = c(vs − ĥĝ)/(1 + cαĥ); e_a frozen.
            let h = one.sadd(eta, ov);
            let g = one.sadd(x, ov);
            let num = vs.ssub(h.smul(g, ov), ov);
            let dx = if S::FLOAT {
                let den = one.sadd(self.ca.smul(h, ov), ov);
                self.c.smul(num, ov).sdiv(den, ov)
            } else {
                num.smul(self.crs.ssub(self.crsu.smul(eta, ov), ov), ov)
            };
            let mut xs = x.sadd(dx, ov);
            if xs < x_floor {
                xs = x_floor;
                status = status.union(Status::CURRENT_CLAMPED);
            }
            return (xs, y, vs, status);
        }
        (x1, y1, v1, status)
    }
}

/// NaN is the only value not equal to itself (fixed point has none).
#[allow(clippy::eq_op)]
fn is_nan<S: PartialEq>(x: S) -> bool {
    x != x
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_accurate;
#[cfg(test)]
mod tests_fast;
