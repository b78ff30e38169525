//! The parameters struct C fills in, and its one conversion to the core's [`LawParams`].
//!
//! Every field is a plain number (`double`, `uint32_t`): C can write any bit pattern into it,
//! so the enumerations (interpolation, scheme, law, geometry) are `uint32_t` codes checked here
//! rather than Rust enums (an out-of-range discriminant would be undefined behaviour). The
//! numeric checks are the core's own ([`LawParams::compile`]); this module only names the
//! field of an error ([`crate::error::from_param_error`]).

use crate::error::maglev_error::{self, *};
use maglev_core::gap::Geometry;
use maglev_core::gap_control::GapParams;
use maglev_core::law::state::StateParams;
use maglev_core::{Interpolation, LawKind, LawParams, Params, Scheme};

/// `interpolation`: the gap is linear across the step.
pub const MAGLEV_INTERPOLATION_LINEAR: u32 = 0;
/// `interpolation`: the parabola through the last three gaps.
pub const MAGLEV_INTERPOLATION_PARABOLIC: u32 = 1;
/// `scheme`: the paper's Eq. 14, `n_sub` times per step.
pub const MAGLEV_SCHEME_PAPER: u32 = 0;
/// `scheme`: order-4 Gauss–Legendre on the same equations (ignores `n_sub` and `alpha`).
pub const MAGLEV_SCHEME_ACCURATE: u32 = 1;
/// `law`: the paper's PI law on `g = i/h` (Eq. 8–14).
pub const MAGLEV_LAW_PAPER: u32 = 0;
/// `law`: an outer gap loop around the paper's law (`gap_loop` holds its gains).
pub const MAGLEV_LAW_GAP_LOOP: u32 = 1;
/// `law`: state feedback on gap, gap rate, acceleration, integral and current (`state`).
pub const MAGLEV_LAW_STATE: u32 = 2;
/// `state.geometry`: the paper's literal Eq. 2 (the gap grows with the magnet's height).
pub const MAGLEV_GEOMETRY_PAPER: u32 = 0;
/// `state.geometry`: an EMS magnet under its rail (the gap shrinks as the magnet rises).
pub const MAGLEV_GEOMETRY_EMS: u32 = 1;

/// Gains of the outer gap loop (`law = MAGLEV_LAW_GAP_LOOP`), per unit of the inner law's
/// `g0 = i0_A/h0_m` and `h0_m` (docs/gap-loop.md).
#[allow(non_camel_case_types, non_snake_case)]
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct maglev_gap_loop_params {
    /// Proportional gain `(Δg_ref/g0)/(Δh/h0)` (dimensionless); > 0 holds an EMS magnet.
    pub kp: f64,
    /// Derivative gain (s), the sign of `kp`.
    pub kd_s: f64,
    /// Derivative filter time constant (s), ≥ 0.
    pub tf_s: f64,
    /// Bound on `|g_ref/g0 − 1|` (dimensionless), > 0.
    pub x_ref_max: f64,
}

/// Gains and timing of the state-feedback law (`law = MAGLEV_LAW_STATE`), SI.
#[allow(non_camel_case_types, non_snake_case)]
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct maglev_state_params {
    /// Gap gain (V/m), ≥ 0.
    pub kp_V_per_m: f64,
    /// Gap-rate gain (V·s/m), ≥ 0.
    pub kd_V_s_per_m: f64,
    /// Acceleration gain (V·s²/m), ≥ 0.
    pub ka_V_s2_per_m: f64,
    /// Integral gain (V/(m·s)), ≥ 0.
    pub ki_V_per_m_s: f64,
    /// Current gain (V/A), ≥ 0.
    pub kc_V_per_A: f64,
    /// Supply bound (V), > `r0_ohm·i0_A`.
    pub vmax_V: f64,
    /// Control rate (Hz) inside the step `dt_s`, ≥ 2π·`observer_Hz`.
    pub rate_Hz: f64,
    /// Gap-rate observer bandwidth (Hz), > 0.
    pub observer_Hz: f64,
    /// `MAGLEV_GEOMETRY_PAPER` or `MAGLEV_GEOMETRY_EMS`.
    pub geometry: u32,
}

/// Everything a magnet's controller is built from, SI (units in each field's name).
/// `maglev_params_paper` fills in the paper's §4.2 magnet.
#[allow(non_camel_case_types, non_snake_case)]
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct maglev_params {
    /// Nominal coil current i0 (A), > 0.
    pub i0_A: f64,
    /// Nominal gap h0 (m), > 0.
    pub h0_m: f64,
    /// Coil resistance R0 (Ω), > 0.
    pub r0_ohm: f64,
    /// Proportional gain KP on `g = i/h` (V per A/m = V·m/A), ≥ 0.
    pub kp_V_m_per_A: f64,
    /// Integral gain KI (V·m/(A·s)), ≥ 0.
    pub ki_V_m_per_A_s: f64,
    /// Static load the magnet carries p0 (N), > 0.
    pub p0_N: f64,
    /// α of the α-method (dimensionless), in [0, 1].
    pub alpha: f64,
    /// Step between two updates Δt (s), > 0.
    pub dt_s: f64,
    /// Internal-loop sub-steps per update, ≥ 1.
    pub n_sub: u32,
    /// `MAGLEV_INTERPOLATION_LINEAR` or `MAGLEV_INTERPOLATION_PARABOLIC`.
    pub interpolation: u32,
    /// Supply voltage bound (V), > 0; `INFINITY` for none.
    pub v_max_V: f64,
    /// `MAGLEV_SCHEME_PAPER` or `MAGLEV_SCHEME_ACCURATE`.
    pub scheme: u32,
    /// `MAGLEV_LAW_PAPER`, `MAGLEV_LAW_GAP_LOOP` or `MAGLEV_LAW_STATE`.
    pub law: u32,
    /// The gap loop's gains (read when `law = MAGLEV_LAW_GAP_LOOP`).
    pub gap_loop: maglev_gap_loop_params,
    /// The state law's gains (read when `law = MAGLEV_LAW_STATE`).
    pub state: maglev_state_params,
}

