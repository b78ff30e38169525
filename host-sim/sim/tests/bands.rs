//! `maglev_sim::bands` against analytic truth (docs/bands.md §Tests): sines at band
//! centres and on an edge, two sines with a DC offset, the quantity conversions, seeded white
//! noise against the 2BT chi-square bound, a tone burst's maximum running rms against the
//! directly summed signal and its closed form, the band table and the input errors.

use std::f64::consts::{PI, SQRT_2, TAU};

mod bands_reference;

use maglev_sim::bands::{
    analyse, band_range, read_history, Averaging, Band, BandLevel, BandsError, Level, Motion,
    Settings, REF_ACCELERATION, REF_VELOCITY,
};

const WHOLE: Averaging = Averaging::WholeRecord;

fn settings(input: Motion, level: Level, averaging: Averaging) -> Settings {
    Settings {
        input,
        level,
        averaging,
    }
}

fn accel(averaging: Averaging) -> Settings {
    settings(Motion::Acceleration, Level::Acceleration, averaging)
}

/// `a·sin(2π·k·j/N + φ)`: `k` whole periods over `n` samples, the phase formed exactly.
fn periodic_sine(n: usize, k: usize, a: f64, phase: f64) -> Vec<f64> {
    (0..n)
        .map(|j| a * (TAU * ((j * k) % n) as f64 / n as f64 + phase).sin())
        .collect()
}

/// The spacing that puts bin `k` of an `n`-sample record exactly on `f` Hz.
fn dt_for(f: f64, n: usize, k: usize) -> f64 {
    k as f64 / (f * n as f64)
}

fn level_at(levels: &[BandLevel], index: i32) -> f64 {
    levels
        .iter()
        .find(|l| l.band.index == index)
        .unwrap_or_else(|| panic!("band {index} not reported"))
        .level_db
        .expect("a level")
}

fn db(rms: f64, reference: f64) -> f64 {
    20.0 * (rms / reference).log10()
}

/// IEC 61260-1 Annex E nominal mid-band frequencies, 1 Hz to 20 kHz, typed from the standard.
const NOMINAL: [f64; 44] = [
    1.0, 1.25, 1.6, 2.0, 2.5, 3.15, 4.0, 5.0, 6.3, 8.0, 10.0, 12.5, 16.0, 20.0, 25.0, 31.5, 40.0,
    50.0, 63.0, 80.0, 100.0, 125.0, 160.0, 200.0, 250.0, 315.0, 400.0, 500.0, 630.0, 800.0, 1000.0,
    1250.0, 1600.0, 2000.0, 2500.0, 3150.0, 4000.0, 5000.0, 6300.0, 8000.0, 10000.0, 12500.0,
    16000.0, 20000.0,
];

#[test]
fn band_table_follows_iec_61260_1() {
    for (i, &nominal) in NOMINAL.iter().enumerate() {
        let band = Band {
            index: i as i32 - 30,
        };
        assert_eq!(band.nominal_hz(), nominal, "band {}", band.index);
        let fm = band.exact_hz();
        // Nominal values are the exact ones rounded to the R10 series: within 1.3 % here.
        assert!((nominal / fm - 1.0).abs() < 0.013, "{nominal} vs {fm}");
        assert!((band.lower_hz() / fm - 10f64.powf(-0.05)).abs() < 1e-14);
        assert!((band.upper_hz() / fm - 10f64.powf(0.05)).abs() < 1e-14);
        // Contiguous: this band's upper edge is the next band's lower edge, bit for bit.
        let next = Band {
            index: band.index + 1,
        };
        assert_eq!(band.upper_hz(), next.lower_hz());
    }
    assert_eq!(Band { index: 0 }.exact_hz(), 1000.0);
    assert_eq!(Band { index: -40 }.nominal_hz(), 0.1);
    assert_eq!(Band { index: -32 }.nominal_hz(), 0.63);
    // Ten bands per decade: f_m(x + 10) = 10·f_m(x).
    let b = Band { index: -17 };
    assert!((Band { index: -7 }.exact_hz() / b.exact_hz() - 10.0).abs() < 1e-13);
}

