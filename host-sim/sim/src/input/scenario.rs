//! Scenarios as written: TOML files whose every key names its unit, bundled ones by name,
//! `--set` overrides. Nothing here converts or checks values; [`crate::input::case::Case::new`]
//! resolves a scenario to SI and checks it, once.

use crate::{Error, Result};
use maglev_core::gap::Geometry;
use maglev_core::law::guidance::GuidanceParams;
use maglev_core::law::state::StateParams;
use maglev_core::{LawName, Params};
use serde::{Deserialize, Serialize};

/// Bundled scenarios: (name, TOML text).
pub const BUNDLED: [(&str, &str); 8] = [
    ("paper-4.2", include_str!("../../scenarios/paper-4.2.toml")),
    ("paper-5", include_str!("../../scenarios/paper-5.toml")),
    (
        "train-forces",
        include_str!("../../scenarios/train-forces.toml"),
    ),
    (
        "moving-force",
        include_str!("../../scenarios/moving-force.toml"),
    ),
    ("unit", include_str!("../../scenarios/unit.toml")),
    (
        "paper-5-quake",
        include_str!("../../scenarios/paper-5-quake.toml"),
    ),
    (
        "paper-5-settled",
        include_str!("../../scenarios/paper-5-settled.toml"),
    ),
    (
        "paper-5-hsr",
        include_str!("../../scenarios/paper-5-hsr.toml"),
    ),
];

/// Short `--set` keys and the scenario key each stands for.
pub const SHORT_KEYS: [(&str, &str); 13] = [
    ("train", "train.kind"),
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
    crate::physics::modal::DEFAULT_MODES
}
fn default_tolerance() -> f64 {
    1e-9
}
fn default_max_iterations() -> u32 {
    50
}

/// The keys of a Timoshenko beam section, in their units: the girders' (in `[bridge]`) and the
/// piers' (in `[bridge.pier]`), each beside its section's own keys ([`WithSection`]).
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct BeamSectionKeys {
    pub youngs_modulus_kN_per_m2: f64,
    pub shear_modulus_kN_per_m2: f64,
    pub area_m2: f64,
    pub shear_area_y_m2: f64,
    pub shear_area_z_m2: f64,
    pub iy_m4: f64,
    pub iz_m4: f64,
    pub torsion_constant_m4: f64,
    pub mass_t_per_m: f64,
}

/// `[bridge]`: the spans and the girders' section (docs/model.md §9).
pub type BridgeSection = WithSection<BridgeKeys>;

/// `[bridge]`'s own keys; the girders' section is its [`BeamSectionKeys`].
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct BridgeKeys {
    pub spans_m: Vec<f64>,
    pub polar_mass_t_m2_per_m: Option<f64>,
    /// `spans` (independent simply supported spans on rigid supports, the default) or
    /// `viaduct` (the girders above on bearings, piers and footings: docs/viaduct.md; needs
    /// `[bridge.bearings]`, `[bridge.pier]`, `[bridge.footing]` and the top-level `[soil]`).
    #[serde(default)]
    pub kind: BridgeKind,
    /// Rayleigh damping of the FE spans (`[bridge.damping]`); none by default (the paper's).
    pub damping: Option<DampingSection>,
    pub bearings: Option<BearingsSection>,
    pub pier: Option<PierSection>,
    pub footing: Option<FootingSection>,
}

/// `[bridge.damping]`: Rayleigh damping `C = α·M + β·K` of the FE spans, given as the damping
/// ratio it has at two frequencies (equal at both, lower between, higher outside).
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct DampingSection {
    pub ratio: f64,
    pub f1_Hz: f64,
    pub f2_Hz: f64,
}

/// `bridge.kind`.
#[derive(Deserialize, Serialize, Debug, Clone, Copy, Default, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum BridgeKind {
    #[default]
    Spans,
    Viaduct,
}

/// `[bridge.bearings]`: the two bearings at each girder end (docs/viaduct.md).
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct BearingsSection {
    /// Vertical stiffness of one bearing.
    pub vertical_kN_per_m: f64,
    /// Lateral spacing of the two bearings of an end.
    pub spacing_m: f64,
    /// Lateral stiffness of a girder end.
    pub lateral_kN_per_m: f64,
    /// Longitudinal stiffness of the fixed (left) end; the right end slides.
    pub longitudinal_kN_per_m: f64,
    /// Height of the girder centroid above the bearing point.
    pub drop_m: f64,
}

/// `[bridge.pier]`: a vertical Timoshenko column (`iz_m4` bends it laterally, `iy_m4`
/// longitudinally; `shear_area_y_m2` lateral, `shear_area_z_m2` longitudinal shear).
pub type PierSection = WithSection<PierKeys>;

/// `[bridge.pier]`'s own keys; the column's section is its [`BeamSectionKeys`].
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct PierKeys {
    pub height_m: f64,
    pub elements: usize,
    pub cap_mass_t: f64,
}

