//! Rail irregularity profiles for a run, sampled once from the core's generator (Eq. 3–5).
//!
//! A passage asks for r(x) at every wheel, every Newton iteration, every step — hundreds of
//! thousands of 2000-term sums for the modal reference at Δt = 1e-5 s. The profile is
//! deterministic, so it is sampled once on a fine grid and read back by the core's fast
//! generator (`maglev_core::irregularity_fast::Table`, 4-point Lagrange): with h = 5 mm and
//! the shortest wavelength 2π/ω_u = 1 m the interpolation error is below 1e-6 of the shortest
//! component's amplitude (checked against the direct sum in the tests below).
//!
//! The samples are the direct sum of Eq. 3 on the uniform grid, computed by the chirp-z
//! transform ([`Synthesis`]: two FFTs per 6193 samples instead of 2000 terms per sample), so
//! a run's start-up costs about what its time loop does. It differs from the direct sum by
//! round-off only (`tests::synthesis_matches_the_direct_sum`, docs/regression.md). The
//! core's direct sum stays the reference and the firmware's path.

use crate::{Error, Result};
use std::sync::Arc;

use maglev_core::irregularity::{Direction, Irregularity, PsdParams, Term};
use maglev_core::irregularity_fast::Table;
use rustfft::num_complex::Complex64;
use rustfft::{Fft, FftPlannerScalar, FftPlannerSse};

/// Grid spacing (m).
pub const GRID: f64 = 0.005;

/// r(x) on `[x0, x0 + (n−1)·GRID]`, zero outside (never needed: the extent covers the run).
#[derive(Clone, Debug)]
pub struct Profile {
    table: Table<f64, Vec<f64>>,
}

impl Profile {
    /// Samples the Table 1 profiles (Y, Z) for `seed` over `[x_min, x_max]`. One
    /// [`Synthesis`] serves both (they share the frequencies). A generator the core refuses,
    /// or an extent that gives no grid, is `Invalid` on `irregularity`.
    pub fn table1_y_z(seed: u64, x_min: f64, x_max: f64) -> Result<(Self, Self)> {
        let (x0, n) = grid(x_min, x_max);
        let y = generator(Direction::Y, seed, x0)?;
        let z = generator(Direction::Z, seed, x0)?;
        let mut synthesis = Synthesis::new(y.terms(), GRID);
        let y = Self::sample(&y, x0, n, &mut synthesis)?;
        if !synthesis.serves(z.terms(), GRID) {
            synthesis = Synthesis::new(z.terms(), GRID);
        }
        Ok((y, Self::sample(&z, x0, n, &mut synthesis)?))
    }

    /// r of the cosine `terms` (uniform frequencies, phases already shifted to the origin
    /// `x0`, as [`Irregularity::with_origin`] does) over `[x_min, x_max]`: the same synthesis,
    /// grid and table as [`Profile::table1_y_z`], for spectra other than Table 1
    /// (`physics::rail::irregularity`). `x0` and `n` as [`grid`] gives them.
    pub fn from_terms(terms: &[Term<f64>], x0: f64, n: usize) -> Result<Self> {
        Self::tabulate(terms, x0, n, &mut Synthesis::new(terms, GRID))
    }

    /// r of `g` (origin `x0`) on `n` grid points, tabulated.
    fn sample(g: &Irregularity<f64>, x0: f64, n: usize, s: &mut Synthesis) -> Result<Self> {
        Self::tabulate(g.terms(), x0, n, s)
    }

    /// r of `terms` (origin `x0`) on `n` grid points by `s`, tabulated.
    fn tabulate(terms: &[Term<f64>], x0: f64, n: usize, s: &mut Synthesis) -> Result<Self> {
        let mut r = vec![0.0; n];
        let mut j0 = 0;
        while j0 < n {
            let block = s.block(terms, j0);
            let m = block.len().min(n - j0);
            r[j0..j0 + m].copy_from_slice(&block[..m]);
            j0 += m;
        }
        let table = Table::new(x0, GRID, r)
            .map_err(|e| Error::invalid("irregularity", format!("{e:?}")))?;
        Ok(Profile { table })
    }