/// The paper's record (5000 samples at 2 ms, T = 10 s, Δf = 0.1 Hz, Nyquist 250 Hz): the
/// 0.4 Hz band is 0.092 Hz wide (< Δf), the 0.5 Hz band 0.116 Hz (≥ Δf); the 200 Hz band ends
/// at 223.9 Hz, the 250 Hz band at 281.8 Hz, above the last interior bin's top 249.95 Hz.
#[test]
fn band_range_rule() {
    let r = band_range(5000, 0.002).unwrap();
    assert_eq!(
        (
            Band { index: *r.start() }.nominal_hz(),
            Band { index: *r.end() }.nominal_hz()
        ),
        (0.5, 200.0)
    );
    // 1 s at 1 kHz: Δf = 1 Hz, the 5 Hz band (1.16 Hz wide) is the first at least 1 Hz wide;
    // the 400 Hz band ends at 447 Hz ≤ 499.5 Hz, the 500 Hz band at 562 Hz.
    let r = band_range(1000, 0.001).unwrap();
    assert_eq!(
        (
            Band { index: *r.start() }.nominal_hz(),
            Band { index: *r.end() }.nominal_hz()
        ),
        (5.0, 400.0)
    );
    assert!(band_range(3, 0.001).is_none());
    assert!(band_range(1, 0.001).is_none());
}

/// Every band `analyse` reports against the independent analyser (tests/bands_reference):
/// within `tol_db`. Returns the worst difference.
fn check_against_reference(x: &[f64], dt: f64, s: &Settings, tol_db: f64) -> f64 {
    let levels = analyse(x, dt, s).unwrap();
    let p = s.level.quantity().order() - s.input.order();
    let bands: Vec<i32> = levels.iter().map(|l| l.band.index).collect();
    let reference = bands_reference::band_mean_squares(x, dt, p, &bands);
    let r2 = s.level.reference().powi(2);
    let mut worst = 0.0f64;
    for (l, ms) in levels.iter().zip(reference) {
        let want = 10.0 * (ms / r2).log10();
        let got = l.level_db.unwrap();
        assert!(
            (got - want).abs() <= tol_db,
            "band {} Hz: {got} dB vs the reference's {want} dB",
            l.band.nominal_hz()
        );
        worst = worst.max((got - want).abs());
    }
    worst
}

/// Closed-form leakage bounds of a sine `A·sin(2πf₀·jΔt + φ)` of whole periods over the
/// record (`N` samples, `T = NΔt`, `f_s = 1/Δt`), mean zero, mean square `A²/2` exactly.
/// Its spectrum is `(A/2i)·(e^{iφ}D(f − f₀) − e^{−iφ}D(f + f₀))` with the Dirichlet kernel
/// `|D(ν)| = |sin(πνT)/sin(πνΔt)| ≤ 1/(2|ν|Δt)` for `|ν| ≤ f_s/2` (and `D` is
/// `f_s`-periodic), so `|V|² ≤ (A²/2)(|D(f − f₀)|² + |D(f + f₀)|²)` and, with
/// `ms = (2Δt/N)∫|V|²`:
/// * a band at distance `d` from `f₀` holds at most `(A²/2)·(1/(2dT) + 1/(2eT))`, `e` the
///   band's least distance from `−f₀` or `f_s − f₀` (the image);
/// * the band holding `f₀`, its edges at least `a` away, holds at least what the rest of
///   `(0, f_s/2)` cannot: `(A²/2)·(1 − 1/(aT) − (1/f₀ + 1/(f_s/2 − f₀))/(2T))`.
///
/// Returns `(lower bound of the own band's fraction, upper bound of band x's fraction)`.
struct SineBounds {
    f0: f64,
    t: f64,
    fs: f64,
}

impl SineBounds {
    fn own_band_at_least(&self, band: Band) -> f64 {
        let a = (self.f0 - band.lower_hz()).min(band.upper_hz() - self.f0);
        let image = (1.0 / self.f0 + 1.0 / (self.fs / 2.0 - self.f0)) / (2.0 * self.t);
        1.0 - 1.0 / (a * self.t) - image
    }

    fn other_band_at_most(&self, band: Band) -> f64 {
        let (lo, hi) = (band.lower_hz(), band.upper_hz());
        let d = (self.f0 - hi).max(lo - self.f0);
        let e = (lo + self.f0).min(self.fs - self.f0 - hi);
        1.0 / (2.0 * d * self.t) + 1.0 / (2.0 * e * self.t)
    }
}

