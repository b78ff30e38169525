//! Error codes: every fallible function returns an `int32_t`, 0 for success, otherwise the
//! [`maglev_error`] that names the argument or parameter field at fault.
//!
//! The core names a bad parameter as data ([`ParamError::field`]: its law and key);
//! [`from_param_error`] maps each core field to the field of [`crate::maglev_params`] that
//! holds it, so a C caller gets a number it can switch on and [`maglev_error_field_name`] / [`maglev_error_message`] turn it
//! back into text.

use core::ffi::c_char;
use maglev_core::ParamError;

/// Result of a C API call: 0 is success, any other value names what was refused.
#[allow(non_camel_case_types)]
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum maglev_error {
    /// Success.
    MAGLEV_OK = 0,
    /// A pointer argument is NULL.
    MAGLEV_ERROR_NULL = 1,
    /// `i0_A`: finite, > 0.
    MAGLEV_ERROR_I0 = 2,
    /// `h0_m`: finite, > 0.
    MAGLEV_ERROR_H0 = 3,
    /// `r0_ohm`: finite, > 0.
    MAGLEV_ERROR_R0 = 4,
    /// `kp_V_m_per_A`: finite, ≥ 0.
    MAGLEV_ERROR_KP = 5,
    /// `ki_V_m_per_A_s`: finite, ≥ 0.
    MAGLEV_ERROR_KI = 6,
    /// `p0_N`: finite, > 0.
    MAGLEV_ERROR_P0 = 7,
    /// `alpha`: in [0, 1].
    MAGLEV_ERROR_ALPHA = 8,
    /// `dt_s`: finite, > 0.
    MAGLEV_ERROR_DT = 9,
    /// `n_sub`: in [1, `MAGLEV_MAX_N_SUB`] (the control period budget, docs/c-api.md).
    MAGLEV_ERROR_N_SUB = 10,
    /// `interpolation`: `MAGLEV_INTERPOLATION_LINEAR` or `_PARABOLIC`.
    MAGLEV_ERROR_INTERPOLATION = 11,
    /// `v_max_V`: > 0 (`INFINITY` for no bound), not NaN.
    MAGLEV_ERROR_V_MAX = 12,
    /// `scheme`: `MAGLEV_SCHEME_PAPER` or `_ACCURATE`.
    MAGLEV_ERROR_SCHEME = 13,
    /// `law`: `MAGLEV_LAW_PAPER`, `_GAP_LOOP` or `_STATE`.
    MAGLEV_ERROR_LAW = 14,
    /// `gap_loop.kp`: finite.
    MAGLEV_ERROR_GAP_KP = 15,
    /// `gap_loop.kd_s`: finite.
    MAGLEV_ERROR_GAP_KD = 16,
    /// `gap_loop.tf_s`: finite, ≥ 0.
    MAGLEV_ERROR_GAP_TF = 17,
    /// `gap_loop.x_ref_max`: finite, > 0.
    MAGLEV_ERROR_GAP_X_REF_MAX = 18,
    /// `state.kp_V_per_m`: finite, ≥ 0.
    MAGLEV_ERROR_STATE_KP = 19,
    /// `state.kd_V_s_per_m`: finite, ≥ 0.
    MAGLEV_ERROR_STATE_KD = 20,
    /// `state.ka_V_s2_per_m`: finite, ≥ 0.
    MAGLEV_ERROR_STATE_KA = 21,
    /// `state.ki_V_per_m_s`: finite, ≥ 0.
    MAGLEV_ERROR_STATE_KI = 22,
    /// `state.kc_V_per_A`: finite, ≥ 0.
    MAGLEV_ERROR_STATE_KC = 23,
    /// `state.vmax_V`: finite, > `r0_ohm·i0_A`.
    MAGLEV_ERROR_STATE_V_MAX = 24,
    /// `state.rate_Hz`: finite, > 0 and at least 2π·`state.observer_Hz`.
    MAGLEV_ERROR_STATE_RATE = 25,
    /// `state.observer_Hz`: finite, > 0.
    MAGLEV_ERROR_STATE_OBSERVER = 26,
    /// `state.geometry`: `MAGLEV_GEOMETRY_PAPER` or `_EMS`.
    MAGLEV_ERROR_STATE_GEOMETRY = 27,
    /// The gap of a state initialisation (`gap_m`): finite, > 0, at most the law's range
    /// (100·`h0_m`; Q4.28: 3.6·`h0_m`).
    MAGLEV_ERROR_GAP = 28,
    /// The parameters are valid, but a run-time coefficient of the paper's law or the gap
    /// loop derived from them is not representable in this type to 1e-4 (Q4.28 with many
    /// sub-steps or a short `dt_s`).
    MAGLEV_ERROR_UNREPRESENTABLE = 29,
    /// A number converted to Q4.28 was NaN or outside ±8 (the result saturated).
    MAGLEV_ERROR_RANGE = 30,
    /// The law storage was not written by a successful `maglev_law_init_*`.
    MAGLEV_ERROR_NOT_INITIALIZED = 31,
    /// A parameter the core refused under a name this API does not know (a newer core).
    MAGLEV_ERROR_OTHER = 32,
    /// `state.rate_Hz`·`dt_s`: at most 10000 control periods in one update (the state law's
    /// budget, `maglev_core::law::state::MAX_PERIODS`).
    MAGLEV_ERROR_STATE_PERIODS = 33,
    /// A state-law coefficient per unit (its gains `kp·h0/Vb`, `kd·h0/Vb`, `ka·g/Vb`,
    /// `kc·i0/Vb`, `ki·h0·δ/Vb`, its observer's `2ω·δ`, `ω²·δ`) is outside the type's range
    /// (Q4.28: [−8, 8)) or below its resolution to 1e-4: use `float`, or smaller gains.
    MAGLEV_ERROR_STATE_UNREPRESENTABLE = 34,
    /// A storage pointer is not aligned for its type (law and state: `MAGLEV_ALIGN`;
    /// measurement and output: 4).
    MAGLEV_ERROR_ALIGNMENT = 35,
    /// `maglev_guidance_params.kp_V_per_m`: finite, ≥ 0.
    MAGLEV_ERROR_GUIDANCE_KP = 36,
    /// `maglev_guidance_params.kd_V_s_per_m`: finite, ≥ 0.
    MAGLEV_ERROR_GUIDANCE_KD = 37,
    /// `maglev_guidance_params.ka_V_s2_per_m`: finite, ≥ 0.
    MAGLEV_ERROR_GUIDANCE_KA = 38,
    /// `maglev_guidance_params.ki_V_per_m_s`: finite, ≥ 0.
    MAGLEV_ERROR_GUIDANCE_KI = 39,
    /// `maglev_guidance_params.kc_V_per_A`: finite, ≥ 0.
    MAGLEV_ERROR_GUIDANCE_KC = 40,
}

