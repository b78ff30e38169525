//! `maglev irregularity`: a rail irregularity profile (Eq. 3–5, Table 1) as CSV `x,r` in m.
//!
//! The profile is `maglev_core::irregularity::Irregularity<f64>`; the phases depend only on
//! `--seed` and `--direction` (see the core module docs), so the CSV is reproducible on any
//! machine. Evaluating the 2000-term sum with one cosine per term and sample would take
//! several seconds for a 26 km profile, so [`sweep`] evaluates the same direct sum on the
//! uniform grid with a complex rotation per term and sample, re-anchored exactly every
//! [`ANCHOR_EVERY`] samples (see there for the accuracy).

use std::io::{BufWriter, Write};

use maglev_core::irregularity::{Direction, Irregularity, PsdParams};

/// Largest number of rows the command will write (10⁸ rows is ~3 GB of CSV).
pub const MAX_SAMPLES: u64 = 100_000_000;

/// Samples between exact re-anchorings of the rotation recurrence in [`sweep`].
pub const ANCHOR_EVERY: usize = 256;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Profile direction: y (lateral, guidance) or z (vertical, levitation); selects Table 1's
    /// row and the random stream.
    #[arg(long)]
    pub direction: String,
    /// Seed of the phase generator (u64).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Sample spacing, m (> 0).
    #[arg(long, default_value_t = 0.1, allow_negative_numbers = true)]
    pub dx: f64,
    /// Profile length, m (> 0); rows x = 0, dx, 2 dx, … ≤ length.
    #[arg(long, default_value_t = 1000.0, allow_negative_numbers = true)]
    pub length: f64,
    /// Override Table 1's A_r, m²·rad/m.
    #[arg(long, allow_negative_numbers = true)]
    pub ar: Option<f64>,
    /// Override Table 1's ω1, rad/m.
    #[arg(long, allow_negative_numbers = true)]
    pub omega1: Option<f64>,
    /// Override Table 1's ω2, rad/m.
    #[arg(long, allow_negative_numbers = true)]
    pub omega2: Option<f64>,
    /// Override Table 1's ω_l, rad/m.
    #[arg(long = "omega-l", allow_negative_numbers = true)]
    pub omega_l: Option<f64>,
    /// Override Table 1's ω_u, rad/m.
    #[arg(long = "omega-u", allow_negative_numbers = true)]
    pub omega_u: Option<f64>,
    /// Override Table 1's number of terms N (at most 2000).
    #[arg(long)]
    pub n: Option<usize>,
}

/// Parse `y`/`z` (any case).
pub fn parse_direction(s: &str) -> Result<Direction, String> {
    match s.trim().to_ascii_lowercase().as_str() {
        "y" => Ok(Direction::Y),
        "z" => Ok(Direction::Z),
        _ => Err(format!("unknown direction {s:?}: expected y or z")),
    }
}

/// Number of rows: x_j = j·dx for j = 0..count with x_j ≤ length (to a relative 1e-9 of dx,
/// so that `--length 1000 --dx 0.1` ends at x = 1000 despite 0.1 not being exact in binary).
pub fn sample_count(dx: f64, length: f64) -> Result<usize, String> {
    if !dx.is_finite() || dx <= 0.0 {
        return Err(format!(
            "--dx must be a positive finite number of metres, got {dx}"
        ));
    }
    if !length.is_finite() || length <= 0.0 {
        return Err(format!(
            "--length must be a positive finite number of metres, got {length}"
        ));
    }
    let last = (length / dx + 1e-9).floor();
    if last + 1.0 > MAX_SAMPLES as f64 {
        return Err(format!(
            "--length/--dx gives {} samples, more than the limit {MAX_SAMPLES}",
            last + 1.0
        ));
    }
    Ok(last as usize + 1)
}

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

/// Decimal places of `dx`'s shortest representation (capped at 17): x is printed with these
/// so that `--dx 0.1` prints `0.3`, not `0.30000000000000004`. The profile is evaluated at
/// j·dx exactly; the printed x differs from it by less than 1e-15 relative.
fn decimals(dx: f64) -> usize {
    let s = format!("{dx}");
    s.split_once('.').map_or(0, |(_, f)| f.len()).min(17)
}

fn params_from(a: &Args, direction: Direction) -> PsdParams {
    let mut p = PsdParams::table1(direction);
    if let Some(v) = a.ar {
        p.a_r = v;
    }
    if let Some(v) = a.omega1 {
        p.omega1 = v;
    }
    if let Some(v) = a.omega2 {
        p.omega2 = v;
    }
    if let Some(v) = a.omega_l {
        p.omega_l = v;
    }
    if let Some(v) = a.omega_u {
        p.omega_u = v;
    }
    if let Some(v) = a.n {
        p.n = v;
    }
    p
}

/// Run the subcommand: CSV with header `x,r` to stdout.
pub fn run(a: Args) -> Result<(), String> {
    let direction = parse_direction(&a.direction)?;
    let count = sample_count(a.dx, a.length)?;
    let params = params_from(&a, direction);
    // The generator holds 2000 terms of 24 bytes; keep it off the stack.
    let mut g: Box<Irregularity<f64>> = Box::default();
    g.rebuild(&params, direction, a.seed, 0.0)
        .map_err(|e| format!("invalid irregularity parameters: {e}"))?;
    let prec = decimals(a.dx);
    let stdout = std::io::stdout();
    let mut w = BufWriter::with_capacity(1 << 16, stdout.lock());
    let io = |e: std::io::Error| format!("writing the profile failed: {e}");
    writeln!(w, "x,r").map_err(io)?;
    sweep(&g, a.dx, count, |_, x, r| writeln!(w, "{x:.prec$},{r:e}")).map_err(io)?;
    w.flush().map_err(io)
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
    fn counts_and_validation() {
        assert_eq!(sample_count(0.1, 1000.0).unwrap(), 10_001);
        assert_eq!(sample_count(0.3, 1.0).unwrap(), 4);
        assert_eq!(sample_count(2.0, 1.0).unwrap(), 1);
        for (dx, len) in [
            (0.0, 1.0),
            (-0.1, 1.0),
            (f64::NAN, 1.0),
            (0.1, -1.0),
            (0.1, 0.0),
            (0.1, f64::INFINITY),
            (1e-9, 1e3),
        ] {
            let e = sample_count(dx, len).unwrap_err();
            assert!(!e.contains('\n'), "{e}");
        }
        assert_eq!(parse_direction("Y").unwrap(), Direction::Y);
        assert_eq!(parse_direction("z").unwrap(), Direction::Z);
        assert!(parse_direction("x").unwrap_err().contains("direction"));
        assert_eq!(decimals(0.1), 1);
        assert_eq!(decimals(0.25), 2);
        assert_eq!(decimals(1.0), 0);
    }
}
