//! Rail irregularity profiles for a run, sampled once from the core's generator (Eq. 3–5).
//!
//! A passage asks for r(x) at every wheel, every Newton iteration, every step — hundreds of
//! thousands of 2000-term sums for the modal reference at Δt = 1e-5 s. The profile is
//! deterministic, so it is sampled once on a fine grid (the CLI's exact-phase sweep, fast on a
//! uniform grid) and read back by the core's fast generator
//! (`maglev_core::irregularity_fast::Table`, 4-point Lagrange): with h = 5 mm and the
//! shortest wavelength 2π/ω_u = 1 m the interpolation error is below 1e-6 of the shortest
//! component's amplitude (checked against the direct sum in the tests below).

use crate::cli::irregularity::sweep;
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
    pub fn table1(direction: Direction, seed: u64, x_min: f64, x_max: f64) -> Result<Self, String> {
        let params = PsdParams::table1(direction);
        let x0 = x_min - 2.0 * GRID;
        let g = Irregularity::<f64>::with_origin(&params, direction, seed, x0)
            .map_err(|e| e.to_string())?;
        let n = ((x_max - x0) / GRID).ceil() as usize + 4;
        let mut r = vec![0.0; n];
        sweep::<()>(&g, GRID, n, |j, _x, v| {
            r[j] = v;
            Ok(())
        })
        .map_err(|_| "irregularity sweep failed".to_string())?;
        let table = Table::new(x0, GRID, r).map_err(|e| format!("{e:?}"))?;
        Ok(Profile { table })
    }

    /// r at x (m), by 4-point Lagrange interpolation (0 outside the sampled extent).
    pub fn at(&self, x: f64) -> f64 {
        let (mut outside, mut ov) = (false, false);
        self.table.eval(x, &mut outside, &mut ov)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
