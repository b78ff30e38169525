//! The C API's contract from Rust, through its `extern "C"` functions: every bad field is
//! named by its own code, every NULL is refused, a law no init wrote is refused, and hostile
//! inputs (random bit patterns in every field and measurement, seeded) never panic — a panic
//! inside an `extern "C"` function aborts this test binary — nor write a NaN or infinity.
//! The expected codes are the header's numbers, written out here.

use maglev_c_api::*;
use std::ffi::CStr;
use std::mem::MaybeUninit;

fn law_f32() -> Box<maglev_law_f32> {
    Box::new(maglev_law_f32 {
        opaque: [0; MAGLEV_LAW_WORDS],
    })
}
fn law_q28() -> Box<maglev_law_q28> {
    Box::new(maglev_law_q28 {
        opaque: [0; MAGLEV_LAW_WORDS],
    })
}
fn state_f32() -> maglev_state_f32 {
    maglev_state_f32 {
        opaque: [0; MAGLEV_STATE_WORDS],
    }
}
fn state_q28() -> maglev_state_q28 {
    maglev_state_q28 {
        opaque: [0; MAGLEV_STATE_WORDS],
    }
}

fn paper() -> maglev_params {
    let mut p = MaybeUninit::uninit();
    assert_eq!(
        unsafe { maglev_params_paper(36787.5, 1e-3, p.as_mut_ptr()) },
        0
    );
    unsafe { p.assume_init() }
}

fn init_both(p: &maglev_params) -> (i32, i32) {
    let (mut a, mut b) = (law_f32(), law_q28());
    unsafe {
        (
            maglev_law_init_f32(p, &mut *a),
            maglev_law_init_q28(p, &mut *b),
        )
    }
}

fn text(p: *const std::ffi::c_char) -> String {
    assert!(!p.is_null());
    unsafe { CStr::from_ptr(p) }.to_str().unwrap().to_owned()
}

#[test]
fn each_bad_field_is_named_by_its_code() {
    type Edit = fn(&mut maglev_params);
    let cases: [(Edit, i32, &str); 28] = [
        (|p| p.i0_A = 0.0, 2, "i0_A"),
        (|p| p.h0_m = f64::NAN, 3, "h0_m"),
        (|p| p.r0_ohm = -1.0, 4, "r0_ohm"),
        (|p| p.kp_V_m_per_A = -0.1, 5, "kp_V_m_per_A"),
        (|p| p.ki_V_m_per_A_s = f64::INFINITY, 6, "ki_V_m_per_A_s"),
        (|p| p.p0_N = 0.0, 7, "p0_N"),
        (|p| p.alpha = 1.5, 8, "alpha"),
        (|p| p.alpha = -0.5, 8, "alpha"),
        (|p| p.dt_s = 0.0, 9, "dt_s"),
        (|p| p.n_sub = 0, 10, "n_sub"),
        (|p| p.interpolation = 2, 11, "interpolation"),
        (|p| p.v_max_V = f64::NAN, 12, "v_max_V"),
        (|p| p.scheme = 7, 13, "scheme"),
        (|p| p.law = 3, 14, "law"),
        (|p| set_gap(p, |g| g.kp = f64::NAN), 15, "gap_loop.kp"),
        (
            |p| set_gap(p, |g| g.kd_s = f64::INFINITY),
            16,
            "gap_loop.kd_s",
        ),
        (|p| set_gap(p, |g| g.tf_s = -1e-3), 17, "gap_loop.tf_s"),
        (
            |p| set_gap(p, |g| g.x_ref_max = 0.0),
            18,
            "gap_loop.x_ref_max",
        ),
        (
            |p| set_state(p, |s| s.kp_V_per_m = -1.0),
            19,
            "state.kp_V_per_m",
        ),
        (
            |p| set_state(p, |s| s.kd_V_s_per_m = f64::NAN),
            20,
            "state.kd_V_s_per_m",
        ),
        (
            |p| set_state(p, |s| s.ka_V_s2_per_m = -1.0),
            21,
            "state.ka_V_s2_per_m",
        ),
        (
            |p| set_state(p, |s| s.ki_V_per_m_s = -1.0),
            22,
            "state.ki_V_per_m_s",
        ),
        (
            |p| set_state(p, |s| s.kc_V_per_A = -1.0),
            23,
            "state.kc_V_per_A",
        ),
        (|p| set_state(p, |s| s.vmax_V = 40.0), 24, "state.vmax_V"), // below R0·i0 = 43 V
        (
            |p| set_state(p, |s| s.rate_Hz = 1000.0),
            25,
            "state.rate_Hz",
        ), // < 2π·300 Hz
        (|p| set_state(p, |s| s.rate_Hz = 0.0), 25, "state.rate_Hz"),
        (
            |p| set_state(p, |s| s.observer_Hz = 0.0),
            26,
            "state.observer_Hz",
        ),
        (|p| set_state(p, |s| s.geometry = 2), 27, "state.geometry"),
    ];
    for (i, (edit, code, field)) in cases.into_iter().enumerate() {
        let mut p = paper();
        edit(&mut p);
        assert_eq!(init_both(&p), (code, code), "case {i}: {field}");
        assert_eq!(text(maglev_error_field_name(code)), field, "case {i}");
        assert!(
            text(maglev_error_message(code)).starts_with(field),
            "case {i}"
        );
    }
}

