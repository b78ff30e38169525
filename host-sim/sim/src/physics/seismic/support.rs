//! Support motion as data: what the ground does at each of the guideway's supports, and the
//! loads by which it enters a structure that stands on springs and dashpots to the ground
//! (docs/seismic.md "Support motion").
//!
//! Why data and not a solver mode: in absolute coordinates a support's motion enters a
//! structure on ground springs k and dashpots c only as the load `k·u_g + c·v_g` on the DOF
//! the spring holds (Eq. S1 of docs/seismic.md), so the structure's matrices, its factor and
//! its time integrator stay what they are; the excitation is a right-hand side.
//!
//! - [`GroundRecord`]: a three-component ground-acceleration record on a uniform grid
//!   (`maglev accelerogram`'s CSV, or a real record in the same shape), linear between
//!   samples, zero before its start and after its end.
//! - [`SupportMotion`]: which record each support follows and when (uniform, wave passage with
//!   each support delayed by its distance over an apparent speed, or one record per support),
//!   plus a static settlement per support (a value × f(t) with f = 1: applied before t = 0).
//! - [`GroundState`]: a support's displacement, velocity and acceleration, advanced once per
//!   time step by the trapezoid rule (Eq. S2), which is exactly what average-acceleration
//!   Newmark does with a prescribed acceleration: the absolute and relative formulations of a
//!   structure driven this way are then the same discrete system (test
//!   `absolute_and_relative_formulations_agree`).
//! - [`GroundLink`]: one ground spring/dashpot of a structure, the DOF it holds and the
//!   support and direction whose motion its ground end follows.

use super::accelerogram::Accelerogram;
use crate::Error;

/// Directions of a record's components: x along the line, y across it, z up.
pub const AXES: usize = 3;

/// The bearing motions a simply supported span on rigid supports takes (docs/seismic.md
/// "Spans on rigid supports"): z at its left and right ends, then y at both.
pub const BEARINGS: usize = 4;

/// A ground-acceleration record: samples `(a_x, a_y, a_z)` (m/s²) at t = 0, Δt, 2Δt, …
#[derive(Clone, Debug, PartialEq)]
pub struct GroundRecord {
    dt: f64,
    samples: Vec<[f64; AXES]>,
}

/// The sample steps a record may have (s): `maglev accelerogram`'s limits (Nyquist above 5 Hz,
/// at most 10 kHz), for a record read from a file too.
pub const DT_LIMITS_S: (f64, f64) = (1e-6, 0.1);

/// How close to rest a record read from a file must end: its last sample and its final
/// velocity within this fraction of their peaks ([`GroundRecord::check_at_rest`]).
pub const AT_REST: f64 = 1e-3;

/// The CSV header of a record (`maglev accelerogram`'s).
pub const HEADER: &str = "t_s,ax_m_per_s2,ay_m_per_s2,az_m_per_s2";

impl GroundRecord {
    /// A record of `samples` at the step `dt`; every value finite, `dt` within
    /// [`DT_LIMITS_S`], at least one sample.
    pub fn new(dt: f64, samples: Vec<[f64; AXES]>) -> crate::Result<Self> {
        let (lo, hi) = DT_LIMITS_S;
        if !(dt.is_finite() && (lo..=hi).contains(&dt)) {
            return Err(Error::invalid(
                "support.record.dt",
                format!("must be within [{lo}, {hi}] s (the sample step of a ground-acceleration record), got {dt:e}"),
            ));
        }
        if samples.is_empty() {
            return Err(Error::invalid(
                "support.record",
                "needs at least 1 sample, got 0",
            ));
        }
        if let Some(i) = samples
            .iter()
            .position(|s| s.iter().any(|v| !v.is_finite()))
        {
            return Err(Error::invalid(
                "support.record",
                format!("sample {i} is not finite"),
            ));
        }
        Ok(GroundRecord { dt, samples })
    }

