//! The accurate scheme ([`super::Scheme::Accurate`]): the coil + PI equations (Eq. 9 + 10)
//! integrated over one outer step by the 2-stage Gauss–Legendre method (order 4).
//!
//! # Why
//! The paper's Eq. 14 is first order in its sub-step `δ = Δt/n_sub` (docs/numerics.md), so the
//! paper asks for n_sub = 1000 — 1000 updates of a controller per magnet per outer step, which
//! dominates a coupled passage (docs/performance.md). As `n_sub → ∞` the paper scheme tends to
//! the continuous system below for every α (host-sim `stability::gloop`, `discrete`); this
//! module integrates that limit directly with a high-order A-stable method, so one outer step
//! costs one (or a few) 2×2 linear solves instead of 1000 sub-steps.
//!
//! # The continuous system (derived from Eq. 8–10)
//! `e = g0 − g` (Eq. 8), `G0·ġ + R0·h·g = V` (Eq. 9), `V = KP·e + KI·e_a`, `ė_a = e` (Eq. 10).
//! Divide Eq. 9 by `V_b = R0·i0 = R0·h0·g0` and write `g = g0(1 + x)`, `h = h0(1 + η)`,
//! `KI·e_a = V_b(1 + y)`: then `V/V_b = 1 + y − kpv·x` and `R0·h·g/V_b = (1 + η)(1 + x)`, so
//!
//! ```text
//! τ·ẋ = 1 + y − kpv·x − (1 + η)(1 + x) = y − η − p(η)·x,   p(η) = 1 + kpv + η
//! ẏ   = KI·(g0 − g)/V_b = −ki·x
//! τ = G0·g0/V_b = 2·K0·g0/V_b (s),  kpv = KP·g0/V_b,  ki = KI·g0/V_b (1/s)
//! ```
//!
//! For a given gap history `η(t)` this is **linear** in `z = (x, y)`: `ż = J(t)·z + f(t)` with
//! `J = [[−p(η)/τ, 1/τ], [−ki, 0]]`, `f = (−η/τ, 0)`. Inside the outer step `η` is the same
//! polynomial the paper scheme uses, `η(s) = η0 + s·b1 + s²·b2`, `s = (t − t0)/Δt ∈ [0, 1]`
//! (linear or parabolic interpolation, docs/model.md §4), so `J` and `f` are smooth within the step
//! and the method keeps its full order there.
//!
//! # The method
//! The outer step is split into `m` equal intervals of length `h = Δt/m`; on each, 2-stage
//! Gauss–Legendre (nodes `c = ½ ∓ √3/6`, weights `b = ½, ½`, Butcher matrix `A`) with the
//! per-unit stage increments `u_i = h·ẋ(stage i)`. The `y` stages are linear in the `x`
//! stages (`ẏ = −ki·x`) and are eliminated exactly, leaving one 2×2 solve (Cramer's rule):
//!
//! ```text
//! [I + c·(diag(p_i)·A + kh·A²)]·u = c·r,   r_i = y − η_i − (p_i + kh·c_i)·x
//! x' = x + (u_1 + u_2)/2,                  y' = y − kh·(x + Σ_j (bᵀA)_j·u_j)
//! c = h/τ,  kh = ki·h,  η_i = η(s_i) at the Gauss nodes,  p_i = 1 + kpv + η_i
//! v' = 1 + y' − kpv·x'                      (Eq. 10, per unit)
//! ```
//!
//! Gauss–Legendre is A-stable (its amplification is the (2, 2) Padé approximant of `e^{hJ}`),
//! so no step is unstable, and at a constant gap it is exact at equilibrium: `x = 0, y = η`
//! gives `r = 0`, hence `u = 0`, in every number type.
//!
//! # How many intervals (error estimate)
//! The local error of the (2, 2) Padé approximant is `(hλ)^5/720` per unit of state
//! (`e^z − R(z) = z^5/720 + O(z^6)`), i.e. `ω^5·h^4/720` per unit time, `ω` the largest
//! `|λ|` of `J`. For `τ·s² + p·s + ki = 0`, `|λ| = √(ki/τ)` when complex and `≤ p/τ` when real;
//! we take `ω = max(√(ki/τ), p(1)/τ)` (gap up to `2·h0`). `m` is the smallest number of
//! intervals with `ω^5·h^4/720 ≤ ε`, [`ERROR_RATE`] `ε = 1e-6` per second, capped at
//! [`MAX_INTERVALS`]: the global error over a 1-s passage is then ≲ `ε·1 s` per unit of the
//! state's excursion, below the paper scheme's at n_sub = 1000 (≈ `δ·0.75 s⁻¹`, δ = Δt/1000,
//! docs/numerics.md §4) for Δt ≥ ~1e-4 s. Paper values: `ω = 38.8 s⁻¹`, `h ≤ 1.69 ms`:
//! `m = 1` for Δt ≤ 1.69 ms, `m = 6` at Δt = 10 ms.
//!
//! # Bounds (same rules as the paper scheme, decided per interval)
//! * Current clamp: if `x' < −1` it is held at `−1` ([`Status::CURRENT_CLAMPED`]) and the
//!   integral is recomputed with the trapezoid `y' = y − kh·(x + x')/2` on the clamped end,
//!   as Eq. 12 does in the paper scheme.
//! * Voltage bound: if the unconstrained interval ends with `|v'| > v_max`, the interval is
//!   redone with the coil alone driven at `V = ±v_max` (`τ·ẋ = v_s − (1 + η)(1 + x)`, the
//!   same Gauss method, a 2×2 solve with `A` only) and the integral frozen (anti-windup),
//!   [`Status::VOLTAGE_SATURATED`]. The bound is thus decided at interval ends, as the paper
//!   scheme decides it at sub-step ends: where it switches on or off inside an interval the
//!   switching instant is resolved only to the interval (no event location). Measured on a
//!   saturating gap ramp (tests/tests/accurate_vs_paper.rs): 1.3e-5 of p0 at Δt = 1 ms
//!   against 7.6e-7 for the paper scheme at n_sub = 1000, and 9.5e-7 at Δt = 0.5 ms — while the
//!   bound switches, this scheme is not more accurate than the paper's internal loop.
//! * Collision, invalid input and overflow are handled by [`super::Levitation::update`] before
//!   and after this module, identically for both schemes.

