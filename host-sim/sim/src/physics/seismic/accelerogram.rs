//! A synthetic ground-acceleration record: stationary Clough–Penzien noise, shaped in time
//! by an envelope, corrected to end at rest, scaled to a peak ground acceleration.
//!
//! Why this model: it is the standard seeded stand-in for a real record when a study needs
//! "a moderate earthquake on firm/medium/soft ground" and has no record. The Kanai–Tajimi
//! filter is the soil column as one damped oscillator (ω_g, ζ_g) on white-noise bedrock; the
//! Clough–Penzien second filter (ω_f, ζ_f) removes the very low frequencies that would make the
//! ground displacement drift. One-sided power spectral density of the acceleration (up to the
//! level S₀, which the PGA scaling replaces):
//!
//! ```text
//! G(ω) = S₀ · (ω_g⁴ + 4ζ_g²ω_g²ω²) / ((ω_g² − ω²)² + 4ζ_g²ω_g²ω²)
//!           · ω⁴ / ((ω_f² − ω²)² + 4ζ_f²ω_f²ω²)
//! ```
//!
//! Steps (docs/seismic.md has the parameters and the figures):
//! 1. **Stationary part** by the spectral representation (Shinozuka & Deodatis 1991):
//!    `a(t_j) = Σ_k √(2 G(ω_k) Δω) cos(ω_k t_j + φ_k)`, ω_k = k·Δω, Δω = 2π/(m·Δt), k = 1 …
//!    m/2 − 1, with m the record's length made even and φ_k uniform in [0, 2π) from SplitMix64
//!    (`maglev_core::irregularity`, one stream per component). The sum on the uniform grid is
//!    one inverse real FFT; the test holds it against the direct sum.
//! 2. **Envelope** (the Jennings, Housner & Tsai 1968 shape): (t/t₁)² while rising, 1 over the
//!    strong motion, e^{−c(t−t₂)} after t₂; tapered to zero over the record's last 5 % (at
//!    most 1 s) so that the record's last sample is zero ([`tapered_envelope`]).
//! 3. **Baseline**: a record used as support motion must end at rest, or the supports drift
//!    away. `a − e(t)(α + βt)` with α, β chosen so that velocity and displacement integrated by
//!    the trapezoid rule (which is what Newmark's average acceleration does to a prescribed
//!    acceleration) are zero at the end, exactly up to round-off; the correction vanishes where
//!    the envelope does.
//! 4. **Scale** each horizontal component to the PGA and the vertical one to
//!    `vertical_ratio`·PGA (peak of |a|).

use maglev_core::irregularity::SplitMix64;
use realfft::num_complex::Complex;
use realfft::RealFftPlanner;

use crate::{Error, Result};

/// Standard gravity, m/s² (the unit of `--pga-g`).
pub const G: f64 = 9.80665;

/// Fewest samples a record may have (fewer leave too few frequencies for a random signal).
pub const MIN_SAMPLES: usize = 64;

/// The stream constants, one per component (ASCII `"quake-X"`, `"quake-Y"`, `"quake-Z"`).
const STREAMS: [u64; 3] = [
    0x0071_7561_6B65_2D58,
    0x0071_7561_6B65_2D59,
    0x0071_7561_6B65_2D5A,
];

/// The generator of component `c` of `seed`: the seed is mixed before its stream constant is
/// XORed in and mixed again, so two (seed, component) pairs share a stream only if
/// `mix(s₁) ⊕ mix(s₂)` equals the XOR of two stream constants, a chance of 2⁻⁶⁴ per pair.
/// (XORing the constant into the raw seed, as before, made seed 1's x seed 2's y whenever the
/// constants differed in the seed's low bits.)
fn stream(seed: u64, c: usize) -> SplitMix64 {
    SplitMix64::new(SplitMix64::mix(SplitMix64::mix(seed) ^ STREAMS[c]))
}

/// The ground's filters: Kanai–Tajimi (ω_g, ζ_g) and the Clough–Penzien high-pass (ω_f, ζ_f).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GroundFilter {
    /// ω_g, rad/s.
    pub omega_g: f64,
    /// ζ_g.
    pub zeta_g: f64,
    /// ω_f, rad/s.
    pub omega_f: f64,
    /// ζ_f.
    pub zeta_f: f64,
}

impl GroundFilter {
    /// Firm ground (Der Kiureghian & Neuenhofer 1992).
    pub const FIRM: Self = Self::new(15.0, 0.6, 1.5, 0.6);
    /// Medium ground (same source).
    pub const MEDIUM: Self = Self::new(10.0, 0.4, 1.0, 0.6);
    /// Soft ground (same source).
    pub const SOFT: Self = Self::new(5.0, 0.2, 0.5, 0.6);

