//! What bounds the f32 instruction count: the same Eq. 14 step without the core's per-operation
//! saturation checks, status bookkeeping and sub-step loop — an experiment, never a controller.
//!
//! [`Unchecked`] holds the core's run-time coefficients for `n_sub = 1` (same f64 formulas,
//! converted once to f32) and [`update_unchecked`] performs the core's operations in the
//! core's order on plain f32, so wherever no check of the core fires its results are
//! bit-identical — the self-test verifies that on every step of the trace without events and
//! prints the instruction count next to the core's (docs/hil.md, "Instruction budget").
use maglev_core::Params;

/// Run-time coefficients for one sub-step (`1 + kpd` and `1 + cα(1 + kph)` pre-added).
#[derive(Clone, Copy, Debug)]
pub struct Unchecked {
    one_kpd: f32,
    one_ca1: f32,
    c: f32,
    ca: f32,
    kih: f32,
    kpv: f32,
}

impl Unchecked {
    /// Coefficients of `p` with `n_sub` taken as 1 (the core's `Params::coefficients`).
    pub fn new(p: &Params) -> Self {
        let (vb, g0, d) = (p.v_base(), p.g0(), p.dt);
        let c = vb * d / (2.0 * p.k0() * g0);
        let kph = (p.kp + p.ki * d / 2.0) * g0 / vb;
        Unchecked {
            one_kpd: 1.0 + ((p.kp + p.ki * d) * g0 / vb) as f32,
            one_ca1: 1.0 + (c * p.alpha * (1.0 + kph)) as f32,
            c: c as f32,
            ca: (c * p.alpha) as f32,
            kih: (p.ki * g0 * d / (2.0 * vb)) as f32,
            kpv: (p.kp * g0 / vb) as f32,
        }
    }
}

/// State `(x, y)` and per-unit gap `h`; returns `(x, y, v, force, current)` after one step.
#[inline(never)]
pub fn update_unchecked(k: &Unchecked, xy: &mut [f32; 2], h: f32) -> [f32; 3] {
    let [x, y] = *xy;
    let eta = h - 1.0;
    let num = (y - eta) - x * (k.one_kpd + eta);
    let den = k.one_ca1 + k.ca * eta;
    let x1 = x + (k.c * num) / den;
    let x1 = if x1 < -1.0 { -1.0 } else { x1 }; // current never negative, as in the core
    let y1 = y - k.kih * (x + x1);
    let v1 = (1.0 + y1) - k.kpv * x1;
    *xy = [x1, y1];
    let g = 1.0 + x1;
    [v1, g * g, g * (1.0 + eta)]
}

/// Runs the paper trace through the core (f32) and [`update_unchecked`] side by side; prints
/// whether they agree bit for bit on every step without events and the unchecked step's
/// instruction counts. Returns whether they agreed.
pub fn compare<W: core::fmt::Write, M: crate::board::selftest::Measure>(
    w: &mut W,
    m: &M,
) -> Result<bool, core::fmt::Error> {
    use crate::board::selftest::{gap, Config, STEPS};
    use maglev_core::Scalar;
    let p = Config::Paper.params();
    let Ok(ctrl) = p.compile::<f32>() else {
        writeln!(w, "lower bound: paper parameters do not compile")?;
        return Ok(false);
    };
    let k = Unchecked::new(&p);
    let mut st = ctrl.initial_state(p.h0);
    let mut xy = [st.x, st.y];
    let (mut same, mut compared) = (true, 0);
    let (mut lo, mut hi) = (u32::MAX, 0);
    for step in 1..=STEPS {
        let mut ov = false;
        let h = f32::from_f64(gap(step), &mut ov);
        let out = ctrl.update(&mut st, h);
        let mut r = [0.0; 3];
        let n = m.count(&mut || r = update_unchecked(&k, &mut xy, h));
        if !out.status.is_empty() {
            xy = [st.x, st.y]; // resynchronise after an event the experiment does not model
            continue;
        }
        compared += 1;
        let core = [st.x, st.y, st.v, out.force, out.current].map(f32::to_bits);
        same &= core == [xy[0], xy[1], r[0], r[1], r[2]].map(f32::to_bits);
        if let Some(n) = n {
            (lo, hi) = (lo.min(n), hi.max(n));
        }
    }
    if hi > 0 {
        write!(w, "insns f32/n1 unchecked straight-line step: {lo}..{hi}")?;
    } else {
        write!(w, "insns f32/n1 unchecked straight-line step: not measured")?;
    }
    let verdict = if same { "bit-identical" } else { "DIFFERENT" };
    writeln!(
        w,
        "; {verdict} to the core on {compared} steps without events"
    )?;
    Ok(same)
}
