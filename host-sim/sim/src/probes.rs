//! What a run records: named probes, one `response.csv` column each, streamed row by row as
//! the run goes.
//!
//! Why named probes: a train over a viaduct has hundreds of magnets and dozens of spans; a
//! fixed set of columns (wheel 1, span 1) cannot say where a §5 study looks. A probe names a
//! quantity by where it is:
//!
//! - `span{K}.midspan.{y,z,rx}`: the beam axis at the middle of span K (from 1), m and rad;
//! - `wheel{N}.{y,z,gap_y,gap_z,force_z}`: wheel N's displacements (m), its guidance gap
//!   `gap_y` (the left magnet's, h0 + d, docs/model.md §2) and levitation gap `gap_z` (m), and
//!   its levitation force (N, up); for a `forces` train, load N's point of the guideway and
//!   its force (no gaps). Wheels are numbered along the train, car by car
//!   ([`crate::physics::train::Train::nodes`]); a wheel–rail car's wheels are its Hertz contacts:
//!   `z` the wheel's displacement, `force_z` the contact force (N, compressive, i.e. the rail
//!   pushing the wheel up — the same "up on the wheel" as a magnet's force; zero once the
//!   wheel has lifted off), no `y` and no gaps (empty cells);
//! - `car{N}.body.{z,az}`: car N's body heave (m) and vertical acceleration (m/s²), at the
//!   body's centre of mass (the carriage centre) for every car kind;
//! - `pier{K}.base.{z,az}`: the base (footing) of pier K (from 1, at x = 0) of a guideway with
//!   piers ([`Guideway::pier_base`]), m and m/s². The case's extent does not know the piers:
//!   [`Probes::check_guideway`] checks them against the guideway before the run.
//! - `ground{N}.vz`: ground receiver N's vertical velocity (m/s, up; `[ground]`, docs/ground.md).
//!   It is not known during the run: the soil's response is computed from the whole record of
//!   pier forces afterwards, so the column streams empty and `maglev run` fills it in from
//!   ground.csv once the run is over ([`Probes::ground_columns`]); a sweep, which reduces
//!   rows as they stream, refuses it. The case checks N against its receivers.
//!
//! Today's default columns keep their names (`midspan_z` is `span1.midspan.z`, `wheel1_gap_z`
//! is `wheel1.gap_z`, …). Every probe is checked against the case before the run starts.

use crate::physics::guideway::{Guideway, SectionMotion};
use crate::physics::train::Node;
use crate::physics::vehicle::{magnet_gaps, Coil};
use crate::{Error, Result};
use std::io::Write;

/// The columns of a run without `[output] probes`.
pub const DEFAULT: [&str; 7] = [
    "midspan_y",
    "midspan_z",
    "midspan_rx",
    "wheel1_y",
    "wheel1_z",
    "wheel1_gap_z",
    "wheel1_force_z",
];

/// A quantity of a section of the beam axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SectionQ {
    Y,
    Z,
    Rx,
}

/// A quantity of a wheel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WheelQ {
    Y,
    Z,
    GapY,
    GapZ,
    ForceZ,
}

/// A quantity of a car body.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyQ {
    Z,
    Az,
}

/// A quantity of a pier's base: vertical displacement and acceleration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PierQ {
    Z,
    Az,
}

/// One probe (indices from 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Probe {
    Midspan {
        span: usize,
        q: SectionQ,
    },
    Wheel {
        wheel: usize,
        q: WheelQ,
    },
    Body {
        car: usize,
        q: BodyQ,
    },
    /// Pier `pier + 1` (the guideway's 1-based numbering).
    Pier {
        pier: usize,
        q: PierQ,
    },
    /// Ground receiver `receiver + 1`'s vertical velocity (filled in after the run).
    Ground {
        receiver: usize,
    },
}

/// What the case offers to probe.
#[derive(Clone, Copy, Debug)]
pub struct Extent {
    pub spans: usize,
    pub wheels: usize,
    pub cars: usize,
    /// Whether the wheels carry magnets (gaps).
    pub magnets: bool,
}

/// A bad probe: the key is `output.probes`, the reason names the probe and the limit.
fn bad_probe(reason: String) -> Error {
    Error::invalid("output.probes", reason)
}

fn index(s: &str, prefix: &str, name: &str, limit: usize) -> Result<usize> {
    let k: usize = s
        .strip_prefix(prefix)
        .and_then(|n| n.parse().ok())
        .filter(|&k| k >= 1)
        .ok_or_else(|| bad_probe(format!("`{name}`: expected {prefix}N with N from 1")))?;
    if k > limit {
        return Err(bad_probe(format!(
            "`{name}`: the case has {limit} {prefix}(s), so N is at most {limit}"
        )));
    }
    Ok(k - 1)
}

