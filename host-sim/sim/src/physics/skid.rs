//! The magnet–rail contact (docs/contact.md): a magnet whose gap closes to the skid's gap
//! `h_s` lands on its skid (Transrapid) or support wheel (medium–low-speed lines), a stiff
//! one-sided Kelvin–Voigt contact with regularised Coulomb friction.
//!
//! Normal force, on the magnet, pushing its gap open (N ≥ 0):
//! `N = max(0, k·δ + c·δ̇)` while `δ = h_s − h > 0`, else 0 (Eq. C1). The penetration rate is
//! the step's backward difference of the penetration, counted from the rail's surface:
//! `δ̇ = (δ − max(δ_prev, 0))/Δt`. So a magnet that arrives within a step is not met by a
//! damper force computed from where it was before it touched (that force, with the gap's
//! response, has no consistent solution: the damper would push it off before it touched),
//! and the force is continuous at first touch.
//!
//! The set-down stop bounds the gap from above: a magnet whose gap opens to `h_d`
//! (`setdown_gap_m`) sets the vehicle down on its skids or support wheels on the guideway's
//! sliding surface. It is the same contact mirrored (Eq. C3): `N_d = max(0, k·δ_d + c·δ̇_d)`
//! with `δ_d = h − h_d`, the force closing the gap (it carries the vehicle's weight into the
//! guideway), with the same friction.
//!
//! Friction, opposing the skid's slip on the rail (the train's speed `V` along the rail and
//! the gap-plane velocity `v_t` across it): `F_t = −μ·N·v_t/√(V² + v_t² + v_ε²)` and the drag
//! `F_x = −μ·N·V/√(…)` (Eq. C2); `v_ε` regularises the sign at rest, so that above a few
//! `v_ε` the friction is `μ·N`.
//!
//! Why a local implicit force: the coupled iteration is a fixed point on the gaps, and a
//! contact stiffer than the magnet's attraction (it must be, or the skid could not hold the
//! magnet off the rail) would make an explicit contact force diverge. Each pass therefore
//! solves Eq. C1 together with the gap's own response `C` (m/N: the car's dynamic flexibility
//! at the magnet's DOF, `Keff⁻¹`'s diagonal) to a change of the force, in closed form
//! ([`Skid::normal_implicit`]); the next pass corrects what the rest of the train and the
//! guideway did. The guideway's own flexibility is left out of `C`.

use serde::Serialize;

/// The skid contact's parameters (SI), one set for every magnet of a run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Skid {
    /// The magnet's gap at which its skid touches the rail (m), ≥ 0.
    #[serde(rename = "skid_gap_m")]
    pub gap: f64,
    /// The levitation gap at which the vehicle sets down on its skids or support wheels on
    /// the guideway (m), above the nominal gap: the gap's upper bound (Eq. C3).
    #[serde(rename = "setdown_gap_m")]
    pub setdown: f64,
    /// Contact stiffness k (N/m), > 0.
    #[serde(rename = "stiffness_N_per_m")]
    pub stiffness: f64,
    /// Contact damping c (N·s/m), ≥ 0.
    #[serde(rename = "damping_N_s_per_m")]
    pub damping: f64,
    /// Sliding friction coefficient μ, ≥ 0.
    pub friction: f64,
    /// The slip speed v_ε below which the friction is regularised (m/s), > 0.
    #[serde(rename = "slip_regularisation_m_per_s")]
    pub slip: f64,
}

impl Skid {
    /// The defaults (docs/contact.md, "Defaults and their sources"); the set-down gap is
    /// twice the project's nominal gap h0 = 10 mm (a scenario's default is twice its own h0).
    pub const DEFAULT: Skid = Skid {
        gap: 0.002,
        setdown: 0.02,
        stiffness: 5e9,
        damping: 6e5,
        friction: 0.3,
        slip: 0.01,
    };

