//! Scenarios: TOML files whose every key names its unit, bundled ones by name, `--set`
//! overrides. Conversion to SI happens here, once; the solvers never see kN or tonnes.

use crate::guideway::{BeamSection, Bridge};
use crate::simulation::{Law, MovingLoad};
use crate::vehicle::Fig1;
use maglev_core::gap::Geometry;
use maglev_core::gap_control::GapParams;
use maglev_core::{Interpolation, Params, Scheme};
use serde::{Deserialize, Serialize};

/// Bundled scenarios: (name, TOML text).
pub const BUNDLED: [(&str, &str); 3] = [
    ("paper-4.2", include_str!("../scenarios/paper-4.2.toml")),
    (
        "train-forces",
        include_str!("../scenarios/train-forces.toml"),
    ),
    (
        "moving-force",
        include_str!("../scenarios/moving-force.toml"),
    ),
];

/// Short `--set` keys and the scenario key each stands for.
/// The most time steps a case may take (t_end / dt): 10⁷ steps is hours of wall time for a
/// vehicle passage; a larger count is a typo in dt or t_end far more often than intent.
pub const MAX_STEPS: f64 = 1e7;

/// The largest estimated condition number of an FE span's Newmark matrix (see
/// `Scenario::check_fe_size`).
pub const MAX_CONDITION: f64 = 1e10;

/// The most FE DOFs a case may have: about 6 GB of banded model at ~70 doubles per DOF,
/// and far beyond any span converged at 16 elements.
pub const MAX_FE_DOFS: f64 = 1e7;

pub const SHORT_KEYS: [(&str, &str); 12] = [
    ("speed", "run.speed_m_per_s"),
    ("model", "run.model"),
    ("elements", "run.elements_per_span"),
    ("modes", "run.modes"),
    ("dt", "run.dt_s"),
    ("t_end", "run.t_end_s"),
    ("nsub", "controller.nsub"),
    ("alpha", "controller.alpha"),
    ("law", "controller.law"),
    ("scheme", "controller.scheme"),
    ("seed", "irregularity.seed"),
    ("geometry", "vehicle.geometry"),
];

#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct RunSection {
    pub model: Model,
    pub speed_m_per_s: f64,
    pub dt_s: f64,
    #[serde(default = "default_elements")]
    pub elements_per_span: usize,
    #[serde(default = "default_modes")]
    pub modes: usize,
    pub t_end_s: Option<f64>,
    #[serde(default = "default_tolerance")]
    pub tolerance_m: f64,
    #[serde(default = "default_max_iterations")]
    pub max_iterations: u32,
}
fn default_elements() -> usize {
    20
}
fn default_modes() -> usize {
    crate::modal::DEFAULT_MODES
}
fn default_tolerance() -> f64 {
    1e-9
}
fn default_max_iterations() -> u32 {
    50
}

#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct BridgeSection {
    pub spans_m: Vec<f64>,
    pub youngs_modulus_kN_per_m2: f64,
    pub shear_modulus_kN_per_m2: f64,
    pub area_m2: f64,
    pub shear_area_y_m2: f64,
    pub shear_area_z_m2: f64,
    pub iy_m4: f64,
    pub iz_m4: f64,
    pub torsion_constant_m4: f64,
    pub mass_t_per_m: f64,
    pub polar_mass_t_m2_per_m: Option<f64>,
}

