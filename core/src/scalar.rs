//! The run-time number types the controller and the irregularity generator are generic over.
//!
//! Why a trait of our own: the core must run on an FPU-less Cortex-M0 in fixed point as well
//! as in `f32`/`f64`, and fixed point must never wrap silently (`fixed`'s `*` and `/` wrap in
//! release builds). Every operation here therefore *saturates* at the type's range and raises
//! a sticky overflow flag that the caller owns (`&mut bool`), much as NaN propagates in
//! floats. Floats follow the same contract: a non-finite result is clamped to the largest
//! finite value (NaN to zero) and flagged, so no NaN or infinity ever leaves the core.
//!
//! Parameters are designed in `f64` and converted once with [`Scalar::from_f64`]; see
//! [`crate::levitation::Params::compile`].
//!
//! Implemented for `f32`, `f64`, [`I32F32`] (64-bit, 32 fractional bits) and [`I4F28`]
//! (32-bit, 28 fractional bits: range ±8 with a resolution of 3.7e-9, meant for per-unit
//! quantities on 32-bit cores without an FPU). Fixed-point products and quotients are
//! computed in a double-width integer and rounded to nearest (ties towards +∞), so results
//! are bit-identical on every platform.

use core::fmt::Debug;

pub use fixed::types::{I32F32, I4F28};

/// A number the core computes with. See the module docs for the saturation contract.
pub trait Scalar: Copy + PartialOrd + PartialEq + Default + Debug + 'static {
    /// Short name used on the command line and in reports (`f64`, `f32`, `i32f32`, `i4f28`).
    const NAME: &'static str;
    /// Additive identity.
    const ZERO: Self;
    /// Multiplicative identity.
    const ONE: Self;
    /// Spacing of representable values around 1.0 (machine epsilon for floats, the
    /// least significant bit for fixed point).
    const RESOLUTION: f64;
    /// Largest representable magnitude.
    const MAX_ABS: f64;
    /// Floating point: division is one correctly rounded (hardware) operation, and an
    /// overflow shows as a non-finite value that one check at the end can catch. Fixed point
    /// (`false`) has neither: its division is a 64/32 software routine on Cortex-M, so the
    /// levitation law evaluates Eq. 14's quotient division-free, and its fast path proves the
    /// absence of overflow from bounds on the inputs instead (`crate::levitation`).
    const FLOAT: bool;

    /// Nearest representable value; saturates at the range and flags (NaN gives zero, flagged).
    fn from_f64(x: f64, overflow: &mut bool) -> Self;
    /// Exact for every type except `f64 -> f64` being the identity; fixed point converts exactly.
    fn to_f64(self) -> f64;
    /// `self.to_f64() as f32` (one rounding), without going through `f64`: on a Cortex-M4F
    /// `f64` is software, and the firmware converts every coil voltage per tick.
    fn to_f32(self) -> f32;
    /// `code / 2^bits`, exactly (`bits ≤ 16`; an ADC code as a fraction of full scale).
    fn from_code(code: u16, bits: u8) -> Self;
    /// Saturating addition.
    fn sadd(self, rhs: Self, overflow: &mut bool) -> Self;
    /// Saturating subtraction.
    fn ssub(self, rhs: Self, overflow: &mut bool) -> Self;
    /// Saturating, rounded multiplication.
    fn smul(self, rhs: Self, overflow: &mut bool) -> Self;
    /// Saturating, rounded division; division by zero saturates (0/0 gives 0) and flags.
    fn sdiv(self, rhs: Self, overflow: &mut bool) -> Self;
    /// Saturating negation (only fixed point's minimum can overflow).
    fn sneg(self, overflow: &mut bool) -> Self;
    /// `self - floor(self)`, in `[0, 1)`.
    fn fract(self) -> Self;

    /// Unchecked addition: the plain IEEE operation for floats, wrapping for fixed point.
    /// Only for a fast path that has proven (fixed) or checks afterwards (floats) that no
    /// operation overflowed; then the result equals [`Scalar::sadd`]'s bit for bit.
    fn add_raw(self, rhs: Self) -> Self;
    /// Unchecked subtraction (see [`Scalar::add_raw`]).
    fn sub_raw(self, rhs: Self) -> Self;
    /// Unchecked, rounded multiplication (see [`Scalar::add_raw`]); fixed point rounds as
    /// [`Scalar::smul`] and wraps instead of saturating.
    fn mul_raw(self, rhs: Self) -> Self;
    /// Unchecked division (see [`Scalar::add_raw`]); fixed point delegates to [`Scalar::sdiv`].
    fn div_raw(self, rhs: Self) -> Self;
    /// Whether the value is finite (always for fixed point).
    fn is_finite_value(self) -> bool;
    /// `0 < self ≤ hi` (false for NaN), for `hi > 0`: one unsigned compare of the bit
    /// patterns (positive IEEE values order as their bits; NaN, −0 and negatives are above).
    fn positive_up_to(self, hi: Self) -> bool;

    /// `cos(2π·t)`, `t` in turns. The default works for any type through [`Scalar`]
    /// arithmetic (used by fixed point); floats override it with libm / micromath.
    fn cos_turns(self, overflow: &mut bool) -> Self {
        crate::trig::cos_turns_generic(self, overflow)
    }

    /// The smaller of two values.
    #[inline]
    fn min_of(self, rhs: Self) -> Self {
        if rhs < self {
            rhs
        } else {
            self
        }
    }
    /// The larger of two values.
    #[inline]
    fn max_of(self, rhs: Self) -> Self {
        if rhs > self {
            rhs
        } else {
            self
        }
    }
    /// Clamp into `[lo, hi]` (assumes `lo <= hi`).
    #[inline]
    fn clamp_to(self, lo: Self, hi: Self) -> Self {
        self.max_of(lo).min_of(hi)
    }
}

