//! The ideal magnets of `maglev run`: per wheel the core's levitation law and guidance pair in
//! f64 on the exact gaps at the end of each step — the paper's scheme, with its internal loop
//! (`n_sub`) interpolating the gap inside the step — under any [`maglev_core::Law`], or any
//! other law behind the core's open interface [`maglev_core::Control`] (a law written outside
//! the core runs here unchanged: `CoreMagnets::with_laws`). Calls the core; never a host copy
//! of a law. What differs between laws (which sensors they read, whether and how their updates
//! batch, [`maglev_core::law::Batch`]) is asked of the law.

use super::{Magnets, Settings, Start, WheelGaps};
use crate::physics::train::Train;
use crate::physics::vehicle::Coil;
use crate::{Error, Result};
use maglev_core::gap::Geometry;
use maglev_core::guidance;
use maglev_core::law::guidance::{GuidanceLaw, GuidanceParams, GuidanceState, PairMeasurement};
use maglev_core::law::state::{batch as state_batch, StateLaw, StateLawState};
use maglev_core::law::Batch;
use maglev_core::levitation::batch::update_batch;
use maglev_core::levitation::GRAVITY;
use maglev_core::levitation::{Output, State};
use maglev_core::{
    Control, Law, LawKind, LawParams, Levitation, Measurement, ParamError, Params, Status,
};

struct WheelCtl<L: Control<f64>> {
    /// The law of the wheel's three magnets.
    law: L,
    /// Whether the law reads the magnet's acceleration (asked once, [`Control::sensors`]).
    accel: bool,
    /// The levitation magnet's state.
    lev_state: L::State,
    /// The guidance pair's states, `[left, right]` (under a guidance law, their coils are
    /// its coils, copied after every update).
    pair: [L::State; 2],
    /// The guidance pair's own law (`[controller.guidance]`), if the run has one.
    guide: Option<Guide>,
}

/// A guidance pair under the guidance law (`maglev_core::law::guidance`): the law, its
/// committed state and the trial of the last [`Magnets::forces`].
struct Guide {
    law: GuidanceLaw<f64>,
    committed: GuidanceState<f64>,
    trial: GuidanceState<f64>,
}

/// The guidance law of one wheel's pair as a run compiles it: `guidance` with the timing and
/// supply of the levitation state law `law`, over the wheel's magnet (its `p0`, the run's
/// `Δt`); a refusal names the key.
pub fn compile_guidance(
    guidance: &GuidanceParams,
    law: &LawKind,
    magnet: &Params,
) -> Result<GuidanceLaw<f64>> {
    let timing = law
        .state()
        .ok_or_else(crate::error::guidance_needs_state_law)?;
    guidance
        .compile::<f64>(timing, magnet)
        .map_err(crate::error::guidance_error)
}

/// The trial state of a step, if any.
#[derive(Clone, Copy, Default, PartialEq)]
enum Pending {
    #[default]
    None,
    /// In `mag_st` and `law_st` ([`CoreMagnets::batched`]).
    Batch,
    /// In `trial`.
    General,
}

/// How every wheel's magnets run at once ([`Batch`], the same for every wheel).
#[derive(Clone, Copy, PartialEq)]
enum Batched {
    /// The paper's law: `update_batch` on the coils.
    Coil,
    /// The state law: `state_batch::update_batch` on the coils and the laws' states.
    State,
}

/// The law of one magnet wheel as a run compiles it: `controller` with the wheel's static load
/// `p0` (N) and the run's step `dt` (s), under `kind`; a refusal names `controller`. Every
/// check a run makes of its law is this one, so `maglev stability --scenario` calls it too
/// and never judges a law a run refuses.
pub fn compile_law(controller: &Params, kind: LawKind, p0: f64, dt: f64) -> Result<Law<f64>> {
    let magnet = Params {
        p0,
        dt,
        ..*controller
    };
    LawParams { magnet, kind }
        .compile::<f64>()
        .map_err(|e| Error::invalid("controller", e.to_string()))
}

/// How [`CoreMagnets`] builds one wheel's law when a run starts: from the run's settings and
/// the wheel's magnet (`s.controller` with its `p0` and the run's `Δt`).
pub type Builder<L> = Box<dyn FnMut(&Settings, Params) -> std::result::Result<L, ParamError>>;

