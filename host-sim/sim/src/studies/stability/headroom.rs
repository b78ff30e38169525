//! The supply headroom of a vehicle's law (issue 39 point 2): the largest `|V|/V_max` of any
//! magnet in the time response of the linearised closed loop (no supply clamp) to the
//! reference disturbances:
//!
//! * `irregularity`: the case's vertical rail irregularity under every levitation magnet at
//!   the case's speed over the run (`t_end`), each magnet reading the profile at
//!   `x0 + v·t`, less its value at `x0` (the run starts in equilibrium over its rail); none at
//!   standstill;
//! * `load_step`: a 10 % step in static load, a force of `−0.1·W` (`W` the vehicle's weight)
//!   on the body's heave DOF at t = 0, held for 5 time constants of the slowest pole (2 s at
//!   least, 20 s at most);
//! * `guideway`: on a flexible guideway at speed, the rail as the run meets it under every
//!   levitation magnet of the train's first and last car: the girders' motion while the
//!   train's static loads cross them, plus the irregularity ([`super::guideway_rail`]; on a
//!   viaduct it holds the steps at the girder joints). Reported as `guideway_ratio`, apart
//!   from `ratio`: the design's targets are on a rigid guideway (issue 39 point 2), and a
//!   design searching over it would also run the guideway for every candidate. Above 0.8 a
//!   run on the case's guideway is likely to saturate the supply.
//!
//! # The model
//! The state matrix is [`VehiclePlant`]'s, with the span's bending modes where the coupled
//! analysis has them (standstill over spans, [`super::coupled`]), else on a rigid guideway.
//! The rail enters every
//! levitation gap as `+r/h0` (the core's `levitation_gap`, docs/model.md Eq. 2), and its
//! rate the law's gap rate: the same terms a girder mode under the magnet gives
//! ([`VehiclePlant::on_girder`], gap `−dh·φ·ξ/h0`). So the rail input is built as one
//! girder "mode" per magnet with `φ = 1` under it alone, driven as an input
//! (`ξ = −dh·r`), its own rows dropped: the remaining matrix is the rigid one (checked in
//! the tests), and the modes' displacement and velocity columns are the inputs `r`, `ṙ`. The
//! response is the exact zero-order-hold discretisation (`exp` of the augmented matrix) at
//! the step `min(dt, 1 ms)`, the input held at its mid-step value (rate: the step's
//! difference). A magnet's voltage is `V = R0·i0·(1 + Δv)`, `Δv` the law's row
//! ([`super::vehicle::MagnetLoop`]) with its direct term from the rail.

use super::girder::GirderMode;
use super::guideway_rail::GuidewayRail;
use super::vehicle::{vehicle_of, VehiclePlant};
use crate::input::case::Case;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// The name of the flexible guideway's disturbance (module docs).
pub const GUIDEWAY: &str = "guideway";

/// The static load step (a fraction of the vehicle's weight).
pub const LOAD_STEP: f64 = 0.1;

/// One disturbance's peak voltage.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct Peak {
    pub disturbance: &'static str,
    /// The largest `|V|` (V), the magnet and the time (s); `|V|/V_max` (null: no bound).
    pub peak_V: f64,
    pub magnet: String,
    pub t_s: f64,
    pub ratio: Option<f64>,
    /// The car of the train whose magnet it is (`guideway` only; 1-based).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub car: Option<usize>,
}

/// `headroom` as reported (module docs).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct Headroom {
    /// The law's supply bound (V; null: none).
    pub vmax_V: Option<f64>,
    /// The largest `|V|/V_max` over the design's reference disturbances, `load_step` and
    /// `irregularity` (the design target; null: no bound).
    pub ratio: Option<f64>,
    /// The largest `|V|/V_max` over the `guideway` disturbance (null: none, or no bound):
    /// the supply the case's own flexible guideway asks for at speed, which the design's
    /// rigid-guideway targets do not include; above 0.8 a run on it is likely to saturate.
    pub guideway_ratio: Option<f64>,
    pub disturbances: Vec<Peak>,
    pub method: &'static str,
}

