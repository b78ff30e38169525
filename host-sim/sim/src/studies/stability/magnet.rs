//! One magnet's law, linearised, as rows of a closed-loop state matrix: the one place the
//! analyses write Eq. 9–10 (with the gap loop's reference) in continuous time.
//!
//! Per unit (`x = g/g0 − 1`, `y = KI·e_a/(R0·i0) − 1`, `η = h/h0 − 1`, [`super::inner_loop`]), with
//! the reference `x_ref` of the outer gap loop (`maglev_core::gap_control`, Eq. 8 with
//! `e = g_ref − g`) and the outer loop's derivative filter state `q`:
//!
//! ```text
//! τ·ẋ  = y − η − p·x + kpv·x_ref,      ẏ = ki·(x_ref − x),      p = 1 + kpv
//! x_ref = kp·η + (kd/tf)·(η − q),      tf·q̇ = η − q             (gap loop; 0 and no q for
//!                                                                 the paper's law)
//! ```
//!
//! `η` is a linear function of the mechanical states (the caller gives its row, from the core's
//! `maglev_core::gap` geometry). The magnet's force change is `ΔG = 2·p0·x` (Eq. 1 linearised,
//! `G = p0·(1 + x)²`), which the caller adds to its force rows.

use super::inner_loop::Loop;
use maglev_core::gap_control::GapParams;
use maglev_core::law::guidance::GuidanceParams;
use maglev_core::law::state::StateParams;
use maglev_core::Params;
use nalgebra::DMatrix;

/// Where one magnet's states sit in the closed-loop state vector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slots {
    /// The flux deviation `x`.
    pub x: usize,
    /// The integral state `y`.
    pub y: usize,
    /// The gap loop's filter state `q` (gap loop only).
    pub q: Option<usize>,
    /// A first-order Padé delay `δ` (s) on the reference and its state `w` (gap loop only):
    /// the inner law sees `x_ref,δ = 2·w − x_ref`, `(δ/2)·ẇ = x_ref − w`, i.e.
    /// `x_ref·(1 − sδ/2)/(1 + sδ/2) ≈ x_ref·e^{−sδ}` — the sampled loop's hold (docs/gap-loop.md).
    pub delay: Option<(usize, f64)>,
}

/// Writes the rows of `x`, `y` (and `q`) of one magnet into `a` (overwriting them): the law of
/// `lp` on the gap `η = Σ eta[j]·state[j]`, alone (`gains = None`, the paper's Eq. 8–10) or
/// under the gap loop (`gains`, `tf > 0` and a `q` slot required). Returns the law's voltage
/// change as a row over the state, `Δv = y + kpv·(x_ref − x)` (the part of `τ·ẋ` that is not
/// the coil's own `−η − x`).
pub fn write_rows(
    a: &mut DMatrix<f64>,
    at: Slots,
    eta: &[(usize, f64)],
    lp: &Loop,
    gains: Option<&GapParams>,
) -> crate::Result<Vec<f64>> {
    let n = a.ncols();
    let mut eta_row = vec![0.0; n];
    for &(j, e) in eta {
        eta_row[j] += e;
    }
    // x_ref as a row over the state.
    let mut r = vec![0.0; n];
    match (gains, at.q) {
        (None, _) => {}
        (Some(g), Some(iq)) => {
            if g.tf.is_nan() || g.tf <= 0.0 {
                return Err(crate::Error::invalid(
                    "gap_loop.tf",
                    format!(
                        "the analysis needs a derivative filter tf > 0, got {}",
                        g.tf
                    ),
                ));
            }
            let kdf = g.kd / g.tf;
            for (rj, ej) in r.iter_mut().zip(&eta_row) {
                *rj = (g.kp + kdf) * ej;
            }
            r[iq] -= kdf;
            for j in 0..n {
                a[(iq, j)] = eta_row[j] / g.tf;
            }
            a[(iq, iq)] -= 1.0 / g.tf;
        }
        (Some(_), None) => {
            return Err(crate::Error::numerical(
                "internal: a gap-loop magnet needs a q slot",
            ))
        }
    }
    if let Some((iw, d)) = at.delay {
        if gains.is_some() {
            if d.is_nan() || d <= 0.0 {
                return Err(crate::Error::invalid(
                    "delay",
                    format!("the reference delay must be > 0, got {d} s"),
                ));
            }
            for j in 0..n {
                a[(iw, j)] = 2.0 * r[j] / d;
            }
            a[(iw, iw)] -= 2.0 / d;
            for rj in r.iter_mut() {
                *rj = -*rj;
            }
            r[iw] += 2.0;
        }
    }
    let kpv = lp.p - 1.0;
    for j in 0..n {
        a[(at.x, j)] = (kpv * r[j] - eta_row[j]) / lp.tau;
        a[(at.y, j)] = lp.ki * r[j];
    }
    a[(at.x, at.x)] -= lp.p / lp.tau;
    a[(at.x, at.y)] += 1.0 / lp.tau;
    a[(at.y, at.x)] -= lp.ki;
    let mut dv: Vec<f64> = r.iter().map(|rj| kpv * rj).collect();
    dv[at.x] -= kpv;
    dv[at.y] += 1.0;
    Ok(dv)
}

