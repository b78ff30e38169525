//! [`Viaduct`]: the paper's §5 viaduct (docs/model.md §10) — simply supported girders on
//! bearings, on piers, on foundation springs and dashpots — as one coupled structure behind
//! the [`Guideway`] interface. Values and their sources: docs/viaduct.md.
//!
//! Layout (x = 0 at the first pier): spans i = 0 … n−1 of equal length L; supports
//! k = 0 … n, each a pier at x = k·L whose top (the bearing level) lies `bearing_drop` below
//! the girder centroid line and whose base node, `height` lower, stands on the footing
//! impedance ([`super::soil`]) with the footing's mass lumped there. Each girder is a
//! Timoshenko beam of its own (its end nodes are not shared: the spans are simply
//! supported), joined at each end to the pier top by a six-DOF bearing spring acting at the
//! bearing point, `bearing_drop` below the centroid (so lateral bearing forces twist the
//! girder). Left end fixed along X, right end sliding; θy and θz free (pinned); θx held by
//! the two bearings' vertical stiffness at their lateral spacing. Piers are Timoshenko
//! elements too (the squat pier's shear flexibility matters: Φ ≈ 0.6 over a 2.5 m
//! element). Pier K of a probe name `pier{K}` is support K − 1 (1-based, from x = 0).
//!
//! Time integration: average-acceleration Newmark (docs/model.md §7, Eq. 19) with the
//! effective stiffness of the whole viaduct factorised once ([`SpanNewmark`], sparse
//! Cholesky, AMD ordering); damping = the foundation dashpots plus optional Rayleigh
//! damping. Each Newton–Raphson iteration is one sparse solve; nothing in the time loop
//! allocates. Wheel loads and motion use Eq. 15, 16 on the girder elements, as in
//! [`super::FeGuideway`].
//!
//! Support motion ([`Viaduct::with_support_motion`], docs/seismic.md "Support motion"): the
//! footings' ground ends follow a [`SupportMotion`]; the ground enters as the loads
//! k_f·u_g + c_f'·v_g on the footing DOFs (Eq. S1), so the matrices and the factor are the
//! same and every displacement is absolute. Without it the viaduct is what it was, bit for bit.

use super::cholesky::SparseCholesky;
use super::newmark::{Rayleigh, SpanNewmark, State};
use super::soil::{gazetas_rectangle, Soil};
use super::structure::{Axis, Builder, NodeKind, Structure};
use crate::physics::check::{non_negative, positive};
use crate::physics::guideway::{BeamSection, Guideway, PointLoad, PointMotion, SectionMotion};
use crate::physics::seismic::support::{
    add_ground_loads, GroundLink, GroundState, GroundTrack, SupportMotion,
};
use crate::Error;
use maglev_core::gap::{dof, locate, ElementVector, WheelShape, DOFS_PER_NODE};
use nalgebra::DVector;

/// The bearings at each girder end.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct BearingSpec {
    /// Vertical stiffness of one bearing (N/m); two bearings per girder end.
    #[serde(rename = "vertical_N_per_m")]
    pub vertical: f64,
    /// Lateral spacing of the two bearings of an end (m).
    #[serde(rename = "spacing_m")]
    pub spacing: f64,
    /// Lateral stiffness of a girder end (N/m): guided or fixed bearings.
    #[serde(rename = "lateral_N_per_m")]
    pub lateral: f64,
    /// Longitudinal stiffness at the fixed (left) end (N/m); the right end slides.
    #[serde(rename = "longitudinal_N_per_m")]
    pub longitudinal: f64,
    /// Height of the girder centroid above the bearing point (m).
    #[serde(rename = "drop_m")]
    pub drop: f64,
}

impl BearingSpec {
    /// Stiffness of a girder end along (u, v, w, θx, θy, θz): θy, θz free (pinned).
    pub fn end_stiffness(&self, fixed: bool) -> [f64; 6] {
        let kz = 2.0 * self.vertical;
        let krx = 2.0 * self.vertical * (self.spacing / 2.0).powi(2);
        let kx = if fixed { self.longitudinal } else { 0.0 };
        [kx, self.lateral, kz, krx, 0.0, 0.0]
    }
}