use maglev_error::*;

/// Every code, in order of value.
const ALL: [maglev_error; 41] = [
    MAGLEV_OK,
    MAGLEV_ERROR_NULL,
    MAGLEV_ERROR_I0,
    MAGLEV_ERROR_H0,
    MAGLEV_ERROR_R0,
    MAGLEV_ERROR_KP,
    MAGLEV_ERROR_KI,
    MAGLEV_ERROR_P0,
    MAGLEV_ERROR_ALPHA,
    MAGLEV_ERROR_DT,
    MAGLEV_ERROR_N_SUB,
    MAGLEV_ERROR_INTERPOLATION,
    MAGLEV_ERROR_V_MAX,
    MAGLEV_ERROR_SCHEME,
    MAGLEV_ERROR_LAW,
    MAGLEV_ERROR_GAP_KP,
    MAGLEV_ERROR_GAP_KD,
    MAGLEV_ERROR_GAP_TF,
    MAGLEV_ERROR_GAP_X_REF_MAX,
    MAGLEV_ERROR_STATE_KP,
    MAGLEV_ERROR_STATE_KD,
    MAGLEV_ERROR_STATE_KA,
    MAGLEV_ERROR_STATE_KI,
    MAGLEV_ERROR_STATE_KC,
    MAGLEV_ERROR_STATE_V_MAX,
    MAGLEV_ERROR_STATE_RATE,
    MAGLEV_ERROR_STATE_OBSERVER,
    MAGLEV_ERROR_STATE_GEOMETRY,
    MAGLEV_ERROR_GAP,
    MAGLEV_ERROR_UNREPRESENTABLE,
    MAGLEV_ERROR_RANGE,
    MAGLEV_ERROR_NOT_INITIALIZED,
    MAGLEV_ERROR_OTHER,
    MAGLEV_ERROR_STATE_PERIODS,
    MAGLEV_ERROR_STATE_UNREPRESENTABLE,
    MAGLEV_ERROR_ALIGNMENT,
    MAGLEV_ERROR_GUIDANCE_KP,
    MAGLEV_ERROR_GUIDANCE_KD,
    MAGLEV_ERROR_GUIDANCE_KA,
    MAGLEV_ERROR_GUIDANCE_KI,
    MAGLEV_ERROR_GUIDANCE_KC,
];