    /// Eq. C1 at the gap `h` (m), `h_prev` the committed gap a step `dt` (s) earlier.
    pub fn normal(&self, h: f64, h_prev: f64, dt: f64) -> f64 {
        let delta = self.gap - h;
        if delta <= 0.0 {
            return 0.0;
        }
        let before = (self.gap - h_prev).max(0.0);
        (self.stiffness * delta + self.damping * (delta - before) / dt).max(0.0)
    }

    /// Eq. C1 solved together with the gap's response to the force: the pass that gave `h`
    /// was loaded with `n_used`, and a force `N` instead opens the gap by `C·(N − n_used)`
    /// (`compliance` C in m/N), so `N = normal(h + C·(N − n_used))`, in closed form.
    pub fn normal_implicit(
        &self,
        h: f64,
        h_prev: f64,
        dt: f64,
        compliance: f64,
        n_used: f64,
    ) -> f64 {
        // k·δ' + c·(δ' − δ_prev⁺)/Δt = A − K·h', δ' = h_s − h', h' = h + C·(N − n_used). A
        // positive N puts h' below h_s − c·δ_prev⁺/(K·Δt) ≤ h_s: in contact, so the clamp at
        // zero is the whole complementarity.
        let kk = self.stiffness + self.damping / dt;
        let before = (self.gap - h_prev).max(0.0);
        let a = kk * self.gap - self.damping * before / dt;
        ((a - kk * (h - compliance * n_used)) / (1.0 + kk * compliance)).max(0.0)
    }

    /// Eq. C3, the set-down stop's force (N, closing the gap) at the gap `h`, solved with the
    /// gap's response as [`Skid::normal_implicit`] is: a force `N` closes the gap by
    /// `C·(N − n_used)`. It is Eq. C1 in the mirrored gap `−h` against the stop `−h_d`.
    pub fn setdown_implicit(
        &self,
        h: f64,
        h_prev: f64,
        dt: f64,
        compliance: f64,
        n_used: f64,
    ) -> f64 {
        let mirrored = Skid {
            gap: -self.setdown,
            ..*self
        };
        mirrored.normal_implicit(-h, -h_prev, dt, compliance, n_used)
    }

    /// Eq. C2: the friction (N) of the normal force `n` along the slip velocity component `v`,
    /// when the skid slips at `speed` (m/s, the magnitude of the whole slip velocity).
    pub fn friction_along(&self, n: f64, v: f64, speed: f64) -> f64 {
        -self.friction * n * v / (speed * speed + self.slip * self.slip).sqrt()
    }
}

/// Per magnet wheel: the levitation skid, guidance left, guidance right, and the set-down
/// stop (the levitation gap's upper bound).
pub const SIDES: usize = 4;

/// The index of the set-down stop in a wheel's `[z, left, right, setdown]`.
pub const SETDOWN: usize = 3;

/// One magnet's contact over a run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SkidRange {
    /// The largest normal force (N) of a committed step.
    pub peak_normal: f64,
    /// The largest friction drag along the rail (N).
    pub peak_drag: f64,
    /// Committed steps in contact, the first one's end time (s).
    pub steps: usize,
    pub first_t: Option<f64>,
}

/// The skids of every magnet of a train within the coupled iteration: the forces of the
/// current pass, the forces the last pass loaded the train with, and the run's ranges.
pub struct Skids {
    skid: Skid,
    /// Per wheel: the normal forces `[z, left, right, setdown]` of the current pass (N).
    normal: Vec<[f64; SIDES]>,
    /// Per wheel: the net contact force on the wheel `(F_z, F_y)` (N, Z up), and each
    /// skid's friction drag along the rail (N).
    force: Vec<(f64, f64)>,
    drag: Vec<[f64; SIDES]>,
    /// Per wheel: the dynamic flexibility `(C_zz, C_yy)` of its DOFs (m/N), computed the first
    /// time a skid nears the rail.
    compliance: Vec<Option<(f64, f64)>>,
    /// Some skid carries a force in the current pass.
    touching: bool,
    ranges: Vec<[SkidRange; SIDES]>,
    /// Committed steps with some magnet in contact, the first one's end time (s).
    steps: usize,
    first_t: Option<f64>,
}