/// A sine of amplitude A at a band's exact mid-band frequency, whole periods over about 10 s:
/// the band holds (A/√2)² but for the leakage bound of [`SineBounds`], every other band at
/// most its bound (30–60 dB down two bands away), and every band within 0.01 dB of the
/// independent analyser.
#[test]
fn sine_at_band_centre() {
    let n = 5000;
    for (index, k, a) in [(-20, 100usize, 0.7), (-13, 500, 2.0), (-7, 1800, 0.05)] {
        let band = Band { index };
        let fm = band.exact_hz();
        let dt = dt_for(fm, n, k);
        let x = periodic_sine(n, k, a, 0.3);
        let levels = analyse(&x, dt, &accel(WHOLE)).unwrap();
        let ms = a * a / 2.0;
        let bounds = SineBounds {
            f0: fm,
            t: n as f64 * dt,
            fs: 1.0 / dt,
        };
        let want = db(a / SQRT_2, REF_ACCELERATION);
        let got = level_at(&levels, index);
        let floor = want + 10.0 * bounds.own_band_at_least(band).log10();
        println!(
            "sine {fm:.4} Hz, A = {a}: level {got:.6} dB, rms {want:.6} dB, bound {floor:.6} dB"
        );
        assert!(
            got <= want + 1e-9 && got >= floor,
            "{got} vs [{floor}, {want}]"
        );
        for l in levels.iter().filter(|l| l.band.index != index) {
            let cap = 10.0 * (ms * bounds.other_band_at_most(l.band) / 1e-12).log10();
            let level = l.level_db.unwrap();
            assert!(level <= cap, "band {:?}: {level} above {cap}", l.band);
            if (l.band.index - index).abs() >= 2 {
                assert!(level < want - 30.0, "band {:?}: {level}", l.band);
            }
        }
        let worst = check_against_reference(&x, dt, &accel(WHOLE), 0.01);
        println!("  against the independent analyser: worst {worst:.2e} dB");
    }
}

/// A tone exactly on the edge between two bands: the two bands share it, each within 0.1 dB
/// of half (−3.0103 dB) and together within the leakage bound of the whole; the levels are
/// the independent analyser's within 0.01 dB.
#[test]
fn sine_on_band_edge_splits_half_and_half() {
    let n = 4000;
    let lower = Band { index: -16 }; // 25 Hz; its upper edge is the 31.5 Hz band's lower edge
    let fe = lower.upper_hz();
    let k = 300;
    let dt = dt_for(fe, n, k);
    let a = 1.5;
    let x = periodic_sine(n, k, a, 1.0);
    let levels = analyse(&x, dt, &accel(WHOLE)).unwrap();
    let tone = db(a / SQRT_2, REF_ACCELERATION);
    let mut sum = 0.0;
    for index in [-16, -15] {
        let got = level_at(&levels, index);
        println!("band {index}: {:.4} dB relative to the tone", got - tone);
        assert!(
            (got - tone + 3.0103).abs() < 0.1,
            "band {index}: {got} vs {tone}"
        );
        sum += 10f64.powf(got / 10.0);
    }
    let t = n as f64 * dt;
    // The pair's outer edges are ≥ 5.8 Hz from the tone; the image as in SineBounds.
    let a_out = (fe - lower.lower_hz()).min(Band { index: -15 }.upper_hz() - fe);
    let floor = 1.0 - 1.0 / (a_out * t) - (1.0 / fe + 1.0 / (0.5 / dt - fe)) / (2.0 * t);
    let both = 10.0 * sum.log10();
    assert!(
        both <= tone + 1e-9 && both >= tone + 10.0 * floor.log10(),
        "{both} vs {tone}"
    );
    check_against_reference(&x, dt, &accel(WHOLE), 0.01);
}

