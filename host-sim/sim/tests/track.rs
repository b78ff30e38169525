//! The track on the girder (`physics::rail::track`): the rail on discrete fastenings against
//! two independent solutions, and the support it gives a wheel.

use maglev_sim::physics::rail::track::{
    discrete_beam_compliance, winkler_compliance, SlabTrack, TrackSupport,
};
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

/// The P2 resonance of a wheel on the track (Jenkins et al. 1974; Zhai): the wheel's mass M on
/// its Hertz spring k_H on the rail, where M ω² (1/k_H + α(ω)) = 1 with α the receptance
/// under the wheel. The exact α of Hetényi's beam on a damped Winkler foundation (mass m per
/// metre, k + iωc per metre), written here from the beam's Fourier transform, is
/// α = 1/(2√2·EI·s³) with s = ((k + iωc − mω²)/EI)^{1/4} (the principal root: the integral
/// (1/2π)∫dξ/(EIξ⁴ + K) = 1/(2√2 EI (K/EI)^{3/4}) continued to complex K), plus the slab's
/// static compliance in series (Hetényi's β_s/(2k_m), written here again). The library's one
/// rail mass (m_e, c_e on 1/c̄) gives α_L = 1/(1/c̄ + iωc_e − m_eω²). With dense fastenings
/// (a/16 at the same k and c per metre, so the discrete rail is the Winkler beam to 1e−4),
/// the two roots agree in frequency within 1 % and in damping ratio within 3 %: the terms
/// left out of the expansion behind m_e and c_e are (3/32)(ωc/k)² ≈ 1 % of the stiffness
/// and (3/16)(ωc/k)(mω²/k) ≈ 0.7 % of it, 2.6 % of the damping term, at 65 Hz. A massless
/// support (m_e = 0) misses the frequency by 3 %.
#[test]
fn the_rail_mass_gives_the_winkler_beams_p2_resonance() {
    use maglev_sim::physics::cars::wheel_rail::zhai_g;
    use maglev_sim::physics::rail::rail_mass::RailMass;
    use nalgebra::Complex;
    type C = Complex<f64>;
    let base = SlabTrack::crts2();
    let dense = SlabTrack {
        pad_stiffness: base.pad_stiffness / 16.0,
        pad_damping: base.pad_damping / 16.0,
        pad_spacing: base.pad_spacing / 16.0,
        ..base
    };
    let support = TrackSupport::new(&dense).unwrap();
    let lumped = RailMass::new(&support, 55.9e3);
    let (ei, m) = (dense.rail_ei, dense.rail_mass);
    let (k, c) = (
        base.pad_stiffness / base.pad_spacing,
        base.pad_damping / base.pad_spacing,
    );
    let beta_s = (dense.mortar_modulus / (4.0 * dense.slab_ei)).powf(0.25);
    let slab = beta_s / (2.0 * dense.mortar_modulus);
    let exact = |w: C| -> C {
        let s = ((C::new(k, 0.0) + C::new(0.0, c) * w - m * w * w) / ei).powf(0.25);
        C::new(1.0, 0.0) / (2.0 * 2f64.sqrt() * ei * s * s * s) + slab
    };
    let lumped_alpha = |mass: f64| {
        let (kl, cl) = (1.0 / support.mean(), lumped.damping);
        move |w: C| C::new(1.0, 0.0) / (C::new(kl, 0.0) + C::new(0.0, cl) * w - mass * w * w)
    };
    // The wheel: half the wheelset of the high-speed car on Zhai's Hertz spring at 55.9 kN.
    let (wheel, p0) = (700.0, 55.9e3);
    let k_h = 1.5 * f64::cbrt(p0) / zhai_g(0.4575);
    let root = |alpha: &dyn Fn(C) -> C| -> C {
        let f = |w: C| wheel * w * w * (1.0 / k_h + alpha(w)) - 1.0;
        let mut w = C::new(2.0 * PI * 69.0, 50.0);
        for _ in 0..100 {
            let h = 1e-4 * w.norm();
            let d = (f(w + h) - f(w - h)) / (2.0 * h);
            let step = f(w) / d;
            w -= step;
            if step.norm() < 1e-12 * w.norm() {
                break;
            }
        }
        w
    };
    let (we, wl, w0) = (
        root(&exact),
        root(&lumped_alpha(lumped.mass)),
        root(&lumped_alpha(0.0)),
    );
    let f = |w: C| w.re / (2.0 * PI);
    let zeta = |w: C| w.im / w.norm();
    println!(
        "P2: Winkler beam {:.3} Hz, ζ {:.4}; one rail mass ({:.1} kg, {:.3e} N·s/m) {:.3} Hz, ζ {:.4}; massless {:.3} Hz, ζ {:.4}",
        f(we),
        zeta(we),
        lumped.mass,
        lumped.damping,
        f(wl),
        zeta(wl),
        f(w0),
        zeta(w0)
    );
    assert!(
        (f(wl) / f(we) - 1.0).abs() < 0.01,
        "{} against {}",
        f(wl),
        f(we)
    );
    assert!(
        (zeta(wl) / zeta(we) - 1.0).abs() < 0.03,
        "{} against {}",
        zeta(wl),
        zeta(we)
    );
    assert!(
        (f(w0) / f(we) - 1.0).abs() > 0.02,
        "the massless support: {}",
        f(w0)
    );
}