/// A section whose table holds its own keys (`T`) and a beam section's
/// ([`BeamSectionKeys`]), both refusing any other key.
///
/// Why by hand: serde's `#[serde(flatten)]` would share the beam keys, but it cannot be
/// combined with `deny_unknown_fields`, and a flattened key's wrong value loses its name
/// ("expected f64 in `bridge`"). Here the table is split by the two structs' own key lists,
/// each half is read by toml (which names the key), and a key neither knows is refused with
/// serde's words, listing both halves' keys (docs/scenarios.md and
/// `tests/scenario_keys.rs` read that list).
#[derive(Serialize, Debug, Clone)]
pub struct WithSection<T> {
    #[serde(flatten)]
    pub own: T,
    #[serde(flatten)]
    pub section: BeamSectionKeys,
}

impl<T> std::ops::Deref for WithSection<T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.own
    }
}

impl<T> std::ops::DerefMut for WithSection<T> {
    fn deref_mut(&mut self) -> &mut T {
        &mut self.own
    }
}

impl<'de, T: serde::de::DeserializeOwned> Deserialize<'de> for WithSection<T> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let (own, section) = split_table(d)?;
        Ok(WithSection { own, section })
    }
}

/// One table read into two structs, each taking its own keys (serde's `flatten` and
/// `deny_unknown_fields` do not combine): a key neither knows is refused as serde refuses one,
/// naming every key of both.
fn split_table<'de, D, A, B>(d: D) -> std::result::Result<(A, B), D::Error>
where
    D: serde::Deserializer<'de>,
    A: serde::de::DeserializeOwned,
    B: serde::de::DeserializeOwned,
{
    use serde::de::Error as _;
    let mut own = toml::Table::deserialize(d)?;
    let (own_keys, other_keys) = (keys_of::<A>(), keys_of::<B>());
    let known = |k: &str| own_keys.contains(&k) || other_keys.contains(&k);
    if let Some(k) = own.keys().find(|k| !known(k)) {
        let all: Vec<String> = own_keys
            .iter()
            .chain(other_keys)
            .map(|k| format!("`{k}`"))
            .collect();
        return Err(D::Error::custom(format!(
            "unknown field `{k}`, expected one of {}",
            all.join(", ")
        )));
    }
    let other: toml::Table = other_keys
        .iter()
        .filter_map(|k| own.remove_entry(*k))
        .collect();
    let a = A::deserialize(toml::Value::Table(own));
    let b = B::deserialize(toml::Value::Table(other));
    match (a, b) {
        (Ok(a), Ok(b)) => Ok((a, b)),
        // serde names a wrong value before a missing key; so does this, across the halves.
        (Err(a), Err(b)) if a.to_string().starts_with("missing field") => Err(D::Error::custom(b)),
        (Err(e), _) | (_, Err(e)) => Err(D::Error::custom(e)),
    }
}

/// The keys of struct `T` as serde's derive names them (the list its "expected one of …"
/// gives): the `fields` its `Deserialize` passes to `deserialize_struct`.
fn keys_of<T: serde::de::DeserializeOwned>() -> &'static [&'static str] {
    use serde::de::{value::Error, Error as _, Visitor};
    struct Fields(&'static [&'static str]);
    impl<'de> serde::Deserializer<'de> for &mut Fields {
        type Error = Error;
        fn deserialize_any<V: Visitor<'de>>(self, _: V) -> std::result::Result<V::Value, Error> {
            Err(Error::custom("not a struct"))
        }
        fn deserialize_struct<V: Visitor<'de>>(
            self,
            _: &'static str,
            fields: &'static [&'static str],
            _: V,
        ) -> std::result::Result<V::Value, Error> {
            self.0 = fields;
            Err(Error::custom("only the keys were asked for"))
        }
        serde::forward_to_deserialize_any! {
            bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
            option unit unit_struct newtype_struct seq tuple tuple_struct map enum identifier
            ignored_any
        }
    }
    let mut f = Fields(&[]);
    let _ = T::deserialize(&mut f);
    f.0
}

/// `[bridge.footing]`: a rigid rectangular concrete footing under each pier.
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct FootingSection {
    pub along_x_m: f64,
    pub across_y_m: f64,
    pub thickness_m: f64,
    pub density_t_per_m3: f64,
}

/// `[soil]`: the homogeneous half-space under the viaduct, once for both the footings
/// (Gazetas' impedances, docs/viaduct.md) and the ground between them (the Green's function
/// of `[ground]`, docs/ground.md).
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct SoilSection {
    pub shear_wave_velocity_m_per_s: f64,
    pub density_t_per_m3: f64,
    pub poisson: f64,
    /// Hysteretic damping ratio ξ of the soil (μ* = μ(1 + 2iξ)); needed by `[ground]`.
    pub damping_ratio: Option<f64>,
}

/// `[ground]`: receivers on the ground surface whose vertical velocity a viaduct run writes
/// to ground.csv (docs/ground.md): `receivers` (points `[x, y]`, m) or `distances_m` across
/// the line at pier `pier`.
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct GroundSection {
    pub receivers: Option<Vec<[f64; 2]>>,
    pub distances_m: Option<Vec<f64>>,
    pub pier: Option<usize>,
}