    /// r at x (m), by 4-point Lagrange interpolation (0 outside the sampled extent).
    pub fn at(&self, x: f64) -> f64 {
        self.table.eval_nominal(x).unwrap_or_else(|| {
            let (mut outside, mut ov) = (false, false);
            self.table.eval(x, &mut outside, &mut ov)
        })
    }
}

/// The grid origin x0 and point count n that cover `[x_min, x_max]` with two cells of margin
/// each side (the 4-point interpolation's stencil).
pub fn grid(x_min: f64, x_max: f64) -> (f64, usize) {
    let x0 = x_min - 2.0 * GRID;
    (x0, ((x_max - x0) / GRID).ceil() as usize + 4)
}

/// The Table 1 generator of `direction` for `seed`, shifted to `origin` (m); on the heap (2000
/// terms of 24 bytes).
fn generator(direction: Direction, seed: u64, origin: f64) -> Result<Box<Irregularity<f64>>> {
    let mut g: Box<Irregularity<f64>> = Box::default();
    g.rebuild(&PsdParams::table1(direction), direction, seed, origin)
        .map_err(|e| Error::invalid("irregularity", e.to_string()))?;
    Ok(g)
}

/// Evaluate `g` at x_j = j·dx, j = 0..count, calling `out(j, x_j, r(x_j))` in order.
///
/// This is the direct sum of Eq. 3 on the real grid x_j = j·dx, computed block by block by
/// the chirp-z transform ([`Synthesis`]); the result differs from the direct sum by
/// round-off only (bounded in [`Synthesis`]'s docs and checked in the tests). The core's
/// plain `f64` sum at the f64 value `j as f64 * dx` differs from both by the rounding of x
/// (≤ ulp(x)/2, 1.8e-12 m at 26 km) and of f_k·x: up to 2π·2⁻⁵³·|x|·Σ f_k a_k.
pub fn sweep<E>(
    g: &Irregularity<f64>,
    dx: f64,
    count: usize,
    out: impl FnMut(usize, f64, f64) -> Result<(), E>,
) -> Result<(), E> {
    Synthesis::new(g.terms(), dx).sweep(g, count, out)
}

/// The chirp-z synthesis of Eq. 3 on a uniform grid: L samples per block from one forward
/// and one inverse FFT of length P = N + L − 1.
///
/// # Why not a plain FFT
/// A plain inverse FFT gives Σ_k c_k e^{2πi k m/P}: it needs the frequency step times the
/// grid step to be 1/P for an integer P (and the lowest frequency on that grid too). Here the
/// step is Δf·h = Δω·h/(2π) (Eq. 4): 6.18/2000 rad/m · 5 mm / 2π = 1/406 678.66…, irrational
/// in exact arithmetic (π in its denominator; the stored f64 values are dyadic fractions with
/// denominators beyond 2⁶⁰), so no usable FFT length puts Table 1's frequencies on its grid,
/// and moving them (or the grid) would change the profile. The chirp-z transform (Bluestein 1970, Rabiner,
/// Schafer & Rader 1969) evaluates Σ_k c_k W^{km} for any W on the unit circle exactly, up to
/// round-off, through k·m = (k² + m² − (m − k)²)/2.
///
/// # The algorithm
/// With f_k = F + k·D (F = f_0, D = (f_{N−1} − f_0)/(N − 1), β = D·h turns) and a block
/// starting at sample j0, sample j0 + m is
///
/// ```text
/// r = Re[ e^{2πi(F m h + β m²/2)} · Σ_k u_k v_{m−k} ],
/// u_k = a_k e^{2πi(f_k j0 h + p_k + β k²/2)},   v_d = e^{−2πi β d²/2},
/// ```
///
/// a linear convolution of N terms with N + L − 1 kernel values, done as a cyclic one of
/// length P. Every phase is reduced modulo one turn from the real product of f64 values
/// ([`grid_turn`]), so its error is ~1e-16 turns whatever j0, k or m.
///
/// # Round-off
/// Besides the phases (≤ ~4 ulp of a turn each, then `sin_cos` to 1 ulp), the errors are the
/// FFTs' and the one of modelling the stored f_k as F + k·D: |e_k| = |f_k − F − k·D| is a
/// few ulp of f_k, so the phase slip within a block is ≤ max|e_k|·(L − 1)·h turns. See
/// `tests::synthesis_matches_the_direct_sum` for the bound and the measured error.
pub struct Synthesis {
    fft: Arc<dyn Fft<f64>>,
    /// The frequencies f_k it was made for (turns/m).
    freqs: Vec<f64>,
    /// FFT of the kernel v, divided by P (exact: P is a power of two).
    kernel: Vec<Complex64>,
    /// β k²/2 in turns, k < N.
    in_chirp: Vec<f64>,
    /// e^{2πi(F m h + β m²/2)}, m < L.
    out_chirp: Vec<Complex64>,
    dx: f64,
    /// u_k for k < N, then zeros; the inverse transform's output overwrites it, so a block
    /// zeroes the tail again. Two working buffers of P, not three, and no temporary ones: the
    /// first touch of fresh memory (a page fault a 4 KiB page) costs the process more than
    /// zeroing the tail (docs/performance.md, start-up).
    input: Vec<Complex64>,
    spectrum: Vec<Complex64>,
    scratch: Vec<Complex64>,
    samples: Vec<f64>,
}