/// The core's controllers of every wheel, committed and trial states: the core's [`Law`] by
/// default, or any law `L` behind [`Control`]. Empty until [started](Magnets::start) on a
/// run's train.
pub struct CoreMagnets<L: Control<f64> = Law<f64>> {
    /// Builds one wheel's law from its magnet (the run's settings, the magnet's `p0` and `Δt`)
    /// when a run [starts](Magnets::start).
    build: Builder<L>,
    ctl: Vec<WheelCtl<L>>,
    /// Per magnet (levitation, guidance left, right of each wheel): its controller, state
    /// and per-unit gap, for the interleaved update of the paper's law ([`Batched::Coil`];
    /// empty otherwise).
    mags: Vec<Levitation<f64>>,
    /// The state law of each magnet in that order ([`Batched::State`]; empty otherwise).
    state_laws: Vec<StateLaw<f64>>,
    /// The committed coil states in that order (the wheels' `lev_state.inner`,
    /// `pair.left.inner`, `pair.right.inner`, refreshed on every commit) and the trial.
    mag_committed: Vec<State<f64>>,
    mag_st: Vec<State<f64>>,
    /// The state law's own states, committed and trial, in that order ([`Batched::State`]).
    law_committed: Vec<StateLawState<f64>>,
    law_st: Vec<StateLawState<f64>>,
    mag_h: Vec<f64>,
    /// Per magnet its acceleration `a/g` where its law reads one, else 0.
    mag_a: Vec<f64>,
    mag_out: Vec<Output<f64>>,
    /// The trial of the general path (one entry per wheel); the paper batch's trial is the
    /// inner states in `mag_st` (its filters `q` stay the committed ones).
    trial: Vec<(L::State, [L::State; 2])>,
    /// The general path's outputs of its trial, per wheel `[levitation, left, right]` (the
    /// batch's are in `mag_out`).
    trial_out: Vec<[Output<f64>; 3]>,
    /// Every magnet's coil at the last committed step ([`Magnets::coils`]).
    coils: Vec<[Coil; 3]>,
    /// Each wheel's lateral acceleration at the iterate ([`Magnets::lateral_accels`]).
    accels_y: Vec<f64>,
    /// Which trial the last `forces` left.
    pending: Pending,
    /// How every wheel's law batches, if they all do alike ([`Control::batch`], asked once).
    batch: Option<Batched>,
    status: Status,
    geometry: Geometry,
}

impl CoreMagnets {
    /// The core's controllers (the law of the run's `s.law` on every magnet), to be
    /// [started](Magnets::start) on a run's train.
    pub fn new() -> Self {
        Self::with_laws(|s, magnet| {
            LawParams {
                magnet,
                kind: s.law,
            }
            .compile::<f64>()
        })
    }
}

impl Default for CoreMagnets {
    fn default() -> Self {
        Self::new()
    }
}

impl<L: Control<f64>> CoreMagnets<L> {
    /// As [`CoreMagnets::new`], each wheel's controller built by `build` from the run's
    /// settings and its magnet when the run starts: any law behind [`Control`].
    pub fn with_laws(
        build: impl FnMut(&Settings, Params) -> std::result::Result<L, ParamError> + 'static,
    ) -> Self {
        CoreMagnets {
            build: Box::new(build),
            ctl: Vec::new(),
            mags: Vec::new(),
            state_laws: Vec::new(),
            mag_committed: Vec::new(),
            mag_st: Vec::new(),
            law_committed: Vec::new(),
            law_st: Vec::new(),
            mag_h: Vec::new(),
            mag_a: Vec::new(),
            mag_out: Vec::new(),
            trial: Vec::new(),
            trial_out: Vec::new(),
            coils: Vec::new(),
            accels_y: Vec::new(),
            pending: Pending::None,
            batch: None,
            status: Status::default(),
            geometry: Geometry::default(),
        }
    }

