//! The scenario's own vehicle on a rigid rail, linearised with all its magnets: the closed-loop
//! state matrix, its poles, the verdict and the critical magnet node mass (issue 8, item 5).
//!
//! # The system
//! The vehicle is the scenario's [`VehicleModel`] (`M q̈ + C q̇ + K q = f`, deviations from
//! static equilibrium, docs/model.md §6). The rail is rigid and smooth (`z_g = y_g = r = 0`), so
//! every gap is a function of the wheel node alone, through the core's geometry
//! ([`Geometry`], docs/model.md §2), linearised with the core's own derivatives:
//!
//! ```text
//! levitation:  η_z = levitation_sign·z_w/h0
//! guidance:    (h_L, h_R) = guidance_gaps(h0, d), d = y_w     → η_L = +y_w/h0, η_R = −y_w/h0
//! forces:      f[z_w] = 2·p0·x_z,   f[y_w] = 2·p0·(∂F_y/∂G_L·x_L + ∂F_y/∂G_R·x_R)
//! ```
//!
//! (`∂F_y/∂G_{L,R}` from `Geometry::guidance_force`; `G = p0·(1 + x)²`, Eq. 1.) Every magnet —
//! each wheel's levitation magnet and both of its guidance magnets — runs its own law, the rows
//! of [`super::magnet`] (Eq. 9–10 in continuous time, states `x`, `y`; plus the gap loop's
//! filter state `q` under `law = gap-loop`), with `p0` the wheel's static load.
//!
//! # Massless nodes
//! A DOF whose mass row is zero (a wheel node with `wheel_mass_kg = 0`) has no inertia: its
//! equation `C_zz·q̇_z + C_za·q̇_a + K_z·q = f_z` is a first-order one. It is eliminated as an
//! index-1 constraint: `q̇_z = C_zz⁻¹·(f_z − K_z·q − C_za·v_a)` (needs `C_zz` regular: every
//! massless node needs a damper), substituted into the massive rows
//! `M_aa·v̇_a = f_a − K_a·q − C_aa·v_a − C_az·q̇_z`. The state is then `(q, v_a, magnets)`: all
//! displacements, the velocities of the DOFs with mass, and the magnets' states. With masses
//! on every node it is the usual `(q, q̇, magnets)`.
//!
//! # Zero poles
//! The paper's law holds `g`, hence the force, not the gap: wherever the vehicle stands with
//! its springs unstretched, every magnet carrying its `p0` (`x = 0`, `y = η`) is an
//! equilibrium. So each rigid-body motion of the vehicle (for Fig. 1: `v, w, θx, θy, θz`, 5)
//! gives a pole at exactly 0. They are counted (|s| < [`ZERO_POLE`]) and left out of the
//! verdict. Under the gap loop the equilibrium needs `x_ref = x = 0`, i.e. `η = 0`: no zero
//! pole.

use super::girder::GirderMode;
use super::inner_loop::Loop;
use super::magnet::{self, Slots};
use super::Complex;
use crate::input::case::{Case, TrainCase};
use crate::physics::vehicle::{Fig1, Unit, VehicleModel};
use maglev_core::gap::{self, Geometry};
use maglev_core::law::guidance::GuidanceParams;
use maglev_core::levitation::GRAVITY;
use maglev_core::LawKind;
use maglev_core::Params;
use nalgebra::DMatrix;

/// Poles with a modulus below this (1/s) count as zero poles.
pub const ZERO_POLE: f64 = 1e-6;

/// The linearised closed loop of a vehicle and all its magnets.
#[derive(Clone, Debug)]
pub struct VehiclePlant {
    /// State matrix.
    pub a: DMatrix<f64>,
    /// Names of the states, in order (`q[i]` vehicle DOF i, `v[i]` its velocity, `lev1.x`,
    /// `guideL1.y`, … per wheel).
    pub states: Vec<String>,
    /// Every magnet's loop as it enters `a`, in state order (for the margins).
    pub magnets: Vec<MagnetLoop>,
}