/// The SI unit of a probe or history column by its quantity (the name's ending): rotations
/// rad, accelerations m/s², forces N, velocities (`.vz`) m/s, everything else
/// (displacements, gaps) m.
pub fn si_unit(name: &str) -> &'static str {
    if name.ends_with("rx") {
        "rad"
    } else if name.ends_with("az") {
        "m/s²"
    } else if name.ends_with("force_z") {
        "N"
    } else if name.ends_with(".vz") {
        "m/s"
    } else {
        "m"
    }
}

/// Parses one probe name against the case's extent.
pub fn parse(name: &str, e: &Extent) -> Result<Probe> {
    let alias = match name {
        "midspan_y" => "span1.midspan.y",
        "midspan_z" => "span1.midspan.z",
        "midspan_rx" => "span1.midspan.rx",
        "wheel1_y" => "wheel1.y",
        "wheel1_z" => "wheel1.z",
        "wheel1_gap_z" => "wheel1.gap_z",
        "wheel1_force_z" => "wheel1.force_z",
        other => other,
    };
    let parts: Vec<&str> = alias.split('.').collect();
    let bad = || {
        bad_probe(format!(
            "unknown probe `{name}` (span{{K}}.midspan.{{y,z,rx}}, wheel{{N}}.{{y,z,gap_y,gap_z,force_z}}, car{{N}}.body.{{z,az}}, pier{{K}}.base.{{z,az}}, ground{{N}}.vz)"
        ))
    };
    match parts.as_slice() {
        [s, "midspan", q] if s.starts_with("span") => {
            let q = match *q {
                "y" => SectionQ::Y,
                "z" => SectionQ::Z,
                "rx" => SectionQ::Rx,
                _ => return Err(bad()),
            };
            Ok(Probe::Midspan {
                span: index(s, "span", name, e.spans)?,
                q,
            })
        }
        [w, q] if w.starts_with("wheel") => {
            let q = match *q {
                "y" => WheelQ::Y,
                "z" => WheelQ::Z,
                "gap_y" => WheelQ::GapY,
                "gap_z" => WheelQ::GapZ,
                "force_z" => WheelQ::ForceZ,
                _ => return Err(bad()),
            };
            if !e.magnets && matches!(q, WheelQ::GapY | WheelQ::GapZ) {
                return Err(bad_probe(format!(
                    "`{name}`: the loads of a forces train have no gaps"
                )));
            }
            Ok(Probe::Wheel {
                wheel: index(w, "wheel", name, e.wheels)?,
                q,
            })
        }
        [c, "body", q] if c.starts_with("car") => {
            let q = match *q {
                "z" => BodyQ::Z,
                "az" => BodyQ::Az,
                _ => return Err(bad()),
            };
            Ok(Probe::Body {
                car: index(c, "car", name, e.cars)?,
                q,
            })
        }
        [p, "base", q] if p.starts_with("pier") => {
            let q = match *q {
                "z" => PierQ::Z,
                "az" => PierQ::Az,
                _ => return Err(bad()),
            };
            Ok(Probe::Pier {
                pier: index(p, "pier", name, usize::MAX)?,
                q,
            })
        }
        [g, "vz"] if g.starts_with("ground") => Ok(Probe::Ground {
            receiver: index(g, "ground", name, usize::MAX)?,
        }),
        _ => Err(bad()),
    }
}

/// The probes of a run and their column names.
#[derive(Clone, Debug)]
pub struct Probes {
    pub names: Vec<String>,
    pub probes: Vec<Probe>,
}

impl Probes {
    /// `names` (or [`DEFAULT`] when `None`), each checked against the case.
    pub fn new(names: Option<&[String]>, e: &Extent) -> Result<Self> {
        let names: Vec<String> = match names {
            Some(n) if !n.is_empty() => n.to_vec(),
            Some(_) => return Err(bad_probe("must name at least one probe".into())),
            None => DEFAULT.iter().map(|s| s.to_string()).collect(),
        };
        let mut probes = Vec::with_capacity(names.len());
        for (i, n) in names.iter().enumerate() {
            // Two columns of one name: response.csv's header would not say which is which.
            if names[..i].contains(n) {
                return Err(bad_probe(format!("names {n:?} twice (each probe once)")));
            }
            // The default set on a forces train: wheel 1's gap is not applicable (empty cells).
            if !e.magnets && n == "wheel1_gap_z" && names.len() == DEFAULT.len() {
                probes.push(Probe::Wheel {
                    wheel: 0,
                    q: WheelQ::GapZ,
                });
                continue;
            }
            probes.push(parse(n, e)?);
        }
        Ok(Probes { names, probes })
    }

