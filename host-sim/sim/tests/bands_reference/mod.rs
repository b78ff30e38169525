//! An independent one-third-octave analyser for the tests of `maglev bands`: written from the
//! band definitions of IEC 61260-1 (base 10, designator 1/3) and from the band mean square as
//! the energy an ideal band-pass filter passes, not from the code under test.
//!
//! Definition (docs/bands.md): the record `v_j` (`N` samples, spacing `Δt`, `T = N·Δt`), its
//! mean removed, has the spectrum `V(f) = Σ_j v_j·e^{−2πi·f·jΔt}` (a trigonometric polynomial,
//! the record taken as zero outside itself). By Parseval `Σ v_j² = Δt·∫_{−f_s/2}^{f_s/2}|V|²`,
//! so a band `[f_l, f_u]` holds the mean square (over `T`)
//! `ms = (2Δt/N)·∫_{f_l}^{f_u} (2πf)^{2p}·|V(f)|² df` for a level `p` time derivatives above
//! the column's quantity.
//!
//! How it differs from the code under test: `V(f)` by a direct sum (Horner in `e^{−2πi·fΔt}`)
//! at the nodes of a composite Gauss–Legendre rule, 8 nodes on panels at most `1/(2T)` wide
//! (`|V|²` has no lag longer than `T`, so a panel sees at most half an oscillation of its
//! fastest term, and the rule's error is ~1e-10 relative); no FFT, no zero padding, no
//! fractional bins, nodes from Newton's iteration on the Legendre polynomial.
#![allow(dead_code)]

use std::f64::consts::{PI, TAU};

/// Exact mid-band frequency of base-10 band `x` (x = 0 is 1 kHz), IEC 61260-1 eq. (2)/(3).
pub fn centre_hz(x: i32) -> f64 {
    1000.0 * 10f64.powf(f64::from(x) / 10.0)
}

/// Band edges `f_m·G^(∓1/6)`, `G = 10^(3/10)`, IEC 61260-1 eq. (4)/(5): `f_m·10^(∓1/20)`.
pub fn edges_hz(x: i32) -> (f64, f64) {
    let g = 10f64.powf(0.3);
    let fm = centre_hz(x);
    (fm * g.powf(-1.0 / 6.0), fm * g.powf(1.0 / 6.0))
}