    /// Parse the CSV of `maglev accelerogram` ([`HEADER`], then `t, a_x, a_y, a_z` rows with
    /// t = 0, Δt, 2Δt, … to 1e-6 Δt). `what` names the source in errors.
    pub fn from_csv(what: &str, text: &str) -> crate::Result<Self> {
        let mut lines = text.lines().enumerate();
        match lines.next() {
            Some((_, h)) if h.trim() == HEADER => {}
            _ => return Err(Error::parse(what, format!("line 1: expected `{HEADER}`"))),
        }
        let mut t = Vec::new();
        let mut samples = Vec::new();
        for (i, line) in lines {
            if line.trim().is_empty() {
                continue;
            }
            let v: Vec<f64> = line
                .split(',')
                .map(|f| f.trim().parse::<f64>())
                .collect::<Result<_, _>>()
                .map_err(|e| Error::parse(what, format!("line {}: {e}", i + 1)))?;
            if v.len() != 4 {
                return Err(Error::parse(
                    what,
                    format!("line {}: expected 4 numbers, got {}", i + 1, v.len()),
                ));
            }
            t.push(v[0]);
            samples.push([v[1], v[2], v[3]]);
        }
        if t.len() < 2 {
            return Err(Error::parse(what, "a record needs at least 2 rows"));
        }
        let dt = t[1] - t[0];
        for (i, &ti) in t.iter().enumerate() {
            let off = (ti - i as f64 * dt).abs();
            if off.is_nan() || off > 1e-6 * dt {
                return Err(Error::parse(
                    what,
                    format!(
                        "row {}: t = {ti} is not {i} × Δt = {} (t from 0, uniform)",
                        i + 1,
                        i as f64 * dt
                    ),
                ));
            }
        }
        let record = Self::new(dt, samples).map_err(|e| Error::parse(what, e))?;
        record
            .check_at_rest()
            .map_err(|why| Error::parse(what, why))?;
        Ok(record)
    }

    /// `Err` saying why when the record does not end at rest: its last sample and the velocity
    /// reached by integrating it with the trapezoid rule at its own Δt (what the ground's
    /// integration does, Eq. S2) must be within [`AT_REST`] of their peaks. A record that
    /// does not would leave its supports moving after it ends; a residual displacement is a
    /// permanent offset of the ground, at rest, and is kept (docs/seismic.md "A record of
    /// your own").
    pub fn check_at_rest(&self) -> std::result::Result<(), String> {
        for (axis, name) in ["ax", "ay", "az"].iter().enumerate() {
            let a: Vec<f64> = self.samples.iter().map(|s| s[axis]).collect();
            let (mut v, mut v_peak, mut a_peak) = (0.0_f64, 0.0_f64, 0.0_f64);
            for j in 0..a.len() {
                if j > 0 {
                    v += 0.5 * self.dt * (a[j - 1] + a[j]);
                }
                v_peak = v_peak.max(v.abs());
                a_peak = a_peak.max(a[j].abs());
            }
            let a_end = a[a.len() - 1];
            if a_end.abs() > AT_REST * a_peak {
                return Err(format!(
                    "does not end at rest: the last {name} is {a_end:e} m/s², more than {AT_REST} of its peak {a_peak:e} m/s² (taper the record's end and correct its baseline, docs/seismic.md)"
                ));
            }
            if v.abs() > AT_REST * v_peak {
                return Err(format!(
                    "does not end at rest: {name} integrates to a final velocity of {v:e} m/s, more than {AT_REST} of its peak {v_peak:e} m/s (correct the record's baseline, docs/seismic.md)"
                ));
            }
        }
        Ok(())
    }

    /// The time of the last sample (s): the record's end, after which the ground is at rest.
    pub fn end(&self) -> f64 {
        (self.samples.len() - 1) as f64 * self.dt
    }

    /// The sample step (s).
    pub fn time_step(&self) -> f64 {
        self.dt
    }

    /// The samples.
    pub fn samples(&self) -> &[[f64; AXES]] {
        &self.samples
    }

    /// The acceleration at `t` (s): linear between samples, zero before 0 and after the last
    /// sample.
    pub fn acceleration(&self, t: f64) -> [f64; AXES] {
        let s = t / self.dt;
        let n = self.samples.len();
        // Compared as floats before any index is formed: a huge t/Δt saturates a cast.
        if s.is_nan() || s < 0.0 || s > (n - 1) as f64 {
            return [0.0; AXES];
        }
        let i = s.floor();
        let k = i as usize;
        if k + 1 >= n {
            return self.samples[n - 1];
        }
        let f = s - i;
        let (a, b) = (self.samples[k], self.samples[k + 1]);
        std::array::from_fn(|d| a[d] + f * (b[d] - a[d]))
    }
}