macro_rules! float_scalar {
    ($t:ty, $name:literal, $cos:expr) => {
        impl Scalar for $t {
            const NAME: &'static str = $name;
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            const RESOLUTION: f64 = <$t>::EPSILON as f64;
            const MAX_ABS: f64 = <$t>::MAX as f64;
            const FLOAT: bool = true;

            #[inline]
            fn add_raw(self, rhs: Self) -> Self {
                self + rhs
            }
            #[inline]
            fn sub_raw(self, rhs: Self) -> Self {
                self - rhs
            }
            #[inline]
            fn mul_raw(self, rhs: Self) -> Self {
                self * rhs
            }
            #[inline]
            fn div_raw(self, rhs: Self) -> Self {
                self / rhs
            }
            #[inline]
            fn is_finite_value(self) -> bool {
                self.is_finite()
            }
            #[inline]
            fn positive_up_to(self, hi: Self) -> bool {
                self.to_bits().wrapping_sub(1) < hi.to_bits()
            }

            #[inline]
            fn from_f64(x: f64, overflow: &mut bool) -> Self {
                Self::finite(x as $t, overflow)
            }
            #[inline]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline]
            fn to_f32(self) -> f32 {
                self as f32
            }
            #[inline]
            fn from_code(code: u16, bits: u8) -> Self {
                // Both factors and the product are exact (16 significant bits at most).
                code as $t * (1.0 / (1u32 << bits.min(16)) as $t)
            }
            #[inline]
            fn sadd(self, rhs: Self, overflow: &mut bool) -> Self {
                Self::finite(self + rhs, overflow)
            }
            #[inline]
            fn ssub(self, rhs: Self, overflow: &mut bool) -> Self {
                Self::finite(self - rhs, overflow)
            }
            #[inline]
            fn smul(self, rhs: Self, overflow: &mut bool) -> Self {
                Self::finite(self * rhs, overflow)
            }
            #[inline]
            fn sdiv(self, rhs: Self, overflow: &mut bool) -> Self {
                Self::finite(self / rhs, overflow)
            }
            #[inline]
            fn sneg(self, _overflow: &mut bool) -> Self {
                -self
            }
            #[inline]
            fn fract(self) -> Self {
                let f = (self as f64 - libm::floor(self as f64)) as $t;
                // `x - floor(x)` can round up to exactly 1.0 for tiny negative x.
                if f >= 1.0 {
                    0.0
                } else {
                    f
                }
            }
            #[inline]
            fn cos_turns(self, overflow: &mut bool) -> Self {
                // Reduce to [-0.5, 0.5] turns first: the libraries lose accuracy on large
                // arguments, and the reduction in turns is exact in binary floating point.
                let t = self - libm_round(self as f64) as $t;
                let c: fn($t) -> $t = $cos;
                Self::finite(c(t * (2.0 * core::f64::consts::PI) as $t), overflow)
            }
        }
    };
}

