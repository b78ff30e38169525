//! The levitation laws behind one type: every magnet of the simulator and every channel of the
//! firmware runs a [`Law`], whichever law it is.
//!
//! # Why one type
//! A magnet's controller is configured once ([`LawParams`]: the magnet and coil of
//! [`Params`] with the law's own gains in [`LawKind`]), compiled once to the run-time scalar
//! ([`LawParams::compile`]) and then stepped as `update(&self, &mut LawState, Measurement)`:
//! configuration apart from state, as in [`crate::levitation`]. Callers hold a `Law<S>` and
//! never branch on which law it is, so a new law is one file beside its siblings (its
//! parameters, compiled form, state and update), one arm in each enum of this module, and the
//! plant arm of the host's linear stability model; no caller changes.
//!
//! # The laws
//! * [`LawKind::Paper`]: the paper's α-method PI law on `g = i/h` with its internal loop
//!   (Eq. 8–14, [`crate::levitation`]).
//! * [`LawKind::GapLoop`]: an outer gap loop setting the paper's law's reference
//!   ([`crate::gap_control`]).
//! * [`LawKind::State`]: state feedback on gap, gap rate, acceleration, its integral and the
//!   current, driving the coil's voltage ([`state`]): the law that holds an EMS magnet's gap.
//!
//! # Measurement
//! Every law reads the gap at the end of the step; a [`Measurement`] may also carry the magnet's
//! absolute vertical acceleration and the coil current, for laws that feed them back. The
//! paper's law and the gap loop read the gap alone; the state law reads the acceleration too.
//! Every law here integrates its coil (Eq. 9) itself, so the current it feeds back is its own
//! state; `current` is for a law whose coil is outside the core (none yet).
//!
//! # Guidance pairs
//! A guidance pair ([`crate::guidance`]) is two magnets under the same law on the gaps
//! `h0 ± d`: [`Law::update_pair`].

mod control;
mod field;
pub mod guidance;
mod properties;
pub mod state;

pub use control::Control;
pub use field::Field;
pub use properties::{Batch, Sensors};

use crate::gap::Geometry;
use crate::gap_control::{GapLoop, GapParams, GapState};
use crate::guidance::PairOutput;
use crate::levitation::{Levitation, Output, ParamError, Params, State, Status};
use crate::scalar::Scalar;
use state::{StateLaw, StateLawState, StateParams};

/// Which law a magnet runs, with the law's own gains (the magnet and the paper's inner gains are
/// in [`LawParams::magnet`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum LawKind {
    /// The paper's PI law on `g = i/h` (Eq. 8–14).
    #[default]
    Paper,
    /// The outer gap loop around the paper's law ([`crate::gap_control`]).
    GapLoop(GapParams),
    /// State feedback driving the coil voltage ([`state`]).
    State(StateParams),
}

/// A law's name, as scenarios and command lines write it (`paper`, `gap-loop`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum LawName {
    /// [`LawKind::Paper`].
    #[default]
    Paper,
    /// [`LawKind::GapLoop`].
    GapLoop,
    /// [`LawKind::State`].
    State,
}

impl LawName {
    /// The name as written (`paper`, `gap-loop`).
    pub const fn as_str(self) -> &'static str {
        match self {
            LawName::Paper => "paper",
            LawName::GapLoop => "gap-loop",
            LawName::State => "state",
        }
    }
}

impl LawKind {
    /// This law's name.
    pub const fn name(&self) -> LawName {
        match self {
            LawKind::Paper => LawName::Paper,
            LawKind::GapLoop(_) => LawName::GapLoop,
            LawKind::State(_) => LawName::State,
        }
    }
}

/// Everything a magnet's controller is compiled from: the magnet and coil with the paper's
/// inner law ([`Params`], SI, f64) and the law on top of it.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct LawParams {
    /// Magnet, coil, the paper's gains, the step and its integrator.
    pub magnet: Params,
    /// The law.
    pub kind: LawKind,
}