impl maglev_error {
    /// The field (or argument) at fault, and what it must be.
    pub const fn texts(self) -> (&'static core::ffi::CStr, &'static core::ffi::CStr) {
        match self {
            MAGLEV_OK => (c"none", c"ok"),
            MAGLEV_ERROR_NULL => (c"(pointer argument)", c"a pointer argument is NULL"),
            MAGLEV_ERROR_I0 => (c"i0_A", c"i0_A must be finite and > 0"),
            MAGLEV_ERROR_H0 => (c"h0_m", c"h0_m must be finite and > 0"),
            MAGLEV_ERROR_R0 => (c"r0_ohm", c"r0_ohm must be finite and > 0"),
            MAGLEV_ERROR_KP => (c"kp_V_m_per_A", c"kp_V_m_per_A must be finite and >= 0"),
            MAGLEV_ERROR_KI => (c"ki_V_m_per_A_s", c"ki_V_m_per_A_s must be finite and >= 0"),
            MAGLEV_ERROR_P0 => (c"p0_N", c"p0_N must be finite and > 0"),
            MAGLEV_ERROR_ALPHA => (c"alpha", c"alpha must lie in [0, 1]"),
            MAGLEV_ERROR_DT => (c"dt_s", c"dt_s must be finite and > 0"),
            MAGLEV_ERROR_N_SUB => (c"n_sub", c"n_sub must lie in [1, 100000] (MAGLEV_MAX_N_SUB)"),
            MAGLEV_ERROR_INTERPOLATION => (
                c"interpolation",
                c"interpolation must be MAGLEV_INTERPOLATION_LINEAR (0) or _PARABOLIC (1)",
            ),
            MAGLEV_ERROR_V_MAX => (
                c"v_max_V",
                c"v_max_V must be > 0 (INFINITY: no bound) and not NaN",
            ),
            MAGLEV_ERROR_SCHEME => (
                c"scheme",
                c"scheme must be MAGLEV_SCHEME_PAPER (0) or _ACCURATE (1)",
            ),
            MAGLEV_ERROR_LAW => (
                c"law",
                c"law must be MAGLEV_LAW_PAPER (0), _GAP_LOOP (1) or _STATE (2)",
            ),
            MAGLEV_ERROR_GAP_KP => (c"gap_loop.kp", c"gap_loop.kp must be finite"),
            MAGLEV_ERROR_GAP_KD => (c"gap_loop.kd_s", c"gap_loop.kd_s must be finite"),
            MAGLEV_ERROR_GAP_TF => (c"gap_loop.tf_s", c"gap_loop.tf_s must be finite and >= 0"),
            MAGLEV_ERROR_GAP_X_REF_MAX => (
                c"gap_loop.x_ref_max",
                c"gap_loop.x_ref_max must be finite and > 0",
            ),
            MAGLEV_ERROR_STATE_KP => (
                c"state.kp_V_per_m",
                c"state.kp_V_per_m must be finite and >= 0",
            ),
            MAGLEV_ERROR_STATE_KD => (
                c"state.kd_V_s_per_m",
                c"state.kd_V_s_per_m must be finite and >= 0",
            ),
            MAGLEV_ERROR_STATE_KA => (
                c"state.ka_V_s2_per_m",
                c"state.ka_V_s2_per_m must be finite and >= 0",
            ),
            MAGLEV_ERROR_STATE_KI => (
                c"state.ki_V_per_m_s",
                c"state.ki_V_per_m_s must be finite and >= 0",
            ),
            MAGLEV_ERROR_STATE_KC => (
                c"state.kc_V_per_A",
                c"state.kc_V_per_A must be finite and >= 0",
            ),
            MAGLEV_ERROR_STATE_V_MAX => (
                c"state.vmax_V",
                c"state.vmax_V must be finite and > r0_ohm * i0_A",
            ),
            MAGLEV_ERROR_STATE_RATE => (
                c"state.rate_Hz",
                c"state.rate_Hz must be finite, > 0 and >= 2*pi*state.observer_Hz",
            ),
            MAGLEV_ERROR_STATE_OBSERVER => (
                c"state.observer_Hz",
                c"state.observer_Hz must be finite and > 0",
            ),
            MAGLEV_ERROR_STATE_GEOMETRY => (
                c"state.geometry",
                c"state.geometry must be MAGLEV_GEOMETRY_PAPER (0) or _EMS (1)",
            ),
            MAGLEV_ERROR_GAP => (
                c"gap_m",
                c"gap_m must be finite, > 0 and at most the law's range (100 h0_m; Q4.28: 3.6 h0_m)",
            ),
            MAGLEV_ERROR_UNREPRESENTABLE => (
                c"(derived coefficient)",
                c"a sub-step coefficient of the paper's law or the gap loop is not representable in this type to 1e-4: use fewer sub-steps, a longer dt_s or f32",
            ),
            MAGLEV_ERROR_RANGE => (
                c"(value)",
                c"the value is NaN or outside the Q4.28 range [-8, 8) and saturated",
            ),
            MAGLEV_ERROR_NOT_INITIALIZED => (
                c"(law)",
                c"the law was not written by a successful maglev_law_init_*",
            ),
            MAGLEV_ERROR_OTHER => (
                c"(parameter)",
                c"the core refused a parameter this API does not name",
            ),
            MAGLEV_ERROR_STATE_PERIODS => (
                c"state.rate_Hz*dt_s",
                c"state.rate_Hz * dt_s must be at most 10000 control periods per update",
            ),
            MAGLEV_ERROR_STATE_UNREPRESENTABLE => (
                c"state",
                c"a state-law gain or observer coefficient per unit is outside this type's range (Q4.28: [-8, 8)) or below its resolution: use float or smaller gains",
            ),
            MAGLEV_ERROR_ALIGNMENT => (
                c"(pointer alignment)",
                c"a storage pointer is misaligned: law and state need MAGLEV_ALIGN (8) bytes, measurement and output 4",
            ),
            MAGLEV_ERROR_GUIDANCE_KP => (
                c"guidance.kp_V_per_m",
                c"guidance.kp_V_per_m must be finite and >= 0",
            ),
            MAGLEV_ERROR_GUIDANCE_KD => (
                c"guidance.kd_V_s_per_m",
                c"guidance.kd_V_s_per_m must be finite and >= 0",
            ),
            MAGLEV_ERROR_GUIDANCE_KA => (
                c"guidance.ka_V_s2_per_m",
                c"guidance.ka_V_s2_per_m must be finite and >= 0",
            ),
            MAGLEV_ERROR_GUIDANCE_KI => (
                c"guidance.ki_V_per_m_s",
                c"guidance.ki_V_per_m_s must be finite and >= 0",
            ),
            MAGLEV_ERROR_GUIDANCE_KC => (
                c"guidance.kc_V_per_A",
                c"guidance.kc_V_per_A must be finite and >= 0",
            ),
        }
    }