    /// Every controller in equilibrium at the wheel's initial gaps `gaps0`
    /// ([`super::initial_gaps`]); `p0` per wheel from the vehicle, `Δt` from the run.
    fn for_train(&mut self, v: &Train, gaps0: &[WheelGaps], s: &Settings) -> Result<()> {
        let mut ctl = Vec::with_capacity(v.wheels.len());
        for (&p0, &(h_init, gy)) in v.p0.iter().zip(gaps0) {
            let mut magnet = s.controller;
            magnet.p0 = p0;
            magnet.dt = s.dt;
            let law =
                (self.build)(s, magnet).map_err(|e| Error::invalid("controller", e.to_string()))?;
            let mut pair = law.pair_equilibrium_state(gy);
            let guide = match &s.guidance {
                Some(g) => {
                    let law = compile_guidance(g, &s.law, &magnet)?;
                    let st = law.equilibrium(gy);
                    *L::coil_state_mut(&mut pair[0]) = st.left;
                    *L::coil_state_mut(&mut pair[1]) = st.right;
                    Some(Guide {
                        law,
                        committed: st,
                        trial: st,
                    })
                }
                None => None,
            };
            ctl.push(WheelCtl {
                accel: law.sensors().accel,
                lev_state: law.equilibrium_state(h_init),
                pair,
                guide,
                law,
            });
        }
        self.accels_y = vec![0.0; ctl.len()];
        let batch = batched(&ctl);
        let n = 3 * ctl.len();
        self.mags.clear();
        self.state_laws.clear();
        for c in &ctl {
            match c.law.batch() {
                Some(Batch::Coil(lev)) if batch == Some(Batched::Coil) => {
                    self.mags.extend([*lev; 3]);
                }
                Some(Batch::State(l)) if batch == Some(Batched::State) => {
                    self.state_laws.extend([*l; 3]);
                }
                _ => {}
            }
        }
        self.mag_committed = vec![State::default(); n];
        self.mag_st = vec![State::default(); n];
        let laws = if batch == Some(Batched::State) { n } else { 0 };
        self.law_committed = vec![StateLawState::default(); laws];
        self.law_st = vec![StateLawState::default(); laws];
        self.mag_h = vec![0.0; n];
        self.mag_a = vec![0.0; n];
        self.mag_out = vec![Output::default(); n];
        self.trial = Vec::with_capacity(ctl.len());
        self.trial_out = Vec::with_capacity(ctl.len());
        self.coils = ctl
            .iter()
            .map(|c| {
                let out = |s: &L::State| c.law.coil().output(L::coil_state(s));
                coils(
                    &c.law,
                    &[out(&c.lev_state), out(&c.pair[0]), out(&c.pair[1])],
                )
            })
            .collect();
        self.pending = Pending::None;
        self.batch = batch;
        self.ctl = ctl;
        self.status = Status::default();
        self.geometry = s.geometry;
        self.gather_committed();
        Ok(())
    }

    /// `mag_committed` (and `law_committed`) from the wheels' committed states.
    fn gather_committed(&mut self) {
        for (c, st) in self.ctl.iter().zip(self.mag_committed.chunks_exact_mut(3)) {
            st.copy_from_slice(&[
                *L::coil_state(&c.lev_state),
                *L::coil_state(&c.pair[0]),
                *L::coil_state(&c.pair[1]),
            ]);
        }
        for (c, st) in self.ctl.iter().zip(self.law_committed.chunks_exact_mut(3)) {
            for (s, m) in st.iter_mut().zip([&c.lev_state, &c.pair[0], &c.pair[1]]) {
                if let Some(l) = L::state_law_state(m) {
                    *s = *l;
                }
            }
        }
    }