/// Where one magnet's loop closes in the state matrix: the coil's row `x` is
/// `τ·ẋ = Δv − η − x` (per unit, [`super::magnet`]), so the loop breaks at the coil voltage
/// with the input column `e_x/τ` and the law's voltage row `Δv` (over the whole state).
#[derive(Clone, Debug)]
pub struct MagnetLoop {
    /// `lev1`, `guideL1`, …
    pub name: String,
    /// The magnet's static load (N) and the mass of the node it acts on (kg).
    pub p0: f64,
    pub mass: f64,
    /// The coil's `x` state and time constant τ (s).
    pub x: usize,
    pub tau: f64,
    /// The law's per-unit voltage change `Δv` as a row over the state.
    pub dv: Vec<f64>,
}

/// Poles and what they say.
#[derive(Clone, Debug, PartialEq)]
pub struct Verdict {
    /// Every pole, sorted by descending real part (1/s).
    pub poles: Vec<Complex>,
    /// Poles with |s| < [`ZERO_POLE`].
    pub zero_poles: usize,
    /// Largest real part among the other poles (1/s).
    pub max_real_part: f64,
    /// `max_real_part < 0`.
    pub stable: bool,
}

impl Verdict {
    /// Classifies `poles` (sorted).
    pub fn of(poles: Vec<Complex>) -> Self {
        let zero_poles = poles.iter().filter(|p| p.abs() < ZERO_POLE).count();
        let max_real_part = poles
            .iter()
            .filter(|p| p.abs() >= ZERO_POLE)
            .map(|p| p.re)
            .fold(f64::NEG_INFINITY, f64::max);
        Verdict {
            poles,
            zero_poles,
            max_real_part,
            stable: max_real_part < 0.0,
        }
    }
}

/// `Err` where a run of `case` would refuse its law: each magnet wheel of `v` compiled as the
/// run compiles it ([`crate::simulation::magnets::compile_law`]), so that no analysis judges a
/// law that `maglev run` refuses (`vmax_V = 1e-300`).
pub fn runnable(case: &Case, v: &VehicleModel, inner: &Params, law: LawKind) -> crate::Result<()> {
    let guidance = case.guidance()?;
    for &p0 in &v.p0 {
        crate::simulation::magnets::compile_law(inner, law, p0, case.dt)?;
        if let Some(g) = &guidance {
            let magnet = Params {
                p0,
                dt: case.dt,
                ..*inner
            };
            crate::simulation::magnets::compile_guidance(g, &law, &magnet)?;
        }
    }
    Ok(())
}

/// Rows `idx` and columns `jdx` of `m`.
fn sub(m: &DMatrix<f64>, idx: &[usize], jdx: &[usize]) -> DMatrix<f64> {
    DMatrix::from_fn(idx.len(), jdx.len(), |i, j| m[(idx[i], jdx[j])])
}

impl VehiclePlant {
    /// Linearises vehicle `v` with the inner law `inner` (its `p0` replaced by each wheel's
    /// static load), the levitation `law` on every magnet and the `geometry` (module docs).
    pub fn new(
        v: &VehicleModel,
        inner: &Params,
        law: &LawKind,
        geometry: Geometry,
    ) -> crate::Result<Self> {
        Self::sampled(v, inner, law, geometry, None)
    }

    /// As [`VehiclePlant::new`], every guidance pair under the guidance law `guidance`
    /// (`maglev_core::law::guidance`, [`super::magnet::write_guidance_rows`]) when given:
    /// one integral per pair (`guide{N}.u`) instead of one per magnet. Needs the state law.
    pub fn guided(
        v: &VehicleModel,
        inner: &Params,
        law: &LawKind,
        guidance: Option<&GuidanceParams>,
        geometry: Geometry,
    ) -> crate::Result<Self> {
        Self::build(v, inner, law, guidance, geometry, None, &[])
    }

