//! The typed case: a [`Scenario`] resolved to SI and checked, once.
//!
//! Why a second type: a scenario is what a user writes — units in the key names, optional
//! sections, a vehicle kind as a tag. Everything downstream (`run`, `hil`, `validate`, `sweep`,
//! `stability --scenario`, the benches and the tests) needs the same thing: numbers in SI that
//! have been checked against their domain and against the size limits. Converting on demand in
//! each of those places is how six conversions drift apart; here there is one, in
//! [`Case::new`], and a value that is wrong is refused with the key that holds it and the limit
//! it broke, before anything is allocated.
//!
//! Derived cases (validate's speeds, a sweep's axes) are made with [`Case::with`]: typed
//! [`Changes`] applied to the scenario as written and resolved again, so a derived case is
//! checked exactly as a loaded one and equals the case the same `--set` text would give.
//!
//! One file per section, each holding that section's one conversion, its checks and its
//! tests: `bridge.rs` (the girders, the beam section shared with the piers, damping, the FE
//! size), `viaduct.rs` (bearings, piers, footings, soil, ground receivers), `train.rs` (each
//! vehicle kind), `controller.rs` (the magnets' parameters and the law), `probes.rs`,
//! `budget.rs` (whole-case limits) and `checks.rs` (the value checks they all use). What
//! summary.json records of a case is its serialisation ([`Case::record`]): the SI types
//! carry the keys (`youngs_modulus_Pa`, …), nothing lists a section's fields a second time.

mod bridge;
mod budget;
mod changes;
mod checks;
mod contact;
mod controller;
mod probes;
mod record;
mod track;
mod train;
mod viaduct;

pub use crate::error::guidance_error;
pub use bridge::{check_fe_size, MAX_CONDITION, MAX_FE_DOFS};
pub use budget::{MAX_PROFILE_M, MAX_RECORD_BYTES, MAX_STEPS, MAX_SUB_STEPS};
pub use changes::Changes;
pub use checks::MAX_MAGNITUDE;
pub use controller::{GuidanceChoice, LawChoice};
pub use track::TrackCase;
pub use train::{fig6, high_speed_car, TrainCase, MAX_CARS, MAX_LOADS};
pub use viaduct::{soil_density, MAX_PIER_ELEMENTS, MAX_RECEIVERS};

use crate::input::scenario::{self, BridgeKind, Model, Scenario};
use crate::physics::fe::newmark::Rayleigh;
use crate::physics::fe::soil::Soil;
use crate::physics::fe::viaduct::ViaductSpec;
use crate::physics::guideway::Bridge;
use crate::physics::seismic::support::SupportMotion;
use crate::physics::train::Train;
use crate::physics::vehicle::VehicleModel;
use crate::probes::Probes;
use crate::{Error, Result};
use checks::{at_least, bounded, non_negative, positive};
use maglev_core::gap::Geometry;
use maglev_core::law::guidance::GuidanceParams;
use maglev_core::levitation::GRAVITY;
use maglev_core::{LawKind, Params};
use serde::Serialize;

/// The most modes the modal reference may keep per span (each mode is a dense vector over
/// the span's shape functions; 10⁴ is far past convergence for any span).
pub const MAX_MODES: usize = 10_000;

/// The most Newton–Raphson iterations a step may take.
pub const MAX_ITERATIONS: u32 = 100_000;

