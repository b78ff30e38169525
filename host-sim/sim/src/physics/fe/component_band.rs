//! [`ComponentBand`]: LLᵀ of a symmetric positive definite matrix whose graph splits into
//! decoupled components, each factorised as a narrow dense band: the span's effective
//! stiffness in the time loop.
//!
//! Why: a straight span's axial, torsion, lateral-bending and vertical-bending DOFs are
//! uncoupled, and within each family the node-by-node numbering is a band of half-width 1
//! (one DOF a node) or 3 (two). Factorised that way, a substitution is a run of short
//! fixed-length dot products over contiguous memory, with no index loads: on the §4.2 span
//! about a third of the instructions of the same substitution through a sparse (AMD)
//! factor's column lists (docs/performance.md). The factor is a different LLᵀ from faer's
//! (another ordering), so the solves agree with faer's to round-off, not bit for bit (test
//! `solve_matches_faer`).
//!
//! Layout: the components' rows follow one another, each storing exactly `B` coefficients
//! for each substitution (zeros beyond its component) and the original index it solves for,
//! so the solve works on the caller's vector in place; `B` is the largest half-bandwidth of
//! any component (at most [`MAX_BAND`]), a compile-time constant of the kernel, which keeps
//! the last `B` values in registers.

use super::banded::SymBanded;

/// The widest half-bandwidth the kernel is built for; a wider matrix is left to the sparse
/// factor.
pub const MAX_BAND: usize = 6;

/// Components substituted together: their recurrences are independent, so interleaving
/// them row by row lets the processor overlap them (one alone is a chain of dependent
/// multiply-adds, latency-bound).
const LANES: usize = 4;

/// The factor (module docs).
#[derive(Clone, Debug)]
pub struct ComponentBand {
    n: usize,
    /// Half-bandwidth B of every row's storage.
    b: usize,
    /// Original index of each slot.
    orig: Vec<usize>,
    /// Slot ranges of the components, in order (together, `0..n`).
    components: Vec<(usize, usize)>,
    /// Per slot p: `L[p, p−B..p] / L[p, p]` (zero before the component's start) then
    /// `1/L[p, p]`.
    fwd: Vec<f64>,
    /// Per slot p: `L[p+1, p], …, L[p+B, p]`, each over `L[p, p]` (zero past the
    /// component's end), then `1/L[p, p]`.
    bwd: Vec<f64>,
}

impl ComponentBand {
    /// Factorise `a`; `None` if some component's half-bandwidth exceeds [`MAX_BAND`] or `a`
    /// is not positive definite.
    pub fn new(a: &SymBanded) -> Option<Self> {
        let n = a.nrows();
        let c = a.components();
        let (members, local) = (c.members, c.local);
        let b = a
            .lower_entries()
            .map(|(i, j, _)| local[i].abs_diff(local[j]))
            .max()
            .unwrap_or(0)
            .max(1);
        if b > MAX_BAND {
            return None;
        }
        let w = b + 1;
        // The factor is computed on a padded layout (B zero rows around each component).
        let mut components = Vec::with_capacity(members.len());
        let mut next = b;
        for m in &members {
            components.push((next, next + m.len()));
            next += m.len() + b;
        }
        let mut rows = vec![0.0; next * w];
        for (m, &(start, _)) in members.iter().zip(&components) {
            let len = m.len();
            for i in 0..len {
                let p = start + i;
                let lo = i.saturating_sub(b);
                for j in lo..=i {
                    let q = start + j;
                    let mut s = a.get(m[i], m[j]);
                    for k in lo.max(j.saturating_sub(b))..j {
                        let r = start + k;
                        s -= rows[p * w + (b + r - p)] * rows[q * w + (b + r - q)];
                    }
                    if j == i {
                        if !(s > 0.0 && s.is_finite()) {
                            return None;
                        }
                        rows[p * w + b] = 1.0 / s.sqrt();
                    } else {
                        rows[p * w + (b + q - p)] = s * rows[q * w + b];
                    }
                }
            }
        }
        // Packed without the padding: slot p of the solve is padded slot p + B·(c + 1) for
        // component c.
        let mut fwd = vec![0.0; n * w];
        let mut bwd = vec![0.0; n * w];
        let mut packed = Vec::with_capacity(components.len());
        let mut q = 0;
        for &(start, end) in &components {
            packed.push((q, q + end - start));
            for p in start..end {
                let (f, g) = (&mut fwd[q * w..(q + 1) * w], &mut bwd[q * w..(q + 1) * w]);
                let dinv = rows[p * w + b];
                for t in 0..b {
                    f[t] = rows[p * w + t] * dinv;
                }
                f[b] = dinv;
                for k in 1..=b {
                    // L[p + k, p] sits in row p + k at position B − k (zero in padding).
                    g[k - 1] = rows[(p + k) * w + (b - k)] * rows[p * w + b];
                }
                g[b] = rows[p * w + b];
                q += 1;
            }
        }
        let orig = members.concat();
        Some(ComponentBand {
            n,
            b,
            orig,
            components: packed,
            fwd,
            bwd,
        })
    }

