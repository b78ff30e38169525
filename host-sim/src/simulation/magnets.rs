//! The ideal magnets of `maglev run`: per wheel the core's levitation law and guidance pair in
//! f64 on the exact gaps at the end of each step — the paper's scheme, with its internal loop
//! (`n_sub`) interpolating the gap inside the step — under either [`Law`]. Calls the core;
//! never a host copy of a law.

use super::{Law, Magnets, Settings, WheelGaps};
use crate::vehicle::VehicleModel;
use maglev_core::gap::Geometry;
use maglev_core::gap_control::{GapLoop, GapPairState, GapState};
use maglev_core::guidance;
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
    trial: Vec<(GapState<f64>, GapPairState<f64>)>,
    status: Status,
    geometry: Geometry,
}

impl CoreMagnets {
    /// Every controller in equilibrium at the wheel's initial gaps `gaps0`
    /// ([`super::initial_gaps`]); `p0` per wheel from the vehicle, `Δt` from the run.
    pub fn new(v: &VehicleModel, gaps0: &[WheelGaps], s: &Settings) -> Result<Self, String> {
        let mut ctl = Vec::with_capacity(v.wheels.len());
        for (&p0, &(h_init, gy)) in v.p0.iter().zip(gaps0) {
            let mut p = s.controller;
            p.p0 = p0;
            p.dt = s.dt;
            let lev = p.compile::<f64>().map_err(|e| e.to_string())?;
            let outer = match s.law {
                Law::Paper => None,
                Law::GapLoop(g) => Some(g.compile::<f64>(s.dt).map_err(|e| e.to_string())?),
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
        Ok(CoreMagnets {
            trial: Vec::with_capacity(ctl.len()),
            ctl,
            status: Status::default(),
            geometry: s.geometry,
        })
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
    ) -> Result<(), String> {
        self.trial.clear();
        self.status = Status::default();
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

    fn commit(&mut self, _step: u32, _t: f64) -> Result<(), String> {
        if self.trial.len() != self.ctl.len() {
            return Err("internal: commit without a step".into());
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
