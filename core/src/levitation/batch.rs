//! Several magnets' paper-scheme updates at once, for hosts: the internal loop of Eq. 14 is a
//! dependent chain (`x → N → Δx → x`, with a division in it), so one controller runs at the
//! chain's latency, about 13 ns a sub-step in f64. Independent magnets interleaved in one loop
//! fill the pipeline instead (docs/performance.md).
//!
//! [`update_batch`] gives exactly the bits of [`Levitation::update`] on each magnet in turn:
//! each lane performs the general path's operations in its order (floats, no contraction),
//! and a lane that meets any event — a gap the update would clamp or refuse, the current
//! floor, the voltage bound, a value no longer finite — is recomputed by
//! [`Levitation::update`] from its saved state. The firmware's path is not touched.

use super::accurate::Gap;
use super::{Interpolation, Levitation, Output, Scheme, State, Status};

/// Magnets interleaved per loop.
pub const LANES: usize = 4;

/// One outer step of every magnet `i` with its own controller `ctl[i]`, state `st[i]` and
/// per-unit gap `h[i]` at the end of the step: `out[i]` is what `ctl[i].update(&mut st[i],
/// h[i])` returns, bit for bit. Controllers under [`Scheme::Accurate`] take [`accurate`]
/// (the Gauss step unchecked, checked once); those with a different `n_sub` than the first
/// magnet's simply take [`Levitation::update`].
pub fn update_batch(
    ctl: &[Levitation<f64>],
    st: &mut [State<f64>],
    h: &[f64],
    out: &mut [Output<f64>],
) {
    let n = ctl.len();
    assert!(st.len() == n && h.len() == n && out.len() == n);
    let n_sub = ctl.first().map_or(1, |c| c.params.n_sub);
    // Lanes the interleaved loop can take; the rest run alone.
    let mut lane = [0usize; LANES];
    let mut fill = 0;
    for i in 0..n {
        let c = &ctl[i];
        if c.params.scheme == Scheme::Accurate {
            out[i] = accurate(c, &mut st[i], h[i]);
            continue;
        }
        let ok = c.params.scheme == Scheme::Paper
            && c.params.n_sub == n_sub
            && h[i] > 0.0
            && h[i] <= c.h_max;
        if !ok {
            out[i] = c.update(&mut st[i], h[i]);
            continue;
        }
        lane[fill] = i;
        fill += 1;
        if fill == LANES {
            chunk(ctl, st, h, out, &lane, n_sub);
            fill = 0;
        }
    }
    for &i in &lane[..fill] {
        out[i] = ctl[i].update(&mut st[i], h[i]);
    }
}

/// One accurate-scheme update: [`Levitation::update`]'s general path (`advance` without a
/// reference) for a gap `0 < h ≤ h_max`, with the Gauss step in plain f64
/// (`Gauss::step_nominal`); any event or non-finite value (and any other gap) goes to
/// [`Levitation::update`] from the untouched state. The same bits either way.
fn accurate(c: &Levitation<f64>, st: &mut State<f64>, h: f64) -> Output<f64> {
    if !(h > 0.0 && h <= c.h_max) {
        return c.update(st, h);
    }
    let eta1 = h - 1.0;
    let eta0 = st.eta;
    let (b1, b2) = match c.params.interpolation {
        Interpolation::Linear => (eta1 - eta0, 0.0),
        Interpolation::Parabolic => {
            let m = st.eta_prev;
            ((eta1 - m) * c.half, ((eta1 - (eta0 + eta0)) + m) * c.half)
        }
    };
    if !(b1 + b2).is_finite() {
        return c.update(st, h);
    }
    let gap = Gap { eta0, b1, b2 };
    let Some((x, y, v)) = c.gauss.step_nominal(st.x, st.y, &gap, c.v_max) else {
        return c.update(st, h);
    };
    let next = State {
        x,
        y,
        v,
        eta_prev: eta0,
        eta: eta1,
    };
    let out = c.output(&next);
    *st = next;
    out
}

