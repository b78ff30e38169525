//! The viaduct of `bridge.kind = "viaduct"` in SI (docs/viaduct.md): the bearings, the piers
//! (their section through the girders' conversion, [`BeamSectionKeys::resolve`]), the
//! footings on `[soil]`, and the ground receivers of `[ground]` (docs/ground.md).
//!
//! [`BeamSectionKeys::resolve`]: crate::input::scenario::BeamSectionKeys::resolve

use super::checks::{bounded, finite, non_negative, positive, positive_within, within};
use crate::ground::green::{MAX_DAMPING, MIN_DAMPING};
use crate::input::scenario::{BridgeKind, BridgeSection, GroundSection, SoilSection};
use crate::input::support::SupportSection;
use crate::physics::fe::soil::Soil;
use crate::physics::fe::viaduct::{BearingSpec, FoundationSpec, PierSpec, ViaductSpec};
use crate::physics::guideway::Bridge;
use crate::physics::seismic::support::SupportMotion;
use crate::{Error, Result};

/// The most elements a pier may have. The viaduct's set-up grows faster than linearly in
/// them (measured on paper-5: 50 elements 0.19 GB and 0.7 s, 100: 0.54 GB and 3.4 s, 200:
/// 1.2 GB and 15 s; 1000 asked for 14 GB); 4 already give the pier's first modes
/// (docs/viaduct.md).
pub const MAX_PIER_ELEMENTS: usize = 100;

/// The viaduct of `bridge.kind = "viaduct"` in SI: the girders of `girders`, on the
/// bearings, piers, footings and soil of the sub-tables.
pub(super) fn viaduct(
    b: &BridgeSection,
    girders: &Bridge,
    elements: usize,
    soil: Option<&Soil>,
) -> Result<Option<ViaductSpec>> {
    if b.kind == BridgeKind::Spans {
        for (name, given) in [
            ("bearings", b.bearings.is_some()),
            ("pier", b.pier.is_some()),
            ("footing", b.footing.is_some()),
        ] {
            if given {
                return Err(Error::invalid(
                    format!("bridge.{name}"),
                    "only a viaduct has it (set bridge.kind = \"viaduct\")",
                ));
            }
        }
        if soil.is_some() {
            return Err(Error::invalid(
                "soil",
                "only a viaduct stands on the soil (set bridge.kind = \"viaduct\")",
            ));
        }
        return Ok(None);
    }
    let need =
        |name: &str| Error::invalid(format!("bridge.{name}"), "a viaduct needs this section");
    let span = girders.spans[0];
    if let Some(i) = girders.spans.iter().position(|&l| l != span) {
        return Err(Error::invalid(
            format!("bridge.spans_m[{i}]"),
            format!(
                "a viaduct's spans are equal ({span} m), got {}",
                girders.spans[i]
            ),
        ));
    }
    let kilo = |key: &str, v: f64| positive(key, v).map(|v| v * 1e3);
    let be = b.bearings.as_ref().ok_or_else(|| need("bearings"))?;
    // Below 1 kN/m a bearing holds nothing (the span's weight would sink it by kilometres) and
    // the viaduct's stiffness is singular to f64; elastomeric and pot bearings are 1e5–1e7.
    let bearing = |key: &str, v: f64| {
        positive_within(key, v, 1.0, 1e9, "kN/m: 1 kN/m holds no span").map(|v| v * 1e3)
    };
    let bearings = BearingSpec {
        vertical: bearing("bridge.bearings.vertical_kN_per_m", be.vertical_kN_per_m)?,
        spacing: positive_within(
            "bridge.bearings.spacing_m",
            be.spacing_m,
            0.1,
            100.0,
            "m: the two bearings of an end stand under the girder",
        )?,
        lateral: bearing("bridge.bearings.lateral_kN_per_m", be.lateral_kN_per_m)?,
        longitudinal: bearing(
            "bridge.bearings.longitudinal_kN_per_m",
            be.longitudinal_kN_per_m,
        )?,
        drop: within(
            "bridge.bearings.drop_m",
            non_negative("bridge.bearings.drop_m", be.drop_m)?,
            0.0,
            20.0,
            "m: the girder's centroid lies within its own depth above the bearings",
        )?,
    };
    let p = b.pier.as_ref().ok_or_else(|| need("pier"))?;
    let pier = PierSpec {
        section: p.section.resolve("bridge.pier")?,
        height: positive_within(
            "bridge.pier.height_m",
            p.height_m,
            0.5,
            300.0,
            "m: a plinth to the tallest viaduct piers (under 250 m)",
        )?,
        elements: bounded("bridge.pier.elements", p.elements, 1, MAX_PIER_ELEMENTS)?,
        cap_mass: non_negative("bridge.pier.cap_mass_t", p.cap_mass_t)? * 1e3,
    };
    let soil = soil.ok_or_else(|| Error::invalid("soil", "a viaduct needs this section"))?;
    let f = b.footing.as_ref().ok_or_else(|| need("footing"))?;
    let foundation = FoundationSpec::footing(
        soil,
        footing_size("bridge.footing.along_x_m", f.along_x_m)?,
        footing_size("bridge.footing.across_y_m", f.across_y_m)?,
        positive("bridge.footing.thickness_m", f.thickness_m)?,
        kilo("bridge.footing.density_t_per_m3", f.density_t_per_m3)?,
    )?;
    let spec = ViaductSpec {
        spans: girders.spans.len(),
        span_length: span,
        girder: girders.section.clone(),
        elements_per_span: elements,
        bearings,
        pier,
        foundation,
        damping: None,
    };
    spec.validate()?;
    Ok(Some(spec))
}