/// A scenario resolved to SI and checked (module docs). Its serialisation is summary.json's
/// `case` ([`Case::record`]).
#[derive(Clone, Debug, Serialize)]
pub struct Case {
    /// The scenario as written, after the overrides (kept so [`Case::with`] can derive).
    #[serde(skip)]
    pub scenario: Scenario,
    pub model: Model,
    /// Train speed (m/s).
    #[serde(rename = "speed_m_per_s")]
    pub speed: f64,
    /// Time step (s).
    #[serde(rename = "dt_s")]
    pub dt: f64,
    /// End time (s): as written, or the last wheel off the bridge plus 0.1 s.
    #[serde(rename = "t_end_s")]
    pub t_end: f64,
    pub elements_per_span: usize,
    pub modes: usize,
    /// Convergence tolerance on the gaps between two iterations (m).
    #[serde(rename = "tolerance_m")]
    pub tolerance: f64,
    pub max_iterations: u32,
    /// The girder section and the spans (for a viaduct: its girders).
    pub bridge: Bridge,
    /// The viaduct on piers and footings (`bridge.kind = "viaduct"`), or `None` for
    /// simply supported spans on rigid supports.
    pub viaduct: Option<ViaductSpec>,
    /// Rayleigh damping of the FE spans (`[bridge.damping]`), `None`: undamped (and not
    /// recorded, so an undamped case records what it always did).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub damping: Option<Rayleigh>,
    pub train: TrainCase,
    /// The magnets' controller (p0 is set per magnet from its car's statics); `None` for a
    /// train without magnets (forces, wheel/rail), whose scenario needs no `[controller]`.
    /// Recorded as its section ([`Case::record`]).
    #[serde(skip)]
    pub controller: Option<Params>,
    /// The levitation law, or what to design (`crate::studies::design::resolve`).
    pub law: LawChoice,
    /// The guidance pairs' law (`[controller.guidance]`), or what to design; absent from
    /// summary.json without the section.
    #[serde(skip_serializing_if = "GuidanceChoice::is_none")]
    pub guidance: GuidanceChoice,
    pub geometry: Geometry,
    /// The irregularity's seed, when the irregularity is on.
    pub irregularity_seed: Option<u64>,
    /// What response.csv records.
    #[serde(serialize_with = "record::probe_names")]
    pub probes: Probes,
    /// The half-space under the viaduct (`[soil]`), in SI.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub soil: Option<Soil>,
    /// Ground receivers `[x, y]` (m) whose vertical velocity the run writes (`[ground]`).
    #[serde(rename = "ground_receivers_m", skip_serializing_if = "Option::is_none")]
    pub ground: Option<Vec<[f64; 2]>>,
    /// The motion of the supports (`[support]`: the viaduct's footings or the spans'
    /// bearings): recorded as its section
    /// ([`Case::record`]).
    #[serde(skip)]
    pub support: Option<SupportMotion>,
    /// The magnets' skid contact (`[contact]`, docs/contact.md), in SI.
    #[serde(rename = "contact")]
    pub skid: crate::physics::skid::Skid,
    /// The track of a `high-speed` train (`[track]`), in SI.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub track: Option<TrackCase>,
}

impl Case {
    /// Loads scenario `name_or_path` (bundled name or file), applies the `key=value`
    /// overrides and resolves it.
    pub fn load(name_or_path: &str, sets: &[String]) -> Result<Case> {
        Case::new(scenario::load(name_or_path, sets)?)
    }

