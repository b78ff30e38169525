//! Many magnets' state-law updates at once, for hosts (`maglev run`'s magnets).
//!
//! One magnet's update is a dependent chain per control period (sample → voltage → coil,
//! with a division in it), so a magnet alone runs at the chain's latency. [`update_batch`]
//! interleaves [`LANES`] magnets in one loop, their values side by side in arrays (structure
//! of arrays), with selects where the per-magnet path branches (the voltage clamp and the
//! conditional integration), so that the compiler keeps them in vector registers.
//!
//! # The same bits
//! Each lane performs [`StateLaw::update`]'s general path's operations in its order (floats,
//! no contraction, no reassociation): the voltage, its clamp and anti-windup, the observer,
//! the interpolation of the gap and acceleration across the step, and the coil's straight
//! line ([`Levitation::fast_update`](crate::levitation::Levitation)). A float's checked
//! operation differs from the plain one only where the result is not finite, and a
//! non-finite value stays non-finite through every later `+ − × ÷` except a division by it
//! (the coil's denominator, bounded here by the gap's range) and the clamp (the voltage,
//! checked before it): so a lane whose checked values — the voltage before its clamp, the
//! coil's voltage and force and the interpolated acceleration each period, and the states it
//! stores — are all
//! finite has the general path's bits. A lane that meets anything else — a non-finite value,
//! a gap outside the coil's straight line `0 < h ≤ 2·h0` (collision, a NaN), the current
//! floor — is recomputed by [`StateLaw::update`] from its untouched state, as are magnets
//! whose number of control periods differs from the first magnet's.
//! `tests::batch_gives_the_bits_of_update` checks it over many magnets and steps, with
//! saturation, anti-windup and those events.

use super::{StateLaw, StateLawState};
use crate::levitation::batch::CoilLanes;
use crate::levitation::{Output, State, Status};

/// Magnets interleaved per loop.
pub const LANES: usize = 8;

/// One structural step of every magnet `i` under its own state law `laws[i]`, coil state
/// `coil[i]` and law state `st[i]`, to the per-unit gap `gap[i]` and acceleration `accel[i]`
/// at the step's end (`0.0` for a magnet without an accelerometer: the law's `None` gives the
/// same bits): `out[i]` is what `laws[i].update(&mut coil[i], &mut st[i], gap[i],
/// Some(accel[i]))` returns, bit for bit, and the states end as it leaves them. Returns how
/// many magnets took that per-magnet path (events, or a number of periods other than the
/// first magnet's).
///
/// # Panics
/// If the slices' lengths differ.
pub fn update_batch(
    laws: &[StateLaw<f64>],
    coil: &mut [State<f64>],
    st: &mut [StateLawState<f64>],
    gap: &[f64],
    accel: &[f64],
    out: &mut [Output<f64>],
) -> usize {
    let n = laws.len();
    assert!(
        coil.len() == n && st.len() == n && gap.len() == n && accel.len() == n && out.len() == n,
        "state::batch::update_batch: slices of different lengths"
    );
    let periods = laws.first().map_or(1, |l| l.n);
    let mut io = Io {
        laws,
        coil,
        st,
        gap,
        accel,
        out,
        alone: 0,
    };
    let mut lane = [0usize; LANES];
    let mut fill = 0;
    for i in 0..n {
        if io.laws[i].n != periods {
            io.alone(i);
            continue;
        }
        lane[fill] = i;
        fill += 1;
        if fill == LANES {
            io.chunk(&lane, periods);
            fill = 0;
        }
    }
    for &i in &lane[..fill] {
        io.alone(i);
    }
    io.alone
}

/// The batch's slices and its count of magnets run alone.
struct Io<'a> {
    laws: &'a [StateLaw<f64>],
    coil: &'a mut [State<f64>],
    st: &'a mut [StateLawState<f64>],
    gap: &'a [f64],
    accel: &'a [f64],
    out: &'a mut [Output<f64>],
    alone: usize,
}

/// One lane's values: an array per quantity, a lane per magnet.
type Lanes = [f64; LANES];