impl Synthesis {
    /// The transform for `terms` (uniform frequencies, as [`Irregularity`] makes them) on the
    /// grid step `dx` (m).
    pub fn new(terms: &[Term<f64>], dx: f64) -> Self {
        let n = terms.len().max(1);
        let p = block_fft_len(n);
        let l = p - n + 1;
        let f0 = terms.first().map_or(0.0, |t| t.freq);
        let step = match terms {
            [first, .., last] => (last.freq - first.freq) / (terms.len() - 1) as f64,
            _ => 0.0,
        };
        // Halving is exact, so β/2 = (D/2)·h is again a real product of f64 values.
        let half = 0.5 * step;
        let chirp = |k: usize| grid_turn(half, dx, k * k);
        // e^{πiβd²} for 0 ≤ d < L; N − 1 < L, so it covers the kernel's negative d too.
        let mut chirps: Vec<Complex64> = (0..l).map(|d| phasor(chirp(d))).collect();
        let fft = plan(p);
        let scale = 1.0 / p as f64;
        // The kernel v, laid out in the spectrum buffer (every block overwrites it).
        let spectrum: Vec<Complex64> = (0..p)
            .map(|i| chirps[if i < l { i } else { p - i }].conj() * scale)
            .collect();
        let mut kernel = vec![Complex64::default(); p];
        let mut scratch = vec![Complex64::default(); fft.get_immutable_scratch_len()];
        fft.process_immutable_with_scratch(&spectrum, &mut kernel, &mut scratch);
        // The output chirp, in place of the kernel's chirps.
        times_linear_phasors(f0, dx, &mut chirps);
        Synthesis {
            freqs: terms.iter().map(|t| t.freq).collect(),
            in_chirp: (0..terms.len()).map(chirp).collect(),
            out_chirp: chirps,
            input: vec![Complex64::default(); p],
            spectrum,
            samples: vec![0.0; l],
            scratch,
            fft,
            kernel,
            dx,
        }
    }

    /// [`sweep`] with this transform, which must [`Synthesis::serves`] `g`'s terms.
    pub fn sweep<E>(
        &mut self,
        g: &Irregularity<f64>,
        count: usize,
        mut out: impl FnMut(usize, f64, f64) -> Result<(), E>,
    ) -> Result<(), E> {
        let (mut j0, dx) = (0, self.dx);
        while j0 < count {
            let block = self.block(g.terms(), j0);
            for (m, &r) in block.iter().take(count - j0).enumerate() {
                let j = j0 + m;
                out(j, j as f64 * dx, r)?;
            }
            j0 += block.len();
        }
        Ok(())
    }

    /// Whether this transform serves `terms` on the step `dx`: the same frequencies, bit for
    /// bit (Table 1's Y and Z profiles share them).
    pub fn serves(&self, terms: &[Term<f64>], dx: f64) -> bool {
        dx == self.dx && self.freqs.iter().eq(terms.iter().map(|t| &t.freq))
    }

