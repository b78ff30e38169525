//! Helpers shared by the modal-reference tests: the §4.2 span and a constant force
//! crossing it. Nothing here computes an expected value.
#![allow(dead_code)]

use maglev_sim::physics::guideway::{BeamSection, Guideway, PointLoad};
use maglev_sim::physics::modal::ModalGuideway;

/// §4.2 span length (m), docs/model.md §9.
pub const L: f64 = 25.0;
/// The force used throughout (N, magnitude; applied downward).
pub const P: f64 = 36.79e3;

/// The §4.2 section made Euler–Bernoulli-like: G·A_s ×1e6 (shear deformation ~1e-6 of
/// bending), and ρI ×1e-6 with E ×1e6 so that E·I is unchanged (rotary inertia negligible).
pub fn euler_bernoulli_like() -> BeamSection {
    let s = BeamSection::paper_4_2();
    BeamSection {
        youngs_modulus: s.youngs_modulus * 1e6,
        iy: s.iy * 1e-6,
        iz: s.iz * 1e-6,
        shear_area_y: s.shear_area_y * 1e6,
        shear_area_z: s.shear_area_z * 1e6,
        polar_mass: Some(s.polar_mass_per_length()),
        ..s
    }
}

/// A load `template` (its `x` ignored) moving from x = 0 at `speed` m/s; steps until the
/// load reaches `x_end`. Returns, per step, (t, x of the load, value of `probe`).
pub fn run_moving_load<F: Fn(&ModalGuideway) -> f64>(
    g: &mut ModalGuideway,
    template: PointLoad,
    speed: f64,
    x_end: f64,
    probe: F,
) -> Vec<(f64, f64, f64)> {
    let dt = g.time_step();
    let steps = (x_end / speed / dt).round() as usize;
    let mut out = Vec::with_capacity(steps);
    for j in 1..=steps {
        let t = j as f64 * dt;
        let x = speed * t;
        g.solve_step(&[PointLoad { x, ..template }]);
        g.commit();
        out.push((t, x, probe(g)));
    }
    out
}

/// Largest |value| in a history.
pub fn peak_abs(h: &[(f64, f64, f64)]) -> f64 {
    h.iter().map(|p| p.2.abs()).fold(0.0, f64::max)
}