/// Every magnet's skid contact over a run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SkidOutcome {
    /// Per magnet wheel `[z, left, right, setdown]`.
    pub per_magnet: Vec<[SkidRange; SIDES]>,
    /// Committed steps with some magnet in contact, the first one's end time (s).
    pub steps: usize,
    pub first_t: Option<f64>,
}

/// What a pass needs to know of one wheel.
pub struct WheelView {
    /// Committed gaps `(h_z, d)` (m) at t − Δt, and the current iterate at t.
    pub prev: (f64, f64),
    pub now: (f64, f64),
    /// The nominal gap h0 (m) (the guidance gaps are `h0 ± d`).
    pub h0: f64,
    /// `dh_z/dz_w`: +1 (paper) or −1 (EMS).
    pub sign: f64,
    /// Whether the wheel has guidance magnets (a lateral DOF).
    pub guided: bool,
}

impl Skids {
    /// No wheel in contact, for `wheels` magnet wheels.
    pub fn new(skid: Skid, wheels: usize) -> Self {
        Skids {
            skid,
            normal: vec![[0.0; SIDES]; wheels],
            force: vec![(0.0, 0.0); wheels],
            drag: vec![[0.0; SIDES]; wheels],
            compliance: vec![None; wheels],
            touching: false,
            ranges: vec![[SkidRange::default(); SIDES]; wheels],
            steps: 0,
            first_t: None,
        }
    }

    /// The pass's contact forces of wheel `i` seen through `w`, the train moving at `speed`
    /// (m/s) with step `dt`; `flex` gives the wheel's `(C_zz, C_yy)` (asked for once, and only
    /// when a gap is within reach of its skid). Returns whether the wheel is in contact.
    pub fn wheel(
        &mut self,
        i: usize,
        w: &WheelView,
        speed: f64,
        dt: f64,
        flex: impl FnOnce() -> (f64, f64),
    ) -> bool {
        let s = self.skid;
        let gaps = |g: (f64, f64)| [g.0, w.h0 + g.1, w.h0 - g.1];
        let (now, prev) = (gaps(w.now), gaps(w.prev));
        let sides = if w.guided { 3 } else { 1 };
        let used = self.normal[i];
        let near = (0..sides).any(|k| now[k] < s.gap || used[k] > 0.0)
            || now[0] > s.setdown
            || used[SETDOWN] > 0.0;
        if !near {
            self.normal[i] = [0.0; SIDES];
            self.force[i] = (0.0, 0.0);
            self.drag[i] = [0.0; SIDES];
            return false;
        }
        let (czz, cyy) = *self.compliance[i].get_or_insert_with(flex);
        let mut n = [0.0; SIDES];
        for k in 0..sides {
            let c = if k == 0 { czz } else { cyy };
            n[k] = s.normal_implicit(now[k], prev[k], dt, c, used[k]);
        }
        n[SETDOWN] = s.setdown_implicit(now[0], prev[0], dt, czz, used[SETDOWN]);
        // Slip velocities: vertical (from h_z) and lateral (from d), relative to the rail.
        let vz = w.sign * (w.now.0 - w.prev.0) / dt;
        let vy = (w.now.1 - w.prev.1) / dt;
        let slip_z_skid = (speed * speed + vy * vy).sqrt();
        let slip_y_skid = (speed * speed + vz * vz).sqrt();
        let [nz, nl, nr, nd] = n;
        // The levitation skid and the set-down stop both slide in the horizontal plane.
        let fz = w.sign * (nz - nd) + s.friction_along(nl + nr, vz, slip_y_skid);
        let fy = nl - nr + s.friction_along(nz + nd, vy, slip_z_skid);
        let drag = [
            s.friction_along(nz, speed, slip_z_skid).abs(),
            s.friction_along(nl, speed, slip_y_skid).abs(),
            s.friction_along(nr, speed, slip_y_skid).abs(),
            s.friction_along(nd, speed, slip_z_skid).abs(),
        ];
        self.normal[i] = n;
        self.force[i] = (fz, fy);
        self.drag[i] = drag;
        n.iter().any(|&x| x > 0.0)
    }

