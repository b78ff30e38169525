//! The closed forms against nalgebra, against the core's own update, and the stability
//! verdicts against simulations of the core (`Params::compile::<f64>()` + `update`).

use super::discrete::{self, critical_dt, critical_dt_bisect, spectral_radius, Step};
use super::inner_loop::Loop;
use super::plant::{rigid_growth_rate, Plant, Suspension};
use maglev_core::gap::Geometry;
use maglev_core::{Params, State, Status};

fn paper(alpha: f64, dt: f64, n_sub: u32) -> Params {
    let mut p = Params::paper_wheel(dt);
    p.alpha = alpha;
    p.n_sub = n_sub;
    p
}

#[test]
fn continuous_poles_solve_the_characteristic_polynomial() {
    let lp = Loop::new(&paper(0.5, 1e-3, 1), 0.0);
    let (s, n) = (lp.poles(), lp.poles_numeric());
    // Vieta: sum −p/τ, product ki/τ (independent of how the roots were found).
    let sum = s[0].re + s[1].re;
    let prod = s[0].re * s[1].re - s[0].im * s[1].im;
    assert!((sum + lp.p / lp.tau).abs() < 1e-12 * lp.p / lp.tau);
    assert!((prod - lp.ki / lp.tau).abs() < 1e-12 * lp.ki / lp.tau);
    for (a, b) in s.iter().zip(&n) {
        assert!((a.re - b.re).abs() + (a.im - b.im).abs() < 1e-9 * a.abs());
    }
    // Paper values by hand: τ = 2·p0·h0/(R0·i0²) = 2·36787.5·0.01/1849 s, p = 2, ki = 600.
    assert!((lp.tau - 2.0 * 36787.5 * 0.01 / 1849.0).abs() < 1e-12);
    assert!((lp.p - 2.0).abs() < 1e-12 && (lp.ki - 600.0).abs() < 1e-9);
}

/// Runs the core one outer step from `(x, y)` at the nominal gap.
fn core_step(p: &Params, x: f64, y: f64) -> (f64, f64) {
    let ctrl = p.compile::<f64>().unwrap();
    let mut st: State<f64> = ctrl.initial_state(p.h0);
    st.x = x;
    st.y = y;
    let out = ctrl.update(&mut st, 1.0);
    assert!(out.status.is_empty());
    (st.x, st.y)
}

#[test]
fn amplification_matrix_is_the_cores_update() {
    // The core is affine in (x, y) at a fixed gap with zero offset at η = 0, so its response
    // to unit perturbations is the matrix's columns (scaled), to rounding.
    for alpha in [0.0, 0.3, 0.5, 0.75, 1.0] {
        for dt in [1e-4, 1e-3, 0.05, 0.3] {
            let p = paper(alpha, dt, 1);
            let m = Step::new(&p, 0.0).matrix();
            let e = 1e-3;
            let (x1, y1) = core_step(&p, e, 0.0);
            let (x2, y2) = core_step(&p, 0.0, e);
            let got = [[x1 / e, x2 / e], [y1 / e, y2 / e]];
            for i in 0..2 {
                for j in 0..2 {
                    let want = m[(i, j)];
                    assert!(
                        (got[i][j] - want).abs() < 1e-10 * want.abs().max(1.0),
                        "α={alpha} Δt={dt} M[{i}{j}] {} vs {want}",
                        got[i][j]
                    );
                }
            }
            let ev = Step::new(&p, 0.0).eigenvalues();
            let r = ev[0].abs().max(ev[1].abs());
            assert!((r - Step::new(&p, 0.0).radius()).abs() < 1e-12 * r.max(1.0));
        }
    }
}

