//! A 3-D high-speed car on rigid rails: body, two bogie frames and four wheelsets with the
//! lateral, vertical, roll, pitch and yaw motion that running safety needs (31 DOFs:
//! body and bogies y, z, φ, θ, ψ; wheelsets y, z, φ, ψ; the wheelsets' spin is the rolling
//! speed, not a DOF), primary and secondary suspension in three directions, and the
//! wheel–rail contact of [`super::wheelset`] under every wheelset. docs/cars.md, "The
//! high-speed car".
//!
//! The suspension is linear (`cars::link`, docs/model.md §6), written in deviations from the
//! static equilibrium; the contact forces are nonlinear, and enter as their change from the
//! static state, F(q, q̇) − F(0, 0), so that q = 0 is the exact equilibrium on smooth rails.
//! Gravity's moments under roll and pitch of the raised bodies (the pendulum terms) are
//! not modelled.

use super::wheelset::{
    rk4, ContactForces, Motion, RailPoint, WheelForce, Wheelset, WheelsetContact,
};
use crate::physics::cars::link::{add_spring_damper, Axis, End, Rigid, RX, RY, RZ, UY, UZ};
use crate::{Error, Result};
use nalgebra::{DMatrix, DVector};

/// Number of DOFs of the car.
pub const DOFS: usize = 31;

/// A spring–damper in three directions (x, y, z): stiffness N/m, damping N·s/m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spring3 {
    /// Stiffnesses (x, y, z), N/m.
    pub k: [f64; 3],
    /// Dampings (x, y, z), N·s/m.
    pub c: [f64; 3],
}

/// The car's parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HsrCar {
    /// Body mass, kg.
    pub body_mass: f64,
    /// Body inertias (roll, pitch, yaw), kg·m².
    pub body_inertia: [f64; 3],
    /// Bogie frame mass, kg.
    pub bogie_mass: f64,
    /// Bogie frame inertias (roll, pitch, yaw), kg·m².
    pub bogie_inertia: [f64; 3],
    /// The wheelsets and their contact.
    pub wheelset: Wheelset,
    /// Half the distance between the bogie centres, m.
    pub half_bogie_spacing: f64,
    /// Half the wheelbase, m.
    pub half_wheelbase: f64,
    /// Primary suspension, per axle box (two per wheelset).
    pub primary: Spring3,
    /// Half the lateral distance between the axle boxes, m.
    pub primary_half_span: f64,
    /// Secondary suspension, per air spring (two per bogie).
    pub secondary: Spring3,
    /// Half the lateral distance between the air springs, m.
    pub secondary_half_span: f64,
    /// Heights above the rail top of the body's centre of mass, the secondary springs and
    /// the bogie frame's centre of mass, m.
    pub heights: [f64; 3],
}

impl HsrCar {
    /// The high-speed passenger car of Zhai (*Vehicle–Track Coupled Dynamics*, 2020), as
    /// tabulated in VTCM_simulation's vehicle parameters (Zhai's table itself was not read):
    /// body 34 t, bogie frames 3 t, wheelsets 1.4 t, primary 1e7/5e6/5.5e5 N/m with
    /// 6 kN·s/m vertical, secondary 1.5e5/1.5e5/4e5 N/m with 60 and 80 kN·s/m lateral and
    /// vertical, bogie centres 18 m apart, wheelbase 2.4 m. The lateral spans (1.0 m) and
    /// heights (body 1.7 m, secondary 0.9 m, frame 0.6 m) are **estimates**.
    pub fn zhai_high_speed() -> Self {
        HsrCar {
            body_mass: 34_000.0,
            body_inertia: [75_060.0, 2_277_000.0, 2_086_000.0],
            bogie_mass: 3_000.0,
            bogie_inertia: [2_260.0, 2_710.0, 3_160.0],
            wheelset: Wheelset::high_speed(),
            half_bogie_spacing: 9.0,
            half_wheelbase: 1.2,
            primary: Spring3 {
                k: [1.0e7, 5.0e6, 5.5e5],
                c: [0.0, 0.0, 6.0e3],
            },
            primary_half_span: 1.0,
            secondary: Spring3 {
                k: [1.5e5, 1.5e5, 4.0e5],
                c: [0.0, 6.0e4, 8.0e4],
            },
            secondary_half_span: 1.0,
            heights: [1.7, 0.9, 0.6],
        }
    }

