//! Rail irregularity: a random profile `r(x)` with the paper's spectral density (Eq. 3–5,
//! Table 1), evaluated by the direct sum of its cosine terms in any [`Scalar`].
//!
//! # Why it is built this way
//!
//! The irregularity is the main disturbance the levitation loop has to reject, and the same
//! profile must be seen by the host simulators (in `f64`) and by firmware (in `f32` or fixed
//! point) so that their responses can be compared sample by sample. Therefore:
//!
//! - Every parameter is designed once in `f64` ([`PsdParams`]) and converted once per term
//!   into the run-time scalar ([`Term`]); the evaluation is then only `N` products, `N`
//!   cosines and `N` additions in `S`, all saturating, with the overflow flag handed back to
//!   the caller instead of a silent wrap.
//! - The random phases come from a small, fully specified generator (below), so a seed
//!   means the same profile on every platform and for every scalar type, to that type's
//!   precision.
//! - No allocation and no panic: the terms live in a [`heapless::Vec`] whose capacity is a
//!   const generic (default [`DEFAULT_CAPACITY`] = 2000 = Table 1's `N`); asking for more
//!   terms than fit is an [`IrregularityError`], not a panic.
//!
//! # The model (Eq. 3–5)
//!
//! ```text
//! r(x)    = Σ_{k=1..N} a_k cos(ω_k x + φ_k)                         (Eq. 3)
//! a_k     = 2 sqrt(G_rr(ω_k) Δω),  ω_k = ω_l + (k − ½) Δω,  Δω = (ω_u − ω_l)/N   (Eq. 4)
//! G_rr(ω) = A_r ω2² (ω² + ω1²) / ( ω⁴ (ω² + ω2²) )                   (Eq. 5)
//! ```
//!
//! `ω` is a spatial angular frequency in rad/m, `x` in m, `r` in m. With this `a_k` the
//! variance of the profile is `Σ a_k²/2 = 2 Σ G_rr(ω_k) Δω`, i.e. `G_rr` is a *two-sided*
//! density in m²/(rad/m); the one-sided density is `2 G_rr`.
//!
//! Terms are stored as spatial frequency in turns/m `f_k = ω_k/(2π)`, amplitude `a_k` in m
//! and phase in turns `p_k = φ_k/(2π)`, so that
//!
//! ```text
//! r(x) = Σ a_k cos_turns( fract(f_k x) + p_k )        cos_turns(t) = cos(2π t)
//! ```
//!
//! Reducing `f_k x` to its fractional turn before adding the phase keeps the argument in
//! `[0, 2)` turns, which fits every scalar type (including `I4F28`, range ±8).
//!
//! # Phases: SplitMix64, one stream per direction
//!
//! Phases are drawn with SplitMix64 (Steele, Lea, Flood 2014; the generator used to seed
//! the xoshiro family):
//!
//! ```text
//! mix(z)  = z ^= z >> 30; z *= 0xBF58_476D_1CE4_E5B9; z ^= z >> 27; z *= 0x94D0_49BB_1331_11EB; z ^ (z >> 31)
//! next()  = state += 0x9E37_79B9_7F4A_7C15; mix(state)          (all arithmetic mod 2⁶⁴)
//! ```
//!
//! For a user seed `s` and a [`Direction`] `d`, the initial state is
//! `mix(s ^ d.stream())` with the stream constants [`STREAM_Y`] = `0x6972_722D_5900_0000`
//! and [`STREAM_Z`] = `0x6972_722D_5A00_0000` (ASCII `"irr-Y"`, `"irr-Z"`). Passing the
//! seed through `mix` matters: two raw SplitMix64 states always lie on the same sequence,
//! a fixed offset apart, so seeding with `s` and `s + c` would give shifted copies of one
//! phase list. After `mix` the offset between the Y and Z streams (or between two user
//! seeds) is pseudo-random in 2⁶⁴, and the chance that two 2000-draw windows overlap is
//! about 4000/2⁶⁴. Y and Z of one seed are therefore independent draws for every practical
//! purpose. (As with any 64-bit seeding, the Z stream of seed `s ^ STREAM_Y ^ STREAM_Z` is
//! the Y stream of seed `s`.)
//!
//! Term `k` (k = 1, 2, …, N in order) consumes exactly one draw `u`, and its phase is
//! `p_k = (u >> 11) · 2⁻⁵³` turns (exact in `f64`, uniform in `[0, 1)`), i.e.
//! `φ_k = 2π p_k` uniform in `[0, 2π)`. Frequencies and amplitudes use only IEEE-754 basic
//! operations and `libm::sqrt` (correctly rounded), so the `f64` design values are
//! bit-identical on every platform.
//!
//! # Precision of the scalar types
//!
//! - `f64`: the reference. The phase `f_k x` carries a relative error of ~1e-16, i.e.
//!   ~3e-12 turns at x = 26 km: negligible.
//! - `f32`: `f_k` is rounded to 24 bits and so is the product `f_k x`; reducing it to a
//!   fractional turn cannot recover the lost bits. The phase error grows like
//!   `|x| f_k 2⁻²³` turns, ≈ 1e-4 turns (7e-4 rad) at x = 1 km and ≈ 3e-3 turns at 26 km;
//!   beyond ~100 km the phases are meaningless. On top of that micromath's `cos` has an
//!   absolute error of up to 0.002. Long runs in `f32` should re-anchor the profile near the
//!   vehicle with [`Irregularity::with_origin`] (phase shift computed in `f64`), so that the
//!   `x` passed in stays small.
//! - `I32F32`: `x` up to ±2³¹ m; each term contributes about one LSB (2.3e-10 m) of
//!   rounding, so the sum is within ~N LSB (worst case 4.7e-7 m for N = 2000).
//! - `I4F28`: range ±8, so `x` in metres does not fit beyond ±8 m: converting such an `x`
//!   (in [`Irregularity::eval_f64`]) saturates and raises the overflow flag, never wraps.
//!   Use [`Irregularity::with_origin`] to evaluate within ±8 m of an origin. Amplitudes
//!   below the LSB (3.7e-9 m) round to zero.

