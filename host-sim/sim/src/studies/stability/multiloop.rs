//! The multi-loop disk margin of a vehicle (issue 39 point 2): every magnet's loop broken at
//! its coil voltage at once, a simultaneous, independent gain and phase variation at every
//! input (D.J. Seiler, A. Packard, P. Gahinet, "An introduction to disk margins", *IEEE
//! Control Systems Magazine* 40(5) (2020) 78–95).
//!
//! # The loop at the inputs
//! With every loop cut at its coil voltage the plant is `A_ol = A − B·F` (`B` the magnets'
//! input columns `e_x/τ`, `F` their voltage rows `Δv`, [`super::vehicle::MagnetLoop`]), and
//! the loop at the inputs, negative feedback, the delay `T` in every channel:
//! ```text
//! L(s) = −F·(s·I − A_ol)⁻¹·B·e^(−s·T),   S = (I + L)⁻¹
//! ```
//!
//! # The margin
//! Each input `u_k` is multiplied by `f_k = (1 + δ_k/2)/(1 − δ_k/2)` with complex `|δ_k| < α`
//! (the symmetric disk, skew σ = 0). The loop stays stable for every such set iff
//! `α < 1/sup_ω μ_Δ(S(jω) − I/2)`, `Δ` diagonal complex (Seiler et al. 2020, eq. 20 with
//! σ = 0). For one loop `μ = |S − 1/2|` and `α = 2/max_ω |S − T|` (`S − T = 2S − 1`).
//!
//! `μ` is bounded above by `min_D σ̄(D·M·D⁻¹)`, `D` positive diagonal; any `D` gives a
//! bound. Here `D` is first Osborne's scaling (the one that minimises the Frobenius norm of the
//! off-diagonal part), then, at the frequencies where that bound could be the largest,
//! descent on `log d` (along the gradient of `σ̄`, which is convex in `log d`, from its top
//! singular pair) lowers `σ̄` further; the value is always a full SVD's. So the
//! reported `μ` is an upper bound and **α a lower bound** of the true margin, on the grid of
//! `ω` (ω = 0 where `L(0)` is finite, then 100 points a decade from 1e-2 to 1e6 rad/s, the
//! loop-at-a-time margins' grid) refined by golden section about the largest grid value.
//!
//! Equivalent margins of the disk (σ = 0): gain `±20·log10((2 + α)/(2 − α))` dB (the gain may
//! fall by the same factor it may rise), phase `±2·atan(α/2)` degrees. Whether the nominal
//! loop with the delay is stable is decided with the delay as its (2, 2) Padé approximant in
//! every channel, as the loop-at-a-time margins do; if not, the margin is null.

use super::resolvent::Resolvent;
use super::vehicle::VehiclePlant;
use nalgebra::{Complex, DMatrix, DVector};
use serde::Serialize;

/// The multi-loop disk margin as reported (module docs).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DiskMargin {
    /// The loops broken at once.
    pub loops: Vec<String>,
    /// The delay in series in every loop (s).
    pub delay_s: f64,
    /// The nominal loop with the delays (Padé (2, 2)) is stable.
    pub stable_with_delay: bool,
    /// The symmetric disk margin α (a lower bound) and its equivalent gain (±dB) and phase
    /// (±deg) margins; null where the nominal loop is unstable (the gain also where α ≥ 2:
    /// every gain increase is then admitted).
    pub alpha: Option<f64>,
    pub gain_db: Option<f64>,
    pub phase_deg: Option<f64>,
    /// The μ upper bound's peak and its frequency (rad/s).
    pub mu_peak: Option<f64>,
    pub peak_rad_per_s: Option<f64>,
    /// How α is computed.
    pub method: &'static str,
}

const METHOD: &str = "α = 1/sup_ω μ(S − I/2) at the coil-voltage inputs (Seiler, Packard & \
    Gahinet 2020); μ bounded above by σ̄(D(S − I/2)D⁻¹), D Osborne's scaling then gradient \
    descent, at ω = 0 (where L(0) is finite) and 100 points a decade from 1e-2 to 1e6 rad/s, with \
    golden-section refinement of the peak: α is a lower bound";

/// The system cut at every input: `ṡ = A_ol·s + B·u`, `Δv = F·s`, delay `T` (module docs).
#[derive(Clone, Debug)]
pub struct Cut {
    pub a_ol: DMatrix<f64>,
    /// `n × m` and `m × n`.
    pub b: DMatrix<f64>,
    pub f: DMatrix<f64>,
    pub delay: f64,
}