    /// Every magnet at once by its law's batch ([`update_batch`], [`state_batch`]: the bits
    /// of one update per magnet), the guidance pairs' net forces by the core's
    /// [`guidance::update_with`] on the outputs. Finite gaps only (the per-unit guidance gaps
    /// `1 ± d` are then formed as the core forms them).
    ///
    /// The trial states stay in `mag_st` and `law_st` ([`Pending::Batch`]); `commit` takes
    /// them.
    fn batched(
        &mut self,
        batch: Batched,
        gaps_next: &[WheelGaps],
        accels: &[f64],
        out: &mut [(f64, f64)],
    ) {
        let n = self.ctl.len();
        self.mag_st.copy_from_slice(&self.mag_committed);
        for (((c, &(hz, dy)), h), (a, &accel)) in self
            .ctl
            .iter()
            .zip(gaps_next)
            .zip(self.mag_h.chunks_exact_mut(3))
            .zip(self.mag_a.chunks_exact_mut(3).zip(accels))
        {
            let h0 = c.law.coil().params().h0;
            let d = dy / h0;
            h.copy_from_slice(&[hz / h0, 1.0 + d, 1.0 - d]);
            // The guidance magnets read their gaps alone (`Control::update_pair`).
            a[0] = if c.accel { accel / GRAVITY } else { 0.0 };
        }
        match batch {
            Batched::Coil => {
                update_batch(&self.mags, &mut self.mag_st, &self.mag_h, &mut self.mag_out);
            }
            Batched::State => {
                self.law_st.copy_from_slice(&self.law_committed);
                state_batch::update_batch(
                    &self.state_laws,
                    &mut self.mag_st,
                    &mut self.law_st,
                    &self.mag_h,
                    &self.mag_a,
                    &mut self.mag_out,
                );
            }
        }
        let mut status = self.status;
        for (((c, &(_, dy)), o), out) in self
            .ctl
            .iter()
            .zip(&gaps_next[..n])
            .zip(self.mag_out.chunks_exact(3))
            .zip(&mut out[..n])
        {
            let (lev_out, mut l, mut r) = (o[0], o[1], o[2]);
            let magnet = c.law.coil().params();
            let d = dy / magnet.h0;
            let pair_out = guidance::update_with(self.geometry, &mut l, &mut r, d, |o, _| *o);
            status = status.union(lev_out.status).union(pair_out.status);
            let p0 = magnet.p0;
            *out = (lev_out.force * p0, pair_out.force_y * p0);
        }
        self.status = status;
        self.pending = Pending::Batch;
    }

    /// Every wheel by its own law (any law, any gap): the trial in `trial`
    /// ([`Pending::General`]).
    fn general(&mut self, gaps_next: &[WheelGaps], accels: &[f64], out: &mut [(f64, f64)]) {
        for (i, c) in self.ctl.iter_mut().enumerate() {
            let (hz, dy) = gaps_next[i];
            let magnet = c.law.coil().params();
            let h0 = magnet.h0;
            let mut st = c.lev_state;
            let lev_out = c.law.update(
                &mut st,
                Measurement {
                    gap: hz / h0,
                    accel: c.accel.then(|| accels[i] / GRAVITY),
                    current: None,
                },
            );
            let mut pair = c.pair;
            let pair_out = match &mut c.guide {
                Some(g) => {
                    g.trial = g.committed;
                    let m = PairMeasurement {
                        d: dy / h0,
                        accel: Some(self.accels_y[i] / GRAVITY),
                    };
                    let out = g.law.update(&mut g.trial, m, self.geometry);
                    *L::coil_state_mut(&mut pair[0]) = g.trial.left;
                    *L::coil_state_mut(&mut pair[1]) = g.trial.right;
                    out
                }
                None => c.law.update_pair(self.geometry, &mut pair, dy / h0),
            };
            self.status = self.status.union(lev_out.status).union(pair_out.status);
            let p0 = magnet.p0;
            out[i] = (lev_out.force * p0, pair_out.force_y * p0);
            self.trial.push((st, pair));
            self.trial_out
                .push([lev_out, pair_out.left, pair_out.right]);
        }
        self.pending = Pending::General;
    }
}

impl<L: Control<f64>> Magnets for CoreMagnets<L> {
    fn start(&mut self, start: &Start<'_>) -> Result<()> {
        self.for_train(start.train, start.gaps, start.settings)
    }

    /// One update of every law from the committed state to the gaps at the end of the step
    /// (the law interpolates from the gap its state last saw; `gaps_prev` is that gap).
    fn forces(
        &mut self,
        _step: u32,
        _t: f64,
        _gaps_prev: &[WheelGaps],
        gaps_next: &[WheelGaps],
        accels: &[f64],
        out: &mut [(f64, f64)],
    ) -> Result<()> {
        self.trial.clear();
        self.trial_out.clear();
        self.pending = Pending::None;
        self.status = Status::default();
        let finite = gaps_next.iter().all(|g| g.0.is_finite() && g.1.is_finite());
        match self.batch {
            Some(batch) if finite => self.batched(batch, gaps_next, accels, out),
            _ => self.general(gaps_next, accels, out),
        }
        Ok(())
    }

    fn lateral_accels(&mut self, accels_y: &[f64]) {
        let n = self.accels_y.len();
        self.accels_y.copy_from_slice(&accels_y[..n]);
    }