/// A pier: a vertical Timoshenko column. In its section, `iz` bends it laterally (Y–Z
/// plane), `iy` longitudinally (X–Z plane), `shear_area_y` / `shear_area_z` are the
/// lateral / longitudinal shear areas, `torsion_constant` its twist about Z.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PierSpec {
    #[serde(flatten)]
    pub section: BeamSection,
    /// Base to bearing level (m).
    #[serde(rename = "height_m")]
    pub height: f64,
    /// Elements along the height.
    pub elements: usize,
    /// Pier cap (head) mass lumped at the top (kg).
    #[serde(rename = "cap_mass_kg")]
    pub cap_mass: f64,
}

/// A foundation: springs and dashpots to the ground at the pier base, and the footing's
/// lumped mass and rotary inertias (about X, Y, Z through the base node).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct FoundationSpec {
    #[serde(rename = "stiffness_N_per_m_or_N_m_per_rad")]
    pub stiffness: [f64; 6],
    #[serde(rename = "damping_N_s_per_m_or_N_m_s_per_rad")]
    pub damping: [f64; 6],
    #[serde(rename = "mass_kg")]
    pub mass: f64,
    #[serde(rename = "rotary_inertia_kg_m2")]
    pub rotary_inertia: [f64; 3],
}

impl FoundationSpec {
    /// A rigid concrete footing `along_x` × `across_y` × `thickness` (density `rho`) on
    /// `soil`, Gazetas' impedance ([`super::soil`]).
    pub fn footing(
        soil: &Soil,
        along_x: f64,
        across_y: f64,
        thickness: f64,
        rho: f64,
    ) -> crate::Result<Self> {
        let z = gazetas_rectangle(soil, along_x, across_y)?;
        let m = rho * along_x * across_y * thickness;
        let (a, b, t) = (along_x, across_y, thickness);
        Ok(FoundationSpec {
            stiffness: z.stiffness,
            damping: z.damping,
            mass: m,
            rotary_inertia: [
                m * (b * b + t * t) / 12.0,
                m * (a * a + t * t) / 12.0,
                m * (a * a + b * b) / 12.0,
            ],
        })
    }
}

/// Everything that defines a viaduct (see the module docs for the layout).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ViaductSpec {
    /// Number of spans (n ≥ 1; n + 1 piers).
    pub spans: usize,
    /// Span length L (m).
    #[serde(rename = "span_length_m")]
    pub span_length: f64,
    /// Girder section (beam along X).
    pub girder: BeamSection,
    /// Timoshenko elements per girder.
    pub elements_per_span: usize,
    pub bearings: BearingSpec,
    pub pier: PierSpec,
    pub foundation: FoundationSpec,
    /// Rayleigh damping added to the dashpots (`None`: dashpots only).
    pub damping: Option<Rayleigh>,
}

impl ViaductSpec {
    /// Checks every value (one-line errors naming the key and the limit).
    pub fn validate(&self) -> crate::Result<()> {
        if self.spans == 0 {
            return Err(Error::invalid("bridge.spans", "must be at least 1, got 0"));
        }
        if self.elements_per_span == 0 || self.pier.elements == 0 {
            return Err(Error::invalid(
                "elements",
                "a girder and a pier need at least 1 element each",
            ));
        }
        positive("bridge.span_length", self.span_length)?;
        positive("bridge.pier.height", self.pier.height)?;
        positive("bridge.bearings.vertical", self.bearings.vertical)?;
        positive("bridge.bearings.lateral", self.bearings.lateral)?;
        positive("bridge.bearings.longitudinal", self.bearings.longitudinal)?;
        positive("bridge.bearings.spacing", self.bearings.spacing)?;
        non_negative("bridge.bearings.drop", self.bearings.drop)?;
        non_negative("bridge.pier.cap_mass", self.pier.cap_mass)?;
        non_negative("bridge.foundation.mass", self.foundation.mass)?;
        for (i, v) in self.foundation.stiffness.iter().enumerate() {
            positive(&format!("bridge.foundation.stiffness[{i}]"), *v)?;
        }
        for (i, v) in self.foundation.damping.iter().enumerate() {
            non_negative(&format!("bridge.foundation.damping[{i}]"), *v)?;
        }
        for (i, v) in self.foundation.rotary_inertia.iter().enumerate() {
            non_negative(&format!("bridge.foundation.rotary_inertia[{i}]"), *v)?;
        }
        for (name, s) in [
            ("girder", &self.girder),
            ("pier.section", &self.pier.section),
        ] {
            s.validate()
                .map_err(|f| f.error(format!("bridge.{name}.{}", f.field.name()), f.value))?;
        }
        Ok(())
    }

