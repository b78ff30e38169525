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
use super::vehicle::VehiclePlant;
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
    /// `T = f·(sI − A)⁻¹·b` of the closed loop at any `s` ([`Resolvent`]), from which the
    /// broken loop's `f·(sI − A_ol)⁻¹·b = T/(1 + T)` ([`open_from_closed`]).
    response: Resolvent,
    /// The delay in series (s).
    pub delay: f64,
}

/// A loop's open response `G = f·(sI − A_ol)⁻¹·b` from its closed one `T = f·(sI − A)⁻¹·b`,
/// `A = A_ol + b·f` (Sherman–Morrison: `T = G/(1 − G)`); `None` (closed): `s` is a pole of
/// the closed loop, where `G = 1`.
fn open_from_closed(t: Option<Complex<f64>>) -> Complex<f64> {
    let one = Complex::new(1.0, 0.0);
    match t {
        None => one,
        Some(t) if t == -one => Complex::new(f64::INFINITY, 0.0),
        Some(t) => t / (one + t),
    }
}

/// `L(s) = −G(s)·e^(−s·T)` (module docs).
fn with_delay(g: Complex<f64>, s: Complex<f64>, delay: f64) -> Complex<f64> {
    if !(g.re.is_finite() && g.im.is_finite()) {
        return Complex::new(f64::INFINITY, 0.0);
    }
    -g * (-s * delay).exp()
}

impl BrokenLoop {
    /// Magnet `k` of `plant` with the delay `delay` (s, ≥ 0).
    pub fn new(plant: &VehiclePlant, k: usize, delay: f64) -> crate::Result<Self> {
        let (b, f) = super::multiloop::loop_matrices(plant, &[k])?;
        Ok(BrokenLoop {
            a_ol: &plant.a - &b * &f,
            response: Resolvent::new(&plant.a, &b, &f),
            b: b.column(0).into_owned(),
            f: f.row(0).transpose(),
            delay,
        })
    }

