//! The guidance law's straight-line path for one control period per step in floating point
//! (the firmware's case, `n = 1`): the operations of [`GuidanceLaw::general_update`] in its
//! order on unchecked arithmetic, with the finiteness of every value they flow into checked
//! once before anything is stored, as the levitation state law's fast path does
//! (`super::super::state`). A float's checked operation differs from the plain one only
//! where the result is not finite, and every intermediate here ends in one of the checked
//! values, so when the check passes the result is the general path's to the bit
//! (`tests::fast_path_is_bit_identical_to_the_general_path`); otherwise `None` and the general
//! path runs from the untouched state. `1/n` is exactly 1 and `x·1 = x` for every float, so
//! the general path's increments `(end − start)·(1/n)` are the differences themselves.

use super::{GuidanceLaw, GuidanceState, PairMeasurement};
use crate::gap::Geometry;
use crate::guidance::PairOutput;
use crate::levitation::{State, Status};
use crate::scalar::Scalar;

impl<S: Scalar> GuidanceLaw<S> {
    /// [`GuidanceLaw::update`] in one period, or `None` (state untouched) where it does not
    /// apply or declines (module docs).
    #[inline(always)]
    pub(super) fn fast_update(
        &self,
        st: &mut GuidanceState<S>,
        m: PairMeasurement<S>,
        geometry: Geometry,
    ) -> Option<PairOutput<S>> {
        if !S::FLOAT || self.n != 1 {
            return None;
        }
        let mut ov = false;
        let one = S::ONE;
        let end_l = m.d;
        // Negation cannot overflow (and keeps the sign of a zero, as the general path's).
        let end_r = m.d.sneg(&mut ov);
        let acc_end = m.accel.unwrap_or(S::ZERO);
        let (eta_l, eta_r, acc) = (st.left.eta, st.right.eta, st.accel);
        let d_l = end_l.sub_raw(eta_l);
        let d_r = end_r.sub_raw(eta_r);
        let d_acc = acc_end.sub_raw(acc);
        let current = |x: S, eta: S| one.add_raw(x).mul_raw(one.add_raw(eta)).sub_raw(one);
        let di_l = current(st.left.x, eta_l);
        let di_r = current(st.right.x, eta_r);
        let di_d = di_l.sub_raw(di_r).mul_raw(self.half);
        let di_c = di_l.add_raw(di_r).mul_raw(self.half);
        let eta_d = eta_l.sub_raw(eta_r).mul_raw(self.half);
        let dv_d = self
            .kp
            .mul_raw(eta_d)
            .add_raw(self.kd.mul_raw(st.rate_est))
            .add_raw(self.ka.mul_raw(acc))
            .add_raw(st.integral)
            .sub_raw(self.kc.mul_raw(di_d));
        let dv_c = self.kc.mul_raw(di_c).sneg(&mut ov);
        let base = one.add_raw(dv_c);
        let v_l = base.add_raw(dv_d);
        let v_r = base.sub_raw(dv_d);
        let clamped = [v_l, v_r].iter().any(|&v| v > self.v_max || v < self.v_min);
        let integral = if clamped {
            st.integral
        } else {
            st.integral.add_raw(self.ki_delta.mul_raw(eta_d))
        };
        let e = eta_d.sub_raw(st.eta_est);
        let rate_change = self.accel_gain.mul_raw(acc).add_raw(self.l2.mul_raw(e));
        let eta_est = st
            .eta_est
            .add_raw(self.delta.mul_raw(st.rate_est))
            .add_raw(self.l1.mul_raw(e));
        let rate_est = st.rate_est.add_raw(rate_change);
        let eta_l1 = eta_l.add_raw(d_l);
        let eta_r1 = eta_r.add_raw(d_r);
        let acc1 = acc.add_raw(d_acc);
        let (h_l, h_r) = (one.add_raw(eta_l1), one.add_raw(eta_r1));
        let all = v_l
            .add_raw(v_r)
            .add_raw(integral)
            .add_raw(eta_est)
            .add_raw(rate_est)
            .add_raw(h_l)
            .add_raw(h_r)
            .add_raw(acc1)
            .add_raw(acc_end)
            .add_raw(end_l);
        // A sum of finite values can overflow; then the general path decides.
        if ov || !all.is_finite_value() {
            return None;
        }
        // Each coil's own fast path, on copies: when either declines, so does this one.
        let coil = |c: &State<S>, v: S, h: S| {
            let mut c = *c;
            c.y = v.clamp_to(self.v_min, self.v_max).sub_raw(one);
            let out = self.coil.fast_update(&mut c, h)?;
            Some((c, out))
        };
        let (left, out_l) = coil(&st.left, v_l, h_l)?;
        let (right, out_r) = coil(&st.right, v_r, h_r)?;
        let force_y = match geometry {
            Geometry::Paper => out_l.force.sub_raw(out_r.force),
            Geometry::Ems => out_r.force.sub_raw(out_l.force),
        };
        if !force_y.is_finite_value() {
            return None;
        }
        st.left = State { eta: end_l, ..left };
        st.right = State {
            eta: end_r,
            ..right
        };
        st.integral = integral;
        st.eta_est = eta_est;
        st.rate_est = rate_est;
        st.accel = acc_end;
        let status = if clamped {
            Status::VOLTAGE_SATURATED
        } else {
            Status::default()
        };
        Some(PairOutput {
            left: out_l,
            right: out_r,
            force_y,
            status,
        })
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::super::GuidanceParams;
    use super::*;
    use crate::law::state::StateParams;
    use crate::levitation::Params;

    /// A seeded walk of measurements, with lateral offsets, accelerations and gains large
    /// enough to clamp the supply now and then: every step of the checked general path and of
    /// the update (fast where it applies) gives the same bits, and the fast path ran.
    fn compare<S: Scalar>(to: fn(f64) -> S, bits: fn(S) -> u64) -> usize {
        let magnet = Params::paper_wheel(1e-4);
        let timing = StateParams {
            kp: 51_600.0,
            kd: 1_600.0,
            ka: 40.0,
            ki: 4_300.0,
            kc: 10.0,
            v_max: 120.0,
            rate_hz: StateParams::RATE_HZ,
            observer_hz: StateParams::OBSERVER_HZ,
            geometry: Geometry::Ems,
        };
        let law = GuidanceParams::same_as(&timing)
            .compile::<S>(&timing, &magnet)
            .unwrap();
        let mut fast_runs = 0;
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for geometry in [Geometry::Ems, Geometry::Paper] {
            let (mut a, mut b) = (law.equilibrium(1e-4), law.equilibrium(1e-4));
            for k in 0..2000 {
                let d = 0.02 * rnd() + if k % 97 == 0 { 3.0 * rnd() } else { 0.0 };
                let accel = (k % 3 != 0).then(|| to(0.2 * rnd()));
                let m = PairMeasurement { d: to(d), accel };
                let before = a;
                let oa = law.update(&mut a, m, geometry);
                let ob = law.general_update(&mut b, m, geometry);
                let mut probe = before;
                fast_runs += usize::from(law.fast_update(&mut probe, m, geometry).is_some());
                let st = |s: &GuidanceState<S>| {
                    [
                        s.left.x,
                        s.left.y,
                        s.left.eta,
                        s.left.eta_prev,
                        s.left.v,
                        s.right.x,
                    ]
                    .into_iter()
                    .chain([s.right.y, s.right.eta, s.right.eta_prev, s.right.v])
                    .chain([s.integral, s.eta_est, s.rate_est, s.accel])
                    .map(bits)
                    .collect::<std::vec::Vec<_>>()
                };
                assert_eq!(st(&a), st(&b), "step {k}");
                let out = |o: &PairOutput<S>| {
                    let v = [o.left.g, o.left.force, o.left.current, o.left.voltage]
                        .into_iter()
                        .chain([o.right.g, o.right.force, o.right.current, o.right.voltage])
                        .chain([o.force_y])
                        .map(bits)
                        .collect::<std::vec::Vec<_>>();
                    (v, o.status, o.left.status, o.right.status)
                };
                assert_eq!(out(&oa), out(&ob), "step {k}");
                // Resynchronise after a collision or a runaway, as a run would restart.
                if !oa.status.is_empty() && k % 5 == 0 {
                    a = law.equilibrium(1e-4);
                    b = a;
                }
            }
        }
        fast_runs
    }

    #[test]
    fn fast_path_is_bit_identical_to_the_general_path() {
        let f32_fast = compare::<f32>(|x| x as f32, |x| x.to_bits() as u64);
        let f64_fast = compare::<f64>(|x| x, f64::to_bits);
        // Both paths ran: the walk has quiet steps and steps with events.
        assert!(f32_fast > 1000 && f32_fast < 4000, "{f32_fast}");
        assert!(f64_fast > 1000 && f64_fast < 4000, "{f64_fast}");
    }
}
