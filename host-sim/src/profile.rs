//! Rail irregularity profiles for a run, sampled once from the core's generator (Eq. 3–5).
//!
//! A passage asks for r(x) at every wheel, every Newton iteration, every step — hundreds of
//! thousands of 2000-term sums for the modal reference at Δt = 1e-5 s. The profile is
//! deterministic, so it is sampled once on a fine grid (the CLI's exact-phase sweep, fast on a
//! uniform grid) and read back by the core's fast generator
//! (`maglev_core::irregularity_fast::Table`, 4-point Lagrange): with h = 5 mm and the
//! shortest wavelength 2π/ω_u = 1 m the interpolation error is below 1e-6 of the shortest
//! component's amplitude (checked against the direct sum in the tests below).

use crate::{Error, Result};
use maglev_core::irregularity::{Direction, Irregularity, PsdParams};
use maglev_core::irregularity_fast::Table;

/// Grid spacing (m).
pub const GRID: f64 = 0.005;

/// r(x) on `[x0, x0 + (n−1)·GRID]`, zero outside (never needed: the extent covers the run).
#[derive(Clone, Debug)]
pub struct Profile {
    table: Table<f64, Vec<f64>>,
}

impl Profile {
    /// Samples the Table 1 profile of `direction` for `seed` over `[x_min, x_max]`.
    /// A generator the core refuses, or an extent that gives no grid, is `Invalid` on
    /// `irregularity`.
    pub fn table1(direction: Direction, seed: u64, x_min: f64, x_max: f64) -> Result<Self> {
        let params = PsdParams::table1(direction);
        let x0 = x_min - 2.0 * GRID;
        let g = Irregularity::<f64>::with_origin(&params, direction, seed, x0)
            .map_err(|e| Error::invalid("irregularity", e.to_string()))?;
        let n = ((x_max - x0) / GRID).ceil() as usize + 4;
        let mut r = vec![0.0; n];
        sweep::<()>(&g, GRID, n, |j, _x, v| {
            r[j] = v;
            Ok(())
        })
        .map_err(|_| Error::numerical("irregularity sweep failed"))?;
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

/// Samples between exact re-anchorings of the rotation recurrence in [`sweep`].
pub const ANCHOR_EVERY: usize = 256;

/// Evaluate `g` at x_j = j·dx, j = 0..count, calling `out(j, x_j, r(x_j))` in order.
///
/// This is the direct sum of Eq. 3, organised for a uniform grid: each term's phasor
/// `z_k = exp(2πi (f_k x + p_k))` is advanced by the rotation `w_k = exp(2πi f_k dx)` from
/// one sample to the next, and `r = Σ a_k Re z_k`. Every [`ANCHOR_EVERY`] samples the phasors
/// are recomputed from the phase `f_k·j·dx + p_k` formed exactly ([`grid_turn`]), so the
/// rounding of the recurrence cannot accumulate: after m ≤ 255 steps each phasor is off by
/// about m·4 ulp (≈ 2e-13 relative), i.e. |r_sweep − r_exact| ≲ 2e-13·Σ a_k in the worst
/// case and far less in practice (the test demands ≤ 1e-12 of max |r|).
///
/// The grid is the real x_j = j·dx. The core's plain `f64` sum at the f64 value
/// `j as f64 * dx` differs from it by the rounding of x (≤ ulp(x)/2, 1.8e-12 m at 26 km)
/// and of f_k·x: up to 2π·2⁻⁵³·|x|·Σ f_k a_k, ~1e-15 m at 26 km, as the test checks.
pub fn sweep<E>(
    g: &Irregularity<f64>,
    dx: f64,
    count: usize,
    mut out: impl FnMut(usize, f64, f64) -> Result<(), E>,
) -> Result<(), E> {
    let terms = g.terms();
    let n = terms.len();
    let amp: Vec<f64> = terms.iter().map(|t| t.amp).collect();
    let (mut wr, mut wi) = (vec![0.0; n], vec![0.0; n]);
    for (k, t) in terms.iter().enumerate() {
        let (s, c) = turn_sin_cos(fract(t.freq * dx));
        wr[k] = c;
        wi[k] = s;
    }
    let (mut zr, mut zi) = (vec![0.0; n], vec![0.0; n]);
    let mut j = 0;
    while j < count {
        for (k, t) in terms.iter().enumerate() {
            let (s, c) = turn_sin_cos(grid_turn(t.freq, dx, j) + t.phase);
            zr[k] = c;
            zi[k] = s;
        }
        let end = (j + ANCHOR_EVERY).min(count);
        while j < end {
            // Four independent partial sums let the compiler keep the loop vectorised while
            // the result stays deterministic.
            let mut acc = [0.0f64; 4];
            let mut k = 0;
            while k + 4 <= n {
                for l in 0..4 {
                    acc[l] += amp[k + l] * zr[k + l];
                }
                k += 4;
            }
            let mut r = (acc[0] + acc[1]) + (acc[2] + acc[3]);
            while k < n {
                r += amp[k] * zr[k];
                k += 1;
            }
            out(j, j as f64 * dx, r)?;
            for k in 0..n {
                let (a, b) = (zr[k], zi[k]);
                zr[k] = a * wr[k] - b * wi[k];
                zi[k] = a * wi[k] + b * wr[k];
            }
            j += 1;
        }
    }
    Ok(())
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

fn fract(v: f64) -> f64 {
    v - v.floor()
}

/// (sin, cos) of 2π·t, reduced to [−½, ½] turns first (exact in binary floating point).
fn turn_sin_cos(t: f64) -> (f64, f64) {
    let u = t - t.round();
    (std::f64::consts::TAU * u).sin_cos()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The direct sum of Eq. 3 with the phase product f_k·x formed exactly (two-product by
    /// FMA), so that its own rounding is ~1e-16 turns per term even at x = 26 km.
    /// Evaluated at the real x = j·dx: x = xh + xl exactly (two-product), then
    /// f·xh = ph + pl exactly and f·xl rounded (a route independent of [`grid_turn`]).
    fn direct_exact_phase(g: &Irregularity<f64>, j: usize, dx: f64) -> f64 {
        let xh = j as f64 * dx;
        let xl = (j as f64).mul_add(dx, -xh);
        g.terms()
            .iter()
            .map(|t| {
                let ph = t.freq * xh;
                let pl = t.freq.mul_add(xh, -ph);
                t.amp * turn_sin_cos(fract(ph) + pl + t.freq * xl + t.phase).1
            })
            .sum()
    }

    /// The sweep equals the direct sum on the real grid j·dx to ≤ 1e-12 of the profile's
    /// largest value, over several anchor blocks, at the start and at the end of a 26 km
    /// track. The core's plain f64 sum at `j as f64 * dx` rounds x and f_k·x (≤ 2⁻⁵³·|x|
    /// turns per term each), which at 26 km is itself a ~1e-12-relative effect; it is checked
    /// against its worst-case bound 2π·2⁻⁵²·|x|·Σ f_k a_k.
    #[test]
    fn sweep_matches_direct_sum() {
        let g = Irregularity::<f64>::new(&PsdParams::TABLE1_Z, Direction::Z, 77).unwrap();
        for (start_block, dx) in [(0usize, 0.1), (100_000, 0.1), (259_000, 0.1), (0, 0.37)] {
            let count = start_block + 3 * ANCHOR_EVERY + 17;
            let (mut worst, mut worst_core, mut peak) = (0.0f64, 0.0f64, 0.0f64);
            let mut ov = false;
            sweep(&g, dx, count, |j, x, r| {
                if j >= start_block {
                    let want = direct_exact_phase(&g, j, dx);
                    worst = worst.max((r - want).abs());
                    peak = peak.max(want.abs());
                    let core = g.eval(x, &mut ov);
                    // Rounding of x (ulp/2 = ε|x|/2) and of f·x (ε|f x|/2) in turns, times
                    // 2π a_k per term; plus the cosines' and additions' own ~1e-16 relative.
                    let bound: f64 = g.terms().iter().map(|t| t.amp * t.freq).sum::<f64>()
                        * std::f64::consts::TAU
                        * x.abs()
                        * f64::EPSILON
                        + 1e-16 * 0.03;
                    assert!((core - want).abs() <= bound, "core at x={x}");
                    worst_core = worst_core.max((core - want).abs());
                }
                Ok::<(), ()>(())
            })
            .unwrap();
            assert!(!ov);
            println!(
                "sweep dx={dx} from x={}: max |sweep - exact| {worst:.3e} m, max |core - exact| {worst_core:.3e} m, max |r| {peak:.3e} m",
                start_block as f64 * dx
            );
            assert!(worst <= 1e-12 * peak, "{worst:e} vs {peak:e}");
        }
    }

    #[test]
    fn interpolated_profile_matches_the_direct_sum() {
        let seed = 7;
        let p = Profile::table1(Direction::Z, seed, -20.0, 60.0).unwrap();
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