    /// `L(s)` (module docs).
    pub fn at(&self, s: Complex<f64>) -> Complex<f64> {
        let t = self.response.diagonal_at(s, Some(0)).map(|t| t[0]);
        with_delay(open_from_closed(t), s, self.delay)
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

/// `L(jω)` of the magnets `ks` on the grid `ws`, one LU of `jωI − A` per frequency for all
/// of them: `[loop][frequency]`.
fn grid_responses(
    plant: &VehiclePlant,
    ks: &[usize],
    delay: f64,
    ws: &[f64],
) -> crate::Result<Vec<Vec<Complex<f64>>>> {
    let (b, f) = super::multiloop::loop_matrices(plant, ks)?;
    let r = Resolvent::new(&plant.a, &b, &f);
    let mut out = vec![Vec::with_capacity(ws.len()); ks.len()];
    for &w in ws {
        let s = Complex::new(0.0, w);
        let t = r.diagonal_at(s, None);
        for (c, l) in out.iter_mut().enumerate() {
            l.push(with_delay(
                open_from_closed(t.as_ref().map(|t| t[c])),
                s,
                delay,
            ));
        }
    }
    Ok(out)
}

/// A root of `g` between `a` and `b` (a sign change, `ga = g(a)`, `gb = g(b)`), to 1e-12
/// relative: the Illinois variant of false position on `ln ω`, which keeps the bracket and
/// converges superlinearly (M. Dowell, P. Jarratt, BIT 11 (1971) 168–174).
fn bisect(a: f64, ga: f64, b: f64, gb: f64, g: impl Fn(f64) -> f64) -> f64 {
    let (mut x0, mut x1, mut g0, mut g1) = (a.ln(), b.ln(), ga, gb);
    let mut kept = 0i8;
    for _ in 0..100 {
        if x1 - x0 < 1e-12 || g0 == 0.0 || g1 == 0.0 {
            break;
        }
        let mut x = (x0 * g1 - x1 * g0) / (g1 - g0);
        if !(x > x0 && x < x1) {
            x = 0.5 * (x0 + x1);
        }
        let gx = g(x.exp());
        if (gx > 0.0) == (g1 > 0.0) {
            (x1, g1) = (x, gx);
            if kept == -1 {
                g0 *= 0.5;
            }
            kept = -1;
        } else {
            (x0, g0) = (x, gx);
            if kept == 1 {
                g1 *= 0.5;
            }
            kept = 1;
        }
    }
    if g0 == 0.0 {
        x0.exp()
    } else if g1 == 0.0 {
        x1.exp()
    } else {
        (0.5 * (x0 + x1)).exp()
    }
}

/// The wrapped distance of `∠z` from −180° (degrees, in [0, 180]).
fn phase_distance(z: Complex<f64>) -> f64 {
    let a = z.arg().to_degrees() + 180.0;
    let w = a - 360.0 * (a / 360.0).round();
    w.abs()
}

/// Magnet `k`'s margins in `plant` with `delay` in series (module docs).
pub fn margins(plant: &VehiclePlant, k: usize, delay: f64) -> crate::Result<Margins> {
    Ok(margins_of(plant, &[k], delay)?.remove(0))
}

/// The margins of the magnets `ks` in `plant` with `delay` in series (module docs), their
/// grid responses computed together ([`grid_responses`]).
pub fn margins_of(plant: &VehiclePlant, ks: &[usize], delay: f64) -> crate::Result<Vec<Margins>> {
    let loops = ks
        .iter()
        .map(|&k| BrokenLoop::new(plant, k, delay))
        .collect::<crate::Result<Vec<_>>>()?;
    // Zero poles (|s| < ZERO_POLE: the integral of a law with ki = 0, the paper's law's free
    // positions) are left out, as in the report's verdict.
    let stable = loops
        .iter()
        .map(|lp| {
            let poles = super::eigenvalues(&lp.closed_with_pade())?;
            Ok(super::vehicle::Verdict::of(poles).stable)
        })
        .collect::<crate::Result<Vec<bool>>>()?;
    let ws = super::resolvent::grid();
    let held: Vec<usize> = (0..ks.len()).filter(|&c| stable[c]).collect();
    let held_ks: Vec<usize> = held.iter().map(|&c| ks[c]).collect();
    let mut grids = grid_responses(plant, &held_ks, delay, &ws)?.into_iter();
    let mut out = Vec::with_capacity(ks.len());
    for (c, lp) in loops.iter().enumerate() {
        let none = Margins {
            magnet: plant.magnets[ks[c]].name.clone(),
            delay_s: delay,
            stable_with_delay: stable[c],
            gain_low_db: None,
            gain_high_db: None,
            phase_deg: None,
            sensitivity_peak: None,
            crossover_rad_per_s: None,
        };
        out.push(if stable[c] {
            let ls = grids
                .next()
                .ok_or_else(|| crate::Error::numerical("internal: a held loop without a grid"))?;
            from_grid(lp, &ws, &ls, none)
        } else {
            none
        });
    }
    Ok(out)
}

/// The margins of a loop stable with its delay from its responses `ls` on the grid `ws`,
/// refined through `lp` (module docs); `none` holds its name and delay.
fn from_grid(lp: &BrokenLoop, ws: &[f64], ls: &[Complex<f64>], none: Margins) -> Margins {
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
            let w = bisect(ws[i - 1], l1.im, ws[i], l2.im, |w| lp.at_freq(w).im);
            let l = lp.at_freq(w);
            if l.re < 0.0 {
                kappas.push(-1.0 / l.re);
            }
        }
        let (g1, g2) = (l1.norm().ln(), l2.norm().ln());
        if (g1 > 0.0) != (g2 > 0.0) {
            let w = bisect(ws[i - 1], g1, ws[i], g2, |w| lp.at_freq(w).norm().ln());
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
    Margins {
        gain_low_db: low.map(|k| -20.0 * k.log10()),
        gain_high_db: high.map(|k| 20.0 * k.log10()),
        phase_deg: pm.map(|p| p.0),
        crossover_rad_per_s: pm.map(|p| p.1),
        sensitivity_peak: Some(sensitivity_peak(lp, ws, ls)),
        ..none
    }
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
    // Golden section, one new point a step; 40 steps leave 2e-10 of the grid interval's
    // ln-width 0.046 (the peak's value is flat there: an error δ in ln ω costs ~δ²).
    let (mut c, mut d) = (b - r * (b - a), a + r * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..40 {
        if fc > fd {
            (b, d, fd) = (d, c, fc);
            c = b - r * (b - a);
            fc = f(c);
        } else {
            (a, c, fc) = (c, d, fd);
            d = a + r * (b - a);
            fd = f(d);
        }
    }
    fc.max(fd).max(s(ls[i]))
}

#[cfg(test)]
mod tests {
    use super::super::vehicle::MagnetLoop;
    use super::*;

    /// The root finder lands on known roots to 1e-12 relative, from either sign, in far fewer
    /// evaluations than bisection's 35 for the grid's interval.
    #[test]
    fn the_root_finder_finds_known_roots() {
        let count = std::cell::Cell::new(0);
        for (root, g) in [
            (
                3.7,
                Box::new(|w: f64| (w / 3.7).ln()) as Box<dyn Fn(f64) -> f64>,
            ),
            (2f64.sqrt(), Box::new(|w: f64| 2.0 - w * w)),
            (1.0, Box::new(|w: f64| (w - 1.0).powi(3) + 1e-3 * (w - 1.0))),
        ] {
            let (a, b) = (root / 1.02, root * 1.03);
            count.set(0);
            let w = bisect(a, g(a), b, g(b), |w| {
                count.set(count.get() + 1);
                g(w)
            });
            assert!((w / root - 1.0).abs() < 2e-12, "{w} vs {root}");
            assert!(count.get() <= 20, "{} evaluations", count.get());
        }
    }

    /// The broken loop's `L(jω)`, taken from the closed loop through Sherman–Morrison, is
    /// `−f·(jωI − A_ol)⁻¹·b·e^(−jωT)` by a dense solve of the cut plant to 1e-10 relative,
    /// on a state matrix with coupled loops (every loop closed but the one cut).
    #[test]
    fn the_broken_loop_is_the_dense_solve_of_the_cut_plant() {
        let n = 9;
        let v = |i: usize, j: usize| ((i * 5 + j * 11) as f64 * 0.61).sin();
        let a = DMatrix::from_fn(n, n, |i, j| if i == j { -3.0 - v(i, j) } else { v(i, j) });
        let mut dv = vec![0.0; n];
        for (j, d) in dv.iter_mut().enumerate() {
            *d = 0.3 * v(j, 2);
        }
        let plant = VehiclePlant {
            a,
            states: (0..n).map(|i| format!("s{i}")).collect(),
            magnets: vec![MagnetLoop {
                name: "m".into(),
                x: 4,
                tau: 0.05,
                dv,
                mass: 1.0,
                p0: 1.0,
            }],
        };
        let delay = 1e-3;
        let lp = BrokenLoop::new(&plant, 0, delay).unwrap();
        for w in [0.05, 1.0, 7.0, 300.0] {
            let s = Complex::new(0.0, w);
            let m = DMatrix::from_fn(n, n, |i, j| {
                let d = if i == j { s } else { Complex::new(0.0, 0.0) };
                d - lp.a_ol[(i, j)]
            });
            let x = m.lu().solve(&lp.b.map(|v| Complex::new(v, 0.0))).unwrap();
            let g: Complex<f64> = (0..n).map(|i| x[i] * lp.f[i]).sum();
            let want = -g * (-s * delay).exp();
            let got = lp.at_freq(w);
            assert!(
                (got - want).norm() <= 1e-10 * want.norm(),
                "{w}: {got} vs {want}"
            );
        }
    }
}
