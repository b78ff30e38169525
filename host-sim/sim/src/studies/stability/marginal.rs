//! The honest verdict of a closed-loop state matrix (issue 39 point 5): `stable`, `marginal`
//! or `unstable`, where a real part within the eigen-solver's error of zero is `marginal`
//! and named by the states that carry its mode, never `unstable`.
//!
//! # The tolerance
//! The QR iteration ([`super::eig`]) runs on the balanced matrix `Ã = D⁻¹·A·D`; its computed
//! eigenvalues are the exact ones of `Ã + E` with `‖E‖₂ ≤ p(n)·ε·‖Ã‖` (backward stability of
//! the Hessenberg QR algorithm: Golub & Van Loan, *Matrix Computations*, 4th ed., §7.5.6,
//! with `p(n)` a modest polynomial in `n`). A simple eigenvalue then moves by at most
//! `κ(λ)·‖E‖₂` to first order, `κ(λ) = ‖x‖·‖y‖/|yᴴ·x|` its condition number (right and left
//! eigenvectors `x`, `y` of `Ã`; ibid. §7.2.2). So the stated tolerance of a pole is
//!
//! ```text
//! tol(λ) = TOLERANCE_FACTOR · n · ε · ‖Ã‖_F · κ(λ)        (p(n) taken as 10·n)
//! ```
//!
//! and a pole with `|re λ| ≤ tol(λ)` is **marginal**: the model cannot tell its sign. A
//! pole beyond it on the right is unstable; the verdict is `unstable` if any pole is,
//! else `marginal` if any pole is, else `stable`. Zero poles (`|s| <` [`ZERO_POLE`], the
//! paper's law's free rigid-body positions) are left out as in [`super::vehicle::Verdict`].
//!
//! # The mode that causes it
//! Each marginal pole reports the states with the largest shares `|x̃_i|²/‖x̃‖²` of its right
//! eigenvector in the balanced coordinates (the scaling that evens out the units: metres,
//! metres a second, per-unit coil states), by inverse iteration on `Ã − λ·I`. A girder mode
//! with a node under every magnet is marginal on an undamped span: its eigenvector lies in
//! that mode's own displacement and velocity (`q`, `v` of the mode), none in the magnets'
//! states, since no magnet's force moves it.

use super::vehicle::ZERO_POLE;
use super::Complex;
use nalgebra::{Complex as C64, DMatrix, DVector};
use serde::Serialize;

/// `p(n) = TOLERANCE_FACTOR·n` in the backward error bound (module docs).
pub const TOLERANCE_FACTOR: f64 = 10.0;

/// Poles whose real part is within this many times `n·ε·‖Ã‖_F` of zero get a condition
/// number (the others are far from the imaginary axis for any `κ` the vehicle matrices
/// have; the factor bounds the work, one complex LU per candidate).
const CANDIDATE_FACTOR: f64 = 1e8;

/// States named per marginal pole.
const NAMED_STATES: usize = 4;

/// The three verdicts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    Stable,
    Marginal,
    Unstable,
}

impl Kind {
    /// `stable`, `marginal` or `unstable`.
    pub fn as_str(self) -> &'static str {
        match self {
            Kind::Stable => "stable",
            Kind::Marginal => "marginal",
            Kind::Unstable => "unstable",
        }
    }
}

/// One state's share of a mode's eigenvector.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Share {
    pub state: String,
    pub share: f64,
}

/// A pole within its tolerance of the imaginary axis.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MarginalPole {
    pub re: f64,
    pub im: f64,
    /// `tol(λ)` (1/s, module docs) and the condition number `κ(λ)` in it.
    pub tolerance: f64,
    pub condition: f64,
    /// The states with the largest shares of the eigenvector, largest first.
    pub states: Vec<Share>,
}

/// The honest verdict (module docs).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Honest {
    pub verdict: Kind,
    /// `TOLERANCE_FACTOR·n·ε·‖Ã‖_F` (1/s): the tolerance of a pole with `κ = 1`.
    pub tolerance_base: f64,
    /// How the tolerance is made.
    pub tolerance_rule: String,
    /// The largest real part of a pole beyond its tolerance (non-zero poles; −∞: none).
    pub max_real_part_beyond_tolerance: f64,
    /// Every marginal pole (one of each conjugate pair, `im ≥ 0`).
    pub marginal: Vec<MarginalPole>,
}

