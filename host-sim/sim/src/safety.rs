//! Running-safety figures of a train's passage (summary.json `safety`, docs/safety.md): for
//! magnets the smallest levitation and guidance gaps, the collisions, the coils' peak current
//! and voltage and the time spent voltage-saturated; for wheel–rail contacts the wheel
//! unloading ΔP/P and the lift-offs; for every car the body's vertical acceleration. Each
//! figure carries the limit it is judged against and that limit's source.
//!
//! Why a [`Recorder`]: the figures are reductions of what every committed step shows, so they
//! ride the run's one recording path beside response.csv (a [`crate::probes::Tee`]), with no
//! second pass over the run and nothing written per step. The buffers are sized at the first
//! step the recorder sees (t = 0, before the time loop proper); after that a step only
//! compares and adds.
//!
//! The derailment quotient Q/P is not computed: the cars have no lateral wheel–rail force
//! (docs/cars.md, "Decision (vertical and roll)").

pub mod running;

use crate::input::case::Case;
use crate::physics::train::Node;
use crate::physics::vehicle::magnet_gaps;
use crate::probes::{Recorder, StepView, Wheels};
use crate::Result;
use serde::Serialize;

/// The skid contact's figures in the report ([`skid::SkidFigures`]).
pub mod skid;

/// The levitation and guidance gaps' limit (m): a magnet touches its rail at a gap of zero
/// (docs/model.md §2; `collision_steps` counts such steps).
pub const GAP_LIMIT: f64 = 0.0;
const GAP_SOURCE: &str = "geometry: the magnet touches its rail at a gap of 0 (docs/model.md §2); no published minimum running gap for an EMS magnet was found (docs/safety.md)";

/// The largest gap change `|h − h0|/h0` inside the linear analysis' range: there the
/// neglected second-order term of the force `F ∝ (i/h)²` (`3η²` against the linear `2η`)
/// reaches 15 % of the linear one (docs/levitation.md "Supply headroom").
pub const LINEAR_GAP_LIMIT: f64 = 0.1;

/// The car body's peak vertical acceleration limit (m/s²).
pub const BODY_ACCEL_LIMIT: f64 = 1.3;
const BODY_ACCEL_SOURCE: &str = "EN 1990:2002/A1:2005 Annex A2, A2.4.4.3.1, Table A2.9: b_v = 1.3 m/s² for a 'good' level of passenger comfort (the value as widely cited; the standard's text was not checked here, docs/safety.md)";

/// The wheel unloading ratio ΔP/P limit.
pub const UNLOADING_LIMIT: f64 = 0.6;
const UNLOADING_SOURCE: &str = "GB 5599-85 permissible wheel unloading ratio 0.6 (also cited for TB 10621-2014); the value as widely cited, the standards' text was not checked here (docs/safety.md)";

const CONTACT_SOURCE: &str =
    "a collision (a magnet's gap ≤ 0, docs/model.md §2) in any step fails the run";
const LIFT_OFF_SOURCE: &str =
    "a wheel off its rail (contact force ≤ 0) carries and guides nothing: any lift-off fails the run";
const CURRENT_SOURCE: &str =
    "no limit: the magnet model has no current bound (maglev_core::Params has none)";
const VOLTAGE_SOURCE: &str = "the law's supply bound V_max (controller.vmax_V, or controller.state.vmax_V under the state law)";
const NO_VOLTAGE_SOURCE: &str = "no limit: the law has no voltage bound (vmax_V = inf)";
const SATURATION_SOURCE: &str =
    "no limit: saturation is where the supply, not the law, sets the force; reported, not judged";
const RMS_SOURCE: &str = "no limit: comfort scales for r.m.s. acceleration (ISO 2631-1, EN 12299) apply to frequency-weighted signals, which the model does not form";
/// Why Q/P is not computed (summary.json and docs/safety.md).
pub const QP_REASON: &str = "not computed: the wheel/rail car has no lateral wheel–rail force (creep and flange contact are not modelled, docs/cars.md), so Q is not known";