#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields, tag = "kind", rename_all = "kebab-case")]
#[allow(non_snake_case)]
pub enum VehicleSection {
    Fig1 {
        body_mass_t: f64,
        jx_t_m2: f64,
        jy_t_m2: f64,
        jz_t_m2: f64,
        spring_kN_per_m: f64,
        damper_kN_s_per_m: f64,
        half_length_m: f64,
        half_width_m: f64,
        offset_y_m: f64,
        target_height_m: f64,
        body_height_m: f64,
        wheel_mass_kg: f64,
        /// How the magnets face their rails (docs/model.md §2); default `paper`.
        #[serde(default)]
        geometry: GeometryKey,
        /// Identical cars, one behind the other (default 1).
        #[serde(default = "one")]
        repeat: usize,
        /// Spacing of the repeated cars, leading wheel to leading wheel (m); needed when
        /// `repeat > 1`, at least the wheelbase `2·half_length_m`.
        car_length_m: Option<f64>,
    },
    MovingForce {
        force_kN: f64,
        offset_y_m: f64,
        offset_z_m: f64,
    },
    /// Constant vertical moving loads (`[train] kind = "forces"`): one car's loads, repeated.
    Forces {
        /// One car's loads (kN, downward).
        loads_kN: Vec<f64>,
        /// Each load's distance behind the car's leading load (m).
        offsets_m: Vec<f64>,
        /// Identical cars, one behind the other (default 1).
        #[serde(default = "one")]
        repeat: usize,
        /// Spacing of the repeated cars (m); needed when `repeat > 1`.
        car_length_m: Option<f64>,
        /// Offset of the loads from the beam axis, Y and Z (m); default on the axis.
        #[serde(default)]
        offset_y_m: f64,
        #[serde(default)]
        offset_z_m: f64,
    },
}

fn one() -> usize {
    1
}

/// The most loads a `forces` train may carry.
pub const MAX_LOADS: usize = 100_000;

/// The most cars a `fig1` train may have (12 magnets each).
pub const MAX_CARS: usize = 1000;

/// `vehicle.geometry`: `paper` (Eq. 2 read literally, the default) or `ems`.
#[derive(Deserialize, Serialize, Debug, Clone, Copy, Default, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum GeometryKey {
    #[default]
    Paper,
    Ems,
}

impl From<GeometryKey> for Geometry {
    fn from(g: GeometryKey) -> Self {
        match g {
            GeometryKey::Paper => Geometry::Paper,
            GeometryKey::Ems => Geometry::Ems,
        }
    }
}

#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct ControllerSection {
    pub i0_A: f64,
    pub h0_m: f64,
    pub r0_ohm: f64,
    pub kp_V_m_per_A: f64,
    pub ki_V_m_per_A_s: f64,
    pub alpha: f64,
    pub nsub: u32,
    pub interp: InterpKey,
    pub vmax_V: f64,
    /// `paper` (Eq. 8–14 alone, the default) or `gap-loop` (the outer gap loop of
    /// `maglev_core::gap_control` at its designed gains around the paper's law).
    #[serde(default)]
    pub law: LawKey,
    /// `paper` (Eq. 14 with `nsub` sub-steps, the default) or `accurate` (Gauss–Legendre).
    #[serde(default)]
    pub scheme: SchemeKey,
}

/// `controller.law`: which levitation law each magnet runs.
#[derive(Deserialize, Serialize, Debug, Clone, Copy, Default, PartialEq, Eq, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum LawKey {
    /// The paper's PI law on `g = i/h` alone (Eq. 8–14).
    #[default]
    Paper,
    /// The outer gap loop of `maglev_core::gap_control` around the paper's law.
    GapLoop,
}

/// `controller.interp`: the gap interpolation inside the outer step.
#[derive(Deserialize, Serialize, Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum InterpKey {
    Linear,
    Parabolic,
}

impl From<InterpKey> for Interpolation {
    fn from(k: InterpKey) -> Self {
        match k {
            InterpKey::Linear => Interpolation::Linear,
            InterpKey::Parabolic => Interpolation::Parabolic,
        }
    }
}

/// `controller.scheme`: the integrator of the coil + PI equations (`maglev_core::Scheme`).
#[derive(Deserialize, Serialize, Debug, Clone, Copy, Default, PartialEq, Eq, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum SchemeKey {
    /// The paper's Eq. 14, `nsub` times per step (first order).
    #[default]
    Paper,
    /// Gauss–Legendre on the limit system (order 4); ignores `nsub` and `alpha`.
    Accurate,
}

impl From<SchemeKey> for Scheme {
    fn from(k: SchemeKey) -> Self {
        match k {
            SchemeKey::Paper => Scheme::Paper,
            SchemeKey::Accurate => Scheme::Accurate,
        }
    }
}

impl SchemeKey {
    /// The name as written in a scenario.
    pub fn as_str(self) -> &'static str {
        match self {
            SchemeKey::Paper => "paper",
            SchemeKey::Accurate => "accurate",
        }
    }
}