    /// As [`VehiclePlant::new`], with the gap loop's reference delayed by `delay` (s, a
    /// first-order Padé, [`super::magnet::Slots::delay`]): the sampled loop's hold, for the
    /// design. Ignored under the paper's law.
    pub fn sampled(
        v: &VehicleModel,
        inner: &Params,
        law: &LawKind,
        geometry: Geometry,
        delay: Option<f64>,
    ) -> crate::Result<Self> {
        Self::build(v, inner, law, None, geometry, delay, &[])
    }

    /// As [`VehiclePlant::new`], the levitation magnets over the flexible girder of `modes`
    /// (module docs of [`super::girder`], eq. G1): one DOF `ξ_j` per mode after the
    /// vehicle's, the gap `h = h0 ± (z_w − Σ φ_j·ξ_j)` (Eq. 2) and each magnet's force
    /// change acting on its node and, opposite, on every mode (`−φ_j·2·p0·x`).
    pub fn on_girder(
        v: &VehicleModel,
        inner: &Params,
        law: &LawKind,
        geometry: Geometry,
        modes: &[GirderMode],
    ) -> crate::Result<Self> {
        Self::build(v, inner, law, None, geometry, None, modes)
    }

    /// As [`VehiclePlant::on_girder`], the guidance pairs under `guidance`
    /// ([`VehiclePlant::guided`]).
    pub fn guided_on_girder(
        v: &VehicleModel,
        inner: &Params,
        law: &LawKind,
        guidance: Option<&GuidanceParams>,
        geometry: Geometry,
        modes: &[GirderMode],
    ) -> crate::Result<Self> {
        Self::build(v, inner, law, guidance, geometry, None, modes)
    }