    /// The ground classes by name (`firm`, `medium`, `soft`; any case).
    pub fn class(name: &str) -> Option<Self> {
        match name.trim().to_ascii_lowercase().as_str() {
            "firm" => Some(Self::FIRM),
            "medium" => Some(Self::MEDIUM),
            "soft" => Some(Self::SOFT),
            _ => None,
        }
    }

    pub const fn new(omega_g: f64, zeta_g: f64, omega_f: f64, zeta_f: f64) -> Self {
        Self {
            omega_g,
            zeta_g,
            omega_f,
            zeta_f,
        }
    }

    /// `G(ω)/S₀` (module docs), dimensionless.
    pub fn shape(&self, omega: f64) -> f64 {
        let (wg2, w2) = (self.omega_g * self.omega_g, omega * omega);
        let kg = 4.0 * self.zeta_g * self.zeta_g * wg2 * w2;
        let kanai_tajimi = (wg2 * wg2 + kg) / ((wg2 - w2).powi(2) + kg);
        let wf2 = self.omega_f * self.omega_f;
        let kf = 4.0 * self.zeta_f * self.zeta_f * wf2 * w2;
        kanai_tajimi * w2 * w2 / ((wf2 - w2).powi(2) + kf)
    }
}

/// The envelope e(t) of step 2 (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Envelope {
    /// t₁: end of the rise, s.
    pub rise_s: f64,
    /// t₂: end of the strong motion, s (≥ t₁).
    pub strong_end_s: f64,
    /// c: decay rate after t₂, 1/s.
    pub decay_per_s: f64,
}

impl Envelope {
    /// e(t), between 0 and 1.
    pub fn at(&self, t: f64) -> f64 {
        if t < self.rise_s {
            (t / self.rise_s).powi(2)
        } else if t <= self.strong_end_s {
            1.0
        } else {
            (-self.decay_per_s * (t - self.strong_end_s)).exp()
        }
    }
}

/// What to synthesise (SI; the command line converts at its edge).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spec {
    pub filter: GroundFilter,
    pub envelope: Envelope,
    /// Record length, s.
    pub duration_s: f64,
    /// Sample step, s.
    pub dt_s: f64,
    /// Peak ground acceleration of each horizontal component, m/s².
    pub pga: f64,
    /// Vertical peak over horizontal peak.
    pub vertical_ratio: f64,
    pub seed: u64,
}

/// A three-component record on t = 0, Δt, …: accelerations in m/s².
#[derive(Clone, Debug, PartialEq)]
pub struct Accelerogram {
    pub dt_s: f64,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub z: Vec<f64>,
}

/// How the caller's edge spells a key: `pga_g` is `--pga-g` on the command line
/// ([`flag`]) and `support.synthetic.pga_g` in a scenario.
pub type KeyName<'a> = &'a dyn Fn(&str) -> String;

/// The command line's spelling of a key (`pga_g` → `--pga-g`).
pub fn flag(key: &str) -> String {
    format!("--{}", key.replace('_', "-"))
}

/// `Err` naming the caller's key when `v` is outside `[lo, hi]` (or not finite).
fn check(name: KeyName, key: &str, v: f64, lo: f64, hi: f64, why: &str) -> Result<()> {
    if v.is_finite() && (lo..=hi).contains(&v) {
        return Ok(());
    }
    Err(Error::invalid(
        name(key),
        format!("must be within [{lo}, {hi}] ({why}), got {v}"),
    ))
}

