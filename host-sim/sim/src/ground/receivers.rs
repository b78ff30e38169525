//! Receivers: each receiver's vertical surface velocity is the sum over the piers of the
//! half-space Green's function ([`super::green`]) applied to that pier's vertical base force,
//! computed in the frequency domain (docs/ground.md, "Receivers").
//!
//! - **The force.** Pier k pushes the soil down with P_k(t) = −(k_z z_k + c_z ż_k), the force
//!   in its footing's vertical spring and dashpot (z up, so a footing pressed down pushes
//!   down); [`BaseForces`] records it at every committed step.
//! - **Before and after the record.** The force is zero before t = 0 (the run starts at rest)
//!   and holds its last value after the record: its spectrum is that of its increments
//!   d_j = P_j − P_{j−1} (P_{−1} = 0), F(ω) = D(ω)/(1 − e^{−iωΔt}), so no jump of the
//!   padded record back to zero is ever seen by the soil.
//! - **The velocity.** V(ω) = iω·Σ_k G(ω, r_k)·F_k(ω), i.e. Σ_k G·D_k·iω/(1 − e^{−iωΔt}),
//!   on the grid of one real FFT (`realfft`) of length M, inverse-transformed; velocity
//!   positive **up** (the project's Z). At 0 Hz and at the Nyquist bin the real part is
//!   kept (a real signal's spectrum is real there; the hysteretic μ* is taken as μ at 0 Hz).
//! - **Padding (nothing wraps around).** M is the smallest power of two
//!   ≥ N + ⌈(2·r_max/c_R + 1 s)/Δt⌉: every wave from the farthest pier (the Rayleigh wave,
//!   the slowest, at r_max/c_R) has arrived and twice that time has passed before the
//!   circular convolution could bring the end of the padded window back onto the record.
//!   host-sim/sim/tests/ground_receivers.rs checks that doubling M changes nothing visible.
//! - **The Green's function once per frequency bin and distance.** W depends on
//!   x = 2πfr/c_s only (green.rs, (G2)), so it is read from one table per soil
//!   ([`super::table`]: within 1e-5 of the direct evaluation, W = 0 beyond its cut-off) for
//!   every (bin, pier–receiver distance) pair; bins beyond the cut-off are skipped. The
//!   table comes from a [`Tables`] cache the caller may keep across runs.
//! - **Threads.** The receivers are independent: [`velocities_with`] and [`of_runs`] share
//!   them among scoped threads in contiguous chunks; each receiver's arithmetic is the same on
//!   any thread, so every count gives the same bits (no thread pool is kept).

use super::green::{complex_shear_modulus, Green};
use super::table::{Table, Tables};
use crate::physics::fe::soil::Soil;
use crate::probes::{Recorder, StepView};
use crate::{Error, Result};
use realfft::RealFftPlanner;
use rustfft::num_complex::Complex64 as C;
use std::f64::consts::PI;

/// Records the vertical force each pier's footing pushes into the soil at every step.
pub struct BaseForces {
    /// Footing vertical spring (N/m) and dashpot (N·s/m).
    stiffness: f64,
    damping: f64,
    piers: usize,
    /// The time of every recorded step (s).
    pub t: Vec<f64>,
    /// Per pier, the downward force (N) at every recorded step.
    pub forces: Vec<Vec<f64>>,
}

impl BaseForces {
    /// For `piers` piers on footings of vertical stiffness `stiffness` and dashpot `damping`.
    pub fn new(piers: usize, stiffness: f64, damping: f64) -> Self {
        BaseForces {
            stiffness,
            damping,
            piers,
            t: Vec::new(),
            forces: vec![Vec::new(); piers],
        }
    }
}

impl Recorder for BaseForces {
    fn record(&mut self, step: &StepView) -> Result<()> {
        self.t.push(step.t);
        for k in 0..self.piers {
            let b = step.guideway.pier_base(k + 1).ok_or_else(|| {
                Error::numerical(format!("ground: the guideway has no pier {}", k + 1))
            })?;
            self.forces[k].push(-(self.stiffness * b.z + self.damping * b.vz));
        }
        Ok(())
    }
}