    fn build(
        v: &VehicleModel,
        inner: &Params,
        law: &LawKind,
        guidance: Option<&GuidanceParams>,
        geometry: Geometry,
        delay: Option<f64>,
        girder: &[GirderMode],
    ) -> crate::Result<Self> {
        let nv = v.m.nrows();
        if v.m.ncols() != nv || v.c.shape() != (nv, nv) || v.k.shape() != (nv, nv) {
            return Err(crate::Error::numerical(
                "internal: vehicle matrices are not square and of one size",
            ));
        }
        if v.p0.len() != v.wheels.len() {
            return Err(crate::Error::numerical(
                "internal: one static load per wheel expected",
            ));
        }
        if girder.iter().any(|g| {
            g.at_magnets.len() != v.wheels.len() || g.lateral_at_magnets.len() != v.wheels.len()
        }) {
            return Err(crate::Error::numerical(
                "internal: one girder mode value per wheel expected",
            ));
        }
        // The vehicle's matrices with one DOF per girder mode after its own (eq. G1).
        let n = nv + girder.len();
        let (mut vm, mut vc, mut vk) = (
            DMatrix::zeros(n, n),
            DMatrix::zeros(n, n),
            DMatrix::zeros(n, n),
        );
        vm.view_mut((0, 0), (nv, nv)).copy_from(&v.m);
        vc.view_mut((0, 0), (nv, nv)).copy_from(&v.c);
        vk.view_mut((0, 0), (nv, nv)).copy_from(&v.k);
        for (j, g) in girder.iter().enumerate() {
            let (mj, w) = (g.modal_mass_kg, g.omega());
            vm[(nv + j, nv + j)] = mj;
            vc[(nv + j, nv + j)] = 2.0 * g.damping_ratio * w * mj;
            vk[(nv + j, nv + j)] = mj * w * w;
        }
        let v_m = &vm;
        let massive: Vec<usize> = (0..n)
            .filter(|&i| v_m.row(i).iter().any(|&x| x != 0.0))
            .collect();
        let massless: Vec<usize> = (0..n).filter(|i| !massive.contains(i)).collect();
        if massless
            .iter()
            .any(|&j| massive.iter().any(|&i| v_m[(i, j)] != 0.0))
        {
            return Err(crate::Error::numerical(
                "internal: the mass matrix couples a massless DOF",
            ));
        }
        let (na, nz) = (massive.len(), massless.len());
        let m_inv = sub(v_m, &massive, &massive)
            .cholesky()
            .ok_or_else(|| {
                crate::Error::numerical(
                    "the vehicle's mass matrix (DOFs with mass) is not positive definite",
                )
            })?
            .inverse();
        let cz_inv = if nz > 0 {
            sub(&vc, &massless, &massless)
                .try_inverse()
                .ok_or_else(|| {
                    crate::Error::invalid(
                        "vehicle",
                        "a massless vehicle node needs a damper (the damping of the massless DOFs is singular)",
                    )
                })?
        } else {
            DMatrix::zeros(0, 0)
        };

        // State layout: q (n), v_a (na), then per wheel: lev, guide L, guide R magnets.
        // The plant arm of each law: the gap loop's reference filter, the state law's
        // observer and integral (the paper's law has neither).
        law.validate().map_err(|e| {
            let key = match law.gap_loop() {
                Some(_) => "gap_loop",
                None => "controller.law",
            };
            crate::Error::invalid(key, e.to_string())
        })?;
        let (gains, state_law) = (law.gap_loop(), law.state());
        if guidance.is_some() && state_law.is_none() {
            return Err(crate::error::guidance_needs_state_law());
        }
        if let Some(g) = guidance {
            g.validate().map_err(crate::input::case::guidance_error)?;
        }
        let delay = delay.filter(|_| gains.is_some());
        let per = 2 + usize::from(gains.is_some()) + usize::from(delay.is_some());
        let nm = n + na;
        // Per wheel its levitation magnet, and its guidance pair when it has a lateral DOF;
        // under the guidance law a pair has its coils and one integral.
        let pair_states = if guidance.is_some() { 3 } else { 2 * per };
        let count: usize = v
            .wheels
            .iter()
            .map(|w| 1 + 2 * usize::from(w.dof_y.is_some()))
            .sum();
        let ns = nm
            + v.wheels
                .iter()
                .map(|w| per + pair_states * usize::from(w.dof_y.is_some()))
                .sum::<usize>();
        let mut states: Vec<String> = (0..n).map(|i| format!("q[{i}]")).collect();
        states.extend(massive.iter().map(|i| format!("v[{i}]")));
        // The next free state; a guidance law's right magnet shares its pair's integral.
        let mut next = nm;
        let mut slot = |shared: Option<usize>| {
            let base = next;
            let at = match shared {
                Some(u) => Slots {
                    x: base,
                    y: u,
                    q: None,
                    delay: None,
                },
                None => Slots {
                    x: base,
                    y: base + 1,
                    q: gains.map(|_| base + 2),
                    delay: delay.map(|d| (base + 3, d)),
                },
            };
            next += if shared.is_some() { 1 } else { per };
            at
        };

        // The core's geometry, differentiated: gaps per metre, lateral force per unit force.
        let dh_dz = geometry.levitation_sign();
        let (hl, hr) = gap::guidance_gaps(0.0, 1.0);
        let (dfy_dl, dfy_dr) = (
            geometry.guidance_force(1.0, 0.0),
            geometry.guidance_force(0.0, 1.0),
        );

        // Force map f = F·s and the magnets' rows.
        let mut f = DMatrix::zeros(n, ns);
        let mut a = DMatrix::zeros(ns, ns);
        // State-law magnets read the gap's rate and the magnet's acceleration, which the
        // mechanical rows give: their rows are written after those.
        let mut state_magnets = Vec::new();
        // Guidance pairs under the guidance law: both magnets' loop indices, slots and gaps.
        let mut guided_pairs = Vec::new();
        let mut loops = Vec::with_capacity(count);
        for (w, (wh, &p0)) in v.wheels.iter().zip(&v.p0).enumerate() {
            let mut p = *inner;
            p.p0 = p0;
            p.validate()
                .map_err(|e| crate::Error::invalid(format!("wheel {}", w + 1), e.to_string()))?;
            let lp = Loop::new(&p, 0.0);
            let h0 = p.h0;
            let mut magnets = vec![("lev", wh.dof_z, dh_dz, 1.0)];
            if let Some(y) = wh.dof_y {
                magnets.extend([("guideL", y, hl, dfy_dl), ("guideR", y, hr, dfy_dr)]);
            }
            let mut pair_u = None;
            for (k, (name, dof, dh, df)) in magnets.into_iter().enumerate() {
                // Under the guidance law the right magnet (k = 2) shares the left's integral.
                let at = slot(pair_u.filter(|_| k == 2));
                if guidance.is_some() && k == 1 {
                    pair_u = Some(at.y);
                }
                // The gap reads the node and the rail under it, vertically (levitation, Eq. 2)
                // or laterally (the pair's offset); the magnet's force loads the girder back.
                let mut gap_terms = vec![(dof, dh / h0)];
                for (j, g) in girder.iter().enumerate() {
                    let phi = if k == 0 {
                        g.at_magnets[w]
                    } else {
                        g.lateral_at_magnets[w]
                    };
                    gap_terms.push((nv + j, -dh * phi / h0));
                    f[(nv + j, at.x)] -= phi * df * 2.0 * p0;
                }
                let dv = match state_law {
                    None => magnet::write_rows(&mut a, at, &gap_terms, &lp, gains)?,
                    Some(_) if guidance.is_some() && k > 0 => {
                        guided_pairs.push((loops.len(), at, dof, gap_terms, p, lp));
                        Vec::new()
                    }
                    Some(_) => {
                        state_magnets.push((loops.len(), at, dof, gap_terms, k == 0, p, lp));
                        Vec::new()
                    }
                };
                loops.push(MagnetLoop {
                    name: format!("{name}{}", w + 1),
                    p0,
                    mass: v_m[(dof, dof)],
                    x: at.x,
                    tau: lp.tau,
                    dv,
                });
                f[(dof, at.x)] += df * 2.0 * p0;
                states.push(format!("{name}{}.x", w + 1));
                match (guidance, k) {
                    (Some(_), 1) => states.push(format!("guide{}.u", w + 1)),
                    (Some(_), 2) => {}
                    _ => states.push(format!("{name}{}.y", w + 1)),
                }
                if at.q.is_some() {
                    states.push(format!("{name}{}.q", w + 1));
                }
                if at.delay.is_some() {
                    states.push(format!("{name}{}.w", w + 1));
                }
            }
        }

        // Mechanical rows (module docs): q̇_a = v_a, q̇_z = C_zz⁻¹(f_z − K_z q − C_za v_a),
        // v̇_a = M_aa⁻¹(f_a − K_a q − C_aa v_a − C_az q̇_z).
        let mut kq = DMatrix::zeros(n, ns); // K·q as a map of the state
        kq.columns_mut(0, n).copy_from(&vk);
        let mut cv = DMatrix::zeros(n, ns); // C restricted to the massive velocities
        for (ia, &i) in massive.iter().enumerate() {
            cv.column_mut(n + ia).copy_from(&vc.column(i));
        }
        let rhs = &f - &kq - &cv; // f − K q − C_{·a} v_a, over every DOF
        let qz_dot = &cz_inv * sub(&rhs, &massless, &(0..ns).collect::<Vec<_>>());
        let c_az = sub(&vc, &massive, &massless);
        let va_dot = &m_inv * (sub(&rhs, &massive, &(0..ns).collect::<Vec<_>>()) - &c_az * &qz_dot);
        for (ia, &i) in massive.iter().enumerate() {
            a[(i, n + ia)] = 1.0;
            a.row_mut(n + ia).copy_from(&va_dot.row(ia));
        }
        for (iz, &i) in massless.iter().enumerate() {
            a.row_mut(i).copy_from(&qz_dot.row(iz));
        }
        if let Some(law) = state_law {
            for (index, at, dof, gap_terms, levitation, p, lp) in state_magnets {
                let (eta, eta_rate) = sensed(&a, &gap_terms);
                // The levitation magnet's accelerometer: the DOF's velocity row derivative.
                let accel: Option<Vec<f64>> = match massive.iter().position(|&i| i == dof) {
                    Some(ia) if levitation => Some(a.row(n + ia).iter().copied().collect()),
                    _ if levitation && law.ka != 0.0 => {
                        return Err(crate::Error::invalid(
                            "vehicle.wheel_mass_kg",
                            "the state law's acceleration feedback (ka > 0) needs a magnet \
                             with mass",
                        ))
                    }
                    _ => None,
                };
                let sensors = magnet::StateSensors {
                    eta: &eta,
                    eta_rate: &eta_rate,
                    accel: accel.as_deref(),
                };
                loops[index].dv = magnet::write_state_rows(&mut a, at, &sensors, &lp, law, &p);
            }
            for pair in guided_pairs.chunks_exact(2) {
                let [(il, at_l, dof, gap_l, p, lp), (ir, at_r, _, gap_r, _, _)] = pair else {
                    continue;
                };
                let Some(g) = guidance else { continue };
                let ((eta_l, rate_l), (eta_r, rate_r)) = (sensed(&a, gap_l), sensed(&a, gap_r));
                // The pair's lateral accelerometer: the DOF's velocity row derivative.
                let accel: Option<Vec<f64>> = match massive.iter().position(|i| i == dof) {
                    Some(ia) => Some(a.row(n + ia).iter().copied().collect()),
                    None if g.ka != 0.0 => {
                        return Err(crate::Error::invalid(
                            "controller.guidance.ka_V_s2_per_m",
                            "the lateral acceleration feedback (ka > 0) needs a magnet with \
                             mass",
                        ))
                    }
                    None => None,
                };
                let sensors = magnet::PairSensors {
                    eta: [&eta_l, &eta_r],
                    eta_rate: [&rate_l, &rate_r],
                    accel: accel.as_deref(),
                };
                let [dl, dr] = magnet::write_guidance_rows(
                    &mut a,
                    [at_l.x, at_r.x],
                    at_l.y,
                    &sensors,
                    lp,
                    g,
                    p,
                );
                loops[*il].dv = dl;
                loops[*ir].dv = dr;
            }
        }
        Ok(VehiclePlant {
            a,
            states,
            magnets: loops,
        })
    }

