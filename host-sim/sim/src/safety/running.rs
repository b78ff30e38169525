//! Running-safety and comfort indices of a wheel/rail passage, each judged against its limit
//! with the limit's source (issue 41 point 5; docs/safety.md, "Running safety of the
//! high-speed car"). Pure functions of sampled signals; no run, no I/O.
//!
//! - Derailment quotient Y/Q per wheel: the ratio of the rail's lateral to vertical force
//!   on the wheel, as EN 14363 evaluates it: a sliding mean over 2 m of track, then the
//!   99.85th percentile of the means (nearest rank). Limit 0.8.
//! - Wheel unloading ΔP/P = (P0 − P)/P0, the largest. Limit 0.6.
//! - Wheelset lateral force ΣY (the sum over its two wheels), sliding mean over 2 m, the
//!   largest |mean|, against Prud'homme's α(10 + P0/3) kN with P0 the static axle load in
//!   kN (α = 1; EN 14363 writes it 10 + 2Q0/3 with Q0 the wheel load).
//! - Car-body acceleration, the largest |a| (vertical and lateral). Limit 2.5 m/s².
//! - Sperling's ride index W = (Σ_f W_f¹⁰)^{1/10}, W_f = 0.896 (a_f³ F(f)/f)^{1/10}, with
//!   a_f the amplitude (cm/s²) of the body acceleration's component at frequency f (Hz,
//!   0.5–40 Hz) and F(f) the frequency weighting, vertical 0.325 f² (0.5–5.9 Hz), 400/f²
//!   (5.9–20 Hz), 1 (> 20 Hz); lateral 0.8 f² (0.5–5.4 Hz), 650/f² (5.4–26 Hz), 1 (> 26 Hz).
//!   Limit 2.5 ("excellent").
//!
//! Before Y/Q, ΔP/P and ΣY the wheel forces pass a 20 Hz low-pass ([`low_pass`]), the
//! filter EN 14363 applies to measured wheel–rail forces (as cited); GB/T 5599's own
//! processing of ΔP/P was not read, and the same filter is applied to it. A wheel whose
//! unfiltered normal force reaches zero is counted apart ([`RailOutcome::lift_off_steps`]).
//!
//! Sources: the limits and the filter as cited for UIC 518 / EN 14363 and GB/T 5599-2019
//! in the vehicle–bridge literature; **the standards' texts were not read**.

use super::Figure;
use crate::physics::rail::run::RailOutcome;
use realfft::RealFftPlanner;

/// One judged index.
#[derive(Clone, Debug, PartialEq)]
pub struct Index {
    /// The figure (SI, or 1 for a ratio).
    pub value: f64,
    /// Its limit.
    pub limit: f64,
    /// Whether `value` is within `limit`.
    pub pass: bool,
    /// Where the limit comes from.
    pub source: &'static str,
}

impl Index {
    fn at_most(value: f64, limit: f64, source: &'static str) -> Self {
        Index {
            value,
            limit,
            pass: value <= limit,
            source,
        }
    }
}

/// Y/Q limit (UIC 518, EN 14363; GB/T 5599-2019 the same value).
pub const Y_Q_LIMIT: f64 = 0.8;
/// ΔP/P limit (GB/T 5599).
pub const UNLOADING_LIMIT: f64 = 0.6;
/// Car-body acceleration limit, m/s² (GB/T 5599).
pub const BODY_ACCELERATION_LIMIT: f64 = 2.5;
/// Sperling index limit, "excellent" (GB/T 5599).
pub const SPERLING_LIMIT: f64 = 2.5;
/// Length of EN 14363's sliding mean, m.
pub const WINDOW_M: f64 = 2.0;
/// EN 14363's percentile of the sliding means.
pub const PERCENTILE: f64 = 99.85;

/// The low-pass cut-off applied to the wheel forces before Y/Q, ΔP/P and ΣY, Hz (module
/// docs).
pub const FORCE_FILTER_HZ: f64 = 20.0;