/// [`LANES`] magnets `lane[..]` through the internal loop together.
fn chunk(
    ctl: &[Levitation<f64>],
    st: &mut [State<f64>],
    h: &[f64],
    out: &mut [Output<f64>],
    lane: &[usize; LANES],
    n_sub: u32,
) {
    let c = lane.map(|i| &ctl[i]);
    let mut x = lane.map(|i| st[i].x);
    let mut y = lane.map(|i| st[i].y);
    let mut v = lane.map(|i| st[i].v);
    let eta0 = lane.map(|i| st[i].eta);
    let eta1 = lane.map(|i| h[i] - 1.0);
    let mut b1 = [0.0; LANES];
    let mut b2 = [0.0; LANES];
    for l in 0..LANES {
        // As `advance` interpolates (docs/model.md §4).
        (b1[l], b2[l]) = match c[l].params.interpolation {
            Interpolation::Linear => (eta1[l] - eta0[l], 0.0),
            Interpolation::Parabolic => {
                let m = st[lane[l]].eta_prev;
                let half = c[l].half;
                (
                    (eta1[l] - m) * half,
                    ((eta1[l] - (eta0[l] + eta0[l])) + m) * half,
                )
            }
        };
    }
    let CoilLanes {
        one_kpd,
        one_ca1,
        ca,
        c: cc,
        kih,
        kpv,
        inv_n,
        v_max: v_lim,
        ..
    } = CoilLanes::of(c);
    let mut s = [0.0; LANES];
    let mut event = [false; LANES];
    for k in 1..=n_sub {
        for l in 0..LANES {
            let eta = if k == n_sub {
                eta1[l]
            } else {
                s[l] += inv_n[l];
                eta0[l] + s[l] * (b1[l] + s[l] * b2[l])
            };
            // `substep` without the reference, unchecked (events are flagged, not handled).
            let factor = one_kpd[l] + eta;
            let num = (y[l] - eta) - x[l] * factor;
            let den = one_ca1[l] + ca[l] * eta;
            let x1 = x[l] + (cc[l] * num) / den;
            let y1 = y[l] - kih[l] * (x[l] + x1);
            let v1 = (1.0 + y1) - kpv[l] * x1;
            event[l] |= x1 < -1.0 || v1 > v_lim[l] || v1 < -v_lim[l];
            x[l] = x1;
            y[l] = y1;
            v[l] = v1;
        }
    }
    for l in 0..LANES {
        let i = lane[l];
        if event[l] || !(x[l].is_finite() && y[l].is_finite() && v[l].is_finite()) {
            out[i] = c[l].update(&mut st[i], h[i]);
            continue;
        }
        let s = &mut st[i];
        s.x = x[l];
        s.y = y[l];
        s.v = v[l];
        s.eta_prev = eta0[l];
        s.eta = eta1[l];
        let g = 1.0 + x[l];
        out[i] = Output {
            g,
            force: g * g,
            current: g * (1.0 + eta1[l]),
            voltage: v[l],
            status: Status::default(),
        };
    }
}

/// The coefficients of `N` coils side by side, a lane per coil (their fields of the same
/// names): for the batches here and in [`crate::law::state::batch`].
pub(crate) struct CoilLanes<const N: usize> {
    pub one_kpd: [f64; N],
    pub one_ca1: [f64; N],
    pub ca: [f64; N],
    pub c: [f64; N],
    pub kih: [f64; N],
    pub kpv: [f64; N],
    pub inv_n: [f64; N],
    pub v_max: [f64; N],
    /// [`Levitation::fast_update`]'s straight line runs for a gap `0 < h ≤ fast_h`.
    pub fast_h: [f64; N],
}

