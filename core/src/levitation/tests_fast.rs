//! The `n_sub = 1` fast path against the general path, the division-free quotient of fixed
//! point against the exact one, and the SI / initial-state guards.
extern crate std;
use super::*;
use crate::scalar::{I32F32, I4F28};

/// A fixed-seed xorshift64 stream of uniform numbers in [0, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// Every field's exact bits (`to_f64` is exact for all four types, signed zeros included).
fn bits<S: Scalar>(st: &State<S>, o: &Output<S>) -> [u64; 10] {
    let b = |v: S| v.to_f64().to_bits();
    [
        b(st.x),
        b(st.y),
        b(st.eta),
        b(st.eta_prev),
        b(st.v),
        b(o.g),
        b(o.force),
        b(o.current),
        b(o.voltage),
        o.status.0 as u64,
    ]
}

/// Random states and gaps, from ordinary to absurd: the fast path must give the general
/// path's bits exactly, or decline. Returns how often it did not decline.
fn fast_equals_general<S: Scalar>(dt: f64, seed: u64) -> usize {
    let p = Params::paper_wheel(dt);
    let ctrl = p.compile::<S>().unwrap();
    assert!(ctrl.fast_h > S::ZERO, "{}: fast path enabled", S::NAME);
    let mut rng = Rng(seed);
    let mut taken = 0;
    for k in 0..20_000 {
        // Mostly near equilibrium, sometimes far out (beyond the fixed-point bound, or huge).
        let scale = match k % 4 {
            0 | 1 => 0.2,
            2 => 2.0,
            _ => 1e30_f64.min(S::MAX_ABS),
        };
        let mut ov = false;
        let mut st = State {
            x: S::from_f64(rng.range(-1.0, scale), &mut ov),
            y: S::from_f64(rng.range(-scale, scale), &mut ov),
            eta: S::from_f64(rng.range(-0.5, 0.5), &mut ov),
            eta_prev: S::from_f64(rng.range(-0.5, 0.5), &mut ov),
            v: S::from_f64(rng.range(-2.0, 2.0), &mut ov),
        };
        let h = match k % 7 {
            0 => S::from_f64(rng.range(-0.5, 3.0), &mut ov),
            1 => S::from_f64(f64::NAN, &mut ov),
            _ => S::from_f64(rng.range(0.6, 1.4), &mut ov),
        };
        let mut st_general = st;
        let general = ctrl.general_update(&mut st_general, h);
        let before = st;
        match ctrl.fast_update(&mut st, h) {
            Some(out) => {
                taken += 1;
                assert!(
                    out.status.is_empty(),
                    "{}: fast path raised an event",
                    S::NAME
                );
                assert_eq!(
                    bits(&st, &out),
                    bits(&st_general, &general),
                    "{} case {k}: fast path differs",
                    S::NAME
                );
            }
            None => assert_eq!(st, before, "{}: declining must leave the state", S::NAME),
        }
        // And `update` as a whole is the general path.
        let mut st_update = before;
        let out = ctrl.update(&mut st_update, h);
        assert_eq!(bits(&st_update, &out), bits(&st_general, &general));
    }
    taken
}

#[test]
fn fast_path_is_bit_identical_to_the_general_path() {
    for dt in [1e-3, 1e-4] {
        for (name, taken) in [
            ("f64", fast_equals_general::<f64>(dt, 1)),
            ("f32", fast_equals_general::<f32>(dt, 2)),
            ("i32f32", fast_equals_general::<I32F32>(dt, 3)),
            ("i4f28", fast_equals_general::<I4F28>(dt, 4)),
        ] {
            // Half the cases are ordinary (small state; gap within 0.6..1.4 h0 five times in
            // seven, 36 % of all): the fast path must take most of those.
            assert!(
                taken > 4_000,
                "{name} dt={dt}: fast path taken {taken} times"
            );
        }
    }
}

#[test]
fn fast_path_off_where_it_does_not_apply() {
    let mut p = Params::paper_wheel(1e-3);
    p.n_sub = 10;
    assert_eq!(p.compile::<f32>().unwrap().fast_h, 0.0);
    p.n_sub = 1;
    p.v_max = 60.0;
    assert_eq!(p.compile::<f32>().unwrap().fast_h, 0.0);
    p.v_max = f64::INFINITY;
    p.scheme = Scheme::Accurate;
    assert_eq!(p.compile::<I4F28>().unwrap().fast_h, I4F28::ZERO);
}

/// Fixed point's Δx (division-free) against Eq. 14's exact quotient computed in f64 from
/// the same quantised state, gap and coefficients: within the rounding of its five
/// operations, the coefficients' quantisation and the series' truncation (`cr·u²`, about
/// one LSB at |η| = 1, Δt = 1 ms).
fn division_free_matches_the_quotient<S: Scalar>(dt: f64, lsb_per_unit_num: f64) -> f64 {
    let p = Params::paper_wheel(dt);
    let ctrl = p.compile::<S>().unwrap();
    let [(_, c), (_, kpd), (_, ca), (_, ca1), ..] = p.coefficients();
    let mut rng = Rng(7);
    let mut worst = 0.0f64;
    for _ in 0..50_000 {
        let mut ov = false;
        let x = S::from_f64(rng.range(-0.5, 0.5), &mut ov);
        let y = S::from_f64(rng.range(-0.5, 0.5), &mut ov);
        let eta = S::from_f64(rng.range(-1.0, 1.0), &mut ov);
        let (x1, ..) = ctrl.substep::<false>(x, y, eta, S::ZERO, &mut ov);
        assert!(!ov);
        let (xf, yf, ef) = (x.to_f64(), y.to_f64(), eta.to_f64());
        let num = yf - ef - xf * (1.0 + kpd + ef);
        let exact = c * num / (1.0 + ca1 + ca * ef);
        let err = ((x1.to_f64() - xf) - exact).abs() / S::RESOLUTION;
        let allowed = 2.0 + lsb_per_unit_num * num.abs();
        assert!(
            err <= allowed,
            "{}: {err} LSB > {allowed} at η = {ef}",
            S::NAME
        );
        worst = worst.max(err);
    }
    worst
}