    /// Total length n·L (m).
    pub fn total_length(&self) -> f64 {
        self.spans as f64 * self.span_length
    }

    /// The same viaduct with `spans` spans.
    pub fn with_spans(&self, spans: usize) -> Self {
        ViaductSpec {
            spans,
            ..self.clone()
        }
    }
}

/// Node indices of the assembled viaduct.
#[derive(Clone, Debug)]
pub struct Layout {
    /// First node of each girder (its nodes are consecutive, `elements_per_span + 1`).
    pub girder_first: Vec<usize>,
    /// Base node of each pier (its nodes are consecutive, base to top).
    pub pier_base: Vec<usize>,
    /// Girder node X positions within a span (m).
    pub girder_nodes: Vec<f64>,
}

/// Assemble the viaduct's structure and node layout (see the module docs).
pub fn assemble(spec: &ViaductSpec) -> crate::Result<(Structure, Layout)> {
    spec.validate()?;
    let mut b = Builder::default();
    let (n, ne, np) = (spec.spans, spec.elements_per_span, spec.pier.elements);
    let le = spec.span_length / ne as f64;
    let lp = spec.pier.height / np as f64;
    let mut pier_base = Vec::with_capacity(n + 1);
    let mut girder_first = Vec::with_capacity(n);
    let pier = |b: &mut Builder| {
        let base = b.node(NodeKind::Pier);
        for e in 0..np {
            let top = b.node(NodeKind::Pier);
            b.beam(base + e, top, Axis::Z, &spec.pier.section, lp);
        }
        let f = &spec.foundation;
        b.ground(base, f.stiffness, f.damping);
        b.lumped(base, f.mass, f.rotary_inertia);
        b.lumped(base + np, spec.pier.cap_mass, [0.0; 3]);
        base
    };
    pier_base.push(pier(&mut b));
    for _ in 0..n {
        let first = b.node(NodeKind::Girder);
        for e in 0..ne {
            let next = b.node(NodeKind::Girder);
            b.beam(first + e, next, Axis::X, &spec.girder, le);
        }
        girder_first.push(first);
        pier_base.push(pier(&mut b));
    }
    for i in 0..n {
        let (g0, g1) = (girder_first[i], girder_first[i] + ne);
        let (left_top, right_top) = (pier_base[i] + np, pier_base[i + 1] + np);
        let drop = spec.bearings.drop;
        b.spring(g0, left_top, drop, spec.bearings.end_stiffness(true));
        b.spring(g1, right_top, drop, spec.bearings.end_stiffness(false));
    }
    let girder_nodes = (0..=ne)
        .map(|i| {
            if i == ne {
                spec.span_length
            } else {
                i as f64 * le
            }
        })
        .collect();
    Ok((
        b.finish(),
        Layout {
            girder_first,
            pier_base,
            girder_nodes,
        },
    ))
}

pub use crate::physics::guideway::BaseMotion;

/// The girder element under `x` (its first DOF) and the wheel shape there; `None` off the
/// viaduct. A pier's x belongs to the span on its right (the last span keeps its end).
fn shape(
    spec: &ViaductSpec,
    layout: &Layout,
    x: f64,
    ey: f64,
    ez: f64,
) -> Option<(usize, WheelShape<f64>)> {
    let l = spec.span_length;
    if !(x.is_finite() && x >= 0.0 && x <= spec.total_length() * (1.0 + 1e-12)) {
        return None;
    }
    let i = ((x / l).floor() as usize).min(spec.spans - 1);
    let local = (x - i as f64 * l).clamp(0.0, l);
    let at = locate(&layout.girder_nodes, local)?;
    let first = (layout.girder_first[i] + at.element) * DOFS_PER_NODE;
    Some((first, WheelShape::new(at.x2, at.length, ey, ez)))
}

