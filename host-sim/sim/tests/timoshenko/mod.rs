//! Closed forms of a simply supported Timoshenko beam (the FE's references; shared by the
//! library's FE tests and the `maglev modes` tests).

use maglev_sim::physics::guideway::BeamSection;
use std::f64::consts::PI;

/// The span (m) of every closed form here.
pub const L: f64 = 25.0;

pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Closed-form circular frequency of mode n of a simply supported Timoshenko beam: the smaller
/// root in ω² of (G A_s k² − ρA ω²)(EI k² + G A_s − ρI ω²) − (G A_s k)² = 0, k = nπ/L.
pub fn timoshenko_omega(n: usize, ei: f64, gas: f64, rho_a: f64, rho_i: f64) -> f64 {
    let k = n as f64 * PI / L;
    let a = rho_a * rho_i;
    let b = rho_a * (ei * k * k + gas) + rho_i * gas * k * k;
    let c = gas * ei * k.powi(4);
    // Smaller root, in the cancellation-free form 2c / (b + sqrt(b² − 4ac)).
    (2.0 * c / (b + (b * b - 4.0 * a * c).sqrt())).sqrt()
}

pub fn vertical_omega(s: &BeamSection, n: usize) -> f64 {
    let rho = s.mass_per_length / s.area;
    timoshenko_omega(
        n,
        s.youngs_modulus * s.iy,
        s.shear_modulus * s.shear_area_z,
        s.mass_per_length,
        rho * s.iy,
    )
}

pub fn lateral_omega(s: &BeamSection, n: usize) -> f64 {
    let rho = s.mass_per_length / s.area;
    timoshenko_omega(
        n,
        s.youngs_modulus * s.iz,
        s.shear_modulus * s.shear_area_y,
        s.mass_per_length,
        rho * s.iz,
    )
}
