//! The guidance law's C functions with hostile arguments: NULL, misaligned storage, a law
//! storage no guidance init wrote (a levitation law's, or zeros), bad offsets. Every call
//! returns its code and writes nothing it should not.

use maglev_c_api::maglev_error::*;
use maglev_c_api::*;

fn params() -> (maglev_params, maglev_guidance_params) {
    let mut p = maglev_params::paper(10000.0, 1e-4);
    p.law = MAGLEV_LAW_STATE;
    p.state = maglev_state_params {
        kp_V_per_m: 51600.0,
        kd_V_s_per_m: 1600.0,
        ka_V_s2_per_m: 40.0,
        ki_V_per_m_s: 4300.0,
        kc_V_per_A: 10.0,
        vmax_V: 500.0,
        rate_Hz: 10000.0,
        observer_Hz: 300.0,
        geometry: MAGLEV_GEOMETRY_EMS,
    };
    let g = maglev_guidance_params {
        kp_V_per_m: 20000.0,
        kd_V_s_per_m: 900.0,
        ka_V_s2_per_m: 25.0,
        ki_V_per_m_s: 3000.0,
        kc_V_per_A: 8.0,
    };
    (p, g)
}

fn law() -> Box<maglev_guidance_law_f32> {
    Box::new(maglev_guidance_law_f32 {
        opaque: [0; MAGLEV_LAW_WORDS],
    })
}

#[test]
fn null_misaligned_and_uninitialised_arguments_are_refused_by_code() {
    let (p, g) = params();
    let mut l = law();
    let mut st = maglev_guidance_state_f32::default();
    let m = maglev_pair_measurement_f32::default();
    let mut o = maglev_pair_output_f32::default();
    unsafe {
        let null = MAGLEV_ERROR_NULL as i32;
        assert_eq!(
            maglev_guidance_init_f32(std::ptr::null(), &g, &mut *l),
            null
        );
        assert_eq!(
            maglev_guidance_init_f32(&p, std::ptr::null(), &mut *l),
            null
        );
        assert_eq!(maglev_guidance_init_f32(&p, &g, std::ptr::null_mut()), null);
        // Zeros are no law.
        let not_init = MAGLEV_ERROR_NOT_INITIALIZED as i32;
        assert_eq!(maglev_guidance_state_init_f32(&*l, 0.0, &mut st), not_init);
        assert_eq!(
            maglev_guidance_update_f32(&*l, &mut st, &m, &mut o),
            not_init
        );
        assert_eq!(o, maglev_pair_output_f32::default(), "nothing written");
        // A levitation law's storage is no guidance law either.
        let mut lev = maglev_law_f32 {
            opaque: [0; MAGLEV_LAW_WORDS],
        };
        assert_eq!(maglev_law_init_f32(&p, &mut lev), MAGLEV_OK as i32);
        let as_pair = (&lev as *const maglev_law_f32).cast::<maglev_guidance_law_f32>();
        assert_eq!(
            maglev_guidance_state_init_f32(as_pair, 0.0, &mut st),
            not_init
        );
        // Misaligned law storage.
        let base = (&mut *l as *mut maglev_guidance_law_f32).cast::<u8>();
        let odd = base.add(4).cast::<maglev_guidance_law_f32>();
        assert_eq!(
            maglev_guidance_init_f32(&p, &g, odd),
            MAGLEV_ERROR_ALIGNMENT as i32
        );
        // Initialised: offsets the gaps cannot have are refused, the rest run.
        assert_eq!(maglev_guidance_init_f32(&p, &g, &mut *l), MAGLEV_OK as i32);
        let gap = MAGLEV_ERROR_GAP as i32;
        for d in [f64::NAN, 0.01, -0.01, f64::INFINITY] {
            assert_eq!(maglev_guidance_state_init_f32(&*l, d, &mut st), gap, "{d}");
        }
        assert_eq!(
            maglev_guidance_state_init_f32(&*l, 1e-4, &mut st),
            MAGLEV_OK as i32
        );
        assert_eq!(
            maglev_guidance_update_f32(&*l, &mut st, std::ptr::null(), &mut o),
            null
        );
        // A NaN offset is an event (a status bit), not an error.
        let nan = maglev_pair_measurement_f32 {
            d_pu: f32::NAN,
            ..m
        };
        assert_eq!(
            maglev_guidance_update_f32(&*l, &mut st, &nan, &mut o),
            MAGLEV_OK as i32
        );
        assert_ne!(o.status, 0);
    }
}

/// A gain of `maglev_guidance_params`, by field.
type Gain = fn(&mut maglev_guidance_params) -> &mut f64;

/// Each gain, negative or NaN, is refused with its own code and field name.
#[test]
fn each_bad_gain_names_its_field() {
    let (p, g) = params();
    let mut l = law();
    let fields: [(Gain, maglev_error, &str); 5] = [
        (
            |g| &mut g.kp_V_per_m,
            MAGLEV_ERROR_GUIDANCE_KP,
            "guidance.kp_V_per_m",
        ),
        (
            |g| &mut g.kd_V_s_per_m,
            MAGLEV_ERROR_GUIDANCE_KD,
            "guidance.kd_V_s_per_m",
        ),
        (
            |g| &mut g.ka_V_s2_per_m,
            MAGLEV_ERROR_GUIDANCE_KA,
            "guidance.ka_V_s2_per_m",
        ),
        (
            |g| &mut g.ki_V_per_m_s,
            MAGLEV_ERROR_GUIDANCE_KI,
            "guidance.ki_V_per_m_s",
        ),
        (
            |g| &mut g.kc_V_per_A,
            MAGLEV_ERROR_GUIDANCE_KC,
            "guidance.kc_V_per_A",
        ),
    ];
    for (field, code, name) in fields {
        for bad in [-1.0, f64::NAN] {
            let mut b = g;
            *field(&mut b) = bad;
            let rc = unsafe { maglev_guidance_init_f32(&p, &b, &mut *l) };
            assert_eq!(rc, code as i32, "{name} = {bad}");
            let text = unsafe { std::ffi::CStr::from_ptr(maglev_error_field_name(rc)) };
            assert_eq!(text.to_str().unwrap(), name);
        }
    }
}