trait Finite: Sized {
    fn finite(self, overflow: &mut bool) -> Self;
}
macro_rules! finite_impl {
    ($t:ty) => {
        impl Finite for $t {
            #[inline]
            fn finite(self, overflow: &mut bool) -> Self {
                if self.is_finite() {
                    self
                } else {
                    *overflow = true;
                    if self.is_nan() {
                        0.0
                    } else if self > 0.0 {
                        <$t>::MAX
                    } else {
                        <$t>::MIN
                    }
                }
            }
        }
    };
}
finite_impl!(f32);
finite_impl!(f64);

#[inline]
fn libm_round(x: f64) -> f64 {
    libm::round(x)
}

float_scalar!(f64, "f64", |x| libm::cos(x));
// micromath is called explicitly: on the host std's inherent `f32::cos` would shadow it and
// the host would compute something the target does not.
float_scalar!(f32, "f32", |x| micromath::F32Ext::cos(x));

macro_rules! fixed_scalar {
    ($t:ty, $bits:ty, $ubits:ty, $wide:ty, $frac:expr, $name:literal) => {
        impl Scalar for $t {
            const NAME: &'static str = $name;
            const ZERO: Self = <$t>::ZERO;
            const ONE: Self = <$t>::ONE;
            const RESOLUTION: f64 = 1.0 / ((1u64 << $frac) as f64);
            const MAX_ABS: f64 = (<$bits>::MAX as f64) / ((1u64 << $frac) as f64);
            const FLOAT: bool = false;

            #[inline]
            fn add_raw(self, rhs: Self) -> Self {
                <$t>::from_bits(self.to_bits().wrapping_add(rhs.to_bits()))
            }
            #[inline]
            fn sub_raw(self, rhs: Self) -> Self {
                <$t>::from_bits(self.to_bits().wrapping_sub(rhs.to_bits()))
            }
            #[inline]
            fn mul_raw(self, rhs: Self) -> Self {
                <$t>::from_bits(<$bits as RoundedProduct>::raw_product(
                    self.to_bits(),
                    rhs.to_bits(),
                    $frac,
                ))
            }
            #[inline]
            fn div_raw(self, rhs: Self) -> Self {
                self.sdiv(rhs, &mut false)
            }
            #[inline]
            fn is_finite_value(self) -> bool {
                true
            }
            #[inline]
            fn positive_up_to(self, hi: Self) -> bool {
                (self.to_bits().wrapping_sub(1) as $ubits) < hi.to_bits() as $ubits
            }

            fn from_f64(x: f64, overflow: &mut bool) -> Self {
                if x.is_nan() {
                    *overflow = true;
                    return <$t>::ZERO;
                }
                let scaled = libm::round(x * ((1u64 << $frac) as f64));
                // `as` saturates float-to-int conversions; detect the saturation explicitly.
                if scaled >= <$bits>::MAX as f64 {
                    *overflow = true;
                    <$t>::MAX
                } else if scaled < <$bits>::MIN as f64 {
                    *overflow = true;
                    <$t>::MIN
                } else {
                    <$t>::from_bits(scaled as $bits)
                }
            }
            #[inline]
            fn to_f64(self) -> f64 {
                // Exact: the integer fits f64's mantissa for I4F28; scaling by 2^-frac is exact.
                self.to_bits() as f64 * (1.0 / ((1u64 << $frac) as f64))
            }
            #[inline]
            fn to_f32(self) -> f32 {
                // One rounding (integer to f32), then an exact power-of-two scaling: the same
                // value as rounding `to_f64()` to f32.
                self.to_bits() as f32 * (1.0 / ((1u64 << $frac) as f32))
            }
            #[inline]
            fn from_code(code: u16, bits: u8) -> Self {
                let bits = bits.min(16) as u32;
                <$t>::from_bits((code as $bits) << ($frac - bits))
            }
            #[inline]
            fn sadd(self, rhs: Self, overflow: &mut bool) -> Self {
                match self.to_bits().checked_add(rhs.to_bits()) {
                    Some(v) => <$t>::from_bits(v),
                    None => {
                        *overflow = true;
                        if rhs.to_bits() > 0 {
                            <$t>::MAX
                        } else {
                            <$t>::MIN
                        }
                    }
                }
            }
            #[inline]
            fn ssub(self, rhs: Self, overflow: &mut bool) -> Self {
                match self.to_bits().checked_sub(rhs.to_bits()) {
                    Some(v) => <$t>::from_bits(v),
                    None => {
                        *overflow = true;
                        if rhs.to_bits() < 0 {
                            <$t>::MAX
                        } else {
                            <$t>::MIN
                        }
                    }
                }
            }
            #[inline]
            fn smul(self, rhs: Self, overflow: &mut bool) -> Self {
                let p = rounded_product(self.to_bits(), rhs.to_bits(), $frac);
                narrow::<$t, $bits, $wide>(p, overflow)
            }
            fn sdiv(self, rhs: Self, overflow: &mut bool) -> Self {
                let d = rhs.to_bits() as $wide;
                let n = (self.to_bits() as $wide) << $frac;
                if d == 0 {
                    if n == 0 {
                        return <$t>::ZERO;
                    }
                    *overflow = true;
                    return if n > 0 { <$t>::MAX } else { <$t>::MIN };
                }
                let mut q = n / d;
                let r = n % d;
                // Round half away from zero on the magnitude of the remainder.
                if 2 * r.unsigned_abs() >= d.unsigned_abs() {
                    q += if (n < 0) == (d < 0) { 1 } else { -1 };
                }
                narrow::<$t, $bits, $wide>(q, overflow)
            }
            #[inline]
            fn fract(self) -> Self {
                <$t>::from_bits(self.to_bits() & ((1 << $frac) - 1))
            }
            #[inline]
            fn sneg(self, overflow: &mut bool) -> Self {
                match self.to_bits().checked_neg() {
                    Some(v) => <$t>::from_bits(v),
                    None => {
                        *overflow = true;
                        <$t>::MAX
                    }
                }
            }
        }

        impl Narrow<$bits, $wide> for $t {
            #[inline]
            fn narrow(v: $wide, overflow: &mut bool) -> Self {
                if v > <$bits>::MAX as $wide {
                    *overflow = true;
                    <$t>::MAX
                } else if v < <$bits>::MIN as $wide {
                    *overflow = true;
                    <$t>::MIN
                } else {
                    <$t>::from_bits(v as $bits)
                }
            }
        }
    };
}