/// What one magnet under the state law reads, as rows over the closed-loop state: the gap
/// `η`, its rate `η̇` (exact: the ideal sensor of the analysis), and the magnet's absolute
/// acceleration in m/s² where it is measured (the levitation magnets; `None` for guidance).
pub struct StateSensors<'a> {
    pub eta: &'a [f64],
    pub eta_rate: &'a [f64],
    pub accel: Option<&'a [f64]>,
}

/// Writes the rows of `x` and of the integral `u` (in `at.y`) of one magnet under the state
/// law (`maglev_core::law::state`), continuous time, ideal sensors, linearised about the
/// magnet's equilibrium at h0 (`x = 0`, `i = i0`):
///
/// ```text
/// τ·ẋ = Δv − η − x,     Δv = Kp·η + Kd·η̇ − (ka/V_b)·a + u − Kc·(x + η),     u̇ = Ki·η
/// Kp = kp·h0/V_b,  Kd = kd·h0/V_b,  Ki = ki·h0/V_b,  Kc = kc·i0/V_b
/// ```
/// (`Δi/i0 = x + η`, the coil's current `g·h` linearised; τ the coil's time constant.) The
/// voltage bound is not active in a linear model. Returns `Δv` as a row over the state.
pub fn write_state_rows(
    a: &mut DMatrix<f64>,
    at: Slots,
    sensors: &StateSensors,
    lp: &Loop,
    law: &StateParams,
    magnet: &Params,
) -> Vec<f64> {
    let vb = magnet.v_base();
    let (h0, i0) = (magnet.h0, magnet.i0);
    let (kp, kd, ki, kc) = (
        law.kp * h0 / vb,
        law.kd * h0 / vb,
        law.ki * h0 / vb,
        law.kc * i0 / vb,
    );
    let mut x_row: Vec<f64> = sensors
        .eta
        .iter()
        .zip(sensors.eta_rate)
        .map(|(e, r)| (kp - kc - 1.0) * e + kd * r)
        .collect();
    if let Some(acc) = sensors.accel {
        for (xj, aj) in x_row.iter_mut().zip(acc) {
            *xj -= law.ka / vb * aj;
        }
    }
    x_row[at.x] -= 1.0 + kc;
    x_row[at.y] += 1.0;
    for (j, v) in x_row.iter().enumerate() {
        a[(at.x, j)] = v / lp.tau;
        a[(at.y, j)] = ki * sensors.eta[j];
    }
    // Δv = τ·ẋ + η + x: the row less the coil's own terms.
    let mut dv = x_row;
    for (d, e) in dv.iter_mut().zip(sensors.eta) {
        *d += e;
    }
    dv[at.x] += 1.0;
    dv
}

