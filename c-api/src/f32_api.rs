//! The `float` variant: the core's laws in IEEE single precision (the Cortex-M4F's FPU).
//!
//! Measurements, outputs and states are per unit, as the core runs them: the gap `h/h0_m`, the
//! acceleration in units of g_n = 9.81 m/s² (Z up), the current `i/i0_A`. Multiply an output
//! by its base for SI: `g_pu·i0_A/h0_m` (A/m), `force_pu·p0_N` (N), `current_pu·i0_A` (A),
//! `voltage_pu·r0_ohm·i0_A` (V).

use crate::error::maglev_error::*;
use crate::law::{self, MAGLEV_LAW_WORDS, MAGLEV_STATE_WORDS};
use crate::params::maglev_params;

/// A compiled law (`float`), caller-owned: `MAGLEV_LAW_SIZE` bytes, aligned to `MAGLEV_ALIGN`.
/// Written by `maglev_law_init_f32`; read-only afterwards; one law may drive many states.
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct maglev_law_f32 {
    /// Opaque.
    pub opaque: [u64; MAGLEV_LAW_WORDS],
}

/// One magnet's controller state (`float`), caller-owned: `MAGLEV_STATE_SIZE` bytes.
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct maglev_state_f32 {
    /// Opaque.
    pub opaque: [u64; MAGLEV_STATE_WORDS],
}

/// What a law reads at the end of a step, per unit.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct maglev_measurement_f32 {
    /// Gap `h/h0_m` (dimensionless). ≤ 0 is a collision; above 100 it is clamped and flagged
    /// `MAGLEV_STATUS_INVALID_INPUT`; NaN raises `_INVALID_INPUT` (the paper's law and the
    /// gap loop hold their state) or `_OVERFLOW` (the state law).
    pub gap_pu: f32,
    /// The magnet's absolute vertical acceleration `a/g_n` (g_n = 9.81 m/s², Z up); read if
    /// `flags & MAGLEV_MEASURED_ACCEL` (the state law uses it).
    pub accel_g: f32,
    /// Coil current `i/i0_A`; read if `flags & MAGLEV_MEASURED_CURRENT` (no law yet feeds it
    /// back: every law integrates its own coil).
    pub current_pu: f32,
    /// `MAGLEV_MEASURED_*` bits.
    pub flags: u32,
}

/// One update's result, per unit; SI: `g_pu·i0_A/h0_m` (A/m), `force_pu·p0_N` (N),
/// `current_pu·i0_A` (A), `voltage_pu·r0_ohm·i0_A` (V).
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct maglev_output_f32 {
    /// `g/g0`, g = i/h (A/m), g0 = i0_A/h0_m.
    pub g_pu: f32,
    /// Magnet force `G/p0_N` (Eq. 1), upward on the magnet.
    pub force_pu: f32,
    /// Coil current `i/i0_A`.
    pub current_pu: f32,
    /// Coil voltage `V/(r0_ohm·i0_A)`.
    pub voltage_pu: f32,
    /// `MAGLEV_STATUS_*` bits raised in this step (0: none).
    pub status: u32,
}

/// The paper law's part of a state, per unit deviations from equilibrium.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct maglev_state_view_f32 {
    /// `g/g0 − 1`.
    pub x: f32,
    /// `KI·e_a/(r0_ohm·i0_A) − 1` (the integral's voltage, per unit).
    pub y: f32,
    /// `h/h0_m − 1` at the end of the last step.
    pub eta: f32,
    /// Coil voltage `V/(r0_ohm·i0_A)` at the end of the last step.
    pub v: f32,
}

/// Checks `*params` and compiles it into `*out` (f32). Returns `MAGLEV_OK`, or the code of
/// the first bad field (`maglev_error_field_name`); on failure `*out` is marked uninitialised.
/// No allocation; runs the parameter checks and the conversion in double precision once.
///
/// # Safety
/// `params` NULL or a readable `maglev_params`; `out` NULL or a writable `maglev_law_f32`.
#[no_mangle]
pub unsafe extern "C" fn maglev_law_init_f32(
    params: *const maglev_params,
    out: *mut maglev_law_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { law::init::<f32>(params, out.cast()) as i32 }
}

/// Writes into `*out` the law's equilibrium state at gap `gap_m` (m): the coil at the static
/// load `p0_N`, every filter at rest there. Returns `MAGLEV_OK`, `MAGLEV_ERROR_NULL`,
/// `MAGLEV_ERROR_ALIGNMENT`, `MAGLEV_ERROR_NOT_INITIALIZED` or `MAGLEV_ERROR_GAP` (NaN, ≤ 0 or beyond the law's range:
/// 100·`h0_m`, Q4.28 3.6·`h0_m`).
///
/// # Safety
/// `law` NULL or a `maglev_law_f32`; `out` NULL or a writable `maglev_state_f32`.
#[no_mangle]
pub unsafe extern "C" fn maglev_state_init_f32(
    law: *const maglev_law_f32,
    gap_m: f64,
    out: *mut maglev_state_f32,
) -> i32 {
    // SAFETY: forwarded contract.
    unsafe { law::state_init::<f32>(law.cast(), gap_m, out.cast()) as i32 }
}

/// One step Δt = `dt_s` of the law: from `*state` to the measurement `*m` at the step's end;
/// writes the step's outputs to `*out`. Returns `MAGLEV_OK`, `MAGLEV_ERROR_NULL`,
/// `MAGLEV_ERROR_ALIGNMENT` or `MAGLEV_ERROR_NOT_INITIALIZED` (then nothing is written).
/// Events of the step (collision, saturation, overflow, a NaN gap) are not errors: they are
/// `out->status` bits, and no NaN or infinity is ever written. No allocation, no recursion, bounded time.
///
/// # Safety
/// Each pointer NULL or valid for its type; `state` and `out` do not overlap the others.
#[no_mangle]
pub unsafe extern "C" fn maglev_law_update_f32(
    law: *const maglev_law_f32,
    state: *mut maglev_state_f32,
    m: *const maglev_measurement_f32,
    out: *mut maglev_output_f32,
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
        let meas = || law::measurement::<f32>(m.gap_pu, m.accel_g, m.current_pu, m.flags);
        match law::update::<f32>(law.cast(), state.cast(), meas, m.gap_pu) {
            Some(o) => {
                out.write(maglev_output_f32 {
                    g_pu: o.g,
                    force_pu: o.force,
                    current_pu: o.current,
                    voltage_pu: o.voltage,
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
/// `state` NULL or a `maglev_state_f32`; `out` NULL or a writable `maglev_state_view_f32`.
#[no_mangle]
pub unsafe extern "C" fn maglev_state_read_f32(
    state: *const maglev_state_f32,
    out: *mut maglev_state_view_f32,
) -> i32 {
    if state.is_null() || out.is_null() {
        return MAGLEV_ERROR_NULL as i32;
    }
    if !state.is_aligned() || !out.is_aligned() {
        return MAGLEV_ERROR_ALIGNMENT as i32;
    }
    // SAFETY: non-null and valid by the caller's contract.
    unsafe {
        let s = &law::state::<f32>(state.cast()).inner;
        out.write(maglev_state_view_f32 {
            x: s.x,
            y: s.y,
            eta: s.eta,
            v: s.v,
        });
    }
    MAGLEV_OK as i32
}
