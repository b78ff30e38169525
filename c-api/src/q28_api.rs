//! The Q4.28 fixed-point variant: the core's laws in `I4F28`, 32-bit signed integers with 28
//! fractional bits (value = raw / 2^28, range [−8, 8), resolution 3.7e-9), for cores without
//! an FPU. Every operation saturates and flags (`MAGLEV_STATUS_OVERFLOW`); results are
//! bit-identical on every target. Quantities are per unit as in the `float` variant (module
//! docs of `f32_api`); `maglev_q28_from_f64` / `maglev_q28_to_f64` convert.

use crate::error::maglev_error::*;
use crate::law::{self, MAGLEV_LAW_WORDS, MAGLEV_STATE_WORDS};
use crate::params::maglev_params;
use maglev_core::scalar::I4F28;
use maglev_core::Scalar;

/// A compiled law (Q4.28), caller-owned: `MAGLEV_LAW_SIZE` bytes, aligned to `MAGLEV_ALIGN`.
/// Written by `maglev_law_init_q28`; read-only afterwards; one law may drive many states.
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct maglev_law_q28 {
    /// Opaque.
    pub opaque: [u64; MAGLEV_LAW_WORDS],
}

/// One magnet's controller state (Q4.28), caller-owned: `MAGLEV_STATE_SIZE` bytes.
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct maglev_state_q28 {
    /// Opaque.
    pub opaque: [u64; MAGLEV_STATE_WORDS],
}

/// What a law reads at the end of a step, per unit.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct maglev_measurement_q28 {
    /// Gap `h/h0_m` (dimensionless). ≤ 0 is a collision; above 3.6 it is clamped and flagged
    /// `MAGLEV_STATUS_INVALID_INPUT`.
    pub gap_pu: i32,
    /// The magnet's absolute vertical acceleration `a/g_n` (g_n = 9.81 m/s², Z up); read if
    /// `flags & MAGLEV_MEASURED_ACCEL` (the state law uses it).
    pub accel_g: i32,
    /// Coil current `i/i0_A`; read if `flags & MAGLEV_MEASURED_CURRENT` (no law yet feeds it
    /// back: every law integrates its own coil).
    pub current_pu: i32,
    /// `MAGLEV_MEASURED_*` bits.
    pub flags: u32,
}

/// One update's result, per unit; SI: `g_pu·i0_A/h0_m` (A/m), `force_pu·p0_N` (N),
/// `current_pu·i0_A` (A), `voltage_pu·r0_ohm·i0_A` (V).
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct maglev_output_q28 {
    /// `g/g0`, g = i/h (A/m), g0 = i0_A/h0_m.
    pub g_pu: i32,
    /// Magnet force `G/p0_N` (Eq. 1), upward on the magnet.
    pub force_pu: i32,
    /// Coil current `i/i0_A`.
    pub current_pu: i32,
    /// Coil voltage `V/(r0_ohm·i0_A)`.
    pub voltage_pu: i32,
    /// `MAGLEV_STATUS_*` bits raised in this step (0: none).
    pub status: u32,
}

/// The paper law's part of a state, per unit deviations from equilibrium.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct maglev_state_view_q28 {
    /// `g/g0 − 1`.
    pub x: i32,
    /// `KI·e_a/(r0_ohm·i0_A) − 1` (the integral's voltage, per unit).
    pub y: i32,
    /// `h/h0_m − 1` at the end of the last step.
    pub eta: i32,
    /// Coil voltage `V/(r0_ohm·i0_A)` at the end of the last step.
    pub v: i32,
}

/// Checks `*params` and compiles it into `*out` (Q4.28). Returns `MAGLEV_OK`, or the code of
/// the first bad field (`maglev_error_field_name`); on failure `*out` is marked uninitialised.
/// No allocation; runs the parameter checks and the conversion in double precision once
/// (`MAGLEV_ERROR_UNREPRESENTABLE` when Q4.28 cannot carry a coefficient to 1e-4).
///
/// # Safety
/// `params` NULL or a readable `maglev_params`; `out` NULL or a writable `maglev_law_q28`.
#[no_mangle]
pub unsafe extern "C" fn maglev_law_init_q28(
    params: *const maglev_params,
    out: *mut maglev_law_q28,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { law::init::<I4F28>(params, out.cast()) as i32 }
}

/// Writes into `*out` the law's equilibrium state at gap `gap_m` (m): the coil at the static
/// load `p0_N`, every filter at rest there. Returns `MAGLEV_OK`, `MAGLEV_ERROR_NULL`,
/// `MAGLEV_ERROR_ALIGNMENT`, `MAGLEV_ERROR_NOT_INITIALIZED` or `MAGLEV_ERROR_GAP` (NaN, ≤ 0 or beyond the law's range:
/// 100·`h0_m`, Q4.28 3.6·`h0_m`).
///
/// # Safety
/// `law` NULL or a `maglev_law_q28`; `out` NULL or a writable `maglev_state_q28`.
#[no_mangle]
pub unsafe extern "C" fn maglev_state_init_q28(
    law: *const maglev_law_q28,
    gap_m: f64,
    out: *mut maglev_state_q28,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { law::state_init::<I4F28>(law.cast(), gap_m, out.cast()) as i32 }
}