impl From<&Accelerogram> for GroundRecord {
    fn from(a: &Accelerogram) -> Self {
        GroundRecord {
            dt: a.dt_s,
            samples: (0..a.x.len()).map(|i| [a.x[i], a.y[i], a.z[i]]).collect(),
        }
    }
}

/// What one support follows.
#[derive(Clone, Debug, PartialEq)]
struct Source {
    /// Index into [`SupportMotion::records`].
    record: usize,
    /// The support follows the record this much later (s).
    delay: f64,
    /// Static displacement (m) along x, y, z, present from before t = 0.
    settlement: [f64; AXES],
}

/// The ground motion at each support (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct SupportMotion {
    records: Vec<GroundRecord>,
    sources: Vec<Source>,
}

impl SupportMotion {
    /// No dynamic motion (a zero record) at `supports` supports: a base for settlements.
    pub fn at_rest(supports: usize) -> Self {
        Self::uniform(
            GroundRecord {
                dt: 1.0,
                samples: vec![[0.0; AXES]],
            },
            supports,
        )
    }

    /// Every support follows `record` at the same time.
    pub fn uniform(record: GroundRecord, supports: usize) -> Self {
        SupportMotion {
            records: vec![record],
            sources: (0..supports)
                .map(|_| Source {
                    record: 0,
                    delay: 0.0,
                    settlement: [0.0; AXES],
                })
                .collect(),
        }
    }

    /// Wave passage: the support at `positions[k]` (m along the line) follows `record`
    /// delayed by `(positions[k] − min position) / apparent_speed`.
    pub fn wave_passage(
        record: GroundRecord,
        positions: &[f64],
        apparent_speed: f64,
    ) -> crate::Result<Self> {
        if !(apparent_speed.is_finite() && apparent_speed > 0.0) {
            return Err(Error::invalid(
                "support.apparent_speed_m_per_s",
                format!("must be > 0, got {apparent_speed}"),
            ));
        }
        if positions.iter().any(|x| !x.is_finite()) {
            return Err(Error::invalid("support.positions", "must be finite"));
        }
        let first = positions.iter().copied().fold(f64::INFINITY, f64::min);
        let mut m = Self::uniform(record, positions.len());
        for (s, &x) in m.sources.iter_mut().zip(positions) {
            s.delay = (x - first) / apparent_speed;
        }
        Ok(m)
    }

    /// Support k follows `records[k]`.
    pub fn per_support(records: Vec<GroundRecord>) -> Self {
        SupportMotion {
            sources: (0..records.len())
                .map(|k| Source {
                    record: k,
                    delay: 0.0,
                    settlement: [0.0; AXES],
                })
                .collect(),
            records,
        }
    }

    /// The same motion with support `k` settled statically by `by` (m along x, y, z; a pier
    /// that sinks 10 mm is `[0, 0, −0.01]`).
    pub fn with_settlement(mut self, k: usize, by: [f64; AXES]) -> crate::Result<Self> {
        let n = self.sources.len();
        let s = self.sources.get_mut(k).ok_or_else(|| {
            Error::invalid(
                "support.settlement.support",
                format!("must be below the number of supports {n}, got {k}"),
            )
        })?;
        if by.iter().any(|v| !v.is_finite()) {
            return Err(Error::invalid("support.settlement", "must be finite"));
        }
        s.settlement = by;
        Ok(self)
    }

    /// Number of supports.
    pub fn supports(&self) -> usize {
        self.sources.len()
    }

    /// Whether support `k`'s record has ended by time `t` (its ground is at rest from then).
    pub fn ended(&self, k: usize, t: f64) -> bool {
        let s = &self.sources[k];
        t - s.delay > self.records[s.record].end()
    }

    /// The dynamic ground acceleration at support `k` at time `t` (m/s²).
    pub fn acceleration(&self, k: usize, t: f64) -> [f64; AXES] {
        let s = &self.sources[k];
        self.records[s.record].acceleration(t - s.delay)
    }

    /// The static settlement of support `k` (m).
    pub fn settlement(&self, k: usize) -> [f64; AXES] {
        self.sources[k].settlement
    }
}

/// Displacement, velocity and acceleration of the ground at one support, per direction.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GroundState {
    pub d: [f64; AXES],
    pub v: [f64; AXES],
    pub a: [f64; AXES],
}

impl GroundState {
    /// At rest at `d` with acceleration `a` (the state at t = 0).
    pub fn at(d: [f64; AXES], a: [f64; AXES]) -> Self {
        GroundState {
            d,
            v: [0.0; AXES],
            a,
        }
    }

