//! The interface every guideway model offers to the coupling loop (docs/model.md §7).
//!
//! Why an interface: the vehicle and the guideway share no stiffness or mass (the magnet force
//! is their only link), so the global Newmark system of the paper is block-diagonal between
//! them and each block can be advanced on its own within a step. The Newton–Raphson loop on
//! the wheel forces then couples them. The FE model (`fe`) and the modal Timoshenko
//! reference (`modal`) both implement [`Guideway`], so the same coupling, vehicles and
//! scenarios drive either.
//!
//! Axes and signs (docs/model.md §0): X along the track, Z up, displacements positive along the
//! axes. SI units throughout.

/// Properties of a straight prismatic beam, SI units.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct BeamSection {
    /// Young's modulus E (Pa).
    #[serde(rename = "youngs_modulus_Pa")]
    pub youngs_modulus: f64,
    /// Shear modulus G (Pa).
    #[serde(rename = "shear_modulus_Pa")]
    pub shear_modulus: f64,
    /// Cross-section area A (m²).
    #[serde(rename = "area_m2")]
    pub area: f64,
    /// Shear area for shear in Y (m²).
    #[serde(rename = "shear_area_y_m2")]
    pub shear_area_y: f64,
    /// Shear area for shear in Z (m²).
    #[serde(rename = "shear_area_z_m2")]
    pub shear_area_z: f64,
    /// Second moment about Y, Iy (m⁴): bending in the X–Z plane (vertical).
    #[serde(rename = "iy_m4")]
    pub iy: f64,
    /// Second moment about Z, Iz (m⁴): bending in the X–Y plane (lateral).
    #[serde(rename = "iz_m4")]
    pub iz: f64,
    /// Torsion constant J (m⁴).
    #[serde(rename = "torsion_constant_m4")]
    pub torsion_constant: f64,
    /// Mass per unit length m (kg/m).
    #[serde(rename = "mass_kg_per_m")]
    pub mass_per_length: f64,
    /// Torsional mass moment of inertia per unit length (kg·m). `None`: ρ·(Iy + Iz).
    #[serde(rename = "polar_mass_kg_m2_per_m")]
    pub polar_mass: Option<f64>,
}

impl BeamSection {
    /// The §4.2 beam of the paper (docs/model.md §9), converted from kN/m², t/m to SI.
    pub fn paper_4_2() -> Self {
        BeamSection {
            youngs_modulus: 3.6e7 * 1e3,
            shear_modulus: 1.6e7 * 1e3,
            area: 1.5,
            shear_area_y: 0.7,
            shear_area_z: 0.7,
            iy: 0.6,
            iz: 0.6,
            torsion_constant: 0.2,
            mass_per_length: 3.5e3,
            polar_mass: None,
        }
    }

    /// Density ρ = m / A (kg/m³).
    pub fn density(&self) -> f64 {
        self.mass_per_length / self.area
    }

    /// Torsional mass per length: the given value, else ρ·(Iy + Iz).
    pub fn polar_mass_per_length(&self) -> f64 {
        self.polar_mass
            .unwrap_or(self.density() * (self.iy + self.iz))
    }
}

/// A constant of a [`BeamSection`] that [`BeamSection::validate`] checks (the optional polar
/// mass aside), in the struct's order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SectionField {
    YoungsModulus,
    ShearModulus,
    Area,
    ShearAreaY,
    ShearAreaZ,
    Iy,
    Iz,
    TorsionConstant,
    MassPerLength,
}

impl SectionField {
    pub const ALL: [Self; 9] = [
        Self::YoungsModulus,
        Self::ShearModulus,
        Self::Area,
        Self::ShearAreaY,
        Self::ShearAreaZ,
        Self::Iy,
        Self::Iz,
        Self::TorsionConstant,
        Self::MassPerLength,
    ];

