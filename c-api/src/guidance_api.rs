//! The guidance law (`maglev_core::law::guidance`, docs/levitation.md "The guidance law") for
//! C: one controller for both magnets of a guidance pair, in `float` (the state law's timing
//! and supply, which Q4.28 cannot carry: its observer's `ω²·δ`).
//!
//! # Shape
//! `maglev_params` (the magnet with `law = MAGLEV_LAW_STATE`: timing, supply, geometry) and
//! `maglev_guidance_params` (the pair's five gains) → `maglev_guidance_init_f32` →
//! `maglev_guidance_state_init_f32(law, d_m, state)` → `maglev_guidance_update_f32(law,
//! state, measurement, output)` once per step. The law lives in opaque storage of
//! [`crate::MAGLEV_LAW_SIZE`] bytes; the state is a plain struct,
//! [`maglev_guidance_state_f32`], field for field the core's `GuidanceState<f32>`
//! (`tests/mirror.rs` checks both mirrors against the core).

use crate::error::{from_param_error, maglev_error::*};
use crate::f32_api::maglev_output_f32;
use crate::law::{MAGLEV_ALIGN, MAGLEV_LAW_SIZE, MAGLEV_LAW_WORDS};
use crate::maglev_error;
use crate::params::{maglev_params, MAGLEV_LAW_STATE};
use maglev_core::gap::Geometry;
use maglev_core::law::guidance::{
    fields, GuidanceLaw, GuidanceParams, GuidanceState, PairMeasurement,
};
use maglev_core::levitation::{Output, State};
use maglev_core::ParamError;

/// The guidance law's gains on the pair's differential mode, SI (`maglev_core`'s
/// `GuidanceParams`; the keys of `[controller.guidance]`).
#[allow(non_camel_case_types, non_snake_case)]
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct maglev_guidance_params {
    /// Lateral offset gain (V/m), ≥ 0.
    pub kp_V_per_m: f64,
    /// Lateral rate gain (V·s/m), ≥ 0.
    pub kd_V_s_per_m: f64,
    /// Lateral acceleration gain (V·s²/m), ≥ 0.
    pub ka_V_s2_per_m: f64,
    /// Integral gain on the lateral offset (V/(m·s)), ≥ 0.
    pub ki_V_per_m_s: f64,
    /// Current gain on both modes (V/A), ≥ 0.
    pub kc_V_per_A: f64,
}

impl maglev_guidance_params {
    /// The core's gains.
    pub fn to_core(&self) -> GuidanceParams {
        GuidanceParams {
            kp: self.kp_V_per_m,
            kd: self.kd_V_s_per_m,
            ka: self.ka_V_s2_per_m,
            ki: self.ki_V_per_m_s,
            kc: self.kc_V_per_A,
        }
    }
}

/// One coil of a pair (`float`), per unit deviations: the core's `State<f32>`.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct maglev_coil_state_f32 {
    /// `g/g0 − 1`.
    pub x: f32,
    /// The coil's voltage less 1, per unit, held over the period.
    pub y: f32,
    /// `h/h0_m − 1` of the last sample.
    pub eta: f32,
    /// `h/h0_m − 1` one step earlier (unused by the guidance law).
    pub eta_prev: f32,
    /// Coil voltage `V/(r0_ohm·i0_A)` at the end of the last step.
    pub v: f32,
}

/// A guidance pair's state (`float`): the core's `GuidanceState<f32>`.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct maglev_guidance_state_f32 {
    /// Left coil (gap `h0 + d`).
    pub left: maglev_coil_state_f32,
    /// Right coil (gap `h0 − d`).
    pub right: maglev_coil_state_f32,
    /// The integral's voltage, per unit.
    pub integral: f32,
    /// Observer: estimated `d/h0_m`.
    pub eta_est: f32,
    /// Observer: its rate (1/s).
    pub rate_est: f32,
    /// `a_y/g_n` of the last sample.
    pub accel: f32,
}

/// What the pair's law reads at the end of a step, per unit.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct maglev_pair_measurement_f32 {
    /// Lateral offset `d/h0_m` (the left gap is `h0·(1 + d)`, the right `h0·(1 − d)`).
    pub d_pu: f32,
    /// The magnet's absolute lateral acceleration `a_y/g_n` (+Y opens the left gap); read if
    /// `flags & MAGLEV_MEASURED_ACCEL`.
    pub accel_y_g: f32,
    /// `MAGLEV_MEASURED_ACCEL` or 0.
    pub flags: u32,
}

/// One pair update's result: each magnet's output and the net lateral force.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct maglev_pair_output_f32 {
    /// Left magnet.
    pub left: maglev_output_f32,
    /// Right magnet.
    pub right: maglev_output_f32,
    /// Net lateral force on the wheel, per unit of `p0_N`, along +Y.
    pub force_y_pu: f32,
    /// `MAGLEV_STATUS_*` bits of the pair (both magnets, and `_VOLTAGE_SATURATED` when
    /// either coil's voltage was clamped).
    pub status: u32,
}

