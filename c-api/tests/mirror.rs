//! The C API's `repr(C)` mirror of the core's parameters (`maglev_params`, with
//! `maglev_gap_loop_params` and `maglev_state_params`) against the core's own types
//! (`LawParams`: `Params` and each law's parameters): every field both ways.
//!
//! Both directions are written here from the structs' fields, destructured without `..` so
//! that a field added to either side fails to compile until it is mirrored: core → C
//! ([`to_c`], this file's) → core through the API's own `to_core` gives the core value back
//! for every law, each field set to a value no other field holds (a swapped pair would show);
//! and C → core changes the core value for every C field the law reads, by that field alone.

use maglev_c_api::*;
use maglev_core::gap::Geometry;
use maglev_core::gap_control::GapParams;
use maglev_core::law::state::StateParams;
use maglev_core::{Interpolation, LawKind, LawName, LawParams, Params, Scheme};

/// The C struct holding `p` (the C fields of the laws `p` does not run keep `base`'s).
fn to_c(p: &LawParams, base: &maglev_params) -> maglev_params {
    let Params {
        i0,
        h0,
        r0,
        kp,
        ki,
        p0,
        alpha,
        dt,
        n_sub,
        interpolation,
        v_max,
        scheme,
    } = p.magnet;
    let mut c = maglev_params {
        i0_A: i0,
        h0_m: h0,
        r0_ohm: r0,
        kp_V_m_per_A: kp,
        ki_V_m_per_A_s: ki,
        p0_N: p0,
        alpha,
        dt_s: dt,
        n_sub,
        interpolation: match interpolation {
            Interpolation::Linear => MAGLEV_INTERPOLATION_LINEAR,
            Interpolation::Parabolic => MAGLEV_INTERPOLATION_PARABOLIC,
        },
        v_max_V: v_max,
        scheme: match scheme {
            Scheme::Paper => MAGLEV_SCHEME_PAPER,
            Scheme::Accurate => MAGLEV_SCHEME_ACCURATE,
        },
        law: match p.kind.name() {
            LawName::Paper => MAGLEV_LAW_PAPER,
            LawName::GapLoop => MAGLEV_LAW_GAP_LOOP,
            LawName::State => MAGLEV_LAW_STATE,
        },
        gap_loop: base.gap_loop,
        state: base.state,
    };
    if let Some(&GapParams {
        kp,
        kd,
        tf,
        x_ref_max,
    }) = p.kind.gap_loop()
    {
        c.gap_loop = maglev_gap_loop_params {
            kp,
            kd_s: kd,
            tf_s: tf,
            x_ref_max,
        };
    }
    if let Some(&StateParams {
        kp,
        kd,
        ka,
        ki,
        kc,
        v_max,
        rate_hz,
        observer_hz,
        geometry,
    }) = p.kind.state()
    {
        c.state = maglev_state_params {
            kp_V_per_m: kp,
            kd_V_s_per_m: kd,
            ka_V_s2_per_m: ka,
            ki_V_per_m_s: ki,
            kc_V_per_A: kc,
            vmax_V: v_max,
            rate_Hz: rate_hz,
            observer_Hz: observer_hz,
            geometry: match geometry {
                Geometry::Paper => MAGLEV_GEOMETRY_PAPER,
                Geometry::Ems => MAGLEV_GEOMETRY_EMS,
            },
        };
    }
    c
}

/// Every law with every core field a value of its own (and the enumerations off their
/// defaults).
fn samples() -> Vec<LawParams> {
    let magnet = Params {
        i0: 1.0,
        h0: 2.0,
        r0: 3.0,
        kp: 4.0,
        ki: 5.0,
        p0: 6.0,
        alpha: 0.7,
        dt: 8.0,
        n_sub: 9,
        interpolation: Interpolation::Parabolic,
        v_max: 10.0,
        scheme: Scheme::Accurate,
    };
    let kinds = [
        LawKind::Paper,
        LawKind::GapLoop(GapParams {
            kp: 11.0,
            kd: 12.0,
            tf: 13.0,
            x_ref_max: 14.0,
        }),
        LawKind::State(StateParams {
            kp: 15.0,
            kd: 16.0,
            ka: 17.0,
            ki: 18.0,
            kc: 19.0,
            v_max: 20.0,
            rate_hz: 21.0,
            observer_hz: 22.0,
            geometry: Geometry::Ems,
        }),
    ];
    kinds
        .into_iter()
        .map(|kind| LawParams { magnet, kind })
        .collect()
}

#[test]
fn core_to_c_to_core_is_the_identity_for_every_law() {
    let base = maglev_params::paper(1.0, 1e-3);
    for p in samples() {
        let c = to_c(&p, &base);
        assert_eq!(c.to_core().unwrap(), p, "{:?}", p.kind.name());
    }
}