    /// The field's key in summary.json (its SI name).
    pub fn name(self) -> &'static str {
        match self {
            Self::YoungsModulus => "youngs_modulus_Pa",
            Self::ShearModulus => "shear_modulus_Pa",
            Self::Area => "area_m2",
            Self::ShearAreaY => "shear_area_y_m2",
            Self::ShearAreaZ => "shear_area_z_m2",
            Self::Iy => "iy_m4",
            Self::Iz => "iz_m4",
            Self::TorsionConstant => "torsion_constant_m4",
            Self::MassPerLength => "mass_kg_per_m",
        }
    }
}

/// The constant [`BeamSection::validate`] refuses, and its value (SI).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SectionFault {
    pub field: SectionField,
    pub value: f64,
}

impl SectionFault {
    /// The one-line error under the caller's name for the field, `key`, showing the value as
    /// the caller was given it, `given` (a scenario's kN/m², t/m).
    pub fn error(&self, key: impl Into<String>, given: f64) -> crate::Error {
        super::check::not_positive(key, given)
    }
}

impl BeamSection {
    /// A section from its constants in SI, `value(field)` each, without a polar mass.
    pub fn from_fields(value: impl Fn(SectionField) -> f64) -> Self {
        use SectionField::*;
        BeamSection {
            youngs_modulus: value(YoungsModulus),
            shear_modulus: value(ShearModulus),
            area: value(Area),
            shear_area_y: value(ShearAreaY),
            shear_area_z: value(ShearAreaZ),
            iy: value(Iy),
            iz: value(Iz),
            torsion_constant: value(TorsionConstant),
            mass_per_length: value(MassPerLength),
            polar_mass: None,
        }
    }

    /// The constant `field` (SI).
    pub fn get(&self, field: SectionField) -> f64 {
        match field {
            SectionField::YoungsModulus => self.youngs_modulus,
            SectionField::ShearModulus => self.shear_modulus,
            SectionField::Area => self.area,
            SectionField::ShearAreaY => self.shear_area_y,
            SectionField::ShearAreaZ => self.shear_area_z,
            SectionField::Iy => self.iy,
            SectionField::Iz => self.iz,
            SectionField::TorsionConstant => self.torsion_constant,
            SectionField::MassPerLength => self.mass_per_length,
        }
    }

    /// The rule of a beam section, the one place it is written (a scenario's `[bridge]` and
    /// `[bridge.pier]` and [`crate::physics::fe::viaduct::ViaductSpec::validate`] call it):
    /// every constant a positive finite number, else the stiffness or mass matrix of its
    /// elements is singular or meaningless. `Err` is the first field (in
    /// [`SectionField::ALL`]'s order) that is not; each caller names it its own way.
    pub fn validate(&self) -> Result<(), SectionFault> {
        for field in SectionField::ALL {
            let value = self.get(field);
            if !super::check::is_positive(value) {
                return Err(SectionFault { field, value });
            }
        }
        Ok(())
    }
}

/// A line of simply supported spans along X starting at x = 0. Outside `[0, total length]`
/// the guideway is rigid (docs/model.md §9).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Bridge {
    #[serde(flatten)]
    pub section: BeamSection,
    /// Span lengths (m), consecutive, each simply supported at both ends.
    #[serde(rename = "spans_m")]
    pub spans: Vec<f64>,
}

impl Bridge {
    pub fn total_length(&self) -> f64 {
        self.spans.iter().sum()
    }
}

/// A force applied to the guideway at a point offset from the beam axis by a rigid link
/// (docs/model.md §5). Forces are those acting *on the guideway* (a magnet pulling itself up pulls
/// the rail down: `fz = -G`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PointLoad {
    /// Position along the track (m).
    pub x: f64,
    /// Offset of the point from the beam axis in Y (m).
    pub ey: f64,
    /// Offset of the point from the beam axis in Z (m).
    pub ez: f64,
    /// Force in Y (N).
    pub fy: f64,
    /// Force in Z (N).
    pub fz: f64,
}

/// Displacement of a point of the guideway (rigidly linked to the axis), SI.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PointMotion {
    pub y: f64,
    pub z: f64,
}