trait Narrow<B, W>: Sized {
    fn narrow(v: W, overflow: &mut bool) -> Self;
}
#[inline]
fn narrow<T: Narrow<B, W>, B, W>(v: W, overflow: &mut bool) -> T {
    T::narrow(v, overflow)
}

fixed_scalar!(I32F32, i64, u64, i128, 32, "i32f32");
fixed_scalar!(I4F28, i32, u32, i64, 28, "i4f28");

/// `round(a·b / 2^frac)` (to nearest, ties towards +∞) as the exact double-width value:
/// add half an LSB to the exact product, then floor-shift.
trait RoundedProduct: Sized {
    type Wide;
    fn rounded_product(a: Self, b: Self, frac: u32) -> Self::Wide;
    /// The same, narrowed by wrapping ([`Scalar::mul_raw`]).
    fn raw_product(a: Self, b: Self, frac: u32) -> Self;
}
impl RoundedProduct for i64 {
    type Wide = i128;
    #[inline]
    fn rounded_product(a: i64, b: i64, frac: u32) -> i128 {
        ((a as i128) * (b as i128) + (1 << (frac - 1))) >> frac
    }
    #[inline]
    fn raw_product(a: i64, b: i64, frac: u32) -> i64 {
        Self::rounded_product(a, b, frac) as i64
    }
}
impl RoundedProduct for i32 {
    type Wide = i64;
    #[inline]
    fn rounded_product(a: i32, b: i32, frac: u32) -> i64 {
        // Thumb-1 (Cortex-M0) has no 32×32→64 multiply: LLVM would call the general 64×64
        // `__aeabi_lmul`; the signed 32×32 product from four 16×16 ones is about half of it.
        // Same exact product, so the same bits (tested against the i64 product below).
        // Stable Rust has no cfg for Thumb-2/ARMv7; ARMv6-M is the ARM profile without
        // 32-bit atomic read-modify-write (no LDREX/STREX), so that selects it.
        #[cfg(all(target_arch = "arm", not(target_has_atomic = "32")))]
        let p = mul_wide_i32(a, b);
        #[cfg(not(all(target_arch = "arm", not(target_has_atomic = "32"))))]
        let p = (a as i64) * (b as i64);
        (p + (1 << (frac - 1))) >> frac
    }
    #[inline]
    fn raw_product(a: i32, b: i32, frac: u32) -> i32 {
        // On Thumb-1 the fast path's operands are bounded (`RAW_OPERAND_MAX`), which allows
        // the three-multiply product without carries.
        #[cfg(all(target_arch = "arm", not(target_has_atomic = "32")))]
        if frac == 28 {
            return q28_product_bounded(a, b);
        }
        Self::rounded_product(a, b, frac) as i32
    }
}

