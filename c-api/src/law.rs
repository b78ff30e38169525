//! The law and its state in caller-owned storage, generic over the run-time scalar; the
//! `extern "C"` functions of both variants ([`crate::f32_api`], [`crate::q28_api`]) are thin
//! shells around the functions here.
//!
//! # Storage
//! C cannot name `Law<S>` or `LawState<S>`, so it holds them in opaque arrays of `uint64_t`
//! whose sizes are published constants ([`MAGLEV_LAW_SIZE`], [`MAGLEV_STATE_SIZE`], alignment
//! [`MAGLEV_ALIGN`]); `const` assertions below fail the build on any target where a core type
//! outgrows its array. The sizes carry headroom so that a law the core gains later need not
//! change the ABI.
//!
//! A law holds enums (which law, which scheme): arbitrary bytes are not a valid `Law<S>`. So
//! init writes a tag word before the law, and every use checks it
//! (`MAGLEV_ERROR_NOT_INITIALIZED`) before reading the law. A state is scalars only: any bytes
//! are a (perhaps meaningless) valid state.

use crate::error::from_param_error;
use crate::error::maglev_error::{self, *};
use crate::params::maglev_params;
use maglev_core::scalar::I4F28;
use maglev_core::{Law, LawState, Measurement, Output, Scalar};

/// Bytes of a `maglev_law_f32` or `maglev_law_q28` (either variant, every target).
pub const MAGLEV_LAW_SIZE: usize = 1024;
/// Bytes of a `maglev_state_f32` or `maglev_state_q28`.
pub const MAGLEV_STATE_SIZE: usize = 64;
/// Alignment (bytes) of the law and state storage (that of `uint64_t` on the targets).
pub const MAGLEV_ALIGN: usize = 8;
/// `uint64_t` words of a law's storage.
pub const MAGLEV_LAW_WORDS: usize = MAGLEV_LAW_SIZE / 8;
/// `uint64_t` words of a state's storage.
pub const MAGLEV_STATE_WORDS: usize = MAGLEV_STATE_SIZE / 8;

/// A measurement carries the acceleration (`accel_g` is read).
pub const MAGLEV_MEASURED_ACCEL: u32 = 1;
/// A measurement carries the coil current (`current_pu` is read).
pub const MAGLEV_MEASURED_CURRENT: u32 = 2;

/// Tags written before the law by a successful init: a law of the other variant, or bytes no
/// init wrote, are refused. The low bit ([`TAG_PAPER`]) is set for the paper's law alone, so
/// the update's dispatch reads one word.
const TAG_F32: u32 = 0x6d67_0f30;
const TAG_Q28: u32 = 0x6d67_0428;
const TAG_PAPER: u32 = 1;

/// What a law's storage holds after init.
#[repr(C)]
struct Stored<S> {
    tag: u32,
    law: Law<S>,
}

/// A scalar of the C API, with the C type its numbers travel in.
pub trait CScalar: Scalar {
    /// `float` or `int32_t` (Q4.28).
    type Raw: Copy;
    /// This variant's tag.
    const TAG: u32;
    /// From C.
    fn from_raw(r: Self::Raw) -> Self;
    /// To C.
    fn to_raw(self) -> Self::Raw;
}

impl CScalar for f32 {
    type Raw = f32;
    const TAG: u32 = TAG_F32;
    #[inline(always)]
    fn from_raw(r: f32) -> f32 {
        r
    }
    #[inline(always)]
    fn to_raw(self) -> f32 {
        self
    }
}

impl CScalar for I4F28 {
    type Raw = i32;
    const TAG: u32 = TAG_Q28;
    #[inline(always)]
    fn from_raw(r: i32) -> I4F28 {
        I4F28::from_bits(r)
    }
    #[inline(always)]
    fn to_raw(self) -> i32 {
        self.to_bits()
    }
}

const _: () = {
    use core::mem::{align_of, size_of};
    assert!(size_of::<Stored<f32>>() <= MAGLEV_LAW_SIZE);
    assert!(size_of::<Stored<I4F28>>() <= MAGLEV_LAW_SIZE);
    assert!(align_of::<Stored<f32>>() <= MAGLEV_ALIGN);
    assert!(align_of::<Stored<I4F28>>() <= MAGLEV_ALIGN);
    assert!(size_of::<LawState<f32>>() <= MAGLEV_STATE_SIZE);
    assert!(size_of::<LawState<I4F28>>() <= MAGLEV_STATE_SIZE);
    assert!(align_of::<LawState<f32>>() <= MAGLEV_ALIGN);
    assert!(align_of::<LawState<I4F28>>() <= MAGLEV_ALIGN);
    assert!(MAGLEV_LAW_WORDS * 8 == MAGLEV_LAW_SIZE && MAGLEV_STATE_WORDS * 8 == MAGLEV_STATE_SIZE);
    assert!(align_of::<u64>() <= MAGLEV_ALIGN);
};

/// Bytes the core's types take in their storage on this target (`[law f32, law q28, state
/// f32, state q28]`), for the docs and tests.
pub const fn used_sizes() -> [usize; 4] {
    use core::mem::size_of;
    [
        size_of::<Stored<f32>>(),
        size_of::<Stored<I4F28>>(),
        size_of::<LawState<f32>>(),
        size_of::<LawState<I4F28>>(),
    ]
}