/// Displacement of the beam axis at a section.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SectionMotion {
    pub y: f64,
    pub z: f64,
    /// Rotation about X (rad).
    pub rx: f64,
}

/// Motion of a pier's base node (the footing), on the committed state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BaseMotion {
    /// Displacement, velocity, acceleration in Z (m, m/s, m/s²).
    pub z: f64,
    pub vz: f64,
    pub az: f64,
    /// Displacement and acceleration in Y.
    pub y: f64,
    pub ay: f64,
}

/// A guideway advanced by Newmark (γ = ½, β = ¼) with a fixed step.
///
/// Protocol per time step: call [`Guideway::solve_step`] once per Newton–Raphson iteration with
/// the current estimate of the loads at `t + dt` (each call restarts from the committed state
/// at `t`), query the trial state with [`Guideway::motion_at`] / [`Guideway::section_at`], and
/// finally [`Guideway::commit`] it.
pub trait Guideway {
    /// The fixed time step (s).
    fn time_step(&self) -> f64;
    /// Solve the step `t -> t + dt` for the given loads at `t + dt`, from the committed state.
    fn solve_step(&mut self, loads: &[PointLoad]);
    /// Displacement of a point (x, ey, ez) on the trial state; zero off the bridge.
    fn motion_at(&self, x: f64, ey: f64, ez: f64) -> PointMotion;
    /// Axis displacement at `x` on the trial state; zero off the bridge.
    fn section_at(&self, x: f64) -> SectionMotion;
    /// Accept the trial state as the state at `t + dt`.
    fn commit(&mut self);
    /// Motion of pier `k`'s base (1-based, pier 1 at x = 0) on the committed state, for the
    /// `pier{K}.base` probes; `None` for a guideway without piers (the default) or no such
    /// pier. The coupling loop never calls it, so it needs no knowledge of the guideway type.
    fn pier_base(&self, _k: usize) -> Option<BaseMotion> {
        None
    }
}

/// A guideway that never moves: `z_g = y_g = θ = 0` everywhere (`run.model = "rigid"`). The
/// vehicle and its magnets alone over the irregular rail, the first thing a control engineer
/// runs; the irregularity is still applied.
#[derive(Clone, Debug)]
pub struct RigidGuideway {
    dt: f64,
}

impl RigidGuideway {
    pub fn new(dt: f64) -> Self {
        RigidGuideway { dt }
    }
}

impl Guideway for RigidGuideway {
    fn time_step(&self) -> f64 {
        self.dt
    }
    fn solve_step(&mut self, _loads: &[PointLoad]) {}
    fn motion_at(&self, _x: f64, _ey: f64, _ez: f64) -> PointMotion {
        PointMotion::default()
    }
    fn section_at(&self, _x: f64) -> SectionMotion {
        SectionMotion::default()
    }
    fn commit(&mut self) {}
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each field's name is the key summary.json gives it (the serde renames above), and its
    /// constant is the one stored there.
    #[test]
    fn section_fields_are_the_summary_keys() {
        let s = BeamSection::paper_4_2();
        let json = serde_json::to_value(&s).unwrap();
        for f in SectionField::ALL {
            assert_eq!(json[f.name()].as_f64(), Some(s.get(f)), "{f:?}");
        }
        assert_eq!(BeamSection::from_fields(|f| s.get(f)), s);
    }

    /// Every constant is held to the rule: zero, a negative, NaN or infinity in any one field
    /// is refused naming that field; the §4.2 section passes.
    #[test]
    fn validate_refuses_each_constant_that_is_not_positive_and_finite() {
        let s = BeamSection::paper_4_2();
        assert_eq!(s.validate(), Ok(()));
        for bad in SectionField::ALL {
            for v in [0.0, -1.0, f64::NAN, f64::INFINITY] {
                let t = BeamSection::from_fields(|f| if f == bad { v } else { s.get(f) });
                let fault = t.validate().unwrap_err();
                assert_eq!(fault.field, bad);
                assert!(fault.value.is_nan() == v.is_nan() && (v.is_nan() || fault.value == v));
            }
        }
    }
}
