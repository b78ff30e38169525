//! Eigenvalues of a general real matrix: balancing, Hessenberg reduction and the shifted
//! double-step QR iteration with exceptional shifts (the EISPACK `hqr` algorithm, as in
//! Press et al., *Numerical Recipes*, 3rd ed., §11.6).
//!
//! Why not nalgebra's `complex_eigenvalues`: its QR iteration has no exceptional shifts and
//! no iteration limit, and it spins forever on some of the vehicle matrices (`super::vehicle`,
//! e.g. the 54-state EMS vehicle under the gap loop, whose guidance magnets repeat the same
//! eigenvalues four times). `Schur::try_new` with a limit returns `None` on the same matrices.
//! The exceptional shifts (after 10, 20, … stalled iterations) break such cycles.

use super::Complex;
use nalgebra::DMatrix;

/// Iterations allowed per eigenvalue (exceptional shifts at every tenth).
const MAX_ITERATIONS: usize = 60;

/// The largest entry magnitude accepted. Balancing (nalgebra's Parlett–Reinsch) squares and
/// sums a row's entries and then halves or doubles the norms until they meet: a norm that
/// overflowed to ∞ never meets, and the loop never ends (`stability --set
/// vehicle.body_mass_t=1e200`). Below 1e100 the sums of squares of any matrix up to 10⁶² rows
/// stay finite, and so does every norm the balancing reaches.
pub const MAX_ENTRY: f64 = 1e100;

/// The eigenvalues of `a` (square, entries finite and within ±[`MAX_ENTRY`]), unsorted; an
/// error naming the matrix size if the iteration fails to converge or an entry is outside.
pub fn eigenvalues(a: &DMatrix<f64>) -> crate::Result<Vec<Complex>> {
    let n = a.nrows();
    if a.ncols() != n {
        return Err(crate::Error::numerical(format!(
            "eigenvalues of a non-square {}×{} matrix",
            n,
            a.ncols()
        )));
    }
    if let Some(v) = a.iter().find(|v| v.is_nan() || v.abs() > MAX_ENTRY) {
        return Err(crate::Error::numerical(format!(
            "a {n}×{n} state matrix holds the entry {v:e}, beyond ±{MAX_ENTRY:e} (a value of the case is too extreme for the linearised analysis)"
        )));
    }
    if n == 0 {
        return Ok(Vec::new());
    }
    // First balanced (a diagonal similarity: the eigenvalues are unchanged, the norms evened
    // out), then, should that iteration stall, on the matrix as given: each is a Hessenberg
    // reduction (orthogonal similarity) and the QR iteration.
    let mut balanced = a.clone();
    nalgebra::linalg::balancing::balance_parlett_reinsch(&mut balanced);
    [balanced, a.clone()]
        .into_iter()
        .find_map(|m| hqr(nalgebra::linalg::Hessenberg::new(m).h()))
        .ok_or_else(|| {
            crate::Error::numerical(format!(
                "the eigenvalues of a {n}×{n} matrix did not converge"
            ))
        })
}

fn sign(a: f64, b: f64) -> f64 {
    if b >= 0.0 {
        a.abs()
    } else {
        -a.abs()
    }
}

/// All eigenvalues of the upper Hessenberg matrix `a` (destroyed), or `None` if some
/// eigenvalue needs more than [`MAX_ITERATIONS`] iterations.
#[cfg(test)]
pub fn hqr_pub(a: DMatrix<f64>) -> Option<Vec<Complex>> {
    hqr(a)
}

