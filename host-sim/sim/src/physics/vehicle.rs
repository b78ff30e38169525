//! Vehicles (docs/model.md §6, §9): lumped masses (Eq. 17), Kelvin–Voigt spring–dampers with
//! rigid links (Eq. 18), and maglev wheels — the nodes that carry the magnets.
//!
//! The vehicle is written in deviations from its static equilibrium: gravity, the spring
//! preload and the static magnet forces p0 cancel exactly, so its load vector holds only the
//! magnet force *changes* `G − p0` (and the guidance forces, zero at equilibrium). The
//! guideway, which starts undeformed, receives the full forces. Each magnet's p0 is its car's
//! exact static equilibrium ([`VehicleModel::static_wheel_loads`]), not a share of the weight
//! by assumption.
//!
//! A train (`crate::physics::train`) is a list of cars, each its own small [`VehicleModel`]
//! (docs/model.md §10). One type serves every kind of car: the Fig. 1 car and the unit
//! (here), the Fig. 6 maglev carriage and the wheel/rail car (`crate::physics::cars`, built
//! from this module's parts). A car meets the guideway through
//! maglev [`Wheel`]s (magnets, with their p0) and wheel–rail [`Contact`]s (Hertz springs,
//! with their P0); both loads come from the one static solution of
//! [`VehicleModel::static_loads`].

use crate::{Error, Result};
use nalgebra::{DMatrix, DVector};

/// A maglev wheel: a node of the vehicle with Y and Z DOFs, running along the target line.
#[derive(Clone, Debug, PartialEq)]
pub struct Wheel {
    /// X position at t = 0 (m).
    pub x0: f64,
    /// Offset of its target point from the beam axis (rigid link, docs/model.md §5), Y (m).
    pub ey: f64,
    /// Offset of its target point from the beam axis, Z (m).
    pub ez: f64,
    /// Index of its Y and Z DOFs in the vehicle system; no Y DOF for a magnet without
    /// guidance magnets (a `unit`: its guidance force, if computed, acts on nothing).
    pub dof_y: Option<usize>,
    pub dof_z: usize,
}

/// A wheel–rail contact: a linearised Hertz spring between the wheel DOF `dof_z` and the rail
/// target point at (x_w, ey, ez) (docs/model.md §5 rigid link; the contact law, its sign
/// convention and its coupling: docs/cars.md "Wheel–rail contact").
#[derive(Clone, Debug, PartialEq)]
pub struct Contact {
    /// X position at t = 0 (m), the leading contact of the car at 0.
    pub x0: f64,
    /// Offset of the rail target point from the beam axis, Y and Z (m).
    pub ey: f64,
    pub ez: f64,
    /// The wheel's vertical DOF in the car (its own DOF, coefficient 1).
    pub dof_z: usize,
    /// Static wheel load P0 (N, compressive), from the car's exact statics.
    pub p0: f64,
    /// Linearised Hertz stiffness at P0 (N/m), `cars::wheel_rail::hertz_stiffness`.
    pub k_h: f64,
    /// The contact spring between the wheel and the girder's rail point (N/m): the Hertz
    /// spring in series with the track (rail on its pads), `cars::wheel_rail::series`. The
    /// coupling and [`VehicleModel::k_on_rigid_rail`] use this one.
    pub k: f64,
}