use super::{convert, ParamError, Params, Status};
use crate::scalar::Scalar;

/// Target local error per unit time of the interval-count estimate (per unit of state, 1/s).
pub const ERROR_RATE: f64 = 1e-6;

/// Upper bound on the number of Gauss intervals per outer step.
pub const MAX_INTERVALS: u32 = 64;

/// √3/6, the offset of the Gauss nodes from the interval's midpoint.
const R3_6: f64 = 0.288_675_134_594_812_9;

/// The number of Gauss intervals `m` per outer step of `p` (module docs, "How many
/// intervals"). Assumes `p` validated.
pub fn intervals(p: &Params) -> u32 {
    let (tau, kpv, ki) = loop_constants(p);
    let omega = libm::sqrt(ki / tau).max((2.0 + kpv) / tau);
    let h_max = libm::pow(720.0 * ERROR_RATE / libm::pow(omega, 5.0), 0.25);
    let m = libm::ceil(p.dt / h_max);
    if m.is_nan() || m < 1.0 {
        1
    } else if m > MAX_INTERVALS as f64 {
        MAX_INTERVALS
    } else {
        m as u32
    }
}

/// `(τ, kpv, ki)` of the module docs.
fn loop_constants(p: &Params) -> (f64, f64, f64) {
    let vb = p.v_base();
    let g0 = p.g0();
    (2.0 * p.k0() * g0 / vb, p.kp * g0 / vb, p.ki * g0 / vb)
}

/// The gap over the outer step: `η(s) = η0 + s·(b1 + s·b2)`, `s ∈ [0, 1]`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Gap<S> {
    pub eta0: S,
    pub b1: S,
    pub b2: S,
}

impl<S: Scalar> Gap<S> {
    #[inline]
    fn at(&self, s: S, ov: &mut bool) -> S {
        let quad = s.smul(self.b2, ov);
        self.eta0.sadd(s.smul(self.b1.sadd(quad, ov), ov), ov)
    }
}

