//! The high-speed track's rail irregularity (`physics::rail::spectrum`, `irregularity`):
//! the spectra's transcription and hand values, the rails' synthesis against the direct sum,
//! and the refusal of a bad band. The PSD statistics test is in
//! tests/tests/irregularity_psd.rs.

use maglev_sim::physics::rail::irregularity::{terms, Band, RailIrregularity};
use maglev_sim::physics::rail::spectrum::{
    Component, TrackSpectrum, CHINESE, GERMAN_LOW, OMEGA_C, OMEGA_R,
};
use std::f64::consts::TAU;

/// TB/T 3352's pieces join: each power law meets the next at its break within 1 % (the
/// published coefficients are rounded to 5 digits), a check on the transcription.
#[test]
fn chinese_pieces_are_continuous_at_their_breaks() {
    for laws in CHINESE {
        for (i, &b) in laws.breaks.iter().enumerate() {
            let below = laws.a[i] / b.powf(laws.n[i]);
            let above = laws.a[i + 1] / b.powf(laws.n[i + 1]);
            assert!((below / above - 1.0).abs() < 0.01, "{b}: {below} {above}");
        }
    }
}

/// Hand values: at Ω = Ω_c the low-disturbance vertical density is A_v/(2(Ω_c² + Ω_r²));
/// at f = 0.1 /m the Chinese vertical one is 1.9784e-2·0.1^−1.3643 mm²/(1/m) over 2π·10⁶.
#[test]
fn densities_at_hand_points() {
    let g = TrackSpectrum::German(GERMAN_LOW);
    let want = 4.032e-7 / (2.0 * (OMEGA_C * OMEGA_C + OMEGA_R * OMEGA_R));
    assert!((g.density(Component::Vertical, OMEGA_C) / want - 1.0).abs() < 1e-14);
    let c = TrackSpectrum::Chinese.density(Component::Vertical, TAU * 0.1);
    let want = 1.9784e-2 * 0.1f64.powf(-1.3643) / (TAU * 1e6);
    assert!((c / want - 1.0).abs() < 1e-14);
}

/// The tabulated rails against the plain direct sum of their own terms (origin 0), and the
/// rails' combination against the components.
#[test]
fn tabulated_rails_match_the_direct_sum() {
    let s = TrackSpectrum::German(GERMAN_LOW);
    let band = Band::default();
    let r = RailIrregularity::new(&s, &band, 11, -10.0, 200.0).unwrap();
    for c in Component::ALL {
        let t = terms(&s, c, &band, 11, 0.0).unwrap();
        let mut worst = 0.0f64;
        for k in 0..500 {
            let x = -9.0 + 0.4123 * k as f64;
            let want: f64 = t
                .iter()
                .map(|t| t.amp * (TAU * (t.freq * x + t.phase)).cos())
                .sum();
            worst = worst.max((r.component(c, x) - want).abs());
        }
        // Origin shift and interpolation: far below a micrometre against ~mm profiles.
        assert!(worst < 1e-9, "{c:?}: {worst:e}");
    }
    let x = 37.3;
    let [v, a, cl, g] = Component::ALL.map(|c| r.component(c, x));
    let ((yl, zl), (yr, zr)) = (r.left(x), r.right(x));
    assert!(((zl + zr) / 2.0 - v).abs() < 1e-18 && ((zl - zr) - cl).abs() < 1e-18);
    assert!(((yl + yr) / 2.0 - a).abs() < 1e-18 && ((yl - yr) - g).abs() < 1e-18);
}

#[test]
fn a_bad_band_is_refused_naming_the_key() {
    let s = TrackSpectrum::Chinese;
    let bad = Band {
        wavelength_max: 0.5,
        ..Band::default()
    };
    let e = RailIrregularity::new(&s, &bad, 1, 0.0, 10.0).unwrap_err();
    assert!(e.to_string().contains("wavelength_max_m"), "{e}");
    let bad = Band {
        terms: 0,
        ..Band::default()
    };
    let e = RailIrregularity::new(&s, &bad, 1, 0.0, 10.0).unwrap_err();
    assert!(e.to_string().contains("terms"), "{e}");
}