    /// The static load of one wheel, N: the car is symmetric fore–aft and left–right, so
    /// each of the 8 wheels carries 1/8 of the weight.
    pub fn wheel_load(&self, gravity: f64) -> f64 {
        (self.body_mass + 2.0 * self.bogie_mass + 4.0 * self.wheelset.mass) * gravity / 8.0
    }

    /// The x positions of the wheelsets (front first) relative to the car's centre, m.
    pub fn wheelset_x(&self) -> [f64; 4] {
        let (lc, lt) = (self.half_bogie_spacing, self.half_wheelbase);
        [lc + lt, lc - lt, -lc + lt, -lc - lt]
    }

    /// The DOFs (y, z, φ, ψ) of wheelset `k` (0..4).
    pub fn wheelset_dofs(k: usize) -> [usize; 4] {
        let base = 15 + 4 * k;
        [base, base + 1, base + 2, base + 3]
    }

    /// The body's DOFs (y, z, φ, θ, ψ); bogie j's are 5 + 5j + the same.
    pub const BODY: [usize; 5] = [0, 1, 2, 3, 4];

    /// M, C, K of the car's bodies and suspensions (the contact is not in them).
    pub fn matrices(&self) -> Result<[DMatrix<f64>; 3]> {
        let n = DOFS;
        let (mut m, mut c, mut k) = (
            DMatrix::zeros(n, n),
            DMatrix::zeros(n, n),
            DMatrix::zeros(n, n),
        );
        let [h_body, h_sec, h_bogie] = self.heights;
        let five = |at: [f64; 3], base: usize| {
            Rigid::new(at)
                .dof(UY, base)
                .dof(UZ, base + 1)
                .dof(RX, base + 2)
                .dof(RY, base + 3)
                .dof(RZ, base + 4)
        };
        let body = five([0.0, 0.0, h_body], 0);
        body.add_mass(&mut m, self.body_mass, self.body_inertia);
        let xs = self.wheelset_x();
        let r0 = self.wheelset.r0;
        let w = &self.wheelset;
        for j in 0..2 {
            let xb = if j == 0 {
                self.half_bogie_spacing
            } else {
                -self.half_bogie_spacing
            };
            let bogie = five([xb, 0.0, h_bogie], 5 + 5 * j);
            bogie.add_mass(&mut m, self.bogie_mass, self.bogie_inertia);
            for s in [1.0, -1.0] {
                let p = [xb, s * self.secondary_half_span, h_sec];
                for (axis, i) in [(Axis::X, 0), (Axis::Y, 1), (Axis::Z, 2)] {
                    let kc = (self.secondary.k[i], self.secondary.c[i]);
                    let (a, b) = (End { body: &body, p }, End { body: &bogie, p });
                    add_spring_damper(&mut k, &mut c, kc, axis, a, b)?;
                }
            }
            for kw in [2 * j, 2 * j + 1] {
                let [dy, dz, dphi, dpsi] = Self::wheelset_dofs(kw);
                let ws = Rigid::new([xs[kw], 0.0, r0])
                    .dof(UY, dy)
                    .dof(UZ, dz)
                    .dof(RX, dphi)
                    .dof(RZ, dpsi);
                ws.add_mass(&mut m, w.mass, [w.i_roll, 0.0, w.i_yaw]);
                for s in [1.0, -1.0] {
                    let p = [xs[kw], s * self.primary_half_span, r0];
                    for (axis, i) in [(Axis::X, 0), (Axis::Y, 1), (Axis::Z, 2)] {
                        let kc = (self.primary.k[i], self.primary.c[i]);
                        let (a, b) = (End { body: &bogie, p }, End { body: &ws, p });
                        add_spring_damper(&mut k, &mut c, kc, axis, a, b)?;
                    }
                }
            }
        }
        Ok([m, c, k])
    }
}

/// The rails under a wheelset at track position x (m) and time: (left, right).
pub trait Rails {
    /// The rails at `x` for a wheelset moving at `v` (m/s).
    fn at(&self, x: f64, v: f64) -> [RailPoint; 2];
}