/// The compiled coefficients of the Gauss–Legendre step (module docs).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Gauss<S> {
    /// Intervals per outer step.
    m: u32,
    /// `1/m`: the interval as a fraction of the outer step.
    inv_m: S,
    /// `c_i/m`: the Gauss nodes inside the first interval, as fractions of the outer step.
    nodes: [S; 2],
    /// `c = h/τ`.
    c: S,
    /// `kh = ki·h`.
    kh: S,
    /// `kpv = KP·g0/V_b`.
    kpv: S,
    /// Butcher matrix `A`, its square, `bᵀA`, the nodes `c_i`.
    a: [[S; 2]; 2],
    a2: [[S; 2]; 2],
    ba: [S; 2],
    cn: [S; 2],
    half: S,
}

impl<S: Scalar> Gauss<S> {
    /// Converts the coefficients of `p` (validated) to `S`, each within `tolerance`.
    pub(super) fn compile(p: &Params, tolerance: f64) -> Result<Self, ParamError> {
        let (tau, kpv, ki) = loop_constants(p);
        let m = intervals(p);
        let h = p.dt / m as f64;
        let cn = [0.5 - R3_6, 0.5 + R3_6];
        let a = [[0.25, 0.25 - R3_6], [0.25 + R3_6, 0.25]];
        let mut a2 = [[0.0; 2]; 2];
        for (i, row) in a2.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = a[i][0] * a[0][j] + a[i][1] * a[1][j];
            }
        }
        let ba = [0.5 * (a[0][0] + a[1][0]), 0.5 * (a[0][1] + a[1][1])];
        let cv = |name, v| convert::<S>(crate::law::Field::derived(None, name), v, tolerance);
        let mat = |name, m: [[f64; 2]; 2]| -> Result<[[S; 2]; 2], ParamError> {
            Ok([
                [cv(name, m[0][0])?, cv(name, m[0][1])?],
                [cv(name, m[1][0])?, cv(name, m[1][1])?],
            ])
        };
        let inv_m = 1.0 / m as f64;
        Ok(Gauss {
            m,
            inv_m: cv("1/m", inv_m)?,
            nodes: [cv("c1/m", cn[0] * inv_m)?, cv("c2/m", cn[1] * inv_m)?],
            c: cv("h/tau", h / tau)?,
            kh: cv("ki*h", ki * h)?,
            kpv: cv("kpv", kpv)?,
            a: mat("gauss A", a)?,
            a2: mat("gauss A^2", a2)?,
            ba: [cv("gauss bA", ba[0])?, cv("gauss bA", ba[1])?],
            cn: [cv("gauss c", cn[0])?, cv("gauss c", cn[1])?],
            half: cv("1/2", 0.5)?,
        })
    }

    /// Intervals per outer step.
    pub(super) fn m(&self) -> u32 {
        self.m
    }

    /// One outer step from `(x, y, v)` over the gap `eta`: `m` Gauss intervals. Returns the
    /// new `(x, y, v)`; events go to `status`, overflow to `ov`.
    #[allow(clippy::too_many_arguments)]
    ///
    /// A reference `g0·(1 + r)` for the inner law (an outer gap loop, held over the step)
    /// enters as `τ·ẋ = ỹ − η − p·x`, `ỹ' = −ki·x + ki·r` with the shifted integral
    /// `ỹ = y + kpv·r`: the same system plus a constant forcing, which the Gauss stages
    /// integrate exactly (`kh·r·c_i` at the nodes, `kh·r` over the interval). `r = 0` is the
    /// paper's law bit for bit.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn step(
        &self,
        mut x: S,
        y: S,
        mut v: S,
        eta: &Gap<S>,
        r: S,
        v_max: S,
        status: &mut Status,
        ov: &mut bool,
    ) -> (S, S, S) {
        let shift = self.kpv.smul(r, ov);
        let mut yt = y.sadd(shift, ov);
        let khr = self.kh.smul(r, ov);
        let mut s0 = S::ZERO;
        for _ in 0..self.m {
            let e = [
                eta.at(s0.sadd(self.nodes[0], ov), ov),
                eta.at(s0.sadd(self.nodes[1], ov), ov),
            ];
            (x, yt, v) = self.interval(x, yt, e, khr, v_max, status, ov);
            s0 = s0.sadd(self.inv_m, ov);
        }
        (x, yt.ssub(shift, ov), v)
    }
}

