//! The ideal magnets of `maglev run`: per wheel the core's levitation law and guidance pair in
//! f64 on the exact gaps at the end of each step — the paper's scheme, with its internal loop
//! (`n_sub`) interpolating the gap inside the step — under either [`Law`]. Calls the core;
//! never a host copy of a law.

use super::{Law, Magnets, Settings, WheelGaps};
use crate::vehicle::Train;
use crate::{Error, Result};
use maglev_core::gap::Geometry;
use maglev_core::gap_control::{GapLoop, GapPairState, GapState};
use maglev_core::guidance;
use maglev_core::levitation::batch::update_batch;
use maglev_core::levitation::{Output, State};
use maglev_core::{Levitation, Status};

struct WheelCtl {
    lev: Levitation<f64>,
    /// The outer gap loop, when selected.
    outer: Option<GapLoop<f64>>,
    /// Inner state (and the outer loop's filter, unused under the paper's law).
    lev_state: GapState<f64>,
    /// Guidance pair (the filters unused under the paper's law).
    pair: GapPairState<f64>,
}

/// The core's controllers of every wheel, committed and trial states.
pub struct CoreMagnets {
    ctl: Vec<WheelCtl>,
    /// Per magnet (levitation, guidance left, right of each wheel): its controller, state
    /// and per-unit gap, for the interleaved update of the paper's law.
    mags: Vec<Levitation<f64>>,
    mag_st: Vec<State<f64>>,
    mag_h: Vec<f64>,
    mag_out: Vec<Output<f64>>,
    trial: Vec<(GapState<f64>, GapPairState<f64>)>,
    status: Status,
    geometry: Geometry,
}

impl CoreMagnets {
    /// Every controller in equilibrium at the wheel's initial gaps `gaps0`
    /// ([`super::initial_gaps`]); `p0` per wheel from the vehicle, `Δt` from the run.
    pub fn new(v: &Train, gaps0: &[WheelGaps], s: &Settings) -> Result<Self> {
        let mut ctl = Vec::with_capacity(v.wheels.len());
        for (&p0, &(h_init, gy)) in v.p0.iter().zip(gaps0) {
            let mut p = s.controller;
            p.p0 = p0;
            p.dt = s.dt;
            let lev = p
                .compile::<f64>()
                .map_err(|e| Error::invalid("controller", e.to_string()))?;
            let outer = match s.law {
                Law::Paper => None,
                Law::GapLoop(g) => Some(
                    g.compile::<f64>(s.dt)
                        .map_err(|e| Error::invalid("controller.law", e.to_string()))?,
                ),
            };
            let inner = lev.equilibrium_state(h_init);
            let pair = guidance::initial_state(&lev, gy);
            ctl.push(WheelCtl {
                lev_state: GapState {
                    inner,
                    q: inner.eta,
                },
                outer,
                pair: GapPairState {
                    left: GapState {
                        inner: pair.left,
                        q: pair.left.eta,
                    },
                    right: GapState {
                        inner: pair.right,
                        q: pair.right.eta,
                    },
                },
                lev,
            });
        }
        let mags: Vec<Levitation<f64>> = ctl.iter().flat_map(|c| [c.lev; 3]).collect();
        let n = mags.len();
        Ok(CoreMagnets {
            mags,
            mag_st: Vec::with_capacity(n),
            mag_h: Vec::with_capacity(n),
            mag_out: vec![Output::default(); n],
            trial: Vec::with_capacity(ctl.len()),
            ctl,
            status: Status::default(),
            geometry: s.geometry,
        })
    }
}

