//! [`ModalGuideway`]: one simply supported Timoshenko span as a Fourier series (Eq. 20a–e),
//! each series term advanced by Newmark, behind the [`Guideway`] interface.

use core::fmt;

use nalgebra::{Matrix1, Matrix2, Vector1, Vector2};

use super::mode_integrator::{ModeState, NewmarkMode};
use super::modes::{
    bearing_force, natural_frequencies, wavenumber, ModeFrequencies, PlaneProperties,
    TorsionProperties,
};
use crate::physics::guideway::{
    BeamSection, Bridge, Guideway, PointLoad, PointMotion, SectionMotion,
};
use crate::physics::seismic::support::BEARINGS;

/// Why a [`ModalGuideway`] could not be built.
#[derive(Clone, Debug, PartialEq)]
pub enum ModalError {
    /// The modal reference covers exactly one span; the bridge had this many.
    SpanCount(usize),
    /// A parameter was out of range (name of the parameter).
    InvalidParameter(&'static str),
}

impl fmt::Display for ModalError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ModalError::SpanCount(n) => write!(
                f,
                "the modal reference is for one simply supported span, the bridge has {n}"
            ),
            ModalError::InvalidParameter(p) => write!(f, "invalid modal guideway parameter: {p}"),
        }
    }
}

impl std::error::Error for ModalError {}

/// State of all series terms at one instant.
#[derive(Clone, Debug)]
struct SpanState {
    /// X–Z bending, per n: (q_n, r_n) — w and bending rotation φ_Y ≈ ∂w/∂x.
    vertical: Vec<ModeState<2>>,
    /// X–Y bending, per n: (q_n, r_n) — v and bending rotation φ_Z ≈ ∂v/∂x.
    lateral: Vec<ModeState<2>>,
    /// Torsion, per n: s_n.
    torsion: Vec<ModeState<1>>,
}

impl SpanState {
    fn zero(modes: usize) -> Self {
        SpanState {
            vertical: vec![ModeState::zero(); modes],
            lateral: vec![ModeState::zero(); modes],
            torsion: vec![ModeState::zero(); modes],
        }
    }
}

/// Generalized forces of term n: (vertical, lateral, torsion), already scaled by 2/L.
type ModalForce = [f64; 3];

/// The modal (Fourier series) Timoshenko reference for one simply supported span of length L
/// starting at x = 0 (paper §4.1, Eq. 20a–e; docs/model.md §8). Undamped, zero initial
/// conditions, no axial vibration, no warping. Outside [0, L] the guideway is rigid.
///
/// Series: w = Σ q_n sin(nπx/L), φ_Y = Σ r_n cos(nπx/L) (and the same for v, φ_Z),
/// θ = Σ s_n sin(nπx/L), n = 1..=modes. Loads act through a rigid link (docs/model.md §5):
/// torque about X is ey·fz − ez·fy; the point motion adds z += θ·ey, y −= θ·ez.
///
/// The state before the first step is at rest with zero acceleration, i.e. the loads at
/// t = 0 are taken as zero (true for a vehicle entering at x = 0, where sin(nπx/L) = 0).
#[derive(Clone, Debug)]
pub struct ModalGuideway {
    section: BeamSection,
    length: f64,
    dt: f64,
    vertical: Vec<NewmarkMode<2>>,
    lateral: Vec<NewmarkMode<2>>,
    torsion: Vec<NewmarkMode<1>>,
    committed: SpanState,
    trial: SpanState,
    forces: Vec<ModalForce>,
    /// Bearing accelerations of the next steps (z left, z right, y left, y right; m/s²),
    /// set by [`Self::set_bearing_acceleration`]; zero otherwise.
    bearings: [f64; BEARINGS],
}