impl Spec {
    /// The number of samples, after checking every value against its limit (an error names
    /// the key as `name` spells it).
    pub fn samples(&self, name: KeyName) -> Result<usize> {
        let f = &self.filter;
        check(
            name,
            "pga_g",
            self.pga / G,
            1e-6,
            2.0,
            "in g; 2 g is above any recorded PGA",
        )?;
        check(
            name,
            "vertical_ratio",
            self.vertical_ratio,
            0.0,
            2.0,
            "vertical over horizontal peak",
        )?;
        check(
            name,
            "duration_s",
            self.duration_s,
            0.1,
            600.0,
            "strong motion lasts seconds to minutes",
        )?;
        check(
            name,
            "dt_s",
            self.dt_s,
            1e-4,
            0.1,
            "Nyquist above 5 Hz, at most 10 kHz",
        )?;
        check(
            name,
            "omega_g",
            f.omega_g,
            0.1,
            1000.0,
            "rad/s, the soil's predominant frequency",
        )?;
        check(
            name,
            "zeta_g",
            f.zeta_g,
            0.01,
            5.0,
            "the soil's damping ratio",
        )?;
        check(
            name,
            "omega_f",
            f.omega_f,
            0.01,
            1000.0,
            "rad/s, the high-pass corner",
        )?;
        check(
            name,
            "zeta_f",
            f.zeta_f,
            0.01,
            5.0,
            "the high-pass damping ratio",
        )?;
        let e = &self.envelope;
        check(
            name,
            "rise_s",
            e.rise_s,
            0.0,
            self.duration_s,
            "within the record",
        )?;
        check(
            name,
            "strong_end_s",
            e.strong_end_s,
            e.rise_s,
            self.duration_s,
            "between the rise and the record's end",
        )?;
        check(name, "decay_per_s", e.decay_per_s, 0.0, 100.0, "1/s")?;
        // At most 600 s / 0.1 ms + 1 = 6·10⁶ + 1 samples by the bounds above.
        let n = (self.duration_s / self.dt_s + 1e-9).floor() as usize + 1;
        if n < MIN_SAMPLES {
            return Err(Error::invalid(
                format!("{}/{}", name("duration_s"), name("dt_s")),
                format!("give {n} samples, fewer than {MIN_SAMPLES}"),
            ));
        }
        Ok(n)
    }
}

/// Synthesises the record of `spec` (module docs, steps 1–4); a value out of its limits is
/// refused naming its key as `name` spells it.
pub fn synthesize(spec: &Spec, name: KeyName) -> Result<Accelerogram> {
    let n = spec.samples(name)?;
    let dt = spec.dt_s;
    let envelope = tapered_envelope(&spec.envelope, n, dt);
    let component = |c: usize, peak: f64| -> Result<Vec<f64>> {
        if peak == 0.0 {
            return Ok(vec![0.0; n]);
        }
        let mut rng = stream(spec.seed, c);
        let mut a = stationary(&spec.filter, n, dt, &mut rng);
        for (a, e) in a.iter_mut().zip(&envelope) {
            *a *= e;
        }
        at_rest(&mut a, &envelope, dt)?;
        let max = a.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let scale = peak / max;
        Ok(a.into_iter().map(|v| v * scale).collect())
    };
    Ok(Accelerogram {
        dt_s: dt,
        x: component(0, spec.pga)?,
        y: component(1, spec.pga)?,
        z: component(2, spec.pga * spec.vertical_ratio)?,
    })
}

/// The longest end taper (s) and its share of the record ([`tapered_envelope`]).
pub const END_TAPER: (f64, f64) = (1.0, 0.05);

/// The envelope e(t) at the `n` samples, times a half-cosine taper from 1 to 0 over the
/// record's last [`END_TAPER`] (5 % of it, at most 1 s), exactly 0 at the last sample: the
/// record then ends at zero acceleration, so the ground's step from its last sample to the
/// zero after it adds nothing (a last sample a_N ≠ 0 left Δt·a_N/2 of velocity per run and a
/// drift that never ended), and the correction of step 3, proportional to the same envelope,
/// keeps it zero.
pub fn tapered_envelope(e: &Envelope, n: usize, dt: f64) -> Vec<f64> {
    let span = (n - 1) as f64 * dt;
    let taper = END_TAPER.0.min(END_TAPER.1 * span);
    (0..n)
        .map(|j| {
            let t = j as f64 * dt;
            let into = t - (span - taper);
            let w = if j + 1 == n {
                0.0
            } else if into > 0.0 {
                0.5 * (1.0 + (std::f64::consts::PI * into / taper).cos())
            } else {
                1.0
            };
            e.at(t) * w
        })
        .collect()
}

/// Step 1: `n` samples of the stationary sum, by one inverse real FFT of even length m ≥ n.
/// The phases are drawn in the order k = 1, 2, … (the test's direct sum draws them alike).
pub fn stationary(filter: &GroundFilter, n: usize, dt: f64, rng: &mut SplitMix64) -> Vec<f64> {
    let m = (n + (n & 1)).max(2);
    let d_omega = 2.0 * std::f64::consts::PI / (m as f64 * dt);
    let mut spectrum = vec![Complex::new(0.0, 0.0); m / 2 + 1];
    for (k, bin) in spectrum.iter_mut().enumerate().take(m / 2).skip(1) {
        let amp = (2.0 * filter.shape(k as f64 * d_omega) * d_omega).sqrt();
        let phase = 2.0 * std::f64::consts::PI * rng.next_unit();
        // The inverse transform sums X_k e^{iω_k t} + its conjugate: half the amplitude each.
        *bin = Complex::from_polar(0.5 * amp, phase);
    }
    let mut out = vec![0.0; m];
    RealFftPlanner::<f64>::new()
        .plan_fft_inverse(m)
        .process(&mut spectrum, &mut out)
        .expect("bins 0 and m/2 are real by construction");
    out.truncate(n);
    out
}

