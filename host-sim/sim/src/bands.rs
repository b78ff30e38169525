//! One-third-octave band levels of a uniformly sampled time history: IEC 61260-1 base-10
//! bands, each band's mean square the integral of the record's spectrum over the band, with
//! ideal band edges (docs/bands.md).
//!
//! Why the spectrum's integral and not the DFT's bins: the DFT samples the spectrum only at
//! multiples of `1/T`, and splitting those bins at the band edges by the fraction of their
//! width assumes each bin's power is spread evenly over it. A passage record is a transient
//! whose spectrum varies on the scale `1/T`, so in bands a few bins wide that assumption is
//! off by decibels (the paper-5 maglev carriage's 1 Hz band was 2.0 dB high, its 1.25 Hz band
//! 1.1 dB low, against an IEC 61260-1 filter bank and a padded-FFT integration that agree with
//! each other within 0.02 dB). The integral is what an ideal band-pass filter passes of the
//! record (its output's energy over all time, divided by `T`): a filter analyser converges to
//! it, it has no free parameter, and it conserves the mean square (the bands sum to the
//! demeaned record's mean square over the range they cover).
//!
//! # Definition
//!
//! Record: `N` samples `v_j` at spacing `Δt`, `f_s = 1/Δt`, `T = N·Δt`. Its mean is removed
//! (an offset is not vibration); the record is taken as zero outside itself, with spectrum
//! `V(f) = Σ_j v_j·e^{−2πi·f·jΔt}`.
//!
//! * **Band mean square** of band `x` with edges `f_l`, `f_u`, for a level `p` time
//!   derivatives above the column's quantity (displacement 0, velocity 1, acceleration 2):
//!   `ms_x = (2Δt/N)·∫_{f_l}^{f_u} (2πf)^{2p}·|V(f)|² df`. By Parseval the integral over
//!   `(0, f_s/2)` with `p = 0` is the demeaned record's mean square.
//! * **Numerics.** `V` on the grid `k/(MΔt)` by one real FFT of the record zero-padded to `M`,
//!   the smallest power of two `≥ 16·N`; the integral by the midpoint rule on that grid, a bin
//!   on an edge weighted by the fraction of it inside the band. Against a Gauss–Legendre
//!   quadrature of the directly summed spectrum (tests/bands_reference) this is within
//!   0.003 dB in every band of the paper-5 histories and of the test signals.
//! * **Bands.** Band `x` (an integer; `x = 0` is 1 kHz) has the exact mid-band frequency
//!   `f_m = 1000·10^(x/10)` Hz and edges `f_m·10^(±1/20)` (IEC 61260-1 base-10,
//!   `G = 10^(3/10)`, bandwidth designator 1/3). It is labelled with its nominal frequency (1,
//!   1.25, 1.6, 2, 2.5, 3.15, 4, 5, 6.3, 8 × 10ⁿ Hz: [`Band::nominal_hz`]).
//! * **Which bands**: from the lowest band at least `1/T` wide (`f_m ≥ 4.33/T`) to the
//!   highest whose upper edge is at or below `(⌈N/2⌉ − ½)/T ≤ f_s/2`.
//! * **Whole-record level** `L = 10·log10(ms_x/ref²)` dB, ref = 1e-6 m/s² (acceleration) or
//!   1e-9 m/s (velocity), ISO 1683. It is computed from the record scaled to a largest
//!   deviation of 1 and `(2πf_m)^p` taken out of the band's weights, so it is finite for every
//!   finite input. A band without energy (only a constant record has one) has no level
//!   (`None`, an empty cell).
//! * **Maximum running rms**: the band signal `y_x(t)` is the inverse transform of
//!   `(i·2πf)^p·V(f)` on the band (the ideal band-pass filter's output; its energy over all
//!   time, divided by `T`, is `ms_x`). Its running mean square is the linear (rectangular)
//!   average over a window of `W = round(τ/Δt)` samples, `r_j = (1/W) Σ_{i=j}^{j+W−1} y_i²`,
//!   over complete windows inside the record only (`0 ≤ j ≤ N − W`); the level is that of
//!   `max_j r_j` (ISO 2631-1 §6.3.1, "linear integration", whose maximum transient vibration
//!   value uses τ = 1 s).
//!
//! The time column must be uniform: `|t_j − (t_0 + j·Δt)| ≤` [`UNIFORM_TOLERANCE`]`·Δt` for
//! all rows, with `Δt = (t_{N−1} − t_0)/(N − 1)`.