impl Cut {
    /// Every magnet loop of `plant` cut at its coil voltage, `delay` (s) in each.
    pub fn of(plant: &VehiclePlant, delay: f64) -> crate::Result<Self> {
        let all: Vec<usize> = (0..plant.magnets.len()).collect();
        let (b, f) = loop_matrices(plant, &all)?;
        Ok(Cut {
            a_ol: &plant.a - &b * &f,
            b,
            f,
            delay,
        })
    }

    fn inputs(&self) -> usize {
        self.b.ncols()
    }

    /// The reduction that evaluates `L(jω)` ([`Resolvent`]), once per cut.
    pub fn resolvent(&self) -> Resolvent {
        Resolvent::new(&self.a_ol, &self.b, &self.f)
    }

    /// `L(jω)` (m × m).
    pub fn loop_at(&self, w: f64) -> DMatrix<Complex<f64>> {
        self.loop_with(&self.resolvent(), w)
    }

    /// `L(jω)` through `r`, this cut's [`Self::resolvent`].
    fn loop_with(&self, r: &Resolvent, w: f64) -> DMatrix<Complex<f64>> {
        let k = self.inputs();
        let s = Complex::new(0.0, w);
        match r.at(s) {
            Some(x) => x * (-(-s * self.delay).exp()),
            None => DMatrix::from_element(k, k, Complex::new(f64::INFINITY, 0.0)),
        }
    }

    /// `S(jω) − I/2`.
    #[cfg(test)]
    fn m_at(&self, w: f64) -> Option<DMatrix<Complex<f64>>> {
        self.m_with(&self.resolvent(), w)
    }

    /// `S(jω) − I/2` through `r`, this cut's [`Self::resolvent`].
    fn m_with(&self, r: &Resolvent, w: f64) -> Option<DMatrix<Complex<f64>>> {
        let k = self.inputs();
        let i = DMatrix::<Complex<f64>>::identity(k, k);
        let l = self.loop_with(r, w);
        if l.iter().any(|v| !(v.re.is_finite() && v.im.is_finite())) {
            return None;
        }
        let s = (&i + l).try_inverse()?;
        Some(s - i.scale(0.5)).filter(|m| m.iter().all(|v| v.re.is_finite() && v.im.is_finite()))
    }

    /// The closed loop with every delay as its (2, 2) Padé approximant: the state matrix.
    pub fn closed_with_pade(&self) -> DMatrix<f64> {
        let n = self.a_ol.nrows();
        let k = self.inputs();
        let bf = &self.b * &self.f;
        if self.delay <= 0.0 {
            return &self.a_ol + bf;
        }
        // Per channel e^(−sT) ≈ 1 + C_d(sI − A_d)⁻¹B_d: A_d = [[0, 1], [−12/T², −6/T]],
        // B_d = [0, 1]ᵀ, C_d = [0, −12/T], D_d = 1; the input is Δv_k = F_k·s, the output
        // enters through B_k.
        let t = self.delay;
        let mut a = DMatrix::zeros(n + 2 * k, n + 2 * k);
        a.view_mut((0, 0), (n, n)).copy_from(&(&self.a_ol + bf));
        for c in 0..k {
            let (p, q) = (n + 2 * c, n + 2 * c + 1);
            for i in 0..n {
                a[(i, q)] = self.b[(i, c)] * (-12.0 / t);
            }
            a[(p, q)] = 1.0;
            a[(q, p)] = -12.0 / (t * t);
            a[(q, q)] = -6.0 / t;
            for j in 0..n {
                a[(q, j)] = self.f[(c, j)];
            }
        }
        a
    }
}

/// The loops `ks` of `plant` where they close: `B` (n × len) of the input columns `e_x/τ` and
/// `F` (len × n) of the law's voltage rows `Δv` ([`super::vehicle::MagnetLoop`]).
pub(super) fn loop_matrices(
    plant: &VehiclePlant,
    ks: &[usize],
) -> crate::Result<(DMatrix<f64>, DMatrix<f64>)> {
    let n = plant.a.nrows();
    let (mut b, mut f) = (DMatrix::zeros(n, ks.len()), DMatrix::zeros(ks.len(), n));
    for (c, &k) in ks.iter().enumerate() {
        let l = plant
            .magnets
            .get(k)
            .ok_or_else(|| crate::Error::numerical("internal: no such magnet"))?;
        if l.dv.len() != n {
            return Err(crate::Error::numerical(
                "internal: a magnet's voltage row does not span the state",
            ));
        }
        b[(l.x, c)] = 1.0 / l.tau;
        for (j, v) in l.dv.iter().enumerate() {
            f[(c, j)] = *v;
        }
    }
    Ok((b, f))
}