use core::fmt;

use heapless::Vec;

use crate::scalar::Scalar;

/// Default number of terms a generator can hold: Table 1's `N`.
pub const DEFAULT_CAPACITY: usize = 2000;

/// Stream constant of the Y (lateral) profile: ASCII `"irr-Y"`. See the module docs.
pub const STREAM_Y: u64 = 0x6972_722D_5900_0000;
/// Stream constant of the Z (vertical) profile: ASCII `"irr-Z"`. See the module docs.
pub const STREAM_Z: u64 = 0x6972_722D_5A00_0000;

const TWO_PI: f64 = 2.0 * core::f64::consts::PI;

/// Which rail profile: Y (guidance, lateral) or Z (levitation, vertical). Selects the
/// Table 1 parameters and the random stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Direction {
    /// Lateral (guidance) irregularity.
    Y,
    /// Vertical (levitation) irregularity.
    Z,
}

impl Direction {
    /// The stream constant XORed into the seed ([`STREAM_Y`] or [`STREAM_Z`]).
    pub const fn stream(self) -> u64 {
        match self {
            Direction::Y => STREAM_Y,
            Direction::Z => STREAM_Z,
        }
    }
}

/// Which parameter of [`PsdParams`] an error is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Param {
    /// `A_r`
    Ar,
    /// `ω1`
    Omega1,
    /// `ω2`
    Omega2,
    /// `ω_l`
    OmegaL,
    /// `ω_u`
    OmegaU,
}

/// Which stored quantity of a [`Term`] did not fit the scalar type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Quantity {
    /// Spatial frequency `f_k` in turns/m.
    Frequency,
    /// Amplitude `a_k` in m.
    Amplitude,
    /// Phase `p_k` in turns.
    Phase,
}

/// Why a profile cannot be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum IrregularityError {
    /// `N = 0`.
    ZeroTerms,
    /// `N` exceeds the generator's const-generic capacity.
    TooManyTerms {
        /// Requested number of terms.
        n: usize,
        /// The generator's capacity.
        capacity: usize,
    },
    /// A parameter is NaN or infinite.
    NonFinite(Param),
    /// `A_r < 0`.
    NegativeAr,
    /// `ω1 < 0`.
    NegativeOmega1,
    /// `ω2 ≤ 0`.
    NonPositiveOmega2,
    /// `ω_l ≤ 0` (`G_rr` has a pole at ω = 0).
    NonPositiveOmegaL,
    /// `ω_u ≤ ω_l`.
    EmptyBand,
    /// The origin given to [`Irregularity::with_origin`] is NaN or infinite.
    NonFiniteOrigin,
    /// The amplitude of term `k` (1-based) is not finite (parameters too extreme).
    NonFiniteAmplitude {
        /// 1-based term index.
        k: usize,
    },
    /// A term's quantity does not fit the scalar type.
    DoesNotFit {
        /// Which quantity.
        quantity: Quantity,
        /// 1-based term index.
        k: usize,
    },
}

impl fmt::Display for IrregularityError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use IrregularityError::*;
        match *self {
            ZeroTerms => write!(f, "number of terms N must be at least 1"),
            TooManyTerms { n, capacity } => {
                write!(f, "number of terms N = {n} exceeds the capacity {capacity}")
            }
            NonFinite(p) => write!(f, "parameter {} is not finite", param_name(p)),
            NegativeAr => write!(f, "A_r must not be negative"),
            NegativeOmega1 => write!(f, "omega1 must not be negative"),
            NonPositiveOmega2 => write!(f, "omega2 must be positive"),
            NonPositiveOmegaL => write!(f, "omega_l must be positive (G_rr has a pole at 0)"),
            EmptyBand => write!(f, "omega_u must be greater than omega_l"),
            NonFiniteOrigin => write!(f, "origin is not finite"),
            NonFiniteAmplitude { k } => write!(f, "amplitude of term {k} is not finite"),
            DoesNotFit { quantity, k } => {
                let q = match quantity {
                    Quantity::Frequency => "frequency",
                    Quantity::Amplitude => "amplitude",
                    Quantity::Phase => "phase",
                };
                write!(f, "{q} of term {k} does not fit the scalar type")
            }
        }
    }
}

fn param_name(p: Param) -> &'static str {
    match p {
        Param::Ar => "A_r",
        Param::Omega1 => "omega1",
        Param::Omega2 => "omega2",
        Param::OmegaL => "omega_l",
        Param::OmegaU => "omega_u",
    }
}

/// Parameters of the spectral density and its discretisation (Eq. 4–5, Table 1), in SI
/// units with ω in rad/m.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PsdParams {
    /// Roughness coefficient `A_r`, m²·rad/m.
    pub a_r: f64,
    /// Corner frequency `ω1`, rad/m.
    pub omega1: f64,
    /// Corner frequency `ω2`, rad/m.
    pub omega2: f64,
    /// Lower end of the band `ω_l`, rad/m.
    pub omega_l: f64,
    /// Upper end of the band `ω_u`, rad/m.
    pub omega_u: f64,
    /// Number of terms `N`.
    pub n: usize,
}