impl maglev_params {
    /// The paper's §4.2 magnet carrying `p0` newtons at step `dt` (s), under the paper's law;
    /// the gap loop's designed gains; the state law's default rates and zero gains.
    pub fn paper(p0: f64, dt: f64) -> Self {
        let p = Params::paper(p0, dt);
        let g = GapParams::designed();
        maglev_params {
            i0_A: p.i0,
            h0_m: p.h0,
            r0_ohm: p.r0,
            kp_V_m_per_A: p.kp,
            ki_V_m_per_A_s: p.ki,
            p0_N: p.p0,
            alpha: p.alpha,
            dt_s: p.dt,
            n_sub: p.n_sub,
            interpolation: MAGLEV_INTERPOLATION_LINEAR,
            v_max_V: p.v_max,
            scheme: MAGLEV_SCHEME_PAPER,
            law: MAGLEV_LAW_PAPER,
            gap_loop: maglev_gap_loop_params {
                kp: g.kp,
                kd_s: g.kd,
                tf_s: g.tf,
                x_ref_max: g.x_ref_max,
            },
            state: maglev_state_params {
                kp_V_per_m: 0.0,
                kd_V_s_per_m: 0.0,
                ka_V_s2_per_m: 0.0,
                ki_V_per_m_s: 0.0,
                kc_V_per_A: 0.0,
                vmax_V: 0.0,
                rate_Hz: StateParams::RATE_HZ,
                observer_Hz: StateParams::OBSERVER_HZ,
                geometry: MAGLEV_GEOMETRY_PAPER,
            },
        }
    }

    /// The core's parameters, or the code of the first enumeration field out of range (the
    /// numbers are checked by the core when compiled).
    pub fn to_core(&self) -> Result<LawParams, maglev_error> {
        let interpolation = match self.interpolation {
            MAGLEV_INTERPOLATION_LINEAR => Interpolation::Linear,
            MAGLEV_INTERPOLATION_PARABOLIC => Interpolation::Parabolic,
            _ => return Err(MAGLEV_ERROR_INTERPOLATION),
        };
        let scheme = match self.scheme {
            MAGLEV_SCHEME_PAPER => Scheme::Paper,
            MAGLEV_SCHEME_ACCURATE => Scheme::Accurate,
            _ => return Err(MAGLEV_ERROR_SCHEME),
        };
        let magnet = Params {
            i0: self.i0_A,
            h0: self.h0_m,
            r0: self.r0_ohm,
            kp: self.kp_V_m_per_A,
            ki: self.ki_V_m_per_A_s,
            p0: self.p0_N,
            alpha: self.alpha,
            dt: self.dt_s,
            n_sub: self.n_sub,
            interpolation,
            v_max: self.v_max_V,
            scheme,
        };
        let kind = match self.law {
            MAGLEV_LAW_PAPER => LawKind::Paper,
            MAGLEV_LAW_GAP_LOOP => {
                let g = &self.gap_loop;
                LawKind::GapLoop(GapParams {
                    kp: g.kp,
                    kd: g.kd_s,
                    tf: g.tf_s,
                    x_ref_max: g.x_ref_max,
                })
            }
            MAGLEV_LAW_STATE => {
                let s = &self.state;
                let geometry = match s.geometry {
                    MAGLEV_GEOMETRY_PAPER => Geometry::Paper,
                    MAGLEV_GEOMETRY_EMS => Geometry::Ems,
                    _ => return Err(MAGLEV_ERROR_STATE_GEOMETRY),
                };
                LawKind::State(StateParams {
                    kp: s.kp_V_per_m,
                    kd: s.kd_V_s_per_m,
                    ka: s.ka_V_s2_per_m,
                    ki: s.ki_V_per_m_s,
                    kc: s.kc_V_per_A,
                    v_max: s.vmax_V,
                    rate_hz: s.rate_Hz,
                    observer_hz: s.observer_Hz,
                    geometry,
                })
            }
            _ => return Err(MAGLEV_ERROR_LAW),
        };
        Ok(LawParams { magnet, kind })
    }
}

/// Fills `*out` with the paper's §4.2 magnet (i0 = 43 A, h0 = 0.01 m, R0 = 1 Ω, KP = 0.01 V·m/A,
/// KI = 6 V·m/(A·s), α = 0.5, one sub-step, linear interpolation, no voltage bound, the paper's
/// scheme and law) carrying `p0_N` newtons with updates every `dt_s` seconds; `gap_loop` holds
/// the designed gains (docs/gap-loop.md), `state` zero gains at 10 kHz with a 300 Hz observer.
/// Nothing is checked here (`maglev_law_init_*` checks). Returns `MAGLEV_ERROR_NULL` if `out`
/// is NULL, else `MAGLEV_OK`.
///
/// # Safety
/// `out` is NULL or points to writable memory for one `maglev_params`.
#[allow(non_snake_case)]
#[no_mangle]
pub unsafe extern "C" fn maglev_params_paper(p0_N: f64, dt_s: f64, out: *mut maglev_params) -> i32 {
    if out.is_null() {
        return MAGLEV_ERROR_NULL as i32;
    }
    if !out.is_aligned() {
        return MAGLEV_ERROR_ALIGNMENT as i32;
    }
    // SAFETY: non-null, and the caller provides a writable maglev_params.
    unsafe { out.write(maglev_params::paper(p0_N, dt_s)) };
    MAGLEV_OK as i32
}