    /// Resolves and checks `sc` (module docs).
    pub fn new(sc: Scenario) -> Result<Case> {
        let r = &sc.run;
        // 0 is standstill (then run.t_end_s is needed below).
        let speed = non_negative("run.speed_m_per_s", r.speed_m_per_s)?;
        let dt = positive("run.dt_s", r.dt_s)?;
        let tolerance = positive("run.tolerance_m", r.tolerance_m)?;
        at_least("run.elements_per_span", r.elements_per_span, 1)?;
        bounded("run.modes", r.modes, 1, MAX_MODES)?;
        bounded(
            "run.max_iterations",
            r.max_iterations as usize,
            1,
            MAX_ITERATIONS as usize,
        )?;
        let mut bridge = bridge::bridge(&sc.bridge)?;
        let track = sc.track.as_ref().map(track::track).transpose()?;
        if let Some(t) = &track {
            // The girder carries the track's mass, on the track's centre line.
            let m = t.slab.mass_per_m();
            let s = &mut bridge.section;
            s.mass_per_length += m;
            s.polar_mass = s.polar_mass.map(|j| j + m * t.track_y * t.track_y);
        }
        let damping = sc
            .bridge
            .damping
            .as_ref()
            .map(bridge::rayleigh)
            .transpose()?;
        if damping.is_some() && (sc.run.model != Model::Fe || sc.bridge.kind != BridgeKind::Spans) {
            return Err(Error::invalid(
                "bridge.damping",
                "only the FE spans take damping (run.model = \"fe\", bridge.kind = \"spans\")",
            ));
        }
        let soil = sc.soil.as_ref().map(viaduct::soil).transpose()?;
        let viaduct = viaduct::viaduct(&sc.bridge, &bridge, r.elements_per_span, soil.as_ref())?;
        let ground = match (&sc.ground, &viaduct, &soil) {
            (None, _, _) => None,
            (Some(g), Some(v), Some(so)) => Some(viaduct::ground(g, v, so, &sc.bridge)?),
            (Some(_), _, _) => {
                return Err(Error::invalid(
                    "ground",
                    "receivers need a viaduct (bridge.kind = \"viaduct\") and its [soil]",
                ))
            }
        };
        let support = match (&sc.support, &viaduct, sc.run.model) {
            (None, _, _) => None,
            (Some(s), Some(v), Model::Fe) => Some(viaduct::support(s, v)?),
            (Some(s), None, Model::Fe | Model::Modal) => Some(viaduct::span_support(s, &bridge)?),
            (Some(_), _, _) => {
                return Err(Error::invalid(
                    "support",
                    "drives the footings of an FE viaduct or the bearings of FE or modal spans (run.model = \"fe\", or \"modal\" with bridge.kind = \"spans\"); the rigid guideway takes no support motion",
                ))
            }
        };
        if sc.run.model == Model::Fe {
            bridge::check_fe_size(&bridge, r.elements_per_span, dt)?;
        }
        if viaduct.is_some() && sc.run.model == Model::Modal {
            return Err(Error::invalid(
                "run.model",
                "the modal reference covers simply supported spans on rigid supports, not a viaduct on piers; use fe or rigid",
            ));
        }
        let (train, geometry) = train::train(&sc.vehicle)?;
        match (&train, &track) {
            (TrainCase::HighSpeed { .. }, None) => {
                return Err(Error::invalid(
                    "track",
                    "a high-speed train needs a [track] section",
                ))
            }
            (TrainCase::HighSpeed { .. }, Some(_)) | (_, None) => {}
            (_, Some(_)) => {
                return Err(Error::invalid(
                    "track",
                    "is read only by a high-speed train (train.kind = \"high-speed\")",
                ))
            }
        }
        let controller = match (&sc.controller, &train) {
            (Some(_), _) => Some(controller::controller(&sc, dt)?),
            (None, TrainCase::Fig1 { .. } | TrainCase::Maglev { .. } | TrainCase::Unit(_)) => {
                return Err(Error::invalid(
                    "controller",
                    "a train with magnets needs a [controller] section",
                ))
            }
            (
                None,
                TrainCase::Forces(_) | TrainCase::WheelRail { .. } | TrainCase::HighSpeed { .. },
            ) => None,
        };
        let t_end =
            match r.t_end_s {
                Some(t) => positive("run.t_end_s", t)?,
                None if speed == 0.0 => return Err(Error::invalid(
                    "run.t_end_s",
                    "is needed when run.speed_m_per_s = 0 (standstill: nothing leaves the bridge)",
                )),
                None => (bridge.total_length() + train::train_length(&train)) / speed + 0.1,
            };
        let steps = budget::steps(t_end, dt)?;
        let law = controller::law(&sc, &train, controller.as_ref(), geometry)?;
        if law.kind().sensors().accel {
            controller::state_law_magnets(&train)?;
        }
        let guidance = controller::guidance(&sc, &law)?;
        budget::check_budget(&budget::Budget {
            steps: steps.round() + 1.0,
            train: &train,
            sub_steps: controller
                .as_ref()
                .map_or(0.0, |p| budget::sub_steps(p, &law, dt)),
            columns: sc.output.as_ref().map_or(0, |o| o.probes.len()),
            profile: match sc.irregularity.as_ref().filter(|i| i.enabled) {
                Some(_) => (speed * t_end, train::train_length(&train)),
                None => (0.0, 0.0),
            },
        })?;
        let irregularity_seed = sc
            .irregularity
            .as_ref()
            .filter(|i| i.enabled)
            .map(|i| i.seed);
        let skid = contact::skid(sc.contact.as_ref(), controller.as_ref().map(|p| p.h0))?;
        let probes = probes::probes(&sc, &bridge, &train)?;
        probes.check_ground(ground.as_ref().map(Vec::len))?;
        Ok(Case {
            model: sc.run.model,
            speed,
            dt,
            t_end,
            elements_per_span: sc.run.elements_per_span,
            modes: sc.run.modes,
            tolerance,
            max_iterations: sc.run.max_iterations,
            bridge,
            viaduct,
            damping,
            train,
            controller,
            law,
            guidance,
            geometry,
            irregularity_seed,
            probes,
            soil,
            ground,
            support,
            skid,
            track,
            scenario: sc,
        })
    }