/// Largest operand magnitude for which [`Scalar::mul_raw`] of I4F28 is exact on every
/// target (the fast path of `crate::levitation` proves its operands below it).
pub const RAW_OPERAND_MAX: f64 = 3.9;

/// `round(a·b / 2^28)` (ties towards +∞) for `|a|, |b| < 3.9·2^28` and a result in range,
/// with four 16×16 multiplies and no carry chain. With `a = ah·2^16 + al`, `b = bh·2^16 + bl`
/// (`al`, `bl` unsigned 16-bit): `a·b = ah·bh·2^32 + m·2^16 + (al·bl mod 2^16)` with
/// `m = ah·bl + al·bh + ⌊al·bl/2^16⌋`, and since the last term is below 2^16 it cannot
/// carry into ⌊(a·b + 2^27)/2^28⌋ = `16·ah·bh + ⌊(m + 2^11)/2^12⌋`. The bound keeps
/// `|ah| < 15 975`, so `|m| < 2^31`.
#[inline]
#[allow(dead_code)] // used on Thumb-1 only; tested on every host
fn q28_product_bounded(a: i32, b: i32) -> i32 {
    let (ah, al) = (a >> 16, a & 0xffff);
    let (bh, bl) = (b >> 16, b & 0xffff);
    let t = ((al as u32 * bl as u32) >> 16) as i32;
    let m = ah * bl + al * bh + t;
    ((ah * bh) << 4).wrapping_add((m + (1 << 11)) >> 12)
}
#[inline]
fn rounded_product<B: RoundedProduct<Wide = W>, W>(a: B, b: B, frac: u32) -> W {
    B::rounded_product(a, b, frac)
}

