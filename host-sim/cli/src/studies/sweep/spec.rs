//! The sweep spec: a TOML file naming a scenario, fixed overrides, axes and reductions.
//!
//! Why typed and checked up front: a sweep is hours of runs, so a misspelt key, an empty axis
//! or a range of a billion values must fail in the first second with one line naming the key
//! and the limit, not in run 4000. The axes keep the order in which the file lists them: the
//! first axis is the x axis of the plots, and the cartesian product runs with the last axis
//! varying fastest.

use crate::{Error, Result};
use serde::{Deserialize, Serialize};

/// The most runs one sweep may hold (the cartesian product of its axes).
pub const MAX_RUNS: usize = 1_000_000;

/// One value of an axis or of `[set]`: what a `--set key=value` takes.
#[derive(Deserialize, Serialize, Clone, Debug, PartialEq)]
#[serde(untagged)]
pub enum Scalar {
    Int(i64),
    Float(f64),
    Bool(bool),
    Str(String),
}

impl Scalar {
    /// The value as TOML text: what `--set key=<text>` is given.
    pub fn toml(&self) -> String {
        match self {
            Scalar::Int(i) => i.to_string(),
            Scalar::Float(f) => toml::Value::Float(*f).to_string(),
            Scalar::Bool(b) => b.to_string(),
            Scalar::Str(s) => toml::Value::String(s.clone()).to_string(),
        }
    }

    /// The value as a results.csv cell (strings unquoted; numbers as in TOML).
    pub fn cell(&self) -> String {
        match self {
            Scalar::Str(s) => s.clone(),
            other => other.toml(),
        }
    }

    /// The value as a number, for plots (None for strings and booleans).
    pub fn number(&self) -> Option<f64> {
        match self {
            Scalar::Int(i) => Some(*i as f64),
            Scalar::Float(f) => Some(*f),
            _ => None,
        }
    }
}

/// An axis as written: a list of values, or `{ from, to, step }`.
#[derive(Deserialize, Clone, Debug)]
#[serde(untagged)]
enum AxisDef {
    List(Vec<Scalar>),
    Range(Range),
}

#[derive(Deserialize, Clone, Debug)]
#[serde(deny_unknown_fields)]
struct Range {
    from: Scalar,
    to: Scalar,
    step: Scalar,
}

/// The axes with where each stands in the file (TOML tables arrive sorted by key; the
/// spans give back the file's order).
type Axes = std::collections::BTreeMap<String, toml::Spanned<AxisDef>>;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Reduce {
    quantities: Vec<String>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct File {
    scenario: String,
    #[serde(default)]
    set: toml::Table,
    axes: Axes,
    reduce: Reduce,
}

/// How a quantity reduces a probe's history.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reduction {
    /// The signed value of the largest magnitude (as summary.json's peaks).
    Peak,
    Min,
    Max,
    /// The root mean square over every recorded step.
    Rms,
}

/// One column of results.csv: `peak|min|max|rms : probe`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(into = "String", try_from = "String")]
pub struct ReducedProbe {
    pub reduction: Reduction,
    /// A probe name as `[output] probes` takes it (`midspan_z`, `span2.midspan.z`, …).
    pub probe: String,
}

impl ReducedProbe {
    /// Parses `kind:probe` (the probe is checked against the case later).
    pub fn parse(s: &str) -> Result<Self> {
        let bad = || {
            Error::invalid(
                "reduce.quantities",
                format!("`{s}`: expected peak|min|max|rms:PROBE, e.g. peak:midspan_z"),
            )
        };
        let (kind, probe) = s.split_once(':').ok_or_else(bad)?;
        let reduction = match kind.trim() {
            "peak" => Reduction::Peak,
            "min" => Reduction::Min,
            "max" => Reduction::Max,
            "rms" => Reduction::Rms,
            _ => return Err(bad()),
        };
        let probe = probe.trim();
        if probe.is_empty() {
            return Err(bad());
        }
        Ok(ReducedProbe {
            reduction,
            probe: probe.to_string(),
        })
    }