#[test]
fn division_free_quotient_is_exact_to_the_format_resolution() {
    // I4F28: coefficient quantisation (½ LSB each of cr, cru·|η|) and the product roundings
    // give ≤ 2 LSB plus ≤ 2.5 LSB per unit of |N|; the omitted series term ≤ 1.1 LSB·|N|.
    let w = division_free_matches_the_quotient::<I4F28>(1e-3, 3.5);
    assert!(w > 0.0);
    division_free_matches_the_quotient::<I4F28>(1e-4, 3.5);
    // I32F32 (16× finer LSB, the same absolute truncation 4e-9·η² at 1 ms: 17 LSB).
    division_free_matches_the_quotient::<I32F32>(1e-3, 20.0);
    division_free_matches_the_quotient::<I32F32>(1e-4, 3.5);
}

#[test]
fn to_si_saturates_and_flags_instead_of_infinity() {
    let p = Params::paper_wheel(1e-3);
    let ctrl = p.compile::<f64>().unwrap();
    let out = Output {
        g: f64::MAX,
        force: f64::MAX,
        current: -f64::MAX,
        voltage: 1.0,
        status: Status::default(),
    };
    let si = ctrl.to_si(&out);
    assert_eq!(si.force, f64::MAX);
    assert_eq!(si.current, f64::MIN);
    assert!(si.g.is_finite() && si.status.contains(Status::OVERFLOW));
    // An ordinary output converts without a flag.
    let si = ctrl.to_si(&ctrl.output(&ctrl.initial_state(p.h0)));
    assert!(si.status.is_empty() && (si.force - p.p0).abs() < 1e-9);
}

#[test]
fn bad_initial_gaps_are_refused_by_name() {
    let p = Params::paper_wheel(1e-3);
    let f = p.compile::<f64>().unwrap();
    let q = p.compile::<I4F28>().unwrap();
    assert_eq!(
        f.try_initial_state(f64::NAN),
        Err(ParamError::NotFinite(fields::GAP))
    );
    assert_eq!(
        q.try_initial_state(f64::INFINITY),
        Err(ParamError::NotFinite(fields::GAP))
    );
    assert_eq!(
        f.try_equilibrium_state(0.0),
        Err(ParamError::NotPositive(fields::GAP))
    );
    assert!(matches!(
        q.try_equilibrium_state(1.0),
        Err(ParamError::Unrepresentable {
            field: fields::GAP,
            ..
        })
    ));
    assert_eq!(q.try_initial_state(0.012), Ok(q.initial_state(0.012)));
    assert_eq!(
        f.try_equilibrium_state(0.009),
        Ok(f.equilibrium_state(0.009))
    );
}

/// `n_sub = 1` (the firmware's law, which takes the fast path) against f64 over 1 s of a
/// 1 mm gap step followed by a 1 mm, 5 Hz sine, within the budgets that
/// `tests/tests/control_vs_reference.rs` sets at `n_sub = 10` (fractions of p0).
fn agreement_n1<S: Scalar>(dt: f64) -> f64 {
    let p = Params::paper_wheel(dt);
    let exact = p.compile::<f64>().unwrap();
    let typed = p.compile::<S>().unwrap();
    let (mut se, mut st) = (exact.initial_state(p.h0), typed.initial_state(p.h0));
    let steps = (1.0 / dt).round() as usize;
    let mut worst = 0.0f64;
    for k in 1..=steps {
        let t = k as f64 * dt;
        let h = if t < 0.5 {
            0.009
        } else {
            0.01 + 0.001 * libm::sin(2.0 * core::f64::consts::PI * 5.0 * t)
        };
        let mut ov = false;
        let fe = exact.to_si(&exact.update(&mut se, h / p.h0)).force;
        let ft = typed
            .to_si(&typed.update(&mut st, typed.gap_pu(h, &mut ov)))
            .force;
        worst = worst.max((fe - ft).abs() / p.p0);
    }
    worst
}

#[test]
fn n_sub_one_agrees_with_f64_within_the_budgets() {
    for dt in [1e-3, 1e-4] {
        let (a, b, c) = (
            agreement_n1::<I32F32>(dt),
            agreement_n1::<I4F28>(dt),
            agreement_n1::<f32>(dt),
        );
        assert!(a <= 4e-6, "i32f32 dt={dt}: {a:e}");
        assert!(b <= 3e-5, "i4f28 dt={dt}: {b:e}");
        assert!(c <= 1e-5, "f32 dt={dt}: {c:e}");
        std::println!("n_sub=1 dt={dt}: |ΔF|/p0 i32f32 {a:e}, i4f28 {b:e}, f32 {c:e}");
    }
}
