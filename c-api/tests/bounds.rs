//! The C API's bounds (docs/c-api.md, "Bounds"): the sub-steps an update may run, the state
//! law's control periods per update and its per-unit coefficients in Q4.28, the alignment of
//! the caller's storage, and the storage sizes the docs state. Expected codes are the
//! header's numbers, written out here.

use maglev_c_api::*;
use std::ffi::CStr;
use std::mem::MaybeUninit;

fn paper() -> maglev_params {
    let mut p = MaybeUninit::uninit();
    assert_eq!(
        unsafe { maglev_params_paper(36787.5, 1e-3, p.as_mut_ptr()) },
        0
    );
    unsafe { p.assume_init() }
}

/// The state law of the CI's HIL run (.ci/run) on EMS magnets.
fn state() -> maglev_params {
    let mut p = paper();
    p.law = MAGLEV_LAW_STATE;
    p.state = maglev_state_params {
        kp_V_per_m: 51600.0,
        kd_V_s_per_m: 1600.0,
        ka_V_s2_per_m: 40.0,
        ki_V_per_m_s: 4300.0,
        kc_V_per_A: 10.0,
        vmax_V: 500.0,
        rate_Hz: 10_000.0,
        observer_Hz: 300.0,
        geometry: MAGLEV_GEOMETRY_EMS,
    };
    p
}

fn law() -> Box<[u64; MAGLEV_LAW_WORDS + 1]> {
    Box::new([0; MAGLEV_LAW_WORDS + 1])
}

fn init_f32(p: &maglev_params) -> i32 {
    let mut l = law();
    unsafe { maglev_law_init_f32(p, l.as_mut_ptr().cast()) }
}

fn init_q28(p: &maglev_params) -> i32 {
    let mut l = law();
    unsafe { maglev_law_init_q28(p, l.as_mut_ptr().cast()) }
}

fn message(code: i32) -> String {
    let p = maglev_error_message(code);
    unsafe { CStr::from_ptr(p) }.to_str().unwrap().to_owned()
}

#[test]
fn n_sub_above_the_budget_is_refused_at_init() {
    let mut p = paper();
    for (n, want) in [
        (MAGLEV_MAX_N_SUB, 0),
        (MAGLEV_MAX_N_SUB + 1, 10),
        (u32::MAX, 10),
    ] {
        p.n_sub = n;
        assert_eq!(init_f32(&p), want, "n_sub {n}");
    }
    // Q4.28 refuses far fewer sub-steps for its resolution; the bound is refused first.
    p.n_sub = u32::MAX;
    assert_eq!(init_q28(&p), 10);
    assert!(message(10).contains("100000"), "{}", message(10));
}

#[test]
fn too_many_state_periods_name_the_rate() {
    for (dt, rate) in [(1.5, 10_000.0), (1e-3, 1e9), (1.0001, 10_000.0)] {
        let mut p = state();
        p.dt_s = dt;
        p.state.rate_Hz = rate;
        assert_eq!(init_f32(&p), 33, "dt {dt} rate {rate}");
    }
    // Q4.28 at dt = 1 ms (at dt ≥ 1 s the paper law's own coefficients do not fit first).
    let mut p = state();
    p.state.rate_Hz = 1e9;
    assert_eq!(init_q28(&p), 33);
    let field = unsafe { CStr::from_ptr(maglev_error_field_name(33)) };
    assert_eq!(field.to_str().unwrap(), "state.rate_Hz*dt_s");
    // 10 000 periods exactly are accepted.
    let mut p = state();
    p.dt_s = 1.0;
    assert_eq!(init_f32(&p), 0);
}

#[test]
fn the_state_law_in_q28_names_its_real_cause() {
    // kp·h0/Vb = 51600·0.01/43 = 12 > 8: outside Q4.28, whatever the sub-steps or dt.
    let code = init_q28(&state());
    assert_eq!(code, 34);
    let m = message(code);
    assert!(!m.contains("sub-step") && !m.contains("dt_s"), "{m}");
    assert!(m.contains("[-8, 8)"), "{m}");
    // The same law in f32 is fine.
    assert_eq!(init_f32(&state()), 0);
}

