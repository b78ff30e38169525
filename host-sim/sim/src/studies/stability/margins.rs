//! Stability margins of each magnet's loop (docs/levitation.md "Margins"): the loop broken at
//! one magnet's coil voltage, every other loop closed, a pure delay in series.
//!
//! # The loop transfer
//! The closed loop is `ṡ = A·s` ([`VehiclePlant`]). Magnet `k`'s coil row holds the law's
//! voltage `Δv = F·s` entering through `B = e_x/τ` ([`MagnetLoop`]), so with that one voltage
//! cut the plant seen from the coil is `A_ol = A − B·F` and, for the negative-feedback
//! convention (closed loop `1 + L = 0`),
//! ```text
//! L(s) = −F·(s·I − A_ol)⁻¹·B · e^(−s·T)
//! ```
//! `T` is the delay in series: what the sampled law adds to the ideal one (its hold and its
//! computation; docs/levitation.md "The delay").
//!
//! # The margins
//! * gains: the loop gain `κ·L` stays stable for `κ` in `(κ_low, κ_high)` around 1. The
//!   stability of `1 + κ·L` changes only where `L(jω)` crosses the negative real axis
//!   (`κ = −1/L(jω)`) or at `ω = 0`, so the interval's ends are the nearest such `κ` below and
//!   above 1, found on a log grid of `ω` (100 points a decade, 1e-2 to 1e6 rad/s) refined by
//!   bisection on `Im L`. `gain_low_db = −20·log10(κ_low)` (how far the gain may fall),
//!   `gain_high_db = 20·log10(κ_high)` (how far it may rise); `None` where no end exists.
//! * phase: at every gain crossover `|L(jω)| = 1` (grid + bisection on `log|L|`) the
//!   distance of `∠L` from −180°; the margin is the smallest over the crossovers.
//! * sensitivity peak `Ms = max_ω |1/(1 + L(jω))|` (grid, then golden section around the
//!   largest grid value).
//!
//! Whether `κ = 1` itself is stable with the delay (zero poles left out, as
//! [`super::vehicle::Verdict`] does) is decided on a rational model: the
//! delay as its (2, 2) Padé approximant in the loop (exact in phase to 1e-5 rad at
//! `ω·T = 0.1`, far above any crossover here). When it is not, the margins are `None`.

use super::resolvent::Resolvent;
use super::vehicle::{MagnetLoop, VehiclePlant};
use nalgebra::{Complex, DMatrix, DVector};
use serde::Serialize;

/// One magnet's margins (module docs).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Margins {
    pub magnet: String,
    /// The delay in series (s).
    pub delay_s: f64,
    /// The closed loop with the delay (Padé (2, 2)) is stable.
    pub stable_with_delay: bool,
    pub gain_low_db: Option<f64>,
    pub gain_high_db: Option<f64>,
    pub phase_deg: Option<f64>,
    pub sensitivity_peak: Option<f64>,
    /// Frequency of the smallest phase margin's crossover (rad/s).
    pub crossover_rad_per_s: Option<f64>,
}

/// Magnet `k`'s loop, broken at its coil voltage.
pub struct BrokenLoop {
    a_ol: DMatrix<f64>,
    b: DVector<f64>,
    f: DVector<f64>,
    /// `f·(sI − A_ol)⁻¹·b` at any `s` ([`Resolvent`]).
    response: Resolvent,
    /// The delay in series (s).
    pub delay: f64,
}

impl BrokenLoop {
    /// Magnet `k` of `plant` with the delay `delay` (s, ≥ 0).
    pub fn new(plant: &VehiclePlant, k: usize, delay: f64) -> crate::Result<Self> {
        let m: &MagnetLoop = plant
            .magnets
            .get(k)
            .ok_or_else(|| crate::Error::numerical("internal: no such magnet"))?;
        let n = plant.a.nrows();
        if m.dv.len() != n {
            return Err(crate::Error::numerical(
                "internal: the magnet's voltage row does not span the state",
            ));
        }
        let mut b = DVector::zeros(n);
        b[m.x] = 1.0 / m.tau;
        let f = DVector::from_column_slice(&m.dv);
        let a_ol = &plant.a - &b * f.transpose();
        let response = Resolvent::new(
            &a_ol,
            &DMatrix::from_column_slice(n, 1, b.as_slice()),
            &DMatrix::from_row_slice(1, n, f.as_slice()),
        );
        Ok(BrokenLoop {
            a_ol,
            b,
            f,
            response,
            delay,
        })
    }

    /// `L(s)` (module docs).
    pub fn at(&self, s: Complex<f64>) -> Complex<f64> {
        let Some(x) = self.response.at(s) else {
            return Complex::new(f64::INFINITY, 0.0);
        };
        -x[(0, 0)] * (-s * self.delay).exp()
    }

    /// `L(jω)`.
    pub fn at_freq(&self, w: f64) -> Complex<f64> {
        self.at(Complex::new(0.0, w))
    }

    /// The closed loop `κ = 1` with the delay as a (2, 2) Padé approximant: its state matrix
    /// (the one-input [`super::multiloop::Cut`]'s).
    pub fn closed_with_pade(&self) -> DMatrix<f64> {
        super::multiloop::Cut {
            a_ol: self.a_ol.clone(),
            b: DMatrix::from_column_slice(self.b.len(), 1, self.b.as_slice()),
            f: DMatrix::from_row_slice(1, self.f.len(), self.f.as_slice()),
            delay: self.delay,
        }
        .closed_with_pade()
    }
}

