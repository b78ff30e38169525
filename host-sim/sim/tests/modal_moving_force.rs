//! (b) A constant force P = 36.79 kN (downward) crossing the §4.2 span at 10, 100, 150 m/s.
//!
//! 1. Against the exact solution of the same modal ODEs: each series term n obeys
//!    M ẍ + K x = [(2/L)·F·sin(nπvt/L), 0]ᵀ (M, K re-derived below from Eq. 20c–d), solved
//!    in closed form through its 2×2 eigen-decomposition (undamped, zero initial conditions):
//!    η_j = p_j/(ω_j² − Ω²)·(sin Ωt − (Ω/ω_j) sin ω_j t). Newmark (γ = ½, β = ¼) must
//!    follow it closely at both steps, and be second order where its terms are resolved.
//! 2. Against Frýba's Euler–Bernoulli series (Vibration of Solids and Structures under
//!    Moving Loads, 1972, ch. 1) on a section with negligible shear and rotary inertia:
//!    w = w0 Σ 1/(n²(n² − α²))·[sin(nωt) − (α/n) sin(ω_n t)]·sin(nπx/L),
//!    w0 = 2PL³/(π⁴EI), ω = πv/L, ω_n = n²ω_1, α = ω/ω_1.
//!
//! Peaks are over the passage (load on the span), at midspan.
mod modal_common;

use maglev_sim::physics::guideway::{BeamSection, Guideway, PointLoad};
use maglev_sim::physics::modal::ModalGuideway;
use modal_common::{euler_bernoulli_like, peak_abs, run_moving_load, L, P};
use std::f64::consts::PI;

const MODES: usize = 40;
const SPEEDS: [f64; 3] = [10.0, 100.0, 150.0];

/// Exact midspan deflection of the N-term modal system at time t (load on the span).
fn exact_modal_midspan(s: &BeamSection, modes: usize, v: f64, fz: f64, t: f64) -> f64 {
    let rho = s.density();
    let (m1, m2) = (s.mass_per_length, rho * s.iy);
    let (ei, gas) = (s.youngs_modulus * s.iy, s.shear_modulus * s.shear_area_z);
    let mut w = 0.0;
    for n in (1..=modes).filter(|n| n % 2 == 1) {
        let k = n as f64 * PI / L;
        let (k11, k12, k22) = (gas * k * k, -gas * k, ei * k * k + gas);
        // det(K − λM) = 0 → m1 m2 λ² − (k11 m2 + k22 m1) λ + (k11 k22 − k12²) = 0
        let (a, b, c) = (m1 * m2, k11 * m2 + k22 * m1, k11 * k22 - k12 * k12);
        let big = (b + (b * b - 4.0 * a * c).sqrt()) / (2.0 * a);
        let omega_load = k * v;
        let f0 = 2.0 / L * fz; // amplitude of the generalized force on q_n
        let mut q = 0.0;
        for lam in [c / (a * big), big] {
            // (K − λM) φ = 0 from the first row; mass-normalise.
            let (p1, p2) = (k12, lam * m1 - k11);
            let norm = (m1 * p1 * p1 + m2 * p2 * p2).sqrt();
            let p1 = p1 / norm; // only the translation component enters w and the force
            let om = lam.sqrt();
            let eta = p1 * f0 / (lam - omega_load * omega_load)
                * ((omega_load * t).sin() - omega_load / om * (om * t).sin());
            q += p1 * eta;
        }
        w += q * (n as f64 * PI / 2.0).sin();
    }
    w
}

/// Frýba's Euler–Bernoulli series at midspan, `terms` terms.
fn fryba_midspan(s: &BeamSection, terms: usize, v: f64, t: f64) -> f64 {
    let ei = s.youngs_modulus * s.iy;
    let w1 = (PI / L).powi(2) * (ei / s.mass_per_length).sqrt();
    let om = PI * v / L;
    let alpha = om / w1;
    let w0 = 2.0 * P * L.powi(3) / (PI.powi(4) * ei);
    let mut w = 0.0;
    for n in (1..=terms).map(|n| n as f64) {
        let wn = n * n * w1;
        w += 1.0 / (n * n * (n * n - alpha * alpha))
            * ((n * om * t).sin() - alpha / n * (wn * t).sin())
            * (n * PI / 2.0).sin();
    }
    -w0 * w // P acts downward
}

fn downward() -> PointLoad {
    PointLoad {
        fz: -P,
        ..Default::default()
    }
}

/// Newmark history of the midspan deflection and the worst deviation from `reference`
/// relative to the reference peak; returns (newmark peak, reference peak, max rel. dev.).
fn compare<R: Fn(f64) -> f64>(
    s: &BeamSection,
    modes: usize,
    v: f64,
    dt: f64,
    reference: R,
) -> (f64, f64, f64) {
    let mut g = ModalGuideway::new(s.clone(), L, modes, dt).unwrap();
    let h = run_moving_load(&mut g, downward(), v, L, |g| g.section_at(L / 2.0).z);
    let reference: Vec<f64> = h.iter().map(|p| reference(p.0)).collect();
    let ref_peak = reference.iter().fold(0.0_f64, |m, w| m.max(w.abs()));
    let dev = h
        .iter()
        .zip(&reference)
        .map(|(p, r)| (p.2 - r).abs())
        .fold(0.0, f64::max);
    (peak_abs(&h), ref_peak, dev / ref_peak)
}