    /// Closed-loop poles (1/s), sorted by descending real part ([`super::eigenvalues`]).
    pub fn poles(&self) -> crate::Result<Vec<Complex>> {
        super::eigenvalues(&self.a)
    }

    /// The poles classified ([`Verdict::of`]).
    pub fn verdict(&self) -> crate::Result<Verdict> {
        Ok(Verdict::of(self.poles()?))
    }
}

/// The gap `η = Σ c·state[j]` of `gap_terms` and its rate from the mechanical rows of `a`
/// (exact: the analysis' ideal sensors), as rows over the state.
fn sensed(a: &DMatrix<f64>, gap_terms: &[(usize, f64)]) -> (Vec<f64>, Vec<f64>) {
    let ns = a.ncols();
    let (mut eta, mut eta_rate) = (vec![0.0; ns], vec![0.0; ns]);
    for &(j, c) in gap_terms {
        eta[j] += c;
        for (r, v) in eta_rate.iter_mut().zip(a.row(j).iter()) {
            *r += c * v;
        }
    }
    (eta, eta_rate)
}

/// The Fig. 1 vehicle `fig` with every wheel node's mass set to `mass` (kg), linearised.
pub fn fig1_with_mass(
    fig: &Fig1,
    mass: f64,
    inner: &Params,
    law: &LawKind,
    geometry: Geometry,
) -> crate::Result<VehiclePlant> {
    let fig = Fig1 {
        wheel_mass: mass,
        ..fig.clone()
    };
    let v = VehicleModel::fig1(&fig, GRAVITY)?;
    VehiclePlant::new(&v, inner, law, geometry)
}