fn hqr(mut a: DMatrix<f64>) -> Option<Vec<Complex>> {
    let n = a.nrows();
    let mut w = vec![Complex { re: 0.0, im: 0.0 }; n];
    let mut anorm = 0.0;
    for i in 0..n {
        for j in i.saturating_sub(1)..n {
            anorm += a[(i, j)].abs();
        }
    }
    let mut nn = n as isize - 1;
    let mut t = 0.0;
    while nn >= 0 {
        let mut its = 0;
        loop {
            let nu = nn as usize;
            // Look for a single small subdiagonal element.
            let mut l = nu;
            while l > 0 {
                let mut s = a[(l - 1, l - 1)].abs() + a[(l, l)].abs();
                if s == 0.0 {
                    s = anorm;
                }
                if a[(l, l - 1)].abs() + s == s {
                    a[(l, l - 1)] = 0.0;
                    break;
                }
                l -= 1;
            }
            let mut x = a[(nu, nu)];
            if l == nu {
                // One root.
                w[nu] = Complex { re: x + t, im: 0.0 };
                nn -= 1;
                break;
            }
            let mut y = a[(nu - 1, nu - 1)];
            let mut ww = a[(nu, nu - 1)] * a[(nu - 1, nu)];
            if l == nu - 1 {
                // Two roots.
                let p = 0.5 * (y - x);
                let q = p * p + ww;
                let mut z = q.abs().sqrt();
                x += t;
                if q >= 0.0 {
                    z = p + sign(z, p);
                    let r1 = x + z;
                    let r2 = if z != 0.0 { x - ww / z } else { r1 };
                    w[nu - 1] = Complex { re: r1, im: 0.0 };
                    w[nu] = Complex { re: r2, im: 0.0 };
                } else {
                    w[nu] = Complex { re: x + p, im: -z };
                    w[nu - 1] = Complex { re: x + p, im: z };
                }
                nn -= 2;
                break;
            }
            // No root yet: a double QR step on rows and columns l..=nu.
            if its == MAX_ITERATIONS {
                return None;
            }
            if its > 0 && its % 10 == 0 {
                // Exceptional shift.
                t += x;
                for i in 0..=nu {
                    a[(i, i)] -= x;
                }
                let s = a[(nu, nu - 1)].abs() + a[(nu - 1, nu - 2)].abs();
                x = 0.75 * s;
                y = x;
                ww = -0.4375 * s * s;
            }
            its += 1;
            // Form the shift and look for two consecutive small subdiagonal elements.
            let (mut p, mut q, mut r);
            let mut m = nu - 2;
            loop {
                let z = a[(m, m)];
                let rr = x - z;
                let ss = y - z;
                p = (rr * ss - ww) / a[(m + 1, m)] + a[(m, m + 1)];
                q = a[(m + 1, m + 1)] - z - rr - ss;
                r = a[(m + 2, m + 1)];
                let s = p.abs() + q.abs() + r.abs();
                p /= s;
                q /= s;
                r /= s;
                if m == l {
                    break;
                }
                let u = a[(m, m - 1)].abs() * (q.abs() + r.abs());
                let v = p.abs() * (a[(m - 1, m - 1)].abs() + z.abs() + a[(m + 1, m + 1)].abs());
                if u + v == v {
                    break;
                }
                m -= 1;
            }
            for i in m..nu - 1 {
                a[(i + 2, i)] = 0.0;
                if i != m {
                    a[(i + 2, i - 1)] = 0.0;
                }
            }
            let mut xk = 0.0;
            for k in m..nu {
                if k != m {
                    p = a[(k, k - 1)];
                    q = a[(k + 1, k - 1)];
                    r = if k + 1 != nu { a[(k + 2, k - 1)] } else { 0.0 };
                    xk = p.abs() + q.abs() + r.abs();
                    if xk != 0.0 {
                        p /= xk;
                        q /= xk;
                        r /= xk;
                    }
                }
                let s = sign((p * p + q * q + r * r).sqrt(), p);
                if s == 0.0 {
                    continue;
                }
                if k == m {
                    if l != m {
                        a[(k, k - 1)] = -a[(k, k - 1)];
                    }
                } else {
                    a[(k, k - 1)] = -s * xk;
                }
                p += s;
                let (x1, y1, z1) = (p / s, q / s, r / s);
                q /= p;
                r /= p;
                for j in k..=nu {
                    let mut pp = a[(k, j)] + q * a[(k + 1, j)];
                    if k + 1 != nu {
                        pp += r * a[(k + 2, j)];
                        a[(k + 2, j)] -= pp * z1;
                    }
                    a[(k + 1, j)] -= pp * y1;
                    a[(k, j)] -= pp * x1;
                }
                let mmin = nu.min(k + 3);
                for i in l..=mmin {
                    let mut pp = x1 * a[(i, k)] + y1 * a[(i, k + 1)];
                    if k + 1 != nu {
                        pp += z1 * a[(i, k + 2)];
                        a[(i, k + 2)] -= pp * r;
                    }
                    a[(i, k + 1)] -= pp * q;
                    a[(i, k)] -= pp;
                }
            }
            if l + 1 >= nu {
                break;
            }
        }
    }
    Some(w)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Smallest singular value of `A − λI` relative to ‖A‖: ~1e-16 for an exact eigenvalue.
    fn residual(a: &DMatrix<f64>, l: Complex) -> f64 {
        let n = a.nrows();
        let lam = nalgebra::Complex::new(l.re, l.im);
        let m = DMatrix::from_fn(n, n, |i, j| {
            nalgebra::Complex::new(a[(i, j)], 0.0) - if i == j { lam } else { 0.0.into() }
        });
        let sv = m.singular_values();
        sv.min() / a.norm().max(1.0)
    }

    #[test]
    fn companion_matrix_gives_its_polynomial_roots() {
        // (s + 1)(s + 2)(s + 3)(s² + 2s + 5): roots −1, −2, −3, −1 ± 2j.
        let roots = [
            nalgebra::Complex::new(-1.0, 0.0),
            nalgebra::Complex::new(-2.0, 0.0),
            nalgebra::Complex::new(-3.0, 0.0),
            nalgebra::Complex::new(-1.0, 2.0),
            nalgebra::Complex::new(-1.0, -2.0),
        ];
        // Coefficients of Π(s − r), highest first.
        let mut c = vec![nalgebra::Complex::new(1.0, 0.0)];
        for r in roots {
            let mut next = vec![nalgebra::Complex::new(0.0, 0.0); c.len() + 1];
            for (i, ci) in c.iter().enumerate() {
                next[i] += ci;
                next[i + 1] -= ci * r;
            }
            c = next;
        }
        let n = roots.len();
        let a = DMatrix::from_fn(n, n, |i, j| {
            if i == 0 {
                -c[j + 1].re
            } else if i == j + 1 {
                1.0
            } else {
                0.0
            }
        });
        let got = eigenvalues(&a).unwrap();
        assert_eq!(got.len(), n);
        // Each root matched by a distinct eigenvalue (a multiset comparison).
        let mut used = vec![false; n];
        for r in roots {
            let (k, d) = got
                .iter()
                .enumerate()
                .filter(|(k, _)| !used[*k])
                .map(|(k, g)| (k, (g.re - r.re).abs() + (g.im - r.im).abs()))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .unwrap();
            used[k] = true;
            assert!(d < 1e-9, "{r:?}: {got:?}");
        }
    }

    #[test]
    fn repeated_pairs_and_zeros_converge() {
        // Four copies of the paper's g-loop block, five zero rows and a coupling: the shape
        // nalgebra's iteration stalls on. Eigenvalues: the block's pair four times, zeros.
        let (tau, p, ki) = (0.398, 2.0, 600.0);
        let n = 13;
        let mut a = DMatrix::zeros(n, n);
        for b in 0..4 {
            let i = 2 * b;
            a[(i, i)] = -p / tau;
            a[(i, i + 1)] = 1.0 / tau;
            a[(i + 1, i)] = -ki;
            // Couple into the zero block (does not change the eigenvalues: block triangular).
            a[(8 + b, i)] = 3.0;
        }
        let ev = eigenvalues(&a).unwrap();
        assert_eq!(ev.len(), n);
        let pair = Complex {
            re: -p / (2.0 * tau),
            im: (ki / tau - (p / (2.0 * tau)).powi(2)).sqrt(),
        };
        let zeros = ev.iter().filter(|e| e.abs() < 1e-9).count();
        assert_eq!(zeros, 5, "{ev:?}");
        for e in ev.iter().filter(|e| e.abs() >= 1e-9) {
            assert!(
                (e.re - pair.re).abs() < 1e-6 && (e.im.abs() - pair.im).abs() < 1e-6,
                "{e:?}"
            );
        }
    }

    #[test]
    fn pseudo_random_matrices_satisfy_trace_and_residual() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut rnd = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        for n in [3, 7, 20, 41] {
            let a = DMatrix::from_fn(n, n, |_, _| rnd() * 10f64.powf(2.0 * rnd()));
            let ev = eigenvalues(&a).unwrap();
            let tr: f64 = ev.iter().map(|e| e.re).sum();
            let im: f64 = ev.iter().map(|e| e.im).sum();
            assert!((tr - a.trace()).abs() < 1e-9 * a.norm(), "n={n}");
            assert!(im.abs() < 1e-9 * a.norm(), "n={n}");
            for e in &ev {
                assert!(residual(&a, *e) < 1e-12, "n={n} {e:?}");
            }
        }
    }

    #[test]
    fn rejects_non_finite_and_extreme_entries() {
        for v in [f64::NAN, f64::INFINITY, -1e200] {
            let mut a = DMatrix::from_diagonal_element(3, 3, 1.0);
            a[(1, 2)] = v;
            let e = eigenvalues(&a).unwrap_err().to_string();
            assert!(e.contains("beyond ±1e100"), "{v}: {e}");
        }
    }

    /// 1e200 entries: the sums of squares in the balancing overflow, and its loop never
    /// ended before the range check.
    #[test]
    fn an_extreme_matrix_is_an_error_not_a_hang() {
        let a = DMatrix::from_fn(
            4,
            4,
            |i, j| if i == j { 1e200 } else { 1.0 + (i + j) as f64 },
        );
        assert!(eigenvalues(&a).is_err());
    }
}