    /// The train this case runs (Fig. 1 cars with per-car static p0), or `None` for a train
    /// of forces.
    pub fn vehicle_train(&self) -> Result<Option<Train>> {
        match &self.train {
            TrainCase::Fig1 {
                car,
                cars,
                car_length,
            } => Train::fig1_repeated(car, *cars, *car_length, GRAVITY).map(Some),
            TrainCase::Maglev {
                cars, magnet_mass, ..
            } => Train::fig6_with(&train::fig6(*magnet_mass), *cars, GRAVITY).map(Some),
            TrainCase::WheelRail { cars, .. } => Train::wheel_rail(*cars, GRAVITY).map(Some),
            TrainCase::HighSpeed { .. } => self.rail_train().map(|t| Some(Train::rail_cars(t))),
            TrainCase::Unit(u) => Ok(Some(VehicleModel::unit(u, GRAVITY)?.into())),
            TrainCase::Forces(_) => Ok(None),
        }
    }

    /// The 3-D cars of a `high-speed` case on its track, with the rails' irregularity over
    /// every position a wheel passes when the irregularity is on.
    pub fn rail_train(&self) -> Result<crate::physics::rail::run::RailTrain> {
        use crate::physics::rail::irregularity::{Band, RailIrregularity};
        use crate::physics::rail::run::RailTrain;
        use crate::physics::rail::track::TrackSupport;
        let (
            TrainCase::HighSpeed {
                cars,
                pitch,
                conicity,
                friction,
                substeps,
                ..
            },
            Some(track),
        ) = (&self.train, &self.track)
        else {
            return Err(Error::numerical("internal: not a high-speed case"));
        };
        let mut spec = RailTrain {
            car: train::high_speed_car(*conicity, *friction),
            cars: *cars,
            pitch: *pitch,
            track_y: track.track_y,
            rail_z: track.rail_z,
            support: Some(TrackSupport::new(&track.slab)?),
            irregularity: None,
            substeps: *substeps,
        };
        if let Some(seed) = self.irregularity_seed {
            let x_min = -spec.length() - 2.0;
            let x_max = self.speed * self.t_end + 2.0;
            spec.irregularity = Some(RailIrregularity::new(
                &track.spectrum(),
                &Band::default(),
                seed,
                x_min,
                x_max,
            )?);
        }
        Ok(spec)
    }

    /// The law to run; an error if it is still to be designed (`crate::studies::design::resolve`).
    pub fn law(&self) -> Result<LawKind> {
        match self.law {
            LawChoice::Given(k) => Ok(k),
            _ => Err(Error::numerical(
                "internal: the law's gains are designed after the case (design::resolve)",
            )),
        }
    }

    /// The guidance pairs' law to run (`None`: the levitation law on each guidance magnet);
    /// an error if it is still to be designed (`crate::studies::design::resolve`).
    pub fn guidance(&self) -> Result<Option<GuidanceParams>> {
        match self.guidance {
            GuidanceChoice::None => Ok(None),
            GuidanceChoice::Given(g) => Ok(Some(g)),
            GuidanceChoice::Design => Err(Error::numerical(
                "internal: the guidance gains are designed after the case (design::resolve)",
            )),
        }
    }

    /// The controller's nominal gap h0 (m); 0 for a train of forces (no gaps).
    pub fn h0(&self) -> f64 {
        self.controller.map_or(0.0, |p| p.h0)
    }