#[test]
fn small_steps_reproduce_the_continuous_poles_to_first_order() {
    // λ = e^{sδ} + O(δ²) per step, so ln(λ)/δ − s = O(δ): the error must fall ~10× per
    // decade of δ (the scheme is first order, see docs/numerics.md).
    let mut errs = vec![];
    for dt in [1e-3, 1e-4, 1e-5] {
        let p = paper(0.5, dt, 1);
        let s = Loop::new(&p, 0.0).poles()[0];
        let l = Step::new(&p, 0.0).eigenvalues()[0];
        let ln = nalgebra::Complex::new(l.re, l.im).ln() / dt;
        errs.push((ln.re - s.re).hypot(ln.im - s.im) / s.abs());
    }
    assert!(errs[0] < 0.05, "{errs:?}");
    for w in errs.windows(2) {
        let ratio = w[0] / w[1];
        assert!((5.0..20.0).contains(&ratio), "{errs:?}");
    }
}

#[test]
fn closed_form_critical_step_matches_bisection_on_eigenvalues() {
    for alpha in [0.0, 0.25, 0.5, 0.6, 0.75, 0.9, 0.99] {
        for n_sub in [1, 7] {
            let p = paper(alpha, 1e-3, n_sub);
            let a = critical_dt(&p, 0.0).expect("α < 1 has a critical step");
            let b = critical_dt_bisect(&p, 0.0, 1e4).unwrap();
            assert!((a - b).abs() < 1e-6 * a, "α={alpha}: {a} vs {b}");
            // Linear in n_sub: n_sub sub-steps of the same δ.
            let one = critical_dt(&paper(alpha, 1e-3, 1), 0.0).unwrap();
            assert!((a - one * n_sub as f64).abs() < 1e-12 * a);
        }
    }
    // α = 1: no critical step up to 10⁴ s, with both methods.
    let p = paper(1.0, 1e-3, 1);
    assert_eq!(critical_dt(&p, 0.0), None);
    assert_eq!(critical_dt_bisect(&p, 0.0, 1e4), None);
    // KI = 0: none for α ≥ ½, the linear root for α < ½.
    let mut p = paper(0.5, 1e-3, 1);
    p.ki = 0.0;
    assert_eq!(critical_dt(&p, 0.0), None);
    p.alpha = 0.25;
    let lp = Loop::new(&p, 0.0);
    assert!((critical_dt(&p, 0.0).unwrap() - 4.0 * lp.tau / lp.p).abs() < 1e-12);
}

#[test]
fn critical_step_solves_the_quadratic_for_the_paper_values() {
    // Q(δ) = (1 − α)·600·δ² + (1 − 2α)·2·δ − 2τ, τ = 2·36787.5·0.01/1849, solved by hand.
    let tau = 2.0 * 36787.5 * 0.01 / 1849.0;
    for alpha in [0.5f64, 0.6, 0.75, 0.9] {
        let (a, b, c) = ((1.0 - alpha) * 600.0, (1.0 - 2.0 * alpha) * 2.0, -2.0 * tau);
        let want = (-b + (b * b - 4.0 * a * c).sqrt()) / (2.0 * a);
        let got = critical_dt(&paper(alpha, 1e-3, 1), 0.0).unwrap();
        assert!((got - want).abs() < 1e-12, "α={alpha}");
    }
    // α = ½: δ* = √(2τ/300) = 51.5 ms.
    let d = critical_dt(&paper(0.5, 1e-3, 1), 0.0).unwrap();
    assert!((d - (2.0 * tau / 300.0).sqrt()).abs() < 1e-12);
}

/// Simulates the core from a small perturbation at the nominal gap until the verdict is
/// unambiguous given the analysis' radius `rho` (≠ 1 by a margin): `true` if it decayed by
/// 10² after ρ^N ≤ 10⁻⁸, `false` if it grew by 10². Panics if neither happened (the
/// remaining factor 10⁶ covers transient, non-normal amplification).
///
/// Size is measured in the continuous loop's energy norm `√(ki·τ·x² + y²)`, which never grows
/// along Eq. 9 + 10 (`d/dt (ki·x² + y²/τ) = −2·ki·p·x²/τ ≤ 0`): in it the exchange between
/// `x` and the much larger `y ≈ τ·ω·x` of an oscillation is not mistaken for growth.
fn simulated_decay(p: &Params, rho: f64) -> bool {
    let ctrl = p.compile::<f64>().unwrap();
    let lp = Loop::new(p, 0.0);
    let norm = |st: &State<f64>| (lp.ki * lp.tau * st.x * st.x + st.y * st.y).sqrt();
    let mut st: State<f64> = ctrl.initial_state(p.h0);
    st.x = 1e-7;
    let n0 = norm(&st);
    let steps = ((8.0 * std::f64::consts::LN_10) / rho.ln().abs()).ceil() as usize;
    for _ in 0..steps {
        let out = ctrl.update(&mut st, 1.0);
        // Reaching the current clamp (x < −1 from 1e-7) or the type's range within one step is
        // growth by more than 10⁷: far past the 10² threshold below.
        if out.status.contains(Status::CURRENT_CLAMPED) || out.status.contains(Status::OVERFLOW) {
            return false;
        }
        assert!(out.status.is_empty(), "{:?}", out.status);
        if norm(&st) > 1e2 * n0 {
            return false;
        }
    }
    let n = norm(&st);
    assert!(
        n < 1e-2 * n0,
        "ambiguous after {steps} steps: {n:e} of {n0:e}, ρ = {rho}"
    );
    true
}