/// A compiled guidance law (`float`), caller-owned: `MAGLEV_LAW_SIZE` bytes, aligned to
/// `MAGLEV_ALIGN`. Written by `maglev_guidance_init_f32`; read-only afterwards.
#[allow(non_camel_case_types)]
#[repr(C)]
pub struct maglev_guidance_law_f32 {
    /// Opaque.
    pub opaque: [u64; MAGLEV_LAW_WORDS],
}

/// The tag before a guidance law in its storage (a levitation law, or bytes no init wrote,
/// are refused).
const TAG: u32 = 0x6d67_6a30;

#[repr(C)]
struct Stored {
    tag: u32,
    geometry: Geometry,
    law: GuidanceLaw<f32>,
}

const _: () = {
    assert!(core::mem::size_of::<Stored>() <= MAGLEV_LAW_SIZE);
    assert!(core::mem::align_of::<Stored>() <= MAGLEV_ALIGN);
};

/// The C field of a guidance gain the core refused.
fn guidance_error(e: &ParamError) -> maglev_error {
    let field = e.field();
    let codes = [
        (fields::KP, MAGLEV_ERROR_GUIDANCE_KP),
        (fields::KD, MAGLEV_ERROR_GUIDANCE_KD),
        (fields::KA, MAGLEV_ERROR_GUIDANCE_KA),
        (fields::KI, MAGLEV_ERROR_GUIDANCE_KI),
        (fields::KC, MAGLEV_ERROR_GUIDANCE_KC),
    ];
    // The guidance gains share the state law's keys: told apart by the whole field.
    codes
        .iter()
        .find(|(f, _)| *f == field)
        .map_or(MAGLEV_ERROR_OTHER, |&(_, code)| code)
}

/// The law, or the code of what is wrong with the arguments.
fn compile(p: &maglev_params, g: &maglev_guidance_params) -> Result<Stored, maglev_error> {
    if p.law != MAGLEV_LAW_STATE {
        return Err(MAGLEV_ERROR_LAW);
    }
    let lp = p.to_core()?;
    let timing = lp.kind.state().ok_or(MAGLEV_ERROR_LAW)?;
    let gains = g.to_core();
    gains.validate().map_err(|e| guidance_error(&e))?;
    let law = gains
        .compile::<f32>(timing, &lp.magnet)
        .map_err(|e| from_param_error(&e))?;
    Ok(Stored {
        tag: TAG,
        geometry: timing.geometry,
        law,
    })
}

/// The law at `law` if `maglev_guidance_init_f32` wrote it.
///
/// # Safety
/// `law` non-null, aligned, readable for `MAGLEV_LAW_SIZE` bytes.
unsafe fn get<'a>(law: *const maglev_guidance_law_f32) -> Option<&'a Stored> {
    // SAFETY: the first word is readable; after a matching tag the rest is what init wrote.
    unsafe { (law.cast::<u32>().read() == TAG).then(|| &*law.cast::<Stored>()) }
}

/// Checks `*params` (the magnet, with `law = MAGLEV_LAW_STATE`: the pair shares the state
/// law's timing, supply and geometry; the state law's own gains are not used) and `*gains`,
/// and compiles the pair's law into `*out`. Returns `MAGLEV_OK`, `MAGLEV_ERROR_NULL`,
/// `MAGLEV_ERROR_ALIGNMENT`, `MAGLEV_ERROR_LAW` (not the state law), or the code of the first
/// bad field (`MAGLEV_ERROR_GUIDANCE_*` for a gain); on failure `*out` is marked
/// uninitialised.
///
/// # Safety
/// `params`, `gains` NULL or readable; `out` NULL or a writable `maglev_guidance_law_f32`.
#[no_mangle]
pub unsafe extern "C" fn maglev_guidance_init_f32(
    params: *const maglev_params,
    gains: *const maglev_guidance_params,
    out: *mut maglev_guidance_law_f32,
) -> i32 {
    if params.is_null() || gains.is_null() || out.is_null() {
        return MAGLEV_ERROR_NULL as i32;
    }
    if !(params.is_aligned() && gains.is_aligned() && out.is_aligned()) {
        return MAGLEV_ERROR_ALIGNMENT as i32;
    }
    // SAFETY: non-null, aligned, readable by the contract; every bit pattern of the fields
    // is a valid f64/u32.
    let (p, g) = unsafe { (params.read(), gains.read()) };
    match compile(&p, &g) {
        Ok(stored) => {
            // SAFETY: large and aligned enough (const assertions), writable.
            unsafe { out.cast::<Stored>().write(stored) };
            MAGLEV_OK as i32
        }
        Err(e) => {
            // SAFETY: writable; a zero tag marks it uninitialised.
            unsafe { out.cast::<u32>().write(0) };
            e as i32
        }
    }
}