/// Upper end of the critical-mass search (kg).
pub const MASS_SEARCH_MAX: f64 = 10e3;

/// The smallest magnet (wheel) node mass in `[fig.wheel_mass, 10 t]` at which the vehicle of
/// `fig` with `law` and `geometry` is unstable, or `None` if it is stable on the whole range.
///
/// Method: the verdict on a grid — the scenario's own mass, then 400 log-spaced masses from
/// 1 kg (or the scenario's mass if larger) to 10 t, a step of 2.3 % — brackets the first
/// unstable mass; bisection on the verdict then narrows the bracket to 1e-3 kg (or 1e-6
/// relative). An unstable window narrower than one grid step (2.3 %) could be missed. If the
/// scenario's own mass is unstable, that mass is returned.
pub fn critical_magnet_mass(
    fig: &Fig1,
    inner: &Params,
    law: &LawKind,
    geometry: Geometry,
) -> crate::Result<Option<f64>> {
    critical_mass(fig.wheel_mass, |m| {
        fig1_with_mass(fig, m, inner, law, geometry)
    })
}

/// [`critical_magnet_mass`] for any vehicle: `build(m)` linearises it with magnet mass `m`,
/// `m0` the scenario's own.
pub fn critical_mass(
    m0: f64,
    build: impl Fn(f64) -> crate::Result<VehiclePlant>,
) -> crate::Result<Option<f64>> {
    let unstable = |m: f64| -> crate::Result<bool> { Ok(!build(m)?.verdict()?.stable) };
    if unstable(m0)? {
        return Ok(Some(m0));
    }
    let lo = m0.max(1.0);
    if lo >= MASS_SEARCH_MAX {
        return Ok(None);
    }
    const N: usize = 400;
    let mut prev = m0;
    for i in 0..=N {
        let m = lo * (MASS_SEARCH_MAX / lo).powf(i as f64 / N as f64);
        if unstable(m)? {
            let (mut a, mut b) = (prev, m);
            while b - a > 1e-3_f64.max(1e-6 * b) {
                let mid = 0.5 * (a + b);
                if unstable(mid)? {
                    b = mid;
                } else {
                    a = mid;
                }
            }
            return Ok(Some(b));
        }
        prev = m;
    }
    Ok(None)
}

