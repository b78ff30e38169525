//! One wheelset on its two rails: the geometry of a conical tread with a flange, the normal
//! (Hertz) and tangential (Kalker, Shen–Hedrick–Elkins) contact forces, and their resultant
//! on the wheelset's lateral, vertical, roll and yaw motion. docs/cars.md, "One wheelset".
//!
//! # Axes and coordinates
//!
//! x along the track (the direction of travel), y lateral (left = +y), z up. The wheelset's
//! centre is at (y, z) with roll φ about x (φ > 0 lifts the left wheel) and yaw ψ about z.
//! The rails' heads are knife edges at y = ±b (their nominal contact points), displaced by
//! the rail irregularity (`irregularity`: y and z of each rail, up positive).
//!
//! # Geometry (conical tread, first order in y, φ, ψ)
//!
//! Wheel i (s = +1 left, −1 right) touches its rail at the lateral arm s·b − (y − y_ri) from
//! the centre, at the rolling radius and with the contact angle
//!
//! ```text
//! r_i = r0 + s λ (y − y_ri),      δ_i = s·atan λ (the tread's cone angle),
//! ```
//!
//! and its normal points (−sin(δ_i + φ), cos(δ_i + φ)) in (y, z). The normal approach is the
//! vertical one times cos δ: d_i = (r_i − (z − z_ri) − s b φ) cos δ_i, and the normal force
//! is Hertz's N_i = (d_i/G)^{3/2} for d_i > 0, zero otherwise (loss of contact), with Zhai's
//! G (`cars::wheel_rail::zhai_g`) measured from the static approach.
//!
//! # Creepages (rolling at v with the wheel spin v/r0)
//!
//! ```text
//! ξ_x = −s λ (y − y_ri)/r0 − s b ψ̇/v,   ξ_y = (ẏ − ẏ_ri + r0 φ̇)/v − ψ,   ξ_sp = ψ̇/v − s sin δ/r0
//! ```
//!
//! # Flange
//!
//! Beyond the flangeway clearance g_f the flange bears on the rail's gauge face: a lateral
//! force −s k_f (s(y − y_ri) − g_f) while s(y − y_ri) > g_f, k_f the rail's lateral contact
//! stiffness.

use super::contact::{creep_forces, hertz_ellipse, kalker, Creep, Creepage, Material};
use crate::physics::cars::wheel_rail::zhai_g;

/// The wheelset and its tread.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wheelset {
    /// Mass, kg.
    pub mass: f64,
    /// Roll moment of inertia, kg·m².
    pub i_roll: f64,
    /// Yaw moment of inertia, kg·m².
    pub i_yaw: f64,
    /// Nominal rolling radius r0, m.
    pub r0: f64,
    /// Half the distance between the nominal contact points b, m.
    pub b: f64,
    /// Tread conicity λ (equivalent conicity of the pair).
    pub conicity: f64,
    /// Flangeway clearance g_f, m.
    pub flange_clearance: f64,
    /// Lateral stiffness of the flange contact k_f, N/m.
    pub flange_stiffness: f64,
    /// Transverse radius of the rail head, m (the Hertz ellipse's lateral curvature).
    pub rail_crown: f64,
    /// Steel and friction.
    pub material: Material,
}

/// The wheelset's motion: position (y, z, φ, ψ) and rates, SI (m, rad).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Motion {
    /// (y, z, φ, ψ): z is measured from the static position on a smooth track.
    pub q: [f64; 4],
    /// Their rates.
    pub dq: [f64; 4],
}

/// One rail's position under a wheel: lateral and vertical deviation and their rates.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RailPoint {
    /// Lateral deviation y_r, m.
    pub y: f64,
    /// Vertical deviation z_r (up), m.
    pub z: f64,
    /// dy_r/dt, m/s.
    pub dy: f64,
}

/// One wheel's contact.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WheelForce {
    /// Normal force N, N (≥ 0).
    pub normal: f64,
    /// Creep forces in the contact plane.
    pub creep: Creep,
    /// Flange force on the wheel, N (along y).
    pub flange: f64,
    /// The rail's force on the wheel along y (normal, creep and flange), N: Y of Y/Q.
    pub lateral: f64,
    /// The rail's force on the wheel along z, N: Q of Y/Q.
    pub vertical: f64,
}

/// The contact forces of both wheels (left, right) and their generalised forces on
/// (y, z, φ, ψ) (N, N·m).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactForces {
    /// Left and right wheel.
    pub wheels: [WheelForce; 2],
    /// Resultant on (y, z, φ, ψ).
    pub generalised: [f64; 4],
}