/// Parameters of the Fig. 1 vehicle (SI), defaults from docs/model.md §9.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Fig1 {
    #[serde(rename = "body_mass_kg")]
    pub body_mass: f64,
    /// Body inertias about the CoM, X, Y, Z (kg·m²).
    #[serde(rename = "jx_kg_m2")]
    pub jx: f64,
    #[serde(rename = "jy_kg_m2")]
    pub jy: f64,
    #[serde(rename = "jz_kg_m2")]
    pub jz: f64,
    /// Body–wheel spring and damper, Y and Z.
    #[serde(rename = "spring_N_per_m")]
    pub k: f64,
    #[serde(rename = "damper_N_s_per_m")]
    pub c: f64,
    /// Half the wheel spacing along X (m): wheels at ±this from the body centre.
    #[serde(rename = "half_length_m")]
    pub half_length: f64,
    /// Half the wheel spacing along Y (m).
    #[serde(rename = "half_width_m")]
    pub half_width: f64,
    /// Y of the vehicle centre from the beam centre (m).
    #[serde(rename = "offset_y_m")]
    pub offset_y: f64,
    /// Height of the target line above the beam centroid (m).
    #[serde(rename = "target_height_m")]
    pub target_height: f64,
    /// Height of the body CoM above the target line (m).
    #[serde(rename = "body_height_m")]
    pub body_height: f64,
    /// Mass of each wheel node (kg); 0 allowed (damping keeps the system regular).
    #[serde(rename = "wheel_mass_kg")]
    pub wheel_mass: f64,
    /// X of the body CoM ahead of the middle of the wheelbase (m); 0 for the paper's car.
    #[serde(rename = "com_ahead_m")]
    pub com_ahead: f64,
    /// X of the leading wheel at t = 0 (m from the left end of span 1); 0 for the paper's
    /// passage, which starts with the leading wheel over the first support. A car at
    /// standstill over a span sits at its position.
    #[serde(rename = "position_m", default, skip_serializing_if = "is_zero")]
    pub position: f64,
}

/// Zero: a default left out of what is serialised (`serde(skip_serializing_if)`).
pub(crate) fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

impl Default for Fig1 {
    fn default() -> Self {
        Fig1 {
            body_mass: 15_000.0,
            jx: 20e3,
            jy: 950e3,
            jz: 1600e3,
            k: 200e3,
            c: 10e3,
            half_length: 7.5,
            half_width: 1.5,
            offset_y: 1.5,
            target_height: 0.6,
            body_height: 2.0,
            wheel_mass: 0.0,
            com_ahead: 0.0,
            position: 0.0,
        }
    }
}

/// A levitation unit (`[vehicle] kind = "unit"`, docs/levitation.md): one magnet of
/// `magnet_mass` carrying a body of `body_mass` through a vertical spring `k` and damper `c`,
/// at `position` along the guideway at t = 0. It has no guidance magnets (no lateral DOF).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Unit {
    /// The magnet (kg), > 0.
    #[serde(rename = "magnet_mass_kg")]
    pub magnet_mass: f64,
    /// The body (kg), 0 for none.
    #[serde(rename = "body_mass_kg")]
    pub body_mass: f64,
    /// Magnet–body spring (N/m) and damper (N·s/m).
    #[serde(rename = "spring_N_per_m")]
    pub k: f64,
    #[serde(rename = "damper_N_s_per_m")]
    pub c: f64,
    /// X of the magnet at t = 0 (m).
    #[serde(rename = "position_m")]
    pub position: f64,
}

/// One car of any kind: mass, damping and stiffness (its own small dense matrices, in
/// deviations from its static equilibrium) and the nodes through which it meets the
/// guideway — maglev wheels, wheel–rail contacts, or (in principle) both.
#[derive(Clone, Debug)]
pub struct VehicleModel {
    pub m: DMatrix<f64>,
    pub c: DMatrix<f64>,
    /// Stiffness of the car's own springs (no contact spring: see [`Self::k_on_rigid_rail`]).
    pub k: DMatrix<f64>,
    /// The car's maglev wheels, DOFs local to this car (empty for a wheel/rail car).
    pub wheels: Vec<Wheel>,
    /// Static load per wheel (N, up): the magnet force of the car's static equilibrium.
    pub p0: Vec<f64>,
    /// The car's wheel–rail contacts (empty for a maglev car).
    pub contacts: Vec<Contact>,
    /// The body's heave DOF (the `car{N}.body` probes): the body's centre of mass, at the
    /// middle of the car.
    pub body_z: usize,
    /// The body's pitch (θy) DOF.
    pub body_pitch: usize,
    /// The car's own pitch along a train (m): the next car's leading node this far behind.
    pub length: f64,
    /// Total weight (N): the sum of the static loads.
    pub weight: f64,
}