// Table 1 prints ω_u = 6.28 rad/m, not 2π: keep the paper's value.
#[allow(clippy::approx_constant)]
impl PsdParams {
    /// Table 1, Y direction.
    pub const TABLE1_Y: Self = Self {
        a_r: 0.4e-7,
        omega1: 0.0,
        omega2: 0.8245,
        omega_l: 0.1,
        omega_u: 6.28,
        n: 2000,
    };
    /// Table 1, Z direction.
    pub const TABLE1_Z: Self = Self {
        a_r: 0.8e-7,
        omega1: 0.0,
        omega2: 0.8245,
        omega_l: 0.1,
        omega_u: 6.28,
        n: 2000,
    };

    /// Table 1 parameters for a direction.
    pub const fn table1(direction: Direction) -> Self {
        match direction {
            Direction::Y => Self::TABLE1_Y,
            Direction::Z => Self::TABLE1_Z,
        }
    }

    /// Check the parameters (not the capacity; see [`Irregularity::new`]).
    pub fn validate(&self) -> Result<(), IrregularityError> {
        use IrregularityError::*;
        let named = [
            (self.a_r, Param::Ar),
            (self.omega1, Param::Omega1),
            (self.omega2, Param::Omega2),
            (self.omega_l, Param::OmegaL),
            (self.omega_u, Param::OmegaU),
        ];
        for (v, p) in named {
            if !v.is_finite() {
                return Err(NonFinite(p));
            }
        }
        if self.n == 0 {
            return Err(ZeroTerms);
        }
        if self.a_r < 0.0 {
            return Err(NegativeAr);
        }
        if self.omega1 < 0.0 {
            return Err(NegativeOmega1);
        }
        if self.omega2 <= 0.0 {
            return Err(NonPositiveOmega2);
        }
        if self.omega_l <= 0.0 {
            return Err(NonPositiveOmegaL);
        }
        if self.omega_u <= self.omega_l {
            return Err(EmptyBand);
        }
        Ok(())
    }

    /// `G_rr(ω)` (Eq. 5), two-sided density in m²/(rad/m), ω in rad/m. Not meaningful for
    /// ω = 0 (pole) or invalid parameters; never panics.
    pub fn psd(&self, omega: f64) -> f64 {
        let w2 = omega * omega;
        let o2 = self.omega2 * self.omega2;
        self.a_r * o2 * (w2 + self.omega1 * self.omega1) / (w2 * w2 * (w2 + o2))
    }

    /// `Δω = (ω_u − ω_l)/N` (Eq. 4), rad/m. Zero if `N = 0`.
    pub fn delta_omega(&self) -> f64 {
        if self.n == 0 {
            0.0
        } else {
            (self.omega_u - self.omega_l) / self.n as f64
        }
    }

    /// `ω_k = ω_l + (k − ½) Δω` (Eq. 4), rad/m, for k = 1..=N.
    pub fn omega_k(&self, k: usize) -> f64 {
        self.omega_l + (k as f64 - 0.5) * self.delta_omega()
    }

    /// `a_k = 2 sqrt(G_rr(ω_k) Δω)` (Eq. 4), m, for k = 1..=N.
    pub fn amplitude(&self, k: usize) -> f64 {
        2.0 * libm::sqrt(self.psd(self.omega_k(k)) * self.delta_omega())
    }

    /// Variance of the profile, `Σ a_k²/2` in m² (Eq. 3 with independent uniform phases).
    pub fn variance(&self) -> f64 {
        let mut v = 0.0;
        for k in 1..=self.n {
            let a = self.amplitude(k);
            v += 0.5 * a * a;
        }
        v
    }
}

/// SplitMix64, the phase generator specified in the module docs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    const GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

    /// A generator with the given raw state (the reference SplitMix64 seeding).
    pub const fn new(state: u64) -> Self {
        Self { state }
    }

    /// The generator of a profile: initial state `mix(seed ^ direction.stream())`.
    pub const fn for_profile(seed: u64, direction: Direction) -> Self {
        Self::new(Self::mix(seed ^ direction.stream()))
    }

    /// SplitMix64's output function (a bijection on u64).
    pub const fn mix(mut z: u64) -> u64 {
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Next 64-bit output.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(Self::GAMMA);
        Self::mix(self.state)
    }

    /// Next value uniform in `[0, 1)`: `(next >> 11) · 2⁻⁵³`, exact in `f64`.
    pub fn next_unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// One cosine term of Eq. 3, in the run-time scalar.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Term<S> {
    /// Spatial frequency `f_k = ω_k/(2π)`, turns/m.
    pub freq: S,
    /// Amplitude `a_k`, m.
    pub amp: S,
    /// Phase `p_k = φ_k/(2π)`, turns, in `[0, 1)`.
    pub phase: S,
}

/// A rail irregularity profile `r(x)` (Eq. 3) with up to `CAP` terms in scalar `S`.
#[derive(Clone, Debug)]
pub struct Irregularity<S: Scalar, const CAP: usize = DEFAULT_CAPACITY> {
    terms: Vec<Term<S>, CAP>,
}

impl<S: Scalar, const CAP: usize> Default for Irregularity<S, CAP> {
    fn default() -> Self {
        Self::empty()
    }
}