    fn commit(&mut self, _step: u32, _t: f64) -> Result<()> {
        match self.pending {
            Pending::None => return Err(Error::numerical("internal: commit without a step")),
            Pending::Batch => {
                for (c, st) in self.ctl.iter_mut().zip(self.mag_st.chunks_exact(3)) {
                    *L::coil_state_mut(&mut c.lev_state) = st[0];
                    *L::coil_state_mut(&mut c.pair[0]) = st[1];
                    *L::coil_state_mut(&mut c.pair[1]) = st[2];
                }
                for (c, st) in self.ctl.iter_mut().zip(self.law_st.chunks_exact(3)) {
                    let [left, right] = &mut c.pair;
                    for (m, s) in [&mut c.lev_state, left, right].into_iter().zip(st) {
                        if let Some(l) = L::state_law_state_mut(m) {
                            *l = *s;
                        }
                    }
                }
                self.mag_committed.copy_from_slice(&self.mag_st);
                self.law_committed.copy_from_slice(&self.law_st);
                for ((c, o), coil) in self
                    .ctl
                    .iter()
                    .zip(self.mag_out.chunks_exact(3))
                    .zip(&mut self.coils)
                {
                    *coil = coils(&c.law, o);
                }
            }
            Pending::General => {
                for ((c, (st, pair)), (o, coil)) in self
                    .ctl
                    .iter_mut()
                    .zip(self.trial.drain(..))
                    .zip(self.trial_out.iter().zip(&mut self.coils))
                {
                    c.lev_state = st;
                    c.pair = pair;
                    if let Some(g) = &mut c.guide {
                        g.committed = g.trial;
                    }
                    *coil = coils(&c.law, o);
                }
                self.gather_committed();
            }
        }
        self.pending = Pending::None;
        Ok(())
    }

    fn status(&self) -> Status {
        self.status
    }

    fn coils(&self) -> &[[Coil; 3]] {
        &self.coils
    }
}

/// How every wheel's law batches, if all alike: the paper's law on every wheel, or the state
/// law on every wheel whose states hold the state law's ([`Control::state_law_state`]).
fn batched<L: Control<f64>>(ctl: &[WheelCtl<L>]) -> Option<Batched> {
    // A guided wheel's lateral pair runs the guidance law, one wheel at a time.
    let of = |c: &WheelCtl<L>| match c.law.batch().filter(|_| c.guide.is_none())? {
        Batch::Coil(_) => Some(Batched::Coil),
        Batch::State(_) => L::state_law_state(&c.lev_state).map(|_| Batched::State),
    };
    let first = of(ctl.first()?)?;
    ctl.iter().all(|c| of(c) == Some(first)).then_some(first)
}