/// One safety figure: its value, where and when it occurred, the limit it is judged against
/// and the limit's source.
#[derive(Serialize, Debug, Clone, PartialEq)]
pub struct Figure {
    pub value: f64,
    pub unit: &'static str,
    /// The magnet (`wheel{N}.z`, `.left`, `.right`), contact (`wheel{N}`) or car (`car{N}`).
    pub at: Option<String>,
    /// When (s): the step of the extreme, or the first step counted.
    pub t_s: Option<f64>,
    /// Null where neither the model nor a standard gives one.
    pub limit: Option<f64>,
    /// Whether the value is within the limit; null where there is no limit.
    pub pass: Option<bool>,
    pub source: &'static str,
}

impl Figure {
    /// A figure, not yet judged.
    fn new(value: f64, unit: &'static str, at: Option<String>, t: Option<f64>) -> Self {
        Figure {
            value,
            unit,
            at,
            t_s: t,
            limit: None,
            pass: None,
            source: "",
        }
    }

    /// A figure judged `≤ limit` (none: not judged) with its source.
    pub(super) fn judged(
        value: f64,
        unit: &'static str,
        at: Option<String>,
        t: Option<f64>,
        limit: Option<f64>,
        source: &'static str,
    ) -> Self {
        Figure::new(value, unit, at, t).limit(limit, source, le)
    }

    /// The figure judged against `limit` (none: not judged) by `within(value, limit)`.
    fn limit(self, limit: Option<f64>, source: &'static str, within: fn(f64, f64) -> bool) -> Self {
        Figure {
            pass: limit.map(|l| within(self.value, l)),
            limit,
            source,
            ..self
        }
    }
}

fn le(v: f64, l: f64) -> bool {
    v <= l
}

fn gt(v: f64, l: f64) -> bool {
    v > l
}

/// A magnet's smallest levitation gap.
#[derive(Serialize, Debug, Clone, PartialEq)]
pub struct MagnetGap {
    pub magnet: String,
    pub min_m: f64,
    pub t_s: f64,
}

/// A contact's largest unloading and smallest force.
#[derive(Serialize, Debug, Clone, PartialEq)]
pub struct ContactUnloading {
    pub wheel: String,
    /// Largest (P0 − P)/P0.
    pub unloading: f64,
    pub t_s: f64,
    #[serde(rename = "min_force_N")]
    pub min_force: f64,
    #[serde(rename = "static_load_N")]
    pub p0: f64,
}

/// A car body's vertical acceleration.
#[derive(Serialize, Debug, Clone, PartialEq)]
pub struct CarAcceleration {
    pub car: String,
    #[serde(rename = "peak_m_per_s2")]
    pub peak: f64,
    pub t_s: f64,
    #[serde(rename = "rms_m_per_s2")]
    pub rms: f64,
}

/// The magnets' figures.
#[derive(Serialize, Debug, Clone, PartialEq)]
pub struct MaglevFigures {
    pub levitation_gap_min: Figure,
    /// Only where some magnet wheel has guidance magnets.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub guidance_gap_min: Option<Figure>,
    /// Steps with a collision (some gap ≤ 0), the first one's time.
    pub collision_steps: Figure,
    /// Only where the magnets report their coils.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub current_peak: Option<Figure>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub voltage_peak: Option<Figure>,
    /// The longest time one magnet spent with its voltage clamped at ±V_max.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub saturated_longest: Option<Figure>,
    /// Every levitation magnet's smallest gap, along the train.
    pub levitation_gap_per_magnet: Vec<MagnetGap>,
    /// Whether the run stayed where the linear analysis (`maglev stability`) holds: no
    /// coil at ±V_max and every gap within [`LINEAR_GAP_LIMIT`] of h0. Reported, not judged.
    pub linear_range: LinearRange,
    /// The magnets' landings on their skids (docs/contact.md); set by the run
    /// ([`SafetyReport::with_skids`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub skid_contact: Option<skid::SkidFigures>,
}