/// The balanced matrix `D⁻¹·A·D` (what [`super::eig`] iterates on).
fn balanced(a: &DMatrix<f64>) -> DMatrix<f64> {
    let mut b = a.clone();
    nalgebra::linalg::balancing::balance_parlett_reinsch(&mut b);
    b
}

/// Two steps of inverse iteration on `m − λ·I` (a complex LU) from a fixed start: the
/// eigenvector of `m` at its eigenvalue `λ` (normalised), `None` if the LU fails.
fn eigenvector(m: &DMatrix<f64>, lambda: C64<f64>, shift: f64) -> Option<DVector<C64<f64>>> {
    let n = m.nrows();
    // The shift keeps `m − λ·I` regular to the floats while λ is an eigenvalue to rounding;
    // inverse iteration converges to the nearest eigenvector all the same.
    let l = lambda + C64::new(shift, shift);
    let a = DMatrix::from_fn(n, n, |i, j| {
        C64::new(m[(i, j)], 0.0) - if i == j { l } else { C64::new(0.0, 0.0) }
    });
    let lu = a.lu();
    let mut x = DVector::from_fn(n, |i, _| C64::new(1.0 + (i % 7) as f64 * 0.1, 0.3));
    for _ in 0..3 {
        let y = lu.solve(&x)?;
        let norm = y.norm();
        if !(norm.is_finite() && norm > 0.0) {
            return None;
        }
        x = y.unscale(norm);
    }
    Some(x)
}

/// The condition number `κ(λ) = 1/|yᴴ·x|` of `m`'s eigenvalue `λ` (unit right and left
/// eigenvectors by [`eigenvector`]) and the right eigenvector.
fn condition(m: &DMatrix<f64>, lambda: C64<f64>, shift: f64) -> Option<(f64, DVector<C64<f64>>)> {
    let x = eigenvector(m, lambda, shift)?;
    let y = eigenvector(&m.transpose(), lambda.conj(), shift)?;
    Some((1.0 / y.dotc(&x).norm().max(f64::MIN_POSITIVE), x))
}

/// The honest verdict of `a` (state names `states`) with its `poles` ([`super::eigenvalues`]).
pub fn honest(a: &DMatrix<f64>, states: &[String], poles: &[Complex]) -> crate::Result<Honest> {
    let n = a.nrows();
    let b = balanced(a);
    let base = TOLERANCE_FACTOR * n as f64 * f64::EPSILON * b.norm();
    let mut marginal = Vec::new();
    let mut beyond = f64::NEG_INFINITY;
    for p in poles.iter().filter(|p| p.abs() >= ZERO_POLE) {
        if p.re.abs() > CANDIDATE_FACTOR * base {
            beyond = beyond.max(p.re);
            continue;
        }
        let shift = base.max(f64::MIN_POSITIVE);
        let Some((condition, x)) = condition(&b, C64::new(p.re, p.im), shift) else {
            return Err(crate::Error::numerical(format!(
                "the eigenvector of the pole {} {:+}j of a {n}×{n} matrix did not converge",
                p.re, p.im
            )));
        };
        let tolerance = base * condition;
        if p.re.abs() > tolerance {
            beyond = beyond.max(p.re);
            continue;
        }
        if p.im < 0.0 {
            continue;
        }
        let mut shares: Vec<(usize, f64)> = x.iter().map(|v| v.norm_sqr()).enumerate().collect();
        shares.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
        marginal.push(MarginalPole {
            re: p.re,
            im: p.im,
            tolerance,
            condition,
            states: shares
                .iter()
                .take(NAMED_STATES)
                .map(|&(i, s)| Share {
                    state: states.get(i).cloned().unwrap_or_else(|| format!("s[{i}]")),
                    share: s,
                })
                .collect(),
        });
    }
    let verdict = if beyond >= 0.0 {
        Kind::Unstable
    } else if !marginal.is_empty() {
        Kind::Marginal
    } else {
        Kind::Stable
    };
    Ok(Honest {
        verdict,
        tolerance_base: base,
        tolerance_rule: format!(
            "a pole is marginal where |re| ≤ {TOLERANCE_FACTOR}·n·ε·‖Ã‖_F·κ(λ) = {base:e}·κ(λ) 1/s \
             (n = {n}, Ã the balanced state matrix, κ the pole's condition number): the \
             backward error bound of the QR eigen-solver"
        ),
        max_real_part_beyond_tolerance: beyond,
        marginal,
    })
}