#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct IrregularitySection {
    pub enabled: bool,
    pub seed: u64,
}

/// A scenario as written (units in the key names).
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    pub run: RunSection,
    pub bridge: BridgeSection,
    /// `[vehicle]`, or `[train]` (the same section under the name a train reads better by).
    #[serde(alias = "train")]
    pub vehicle: VehicleSection,
    pub controller: Option<ControllerSection>,
    pub irregularity: Option<IrregularitySection>,
    pub output: Option<OutputSection>,
}

/// `[output]`: what a run records.
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct OutputSection {
    /// Probe names (`crate::probes`), one response.csv column each, in this order.
    pub probes: Vec<String>,
}

/// Which guideway model runs.
#[derive(Deserialize, Serialize, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Model {
    Fe,
    Modal,
    /// A guideway that never moves (the vehicle on a rigid, irregular rail).
    Rigid,
}

/// Loads a scenario by bundled name or path, applies `key=value` overrides, validates.
pub fn load(name_or_path: &str, sets: &[String]) -> Result<Scenario, String> {
    let text = match BUNDLED.iter().find(|(n, _)| *n == name_or_path) {
        Some((_, t)) => t.to_string(),
        None => std::fs::read_to_string(name_or_path).map_err(|e| {
            let names: Vec<&str> = BUNDLED.iter().map(|(n, _)| *n).collect();
            format!(
                "scenario `{name_or_path}` is neither a bundled name ({}) nor a readable file: {e}",
                names.join(", ")
            )
        })?,
    };
    parse(&text, name_or_path, sets)
}

/// Parses scenario text with overrides.
pub fn parse(text: &str, name: &str, sets: &[String]) -> Result<Scenario, String> {
    let mut table: toml::Table = toml::from_str(text)
        .map_err(|e| format!("scenario {name}: {}", one_line(&e.to_string())))?;
    for set in sets {
        apply_set(&mut table, set)?;
    }
    let sc: Scenario = table
        .try_into()
        .map_err(|e: toml::de::Error| format!("scenario {name}: {}", one_line(&e.to_string())))?;
    sc.validate()?;
    Ok(sc)
}

fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

fn apply_set(table: &mut toml::Table, set: &str) -> Result<(), String> {
    let (key, value) = set
        .split_once('=')
        .ok_or_else(|| format!("--set `{set}`: expected key=value"))?;
    let key = key.trim();
    let full = SHORT_KEYS
        .iter()
        .find(|(s, _)| *s == key)
        .map(|(_, f)| *f)
        .unwrap_or(key);
    let (section, field) = full.split_once('.').ok_or_else(|| {
        let shorts: Vec<&str> = SHORT_KEYS.iter().map(|(s, _)| *s).collect();
        format!(
            "--set: unknown key `{key}` (use one of {} or section.key)",
            shorts.join(", ")
        )
    })?;
    let value = value.trim();
    // A TOML value if it parses as one (numbers, booleans, inf), else a bare string.
    let parsed: toml::Value = toml::from_str::<toml::Table>(&format!("v = {value}"))
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| toml::Value::String(value.to_string()));
    let sec = table
        .entry(section.to_string())
        .or_insert_with(|| toml::Value::Table(toml::Table::new()));
    let sec = sec
        .as_table_mut()
        .ok_or_else(|| format!("--set: `{section}` is not a section"))?;
    // Integers given where floats are expected (speed=100) are fine for serde; floats given
    // for integers are not, which is the error we want.
    sec.insert(field.to_string(), parsed);
    Ok(())
}

fn positive(name: &str, v: f64) -> Result<(), String> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(format!("{name} must be a positive number, got {v}"))
    }
}