impl CoreMagnets {
    /// The paper's law on every magnet at once ([`update_batch`]: the bits of one
    /// `Levitation::update` per magnet), the guidance pairs' net forces by the core's
    /// [`guidance::update_with`] on the outputs. Finite gaps only (the per-unit guidance gaps
    /// `1 ± d` are then formed as the core forms them).
    fn paper_batch(&mut self, gaps_next: &[WheelGaps], out: &mut [(f64, f64)]) {
        self.mag_st.clear();
        self.mag_h.clear();
        for (c, &(hz, dy)) in self.ctl.iter().zip(gaps_next) {
            let h0 = c.lev.params().h0;
            let d = dy / h0;
            self.mag_st
                .extend([c.lev_state.inner, c.pair.left.inner, c.pair.right.inner]);
            self.mag_h.extend([hz / h0, 1.0 + d, 1.0 - d]);
        }
        update_batch(&self.mags, &mut self.mag_st, &self.mag_h, &mut self.mag_out);
        for (i, c) in self.ctl.iter().enumerate() {
            let (lev_out, left, right) = (
                self.mag_out[3 * i],
                self.mag_out[3 * i + 1],
                self.mag_out[3 * i + 2],
            );
            let d = gaps_next[i].1 / c.lev.params().h0;
            let (mut l, mut r) = (left, right);
            let pair_out = guidance::update_with(self.geometry, &mut l, &mut r, d, |o, _| *o);
            self.status = self.status.union(lev_out.status).union(pair_out.status);
            let p0 = c.lev.params().p0;
            out[i] = (lev_out.force * p0, pair_out.force_y * p0);
            let mut st = c.lev_state;
            st.inner = self.mag_st[3 * i];
            let mut pair = c.pair;
            pair.left.inner = self.mag_st[3 * i + 1];
            pair.right.inner = self.mag_st[3 * i + 2];
            self.trial.push((st, pair));
        }
    }
}

impl Magnets for CoreMagnets {
    /// One update of every law from the committed state to the gaps at the end of the step
    /// (the law interpolates from the gap its state last saw; `gaps_prev` is that gap).
    fn forces(
        &mut self,
        _step: u32,
        _t: f64,
        _gaps_prev: &[WheelGaps],
        gaps_next: &[WheelGaps],
        out: &mut [(f64, f64)],
    ) -> Result<()> {
        self.trial.clear();
        self.status = Status::default();
        let finite = gaps_next.iter().all(|g| g.0.is_finite() && g.1.is_finite());
        if finite && self.ctl.iter().all(|c| c.outer.is_none()) {
            self.paper_batch(gaps_next, out);
            return Ok(());
        }
        for (i, c) in self.ctl.iter().enumerate() {
            let (hz, dy) = gaps_next[i];
            let h0 = c.lev.params().h0;
            let mut st = c.lev_state;
            let lev_out = match &c.outer {
                Some(o) => o.update(&c.lev, &mut st, hz / h0).inner,
                None => c.lev.update(&mut st.inner, hz / h0),
            };
            let mut pair = c.pair;
            let pair_out = match &c.outer {
                Some(o) => o.update_pair(&c.lev, self.geometry, &mut pair, dy / h0),
                None => {
                    let mut ps = guidance::PairState {
                        left: pair.left.inner,
                        right: pair.right.inner,
                    };
                    let o = guidance::update(&c.lev, self.geometry, &mut ps, dy / h0);
                    (pair.left.inner, pair.right.inner) = (ps.left, ps.right);
                    o
                }
            };
            self.status = self.status.union(lev_out.status).union(pair_out.status);
            let p0 = c.lev.params().p0;
            out[i] = (lev_out.force * p0, pair_out.force_y * p0);
            self.trial.push((st, pair));
        }
        Ok(())
    }

    fn commit(&mut self, _step: u32, _t: f64) -> Result<()> {
        if self.trial.len() != self.ctl.len() {
            return Err(Error::numerical("internal: commit without a step"));
        }
        for (c, (st, pair)) in self.ctl.iter_mut().zip(self.trial.drain(..)) {
            c.lev_state = st;
            c.pair = pair;
        }
        Ok(())
    }

    fn status(&self) -> Status {
        self.status
    }
}
