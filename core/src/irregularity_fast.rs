//! Fast rail irregularity: the profile of Eq. 3 sampled once on a uniform grid and read back
//! in O(1) per query by 4-point (cubic) Lagrange interpolation.
//!
//! # Why
//! The direct sum ([`crate::irregularity::Irregularity::eval`]) costs `N` = 2000 cosines per
//! sample (Table 1): too much for a controller's time step or for a simulation that asks at
//! every wheel, every Newton iteration, every step. The profile is deterministic, so it is
//! tabulated once and interpolated.
//!
//! # Storage and capacity
//! The table is any `B: AsRef<[S]>`: `[S; N]` on firmware (capacity fixed at compile time,
//! no allocation; see [`FixedTable`]) or a `Vec` on the host. The core never allocates.
//!
//! # Accuracy
//! For one term `a·cos(ωx + φ)` the 4-point Lagrange error on the middle interval is at most
//! `a·(ωh)⁴·3/128` (`|(u+1)u(u−1)(u−2)|/4! ≤ 3/128` for `u ∈ [0, 1]`). Summed in quadrature over
//! Table 1's terms this bounds the relative RMS error by `[Σ a_k²·((ω_k h)⁴·3/128)²/Σ a_k²]^½`:
//! 1.8e-10 at `h` = 5 mm, 1.8e-6 at 5 cm, 2.9e-5 at 10 cm ([`rms_error_bound`]); the
//! high-frequency terms that interpolation handles worst carry little amplitude
//! (`G_rr ∝ ω⁻⁴`). Outside the table the profile reads 0 and the query is flagged.

use crate::irregularity::{Irregularity, Term};
use crate::scalar::Scalar;

/// A tabulated profile on `x_j = x0 + j·h`, `j = 0..len`.
#[derive(Clone, Debug)]
pub struct Table<S, B> {
    x0: f64,
    h: f64,
    inv_h: f64,
    samples: B,
    _s: core::marker::PhantomData<S>,
}

/// A table whose capacity `N` is fixed at compile time (firmware).
pub type FixedTable<S, const N: usize> = Table<S, [S; N]>;

/// Why a table cannot be built.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum TableError {
    /// Spacing not positive and finite, or origin not finite.
    BadGrid,
    /// Fewer than 4 samples: cubic interpolation needs 4.
    TooShort,
}

impl<S: Scalar, B: AsRef<[S]>> Table<S, B> {
    /// Wraps samples `samples[j] = r(x0 + j·h)` (m, as produced by [`fill`] or any exact
    /// sweep of Eq. 3).
    pub fn new(x0: f64, h: f64, samples: B) -> Result<Self, TableError> {
        if !(h.is_finite() && h > 0.0 && x0.is_finite()) {
            return Err(TableError::BadGrid);
        }
        if samples.as_ref().len() < 4 {
            return Err(TableError::TooShort);
        }
        Ok(Table {
            x0,
            h,
            inv_h: 1.0 / h,
            samples,
            _s: core::marker::PhantomData,
        })
    }

    /// `[first, last]` x (m) at which a query interpolates inside the table (at the very ends
    /// to within the rounding of `(x − x0)/h`).
    pub fn range(&self) -> (f64, f64) {
        let n = self.samples.as_ref().len();
        (self.x0 + self.h, self.x0 + (n - 2) as f64 * self.h)
    }

    /// r(x) (m) by 4-point Lagrange interpolation on the nodes around `x`; 0 and
    /// `*outside = true` beyond [`Table::range`]. Saturating arithmetic flags `overflow`.
    pub fn eval(&self, x: f64, outside: &mut bool, overflow: &mut bool) -> S {
        let r = self.samples.as_ref();
        let Some((i, w)) = cell(self.x0, self.inv_h, r.len(), x) else {
            *outside = true;
            return S::ZERO;
        };
        let mut acc = S::ZERO;
        for (k, wk) in w.iter().enumerate() {
            let wk = S::from_f64(*wk, overflow);
            acc = acc.sadd(wk.smul(r[i - 1 + k], overflow), overflow);
        }
        acc
    }
}

impl<B: AsRef<[f64]>> Table<f64, B> {
    /// [`Table::eval`] in plain f64, for hosts: the same operations in the same order without
    /// the per-operation finiteness checks. `None` outside [`Table::range`] or when the result
    /// is not finite (then every check of [`Table::eval`] would have passed only if it were),
    /// so wherever this returns a value it is `eval`'s, bit for bit.
    #[inline]
    pub fn eval_nominal(&self, x: f64) -> Option<f64> {
        let r = self.samples.as_ref();
        let (i, w) = cell(self.x0, self.inv_h, r.len(), x)?;
        let r = r.get(i - 1..i + 3)?;
        let mut acc = 0.0;
        for k in 0..4 {
            acc += w[k] * r[k];
        }
        // A non-finite weight, product or partial sum leaves the sum non-finite.
        acc.is_finite().then_some(acc)
    }
}

/// The cell of `x` on a grid `x0 + j/inv_h` of `len` nodes and its 4-point Lagrange weights
/// on nodes −1, 0, 1, 2 at u ∈ [0, 1), formed in f64 (O(1) work); `None` unless the nodes
/// i−1 … i+2 exist (NaN fails both comparisons).
#[inline]
fn cell(x0: f64, inv_h: f64, len: usize, x: f64) -> Option<(usize, [f64; 4])> {
    let s = (x - x0) * inv_h;
    let fl = libm::floor(s);
    if !(fl >= 1.0 && fl + 2.0 < len as f64) {
        return None;
    }
    let u = s - fl;
    let (um, u1, u2) = (u + 1.0, u - 1.0, u - 2.0);
    let w = [
        -u * u1 * u2 / 6.0,
        um * u1 * u2 / 2.0,
        -um * u * u2 / 2.0,
        um * u * u1 / 6.0,
    ];
    Some((fl as usize, w))
}

/// Fills `out[j] = r(x0 + j·h)` from the direct sum (O(N) per sample, once, in `S`).
pub fn fill<S: Scalar, const CAP: usize>(
    g: &Irregularity<S, CAP>,
    x0: f64,
    h: f64,
    out: &mut [S],
    overflow: &mut bool,
) {
    for (j, o) in out.iter_mut().enumerate() {
        *o = g.eval_f64(x0 + j as f64 * h, overflow);
    }
}

/// The relative RMS interpolation error bound of the module docs for spacing `h` (m):
/// `[Σ a_k²·((ω_k h)⁴·3/128)² / Σ a_k²]^½` over the terms (f64 design values).
pub fn rms_error_bound<S: Scalar>(terms: &[Term<S>], h: f64) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for t in terms {
        let a = t.amp.to_f64();
        let wh = core::f64::consts::TAU * t.freq.to_f64() * h;
        let e = wh * wh * wh * wh * 3.0 / 128.0;
        num += a * a * e * e;
        den += a * a;
    }
    libm::sqrt(num / den)
}

#[cfg(test)]
mod tests;