impl ModalGuideway {
    /// One span of `length` (m) with `modes` series terms per field, time step `dt` (s).
    pub fn new(
        section: BeamSection,
        length: f64,
        modes: usize,
        dt: f64,
    ) -> Result<Self, ModalError> {
        if !(length.is_finite() && length > 0.0) {
            return Err(ModalError::InvalidParameter("length"));
        }
        if modes == 0 {
            return Err(ModalError::InvalidParameter("modes"));
        }
        if !(dt.is_finite() && dt > 0.0) {
            return Err(ModalError::InvalidParameter("dt"));
        }
        let positive = |v: f64| v.is_finite() && v > 0.0;
        let vp = PlaneProperties::vertical(&section);
        let lp = PlaneProperties::lateral(&section);
        let tp = TorsionProperties::new(&section);
        for (ok, name) in [
            (positive(vp.mass_per_length), "mass_per_length"),
            (positive(vp.rotary_inertia), "iy"),
            (positive(lp.rotary_inertia), "iz"),
            (
                positive(vp.flexural_rigidity) && positive(lp.flexural_rigidity),
                "youngs_modulus",
            ),
            (positive(vp.shear_rigidity), "shear_area_z"),
            (positive(lp.shear_rigidity), "shear_area_y"),
            (positive(tp.polar_mass), "polar_mass"),
            (positive(tp.torsional_rigidity), "torsion_constant"),
        ] {
            if !ok {
                return Err(ModalError::InvalidParameter(name));
            }
        }
        let plane = |p: &PlaneProperties, k: f64| {
            let [m1, m2] = p.mode_mass();
            let kk = p.mode_stiffness(k);
            NewmarkMode::new(
                Matrix2::new(m1, 0.0, 0.0, m2),
                Matrix2::new(kk[0][0], kk[0][1], kk[1][0], kk[1][1]),
                dt,
            )
        };
        let mut vertical = Vec::with_capacity(modes);
        let mut lateral = Vec::with_capacity(modes);
        let mut torsion = Vec::with_capacity(modes);
        for n in 1..=modes {
            let k = wavenumber(length, n);
            let singular = ModalError::InvalidParameter("effective stiffness singular");
            vertical.push(plane(&vp, k).ok_or(singular.clone())?);
            lateral.push(plane(&lp, k).ok_or(singular.clone())?);
            torsion.push(
                NewmarkMode::new(
                    Matrix1::new(tp.polar_mass),
                    Matrix1::new(tp.mode_stiffness(k)),
                    dt,
                )
                .ok_or(singular)?,
            );
        }
        Ok(ModalGuideway {
            section,
            length,
            dt,
            vertical,
            lateral,
            torsion,
            committed: SpanState::zero(modes),
            trial: SpanState::zero(modes),
            forces: vec![[0.0; 3]; modes],
            bearings: [0.0; 4],
        })
    }

    /// The modal reference for a one-span [`Bridge`]; [`ModalError::SpanCount`] otherwise.
    ///
    /// ```
    /// use maglev_sim::physics::guideway::{BeamSection, Bridge, Guideway, PointLoad};
    /// use maglev_sim::physics::modal::ModalGuideway;
    ///
    /// // The §4.2 span (docs/model.md §9): 25 m, simply supported.
    /// let bridge = Bridge { section: BeamSection::paper_4_2(), spans: vec![25.0] };
    /// let mut g = ModalGuideway::from_bridge(&bridge, 40, 1e-5).unwrap();
    /// // One Newmark step with 36.79 kN pushing down at midspan, 1.5 m off the axis.
    /// let load = PointLoad { x: 12.5, ey: 1.5, ez: 0.0, fy: 0.0, fz: -36.79e3 };
    /// g.solve_step(&[load]);
    /// g.commit();
    /// assert!(g.section_at(12.5).z < 0.0);
    ///
    /// let two = Bridge { section: BeamSection::paper_4_2(), spans: vec![25.0, 25.0] };
    /// assert!(ModalGuideway::from_bridge(&two, 40, 1e-5).is_err());
    /// ```
    pub fn from_bridge(bridge: &Bridge, modes: usize, dt: f64) -> Result<Self, ModalError> {
        match bridge.spans.as_slice() {
            [length] => Self::new(bridge.section.clone(), *length, modes, dt),
            spans => Err(ModalError::SpanCount(spans.len())),
        }
    }

    /// Span length L (m).
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Number of series terms per field.
    pub fn modes(&self) -> usize {
        self.vertical.len()
    }

    /// The beam section.
    pub fn section(&self) -> &BeamSection {
        &self.section
    }