/// `n`-point Gauss–Legendre nodes and weights on [−1, 1] (Newton on `P_n`).
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (1..=n)
        .map(|i| {
            let mut x = (PI * (i as f64 - 0.25) / (n as f64 + 0.5)).cos();
            let mut dp = 0.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let k = k as f64;
                    (p0, p1) = (p1, ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k);
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let step = p1 / dp;
                x -= step;
                if step.abs() < 1e-16 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// The record with its mean removed.
fn demeaned(v: &[f64]) -> Vec<f64> {
    let mean = v.iter().sum::<f64>() / v.len() as f64;
    v.iter().map(|x| x - mean).collect()
}

/// `|V(f)|²` by Horner's rule.
fn power(v: &[f64], dt: f64, f: f64) -> f64 {
    let (c, s) = ((TAU * f * dt).cos(), -(TAU * f * dt).sin());
    let (mut re, mut im) = (0.0, 0.0);
    for &x in v.iter().rev() {
        (re, im) = (re * c - im * s + x, re * s + im * c);
    }
    re * re + im * im
}

/// Mean square over `T` in `[lo, hi]` Hz of the demeaned record `v`, its level `p` derivatives
/// above the column (`p` = −1: acceleration → velocity, 0, 1, 2).
fn mean_square(v: &[f64], dt: f64, p: i32, lo: f64, hi: f64, rule: &[(f64, f64)]) -> f64 {
    let t = v.len() as f64 * dt;
    let panels = ((hi - lo) * 2.0 * t).ceil().max(1.0) as usize;
    let h = (hi - lo) / panels as f64;
    let mut sum = 0.0;
    for i in 0..panels {
        let mid = lo + (i as f64 + 0.5) * h;
        for &(x, w) in rule {
            let f = mid + 0.5 * h * x;
            sum += 0.5 * h * w * (TAU * f).powi(2 * p) * power(v, dt, f);
        }
    }
    2.0 * dt / v.len() as f64 * sum
}

/// Band mean squares of `samples` for the base-10 bands `bands`, `p` derivatives above the
/// column's quantity.
pub fn band_mean_squares(samples: &[f64], dt: f64, p: i32, bands: &[i32]) -> Vec<f64> {
    let v = demeaned(samples);
    let rule = gauss_legendre(8);
    bands
        .iter()
        .map(|&x| {
            let (lo, hi) = edges_hz(x);
            mean_square(&v, dt, p, lo, hi, &rule)
        })
        .collect()
}

/// The mean square of the demeaned record over `[0, f_s/2]` by the same quadrature: equals
/// `Σ(v_j − mean)²/N` (Parseval), a check of the analyser itself.
pub fn mean_square_to_nyquist(samples: &[f64], dt: f64) -> f64 {
    mean_square(&demeaned(samples), dt, 0, 0.0, 0.5 / dt, &gauss_legendre(8))
}

/// A CSV history: column `t` and `column` (header row, no comments).
pub fn read_csv_column(path: &std::path::Path, column: &str) -> (Vec<f64>, f64) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let it = header.iter().position(|h| *h == "t").unwrap();
    let ic = header.iter().position(|h| *h == column).unwrap();
    let (mut t, mut v) = (Vec::new(), Vec::new());
    for line in lines {
        let cells: Vec<&str> = line.split(',').collect();
        t.push(cells[it].parse::<f64>().unwrap());
        v.push(cells[ic].parse::<f64>().unwrap());
    }
    let dt = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
    (v, dt)
}

/// The band signal at the record's samples, `y_j = 2Δt·Re ∫_{f_l}^{f_u} (i2πf)^p·V(f)·
/// e^{2πi·f·jΔt} df` (the inverse transform restricted to the band and its mirror image),
/// by the same quadrature as the mean squares.
pub fn band_signal(samples: &[f64], dt: f64, p: i32, x: i32) -> Vec<f64> {
    let v = demeaned(samples);
    let (lo, hi) = edges_hz(x);
    let t = v.len() as f64 * dt;
    let panels = ((hi - lo) * 2.0 * t).ceil().max(1.0) as usize;
    let h = (hi - lo) / panels as f64;
    let rule = gauss_legendre(8);
    // (frequency, weight × (i2πf)^p·V(f)) at every node.
    let mut nodes = Vec::with_capacity(panels * rule.len());
    for i in 0..panels {
        let mid = lo + (i as f64 + 0.5) * h;
        for &(xn, w) in &rule {
            let f = mid + 0.5 * h * xn;
            let (c, s) = ((TAU * f * dt).cos(), -(TAU * f * dt).sin());
            let (mut re, mut im) = (0.0, 0.0);
            for &s_j in v.iter().rev() {
                (re, im) = (re * c - im * s + s_j, re * s + im * c);
            }
            // (i2πf)^p: magnitude (2πf)^p, phase p·π/2.
            let (m, ph) = ((TAU * f).powi(p), f64::from(p) * PI / 2.0);
            let (cr, ci) = (m * ph.cos(), m * ph.sin());
            let g = 0.5 * h * w;
            nodes.push((f, g * (re * cr - im * ci), g * (re * ci + im * cr)));
        }
    }
    (0..v.len())
        .map(|j| {
            let tj = j as f64 * dt;
            2.0 * dt
                * nodes
                    .iter()
                    .map(|&(f, re, im)| re * (TAU * f * tj).cos() - im * (TAU * f * tj).sin())
                    .sum::<f64>()
        })
        .collect()
}

/// `max_j` of the mean of `y²` over `m` consecutive samples, summed directly.
pub fn max_running_mean_square(y: &[f64], m: usize) -> f64 {
    (0..=y.len() - m)
        .map(|j| y[j..j + m].iter().map(|v| v * v).sum::<f64>() / m as f64)
        .fold(0.0, f64::max)
}