/// A footing's plan dimension (m): at least 0.1 m (a smaller one has no stiffness in f64) and at
/// most 100 m.
fn footing_size(key: &str, v: f64) -> Result<f64> {
    positive_within(key, v, 0.1, 100.0, "m: a post's base to a raft")
}

/// The largest ground-record file `[support]` reads (16 MiB: about 400 000 rows, over half an
/// hour at 5 ms).
pub const MAX_RECORD_BYTES: u64 = 16 << 20;

/// The ground motion and settlements of `[support]` at the viaduct's `spans + 1` piers, a span
/// length apart; record files are read relative to the working directory.
pub(super) fn support(s: &SupportSection, v: &ViaductSpec) -> Result<SupportMotion> {
    s.to_motion(v.spans + 1, v.span_length, record_text)
}

/// The ground motion and settlements of `[support]` at the `spans + 1` supports of simply
/// supported spans on rigid supports (support k at the start of span k, the last at the end
/// of the last span), counted and keyed as a viaduct's piers.
pub(super) fn span_support(s: &SupportSection, bridge: &Bridge) -> Result<SupportMotion> {
    let x: Vec<f64> = std::iter::once(0.0)
        .chain(bridge.spans.iter().scan(0.0, |x, l| {
            *x += l;
            Some(*x)
        }))
        .collect();
    s.to_motion_at(&x, record_text)
}

/// A record file's text: a regular file of at most [`MAX_RECORD_BYTES`] (a device or a pipe
/// named in a scenario could be endless or block the run before it starts).
fn record_text(path: &str) -> Result<String> {
    let p = std::path::Path::new(path);
    let meta = std::fs::metadata(p).map_err(|e| Error::io(p, e))?;
    if !meta.is_file() {
        return Err(Error::invalid(
            "support.record",
            format!("{path:?} is not a regular file"),
        ));
    }
    if meta.len() > MAX_RECORD_BYTES {
        return Err(Error::invalid(
            "support.record",
            format!(
                "{path:?} has {} bytes, more than the {} MiB a record may have",
                meta.len(),
                MAX_RECORD_BYTES >> 20
            ),
        ));
    }
    crate::input::read_text(p)
}

/// A soil density given in t/m³ (as `[soil]` and `ground green --rho-t-per-m3` take it),
/// checked and in kg/m³; `key` names it in the error. The one unit and range of soil density
/// at every edge.
pub fn soil_density(key: &str, t_per_m3: f64) -> Result<f64> {
    Ok(positive_within(
        key,
        t_per_m3,
        0.5,
        5.0,
        "t/m³: peat (about 1) to dense rock (about 3)",
    )? * 1e3)
}