/// Each C field the law reads, changed alone, changes the core's value (and the change comes
/// back in the C struct): no C field is left unread, none is read into two places.
#[test]
fn every_c_field_reaches_the_core() {
    let base = maglev_params::paper(1.0, 1e-3);
    for p in samples() {
        let c = to_c(&p, &base);
        let mut edits: Vec<(&str, maglev_params)> = Vec::new();
        let mut edit = |name, set: fn(&mut maglev_params)| {
            let mut e = c;
            set(&mut e);
            edits.push((name, e));
        };
        edit("i0_A", |c| c.i0_A += 0.5);
        edit("h0_m", |c| c.h0_m += 0.5);
        edit("r0_ohm", |c| c.r0_ohm += 0.5);
        edit("kp_V_m_per_A", |c| c.kp_V_m_per_A += 0.5);
        edit("ki_V_m_per_A_s", |c| c.ki_V_m_per_A_s += 0.5);
        edit("p0_N", |c| c.p0_N += 0.5);
        edit("alpha", |c| c.alpha += 0.125);
        edit("dt_s", |c| c.dt_s += 0.5);
        edit("n_sub", |c| c.n_sub += 1);
        edit("interpolation", |c| {
            c.interpolation = MAGLEV_INTERPOLATION_LINEAR
        });
        edit("v_max_V", |c| c.v_max_V += 0.5);
        edit("scheme", |c| c.scheme = MAGLEV_SCHEME_PAPER);
        if p.kind.gap_loop().is_some() {
            edit("gap_loop.kp", |c| c.gap_loop.kp += 0.5);
            edit("gap_loop.kd_s", |c| c.gap_loop.kd_s += 0.5);
            edit("gap_loop.tf_s", |c| c.gap_loop.tf_s += 0.5);
            edit("gap_loop.x_ref_max", |c| c.gap_loop.x_ref_max += 0.5);
        }
        if p.kind.state().is_some() {
            edit("state.kp_V_per_m", |c| c.state.kp_V_per_m += 0.5);
            edit("state.kd_V_s_per_m", |c| c.state.kd_V_s_per_m += 0.5);
            edit("state.ka_V_s2_per_m", |c| c.state.ka_V_s2_per_m += 0.5);
            edit("state.ki_V_per_m_s", |c| c.state.ki_V_per_m_s += 0.5);
            edit("state.kc_V_per_A", |c| c.state.kc_V_per_A += 0.5);
            edit("state.vmax_V", |c| c.state.vmax_V += 0.5);
            edit("state.rate_Hz", |c| c.state.rate_Hz += 0.5);
            edit("state.observer_Hz", |c| c.state.observer_Hz += 0.5);
            edit("state.geometry", |c| {
                c.state.geometry = MAGLEV_GEOMETRY_PAPER
            });
        }
        // The paper's law, the gap loop and the state law read 12, 16 and 21 fields.
        let read = 12
            + 4 * usize::from(p.kind.gap_loop().is_some())
            + 9 * usize::from(p.kind.state().is_some());
        assert_eq!(edits.len(), read);
        let mut seen: Vec<LawParams> = vec![p];
        for (name, e) in edits {
            let q = e.to_core().unwrap();
            assert!(
                !seen.contains(&q),
                "{name}: the core did not see the change"
            );
            assert_eq!(to_c(&q, &base), e, "{name}: the change did not come back");
            seen.push(q);
        }
    }
}

/// The guidance law's gains: `maglev_guidance_params` holds each of the core's
/// `GuidanceParams` fields in the C field of its name (both destructured without `..`), and
/// the API's `to_core` gives the core value back, each field distinct.
#[test]
fn guidance_gains_mirror_the_cores_field_for_field() {
    use maglev_core::law::guidance::GuidanceParams;
    let core = GuidanceParams {
        kp: 1.0,
        kd: 2.0,
        ka: 3.0,
        ki: 4.0,
        kc: 5.0,
    };
    let GuidanceParams { kp, kd, ka, ki, kc } = core;
    let c = maglev_guidance_params {
        kp_V_per_m: kp,
        kd_V_s_per_m: kd,
        ka_V_s2_per_m: ka,
        ki_V_per_m_s: ki,
        kc_V_per_A: kc,
    };
    assert_eq!(c.to_core(), core);
    let maglev_guidance_params {
        kp_V_per_m,
        kd_V_s_per_m,
        ka_V_s2_per_m,
        ki_V_per_m_s,
        kc_V_per_A,
    } = c;
    // Five distinct values: a swapped pair would show.
    assert_eq!(
        [
            kp_V_per_m,
            kd_V_s_per_m,
            ka_V_s2_per_m,
            ki_V_per_m_s,
            kc_V_per_A
        ],
        [1.0, 2.0, 3.0, 4.0, 5.0]
    );
}

/// The pair's state: `maglev_guidance_state_f32` holds each field of the core's
/// `GuidanceState<f32>` (and of each coil's `State<f32>`) in the C field of its name, and the
/// API's conversions are each other's inverse.
#[test]
fn guidance_state_mirrors_the_cores_field_for_field() {
    use maglev_c_api::guidance_api::{from_c, to_c};
    use maglev_core::law::guidance::GuidanceState;
    use maglev_core::State;
    let coil = |b: f32| State {
        x: b + 1.0,
        y: b + 2.0,
        eta: b + 3.0,
        eta_prev: b + 4.0,
        v: b + 5.0,
    };
    let core = GuidanceState {
        left: coil(0.0),
        right: coil(10.0),
        integral: 21.0,
        eta_est: 22.0,
        rate_est: 23.0,
        accel: 24.0,
    };
    let c = to_c(&core);
    let c_coil = |s: &maglev_coil_state_f32| {
        let &maglev_coil_state_f32 {
            x,
            y,
            eta,
            eta_prev,
            v,
        } = s;
        [x, y, eta, eta_prev, v]
    };
    let maglev_guidance_state_f32 {
        left,
        right,
        integral,
        eta_est,
        rate_est,
        accel,
    } = c;
    assert_eq!(c_coil(&left), [1.0, 2.0, 3.0, 4.0, 5.0]);
    assert_eq!(c_coil(&right), [11.0, 12.0, 13.0, 14.0, 15.0]);
    assert_eq!(
        [integral, eta_est, rate_est, accel],
        [21.0, 22.0, 23.0, 24.0]
    );
    assert_eq!(from_c(&c), core);
    assert_eq!(
        std::mem::size_of::<maglev_guidance_state_f32>(),
        std::mem::size_of::<GuidanceState<f32>>()
    );
}