    /// The [`DEFAULT`] columns, which every case has (span 1 and wheel 1 always exist; a
    /// forces train's gap is not applicable), without a case to check them against.
    pub fn default_columns() -> Self {
        let any = Extent {
            spans: 1,
            wheels: 1,
            cars: 0,
            magnets: false,
        };
        Probes::new(None, &any).expect("the default columns parse against any case")
    }

    /// Checks the probes that only the guideway can answer (`pier{K}`) against it: one
    /// line naming the probe and the limit.
    pub fn check_guideway(&self, g: &dyn Guideway) -> Result<()> {
        for (name, p) in self.names.iter().zip(&self.probes) {
            if let Probe::Pier { pier, .. } = *p {
                if g.pier_base(pier + 1).is_none() {
                    let n = (1..=pier).take_while(|&k| g.pier_base(k).is_some()).count();
                    return Err(bad_probe(format!(
                        "`{name}`: the guideway has {n} pier(s), so K is at most {n}"
                    )));
                }
            }
        }
        Ok(())
    }

    /// Checks the `ground{N}` probes against the case's `receivers` ground receivers (`None`:
    /// no `[ground]`): one line naming the probe and the limit.
    pub fn check_ground(&self, receivers: Option<usize>) -> Result<()> {
        for (name, p) in self.names.iter().zip(&self.probes) {
            if let Probe::Ground { receiver } = *p {
                match receivers {
                    None => {
                        return Err(bad_probe(format!(
                            "`{name}`: the case has no [ground] receivers"
                        )))
                    }
                    Some(n) if receiver >= n => {
                        return Err(bad_probe(format!(
                            "`{name}`: the case has {n} ground receiver(s), so N is at most {n}"
                        )))
                    }
                    _ => {}
                }
            }
        }
        Ok(())
    }

    /// The columns (from 0, among the probes) of the `ground{N}` probes, with their
    /// receivers (from 0).
    pub fn ground_columns(&self) -> Vec<(usize, usize)> {
        self.probes
            .iter()
            .enumerate()
            .filter_map(|(k, p)| match *p {
                Probe::Ground { receiver } => Some((k, receiver)),
                _ => None,
            })
            .collect()
    }
}

/// The wheels of a step as the probes see them.
pub enum Wheels<'a> {
    /// A vehicle: its committed displacements and accelerations, each wheel's (point on the
    /// guideway, DOFs), gaps `(h_z, d)` and levitation forces.
    Vehicle {
        u: &'a [f64],
        a: &'a [f64],
        /// Each wheel's (Y, Z) DOFs; no Y for a magnet without guidance (a `unit`).
        dofs: &'a [(Option<usize>, usize)],
        gaps: &'a [(f64, f64)],
        forces: &'a [(f64, f64)],
        h0: f64,
        /// The body's heave DOF of each car.
        body_z: &'a [usize],
        /// Every guideway node in probe order (`wheel{N}`).
        nodes: &'a [Node],
        /// Each wheel–rail contact's Z DOF, its force and its static load P0 (N, compressive).
        contact_dofs: &'a [usize],
        contact_forces: &'a [f64],
        contact_p0: &'a [f64],
        /// Each magnet wheel's coils (levitation, guidance left, right) at the step, as the
        /// magnets report them ([`crate::simulation::Magnets::coils`]; empty where they do not).
        coils: &'a [[Coil; 3]],
    },
    /// Moving forces: each load's position and force.
    Forces {
        points: &'a [(f64, f64, f64)],
        forces: &'a [f64],
    },
}

/// Everything the probes may read at the end of a committed step.
pub struct StepView<'a> {
    pub t: f64,
    pub guideway: &'a dyn Guideway,
    /// X of each span's middle.
    pub midspans: &'a [f64],
    pub wheels: Wheels<'a>,
    pub iterations: u32,
    pub collision: bool,
}