/// summary.json `safety.maglev.linear_range` ([`MaglevFigures::linear_range`]).
#[derive(Serialize, Debug, Clone, PartialEq)]
pub struct LinearRange {
    /// Neither limit below was crossed.
    pub within: bool,
    /// Some coil spent time at ±V_max (the longest: `saturated_longest`).
    pub saturated: bool,
    /// The largest `|h − h0|/h0` of any gap, where and when, and [`LINEAR_GAP_LIMIT`].
    pub gap_deviation_max: f64,
    pub at: String,
    pub t_s: f64,
    pub gap_deviation_limit: f64,
}

/// Q/P, not computed.
#[derive(Serialize, Debug, Clone, PartialEq)]
pub struct NotComputed {
    pub computed: bool,
    pub reason: &'static str,
}

/// The wheel–rail contacts' figures.
#[derive(Serialize, Debug, Clone, PartialEq)]
pub struct WheelRailFigures {
    /// The largest wheel unloading ratio ΔP/P of any contact.
    pub unloading_max: Figure,
    /// Recorded states with some contact force ≤ 0 (t = 0 included), the first one's time.
    pub lift_off_steps: Figure,
    pub derailment_quotient: NotComputed,
    pub per_contact: Vec<ContactUnloading>,
}

/// summary.json `safety`.
#[derive(Serialize, Debug, Clone, PartialEq)]
pub struct SafetyReport {
    /// Every figure with a limit within it.
    pub pass: bool,
    pub body_acceleration_peak: Figure,
    pub body_acceleration_rms: Figure,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub maglev: Option<MaglevFigures>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wheel_rail: Option<WheelRailFigures>,
    /// The 3-D high-speed cars' running safety ([`running`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub high_speed: Option<running::HighSpeedFigures>,
    pub per_car: Vec<CarAcceleration>,
}

impl SafetyReport {
    /// Every figure judged against a limit, by its summary.json name, with its verdict: what
    /// `pass` is made of, and what a sweep names when a run fails.
    pub fn judged(&self) -> Vec<(&'static str, bool)> {
        let mut all = vec![("body_acceleration_peak", &self.body_acceleration_peak)];
        if let Some(m) = &self.maglev {
            all.push(("maglev.levitation_gap_min", &m.levitation_gap_min));
            all.push(("maglev.collision_steps", &m.collision_steps));
            if let Some(s) = &m.skid_contact {
                all.push(("maglev.skid_contact.contact_steps", &s.contact_steps));
            }
            for (name, f) in [
                ("maglev.guidance_gap_min", &m.guidance_gap_min),
                ("maglev.current_peak", &m.current_peak),
                ("maglev.voltage_peak", &m.voltage_peak),
            ] {
                all.extend(f.as_ref().map(|f| (name, f)));
            }
        }
        if let Some(w) = &self.wheel_rail {
            all.push(("wheel_rail.unloading_max", &w.unloading_max));
            all.push(("wheel_rail.lift_off_steps", &w.lift_off_steps));
        }
        if let Some(h) = &self.high_speed {
            all.extend(h.all());
        }
        all.into_iter()
            .filter_map(|(name, f)| f.pass.map(|p| (name, p)))
            .collect()
    }
}

/// The smallest (or largest) value seen and its first time.
#[derive(Clone, Copy, Debug)]
struct Extreme {
    value: f64,
    t: f64,
}

impl Extreme {
    const LOW: Extreme = Extreme {
        value: f64::INFINITY,
        t: f64::NAN,
    };
    const HIGH: Extreme = Extreme {
        value: f64::NEG_INFINITY,
        t: f64::NAN,
    };

    fn lower(&mut self, v: f64, t: f64) {
        if v < self.value {
            *self = Extreme { value: v, t };
        }
    }

    fn higher(&mut self, v: f64, t: f64) {
        if v > self.value {
            *self = Extreme { value: v, t };
        }
    }
}

