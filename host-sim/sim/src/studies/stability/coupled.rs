//! The scenario's vehicle over its flexible girder (issue 26 point 4): the closed-loop poles
//! of the linear model with the span's bending modes coupled at the magnets
//! ([`super::girder`], [`super::vehicle::VehiclePlant::on_girder`]), and the girder value at
//! which that model loses stability (`maglev stability --critical KEY --range LO HI`).
//!
//! The law is the case's as resolved once (designed on the rigid guideway,
//! `crate::studies::design`): the coupled analysis and every point of the critical search analyse
//! those same gains, never a re-design.

use crate::input::case::Case;
use crate::input::scenario::Model;
use crate::studies::stability::girder::{girder_modes, GirderMode};
use crate::studies::stability::marginal::{self, Honest, Kind};
use crate::studies::stability::vehicle::{min_damping, vehicle_of, VehiclePlant, Verdict};
use serde::Serialize;

/// Default number of vertical bending modes per span (`--girder-modes`).
pub const GIRDER_MODES: usize = 8;

/// Points of the critical search's scan over `[LO, HI]` (bisection follows).
const SCAN: usize = 32;

/// The most bisections of the critical search: 1e-9 of the range takes 30, and a range
/// narrower than the floats can halve stops earlier (its midpoint is one of its ends).
const MAX_BISECTIONS: usize = 200;

/// The coupled model's verdict.
#[derive(Debug, Serialize)]
pub struct Coupled {
    /// Where the modes come from.
    pub source: String,
    /// Closed-loop poles `[re, im]` (1/s), sorted by descending real part.
    pub poles: Vec<[f64; 2]>,
    pub max_real_part: f64,
    pub min_damping_ratio: f64,
    /// The verdict is `stable`.
    pub stable: bool,
    /// `stable`, `marginal` or `unstable`, the marginal poles and their modes
    /// ([`crate::studies::stability::marginal`]).
    pub verdict: Kind,
    pub honest: Honest,
}

/// The girder modes of `case` under its magnets and the coupled verdict; `None` on a rigid
/// guideway (`run.model = "rigid"`) and for a moving vehicle (`speed > 0`: the modes
/// under a moving magnet change with time, a linear time-invariant model does not hold).
pub fn coupled(case: &Case, count: usize) -> crate::Result<Option<(Vec<GirderMode>, Coupled)>> {
    if case.model == Model::Rigid || case.speed != 0.0 {
        return Ok(None);
    }
    let (v, _, _) = vehicle_of(case)?;
    let inner = case.controller.ok_or_else(|| {
        crate::Error::invalid(
            "controller",
            "the coupled analysis needs a [controller] section",
        )
    })?;
    let law = case.law()?;
    crate::studies::stability::vehicle::runnable(case, &v, &inner, law)?;
    let modes = girder_modes(case, &v.wheels, count)?;
    let guidance = case.guidance()?;
    let mut plant =
        VehiclePlant::guided_on_girder(&v, &inner, &law, guidance.as_ref(), case.geometry, &modes)?;
    name_girder_states(&mut plant.states, v.m.nrows(), &modes);
    let vd: Verdict = plant.verdict()?;
    let honest = marginal::honest(&plant.a, &plant.states, &vd.poles)?;
    let source = format!(
        "the FE span's first {count} vertical bending modes{} ({} elements per span), each \
         checked against the closed-form Timoshenko frequency (fe_vs_closed_form)",
        if modes.iter().any(|m| m.kind != "bending-z") {
            format!(", and its first {count} torsion and lateral bending modes where the magnets see them")
        } else {
            String::new()
        },
        case.elements_per_span
    );
    let c = Coupled {
        source,
        poles: vd.poles.iter().map(|p| [p.re, p.im]).collect(),
        max_real_part: vd.max_real_part,
        min_damping_ratio: min_damping(&vd.poles),
        stable: honest.verdict == Kind::Stable,
        verdict: honest.verdict,
        honest,
    };
    Ok(Some((modes, c)))
}

/// Names the girder modes' states (`q[i]`, `v[i]` for DOF `i = nv + j`) by span and mode:
/// `span1.mode5.q`, `span1.mode5.v`.
fn name_girder_states(states: &mut [String], nv: usize, modes: &[GirderMode]) {
    for (j, m) in modes.iter().enumerate() {
        for (from, to) in [("q", "q"), ("v", "v")] {
            let old = format!("{from}[{}]", nv + j);
            if let Some(s) = states.iter_mut().find(|s| **s == old) {
                *s = match m.kind {
                    "bending-z" => format!("span{}.mode{}.{to}", m.span, m.n),
                    kind => format!("span{}.{kind}{}.{to}", m.span, m.n),
                };
            }
        }
    }
}