impl StepView<'_> {
    /// The value of `p` (NaN where not applicable).
    pub fn value(&self, p: &Probe) -> f64 {
        self.value_with(p, &mut None)
    }

    /// As [`Self::value`], keeping in `memo` the section of the last midspan read, so a
    /// span's three midspan columns query the guideway once (a row's probes in order).
    pub fn value_with(&self, p: &Probe, memo: &mut Option<(usize, SectionMotion)>) -> f64 {
        self.reading_with(p, memo).unwrap_or(f64::NAN)
    }

    /// The value of `p`, `None` where it does not apply (an empty cell) — kept apart from a
    /// value that applies and is not finite (the run diverged, [`finite_reading`]).
    pub fn reading_with(
        &self,
        p: &Probe,
        memo: &mut Option<(usize, SectionMotion)>,
    ) -> Option<f64> {
        Some(match *p {
            Probe::Midspan { span, q } => {
                let m = match *memo {
                    Some((s, m)) if s == span => m,
                    _ => {
                        let m = self.guideway.section_at(self.midspans[span]);
                        *memo = Some((span, m));
                        m
                    }
                };
                match q {
                    SectionQ::Y => m.y,
                    SectionQ::Z => m.z,
                    SectionQ::Rx => m.rx,
                }
            }
            Probe::Wheel { wheel, q } => match &self.wheels {
                Wheels::Vehicle {
                    u,
                    dofs,
                    gaps,
                    forces,
                    h0,
                    nodes,
                    contact_dofs,
                    contact_forces,
                    ..
                } => match nodes[wheel] {
                    Node::Magnet(i) => {
                        let (dy, dz) = dofs[i];
                        match q {
                            WheelQ::Y => u[dy?],
                            WheelQ::Z => u[dz],
                            WheelQ::GapY => {
                                dy?;
                                magnet_gaps(gaps[i], *h0)[1]
                            }
                            WheelQ::GapZ => gaps[i].0,
                            WheelQ::ForceZ => forces[i].0,
                        }
                    }
                    Node::Contact(i) => match q {
                        WheelQ::Z => u[contact_dofs[i]],
                        WheelQ::ForceZ => contact_forces[i],
                        WheelQ::Y | WheelQ::GapY | WheelQ::GapZ => return None,
                    },
                },
                Wheels::Forces { points, forces } => {
                    let (x, ey, ez) = points[wheel];
                    match q {
                        WheelQ::Y => self.guideway.motion_at(x, ey, ez).y,
                        WheelQ::Z => self.guideway.motion_at(x, ey, ez).z,
                        WheelQ::ForceZ => forces[wheel],
                        WheelQ::GapY | WheelQ::GapZ => return None,
                    }
                }
            },
            Probe::Body { car, q } => match &self.wheels {
                Wheels::Vehicle { u, a, body_z, .. } => match q {
                    BodyQ::Z => u[body_z[car]],
                    BodyQ::Az => a[body_z[car]],
                },
                Wheels::Forces { .. } => return None,
            },
            Probe::Pier { pier, q } => match self.guideway.pier_base(pier + 1) {
                Some(b) => match q {
                    PierQ::Z => b.z,
                    PierQ::Az => b.az,
                },
                None => return None,
            },
            // Filled in after the run (module docs).
            Probe::Ground { .. } => return None,
        })
    }
}

/// Probe `k` of `probes` at `step` for a row: `None` where it does not apply, the value
/// where it is finite, and an error naming the time and the probe where it is not — the one
/// place a diverged run is told from a quantity that does not apply (both were an empty
/// cell, and the peaks of a diverged run read 0). Every recorder goes through it.
pub fn finite_reading(
    step: &StepView,
    probes: &Probes,
    k: usize,
    memo: &mut Option<(usize, SectionMotion)>,
) -> Result<Option<f64>> {
    match step.reading_with(&probes.probes[k], memo) {
        Some(v) if !v.is_finite() => Err(diverged(step.t, &probes.names[k], v)),
        r => Ok(r),
    }
}

/// The error of a run whose `quantity` became `v` (not finite) at time `t`.
fn diverged(t: f64, quantity: &str, v: f64) -> Error {
    Error::numerical(format!(
        "the run diverged at t = {t} s: {quantity} = {v} (not finite); no outputs are written (a value of the case may be too extreme, or run.dt_s too long)"
    ))
}

/// `step.t`, or the error if it is not finite (what every recorder checks first).
pub fn finite_t(step: &StepView) -> Result<f64> {
    if step.t.is_finite() {
        Ok(step.t)
    } else {
        Err(diverged(step.t, "t", step.t))
    }
}

/// Where each committed step goes.
pub trait Recorder {
    fn record(&mut self, step: &StepView) -> Result<()>;
}

/// Keeps every step's time, iteration count and probe values in memory, one row per committed
/// step (tests, studies that post-process a few columns, `hil --compare`).
pub struct Rows {
    pub probes: Probes,
    /// Each recorded step's time (s) and iterations (0 at t = 0).
    pub t: Vec<f64>,
    pub iterations: Vec<u32>,
    pub rows: Vec<Vec<f64>>,
}