/// Two sines in different bands (whole periods at the bins nearest the 8 Hz and 63 Hz
/// centres) over a DC offset of 100: the mean is removed, so each band holds its sine within
/// the leakage bound (the offset's 80 dB more would swamp every band if it leaked), and all
/// bands are the independent analyser's within 0.01 dB.
#[test]
fn two_sines_in_different_bands_with_offset() {
    let (n, dt) = (5000, 0.002);
    let df = 1.0 / (n as f64 * dt);
    let (i1, i2) = (-21, -12);
    let k1 = (Band { index: i1 }.exact_hz() / df).round() as usize;
    let k2 = (Band { index: i2 }.exact_hz() / df).round() as usize;
    let (a1, a2) = (0.2, 3.0);
    let s1 = periodic_sine(n, k1, a1, 0.0);
    let s2 = periodic_sine(n, k2, a2, 2.0);
    let x: Vec<f64> = s1.iter().zip(&s2).map(|(p, q)| 100.0 + p + q).collect();
    let levels = analyse(&x, dt, &accel(WHOLE)).unwrap();
    for (index, k, a, other_a) in [(i1, k1, a1, a2), (i2, k2, a2, a1)] {
        let band = Band { index };
        let bounds = SineBounds {
            f0: k as f64 * df,
            t: n as f64 * dt,
            fs: 1.0 / dt,
        };
        // The other sine adds at most its own leakage bound here: √ms between
        // √(own) − √(other) and √(own) + √(other) (triangle inequality over the band).
        let other = SineBounds {
            f0: if index == i1 { k2 } else { k1 } as f64 * df,
            ..bounds
        };
        let leak = (other_a * other_a / 2.0 * other.other_band_at_most(band)).sqrt();
        let own = a / SQRT_2;
        let lo = own * bounds.own_band_at_least(band).sqrt() - leak;
        let hi = own + leak;
        let got = level_at(&levels, index);
        println!(
            "band {index}: {got:.4} dB in [{:.4}, {:.4}]",
            db(lo, 1e-6),
            db(hi, 1e-6)
        );
        assert!(got >= db(lo, 1e-6) && got <= db(hi, 1e-6));
    }
    check_against_reference(&x, dt, &accel(WHOLE), 0.01);
}

/// The quantity conversions weight the spectrum by (2πf)^(2p) inside the band: displacement
/// → acceleration and velocity, acceleration → velocity, velocity → acceleration and
/// velocity, of a 5 Hz sine (40 periods) and of a seeded noise record, against the
/// independent analyser within 0.01 dB; and, for the sine, the level of a conversion differs
/// from the unconverted level by 20·p·log10(2πf₀) within 0.1 dB (the band's weight varies by
/// ±0.1·p decade over it, but a 40-period sine's spectrum sits within ±0.1 Hz of f₀).
#[test]
fn quantity_conversions() {
    let n = 6000;
    let index = -23; // 5 Hz band
    let k = 40;
    let dt = dt_for(Band { index }.exact_hz(), n, k);
    let f = k as f64 / (n as f64 * dt);
    let w = TAU * f;
    let sine = periodic_sine(n, k, 1e-4, 0.7);
    let mut rng = Normal(0x5EED_00C0);
    let noise: Vec<f64> = (0..n).map(|_| rng.pair().0).collect();
    let cases = [
        (Motion::Displacement, Level::Acceleration, 2),
        (Motion::Displacement, Level::Velocity, 1),
        (Motion::Acceleration, Level::Velocity, -1),
        (Motion::Velocity, Level::Acceleration, 1),
        (Motion::Velocity, Level::Velocity, 0),
    ];
    for (input, level, p) in cases {
        let s = settings(input, level, WHOLE);
        let worst = check_against_reference(&sine, dt, &s, 0.01)
            .max(check_against_reference(&noise, dt, &s, 0.01));
        let plain = settings(Motion::Velocity, Level::Velocity, WHOLE);
        let base = level_at(&analyse(&sine, dt, &plain).unwrap(), index);
        let got = level_at(&analyse(&sine, dt, &s).unwrap(), index)
            + 20.0 * (s.level.reference() / REF_VELOCITY).log10();
        let want = base + 20.0 * f64::from(p) * w.log10();
        println!("{input:?} -> {level:?}: worst {worst:.1e} dB; sine {got:.4} vs {want:.4}");
        assert!(
            (got - want).abs() < 0.1,
            "{input:?}->{level:?}: {got} vs {want}"
        );
    }
}

/// SplitMix64 → uniform (0, 1) → Box–Muller: a seeded standard normal stream.
struct Normal(u64);