impl<S: Scalar, const CAP: usize> Irregularity<S, CAP> {
    /// A profile with no terms (`r ≡ 0`); fill it in place with [`Self::rebuild`] (e.g. in a
    /// `static`, to keep the terms off the stack).
    pub const fn empty() -> Self {
        Self { terms: Vec::new() }
    }

    /// The profile of `params` for `direction` and `seed` (phases as in the module docs).
    pub fn new(
        params: &PsdParams,
        direction: Direction,
        seed: u64,
    ) -> Result<Self, IrregularityError> {
        Self::with_origin(params, direction, seed, 0.0)
    }

    /// The same profile as [`Self::new`], shifted so that evaluating at `ξ` gives
    /// `r(origin + ξ)`. The shift `fract(f_k · origin)` is folded into each phase in `f64`,
    /// so a short-range type (`f32`, `I4F28`) can evaluate far along the track with a small
    /// `ξ`. A non-finite `origin` is [`IrregularityError::NonFiniteOrigin`].
    pub fn with_origin(
        params: &PsdParams,
        direction: Direction,
        seed: u64,
        origin: f64,
    ) -> Result<Self, IrregularityError> {
        let mut s = Self::empty();
        s.rebuild(params, direction, seed, origin)?;
        Ok(s)
    }

    /// Rebuild in place (see [`Self::with_origin`]). On error the profile is left empty.
    pub fn rebuild(
        &mut self,
        params: &PsdParams,
        direction: Direction,
        seed: u64,
        origin: f64,
    ) -> Result<(), IrregularityError> {
        self.terms.clear();
        params.validate()?;
        if params.n > CAP {
            return Err(IrregularityError::TooManyTerms {
                n: params.n,
                capacity: CAP,
            });
        }
        if !origin.is_finite() {
            return Err(IrregularityError::NonFiniteOrigin);
        }
        let mut rng = SplitMix64::for_profile(seed, direction);
        for k in 1..=params.n {
            // One draw per term, always, so the phases do not depend on the origin or S.
            let p = rng.next_unit();
            match design_term::<S>(params, k, p, origin) {
                Ok(t) => {
                    // Cannot fail: n <= CAP was checked above.
                    let _ = self.terms.push(t);
                }
                Err(e) => {
                    self.terms.clear();
                    return Err(e);
                }
            }
        }
        Ok(())
    }

    /// The stored terms, in order k = 1..=N.
    pub fn terms(&self) -> &[Term<S>] {
        &self.terms
    }

    /// `r(x)` in m by the direct sum `Σ a_k cos_turns(fract(f_k x) + p_k)` (Eq. 3), `x` in m.
    /// Saturating; any overflow raises `overflow` (sticky).
    pub fn eval(&self, x: S, overflow: &mut bool) -> S {
        let mut acc = S::ZERO;
        for t in self.terms.iter() {
            let turn = t.freq.smul(x, overflow).fract().sadd(t.phase, overflow);
            acc = acc.sadd(t.amp.smul(turn.cos_turns(overflow), overflow), overflow);
        }
        acc
    }

    /// [`Self::eval`] with `x` given in `f64` metres; an `x` outside the scalar's range (e.g.
    /// beyond ±8 m in `I4F28`) saturates and raises `overflow`.
    pub fn eval_f64(&self, x: f64, overflow: &mut bool) -> S {
        let xs = S::from_f64(x, overflow);
        self.eval(xs, overflow)
    }
}

/// Term `k` (1-based) designed in `f64` with phase `p` turns, shifted to `origin`, then
/// converted once to `S`.
fn design_term<S: Scalar>(
    params: &PsdParams,
    k: usize,
    p: f64,
    origin: f64,
) -> Result<Term<S>, IrregularityError> {
    let f = params.omega_k(k) / TWO_PI;
    let a = params.amplitude(k);
    if !a.is_finite() {
        return Err(IrregularityError::NonFiniteAmplitude { k });
    }
    let phase = if origin == 0.0 {
        p
    } else {
        fract_f64(p + fract_f64(f * origin))
    };
    let conv = |v: f64, quantity: Quantity| {
        let mut ov = false;
        let s = S::from_f64(v, &mut ov);
        if ov || !v.is_finite() {
            Err(IrregularityError::DoesNotFit { quantity, k })
        } else {
            Ok(s)
        }
    };
    Ok(Term {
        freq: conv(f, Quantity::Frequency)?,
        amp: conv(a, Quantity::Amplitude)?,
        phase: conv(phase, Quantity::Phase)?,
    })
}

/// `v − floor(v)` in `[0, 1)` for finite `v`; NaN/inf pass through (caught by the caller).
fn fract_f64(v: f64) -> f64 {
    let r = v - libm::floor(v);
    if r >= 1.0 {
        0.0
    } else {
        r
    }
}

#[cfg(test)]
#[allow(clippy::approx_constant)] // 6.28 is Table 1's ω_u, not 2π
mod tests {
    extern crate std;
    use super::*;
    use crate::scalar::{I32F32, I4F28};
    use std::println;