    /// Starts a pass: no wheel touching yet.
    pub fn begin_pass(&mut self) {
        self.touching = false;
    }

    /// Notes that some wheel touched in this pass.
    pub fn touched(&mut self, any: bool) {
        self.touching |= any;
    }

    /// The magnet forces `(G_z, G_y)` of wheel `i` with its contact force added, when it has
    /// one (unchanged, bit for bit, when it has none).
    pub fn add(&self, i: usize, g: (f64, f64)) -> (f64, f64) {
        let n = self.normal[i];
        if n == [0.0; SIDES] {
            return g;
        }
        let (fz, fy) = self.force[i];
        (g.0 + fz, g.1 + fy)
    }

    /// Some skid carries a force in the last pass.
    pub fn touching(&self) -> bool {
        self.touching
    }

    /// Takes the last pass's forces into the run's ranges (a committed step ending at `t`).
    pub fn commit(&mut self, t: f64) {
        if !self.touching {
            return;
        }
        self.steps += 1;
        self.first_t.get_or_insert(t);
        for ((r, n), d) in self.ranges.iter_mut().zip(&self.normal).zip(&self.drag) {
            for ((r, &n), &d) in r.iter_mut().zip(n).zip(d) {
                if n > 0.0 {
                    r.peak_normal = r.peak_normal.max(n);
                    r.peak_drag = r.peak_drag.max(d);
                    r.steps += 1;
                    r.first_t.get_or_insert(t);
                }
            }
        }
    }

    /// Every magnet's contact over the run.
    pub fn outcome(self) -> SkidOutcome {
        SkidOutcome {
            per_magnet: self.ranges,
            steps: self.steps,
            first_t: self.first_t,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed form of Eq. C1 with a flexibility agrees with a bisection on
    /// `N = normal(h + C·(N − n_used))`, and with `C = 0` it is [`Skid::normal`].
    #[test]
    fn the_implicit_force_solves_its_equation() {
        let s = Skid::DEFAULT;
        let dt = 1e-3;
        for (h, h_prev, c, used) in [
            (0.0015, 0.0018, 1e-9, 0.0),
            (0.0010, 0.0012, 1e-8, 2e6),
            (0.0019, 0.0015, 2e-10, 1e5),
            (0.0030, 0.0030, 1e-9, 0.0),
        ] {
            let n = s.normal_implicit(h, h_prev, dt, c, used);
            // Bisection on the residual r(N) = N − normal(h + C (N − used)), increasing in N.
            let r = |x: f64| x - s.normal(h + c * (x - used), h_prev, dt);
            let (mut lo, mut hi) = (0.0, 1e9);
            if r(0.0) >= 0.0 {
                hi = 0.0;
            }
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if r(mid) > 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            assert!((n - hi).abs() <= 1e-9 * hi.max(1.0), "{h} {c}: {n} vs {hi}");
            // The same force by another order of operations: equal to round-off, not bit for
            // bit. The closed form subtracts (k + c/Δt)·h from (k + c/Δt)·h_s, so its
            // round-off is that of terms of that size.
            let (implicit, direct) = (
                s.normal_implicit(h, h_prev, dt, 0.0, used),
                s.normal(h, h_prev, dt),
            );
            assert!(
                (implicit - direct).abs()
                    <= 4.0 * f64::EPSILON * (s.stiffness + s.damping / dt) * s.gap,
                "{h}: {implicit} vs {direct}"
            );
        }
    }

    #[test]
    fn friction_is_mu_n_at_speed_and_vanishes_at_rest() {
        let s = Skid::DEFAULT;
        let f = s.friction_along(1e4, 50.0, 50.0);
        assert!(
            (f + s.friction * 1e4).abs() < 1e-6 * s.friction * 1e4,
            "{f}"
        );
        assert_eq!(s.friction_along(1e4, 0.0, 0.0), 0.0);
    }
}