use std::io::{Read, Write};
use std::ops::RangeInclusive;

use realfft::num_complex::Complex;
use realfft::RealFftPlanner;
use thiserror::Error;

/// Reference acceleration for levels, m/s² (ISO 1683).
pub const REF_ACCELERATION: f64 = 1e-6;
/// Reference velocity for levels, m/s (ISO 1683).
pub const REF_VELOCITY: f64 = 1e-9;
/// Largest allowed deviation of a time stamp from the uniform grid, as a fraction of `Δt`.
/// At this jitter the phase error is at most π·10⁻³ rad at Nyquist: negligible in every band.
pub const UNIFORM_TOLERANCE: f64 = 1e-3;

/// The band edges lie 1/20 decade either side of `f_m`: `f_m·10^(±1/20)`.
const HALF_BAND_EXPONENT: f64 = 1.0 / 20.0;

/// Errors of the band analysis, each one line naming the column or the limit.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum BandsError {
    #[error("the CSV has no column {column:?} (columns: {available})")]
    MissingColumn { column: String, available: String },
    #[error("column {column:?} line {line}: {text:?} is not a finite number")]
    BadCell {
        column: String,
        line: u64,
        text: String,
    },
    #[error("the CSV has {rows} data rows; a band analysis needs at least 2")]
    TooFewRows { rows: usize },
    #[error("sample {index} is {value}: every sample must be a finite number")]
    BadSample { index: usize, value: f64 },
    #[error("the sample spacing dt = {dt} s must be a positive finite number")]
    BadStep { dt: f64 },
    #[error("reading the CSV failed: {0}")]
    Csv(String),
    #[error("column \"t\" must increase: t runs from {first} s to {last} s over {rows} rows")]
    NotIncreasing { first: f64, last: f64, rows: usize },
    #[error(
        "column \"t\" is not uniformly sampled: line {line} t = {t} s is {offset:.3e} s off the \
         grid t0 + j*dt (dt = {dt} s), more than the tolerance {tol}*dt"
    )]
    NonUniform {
        line: u64,
        t: f64,
        offset: f64,
        dt: f64,
        tol: f64,
    },
    #[error(
        "record too short for a 1/3-octave band: {n} samples at dt = {dt} s (T = {record} s); \
         the lowest band must be at least 1/T wide and the highest below Nyquist"
    )]
    TooShort { n: usize, dt: f64, record: f64 },
    #[error(
        "running-rms window {window} s must cover at least one sample (dt = {dt} s) and at \
         most the record length T = {record} s"
    )]
    BadWindow { window: f64, dt: f64, record: f64 },
    #[error("writing the band levels failed: {0}")]
    Write(String),
}

/// What a column holds (or what a level is of); the order is the number of time derivatives
/// of displacement.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    Displacement,
    Velocity,
    Acceleration,
}

impl Motion {
    /// Time derivatives of displacement: 0, 1, 2.
    pub fn order(self) -> i32 {
        match self {
            Motion::Displacement => 0,
            Motion::Velocity => 1,
            Motion::Acceleration => 2,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Motion::Displacement => "displacement",
            Motion::Velocity => "velocity",
            Motion::Acceleration => "acceleration",
        }
    }

    /// SI unit.
    pub fn unit(self) -> &'static str {
        match self {
            Motion::Displacement => "m",
            Motion::Velocity => "m/s",
            Motion::Acceleration => "m/s^2",
        }
    }
}

/// What the level is of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Level {
    Velocity,
    Acceleration,
}

impl Level {
    pub fn quantity(self) -> Motion {
        match self {
            Level::Velocity => Motion::Velocity,
            Level::Acceleration => Motion::Acceleration,
        }
    }

    /// Reference value of the level, SI.
    pub fn reference(self) -> f64 {
        match self {
            Level::Velocity => REF_VELOCITY,
            Level::Acceleration => REF_ACCELERATION,
        }
    }
}

/// How each band's rms is formed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Averaging {
    /// The rms over the whole record.
    WholeRecord,
    /// The maximum running rms, linear (rectangular) window of `window_s` seconds.
    MaxRunning { window_s: f64 },
}

/// An IEC 61260-1 base-10 one-third-octave band; `index` x = 0 is the 1 kHz band.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Band {
    pub index: i32,
}