/// The padded FFT length for `n` samples at `dt` and a farthest pier `r_max` away on `soil`
/// (module docs), and the Rayleigh speed it used.
pub fn padded_length(n: usize, dt: f64, r_max: f64, soil: &Soil, green: &Green) -> Result<usize> {
    let c_r = soil.shear_wave_velocity / green.rayleigh_pole()?.re;
    let extra = ((2.0 * r_max / c_r + 1.0) / dt).ceil();
    let m = (n as f64 + extra).max(2.0);
    if m > 1e9 {
        return Err(Error::invalid(
            "ground",
            format!("the padded record would hold {m:.3e} samples (farthest pier {r_max} m away)"),
        ));
    }
    Ok((m as usize).next_power_of_two())
}

/// The vertical velocity (m/s, up) at each receiver at each of the `n` samples, from the
/// downward forces `forces[k][j]` (N) of piers at `piers[k]` (x, y in m), sampled at `dt`,
/// on `soil`, with the FFT length `m` (at least [`padded_length`]'s; module docs): on one
/// thread with a table of its own ([`velocities_with`] takes both).
pub fn velocities(
    soil: &Soil,
    dt: f64,
    forces: &[Vec<f64>],
    piers: &[[f64; 2]],
    receivers: &[[f64; 2]],
    m: usize,
) -> Result<Vec<Vec<f64>>> {
    velocities_with(&mut Tables::new(), 1, soil, dt, forces, piers, receivers, m)
}

/// [`velocities`] with the table of W taken from (and left in) `tables`, the receivers
/// shared among `threads` threads (the same bits for every count and every cache).
#[allow(clippy::too_many_arguments)]
pub fn velocities_with(
    tables: &mut Tables,
    threads: usize,
    soil: &Soil,
    dt: f64,
    forces: &[Vec<f64>],
    piers: &[[f64; 2]],
    receivers: &[[f64; 2]],
    m: usize,
) -> Result<Vec<Vec<f64>>> {
    let x = x_max(soil, dt, piers, receivers, m);
    let table = tables.get(soil.poisson, soil.damping, x)?;
    Record::new(soil, dt, forces, piers, m)?.at(table, receivers, threads)
}

/// The farthest pier–receiver distance (m).
fn r_max(piers: &[[f64; 2]], receivers: &[[f64; 2]]) -> f64 {
    receivers
        .iter()
        .flat_map(|q| piers.iter().map(move |p| (p[0] - q[0]).hypot(p[1] - q[1])))
        .fold(0.0, f64::max)
}

/// The largest x = ωr/c_s the receivers need: the Nyquist bin of an `m`-point FFT at `dt`
/// times the farthest distance.
fn x_max(soil: &Soil, dt: f64, piers: &[[f64; 2]], receivers: &[[f64; 2]], m: usize) -> f64 {
    let df = 1.0 / (m as f64 * dt);
    2.0 * PI * (m / 2) as f64 * df * r_max(piers, receivers) / soil.shear_wave_velocity
}

/// One record's pier spectra, ready to be carried to any receiver.
struct Record<'a> {
    soil: &'a Soil,
    piers: &'a [[f64; 2]],
    n: usize,
    m: usize,
    df: f64,
    /// Per pier, the increments' spectrum times iω/(1 − e^{−iωΔt}) (module docs).
    spectra: Vec<Vec<C>>,
}