const METHOD: &str = "the linearised closed loop (with the coupled analysis' girder modes at \
    standstill on spans, else on a rigid guideway), no supply clamp, exact \
    zero-order-hold steps of min(dt, 1 ms): the rail irregularity under every levitation \
    magnet at the case's speed over t_end (less its value at t = 0), and a step of −10 % of \
    the weight on the body's heave (ratio: the largest of these); on a flexible guideway \
    at speed, the rail under the first and last car as the train's static loads cross the \
    girders, irregularity included (guideway_ratio); V = R0·i0·(1 + Δv)";

/// The plant with rail inputs (module docs): `ẋ = A·x + B·u`, `u = (r_1…r_m, ṙ_1…ṙ_m)`,
/// `Δv_k = F_k·x + D_k·u`.
#[derive(Clone, Debug)]
pub struct RailPlant {
    pub a: DMatrix<f64>,
    pub b: DMatrix<f64>,
    pub f: DMatrix<f64>,
    pub d: DMatrix<f64>,
    /// The kept states' indices in the girder plant (for the force input).
    keep: Vec<usize>,
    /// The wheels' positions at t = 0 (m), the magnets' names.
    pub x0: Vec<f64>,
    pub names: Vec<String>,
    /// The plant as built with the rail modes (their rows included).
    pub full: VehiclePlant,
}

impl RailPlant {
    /// The plant of `case`'s vehicle with its law, the rail under each levitation magnet an
    /// input.
    pub fn of(case: &Case) -> crate::Result<Self> {
        let (v, _, _) = vehicle_of(case)?;
        let inner = case
            .controller
            .ok_or_else(|| crate::Error::invalid("controller", "needs a [controller] section"))?;
        let law = case.law()?;
        let nw = v.wheels.len();
        // The span's own modes where the coupled analysis has them (standstill on spans).
        let girder = match super::coupled::coupled(case, super::coupled::GIRDER_MODES)? {
            Some((modes, _)) => modes,
            None => Vec::new(),
        };
        let ng = girder.len();
        let rail: Vec<GirderMode> = (0..nw)
            .map(|w| GirderMode {
                span: 0,
                n: w + 1,
                kind: "bending-z",
                frequency_hz: 0.0,
                modal_mass_kg: 1.0,
                damping_ratio: 0.0,
                at_magnets: (0..nw).map(|k| if k == w { 1.0 } else { 0.0 }).collect(),
                lateral_at_magnets: vec![0.0; nw],
                closed_form_hz: 0.0,
                fe_vs_closed_form: 0.0,
            })
            .collect();
        let modes: Vec<GirderMode> = girder.into_iter().chain(rail).collect();
        let full = VehiclePlant::on_girder(&v, &inner, &law, case.geometry, &modes)?;
        let nv = v.m.nrows() + ng;
        let q_of = |j: usize| format!("q[{}]", nv + j);
        let v_of = |j: usize| format!("v[{}]", nv + j);
        let index = |name: &str| {
            full.states
                .iter()
                .position(|s| s == name)
                .ok_or_else(|| crate::Error::numerical(format!("internal: no state {name}")))
        };
        let mut inputs = Vec::with_capacity(2 * nw);
        for j in 0..nw {
            inputs.push(index(&q_of(j))?);
        }
        for j in 0..nw {
            inputs.push(index(&v_of(j))?);
        }
        let keep: Vec<usize> = (0..full.a.nrows())
            .filter(|i| !inputs.contains(i))
            .collect();
        let dh = case.geometry.levitation_sign();
        // ξ = −dh·r: the input columns times −dh.
        let b = DMatrix::from_fn(keep.len(), inputs.len(), |i, j| {
            -dh * full.a[(keep[i], inputs[j])]
        });
        let a = DMatrix::from_fn(keep.len(), keep.len(), |i, j| full.a[(keep[i], keep[j])]);
        let m = full.magnets.len();
        let f = DMatrix::from_fn(m, keep.len(), |k, j| full.magnets[k].dv[keep[j]]);
        let d = DMatrix::from_fn(m, inputs.len(), |k, j| -dh * full.magnets[k].dv[inputs[j]]);
        let names = full.magnets.iter().map(|l| l.name.clone()).collect();
        Ok(RailPlant {
            a,
            b,
            f,
            d,
            keep,
            x0: v.wheels.iter().map(|w| w.x0).collect(),
            names,
            full,
        })
    }
}