impl Gauss<f64> {
    /// [`Gauss::step`] without a reference (`r = 0`) in plain f64, for hosts
    /// ([`super::batch::update_batch`]): the same operations in the same order, including the
    /// reference's zero terms (they decide the sign of a zero), unchecked. `None` (the caller
    /// then runs the general path) if an interval meets the current floor or the voltage
    /// bound, or if a determinant, scale, stage increment or an interval's result is not
    /// finite. Every non-finite intermediate reaches one of these (the division is the one
    /// operation that can absorb an infinity, and its inputs and result are checked), so
    /// wherever this returns a value the checked path returns the same bits with no event and
    /// no overflow.
    #[inline]
    pub(super) fn step_nominal(
        &self,
        x: f64,
        y: f64,
        eta: &Gap<f64>,
        v_max: f64,
    ) -> Option<(f64, f64, f64)> {
        let r = 0.0;
        let shift = self.kpv * r;
        let mut yt = y + shift;
        let khr = self.kh * r;
        let (mut x, mut v) = (x, 0.0);
        let mut s0 = 0.0;
        let at = |s: f64| eta.eta0 + s * (eta.b1 + s * eta.b2);
        let mut finite = true;
        for _ in 0..self.m {
            let e = [at(s0 + self.nodes[0]), at(s0 + self.nodes[1])];
            let p = [(1.0 + self.kpv) + e[0], (1.0 + self.kpv) + e[1]];
            let mij = |i: usize, j: usize| {
                let d = self.c * (p[i] * self.a[i][j] + self.kh * self.a2[i][j]);
                if i == j {
                    1.0 + d
                } else {
                    d
                }
            };
            let m = [[mij(0, 0), mij(0, 1)], [mij(1, 0), mij(1, 1)]];
            let ri = |i: usize| {
                let f = p[i] + self.kh * self.cn[i];
                let forced = yt + khr * self.cn[i];
                (forced - e[i]) - f * x
            };
            let rr = [ri(0), ri(1)];
            let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
            let scale = self.c / det;
            let w0 = m[1][1] * rr[0] - m[0][1] * rr[1];
            let w1 = m[0][0] * rr[1] - m[1][0] * rr[0];
            let u = [w0 * scale, w1 * scale];
            let x1 = x + (u[0] + u[1]) * self.half;
            let bau = self.ba[0] * u[0] + self.ba[1] * u[1];
            let y1 = (yt - self.kh * (x + bau)) + khr;
            if x1 < -1.0 {
                return None;
            }
            let v1 = (1.0 + y1) - self.kpv * x1;
            if v1 > v_max || v1 < -v_max {
                return None;
            }
            finite &= (det + scale + u[0] + u[1] + x1 + y1 + v1).is_finite();
            (x, yt, v) = (x1, y1, v1);
            s0 += self.inv_m;
        }
        finite.then_some((x, yt - shift, v))
    }
}