    /// Natural frequencies (rad/s) of every series term n = 1..=modes: both Timoshenko
    /// branches per bending plane and torsion. For cross-checking the FE model.
    pub fn natural_frequencies(&self) -> Vec<ModeFrequencies> {
        (1..=self.modes())
            .map(|n| natural_frequencies(&self.section, self.length, n))
            .collect()
    }

    /// Section rotations (θy, θz) of the trial state at `x`, with the FE's DOF signs
    /// (docs/model.md §5): θy = −φ_Y (≈ −∂w/∂x), θz = +φ_Z (≈ +∂v/∂x). Zero off the span.
    pub fn rotations_at(&self, x: f64) -> (f64, f64) {
        if !self.on_span(x) {
            return (0.0, 0.0);
        }
        let (mut ry, mut rz) = (0.0, 0.0);
        for (n, (_, c)) in harmonics(self.length, x, self.modes()).enumerate() {
            ry -= self.trial.vertical[n].d[1] * c;
            rz += self.trial.lateral[n].d[1] * c;
        }
        (ry, rz)
    }

    /// The accelerations of the bearings at the end of the next steps, `[z left, z right,
    /// y left, y right]` (m/s²): the series then holds the motion relative to the span's
    /// rigid-body motion between its bearings, driven by that motion's inertia (Eq. S5,
    /// [`bearing_force`]). The rigid-body motion itself is the caller's to add
    /// ([`super::ModalSpans`]).
    pub fn set_bearing_acceleration(&mut self, a: [f64; BEARINGS]) {
        self.bearings = a;
    }

    fn on_span(&self, x: f64) -> bool {
        (0.0..=self.length).contains(&x)
    }

    /// Project the loads on the series terms (the paper's e_i: only loads on the span count).
    fn project(&mut self, loads: &[PointLoad]) {
        let scale = 2.0 / self.length;
        self.forces.iter_mut().for_each(|f| *f = [0.0; 3]);
        for l in loads.iter().filter(|l| (0.0..=self.length).contains(&l.x)) {
            let torque = l.ey * l.fz - l.ez * l.fy;
            let (fz, fy, mx) = (scale * l.fz, scale * l.fy, scale * torque);
            for (f, (s, _)) in self
                .forces
                .iter_mut()
                .zip(harmonics(self.length, l.x, usize::MAX))
            {
                f[0] += fz * s;
                f[1] += fy * s;
                f[2] += mx * s;
            }
        }
        if self.bearings.iter().any(|&a| a != 0.0) {
            let [zl, zr, yl, yr] = self.bearings;
            let rho_a = self.section.mass_per_length;
            for (i, f) in self.forces.iter_mut().enumerate() {
                f[0] += bearing_force(i + 1, rho_a, zl, zr);
                f[1] += bearing_force(i + 1, rho_a, yl, yr);
            }
        }
    }
}

/// (sin(nπx/L), cos(nπx/L)) for n = 1, 2, …, `count`, by repeated rotation (one sin/cos
/// pair per call; the rounding error grows only linearly with n).
fn harmonics(length: f64, x: f64, count: usize) -> impl Iterator<Item = (f64, f64)> {
    let (s1, c1) = (core::f64::consts::PI * x / length).sin_cos();
    let mut sc = (0.0, 1.0);
    (0..count).map(move |_| {
        sc = (sc.0 * c1 + sc.1 * s1, sc.1 * c1 - sc.0 * s1);
        sc
    })
}

impl Guideway for ModalGuideway {
    fn time_step(&self) -> f64 {
        self.dt
    }

    fn solve_step(&mut self, loads: &[PointLoad]) {
        self.project(loads);
        let (c, t) = (&self.committed, &mut self.trial);
        for (n, f) in self.forces.iter().enumerate() {
            t.vertical[n] = self.vertical[n].step(&c.vertical[n], &Vector2::new(f[0], 0.0));
            t.lateral[n] = self.lateral[n].step(&c.lateral[n], &Vector2::new(f[1], 0.0));
            t.torsion[n] = self.torsion[n].step(&c.torsion[n], &Vector1::new(f[2]));
        }
    }

    fn motion_at(&self, x: f64, ey: f64, ez: f64) -> PointMotion {
        let s = self.section_at(x);
        PointMotion {
            y: s.y - s.rx * ez,
            z: s.z + s.rx * ey,
        }
    }