impl Wheelset {
    /// The wheelset of the high-speed passenger car of Zhai (docs/cars.md, "The high-speed
    /// car": 1 400 kg, roll and yaw inertias 915 kg·m², r0 = 0.4575 m), on standard gauge
    /// (b = 0.7465 m) with λ = 0.05 (new LMA/S1002CN-type profiles run at 0.03–0.1; an
    /// **estimate**), flangeway clearance 8 mm and flange stiffness 1.5e7 N/m (**estimates**
    /// of the gauge clearance and the rail's lateral stiffness at the flange), rail crown
    /// 0.3 m (60 kg rail head).
    pub fn high_speed() -> Self {
        Wheelset {
            mass: 1400.0,
            i_roll: 915.0,
            i_yaw: 915.0,
            r0: 0.4575,
            b: 0.7465,
            conicity: 0.05,
            flange_clearance: 0.008,
            flange_stiffness: 1.5e7,
            rail_crown: 0.3,
            material: Material::default(),
        }
    }

    /// The contact of this wheelset under the static wheel load `p0` (N): the static
    /// approach (Hertz's, G·p^{2/3}, p the static normal force) and Kalker's coefficients at
    /// a unit load, computed once.
    pub fn contact(&self, p0: f64) -> WheelsetContact {
        let cone = self.conicity.atan();
        let p = p0 / cone.cos();
        let unit = hertz_ellipse(1.0, 0.5 / self.r0, 0.5 / self.rail_crown, &self.material);
        WheelsetContact {
            wheelset: *self,
            g: zhai_g(self.r0),
            d0: zhai_g(self.r0) * p.powf(2.0 / 3.0),
            unit: kalker(&unit, &self.material),
            sin_cone: cone.sin(),
            cos_cone: cone.cos(),
        }
    }
}

/// A wheelset's contact with its rails at a given static wheel load ([`Wheelset::contact`]).
///
/// The Hertz ellipse is the one at the nominal radius r0; under a normal force N its axes
/// scale as N^{1/3} (Hertz), so f11, f22 ∝ N^{2/3}, f23 ∝ N and f33 ∝ N^{4/3} from their
/// values at 1 N. The radius change λ(y − y_r), a few parts in 10⁴ of r0, is neglected in
/// the ellipse only.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WheelsetContact {
    /// The wheelset.
    pub wheelset: Wheelset,
    /// Zhai's G, m/N^{2/3}.
    g: f64,
    /// The static normal approach, m.
    d0: f64,
    /// Kalker's f11, f22, f23, f33 at N = 1 N.
    unit: [f64; 4],
    /// sin δ and cos δ of the cone angle δ = atan λ.
    sin_cone: f64,
    cos_cone: f64,
}

impl WheelsetContact {
    /// Kalker's coefficients under the normal force `n` (N).
    pub fn coefficients(&self, n: f64) -> [f64; 4] {
        self.coefficients_at(n, n.cbrt())
    }

    /// [`WheelsetContact::coefficients`] given N (`n`) and N^{1/3} (`c`).
    fn coefficients_at(&self, n: f64, c: f64) -> [f64; 4] {
        let c2 = c * c;
        let u = &self.unit;
        [u[0] * c2, u[1] * c2, u[2] * n, u[3] * c2 * c2]
    }

    /// The contact forces at the motion `m`, speed `v` (> 0, m/s), rails `rails` (left,
    /// right).
    pub fn forces(&self, m: &Motion, v: f64, rails: &[RailPoint; 2]) -> ContactForces {
        let w = &self.wheelset;
        let [y, z, phi, psi] = m.q;
        let [dy, _, dphi, dpsi] = m.dq;
        let g = self.g;
        // sin and cos of δ + φ from δ's (constant) and φ's.
        let (sin_phi, cos_phi) = phi.sin_cos();
        let mut out = ContactForces::default();
        for (i, s) in [(0usize, 1.0f64), (1, -1.0)] {
            let r = &rails[i];
            let rel = y - r.y;
            let radius_change = s * w.conicity * rel;
            let d = self.d0 + (radius_change - (z - r.z) - s * w.b * phi) * self.cos_cone;
            // N = (d/G)^{3/2}, and N^{1/3} = (d/G)^{1/2} for Kalker's coefficients.
            let (normal, cbrt_n) = if d > 0.0 {
                let r = d / g;
                let root = r.sqrt();
                (r * root, root)
            } else {
                (0.0, 0.0)
            };
            let creepage = Creepage {
                x: -radius_change / w.r0 - s * w.b * dpsi / v,
                y: (dy - r.dy + w.r0 * dphi) / v - psi,
                spin: dpsi / v - s * self.sin_cone / w.r0,
            };
            let radius = w.r0 + radius_change;
            let creep = creep_forces(
                &creepage,
                &self.coefficients_at(normal, cbrt_n),
                normal,
                w.material.friction,
            );
            let over = s * rel - w.flange_clearance;
            let flange = if over > 0.0 {
                -s * w.flange_stiffness * over
            } else {
                0.0
            };
            // Normal n = (−sin(δ + φ), cos(δ + φ)), tangent t = (cos(δ + φ), sin(δ + φ)).
            let (sn, cs) = (
                s * self.sin_cone * cos_phi + self.cos_cone * sin_phi,
                self.cos_cone * cos_phi - s * self.sin_cone * sin_phi,
            );
            let lateral = -normal * sn + creep.fy * cs + flange;
            let vertical = normal * cs + creep.fy * sn;
            let arm = s * w.b - rel;
            let sum = &mut out.generalised;
            sum[0] += lateral;
            sum[1] += vertical;
            sum[2] += arm * vertical + radius * lateral;
            sum[3] += -arm * creep.fx + creep.mz * cs;
            out.wheels[i] = WheelForce {
                normal,
                creep,
                flange,
                lateral,
                vertical,
            };
        }
        out
    }
}