impl Scenario {
    fn validate(&self) -> Result<(), String> {
        let r = &self.run;
        self.model()?;
        positive("run.speed_m_per_s", r.speed_m_per_s)?;
        positive("run.dt_s", r.dt_s)?;
        positive("run.tolerance_m", r.tolerance_m)?;
        if let Some(t) = r.t_end_s {
            positive("run.t_end_s", t)?;
        }
        if r.elements_per_span == 0 {
            return Err("run.elements_per_span must be at least 1".into());
        }
        if r.modes == 0 {
            return Err("run.modes must be at least 1".into());
        }
        if r.max_iterations == 0 {
            return Err("run.max_iterations must be at least 1".into());
        }
        let b = &self.bridge;
        if b.spans_m.is_empty() {
            return Err("bridge.spans_m must list at least one span".into());
        }
        for (i, &l) in b.spans_m.iter().enumerate() {
            positive(&format!("bridge.spans_m[{i}]"), l)?;
        }
        for (n, v) in [
            (
                "bridge.youngs_modulus_kN_per_m2",
                b.youngs_modulus_kN_per_m2,
            ),
            ("bridge.shear_modulus_kN_per_m2", b.shear_modulus_kN_per_m2),
            ("bridge.area_m2", b.area_m2),
            ("bridge.shear_area_y_m2", b.shear_area_y_m2),
            ("bridge.shear_area_z_m2", b.shear_area_z_m2),
            ("bridge.iy_m4", b.iy_m4),
            ("bridge.iz_m4", b.iz_m4),
            ("bridge.torsion_constant_m4", b.torsion_constant_m4),
            ("bridge.mass_t_per_m", b.mass_t_per_m),
        ] {
            positive(n, v)?;
        }
        match &self.vehicle {
            VehicleSection::Fig1 { .. } => {
                if self.controller.is_none() {
                    return Err("a fig1 vehicle needs a [controller] section".into());
                }
                self.fig1()?;
                self.fig1_cars()?;
                self.controller_params()?;
            }
            VehicleSection::Forces { .. } => {
                self.forces()?;
            }
            VehicleSection::MovingForce {
                force_kN,
                offset_y_m,
                offset_z_m,
            } => {
                for (n, v) in [
                    ("vehicle.force_kN", *force_kN),
                    ("vehicle.offset_y_m", *offset_y_m),
                    ("vehicle.offset_z_m", *offset_z_m),
                ] {
                    if !v.is_finite() {
                        return Err(format!("{n} must be a finite number, got {v}"));
                    }
                }
            }
        }
        if self.run.model == Model::Fe {
            self.check_fe_size()?;
        }
        let steps = self.t_end() / self.run.dt_s;
        if steps.is_nan() || steps > MAX_STEPS {
            return Err(format!(
                "run.t_end_s / run.dt_s = {steps:.3e} steps exceeds the limit of {MAX_STEPS:.0e} steps"
            ));
        }
        Ok(())
    }

    /// The loads of a `forces` train in SI, the leading load at x = 0 at t = 0 and every other
    /// behind it (x0 = −offset − car·car_length).
    pub fn forces(&self) -> Result<Vec<MovingLoad>, String> {
        let VehicleSection::Forces {
            loads_kN,
            offsets_m,
            repeat,
            car_length_m,
            offset_y_m,
            offset_z_m,
        } = &self.vehicle
        else {
            return Err("not a forces train".into());
        };
        if loads_kN.is_empty() || loads_kN.len() != offsets_m.len() {
            return Err(format!(
                "train.loads_kN and train.offsets_m must be non-empty lists of equal length (got {} and {})",
                loads_kN.len(),
                offsets_m.len()
            ));
        }
        if *repeat == 0 || repeat.saturating_mul(loads_kN.len()) > MAX_LOADS {
            return Err(format!(
                "train.repeat × {} loads must be between 1 and {MAX_LOADS}, got repeat = {repeat}",
                loads_kN.len()
            ));
        }
        let car = match car_length_m {
            Some(l) => {
                positive("train.car_length_m", *l)?;
                *l
            }
            None if *repeat == 1 => 0.0,
            None => return Err("train.car_length_m is needed when train.repeat > 1".into()),
        };
        for (i, (&f, &o)) in loads_kN.iter().zip(offsets_m).enumerate() {
            if !f.is_finite() {
                return Err(format!(
                    "train.loads_kN[{i}] must be a finite number, got {f}"
                ));
            }
            if !(o.is_finite() && o >= 0.0) {
                return Err(format!(
                    "train.offsets_m[{i}] must be zero or positive (behind the leading load), got {o}"
                ));
            }
        }
        for (n, v) in [
            ("train.offset_y_m", *offset_y_m),
            ("train.offset_z_m", *offset_z_m),
        ] {
            if !v.is_finite() {
                return Err(format!("{n} must be a finite number, got {v}"));
            }
        }
        Ok((0..*repeat)
            .flat_map(|c| {
                loads_kN
                    .iter()
                    .zip(offsets_m)
                    .map(move |(&f, &o)| MovingLoad {
                        x0: -o - c as f64 * car,
                        force: f * 1e3,
                        ey: *offset_y_m,
                        ez: *offset_z_m,
                    })
            })
            .collect())
    }

