//! A moving force over three simply supported spans: the FE guideway against the modal
//! reference over the same viaduct (an independent method: Fourier series per span,
//! docs/model.md §8) at every span's midspan, and both against the closed-form forced response of
//! each span's modal system while the force is on that span.

use maglev_sim::physics::fe::FeGuideway;
use maglev_sim::physics::guideway::{BeamSection, Bridge, Guideway, PointLoad};
use maglev_sim::physics::modal::{ModalSpans, DEFAULT_MODES};
use std::f64::consts::PI;

const L: f64 = 25.0;
const SPANS: usize = 3;
const P: f64 = 36.79e3;
const V: f64 = 100.0;
const DT: f64 = 1e-4;

/// Closed-form midspan deflection of one simply supported span, `modes` series terms of
/// Eq. 20c–d, a downward force P entering at x = 0 at time 0 with speed V, at time t while
/// it is on the span (zero initial conditions): per term the 2×2 system is diagonalised and
/// each mode answers p_j/(ω_j² − Ω²)·(sin Ωt − (Ω/ω_j) sin ω_j t).
fn closed_form_midspan(s: &BeamSection, modes: usize, t: f64) -> f64 {
    let (m1, m2) = (s.mass_per_length, s.density() * s.iy);
    let (ei, gas) = (s.youngs_modulus * s.iy, s.shear_modulus * s.shear_area_z);
    let mut w = 0.0;
    for n in (1..=modes).filter(|n| n % 2 == 1) {
        let k = n as f64 * PI / L;
        let (k11, k12, k22) = (gas * k * k, -gas * k, ei * k * k + gas);
        let (a, b, c) = (m1 * m2, k11 * m2 + k22 * m1, k11 * k22 - k12 * k12);
        let big = (b + (b * b - 4.0 * a * c).sqrt()) / (2.0 * a);
        let om_load = k * V;
        let f0 = -2.0 / L * P;
        for lam in [c / (a * big), big] {
            let (p1, p2) = (k12, lam * m1 - k11);
            let p1 = p1 / (m1 * p1 * p1 + m2 * p2 * p2).sqrt();
            let om = lam.sqrt();
            let eta = p1 * f0 / (lam - om_load * om_load)
                * ((om_load * t).sin() - om_load / om * (om * t).sin());
            w += p1 * eta * (n as f64 * PI / 2.0).sin();
        }
    }
    w
}

/// Midspan deflections of every span, per step, for the force crossing all spans and 0.2 s
/// beyond.
fn history(g: &mut impl Guideway) -> Vec<[f64; SPANS]> {
    let steps = ((SPANS as f64 * L / V + 0.2) / DT).round() as usize;
    (1..=steps)
        .map(|n| {
            let x = V * DT * n as f64;
            let loads = [PointLoad {
                x,
                fz: -P,
                ..Default::default()
            }];
            g.solve_step(if x <= SPANS as f64 * L { &loads } else { &[] });
            g.commit();
            core::array::from_fn(|k| g.section_at((k as f64 + 0.5) * L).z)
        })
        .collect()
}

#[test]
fn three_spans_fe_matches_modal_reference_and_closed_form() {
    let s = BeamSection::paper_4_2();
    let bridge = Bridge {
        section: s.clone(),
        spans: vec![L; SPANS],
    };
    let fe = history(&mut FeGuideway::new(&bridge, 20, DT).unwrap());
    let modal = history(&mut ModalSpans::new(&bridge, DEFAULT_MODES, DT).unwrap());
    let on_span = (L / V / DT).round() as usize;
    let mut peaks = Vec::new();
    for k in 0..SPANS {
        let peak = modal.iter().fold(0.0f64, |m, w| m.max(w[k].abs()));
        let dev = fe
            .iter()
            .zip(&modal)
            .fold(0.0f64, |m, (a, b)| m.max((a[k] - b[k]).abs()));
        // While the force is on span k (steps k·on_span + 1 ..= (k+1)·on_span), the closed
        // form of that span with the time shifted to its entry.
        let (mut dev_fe, mut dev_modal) = (0.0f64, 0.0f64);
        for step in k * on_span + 1..=(k + 1) * on_span {
            let t = step as f64 * DT - k as f64 * L / V;
            let exact = closed_form_midspan(&s, DEFAULT_MODES, t);
            dev_fe = dev_fe.max((fe[step - 1][k] - exact).abs());
            dev_modal = dev_modal.max((modal[step - 1][k] - exact).abs());
        }
        // Before the force arrives the span is exactly at rest.
        assert!(fe[..k * on_span].iter().all(|w| w[k] == 0.0), "span {k}");
        println!(
            "span {}: peak {peak:.6e} m; FE vs modal {:.3} %, FE vs closed form {:.3} %, modal vs closed form {:.3} %",
            k + 1,
            100.0 * dev / peak,
            100.0 * dev_fe / peak,
            100.0 * dev_modal / peak
        );
        assert!(dev <= 5e-3 * peak, "span {k}: FE vs modal {dev} of {peak}");
        assert!(dev_fe <= 5e-3 * peak, "span {k}: FE vs closed form");
        assert!(dev_modal <= 5e-3 * peak, "span {k}: modal vs closed form");
        peaks.push(peak);
    }
    // Identical spans, identical crossings (up to the step grid): the same peak.
    assert!(
        peaks.iter().all(|p| (p / peaks[0] - 1.0).abs() < 1e-3),
        "{peaks:?}"
    );
}
