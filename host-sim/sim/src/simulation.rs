//! Vehicle–guideway coupling in step-lockstep with the magnets' controllers (docs/model.md §7):
//! the one Newton–Raphson loop of the project, shared by `maglev run` and `maglev hil`.
//!
//! Each time step runs a Newton–Raphson (fixed-point) loop on the wheel forces:
//! (1) from the current displacement estimate compute every gap (Eq. 2, 16) and ask the
//! [`Magnets`] for the forces over the step;
//! (2) load the guideway (Eq. 15) and the vehicle and solve both for t + Δt;
//! (3) repeat until the gaps the forces were computed from agree with the gaps the solution
//! gives. The magnets restart from their committed state at every iteration and commit only on
//! convergence. The iteration count of each step is recorded (Fig. 5).
//!
//! The loop itself, one for every train kind (moving forces included), is
//! `time_loop`'s: kinematics at t, the coupled iteration, the step's
//! bookkeeping. What a run keeps of every step goes through one [`Recorder`]; the
//! [`Outcome`] holds only the run's counters and ranges.
//!
//! Wheel–rail contacts (Hertz springs, docs/cars.md "Wheel–rail contact") ride in the same
//! loop: their springs are implicit in the cars, the rail's motion is their forcing, and the
//! iteration runs until that motion agrees too.
//!
//! Any [`Magnets`] plug into the loop: [`magnets::CoreMagnets`], the core's controllers in f64
//! with exact gaps (every law; `maglev run`), `maglev_hil::coupling::FirmwareMagnets`, the
//! firmware behind a link with sampled, quantised gaps (`maglev hil`), or a user's own (a
//! Rust type, a Python class). One loop means two runs differ only in the controller, which
//! is what `maglev hil --compare` measures.

pub mod magnets;
mod time_loop;
pub mod train;

use crate::physics::guideway::Guideway;
use crate::physics::train::Train;
use crate::physics::vehicle::Coil;
use crate::probes::Recorder;
use crate::{Error, Result};
use maglev_core::gap::Geometry;
use maglev_core::{LawKind, Params, Status};
use std::sync::atomic::{AtomicBool, Ordering};
use time_loop::Riders;

/// What runs over the guideway.
// One Load per run, built once: its size does not matter.
#[allow(clippy::large_enum_variant)]
pub enum Load {
    /// Constant vertical forces moving with the run's speed (a `forces` train, or the single
    /// moving force of the verification case); no controller, no irregularity. They run
    /// through the same loop as a train, as a train with no cars whose loads are constant.
    Forces(Vec<MovingLoad>),
    /// A train (one car or more): one levitation magnet and one guidance pair per maglev
    /// wheel, one Hertz spring per wheel–rail contact.
    Vehicle(Train),
}

/// One constant moving force.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct MovingLoad {
    /// X at t = 0 (m).
    #[serde(rename = "x0_m")]
    pub x0: f64,
    /// Force (N, positive downward).
    #[serde(rename = "force_N")]
    pub force: f64,
    /// Offset of its point from the beam axis, Y and Z (m).
    #[serde(rename = "ey_m")]
    pub ey: f64,
    #[serde(rename = "ez_m")]
    pub ez: f64,
}

/// Rail irregularity profiles r_y(x), r_z(x) (m), shared by every wheel (docs/model.md §3).
pub struct Profiles {
    pub y: Box<dyn Fn(f64) -> f64>,
    pub z: Box<dyn Fn(f64) -> f64>,
}

impl Profiles {
    /// A perfectly smooth rail.
    pub fn smooth() -> Self {
        Profiles {
            y: Box::new(|_| 0.0),
            z: Box::new(|_| 0.0),
        }
    }
}