    /// Refuses FE discretisations whose Newmark matrix cannot be solved to useful precision
    /// or that exceed the memory limit.
    ///
    /// Condition estimate of K + (4/Δt²)·M per span: its largest eigenvalue is at most about
    /// the stiffest element term k_max = max(E·A/l, 12·E·I/l³, G·A_s/l) (l the element
    /// length), its smallest at least the nodal mass term 4·m·l/Δt². Their ratio, plus one,
    /// bounds the digits a solve loses; above [`MAX_CONDITION`] fewer than six of the sixteen
    /// digits of f64 survive. Memory: [`MAX_FE_DOFS`] DOFs (the banded model holds about
    /// 70 doubles per DOF).
    fn check_fe_size(&self) -> Result<(), String> {
        let b = self.bridge();
        let s = &b.section;
        let n = self.run.elements_per_span as f64;
        let dofs = 6.0 * (n + 1.0) * b.spans.len() as f64;
        if dofs > MAX_FE_DOFS {
            return Err(format!(
                "run.elements_per_span = {n} over {} span(s) is {dofs:.3e} FE DOFs, above the limit of {MAX_FE_DOFS:.0e}",
                b.spans.len()
            ));
        }
        let dt = self.run.dt_s;
        for (i, &span) in b.spans.iter().enumerate() {
            let l = span / n;
            let k_max = (s.youngs_modulus * s.area / l)
                .max(12.0 * s.youngs_modulus * s.iy.max(s.iz) / l.powi(3))
                .max(s.shear_modulus * s.shear_area_y.max(s.shear_area_z) / l);
            let m_min = 4.0 * s.mass_per_length * l / (dt * dt);
            let cond = 1.0 + k_max / m_min;
            if cond > MAX_CONDITION {
                return Err(format!(
                    "run.elements_per_span = {n}: span {} ({span} m) has {l:.3e} m elements whose Newmark matrix has an estimated condition number {cond:.1e}, above the limit of {MAX_CONDITION:.0e} (fewer than 6 significant digits would survive); use fewer elements or a larger run.dt_s",
                    i + 1
                ));
            }
        }
        Ok(())
    }

    /// The guideway model to run.
    pub fn model(&self) -> Result<Model, String> {
        Ok(self.run.model)
    }

    pub fn bridge(&self) -> Bridge {
        let b = &self.bridge;
        Bridge {
            section: BeamSection {
                youngs_modulus: b.youngs_modulus_kN_per_m2 * 1e3,
                shear_modulus: b.shear_modulus_kN_per_m2 * 1e3,
                area: b.area_m2,
                shear_area_y: b.shear_area_y_m2,
                shear_area_z: b.shear_area_z_m2,
                iy: b.iy_m4,
                iz: b.iz_m4,
                torsion_constant: b.torsion_constant_m4,
                mass_per_length: b.mass_t_per_m * 1e3,
                polar_mass: b.polar_mass_t_m2_per_m.map(|v| v * 1e3),
            },
            spans: b.spans_m.clone(),
        }
    }