/// Add the nodal forces of the loads to `f` (Eq. 15); loads off the viaduct are ignored.
/// True if any load is on the viaduct.
fn distribute(
    spec: &ViaductSpec,
    layout: &Layout,
    loads: &[PointLoad],
    f: &mut DVector<f64>,
) -> bool {
    let mut any = false;
    for p in loads {
        if let Some((first, s)) = shape(spec, layout, p.x, p.ey, p.ez) {
            let fe = s.nodal_forces(p.fy, p.fz);
            for (i, v) in fe.iter().enumerate() {
                f[first + i] += v;
            }
            any = true;
        }
    }
    any
}

/// The viaduct guideway (module docs).
#[derive(Debug)]
pub struct Viaduct {
    spec: ViaductSpec,
    structure: Structure,
    layout: Layout,
    dt: f64,
    newmark: SpanNewmark,
    static_factor: SparseCholesky,
    committed: State,
    trial: State,
    load: DVector<f64>,
    rhs_free: DVector<f64>,
    pred: DVector<f64>,
    rhs: DVector<f64>,
    scratch: super::cholesky::Scratch,
    free_valid: bool,
    committed_at_rest: bool,
    trial_at_rest: bool,
    solved: bool,
    /// The support motion driving the piers' footings, if any (docs/seismic.md).
    drive: Option<Drive>,
}

/// Support motion at the footings: the ground at each pier ([`GroundTrack`]) and the loads
/// `k·u_g + c·v_g` it puts on the footing DOFs (docs/seismic.md Eq. S1).
#[derive(Debug)]
struct Drive {
    track: GroundTrack,
    links: Vec<GroundLink>,
}

impl Viaduct {
    /// Assemble and factorise the viaduct of `spec` for the step `dt`.
    pub fn new(spec: &ViaductSpec, dt: f64) -> crate::Result<Self> {
        let (structure, layout) = assemble(spec)?;
        let c = match spec.damping {
            Some(r) => structure.c.combine(
                1.0,
                &structure.m.combine(r.alpha, &structure.k, r.beta),
                1.0,
            ),
            None => structure.c.clone(),
        };
        let newmark = SpanNewmark::with_damping_matrix(&structure.k, &structure.m, Some(c), dt)?;
        let pred_len = newmark.pred_len();
        let static_factor = SparseCholesky::new(&structure.k)
            .map_err(|e| Error::numerical(format!("viaduct stiffness: {e}")))?;
        let n = structure.dofs();
        Ok(Viaduct {
            spec: spec.clone(),
            scratch: newmark.factor().scratch(),
            structure,
            layout,
            dt,
            newmark,
            static_factor,
            committed: State::zeros(n),
            trial: State::zeros(n),
            load: DVector::zeros(n),
            rhs_free: DVector::zeros(n),
            pred: DVector::zeros(pred_len),
            rhs: DVector::zeros(n),
            free_valid: false,
            committed_at_rest: true,
            trial_at_rest: true,
            solved: false,
            drive: None,
        })
    }

    /// As [`Self::new`], with the piers' footings driven by `motion` (one support per pier,
    /// pier 1 first; docs/seismic.md "Support motion"). The viaduct starts at rest in its
    /// static equilibrium over the settled ground (the settlements of `motion`); displacements
    /// are absolute. Damping may only be stiffness-proportional: mass-proportional damping
    /// would resist the rigid-body motion the ground imposes.
    pub fn with_support_motion(
        spec: &ViaductSpec,
        dt: f64,
        motion: SupportMotion,
    ) -> crate::Result<Self> {
        let mut v = Self::new(spec, dt)?;
        let piers = v.pier_count();
        let track = GroundTrack::new(motion, piers, &format!("the viaduct has {piers} piers"))?;
        let beta = match spec.damping {
            Some(r) if r.alpha != 0.0 => {
                return Err(Error::invalid(
                    "bridge.damping",
                    format!(
                        "must be stiffness-proportional under support motion (mass-proportional \
                         damping drags the rigid-body motion), got alpha = {} 1/s",
                        r.alpha
                    ),
                ))
            }
            Some(r) => r.beta,
            None => 0.0,
        };
        let f = &spec.foundation;
        let links: Vec<GroundLink> = v
            .layout
            .pier_base
            .iter()
            .enumerate()
            .flat_map(|(support, &base)| {
                (0..3).map(move |axis| GroundLink {
                    dof: base * DOFS_PER_NODE + axis,
                    support,
                    axis,
                    k: f.stiffness[axis],
                    // β K holds β k_f on the footing: its ground end moves too.
                    c: f.damping[axis] + beta * f.stiffness[axis],
                })
            })
            .collect();
        // The settled shape: K d = K_g u_g (the ground at rest, v_g = 0).
        let mut d = DVector::zeros(v.structure.dofs());
        add_ground_loads(&links, track.committed(), d.as_mut_slice());
        if d.iter().any(|&x| x != 0.0) {
            v.static_factor
                .solve_in_place(d.as_mut_slice(), &mut v.static_factor.scratch());
            v.committed.d.copy_from(&d);
            v.trial.d.copy_from(&d);
            v.committed_at_rest = false;
            v.trial_at_rest = false;
        }
        v.drive = Some(Drive { track, links });
        Ok(v)
    }

