//! The QEMU self-test: a canned gap trace through the core controller, printed exactly.
//!
//! Every step prints the state and output *bits* in hex (f32 `to_bits`, I4F28 raw bits), so
//! the image's output can be diffed against a golden file and cross-checked bit for bit
//! against the host build of the core (`tests/qemu_golden.rs` recomputes each line
//! independently of this module). The trace is built from exact decimal steps in `f64` and
//! converted once with `Scalar::from_f64`; it covers holding, ramps, a sudden gap jump, a
//! collision (`h ≤ 0`) and an out-of-range gap, and a second configuration with ten sub-steps,
//! parabolic interpolation and a 60 V supply bound exercises the internal loop and the
//! saturated branch. Instruction counts come from a [`Measure`] (QEMU's `-icount` on the
//! boards, nothing on the host).
use core::fmt::{self, Write};
use maglev_core::scalar::I4F28;
use maglev_core::{
    Interpolation, Law, LawKind, LawParams, LawState, Levitation, Measurement, Output, Params,
    Scalar, State,
};

/// Outer time step (s).
pub const DT: f64 = 1e-3;
/// Steps in the trace.
pub const STEPS: usize = 32;

/// Per-unit gap `h/h0` that step `k` (1-based) moves to; the trace starts at `h0`.
pub fn gap(k: usize) -> f64 {
    match k {
        4..=11 => 1.0 + 0.01 * (k - 3) as f64,
        12..=15 => 1.08,
        16..=23 => 0.92 + 0.01 * (k - 16) as f64,
        27 => 0.0,
        29 => 250.0,
        _ => 1.0,
    }
}

/// The two controller configurations of the self-test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Config {
    /// The paper's wheel magnet, one sub-step (no internal loop), no voltage bound.
    Paper,
    /// Ten sub-steps, parabolic interpolation, supply bounded at 60 V.
    Loop,
}

impl Config {
    /// Both configurations, in print order.
    pub const ALL: [Config; 2] = [Config::Paper, Config::Loop];

    /// Tag printed on each line.
    pub fn tag(self) -> &'static str {
        match self {
            Config::Paper => "n1",
            Config::Loop => "n10p60v",
        }
    }

    /// The configuration named by a tag.
    pub fn from_tag(tag: &str) -> Option<Config> {
        Config::ALL.into_iter().find(|c| c.tag() == tag)
    }

    /// Its parameters.
    pub fn params(self) -> Params {
        let mut p = Params::paper_wheel(DT);
        if self == Config::Loop {
            p.n_sub = 10;
            p.interpolation = Interpolation::Parabolic;
            p.v_max = 60.0;
        }
        p
    }
}

/// Exact bit pattern of a scalar as printed (32-bit types only).
pub trait Bits: Scalar {
    /// The raw bits.
    fn bits(self) -> u32;
}
impl Bits for f32 {
    fn bits(self) -> u32 {
        self.to_bits()
    }
}
impl Bits for I4F28 {
    fn bits(self) -> u32 {
        self.to_bits() as u32
    }
}

/// Counts the instructions a closure executes, where the platform can.
pub trait Measure {
    /// Runs `f` once, returning the instructions it took (`None`: not measured).
    fn count(&self, f: &mut dyn FnMut()) -> Option<u32>;
}

/// No counting (the host).
pub struct NoCount;
impl Measure for NoCount {
    fn count(&self, f: &mut dyn FnMut()) -> Option<u32> {
        f();
        None
    }
}

/// One controller update as a real call, so that a measurement window holds exactly it
/// (arguments set up, `bl`, body, return).
#[inline(never)]
pub fn update_once<S: Scalar>(c: &Levitation<S>, st: &mut State<S>, h: S) -> Output<S> {
    c.update(st, h)
}

/// One update of the law type (`maglev_core::Law`, the path the firmware and the C API take)
/// as a real call, as [`update_once`].
#[inline(never)]
pub fn law_update_once<S: Scalar>(l: &Law<S>, st: &mut LawState<S>, h: S) -> Output<S> {
    l.update(st, Measurement::gap(h))
}