/// `[soil]` in SI, checked: one soil for the footings and the ground.
pub(super) fn soil(s: &SoilSection) -> Result<Soil> {
    let poisson = s.poisson;
    if !(0.0..0.5).contains(&poisson) {
        return Err(Error::invalid(
            "soil.poisson",
            format!("must be in [0, 0.5), got {poisson}"),
        ));
    }
    let damping = match s.damping_ratio {
        None => 0.0,
        Some(d) if (MIN_DAMPING..=MAX_DAMPING).contains(&d) => d,
        Some(d) => {
            return Err(Error::invalid(
                "soil.damping_ratio",
                format!("must be in [{MIN_DAMPING}, {MAX_DAMPING}], got {d}"),
            ))
        }
    };
    Ok(Soil {
        shear_wave_velocity: positive_within(
            "soil.shear_wave_velocity_m_per_s",
            s.shear_wave_velocity_m_per_s,
            10.0,
            5000.0,
            "m/s: peat (about 30) to hard rock (about 3500)",
        )?,
        density: soil_density("soil.density_t_per_m3", s.density_t_per_m3)?,
        poisson,
        damping,
    })
}

/// The most ground receivers a case may have.
pub const MAX_RECEIVERS: usize = 1000;

/// `[ground]`'s receivers as points `[x, y]` (m): given, or at `distances_m` across the line
/// at pier `pier` (x of the pier). Each must lie outside every footing's circumscribed
/// circle (the point load stands for the footing: inside it the model says nothing), and the
/// soil needs its damping ratio (the Green's function needs ξ > 0).
pub(super) fn ground(
    g: &GroundSection,
    v: &ViaductSpec,
    soil: &Soil,
    b: &BridgeSection,
) -> Result<Vec<[f64; 2]>> {
    if soil.damping == 0.0 {
        return Err(Error::invalid(
            "soil.damping_ratio",
            format!("[ground] needs the soil's hysteretic damping ratio, in [{MIN_DAMPING}, {MAX_DAMPING}]"),
        ));
    }
    let (points, key): (Vec<[f64; 2]>, &str) = match (&g.receivers, &g.distances_m, g.pier) {
        (Some(r), None, None) => {
            for (i, p) in r.iter().enumerate() {
                finite(&format!("ground.receivers[{i}][0]"), p[0])?;
                finite(&format!("ground.receivers[{i}][1]"), p[1])?;
            }
            (r.clone(), "ground.receivers")
        }
        (None, Some(d), Some(pier)) => {
            let pier = bounded("ground.pier", pier, 1, v.spans + 1)?;
            let x = (pier - 1) as f64 * v.span_length;
            let mut pts = Vec::with_capacity(d.len());
            for (i, &y) in d.iter().enumerate() {
                pts.push([x, finite(&format!("ground.distances_m[{i}]"), y)?]);
            }
            (pts, "ground.distances_m")
        }
        _ => {
            return Err(Error::invalid(
                "ground",
                "give either `receivers` ([x, y] points) or `distances_m` with `pier`",
            ))
        }
    };
    bounded(key, points.len(), 1, MAX_RECEIVERS)?;
    let radius = b
        .footing
        .as_ref()
        .map_or(0.0, |f| f.along_x_m.hypot(f.across_y_m) / 2.0);
    for (i, p) in points.iter().enumerate() {
        for k in 0..=v.spans {
            let r = (p[0] - k as f64 * v.span_length).hypot(p[1]);
            if r < radius {
                return Err(Error::invalid(
                    format!("{key}[{i}]"),
                    format!(
                        "lies {r:.3} m from pier {}, inside its footing's circumscribed circle (radius {radius:.3} m)",
                        k + 1
                    ),
                ));
            }
        }
    }
    Ok(points)
}