    const Y: PsdParams = PsdParams::TABLE1_Y;
    const Z: PsdParams = PsdParams::TABLE1_Z;

    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    #[test]
    fn psd_hand_values() {
        // Hand computation with ω1 = 0: G = A_r ω2² / (ω² (ω² + ω2²)), ω2² = 0.67980025.
        // ω = 1: 0.8e-7 · 0.67980025 / 1.67980025 = 3.2375289859612e-8
        assert!(rel(Z.psd(1.0), 3.237_528_985_961_2e-8) < 1e-12);
        // ω = 0.1: 0.8e-7 · 0.67980025 / (1e-2 · 0.68980025) = 7.884024396917e-6
        assert!(rel(Z.psd(0.1), 7.884_024_396_917_8e-6) < 1e-12);
        // ω = 6.28: 0.8e-7 · 0.67980025 / (39.4384 · 40.11820025) = 3.437245702569e-11
        assert!(rel(Z.psd(6.28), 3.437_245_702_569e-11) < 1e-12);
        // Y has half of Z's A_r.
        assert!(rel(Y.psd(1.0), 0.5 * 3.237_528_985_961_2e-8) < 1e-12);
        // Non-zero ω1: A_r = 0.4e-7, ω1 = 0.5, ω = 2:
        // 0.4e-7 · 0.67980025 · 4.25 / (16 · 4.67980025) = 1.5434158020420e-9
        let p = PsdParams {
            a_r: 0.4e-7,
            omega1: 0.5,
            ..Z
        };
        assert!(rel(p.psd(2.0), 1.543_415_802_042e-9) < 1e-12);
    }

    #[test]
    fn amplitudes_and_terms() {
        // Δω = 6.18/2000 = 3.09e-3; ω_1 = 0.1 + 1.545e-3 = 0.101545;
        // a_1 = 2 sqrt(G(0.101545) · 3.09e-3) = 3.073453660751e-4 m (hand/calculator).
        assert!(rel(Z.delta_omega(), 3.09e-3) < 1e-14);
        assert!(rel(Z.omega_k(1), 0.101_545) < 1e-14);
        assert!(rel(Z.omega_k(2000), 6.28 - 1.545e-3) < 1e-14);
        assert!(rel(Z.amplitude(1), 3.073_453_660_751e-4) < 1e-11);
        // Y's amplitudes are Z's over sqrt(2).
        assert!(rel(Y.amplitude(7) * core::f64::consts::SQRT_2, Z.amplitude(7)) < 1e-14);
        let g = Irregularity::<f64>::new(&Z, Direction::Z, 3).unwrap();
        assert_eq!(g.terms().len(), 2000);
        for (i, t) in g.terms().iter().enumerate() {
            let k = i + 1;
            assert_eq!(t.amp, Z.amplitude(k));
            assert_eq!(t.freq, Z.omega_k(k) / TWO_PI);
            assert!((0.0..1.0).contains(&t.phase));
        }
    }