/// `[vehicle]` / `[train]`: what runs over the guideway, by `kind`. Each kind's keys are a
/// struct of their own, read after the tag ([`VehicleSection::from_table`]), so a wrong value
/// is named by its key (`vehicle.body_mass_t`), not only by the section.
#[derive(Serialize, Debug, Clone)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum VehicleSection {
    Fig1(Fig1Keys),
    MovingForce(MovingForceKeys),
    /// The paper's §5 maglev train: `cars` Fig. 6 carriages at their pitch (docs/cars.md),
    /// every magnet with its own controller (`[controller]`).
    Maglev(MaglevKeys),
    /// The paper's §5 wheel/rail train: `cars` cars of 25 m on Hertz contacts (docs/cars.md).
    WheelRail(WheelRailKeys),
    /// A train of 3-D high-speed cars on the `[track]` (docs/cars.md, "The 3-D car in a
    /// run").
    HighSpeed(HighSpeedKeys),
    /// Constant vertical moving loads (`[train] kind = "forces"`): one car's loads, repeated.
    Forces(ForcesKeys),
    /// One levitation magnet carrying a body through a spring and a damper (`kind = "unit"`),
    /// for the levitation analysis and standstill runs (docs/levitation.md).
    Unit(UnitKeys),
}

/// `kind = "fig1"`: the Fig. 1 car (docs/model.md §5).
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct Fig1Keys {
    pub body_mass_t: f64,
    pub jx_t_m2: f64,
    pub jy_t_m2: f64,
    pub jz_t_m2: f64,
    pub spring_kN_per_m: f64,
    pub damper_kN_s_per_m: f64,
    pub half_length_m: f64,
    pub half_width_m: f64,
    pub offset_y_m: f64,
    pub target_height_m: f64,
    pub body_height_m: f64,
    pub wheel_mass_kg: f64,
    /// X of the leading wheel at t = 0 (m from the left end of span 1; default 0: the
    /// paper's passage starts with it over the first support).
    #[serde(default, skip_serializing_if = "crate::physics::vehicle::is_zero")]
    pub position_m: f64,
    /// How the magnets face their rails (docs/model.md §2); default `paper`.
    #[serde(default)]
    pub geometry: Geometry,
    /// Identical cars, one behind the other (default 1).
    #[serde(default = "one")]
    pub repeat: usize,
    /// Spacing of the repeated cars, leading wheel to leading wheel (m); needed when
    /// `repeat > 1`, at least the wheelbase `2·half_length_m`.
    pub car_length_m: Option<f64>,
}

/// `kind = "moving-force"`: one constant vertical force.
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct MovingForceKeys {
    pub force_kN: f64,
    pub offset_y_m: f64,
    pub offset_z_m: f64,
}

/// `kind = "maglev"`.
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct MaglevKeys {
    #[serde(default = "twelve")]
    pub cars: usize,
    /// Mass of each magnet node (kg); default 0, the paper's massless nodes (docs/cars.md).
    #[serde(default)]
    pub wheel_mass_kg: f64,
    /// How the magnets face their rails (docs/model.md §2); default `paper`.
    #[serde(default)]
    pub geometry: Geometry,
}

/// `kind = "wheel-rail"`.
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct WheelRailKeys {
    #[serde(default = "twelve")]
    pub cars: usize,
}

/// `kind = "high-speed"`: `cars` 3-D high-speed cars (`physics::rail::car`) on `[track]`.
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct HighSpeedKeys {
    #[serde(default = "twelve")]
    pub cars: usize,
    /// Distance between car centres (m); default 25.
    #[serde(default = "car_pitch")]
    pub car_length_m: f64,
    /// Equivalent conicity of the wheel–rail pair; default the car's 0.05.
    pub conicity: Option<f64>,
    /// Wheel–rail friction coefficient; default 0.3.
    pub friction: Option<f64>,
    /// RK4 sub-steps of the cars per time step; default 4 (on the track, the wheel on the
    /// rail's mass needs dt/substeps ≤ 0.5 ms, `physics::rail::run::MAX_CONTACT_STEP`).
    #[serde(default = "four")]
    pub substeps: usize,
}

fn car_pitch() -> f64 {
    25.0
}

fn four() -> usize {
    4
}

/// `[track]`: the rails on their fastenings over a slab on the deck (`physics::rail::track`),
/// where they lie on the girder, and the spectrum of their irregularity.
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct TrackSection {
    pub rail_bending_stiffness_N_m2: f64,
    pub rail_mass_kg_per_m: f64,
    pub pad_stiffness_N_per_m: f64,
    pub pad_spacing_m: f64,
    pub pad_damping_N_s_per_m: f64,
    pub slab_bending_stiffness_N_m2: f64,
    pub slab_mass_kg_per_m: f64,
    pub mortar_modulus_N_per_m2: f64,
    pub mortar_mass_kg_per_m: f64,
    /// Y of the track centre and Z of the rail heads from the beam axis (m).
    pub track_y_m: f64,
    pub rail_z_m: f64,
    /// The rails' irregularity under `[irregularity]`: `german-low`, `german-high` or
    /// `chinese` (`physics::rail::spectrum`).
    pub spectrum: String,
}