/// Nominal mid-band mantissas in hundredths (IEC 61260-1 Annex E, one decade).
const NOMINAL_HUNDREDTHS: [u32; 10] = [100, 125, 160, 200, 250, 315, 400, 500, 630, 800];

impl Band {
    /// Exact mid-band frequency `1000·10^(x/10)` Hz.
    pub fn exact_hz(self) -> f64 {
        1000.0 * 10f64.powf(f64::from(self.index) / 10.0)
    }

    /// Lower edge `f_m·10^(−1/20)`, computed so that it equals the band below's upper edge bit
    /// for bit.
    pub fn lower_hz(self) -> f64 {
        edge_hz(2 * self.index - 1)
    }

    /// Upper edge `f_m·10^(1/20)`.
    pub fn upper_hz(self) -> f64 {
        edge_hz(2 * self.index + 1)
    }

    pub fn width_hz(self) -> f64 {
        self.upper_hz() - self.lower_hz()
    }

    /// Nominal mid-band frequency (the label): 1, 1.25, 1.6, 2, 2.5, 3.15, 4, 5, 6.3, 8 × 10ⁿ,
    /// formed from integers so that it prints as its decimal (`0.63`, not `0.630…01`).
    pub fn nominal_hz(self) -> f64 {
        let m = f64::from(NOMINAL_HUNDREDTHS[self.index.rem_euclid(10) as usize]);
        // Hundredths × 10^(decade + 3) = m × 10^(decade + 1).
        let e = self.index.div_euclid(10) + 1;
        let p = (0..e.unsigned_abs()).fold(1.0, |p, _| p * 10.0);
        if e >= 0 {
            m * p
        } else {
            m / p
        }
    }
}

/// `1000·10^(k/20)` Hz: band edges for odd k.
fn edge_hz(k: i32) -> f64 {
    1000.0 * 10f64.powf(f64::from(k) / 20.0)
}

/// Highest interior bin (neither DC nor Nyquist): `⌈N/2⌉ − 1`.
fn last_bin(n: usize) -> usize {
    n.div_ceil(2).saturating_sub(1)
}

/// The bands a record of `n` samples at `dt` resolves (see the module doc), lowest first, or
/// `None` when there is none.
pub fn band_range(n: usize, dt: f64) -> Option<RangeInclusive<i32>> {
    if n < 2 || !(dt.is_finite() && dt > 0.0) {
        return None;
    }
    let df = 1.0 / (n as f64 * dt);
    let top = (last_bin(n) as f64 + 0.5) * df;
    // f_m(x) = 1000·10^(x/10); start from the closed-form estimate and step to the exact edge
    // by the same expressions the bands use.
    let c = 10f64.powf(HALF_BAND_EXPONENT) - 10f64.powf(-HALF_BAND_EXPONENT);
    let lo_est = (10.0 * (df / (1000.0 * c)).log10()).ceil();
    let hi_est = (10.0 * (top / 1000.0).log10() - 0.5).floor();
    if !(lo_est.is_finite() && hi_est.is_finite()) || lo_est.abs() > 1e6 || hi_est.abs() > 1e6 {
        return None;
    }
    let mut lo = lo_est as i32;
    while (Band { index: lo - 1 }).width_hz() >= df {
        lo -= 1;
    }
    while (Band { index: lo }).width_hz() < df {
        lo += 1;
    }
    let mut hi = hi_est as i32;
    while (Band { index: hi + 1 }).upper_hz() <= top {
        hi += 1;
    }
    while (Band { index: hi }).upper_hz() > top {
        hi -= 1;
    }
    (lo <= hi).then_some(lo..=hi)
}

/// Bins of one band on an `n`-point DFT grid of spacing `df` (the zero-padded one), with their
/// weights `w_k` (the fraction of the bin's interval inside the band).
fn band_bins(band: Band, n: usize, df: f64) -> Vec<(usize, f64)> {
    let (fl, fu) = (band.lower_hz(), band.upper_hz());
    let first = ((fl / df - 0.5).floor().max(1.0)) as usize;
    let last = ((fu / df + 0.5).ceil() as usize).min(last_bin(n));
    (first..=last)
        .filter_map(|k| {
            let a = (k as f64 - 0.5) * df;
            let b = (k as f64 + 0.5) * df;
            let w = (fu.min(b) - fl.max(a)) / df;
            (w > 0.0).then_some((k, w.min(1.0)))
        })
        .collect()
}