/// The exact zero-order-hold step of `ẋ = A·x + B·u` over `h`: `(Φ, Γ)`.
fn zoh(a: &DMatrix<f64>, b: &DMatrix<f64>, h: f64) -> (DMatrix<f64>, DMatrix<f64>) {
    let (n, m) = (a.nrows(), b.ncols());
    let mut aug = DMatrix::zeros(n + m, n + m);
    aug.view_mut((0, 0), (n, n)).copy_from(&(a * h));
    aug.view_mut((0, n), (n, m)).copy_from(&(b * h));
    let e = aug.exp();
    (
        e.view((0, 0), (n, n)).into_owned(),
        e.view((0, n), (n, m)).into_owned(),
    )
}

/// `ẋ = A·x + B·u`, `Δv = F·x + D·u`, as its exact zero-order-hold steps of `h`:
/// `x ← Φ·x + Γ·u` ([`zoh`], once per input map).
struct System<'a> {
    phi: DMatrix<f64>,
    gamma: DMatrix<f64>,
    f: &'a DMatrix<f64>,
    d: &'a DMatrix<f64>,
    h: f64,
}

impl<'a> System<'a> {
    fn new(
        a: &DMatrix<f64>,
        b: &DMatrix<f64>,
        f: &'a DMatrix<f64>,
        d: &'a DMatrix<f64>,
        h: f64,
    ) -> Self {
        let (phi, gamma) = zoh(a, b, h);
        System {
            phi,
            gamma,
            f,
            d,
            h,
        }
    }
}

/// The largest `|V|` of the response to `input(k)` (held over step `k`) over `steps` steps
/// from rest: `(V, magnet index, t)`.
fn peak_response(
    sys: &System,
    v_base: f64,
    steps: usize,
    input: &dyn Fn(usize) -> DVector<f64>,
) -> (f64, usize, f64) {
    let mut x = DVector::zeros(sys.phi.nrows());
    let mut best = (v_base, 0, 0.0);
    for k in 0..steps {
        let u = input(k);
        x = &sys.phi * &x + &sys.gamma * &u;
        let dv = sys.f * &x + sys.d * &u;
        for (i, dvi) in dv.iter().enumerate() {
            let v = (v_base * (1.0 + dvi)).abs();
            if v > best.0 {
                best = (v, i, (k + 1) as f64 * sys.h);
            }
        }
    }
    best
}

/// The rail input of step `k` of `h` for `nw` magnets, the rail under magnet `w` at `t` being
/// `r(w, t)`: `u = (r_1…r_nw, ṙ_1…ṙ_nw)`, `r` at the step's middle, `ṙ` the step's difference.
fn rail_input(nw: usize, h: f64, r: impl Fn(usize, f64) -> f64) -> impl Fn(usize) -> DVector<f64> {
    move |k: usize| {
        let t = k as f64 * h;
        DVector::from_fn(2 * nw, |i, _| {
            if i < nw {
                r(i, t + 0.5 * h)
            } else {
                (r(i - nw, t + h) - r(i - nw, t)) / h
            }
        })
    }
}

/// The step and the load step's duration (module docs).
fn load_step_time(a: &DMatrix<f64>) -> crate::Result<f64> {
    let slowest = super::eigenvalues(a)?
        .iter()
        .filter(|p| p.abs() >= super::vehicle::ZERO_POLE)
        .map(|p| -p.re)
        .fold(f64::INFINITY, f64::min);
    Ok(if slowest > 0.0 {
        (5.0 / slowest).clamp(2.0, 20.0)
    } else {
        20.0
    })
}