/// Body DOFs: v, w, θx, θy, θz (u along X carries no force and is left out).
const BODY_V: usize = 0;
const BODY_W: usize = 1;
const BODY_RX: usize = 2;
const BODY_RY: usize = 3;
const BODY_RZ: usize = 4;

/// Direction of a spring–damper element (Eq. 18).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    Y,
    Z,
}

/// Adds `s·S·Sᵀ` for a spring (or damper) of value `s` between a free node DOF `node_dof`
/// and a slave point of the body at offset Δ = master − slave (Eq. 18). For Z:
/// S = [1 at node, −1 at body w, −D1 at θx, −D2 at θy] with (D1, D2) = (−ΔY, ΔX); for Y:
/// (D1, D2) = (ΔZ, −ΔX) on (θx, θz). The slave point moves as master + θ × (slave − master).
pub fn add_link_spring(
    mat: &mut DMatrix<f64>,
    s: f64,
    dir: Direction,
    node_dof: usize,
    delta: [f64; 3],
) {
    let [dx, dy, dz] = delta;
    let entries: [(usize, f64); 4] = match dir {
        Direction::Z => [
            (node_dof, 1.0),
            (BODY_W, -1.0),
            (BODY_RX, dy),
            (BODY_RY, -dx),
        ],
        Direction::Y => [
            (node_dof, 1.0),
            (BODY_V, -1.0),
            (BODY_RX, -dz),
            (BODY_RZ, dx),
        ],
    };
    for &(i, si) in &entries {
        for &(j, sj) in &entries {
            mat[(i, j)] += s * si * sj;
        }
    }
}

impl VehicleModel {
    /// The Fig. 1 car: rigid body on four maglev wheels. Wheel 1 leads on the line nearest
    /// the beam axis; wheel 1 is at x = 0 at t = 0, the others behind it (docs/model.md §9).
    /// Each wheel's p0 is the car's static equilibrium under the body's weight.
    pub fn fig1(p: &Fig1, gravity: f64) -> Result<Self> {
        let n = 5 + 4 * 2;
        let mut m = DMatrix::zeros(n, n);
        let mut c = DMatrix::zeros(n, n);
        let mut k = DMatrix::zeros(n, n);
        m[(BODY_V, BODY_V)] = p.body_mass;
        m[(BODY_W, BODY_W)] = p.body_mass;
        m[(BODY_RX, BODY_RX)] = p.jx;
        m[(BODY_RY, BODY_RY)] = p.jy;
        m[(BODY_RZ, BODY_RZ)] = p.jz;
        // Wheels: (X from the middle of the wheelbase, Y from vehicle centre): 1 front-near,
        // 2 front-far, 3 rear-near, 4 rear-far. "Near" is the line closest to the beam axis.
        let layout = [
            (p.half_length, -p.half_width),
            (p.half_length, p.half_width),
            (-p.half_length, -p.half_width),
            (-p.half_length, p.half_width),
        ];
        let mut wheels = Vec::new();
        for (i, &(wx, wy)) in layout.iter().enumerate() {
            let (dof_y, dof_z) = (5 + 2 * i, 6 + 2 * i);
            m[(dof_y, dof_y)] = p.wheel_mass;
            m[(dof_z, dof_z)] = p.wheel_mass;
            // Slave point on the body at the wheel; master = body CoM, Δ = master − slave.
            let delta = [p.com_ahead - wx, -wy, p.body_height];
            for dir in [Direction::Y, Direction::Z] {
                let dof = if dir == Direction::Y { dof_y } else { dof_z };
                add_link_spring(&mut k, p.k, dir, dof, delta);
                add_link_spring(&mut c, p.c, dir, dof, delta);
            }
            wheels.push(Wheel {
                x0: p.position + (wx - p.half_length),
                ey: p.offset_y + wy,
                ez: p.target_height,
                dof_y: Some(dof_y),
                dof_z,
            });
        }
        let mut weight = DVector::zeros(n);
        weight[BODY_W] = -p.body_mass * gravity;
        let mut v = VehicleModel {
            m,
            c,
            k,
            wheels,
            p0: Vec::new(),
            contacts: Vec::new(),
            body_z: BODY_W,
            body_pitch: BODY_RY,
            length: 2.0 * p.half_length,
            weight: p.body_mass * gravity,
        };
        (v.p0, _) = v.static_loads(&weight)?;
        Ok(v)
    }