impl Normal {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        ((z >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    fn pair(&mut self) -> (f64, f64) {
        let (u, v) = (self.uniform(), self.uniform());
        let r = (-2.0 * u.ln()).sqrt();
        (r * (TAU * v).cos(), r * (TAU * v).sin())
    }
}

/// Wilson–Hilferty approximation of the chi-square quantile ratio χ²_ν(z)/ν.
fn chi2_ratio(nu: f64, z: f64) -> f64 {
    let c = 2.0 / (9.0 * nu);
    (1.0 - c + z * c.sqrt()).max(0.0).powi(3)
}

/// Gaussian white noise of variance σ² (seeded): the band mean square's expectation is
/// σ²·B/(f_s/2), and it is (1/N)·vᵀPv with P the band-limiting projector restricted to the
/// record (eigenvalues λ in [0, 1], trace 2BT): σ²/N·Σλ·χ²₁, with Satterthwaite's
/// ν = (Σλ)²/Σλ² ≥ Σλ = 2BT degrees of freedom (as λ ≤ 1). Every band must
/// lie within the z = ±4 Wilson–Hilferty quantiles for ν = 2BT (a per-band false alarm of
/// 6e-5; over ~40 bands 0.3 %), and the sum over the bands within the same bound for the
/// summed bandwidth.
#[test]
fn white_noise_level_is_proportional_to_bandwidth() {
    let (n, dt, sigma) = (20_000, 0.002, 0.3);
    let mut rng = Normal(0x5EED_0010);
    let mut x = Vec::with_capacity(n);
    while x.len() < n {
        let (a, b) = rng.pair();
        x.push(sigma * a);
        x.push(sigma * b);
    }
    let (fs, t) = (1.0 / dt, n as f64 * dt);
    let levels = analyse(&x, dt, &accel(WHOLE)).unwrap();
    let (mut sum_ms, mut sum_b, mut worst_z) = (0.0, 0.0, 0.0f64);
    for l in &levels {
        let b = l.band.width_hz();
        let expected = sigma * sigma * b / (fs / 2.0);
        let ms = l.rms * l.rms;
        let nu = 2.0 * b * t;
        let ratio = ms / expected;
        let (lo, hi) = (chi2_ratio(nu, -4.0), chi2_ratio(nu, 4.0));
        let want_db = 10.0 * (expected / (REF_ACCELERATION * REF_ACCELERATION)).log10();
        // The equivalent standard-normal deviate (Wilson–Hilferty), for the report.
        let c = 2.0 / (9.0 * nu);
        let zeq = (ratio.cbrt() - 1.0 + c) / c.sqrt();
        worst_z = worst_z.max(zeq.abs());
        println!(
            "band {:>6} Hz: {:8.3} dB, expected {:8.3} dB ({:+.3} dB, nu = {:7.1}, z = {:+.2})",
            l.band.nominal_hz(),
            l.level_db.unwrap(),
            want_db,
            l.level_db.unwrap() - want_db,
            nu,
            zeq
        );
        assert!(
            ratio >= lo && ratio <= hi,
            "band {}: ratio {ratio} outside [{lo}, {hi}]",
            l.band.nominal_hz()
        );
        sum_ms += ms;
        sum_b += b;
    }
    let expected = sigma * sigma * sum_b / (fs / 2.0);
    let nu = 2.0 * sum_b * t;
    let ratio = sum_ms / expected;
    println!(
        "all bands: ratio {ratio:.5} (bound [{:.5}, {:.5}]), worst |z| {worst_z:.2}",
        chi2_ratio(nu, -4.0),
        chi2_ratio(nu, 4.0)
    );
    assert!(ratio >= chi2_ratio(nu, -4.0) && ratio <= chi2_ratio(nu, 4.0));
}

/// A Hann-enveloped tone burst: A·sin(2πf₀t)·½(1 − cos(2π(t − t₁)/D)) for t₁ ≤ t ≤ t₁ + D,
/// zero elsewhere, f₀ on the bin nearest the 100 Hz centre. Its spectrum is within ±1 Hz of
/// f₀ but for sidelobes falling as f⁻³: outside the band (±11 Hz) lies a fraction
/// ≈ 16/(60π²(11·D)⁵) ≈ 5e-9 of its energy, so the band signal is the burst itself to
/// ~1e-4 in amplitude, i.e. 0.001 dB. Truths:
/// 1. the maximum running mean square of the burst summed directly in the time domain
///    (tolerance 0.01 dB);
/// 2. the closed form for the window τ centred on the burst,
///    (A²/2)·¼[3/2 + (2D/πτ)·sin(πτ/D) + (D/4πτ)·sin(2πτ/D)], whose neglected carrier term
///    (A²/2)(1/τ)∫g²cos(4πf₀t)dt is at most (A²/2)/(π f₀ τ) by parts: relative ≤ 0.0065 for
///    τ ≥ 0.5 s (where the mean of g² ≥ 0.99), so
///    0.03 dB;
/// 3. the whole-record mean square (A²/2)·(3/8)·D/T (the same bound over T, relative to
///    (3/8)·D/T: ≤ 0.0022, so 0.01 dB).
#[test]
fn running_rms_of_a_tone_burst() {
    let (n, dt) = (10_000, 0.001);
    let t_rec = n as f64 * dt;
    let df = 1.0 / t_rec;
    let index = -10;
    let f0 = (Band { index }.exact_hz() / df).round() * df;
    let (a, t1, d) = (0.8, 3.0, 4.0);
    let x: Vec<f64> = (0..n)
        .map(|j| {
            let t = j as f64 * dt;
            if (t1..=t1 + d).contains(&t) {
                a * (TAU * f0 * t).sin() * 0.5 * (1.0 - (TAU * (t - t1) / d).cos())
            } else {
                0.0
            }
        })
        .collect();
    for tau in [0.5, 1.0, 2.0] {
        let m = (tau / dt).round() as usize;
        let direct = (0..=n - m)
            .map(|j| x[j..j + m].iter().map(|v| v * v).sum::<f64>() / m as f64)
            .fold(0.0, f64::max);
        let q = PI * tau / d;
        let closed =
            a * a / 2.0 * 0.25 * (1.5 + 2.0 / q * q.sin() + 1.0 / (4.0 * q) * (2.0 * q).sin());
        let levels = analyse(&x, dt, &accel(Averaging::MaxRunning { window_s: tau })).unwrap();
        let got = level_at(&levels, index);
        let (want_direct, want_closed) = (
            10.0 * (direct / 1e-12).log10(),
            10.0 * (closed / 1e-12).log10(),
        );
        println!(
            "burst, tau = {tau} s: {got:.5} dB, direct {want_direct:.5} dB, closed form {want_closed:.5} dB"
        );
        assert!((got - want_direct).abs() < 0.01, "{got} vs {want_direct}");
        assert!((got - want_closed).abs() < 0.03, "{got} vs {want_closed}");
    }
    let whole = analyse(&x, dt, &accel(WHOLE)).unwrap();
    let want = 10.0 * ((a * a / 2.0) * (3.0 / 8.0) * d / t_rec / 1e-12).log10();
    let got = level_at(&whole, index);
    println!("burst, whole record: {got:.5} dB, closed form {want:.5} dB");
    assert!((got - want).abs() < 0.01, "{got} vs {want}");
}

/// The maximum running rms against the independent analyser's band signal (its quadrature
/// of the band's spectrum at every sample, the running mean square summed directly), within
/// 0.01 dB: a stationary sine of 250 periods in its band and in the bands next to it (where
/// only its leakage is), and noise, windows of 0.2 and 2 s. A stationary sine's band signal
/// is the sine but near the record's ends, where the ideal band edges ring (Gibbs): its
/// maximum running rms over 50 periods is A/√2 within 0.1 dB.
#[test]
fn running_rms_against_the_reference_band_signal() {
    let (n, k) = (5000, 250);
    let index = -13;
    let dt = dt_for(Band { index }.exact_hz(), n, k);
    let sine = periodic_sine(n, k, 1.0, 0.0);
    let mut rng = Normal(0x5EED_00A1);
    let noise: Vec<f64> = (0..n).map(|_| rng.pair().0).collect();
    for (x, what) in [(&sine, "sine"), (&noise, "noise")] {
        for m in [100usize, 1000] {
            let s = accel(Averaging::MaxRunning {
                window_s: m as f64 * dt,
            });
            let levels = analyse(x, dt, &s).unwrap();
            for band in index - 1..=index + 1 {
                let y = bands_reference::band_signal(x, dt, 0, band);
                let ms = bands_reference::max_running_mean_square(&y, m);
                let want = 10.0 * (ms / 1e-12).log10();
                let got = level_at(&levels, band);
                println!("{what}, {m} samples, band {band}: {got:.5} dB vs {want:.5} dB");
                assert!((got - want).abs() < 0.01, "{got} vs {want}");
            }
            if std::ptr::eq(x, &sine) && m == 1000 {
                let want = db(1.0 / SQRT_2, REF_ACCELERATION);
                let got = level_at(&levels, index);
                assert!((got - want).abs() < 0.1, "{got} vs {want}");
            }
        }
    }
}

fn csv_rows(rows: &[(f64, &str)]) -> String {
    let mut s = String::from("t,a\n");
    for (t, v) in rows {
        s += &format!("{t},{v}\n");
    }
    s
}

#[test]
fn reads_a_uniform_history_and_rejects_bad_input() {
    let good = "# a comment\nt, a ,b\n0,1,9\n0.5,2,9\n1.0,3,9\n";
    let h = read_history(good.as_bytes(), "a").unwrap();
    assert_eq!(
        (h.t0, h.dt, h.values.clone()),
        (0.0, 0.5, vec![1.0, 2.0, 3.0])
    );

    let missing = read_history(good.as_bytes(), "z").unwrap_err();
    assert!(matches!(missing, BandsError::MissingColumn { .. }));
    assert!(missing.to_string().contains("\"z\""), "{missing}");

    for bad in ["NaN", "", "inf", "x"] {
        let text = csv_rows(&[(0.0, "1"), (0.1, bad), (0.2, "1")]);
        let e = read_history(text.as_bytes(), "a").unwrap_err();
        assert!(
            matches!(e, BandsError::BadCell { line: 3, .. }),
            "{bad:?}: {e}"
        );
        assert!(e.to_string().contains("\"a\""), "{e}");
    }

    // 0.1 % of dt off the grid is the limit; 0.2 % is refused, naming the tolerance.
    let ok = csv_rows(&[(0.0, "1"), (0.1 + 0.9e-4, "1"), (0.2, "1")]);
    assert!(read_history(ok.as_bytes(), "a").is_ok());
    let jitter = csv_rows(&[(0.0, "1"), (0.1002, "1"), (0.2, "1")]);
    let e = read_history(jitter.as_bytes(), "a").unwrap_err();
    assert!(matches!(e, BandsError::NonUniform { line: 3, .. }), "{e}");
    assert!(
        e.to_string().contains("0.001*dt") && e.to_string().contains("\"t\""),
        "{e}"
    );

    let backwards = csv_rows(&[(1.0, "1"), (0.5, "1"), (0.0, "1")]);
    assert!(matches!(
        read_history(backwards.as_bytes(), "a").unwrap_err(),
        BandsError::NotIncreasing { .. }
    ));
    let one = csv_rows(&[(0.0, "1")]);
    assert!(matches!(
        read_history(one.as_bytes(), "a").unwrap_err(),
        BandsError::TooFewRows { rows: 1 }
    ));

    let short = analyse(&[1.0, 2.0, 3.0], 0.001, &accel(WHOLE)).unwrap_err();
    assert!(
        matches!(short, BandsError::TooShort { n: 3, .. }),
        "{short}"
    );
    for window_s in [20.0, 1e-5, f64::NAN] {
        let e = analyse(
            &vec![0.0; 5000],
            0.002,
            &accel(Averaging::MaxRunning { window_s }),
        )
        .unwrap_err();
        assert!(matches!(e, BandsError::BadWindow { .. }), "{e}");
    }
    let nan = analyse(&[0.0, f64::NAN, 0.0], 0.001, &accel(WHOLE)).unwrap_err();
    assert!(
        matches!(nan, BandsError::BadSample { index: 1, .. }),
        "{nan}"
    );
    for dt in [0.0, -1.0, f64::INFINITY] {
        let e = analyse(&vec![0.0; 5000], dt, &accel(WHOLE)).unwrap_err();
        assert!(matches!(e, BandsError::BadStep { .. }), "{e}");
    }
    for e in [missing, short, nan] {
        assert!(!e.to_string().contains('\n'));
    }
}