/// Bisection on a sign change of `g` in `[a, b]` (log-spaced), to 1e-12 relative.
fn bisect(mut a: f64, mut b: f64, g: impl Fn(f64) -> f64) -> f64 {
    let ga = g(a);
    for _ in 0..100 {
        let m = (a * b).sqrt();
        if (g(m) > 0.0) == (ga > 0.0) {
            a = m;
        } else {
            b = m;
        }
        if b / a - 1.0 < 1e-12 {
            break;
        }
    }
    (a * b).sqrt()
}

/// The wrapped distance of `∠z` from −180° (degrees, in [0, 180]).
fn phase_distance(z: Complex<f64>) -> f64 {
    let a = z.arg().to_degrees() + 180.0;
    let w = a - 360.0 * (a / 360.0).round();
    w.abs()
}

/// Magnet `k`'s margins in `plant` with `delay` in series (module docs).
pub fn margins(plant: &VehiclePlant, k: usize, delay: f64) -> crate::Result<Margins> {
    let lp = BrokenLoop::new(plant, k, delay)?;
    let name = plant.magnets[k].name.clone();
    // Zero poles (|s| < ZERO_POLE: the integral of a law with ki = 0, the paper's law's free
    // positions) are left out, as in the report's verdict.
    let poles = super::eigenvalues(&lp.closed_with_pade())?;
    let stable = super::vehicle::Verdict::of(poles).stable;
    let none = Margins {
        magnet: name.clone(),
        delay_s: delay,
        stable_with_delay: stable,
        gain_low_db: None,
        gain_high_db: None,
        phase_deg: None,
        sensitivity_peak: None,
        crossover_rad_per_s: None,
    };
    if !stable {
        return Ok(none);
    }
    let ws = super::resolvent::grid();
    let ls: Vec<Complex<f64>> = ws.iter().map(|&w| lp.at_freq(w)).collect();
    // Gain: κ = −1/L where L is real and negative; ω = 0 included when L(0) is finite.
    let mut kappas = Vec::new();
    // At s = 1e-9 (real) rather than 0: a law's integral with ki = 0 leaves a zero row.
    let l0 = lp.at(Complex::new(1e-9, 0.0));
    if l0.re.is_finite() && l0.re.abs() < 1e12 && l0.re < 0.0 {
        kappas.push(-1.0 / l0.re);
    }
    let mut crossings = Vec::new();
    for i in 1..ws.len() {
        let (l1, l2) = (ls[i - 1], ls[i]);
        if (l1.im > 0.0) != (l2.im > 0.0) {
            let w = bisect(ws[i - 1], ws[i], |w| lp.at_freq(w).im);
            let l = lp.at_freq(w);
            if l.re < 0.0 {
                kappas.push(-1.0 / l.re);
            }
        }
        let (g1, g2) = (l1.norm().ln(), l2.norm().ln());
        if (g1 > 0.0) != (g2 > 0.0) {
            let w = bisect(ws[i - 1], ws[i], |w| lp.at_freq(w).norm().ln());
            crossings.push((phase_distance(lp.at_freq(w)), w));
        }
    }
    let low = kappas
        .iter()
        .copied()
        .filter(|&k| k < 1.0)
        .fold(None, |m: Option<f64>, k| Some(m.map_or(k, |m| m.max(k))));
    let high = kappas
        .iter()
        .copied()
        .filter(|&k| k > 1.0)
        .fold(None, |m: Option<f64>, k| Some(m.map_or(k, |m| m.min(k))));
    let pm = crossings
        .iter()
        .copied()
        .fold(None, |m: Option<(f64, f64)>, c| match m {
            Some(b) if b.0 <= c.0 => Some(b),
            _ => Some(c),
        });
    Ok(Margins {
        gain_low_db: low.map(|k| -20.0 * k.log10()),
        gain_high_db: high.map(|k| 20.0 * k.log10()),
        phase_deg: pm.map(|p| p.0),
        crossover_rad_per_s: pm.map(|p| p.1),
        sensitivity_peak: Some(sensitivity_peak(&lp, &ws, &ls)),
        ..none
    })
}

/// `max |1/(1 + L(jω))|`: the grid's largest, refined by golden section between its
/// neighbours.
fn sensitivity_peak(lp: &BrokenLoop, ws: &[f64], ls: &[Complex<f64>]) -> f64 {
    let s = |l: Complex<f64>| 1.0 / (Complex::new(1.0, 0.0) + l).norm();
    let (i, _) = ls
        .iter()
        .enumerate()
        .fold((0, f64::NEG_INFINITY), |(bi, bv), (i, &l)| {
            let v = s(l);
            if v > bv {
                (i, v)
            } else {
                (bi, bv)
            }
        });
    let (mut a, mut b) = (
        ws[i.saturating_sub(1)].ln(),
        ws[(i + 1).min(ws.len() - 1)].ln(),
    );
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let f = |x: f64| s(lp.at_freq(x.exp()));
    for _ in 0..80 {
        let (c, d) = (b - r * (b - a), a + r * (b - a));
        if f(c) > f(d) {
            b = d;
        } else {
            a = c;
        }
    }
    f(0.5 * (a + b)).max(s(ls[i]))
}