#[test]
fn simulation_confirms_the_region_on_both_sides_of_the_critical_step() {
    for alpha in [0.0, 0.5, 0.6, 0.75, 0.9] {
        for n_sub in [1, 4] {
            let crit = critical_dt(&paper(alpha, 1e-3, n_sub), 0.0).unwrap();
            for (f, stable) in [(0.8, true), (0.99, true), (1.01, false), (1.25, false)] {
                let p = paper(alpha, f * crit, n_sub);
                let rho = spectral_radius(&p, 0.0);
                assert_eq!(rho < 1.0, stable, "α={alpha} n={n_sub} Δt={}·Δt*", f);
                assert_eq!(simulated_decay(&p, rho), stable, "α={alpha} Δt={f}·Δt*");
            }
        }
    }
    // α = 1 at steps far beyond anything else's critical value.
    for dt in [0.1, 10.0, 1e3] {
        let p = paper(1.0, dt, 1);
        let rho = spectral_radius(&p, 0.0);
        assert!(rho < 1.0);
        assert!(simulated_decay(&p, rho));
    }
}

#[test]
fn plant_has_a_neutral_and_an_unstable_gap_mode() {
    let p = paper(0.5, 1e-3, 1);
    for s in [
        Suspension::FIG1,
        Suspension {
            magnet_mass: 500.0,
            ..Suspension::FIG1
        },
    ] {
        let poles = Plant::new(&p, &s, Geometry::Ems).unwrap().poles();
        let scale = poles.iter().map(|z| z.abs()).fold(0.0, f64::max);
        assert!(poles.iter().any(|z| z.abs() < 1e-9 * scale), "{poles:?}");
        assert!(poles.iter().any(|z| z.re > 0.1 && z.im == 0.0), "{poles:?}");
    }
    // A very stiff suspension makes magnet and body one rigid mass: the largest real
    // pole tends to the root of the rigid cubic (found independently by bisection).
    let stiff = Suspension {
        magnet_mass: 0.0,
        k: 1e12,
        c: 1e9,
    };
    let poles = Plant::new(&p, &stiff, Geometry::Ems).unwrap().poles();
    let real_max = poles
        .iter()
        .filter(|z| z.im == 0.0)
        .map(|z| z.re)
        .fold(f64::MIN, f64::max);
    let rigid = rigid_growth_rate(&p);
    assert!(
        (real_max - rigid).abs() < 1e-4 * rigid,
        "{real_max} vs {rigid}"
    );
    // ...which is positive: M·τ·s³ + M·p·s² + M·ki·s − 2·p0/h0 at the root.
    let lp = Loop::new(&p, 0.0);
    let m = p.p0 / 9.81;
    let f = |s: f64| m * lp.tau * s.powi(3) + m * lp.p * s * s + m * lp.ki * s - 2.0 * p.p0 / p.h0;
    assert!(rigid > 0.0 && f(rigid).abs() < 1e-9 * 2.0 * p.p0 / p.h0);
}

mod props {
    use super::*;
    use proptest::prelude::*;