    /// The levitation unit `p` (DOF 0 the magnet's Z, DOF 1 the body's Z when it has one):
    /// `M = diag(m, m_b)`, the spring and damper between the two; the magnet carries
    /// (m + m_b)·g, the car's statics with the magnet held ([`Self::static_loads`]).
    pub fn unit(p: &Unit, gravity: f64) -> Result<Self> {
        let body = p.body_mass > 0.0;
        let n = 1 + usize::from(body);
        let mut m = DMatrix::zeros(n, n);
        let mut c = DMatrix::zeros(n, n);
        let mut k = DMatrix::zeros(n, n);
        let mut weight = DVector::zeros(n);
        m[(0, 0)] = p.magnet_mass;
        weight[0] = -p.magnet_mass * gravity;
        if body {
            m[(1, 1)] = p.body_mass;
            weight[1] = -p.body_mass * gravity;
            for (i, j, sign) in [(0, 0, 1.0), (0, 1, -1.0), (1, 0, -1.0), (1, 1, 1.0)] {
                k[(i, j)] = sign * p.k;
                c[(i, j)] = sign * p.c;
            }
        }
        let mut v = VehicleModel {
            m,
            c,
            k,
            wheels: vec![Wheel {
                x0: p.position,
                ey: 0.0,
                ez: 0.0,
                dof_y: None,
                dof_z: 0,
            }],
            p0: Vec::new(),
            contacts: Vec::new(),
            body_z: n - 1,
            body_pitch: n - 1,
            length: 0.0,
            weight: (p.magnet_mass + p.body_mass) * gravity,
        };
        (v.p0, _) = v.static_loads(&weight)?;
        Ok(v)
    }

    /// The stiffness with every contact spring tied to a fixed, smooth rail (`k` on each
    /// contact DOF): the car on a rigid rail, and the matrix the coupling integrates (the
    /// contact springs are implicit on the car's side, docs/cars.md). For a maglev car, `k`.
    pub fn k_on_rigid_rail(&self) -> DMatrix<f64> {
        let mut k = self.k.clone();
        for c in &self.contacts {
            k[(c.dof_z, c.dof_z)] += c.k;
        }
        k
    }

    /// The DOFs of the guideway nodes (wheels' Y and Z, contacts' Z), the ones the static
    /// solution holds.
    pub fn node_dofs(&self) -> Vec<usize> {
        let mut d: Vec<usize> = self
            .wheels
            .iter()
            .flat_map(|w| w.dof_y.into_iter().chain([w.dof_z]))
            .collect();
        d.extend(self.contacts.iter().map(|c| c.dof_z));
        d
    }