/// `x` sampled every `dt` s through a 4th-order Butterworth low-pass of cut-off `fc` Hz
/// (below the Nyquist frequency 1/(2dt)): two biquad sections of Q = 1/(2 cos(π/8)) and
/// 1/(2 cos(3π/8)), each the bilinear transform of 1/(s² + s/Q + 1) with the cut-off
/// pre-warped (K = tan(π fc dt)), so that the digital response is
/// |H| = 1/√(1 + (tan(π f dt)/K)⁸). Causal, started at rest on x[0] (a signal constant from
/// its start passes unchanged).
pub fn low_pass(x: &[f64], dt: f64, fc: f64) -> Vec<f64> {
    let k = (std::f64::consts::PI * fc * dt).tan();
    let mut y = x.to_vec();
    for q in [
        0.5 / (std::f64::consts::PI / 8.0).cos(),
        0.5 / (3.0 * std::f64::consts::PI / 8.0).cos(),
    ] {
        let norm = 1.0 / (1.0 + k / q + k * k);
        let b0 = k * k * norm;
        let (b1, b2) = (2.0 * b0, b0);
        let a1 = 2.0 * (k * k - 1.0) * norm;
        let a2 = (1.0 - k / q + k * k) * norm;
        // Transposed direct form II, its state at rest on the first sample.
        let x0 = y.first().copied().unwrap_or(0.0);
        let (mut s1, mut s2) = (x0 * (1.0 - b0), x0 * (b2 - a2));
        for v in y.iter_mut() {
            let input = *v;
            let out = b0 * input + s1;
            s1 = b1 * input - a1 * out + s2;
            s2 = b2 * input - a2 * out;
            *v = out;
        }
    }
    y
}

/// Sliding means of `x` over windows of `window` samples (each full window, in order);
/// empty when `x` is shorter than one window.
pub fn sliding_mean(x: &[f64], window: usize) -> Vec<f64> {
    let w = window.max(1);
    if x.len() < w {
        return Vec::new();
    }
    let mut sum: f64 = x[..w].iter().sum();
    let mut out = Vec::with_capacity(x.len() - w + 1);
    out.push(sum / w as f64);
    for i in w..x.len() {
        sum += x[i] - x[i - w];
        out.push(sum / w as f64);
    }
    out
}

/// The `p`-th percentile of `x` by nearest rank (the smallest value with at least p % of
/// the values at or below it); NaN for an empty `x`.
pub fn percentile(x: &[f64], p: f64) -> f64 {
    if x.is_empty() {
        return f64::NAN;
    }
    let mut v = x.to_vec();
    v.sort_by(f64::total_cmp);
    let rank = ((p / 100.0) * v.len() as f64).ceil() as usize;
    v[rank.clamp(1, v.len()) - 1]
}

/// The number of samples in 2 m of track at the sample spacing `dx` (m).
pub fn window(dx: f64) -> usize {
    ((WINDOW_M / dx).round() as usize).max(1)
}

/// Y/Q of one wheel from its lateral `y` and vertical `q` forces (N) sampled every `dx`
/// metres: |Y|/Q (a wheel off its rail, Q ≤ 0, counts as Y/Q = ∞), 2 m sliding mean, the
/// 99.85th percentile.
pub fn derailment_quotient(y: &[f64], q: &[f64], dx: f64) -> Index {
    let ratio: Vec<f64> = y
        .iter()
        .zip(q)
        .map(|(y, q)| if *q > 0.0 { y.abs() / q } else { f64::INFINITY })
        .collect();
    let value = percentile(&sliding_mean(&ratio, window(dx)), PERCENTILE);
    Index::at_most(
        value,
        Y_Q_LIMIT,
        "UIC 518 / EN 14363 (20 Hz low-pass, 2 m sliding mean, 99.85th percentile), as cited",
    )
}

/// The largest wheel unloading (P0 − P)/P0 of the forces `p` (N) with static load `p0`.
pub fn unloading(p: &[f64], p0: f64) -> Index {
    let value = p
        .iter()
        .map(|p| (p0 - p.max(0.0)) / p0)
        .fold(f64::NEG_INFINITY, f64::max);
    Index::at_most(
        value,
        UNLOADING_LIMIT,
        "GB/T 5599-2019, as cited (20 Hz low-pass as EN 14363's wheel forces)",
    )
}

/// Prud'homme's limit of the wheelset lateral force, N, for the static axle load `axle`
/// (N): α(10 + P0/3) kN with P0 in kN, α = 1.
pub fn prudhomme_limit(axle: f64) -> f64 {
    1e3 * (10.0 + axle / 1e3 / 3.0)
}