/// The headroom of `case`'s vehicle and law (module docs), the guideway's rail `rail`
/// ([`GuidewayRail::of`] of the case: it does not depend on the gains, so a design computes
/// it once; `None`: no `guideway` disturbance).
pub fn headroom(case: &Case, rail: Option<&GuidewayRail>) -> crate::Result<Headroom> {
    let rp = RailPlant::of(case)?;
    let inner = case
        .controller
        .ok_or_else(|| crate::Error::invalid("controller", "needs a [controller] section"))?;
    let law = case.law()?;
    let vmax = law.voltage_bound(&inner);
    let v_base = inner.r0 * inner.i0;
    let h = case.dt.min(1e-3);
    let mut out = Vec::new();
    let peak = |name: &'static str, (v, k, t): (f64, usize, f64)| Peak {
        disturbance: name,
        peak_V: v,
        magnet: rp.names[k].clone(),
        t_s: t,
        ratio: vmax.map(|m| v / m),
        car: None,
    };
    // The load step: the force column of the body's heave (the mechanical rows of the girder
    // plant, with no magnet reading it directly: the body carries no sensor).
    let (veh, _, _) = vehicle_of(case)?;
    let force = load_column(&rp, &veh)?;
    let w = -LOAD_STEP * veh.weight;
    let steps = (load_step_time(&rp.a)? / h).ceil() as usize;
    let zero_d = DMatrix::zeros(rp.f.nrows(), 1);
    out.push(peak(
        "load_step",
        peak_response(
            &System::new(&rp.a, &force, &rp.f, &zero_d, h),
            v_base,
            steps,
            &|_| DVector::from_element(1, w),
        ),
    ));
    // The rail's inputs, one discretisation for every rail disturbance.
    let rail_system = (case.speed > 0.0).then(|| System::new(&rp.a, &rp.b, &rp.f, &rp.d, h));
    if let Some(sys) = &rail_system {
        let profiles = crate::setup::irregularity(case)?;
        let z = &profiles.z;
        let speed = case.speed;
        let r = |w: usize, t: f64| z(rp.x0[w] + speed * t) - z(rp.x0[w]);
        let steps = (case.t_end / h).ceil() as usize;
        let input = rail_input(rp.x0.len(), h, r);
        out.push(peak(
            "irregularity",
            peak_response(sys, v_base, steps, &input),
        ));
    }
    if let (Some(rail), Some(sys)) = (rail, &rail_system) {
        let steps = (case.t_end / h).ceil() as usize;
        for (c, (number, _)) in rail.cars.iter().enumerate() {
            let input = rail_input(rp.x0.len(), h, |k, t| rail.at(c, k, t));
            let p = peak(GUIDEWAY, peak_response(sys, v_base, steps, &input));
            out.push(Peak {
                car: Some(*number),
                ..p
            });
        }
    }
    let ratio_of = |guideway: bool| {
        vmax.map(|m| {
            out.iter()
                .filter(|p| (p.disturbance == GUIDEWAY) == guideway)
                .map(|p| p.peak_V / m)
                .fold(0.0, f64::max)
        })
    };
    Ok(Headroom {
        vmax_V: vmax,
        ratio: ratio_of(false),
        guideway_ratio: ratio_of(true).filter(|_| out.iter().any(|p| p.disturbance == GUIDEWAY)),
        disturbances: out,
        method: METHOD,
    })
}