/// A function with [`update_once`]'s signature that returns at once: measured in the same
/// window, it is the harness's share of an update count (docs/hil.md).
#[inline(never)]
pub fn update_shaped<S: Scalar>(_c: &Levitation<S>, _st: &mut State<S>, _h: S) -> Output<S> {
    Output::default()
}

/// Prints the instructions of a call of [`update_shaped`] in the update's measuring window.
pub fn call_cost<S: Bits, W: Write, M: Measure>(w: &mut W, m: &M) -> fmt::Result {
    let p = Config::Paper.params();
    let Ok(ctrl) = p.compile::<S>() else {
        return writeln!(w, "insns {} update-shaped call: not compiled", S::NAME);
    };
    let mut st = ctrl.initial_state(p.h0);
    let mut out = Output::default();
    match m.count(&mut || out = update_shaped(&ctrl, &mut st, S::ONE)) {
        Some(n) => writeln!(
            w,
            "insns {} update-shaped call that returns at once (the harness): {n}",
            S::NAME
        ),
        None => writeln!(w, "insns {} update-shaped call: not measured", S::NAME),
    }
}

/// Instruction counts of one run: over steps without events (`nominal`) and over all.
#[derive(Clone, Copy, Debug, Default)]
pub struct Counts {
    /// Fewest instructions of a step without events.
    pub nominal_min: u32,
    /// Most instructions of a step without events.
    pub nominal_max: u32,
    /// Most instructions of any step.
    pub max: u32,
}

impl Counts {
    /// Adds one step's count `n` (`nominal`: a step without events) to `counts`.
    fn note(counts: &mut Option<Counts>, n: u32, nominal: bool) {
        let c = counts.get_or_insert(Counts {
            nominal_min: u32::MAX,
            ..Counts::default()
        });
        if nominal {
            c.nominal_min = c.nominal_min.min(n);
            c.nominal_max = c.nominal_max.max(n);
        }
        c.max = c.max.max(n);
    }
}

/// Runs the trace with scalar `S` and configuration `cfg`, one line per step.
pub fn run<S: Bits, W: Write, M: Measure>(
    w: &mut W,
    m: &M,
    cfg: Config,
) -> Result<Option<Counts>, fmt::Error> {
    let (name, tag) = (S::NAME, cfg.tag());
    let p = cfg.params();
    let ctrl = match p.compile::<S>() {
        Ok(c) => c,
        Err(e) => {
            writeln!(w, "{name}/{tag} compile error: {e}")?;
            return Ok(None);
        }
    };
    let mut st = ctrl.initial_state(p.h0);
    let mut counts: Option<Counts> = None;
    for k in 1..=STEPS {
        let mut ov = false;
        let h = S::from_f64(gap(k), &mut ov);
        let mut out = Output::default();
        let n = m.count(&mut || out = update_once(&ctrl, &mut st, h));
        writeln!(
            w,
            "{name}/{tag} {k:02} h={:08x} x={:08x} y={:08x} v={:08x} F={:08x} i={:08x} st={:02x}",
            h.bits(),
            st.x.bits(),
            st.y.bits(),
            st.v.bits(),
            out.force.bits(),
            out.current.bits(),
            out.status.0 | if ov { 0x80 } else { 0 }, // 0x80: the gap saturated on conversion
        )?;
        if let Some(n) = n {
            Counts::note(&mut counts, n, out.status.is_empty());
        }
    }
    Ok(counts)
}

/// Prints one run's instruction counts against a budget (`over` marks a miss).
pub fn report<S: Scalar, W: Write>(
    w: &mut W,
    cfg: Config,
    counts: Option<Counts>,
    budget: u32,
) -> fmt::Result {
    let (name, tag) = (S::NAME, cfg.tag());
    match counts {
        Some(c) => writeln!(
            w,
            "insns {name}/{tag} update: nominal {}..{}, max {} (budget {budget}: {})",
            c.nominal_min,
            c.nominal_max,
            c.max,
            if c.nominal_max <= budget {
                "met"
            } else {
                "over"
            }
        ),
        None => writeln!(w, "insns {name}/{tag} update: not measured"),
    }
}