/// One step Δt = `dt_s` of the law: from `*state` to the measurement `*m` at the step's end;
/// writes the step's outputs to `*out`. Returns `MAGLEV_OK`, `MAGLEV_ERROR_NULL` or
/// `MAGLEV_ERROR_ALIGNMENT`, `MAGLEV_ERROR_NOT_INITIALIZED` (then nothing is written). Events of the step (collision,
/// saturation, overflow, a NaN gap) are not errors: they are `out->status` bits, and results
/// saturate at the format's range (`MAGLEV_STATUS_OVERFLOW`). No allocation, no recursion, bounded time.
///
/// # Safety
/// Each pointer NULL or valid for its type; `state` and `out` do not overlap the others.
#[no_mangle]
pub unsafe extern "C" fn maglev_law_update_q28(
    law: *const maglev_law_q28,
    state: *mut maglev_state_q28,
    m: *const maglev_measurement_q28,
    out: *mut maglev_output_q28,
) -> i32 {
    if law.is_null() || state.is_null() || m.is_null() || out.is_null() {
        return MAGLEV_ERROR_NULL as i32;
    }
    if !(law.is_aligned() && state.is_aligned() && m.is_aligned() && out.is_aligned()) {
        return MAGLEV_ERROR_ALIGNMENT as i32;
    }
    // SAFETY: non-null and valid by the caller's contract.
    unsafe {
        let m = &*m;
        let meas = || law::measurement::<I4F28>(m.gap_pu, m.accel_g, m.current_pu, m.flags);
        match law::update::<I4F28>(law.cast(), state.cast(), meas, m.gap_pu) {
            Some(o) => {
                out.write(maglev_output_q28 {
                    g_pu: o.g.to_bits(),
                    force_pu: o.force.to_bits(),
                    current_pu: o.current.to_bits(),
                    voltage_pu: o.voltage.to_bits(),
                    status: o.status.0 as u32,
                });
                MAGLEV_OK as i32
            }
            None => MAGLEV_ERROR_NOT_INITIALIZED as i32,
        }
    }
}

/// Copies the paper law's part of `*state` (per unit) into `*out`, for logs and tests.
/// Returns `MAGLEV_OK`, `MAGLEV_ERROR_NULL` or `MAGLEV_ERROR_ALIGNMENT`.
///
/// # Safety
/// `state` NULL or a `maglev_state_q28`; `out` NULL or a writable `maglev_state_view_q28`.
#[no_mangle]
pub unsafe extern "C" fn maglev_state_read_q28(
    state: *const maglev_state_q28,
    out: *mut maglev_state_view_q28,
) -> i32 {
    if state.is_null() || out.is_null() {
        return MAGLEV_ERROR_NULL as i32;
    }
    if !state.is_aligned() || !out.is_aligned() {
        return MAGLEV_ERROR_ALIGNMENT as i32;
    }
    // SAFETY: non-null and valid by the caller's contract.
    unsafe {
        let s = &law::state::<I4F28>(state.cast()).inner;
        out.write(maglev_state_view_q28 {
            x: s.x.to_bits(),
            y: s.y.to_bits(),
            eta: s.eta.to_bits(),
            v: s.v.to_bits(),
        });
    }
    MAGLEV_OK as i32
}

/// `x` as Q4.28 (`round(x·2^28)`) into `*out`. Returns `MAGLEV_OK`, `MAGLEV_ERROR_NULL`, or
/// `MAGLEV_ERROR_RANGE` when `x` is NaN (then 0) or outside [−8, 8) (then the nearest end):
/// `*out` is written in both cases. The core's own conversion (`Scalar::from_f64`).
///
/// # Safety
/// `out` NULL or a writable `int32_t`.
#[no_mangle]
pub unsafe extern "C" fn maglev_q28_from_f64(x: f64, out: *mut i32) -> i32 {
    if out.is_null() {
        return MAGLEV_ERROR_NULL as i32;
    }
    if !out.is_aligned() {
        return MAGLEV_ERROR_ALIGNMENT as i32;
    }
    let mut saturated = false;
    let q = I4F28::from_f64(x, &mut saturated);
    // SAFETY: non-null and writable by the caller's contract.
    unsafe { out.write(q.to_bits()) };
    if saturated {
        MAGLEV_ERROR_RANGE as i32
    } else {
        MAGLEV_OK as i32
    }
}

/// The value of a Q4.28 number, `raw / 2^28`, exactly.
#[no_mangle]
pub extern "C" fn maglev_q28_to_f64(raw: i32) -> f64 {
    I4F28::from_bits(raw).to_f64()
}
