//! What callers ask of a law, answered by the law: its supply bound, its control period,
//! the sensors it reads, whether its updates batch, its section and gains by name. Callers
//! (the simulator's magnets, the stability model, the firmware, the C API) ask these
//! questions instead of matching on [`LawKind`].

use super::state::{StateLaw, StateParams};
use super::{LawKind, LawName, LawParams};
use crate::gap::Geometry;
use crate::gap_control::GapParams;
use crate::levitation::{accurate, Levitation, ParamError, Params, Scheme};

/// How a caller may run many magnets under a law at once, with the bits of one update per
/// magnet ([`super::Control::batch`]).
#[derive(Clone, Copy, Debug)]
pub enum Batch<'a, S> {
    /// Every update is the paper's law's `coil.update` on [`super::Control::coil_state`]
    /// alone ([`crate::levitation::batch::update_batch`]).
    Coil(&'a Levitation<S>),
    /// Every update is [`StateLaw::update`] on [`super::Control::coil_state`] and
    /// [`super::Control::state_law_state`], the magnet's acceleration read where the law's
    /// sensors say ([`super::state::batch::update_batch`]).
    State(&'a StateLaw<S>),
}

/// The measurements a law reads at the end of a step ([`super::Measurement`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Sensors {
    /// The magnet's gap (every law here).
    pub gap: bool,
    /// The magnet's absolute acceleration along the gap's axis (an accelerometer).
    pub accel: bool,
    /// The coil current (a current sensor; the laws here integrate their own coil).
    pub current: bool,
}

impl Sensors {
    /// The gap alone.
    pub const GAP: Sensors = Sensors {
        gap: true,
        accel: false,
        current: false,
    };
    /// The gap and the magnet's acceleration.
    pub const GAP_ACCEL: Sensors = Sensors {
        gap: true,
        accel: true,
        current: false,
    };
}

impl LawName {
    /// The law's own section under `[controller]` (`state` for `[controller.state]`), where
    /// scenarios give its parameters; `None` for a law without one (the paper's law's gains
    /// are `[controller]`'s own, the gap loop's are designed).
    pub const fn section(self) -> Option<&'static str> {
        match self {
            LawName::Paper | LawName::GapLoop => None,
            LawName::State => Some("state"),
        }
    }
}

impl LawKind {
    /// The sensors this law reads.
    pub const fn sensors(&self) -> Sensors {
        match self {
            LawKind::Paper | LawKind::GapLoop(_) => Sensors::GAP,
            LawKind::State(_) => Sensors::GAP_ACCEL,
        }
    }

    /// Whether this law's update is the paper's law's alone on the coil state, so that a
    /// caller may run many magnets under it at once ([`crate::levitation::batch`]).
    pub const fn batches(&self) -> bool {
        matches!(self, LawKind::Paper)
    }

    /// Whether this law drives the coil voltage itself at its own control rate (its supply
    /// bound and period are its own), rather than through the paper's law (Eq. 10–11).
    pub const fn drives_voltage(&self) -> bool {
        matches!(self, LawKind::State(_))
    }

    /// The gap loop's gains, when this is the gap loop (for the studies that design or
    /// analyse that law).
    pub const fn gap_loop(&self) -> Option<&GapParams> {
        match self {
            LawKind::GapLoop(g) => Some(g),
            _ => None,
        }
    }

    /// The state law's gains and timing, when this is the state law (for the studies that
    /// design or analyse that law).
    pub const fn state(&self) -> Option<&StateParams> {
        match self {
            LawKind::State(s) => Some(s),
            _ => None,
        }
    }

    /// This law on magnets facing their rails as `geometry` (docs/model.md §2), for a law
    /// whose parameters carry it (the state law's observer); others are unchanged.
    pub fn with_geometry(self, geometry: Geometry) -> Self {
        match self {
            LawKind::State(s) => LawKind::State(StateParams { geometry, ..s }),
            other => other,
        }
    }

    /// Checks the law's own parameters (those [`LawParams::compile`] checks beyond the
    /// magnet's), naming the first bad one.
    pub fn validate(&self) -> Result<(), ParamError> {
        match self {
            LawKind::Paper => Ok(()),
            LawKind::GapLoop(g) => g.validate(),
            LawKind::State(s) => s.validate(),
        }
    }

    /// The supply bound `V_max` (V) this law clamps the coil at over the magnet `magnet`,
    /// if it has one: the state law's own `vmax_V`, otherwise the paper's Eq. 11 bound
    /// `magnet.v_max` (the gap loop drives the paper's law); `None` when that is infinite.
    pub fn voltage_bound(&self, magnet: &Params) -> Option<f64> {
        let v = match self {
            LawKind::State(s) => s.v_max,
            LawKind::Paper | LawKind::GapLoop(_) => magnet.v_max,
        };
        v.is_finite().then_some(v)
    }

    /// How many times per structural step `dt` this law updates the coil voltage over the
    /// magnet `magnet`: the state law's control periods, else the inner law's sub-steps
    /// (`n_sub`, or the accurate scheme's Gauss intervals).
    pub fn sub_steps(&self, magnet: &Params, dt: f64) -> u32 {
        match self {
            LawKind::State(s) => s.periods(dt),
            LawKind::Paper | LawKind::GapLoop(_) => match magnet.scheme {
                Scheme::Paper => magnet.n_sub,
                Scheme::Accurate => accurate::intervals(&Params { dt, ..*magnet }),
            },
        }
    }

    /// The period (s) at which this law updates the coil voltage within a structural step
    /// `dt`: `dt` over [`LawKind::sub_steps`].
    pub fn control_period(&self, magnet: &Params, dt: f64) -> f64 {
        dt / self.sub_steps(magnet, dt) as f64
    }
}

impl LawParams {
    /// [`LawKind::voltage_bound`] over this law's magnet.
    pub fn voltage_bound(&self) -> Option<f64> {
        self.kind.voltage_bound(&self.magnet)
    }

    /// [`LawKind::control_period`] at this law's step `magnet.dt`.
    pub fn control_period(&self) -> f64 {
        self.kind.control_period(&self.magnet, self.magnet.dt)
    }
}