    fn section_at(&self, x: f64) -> SectionMotion {
        if !self.on_span(x) {
            return SectionMotion::default();
        }
        let mut m = SectionMotion::default();
        for (n, (s, _)) in harmonics(self.length, x, self.modes()).enumerate() {
            m.z += self.trial.vertical[n].d[0] * s;
            m.y += self.trial.lateral[n].d[0] * s;
            m.rx += self.trial.torsion[n].d[0] * s;
        }
        m
    }

    fn commit(&mut self) {
        self.committed.clone_from(&self.trial);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn span() -> ModalGuideway {
        ModalGuideway::new(BeamSection::paper_4_2(), 25.0, 12, 1e-3).unwrap()
    }

    fn load(x: f64) -> PointLoad {
        PointLoad {
            x,
            ey: 1.5,
            ez: 0.6,
            fy: 1e3,
            fz: -3e4,
        }
    }

    #[test]
    fn harmonics_match_direct_evaluation() {
        let (l, x) = (25.0, 7.3);
        for (i, (s, c)) in harmonics(l, x, 200).enumerate() {
            let a = (i + 1) as f64 * core::f64::consts::PI * x / l;
            assert!(
                (s - a.sin()).abs() < 1e-12 && (c - a.cos()).abs() < 1e-12,
                "n = {}",
                i + 1
            );
        }
    }

    /// Each solve_step restarts from the committed state: repeating it with other loads
    /// first must not change the result (the Newton–Raphson protocol of the trait).
    #[test]
    fn solve_step_restarts_from_committed_state() {
        let mut a = span();
        let mut b = span();
        for step in 0..5 {
            let x = 2.0 * step as f64 + 5.0;
            a.solve_step(&[load(x + 3.0)]);
            a.solve_step(&[load(x - 1.0), load(x)]);
            a.solve_step(&[load(x)]);
            b.solve_step(&[load(x)]);
            a.commit();
            b.commit();
        }
        for x in [3.0, 12.5, 20.0] {
            assert_eq!(a.section_at(x), b.section_at(x));
            assert_eq!(a.rotations_at(x), b.rotations_at(x));
        }
    }

    /// Loads off the span act on nothing, and the span reads zero outside [0, L].
    #[test]
    fn off_span_loads_and_points_are_ignored() {
        let mut g = span();
        g.solve_step(&[load(-0.5), load(25.5)]);
        assert_eq!(g.section_at(12.5), SectionMotion::default());
        g.solve_step(&[load(10.0)]);
        assert!(g.section_at(12.5).z < 0.0);
        assert_eq!(g.section_at(-1e-9), SectionMotion::default());
        assert_eq!(g.section_at(25.0 + 1e-9), SectionMotion::default());
        assert_eq!(g.motion_at(30.0, 1.5, 0.6), PointMotion::default());
    }

    #[test]
    fn bridge_must_have_one_span_and_parameters_are_checked() {
        let section = BeamSection::paper_4_2();
        let bridge = |spans: Vec<f64>| Bridge {
            section: section.clone(),
            spans,
        };
        assert_eq!(
            ModalGuideway::from_bridge(&bridge(vec![]), 10, 1e-3).unwrap_err(),
            ModalError::SpanCount(0)
        );
        assert_eq!(
            ModalGuideway::from_bridge(&bridge(vec![25.0, 25.0]), 10, 1e-3).unwrap_err(),
            ModalError::SpanCount(2)
        );
        assert!(ModalGuideway::from_bridge(&bridge(vec![25.0]), 10, 1e-3).is_ok());
        assert!(ModalGuideway::new(section.clone(), 25.0, 0, 1e-3).is_err());
        assert!(ModalGuideway::new(section.clone(), 25.0, 10, 0.0).is_err());
        assert!(ModalGuideway::new(section.clone(), -1.0, 10, 1e-3).is_err());
        let no_shear = BeamSection {
            shear_area_z: 0.0,
            ..section
        };
        assert_eq!(
            ModalGuideway::new(no_shear, 25.0, 10, 1e-3).unwrap_err(),
            ModalError::InvalidParameter("shear_area_z")
        );
    }
}