/// One magnet wheel's running figures.
#[derive(Clone, Copy, Debug)]
struct MagnetTrack {
    node: usize,
    guided: bool,
    lev: Extreme,
    /// The largest `|h/h0 − 1|` of its gaps, and which (index into [`SIDES`]).
    deviation: (Extreme, usize),
    /// Guidance left and right.
    guide: [Extreme; 2],
    /// Levitation, left, right: peak |i|, peak |V|, saturated steps.
    current: [Extreme; 3],
    voltage: [Extreme; 3],
    saturated: [usize; 3],
}

impl MagnetTrack {
    /// Its coils by index into [`SIDES`]: levitation, and the guidance pair where it has one.
    fn coils(&self) -> std::ops::Range<usize> {
        0..if self.guided { 3 } else { 1 }
    }
}

/// One contact's running figures.
#[derive(Clone, Copy, Debug)]
struct ContactTrack {
    node: usize,
    p0: f64,
    unloading: Extreme,
    force: Extreme,
}

/// One car body's running figures.
#[derive(Clone, Copy, Debug)]
struct CarTrack {
    peak: Extreme,
    sum_sq: f64,
}

/// Counted steps and the first one's time.
#[derive(Clone, Copy, Debug, Default)]
struct Count {
    steps: usize,
    first: Option<(f64, Option<usize>)>,
}

impl Count {
    fn add(&mut self, t: f64, at: Option<usize>) {
        self.steps += 1;
        self.first.get_or_insert((t, at));
    }
}

/// The safety recorder (module docs).
pub struct Safety {
    dt: f64,
    voltage_limit: Option<f64>,
    started: bool,
    vehicle: bool,
    coils: bool,
    samples: usize,
    magnets: Vec<MagnetTrack>,
    contacts: Vec<ContactTrack>,
    cars: Vec<CarTrack>,
    collisions: Count,
    lift_offs: Count,
}

impl Safety {
    /// A recorder for a run of step `dt` (s) whose law clamps at `voltage_limit` (V, None:
    /// unbounded).
    pub fn new(dt: f64, voltage_limit: Option<f64>) -> Self {
        Safety {
            dt,
            voltage_limit,
            started: false,
            vehicle: false,
            coils: false,
            samples: 0,
            magnets: Vec::new(),
            contacts: Vec::new(),
            cars: Vec::new(),
            collisions: Count::default(),
            lift_offs: Count::default(),
        }
    }

    /// The recorder of `case`'s run: its step and its law's voltage bound.
    pub fn for_case(case: &Case) -> Self {
        let limit = case
            .controller
            .as_ref()
            .and_then(|c| case.law.kind().voltage_bound(c));
        Safety::new(case.dt, limit)
    }

    /// Sizes the tracks from the first step's view.
    fn start(&mut self, step: &StepView) {
        self.started = true;
        let Wheels::Vehicle {
            dofs,
            nodes,
            contact_p0,
            body_z,
            coils,
            ..
        } = &step.wheels
        else {
            return;
        };
        self.vehicle = true;
        self.coils = !coils.is_empty();
        for (node, n) in nodes.iter().enumerate() {
            match *n {
                Node::Magnet(i) => self.magnets.push(MagnetTrack {
                    node,
                    guided: dofs[i].0.is_some(),
                    lev: Extreme::LOW,
                    deviation: (Extreme::HIGH, 0),
                    guide: [Extreme::LOW; 2],
                    current: [Extreme::HIGH; 3],
                    voltage: [Extreme::HIGH; 3],
                    saturated: [0; 3],
                }),
                Node::Contact(j) => self.contacts.push(ContactTrack {
                    node,
                    p0: contact_p0[j],
                    unloading: Extreme::HIGH,
                    force: Extreme::LOW,
                }),
            }
        }
        self.cars = vec![
            CarTrack {
                peak: Extreme::HIGH,
                sum_sq: 0.0,
            };
            body_z.len()
        ];
    }
}