    /// The state one step `dt` later, where the acceleration is `a1` (Eq. S2, the trapezoid
    /// rule, average-acceleration Newmark with the acceleration prescribed):
    /// v₁ = v + Δt (a + a₁)/2, d₁ = d + Δt v + Δt² (a + a₁)/4.
    pub fn step(&self, dt: f64, a1: [f64; AXES]) -> Self {
        let mut next = GroundState { a: a1, ..*self };
        for (i, &a1i) in a1.iter().enumerate() {
            let sum = self.a[i] + a1i;
            next.v[i] = self.v[i] + 0.5 * dt * sum;
            next.d[i] = self.d[i] + dt * self.v[i] + 0.25 * dt * dt * sum;
        }
        next
    }
}

impl GroundState {
    /// The state one step `dt` later once the record has ended: at rest, its displacement
    /// advanced by the trapezoid rule on the velocity (v₀ + 0)/2 and held from then on. A
    /// record that ends at rest has v₀ = 0 there (to its check, [`AT_REST`]); integrating on
    /// instead would carry any residual velocity, Δt·a_N/2 of a last sample a_N ≠ 0, into a
    /// drift that never ends.
    pub fn at_rest(&self, dt: f64) -> Self {
        let mut next = GroundState::default();
        for i in 0..AXES {
            next.d[i] = self.d[i] + 0.5 * dt * self.v[i];
        }
        next
    }
}

/// The ground at every support of a structure on the committed state and at the end of the
/// current step: the clock of a guideway under support motion.
///
/// The clock is the step count: the trial step ends at `(steps + 1)·Δt`, the time loop's
/// `t = n·Δt` from t = 0 (`simulation/time_loop.rs`), so the `Guideway` interface needs no
/// time argument. At t = 0 each support rests at its settlement with the record's
/// acceleration there.
#[derive(Clone, Debug)]
pub struct GroundTrack {
    motion: SupportMotion,
    committed: Vec<GroundState>,
    trial: Vec<GroundState>,
    steps: u64,
    /// `trial` holds the ground at the end of the current step.
    trial_valid: bool,
}

impl GroundTrack {
    /// The bearing motions of span `span` (on supports `span` and `span + 1`) from the trial
    /// ground's accelerations, in the order of [`BEARINGS`]: z left, z right, y left, y right.
    pub fn bearing_accelerations(&self, span: usize) -> [f64; BEARINGS] {
        let (l, r) = (&self.trial[span].a, &self.trial[span + 1].a);
        [l[2], r[2], l[1], r[1]]
    }

    /// The quasi-static rigid-body motion (y, z) of span `span` at `xi` = x/L along it on the
    /// trial ground (Eq. S3): linear between its two supports.
    pub fn rigid_body(&self, span: usize, xi: f64) -> (f64, f64) {
        let g = &self.trial;
        let at = |axis: usize| (1.0 - xi) * g[span].d[axis] + xi * g[span + 1].d[axis];
        (at(1), at(2))
    }

    /// At t = 0 (module docs), for a structure with `supports` supports; `motion` must give
    /// that many, else one line naming `support` and saying what the structure `has`.
    pub fn new(motion: SupportMotion, supports: usize, has: &str) -> crate::Result<Self> {
        if motion.supports() != supports {
            return Err(Error::invalid(
                "support",
                format!("gives the motion of {} supports, {has}", motion.supports()),
            ));
        }
        let ground: Vec<GroundState> = (0..supports)
            .map(|k| GroundState::at(motion.settlement(k), motion.acceleration(k, 0.0)))
            .collect();
        Ok(GroundTrack {
            motion,
            trial: ground.clone(),
            committed: ground,
            steps: 0,
            trial_valid: false,
        })
    }

    /// The ground at the end of the current step (Eq. S2; computed once per step). No
    /// allocation.
    pub fn prepare(&mut self, dt: f64) {
        if self.trial_valid {
            return;
        }
        let t = (self.steps + 1) as f64 * dt;
        for (k, (g1, g0)) in self.trial.iter_mut().zip(&self.committed).enumerate() {
            *g1 = if self.motion.ended(k, t) {
                g0.at_rest(dt)
            } else {
                g0.step(dt, self.motion.acceleration(k, t))
            };
        }
        self.trial_valid = true;
    }