impl LawParams {
    /// Checks every parameter and converts once to the run-time type `S`.
    pub fn compile<S: Scalar>(&self) -> Result<Law<S>, ParamError> {
        let inner = self.magnet.compile::<S>()?;
        let kind = match self.kind {
            LawKind::Paper => Compiled::Paper,
            LawKind::GapLoop(g) => Compiled::GapLoop(g.compile::<S>(self.magnet.dt)?),
            LawKind::State(p) => Compiled::State(p.compile::<S>(&self.magnet)?),
        };
        Ok(Law { inner, kind })
    }
}

/// What a law reads at the end of a step. Per unit, as the core's laws run: the gap `h/h0`,
/// the acceleration in units of [`crate::levitation::GRAVITY`] (Z up), the current `i/i0`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Measurement<S> {
    /// Gap `h/h0`.
    pub gap: S,
    /// The magnet's absolute vertical acceleration `a/g` (Z up), where measured.
    pub accel: Option<S>,
    /// Coil current `i/i0`, where measured.
    pub current: Option<S>,
}

impl<S> Measurement<S> {
    /// A gap sample alone.
    pub const fn gap(gap: S) -> Self {
        Measurement {
            gap,
            accel: None,
            current: None,
        }
    }
}

/// The compiled law-specific part.
#[derive(Clone, Copy, Debug)]
enum Compiled<S> {
    Paper,
    GapLoop(GapLoop<S>),
    State(StateLaw<S>),
}

/// A compiled controller of one magnet: any law, one type.
#[derive(Clone, Copy, Debug)]
pub struct Law<S> {
    /// The paper's law: the coil and flux loop every law here drives (its outputs and SI
    /// conversion are every law's).
    inner: Levitation<S>,
    kind: Compiled<S>,
}

/// State of one magnet under a [`Law`]: the coil and inner loop ([`State`]) and each law's own
/// states (a law leaves the others' at rest).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LawState<S> {
    /// The coil and the paper's inner loop; its `eta` is the last measured gap.
    pub inner: State<S>,
    /// The gap loop's derivative filter.
    pub q: S,
    /// The state law's integral and observer.
    pub state: StateLawState<S>,
}

impl<S: Scalar> Law<S> {
    /// The paper's inner law (coil, flux loop, per-unit conversions, [`Levitation::to_si`]).
    pub fn levitation(&self) -> &Levitation<S> {
        &self.inner
    }

    /// The parameters this law was compiled from.
    pub fn params(&self) -> LawParams {
        LawParams {
            magnet: *self.inner.params(),
            kind: match &self.kind {
                Compiled::Paper => LawKind::Paper,
                Compiled::GapLoop(g) => LawKind::GapLoop(*g.params()),
                Compiled::State(l) => LawKind::State(*l.params()),
            },
        }
    }

    /// The state law, when this is one: [`Law::update`]'s state arm is its
    /// [`StateLaw::update`] on the state's `inner` and `state`, so a caller that runs many
    /// magnets under it (the firmware's tick) chooses the law once, not per magnet, as it
    /// does for the paper's law through [`Law::levitation`].
    pub fn state_law(&self) -> Option<&StateLaw<S>> {
        match &self.kind {
            Compiled::State(l) => Some(l),
            _ => None,
        }
    }

    /// Whether this is the paper's law alone (whose updates may be batched,
    /// [`crate::levitation::batch`]).
    pub fn is_paper(&self) -> bool {
        matches!(self.kind, Compiled::Paper)
    }

    /// Equilibrium at gap `h` (m): the coil at the static load, every filter at rest there.
    pub fn equilibrium_state(&self, h: f64) -> LawState<S> {
        let inner = self.inner.equilibrium_state(h);
        let state = match &self.kind {
            Compiled::State(l) => l.equilibrium(&inner),
            _ => StateLawState::default(),
        };
        LawState {
            inner,
            q: inner.eta,
            state,
        }
    }

    /// [`Law::equilibrium_state`], refusing a NaN, non-positive or unrepresentable gap by name
    /// ([`Levitation::try_equilibrium_state`]).
    pub fn try_equilibrium_state(&self, h: f64) -> Result<LawState<S>, ParamError> {
        self.inner.try_equilibrium_state(h)?;
        Ok(self.equilibrium_state(h))
    }