/// `kind = "forces"`.
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct ForcesKeys {
    /// One car's loads (kN, downward).
    pub loads_kN: Vec<f64>,
    /// Each load's distance behind the car's leading load (m).
    pub offsets_m: Vec<f64>,
    /// Identical cars, one behind the other (default 1).
    #[serde(default = "one")]
    pub repeat: usize,
    /// Spacing of the repeated cars (m); needed when `repeat > 1`.
    pub car_length_m: Option<f64>,
    /// Offset of the loads from the beam axis, Y and Z (m); default on the axis.
    #[serde(default)]
    pub offset_y_m: f64,
    #[serde(default)]
    pub offset_z_m: f64,
}

/// `kind = "unit"`: one magnet of `magnet_mass_kg` carrying a body of `body_mass_t` through a
/// spring and a damper, static load (magnet + body)·g, at `position_m` along the guideway.
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct UnitKeys {
    pub magnet_mass_kg: f64,
    /// The body (t); 0, the default, leaves the magnet alone.
    #[serde(default)]
    pub body_mass_t: f64,
    /// Magnet–body spring and damper; needed with a body.
    #[serde(default)]
    pub spring_kN_per_m: f64,
    #[serde(default)]
    pub damper_kN_s_per_m: f64,
    /// Where the magnet stands at t = 0 along the guideway (m from the left end of span 1);
    /// it moves on at `run.speed_m_per_s` (0: standstill).
    #[serde(default)]
    pub position_m: f64,
    /// How the magnet faces its rail (docs/model.md §2); default `ems`.
    #[serde(default = "ems")]
    pub geometry: Geometry,
}

fn ems() -> Geometry {
    Geometry::Ems
}

/// The `kind` words, in the enum's order.
const VEHICLE_KINDS: &[&str] = &[
    "fig1",
    "moving-force",
    "maglev",
    "wheel-rail",
    "high-speed",
    "forces",
    "unit",
];

impl VehicleSection {
    /// The section from its table: the `kind` tag, then that kind's keys, each error naming
    /// the key it is about (`invalid type: … in `body_mass_t``).
    fn from_table(mut t: toml::Table) -> std::result::Result<Self, String> {
        use serde::de::Error as _;
        let kind = match t.remove("kind") {
            Some(toml::Value::String(k)) => k,
            Some(other) => return Err(format!("kind: expected a string, got {other}")),
            None => return Err(toml::de::Error::missing_field("kind").to_string()),
        };
        // toml's own deserializer names the key of a wrong value ("… in `body_mass_t`").
        fn keys<T: serde::de::DeserializeOwned>(t: toml::Table) -> std::result::Result<T, String> {
            T::deserialize(toml::Value::Table(t)).map_err(|e| e.to_string())
        }
        Ok(match kind.as_str() {
            "fig1" => VehicleSection::Fig1(keys(t)?),
            "moving-force" => VehicleSection::MovingForce(keys(t)?),
            "maglev" => VehicleSection::Maglev(keys(t)?),
            "wheel-rail" => VehicleSection::WheelRail(keys(t)?),
            "high-speed" => VehicleSection::HighSpeed(keys(t)?),
            "forces" => VehicleSection::Forces(keys(t)?),
            "unit" => VehicleSection::Unit(keys(t)?),
            other => return Err(toml::de::Error::unknown_variant(other, VEHICLE_KINDS).to_string()),
        })
    }
}

impl<'de> Deserialize<'de> for VehicleSection {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let table = toml::Table::deserialize(d)?;
        VehicleSection::from_table(table).map_err(serde::de::Error::custom)
    }
}

fn one() -> usize {
    1
}

fn twelve() -> usize {
    12
}

/// `[controller]`: the magnet, its coil and the paper's law in the core's own type (the keys
/// `i0_A` … `vmax_V`, `scheme` are [`Params`]' serde names; its `p0` and `dt` are the vehicle's
/// and the run's), and the law with its section.
#[derive(Serialize, Debug, Clone)]
pub struct ControllerSection {
    /// The magnet, coil and paper's law (`p0` and `dt` as read: 1 N, 0 s).
    #[serde(flatten)]
    pub magnet: Params,
    #[serde(flatten)]
    pub law: LawSection,
}

/// `[controller]`'s keys beyond the magnet's: the law and its section.
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct LawSection {
    /// `paper` (Eq. 8–14 alone, the default), `gap-loop` (the outer gap loop of
    /// `maglev_core::gap_control` at its designed gains around the paper's law) or `state`
    /// (state feedback with the gains of `[controller.state]`).
    #[serde(default)]
    pub law: LawName,
    /// The state law's gains and timing (`[controller.state]`), used when `law = "state"`.
    pub state: Option<StateSection>,
    /// The guidance pairs' own law under the state law (`[controller.guidance]`); absent,
    /// each guidance magnet runs the levitation law on its own gap.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub guidance: Option<GuidanceSection>,
}

/// `[controller.guidance]`: the guidance law's five gains in the core's own type (units in
/// the keys, `maglev_core::law::guidance::GuidanceParams`), or `design = true` alone to have
/// them designed from the case's vehicle (docs/levitation.md). Timing and supply are
/// `[controller.state]`'s.
#[derive(Serialize, Debug, Clone, Copy, PartialEq)]
#[serde(untagged)]
pub enum GuidanceSection {
    /// The gains as given.
    Gains(GuidanceParams),
    /// `design = true`.
    Design { design: bool },
}