#[test]
fn newmark_matches_exact_modal_solution_second_order() {
    let s = BeamSection::paper_4_2();
    for v in SPEEDS {
        let exact = |t| exact_modal_midspan(&s, MODES, v, -P, t);
        let (pk4, ex4, d4) = compare(&s, MODES, v, 1e-4, exact);
        let (pk5, ex5, d5) = compare(&s, MODES, v, 1e-5, exact);
        println!(
            "v = {v:5} m/s  exact peak {:.6e} m | dt 1e-4: peak {:.6e} (Δpeak {:.2e}, max dev {:.2e}) \
             | dt 1e-5: peak {:.6e} (Δpeak {:.2e}, max dev {:.2e})",
            ex5,
            pk4,
            (pk4 - ex4) / ex4,
            d4,
            pk5,
            (pk5 - ex5) / ex5,
            d5
        );
        // Newmark's period error is (ωΔt)²/12; on the dominant first mode (ω ≈ 38 rad/s)
        // over a ≤ 2.5 s passage that is a phase error ≲ 1e-4 at Δt = 1e-4.
        assert!(d4 < 1e-3, "v = {v}: deviation {d4} at dt = 1e-4");
        assert!(d5 < 1e-5, "v = {v}: deviation {d5} at dt = 1e-5");
    }
}

/// Second order in Δt. The deviation from the exact modal solution has two parts: the
/// period error (ωΔt)²/12 of the bending branch, second order; and the shear/rotation-branch
/// terms (ω ≥ 2.9e3 rad/s, up to ≈ 2e4 rad/s at n = 40), which carry only ~1e-7–1e-6 of the
/// peak but whose phase error ω·t·(ωΔt)²/12 is ≳ 1 rad over a passage at either step: a
/// floor that does not shrink as Δt². Measured at 10 m/s, max deviation relative to the
/// peak: 5 terms 3.1e-5 / 3.1e-7 / 1.5e-7 at Δt = 1e-4 / 1e-5 / 3e-6; 40 terms 4.8e-5 /
/// 3.9e-6 / 8.1e-7. With 5 terms the floor sits below the Δt = 1e-5 error, so a 10× smaller
/// step must cut the deviation ~100× (≥ 50× required).
#[test]
fn newmark_error_is_second_order() {
    let s = BeamSection::paper_4_2();
    for v in SPEEDS {
        let exact = |t| exact_modal_midspan(&s, 5, v, -P, t);
        let (_, _, d3) = compare(&s, 5, v, 1e-4, exact);
        let (_, _, d4) = compare(&s, 5, v, 1e-5, exact);
        println!(
            "v = {v:5} m/s, 5 terms: max dev {d3:.2e} (dt 1e-4), {d4:.2e} (dt 1e-5), ratio {:.1}",
            d3 / d4
        );
        assert!(
            d3 / d4 > 50.0,
            "v = {v}: error ratio {} is not second order",
            d3 / d4
        );
    }
}

#[test]
fn euler_bernoulli_limit_matches_fryba() {
    let eb = euler_bernoulli_like();
    let real = BeamSection::paper_4_2();
    for v in SPEEDS {
        for dt in [1e-4, 1e-5] {
            let (pk, fr, dev) = compare(&eb, MODES, v, dt, |t| fryba_midspan(&eb, MODES, v, t));
            println!(
                "v = {v:5} m/s dt = {dt:.0e}: EB-limit modal peak {pk:.6e} m, Frýba {fr:.6e} m, \
                 Δpeak {:.2e}, max dev {dev:.2e}",
                (pk - fr) / fr
            );
            // Residual shear/rotary terms ~1e-6 plus the Newmark error bounded above.
            let tol = if dt > 5e-5 { 1e-3 } else { 2e-5 };
            assert!(dev < tol, "v = {v}, dt = {dt}: deviation {dev}");
        }
        // For the record: the real (Timoshenko) §4.2 span against Frýba's EB beam.
        let (pk, fr, _) = compare(&real, MODES, v, 1e-5, |t| fryba_midspan(&real, MODES, v, t));
        println!(
            "v = {v:5} m/s: Timoshenko §4.2 peak {pk:.6e} m vs Frýba EB {fr:.6e} m ({:+.2} %)",
            100.0 * (pk - fr) / fr
        );
        assert!(
            pk > fr,
            "shear deformation must make the Timoshenko span deflect more"
        );
    }
}

/// Wall time of one 100 m/s passage at Δt = 1e-5 with the default number of modes (printed,
/// not asserted: CI machines differ).
#[test]
fn passage_wall_time() {
    let s = BeamSection::paper_4_2();
    let mut g = ModalGuideway::new(s, L, maglev_sim::physics::modal::DEFAULT_MODES, 1e-5).unwrap();
    let t0 = std::time::Instant::now();
    let h = run_moving_load(&mut g, downward(), 100.0, L, |g| g.section_at(L / 2.0).z);
    println!(
        "100 m/s passage, dt 1e-5, {} modes, {} steps: {:.3} s wall, peak {:.6e} m",
        g.modes(),
        h.len(),
        t0.elapsed().as_secs_f64(),
        peak_abs(&h)
    );
}