    /// The ground at each pier on the committed state (`None` without support motion).
    pub fn ground(&self) -> Option<&[GroundState]> {
        self.drive.as_ref().map(|d| d.track.committed())
    }

    /// The description it was built from.
    pub fn spec(&self) -> &ViaductSpec {
        &self.spec
    }

    /// The assembled structure (K, M, dashpots).
    pub fn structure(&self) -> &Structure {
        &self.structure
    }

    /// Node layout.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// Number of piers (spans + 1).
    pub fn pier_count(&self) -> usize {
        self.layout.pier_base.len()
    }

    /// Committed state (all DOFs, node by node).
    pub fn state(&self) -> &State {
        &self.committed
    }

    /// Motion of pier `k`'s base (1-based, pier 1 at x = 0; probe `pier{k}.base.*`) on the
    /// committed state; `None` if there is no such pier.
    pub fn pier_base(&self, k: usize) -> Option<BaseMotion> {
        let node = *self.layout.pier_base.get(k.checked_sub(1)?)?;
        let i = node * DOFS_PER_NODE;
        let s = &self.committed;
        Some(BaseMotion {
            z: s.d[i + dof::W],
            vz: s.v[i + dof::W],
            az: s.a[i + dof::W],
            y: s.d[i + dof::V],
            ay: s.a[i + dof::V],
        })
    }

    fn shape(&self, x: f64, ey: f64, ez: f64) -> Option<(usize, WheelShape<f64>)> {
        shape(&self.spec, &self.layout, x, ey, ez)
    }

    fn gather(d: &DVector<f64>, first: usize) -> ElementVector<f64> {
        ElementVector::from_fn(|i, _| d[first + i])
    }

    /// Static displacements K d = F for the loads (all DOFs).
    pub fn solve_static(&self, loads: &[PointLoad]) -> DVector<f64> {
        let mut f = DVector::zeros(self.structure.dofs());
        distribute(&self.spec, &self.layout, loads, &mut f);
        self.static_factor
            .solve_in_place(f.as_mut_slice(), &mut self.static_factor.scratch());
        f
    }

    /// Motion of a point for displacements `d` (as from [`Self::solve_static`]).
    pub fn motion_in(&self, d: &DVector<f64>, x: f64, ey: f64, ez: f64) -> PointMotion {
        self.shape(x, ey, ez)
            .map(|(first, s)| {
                let de = Self::gather(d, first);
                PointMotion {
                    y: s.y_at(&de),
                    z: s.z_at(&de),
                }
            })
            .unwrap_or_default()
    }
}

impl Guideway for Viaduct {
    fn time_step(&self) -> f64 {
        self.dt
    }

    fn pier_base(&self, k: usize) -> Option<BaseMotion> {
        Viaduct::pier_base(self, k)
    }