impl<'a> Record<'a> {
    fn new(
        soil: &'a Soil,
        dt: f64,
        forces: &[Vec<f64>],
        piers: &'a [[f64; 2]],
        m: usize,
    ) -> Result<Self> {
        let n = forces.first().map_or(0, Vec::len);
        if forces.len() != piers.len() || forces.iter().any(|f| f.len() != n) || n == 0 || m < n {
            return Err(Error::invalid(
                "ground",
                "every pier needs one force history of the record's length",
            ));
        }
        let df = 1.0 / (m as f64 * dt);
        let fwd = RealFftPlanner::<f64>::new().plan_fft_forward(m);
        let mut spectra = Vec::with_capacity(piers.len());
        for f in forces {
            let mut d = vec![0.0; m];
            let mut last = 0.0;
            for (j, &p) in f.iter().enumerate() {
                d[j] = p - last;
                last = p;
            }
            let mut s = fwd.make_output_vec();
            fwd.process(&mut d, &mut s)
                .map_err(|e| Error::numerical(format!("ground FFT: {e}")))?;
            for (i, v) in s.iter_mut().enumerate() {
                let w = 2.0 * PI * i as f64 * df;
                *v *= if i == 0 {
                    C::new(1.0 / dt, 0.0)
                } else {
                    C::new(0.0, w) / (1.0 - C::from_polar(1.0, -w * dt))
                };
            }
            spectra.push(s);
        }
        Ok(Record {
            soil,
            piers,
            n,
            m,
            df,
            spectra,
        })
    }

    /// The velocities at `receivers`, shared among `threads` threads in contiguous chunks
    /// (each receiver's arithmetic is the same whichever thread does it).
    fn at(&self, table: &Table, receivers: &[[f64; 2]], threads: usize) -> Result<Vec<Vec<f64>>> {
        if receivers.is_empty() {
            return Ok(Vec::new());
        }
        let inv = RealFftPlanner::<f64>::new().plan_fft_inverse(self.m);
        let chunk = receivers.len().div_ceil(threads.clamp(1, receivers.len()));
        let one = |qs: &[[f64; 2]]| -> Result<Vec<Vec<f64>>> {
            qs.iter().map(|q| self.receiver(table, &*inv, q)).collect()
        };
        let parts: Vec<Result<Vec<Vec<f64>>>> = std::thread::scope(|s| {
            let handles: Vec<_> = receivers
                .chunks(chunk)
                .map(|qs| s.spawn(move || one(qs)))
                .collect();
            handles
                .into_iter()
                .map(|h| {
                    h.join()
                        .unwrap_or_else(|_| Err(Error::numerical("ground: a thread panicked")))
                })
                .collect()
        });
        let mut out = Vec::with_capacity(receivers.len());
        for p in parts {
            out.extend(p?);
        }
        Ok(out)
    }

    /// One receiver's velocity: Σ over the piers of G·spectrum, inverse-transformed.
    fn receiver(
        &self,
        table: &Table,
        inv: &dyn realfft::ComplexToReal<f64>,
        q: &[f64; 2],
    ) -> Result<Vec<f64>> {
        let bins = self.m / 2 + 1;
        let mu = complex_shear_modulus(self.soil);
        let c_s = self.soil.shear_wave_velocity;
        let mut v = vec![C::new(0.0, 0.0); bins];
        for (p, s) in self.piers.iter().zip(&self.spectra) {
            let r = (p[0] - q[0]).hypot(p[1] - q[1]);
            if r <= 0.0 {
                return Err(Error::invalid("ground", "a receiver stands on a pier"));
            }
            let g0 = (1.0 - self.soil.poisson) / (2.0 * PI * r * self.soil.shear_modulus());
            v[0] += s[0] * g0;
            let dx = 2.0 * PI * self.df * r / c_s;
            add_pier(table, dx, C::new(1.0, 0.0) / (2.0 * PI * r * mu), s, &mut v);
        }
        // Real at 0 Hz and Nyquist (module docs); displacement down → velocity up: minus.
        v[0].im = 0.0;
        // M is a power of two (≥ 2): the last bin is the Nyquist bin.
        v[bins - 1].im = 0.0;
        let mut t = vec![0.0; self.m];
        inv.process(&mut v, &mut t)
            .map_err(|e| Error::numerical(format!("ground inverse FFT: {e}")))?;
        Ok(t[..self.n].iter().map(|x| -x / self.m as f64).collect())
    }
}