    /// The code of an `int32_t` a caller passes back (`None`: no such code).
    pub fn from_code(code: i32) -> Option<maglev_error> {
        usize::try_from(code).ok().and_then(|i| ALL.get(i).copied())
    }
}

/// The name under which the state law refuses more than `MAX_PERIODS` control periods per
/// update (`maglev_core::law::state`; `tests/api.rs` checks the code it maps to).
const PERIODS: &str = "10 000 − state rate_hz·dt (control periods per step)";

/// The field of [`crate::maglev_params`] (or the gap argument) a core error names.
pub fn from_param_error(e: &ParamError) -> maglev_error {
    use maglev_core::gap_control::fields as gap;
    use maglev_core::law::state::fields as state;
    use maglev_core::levitation::fields as magnet;
    let field = e.field();
    if field.is(magnet::GAP) {
        return MAGLEV_ERROR_GAP;
    }
    if let ParamError::Unrepresentable { .. } = e {
        return if field.law == Some(maglev_core::LawName::State) {
            MAGLEV_ERROR_STATE_UNREPRESENTABLE
        } else {
            MAGLEV_ERROR_UNREPRESENTABLE
        };
    }
    if field.is(state::RATE) && field.name == PERIODS {
        return MAGLEV_ERROR_STATE_PERIODS;
    }
    // Each core field ([`maglev_core::Field`], law and key) and the code of the C field
    // that holds it.
    let codes = [
        (magnet::I0, MAGLEV_ERROR_I0),
        (magnet::H0, MAGLEV_ERROR_H0),
        (magnet::R0, MAGLEV_ERROR_R0),
        (magnet::KP, MAGLEV_ERROR_KP),
        (magnet::KI, MAGLEV_ERROR_KI),
        (magnet::P0, MAGLEV_ERROR_P0),
        (magnet::ALPHA, MAGLEV_ERROR_ALPHA),
        (magnet::DT, MAGLEV_ERROR_DT),
        (magnet::N_SUB, MAGLEV_ERROR_N_SUB),
        (magnet::V_MAX, MAGLEV_ERROR_V_MAX),
        (gap::KP, MAGLEV_ERROR_GAP_KP),
        (gap::KD, MAGLEV_ERROR_GAP_KD),
        (gap::TF, MAGLEV_ERROR_GAP_TF),
        (gap::X_REF_MAX, MAGLEV_ERROR_GAP_X_REF_MAX),
        (state::KP, MAGLEV_ERROR_STATE_KP),
        (state::KD, MAGLEV_ERROR_STATE_KD),
        (state::KA, MAGLEV_ERROR_STATE_KA),
        (state::KI, MAGLEV_ERROR_STATE_KI),
        (state::KC, MAGLEV_ERROR_STATE_KC),
        (state::V_MAX, MAGLEV_ERROR_STATE_V_MAX),
        (state::RATE, MAGLEV_ERROR_STATE_RATE),
        (state::OBSERVER, MAGLEV_ERROR_STATE_OBSERVER),
    ];
    codes
        .iter()
        .find(|(f, _)| field.is(*f))
        .map_or(MAGLEV_ERROR_OTHER, |&(_, code)| code)
}

/// The name of the field (or argument) an error code names, as the C structs spell it
/// (`"i0_A"`, `"gap_loop.tf_s"`, `"state.rate_Hz"`); `"none"` for `MAGLEV_OK`, `"unknown"` for
/// a value that is no code. A static NUL-terminated string; never NULL.
#[no_mangle]
pub extern "C" fn maglev_error_field_name(code: i32) -> *const c_char {
    match maglev_error::from_code(code) {
        Some(e) => e.texts().0.as_ptr(),
        None => c"unknown".as_ptr(),
    }
}

/// One line saying what the field an error code names must be
/// (`"h0_m must be finite and > 0"`); `"unknown error code"` for a value that is no code.
/// A static NUL-terminated string; never NULL.
#[no_mangle]
pub extern "C" fn maglev_error_message(code: i32) -> *const c_char {
    match maglev_error::from_code(code) {
        Some(e) => e.texts().1.as_ptr(),
        None => c"unknown error code".as_ptr(),
    }
}