    fn solve_step(&mut self, loads: &[PointLoad]) {
        self.load.fill(0.0);
        let loaded = distribute(&self.spec, &self.layout, loads, &mut self.load);
        self.solved = true;
        if let Some(d) = &mut self.drive {
            d.track.prepare(self.dt);
            add_ground_loads(&d.links, d.track.trial(), self.load.as_mut_slice());
        }
        if self.committed_at_rest && !loaded && self.drive.is_none() {
            if !self.trial_at_rest {
                self.trial.d.fill(0.0);
                self.trial_at_rest = true;
            }
            return;
        }
        self.trial_at_rest = false;
        if !self.free_valid {
            if self.committed_at_rest {
                self.rhs_free.fill(0.0);
            } else {
                self.newmark
                    .free_rhs(&self.committed, &mut self.pred, &mut self.rhs_free);
            }
            self.free_valid = true;
        }
        self.rhs.copy_from(&self.rhs_free);
        self.rhs += &self.load;
        self.newmark
            .solve_in_place(&mut self.rhs, &mut self.scratch);
        self.trial.d.copy_from(&self.rhs);
    }

    fn motion_at(&self, x: f64, ey: f64, ez: f64) -> PointMotion {
        self.motion_in(&self.trial.d, x, ey, ez)
    }

    fn section_at(&self, x: f64) -> SectionMotion {
        self.shape(x, 0.0, 0.0)
            .map(|(first, s)| {
                let de = Self::gather(&self.trial.d, first);
                SectionMotion {
                    y: s.y_at(&de),
                    z: s.z_at(&de),
                    rx: s.rx_at(&de),
                }
            })
            .unwrap_or_default()
    }

    fn commit(&mut self) {
        if !self.solved {
            return;
        }
        if !self.trial_at_rest {
            self.newmark.finish(&mut self.committed, &mut self.trial);
        }
        self.committed_at_rest = self.trial_at_rest;
        self.free_valid = false;
        self.solved = false;
        if let Some(d) = &mut self.drive {
            d.track.commit();
        }
    }
}

/// The bundled `paper-5` viaduct: 35 spans of 30 m, every value from docs/viaduct.md.
pub fn paper5_viaduct() -> ViaductSpec {
    // Girder: simplified single-cell box of the standard HSR double-track girder (depth
    // 3.05 m, deck 12 m), C50 concrete; section constants computed in docs/viaduct.md.
    let e_girder = 3.55e10;
    let girder = BeamSection {
        youngs_modulus: e_girder,
        shear_modulus: e_girder / (2.0 * 1.2),
        area: 7.51,
        shear_area_y: 5.14,
        shear_area_z: 2.37,
        iy: 9.96,
        iz: 62.1,
        torsion_constant: 16.6,
        // 18.8 t/m concrete + 12 t/m second-stage dead load.
        mass_per_length: 30.8e3,
        // ρ_c (Iy + Iz) + 12 t/m spread over the 12 m deck (12²/12 m²).
        polar_mass: Some(2500.0 * (9.96 + 62.1) + 12.0e3 * 12.0),
    };
    // Pier: solid 6.0 m (across) × 2.8 m (along) rectangle, C35.
    let e_pier = 3.15e10;
    let (a, b) = (6.0f64, 2.8f64);
    let pier = PierSpec {
        section: BeamSection {
            youngs_modulus: e_pier,
            shear_modulus: e_pier / (2.0 * 1.2),
            area: a * b,
            shear_area_y: a * b * 5.0 / 6.0,
            shear_area_z: a * b * 5.0 / 6.0,
            iy: a * b.powi(3) / 12.0,
            iz: b * a.powi(3) / 12.0,
            // Rectangle a/b = 2.14: β ≈ 0.247 (Timoshenko & Goodier's table).
            torsion_constant: 0.247 * a * b.powi(3),
            mass_per_length: 2500.0 * a * b,
            polar_mass: None,
        },
        height: 10.0,
        elements: 4,
        cap_mass: 150e3,
    };
    let soil = Soil {
        shear_wave_velocity: 250.0,
        density: 1900.0,
        poisson: 0.33,
        damping: 0.03,
    };
    let foundation = FoundationSpec::footing(&soil, 9.0, 12.0, 2.5, 2500.0)
        .expect("the paper-5 footing values are valid");
    ViaductSpec {
        spans: 35,
        span_length: 30.0,
        girder,
        elements_per_span: 16,
        bearings: BearingSpec {
            vertical: 1.0e9,
            spacing: 4.4,
            lateral: 2.0e10,
            longitudinal: 2.0e10,
            drop: 2.1,
        },
        pier,
        foundation,
        damping: None,
    }
}