/// `σ̄(D·M·D⁻¹)`, `D = diag(e^d)`.
fn scaled_norm(m: &DMatrix<Complex<f64>>, d: &[f64]) -> f64 {
    let n = m.nrows();
    let s = DMatrix::from_fn(n, n, |i, j| m[(i, j)] * (d[i] - d[j]).exp());
    s.singular_values().max()
}

/// The largest `|log d_k|` of a scaling (a triangular `M` drives `d` to its bounds: its `μ`
/// is the largest diagonal entry, reached as the off-diagonal part is scaled away).
const D_BOUND: f64 = 35.0;

/// Osborne's iteration on `|M|`: `d` that evens each off-diagonal row and column norm.
fn osborne(m: &DMatrix<Complex<f64>>) -> Vec<f64> {
    let n = m.nrows();
    let mut d = vec![0.0_f64; n];
    for _ in 0..200 {
        let mut moved = 0.0_f64;
        for i in 0..n {
            let (mut r, mut c) = (0.0_f64, 0.0_f64);
            for j in (0..n).filter(|&j| j != i) {
                r += m[(i, j)].norm_sqr() * (2.0 * (d[i] - d[j])).exp();
                c += m[(j, i)].norm_sqr() * (2.0 * (d[j] - d[i])).exp();
            }
            if r == 0.0 && c == 0.0 {
                continue;
            }
            // Scaling d_i by f multiplies row i by f and column i by 1/f: f² = c/r.
            let step = if r == 0.0 {
                3.0
            } else if c == 0.0 {
                -3.0
            } else {
                (0.25 * (c / r).ln()).clamp(-3.0, 3.0)
            };
            let new = (d[i] + step).clamp(-D_BOUND, D_BOUND);
            moved = moved.max((new - d[i]).abs());
            d[i] = new;
        }
        if moved < 1e-6 {
            break;
        }
    }
    d
}

/// Golden-section minimum of `g` on `[a, b]` (60 steps).
fn golden(mut a: f64, mut b: f64, g: impl Fn(f64) -> f64) -> (f64, f64) {
    let r = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..60 {
        let (c, e) = (b - r * (b - a), a + r * (b - a));
        if g(c) < g(e) {
            b = e;
        } else {
            a = c;
        }
    }
    let x = 0.5 * (a + b);
    (x, g(x))
}

/// `min_D σ̄(D·M·D⁻¹)` as far as Osborne's scaling and (with `refine`) descent get: an upper
/// bound of `μ_Δ(M)` for diagonal complex `Δ` (every `D` gives one; the value is `σ̄` of the
/// final scaling by a full SVD).
fn mu_upper(m: &DMatrix<Complex<f64>>, refine: bool) -> f64 {
    let n = m.nrows();
    if n == 1 {
        return m[(0, 0)].norm();
    }
    let mut d = osborne(m);
    let best = scaled_norm(m, &d);
    if !refine {
        return best;
    }
    descend(m, &mut d);
    best.min(scaled_norm(m, &d))
}

/// The top singular triplet `(σ̄, u, v)` of `D·M·D⁻¹` by power iteration from `v`
/// (a lower estimate of `σ̄`: a guide for [`descend`], never the bound).
fn top_triplet(
    m: &DMatrix<Complex<f64>>,
    d: &[f64],
    mut v: DVector<Complex<f64>>,
) -> (f64, DVector<Complex<f64>>, DVector<Complex<f64>>) {
    let n = m.nrows();
    let s = DMatrix::from_fn(n, n, |i, j| m[(i, j)] * (d[i] - d[j]).exp());
    let mut sigma = 0.0;
    let mut u = DVector::zeros(n);
    for _ in 0..200 {
        let y = &s * &v;
        let ny = y.norm();
        if ny == 0.0 {
            return (0.0, u, v);
        }
        u = y / Complex::new(ny, 0.0);
        let z = s.adjoint() * &u;
        let nz = z.norm();
        v = z / Complex::new(nz, 0.0);
        let done = (nz - sigma).abs() <= 1e-12 * nz;
        sigma = nz;
        if done {
            break;
        }
    }
    (sigma, u, v)
}