/// The keys of `[controller.guidance]`: the core's gains as `GuidanceParams` spells them
/// (checked by a test), and `design`.
const GUIDANCE_KEYS: &[&str] = &[
    "kp_V_per_m",
    "kd_V_s_per_m",
    "ka_V_s2_per_m",
    "ki_V_per_m_s",
    "kc_V_per_A",
    "design",
];

impl<'de> Deserialize<'de> for GuidanceSection {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        use serde::de::Error as _;
        let mut table = toml::Table::deserialize(d)?;
        if let Some(k) = table.keys().find(|k| !GUIDANCE_KEYS.contains(&k.as_str())) {
            return Err(D::Error::unknown_field(k, GUIDANCE_KEYS));
        }
        match table.remove("design") {
            Some(toml::Value::Boolean(true)) => match table.keys().next() {
                Some(k) => Err(D::Error::custom(format!(
                    "{k}: is designed with design = true; give the gains or design, not both"
                ))),
                None => Ok(GuidanceSection::Design { design: true }),
            },
            Some(toml::Value::Boolean(false)) | None => {
                GuidanceParams::deserialize(toml::Value::Table(table))
                    .map(GuidanceSection::Gains)
                    .map_err(D::Error::custom)
            }
            Some(v) => Err(D::Error::custom(format!(
                "design: must be true or false, got {v}"
            ))),
        }
    }
}

impl<'de> Deserialize<'de> for ControllerSection {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let (magnet, law) = split_table(d)?;
        Ok(ControllerSection { magnet, law })
    }
}

/// `[controller.state]`: the state law's gains (units in the keys, as
/// `maglev_core::law::state::StateParams` names them), or `design = true` to have them
/// designed from the case's plant (docs/levitation.md); timing and supply either way.
#[derive(Deserialize, Serialize, Debug, Clone, Copy)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct StateSection {
    pub kp_V_per_m: Option<f64>,
    pub kd_V_s_per_m: Option<f64>,
    pub ka_V_s2_per_m: Option<f64>,
    pub ki_V_per_m_s: Option<f64>,
    pub kc_V_per_A: Option<f64>,
    pub vmax_V: f64,
    #[serde(default = "rate")]
    pub rate_Hz: f64,
    #[serde(default = "observer")]
    pub observer_Hz: f64,
    #[serde(default)]
    pub design: bool,
}

fn rate() -> f64 {
    StateParams::RATE_HZ
}

fn observer() -> f64 {
    StateParams::OBSERVER_HZ
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
    /// The half-space under the viaduct (`[soil]`).
    pub soil: Option<SoilSection>,
    /// Ground receivers (`[ground]`).
    pub ground: Option<GroundSection>,
    /// Ground motion and settlement at the viaduct's piers or the spans' bearings (`[support]`, docs/seismic.md).
    pub support: Option<crate::input::support::SupportSection>,
    /// The magnets' skid contact with their rails (`[contact]`, docs/contact.md).
    pub contact: Option<ContactSection>,
    /// The track of a `high-speed` train (`[track]`).
    pub track: Option<TrackSection>,
}

/// `[contact]`: where and how a magnet lands on its rail (docs/contact.md); every key has a
/// default (`crate::physics::skid::Skid::DEFAULT`).
#[derive(Deserialize, Serialize, Debug, Clone, Default)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct ContactSection {
    pub skid_gap_m: Option<f64>,
    pub setdown_gap_m: Option<f64>,
    pub stiffness_MN_per_m: Option<f64>,
    pub damping_kN_s_per_m: Option<f64>,
    pub friction: Option<f64>,
    pub slip_regularisation_m_per_s: Option<f64>,
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

/// Loads a scenario by bundled name or path and applies `key=value` overrides (not checked:
/// [`crate::input::case::Case::new`] does that).
pub fn load(name_or_path: &str, sets: &[String]) -> Result<Scenario> {
    let text = match BUNDLED.iter().find(|(n, _)| *n == name_or_path) {
        Some((_, t)) => t.to_string(),
        None => crate::input::read_text(std::path::Path::new(name_or_path)).map_err(|e| {
            let names: Vec<&str> = BUNDLED.iter().map(|(n, _)| *n).collect();
            Error::invalid(
                "scenario",
                format!(
                    "`{name_or_path}` is neither a bundled name ({}) nor a readable file: {e}",
                    names.join(", ")
                ),
            )
        })?,
    };
    parse(&text, name_or_path, sets)
}