// The ground's recorder for a case: here, where the case is known, so that `ground` never
// names the input layer.
impl crate::ground::receivers::BaseForces {
    /// The recorder a run of `case` needs: every pier's base force when the case has a
    /// viaduct and ground receivers (`maglev run`, the Python binding), else `None`.
    pub fn for_case(case: &crate::input::case::Case) -> Option<Self> {
        let v = case.viaduct.as_ref()?;
        case.ground.as_ref()?;
        let f = &v.foundation;
        Some(Self::new(v.spans + 1, f.stiffness[2], f.damping[2]))
    }
}

#[cfg(test)]
mod tests {
    use super::super::Case;

    /// A record that is a device (endless) or a directory is refused in one line naming
    /// `support.record`, before anything is read.
    #[test]
    fn a_record_that_is_no_regular_file_is_refused() {
        for path in ["/dev/zero", "/"] {
            let e = Case::load("paper-5", &[format!("support.record={path:?}")])
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("support.record") && e.contains("not a regular file"),
                "{e}"
            );
        }
    }

    /// The bundled paper-5 scenario is `fe::paper5_viaduct()` in the file's units.
    #[test]
    fn paper5_scenario_is_the_documented_viaduct() {
        let c = Case::load("paper-5", &[]).unwrap();
        let v = c.viaduct.clone().unwrap();
        let r = crate::physics::fe::paper5_viaduct();
        let close = |a: f64, b: f64, what: &str| {
            assert!(
                (a - b).abs() <= 1e-12 * b.abs().max(1e-300),
                "{what}: {a} vs {b}"
            )
        };
        assert_eq!((v.spans, v.elements_per_span, v.pier.elements), (35, 16, 4));
        close(v.span_length, r.span_length, "span");
        let sections = [(&v.girder, &r.girder), (&v.pier.section, &r.pier.section)];
        for (a, b) in sections {
            close(a.youngs_modulus, b.youngs_modulus, "E");
            close(a.shear_modulus, b.shear_modulus, "G");
            close(a.area, b.area, "A");
            close(a.shear_area_y, b.shear_area_y, "Asy");
            close(a.shear_area_z, b.shear_area_z, "Asz");
            close(a.iy, b.iy, "Iy");
            close(a.iz, b.iz, "Iz");
            close(a.torsion_constant, b.torsion_constant, "J");
            close(a.mass_per_length, b.mass_per_length, "m");
            assert_eq!(a.polar_mass.is_some(), b.polar_mass.is_some());
            if let (Some(x), Some(y)) = (a.polar_mass, b.polar_mass) {
                close(x, y, "polar mass");
            }
        }
        let (a, b) = (&v.bearings, &r.bearings);
        for (x, y) in [
            (a.vertical, b.vertical),
            (a.spacing, b.spacing),
            (a.lateral, b.lateral),
            (a.longitudinal, b.longitudinal),
            (a.drop, b.drop),
            (v.pier.height, r.pier.height),
            (v.pier.cap_mass, r.pier.cap_mass),
            (v.foundation.mass, r.foundation.mass),
        ] {
            close(x, y, "bearing/pier/footing");
        }
        for i in 0..6 {
            close(v.foundation.stiffness[i], r.foundation.stiffness[i], "K");
            close(v.foundation.damping[i], r.foundation.damping[i], "C");
        }
        assert_eq!(v.damping, r.damping);
        assert_eq!((c.dt, c.speed), (0.002, 83.33));
        assert!(((c.t_end / c.dt) - 5000.0).abs() < 1e-9);
        // The viaduct's sub-tables belong to a viaduct only; a modal viaduct is refused.
        let e = Case::load("paper-5", &["bridge.kind=spans".into()]).unwrap_err();
        assert!(e.to_string().starts_with("bridge.bearings"), "{e}");
        let e = Case::load("paper-5", &["model=modal".into()]).unwrap_err();
        assert!(e.to_string().starts_with("run.model"), "{e}");
        let e = Case::load("paper-5", &["bridge.pier.height_m=-1".into()]).unwrap_err();
        assert!(e.to_string().starts_with("bridge.pier.height_m"), "{e}");
    }
}