/// Velocity and displacement at the end of `a` integrated from rest by the trapezoid rule.
fn end_state(a: impl Iterator<Item = f64>, dt: f64) -> (f64, f64) {
    let (mut v, mut d, mut prev) = (0.0, 0.0, None);
    for a in a {
        if let Some(p) = prev {
            let v1 = v + 0.5 * dt * (p + a);
            d += 0.5 * dt * (v + v1);
            v = v1;
        }
        prev = Some(a);
    }
    (v, d)
}

/// Step 3: subtracts e(t)(α + βt) so that the record ends at rest (module docs).
fn at_rest(a: &mut [f64], envelope: &[f64], dt: f64) -> Result<()> {
    let t = |j: usize| j as f64 * dt;
    let (va, da) = end_state(a.iter().copied(), dt);
    let (v0, d0) = end_state(envelope.iter().copied(), dt);
    let (v1, d1) = end_state(envelope.iter().enumerate().map(|(j, e)| e * t(j)), dt);
    let det = v0 * d1 - v1 * d0;
    if !det.is_normal() || det.abs() < 1e-12 * (v0 * d1).abs().max((v1 * d0).abs()) {
        return Err(Error::invalid(
            "--rise-s/--strong-end-s/--decay-per-s",
            "the envelope is too short to bring the record to rest (lengthen the strong motion)",
        ));
    }
    let alpha = (va * d1 - v1 * da) / det;
    let beta = (v0 * da - va * d0) / det;
    for (j, (a, e)) in a.iter_mut().zip(envelope).enumerate() {
        *a -= e * (alpha + beta * t(j));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The default record of seed 7 (the independence test varies the seed).
    pub(super) fn spec() -> Spec {
        Spec {
            filter: GroundFilter::MEDIUM,
            envelope: Envelope {
                rise_s: 2.0,
                strong_end_s: 10.0,
                decay_per_s: 0.4,
            },
            duration_s: 20.0,
            dt_s: 0.005,
            pga: 0.2 * G,
            vertical_ratio: 2.0 / 3.0,
            seed: 7,
        }
    }

    /// The filters' closed-form values: Kanai–Tajimi at ω_g is (1 + 4ζ_g²)/(4ζ_g²) and tends
    /// to 1 at low frequency; the high-pass is 1/(4ζ_f²) at ω_f and ω⁴/ω_f⁴ near zero.
    #[test]
    fn the_spectrum_shape_has_its_closed_form_values() {
        let only_kt = GroundFilter::new(10.0, 0.4, 1e-3, 0.6);
        let kt_at_wg = (1.0 + 4.0 * 0.16) / (4.0 * 0.16);
        assert!((only_kt.shape(10.0) / kt_at_wg - 1.0).abs() < 1e-6);
        let only_hp = GroundFilter::new(1e4, 0.4, 1.0, 0.6);
        assert!((only_hp.shape(1.0) * 4.0 * 0.36 - 1.0).abs() < 1e-6);
        assert!((only_hp.shape(1e-3) / 1e-12 - 1.0).abs() < 1e-5);
        assert_eq!(GroundFilter::FIRM.shape(0.0), 0.0);
    }

    /// Step 1 against the direct cosine sum, written here with its own phases.
    #[test]
    fn the_fft_synthesis_equals_the_direct_sum() {
        for n in [1, 2, 199, 200] {
            let (f, dt) = (GroundFilter::SOFT, 0.01);
            let fast = stationary(&f, n, dt, &mut SplitMix64::new(42));
            let m = if n % 2 == 0 { n.max(2) } else { n + 1 };
            let dw = 2.0 * std::f64::consts::PI / (m as f64 * dt);
            let mut rng = SplitMix64::new(42);
            let terms: Vec<(f64, f64, f64)> = (1..m / 2)
                .map(|k| {
                    let w = k as f64 * dw;
                    let phase = 2.0 * std::f64::consts::PI * rng.next_unit();
                    ((2.0 * f.shape(w) * dw).sqrt(), w, phase)
                })
                .collect();
            let peak = fast.iter().fold(1e-300_f64, |p, v| p.max(v.abs()));
            for (j, v) in fast.iter().enumerate() {
                let t = j as f64 * dt;
                let direct: f64 = terms.iter().map(|(a, w, p)| a * (w * t + p).cos()).sum();
                assert!(
                    (v - direct).abs() <= 1e-12 * peak,
                    "n {n} j {j}: {v} vs {direct}"
                );
            }
        }
    }

    #[test]
    fn the_envelope_rises_holds_and_decays() {
        let e = spec().envelope;
        assert_eq!(e.at(0.0), 0.0);
        assert_eq!(e.at(1.0), 0.25);
        assert_eq!(e.at(5.0), 1.0);
        assert!((e.at(12.0) - (-0.8_f64).exp()).abs() < 1e-15);
    }

    /// Step 3 and 4: the peaks are the requested ones and the record ends at rest (velocity
    /// and displacement integrated here by the trapezoid rule, independently of `end_state`).
    #[test]
    fn the_record_has_its_peaks_and_ends_at_rest() {
        let s = spec();
        let r = synthesize(&s, &flag).unwrap();
        assert_eq!(r.x.len(), 4001);
        let peak = |a: &[f64]| a.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        assert!((peak(&r.x) / s.pga - 1.0).abs() < 1e-15);
        assert!((peak(&r.y) / s.pga - 1.0).abs() < 1e-15);
        assert!((peak(&r.z) / (s.pga * 2.0 / 3.0) - 1.0).abs() < 1e-15);
        for a in [&r.x, &r.y, &r.z] {
            let mut v = vec![0.0; a.len()];
            for j in 1..a.len() {
                v[j] = v[j - 1] + 0.5 * s.dt_s * (a[j - 1] + a[j]);
            }
            let d: f64 = (1..a.len()).map(|j| 0.5 * s.dt_s * (v[j - 1] + v[j])).sum();
            let vmax = peak(&v);
            assert!(
                v[a.len() - 1].abs() < 1e-9 * vmax,
                "final velocity {}",
                v[a.len() - 1]
            );
            assert!(
                d.abs() < 1e-9 * vmax * s.duration_s,
                "final displacement {d}"
            );
            assert_eq!(a[0], 0.0, "the envelope starts at zero");
            assert_eq!(a[a.len() - 1], 0.0, "the last sample is zero");
        }
    }

    #[test]
    fn a_seed_gives_one_record_and_components_differ() {
        let a = synthesize(&spec(), &flag).unwrap();
        assert_eq!(a, synthesize(&spec(), &flag).unwrap());
        assert_ne!(a.x, a.y);
        let other = synthesize(&Spec { seed: 8, ..spec() }, &flag).unwrap();
        assert_ne!(a.x, other.x);
        let flat = synthesize(
            &Spec {
                vertical_ratio: 0.0,
                ..spec()
            },
            &flag,
        )
        .unwrap();
        assert!(flat.z.iter().all(|v| *v == 0.0 && v.is_sign_positive()));
    }

    #[test]
    fn bad_values_name_their_key() {
        let cases: [(&str, Spec); 6] = [
            (
                "--pga-g",
                Spec {
                    pga: -1.0,
                    ..spec()
                },
            ),
            (
                "--dt-s",
                Spec {
                    dt_s: f64::NAN,
                    ..spec()
                },
            ),
            (
                "--duration-s",
                Spec {
                    duration_s: 1e9,
                    ..spec()
                },
            ),
            (
                "--zeta-g",
                Spec {
                    filter: GroundFilter::new(10.0, 0.0, 1.0, 0.6),
                    ..spec()
                },
            ),
            (
                "--strong-end-s",
                Spec {
                    envelope: Envelope {
                        rise_s: 5.0,
                        strong_end_s: 1.0,
                        decay_per_s: 0.4,
                    },
                    ..spec()
                },
            ),
            (
                "--duration-s/--dt-s",
                Spec {
                    duration_s: 0.2,
                    dt_s: 0.1,
                    envelope: Envelope {
                        rise_s: 0.0,
                        strong_end_s: 0.1,
                        decay_per_s: 0.4,
                    },
                    ..spec()
                },
            ),
        ];
        for (key, s) in cases {
            let e = synthesize(&s, &flag).unwrap_err().to_string();
            assert!(
                e.starts_with(&format!("{key}: ")) && !e.contains('\n'),
                "{e}"
            );
        }
    }
}

#[cfg(test)]
#[path = "accelerogram_independence.rs"]
mod independence;