/// The input column of a force (N) on the body's heave DOF in `rp`'s kept state: the
/// massive rows' `M⁻¹·e_body`, an error where the mass matrix couples the body to a magnet
/// node (a magnet's accelerometer would then read the force directly).
fn load_column(
    rp: &RailPlant,
    veh: &crate::physics::vehicle::VehicleModel,
) -> crate::Result<DMatrix<f64>> {
    let body = veh.body_z;
    let m = &veh.m;
    if veh.wheels.iter().any(|w| m[(body, w.dof_z)] != 0.0) || m[(body, body)] <= 0.0 {
        return Err(crate::Error::invalid(
            "vehicle",
            "the headroom's load step needs a body with mass, its mass matrix apart from the magnets'",
        ));
    }
    let massive: Vec<usize> = (0..m.nrows())
        .filter(|&i| m.row(i).iter().any(|&x| x != 0.0))
        .collect();
    let m_aa = DMatrix::from_fn(massive.len(), massive.len(), |i, j| {
        m[(massive[i], massive[j])]
    });
    let inv = m_aa.cholesky().ok_or_else(|| {
        crate::Error::numerical("the vehicle's mass matrix is not positive definite")
    })?;
    let ib = massive
        .iter()
        .position(|&i| i == body)
        .ok_or_else(|| crate::Error::numerical("internal: the body has no mass row"))?;
    let mut e = DVector::zeros(massive.len());
    e[ib] = 1.0;
    let col = inv.solve(&e);
    let mut out = DMatrix::zeros(rp.a.nrows(), 1);
    for (ia, &i) in massive.iter().enumerate() {
        let name = format!("v[{i}]");
        if let Some(full_index) = rp.full.states.iter().position(|s| *s == name) {
            if let Some(k) = rp.keep.iter().position(|&j| j == full_index) {
                out[(k, 0)] = col[ia];
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit(sets: &[&str]) -> Case {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        crate::studies::design::load("unit", &sets).unwrap()
    }

    /// Dropping the rail "modes" leaves the rigid plant: the same matrix to rounding.
    #[test]
    fn the_rail_plant_is_the_rigid_plant_with_inputs() {
        for sets in [
            &["run.model=rigid"][..],
            &["run.model=rigid", "law=paper"][..],
        ] {
            let case = unit(sets);
            let rp = RailPlant::of(&case).unwrap();
            let (v, _, _) = vehicle_of(&case).unwrap();
            let rigid = VehiclePlant::new(
                &v,
                &case.controller.unwrap(),
                &case.law().unwrap(),
                case.geometry,
            )
            .unwrap();
            assert_eq!(rp.a.shape(), rigid.a.shape(), "{sets:?}");
            let d = (&rp.a - &rigid.a).norm();
            assert!(d <= 1e-12 * rigid.a.norm(), "{sets:?}: {d}");
            for (k, l) in rigid.magnets.iter().enumerate() {
                let dv = DVector::from_column_slice(&l.dv);
                assert!((rp.f.row(k).transpose() - &dv).norm() <= 1e-12 * dv.norm().max(1.0));
            }
        }
    }

    /// A 10 % load step on the unit under the state law (an integral on the gap): the gap
    /// returns to h0 and the coil carries 1.1·p0 with `(1 + x)² = 1.1`, linearised
    /// `x = Δv = 0.05`, so the voltage settles at `1.05·R0·i0`.
    #[test]
    fn the_load_step_settles_at_the_linearised_static_voltage() {
        let case = unit(&["run.model=rigid"]);
        let rp = RailPlant::of(&case).unwrap();
        let (veh, _, _) = vehicle_of(&case).unwrap();
        let force = load_column(&rp, &veh).unwrap();
        let (phi, gamma) = zoh(&rp.a, &force, 1e-3);
        let mut x = DVector::zeros(rp.a.nrows());
        let u = DVector::from_element(1, -LOAD_STEP * veh.weight);
        for _ in 0..30_000 {
            x = &phi * &x + &gamma * &u;
        }
        let dv = (&rp.f * &x)[0];
        assert!((dv - 0.05).abs() < 1e-6, "{dv}");
        let h = headroom(&case, None).unwrap();
        assert_eq!(h.guideway_ratio, None, "no guideway disturbance");
        let p = &h.disturbances[0];
        assert_eq!(p.disturbance, "load_step");
        // The peak is at least the settled voltage, and overshoots it.
        let v_base = case.controller.unwrap().r0 * case.controller.unwrap().i0;
        assert!(p.peak_V >= 1.05 * v_base * (1.0 - 1e-6), "{h:?}");
        assert_eq!(h.disturbances.len(), 1, "standstill: no irregularity");
    }
}