/// A scalar operation with the core's signature, called through a pointer so each
/// measurement window has the same shape.
type Op<S> = fn(S, S, &mut bool) -> S;

#[inline(never)]
fn op_first<S: Scalar>(a: S, _b: S, _ov: &mut bool) -> S {
    a
}
#[inline(never)]
fn op_add<S: Scalar>(a: S, b: S, ov: &mut bool) -> S {
    a.sadd(b, ov)
}
#[inline(never)]
fn op_mul<S: Scalar>(a: S, b: S, ov: &mut bool) -> S {
    a.smul(b, ov)
}
#[inline(never)]
fn op_div<S: Scalar>(a: S, b: S, ov: &mut bool) -> S {
    a.sdiv(b, ov)
}

/// Prints what one saturating operation costs: instructions of a call of `sadd`, `smul` and
/// `sdiv` (operands 0.7 and 1.3, no overflow) minus those of a call of a function with the
/// same signature that returns its first argument. This is what bounds an update (docs/hil.md).
pub fn op_costs<S: Bits, W: Write, M: Measure>(w: &mut W, m: &M) -> fmt::Result {
    let mut ov = false;
    let a = S::from_f64(0.7, &mut ov);
    let b = S::from_f64(1.3, &mut ov);
    let mut time = |op: Op<S>| {
        let mut r = S::ZERO;
        m.count(&mut || r = op(a, b, &mut ov))
    };
    let base = time(op_first::<S>);
    let ops: [(&str, Op<S>); 3] = [
        ("sadd", op_add::<S>),
        ("smul", op_mul::<S>),
        ("sdiv", op_div::<S>),
    ];
    write!(w, "insns {} ops beyond a trivial call:", S::NAME)?;
    for (name, op) in ops {
        match (time(op), base) {
            (Some(n), Some(b)) => write!(w, " {name} {}", n as i64 - b as i64)?,
            _ => write!(w, " {name} n/a")?,
        }
    }
    writeln!(w)
}

/// Prints the instructions of the trace's updates through the law type ([`law_update_once`],
/// the paper's law of configuration `cfg`): the Rust path the C API's count is held against
/// (`scripts/c-firmware.sh`, docs/c-api.md). Fails if a step's bits differ from [`run`]'s
/// controller's.
pub fn law_type_cost<S: Bits, W: Write, M: Measure>(w: &mut W, m: &M, cfg: Config) -> fmt::Result {
    let (name, tag) = (S::NAME, cfg.tag());
    let magnet = cfg.params();
    let lp = LawParams {
        magnet,
        kind: LawKind::Paper,
    };
    let (Ok(law), Ok(ctrl)) = (lp.compile::<S>(), magnet.compile::<S>()) else {
        return writeln!(w, "insns {name}/{tag} law-type update: not compiled");
    };
    let mut st = law.equilibrium_state(magnet.h0);
    let mut reference = ctrl.initial_state(magnet.h0);
    let mut counts: Option<Counts> = None;
    for k in 1..=STEPS {
        let h = S::from_f64(gap(k), &mut false);
        let mut out = Output::default();
        let n = m.count(&mut || out = law_update_once(&law, &mut st, h));
        if out != ctrl.update(&mut reference, h) || st.inner != reference {
            return Err(fmt::Error); // the law type no longer gives the controller's bits
        }
        if let Some(n) = n {
            Counts::note(&mut counts, n, out.status.is_empty());
        }
    }
    match counts {
        Some(c) => writeln!(
            w,
            "insns {name}/{tag} law-type update (maglev_core::Law): nominal {}..{}, max {}",
            c.nominal_min, c.nominal_max, c.max
        ),
        None => writeln!(w, "insns {name}/{tag} law-type update: not measured"),
    }
}
