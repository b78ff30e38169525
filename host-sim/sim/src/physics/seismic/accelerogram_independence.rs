//! The records of different seeds and components are independent draws: the correlation
//! coefficient between any two of the 150 components of seeds 1…50 lies within the bound that
//! independent records of these spectra and envelopes obey.
//!
//! The bound: for two independent zero-mean records x = e·u, y = e·v (one envelope e over
//! stationary u, v) the sum Σ_t x_t y_t has variance Σ_t Σ_s E[x_t x_s] E[y_t y_s]
//! (Bartlett), which is Σ_t e_t⁴ · Σ_τ ρ_u(τ) ρ_v(τ) times the variances, so
//! σ_r² = (Σ e⁴ / (Σ e²)²) · Σ_{|τ| ≤ L} ρ_x(τ) ρ_y(τ), the correlations ρ(τ) = R(τ)/R(0)
//! estimated from the records' own autocovariances R_x(τ) = Σ_t x_t x_{t+τ}, and
//! Σ e⁴ / (Σ e²)² = 1/N_eff the envelope's (1/N for a constant one). With
//! 11 175 pairs the largest |r|/σ_r of independent Gaussian pairs is about 4.3; the test asks
//! for at most 5.5 (a chance of 4·10⁻⁴ for the whole set), and a swapped or scaled copy gives
//! |r| = 1, tens of σ_r.

use super::*;

/// Lags of the autocovariance the bound sums: 2 s at 5 ms, beyond the correlation time of
/// the medium ground's filters (1/(ζ_g ω_g) = 0.25 s, 1/(ζ_f ω_f) = 1.7 s).
const LAGS: usize = 400;

fn spec(seed: u64) -> Spec {
    Spec {
        seed,
        ..super::tests::spec()
    }
}

/// R(τ) for τ = 0 … LAGS, directly.
fn autocovariance(a: &[f64]) -> Vec<f64> {
    (0..=LAGS)
        .map(|tau| a.iter().zip(&a[tau..]).map(|(p, q)| p * q).sum())
        .collect()
}

#[test]
fn components_of_seeds_1_to_50_are_uncorrelated_within_the_bound_of_independent_records() {
    let records: Vec<(String, Vec<f64>)> = (1..=50)
        .flat_map(|seed| {
            let r = synthesize(&spec(seed), &flag).unwrap();
            [("x", r.x), ("y", r.y), ("z", r.z)].map(|(c, a)| (format!("seed {seed} {c}"), a))
        })
        .collect();
    let cov: Vec<Vec<f64>> = records.iter().map(|(_, a)| autocovariance(a)).collect();
    let s = spec(1);
    let n = records[0].1.len();
    let e = tapered_envelope(&s.envelope, n, s.dt_s);
    let (e2, e4): (f64, f64) = e
        .iter()
        .fold((0.0, 0.0), |(a, b), v| (a + v * v, b + v.powi(4)));
    let inv_n_eff = e4 / (e2 * e2);
    let (mut worst, mut pair) = (0.0_f64, String::new());
    for i in 0..records.len() {
        for j in i + 1..records.len() {
            let (x, y) = (&records[i].1, &records[j].1);
            let r: f64 =
                x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>() / (cov[i][0] * cov[j][0]).sqrt();
            let rho = |k: usize, t: usize| cov[k][t] / cov[k][0];
            let var =
                inv_n_eff * (1.0 + 2.0 * (1..=LAGS).map(|t| rho(i, t) * rho(j, t)).sum::<f64>());
            let z = r.abs() / var.sqrt();
            if z > worst {
                worst = z;
                pair = format!(
                    "{} and {}: r = {r:.4}, σ_r = {:.4}",
                    records[i].0,
                    records[j].0,
                    var.sqrt()
                );
            }
        }
    }
    eprintln!("largest |r|/σ_r over 11 175 pairs: {worst:.2} ({pair})");
    assert!(worst < 5.5, "{worst:.2} σ_r: {pair}");
}