    /// The column name in results.csv: `kind:probe`.
    pub fn name(&self) -> String {
        let k = match self.reduction {
            Reduction::Peak => "peak",
            Reduction::Min => "min",
            Reduction::Max => "max",
            Reduction::Rms => "rms",
        };
        format!("{k}:{}", self.probe)
    }
}

impl From<ReducedProbe> for String {
    fn from(q: ReducedProbe) -> String {
        q.name()
    }
}

impl TryFrom<String> for ReducedProbe {
    type Error = Error;
    fn try_from(s: String) -> Result<Self> {
        ReducedProbe::parse(&s)
    }
}

/// One axis: its `--set` key and its values, in order.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Axis {
    pub key: String,
    pub values: Vec<Scalar>,
}

/// A parsed and checked sweep spec (also what a sweep directory's `sweep.json` holds).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Spec {
    /// A bundled scenario name or a file path (relative paths are taken from the spec's
    /// directory by [`Spec::load`]).
    pub scenario: String,
    /// The fixed overrides as `key=value` strings, in key order.
    pub sets: Vec<String>,
    pub axes: Vec<Axis>,
    pub quantities: Vec<ReducedProbe>,
}

impl Spec {
    /// Reads and checks the spec file at `path`.
    pub fn load(path: &std::path::Path) -> Result<Self> {
        let text = crate::input::read_text(path)?;
        let mut spec = Self::parse(&text)?;
        // A scenario file named relative to the spec is found beside it.
        let bundled = crate::input::scenario::BUNDLED
            .iter()
            .any(|(n, _)| *n == spec.scenario);
        if !bundled {
            let p = std::path::Path::new(&spec.scenario);
            if p.is_relative() {
                if let Some(dir) = path.parent() {
                    let beside = dir.join(p);
                    if beside.is_file() {
                        spec.scenario = beside.to_string_lossy().into_owned();
                    }
                }
            }
        }
        Ok(spec)
    }

    /// Parses and checks spec text.
    pub fn parse(text: &str) -> Result<Self> {
        let text = crate::input::toml_within_cap("sweep spec", text)?;
        let file: File = toml::from_str(text).map_err(|e| {
            Error::parse(
                "sweep spec",
                e.to_string()
                    .split_whitespace()
                    .collect::<Vec<_>>()
                    .join(" "),
            )
        })?;
        if file.scenario.trim().is_empty() {
            return Err(Error::invalid("scenario", "must name a scenario"));
        }
        let mut sets = Vec::new();
        for (k, v) in &file.set {
            if matches!(v, toml::Value::Table(_)) {
                return Err(Error::invalid(
                    format!("set.{k}"),
                    "must be a value (write section.key = value for a nested key)",
                ));
            }
            sets.push(format!("{k}={v}"));
        }
        if file.axes.is_empty() {
            return Err(Error::invalid("axes", "must list at least one axis"));
        }
        let mut axes: Vec<Axis> = Vec::new();
        let mut in_order: Vec<(String, toml::Spanned<AxisDef>)> = file.axes.into_iter().collect();
        in_order.sort_by_key(|(_, d)| d.span().start);
        for (key, def) in in_order {
            let def = def.into_inner();
            let name = format!("axes.{key}");
            if file.set.contains_key(&key) {
                return Err(Error::invalid(name, "is also fixed in [set]; keep one"));
            }
            let values = match def {
                AxisDef::List(v) => v,
                AxisDef::Range(r) => range(&name, &r)?,
            };
            if values.is_empty() {
                return Err(Error::invalid(name, "must hold at least one value"));
            }
            // Distinct by their TOML text (what `--set` is given): linear in the axis's length.
            let mut seen = std::collections::HashSet::with_capacity(values.len());
            for v in &values {
                if !seen.insert(v.toml()) {
                    return Err(Error::invalid(
                        name,
                        format!(
                            "value {} appears twice; each run must be distinct",
                            v.cell()
                        ),
                    ));
                }
            }
            axes.push(Axis { key, values });
        }
        let mut runs: usize = 1;
        for a in &axes {
            runs = runs.saturating_mul(a.values.len());
        }
        if runs > MAX_RUNS {
            return Err(Error::invalid(
                "axes",
                format!("the product holds {runs} runs, at most {MAX_RUNS}"),
            ));
        }
        if file.reduce.quantities.is_empty() {
            return Err(Error::invalid(
                "reduce.quantities",
                "must name at least one quantity",
            ));
        }
        let quantities = file
            .reduce
            .quantities
            .iter()
            .map(|q| ReducedProbe::parse(q))
            .collect::<Result<Vec<_>>>()?;
        for (i, q) in quantities.iter().enumerate() {
            if quantities[..i].contains(q) {
                return Err(Error::invalid(
                    "reduce.quantities",
                    format!("`{}` appears twice", q.name()),
                ));
            }
        }
        Ok(Spec {
            scenario: file.scenario,
            sets,
            axes,
            quantities,
        })
    }