/// Run settings (SI).
pub struct Settings {
    pub speed: f64,
    pub dt: f64,
    pub t_end: f64,
    /// Controller parameters (p0 is replaced by each wheel's static load).
    pub controller: Params,
    /// The law of every levitation and guidance magnet (`maglev_core::law`).
    pub law: LawKind,
    /// The guidance pairs' own law under the state law (`[controller.guidance]`,
    /// `maglev_core::law::guidance`): `None`, each guidance magnet runs `law` on its gap.
    pub guidance: Option<maglev_core::law::guidance::GuidanceParams>,
    /// How the magnets face their rails (Eq. 2 and the guidance pair's sign, docs/model.md §2).
    pub geometry: Geometry,
    /// Convergence tolerance on the gaps between two iterations (m).
    pub tolerance: f64,
    pub max_iterations: u32,
    /// X of the first span's middle. Read by nothing since the per-step records went (the
    /// probes read `midspans`); it goes when the tests that set it do.
    pub midspan_x: f64,
    /// X of the middle of every span (the `span{K}.midspan` probes).
    pub midspans: Vec<f64>,
    /// The magnets' skid contact with their rails (`[contact]`, docs/contact.md).
    pub skid: crate::physics::skid::Skid,
}

/// The range `(min, max)` (m) of each magnet's gap over a run, per wheel: levitation,
/// guidance left, guidance right.
pub type GapRanges = Vec<[(f64, f64); 3]>;

/// One magnet's coil over a run: the largest `|i|` (A) and `|V|` (V) of the committed steps
/// (t = 0 included), and the number of steps in which its law clamped the voltage.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CoilRange {
    pub peak_current: f64,
    pub peak_voltage: f64,
    pub saturated_steps: usize,
}

impl CoilRange {
    /// The range of one step's sample alone (saturation is counted per step, not at t = 0).
    fn of(c: &Coil) -> Self {
        CoilRange {
            peak_current: c.current.abs(),
            peak_voltage: c.voltage.abs(),
            saturated_steps: 0,
        }
    }

    /// Takes in a committed step's sample.
    fn add(&mut self, c: &Coil) {
        self.peak_current = self.peak_current.max(c.current.abs());
        self.peak_voltage = self.peak_voltage.max(c.voltage.abs());
        self.saturated_steps += usize::from(c.saturated);
    }
}

/// Per wheel, each magnet's [`CoilRange`] (levitation, guidance left, guidance right); empty
/// when the magnets report no coil ([`Magnets::coils`]).
pub type CoilRanges = Vec<[CoilRange; 3]>;

/// Result of a run.
pub struct Outcome {
    /// Steps run (t = 0 is not a step).
    pub steps: usize,
    /// The last step's time (s).
    pub simulated_seconds: f64,
    /// Iterations summed over every step, and the most any step took.
    pub total_iterations: u64,
    pub max_iterations: u32,
    /// Steps whose iterations hit `max_iterations` without converging.
    pub unconverged_steps: usize,
    /// Steps in which some magnet's gap was at or below zero or some magnet was on its skid
    /// (docs/contact.md).
    pub collision_steps: usize,
    /// The end time (s) of the first such step.
    pub first_collision_t: Option<f64>,
    /// Each magnet's gap range over the run (empty for a moving force).
    pub gap_ranges: GapRanges,
    /// Per magnet wheel, whether it has guidance magnets (the `left` and `right` of its gap
    /// and coil ranges mean nothing where it has not: a `unit`).
    pub guided: Vec<bool>,
    /// Each magnet's coil over the run (empty for a moving force, and where the magnets
    /// report no coil).
    pub coil_ranges: CoilRanges,
    /// Steps in which some wheel–rail contact lifted off (its force clamped at zero).
    pub contact_loss_steps: usize,
    /// Each contact's force range `(min, max)` (N, compressive) over the run, clamped.
    pub contact_ranges: Vec<(f64, f64)>,
    /// Every magnet's skid contact over the run (docs/contact.md).
    pub skids: crate::physics::skid::SkidOutcome,
    /// What the run kept of its 3-D high-speed cars (`crate::physics::rail::run`), if any.
    pub rail: Option<crate::physics::rail::run::RailOutcome>,
    /// The irregularity the run used, `[x, r_y, r_z]` (m) at every position a wheel occupied
    /// at a step, sorted by x, duplicates removed (empty for a moving force).
    pub profile: Vec<[f64; 3]>,
}