    /// Accept the step's ground (after [`Self::prepare`]).
    pub fn commit(&mut self) {
        self.committed.copy_from_slice(&self.trial);
        self.steps += 1;
        self.trial_valid = false;
    }

    /// The ground on the committed state, one per support.
    pub fn committed(&self) -> &[GroundState] {
        &self.committed
    }

    /// The ground at the end of the current step once prepared, else the committed ground
    /// (what a trial state is read against).
    pub fn trial(&self) -> &[GroundState] {
        &self.trial
    }
}

/// One ground spring `k` and dashpot `c` of a structure: it holds DOF `dof`, its ground end
/// moves with support `support`'s ground along direction `axis` (0, 1, 2: x, y, z).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GroundLink {
    pub dof: usize,
    pub support: usize,
    pub axis: usize,
    pub k: f64,
    pub c: f64,
}

/// Add the support-motion loads `k·u_g + c·v_g` (Eq. S1) of `links` for the ground states
/// `ground` (one per support) to `f`. No allocation.
pub fn add_ground_loads(links: &[GroundLink], ground: &[GroundState], f: &mut [f64]) {
    for l in links {
        let g = &ground[l.support];
        f[l.dof] += l.k * g.d[l.axis] + l.c * g.v[l.axis];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(dt: f64, n: usize, a: impl Fn(f64) -> [f64; AXES]) -> GroundRecord {
        GroundRecord::new(dt, (0..=n).map(|i| a(i as f64 * dt)).collect()).unwrap()
    }

    /// Constant acceleration from rest: the trapezoid rule gives d = a t²/2, v = a t exactly.
    #[test]
    fn trapezoid_is_exact_for_constant_acceleration() {
        let dt = 0.01;
        let mut g = GroundState::at([0.0; AXES], [0.5, -2.0, 9.0]);
        for n in 1..=1000 {
            g = g.step(dt, [0.5, -2.0, 9.0]);
            let t = n as f64 * dt;
            for (i, a) in [0.5, -2.0, 9.0].into_iter().enumerate() {
                assert!((g.v[i] - a * t).abs() <= 1e-12 * (a * t).abs());
                assert!((g.d[i] - a * t * t / 2.0).abs() <= 1e-12 * (a * t * t / 2.0).abs());
            }
        }
    }

    /// a = sin ωt from rest: v = (1 − cos ωt)/ω and d = (t − sin ωt / ω)/ω, with the trapezoid
    /// rule's error of second order (halving Δt divides it by 4 within 1 %).
    #[test]
    fn trapezoid_converges_at_second_order() {
        let w = 2.0 * std::f64::consts::PI * 1.7;
        let end = 2.0;
        let error = |dt: f64| {
            let n = (end / dt).round() as usize;
            let mut g = GroundState::default();
            let mut worst = 0.0f64;
            for k in 1..=n {
                let t = k as f64 * dt;
                g = g.step(dt, [(w * t).sin(), 0.0, 0.0]);
                let d = (t - (w * t).sin() / w) / w;
                worst = worst.max((g.d[0] - d).abs());
            }
            worst
        };
        let (e1, e2) = (error(1e-2), error(5e-3));
        let ratio = e1 / e2;
        assert!((ratio - 4.0).abs() < 0.04, "{e1} {e2} {ratio}");
    }

    /// Linear between samples, exact at them, zero outside the record.
    #[test]
    fn record_interpolates_linearly() {
        // Δt = 1/16 s: every time below is exact in binary.
        let dt = 0.0625;
        let r = record(dt, 4, |t| [t, 2.0 * t, -t * t]);
        let at = |k: f64| r.acceleration(k * dt);
        assert_eq!(at(2.0), [2.0 * dt, 4.0 * dt, -4.0 * dt * dt]);
        assert_eq!(at(2.5), [2.5 * dt, 5.0 * dt, -(4.0 + 9.0) / 2.0 * dt * dt]);
        assert_eq!(at(4.0), [4.0 * dt, 8.0 * dt, -16.0 * dt * dt]);
        assert_eq!(at(-0.1), [0.0; AXES]);
        assert_eq!(at(4.2), [0.0; AXES]);
    }

    /// Wave passage: support k follows the record delayed by (x_k − x_min)/c.
    #[test]
    fn wave_passage_delays_each_support() {
        let r = record(0.01, 400, |t| [t.sin(), (2.0 * t).cos(), t]);
        let x = [30.0, 0.0, 90.0];
        let m = SupportMotion::wave_passage(r.clone(), &x, 300.0).unwrap();
        for (k, xk) in x.iter().enumerate() {
            for t in [0.35, 1.0, 2.5] {
                assert_eq!(m.acceleration(k, t), r.acceleration(t - xk / 300.0));
            }
        }
        assert!(SupportMotion::wave_passage(r, &x, 0.0).is_err());
    }

    /// The accelerogram's CSV reads back to the same samples; malformed files are refused
    /// with the line.
    #[test]
    fn csv_reads_the_accelerogram_shape() {
        let text = format!(
            "{HEADER}\n0.000,0e0,0e0,0e0\n0.005,1.5e-3,1e0,-2e0\n0.010,-1.5e-3,-1e0,2e0\n0.015,0,0,0\n"
        );
        let r = GroundRecord::from_csv("quake.csv", &text).unwrap();
        assert_eq!(
            r.samples(),
            &[
                [0.0; 3],
                [1.5e-3, 1.0, -2.0],
                [-1.5e-3, -1.0, 2.0],
                [0.0; 3]
            ]
        );
        assert!((r.time_step() - 0.005).abs() < 1e-15);
        let bad_t = format!("{HEADER}\n0.000,0,0,0\n0.005,0,0,0\n0.020,0,0,0\n");
        let e = GroundRecord::from_csv("quake.csv", &bad_t)
            .unwrap_err()
            .to_string();
        assert!(e.contains("row 3"), "{e}");
        let e = GroundRecord::from_csv("quake.csv", "t,a\n0,0\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 1"), "{e}");
        let e = GroundRecord::from_csv("quake.csv", &format!("{HEADER}\n0,0,0\n0.1,0,0,0\n"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 2"), "{e}");
    }

    /// A sample step outside [`DT_LIMITS_S`] is refused naming it (Δt = 1e-300 s indexed
    /// usize::MAX: t/Δt saturated the cast), and a time far beyond the record reads zero.
    #[test]
    fn the_sample_step_is_bounded_and_no_time_indexes_past_the_record() {
        for dt in ["1e-300", "1e-7", "0.5"] {
            let text = format!("{HEADER}\n0,0,0,0\n{dt},0,0,0\n");
            let e = GroundRecord::from_csv("quake.csv", &text)
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("support.record.dt: must be within [0.000001, 0.1] s")
                    && !e.contains('\n'),
                "{dt}: {e}"
            );
        }
        let dt = 1.0 / 1024.0;
        let r = record(dt, 4, |_| [0.0, 0.0, 1.0]);
        for t in [1e300, f64::MAX, f64::INFINITY, 4.0 * dt, 4.0 * dt + 1e-12] {
            let want = if t == 4.0 * dt {
                [0.0, 0.0, 1.0]
            } else {
                [0.0; AXES]
            };
            assert_eq!(r.acceleration(t), want, "t = {t:e}");
        }
    }

    /// A record of the user's must end at rest ([`AT_REST`]): a last sample or a final
    /// velocity beyond 1e-3 of its peak is refused saying which; a residual displacement is
    /// kept.
    #[test]
    fn a_record_that_does_not_end_at_rest_is_refused_saying_why() {
        let csv = |rows: &[[f64; 3]]| {
            let mut t = format!("{HEADER}\n");
            for (j, r) in rows.iter().enumerate() {
                t += &format!("{},{},{},{}\n", j as f64 * 0.01, r[0], r[1], r[2]);
            }
            t
        };
        let e =
            GroundRecord::from_csv("q.csv", &csv(&[[0.0; 3], [0.0, 1.0, 0.0], [0.0, 1.0, 0.0]]))
                .unwrap_err()
                .to_string();
        assert!(
            e.contains("does not end at rest: the last ay is 1e0 m/s²"),
            "{e}"
        );
        let e = GroundRecord::from_csv("q.csv", &csv(&[[0.0; 3], [0.0, 0.0, 1.0], [0.0; 3]]))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("does not end at rest: az integrates to a final velocity of 1e-2 m/s"),
            "{e}"
        );
        // Up, down, at rest: velocity back to zero, the ground displaced: accepted.
        GroundRecord::from_csv(
            "q.csv",
            &csv(&[[0.0; 3], [1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0; 3]]),
        )
        .unwrap();
    }
}