/// One band's result.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BandLevel {
    pub band: Band,
    /// The band's rms (whole record or maximum running), SI units of the level's quantity
    /// (`inf` only where the rms itself exceeds the f64 range; the level stays finite).
    pub rms: f64,
    /// `20·log10(rms/ref)`, dB, always finite; `None` for a band without energy (a constant
    /// record: no other record has a band of exactly zero energy).
    pub level_db: Option<f64>,
}

/// The analysis settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// What the samples are.
    pub input: Motion,
    /// What the level is of.
    pub level: Level,
    pub averaging: Averaging,
}

/// Band levels of `samples` (spacing `dt` s) over [`band_range`], lowest band first.
pub fn analyse(samples: &[f64], dt: f64, s: &Settings) -> Result<Vec<BandLevel>, BandsError> {
    if !(dt.is_finite() && dt > 0.0) {
        return Err(BandsError::BadStep { dt });
    }
    if let Some((index, &value)) = samples.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(BandsError::BadSample { index, value });
    }
    let n = samples.len();
    let record = n as f64 * dt;
    let bands = band_range(n, dt).ok_or(BandsError::TooShort { n, dt, record })?;
    let window = running_window(s.averaging, n, dt)?;
    let spectrum = Spectrum::of(samples, dt);
    let p = s.level.quantity().order() - s.input.order();
    let reference = s.level.reference();
    let mut inverse = None;
    let mut out = Vec::with_capacity(bands.clone().count());
    for index in bands {
        let band = Band { index };
        // Mean square in the spectrum's scaled units, with (2π·f_m)^p taken out.
        let ms = match window {
            None => spectrum.band_mean_square(band, p),
            Some(m) => {
                let ifft = inverse.get_or_insert_with(|| {
                    RealFftPlanner::<f64>::new().plan_fft_inverse(spectrum.padded)
                });
                let y = spectrum.band_signal(band, p, ifft.as_ref());
                max_running_mean_square(&y[..n], m)
            }
        };
        let level_db = (ms > 0.0).then(|| {
            10.0 * ms.log10()
                + 20.0 * (spectrum.scale / reference).log10()
                + 20.0 * f64::from(p) * (std::f64::consts::TAU * band.exact_hz()).log10()
        });
        out.push(BandLevel {
            band,
            rms: level_db.map_or(0.0, |l| reference * 10f64.powf(l / 20.0)),
            level_db,
        });
    }
    Ok(out)
}

/// The running-rms window in samples, `M = round(τ/Δt)`, checked to `1 ≤ M ≤ N`.
fn running_window(averaging: Averaging, n: usize, dt: f64) -> Result<Option<usize>, BandsError> {
    let Averaging::MaxRunning { window_s } = averaging else {
        return Ok(None);
    };
    let m = (window_s / dt).round();
    if !(window_s.is_finite() && m >= 1.0 && m <= n as f64) {
        return Err(BandsError::BadWindow {
            window: window_s,
            dt,
            record: n as f64 * dt,
        });
    }
    Ok(Some(m as usize))
}

/// The record at least this many times zero-padded: the spectrum's grid spacing is then at
/// most `1/(16·T)`, and the midpoint rule over it is within 0.003 dB of the band integral in
/// every band at least `1/T` wide that the tests measure (docs/bands.md, "Accuracy").
const MIN_PADDING: usize = 16;

/// The FFT length for a record of `n` samples: a power of two at least `MIN_PADDING·n`.
fn padded_len(n: usize) -> usize {
    (MIN_PADDING * n).next_power_of_two()
}

/// The spectrum `V(f)` of the demeaned record divided by `scale`, sampled on the zero-padded
/// grid `f_k = k/(padded·Δt)`.
struct Spectrum {
    bins: Vec<Complex<f64>>,
    /// Samples in the record, `N`.
    n: usize,
    /// Samples after zero padding, a power of two `≥ 16·N`.
    padded: usize,
    dt: f64,
    /// The record was divided by this before the FFT (its largest deviation from the mean, or
    /// 1 for a constant record), so no square overflows or underflows.
    scale: f64,
}