    /// The static load of every guideway node under the load `weight` (N per DOF; gravity on
    /// the bodies), the nodes held at their targets — the one static solution of every car
    /// kind ([`static_solution`]: `K_ff u_f = weight_f`, the reactions `(K u)_h − weight_h`).
    /// Returns the magnets' forces (N, up; the p0) and the contacts' loads (N, compressive;
    /// the P0), both in node order. A lateral reaction at a magnet would need a guidance
    /// preload the model does not have, so it is refused; a load that is not positive too
    /// (a magnet only pulls, a wheel only pushes).
    pub fn static_loads(&self, weight: &DVector<f64>) -> Result<(Vec<f64>, Vec<f64>)> {
        let (_, r) = static_solution(&self.k, weight, &self.node_dofs())?;
        let total: f64 = weight.iter().map(|w| w.abs()).sum();
        let mut p0 = Vec::with_capacity(self.wheels.len());
        for (i, w) in self.wheels.iter().enumerate() {
            let fy = w.dof_y.map_or(0.0, |y| r[y]);
            if fy.abs() > 1e-9 * total {
                return Err(Error::invalid(
                    "vehicle",
                    format!(
                        "wheel {} carries a static lateral load of {fy:.3e} N; the guidance magnets have no preload (|F_y| ≤ 1e-9 of the weight)",
                        i + 1
                    ),
                ));
            }
            let fz = r[w.dof_z];
            if !(fz.is_finite() && fz > 0.0) {
                return Err(Error::invalid(
                    "vehicle",
                    format!(
                        "wheel {} static load {fz:.3e} N: must be positive (a magnet only pulls)",
                        i + 1
                    ),
                ));
            }
            p0.push(fz);
        }
        let mut contact = Vec::with_capacity(self.contacts.len());
        for (i, c) in self.contacts.iter().enumerate() {
            let fz = r[c.dof_z];
            if !(fz.is_finite() && fz > 0.0) {
                return Err(Error::invalid(
                    "vehicle",
                    format!(
                        "contact {} static load {fz:.3e} N: must be positive (a wheel only pushes on its rail)",
                        i + 1
                    ),
                ));
            }
            contact.push(fz);
        }
        Ok((p0, contact))
    }
}

/// The static solution with the DOFs `held` fixed at zero: solves `K_ff u_f = f_f` and
/// returns `(u, r)`, u the displacements (zero on the held DOFs) and r the support
/// reactions, the forces the supports exert on the held DOFs, `r_h = (K u)_h − f_h`.
pub fn static_solution(
    k: &DMatrix<f64>,
    f: &DVector<f64>,
    held: &[usize],
) -> Result<(DVector<f64>, DVector<f64>)> {
    let n = k.nrows();
    let free: Vec<usize> = (0..n).filter(|i| !held.contains(i)).collect();
    let kff = DMatrix::from_fn(free.len(), free.len(), |i, j| k[(free[i], free[j])]);
    let ff = DVector::from_fn(free.len(), |i, _| f[free[i]]);
    let uf = kff.cholesky().ok_or_else(|| {
        Error::numerical(
            "car statics: the stiffness with the supports held is not positive definite",
        )
    })?;
    let uf = uf.solve(&ff);
    let mut u = DVector::zeros(n);
    for (i, &d) in free.iter().enumerate() {
        u[d] = uf[i];
    }
    let ku = k * &u;
    let mut r = DVector::zeros(n);
    for &h in held {
        r[h] = ku[h] - f[h];
    }
    Ok((u, r))
}

/// One magnet's coil at the end of a committed step, as its law output it (SI): the current
/// (A), the voltage (V), and whether the law clamped the voltage at `±V_max` in at least one
/// of its control periods (or the paper's sub-steps) within the step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Coil {
    pub current: f64,
    pub voltage: f64,
    pub saturated: bool,
}