/// Smooth rigid rails.
pub struct Smooth;

impl Rails for Smooth {
    fn at(&self, _x: f64, _v: f64) -> [RailPoint; 2] {
        [RailPoint::default(); 2]
    }
}

/// The car running at speed v on rigid rails: M⁻¹ of its matrices and its wheelsets'
/// contact.
pub struct Running {
    /// The car.
    pub car: HsrCar,
    /// Speed, m/s.
    pub v: f64,
    minv: DMatrix<f64>,
    minv_c: DMatrix<f64>,
    minv_k: DMatrix<f64>,
    /// [M⁻¹, −M⁻¹K, −M⁻¹C] row by row, each row's non-zero (column, value) pairs, for
    /// [`Running::rate_of`].
    rows: Vec<Vec<(usize, f64)>>,
    contact: WheelsetContact,
    /// The static contact forces of a centred wheelset (subtracted: deviations).
    rest: ContactForces,
}

impl Running {
    /// The car at speed `v` (> 0) under `gravity`.
    pub fn new(car: &HsrCar, v: f64, gravity: f64) -> Result<Self> {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::invalid(
                "train.speed_mps",
                format!("must be > 0, got {v}"),
            ));
        }
        let [m, c, k] = car.matrices()?;
        let minv = m
            .try_inverse()
            .ok_or_else(|| Error::numerical("high-speed car: singular mass matrix"))?;
        let contact = car.wheelset.contact(car.wheel_load(gravity));
        let rest = contact.forces(&Motion::default(), v, &[RailPoint::default(); 2]);
        let (minv_c, minv_k) = (&minv * c, &minv * k);
        // Row i of [M⁻¹, −M⁻¹K, −M⁻¹C], its non-zero entries in column order (the sums of
        // [`Running::rate_of`] then add the same terms in the same order as a dense row).
        let mut rows = Vec::with_capacity(DOFS);
        for i in 0..DOFS {
            let dense = (0..DOFS)
                .map(|j| minv[(i, j)])
                .chain((0..DOFS).map(|j| -minv_k[(i, j)]))
                .chain((0..DOFS).map(|j| -minv_c[(i, j)]));
            rows.push(
                dense
                    .enumerate()
                    .filter(|(_, a)| *a != 0.0)
                    .collect::<Vec<_>>(),
            );
        }
        Ok(Running {
            car: *car,
            v,
            minv_c,
            minv_k,
            minv,
            rows,
            contact,
            rest,
        })
    }

    /// The rail's force on a wheel of a centred wheelset at rest on smooth rails (left,
    /// right): the static state the contact forces are deviations from.
    pub fn rest_wheel(&self, side: usize) -> WheelForce {
        self.rest.wheels[side]
    }

    /// The contact forces of wheelset `k` at the car state (q, q̇) over `rails`, the
    /// wheelset at the track position `x` (m).
    pub fn wheelset_forces(
        &self,
        k: usize,
        q: &[f64],
        dq: &[f64],
        rails: &dyn Rails,
        x: f64,
    ) -> ContactForces {
        let d = HsrCar::wheelset_dofs(k);
        let m = Motion {
            q: d.map(|i| q[i]),
            dq: d.map(|i| dq[i]),
        };
        self.contact.forces(&m, self.v, &rails.at(x, self.v))
    }

    /// The generalised contact force on the car's DOFs, as deviation from rest.
    fn contact_load(&self, q: &[f64], dq: &[f64], rails: &dyn Rails, x_car: f64) -> DVector<f64> {
        let mut f = DVector::zeros(DOFS);
        for (k, xw) in self.car.wheelset_x().iter().enumerate() {
            let g = self
                .wheelset_forces(k, q, dq, rails, x_car + xw)
                .generalised;
            for (i, dof) in HsrCar::wheelset_dofs(k).iter().enumerate() {
                f[*dof] += g[i] - self.rest.generalised[i];
            }
        }
        f
    }

    /// d/dt of the state (q, q̇) at the car position `x_car`.
    pub fn rate(&self, state: &[f64], rails: &dyn Rails, x_car: f64) -> Vec<f64> {
        let mut s = [0.0; 2 * DOFS];
        s.copy_from_slice(state);
        self.rate_of(&s, rails, x_car).to_vec()
    }

    /// d/dt of the state (q, q̇) at the car position `x_car`, without allocating:
    /// q̈ = M⁻¹ F − M⁻¹K q − M⁻¹C q̇ (F the contact load as deviation from rest).
    pub fn rate_of(
        &self,
        state: &[f64; 2 * DOFS],
        rails: &dyn Rails,
        x_car: f64,
    ) -> [f64; 2 * DOFS] {
        self.rate_with(state, rails, x_car, &mut [WheelForce::default(); 8])
    }

    /// [`Running::rate_of`], writing the rail's force on every wheel (wheelset by
    /// wheelset, left then right) into `wheels`.
    pub fn rate_with(
        &self,
        state: &[f64; 2 * DOFS],
        rails: &dyn Rails,
        x_car: f64,
        wheels: &mut [WheelForce; 8],
    ) -> [f64; 2 * DOFS] {
        let (q, dq) = state.split_at(DOFS);
        let mut input = [0.0; 3 * DOFS];
        for (k, xw) in self.car.wheelset_x().iter().enumerate() {
            let c = self.wheelset_forces(k, q, dq, rails, x_car + xw);
            for (i, dof) in HsrCar::wheelset_dofs(k).iter().enumerate() {
                input[*dof] += c.generalised[i] - self.rest.generalised[i];
            }
            wheels[2 * k] = c.wheels[0];
            wheels[2 * k + 1] = c.wheels[1];
        }
        input[DOFS..].copy_from_slice(state);
        let mut out = [0.0; 2 * DOFS];
        out[..DOFS].copy_from_slice(dq);
        for (o, row) in out[DOFS..].iter_mut().zip(&self.rows) {
            *o = row.iter().map(|(j, a)| a * input[*j]).sum();
        }
        out
    }

    /// One RK4 step of `dt` from time `t` (car centre at x0 + v t).
    pub fn step(&self, state: &mut [f64; 2 * DOFS], t: f64, dt: f64, rails: &dyn Rails, x0: f64) {
        rk4(state, dt, |tau, s| {
            self.rate_of(s, rails, x0 + self.v * (t + tau))
        });
    }

    /// The start of [`Running::settle`]: each wheelset centred on its two rails (y, z their
    /// means, roll their height difference over 2b), each frame at the mean of its two
    /// wheelsets and the body at the mean of the frames (lateral, vertical, roll), so that
    /// every wheel touches its rail: a car whose wheels all miss a rail lower than nominal
    /// has no static stiffness against its rigid motions.
    fn on_rails(&self, rails: &dyn Rails, x_car: f64) -> [f64; DOFS] {
        let mut q = [0.0; DOFS];
        let b = self.car.wheelset.b;
        let mut ws = [[0.0; 3]; 4];
        for (k, xw) in self.car.wheelset_x().iter().enumerate() {
            let [l, r] = rails.at(x_car + xw, self.v);
            ws[k] = [
                0.5 * (l.y + r.y),
                0.5 * (l.z + r.z),
                (l.z - r.z) / (2.0 * b),
            ];
            let d = HsrCar::wheelset_dofs(k);
            (q[d[0]], q[d[1]], q[d[2]]) = (ws[k][0], ws[k][1], ws[k][2]);
        }
        let mut body = [0.0; 3];
        for j in 0..2 {
            for i in 0..3 {
                let m = 0.5 * (ws[2 * j][i] + ws[2 * j + 1][i]);
                q[5 + 5 * j + i] = m;
                body[i] += 0.5 * m;
            }
        }
        q[..3].copy_from_slice(&body);
        q
    }

    /// The car at rest (q̇ = 0) in its static equilibrium on `rails` with its centre at
    /// `x_car`: Newton on the accelerations a(q) = M⁻¹(F(q, 0) − F(0, 0)) − M⁻¹K q = 0 with
    /// a central-difference Jacobian (1e−8 m, rad), from [`Running::on_rails`], to
    /// |Δq| ≤ 1e−12 in at most
    /// 50 iterations. On smooth rails q = 0 at once.
    pub fn settle(&self, rails: &dyn Rails, x_car: f64) -> Result<[f64; 2 * DOFS]> {
        let n = DOFS;
        let zero = [0.0; DOFS];
        let acc = |q: &[f64]| -> DVector<f64> {
            &self.minv * self.contact_load(q, &zero, rails, x_car)
                - &self.minv_k * DVector::from_column_slice(q)
        };
        let mut q = self.on_rails(rails, x_car);
        let mut last = f64::NAN;
        for _ in 0..50 {
            let a = acc(&q);
            if a.iter().all(|v| *v == 0.0) {
                break;
            }
            let mut jac = DMatrix::zeros(n, n);
            let h = 1e-8;
            for j in 0..n {
                let (mut up, mut down) = (q, q);
                up[j] += h;
                down[j] -= h;
                jac.set_column(j, &((acc(&up) - acc(&down)) / (2.0 * h)));
            }
            let dq = jac
                .lu()
                .solve(&(-a))
                .ok_or_else(|| Error::numerical("high-speed car: singular static Jacobian"))?;
            for (qi, d) in q.iter_mut().zip(dq.iter()) {
                *qi += d;
            }
            last = dq.amax();
            if last <= 1e-12 {
                let mut state = [0.0; 2 * DOFS];
                state[..DOFS].copy_from_slice(&q);
                return Ok(state);
            }
        }
        let mut state = [0.0; 2 * DOFS];
        state[..DOFS].copy_from_slice(&q);
        if acc(&q).amax() == 0.0 {
            return Ok(state);
        }
        Err(Error::numerical(format!(
            "high-speed car at x = {x_car} m: the static equilibrium on the rail at t = 0 did not converge (last Newton step {last:.3e}, largest acceleration {:.3e} m/s²)",
            acc(&q).amax()
        )))
    }

    /// The state matrix of the model linearised about rest on smooth rails (central
    /// differences of the contact forces, 1e-7 m, rad and m/s, rad/s).
    pub fn linearised(&self) -> DMatrix<f64> {
        let n = DOFS;
        let mut jq = DMatrix::zeros(n, n);
        let mut jdq = DMatrix::zeros(n, n);
        let zero = vec![0.0; n];
        let h = 1e-7;
        for j in 0..n {
            let mut up = zero.clone();
            let mut down = zero.clone();
            up[j] = h;
            down[j] = -h;
            let dq_col = (self.contact_load(&up, &zero, &Smooth, 0.0)
                - self.contact_load(&down, &zero, &Smooth, 0.0))
                / (2.0 * h);
            let dv_col = (self.contact_load(&zero, &up, &Smooth, 0.0)
                - self.contact_load(&zero, &down, &Smooth, 0.0))
                / (2.0 * h);
            jq.set_column(j, &dq_col);
            jdq.set_column(j, &dv_col);
        }
        let mut a = DMatrix::zeros(2 * n, 2 * n);
        for i in 0..n {
            a[(i, n + i)] = 1.0;
        }
        let kk = &self.minv * jq - &self.minv_k;
        let cc = &self.minv * jdq - &self.minv_c;
        a.view_mut((n, 0), (n, n)).copy_from(&kk);
        a.view_mut((n, n), (n, n)).copy_from(&cc);
        a
    }

    /// The largest real part of the linearised model's eigenvalues, 1/s.
    pub fn abscissa(&self) -> f64 {
        self.linearised()
            .complex_eigenvalues()
            .iter()
            .map(|l| l.re)
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

/// The linear critical (hunting) speed of `car`: the speed in `[lo, hi]` (m/s) where the
/// linearised model's spectral abscissa crosses zero, by bisection to `tol` (m/s). `None`
/// when it does not change sign over the bracket.
pub fn critical_speed(
    car: &HsrCar,
    gravity: f64,
    lo: f64,
    hi: f64,
    tol: f64,
) -> Result<Option<f64>> {
    let sigma = |v: f64| Running::new(car, v, gravity).map(|r| r.abscissa());
    let (mut a, mut b) = (lo, hi);
    if sigma(a)? >= 0.0 || sigma(b)? <= 0.0 {
        return Ok(None);
    }
    while b - a > tol {
        let mid = 0.5 * (a + b);
        if sigma(mid)? < 0.0 {
            a = mid;
        } else {
            b = mid;
        }
    }
    Ok(Some(0.5 * (a + b)))
}
