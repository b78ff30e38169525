//! The open interface of a magnet's controller ([`Control`]): what the simulator's magnets
//! (`maglev run`) ask of the controller of every magnet. [`super::Law`], the core's laws
//! behind one type, is one implementation; a law written elsewhere (a test, a user's crate)
//! is another, and runs through the same magnets without a change to them.
//!
//! Every law drives the paper's coil (Eq. 9, a [`Levitation`], whose per-unit outputs and SI
//! conversion are every law's) and keeps its coil's [`State`] in its own state.

use super::state::StateLawState;
use super::{Batch, Compiled, Law, LawState, Measurement, Sensors};
use crate::gap::Geometry;
use crate::guidance::{self, PairOutput};
use crate::levitation::{Levitation, Output, State};
use crate::scalar::Scalar;

/// A compiled controller of one magnet, as its callers drive it.
pub trait Control<S: Scalar> {
    /// One magnet's state under this law.
    type State: Copy;

    /// The coil this law drives: its parameters (`h0`, `p0`, the step), per-unit outputs and
    /// their SI conversion ([`Levitation::to_si`]).
    fn coil(&self) -> &Levitation<S>;

    /// The coil's state within a magnet's state.
    fn coil_state(st: &Self::State) -> &State<S>;

    /// The coil's state within a magnet's state, to change.
    fn coil_state_mut(st: &mut Self::State) -> &mut State<S>;

    /// The measurements this law reads; a caller need not provide the others.
    fn sensors(&self) -> Sensors;

    /// The supply bound `V_max` (V) the law clamps the coil at, if any.
    fn voltage_bound(&self) -> Option<f64>;

    /// The period (s) at which the law updates the coil voltage.
    fn control_period(&self) -> f64;

    /// How a caller may run many magnets under this law at once ([`Batch`]); `None` (the
    /// default) when it may not.
    fn batch(&self) -> Option<Batch<'_, S>> {
        None
    }

    /// The state law's own states within a magnet's state, for a law whose
    /// [`Control::batch`] is [`Batch::State`]; `None` (the default) otherwise.
    fn state_law_state(_st: &Self::State) -> Option<&StateLawState<S>> {
        None
    }

    /// [`Control::state_law_state`], to change.
    fn state_law_state_mut(_st: &mut Self::State) -> Option<&mut StateLawState<S>> {
        None
    }

    /// Equilibrium at gap `h` (m).
    fn equilibrium_state(&self, h: f64) -> Self::State;

    /// One outer step from `st` to the measurement at its end; never panics.
    fn update(&self, st: &mut Self::State, m: Measurement<S>) -> Output<S>;

    /// Both magnets of a guidance pair in equilibrium at relative lateral position `d` (m):
    /// `[left, right]` at `h0 + d`, `h0 − d`.
    fn pair_equilibrium_state(&self, d: f64) -> [Self::State; 2] {
        let h0 = self.coil().params().h0;
        [
            self.equilibrium_state(h0 + d),
            self.equilibrium_state(h0 - d),
        ]
    }

    /// One outer step of both magnets of a guidance pair, each under this law on its own
    /// gap; `d_pu = (y_w − y_g + r_y)/h0` at the end of the step
    /// ([`guidance::update_with`]).
    fn update_pair(&self, geometry: Geometry, st: &mut [Self::State; 2], d_pu: S) -> PairOutput<S> {
        let [left, right] = st;
        guidance::update_with(geometry, left, right, d_pu, |s, h| {
            self.update(s, Measurement::gap(h))
        })
    }
}

impl<S: Scalar> Control<S> for Law<S> {
    type State = LawState<S>;

    fn coil(&self) -> &Levitation<S> {
        self.levitation()
    }

    #[inline]
    fn coil_state(st: &LawState<S>) -> &State<S> {
        &st.inner
    }

    #[inline]
    fn coil_state_mut(st: &mut LawState<S>) -> &mut State<S> {
        &mut st.inner
    }

    fn sensors(&self) -> Sensors {
        self.params().kind.sensors()
    }

    fn voltage_bound(&self) -> Option<f64> {
        self.params().voltage_bound()
    }

    fn control_period(&self) -> f64 {
        self.params().control_period()
    }

    #[inline]
    fn batch(&self) -> Option<Batch<'_, S>> {
        match &self.kind {
            Compiled::Paper => Some(Batch::Coil(self.levitation())),
            Compiled::State(l) => Some(Batch::State(l)),
            Compiled::GapLoop(_) => None,
        }
    }

    #[inline]
    fn state_law_state(st: &LawState<S>) -> Option<&StateLawState<S>> {
        Some(&st.state)
    }

    #[inline]
    fn state_law_state_mut(st: &mut LawState<S>) -> Option<&mut StateLawState<S>> {
        Some(&mut st.state)
    }

    fn equilibrium_state(&self, h: f64) -> LawState<S> {
        Law::equilibrium_state(self, h)
    }

    #[inline]
    fn update(&self, st: &mut LawState<S>, m: Measurement<S>) -> Output<S> {
        Law::update(self, st, m)
    }

    fn pair_equilibrium_state(&self, d: f64) -> [LawState<S>; 2] {
        Law::pair_equilibrium_state(self, d)
    }

    #[inline]
    fn update_pair(&self, geometry: Geometry, st: &mut [LawState<S>; 2], d_pu: S) -> PairOutput<S> {
        Law::update_pair(self, geometry, st, d_pu)
    }
}