impl<const N: usize> CoilLanes<N> {
    /// The coefficients of the coils `c`.
    pub(crate) fn of(c: [&Levitation<f64>; N]) -> Self {
        CoilLanes {
            one_kpd: c.map(|c| c.one_kpd),
            one_ca1: c.map(|c| c.one_ca1),
            ca: c.map(|c| c.ca),
            c: c.map(|c| c.c),
            kih: c.map(|c| c.kih),
            kpv: c.map(|c| c.kpv),
            inv_n: c.map(|c| c.inv_n),
            v_max: c.map(|c| c.v_max),
            fast_h: c.map(|c| c.fast_h),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::levitation::Params;

    /// Bit-identical to one `update` per magnet, for magnets of different loads, both
    /// interpolations, gaps that move, and with events (collision, voltage bound, a NaN gap).
    #[test]
    fn batch_gives_the_bits_of_update() {
        for interpolation in [Interpolation::Linear, Interpolation::Parabolic] {
            for n_sub in [1, 7, 100] {
                let ctls: [Levitation<f64>; 11] = core::array::from_fn(|i| {
                    let mut p = Params::paper(30e3 + 1e3 * i as f64, 1e-3);
                    p.n_sub = n_sub;
                    p.interpolation = interpolation;
                    if i == 5 {
                        p.v_max = 60.0; // saturates on the large gap steps
                    }
                    p.compile().unwrap()
                });
                let mut a: [State<f64>; 11] =
                    core::array::from_fn(|i| ctls[i].equilibrium_state(0.01 + 1e-4 * i as f64));
                let mut b = a;
                let mut out = [Output::default(); 11];
                for step in 0..200 {
                    let h: [f64; 11] = core::array::from_fn(|i| {
                        let t = step as f64 * 1e-3;
                        let mut h = 1.0 + 0.3 * triangle(6.0 * t + 0.1 * i as f64);
                        if i == 3 && step == 50 {
                            h = -0.1; // collision
                        }
                        if i == 7 && step == 60 {
                            h = f64::NAN;
                        }
                        h
                    });
                    update_batch(&ctls, &mut b, &h, &mut out);
                    for i in 0..11 {
                        let want = ctls[i].update(&mut a[i], h[i]);
                        assert_eq!(out[i], want, "magnet {i} step {step} n_sub {n_sub}");
                        assert_eq!(a[i], b[i]);
                    }
                }
            }
        }
    }

    /// The accurate scheme through the batch: bit-identical to `update`, for one and several
    /// Gauss intervals per step (Δt = 1 and 10 ms), both interpolations, and with events
    /// (collision, a gap beyond h_max, the voltage bound, the current floor, a NaN gap).
    #[test]
    fn batch_gives_the_bits_of_update_accurate() {
        for interpolation in [Interpolation::Linear, Interpolation::Parabolic] {
            for dt in [1e-3, 1e-2] {
                let ctls: [Levitation<f64>; 9] = core::array::from_fn(|i| {
                    let mut p = Params::paper(30e3 + 1e3 * i as f64, dt);
                    p.scheme = Scheme::Accurate;
                    p.interpolation = interpolation;
                    if i == 5 {
                        p.v_max = 60.0; // saturates on the large gap steps
                    }
                    p.compile().unwrap()
                });
                assert!(ctls[0].accurate_intervals() >= if dt > 5e-3 { 2 } else { 1 });
                let mut a: [State<f64>; 9] =
                    core::array::from_fn(|i| ctls[i].equilibrium_state(0.01 + 1e-4 * i as f64));
                let mut b = a;
                let mut out = [Output::default(); 9];
                let mut nominal = 0;
                for step in 0..300 {
                    let h: [f64; 9] = core::array::from_fn(|i| {
                        let t = step as f64 * 1e-3;
                        let mut h = 1.0 + 0.3 * triangle(6.0 * t + 0.1 * i as f64);
                        if i == 3 && step == 50 {
                            h = -0.1; // collision
                        }
                        if i == 4 && step == 70 {
                            h = 1e3; // beyond h_max
                        }
                        if i == 6 && (100..140).contains(&step) {
                            h = 0.02; // the magnet closes: the current floor
                        }
                        if i == 7 && step == 60 {
                            h = f64::NAN;
                        }
                        h
                    });
                    update_batch(&ctls, &mut b, &h, &mut out);
                    for i in 0..9 {
                        let want = ctls[i].update(&mut a[i], h[i]);
                        assert_eq!(out[i], want, "magnet {i} step {step} dt {dt}");
                        assert_eq!(a[i], b[i]);
                        assert_eq!(a[i].x.to_bits(), b[i].x.to_bits());
                        assert_eq!(a[i].y.to_bits(), b[i].y.to_bits());
                        assert_eq!(a[i].v.to_bits(), b[i].v.to_bits());
                        nominal += usize::from(want.status == Status::default());
                    }
                }
                // Both paths were exercised: most updates nominal, some with events.
                assert!(
                    nominal > 2000 && nominal < 2700,
                    "{nominal} nominal updates"
                );
            }
        }
    }

    /// A triangle wave of period 1 between −1 and 1 (test gaps without std).
    fn triangle(x: f64) -> f64 {
        let f = x - (x as i64) as f64;
        if f < 0.5 {
            4.0 * f - 1.0
        } else {
            3.0 - 4.0 * f
        }
    }
}