fn set_gap(p: &mut maglev_params, f: fn(&mut maglev_gap_loop_params)) {
    p.law = MAGLEV_LAW_GAP_LOOP;
    f(&mut p.gap_loop);
}

/// A state law that compiles in f32 (the README's gains), then one field edited.
fn set_state(p: &mut maglev_params, f: fn(&mut maglev_state_params)) {
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
    f(&mut p.state);
}

#[test]
fn every_law_initialises_and_q28_refuses_what_it_cannot_carry() {
    let mut p = paper();
    assert_eq!(init_both(&p), (0, 0));
    p.law = MAGLEV_LAW_GAP_LOOP;
    assert_eq!(init_both(&p), (0, 0));
    set_state(&mut p, |_| ());
    // kp·h0/(R0·i0) = 12 is beyond Q4.28's ±8: MAGLEV_ERROR_STATE_UNREPRESENTABLE.
    assert_eq!(init_both(&p), (0, 34));
    let mut p = paper();
    p.scheme = MAGLEV_SCHEME_ACCURATE;
    p.n_sub = 10;
    p.interpolation = MAGLEV_INTERPOLATION_PARABOLIC;
    p.v_max_V = 60.0;
    assert_eq!(init_both(&p).0, 0);
}

#[test]
fn codes_have_distinct_names_and_unknown_codes_say_so() {
    let names: Vec<_> = (0..=40).map(|c| text(maglev_error_field_name(c))).collect();
    let mut sorted = names.clone();
    sorted.sort();
    sorted.dedup();
    assert_eq!(sorted.len(), names.len(), "{names:?}");
    assert_eq!(names[0], "none");
    for c in [-1, 41, i32::MIN, i32::MAX] {
        assert_eq!(text(maglev_error_field_name(c)), "unknown");
        assert_eq!(text(maglev_error_message(c)), "unknown error code");
    }
}