    /// r(x_j) for j = j0 .. j0 + L (L = this transform's block length) of the profile with
    /// `terms` (which this transform [`Synthesis::serves`]).
    pub fn block(&mut self, terms: &[Term<f64>], j0: usize) -> &[f64] {
        let (head, tail) = self.input.split_at_mut(terms.len());
        for ((u, t), c) in head.iter_mut().zip(terms).zip(&self.in_chirp) {
            *u = phasor(grid_turn(t.freq, self.dx, j0) + t.phase + c) * t.amp;
        }
        tail.fill(Complex64::default());
        let (fft, scratch) = (&self.fft, &mut self.scratch);
        fft.process_immutable_with_scratch(&self.input, &mut self.spectrum, scratch);
        // The inverse transform as conj ∘ forward ∘ conj (one plan, the same round-off).
        for (b, v) in self.spectrum.iter_mut().zip(&self.kernel) {
            *b = (*b * v).conj();
        }
        let output = &mut self.input;
        fft.process_immutable_with_scratch(&self.spectrum, output, scratch);
        // r = Re(w · conj(q)) for the forward transform q of the conjugated product.
        for ((s, q), w) in self
            .samples
            .iter_mut()
            .zip(output.iter())
            .zip(&self.out_chirp)
        {
            *s = w.re * q.re + w.im * q.im;
        }
        &self.samples
    }
}

/// Multiplies `xs[m]` by e^{2πi f m dx} (as `e · xs[m]`) for every m, the phasor formed as the
/// product of two exact phasors (m = 64a + b: one for f·64a·dx, one for f·b·dx; [`grid_turn`]
/// each): 1 ulp more than one phasor per m, for len/64 + 64 sines and cosines instead of len.
fn times_linear_phasors(f: f64, dx: f64, xs: &mut [Complex64]) {
    const SPLIT: usize = 64;
    let fine: Vec<Complex64> = (0..SPLIT).map(|b| phasor(grid_turn(f, dx, b))).collect();
    for (a, chunk) in xs.chunks_mut(SPLIT).enumerate() {
        let coarse = phasor(grid_turn(f, dx, a * SPLIT));
        for (x, fine) in chunk.iter_mut().zip(&fine) {
            *x = coarse * fine * *x;
        }
    }
}

/// A forward FFT of length `p`: rustfft's SSE4.1 code on x86-64 machines that have it, its
/// scalar code elsewhere. Not the auto-selecting planner: it picks AVX where present, and the
/// table's round-off would then depend on the machine's CPU generation.
fn plan(p: usize) -> Arc<dyn Fft<f64>> {
    match FftPlannerSse::new() {
        Ok(mut sse) => sse.plan_fft_forward(p),
        Err(()) => FftPlannerScalar::new().plan_fft_forward(p),
    }
}

/// The cyclic length for N terms: the power of two of at least 4N (8192 for Table 1), so
/// that a block yields L = P − N + 1 ≥ ¾P samples. Measured on `maglev run paper-4.2`
/// (13 406 samples a profile): 2¹³ (3 blocks) builds both tables in 15.5 M instructions,
/// 2¹⁴ (1 block, but twice the set-up) in 16.2 M; 2¹² (7 blocks) is estimated at ~14.5 M
/// from the per-FFT counts. A smaller P also keeps the e_k phase slip ([`Synthesis`]) small.
fn block_fft_len(n: usize) -> usize {
    (4 * n).next_power_of_two().max(64)
}

/// e^{2πi t} for t in turns.
fn phasor(t: f64) -> Complex64 {
    let (s, c) = turn_sin_cos(t);
    Complex64::new(c, s)
}

/// `f·(j·dx)` modulo 1 turn for the *real* product of the f64 values `f`, `dx` and the
/// integer `j` (< 2⁵³), to ~1e-16 turns: `f·dx = h + l` exactly (FMA two-product), then
/// `j·h = H + L` exactly, and `j·l` is below 2⁻⁵³·|j·h|, so it carries its own rounding only.
fn grid_turn(f: f64, dx: f64, j: usize) -> f64 {
    let jf = j as f64;
    let h = f * dx;
    let l = f.mul_add(dx, -h);
    let hh = jf * h;
    let hl = jf.mul_add(h, -hh);
    fract(fract(hh) + hl + jf * l)
}

/// `v − ⌊v⌋`, exact in binary floating point.
fn fract(v: f64) -> f64 {
    v - floor(v)
}