    /// Physically plausible magnets and gains, with Δt spread around the critical step.
    fn any_case() -> impl Strategy<Value = Params> {
        (
            (10.0f64..100.0, 5e-3f64..20e-3, 0.1f64..5.0, 1e3f64..1e5),
            (0.0f64..0.1, 0.5f64..50.0, 0.0f64..=1.0),
            (1u32..=6, -2.0f64..1.0),
        )
            .prop_map(|((i0, h0, r0, p0), (kp, ki, alpha), (n_sub, log_f))| {
                let mut p = Params::paper(p0, 1.0);
                (p.i0, p.h0, p.r0, p.kp, p.ki, p.alpha, p.n_sub) =
                    (i0, h0, r0, kp, ki, alpha, n_sub);
                // Δt = f·Δt* with f ∈ [0.01, 10] where Δt* exists, else f·τ·n_sub.
                let base = critical_dt(&p, 0.0).unwrap_or(Loop::new(&p, 0.0).tau * n_sub as f64);
                p.dt = base * 10f64.powf(log_f);
                p
            })
    }

    proptest! {
        #![proptest_config(ProptestConfig {
            cases: 96,
            rng_algorithm: proptest::test_runner::RngAlgorithm::ChaCha,
            rng_seed: proptest::test_runner::RngSeed::Fixed(0x5eed_0002),
            failure_persistence: None,
            ..ProptestConfig::default()
        })]
        #[test]
        fn analysis_verdict_matches_simulation(p in any_case()) {
            let rho = spectral_radius(&p, 0.0);
            prop_assume!(!(0.999..=1.001).contains(&rho));
            prop_assert_eq!(simulated_decay(&p, rho), rho < 1.0, "ρ = {}", rho);
            // The closed-form region agrees with the eigenvalues: Q < 0 ⇔ ρ < 1.
            let q = discrete::Step::new(&p, 0.0).q();
            prop_assert_eq!(q < 0.0, rho < 1.0);
        }
    }
}

fn accurate(dt: f64) -> Params {
    let mut p = Params::paper_wheel(dt);
    p.scheme = maglev_core::Scheme::Accurate;
    p
}

#[test]
fn accurate_scheme_is_the_pade_map_and_stable_at_every_step() {
    // The core's accurate update at a fixed gap against the (2, 2) Padé approximant of e^{ΔtJ}
    // computed by nalgebra from J alone (gauss.rs): the same matrix to rounding.
    for dt in [1e-4, 1e-3, 1e-2, 0.05, 0.3, 10.0] {
        let p = accurate(dt);
        let want = super::gauss::outer_matrix(&p, 0.0);
        let e = 1e-3;
        let (x1, y1) = core_step(&p, e, 0.0);
        let (x2, y2) = core_step(&p, 0.0, e);
        let got = [[x1 / e, x2 / e], [y1 / e, y2 / e]];
        for i in 0..2 {
            for j in 0..2 {
                let w = want[(i, j)];
                assert!(
                    (got[i][j] - w).abs() < 1e-9 * w.abs().max(1.0),
                    "Δt={dt} R[{i}{j}] {} vs {w}",
                    got[i][j]
                );
            }
        }
        // A-stable: below 1 for every step, including far beyond the paper scheme's Δt*.
        let rho = super::gauss::spectral_radius(&p, 0.0);
        assert!(rho < 1.0, "Δt={dt}: ρ = {rho}");
    }
}

#[test]
fn accurate_scheme_reproduces_the_continuous_poles_to_fourth_order() {
    // ln(λ)/Δt − s = O(Δt⁴) for the Padé map: the error must fall ~10⁴× per decade of Δt.
    let mut errs = vec![];
    for dt in [1e-3, 1e-4] {
        let p = accurate(dt);
        let s = Loop::new(&p, 0.0).poles()[0];
        let ev = super::gauss::outer_matrix(&p, 0.0).complex_eigenvalues();
        let z = ev.iter().find(|z| z.im > 0.0).unwrap().ln() / dt;
        errs.push((z.re - s.re).hypot(z.im - s.im));
    }
    let order = (errs[0] / errs[1]).log10();
    assert!((3.7..4.3).contains(&order), "{errs:?}");
}