/// The wheelset lateral force ΣY (N, sampled every `dx` m): the largest |2 m sliding mean|
/// against Prud'homme's limit for the static axle load `axle` (N).
pub fn wheelset_lateral_force(sum_y: &[f64], axle: f64, dx: f64) -> Index {
    let value = sliding_mean(sum_y, window(dx))
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    Index::at_most(
        value,
        prudhomme_limit(axle),
        "Prud'homme, EN 14363 (10 + 2Q0/3 kN, 20 Hz low-pass, 2 m sliding mean), as cited",
    )
}

/// The largest |a| of a car-body acceleration (m/s²).
pub fn body_acceleration(a: &[f64]) -> Index {
    let value = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    Index::at_most(value, BODY_ACCELERATION_LIMIT, "GB/T 5599-2019, as cited")
}

/// The direction of a Sperling index (its frequency weighting).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// Vertical.
    Vertical,
    /// Lateral.
    Lateral,
}

/// Sperling's frequency weighting F(f) (module docs).
pub fn sperling_weight(direction: Direction, f: f64) -> f64 {
    match direction {
        Direction::Vertical if f <= 5.9 => 0.325 * f * f,
        Direction::Vertical if f <= 20.0 => 400.0 / (f * f),
        Direction::Lateral if f <= 5.4 => 0.8 * f * f,
        Direction::Lateral if f <= 26.0 => 650.0 / (f * f),
        _ => 1.0,
    }
}

/// Sperling's index of the body acceleration `a` (m/s²) sampled every `dt` s: the
/// amplitude spectrum of one real FFT over the record (a_f = 2|X_f|/n), every bin in
/// 0.5–40 Hz, combined as (Σ W_f¹⁰)^{1/10} (module docs).
pub fn sperling(a: &[f64], dt: f64, direction: Direction) -> Index {
    let n = a.len();
    let mut value = 0.0;
    if n >= 2 {
        let fft = RealFftPlanner::<f64>::new().plan_fft_forward(n);
        let mut input = a.to_vec();
        let mut spectrum = fft.make_output_vec();
        if fft.process(&mut input, &mut spectrum).is_ok() {
            let df = 1.0 / (n as f64 * dt);
            let sum: f64 = spectrum
                .iter()
                .enumerate()
                .skip(1)
                .filter(|(k, _)| (0.5..=40.0).contains(&(*k as f64 * df)))
                .map(|(k, x)| {
                    let f = k as f64 * df;
                    let amp = 2.0 * x.norm() / n as f64 * 100.0; // cm/s²
                    let w = 0.896 * (amp.powi(3) * sperling_weight(direction, f) / f).powf(0.1);
                    w.powi(10)
                })
                .sum();
            value = sum.powf(0.1);
        }
    }
    Index::at_most(
        value,
        SPERLING_LIMIT,
        "Sperling, GB/T 5599-2019 Annex E, as cited",
    )
}

/// The running-safety figures of a run of 3-D high-speed cars (summary.json
/// `safety.high_speed`), each the worst over the train's wheels, wheelsets or cars, with its
/// limit, the limit's source and the verdict.
#[derive(serde::Serialize, Debug, Clone, PartialEq)]
pub struct HighSpeedFigures {
    /// Y/Q ([`derailment_quotient`]), the worst wheel.
    pub derailment_quotient: Figure,
    /// ΔP/P ([`unloading`]), the worst wheel.
    pub unloading_max: Figure,
    /// ΣY against Prud'homme ([`wheelset_lateral_force`]), the worst wheelset.
    pub wheelset_lateral_force: Figure,
    /// Body acceleration ([`body_acceleration`]), vertical and lateral, the worst car.
    pub body_acceleration_vertical: Figure,
    /// See `body_acceleration_vertical`.
    pub body_acceleration_lateral: Figure,
    /// Sperling's W ([`sperling`]), vertical and lateral, the worst car.
    pub sperling_vertical: Figure,
    /// See `sperling_vertical`.
    pub sperling_lateral: Figure,
    /// Steps with some wheel off its rail (t = 0 included), the first one's time.
    pub lift_off_steps: Figure,
}

const LIFT_OFF_SOURCE: &str =
    "a wheel off its rail (normal force 0) carries and guides nothing: any lift-off fails the run";

