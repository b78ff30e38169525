//! (a) Natural frequencies of the modal reference (Eq. 20a–e) against the closed-form
//! frequency equation of a simply supported Timoshenko beam, written here in its textbook
//! form (e.g. Han, Benaroya & Wei, JSV 225 (1999), pinned–pinned case), with κ = A_s/A:
//!
//!   (ρ² I / (κG)) ω⁴ − (ρA + ρI k² + ρ E I k² / (κG)) ω² + E I k⁴ = 0,   k = nπ/L
//!
//! and torsion ω = k √(G J / ρI_p). The code under test solves a symmetric 2×2 eigenproblem
//! instead; agreement to 1e-9 relative is far above its rounding (the two branches differ by
//! at most ~1e4 in ω², so eigenvalue rounding is ≲ 1e-12 relative).
mod modal_common;

use maglev_sim::physics::guideway::BeamSection;
use maglev_sim::physics::modal::{natural_frequencies, ModalGuideway};
use modal_common::{euler_bernoulli_like, L};
use std::f64::consts::PI;

/// Both roots ω (ascending) of the textbook frequency equation for one plane.
fn textbook(s: &BeamSection, i: f64, a_s: f64, k: f64) -> [f64; 2] {
    let rho = s.density();
    let kappa = a_s / s.area;
    let (e, g) = (s.youngs_modulus, s.shear_modulus);
    let a = rho * rho * i / (kappa * g);
    let b = rho * s.area + rho * i * k * k + rho * e * i * k * k / (kappa * g);
    let c = e * i * k.powi(4);
    let big = (b + (b * b - 4.0 * a * c).sqrt()) / (2.0 * a);
    let small = c / (a * big);
    [small.sqrt(), big.sqrt()]
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn frequencies_match_textbook_timoshenko_equation() {
    let s = BeamSection::paper_4_2();
    let g = ModalGuideway::new(s.clone(), L, 40, 1e-5).unwrap();
    let mut worst: f64 = 0.0;
    for f in g.natural_frequencies() {
        let k = f.n as f64 * PI / L;
        let v = textbook(&s, s.iy, s.shear_area_z, k);
        let h = textbook(&s, s.iz, s.shear_area_y, k);
        let t = k * (s.shear_modulus * s.torsion_constant / s.polar_mass_per_length()).sqrt();
        for (got, want) in [
            (f.vertical[0], v[0]),
            (f.vertical[1], v[1]),
            (f.lateral[0], h[0]),
            (f.lateral[1], h[1]),
            (f.torsion, t),
        ] {
            worst = worst.max(rel(got, want));
            assert!(rel(got, want) < 1e-9, "n = {}: {got} vs {want}", f.n);
        }
        if f.n <= 5 || f.n == 40 {
            println!(
                "n={:2}  vertical {:9.3} / {:9.3} Hz  lateral {:9.3} / {:9.3} Hz  torsion {:8.3} Hz",
                f.n,
                f.vertical[0] / (2.0 * PI),
                f.vertical[1] / (2.0 * PI),
                f.lateral[0] / (2.0 * PI),
                f.lateral[1] / (2.0 * PI),
                f.torsion / (2.0 * PI)
            );
        }
    }
    println!("worst relative difference vs textbook equation: {worst:.2e}");
}

/// With negligible shear deformation and rotary inertia the bending branch must tend to the
/// Euler–Bernoulli value k² √(EI/ρA) (1e-5: the residual shear/rotary terms are ~1e-6 and
/// grow as k²).
#[test]
fn bending_branch_tends_to_euler_bernoulli() {
    let s = euler_bernoulli_like();
    for n in [1, 2, 5, 10, 20] {
        let k = n as f64 * PI / L;
        let eb = k * k * (s.youngs_modulus * s.iy / s.mass_per_length).sqrt();
        let f = natural_frequencies(&s, L, n);
        assert!(
            rel(f.vertical[0], eb) < 1e-5,
            "n = {n}: {} vs {eb}",
            f.vertical[0]
        );
    }
}

/// Shear deformation lowers the bending branch of the real §4.2 section (Timoshenko below
/// Euler–Bernoulli), more so for short wavelengths: an ordering that a sign slip in the
/// coupling terms would break.
#[test]
fn shear_lowers_the_bending_branch() {
    let s = BeamSection::paper_4_2();
    let mut prev_ratio = 1.0;
    for n in 1..=10 {
        let k = n as f64 * PI / L;
        let eb = k * k * (s.youngs_modulus * s.iy / s.mass_per_length).sqrt();
        let ratio = natural_frequencies(&s, L, n).vertical[0] / eb;
        assert!(
            ratio < prev_ratio,
            "n = {n}: ratio {ratio} not below {prev_ratio}"
        );
        prev_ratio = ratio;
    }
}
