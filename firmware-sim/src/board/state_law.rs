//! The state law (`maglev_core::law::state`) as the firmware runs it: one update per 10 kHz
//! control period on the sampled gap and acceleration, measured in instructions (docs/hil.md,
//! "The state law on the M4").
//!
//! The magnet is the Fig. 1 wheel's (p0 = 36 787.5 N) under its rail (EMS geometry) with the
//! gains the project's tests run the Fig. 1 car with (`host-sim/cli/tests/state_law.rs`, `GAINS`).
//! The update is called through [`update_once`], a real call with the law's signature, and
//! [`update_shaped`] (the same signature, returning at once) measures the harness, as
//! [`crate::board::selftest::call_cost`] does for the paper's law.
use crate::board::selftest::{gap, Measure, STEPS};
use core::fmt::{self, Write};
use maglev_core::gap::Geometry;
use maglev_core::law::guidance::GuidanceParams;
use maglev_core::law::state::{StateLaw, StateParams};
use maglev_core::{LawKind, LawParams, LawState, Measurement, Output, Params, Scalar};

/// Control period (s): one period per update.
pub const PERIOD: f64 = 1e-4;

/// The state law's gains (SI) and its 500 V supply bound.
pub fn gains() -> StateParams {
    StateParams {
        kp: 51_600.0,
        kd: 1_600.0,
        ka: 40.0,
        ki: 4_300.0,
        kc: 10.0,
        v_max: 500.0,
        rate_hz: StateParams::RATE_HZ,
        observer_hz: StateParams::OBSERVER_HZ,
        geometry: Geometry::Ems,
    }
}

/// The guidance pairs' gains: the levitation law's five, as the core's guidance tests run
/// them (`maglev_core::law::guidance`; docs/levitation.md, "The guidance law").
pub fn guidance_gains() -> GuidanceParams {
    GuidanceParams::same_as(&gains())
}

/// The Fig. 1 wheel's magnet under the state law at one update per control period.
pub fn params() -> LawParams {
    LawParams {
        magnet: Params::paper_wheel(PERIOD),
        kind: LawKind::State(gains()),
    }
}

/// The acceleration `a/g_n` of trace step `k`: a few hundredths of g, changing sign.
pub fn accel(k: usize) -> f64 {
    0.02 * ((k % 5) as f64 - 2.0)
}

/// One update as a real call (the measuring window holds exactly it): `Law::update`'s state
/// arm, [`StateLaw::update`], called as the firmware's tick calls it (the law chosen once,
/// `crate::firmware`).
#[inline(never)]
pub fn update_once<S: Scalar>(
    law: &StateLaw<S>,
    st: &mut LawState<S>,
    m: Measurement<S>,
) -> Output<S> {
    law.update(&mut st.inner, &mut st.state, m.gap, m.accel)
}

/// [`update_once`]'s signature, returning at once: the harness's share of a count.
#[inline(never)]
pub fn update_shaped<S: Scalar>(
    _law: &StateLaw<S>,
    _st: &mut LawState<S>,
    _m: Measurement<S>,
) -> Output<S> {
    Output::default()
}

/// Runs the self-test's gap trace (with [`accel`]) through the state law in `S` and prints
/// the instructions of one update over the steps without events (fewest..most), the harness,
/// and the update net of the harness against `target`.
pub fn report<S: Scalar, W: Write, M: Measure>(w: &mut W, m: &M, target: u32) -> fmt::Result {
    let p = params();
    let law = match p.compile::<S>() {
        Ok(l) => l,
        Err(e) => return writeln!(w, "insns {}/state law: compile error: {e}", S::NAME),
    };
    let mut st = law.equilibrium_state(p.magnet.h0);
    let mut shaped_st = st;
    let Some(law) = law.state_law() else {
        return writeln!(w, "insns {}/state law: not a state law", S::NAME);
    };
    let (mut lo, mut hi, mut events) = (u32::MAX, 0, 0);
    for k in 1..=STEPS {
        let mut ov = false;
        let meas = Measurement {
            gap: S::from_f64(gap(k), &mut ov),
            accel: Some(S::from_f64(accel(k), &mut ov)),
            current: None,
        };
        let mut out = Output::default();
        let Some(n) = m.count(&mut || out = update_once(law, &mut st, meas)) else {
            return writeln!(w, "insns {}/state law: not measured", S::NAME);
        };
        if out.status.is_empty() && !ov {
            (lo, hi) = (lo.min(n), hi.max(n));
        } else {
            events += 1;
        }
    }
    let meas = Measurement::gap(S::ONE);
    let mut out = Output::default();
    let Some(harness) = m.count(&mut || out = update_shaped(law, &mut shaped_st, meas)) else {
        return writeln!(w, "insns {}/state law: not measured", S::NAME);
    };
    let net = hi.saturating_sub(harness);
    writeln!(
        w,
        "insns {}/state law, one 10 kHz period (gap + accel): {lo}..{hi} on {} steps without \
         events; harness {harness}; net {}..{net} (target {target}: {})",
        S::NAME,
        STEPS - events,
        lo.saturating_sub(harness),
        if net <= target { "met" } else { "over" }
    )
}