impl Recorder for Safety {
    fn record(&mut self, step: &StepView) -> Result<()> {
        if !self.started {
            self.start(step);
        }
        let Wheels::Vehicle {
            a,
            gaps,
            h0,
            body_z,
            nodes,
            contact_forces,
            coils,
            ..
        } = &step.wheels
        else {
            return Ok(());
        };
        let (t, first) = (step.t, self.samples == 0);
        self.samples += 1;
        let mut lifted = None;
        let (mut m, mut c) = (0, 0);
        for n in nodes.iter() {
            match *n {
                Node::Magnet(i) => {
                    let track = &mut self.magnets[m];
                    m += 1;
                    let [hz, hl, hr] = magnet_gaps(gaps[i], *h0);
                    track.lev.lower(hz, t);
                    track.guide[0].lower(hl, t);
                    track.guide[1].lower(hr, t);
                    let sides = if track.guided { 3 } else { 1 };
                    for (k, h) in [hz, hl, hr].into_iter().enumerate().take(sides) {
                        let d = (h / *h0 - 1.0).abs();
                        if d > track.deviation.0.value {
                            track.deviation = (Extreme { value: d, t }, k);
                        }
                    }
                    if let Some(coil) = coils.get(i) {
                        // As summary.json's coils: saturation is counted per step, not at t = 0.
                        for (k, c) in coil.iter().enumerate() {
                            track.current[k].higher(c.current.abs(), t);
                            track.voltage[k].higher(c.voltage.abs(), t);
                            track.saturated[k] += usize::from(c.saturated && !first);
                        }
                    }
                }
                Node::Contact(j) => {
                    let track = &mut self.contacts[c];
                    c += 1;
                    let p = contact_forces[j];
                    track.force.lower(p, t);
                    track.unloading.higher((track.p0 - p) / track.p0, t);
                    if p <= 0.0 && lifted.is_none() {
                        lifted = Some(track.node);
                    }
                }
            }
        }
        if let Some(node) = lifted {
            self.lift_offs.add(t, Some(node));
        }
        if step.collision {
            self.collisions.add(t, None);
        }
        for (car, &dof) in self.cars.iter_mut().zip(body_z.iter()) {
            let az = a[dof];
            car.peak.higher(az.abs(), t);
            car.sum_sq += az * az;
        }
        Ok(())
    }
}

/// The first item with the largest key (the extremes are named by their first occurrence
/// along the train, as their times are by their first step; `min_by` already keeps the first).
fn first_max<T>(items: impl Iterator<Item = T>, key: impl Fn(&T) -> f64) -> Option<T> {
    items.fold(None, |best, x| match best {
        Some(b) if key(&b) >= key(&x) => Some(b),
        _ => Some(x),
    })
}

fn wheel(node: usize) -> String {
    format!("wheel{}", node + 1)
}

const SIDES: [&str; 3] = ["z", "left", "right"];

impl Safety {
    /// The figures of the steps recorded; None for a run without a vehicle (moving forces)
    /// or before any step.
    pub fn report(&self) -> Option<SafetyReport> {
        if !self.vehicle || self.samples == 0 {
            return None;
        }
        let n = self.samples as f64;
        let per_car: Vec<CarAcceleration> = self
            .cars
            .iter()
            .enumerate()
            .map(|(k, c)| CarAcceleration {
                car: format!("car{}", k + 1),
                peak: c.peak.value,
                t_s: c.peak.t,
                rms: (c.sum_sq / n).sqrt(),
            })
            .collect();
        let worst = first_max(per_car.iter(), |c| c.peak);
        let rough = first_max(per_car.iter(), |c| c.rms);
        let body_acceleration_peak = Figure::new(
            worst.map_or(0.0, |c| c.peak),
            "m/s²",
            worst.map(|c| c.car.clone()),
            worst.map(|c| c.t_s),
        )
        .limit(Some(BODY_ACCEL_LIMIT), BODY_ACCEL_SOURCE, le);
        let body_acceleration_rms = Figure::new(
            rough.map_or(0.0, |c| c.rms),
            "m/s²",
            rough.map(|c| c.car.clone()),
            None,
        )
        .limit(None, RMS_SOURCE, le);
        let maglev = (!self.magnets.is_empty()).then(|| self.maglev_figures());
        let wheel_rail = (!self.contacts.is_empty()).then(|| self.wheel_rail_figures());
        let mut report = SafetyReport {
            pass: true,
            body_acceleration_peak,
            body_acceleration_rms,
            maglev,
            wheel_rail,
            high_speed: None,
            per_car,
        };
        report.pass = report.judged().iter().all(|(_, pass)| *pass);
        Some(report)
    }