/// The vehicle of a case as a function of its magnet mass (kg), and that mass.
type Builder = Box<dyn Fn(f64) -> crate::Result<VehicleModel>>;

pub fn vehicle_of(case: &Case) -> crate::Result<(VehicleModel, f64, Builder)> {
    match &case.train {
        TrainCase::Fig1 { car, .. } => {
            let car = car.clone();
            let v = VehicleModel::fig1(&car, GRAVITY)?;
            let m0 = car.wheel_mass;
            let build: Builder = Box::new(move |m| {
                let fig = Fig1 {
                    wheel_mass: m,
                    ..car.clone()
                };
                VehicleModel::fig1(&fig, GRAVITY)
            });
            Ok((v, m0, build))
        }
        TrainCase::Unit(u) => {
            let u = u.clone();
            let v = VehicleModel::unit(&u, GRAVITY)?;
            let m0 = u.magnet_mass;
            let build: Builder = Box::new(move |m| {
                VehicleModel::unit(
                    &Unit {
                        magnet_mass: m,
                        ..u.clone()
                    },
                    GRAVITY,
                )
            });
            Ok((v, m0, build))
        }
        TrainCase::Maglev { magnet_mass, .. } => {
            // One carriage: the train's carriages share no spring or damper
            // (`Train::from_cars`), so on a rigid rail the train's poles are one carriage's,
            // each once per carriage.
            let carriage = |m: f64| -> crate::Result<VehicleModel> {
                let mut t = crate::physics::train::Train::fig6_with(
                    &crate::input::case::fig6(m),
                    1,
                    GRAVITY,
                )?;
                Ok(t.cars.remove(0))
            };
            let m0 = *magnet_mass;
            Ok((carriage(m0)?, m0, Box::new(carriage)))
        }
        _ => Err(crate::Error::invalid(
            "vehicle.kind",
            "stability --scenario needs a fig1, maglev or unit vehicle (magnets to analyse)",
        )),
    }
}

/// Smallest damping ratio `−re/|s|` of `poles` other than the zero poles.
pub fn min_damping(poles: &[Complex]) -> f64 {
    poles
        .iter()
        .filter(|p| p.abs() >= ZERO_POLE)
        .map(|p| -p.re / p.abs())
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
pub(super) mod tests;