/// One line naming the marginal modes, for notes and tables.
pub fn describe(h: &Honest) -> String {
    h.marginal
        .iter()
        .map(|m| {
            let states = m
                .states
                .iter()
                .map(|s| format!("{} {:.2}", s.state, s.share))
                .collect::<Vec<_>>()
                .join(", ");
            format!(
                "{:.3e} ± {:.4}j (tolerance {:.1e}; {states})",
                m.re, m.im, m.tolerance
            )
        })
        .collect::<Vec<_>>()
        .join("; ")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(n: usize) -> Vec<String> {
        (0..n).map(|i| format!("s{i}")).collect()
    }

    /// A damped oscillator, an undamped one decoupled from it, a coupling from the undamped
    /// into the damped (block triangular: the poles are the blocks').
    fn blocks(zeta: f64) -> DMatrix<f64> {
        let (w1, w2) = (7.0, 727.5);
        let mut a = DMatrix::zeros(4, 4);
        a[(0, 1)] = 1.0;
        a[(1, 0)] = -w1 * w1;
        a[(1, 1)] = -2.0 * 0.2 * w1;
        a[(2, 3)] = 1.0;
        a[(3, 2)] = -w2 * w2;
        a[(3, 3)] = -2.0 * zeta * w2;
        a[(1, 2)] = 3.0e4;
        a
    }

    #[test]
    fn an_undamped_mode_is_marginal_and_named() {
        let a = blocks(0.0);
        let p = super::super::eigenvalues(&a).unwrap();
        let h = honest(&a, &names(4), &p).unwrap();
        assert_eq!(h.verdict, Kind::Marginal, "{h:?}");
        assert_eq!(h.marginal.len(), 1);
        let m = &h.marginal[0];
        assert!((m.im - 727.5).abs() < 1e-9, "{m:?}");
        // The undamped block's two states carry the mode.
        let top: Vec<&str> = m.states.iter().take(2).map(|s| s.state.as_str()).collect();
        assert!(top.contains(&"s2") && top.contains(&"s3"), "{m:?}");
        assert!(m.states[0].share + m.states[1].share > 0.99, "{m:?}");
    }

    #[test]
    fn a_small_but_real_growth_is_unstable_and_damping_is_stable() {
        // ζ = −1e-9: re = +7.3e-7 1/s, far beyond the tolerance (~1e-11).
        let a = blocks(-1e-9);
        let p = super::super::eigenvalues(&a).unwrap();
        let h = honest(&a, &names(4), &p).unwrap();
        assert_eq!(h.verdict, Kind::Unstable, "{h:?}");
        assert!((h.max_real_part_beyond_tolerance - 1e-9 * 727.5).abs() < 1e-12);
        let a = blocks(1e-9);
        let p = super::super::eigenvalues(&a).unwrap();
        assert_eq!(honest(&a, &names(4), &p).unwrap().verdict, Kind::Stable);
    }

    #[test]
    fn the_condition_number_is_the_closed_form() {
        // [[λ1, c], [0, λ2]]: right eigenvector (1, 0), left (1, c/(λ1 − λ2)) up to scale, so
        // κ(λ1) = √(1 + (c/(λ1 − λ2))²).
        for c in [0.0, 2.0, 50.0] {
            let m = DMatrix::from_row_slice(2, 2, &[-0.5, c, 0.0, -2.0]);
            let (k, x) = condition(&m, C64::new(-0.5, 0.0), 1e-15).unwrap();
            let r = c / (-0.5 + 2.0);
            assert!((k - (1.0 + r * r).sqrt()).abs() < 1e-9 * k, "{c}: {k}");
            assert!(
                (x[0].norm() - 1.0).abs() < 1e-12 && x[1].norm() < 1e-12,
                "{x:?}"
            );
        }
    }
}