/// The exact signed product `a·b` from 16×16→32 multiplies and 32-bit additions only:
/// the unsigned product of the two's-complement bit patterns (four partial products,
/// carries propagated), then the signed correction `−2^32·(b·[a<0] + a·[b<0])`.
#[inline]
#[allow(dead_code)] // used on Thumb-1 only; tested on every host
fn mul_wide_i32(a: i32, b: i32) -> i64 {
    let (ua, ub) = (a as u32, b as u32);
    let (al, ah) = (ua & 0xffff, ua >> 16);
    let (bl, bh) = (ub & 0xffff, ub >> 16);
    let ll = al * bl;
    let (mid, c1) = (al * bh).overflowing_add(ah * bl);
    let (lo, c2) = ll.overflowing_add(mid << 16);
    let mut hi = (ah * bh)
        .wrapping_add(mid >> 16)
        .wrapping_add((c1 as u32) << 16)
        .wrapping_add(c2 as u32);
    if a < 0 {
        hi = hi.wrapping_sub(ub);
    }
    if b < 0 {
        hi = hi.wrapping_sub(ua);
    }
    (((hi as u64) << 32) | lo as u64) as i64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all_types_roundtrip<S: Scalar>() {
        let mut ov = false;
        for x in [0.0, 1.0, -1.0, 0.5, -2.75, 3.0e-3] {
            let s = S::from_f64(x, &mut ov);
            assert!(
                (s.to_f64() - x).abs() <= S::RESOLUTION * 4.0,
                "{} {}",
                S::NAME,
                x
            );
        }
        assert!(!ov);
    }

    #[test]
    fn thumb1_wide_product_is_the_exact_product() {
        let edge = [
            0,
            1,
            -1,
            2,
            -2,
            0x7fff,
            0x8000,
            0xffff,
            0x1_0000,
            -0x8000,
            -0x1_0000,
            i32::MAX,
            i32::MIN,
            i32::MAX - 1,
            i32::MIN + 1,
            0x1234_5678,
            -0x1234_5678,
        ];
        for &a in &edge {
            for &b in &edge {
                assert_eq!(mul_wide_i32(a, b), a as i64 * b as i64, "{a} * {b}");
            }
        }
        // A fixed-seed xorshift sweep over the whole range.
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..200_000 {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            let (a, b) = (s as i32, (s >> 32) as i32);
            assert_eq!(mul_wide_i32(a, b), a as i64 * b as i64, "{a} * {b}");
        }
    }

    #[test]
    fn bounded_q28_product_is_the_rounded_product() {
        let max = (RAW_OPERAND_MAX * (1u64 << 28) as f64) as i32;
        let exact = |a: i32, b: i32| ((a as i64 * b as i64 + (1 << 27)) >> 28) as i32;
        let edge = [
            0,
            1,
            -1,
            0x7fff,
            0x8000,
            0xffff,
            0x1_0000,
            -0x8000,
            -0x1_0000,
            max,
            -max,
            max - 1,
            1 << 28,
            -(1 << 28),
            0x0123_4567,
            -0x0123_4567,
        ];
        for &a in &edge {
            for &b in &edge {
                assert_eq!(q28_product_bounded(a, b), exact(a, b), "{a} * {b}");
            }
        }
        let mut s = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..200_000 {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            let a = (s as i32) % max;
            let b = ((s >> 32) as i32) % max;
            assert_eq!(q28_product_bounded(a, b), exact(a, b), "{a} * {b}");
        }
    }

    #[test]
    fn positive_up_to_is_the_open_closed_interval() {
        let hi = 2.5f32;
        for (x, want) in [
            (0.0f32, false),
            (-0.0, false),
            (1e-45, true),
            (2.5, true),
            (2.5000002, false),
            (-1.0, false),
            (f32::NAN, false),
            (f32::INFINITY, false),
        ] {
            assert_eq!(x.positive_up_to(hi), want, "{x}");
        }
        let mut ov = false;
        let h = I4F28::from_f64(2.5, &mut ov);
        for (x, want) in [
            (0.0, false),
            (-1.0, false),
            (1e-8, true),
            (2.5, true),
            (2.6, false),
        ] {
            assert_eq!(I4F28::from_f64(x, &mut ov).positive_up_to(h), want, "{x}");
        }
        assert!(!I4F28::MIN.positive_up_to(h) && I4F28::from_bits(1).positive_up_to(h));
    }

    #[test]
    fn to_f32_and_from_code_are_the_f64_conversions() {
        fn check<S: Scalar>() {
            let mut ov = false;
            for x in [0.0, 1.0, -1.0, 0.1, -2.75, 3.0e-3, 7.999, -7.5, 1.0 / 3.0] {
                let s = S::from_f64(x, &mut ov);
                assert_eq!(s.to_f32().to_bits(), (s.to_f64() as f32).to_bits(), "{x}");
            }
            for bits in [2u8, 12, 16] {
                for code in [0u16, 1, 2, 3, 1000, u16::MAX] {
                    let code = code & ((1u32 << bits) - 1) as u16;
                    let want = S::from_f64(code as f64 / (1u32 << bits) as f64, &mut ov);
                    assert_eq!(S::from_code(code, bits), want, "{code}/2^{bits}");
                }
            }
            assert!(!ov);
        }
        check::<f64>();
        check::<f32>();
        check::<I32F32>();
        check::<I4F28>();
        // Integers beyond f32's mantissa round once, as through f64.
        for b in [
            0x0123_4567,
            -0x0765_4321,
            i32::MAX,
            i32::MIN,
            0x00ff_ffff + 2,
        ] {
            let s = I4F28::from_bits(b);
            assert_eq!(s.to_f32().to_bits(), (s.to_f64() as f32).to_bits(), "{b}");
        }
    }

    #[test]
    fn roundtrip() {
        all_types_roundtrip::<f64>();
        all_types_roundtrip::<f32>();
        all_types_roundtrip::<I32F32>();
        all_types_roundtrip::<I4F28>();
    }

    #[test]
    fn fixed_saturates_and_flags() {
        let mut ov = false;
        let big = I4F28::from_f64(7.5, &mut ov);
        assert!(!ov);
        let s = big.sadd(big, &mut ov);
        assert!(ov);
        assert_eq!(s, I4F28::MAX);
        let mut ov = false;
        let p = big.smul(big.sneg(&mut ov), &mut ov);
        assert!(ov);
        assert_eq!(p, I4F28::MIN);
        let mut ov = false;
        assert_eq!(I4F28::ONE.sdiv(I4F28::ZERO, &mut ov), I4F28::MAX);
        assert!(ov);
        let mut ov = false;
        assert_eq!(I4F28::ZERO.sdiv(I4F28::ZERO, &mut ov), I4F28::ZERO);
        assert!(!ov);
        let mut ov = false;
        assert_eq!(I4F28::from_f64(f64::NAN, &mut ov), I4F28::ZERO);
        assert!(ov);
        let mut ov = false;
        assert_eq!(I4F28::from_f64(1e9, &mut ov), I4F28::MAX);
        assert!(ov);
    }

    #[test]
    fn float_never_leaves_nan_or_inf() {
        let mut ov = false;
        let x = f32::MAX.smul(2.0, &mut ov);
        assert!(ov && x == f32::MAX);
        let mut ov = false;
        let y = 0.0f64.sdiv(0.0, &mut ov);
        assert!(ov && y == 0.0);
    }

    #[test]
    fn fixed_mul_div_round_to_nearest() {
        let mut ov = false;
        let third = I32F32::ONE.sdiv(I32F32::from_f64(3.0, &mut ov), &mut ov);
        assert!((third.to_f64() - 1.0 / 3.0).abs() <= 0.5 * I32F32::RESOLUTION);
        let lsb = I4F28::from_bits(1);
        let half = I4F28::from_f64(0.5, &mut ov);
        // 0.5 LSB rounds up (ties towards +inf), -0.5 LSB rounds to zero.
        assert_eq!(lsb.smul(half, &mut ov).to_bits(), 1);
        assert_eq!(lsb.sneg(&mut ov).smul(half, &mut ov).to_bits(), 0);
        let a = I4F28::from_f64(-1.234567, &mut ov);
        let b = I4F28::from_f64(0.987654, &mut ov);
        assert!(
            ((a.smul(b, &mut ov)).to_f64() - a.to_f64() * b.to_f64()).abs()
                <= 0.5 * I4F28::RESOLUTION
        );
        assert!(
            ((a.sdiv(b, &mut ov)).to_f64() - a.to_f64() / b.to_f64()).abs()
                <= 0.5 * I4F28::RESOLUTION + 1e-15
        );
        assert!(!ov);
    }

    #[test]
    fn cos_turns_all_types() {
        fn check<S: Scalar>(tol: f64) {
            let mut ov = false;
            for i in -40..=40 {
                let t = i as f64 * 0.0371;
                let c = S::from_f64(t, &mut ov).cos_turns(&mut ov).to_f64();
                let tq = S::from_f64(t, &mut ov).to_f64();
                let want = libm::cos(2.0 * core::f64::consts::PI * tq);
                assert!(
                    (c - want).abs() <= tol,
                    "{} t={} got {} want {}",
                    S::NAME,
                    t,
                    c,
                    want
                );
            }
            assert!(!ov);
        }
        check::<f64>(1e-14);
        check::<f32>(3e-3); // micromath's documented accuracy
        check::<I32F32>(2e-9);
        check::<I4F28>(3e-8);
    }
}