    /// The Fig. 1 vehicle in SI (error for other vehicle kinds).
    pub fn fig1(&self) -> Result<Fig1, String> {
        match &self.vehicle {
            VehicleSection::Fig1 {
                body_mass_t,
                jx_t_m2,
                jy_t_m2,
                jz_t_m2,
                spring_kN_per_m,
                damper_kN_s_per_m,
                half_length_m,
                half_width_m,
                offset_y_m,
                target_height_m,
                body_height_m,
                wheel_mass_kg,
                ..
            } => {
                for (n, v) in [
                    ("vehicle.body_mass_t", *body_mass_t),
                    ("vehicle.jx_t_m2", *jx_t_m2),
                    ("vehicle.jy_t_m2", *jy_t_m2),
                    ("vehicle.jz_t_m2", *jz_t_m2),
                    ("vehicle.spring_kN_per_m", *spring_kN_per_m),
                    ("vehicle.damper_kN_s_per_m", *damper_kN_s_per_m),
                    ("vehicle.half_length_m", *half_length_m),
                ] {
                    positive(n, v)?;
                }
                if !(*wheel_mass_kg >= 0.0 && wheel_mass_kg.is_finite()) {
                    return Err("vehicle.wheel_mass_kg must be zero or positive".into());
                }
                for (n, v) in [
                    ("vehicle.half_width_m", *half_width_m),
                    ("vehicle.offset_y_m", *offset_y_m),
                    ("vehicle.target_height_m", *target_height_m),
                    ("vehicle.body_height_m", *body_height_m),
                ] {
                    if !v.is_finite() {
                        return Err(format!("{n} must be a finite number, got {v}"));
                    }
                }
                Ok(Fig1 {
                    body_mass: body_mass_t * 1e3,
                    jx: jx_t_m2 * 1e3,
                    jy: jy_t_m2 * 1e3,
                    jz: jz_t_m2 * 1e3,
                    k: spring_kN_per_m * 1e3,
                    c: damper_kN_s_per_m * 1e3,
                    half_length: *half_length_m,
                    half_width: *half_width_m,
                    offset_y: *offset_y_m,
                    target_height: *target_height_m,
                    body_height: *body_height_m,
                    wheel_mass: *wheel_mass_kg,
                    com_ahead: 0.0,
                })
            }
            _ => Err("not a fig1 vehicle".into()),
        }
    }

    /// A fig1 train's cars: `(repeat, car_length_m)` (one car: length 0), checked.
    pub fn fig1_cars(&self) -> Result<(usize, f64), String> {
        let VehicleSection::Fig1 {
            repeat,
            car_length_m,
            half_length_m,
            ..
        } = &self.vehicle
        else {
            return Err("not a fig1 vehicle".into());
        };
        if !(1..=MAX_CARS).contains(repeat) {
            return Err(format!(
                "train.repeat must be between 1 and {MAX_CARS}, got {repeat}"
            ));
        }
        match car_length_m {
            Some(l) if !(l.is_finite() && *l >= 2.0 * half_length_m) => Err(format!(
                "train.car_length_m must be a finite number of at least the wheelbase 2·half_length_m = {} m, got {l}",
                2.0 * half_length_m
            )),
            Some(l) => Ok((*repeat, *l)),
            None if *repeat == 1 => Ok((1, 0.0)),
            None => Err("train.car_length_m is needed when train.repeat > 1".into()),
        }
    }

    /// The levitation law (`controller.law`); the paper's without a controller section.
    /// The vehicle's magnet geometry (docs/model.md §2): `paper` unless the scenario says `ems`.
    pub fn geometry(&self) -> Geometry {
        match &self.vehicle {
            VehicleSection::Fig1 { geometry, .. } => (*geometry).into(),
            VehicleSection::MovingForce { .. } | VehicleSection::Forces { .. } => Geometry::Paper,
        }
    }

    pub fn law(&self) -> Result<Law, String> {
        match self.controller.as_ref().map_or(LawKey::Paper, |c| c.law) {
            LawKey::Paper => Ok(Law::Paper),
            LawKey::GapLoop => Ok(Law::GapLoop(match &self.vehicle {
                // Gains designed for this scenario's vehicle, inner law and geometry
                // (docs/gap-loop.md); a moving force has no magnets to run them.
                VehicleSection::Fig1 { .. } => {
                    let v = crate::vehicle::VehicleModel::fig1(
                        &self.fig1()?,
                        maglev_core::levitation::GRAVITY,
                    )
                    .map_err(|e| e.to_string())?;
                    crate::stability::design::design(
                        &v,
                        &self.controller_params()?,
                        self.geometry(),
                        Some(self.run.dt_s),
                    )?
                    .gains
                }
                VehicleSection::MovingForce { .. } | VehicleSection::Forces { .. } => {
                    GapParams::designed()
                }
            })),
        }
    }