    #[test]
    fn splitmix64_reference_outputs() {
        // Reference SplitMix64 (Vigna's splitmix64.c) from state 0.
        let mut r = SplitMix64::new(0);
        assert_eq!(r.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(r.next_u64(), 0x6E78_9E6A_A1B9_65F4);
        assert_eq!(r.next_u64(), 0x06C4_5D18_8009_454F);
        // Phase k = 1 of seed s, direction d is (next >> 11)·2⁻⁵³ of mix(s ^ stream).
        let mut r = SplitMix64::new(SplitMix64::mix(42 ^ STREAM_Y));
        let u = r.next_u64();
        let g = Irregularity::<f64>::new(&Y, Direction::Y, 42).unwrap();
        assert_eq!(
            g.terms()[0].phase,
            (u >> 11) as f64 / 9_007_199_254_740_992.0
        );
    }

    /// Variance identity: Σ a_k²/2 = 2 Σ G(ω_k) Δω is the midpoint rule for 2∫G dω, whose
    /// closed form for ω1 = 0 is 2 A_r [1/ω_l − 1/ω_u − (atan(ω_u/ω2) − atan(ω_l/ω2))/ω2].
    /// Midpoint error per cell ≤ Δω³/24·max|G''| with |G''| ≤ 12 A_r/ω⁴ (each of the two
    /// partial fractions A_r/ω² and A_r/(ω²+ω2²) has |second derivative| ≤ 6 A_r/ω⁴), summed
    /// ≤ 2·(Δω²/24)·12 A_r/(3 (ω_l − Δω)³).
    #[test]
    fn variance_matches_closed_form() {
        for p in [Y, Z] {
            let g = Irregularity::<f64>::new(&p, Direction::Z, 9).unwrap();
            let v_terms: f64 = g.terms().iter().map(|t| 0.5 * t.amp * t.amp).sum();
            assert!(rel(v_terms, p.variance()) < 1e-13);
            let (wl, wu, w2, dw) = (p.omega_l, p.omega_u, p.omega2, p.delta_omega());
            let exact = 2.0
                * p.a_r
                * (1.0 / wl - 1.0 / wu - (libm::atan(wu / w2) - libm::atan(wl / w2)) / w2);
            let bound =
                2.0 * (dw * dw / 24.0) * 12.0 * p.a_r / (3.0 * (wl - dw) * (wl - dw) * (wl - dw));
            println!(
                "variance: terms {:.6e} closed form {:.6e} diff {:.2e} bound {:.2e}; rms {:.4e} m",
                v_terms,
                exact,
                (v_terms - exact).abs(),
                bound,
                libm::sqrt(v_terms)
            );
            assert!((v_terms - exact).abs() <= bound);
        }
    }

    /// The mean square of a sampled profile estimates Σ a_k²/2. Under the model (independent
    /// uniform phases, fixed a_k) the estimator m = (1/J) Σ_j r(x_j)² has mean Σ a_k²/2 and,
    /// expanding r² into cosines of 2θ_k, θ_k − θ_l and θ_k + θ_l (mutually uncorrelated),
    /// variance  Σ_k (a_k²/2)²·|D(2ω_k)|²/2 + Σ_{k<l} (a_k a_l)²·(|D(ω_k−ω_l)|² + |D(ω_k+ω_l)|²)/2,
    /// with D(δ) = (1/J) Σ_j e^{iδ x_j} (a Dirichlet kernel). The test allows 5 σ
    /// (two-sided Gaussian tail 6e-7; even Chebyshev gives ≤ 4 %).
    #[test]
    fn sampled_rms_matches() {
        let p = Z;
        let g = Irregularity::<f64>::new(&p, Direction::Z, 2024).unwrap();
        // dx = 0.37 m keeps 2ω_u = 12.56 rad/m below 2π/dx = 16.98 rad/m (no aliasing of the
        // squared profile), J·dx = 18.5 km.
        let (dx, jn) = (0.37, 50_000usize);
        let mut ov = false;
        let mut m = 0.0;
        for j in 0..jn {
            let r = g.eval(j as f64 * dx, &mut ov);
            m += r * r;
        }
        assert!(!ov);
        m /= jn as f64;
        let d2 = |delta: f64| {
            let h = 0.5 * delta * dx;
            let den = jn as f64 * libm::sin(h);
            if den.abs() < 1e-300 {
                1.0
            } else {
                let v = libm::sin(jn as f64 * h) / den;
                v * v
            }
        };
        let a: std::vec::Vec<f64> = g.terms().iter().map(|t| t.amp).collect();
        let w: std::vec::Vec<f64> = (1..=p.n).map(|k| p.omega_k(k)).collect();
        let mut var = 0.0;
        for k in 0..a.len() {
            var += (0.5 * a[k] * a[k]).powi(2) * d2(2.0 * w[k]) / 2.0;
            for l in k + 1..a.len() {
                var += (a[k] * a[l]).powi(2) * (d2(w[k] - w[l]) + d2(w[k] + w[l])) / 2.0;
            }
        }
        let sigma = libm::sqrt(var);
        let expect = p.variance();
        println!(
            "sampled mean square {:.6e} expected {:.6e} (rel {:+.4}), model sigma {:.3e} (rel {:.4}), rms {:.4e} vs {:.4e}",
            m,
            expect,
            (m - expect) / expect,
            sigma,
            sigma / expect,
            libm::sqrt(m),
            libm::sqrt(expect)
        );
        assert!((m - expect).abs() <= 5.0 * sigma);
    }

    #[test]
    fn same_seed_bit_identical_different_seed_or_direction_differs() {
        let a = Irregularity::<f64>::new(&Z, Direction::Z, 7).unwrap();
        let b = Irregularity::<f64>::new(&Z, Direction::Z, 7).unwrap();
        let c = Irregularity::<f64>::new(&Z, Direction::Z, 8).unwrap();
        let d = Irregularity::<f64>::new(&Z, Direction::Y, 7).unwrap();
        let mut ov = false;
        let mut diff_c = 0;
        let mut diff_d = 0;
        for i in 0..200 {
            let x = i as f64 * 1.37 - 50.0;
            let (ra, rb) = (a.eval(x, &mut ov), b.eval(x, &mut ov));
            assert_eq!(ra.to_bits(), rb.to_bits());
            diff_c += (c.eval(x, &mut ov) != ra) as usize;
            diff_d += (d.eval(x, &mut ov) != ra) as usize;
        }
        assert!(!ov);
        assert_eq!((diff_c, diff_d), (200, 200));
        // The phases are the same f64 values in every scalar type (rounded to its precision).
        let f = Irregularity::<f32>::new(&Z, Direction::Z, 7).unwrap();
        let q = Irregularity::<I32F32>::new(&Z, Direction::Z, 7).unwrap();
        for k in 0..2000 {
            assert_eq!(f.terms()[k].phase, a.terms()[k].phase as f32);
            let mut o = false;
            assert_eq!(
                q.terms()[k].phase,
                I32F32::from_f64(a.terms()[k].phase, &mut o)
            );
        }
    }

    /// Phases are uniform on [0, 1) turns and Y, Z streams uncorrelated: sample mean within
    /// 5 σ of ½ (σ = sqrt(1/12/N)), correlation of Y and Z phases within 5/sqrt(N).
    #[test]
    fn phases_uniform_and_directions_independent() {
        for seed in [0u64, 1, 0xDEAD_BEEF] {
            let y = Irregularity::<f64>::new(&Y, Direction::Y, seed).unwrap();
            let z = Irregularity::<f64>::new(&Y, Direction::Z, seed).unwrap();
            let n = 2000.0;
            let (mut my, mut mz, mut syz, mut syy, mut szz) = (0.0, 0.0, 0.0, 0.0, 0.0);
            for (a, b) in y.terms().iter().zip(z.terms()) {
                my += a.phase;
                mz += b.phase;
            }
            my /= n;
            mz /= n;
            for (a, b) in y.terms().iter().zip(z.terms()) {
                syz += (a.phase - my) * (b.phase - mz);
                syy += (a.phase - my) * (a.phase - my);
                szz += (b.phase - mz) * (b.phase - mz);
            }
            let sigma = libm::sqrt(1.0 / 12.0 / n);
            assert!((my - 0.5).abs() < 5.0 * sigma && (mz - 0.5).abs() < 5.0 * sigma);
            let rho = syz / libm::sqrt(syy * szz);
            assert!(rho.abs() < 5.0 / libm::sqrt(n), "rho {rho}");
        }
    }

    /// Worst-case error bound of the evaluation in a scalar with unit roundoff `u` (half an
    /// LSB for fixed point, 2⁻²⁴ for f32), relative to the f64 sum, at x (x itself exactly
    /// representable in the test). Per term: the turn argument is off by
    /// |x|·δf + δ(f·x) + δ(+p) + δp, the cosine by 2π·that plus the cosine's own error
    /// `cos_err`; the product a·cos and the stored a add `prod_err(a)`; the additions add
    /// `add_err` each (0 for fixed point, whose additions are exact).
    fn budget(
        g: &Irregularity<f64>,
        x: f64,
        turn_err: impl Fn(f64) -> f64,
        cos_err: f64,
        prod_err: impl Fn(f64) -> f64,
        add_err: f64,
    ) -> f64 {
        let sum_a: f64 = g.terms().iter().map(|t| t.amp).sum();
        g.terms()
            .iter()
            .map(|t| t.amp * (TWO_PI * turn_err(t.freq * x.abs()) + cos_err) + prod_err(t.amp))
            .sum::<f64>()
            + g.terms().len() as f64 * add_err * sum_a
    }

    fn max_err<S: Scalar>(
        r: &Irregularity<f64>,
        g: &Irregularity<S>,
        xs: &[f64],
        bud: impl Fn(f64) -> f64,
    ) -> (f64, f64) {
        let mut worst = 0.0f64;
        let mut worst_frac = 0.0f64;
        for &x in xs {
            let mut ov = false;
            let want = r.eval(x, &mut ov);
            let got = g.eval_f64(x, &mut ov).to_f64();
            assert!(!ov, "{} x={x}", S::NAME);
            let e = (got - want).abs();
            let b = bud(x);
            assert!(e <= b, "{} x={x}: error {e:e} > budget {b:e}", S::NAME);
            worst = worst.max(e);
            worst_frac = worst_frac.max(e / b);
        }
        (worst, worst_frac)
    }

    #[test]
    fn reduced_precision_types_within_budget() {
        let r = Irregularity::<f64>::new(&Z, Direction::Z, 11).unwrap();
        let rms = libm::sqrt(Z.variance());
        // x values exactly representable in f32 and in fixed point (multiples of 1/64 m).
        let xs: std::vec::Vec<f64> = (0..120).map(|i| (i * i) as f64 * 0.078125 - 3.0).collect();

        // f32: unit roundoff u = 2⁻²⁴. δf ≤ f u, δ(f x) ≤ f x u, fract exact, + p ≤ u (result
        // < 2), δp ≤ u/2; cos_turns: micromath's documented 0.002 plus the 2π scaling
        // (3 u on an angle ≤ π: 3πu); a·cos: 2 a u; additions: ≤ u · Σ a_k each.
        let u = f32::EPSILON as f64 / 2.0;
        let f32g = Irregularity::<f32>::new(&Z, Direction::Z, 11).unwrap();
        let (w, frac) = max_err(&r, &f32g, &xs, |x| {
            budget(
                &r,
                x,
                |fx| 2.0 * fx * u + 1.5 * u,
                0.002 + 3.0 * core::f64::consts::PI * u,
                |a| 2.0 * a * u,
                u,
            )
        });
        println!(
            "f32: max error {w:.3e} m ({:.2e} of rms), worst error/budget {frac:.3}",
            w / rms
        );

        // I32F32: LSB q = 2⁻³², unit roundoff q/2 (absolute). δf, δp ≤ q/2, δ(f x) ≤ q/2,
        // + p exact; cos_turns_generic ≤ 2e-9 (its tested accuracy); a·cos: δa + q/2 ≤ q;
        // additions exact.
        let q = I32F32::RESOLUTION;
        let fixg = Irregularity::<I32F32>::new(&Z, Direction::Z, 11).unwrap();
        let (w, frac) = max_err(&r, &fixg, &xs, |x| {
            budget(&r, x, |_| 0.5 * q * (x.abs() + 2.0), 2e-9, |_| q, 0.0)
        });
        println!(
            "I32F32: max error {w:.3e} m ({:.2e} of rms), worst error/budget {frac:.3}",
            w / rms
        );
        // A point far along the track (2²⁰ m ≈ 1049 km) still fits I32F32.
        let _ = max_err(&r, &fixg, &[1_048_576.0 + 0.25], |x| {
            budget(&r, x, |_| 0.5 * q * (x.abs() + 2.0), 2e-9, |_| q, 0.0)
        });

        // I4F28 within ±8 m: LSB 2⁻²⁸, cos_turns_generic ≤ 3e-8 (its tested accuracy).
        let q = I4F28::RESOLUTION;
        let small: std::vec::Vec<f64> = (0..64).map(|i| i as f64 * 0.234375 - 7.5).collect();
        let i4 = Irregularity::<I4F28>::new(&Z, Direction::Z, 11).unwrap();
        let (w, frac) = max_err(&r, &i4, &small, |x| {
            budget(&r, x, |_| 0.5 * q * (x.abs() + 2.0), 3e-8, |_| q, 0.0)
        });
        println!(
            "I4F28 (|x| < 8 m): max error {w:.3e} m ({:.2e} of rms), worst error/budget {frac:.3}",
            w / rms
        );
    }

    #[test]
    fn fixed_point_x_out_of_range_flags_and_origin_shift_works() {
        let i4 = Irregularity::<I4F28>::new(&Z, Direction::Z, 5).unwrap();
        let mut ov = false;
        let _ = i4.eval_f64(7.9, &mut ov);
        assert!(!ov);
        let _ = i4.eval_f64(10.0, &mut ov);
        assert!(ov, "x = 10 m does not fit I4F28: the flag must be raised");
        let mut ov = false;
        let _ = i4.eval_f64(f64::NAN, &mut ov);
        assert!(ov);

        // Shifted generators reproduce the profile far along the track.
        let r = Irregularity::<f64>::new(&Z, Direction::Z, 5).unwrap();
        let origin = 12_345.5;
        let r0 = Irregularity::<f64>::with_origin(&Z, Direction::Z, 5, origin).unwrap();
        let i40 = Irregularity::<I4F28>::with_origin(&Z, Direction::Z, 5, origin).unwrap();
        let f320 = Irregularity::<f32>::with_origin(&Z, Direction::Z, 5, origin).unwrap();
        let sum_a: f64 = r.terms().iter().map(|t| t.amp).sum();
        let mut ov = false;
        for i in 0..40 {
            let xi = i as f64 * 0.375 - 7.0;
            let want = r.eval(origin + xi, &mut ov);
            // f64: the phase shift is exact up to ~|f·origin|·2⁻⁵³ ≈ 1.4e-12 turns per term.
            assert!((r0.eval(xi, &mut ov) - want).abs() <= 1e-10 * sum_a);
            // Same per-term error model as `reduced_precision_types_within_budget`, |ξ| < 8.
            let q = I4F28::RESOLUTION;
            let b = budget(
                &r,
                xi,
                |_| 0.5 * q * (xi.abs() + 2.0) + 1e-11,
                3e-8,
                |_| q,
                0.0,
            );
            assert!((i40.eval_f64(xi, &mut ov).to_f64() - want).abs() <= b);
            let u = f32::EPSILON as f64 / 2.0;
            let b = budget(
                &r,
                xi,
                |fx| 2.0 * fx * u + 1.5 * u + 1e-11,
                0.002 + 3.0 * core::f64::consts::PI * u,
                |a| 2.0 * a * u,
                u,
            );
            assert!((f320.eval_f64(xi, &mut ov).to_f64() - want).abs() <= b);
        }
        assert!(!ov);
    }

    #[test]
    fn errors_name_the_problem() {
        use IrregularityError as E;
        let new = |p: PsdParams| Irregularity::<f64>::new(&p, Direction::Z, 0).err();
        assert_eq!(new(PsdParams { n: 0, ..Z }), Some(E::ZeroTerms));
        assert_eq!(
            new(PsdParams { n: 2001, ..Z }),
            Some(E::TooManyTerms {
                n: 2001,
                capacity: 2000
            })
        );
        assert_eq!(
            Irregularity::<f64, 16>::new(&Z, Direction::Z, 0).err(),
            Some(E::TooManyTerms {
                n: 2000,
                capacity: 16
            })
        );
        assert!(Irregularity::<f64, 16>::new(&PsdParams { n: 16, ..Z }, Direction::Z, 0).is_ok());
        assert_eq!(new(PsdParams { omega_u: 0.1, ..Z }), Some(E::EmptyBand));
        assert_eq!(new(PsdParams { omega_u: 0.05, ..Z }), Some(E::EmptyBand));
        assert_eq!(new(PsdParams { a_r: -1e-7, ..Z }), Some(E::NegativeAr));
        assert_eq!(
            new(PsdParams { a_r: f64::NAN, ..Z }),
            Some(E::NonFinite(Param::Ar))
        );
        assert_eq!(
            new(PsdParams {
                omega_u: f64::INFINITY,
                ..Z
            }),
            Some(E::NonFinite(Param::OmegaU))
        );
        assert_eq!(
            new(PsdParams { omega1: -0.1, ..Z }),
            Some(E::NegativeOmega1)
        );
        assert_eq!(
            new(PsdParams { omega2: 0.0, ..Z }),
            Some(E::NonPositiveOmega2)
        );
        assert_eq!(
            new(PsdParams { omega_l: 0.0, ..Z }),
            Some(E::NonPositiveOmegaL)
        );
        assert_eq!(
            new(PsdParams {
                omega_l: 1e-300,
                omega_u: 2e-300,
                n: 1,
                ..Z
            }),
            Some(E::NonFiniteAmplitude { k: 1 })
        );
        assert_eq!(
            Irregularity::<f64>::with_origin(&Z, Direction::Z, 0, f64::INFINITY).err(),
            Some(E::NonFiniteOrigin)
        );
        // ω_u = 100 rad/m is 15.9 turns/m, beyond I4F28's ±8.
        let wide = PsdParams {
            omega_u: 100.0,
            ..Z
        };
        match Irregularity::<I4F28>::new(&wide, Direction::Z, 0).err() {
            Some(E::DoesNotFit {
                quantity: Quantity::Frequency,
                k,
            }) => {
                assert!(wide.omega_k(k) / TWO_PI >= 8.0 - I4F28::RESOLUTION);
                assert!(wide.omega_k(k - 1) / TWO_PI < 8.0);
            }
            other => panic!("{other:?}"),
        }
        // A failed rebuild leaves an empty (r ≡ 0) profile, not a half-built one.
        let mut g = Irregularity::<f64>::new(&Z, Direction::Z, 0).unwrap();
        assert!(g
            .rebuild(&PsdParams { n: 0, ..Z }, Direction::Z, 0, 0.0)
            .is_err());
        assert!(g.terms().is_empty());
        // Display is one line naming the problem.
        let msg = std::format!(
            "{}",
            E::TooManyTerms {
                n: 5000,
                capacity: 2000
            }
        );
        assert!(msg.contains("5000") && msg.contains("2000") && !msg.contains('\n'));
    }
}