impl Io<'_> {
    /// Magnet `i` by the per-magnet path.
    fn alone(&mut self, i: usize) {
        self.out[i] = self.laws[i].update(
            &mut self.coil[i],
            &mut self.st[i],
            self.gap[i],
            Some(self.accel[i]),
        );
        self.alone += 1;
    }

    /// [`LANES`] magnets `lane[..]`, each with `periods` control periods, together.
    fn chunk(&mut self, lane: &[usize; LANES], periods: u32) {
        let law = lane.map(|i| &self.laws[i]);
        let k = |f: fn(&StateLaw<f64>) -> f64| -> Lanes { law.map(f) };
        let (kp, kd, ka, kc) = (k(|l| l.kp), k(|l| l.kd), k(|l| l.ka), k(|l| l.kc));
        let (ki_delta, v_max, v_min) = (k(|l| l.ki_delta), k(|l| l.v_max), k(|l| l.v_min));
        let (l1, l2, accel_gain) = (k(|l| l.l1), k(|l| l.l2), k(|l| l.accel_gain));
        let (delta, steps) = (k(|l| l.delta), k(|l| l.steps));
        let CoilLanes {
            one_kpd,
            one_ca1,
            ca,
            c: cc,
            kih,
            kpv,
            fast_h,
            ..
        } = CoilLanes::of(law.map(|l| &l.coil));

        let c0 = lane.map(|i| self.coil[i]);
        let s0 = lane.map(|i| self.st[i]);
        let mut x = c0.map(|c| c.x);
        let (mut y, mut v1) = (c0.map(|c| c.y), c0.map(|c| c.v));
        // The coil's last two gaps (its `eta`, `eta_prev`) as its updates leave them.
        let (mut ce, mut cp) = (c0.map(|c| c.eta), c0.map(|c| c.eta_prev));
        let mut integral = s0.map(|s| s.integral);
        let mut eta_est = s0.map(|s| s.eta_est);
        let mut rate_est = s0.map(|s| s.rate_est);
        let eta_end = lane.map(|i| self.gap[i] - 1.0);
        let acc_end = lane.map(|i| self.accel[i]);
        let (mut eta, mut acc) = (c0.map(|c| c.eta), s0.map(|s| s.accel));
        let mut d_eta = [0.0; LANES];
        let mut d_acc = [0.0; LANES];
        for l in 0..LANES {
            d_eta[l] = (eta_end[l] - eta[l]) * steps[l];
            d_acc[l] = (acc_end[l] - acc[l]) * steps[l];
        }
        let mut force = [0.0; LANES];
        let mut saturated = [false; LANES];
        let mut bail = [false; LANES];
        // The sum of every checked value: finite iff each is (or a spurious overflow, which
        // only sends the lane the per-magnet way).
        let mut check = [0.0; LANES];
        for _ in 0..periods {
            for l in 0..LANES {
                // `StateLaw::voltage`: v = 1 + Δv, clamped to ±v_max (`clamp_to`'s compares).
                let i_pu = (1.0 + x[l]) * (1.0 + eta[l]);
                let di = i_pu - 1.0;
                let dv = kp[l] * eta[l] + kd[l] * rate_est[l] - ka[l] * acc[l] + integral[l]
                    - kc[l] * di;
                let v = 1.0 + dv;
                let lo = v_min[l];
                let above = if lo > v { lo } else { v };
                let vc = if v_max[l] < above { v_max[l] } else { above };
                let clamped = (v > v_max[l]) | (v < lo);
                saturated[l] |= clamped;
                // Conditional integration (anti-windup).
                let next = integral[l] + ki_delta[l] * eta[l];
                integral[l] = if clamped { integral[l] } else { next };
                // `StateLaw::observe`.
                let e = eta[l] - eta_est[l];
                let rate_change = accel_gain[l] * acc[l] + l2[l] * e;
                eta_est[l] = eta_est[l] + delta[l] * rate_est[l] + l1[l] * e;
                rate_est[l] += rate_change;
                eta[l] += d_eta[l];
                acc[l] += d_acc[l];
                // The coil at `y = v − 1` to the gap `1 + η` (`Levitation::fast_update`).
                let yc = vc - 1.0;
                let h1 = 1.0 + eta[l];
                bail[l] |= !((h1 > 0.0) & (h1 <= fast_h[l]));
                let ec = h1 - 1.0;
                let num = (yc - ec) - x[l] * (one_kpd[l] + ec);
                let den = one_ca1[l] + ca[l] * ec;
                let x1 = x[l] + (cc[l] * num) / den;
                let gl = 1.0 + x1;
                bail[l] |= gl < 0.0;
                y[l] = yc - kih[l] * (x[l] + x1);
                v1[l] = (1.0 + y[l]) - kpv[l] * x1;
                force[l] = gl * gl;
                x[l] = x1;
                cp[l] = ce[l];
                ce[l] = ec;
                check[l] += v + (v1[l] + force[l]) + acc[l];
            }
        }
        for l in 0..LANES {
            let i = lane[l];
            let stored = integral[l] + eta_est[l] + rate_est[l] + eta_end[l];
            if bail[l] || !(check[l] + stored).is_finite() {
                self.alone(i);
                continue;
            }
            self.coil[i] = State {
                x: x[l],
                y: y[l],
                v: v1[l],
                eta_prev: cp[l],
                eta: eta_end[l],
            };
            self.st[i] = StateLawState {
                integral: integral[l],
                eta_est: eta_est[l],
                rate_est: rate_est[l],
                accel: acc_end[l],
            };
            // The last period's coil outputs (`Levitation::fast_update`'s).
            let g = 1.0 + x[l];
            self.out[i] = Output {
                g,
                force: force[l],
                current: g * (1.0 + ce[l]),
                voltage: v1[l],
                status: if saturated[l] {
                    Status::VOLTAGE_SATURATED
                } else {
                    Status::default()
                },
            };
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::gap::Geometry;
    use crate::law::state::StateParams;
    use crate::levitation::Params;

    /// The paper-5 gains (`host-sim/cli/tests/state_law.rs`), with supply bound `v_max`.
    fn gains(v_max: f64) -> StateParams {
        StateParams {
            kp: 51_600.0,
            kd: 1_600.0,
            ka: 40.0,
            ki: 4_300.0,
            kc: 10.0,
            v_max,
            rate_hz: StateParams::RATE_HZ,
            observer_hz: StateParams::OBSERVER_HZ,
            geometry: Geometry::Ems,
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

    fn output_bits(o: &Output<f64>) -> ([u64; 4], Status) {
        let b = [o.g, o.force, o.current, o.voltage].map(f64::to_bits);
        (b, o.status)
    }

    fn state_bits(c: &State<f64>, s: &StateLawState<f64>) -> [u64; 9] {
        [
            c.x, c.y, c.v, c.eta, c.eta_prev, s.integral, s.eta_est, s.rate_est, s.accel,
        ]
        .map(f64::to_bits)
    }

    /// Bit-identical to one `StateLaw::update` per magnet, outputs and both states, over 400
    /// steps of magnets of different coils and gains, at 1, 7 and 20 control periods a step,
    /// with a remainder that does not fill a chunk, a magnet of another period, magnets
    /// without an accelerometer (`0.0` against the law's `None`), voltages that saturate at a
    /// tight supply bound (anti-windup: the integral frozen), and events (a collision, a gap
    /// beyond 2·h0, a NaN gap, an infinite acceleration).
    #[test]
    fn batch_gives_the_bits_of_update() {
        for (dt, count) in [(1e-4, 40), (7e-4, 37), (2e-3, 40), (2e-3, 19)] {
            let laws: std::vec::Vec<StateLaw<f64>> = (0..count)
                .map(|i| {
                    let mut m = Params::paper(20e3 + 1e3 * i as f64, dt);
                    m.i0 = 40.0 + 0.2 * i as f64;
                    if i == 13 {
                        m.dt = 2.0 * dt; // another number of periods: alone
                    }
                    // Every third magnet on a bound just above R0·i0: it saturates.
                    let v_max = if i % 3 == 1 { 1.4 * m.v_base() } else { 500.0 };
                    gains(v_max).compile::<f64>(&m).unwrap()
                })
                .collect();
            let eq = |i: usize| {
                let h = 0.01 * (1.0 + 0.01 * i as f64);
                let lev = laws[i].coil;
                let coil = lev.equilibrium_state(h);
                (coil, laws[i].equilibrium(&coil))
            };
            let (mut coil_a, mut st_a): (std::vec::Vec<_>, std::vec::Vec<_>) =
                (0..count).map(eq).unzip();
            let (mut coil_b, mut st_b) = (coil_a.clone(), st_a.clone());
            let mut out = std::vec![Output::default(); count];
            let (mut gap, mut accel) = (std::vec![0.0; count], std::vec![0.0; count]);
            // The magnets the chunks take: those of the first magnet's periods, as many as
            // fill whole chunks.
            let eligible: std::vec::Vec<usize> = (0..count).filter(|&i| i != 13).collect();
            let mut in_lanes = std::vec![false; count];
            for &i in &eligible[..eligible.len() / LANES * LANES] {
                in_lanes[i] = true;
            }
            let (mut alone, mut saturated, mut events) = (0, 0, 0);
            for step in 0..400 {
                let t = step as f64 * 1e-3;
                for i in 0..count {
                    gap[i] = 1.0 + 0.25 * triangle(3.0 * t + 0.07 * i as f64);
                    accel[i] = if i % 3 == 2 {
                        0.0
                    } else {
                        0.3 * triangle(5.0 * t + 0.11 * i as f64)
                    };
                }
                match step {
                    50 => gap[3] = -0.1, // collision
                    70 => gap[9] = 2.5,  // beyond the coil's straight line
                    90 => gap[20 % count] = f64::NAN,
                    110 => accel[4] = f64::INFINITY,
                    _ => {}
                }
                alone += update_batch(&laws, &mut coil_b, &mut st_b, &gap, &accel, &mut out);
                for i in 0..count {
                    let a = (i % 3 != 2).then_some(accel[i]);
                    let want = laws[i].update(&mut coil_a[i], &mut st_a[i], gap[i], a);
                    let ctx = (dt, count, step, i);
                    assert_eq!(output_bits(&out[i]), output_bits(&want), "{ctx:?}");
                    assert_eq!(
                        state_bits(&coil_b[i], &st_b[i]),
                        state_bits(&coil_a[i], &st_a[i]),
                        "{ctx:?}"
                    );
                    saturated +=
                        usize::from(in_lanes[i] && want.status == Status::VOLTAGE_SATURATED);
                    events += usize::from(
                        !want.status.is_empty() && want.status != Status::VOLTAGE_SATURATED,
                    );
                }
            }
            // Both paths ran, and the lanes' magnets saturated (a saturated step of theirs is
            // a lane's unless an event sent it alone: a few).
            let rest = count - eligible.len() / LANES * LANES; // the remainder and magnet 13
            assert!(events >= 3, "{events} events");
            assert!(
                alone >= 400 * rest && alone < 400 * rest + 400,
                "{alone} alone"
            );
            assert!(saturated > 1000, "{saturated} saturated");
        }
    }
}