#[test]
fn null_pointers_and_uninitialised_laws_are_refused() {
    let p = paper();
    let (mut law, mut st) = (law_f32(), state_f32());
    let m = maglev_measurement_f32 {
        gap_pu: 1.0,
        ..Default::default()
    };
    let mut o = maglev_output_f32::default();
    let mut v = maglev_state_view_f32::default();
    unsafe {
        assert_eq!(maglev_params_paper(1.0, 1.0, std::ptr::null_mut()), 1);
        assert_eq!(maglev_law_init_f32(std::ptr::null(), &mut *law), 1);
        assert_eq!(maglev_law_init_f32(&p, std::ptr::null_mut()), 1);
        assert_eq!(
            maglev_law_init_q28(std::ptr::null(), std::ptr::null_mut()),
            1
        );
        // Zeroed storage: no init wrote it.
        assert_eq!(maglev_state_init_f32(&*law, 0.01, &mut st), 31);
        assert_eq!(maglev_law_update_f32(&*law, &mut st, &m, &mut o), 31);
        assert_eq!(maglev_law_init_f32(&p, &mut *law), 0);
        assert_eq!(maglev_state_init_f32(&*law, 0.01, std::ptr::null_mut()), 1);
        assert_eq!(maglev_state_init_f32(std::ptr::null(), 0.01, &mut st), 1);
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert_eq!(maglev_state_init_f32(&*law, bad, &mut st), 28, "{bad}");
        }
        assert_eq!(maglev_state_init_f32(&*law, 0.01, &mut st), 0);
        assert_eq!(
            maglev_law_update_f32(std::ptr::null(), &mut st, &m, &mut o),
            1
        );
        assert_eq!(
            maglev_law_update_f32(&*law, std::ptr::null_mut(), &m, &mut o),
            1
        );
        assert_eq!(
            maglev_law_update_f32(&*law, &mut st, std::ptr::null(), &mut o),
            1
        );
        assert_eq!(
            maglev_law_update_f32(&*law, &mut st, &m, std::ptr::null_mut()),
            1
        );
        assert_eq!(maglev_law_update_f32(&*law, &mut st, &m, &mut o), 0);
        assert_eq!(maglev_state_read_f32(std::ptr::null(), &mut v), 1);
        assert_eq!(maglev_state_read_f32(&st, std::ptr::null_mut()), 1);
        // An f32 law handed to the Q4.28 update (a C cast): refused by its tag.
        let as_q28 = (&*law as *const maglev_law_f32).cast::<maglev_law_q28>();
        let mut sq = state_q28();
        let mq = maglev_measurement_q28::default();
        let mut oq = maglev_output_q28::default();
        assert_eq!(maglev_law_update_q28(as_q28, &mut sq, &mq, &mut oq), 31);
        // A failed init leaves the storage refused, whatever it held before.
        let mut bad = p;
        bad.h0_m = -1.0;
        assert_eq!(maglev_law_init_f32(&bad, &mut *law), 3);
        assert_eq!(maglev_law_update_f32(&*law, &mut st, &m, &mut o), 31);
    }
}

#[test]
fn q28_conversion_rounds_and_saturates_as_the_core() {
    let mut q = 0;
    unsafe {
        assert_eq!(maglev_q28_from_f64(1.5, &mut q), 0);
        assert_eq!(q, 3 << 27);
        assert_eq!(maglev_q28_from_f64(-8.0, &mut q), 0);
        assert_eq!(q, i32::MIN);
        assert_eq!(maglev_q28_from_f64(8.0, &mut q), 30);
        assert_eq!(q, i32::MAX);
        assert_eq!(maglev_q28_from_f64(f64::NAN, &mut q), 30);
        assert_eq!(q, 0);
        // Half an LSB rounds away from zero.
        assert_eq!(maglev_q28_from_f64(1.5 / (1u64 << 28) as f64, &mut q), 0);
        assert_eq!(q, 2);
        assert_eq!(maglev_q28_from_f64(0.0, std::ptr::null_mut()), 1);
    }
    assert_eq!(maglev_q28_to_f64(3 << 27), 1.5);
    assert_eq!(maglev_q28_to_f64(i32::MIN), -8.0);
}

/// xorshift64*, seeded: the same hostile inputs on every run.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    /// Any bit pattern, or one of the values that break checks (NaN, ±∞, 0, −1, huge).
    fn hostile(&mut self) -> f64 {
        if self.next() % 2 == 0 {
            f64::from_bits(self.next())
        } else {
            [0.0, -0.0, f64::NAN, f64::INFINITY, -1.0, 1e300, 5e-324][(self.next() % 7) as usize]
        }
    }
}

/// Parameters for one round: every field within ×0.5…×1.5 of a law that compiles, and in
/// two rounds of three one field (or enumeration) replaced by a hostile value.
fn hostile_params(rng: &mut Rng) -> maglev_params {
    let mut p = paper();
    set_state(&mut p, |s| s.observer_Hz = 40.0);
    p.law = (rng.next() % 3) as u32;
    p.n_sub = 1 + (rng.next() % 4) as u32;
    p.interpolation = (rng.next() % 2) as u32;
    p.scheme = (rng.next() % 2) as u32;
    let mut fields: [&mut f64; 17] = [
        &mut p.i0_A,
        &mut p.h0_m,
        &mut p.r0_ohm,
        &mut p.kp_V_m_per_A,
        &mut p.ki_V_m_per_A_s,
        &mut p.p0_N,
        &mut p.alpha,
        &mut p.dt_s,
        &mut p.v_max_V,
        &mut p.gap_loop.kp,
        &mut p.gap_loop.kd_s,
        &mut p.gap_loop.tf_s,
        &mut p.gap_loop.x_ref_max,
        &mut p.state.kp_V_per_m,
        &mut p.state.ki_V_per_m_s,
        &mut p.state.vmax_V,
        &mut p.state.observer_Hz,
    ];
    for f in fields.iter_mut() {
        **f *= 0.5 + (rng.next() % 1000) as f64 / 1000.0;
    }
    match rng.next() % 24 {
        k @ 0..=16 => *fields[k as usize] = rng.hostile(),
        17 => p.interpolation = rng.next() as u32,
        18 => p.scheme = rng.next() as u32,
        19 => p.law = rng.next() as u32,
        20 => p.n_sub = rng.next() as u32 % 3,
        21 => p.state.geometry = rng.next() as u32,
        _ => {}
    }
    if p.alpha > 1.0 && rng.next() % 2 == 0 {
        p.alpha = 1.0;
    }
    p
}