/// A wheel's three magnets' coils in SI from their law's outputs `[levitation, left, right]`.
fn coils<L: Control<f64>>(law: &L, o: &[Output<f64>]) -> [Coil; 3] {
    [0, 1, 2].map(|k| {
        let si = law.coil().to_si(&o[k]);
        Coil {
            current: si.current,
            voltage: si.voltage,
            saturated: o[k].status.contains(Status::VOLTAGE_SATURATED),
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::vehicle::{Fig1, VehicleModel};
    use maglev_core::levitation::{Params, Scheme};

    /// The core's controllers started on `train`.
    fn started(train: &Train, gaps0: &[WheelGaps], s: &Settings) -> CoreMagnets {
        let mut m = CoreMagnets::new();
        m.for_train(train, gaps0, s).unwrap();
        m
    }

    fn noise(s: &mut u64) -> f64 {
        *s ^= *s << 13;
        *s ^= *s >> 7;
        *s ^= *s << 17;
        (*s >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    /// The batches (trial kept in `mag_st` and `law_st`, committed states cached in
    /// `mag_committed` and `law_committed`) give the bits of the per-wheel path, forces,
    /// status and coils, over 300 steps of three iterations on pseudo-random gaps and
    /// accelerations: the paper's law under both schemes, and the state law (20 control
    /// periods a step, a supply bound it saturates at); and a run that switches path every
    /// step (as a non-finite gap would make it) gives the same bits too.
    #[test]
    fn batch_matches_the_per_wheel_path_across_commits() {
        let car = VehicleModel::fig1(&Fig1::default(), 9.81).unwrap();
        let train = Train::from_cars(vec![car]);
        let state = maglev_core::LawKind::State(maglev_core::law::state::StateParams {
            kp: 51_600.0,
            kd: 1_600.0,
            ka: 40.0,
            ki: 4_300.0,
            kc: 10.0,
            v_max: 60.0,
            rate_hz: 10_000.0,
            observer_hz: 300.0,
            geometry: Geometry::Ems,
        });
        let cases = [
            (
                Scheme::Paper,
                maglev_core::LawKind::Paper,
                Geometry::Paper,
                1e-3,
            ),
            (
                Scheme::Accurate,
                maglev_core::LawKind::Paper,
                Geometry::Paper,
                1e-3,
            ),
            (Scheme::Paper, state, Geometry::Ems, 2e-3),
        ];
        for (scheme, law, geometry, dt) in cases {
            let mut controller = Params::paper_wheel(dt);
            controller.scheme = scheme;
            let h0 = controller.h0;
            let s = Settings {
                speed: 100.0,
                dt,
                t_end: 0.3,
                controller,
                law,
                guidance: None,
                geometry,
                tolerance: 1e-9,
                max_iterations: 10,
                midspan_x: 0.0,
                midspans: Vec::new(),
                skid: crate::physics::skid::Skid::DEFAULT,
            };
            let nw = train.wheels.len();
            let gaps0 = vec![(h0, 0.0); nw];
            let mut accels = vec![0.0; nw];
            let mut batch = started(&train, &gaps0, &s);
            let mut general = started(&train, &gaps0, &s);
            let mut mixed = started(&train, &gaps0, &s);
            let (mut fb, mut fg, mut fm) = (
                vec![(0.0, 0.0); nw],
                vec![(0.0, 0.0); nw],
                vec![(0.0, 0.0); nw],
            );
            let mut seed = 0x2545_F491_4F6C_DD1D_u64;
            let mut gaps = gaps0.clone();
            let (mut moved, mut saturated) = (false, false);
            for step in 1..=300u32 {
                for _ in 0..3 {
                    for (g, a) in gaps.iter_mut().zip(&mut accels) {
                        *g = (
                            h0 * (1.0 + 0.2 * noise(&mut seed)),
                            0.3 * h0 * noise(&mut seed),
                        );
                        *a = 3.0 * noise(&mut seed);
                    }
                    batch
                        .forces(step, 0.0, &gaps0, &gaps, &accels, &mut fb)
                        .unwrap();
                    assert!(batch.pending == Pending::Batch);
                    saturated |= batch.status().contains(Status::VOLTAGE_SATURATED);
                    general.trial.clear();
                    general.trial_out.clear();
                    general.status = Status::default();
                    general.general(&gaps, &accels, &mut fg);
                    if step % 2 == 0 {
                        mixed
                            .forces(step, 0.0, &gaps0, &gaps, &accels, &mut fm)
                            .unwrap();
                    } else {
                        mixed.trial.clear();
                        mixed.trial_out.clear();
                        mixed.status = Status::default();
                        mixed.general(&gaps, &accels, &mut fm);
                    }
                    for i in 0..nw {
                        for (x, y) in [(fb[i], fg[i]), (fb[i], fm[i])] {
                            assert_eq!(x.0.to_bits(), y.0.to_bits(), "step {step} wheel {i}");
                            assert_eq!(x.1.to_bits(), y.1.to_bits(), "step {step} wheel {i}");
                        }
                    }
                    assert_eq!(batch.status(), general.status());
                    assert_eq!(batch.status(), mixed.status());
                    moved |= fb
                        .iter()
                        .any(|f| (f.0 - train.p0[0]).abs() > 1.0 && f.1 != 0.0);
                }
                for m in [&mut batch, &mut general, &mut mixed] {
                    m.commit(step, 0.0).unwrap();
                }
                assert!(batch.commit(step, 0.0).is_err(), "a second commit");
                assert_eq!(batch.coils(), general.coils(), "step {step}");
                assert_eq!(batch.coils(), mixed.coils(), "step {step}");
            }
            assert!(moved, "the forces never left their static values");
            assert_eq!(saturated, law != maglev_core::LawKind::Paper, "{law:?}");
        }
    }
}