/// The worst (largest value) of `items`, judged, named `at`.
fn worst(items: impl Iterator<Item = (String, Index)>, unit: &'static str) -> Figure {
    let (at, ix) = items
        .fold(None::<(String, Index)>, |best, x| match best {
            Some(b) if x.1.value.is_nan() || x.1.value <= b.1.value => Some(b),
            _ => Some(x),
        })
        .unwrap_or_else(|| (String::new(), Index::at_most(f64::NAN, f64::NAN, "")));
    Figure::judged(ix.value, unit, Some(at), None, Some(ix.limit), ix.source)
}

/// The figures of `out` (module docs; the wheels named `car{N}.axle{K}.left|right`).
pub fn high_speed_figures(out: &RailOutcome) -> HighSpeedFigures {
    let dx = out.speed * out.dt;
    let wheel = |w: usize| {
        let side = if w.is_multiple_of(2) { "left" } else { "right" };
        format!("car{}.axle{}.{side}", w / 8 + 1, (w % 8) / 2 + 1)
    };
    let n = out.lateral.len();
    let filter = |x: &Vec<f64>| low_pass(x, out.dt, FORCE_FILTER_HZ);
    let lateral: Vec<Vec<f64>> = out.lateral.iter().map(filter).collect();
    let vertical: Vec<Vec<f64>> = out.vertical.iter().map(filter).collect();
    let derailment_quotient = worst(
        (0..n).map(|w| (wheel(w), derailment_quotient(&lateral[w], &vertical[w], dx))),
        "1",
    );
    let unloading_max = worst(
        (0..n).map(|w| (wheel(w), unloading(&vertical[w], out.p0))),
        "1",
    );
    let wheelset_lateral_force = worst(
        (0..n / 2).map(|a| {
            let sum: Vec<f64> = lateral[2 * a]
                .iter()
                .zip(&lateral[2 * a + 1])
                .map(|(l, r)| l + r)
                .collect();
            let name = format!("car{}.axle{}", a / 4 + 1, a % 4 + 1);
            (name, wheelset_lateral_force(&sum, 2.0 * out.p0, dx))
        }),
        "N",
    );
    let car = |c: usize| format!("car{}", c + 1);
    let cars = out.body_az.len();
    let body_acceleration_vertical = worst(
        (0..cars).map(|c| (car(c), body_acceleration(&out.body_az[c]))),
        "m/s²",
    );
    let body_acceleration_lateral = worst(
        (0..cars).map(|c| (car(c), body_acceleration(&out.body_ay[c]))),
        "m/s²",
    );
    let sperling_vertical = worst(
        (0..cars).map(|c| {
            (
                car(c),
                sperling(&out.body_az[c], out.dt, Direction::Vertical),
            )
        }),
        "1",
    );
    let sperling_lateral = worst(
        (0..cars).map(|c| {
            (
                car(c),
                sperling(&out.body_ay[c], out.dt, Direction::Lateral),
            )
        }),
        "1",
    );
    let lift_off_steps = Figure::judged(
        out.lift_off_steps as f64,
        "steps",
        None,
        out.first_lift_off_t,
        Some(0.0),
        LIFT_OFF_SOURCE,
    );
    HighSpeedFigures {
        derailment_quotient,
        unloading_max,
        wheelset_lateral_force,
        body_acceleration_vertical,
        body_acceleration_lateral,
        sperling_vertical,
        sperling_lateral,
        lift_off_steps,
    }
}

impl HighSpeedFigures {
    /// Every figure by its summary.json name under `high_speed`.
    pub fn all(&self) -> [(&'static str, &Figure); 8] {
        [
            ("high_speed.derailment_quotient", &self.derailment_quotient),
            ("high_speed.unloading_max", &self.unloading_max),
            (
                "high_speed.wheelset_lateral_force",
                &self.wheelset_lateral_force,
            ),
            (
                "high_speed.body_acceleration_vertical",
                &self.body_acceleration_vertical,
            ),
            (
                "high_speed.body_acceleration_lateral",
                &self.body_acceleration_lateral,
            ),
            ("high_speed.sperling_vertical", &self.sperling_vertical),
            ("high_speed.sperling_lateral", &self.sperling_lateral),
            ("high_speed.lift_off_steps", &self.lift_off_steps),
        ]
    }
}