impl WheelsetContact {
    /// The accelerations of (y, z, φ, ψ) under the contact forces, gravity and the vertical
    /// `axle_load` (N, down) the suspension puts on the axle at its centre, on rigid rails
    /// `rails` at speed `v`: the rigid wheelset's diagonal mass matrix (m, m, I_x, I_z).
    pub fn accelerations(
        &self,
        m: &Motion,
        v: f64,
        rails: &[RailPoint; 2],
        axle_load: f64,
        gravity: f64,
    ) -> [f64; 4] {
        let f = self.forces(m, v, rails).generalised;
        let w = &self.wheelset;
        [
            f[0] / w.mass,
            (f[1] - axle_load) / w.mass - gravity,
            f[2] / w.i_roll,
            f[3] / w.i_yaw,
        ]
    }

    /// The motion at rest in (z, φ) for a given lateral position `y` and yaw `psi` on smooth
    /// rails: Newton on the vertical and roll balance (central-difference Jacobian), from
    /// z = φ = 0. `None` if it does not converge to 1e-12 m in 50 iterations.
    pub fn settle(&self, y: f64, psi: f64, v: f64, axle_load: f64, gravity: f64) -> Option<Motion> {
        let w = &self.wheelset;
        let rails = [RailPoint::default(); 2];
        let mut m = Motion {
            q: [y, 0.0, 0.0, psi],
            dq: [0.0; 4],
        };
        let residual = |m: &Motion| {
            let a = self.accelerations(m, v, &rails, axle_load, gravity);
            [a[1] * w.mass, a[2] * w.i_roll]
        };
        for _ in 0..50 {
            let r = residual(&m);
            let h = 1e-9;
            let mut jac = [[0.0; 2]; 2];
            for (col, dof) in [1usize, 2].iter().enumerate() {
                let (mut up, mut down) = (m, m);
                up.q[*dof] += h;
                down.q[*dof] -= h;
                let (ru, rd) = (residual(&up), residual(&down));
                for (row, (u, d)) in jac.iter_mut().zip(ru.iter().zip(&rd)) {
                    row[col] = (u - d) / (2.0 * h);
                }
            }
            let det = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0];
            let dz = (r[0] * jac[1][1] - r[1] * jac[0][1]) / det;
            let dphi = (jac[0][0] * r[1] - jac[1][0] * r[0]) / det;
            m.q[1] -= dz;
            m.q[2] -= dphi;
            if dz.abs() < 1e-12 && (dphi * w.b).abs() < 1e-12 {
                return Some(m);
            }
        }
        None
    }
}

/// One classical Runge–Kutta step of ẋ = f(τ, x) over `dt`, in place; τ is the time within
/// the step (0, dt/2, dt/2, dt).
pub fn rk4<const N: usize>(
    x: &mut [f64; N],
    dt: f64,
    mut f: impl FnMut(f64, &[f64; N]) -> [f64; N],
) {
    let shift = |x: &[f64; N], k: &[f64; N], h: f64| {
        let mut out = *x;
        for (o, k) in out.iter_mut().zip(k) {
            *o += h * k;
        }
        out
    };
    let k1 = f(0.0, x);
    let k2 = f(0.5 * dt, &shift(x, &k1, 0.5 * dt));
    let k3 = f(0.5 * dt, &shift(x, &k2, 0.5 * dt));
    let k4 = f(dt, &shift(x, &k3, dt));
    for (i, xi) in x.iter_mut().enumerate() {
        *xi += dt / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
    }
}