/// Parses scenario text with overrides.
pub fn parse(text: &str, name: &str, sets: &[String]) -> Result<Scenario> {
    let text = crate::input::toml_within_cap(&format!("scenario {name}"), text)?;
    let mut table: toml::Table = toml::from_str(text)
        .map_err(|e| Error::parse(format!("scenario {name}"), one_line(&e.to_string())))?;
    let base = table.clone();
    for set in sets {
        apply_set(&mut table, set)?;
    }
    table.try_into().map_err(|e: toml::de::Error| {
        // Name the override that made the text unreadable, when one did: serde's path stops
        // at the table for an enum's variant (`in vehicle` for `--set geometry=foo`).
        let culprit = (0..sets.len()).find(|&i| {
            let mut t = base.clone();
            sets[..=i].iter().all(|s| apply_set(&mut t, s).is_ok())
                && t.try_into::<Scenario>().is_err()
        });
        let what = match culprit {
            Some(i) => {
                let key = sets[i]
                    .split_once('=')
                    .map_or(&sets[i][..], |(k, _)| k.trim());
                match full_key(key) {
                    full if full != key => format!("--set {key} ({full}), scenario {name}"),
                    _ => format!("--set {key}, scenario {name}"),
                }
            }
            None => format!("scenario {name}"),
        };
        Error::parse(what, one_line(&e.to_string()))
    })
}

/// toml's error on one line, with the key it names written whole: a section read by hand
/// ([`WithSection`], [`VehicleSection`]) makes toml name its key in parts, innermost first
/// ("… in `iy_m4` in `pier` in `bridge`"), and this joins them as the rest of the reader
/// names a key ("… in `bridge.pier.iy_m4`").
fn one_line(s: &str) -> String {
    let s = s.split_whitespace().collect::<Vec<_>>().join(" ");
    let mut parts: Vec<&str> = s.split(" in `").collect();
    let is_key =
        |p: &&&str| p.len() > 1 && p.ends_with('`') && !p[..p.len() - 1].contains(['`', ' ']);
    let keys = parts.iter().skip(1).rev().take_while(is_key).count();
    if keys < 2 {
        return s;
    }
    let path: Vec<&str> = parts
        .drain(parts.len() - keys..)
        .rev()
        .map(|p| &p[..p.len() - 1])
        .collect();
    format!("{} in `{}`", parts.join(" in `"), path.join("."))
}

/// `section.key` of a `--set` key: a short key's full name, any other key as written.
fn full_key(key: &str) -> &str {
    SHORT_KEYS
        .iter()
        .find(|(s, _)| *s == key)
        .map_or(key, |(_, f)| *f)
}

/// Most names a `--set` key joins by dots: one more than the deepest table key today
/// (`bridge.pier.height_m`), so a sub-table added later still fits; a list entry's key
/// (`support.settlement.1.dz_m`) takes them all. A deeper key is refused
/// before any table is made: one of 60 000 names nested tables that deep and overflowed the
/// stack when they were read (the input fuzz target's finding).
pub const MAX_KEY_PARTS: usize = 4;