impl<S: Scalar> Gauss<S> {
    /// One Gauss interval with the gap `e` at its two nodes (module docs, "The method").
    #[inline]
    #[allow(clippy::too_many_arguments)]
    fn interval(
        &self,
        x: S,
        y: S,
        e: [S; 2],
        khr: S,
        v_max: S,
        status: &mut Status,
        ov: &mut bool,
    ) -> (S, S, S) {
        let one = S::ONE;
        let p = [
            one.sadd(self.kpv, ov).sadd(e[0], ov),
            one.sadd(self.kpv, ov).sadd(e[1], ov),
        ];
        // M = I + c·(diag(p)·A + kh·A²)
        let mij = |i: usize, j: usize, ov: &mut bool| {
            let t = p[i]
                .smul(self.a[i][j], ov)
                .sadd(self.kh.smul(self.a2[i][j], ov), ov);
            let d = self.c.smul(t, ov);
            if i == j {
                one.sadd(d, ov)
            } else {
                d
            }
        };
        let m = [
            [mij(0, 0, ov), mij(0, 1, ov)],
            [mij(1, 0, ov), mij(1, 1, ov)],
        ];
        let r = |i: usize, ov: &mut bool| {
            let f = p[i].sadd(self.kh.smul(self.cn[i], ov), ov);
            // The reference's forcing reaches the integral at node i as kh·r·c_i.
            let forced = y.sadd(khr.smul(self.cn[i], ov), ov);
            forced.ssub(e[i], ov).ssub(f.smul(x, ov), ov)
        };
        let u = self.solve(&m, [r(0, ov), r(1, ov)], ov);
        let mut x1 = x.sadd(u[0].sadd(u[1], ov).smul(self.half, ov), ov);
        let bau = self.ba[0]
            .smul(u[0], ov)
            .sadd(self.ba[1].smul(u[1], ov), ov);
        let mut y1 = y.ssub(self.kh.smul(x.sadd(bau, ov), ov), ov).sadd(khr, ov);
        let x_floor = one.sneg(ov);
        if x1 < x_floor {
            x1 = x_floor;
            *status = status.union(Status::CURRENT_CLAMPED);
            // Eq. 12's trapezoid on the clamped end, as in the paper scheme.
            let mean = x.sadd(x1, ov).smul(self.half, ov);
            y1 = y.ssub(self.kh.smul(mean, ov), ov).sadd(khr, ov);
        }
        let v1 = one.sadd(y1, ov).ssub(self.kpv.smul(x1, ov), ov);
        if v1 > v_max || v1 < v_max.sneg(ov) {
            *status = status.union(Status::VOLTAGE_SATURATED);
            let vs = if v1 > v_max { v_max } else { v_max.sneg(ov) };
            return (self.coil_alone(x, vs, e, status, ov), y, vs);
        }
        (x1, y1, v1)
    }

    /// The coil alone at voltage `vs` over one interval, `τ·ẋ = vs − (1 + η)(1 + x)`, by the
    /// same Gauss method: `[I + c·diag(q_i)·A]·u = c·(vs − q_i·(1 + x))`, `q_i = 1 + η_i`.
    fn coil_alone(&self, x: S, vs: S, e: [S; 2], status: &mut Status, ov: &mut bool) -> S {
        let one = S::ONE;
        let q = [one.sadd(e[0], ov), one.sadd(e[1], ov)];
        let g = one.sadd(x, ov);
        let mij = |i: usize, j: usize, ov: &mut bool| {
            let d = self.c.smul(q[i].smul(self.a[i][j], ov), ov);
            if i == j {
                one.sadd(d, ov)
            } else {
                d
            }
        };
        let m = [
            [mij(0, 0, ov), mij(0, 1, ov)],
            [mij(1, 0, ov), mij(1, 1, ov)],
        ];
        let r = [vs.ssub(q[0].smul(g, ov), ov), vs.ssub(q[1].smul(g, ov), ov)];
        let u = self.solve(&m, r, ov);
        let xs = x.sadd(u[0].sadd(u[1], ov).smul(self.half, ov), ov);
        let x_floor = one.sneg(ov);
        if xs < x_floor {
            *status = status.union(Status::CURRENT_CLAMPED);
            return x_floor;
        }
        xs
    }

    /// `c·M⁻¹·r` by Cramer's rule, one division (a singular `M` saturates and flags, never
    /// panics).
    #[inline]
    fn solve(&self, m: &[[S; 2]; 2], r: [S; 2], ov: &mut bool) -> [S; 2] {
        let det = m[0][0]
            .smul(m[1][1], ov)
            .ssub(m[0][1].smul(m[1][0], ov), ov);
        let scale = self.c.sdiv(det, ov);
        let w0 = m[1][1].smul(r[0], ov).ssub(m[0][1].smul(r[1], ov), ov);
        let w1 = m[0][0].smul(r[1], ov).ssub(m[1][0].smul(r[0], ov), ov);
        [w0.smul(scale, ov), w1.smul(scale, ov)]
    }
}