    /// How many runs the sweep holds.
    pub fn runs(&self) -> usize {
        self.axes.iter().map(|a| a.values.len()).product()
    }
}

/// The values of `{from, to, step}`: from + k·step for k = 0, 1, … while within `to` (to a
/// millionth of a step, so 0.1-steps end where written). Integers stay integers; floats are
/// rounded to 12 significant digits so that 0.1 + 2·0.1 is written 0.3.
fn range(name: &str, r: &Range) -> Result<Vec<Scalar>> {
    if let (Scalar::Int(from), Scalar::Int(to), Scalar::Int(step)) = (&r.from, &r.to, &r.step) {
        let (from, to, step) = (*from, *to, *step);
        if step <= 0 {
            return Err(Error::invalid(
                format!("{name}.step"),
                format!("must be > 0, got {step}"),
            ));
        }
        if to < from {
            return Err(Error::invalid(
                format!("{name}.to"),
                format!("must be ≥ from = {from}, got {to}"),
            ));
        }
        let n = (to - from) / step + 1;
        if n as u128 > MAX_RUNS as u128 {
            return Err(Error::invalid(
                name,
                format!("holds {n} values, at most {MAX_RUNS}"),
            ));
        }
        return Ok((0..n).map(|k| Scalar::Int(from + k * step)).collect());
    }
    let num = |field: &str, v: &Scalar| {
        v.number().filter(|x| x.is_finite()).ok_or_else(|| {
            Error::invalid(
                format!("{name}.{field}"),
                format!("must be a finite number, got {}", v.cell()),
            )
        })
    };
    let (from, to, step) = (
        num("from", &r.from)?,
        num("to", &r.to)?,
        num("step", &r.step)?,
    );
    if step <= 0.0 {
        return Err(Error::invalid(
            format!("{name}.step"),
            format!("must be > 0, got {step}"),
        ));
    }
    if to < from {
        return Err(Error::invalid(
            format!("{name}.to"),
            format!("must be ≥ from = {from}, got {to}"),
        ));
    }
    let n = ((to - from) / step + 1e-6).floor() + 1.0;
    if n > MAX_RUNS as f64 {
        return Err(Error::invalid(
            name,
            format!("holds {n} values, at most {MAX_RUNS}"),
        ));
    }
    Ok((0..n as usize)
        .map(|k| {
            let v = from + k as f64 * step;
            Scalar::Float(format!("{v:.11e}").parse().unwrap_or(v))
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    const ISSUE: &str = r#"
scenario = "paper-4.2"
[set]
scheme = "accurate"
[axes]
speed = [50.0, 100.0, 150.0]
seed = [1, 2]
[reduce]
quantities = ["peak:midspan_z", "peak:wheel1_gap_z"]
"#;

    #[test]
    fn the_issue_spec_parses_with_its_axes_in_file_order() {
        let s = Spec::parse(ISSUE).unwrap();
        assert_eq!(s.scenario, "paper-4.2");
        assert_eq!(s.sets, vec![r#"scheme="accurate""#.to_string()]);
        // "speed" is listed first although "seed" sorts first.
        assert_eq!(s.axes[0].key, "speed");
        assert_eq!(s.axes[1].key, "seed");
        assert_eq!(
            s.axes[0].values,
            vec![
                Scalar::Float(50.0),
                Scalar::Float(100.0),
                Scalar::Float(150.0)
            ]
        );
        assert_eq!(s.axes[1].values, vec![Scalar::Int(1), Scalar::Int(2)]);
        assert_eq!(s.runs(), 6);
        assert_eq!(s.quantities[1].reduction, Reduction::Peak);
        assert_eq!(s.quantities[1].probe, "wheel1_gap_z");
        assert_eq!(s.axes[0].values[0].toml(), "50.0");
    }

    #[test]
    fn ranges_end_where_written() {
        let s = Spec::parse(
            "scenario='moving-force'\n[axes]\nspeed={from=0.1,to=0.5,step=0.1}\nseed={from=1,to=100,step=1}\n[reduce]\nquantities=['max:midspan_z']",
        )
        .unwrap();
        let v: Vec<String> = s.axes[0].values.iter().map(Scalar::cell).collect();
        assert_eq!(v, ["0.1", "0.2", "0.3", "0.4", "0.5"]);
        assert_eq!(s.axes[1].values.len(), 100);
        assert_eq!(s.axes[1].values[99], Scalar::Int(100));
    }

    fn err(text: &str) -> String {
        Spec::parse(text).unwrap_err().to_string()
    }

    #[test]
    fn bad_specs_name_the_key_and_the_limit() {
        let base = |axes: &str, red: &str| {
            format!("scenario='moving-force'\n[axes]\n{axes}\n[reduce]\nquantities=[{red}]")
        };
        let e = err(&base(
            "speed={from=1.0,to=2.0,step=0.0}",
            "'peak:midspan_z'",
        ));
        assert!(e.contains("axes.speed.step") && e.contains("> 0"), "{e}");
        let e = err(&base(
            "seed={from=1,to=10000000,step=1}",
            "'peak:midspan_z'",
        ));
        assert!(
            e.contains("axes.seed") && e.contains("at most 1000000"),
            "{e}"
        );
        let e = err(&base("speed=[]", "'peak:midspan_z'"));
        assert!(
            e.contains("axes.speed") && e.contains("at least one"),
            "{e}"
        );
        let e = err(&base("speed=[1.0,1.0]", "'peak:midspan_z'"));
        assert!(e.contains("appears twice"), "{e}");
        let e = err(&base("speed=[1.0]", "'mean:midspan_z'"));
        assert!(
            e.contains("reduce.quantities") && e.contains("peak|min|max|rms"),
            "{e}"
        );
        let e = err(&base("speed=[1.0]", ""));
        assert!(e.contains("reduce.quantities"), "{e}");
        let e = err("scenario='x'\n[axes]\n[reduce]\nquantities=['peak:midspan_z']");
        assert!(e.contains("axes"), "{e}");
        let e = err("scenario='x'\ncolour=1\n[axes]\nspeed=[1]\n[reduce]\nquantities=['peak:z']");
        assert!(e.contains("colour"), "{e}");
        let e =
            err("scenario='x'\n[set]\nspeed=1\n[axes]\nspeed=[1]\n[reduce]\nquantities=['peak:z']");
        assert!(e.contains("axes.speed") && e.contains("[set]"), "{e}");
        for e in [
            err(&base(
                "speed={from=1.0,to=2.0,step=0.0}",
                "'peak:midspan_z'",
            )),
            err(&base("speed=[1.0]", "'mean:midspan_z'")),
        ] {
            assert!(!e.contains('\n'), "{e}");
        }
    }
}