    /// Dimension n.
    pub fn nrows(&self) -> usize {
        self.n
    }

    /// Stored values.
    pub fn stored(&self) -> usize {
        self.fwd.len() + self.bwd.len()
    }

    /// x ← A⁻¹ x. No allocation.
    pub fn solve_in_place(&self, x: &mut [f64]) {
        assert_eq!(x.len(), self.n, "dimension mismatch");
        match self.b {
            1 => self.solve::<1>(x),
            2 => self.solve::<2>(x),
            3 => self.solve::<3>(x),
            4 => self.solve::<4>(x),
            5 => self.solve::<5>(x),
            _ => self.solve::<MAX_BAND>(x),
        }
    }

    /// The substitutions with the last B values in a register window (no index loads, no
    /// bounds case at a component's ends: the window starts at zero).
    fn solve<const B: usize>(&self, x: &mut [f64]) {
        let mut next = 0;
        while next < self.components.len() {
            // Up to LANES components with load (one without, such as the axial DOFs of a
            // span under vertical and lateral loads, stays at zero: nothing to solve).
            let mut lanes = [(0, 0); LANES];
            let mut m = 0;
            while next < self.components.len() && m < LANES {
                let (start, end) = self.components[next];
                next += 1;
                if self.orig[start..end].iter().any(|&i| x[i] != 0.0) {
                    lanes[m] = (start, end);
                    m += 1;
                }
            }
            let len = lanes[..m].iter().map(|&(s, e)| e - s).max().unwrap_or(0);
            // Lanes past their component's end (or unused) skip; the loop over the lanes is
            // unrolled, so every window stays in registers.
            // Forward L y = x: y_p = x_p / L[p, p] − Σ_k (L[p, p−B+k] / L[p, p]) y_{p−B+k},
            // the newest term last, so the chain from one row to the next is one multiply
            // and one subtraction.
            let mut win = [[0.0; B]; LANES];
            for r in 0..len {
                for l in 0..LANES {
                    let (start, end) = lanes[l];
                    let p = start + r;
                    if l >= m || p >= end {
                        continue;
                    }
                    let row = &self.fwd[p * (B + 1)..(p + 1) * (B + 1)];
                    let i = self.orig[p];
                    let mut y = x[i] * row[B];
                    for k in 0..B {
                        y -= row[k] * win[l][k];
                    }
                    x[i] = y;
                    for k in 1..B {
                        win[l][k - 1] = win[l][k];
                    }
                    win[l][B - 1] = y;
                }
            }
            // Back Lᵀ x = y: x_p = y_p / L[p, p] − Σ_k (L[p+1+k, p] / L[p, p]) x_{p+1+k}, the
            // newest term last.
            let mut win = [[0.0; B]; LANES];
            for r in 0..len {
                for l in 0..LANES {
                    let (start, end) = lanes[l];
                    if l >= m || r >= end - start {
                        continue;
                    }
                    let p = end - 1 - r;
                    let row = &self.bwd[p * (B + 1)..(p + 1) * (B + 1)];
                    let i = self.orig[p];
                    let mut v = x[i] * row[B];
                    for k in (0..B).rev() {
                        v -= row[k] * win[l][k];
                    }
                    x[i] = v;
                    for k in (1..B).rev() {
                        win[l][k] = win[l][k - 1];
                    }
                    win[l][0] = v;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::fe::assembly::SpanModel;
    use crate::physics::fe::cholesky::SparseCholesky;
    use crate::physics::guideway::BeamSection;

    /// Pseudo-random entries in [−1, 1) scaled over seven decades (xorshift).
    fn vector(n: usize, seed: u64) -> Vec<f64> {
        let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
        (0..n)
            .map(|_| {
                s ^= s << 13;
                s ^= s >> 7;
                s ^= s << 17;
                let u = (s >> 11) as f64 / (1u64 << 53) as f64;
                (2.0 * u - 1.0) * 10f64.powi((s % 7) as i32 - 3)
            })
            .collect()
    }

    fn check(a: &SymBanded, what: &str) {
        let band = ComponentBand::new(a).expect(what);
        let faer = SparseCholesky::new(a).unwrap();
        let mut scratch = faer.scratch();
        for seed in 1..20 {
            let rhs = vector(a.nrows(), seed);
            let (mut x, mut want) = (rhs.clone(), rhs);
            band.solve_in_place(&mut x);
            faer.solve_in_place(&mut want, &mut scratch);
            let peak = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (i, (x, w)) in x.iter().zip(&want).enumerate() {
                assert!(
                    (x - w).abs() <= 1e-12 * peak,
                    "{what}, seed {seed}, entry {i}: {x} against faer's {w}"
                );
            }
        }
    }

    /// Against faer's solve, on the §4.2 span's effective stiffness (20 and 80 elements,
    /// with and without Rayleigh damping terms) and on matrices with components of several
    /// bandwidths.
    #[test]
    fn solve_matches_faer() {
        let section = BeamSection::paper_4_2();
        for elements in [1, 20, 80] {
            let model = SpanModel::new(&section, 25.0, elements).unwrap();
            let dt = 1e-3;
            let keff = model.k.combine(1.0, &model.m, 4.0 / (dt * dt));
            check(&keff, &format!("{elements} elements"));
            let damped = keff.combine(
                1.0,
                &model.m.combine(0.3 * 2.0 / dt, &model.k, 1e-4 * 2.0 / dt),
                1.0,
            );
            check(&damped, &format!("{elements} elements, damped"));
        }
        // Two interleaved components, half-bandwidths 2 and 4 in their own numbering.
        let n = 41;
        let mut a = SymBanded::zeros(n, 8);
        for j in 0..n {
            a.add_lower(j, j, 10.0 + j as f64 * 0.1);
            if j + 2 < n {
                a.add_lower(j + 2, j, -1.0 - 0.01 * j as f64);
            }
            if j % 2 == 0 && j + 8 < n {
                a.add_lower(j + 8, j, 0.5);
            }
        }
        check(&a, "two components");
        // A diagonal matrix (every DOF its own component).
        let mut d = SymBanded::zeros(5, 1);
        for j in 0..5 {
            d.add_lower(j, j, 1.0 + j as f64);
        }
        check(&d, "diagonal");
    }

    /// Too wide a band and an indefinite matrix are refused (the caller keeps faer's factor).
    #[test]
    fn refuses_wide_and_indefinite() {
        let n = 20;
        let mut wide = SymBanded::zeros(n, MAX_BAND + 1);
        for j in 0..n {
            wide.add_lower(j, j, 10.0);
            if j + MAX_BAND + 1 < n {
                wide.add_lower(j + MAX_BAND + 1, j, 1.0);
            }
            if j + 1 < n {
                wide.add_lower(j + 1, j, 1.0);
            }
        }
        assert!(ComponentBand::new(&wide).is_none());
        let mut indefinite = SymBanded::zeros(3, 1);
        indefinite.add_lower(0, 0, 1.0);
        indefinite.add_lower(1, 0, 2.0);
        indefinite.add_lower(1, 1, 1.0);
        indefinite.add_lower(2, 2, 1.0);
        assert!(ComponentBand::new(&indefinite).is_none());
    }
}