    /// X of the middle of every span (the `span{K}.midspan` probes).
    pub fn midspans(&self) -> Vec<f64> {
        self.bridge
            .spans
            .iter()
            .scan(0.0, |x0, &l| {
                let mid = *x0 + l / 2.0;
                *x0 += l;
                Some(mid)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bundled_scenarios_resolve() {
        for (name, _) in scenario::BUNDLED {
            Case::load(name, &[]).unwrap();
        }
    }

    #[test]
    fn bad_values_name_their_key() {
        for (set, key) in [
            ("speed=-3", "run.speed_m_per_s"),
            ("dt=0", "run.dt_s"),
            ("dt=1e-12", "run.t_end_s"),
            ("t_end=1e12", "run.t_end_s"),
            ("t_end=nan", "run.t_end_s"),
            ("t_end=1e-300", "run.t_end_s"),
            ("speed=50\nx=1", "--set `speed=50\\nx=1`"),
            ("speed=50\rx=1", "--set `speed=50\\rx=1`"),
            (
                "output.probes=[\"wheel1_gap_z\", \"wheel1_gap_z\"]",
                "output.probes",
            ),
            ("elements=100000", "run.elements_per_span"),
            ("elements=0", "run.elements_per_span"),
            ("modes=0", "run.modes"),
            ("vehicle.target_height_m=nan", "vehicle.target_height_m"),
            ("vehicle.offset_y_m=inf", "vehicle.offset_y_m"),
            ("vehicle.body_mass_t=-1", "vehicle.body_mass_t"),
            ("vehicle.wheel_mass_kg=nan", "vehicle.wheel_mass_kg"),
            ("vehicle.repeat=2", "train.car_length_m"),
            ("vehicle.repeat=1001", "train.repeat"),
            ("bridge.iy_m4=0", "bridge.iy_m4"),
            ("bridge.spans_m=[]", "bridge.spans_m"),
            ("controller.alpha=2", "controller.alpha"),
            ("controller.i0_A=nan", "controller.i0_A"),
            ("controller.nsub=0", "controller.nsub"),
            ("controller.vmax_V=-1", "controller.vmax_V"),
            ("controller.r0_ohm=0", "controller.r0_ohm"),
            ("vehicle.body_mass_t=1e300", "vehicle.body_mass_t"),
            ("bridge.iy_m4=1e12", "bridge.iy_m4"),
            ("controller.kp_V_m_per_A=1e200", "controller.kp_V_m_per_A"),
            ("controller.vmax_V=1e300", "controller.vmax_V"),
        ] {
            let e = Case::load("paper-4.2", &[set.into()]).unwrap_err();
            let m = e.to_string();
            assert!(matches!(e, Error::Invalid { .. }), "{set}: {m}");
            assert!(m.starts_with(key), "{set}: expected the key {key}: {m}");
            assert!(!m.contains('\n'), "{set}: {m}");
        }
        let e = Case::load("train-forces", &["train.offsets_m=[0.0]".into()]).unwrap_err();
        assert!(e.to_string().starts_with("train.loads_kN"), "{e}");
    }

    /// The committed seeds of the input fuzz target (fuzz/corpus/input, docs/scenarios.md
    /// "Fuzzing the input path") resolve: a seed that no longer does starts the fuzzer at an
    /// error instead of deep in `Case::new`. Input shape: TEXT or a bundled name, then NUL and
    /// one `--set` per line.
    #[test]
    fn fuzz_seeds_resolve() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz/corpus/input");
        let mut seeds = 0;
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            let data = std::fs::read_to_string(&path).unwrap();
            let (text, sets) = data.split_once('\0').unwrap_or((&data, ""));
            // The record files of the `[support]` seeds are named from fuzz/, where the
            // fuzzer runs (make-corpus.sh).
            let fuzz = dir
                .parent()
                .and_then(|d| d.parent())
                .unwrap()
                .display()
                .to_string();
            let sets: Vec<String> = sets
                .lines()
                .map(|s| s.replace("records/", &format!("{fuzz}/records/")))
                .collect();
            let text = scenario::BUNDLED
                .iter()
                .find(|(n, _)| *n == text)
                .map_or(text, |(_, t)| t);
            scenario::parse(text, "seed", &sets)
                .and_then(Case::new)
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            seeds += 1;
        }
        assert!(seeds >= 10, "{seeds} seeds in {}", dir.display());
    }
}