#[test]
fn hostile_inputs_never_panic_nor_write_nan() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let (mut ok_f32, mut ok_q28, mut steps) = (0, 0, 0);
    for _ in 0..3000 {
        let p = hostile_params(&mut rng);
        let mut law = law_f32();
        let mut lq = law_q28();
        let (rf, rq) = unsafe {
            (
                maglev_law_init_f32(&p, &mut *law),
                maglev_law_init_q28(&p, &mut *lq),
            )
        };
        assert!((0..=35).contains(&rf) && (0..=35).contains(&rq));
        let gap0 = if rng.next() % 4 == 0 {
            rng.hostile()
        } else {
            p.h0_m * (0.5 + (rng.next() % 1000) as f64 / 1000.0)
        };
        if rf == 0 {
            let mut st = state_f32();
            if unsafe { maglev_state_init_f32(&*law, gap0, &mut st) } == 0 {
                ok_f32 += 1;
                for _ in 0..20 {
                    let m = maglev_measurement_f32 {
                        gap_pu: if rng.next() % 2 == 0 {
                            f32::from_bits(rng.next() as u32)
                        } else {
                            0.5 + (rng.next() % 1000) as f32 / 1000.0
                        },
                        accel_g: f32::from_bits(rng.next() as u32),
                        current_pu: f32::from_bits(rng.next() as u32),
                        flags: rng.next() as u32,
                    };
                    let mut o = maglev_output_f32::default();
                    assert_eq!(
                        unsafe { maglev_law_update_f32(&*law, &mut st, &m, &mut o) },
                        0
                    );
                    for v in [o.g_pu, o.force_pu, o.current_pu, o.voltage_pu] {
                        assert!(v.is_finite(), "{p:?} {m:?} {o:?}");
                    }
                    steps += 1;
                }
            }
        }
        if rq == 0 {
            let mut st = state_q28();
            if unsafe { maglev_state_init_q28(&*lq, gap0, &mut st) } == 0 {
                ok_q28 += 1;
                for _ in 0..20 {
                    let m = maglev_measurement_q28 {
                        gap_pu: rng.next() as i32,
                        accel_g: rng.next() as i32,
                        current_pu: rng.next() as i32,
                        flags: rng.next() as u32,
                    };
                    let mut o = maglev_output_q28::default();
                    assert_eq!(
                        unsafe { maglev_law_update_q28(&*lq, &mut st, &m, &mut o) },
                        0
                    );
                    steps += 1;
                }
            }
        }
    }
    // The hostile parameters still let enough laws through to exercise the updates.
    assert!(ok_f32 > 1000 && ok_q28 > 500, "{ok_f32} {ok_q28}");
    assert!(steps > 30_000, "{steps}");
}

#[test]
fn storage_sizes_hold_the_core_types() {
    let used = maglev_c_api::law::used_sizes();
    assert!(
        used[0] <= MAGLEV_LAW_SIZE && used[1] <= MAGLEV_LAW_SIZE,
        "{used:?}"
    );
    assert!(
        used[2] <= MAGLEV_STATE_SIZE && used[3] <= MAGLEV_STATE_SIZE,
        "{used:?}"
    );
    assert_eq!(std::mem::size_of::<maglev_law_f32>(), MAGLEV_LAW_SIZE);
    assert_eq!(std::mem::size_of::<maglev_state_q28>(), MAGLEV_STATE_SIZE);
    assert_eq!(std::mem::align_of::<maglev_law_q28>(), MAGLEV_ALIGN);
}