/// ⌊v⌋ for |v| < 2⁶³ (every phase here: |v| ≤ f·j·dx ≪ 2⁶³) by truncation, which compiles
/// to two instructions; `f64::floor` is a library call on baseline x86-64 (no SSE4.1).
fn floor(v: f64) -> f64 {
    let t = v as i64 as f64;
    if t > v {
        t - 1.0
    } else {
        t
    }
}

/// (sin, cos) of 2π·t, reduced to [−½, ½] turns first (t − n is exact for an integer n
/// next to t, so the rounding of t + ½ only picks which of two neighbours).
fn turn_sin_cos(t: f64) -> (f64, f64) {
    let u = t - floor(t + 0.5);
    (std::f64::consts::TAU * u).sin_cos()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Σ a_k cos 2π(f_k x + p_k) at the real x = j·dx with the phase product formed exactly
    /// (x = xh + xl and f·xh = ph + pl by FMA two-products: a route independent of
    /// [`grid_turn`]),
    /// summed with Neumaier's compensation, so that its error is the cosines' own rounding.
    fn reference(g: &Irregularity<f64>, j: usize, dx: f64) -> f64 {
        let xh = j as f64 * dx;
        let xl = (j as f64).mul_add(dx, -xh);
        let (mut sum, mut c) = (0.0f64, 0.0f64);
        for t in g.terms() {
            let ph = t.freq * xh;
            let pl = t.freq.mul_add(xh, -ph);
            let v = t.amp * turn_sin_cos(fract(ph) + pl + t.freq * xl + t.phase).1;
            let s = sum + v;
            c += if sum.abs() >= v.abs() {
                (sum - s) + v
            } else {
                (v - s) + sum
            };
            sum = s;
        }
        sum + c
    }

    /// e_k = f_k − F − k·D in turns/m, the stored frequencies' departure from the uniform
    /// grid the transform uses, formed without rounding that matters: f_k − F and k·D are
    /// split exactly (TwoSum, FMA two-product) and their high parts cancel exactly (Sterbenz).
    fn grid_departures(g: &Irregularity<f64>) -> Vec<f64> {
        let f = |k: usize| g.terms()[k].freq;
        let (f0, n) = (f(0), g.terms().len());
        let step = (f(n - 1) - f0) / (n - 1) as f64;
        (0..n)
            .map(|k| {
                let s = f(k) - f0;
                let bb = s - f(k);
                let s_err = (f(k) - (s - bb)) + (-f0 - bb);
                let p = k as f64 * step;
                let p_err = (k as f64).mul_add(step, -p);
                (s - p) + (s_err - p_err)
            })
            .collect()
    }

    /// The chirp-z synthesis against the direct sum of the same terms ([`reference`]), block
    /// by block, near the origin and 1.3 km, 26 km along (where the core's plain f64 sum is
    /// checked against the same reference within its own worst-case bound, as a cross-check
    /// that the reference is the core's sum), on the runs' grid (5 mm) and the CLI's (0.1 m).
    ///
    /// Tolerance, from a round-off model in which each rounding is an independent error of
    /// standard deviation u = 2⁻⁵³ relative (u absolute for a turn below 2, 2u below 4):
    /// - the input u_k: phase f_k·j0·h (2 roundings), + p_k (1), + β k²/2 (2 + 1 at up to 3
    ///   turns), so ≈ 3.2u turns = 20u rad, plus sin/cos and × a_k (√2 u): σ_in ≈ 20u of a_k;
    /// - the kernel v_d and the output chirp w_m: ≈ 14u and 20u of their unit magnitude;
    /// - each of the two FFTs: log₂P stages of a complex multiply-add, 2u² variance each;
    /// - the real part halves a phase error's mean square (⟨sin²⟩ = ½);
    /// - e_k: the phase slips by 2π e_k·m·h over a block, RMS 2π m h [Σ a_k² e_k²/2]^½.
    ///
    /// So the RMS error per sample is σ = u‖a‖₂·[(20² + 14² + 20²)/2 + 2·2·log₂P]^½ in
    /// quadrature with the e_k term at m = L − 1. The test asserts the block's RMS ≤ σ and
    /// its largest error ≤ 5σ (a 5-sigma excursion among ~800 samples), and prints both.
    #[test]
    fn synthesis_matches_the_direct_sum() {
        let g = Irregularity::<f64>::new(&PsdParams::TABLE1_Z, Direction::Z, 77).unwrap();
        let u = f64::EPSILON / 2.0;
        let a2: f64 = g.terms().iter().map(|t| t.amp * t.amp).sum::<f64>().sqrt();
        let e = grid_departures(&g);
        let slip: f64 = (g.terms().iter().zip(&e))
            .map(|(t, e)| 0.5 * (t.amp * e).powi(2))
            .sum::<f64>()
            .sqrt();
        let tau = std::f64::consts::TAU;
        for dx in [GRID, 0.1] {
            let mut s = Synthesis::new(g.terms(), dx);
            let l = s.samples.len();
            let p = s.input.len() as f64;
            let model =
                u * a2 * ((20f64.powi(2) * 2.0 + 14f64.powi(2)) / 2.0 + 4.0 * p.log2()).sqrt();
            let sigma = model.hypot(tau * (l - 1) as f64 * dx * slip);
            for j0 in [0, l, 260_000 / l * l, 5_200_000 / l * l] {
                let block = s.block(g.terms(), j0).to_vec();
                let (mut worst, mut ss, mut count) = (0.0f64, 0.0f64, 0);
                for m in (0..l).step_by(l / 800) {
                    let want = reference(&g, j0 + m, dx);
                    let err = block[m] - want;
                    worst = worst.max(err.abs());
                    ss += err * err;
                    count += 1;
                    // The core's plain sum at the f64 x: its x and f_k·x round (ε|x|/2 each).
                    let x = (j0 + m) as f64 * dx;
                    let core = g.eval(x, &mut false);
                    let bound = tau
                        * x
                        * f64::EPSILON
                        * g.terms().iter().map(|t| t.amp * t.freq).sum::<f64>()
                        + 64.0 * u * g.terms().iter().map(|t| t.amp).sum::<f64>();
                    assert!((core - want).abs() <= bound, "core at x = {x}");
                }
                let rms = (ss / count as f64).sqrt();
                println!(
                    "dx = {dx} m, x0 = {:.0} m: RMS error {:.1} u‖a‖₂, max {:.1} u‖a‖₂ (σ = {:.1} u‖a‖₂)",
                    j0 as f64 * dx,
                    rms / (u * a2),
                    worst / (u * a2),
                    sigma / (u * a2)
                );
                assert!(rms <= sigma && worst <= 5.0 * sigma, "dx = {dx}, j0 = {j0}");
            }
        }
    }

    /// A block does not depend on the blocks computed before it with the same transform (the
    /// inverse FFT's output overwrites the input buffer, whose tail must be zeros again): the
    /// third block after the first two, bit for bit, equals it from a fresh transform.
    #[test]
    fn a_block_does_not_depend_on_the_blocks_before_it() {
        let g = Irregularity::<f64>::new(&PsdParams::TABLE1_Y, Direction::Y, 3).unwrap();
        let mut used = Synthesis::new(g.terms(), GRID);
        let l = used.samples.len();
        used.block(g.terms(), 0);
        used.block(g.terms(), l);
        let after = used.block(g.terms(), 2 * l).to_vec();
        let fresh = Synthesis::new(g.terms(), GRID)
            .block(g.terms(), 2 * l)
            .to_vec();
        assert!(after
            .iter()
            .zip(&fresh)
            .all(|(a, b)| a.to_bits() == b.to_bits()));
    }

    #[test]
    fn interpolated_profile_matches_the_direct_sum() {
        let seed = 7;
        let p = Profile::table1_y_z(seed, -20.0, 60.0).unwrap().1;
        let g =
            Irregularity::<f64>::new(&PsdParams::table1(Direction::Z), Direction::Z, seed).unwrap();
        let mut worst = 0.0f64;
        for k in 0..800 {
            let x = -19.0 + k as f64 * 0.0987;
            let mut ov = false;
            let want = g.eval_f64(x, &mut ov);
            worst = worst.max((p.at(x) - want).abs());
        }
        // Interpolation error bound: Σ a_k·(ω_k h)⁴·(3/128) over the terms, well under 1e-10 m
        // for Table 1; the profile itself is ~1 mm RMS.
        assert!(worst < 1e-10, "worst {worst:e} m");
    }
}