    /// The controller parameters in SI (p0 is set per wheel by the simulation).
    pub fn controller_params(&self) -> Result<Params, String> {
        let c = self
            .controller
            .as_ref()
            .ok_or("the scenario has no [controller] section")?;
        let interpolation = c.interp.into();
        let scheme = c.scheme.into();
        let p = Params {
            i0: c.i0_A,
            h0: c.h0_m,
            r0: c.r0_ohm,
            kp: c.kp_V_m_per_A,
            ki: c.ki_V_m_per_A_s,
            p0: 1.0,
            alpha: c.alpha,
            dt: self.run.dt_s,
            n_sub: c.nsub,
            interpolation,
            v_max: c.vmax_V,
            scheme,
        };
        p.validate().map_err(|e| format!("controller: {e}"))?;
        Ok(p)
    }

    /// Default end time: the last wheel leaves the bridge, plus 0.1 s.
    pub fn t_end(&self) -> f64 {
        if let Some(t) = self.run.t_end_s {
            return t;
        }
        let length: f64 = self.bridge.spans_m.iter().sum();
        let behind = match &self.vehicle {
            VehicleSection::Fig1 { half_length_m, .. } => {
                let (cars, length) = self.fig1_cars().unwrap_or((1, 0.0));
                2.0 * half_length_m + (cars - 1) as f64 * length
            }
            VehicleSection::MovingForce { .. } => 0.0,
            VehicleSection::Forces { .. } => self
                .forces()
                .map_or(0.0, |f| f.iter().map(|l| -l.x0).fold(0.0, f64::max)),
        };
        (length + behind) / self.run.speed_m_per_s + 0.1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bundled_scenarios_parse() {
        for (name, _) in BUNDLED {
            load(name, &[]).unwrap();
        }
    }

    #[test]
    fn set_overrides_and_errors_name_the_key() {
        let s = load(
            "paper-4.2",
            &["speed=150".into(), "model=modal".into(), "dt=1e-5".into()],
        )
        .unwrap();
        assert_eq!(s.run.speed_m_per_s, 150.0);
        assert_eq!(s.model().unwrap(), Model::Modal);
        let e = load("paper-4.2", &["colour=red".into()]).unwrap_err();
        assert!(e.contains("colour"), "{e}");
        let e = load("paper-4.2", &["run.sped=3".into()]).unwrap_err();
        assert!(e.contains("sped"), "{e}");
        let e = load("paper-4.2", &["speed=-3".into()]).unwrap_err();
        assert!(e.contains("speed_m_per_s"), "{e}");
        let e = load("paper-4.2", &["model=beam".into()]).unwrap_err();
        assert!(e.contains("run.model"), "{e}");
        assert_eq!(load("paper-4.2", &[]).unwrap().law().unwrap(), Law::Paper);
        let s = load("paper-4.2", &["law=gap-loop".into()]).unwrap();
        assert!(matches!(s.law().unwrap(), Law::GapLoop(g) if g.kp < 0.0));
        let e = load("paper-4.2", &["law=pid".into()]).unwrap_err();
        assert!(e.contains("controller.law"), "{e}");
        let s = load("paper-4.2", &["scheme=accurate".into()]).unwrap();
        assert_eq!(s.controller_params().unwrap().scheme, Scheme::Accurate);
        assert_eq!(
            load("paper-4.2", &[])
                .unwrap()
                .controller_params()
                .unwrap()
                .scheme,
            Scheme::Paper
        );
        let e = load("paper-4.2", &["scheme=exact".into()]).unwrap_err();
        assert!(e.contains("controller.scheme"), "{e}");
        let e = load("nonexistent-scenario", &[]).unwrap_err();
        assert!(e.contains("paper-4.2"), "{e}");
    }

    #[test]
    fn units_are_converted_at_the_edge() {
        let s = load("paper-4.2", &[]).unwrap();
        assert_eq!(s.bridge().section, BeamSection::paper_4_2());
        let f = s.fig1().unwrap();
        assert_eq!(f.body_mass, 15_000.0);
        assert_eq!(f.jy, 950e3);
        // (25 + 15)/100 + 0.1
        assert!((s.t_end() - 0.5).abs() < 1e-12);
    }
}