/// What a guidance pair under the guidance law reads, as rows over the closed-loop state:
/// each magnet's gap `[η_L, η_R]` and its rate (exact), and the pair's absolute lateral
/// acceleration in m/s² (+Y) where it has an accelerometer.
pub struct PairSensors<'a> {
    pub eta: [&'a [f64]; 2],
    pub eta_rate: [&'a [f64]; 2],
    pub accel: Option<&'a [f64]>,
}

/// Writes the rows of both coils `x = [x_L, x_R]` and of the pair's integral `u` of a
/// guidance pair under the guidance law (`maglev_core::law::guidance`, G1–G3), continuous
/// time, ideal sensors, linearised about the pair's equilibrium at `d = 0`:
///
/// ```text
/// τ·ẋ_k = Δv_k − η_k − x_k,     Δv_L = Δv_c + Δv_d,  Δv_R = Δv_c − Δv_d
/// Δv_d = Kp·η_d + Kd·η̇_d + (ka/V_b)·a_y + u − Kc·Δi_d,   Δv_c = −Kc·Δi_c,   u̇ = Ki·η_d
/// η_d = (η_L − η_R)/2,  Δi_d = (Δi_L − Δi_R)/2,  Δi_c = (Δi_L + Δi_R)/2,  Δi_k = x_k + η_k
/// ```
/// (per-unit gains as [`write_state_rows`]'). Returns `[Δv_L, Δv_R]` as rows over the state.
pub fn write_guidance_rows(
    a: &mut DMatrix<f64>,
    x: [usize; 2],
    u: usize,
    sensors: &PairSensors,
    lp: &Loop,
    law: &GuidanceParams,
    magnet: &Params,
) -> [Vec<f64>; 2] {
    let n = a.ncols();
    let vb = magnet.v_base();
    let (h0, i0) = (magnet.h0, magnet.i0);
    let (kp, kd, ki, kc) = (
        law.kp * h0 / vb,
        law.kd * h0 / vb,
        law.ki * h0 / vb,
        law.kc * i0 / vb,
    );
    let [el, er] = sensors.eta;
    let [rl, rr] = sensors.eta_rate;
    // Δi_k as rows.
    let di = |k: usize, eta: &[f64]| -> Vec<f64> {
        let mut r = eta.to_vec();
        r[x[k]] += 1.0;
        r
    };
    let (di_l, di_r) = (di(0, el), di(1, er));
    let mut dv_d = vec![0.0; n];
    let mut dv_c = vec![0.0; n];
    for j in 0..n {
        let eta_d = 0.5 * (el[j] - er[j]);
        let rate_d = 0.5 * (rl[j] - rr[j]);
        dv_d[j] = kp * eta_d + kd * rate_d - kc * 0.5 * (di_l[j] - di_r[j]);
        dv_c[j] = -kc * 0.5 * (di_l[j] + di_r[j]);
        a[(u, j)] = ki * eta_d;
    }
    if let Some(acc) = sensors.accel {
        for (d, aj) in dv_d.iter_mut().zip(acc) {
            *d += law.ka / vb * aj;
        }
    }
    dv_d[u] += 1.0;
    let dv_l: Vec<f64> = dv_c.iter().zip(&dv_d).map(|(c, d)| c + d).collect();
    let dv_r: Vec<f64> = dv_c.iter().zip(&dv_d).map(|(c, d)| c - d).collect();
    for (k, (dv, eta)) in [(&dv_l, el), (&dv_r, er)].into_iter().enumerate() {
        for j in 0..n {
            a[(x[k], j)] = (dv[j] - eta[j]) / lp.tau;
        }
        a[(x[k], x[k])] -= 1.0 / lp.tau;
    }
    [dv_l, dv_r]
}