/// Descent on `log d` for `σ̄(D·M·D⁻¹)` from `d` (convex in `log d`): the gradient
/// `∂σ̄/∂d_i = σ̄·(|u_i|² − |v_i|²)` of the top singular pair ([`top_triplet`]), steps grown
/// on success and halved on failure, `d` kept within ±[`D_BOUND`].
fn descend(m: &DMatrix<Complex<f64>>, d: &mut [f64]) {
    let n = m.nrows();
    let start = DVector::from_element(n, Complex::new(1.0 / (n as f64).sqrt(), 0.0));
    let (mut sigma, mut u, mut v) = top_triplet(m, d, start);
    let mut step = 1.0;
    for _ in 0..200 {
        if sigma == 0.0 {
            return;
        }
        let g: Vec<f64> = (0..n).map(|i| u[i].norm_sqr() - v[i].norm_sqr()).collect();
        let gn = g.iter().map(|x| x * x).sum::<f64>().sqrt();
        if gn < 1e-9 {
            return;
        }
        let trial: Vec<f64> = (0..n)
            .map(|i| (d[i] - step * g[i] / gn).clamp(-D_BOUND, D_BOUND))
            .collect();
        let (s2, u2, v2) = top_triplet(m, &trial, v.clone());
        if s2 < sigma * (1.0 - 1e-12) {
            d.copy_from_slice(&trial);
            (sigma, u, v) = (s2, u2, v2);
            step *= 2.0;
        } else {
            step *= 0.5;
            if step < 1e-8 {
                return;
            }
        }
    }
}

/// The frequency grid (rad/s): ω = 0, then the loop-at-a-time margins' grid.
fn grid() -> Vec<f64> {
    std::iter::once(0.0)
        .chain(super::resolvent::grid())
        .collect()
}

/// The disk margin of `cut`, its loops named `loops` (module docs).
pub fn disk_margin(cut: &Cut, loops: Vec<String>) -> crate::Result<DiskMargin> {
    let poles = super::eigenvalues(&cut.closed_with_pade())?;
    let stable = super::vehicle::Verdict::of(poles).stable;
    let mut out = DiskMargin {
        loops,
        delay_s: cut.delay,
        stable_with_delay: stable,
        alpha: None,
        gain_db: None,
        phase_deg: None,
        mu_peak: None,
        peak_rad_per_s: None,
        method: METHOD,
    };
    if !stable {
        return Ok(out);
    }
    let ws = grid();
    let r = cut.resolvent();
    // ω = 0 counts where L(0) is finite (no free integrator in the cut plant); elsewhere a
    // singular `jω·I − A_ol` is no bound.
    let mu = |w: f64, refine: bool| match cut.m_with(&r, w) {
        Some(m) => mu_upper(&m, refine),
        None if w == 0.0 => f64::NEG_INFINITY,
        None => f64::INFINITY,
    };
    // Osborne's bound everywhere; refined where it exceeds the best refined bound so far.
    let coarse: Vec<f64> = ws.iter().map(|&w| mu(w, false)).collect();
    let mut order: Vec<usize> = (0..ws.len()).collect();
    order.sort_by(|&a, &b| coarse[b].total_cmp(&coarse[a]));
    let mut bound = coarse.clone();
    let mut peak = (f64::NEG_INFINITY, 0usize);
    for &i in &order {
        if coarse[i] <= peak.0 {
            break;
        }
        bound[i] = mu(ws[i], true);
        if bound[i] > peak.0 {
            peak = (bound[i], i);
        }
    }
    let (mut mu_peak, mut w_peak) = (peak.0, ws[peak.1]);
    // Golden section on −μ about the grid's peak (between its neighbours, ω > 0).
    let i = peak.1;
    if i > 0 {
        let (a, b) = (ws[(i - 1).max(1)].ln(), ws[(i + 1).min(ws.len() - 1)].ln());
        let (x, v) = golden(a, b, |x| -mu(x.exp(), true));
        if -v > mu_peak {
            (mu_peak, w_peak) = (-v, x.exp());
        }
    }
    let alpha = 1.0 / mu_peak;
    out.alpha = Some(alpha);
    out.mu_peak = Some(mu_peak);
    out.peak_rad_per_s = Some(w_peak);
    // The disk's equivalent margins; α ≥ 2 admits any gain increase.
    out.gain_db = Some(if alpha < 2.0 {
        20.0 * ((2.0 + alpha) / (2.0 - alpha)).log10()
    } else {
        f64::INFINITY
    })
    .filter(|g| g.is_finite());
    out.phase_deg = Some((2.0 * (alpha / 2.0).atan()).to_degrees());
    Ok(out)
}

/// [`disk_margin`] of every magnet loop of `plant` with `delay` (s) in each.
pub fn vehicle_disk_margin(plant: &VehiclePlant, delay: f64) -> crate::Result<DiskMargin> {
    let names = plant.magnets.iter().map(|m| m.name.clone()).collect();
    disk_margin(&Cut::of(plant, delay)?, names)
}

#[cfg(test)]
mod tests;