    /// The report of a run of 3-D high-speed cars ([`crate::physics::rail::run`]), which the
    /// recorder does not see: their running safety, and each body's vertical acceleration
    /// judged as every train's.
    pub fn of_rail_cars(out: &crate::physics::rail::run::RailOutcome) -> SafetyReport {
        let per_car: Vec<CarAcceleration> = out
            .body_az
            .iter()
            .enumerate()
            .map(|(k, a)| {
                let (i, peak) = a.iter().enumerate().fold((0, 0.0f64), |m, (i, v)| {
                    if v.abs() > m.1 {
                        (i, v.abs())
                    } else {
                        m
                    }
                });
                let rms = (a.iter().map(|v| v * v).sum::<f64>() / a.len().max(1) as f64).sqrt();
                CarAcceleration {
                    car: format!("car{}", k + 1),
                    peak,
                    t_s: i as f64 * out.dt,
                    rms,
                }
            })
            .collect();
        let worst = first_max(per_car.iter(), |c| c.peak);
        let rough = first_max(per_car.iter(), |c| c.rms);
        let mut report = SafetyReport {
            pass: true,
            body_acceleration_peak: Figure::new(
                worst.map_or(0.0, |c| c.peak),
                "m/s²",
                worst.map(|c| c.car.clone()),
                worst.map(|c| c.t_s),
            )
            .limit(Some(BODY_ACCEL_LIMIT), BODY_ACCEL_SOURCE, le),
            body_acceleration_rms: Figure::new(
                rough.map_or(0.0, |c| c.rms),
                "m/s²",
                rough.map(|c| c.car.clone()),
                None,
            )
            .limit(None, RMS_SOURCE, le),
            maglev: None,
            wheel_rail: None,
            high_speed: Some(running::high_speed_figures(out)),
            per_car,
        };
        report.pass = report.judged().iter().all(|(_, pass)| *pass);
        report
    }