impl Spectrum {
    fn of(samples: &[f64], dt: f64) -> Spectrum {
        let n = samples.len();
        let padded = padded_len(n);
        let mut x = demeaned_scaled(samples);
        let scale = x.pop().expect("demeaned_scaled appends the scale");
        x.resize(padded, 0.0);
        let fft = RealFftPlanner::<f64>::new().plan_fft_forward(padded);
        let mut bins = fft.make_output_vec();
        fft.process(&mut x, &mut bins)
            .expect("buffer lengths come from the plan");
        Spectrum {
            bins,
            n,
            padded,
            dt,
            scale,
        }
    }

    fn df(&self) -> f64 {
        1.0 / (self.padded as f64 * self.dt)
    }

    /// The band's bins with their weights `w_k·(f_k/f_m)^{2p}` (the fraction of the bin
    /// inside the band times the conversion, relative to the band's centre).
    fn weighted_bins(&self, band: Band, p: i32) -> Vec<(usize, f64)> {
        let fm = band.exact_hz();
        let df = self.df();
        band_bins(band, self.padded, df)
            .into_iter()
            .map(|(k, w)| (k, w * (k as f64 * df / fm).powi(2 * p)))
            .collect()
    }

    /// `(2/(N·M))·Σ_k w_k·(f_k/f_m)^{2p}·|V_k|²`: the band integral's midpoint rule.
    fn band_mean_square(&self, band: Band, p: i32) -> f64 {
        let norm = 2.0 / (self.n as f64 * self.padded as f64);
        self.weighted_bins(band, p)
            .iter()
            .map(|&(k, w)| w * norm * self.bins[k].norm_sqr())
            .sum()
    }

    /// The band signal over the padded length (the record is its first `N` samples): the
    /// inverse DFT of `√w_k·(i·f_k/f_m)^p·V_k` on the band's bins; its sum of squares over
    /// all `M` samples, divided by `N`, is [`Self::band_mean_square`].
    fn band_signal(&self, band: Band, p: i32, ifft: &dyn realfft::ComplexToReal<f64>) -> Vec<f64> {
        let mut z = ifft.make_input_vec();
        let phase = Complex::new(0.0, 1.0).powi(p);
        for (k, w) in self.weighted_bins(band, p) {
            z[k] = self.bins[k] * phase * w.sqrt();
        }
        let mut y = ifft.make_output_vec();
        ifft.process(&mut z, &mut y)
            .expect("DC and Nyquist bins are zero and the lengths come from the plan");
        // realfft's inverse is unnormalised (M times the band signal).
        let m = self.padded as f64;
        y.iter_mut().for_each(|v| *v /= m);
        y
    }
}

/// The record minus its mean, divided by its largest deviation (all zeros for a constant
/// record), with that divisor appended (1 for a constant record). The division comes first so
/// that no sum overflows.
fn demeaned_scaled(samples: &[f64]) -> Vec<f64> {
    if samples.iter().all(|&v| v == samples[0]) {
        let mut x = vec![0.0; samples.len()];
        x.push(1.0);
        return x;
    }
    let peak = samples.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let mean = samples.iter().map(|v| v / peak).sum::<f64>() / samples.len() as f64;
    let mut x: Vec<f64> = samples.iter().map(|v| v / peak - mean).collect();
    let dev = x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    x.iter_mut().for_each(|v| *v /= dev);
    x.push(peak * dev);
    x
}

/// `max_j (1/m) Σ_{i=j}^{j+m−1} y_i²` over complete windows, by prefix sums (relative rounding
/// ≲ N·ε·(record mean square / window mean square), far below 0.001 dB for these records).
pub fn max_running_mean_square(y: &[f64], m: usize) -> f64 {
    let mut prefix = Vec::with_capacity(y.len() + 1);
    let mut acc = 0.0;
    prefix.push(0.0);
    for v in y {
        acc += v * v;
        prefix.push(acc);
    }
    (0..=y.len() - m)
        .map(|j| (prefix[j + m] - prefix[j]) / m as f64)
        .fold(0.0, f64::max)
}

/// A uniformly sampled history read from CSV.
#[derive(Clone, Debug, PartialEq)]
pub struct History {
    pub t0: f64,
    pub dt: f64,
    pub values: Vec<f64>,
}