    /// Both magnets of a guidance pair in equilibrium at relative lateral position `d` (m):
    /// `[left, right]` at `h0 + d`, `h0 − d` ([`crate::guidance::initial_state`]).
    pub fn pair_equilibrium_state(&self, d: f64) -> [LawState<S>; 2] {
        let h0 = self.inner.params().h0;
        [
            self.equilibrium_state(h0 + d),
            self.equilibrium_state(h0 - d),
        ]
    }

    /// One outer step from `st` to the measurement at its end; never panics (events in the
    /// output's status).
    pub fn update(&self, st: &mut LawState<S>, m: Measurement<S>) -> Output<S> {
        match &self.kind {
            Compiled::Paper => self.inner.update(&mut st.inner, m.gap),
            Compiled::GapLoop(g) => {
                let mut gs = GapState {
                    inner: st.inner,
                    q: st.q,
                };
                let o = g.update(&self.inner, &mut gs, m.gap);
                (st.inner, st.q) = (gs.inner, gs.q);
                let mut out = o.inner;
                if o.reference_limited {
                    out.status = out.status.union(Status::REFERENCE_LIMITED);
                }
                out
            }
            Compiled::State(l) => l.update(&mut st.inner, &mut st.state, m.gap, m.accel),
        }
    }

    /// One outer step of both magnets of a guidance pair, each under this law on its own gap;
    /// `d_pu = (y_w − y_g + r_y)/h0` at the end of the step ([`crate::guidance::update_with`]).
    pub fn update_pair(
        &self,
        geometry: Geometry,
        st: &mut [LawState<S>; 2],
        d_pu: S,
    ) -> PairOutput<S> {
        let [left, right] = st;
        crate::guidance::update_with(geometry, left, right, d_pu, |s, h| {
            self.update(s, Measurement::gap(h))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gap_control::GapParams;

    /// Each arm gives the bits of the law it wraps, single magnets and pairs.
    #[test]
    fn each_arm_is_its_law() {
        let magnet = Params::paper_wheel(1e-3);
        let lev = magnet.compile::<f64>().unwrap();
        let gl = GapParams::designed().compile::<f64>(magnet.dt).unwrap();
        for kind in [LawKind::Paper, LawKind::GapLoop(GapParams::designed())] {
            let law = LawParams { magnet, kind }.compile::<f64>().unwrap();
            assert_eq!(law.params().kind, kind);
            let mut st = law.equilibrium_state(0.0101);
            let mut reference = GapState {
                inner: st.inner,
                q: st.q,
            };
            let mut pair = law.pair_equilibrium_state(2e-4);
            let mut pair_ref = pair;
            for k in 0..200 {
                let h = 1.0 + 0.05 * libm::sin(k as f64 * 0.1);
                let out = law.update(&mut st, Measurement::gap(h));
                let want = match kind {
                    LawKind::Paper => lev.update(&mut reference.inner, h),
                    _ => {
                        let o = gl.update(&lev, &mut reference, h);
                        let mut out = o.inner;
                        if o.reference_limited {
                            out.status = out.status.union(Status::REFERENCE_LIMITED);
                        }
                        out
                    }
                };
                assert_eq!(out, want, "step {k}");
                assert_eq!((st.inner, st.q), (reference.inner, reference.q));
                let d = 0.03 * libm::cos(k as f64 * 0.07);
                let po = law.update_pair(Geometry::Ems, &mut pair, d);
                let [l, r] = &mut pair_ref;
                let want = crate::guidance::update_with(Geometry::Ems, l, r, d, |s, h| {
                    law.update(s, Measurement::gap(h))
                });
                assert_eq!(po, want, "pair step {k}");
            }
        }
    }

    #[test]
    fn a_bad_gain_is_named() {
        let law = LawParams {
            magnet: Params::paper_wheel(1e-3),
            kind: LawKind::GapLoop(GapParams {
                tf: -1.0,
                ..GapParams::designed()
            }),
        };
        assert_eq!(
            law.compile::<f32>().unwrap_err(),
            ParamError::Negative(crate::gap_control::fields::TF)
        );
    }
}