    fn maglev_figures(&self) -> MaglevFigures {
        let ms = &self.magnets;
        let lowest = ms
            .iter()
            .min_by(|a, b| a.lev.value.total_cmp(&b.lev.value))
            .expect("some magnet");
        let levitation_gap_min = Figure::new(
            lowest.lev.value,
            "m",
            Some(format!("{}.z", wheel(lowest.node))),
            Some(lowest.lev.t),
        )
        .limit(Some(GAP_LIMIT), GAP_SOURCE, gt);
        let guidance_gap_min = ms
            .iter()
            .filter(|m| m.guided)
            .flat_map(|m| (0..2).map(move |k| (m, k)))
            .min_by(|a, b| a.0.guide[a.1].value.total_cmp(&b.0.guide[b.1].value))
            .map(|(m, k)| {
                Figure::new(
                    m.guide[k].value,
                    "m",
                    Some(format!("{}.{}", wheel(m.node), SIDES[k + 1])),
                    Some(m.guide[k].t),
                )
                .limit(Some(GAP_LIMIT), GAP_SOURCE, gt)
            });
        let c = &self.collisions;
        let collision_steps = Figure::new(c.steps as f64, "steps", None, c.first.map(|f| f.0))
            .limit(Some(0.0), CONTACT_SOURCE, le);
        // Each coil quantity's largest over every magnet (levitation and guidance).
        let coil_peak = |q: fn(&MagnetTrack) -> &[Extreme; 3]| {
            first_max(
                ms.iter()
                    .flat_map(|m| m.coils().map(move |k| (m, k, q(m)[k]))),
                |a| a.2.value,
            )
            .map(|(m, k, e)| (format!("{}.{}", wheel(m.node), SIDES[k]), e))
        };
        let (current_peak, voltage_peak, saturated_longest) = if self.coils {
            let current = coil_peak(|m| &m.current).map(|(at, e)| {
                Figure::new(e.value, "A", Some(at), Some(e.t)).limit(None, CURRENT_SOURCE, le)
            });
            let voltage = coil_peak(|m| &m.voltage).map(|(at, e)| {
                let source = match self.voltage_limit {
                    Some(_) => VOLTAGE_SOURCE,
                    None => NO_VOLTAGE_SOURCE,
                };
                Figure::new(e.value, "V", Some(at), Some(e.t)).limit(self.voltage_limit, source, le)
            });
            let saturated = first_max(
                ms.iter().flat_map(|m| m.coils().map(move |k| (m, k))),
                |a| a.0.saturated[a.1] as f64,
            )
            .map(|(m, k)| {
                let n = m.saturated[k];
                Figure::new(
                    n as f64 * self.dt,
                    "s",
                    (n > 0).then(|| format!("{}.{}", wheel(m.node), SIDES[k])),
                    None,
                )
                .limit(None, SATURATION_SOURCE, le)
            });
            (current, voltage, saturated)
        } else {
            (None, None, None)
        };
        let widest = first_max(ms.iter(), |m| m.deviation.0.value).expect("some magnet");
        let saturated = saturated_longest.as_ref().is_some_and(|f| f.value > 0.0);
        let gap_deviation_max = widest.deviation.0.value;
        let linear_range = LinearRange {
            within: !saturated && gap_deviation_max <= LINEAR_GAP_LIMIT,
            saturated,
            gap_deviation_max,
            at: format!("{}.{}", wheel(widest.node), SIDES[widest.deviation.1]),
            t_s: widest.deviation.0.t,
            gap_deviation_limit: LINEAR_GAP_LIMIT,
        };
        MaglevFigures {
            linear_range,
            levitation_gap_min,
            guidance_gap_min,
            collision_steps,
            current_peak,
            voltage_peak,
            saturated_longest,
            levitation_gap_per_magnet: ms
                .iter()
                .map(|m| MagnetGap {
                    magnet: format!("{}.z", wheel(m.node)),
                    min_m: m.lev.value,
                    t_s: m.lev.t,
                })
                .collect(),
            skid_contact: None,
        }
    }

    /// The name of every magnet wheel (`wheel{N}`, N its node along the train), in the
    /// order of the train's magnet wheels.
    pub fn magnet_wheel_names(&self) -> Vec<String> {
        self.magnets.iter().map(|m| wheel(m.node)).collect()
    }

    fn wheel_rail_figures(&self) -> WheelRailFigures {
        let cs = &self.contacts;
        let worst = first_max(cs.iter(), |c| c.unloading.value).expect("some contact");
        let unloading_max = Figure::new(
            worst.unloading.value,
            "1",
            Some(wheel(worst.node)),
            Some(worst.unloading.t),
        )
        .limit(Some(UNLOADING_LIMIT), UNLOADING_SOURCE, le);
        let l = &self.lift_offs;
        let lift_off_steps = Figure::new(
            l.steps as f64,
            "steps",
            l.first.and_then(|f| f.1).map(wheel),
            l.first.map(|f| f.0),
        )
        .limit(Some(0.0), LIFT_OFF_SOURCE, le);
        WheelRailFigures {
            unloading_max,
            lift_off_steps,
            derailment_quotient: NotComputed {
                computed: false,
                reason: QP_REASON,
            },
            per_contact: cs
                .iter()
                .map(|c| ContactUnloading {
                    wheel: wheel(c.node),
                    unloading: c.unloading.value,
                    t_s: c.unloading.t,
                    min_force: c.force.value,
                    p0: c.p0,
                })
                .collect(),
        }
    }
}