/// `--critical` as reported.
#[derive(Debug, Serialize)]
pub struct Critical {
    pub key: String,
    pub range: [f64; 2],
    /// The coupled `max_real_part` (1/s) and verdict at both ends of the range.
    pub max_real_part_at_range: [f64; 2],
    pub verdict_at_range: [Kind; 2],
    /// The value where the verdict turns `unstable` (or stops being so); null: none in range.
    pub critical: Option<f64>,
    pub note: String,
}

/// The value of scenario key `key` in `[lo, hi]` where the coupled model's honest verdict
/// ([`crate::studies::stability::marginal`]) changes between `unstable` and not (`stable` or
/// `marginal`: a real part within the eigen-solver's error of zero is no crossing), with the law resolved once at the scenario's own values (`base` is `name`
/// with `sets`, loaded with its law resolved, [`crate::studies::design::load`]), unless
/// `key` changes the law itself (a gain of `[controller.state]`, `controller.law`): then each
/// point analyses the law as the key gives it there, designed there by `resolve` where it is
/// designed (the caller passes [`crate::studies::design::resolve`]: design sits above this
/// module).
///
/// Method: the verdict on [`SCAN`] points (log-spaced if `lo > 0`, else even) brackets the
/// first change; bisection narrows it to 1e-9 of the range, or to adjacent floats (at
/// most [`MAX_BISECTIONS`]). A stable or unstable window narrower than one scan step could be
/// missed.
pub fn critical(
    name: &str,
    sets: &[String],
    base: &Case,
    key: &str,
    [lo, hi]: [f64; 2],
    count: usize,
    resolve: &dyn Fn(Case) -> crate::Result<Case>,
) -> crate::Result<Critical> {
    if !(lo.is_finite() && hi.is_finite() && lo < hi) {
        return Err(crate::Error::invalid(
            "--range",
            format!("needs finite LO < HI, got {lo} {hi}"),
        ));
    }
    let unresolved = Case::load(name, sets)?.law;
    let at = |x: f64| -> crate::Result<(f64, Kind)> {
        let mut s = sets.to_vec();
        s.push(format!("{key}={x:?}"));
        let mut c = Case::load(name, &s)?;
        if c.law == unresolved {
            c.law = base.law;
        } else {
            c = resolve(c)?;
        }
        match coupled(&c, count)? {
            Some((_, v)) => Ok((v.max_real_part, v.verdict)),
            None => Err(crate::Error::invalid(
                "run.model",
                "--critical needs a flexible guideway (fe or modal) at speed 0",
            )),
        }
    };
    let point = |i: usize| {
        let f = i as f64 / (SCAN - 1) as f64;
        if lo > 0.0 {
            lo * (hi / lo).powf(f)
        } else {
            lo + (hi - lo) * f
        }
    };
    let ends = [at(lo)?, at(hi)?];
    let unstable = |r: (f64, Kind)| r.1 == Kind::Unstable;
    let mut prev = (lo, ends[0]);
    let mut found = None;
    for i in 1..SCAN {
        let x = if i == SCAN - 1 { hi } else { point(i) };
        let r = if i == SCAN - 1 { ends[1] } else { at(x)? };
        if unstable(r) != unstable(prev.1) {
            let (mut a, mut b, ra) = (prev.0, x, unstable(prev.1));
            for _ in 0..MAX_BISECTIONS {
                let m = 0.5 * (a + b);
                if b - a <= 1e-9 * (hi - lo) || m <= a || m >= b {
                    break;
                }
                if unstable(at(m)?) == ra {
                    a = m;
                } else {
                    b = m;
                }
            }
            found = Some(0.5 * (a + b));
            break;
        }
        prev = (x, r);
    }
    let note = match found {
        Some(x) => format!(
            "the verdict turns at {key} = {x:e}: {} below it, {} above",
            ends[0].1.as_str(),
            ends[1].1.as_str()
        ),
        None => format!(
            "no crossing in [{lo:e}, {hi:e}] (scanned at {SCAN} points): {}{}",
            ends[0].1.as_str(),
            if ends[0].1 == Kind::Marginal {
                " (a real part within the eigen-solver's error of zero, not a crossing)"
            } else {
                ""
            }
        ),
    };
    Ok(Critical {
        key: key.to_string(),
        range: [lo, hi],
        max_real_part_at_range: [ends[0].0, ends[1].0],
        verdict_at_range: [ends[0].1, ends[1].1],
        critical: found,
        note,
    })
}
