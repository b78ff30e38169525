//! The track on the girder (`physics::rail::track`): the rail on discrete fastenings against
//! two independent solutions, and Hertz in series with the track.

use maglev_sim::physics::rail::track::{
    discrete_beam_compliance, winkler_compliance, SlabTrack, TrackSupport,
};
use maglev_sim::physics::rail::wheelset::hertz_in_series;
use std::f64::consts::PI;

/// The exact compliance of an infinite Euler beam (`ei`) on springs `k` every `a` metres
/// under a point load on a spring, written here from the beam's Fourier transform (not the
/// finite elements of the library). With w_n the deflections at the springs and their
/// discrete transform Ŵ(θ) = Σ w_n e^{−inθ}, the beam's equation EI w'''' = Pδ(x) −
/// k Σ w_n δ(x − na), transformed and folded onto one period of θ = ξa, gives
/// Ŵ = (P − kŴ) F(θ) with F(θ) = (a³/EI) Σ_j (θ + 2πj)⁻⁴ = (a³/EI) csc²(θ/2)(3 csc²(θ/2) − 2)/48
/// (twice the derivative of Σ_j (θ + 2πj)⁻² = csc²(θ/2)/4, divided by 6). So
/// w_0/P = (1/π) ∫_0^π F/(1 + kF) dθ, integrated here by composite Simpson (the integrand
/// tends to 1/k at θ = 0).
fn periodic_support_compliance(ei: f64, k: f64, a: f64) -> f64 {
    let f = |theta: f64| {
        if theta == 0.0 {
            return 1.0 / k;
        }
        let csc2 = 1.0 / (0.5 * theta).sin().powi(2);
        let big_f = a * a * a / ei * csc2 * (3.0 * csc2 - 2.0) / 48.0;
        big_f / (1.0 + k * big_f)
    };
    let n = 20_000;
    let h = PI / n as f64;
    let mut sum = f(0.0) + f(PI);
    for i in 1..n {
        sum += f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    sum * h / 3.0 / PI
}

/// Over a fastening, the library's finite elements (a finite rail, free ends) against the
/// exact periodic solution, at the default track's spacing and at a tenth and ten times its
/// pad stiffness.
#[test]
fn the_rail_over_a_fastening_against_the_periodic_closed_form() {
    let t = SlabTrack::crts2();
    for scale in [0.1, 1.0, 10.0] {
        let k = t.pad_stiffness * scale;
        let fe = discrete_beam_compliance(t.rail_ei, k, t.pad_spacing, 0.0).unwrap();
        let exact = periodic_support_compliance(t.rail_ei, k, t.pad_spacing);
        let rel = (fe - exact).abs() / exact;
        println!("k = {k:.3e} N/m: FE {fe:.6e}, exact {exact:.6e} m/N, rel {rel:.2e}");
        assert!(rel < 1e-9, "{rel}");
    }
}

/// As the fastenings get denser at a fixed foundation modulus k_p/a, the discrete rail tends
/// to Hetényi's beam on a Winkler foundation, over a fastening and between two; at the real
/// spacing the discreteness is a few per cent.
#[test]
fn dense_fastenings_tend_to_the_winkler_beam() {
    let t = SlabTrack::crts2();
    let modulus = t.pad_stiffness / t.pad_spacing;
    let winkler = winkler_compliance(t.rail_ei, modulus);
    let mut last = f64::INFINITY;
    for n in [1usize, 2, 4, 8, 16] {
        let a = t.pad_spacing / n as f64;
        let k = modulus * a;
        let over = discrete_beam_compliance(t.rail_ei, k, a, 0.0).unwrap();
        let between = discrete_beam_compliance(t.rail_ei, k, a, 0.5 * a).unwrap();
        let err = ((over - winkler).abs()).max((between - winkler).abs()) / winkler;
        println!(
            "a = {a:.4} m: over {:+.4} %, between {:+.4} % of Winkler",
            100.0 * (over / winkler - 1.0),
            100.0 * (between / winkler - 1.0)
        );
        assert!(between > over, "the rail is softer between two fastenings");
        assert!(err < last, "{err} after {last}");
        last = err;
    }
    assert!(last < 1e-4, "{last}");
}

/// The compliance along the track is periodic in the fastening spacing, softest midway, and
/// its mean lies between its extremes.
#[test]
fn the_support_along_the_track() {
    let t = SlabTrack::crts2();
    let s = TrackSupport::new(&t).unwrap();
    let a = t.pad_spacing;
    let (over, mid) = (s.compliance_at(0.0), s.compliance_at(0.5 * a));
    assert!(mid > over);
    assert!((s.compliance_at(7.0 * a + 0.1) - s.compliance_at(0.1)).abs() < 1e-12 * over);
    assert!(s.mean() > over && s.mean() < mid);
    // The slab on its mortar is in series.
    let rail = t.rail_compliance(0.0).unwrap();
    assert!((over - rail - t.slab_compliance()).abs() < 1e-12 * over);
    println!(
        "track: {over:.4e} m/N over a fastening ({:.1} MN/m), {mid:.4e} midway; slab {:.2e} m/N; {:.0} kg/m",
        1e-6 / over,
        t.slab_compliance(),
        t.mass_per_m()
    );
}

/// Hertz in series with the track: the force it returns for an approach gives that approach
/// back through the forward relation d = G N^{2/3} + c N, and c = 0 is Hertz alone.
#[test]
fn hertz_in_series_inverts_the_forward_relation() {
    let g = 5.1e-8;
    for c in [0.0, 1e-10, 7e-9, 1e-6] {
        for n in [1.0, 1e3, 5.6e4, 3e5] {
            let d = g * f64::powf(n, 2.0 / 3.0) + c * n;
            let got = hertz_in_series(d, g, c);
            assert!((got - n).abs() <= 1e-12 * n, "c {c}, N {n}: {got}");
        }
    }
    assert_eq!(hertz_in_series(-1e-6, g, 7e-9), 0.0);
    assert_eq!(hertz_in_series(1e-4, g, 0.0), (1e-4 / g).powf(1.5));
}