impl Rows {
    pub fn new(probes: Probes) -> Self {
        Rows {
            probes,
            t: Vec::new(),
            iterations: Vec::new(),
            rows: Vec::new(),
        }
    }

    /// The history of column `name` (None if no probe has that name).
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let i = self.probes.names.iter().position(|n| n == name)?;
        Some(self.rows.iter().map(|r| r[i]).collect())
    }
}

impl Recorder for Rows {
    fn record(&mut self, step: &StepView) -> Result<()> {
        finite_t(step)?;
        let mut memo = None;
        let row = (0..self.probes.probes.len())
            .map(|k| Ok(finite_reading(step, &self.probes, k, &mut memo)?.unwrap_or(f64::NAN)))
            .collect::<Result<_>>()?;
        self.t.push(step.t);
        self.iterations.push(step.iterations);
        self.rows.push(row);
        Ok(())
    }
}

/// Hands every step to two recorders in turn (a run's response.csv and an in-memory copy).
pub struct Tee<'a>(pub &'a mut dyn Recorder, pub &'a mut dyn Recorder);

impl Recorder for Tee<'_> {
    fn record(&mut self, step: &StepView) -> Result<()> {
        self.0.record(step)?;
        self.1.record(step)
    }
}

/// Records nothing (runs whose callers keep only the outcome's counters and ranges).
pub struct NoRecorder;

impl Recorder for NoRecorder {
    fn record(&mut self, _step: &StepView) -> Result<()> {
        Ok(())
    }
}

/// The file a [`CsvRecorder`] names in its errors.
pub const RESPONSE_CSV: &str = "response.csv";

/// Appends `v` to a CSV line as its shortest round-trip decimal (ryu's layout: `0.0`,
/// `36787.5`, `4.360489000582685e-17`, `1e21`; never needs quoting); nothing for NaN or ±∞
/// (an empty cell: not applicable). Every finite value parses back (`str::parse::<f64>`) to
/// the same bits, `-0.0` included.
///
/// The digits come from zmij (serde_json's formatter; 0.70 M instructions against ryu's
/// 1.33 M over the §4.2 passage's rows, docs/performance.md), whose layout differs from
/// ryu's only in the `+` of a positive exponent (`1e+21`), dropped here: the bytes are
/// ryu's (test `layout_is_ryus`), so response.csv did not change.
pub fn push_csv_f64(line: &mut Vec<u8>, v: f64) {
    if v.is_finite() {
        let mut buf = zmij::Buffer::new();
        let s = buf.format_finite(v).as_bytes();
        // Below 1e16 both write plain digits or a negative exponent: no `+` to look for.
        let plus = if v.abs() >= 1e16 {
            s.iter().position(|&b| b == b'+')
        } else {
            None
        };
        match plus {
            None => line.extend_from_slice(s),
            Some(p) => {
                line.extend_from_slice(&s[..p]);
                line.extend_from_slice(&s[p + 1..]);
            }
        }
    }
}