/// Bins between exact phases of the recurrence in [`add_pier`].
const REANCHOR: usize = 256;

/// v[i] += scale·W(i·dx)·s[i] for the bins i ≥ 1 below the table's cut-off. The phase
/// e^{−i·Re(q_R)·x} that [`Table::shifted`] leaves out is carried from bin to bin by one
/// complex product, set exactly every [`REANCHOR`] bins (its round-off stays below 1e-13).
fn add_pier(table: &Table, dx: f64, scale: C, s: &[C], v: &mut [C]) {
    let bins = v.len();
    let stop = table
        .end()
        .map_or(bins, |e| ((e / dx).ceil() as usize).clamp(1, bins));
    let turn = C::from_polar(1.0, -table.phase() * dx);
    let mut z = scale;
    for i in 1..stop {
        let x = i as f64 * dx;
        z = if i % REANCHOR == 1 {
            scale * C::from_polar(1.0, -table.phase() * x)
        } else {
            z * turn
        };
        v[i] += table.shifted(x) * z * s[i];
    }
}

/// ground.csv: `t` and one column `ground{N}.vz` per receiver (m/s, up), shortest
/// round-trip decimals as response.csv.
pub fn csv(t: &[f64], v: &[Vec<f64>]) -> String {
    let mut line = Vec::new();
    line.extend_from_slice(b"t");
    for i in 0..v.len() {
        line.extend_from_slice(format!(",ground{}.vz", i + 1).as_bytes());
    }
    line.push(b'\n');
    for (j, &tj) in t.iter().enumerate() {
        crate::probes::push_csv_f64(&mut line, tj);
        for r in v {
            line.push(b',');
            crate::probes::push_csv_f64(&mut line, r[j]);
        }
        line.push(b'\n');
    }
    String::from_utf8(line).unwrap_or_default()
}

/// The receivers' velocities of a viaduct run: piers at x = k·`span` (k = 0 … piers − 1,
/// y = 0), the recorded base forces, padding by [`padded_length`]; one thread, a table of its
/// own ([`of_runs`] shares one).
pub fn of_run(
    soil: &Soil,
    span: f64,
    rec: &BaseForces,
    receivers: &[[f64; 2]],
) -> Result<Vec<Vec<f64>>> {
    Ok(of_runs(&mut Tables::new(), soil, span, &[rec], receivers, 1)?.remove(0))
}

/// [`of_run`] for several runs on the same soil and viaduct (the report's two trains): one
/// table of W from `tables` for all, each run's receivers shared among `threads` threads
/// (the same bits as run by run, on one thread, with a new cache).
pub fn of_runs(
    tables: &mut Tables,
    soil: &Soil,
    span: f64,
    recs: &[&BaseForces],
    receivers: &[[f64; 2]],
    threads: usize,
) -> Result<Vec<Vec<Vec<f64>>>> {
    let green = Green::new(soil.poisson, soil.damping)?;
    let mut jobs = Vec::with_capacity(recs.len());
    for rec in recs {
        let piers: Vec<[f64; 2]> = (0..rec.piers).map(|k| [k as f64 * span, 0.0]).collect();
        let n = rec.t.len();
        if n < 2 {
            return Err(Error::invalid(
                "ground",
                "the run recorded fewer than 2 steps",
            ));
        }
        let dt = (rec.t[n - 1] - rec.t[0]) / (n - 1) as f64;
        let m = padded_length(n, dt, r_max(&piers, receivers), soil, &green)?;
        jobs.push((piers, dt, m));
    }
    let x = jobs
        .iter()
        .map(|(p, dt, m)| x_max(soil, *dt, p, receivers, *m))
        .fold(0.0, f64::max);
    let table = tables.get(soil.poisson, soil.damping, x)?;
    recs.iter()
        .zip(&jobs)
        .map(|(rec, (piers, dt, m))| {
            Record::new(soil, *dt, &rec.forces, piers, *m)?.at(table, receivers, threads)
        })
        .collect()
}