#[test]
fn misaligned_storage_is_refused() {
    let p = paper();
    let mut words = law();
    let base = words.as_mut_ptr().cast::<u8>();
    // SAFETY of the offsets: the buffer has a spare word, so base + 4 .. + 4 + LAW_SIZE is in it.
    let odd = unsafe { base.add(4) };
    assert_eq!(unsafe { maglev_law_init_f32(&p, odd.cast()) }, 35);
    assert_eq!(unsafe { maglev_law_init_q28(&p, odd.cast()) }, 35);
    let mut l = MaybeUninit::<maglev_law_f32>::uninit();
    assert_eq!(unsafe { maglev_law_init_f32(&p, l.as_mut_ptr()) }, 0);
    let mut st = [0u64; MAGLEV_STATE_WORDS + 1];
    let odd_state = unsafe { st.as_mut_ptr().cast::<u8>().add(4) };
    assert_eq!(
        unsafe { maglev_state_init_f32(l.as_ptr(), 0.01, odd_state.cast()) },
        35
    );
    let mut s = MaybeUninit::<maglev_state_f32>::uninit();
    assert_eq!(
        unsafe { maglev_state_init_f32(l.as_ptr(), 0.01, s.as_mut_ptr()) },
        0
    );
    let m = maglev_measurement_f32 {
        gap_pu: 1.0,
        ..Default::default()
    };
    let mut out = maglev_output_f32::default();
    let odd_law = unsafe { l.as_ptr().cast::<u8>().add(4) };
    assert_eq!(
        unsafe { maglev_law_update_f32(odd_law.cast(), s.as_mut_ptr(), &m, &mut out) },
        35
    );
    assert_eq!(
        unsafe { maglev_law_update_f32(l.as_ptr(), odd_state.cast(), &m, &mut out) },
        35
    );
    let mut bytes = [0u32; 8];
    let odd_out = unsafe { bytes.as_mut_ptr().cast::<u8>().add(1) };
    assert_eq!(
        unsafe { maglev_law_update_f32(l.as_ptr(), s.as_mut_ptr(), &m, odd_out.cast()) },
        35
    );
    assert_eq!(
        unsafe { maglev_law_update_f32(l.as_ptr(), s.as_mut_ptr(), &m, &mut out) },
        0
    );
    let mut view = maglev_state_view_f32::default();
    assert_eq!(
        unsafe { maglev_state_read_f32(odd_state.cast(), &mut view) },
        35
    );
    let mut params = [0u64; 40];
    let odd_params = unsafe { params.as_mut_ptr().cast::<u8>().add(4) };
    assert_eq!(
        unsafe { maglev_params_paper(1.0, 1e-3, odd_params.cast()) },
        35
    );
    let mut q = [0u32; 2];
    let odd_q = unsafe { q.as_mut_ptr().cast::<u8>().add(2) };
    assert_eq!(unsafe { maglev_q28_from_f64(0.5, odd_q.cast()) }, 35);
}

/// docs/c-api.md's "Sizes" table states what the core types take in their storage on
/// x86-64: the numbers must be `law::used_sizes`.
#[test]
fn the_documented_sizes_are_the_types_sizes() {
    let doc =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/c-api.md")).unwrap();
    let row = |name: &str| -> usize {
        let line = doc
            .lines()
            .find(|l| l.starts_with(&format!("| `{name}` |")))
            .unwrap_or_else(|| panic!("no row for {name}"));
        let last = line.trim_end_matches('|').rsplit(':').next().unwrap();
        last.trim()
            .parse()
            .unwrap_or_else(|e| panic!("{line}: {e}"))
    };
    let [law_f32, law_q28, state_f32, state_q28] = maglev_c_api::law::used_sizes();
    if cfg!(target_arch = "x86_64") {
        assert_eq!(row("MAGLEV_LAW_SIZE"), law_f32.max(law_q28));
        assert_eq!(row("MAGLEV_STATE_SIZE"), state_f32.max(state_q28));
    }
}
