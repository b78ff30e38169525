//! `[bridge]` in SI: the spans and the girders' section, the one conversion of a beam
//! section's keys (the piers' too, [`BeamSectionKeys::resolve`]), the spans' Rayleigh damping
//! and the size checks of the FE spans.

use super::checks::{non_negative, positive, within};
use crate::input::scenario::{BeamSectionKeys, BridgeSection, DampingSection};
use crate::physics::fe::newmark::Rayleigh;
use crate::physics::guideway::{BeamSection, Bridge, SectionField};
use crate::{Error, Result};

/// The largest estimated condition number of an FE span's Newmark matrix
/// (see [`check_fe_size`]).
pub const MAX_CONDITION: f64 = 1e10;

/// The most FE DOFs a case may have: about 6 GB of banded model at ~70 doubles per DOF,
/// and far beyond any span converged at 16 elements.
pub const MAX_FE_DOFS: f64 = 1e7;

impl BeamSectionKeys {
    /// Field `f`'s key, its value as given (in the key's unit) and the factor from that unit
    /// to SI: the one conversion of a beam section's keys.
    fn given(&self, f: SectionField) -> (&'static str, f64, f64) {
        match f {
            SectionField::YoungsModulus => (
                "youngs_modulus_kN_per_m2",
                self.youngs_modulus_kN_per_m2,
                1e3,
            ),
            SectionField::ShearModulus => {
                ("shear_modulus_kN_per_m2", self.shear_modulus_kN_per_m2, 1e3)
            }
            SectionField::Area => ("area_m2", self.area_m2, 1.0),
            SectionField::ShearAreaY => ("shear_area_y_m2", self.shear_area_y_m2, 1.0),
            SectionField::ShearAreaZ => ("shear_area_z_m2", self.shear_area_z_m2, 1.0),
            SectionField::Iy => ("iy_m4", self.iy_m4, 1.0),
            SectionField::Iz => ("iz_m4", self.iz_m4, 1.0),
            SectionField::TorsionConstant => ("torsion_constant_m4", self.torsion_constant_m4, 1.0),
            SectionField::MassPerLength => ("mass_t_per_m", self.mass_t_per_m, 1e3),
        }
    }

    /// The section in SI, every key named under `prefix` (`bridge`, `bridge.pier`): checked
    /// by the section's own rule ([`BeamSection::validate`], its sign), then each key for its
    /// plausible range ([`within`]) in its own unit: a value that passes the sign check but
    /// leaves the element's stiffness singular to f64 or the Newmark matrix without digits is
    /// refused by its key. The ranges lie within [`super::MAX_MAGNITUDE`]. `polar_mass` is
    /// `None` (the girders' own key sets it).
    pub fn resolve(&self, prefix: &str) -> Result<BeamSection> {
        let key = |k: &str| format!("{prefix}.{k}");
        let section = BeamSection::from_fields(|f| {
            let (_, v, to_si) = self.given(f);
            v * to_si
        });
        section.validate().map_err(|fault| {
            let (k, v, _) = self.given(fault.field);
            fault.error(key(k), v)
        })?;
        let range = |k: &str, v: f64, lo: f64, hi: f64, why: &str| within(&key(k), v, lo, hi, why);
        let e = self.youngs_modulus_kN_per_m2;
        range(
            "youngs_modulus_kN_per_m2",
            e,
            1e3,
            1e9,
            "kN/m²: soft rubber's 1 MPa to 1000 GPa, stiffer than any steel",
        )?;
        range(
            "shear_modulus_kN_per_m2",
            self.shear_modulus_kN_per_m2,
            e * 1e-3,
            e,
            "youngs_modulus/1000 to youngs_modulus: an isotropic solid has E/3 ≤ G ≤ E/2",
        )?;
        let area = self.area_m2;
        range(
            "area_m2",
            area,
            1e-4,
            1e3,
            "m²: a hundredth of a rail's section to a 1000 m² deck",
        )?;
        for (k, v) in [
            ("shear_area_y_m2", self.shear_area_y_m2),
            ("shear_area_z_m2", self.shear_area_z_m2),
        ] {
            let why = "area_m2/1000 to area_m2: a shear area is a part of the section";
            range(k, v, area * 1e-3, area, why)?;
        }
        for (k, v) in [
            ("iy_m4", self.iy_m4),
            ("iz_m4", self.iz_m4),
            ("torsion_constant_m4", self.torsion_constant_m4),
        ] {
            let why =
                "m⁴: a hundredth of a rail's 3e-5 m⁴ to a hundred times the largest box girder's";
            range(k, v, 1e-8, 1e4, why)?;
        }
        range(
            "mass_t_per_m",
            self.mass_t_per_m,
            1e-2,
            1e3,
            "t/m: 10 kg/m, lighter than any rail, to 1000 t/m; lighter girders leave the \
             Newmark matrix of the FE spans without digits",
        )?;
        Ok(section)
    }
}

/// The spans and the girders' section in SI.
pub(super) fn bridge(b: &BridgeSection) -> Result<Bridge> {
    if b.spans_m.is_empty() {
        return Err(Error::invalid(
            "bridge.spans_m",
            "must list at least one span",
        ));
    }
    for (i, &l) in b.spans_m.iter().enumerate() {
        positive(&format!("bridge.spans_m[{i}]"), l)?;
    }
    let polar_mass = b
        .polar_mass_t_m2_per_m
        .map(|v| positive("bridge.polar_mass_t_m2_per_m", v).map(|v| v * 1e3))
        .transpose()?;
    Ok(Bridge {
        section: BeamSection {
            polar_mass,
            ..b.section.resolve("bridge")?
        },
        spans: b.spans_m.clone(),
    })
}