/// Per wheel: the levitation gap `h_z` (m, Eq. 2) and the relative lateral position
/// `d = y_w − y_g + r_y` (m, docs/model.md §2; the guidance magnets' gaps are `h0 ± d`).
pub type WheelGaps = (f64, f64);

/// What the magnets are told before the first step of a run.
pub struct Start<'a> {
    /// The train (no cars and no wheels for a train of moving forces).
    pub train: &'a Train,
    /// Each wheel's gaps at t = 0 ([`initial_gaps`]).
    pub gaps: &'a [WheelGaps],
    /// The run's settings: step, controller parameters, law, geometry.
    pub settings: &'a Settings,
}

/// The magnets of a vehicle as the coupling loop sees them: forces from gaps, with a
/// committed state and a trial state (docs/model.md §7). The plug-in for a controller: the
/// core's ([`magnets::CoreMagnets`]), the firmware's (`maglev-hil`), or a user's.
pub trait Magnets {
    /// Readies the magnets for a run of `start.train` (one call, before the first step): one
    /// levitation magnet and one guidance pair per wheel, in equilibrium at `start.gaps`.
    fn start(&mut self, start: &Start<'_>) -> Result<()>;

    /// Per wheel `(G_z, G_y)` (N, magnet forces, positive up and along +Y) over step `step`
    /// ending at `t`, as the gaps move from `gaps_prev` (committed, at t − Δt) to `gaps_next`
    /// (the current iterate, at t). Always starts from the committed state, so the loop may
    /// call it several times per step. `accels` is each wheel's vertical acceleration at the
    /// iterate (m/s², Z up, absolute): what an accelerometer on the levitation magnet reads.
    fn forces(
        &mut self,
        step: u32,
        t: f64,
        gaps_prev: &[WheelGaps],
        gaps_next: &[WheelGaps],
        accels: &[f64],
        out: &mut [(f64, f64)],
    ) -> Result<()>;

    /// Each wheel's lateral acceleration at the iterate of the next [`Magnets::forces`] call
    /// (m/s², +Y, absolute; 0 for a wheel without a lateral DOF): what an accelerometer on
    /// the guidance magnets reads. Given before every call; ignored by default (only a
    /// guidance law that feeds it back, `maglev_core::law::guidance`, reads it).
    fn lateral_accels(&mut self, _accels_y: &[f64]) {}

    /// Makes the state after the last [`Magnets::forces`] call of `step` the committed one.
    fn commit(&mut self, step: u32, t: f64) -> Result<()>;

    /// The core's status flags of the last [`Magnets::forces`] call (recorded per step).
    fn status(&self) -> Status;

    /// Per wheel, each magnet's coil (levitation, guidance left, guidance right) at the last
    /// committed step (before the first commit: at t = 0); empty where the magnets do not
    /// report their coils.
    fn coils(&self) -> &[[Coil; 3]] {
        &[]
    }
}

/// Each wheel's gaps at t = 0 with the vehicle at rest at its static position:
/// `(h0 + r_z(x0), r_y(x0))`.
pub fn initial_gaps(v: &Train, profiles: &Profiles, h0: f64) -> Vec<WheelGaps> {
    v.wheels
        .iter()
        .map(|w| (h0 + (profiles.z)(w.x0), (profiles.y)(w.x0)))
        .collect()
}

/// What a long run tells its caller and asks of it: the fraction done now and then, and
/// after every step whether to stop. `()` is a monitor that hears nothing and never stops; a
/// closure `FnMut(f64)` hears the progress; an [`AtomicBool`] the caller sets (a signal
/// handler, another thread) stops the run.
pub trait Monitor {
    /// The fraction of the run done, in (0, 1], now and then.
    fn progress(&mut self, _done: f64) {}
    /// Polled once per step: `true` ends the run with [`Error::Cancelled`].
    fn cancelled(&mut self) -> bool {
        false
    }
}

impl Monitor for () {}

impl<F: FnMut(f64)> Monitor for F {
    fn progress(&mut self, done: f64) {
        self(done)
    }
}

impl Monitor for &AtomicBool {
    fn cancelled(&mut self) -> bool {
        self.load(Ordering::Relaxed)
    }
}

/// Runs from t = 0 to `t_end` with `magnets` on a train (a train of moving forces has none:
/// its magnets are started on no wheels and never asked for a force).
pub fn simulate<G: Guideway>(
    guideway: &mut G,
    load: &Load,
    profiles: &Profiles,
    s: &Settings,
    magnets: &mut dyn Magnets,
    rec: &mut dyn Recorder,
    monitor: &mut dyn Monitor,
) -> Result<Outcome> {
    match load {
        Load::Forces(forces) => {
            // A train with no cars: no magnets, no contacts, only the moving forces.
            let train = Train {
                cars: Vec::new(),
                wheels: Vec::new(),
                p0: Vec::new(),
                contacts: Vec::new(),
                nodes: Vec::new(),
                parallel: false,
                rail: None,
            };
            magnets.start(&Start {
                train: &train,
                gaps: &[],
                settings: s,
            })?;
            if forces.is_empty() {
                return Err(Error::invalid("train.loads_kN", "needs at least one load"));
            }
            let riders = Riders {
                train: &train,
                forces,
            };
            time_loop::run(guideway, riders, profiles, s, magnets, rec, monitor)
        }
        Load::Vehicle(v) => {
            let gaps0 = initial_gaps(v, profiles, s.controller.h0);
            magnets.start(&Start {
                train: v,
                gaps: &gaps0,
                settings: s,
            })?;
            couple(guideway, v, profiles, s, magnets, rec, monitor)
        }
    }
}

/// The coupling loop of a train with `magnets` (already [started](Magnets::start)) over
/// `guideway` (module docs). Wheel–rail contacts join the same loop (docs/cars.md "Wheel–rail contact"): their Hertz springs are
/// in the cars' matrices, the rail's motion enters the car as the forcing `k_h·(z_g − r_z)`,
/// and the guideway receives the contact forces; the iteration also runs until the rail's
/// motion under every contact agrees between two iterations.
pub fn couple<G: Guideway, M: Magnets + ?Sized>(
    guideway: &mut G,
    v: &Train,
    profiles: &Profiles,
    s: &Settings,
    magnets: &mut M,
    rec: &mut dyn Recorder,
    monitor: &mut dyn Monitor,
) -> Result<Outcome> {
    if v.nodes.is_empty() && v.rail.is_none() {
        return Err(Error::invalid(
            "train",
            "has no magnet and no wheel to meet the guideway",
        ));
    }
    let riders = Riders {
        train: v,
        forces: &[],
    };
    time_loop::run(guideway, riders, profiles, s, magnets, rec, monitor)
}

/// The linearised contact force (N, compressive positive; docs/cars.md "Wheel–rail
/// contact"): `P = P0 − k·(z_w − z_g + r_z)`, k the contact spring ([`crate::physics::vehicle::Contact::k`]), with z_w the wheel's and z_g the rail point's
/// displacement (m, up) and r_z the irregularity (m; r_z > 0 opens the gap, as in Eq. 2).
/// Negative means the wheel has lifted off: the caller clamps it at zero.
pub fn contact_force(p0: f64, k: f64, z_w: f64, z_g: f64, r_z: f64) -> f64 {
    p0 - k * (z_w - z_g + r_z)
}