/// Writes into `*out` both magnets in equilibrium at lateral offset `d_m` (m; the gaps
/// `h0_m ± d_m`), the integral holding them there. Returns `MAGLEV_OK`, `MAGLEV_ERROR_NULL`,
/// `MAGLEV_ERROR_ALIGNMENT`, `MAGLEV_ERROR_NOT_INITIALIZED` or `MAGLEV_ERROR_GAP` (`d_m` NaN,
/// or a gap ≤ 0: `|d_m| ≥ h0_m`).
///
/// # Safety
/// `law` NULL or a `maglev_guidance_law_f32`; `out` NULL or a writable
/// `maglev_guidance_state_f32`.
#[no_mangle]
pub unsafe extern "C" fn maglev_guidance_state_init_f32(
    law: *const maglev_guidance_law_f32,
    d_m: f64,
    out: *mut maglev_guidance_state_f32,
) -> i32 {
    if law.is_null() || out.is_null() {
        return MAGLEV_ERROR_NULL as i32;
    }
    if !law.is_aligned() || !out.is_aligned() {
        return MAGLEV_ERROR_ALIGNMENT as i32;
    }
    // SAFETY: the contract.
    let Some(s) = (unsafe { get(law) }) else {
        return MAGLEV_ERROR_NOT_INITIALIZED as i32;
    };
    let h0 = s.law.coil().params().h0;
    if d_m.is_nan() || d_m.abs() >= h0 {
        return MAGLEV_ERROR_GAP as i32;
    }
    // SAFETY: writable by the contract.
    unsafe { out.write(to_c(&s.law.equilibrium(d_m))) };
    MAGLEV_OK as i32
}

/// One step `dt_s` of the pair from `*state` to the measurement `*m` at its end; writes the
/// outputs to `*out`. Returns `MAGLEV_OK`, `MAGLEV_ERROR_NULL`, `MAGLEV_ERROR_ALIGNMENT` or
/// `MAGLEV_ERROR_NOT_INITIALIZED` (then nothing is written). Events are `out->status` bits.
///
/// # Safety
/// Each pointer NULL or valid for its type; `state` and `out` do not overlap the others.
#[no_mangle]
pub unsafe extern "C" fn maglev_guidance_update_f32(
    law: *const maglev_guidance_law_f32,
    state: *mut maglev_guidance_state_f32,
    m: *const maglev_pair_measurement_f32,
    out: *mut maglev_pair_output_f32,
) -> i32 {
    if law.is_null() || state.is_null() || m.is_null() || out.is_null() {
        return MAGLEV_ERROR_NULL as i32;
    }
    if !(law.is_aligned() && state.is_aligned() && m.is_aligned() && out.is_aligned()) {
        return MAGLEV_ERROR_ALIGNMENT as i32;
    }
    // SAFETY: non-null, aligned and valid by the contract.
    unsafe {
        let Some(s) = get(law) else {
            return MAGLEV_ERROR_NOT_INITIALIZED as i32;
        };
        let m = m.read();
        let meas = PairMeasurement {
            d: m.d_pu,
            accel: (m.flags & crate::MAGLEV_MEASURED_ACCEL != 0).then_some(m.accel_y_g),
        };
        let mut st = from_c(&state.read());
        let o = s.law.update(&mut st, meas, s.geometry);
        state.write(to_c(&st));
        out.write(maglev_pair_output_f32 {
            left: output(&o.left),
            right: output(&o.right),
            force_y_pu: o.force_y,
            status: o.status.0 as u32,
        });
    }
    MAGLEV_OK as i32
}

fn output(o: &Output<f32>) -> maglev_output_f32 {
    maglev_output_f32 {
        g_pu: o.g,
        force_pu: o.force,
        current_pu: o.current,
        voltage_pu: o.voltage,
        status: o.status.0 as u32,
    }
}

fn coil_to_c(s: &State<f32>) -> maglev_coil_state_f32 {
    let &State {
        x,
        y,
        eta,
        eta_prev,
        v,
    } = s;
    maglev_coil_state_f32 {
        x,
        y,
        eta,
        eta_prev,
        v,
    }
}

fn coil_from_c(s: &maglev_coil_state_f32) -> State<f32> {
    let &maglev_coil_state_f32 {
        x,
        y,
        eta,
        eta_prev,
        v,
    } = s;
    State {
        x,
        y,
        eta,
        eta_prev,
        v,
    }
}

/// The core's state as C holds it (every field, destructured: a field added to the core's
/// state fails to compile here until it is mirrored).
pub fn to_c(s: &GuidanceState<f32>) -> maglev_guidance_state_f32 {
    let GuidanceState {
        left,
        right,
        integral,
        eta_est,
        rate_est,
        accel,
    } = s;
    maglev_guidance_state_f32 {
        left: coil_to_c(left),
        right: coil_to_c(right),
        integral: *integral,
        eta_est: *eta_est,
        rate_est: *rate_est,
        accel: *accel,
    }
}

/// C's state as the core's.
pub fn from_c(s: &maglev_guidance_state_f32) -> GuidanceState<f32> {
    let maglev_guidance_state_f32 {
        left,
        right,
        integral,
        eta_est,
        rate_est,
        accel,
    } = s;
    GuidanceState {
        left: coil_from_c(left),
        right: coil_from_c(right),
        integral: *integral,
        eta_est: *eta_est,
        rate_est: *rate_est,
        accel: *accel,
    }
}