fn apply_set(table: &mut toml::Table, set: &str) -> Result<()> {
    // One override is one line: a newline would let the value's TOML carry more keys.
    if set.contains(['\n', '\r']) {
        return Err(Error::invalid(
            format!("--set `{}`", set.escape_default()),
            "must be one line (key=value, no newline)",
        ));
    }
    let (key, value) = set
        .split_once('=')
        .ok_or_else(|| Error::invalid(format!("--set `{set}`"), "expected key=value"))?;
    let key = key.trim();
    let full = full_key(key);
    let parts = full.split('.').count();
    if parts > MAX_KEY_PARTS || full.split('.').any(|p| p.trim().is_empty()) {
        return Err(Error::invalid(
            format!("--set {key}"),
            format!(
                "a key is at most {MAX_KEY_PARTS} names joined by dots (section.table.key), \
                 none of them empty; got {parts}"
            ),
        ));
    }
    let (section, field) = full.split_once('.').ok_or_else(|| {
        let shorts: Vec<&str> = SHORT_KEYS.iter().map(|(s, _)| *s).collect();
        Error::invalid(
            format!("--set {key}"),
            format!(
                "unknown key (use one of {} or section.key)",
                shorts.join(", ")
            ),
        )
    })?;
    let value = value.trim();
    // A TOML value if it parses as one (numbers, booleans, inf), else a bare string.
    let parsed: toml::Value = toml::from_str::<toml::Table>(&format!("v = {value}"))
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| toml::Value::String(value.to_string()));
    // `[vehicle]` and `[train]` are one section under two names: use the one the text has.
    let section = match section {
        "vehicle" | "train" if table.contains_key("train") => "train",
        "vehicle" | "train" => "vehicle",
        other => other,
    };
    // `section.sub.key`: walk (or create) the tables down to the last key.
    let mut path: Vec<&str> = field.split('.').collect();
    let leaf = path.pop().unwrap_or(field);
    let mut sec = table
        .entry(section.to_string())
        .or_insert_with(|| toml::Value::Table(toml::Table::new()))
        .as_table_mut()
        .ok_or_else(|| Error::invalid(format!("--set {section}"), "is not a section"))?;
    // A list of tables (`[[support.settlement]]`) is entered by an entry's number, from 1
    // (`support.settlement.1.dz_m`), so a sweep can vary one key of one entry.
    let at = |depth: usize| [&[section][..], &path[..=depth]].concat().join(".");
    let mut names = path.iter().enumerate();
    while let Some((depth, name)) = names.next() {
        let next = path.get(depth + 1).copied().unwrap_or(leaf);
        if !sec.contains_key(*name) && next.parse::<usize>().is_ok() {
            return Err(Error::invalid(
                format!("--set {}", at(depth)),
                format!(
                    "the scenario has no list {} to take entry {next} of (a list entry is set \
                     by its number only where the scenario writes the list, e.g. \
                     [[{}]])",
                    at(depth),
                    at(depth)
                ),
            ));
        }
        let value = sec
            .entry(name.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        let (depth, table) = match value {
            toml::Value::Array(list) => {
                let len = list.len();
                let wrong = |d: usize| {
                    Error::invalid(
                        format!("--set {}", at(d)),
                        format!(
                            "{} is a list of {len} entries: name one by its number, 1 to {len}, \
                             then its key ({}.1.KEY)",
                            at(depth),
                            at(depth)
                        ),
                    )
                };
                let (d, number) = names.next().ok_or_else(|| wrong(depth))?;
                let i = number
                    .parse::<usize>()
                    .ok()
                    .filter(|i| (1..=len).contains(i))
                    .ok_or_else(|| wrong(d))?;
                (d, list[i - 1].as_table_mut())
            }
            other => (depth, other.as_table_mut()),
        };
        sec = table
            .ok_or_else(|| Error::invalid(format!("--set {}", at(depth)), "is not a section"))?;
    }
    // Integers given where floats are expected (speed=100) are fine for serde; floats given
    // for integers are not, which is the error we want.
    sec.insert(leaf.to_string(), parsed);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `[controller.guidance]`'s keys are the core's `GuidanceParams` keys and `design`.
    #[test]
    fn the_guidance_keys_are_the_cores() {
        let core: Vec<&str> = GuidanceParams::default()
            .gains()
            .map(|(f, _)| f.key.unwrap())
            .to_vec();
        assert_eq!(core, GUIDANCE_KEYS[..5]);
        assert_eq!(GUIDANCE_KEYS[5], "design");
    }

    #[test]
    fn overrides_reach_their_keys_and_unknown_keys_are_named() {
        let s = load("paper-4.2", &["speed=150".into(), "model=modal".into()]).unwrap();
        assert_eq!(s.run.speed_m_per_s, 150.0);
        assert_eq!(s.run.model, Model::Modal);
        for (set, key) in [
            ("colour=red", "colour"),
            ("run.sped=3", "sped"),
            ("model=beam", "run.model"),
            ("law=pid", "controller.law"),
            ("scheme=exact", "controller.scheme"),
            ("geometry=foo", "--set geometry (vehicle.geometry)"),
            ("run.elements_per_span=4.5", "--set run.elements_per_span"),
        ] {
            let e = load("paper-4.2", &[set.into()]).unwrap_err().to_string();
            assert!(e.contains(key), "{set}: {e}");
            assert!(!e.contains('\n'), "{set}: {e}");
        }
        let e = load("nonexistent-scenario", &[]).unwrap_err().to_string();
        assert!(e.contains("paper-4.2"), "{e}");
    }

    /// `paper-5-quake` and `paper-5-settled` write out paper-5's viaduct and run again (a
    /// bundled scenario is one self-contained file): they must stay paper-5's. The quake one
    /// differs only by `[support]`; the settled one also runs its own train and law.
    #[test]
    fn the_paper_5_variants_keep_paper_5s_viaduct() {
        let table = |name: &str| -> toml::Table {
            toml::from_str(BUNDLED.iter().find(|(n, _)| *n == name).unwrap().1).unwrap()
        };
        let p5 = table("paper-5");
        for (name, own) in [
            ("paper-5-quake", &["support"][..]),
            (
                "paper-5-settled",
                &["support", "train", "controller", "output"][..],
            ),
            (
                "paper-5-hsr",
                &["train", "controller", "track", "output"][..],
            ),
        ] {
            let v = table(name);
            let keys: std::collections::BTreeSet<&String> = p5.keys().chain(v.keys()).collect();
            for key in keys {
                if !own.contains(&key.as_str()) {
                    assert_eq!(
                        p5.get(key),
                        v.get(key),
                        "{name}: [{key}] differs from paper-5"
                    );
                }
            }
        }
    }

    /// `[[support.settlement]]` entries are reached by their number from 1; a number outside
    /// the list, a name that is not a number, or the entry itself as the key is one line naming
    /// the key and the range.
    #[test]
    fn a_list_entry_is_reached_by_its_number() {
        let settled = "paper-5-settled";
        let s = load(settled, &["support.settlement.1.dz_m=-0.03".into()]).unwrap();
        let list = &s.support.as_ref().unwrap().settlement;
        assert_eq!((list.len(), list[0].dz_m), (1, -0.03));
        for (set, named) in [
            ("support.settlement.2.dz_m=-0.03", "support.settlement.2"),
            ("support.settlement.0.dz_m=-0.03", "support.settlement.0"),
            ("support.settlement.x.dz_m=-0.03", "support.settlement.x"),
            ("support.settlement.1=3", "support.settlement"),
        ] {
            let e = load(settled, &[set.into()]).unwrap_err().to_string();
            assert!(e.starts_with(&format!("--set {named}:")), "{set}: {e}");
            assert!(
                e.contains("a list of 1 entries") && e.contains("1 to 1"),
                "{e}"
            );
            assert!(!e.contains('\n'), "{e}");
        }
        // Where the scenario has no list, a number after its name is refused naming the list.
        let e = load("paper-5", &["support.settlement.1.dz_m=-0.03".into()])
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("--set support.settlement:") && e.contains("no list"),
            "{e}"
        );
        assert!(!e.contains('\n'), "{e}");
    }

    /// A key of 60 000 names once nested tables so deep that reading them overflowed the
    /// stack (an abort, found by the input fuzz target); empty names made tables named "".
    #[test]
    fn deep_or_empty_keys_are_refused_in_one_short_line() {
        let deep = format!("run.{}=1", vec!["a"; 60_000].join("."));
        for set in [
            deep.as_str(),
            "run..dt_s=1",
            "run.dt_s.=1",
            "bridge.pier.a.b.c=1",
        ] {
            let e = load("paper-4.2", &[set.into()]).unwrap_err().to_string();
            assert!(
                e.starts_with("--set ") && e.contains("at most 4 names"),
                "{e}"
            );
            assert!(!e.contains('\n') && e.len() < 400, "{}", e.len());
        }
        // The deepest keys there are still work.
        load("paper-5", &["bridge.pier.height_m=12".into()]).unwrap();
    }

    /// A wrong value inside the tagged `[vehicle]` / `[train]` section is named by its key, as
    /// in every other section (serde's internally tagged enums lose it: "in `vehicle`" only).
    #[test]
    fn a_wrong_vehicle_value_in_a_file_names_its_key() {
        for (name, text) in BUNDLED {
            let (key, bad) = match name {
                "paper-4.2" => ("body_mass_t", "body_mass_t = \"x\""),
                "paper-5" | "paper-5-quake" | "paper-5-settled" | "paper-5-hsr" => {
                    ("cars", "cars = -3")
                }
                "train-forces" => ("loads_kN", "loads_kN = 5"),
                "unit" => ("magnet_mass_kg", "magnet_mass_kg = true"),
                _ => ("force_kN", "force_kN = [1]"),
            };
            let line = text
                .lines()
                .find(|l| l.starts_with(&format!("{key} ")))
                .unwrap_or_else(|| panic!("{name} has no {key} line"));
            let e = parse(&text.replace(line, bad), name, &[])
                .unwrap_err()
                .to_string();
            let section = if text.contains("[train]") {
                "train"
            } else {
                "vehicle"
            };
            assert!(e.contains(&format!("`{section}.{key}`")), "{name}: {e}");
        }
    }

    /// The beam section's keys, read beside `[bridge]`'s and `[bridge.pier]`'s own
    /// ([`WithSection`]): a wrong value and an unknown key are named whole, in a file and by
    /// `--set`, and the unknown key's error lists every key of its table.
    #[test]
    fn a_beam_section_key_is_named_whole() {
        let p5 = BUNDLED.iter().find(|(n, _)| *n == "paper-5").unwrap().1;
        for (text, sets, want) in [
            (
                p5.replace("iy_m4 = 9.96", "iy_m4 = \"x\""),
                vec![],
                "expected f64 in `bridge.iy_m4`",
            ),
            (
                p5.to_string(),
                vec!["bridge.pier.iz_m4=true"],
                "expected f64 in `bridge.pier.iz_m4`",
            ),
            (
                p5.to_string(),
                vec!["bridge.pier.height_m=[1]"],
                "expected f64 in `bridge.pier.height_m`",
            ),
            (
                p5.to_string(),
                vec!["bridge.spans_m=3"],
                "in `bridge.spans_m`",
            ),
            (
                p5.to_string(),
                vec!["bridge.damping.ratio=\"a\""],
                "in `bridge.damping.ratio`",
            ),
            (
                p5.to_string(),
                vec!["bridge.iy=1"],
                "unknown field `iy`, expected one of `spans_m`",
            ),
            (
                p5.to_string(),
                vec!["bridge.pier.iy=1"],
                "unknown field `iy`, expected one of `height_m`",
            ),
        ] {
            let sets: Vec<String> = sets.into_iter().map(String::from).collect();
            let e = parse(&text, "paper-5", &sets).unwrap_err().to_string();
            assert!(e.contains(want) && !e.contains('\n'), "{sets:?}: {e}");
        }
        for (set, section, has, not) in [
            ("bridge.zz=1", "bridge", "spans_m", "height_m"),
            ("bridge.pier.zz=1", "bridge.pier", "height_m", "spans_m"),
        ] {
            let e = parse(p5, "paper-5", &[set.into()]).unwrap_err().to_string();
            assert!(e.ends_with(&format!("in `{section}`")), "{e}");
            for key in [has, "youngs_modulus_kN_per_m2", "mass_t_per_m"] {
                assert!(e.contains(&format!("`{key}`")), "{key}: {e}");
            }
            assert!(!e.contains(&format!("`{not}`")), "{not}: {e}");
        }
        // A key left out is named; the beam's keys are as required as the section's own.
        let e = parse(&p5.replace("iz_m4 = 62.1", ""), "paper-5", &[])
            .unwrap_err()
            .to_string();
        assert!(e.contains("missing field `iz_m4`"), "{e}");
    }
}