/// Rayleigh coefficients with damping ratio `ratio` at `f1_Hz` and `f2_Hz`:
/// `α = 2ζ·ω1·ω2/(ω1 + ω2)`, `β = 2ζ/(ω1 + ω2)` (ζ(ω) = α/(2ω) + β·ω/2).
pub(super) fn rayleigh(d: &DampingSection) -> Result<Rayleigh> {
    let ratio = non_negative("bridge.damping.ratio", d.ratio)?;
    if ratio >= 1.0 {
        return Err(Error::invalid(
            "bridge.damping.ratio",
            format!("must be below 1 (critical damping), got {ratio}"),
        ));
    }
    let w1 = 2.0 * std::f64::consts::PI * positive("bridge.damping.f1_Hz", d.f1_Hz)?;
    let w2 = 2.0 * std::f64::consts::PI * positive("bridge.damping.f2_Hz", d.f2_Hz)?;
    if w2 < w1 {
        return Err(Error::invalid(
            "bridge.damping.f2_Hz",
            format!("must be at least f1_Hz = {}, got {}", d.f1_Hz, d.f2_Hz),
        ));
    }
    Ok(Rayleigh {
        alpha: 2.0 * ratio * w1 * w2 / (w1 + w2),
        beta: 2.0 * ratio / (w1 + w2),
    })
}

/// Refuses FE discretisations whose Newmark matrix cannot be solved to useful precision or
/// that exceed the memory limit.
///
/// Condition estimate of K + (4/Δt²)·M per span: its largest eigenvalue is at most about the
/// stiffest element term k_max = max(E·A/l, 12·E·I/l³, G·A_s/l) (l the element length), its
/// smallest at least the nodal mass term 4·m·l/Δt². Their ratio, plus one, bounds the digits a
/// solve loses; above [`MAX_CONDITION`] fewer than six of the sixteen digits of f64 survive.
/// Memory: [`MAX_FE_DOFS`] DOFs (the banded model holds about 70 doubles per DOF).
pub fn check_fe_size(b: &Bridge, elements: usize, dt: f64) -> Result<()> {
    let s = &b.section;
    let n = elements as f64;
    let dofs = 6.0 * (n + 1.0) * b.spans.len() as f64;
    if dofs > MAX_FE_DOFS {
        return Err(Error::invalid(
            "run.elements_per_span",
            format!(
                "{n} elements over {} span(s) is {dofs:.3e} FE DOFs, above the limit of {MAX_FE_DOFS:.0e}",
                b.spans.len()
            ),
        ));
    }
    for (i, &span) in b.spans.iter().enumerate() {
        let l = span / n;
        let k_max = (s.youngs_modulus * s.area / l)
            .max(12.0 * s.youngs_modulus * s.iy.max(s.iz) / l.powi(3))
            .max(s.shear_modulus * s.shear_area_y.max(s.shear_area_z) / l);
        let m_min = 4.0 * s.mass_per_length * l / (dt * dt);
        let cond = 1.0 + k_max / m_min;
        if cond > MAX_CONDITION {
            return Err(Error::invalid(
                "run.elements_per_span",
                format!(
                    "{n} elements: span {} ({span} m) has {l:.3e} m elements whose Newmark matrix has an estimated condition number {cond:.1e}, above the limit of {MAX_CONDITION:.0e} (fewer than 6 significant digits would survive); use fewer elements or a larger run.dt_s",
                    i + 1
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::Case;
    use crate::physics::guideway::BeamSection;

    /// The file's kN/m² and t/m are the hand-converted SI section of docs/model.md §9.
    #[test]
    fn the_girder_section_is_converted_to_si() {
        let c = Case::load("paper-4.2", &[]).unwrap();
        assert_eq!(c.bridge.section, BeamSection::paper_4_2());
        assert_eq!(c.bridge.spans, vec![25.0]);
    }

    /// The girders' and the piers' keys go through the one conversion: the section's sign
    /// rule (`BeamSection::validate`) and each plausible range are checked under either
    /// prefix, with the key's own name, unit and given value in the error.
    #[test]
    fn girder_and_pier_keys_are_checked_alike() {
        for prefix in ["bridge", "bridge.pier"] {
            for (key, value, says) in [
                (
                    "shear_modulus_kN_per_m2",
                    "1.0",
                    "youngs_modulus/1000 to youngs_modulus",
                ),
                (
                    "shear_area_y_m2",
                    "1000.0",
                    "a shear area is a part of the section",
                ),
                ("iz_m4", "1e-9", "m⁴"),
                ("mass_t_per_m", "1e-3", "t/m"),
                ("youngs_modulus_kN_per_m2", "-1.0", "positive"),
                ("mass_t_per_m", "nan", "positive finite number, got NaN"),
                // Above MAX_MAGNITUDE: refused by the key's range, in its unit.
                ("youngs_modulus_kN_per_m2", "2e9", "kN/m²"),
            ] {
                let set = format!("{prefix}.{key}={value}");
                let e = Case::load("paper-5", std::slice::from_ref(&set))
                    .unwrap_err()
                    .to_string();
                assert!(
                    e.starts_with(&format!("{prefix}.{key}: must be")) && e.contains(says),
                    "{set}: {e}"
                );
            }
        }
    }
}