/// Read column `t` and `column` of a CSV (header row; `#` lines are comments; cells trimmed).
/// Every cell of both must be a finite number, and `t` uniform (see the module doc).
pub fn read_history<R: Read>(reader: R, column: &str) -> Result<History, BandsError> {
    let mut rdr = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(reader);
    let headers = rdr
        .headers()
        .map_err(|e| BandsError::Csv(e.to_string()))?
        .clone();
    let find = |name: &str| {
        headers
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| BandsError::MissingColumn {
                column: name.to_string(),
                available: headers.iter().collect::<Vec<_>>().join(","),
            })
    };
    let (it, iv) = (find("t")?, find(column)?);
    let (mut t, mut values) = (Vec::new(), Vec::new());
    let mut lines = Vec::new();
    for rec in rdr.records() {
        let rec = rec.map_err(|e| BandsError::Csv(e.to_string()))?;
        let line = rec.position().map_or(0, |p| p.line());
        let cell = |i: usize, name: &str| {
            let text = rec.get(i).unwrap_or("");
            text.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| BandsError::BadCell {
                    column: name.to_string(),
                    line,
                    text: text.to_string(),
                })
        };
        t.push(cell(it, "t")?);
        values.push(cell(iv, column)?);
        lines.push(line);
    }
    let n = t.len();
    if n < 2 {
        return Err(BandsError::TooFewRows { rows: n });
    }
    let (t0, last) = (t[0], t[n - 1]);
    let dt = (last - t0) / (n - 1) as f64;
    if !(dt > 0.0 && dt.is_finite()) {
        return Err(BandsError::NotIncreasing {
            first: t0,
            last,
            rows: n,
        });
    }
    for (j, (&tj, &line)) in t.iter().zip(&lines).enumerate() {
        let offset = tj - (t0 + j as f64 * dt);
        if offset.abs() > UNIFORM_TOLERANCE * dt {
            return Err(BandsError::NonUniform {
                line,
                t: tj,
                offset,
                dt,
                tol: UNIFORM_TOLERANCE,
            });
        }
    }
    Ok(History { t0, dt, values })
}

/// The level column's name: the level in dB with its reference and unit, as pandas and a
/// spreadsheet show it (`level_db_re_1e-6_m_per_s2`, `level_db_re_1e-9_m_per_s`).
pub fn level_column(s: &Settings) -> String {
    let unit = s
        .level
        .quantity()
        .unit()
        .replace("m/s^2", "m_per_s2")
        .replace("m/s", "m_per_s");
    format!("level_db_re_{:e}_{unit}", s.level.reference())
}

/// The method in one line: reference, quantities and method (`maglev bands` prints it on
/// stderr, or writes it to the `--out` file's sidecar; the CSV itself has a plain header).
pub fn description(column: &str, n: usize, dt: f64, s: &Settings) -> String {
    let q = s.level.quantity();
    let averaging = match s.averaging {
        Averaging::WholeRecord => "whole-record rms".to_string(),
        Averaging::MaxRunning { window_s } => format!(
            "maximum running rms, linear (rectangular) window {window_s} s ({} samples)",
            (window_s / dt).round()
        ),
    };
    format!(
        "{} level L = 20*log10(rms/ref) dB re {:e} {}; column {column:?} is {} \
         in {}; IEC 61260-1 base-10 1/3-octave bands (centre_hz nominal, exact f_m = \
         1000*10^(x/10) Hz, edges f_m*10^(+-1/20)); method: the record's mean removed, its spectrum \
         (the record zero outside itself: N = {n}, dt = {dt} s, FFT zero-padded to {padded}) \
         integrated over each band, ideal band edges; {averaging}; an empty level: the band has \
         no energy (a constant record)",
        q.name(),
        s.level.reference(),
        q.unit(),
        s.input.name(),
        s.input.unit(),
        padded = padded_len(n),
    )
}

/// Write the CSV `centre_hz,<level column>` ([`level_column`]; levels to 0.0001 dB; an empty
/// level for a band without energy).
pub fn write_levels<W: Write>(
    w: W,
    level_column: &str,
    levels: &[BandLevel],
) -> Result<(), BandsError> {
    let io = |e: std::io::Error| BandsError::Write(e.to_string());
    let mut wr = csv::Writer::from_writer(w);
    let csv_err = |e: csv::Error| BandsError::Write(e.to_string());
    wr.write_record(["centre_hz", level_column])
        .map_err(csv_err)?;
    for l in levels {
        wr.write_record([
            format!("{}", l.band.nominal_hz()),
            l.level_db.map_or(String::new(), |db| format!("{db:.4}")),
        ])
        .map_err(csv_err)?;
    }
    wr.flush().map_err(io)
}