/// Compiles `params` into the storage at `out` (tag first, then the law).
///
/// # Safety
/// `params` is NULL or readable as a `maglev_params`; `out` is NULL or writable for
/// [`MAGLEV_LAW_SIZE`] bytes aligned to [`MAGLEV_ALIGN`].
pub unsafe fn init<S: CScalar>(params: *const maglev_params, out: *mut u64) -> maglev_error {
    if params.is_null() || out.is_null() {
        return MAGLEV_ERROR_NULL;
    }
    if !params.is_aligned() || !out.is_aligned() {
        return MAGLEV_ERROR_ALIGNMENT;
    }
    // SAFETY: non-null and readable by the caller's contract; every bit pattern of its
    // fields is a valid f64/u32.
    let p = unsafe { params.read() };
    let law = match p.to_core() {
        Ok(lp) => match lp.compile::<S>() {
            Ok(law) => law,
            Err(e) => {
                // SAFETY: the storage is writable; a zero tag marks it uninitialised.
                unsafe { out.cast::<u32>().write(0) };
                return from_param_error(&e);
            }
        },
        Err(e) => {
            // SAFETY: as above.
            unsafe { out.cast::<u32>().write(0) };
            return e;
        }
    };
    let tag = S::TAG | if law.is_paper() { TAG_PAPER } else { 0 };
    // SAFETY: the storage is large and aligned enough (const assertions above).
    unsafe { out.cast::<Stored<S>>().write(Stored { tag, law }) };
    MAGLEV_OK
}

/// The law at `law`, if a successful init of this variant wrote it.
///
/// # Safety
/// `law` is non-null and readable for [`MAGLEV_LAW_SIZE`] bytes, aligned.
#[inline(always)]
pub unsafe fn get<'a, S: CScalar>(law: *const u64) -> Option<&'a Law<S>> {
    // SAFETY: the first word is readable; after a matching tag the rest is the law init wrote.
    unsafe {
        if law.cast::<u32>().read() & !TAG_PAPER != S::TAG {
            return None;
        }
        Some(&(*law.cast::<Stored<S>>()).law)
    }
}

/// The equilibrium state at gap `gap_m` (m) into `out`.
///
/// # Safety
/// Pointers NULL or valid for their storage sizes, aligned.
pub unsafe fn state_init<S: CScalar>(law: *const u64, gap_m: f64, out: *mut u64) -> maglev_error {
    if law.is_null() || out.is_null() {
        return MAGLEV_ERROR_NULL;
    }
    if !law.is_aligned() || !out.is_aligned() {
        return MAGLEV_ERROR_ALIGNMENT;
    }
    // SAFETY: caller's contract.
    let Some(law) = (unsafe { get::<S>(law) }) else {
        return MAGLEV_ERROR_NOT_INITIALIZED;
    };
    match law.try_equilibrium_state(gap_m) {
        Ok(st) => {
            // SAFETY: large and aligned enough (const assertions).
            unsafe { out.cast::<LawState<S>>().write(st) };
            MAGLEV_OK
        }
        Err(e) => from_param_error(&e),
    }
}

/// A measurement as the core takes it.
#[inline(always)]
pub fn measurement<S: CScalar>(
    gap: S::Raw,
    accel: S::Raw,
    current: S::Raw,
    flags: u32,
) -> Measurement<S> {
    Measurement {
        gap: S::from_raw(gap),
        accel: (flags & MAGLEV_MEASURED_ACCEL != 0).then(|| S::from_raw(accel)),
        current: (flags & MAGLEV_MEASURED_CURRENT != 0).then(|| S::from_raw(current)),
    }
}

/// One update: `None` if the law's storage is not this variant's initialised law.
///
/// The paper's law alone (its tag's low bit, set by init from [`Law::is_paper`], the test
/// the core's batched updates use) goes straight to its update: `Law::update`'s paper arm is
/// that call, so the bits are the same, and the call skips the frame of the function that
/// holds every law's arm (docs/c-api.md has the instruction counts). Every other law goes
/// through [`Law::update`].
///
/// # Safety
/// `law` and `state` non-null, valid for their types, aligned, not overlapping.
#[inline(always)]
pub unsafe fn update<S: CScalar>(
    law: *const u64,
    state: *mut u64,
    m: impl FnOnce() -> Measurement<S>,
    gap: S::Raw,
) -> Option<Output<S>> {
    // SAFETY: caller's contract; any bytes are a valid LawState of scalars; the law is
    // referenced only after its tag matched, i.e. init wrote it.
    unsafe {
        let tag = law.cast::<u32>().read();
        let st = &mut *state.cast::<LawState<S>>();
        if tag == S::TAG | TAG_PAPER {
            let law = &(*law.cast::<Stored<S>>()).law;
            Some(law.levitation().update(&mut st.inner, S::from_raw(gap)))
        } else if tag == S::TAG {
            Some(other_law(&(*law.cast::<Stored<S>>()).law, st, m()))
        } else {
            None
        }
    }
}

/// [`Law::update`] out of line (and cold), so that the paper's path does not carry its frame.
#[cold]
#[inline(never)]
fn other_law<S: CScalar>(law: &Law<S>, st: &mut LawState<S>, m: Measurement<S>) -> Output<S> {
    law.update(st, m)
}

/// The state at `state`.
///
/// # Safety
/// `state` non-null, readable for [`MAGLEV_STATE_SIZE`] bytes, aligned.
#[inline(always)]
pub unsafe fn state<'a, S: CScalar>(state: *const u64) -> &'a LawState<S> {
    // SAFETY: caller's contract; any bytes are a valid LawState of scalars.
    unsafe { &*state.cast::<LawState<S>>() }
}