/// Appends `n` in decimal (as `{n}` formats it).
fn push_decimal(line: &mut Vec<u8>, n: u32) {
    let mut digits = [0u8; 10];
    let (mut k, mut n) = (digits.len(), n);
    loop {
        k -= 1;
        digits[k] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    line.extend_from_slice(&digits[k..]);
}

/// Streams `t, <probes…>, iterations, collision` rows to a CSV file (SI; shortest round-trip
/// decimals, [`push_csv_f64`]; not-applicable values empty).
///
/// The header goes through the csv crate (a probe name could need quoting); a row is only
/// numbers, so it is appended to one reusable buffer as it is, and the buffer goes to the
/// sink in writes of [`CsvRecorder::CHUNK`] bytes (the sink needs no buffering of its own).
/// The buffer's memory is touched when the recorder is made, so the time loop meets no page
/// fault of it (nor an allocation).
pub struct CsvRecorder<W: Write> {
    probes: Probes,
    out: W,
    buf: Vec<u8>,
}

impl<W: Write> CsvRecorder<W> {
    /// Writes the header. A failed write is an [`Error::Io`] on `response.csv` (the caller
    /// that knows the file's path may replace it).
    pub fn new(probes: Probes, mut sink: W) -> Result<Self> {
        let mut header = csv::Writer::from_writer(Vec::new());
        let mut names = vec!["t".to_string()];
        names.extend(probes.names.iter().cloned());
        names.push("iterations".into());
        names.push("collision".into());
        header
            .write_record(&names)
            .map_err(|e| Error::io(RESPONSE_CSV, e.into()))?;
        let header = header
            .into_inner()
            .map_err(|e| Error::io(RESPONSE_CSV, e.into_error()))?;
        sink.write_all(&header)
            .map_err(|e| Error::io(RESPONSE_CSV, e))?;
        // Room for a chunk and one more row (a cell is at most 24 bytes), pages written.
        let mut buf = written(Self::CHUNK + 32 * names.len(), 0u8);
        buf.clear();
        Ok(CsvRecorder {
            probes,
            out: sink,
            buf,
        })
    }

    /// The size of the writes to the sink: 64 KiB, as `maglev irregularity` writes stdout.
    /// Measured here (`dd if=/dev/zero of=F bs=8k count=10000` against `bs=64k count=1250`):
    /// 12 µs a write of 8 KiB (a `BufWriter`'s default) against 35 µs for 64 KiB.
    pub const CHUNK: usize = 1 << 16;

    /// Writes what is buffered, flushes and returns the sink.
    pub fn finish(mut self) -> Result<W> {
        self.out
            .write_all(&self.buf)
            .and_then(|()| self.out.flush())
            .map_err(|e| Error::io(RESPONSE_CSV, e))?;
        Ok(self.out)
    }
}

impl<W: Write> Recorder for CsvRecorder<W> {
    fn record(&mut self, step: &StepView) -> Result<()> {
        // The row goes straight after the rows still buffered.
        let line = &mut self.buf;
        push_csv_f64(line, finite_t(step)?);
        let mut memo = None;
        for k in 0..self.probes.probes.len() {
            let v = finite_reading(step, &self.probes, k, &mut memo)?;
            line.push(b',');
            push_csv_f64(line, v.unwrap_or(f64::NAN));
        }
        line.push(b',');
        push_decimal(line, step.iterations);
        line.push(b',');
        line.push(if step.collision { b'1' } else { b'0' });
        line.push(b'\n');
        if line.len() < Self::CHUNK {
            return Ok(());
        }
        let written = self.out.write_all(line);
        line.clear();
        written.map_err(|e| Error::io(RESPONSE_CSV, e))
    }
}

/// `n` copies of `value` in memory already written, so that the time loop, which fills it,
/// meets no page fault (the OS maps a fresh or zeroed allocation, `vec![0.0; n]`, only on
/// first touch). A vector cleared after this keeps its pages.
pub(crate) fn written<T: Clone>(n: usize, value: T) -> Vec<T> {
    let mut v = Vec::with_capacity(n);
    v.resize(n, value);
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    const E: Extent = Extent {
        spans: 3,
        wheels: 4,
        cars: 1,
        magnets: true,
    };

    /// The message of a refused probe name; every refusal is `Invalid` on `output.probes`.
    fn refused(name: &str, e: &Extent) -> String {
        match parse(name, e).unwrap_err() {
            Error::Invalid { key, reason } => {
                assert_eq!(key, "output.probes", "{reason}");
                reason
            }
            other => panic!("{name}: not an Invalid error: {other}"),
        }
    }

    /// A row of awkward values through the recorder: every cell parses back to the value's
    /// bits (`-0.0` stays `-0.0`), not-applicable values are empty cells, and the integers
    /// are plain.
    /// Iteration counts are written as `{n}` writes them.
    #[test]
    fn decimal_matches_format() {
        for n in [0u32, 1, 9, 10, 99, 100, 12345, u32::MAX] {
            let mut line = Vec::new();
            push_decimal(&mut line, n);
            assert_eq!(String::from_utf8(line).unwrap(), n.to_string());
        }
    }

    /// [`push_csv_f64`] writes exactly ryu's text: 2·10⁶ values over every exponent (random
    /// bit patterns), probability-like values, integers in milli-units and subnormals,
    /// and the layout's edge cases.
    #[test]
    fn layout_is_ryus() {
        let mut s: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut line = Vec::new();
        let check = |v: f64, line: &mut Vec<u8>| {
            line.clear();
            push_csv_f64(line, v);
            let want = if v.is_finite() {
                ryu::Buffer::new().format_finite(v).to_string()
            } else {
                String::new()
            };
            assert_eq!(std::str::from_utf8(line).unwrap(), want, "{v:e}");
        };
        for v in [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.1,
            1e-5,
            1e-7,
            1e15,
            9.999999999999998e15,
            1e16,
            1e21,
            1e22,
            5e-324,
            f64::MAX,
            f64::MIN,
            f64::MIN_POSITIVE,
            36787.5,
            123456789012345680.0,
            f64::NAN,
            f64::INFINITY,
        ] {
            check(v, &mut line);
        }
        for i in 0..2_000_000u64 {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            let v = match i % 4 {
                0 => f64::from_bits(s),
                1 => (s >> 11) as f64 / (1u64 << 53) as f64,
                2 => (s >> 40) as f64 * 1e-3,
                _ => f64::from_bits(s >> 12),
            };
            check(v, &mut line);
        }
    }

    #[test]
    fn csv_cells_parse_back_to_the_same_bits() {
        let values = [
            f64::from_bits(1),       // the smallest subnormal
            f64::MIN_POSITIVE / 3.0, // a subnormal with many digits
            1e-300,
            -0.0,
            0.0,
            0.1 + 0.2, // 0.30000000000000004
            f64::MAX,
            f64::MIN,
            4.360489000582685e-17, // Display: 0.00000000000000004360489000582685
            -3.51385004004739e-23,
            36787.41873257823,
            1e21,
            123456789012345680.0,
        ];
        let n = values.len();
        let e = Extent {
            spans: 1,
            wheels: n,
            cars: 0,
            magnets: false,
        };
        let names: Vec<String> = (1..=n).map(|k| format!("wheel{k}.force_z")).collect();
        let probes = Probes::new(Some(&names), &e).unwrap();
        let mut rec = CsvRecorder::new(probes, Vec::new()).unwrap();
        let g = crate::physics::guideway::RigidGuideway::new(1e-3);
        let points = vec![(0.0, 0.0, 0.0); n];
        let t = 0.1 + 0.2;
        let step = StepView {
            t,
            guideway: &g,
            midspans: &[],
            wheels: Wheels::Forces {
                points: &points,
                forces: &values,
            },
            iterations: 17,
            collision: true,
        };
        rec.record(&step).unwrap();
        rec.record(&StepView {
            collision: false,
            ..step
        })
        .unwrap();
        let text = String::from_utf8(rec.finish().unwrap()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3, "{text}");
        assert_eq!(
            lines[0],
            format!("t,{},iterations,collision", names.join(","))
        );
        for (row, collision) in [(lines[1], "1"), (lines[2], "0")] {
            let cells: Vec<&str> = row.split(',').collect();
            assert_eq!(cells.len(), n + 3, "{row}");
            assert_eq!(cells[0].parse::<f64>().unwrap().to_bits(), t.to_bits());
            for (v, c) in values.iter().zip(&cells[1..=n]) {
                let back: f64 = c.parse().unwrap_or_else(|_| panic!("{c:?}"));
                assert_eq!(back.to_bits(), v.to_bits(), "{v:e} written as {c:?}");
            }
            assert_eq!(cells[n + 1], "17");
            assert_eq!(cells[n + 2], collision);
        }
        // Small values in exponent form, not Display's run of zeros; -0.0 keeps its sign.
        let cells: Vec<&str> = lines[1].split(',').collect();
        assert_eq!(cells[9], "4.360489000582685e-17");
        assert_eq!(cells[4], "-0.0");
        assert!(text.ends_with("0\n") && !text.contains('\r'));
    }

    /// A quantity that does not apply is an empty cell; one that applies and is not finite
    /// stops the recording with an error naming the time and the probe (it was an empty
    /// cell too, and a diverged run's peaks read 0).
    #[test]
    fn not_applicable_is_empty_and_diverged_is_an_error() {
        let e = Extent {
            spans: 1,
            wheels: 1,
            cars: 0,
            magnets: false,
        };
        let names = vec!["pier1.base.z".to_string(), "wheel1.force_z".to_string()];
        let g = crate::physics::guideway::RigidGuideway::new(1e-3);
        let points = [(0.0, 0.0, 0.0)];
        for v in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1.5] {
            let forces = [v];
            let step = StepView {
                t: 0.25,
                guideway: &g,
                midspans: &[],
                wheels: Wheels::Forces {
                    points: &points,
                    forces: &forces,
                },
                iterations: 1,
                collision: false,
            };
            let probes = Probes::new(Some(&names), &e).unwrap();
            let mut csv = CsvRecorder::new(probes.clone(), Vec::new()).unwrap();
            let mut rows = Rows::new(probes);
            let (a, b) = (csv.record(&step), rows.record(&step));
            if v.is_finite() {
                a.unwrap();
                b.unwrap();
                let text = String::from_utf8(csv.finish().unwrap()).unwrap();
                assert!(text.ends_with("\n0.25,,1.5,1,0\n"), "{text}");
            } else {
                for r in [a, b] {
                    let m = r.unwrap_err().to_string();
                    assert!(
                        m.starts_with(&format!(
                            "the run diverged at t = 0.25 s: wheel1.force_z = {v}"
                        )),
                        "{m}"
                    );
                }
            }
        }
    }

    /// A sink that keeps every write's size.
    struct Writes {
        bytes: Vec<u8>,
        sizes: Vec<usize>,
    }

    impl Write for Writes {
        fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
            self.bytes.extend_from_slice(b);
            self.sizes.push(b.len());
            Ok(b.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    /// 6000 rows (≈ 180 KB) reach the sink whole and in order: the header's write, then
    /// writes of at least [`CsvRecorder::CHUNK`] bytes, then what `finish` leaves.
    #[test]
    fn rows_go_out_in_chunks() {
        let e = Extent {
            spans: 1,
            wheels: 1,
            cars: 0,
            magnets: false,
        };
        let names = vec!["wheel1.force_z".to_string()];
        let probes = Probes::new(Some(&names), &e).unwrap();
        let sink = Writes {
            bytes: Vec::new(),
            sizes: Vec::new(),
        };
        let mut rec = CsvRecorder::new(probes, sink).unwrap();
        let g = crate::physics::guideway::RigidGuideway::new(1e-3);
        let points = [(0.0, 0.0, 0.0)];
        let mut want = String::from("t,wheel1.force_z,iterations,collision\n");
        for k in 0..6000u32 {
            let t = k as f64 * 1e-3;
            let f = [36787.5 + (k as f64).sin()];
            rec.record(&StepView {
                t,
                guideway: &g,
                midspans: &[],
                wheels: Wheels::Forces {
                    points: &points,
                    forces: &f,
                },
                iterations: k % 4,
                collision: false,
            })
            .unwrap();
            want.push_str(&format!("{t:?},{:?},{},0\n", f[0], k % 4));
        }
        let out = rec.finish().unwrap();
        assert_eq!(String::from_utf8(out.bytes).unwrap(), want);
        let (first, rest) = out.sizes.split_first().unwrap();
        assert_eq!(*first, "t,wheel1.force_z,iterations,collision\n".len());
        let (last, chunks) = rest.split_last().unwrap();
        let chunk = CsvRecorder::<Writes>::CHUNK;
        // A chunk goes out with the row that fills it (a row here is under 64 bytes).
        assert!(chunks.len() >= 2, "{:?}", out.sizes);
        assert!(chunks.iter().all(|&c| (chunk..chunk + 64).contains(&c)));
        assert!(*last < chunk);
    }

    #[test]
    fn names_parse_and_are_checked_against_the_case() {
        assert_eq!(
            parse("span3.midspan.rx", &E).unwrap(),
            Probe::Midspan {
                span: 2,
                q: SectionQ::Rx
            }
        );
        assert_eq!(
            parse("midspan_z", &E).unwrap(),
            parse("span1.midspan.z", &E).unwrap()
        );
        assert_eq!(
            parse("wheel4.gap_y", &E).unwrap(),
            Probe::Wheel {
                wheel: 3,
                q: WheelQ::GapY
            }
        );
        assert_eq!(
            parse("car1.body.az", &E).unwrap(),
            Probe::Body {
                car: 0,
                q: BodyQ::Az
            }
        );
        assert_eq!(
            parse("span4.midspan.z", &E).unwrap_err().to_string(),
            "output.probes: `span4.midspan.z`: the case has 3 span(s), so N is at most 3"
        );
        let e = refused("wheel0.z", &E);
        assert!(e.contains("from 1"), "{e}");
        assert!(refused("wheel1.colour", &E).contains("unknown probe"));
        // Found by the input fuzz target: a name with a line break made a two-line error.
        let e = parse("%spa#\\\ngap_y", &E).unwrap_err().to_string();
        assert!(!e.contains('\n') && e.contains("%spa#\\\\ngap_y"), "{e}");
        assert!(refused("car2.body.z", &E).contains("at most 1"));
        let forces = Extent {
            magnets: false,
            cars: 0,
            ..E
        };
        assert!(refused("wheel1.gap_z", &forces).contains("no gaps"));
        assert!(parse("car1.body.z", &forces).is_err());
        assert_eq!(
            parse("pier20.base.az", &E).unwrap(),
            Probe::Pier {
                pier: 19,
                q: PierQ::Az
            }
        );
        assert!(refused("pier0.base.z", &E).contains("from 1"));
        assert!(refused("pier2.base.y", &E).contains("unknown probe"));
        assert_eq!(
            Probes::new(Some(&[]), &E).unwrap_err().to_string(),
            "output.probes: must name at least one probe"
        );
        assert_eq!(Probes::new(None, &E).unwrap().names.len(), DEFAULT.len());
    }
}