/// The three magnet gaps `[h_z, h_L, h_R]` (m) of a wheel's gaps `(h_z, d)`
/// (docs/model.md §2: the guidance pair's are `h0 ± d`).
pub fn magnet_gaps((hz, d): (f64, f64), h0: f64) -> [f64; 3] {
    let (hl, hr) = maglev_core::gap::guidance_gaps(h0, d);
    [hz, hl, hr]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rigid_body_motion_strains_no_spring() {
        // Move the body and the wheels as one rigid body: K·u must vanish.
        let p = Fig1::default();
        let v = VehicleModel::fig1(&p, 9.81).unwrap();
        let (ry, rx, rz) = (1e-3, 2e-3, 3e-3);
        let mut u = nalgebra::DVector::zeros(13);
        u[BODY_V] = 0.01;
        u[BODY_W] = 0.02;
        u[BODY_RX] = rx;
        u[BODY_RY] = ry;
        u[BODY_RZ] = rz;
        for (i, w) in v.wheels.iter().enumerate() {
            // Wheel position relative to the CoM: r = (wx, wy, −body_height).
            let wx = w.x0 + p.half_length;
            let wy = w.ey - p.offset_y;
            let r = [wx, wy, -p.body_height];
            // displacement = translation + θ × r
            u[w.dof_y.unwrap()] = 0.01 + (rz * r[0] - rx * r[2]);
            u[w.dof_z] = 0.02 + (rx * r[1] - ry * r[0]);
            let _ = i;
        }
        let f = &v.k * &u;
        assert!(f.amax() < 1e-9, "{f}");
    }

    #[test]
    fn heave_frequency_of_the_suspension() {
        // Body on four springs, massless wheels held (rigid rail): ω² = 4k/m.
        let p = Fig1 {
            wheel_mass: 0.0,
            ..Fig1::default()
        };
        let v = VehicleModel::fig1(&p, 9.81).unwrap();
        let mut u = nalgebra::DVector::zeros(13);
        u[BODY_W] = 1.0;
        let f = &v.k * &u;
        assert!((f[BODY_W] - 4.0 * p.k).abs() < 1e-6);
        // A unit heave pulls each wheel up with k.
        for w in &v.wheels {
            assert!((f[w.dof_z] + p.k).abs() < 1e-6);
        }
    }

    #[test]
    fn symmetric_car_carries_a_quarter_of_the_weight_per_wheel() {
        let p = Fig1::default();
        let v = VehicleModel::fig1(&p, 9.81).unwrap();
        let quarter = p.body_mass * 9.81 / 4.0;
        for &p0 in &v.p0 {
            assert!(
                (p0 - quarter).abs() <= 4.0 * f64::EPSILON * quarter,
                "{p0} vs {quarter}"
            );
        }
    }

    #[test]
    fn com_ahead_loads_the_front_wheels_as_the_lever_rule_says() {
        // Body CoM e ahead of the middle of the wheelbase 2h: moments about the CoM,
        // 2·F_f·(h − e) = 2·F_r·(h + e), and 2·F_f + 2·F_r = W, so
        // F_f = W (h + e)/(4h), F_r = W (h − e)/(4h) (lateral symmetry: near = far).
        for e in [0.9, -2.5, 6.0] {
            let p = Fig1 {
                com_ahead: e,
                wheel_mass: 300.0,
                ..Fig1::default()
            };
            let v = VehicleModel::fig1(&p, 9.81).unwrap();
            let (w, h) = (p.body_mass * 9.81, p.half_length);
            let want = [
                w * (h + e) / (4.0 * h),
                w * (h + e) / (4.0 * h),
                w * (h - e) / (4.0 * h),
                w * (h - e) / (4.0 * h),
            ];
            for (got, want) in v.p0.iter().zip(want) {
                assert!((got - want).abs() <= 1e-12 * w, "e = {e}: {got} vs {want}");
            }
        }
        // CoM beyond the front axle: the rear magnets would have to push.
        let p = Fig1 {
            com_ahead: 8.0,
            ..Fig1::default()
        };
        let e = VehicleModel::fig1(&p, 9.81).unwrap_err().to_string();
        assert!(e.contains("must be positive"), "{e}");
    }

    /// The unit's magnet carries (magnet + body)·g, with or without a body, and its model
    /// is the two-mass oscillator written out by hand.
    #[test]
    fn a_unit_carries_magnet_and_body() {
        for body in [0.0, 4000.0] {
            let p = Unit {
                magnet_mass: 600.0,
                body_mass: body,
                k: 3e5,
                c: 2e4,
                position: 10.0,
            };
            let v = VehicleModel::unit(&p, 9.81).unwrap();
            let want = (600.0 + body) * 9.81;
            assert!((v.p0[0] - want).abs() <= 1e-12 * want, "{:?}", v.p0);
            assert_eq!(v.wheels[0].x0, 10.0);
            assert_eq!(v.wheels[0].dof_y, None);
            if body > 0.0 {
                assert_eq!(v.k[(0, 1)], -3e5);
                assert_eq!(v.c[(1, 1)], 2e4);
                assert_eq!(v.m[(1, 1)], body);
                assert_eq!(v.body_z, 1);
            } else {
                assert_eq!(v.m.shape(), (1, 1));
            }
        }
    }
}
