//! `maglev modes`: natural frequencies of the §4.2 beam (one simply supported span of 25 m,
//! docs/model.md §9), of the paper-5 viaduct (`--viaduct SPANS`), or of a scenario's guideway
//! (`--scenario NAME`), from the FE model, as JSON or CSV on stdout.

use crate::physics::fe::{natural_modes, SpanModel};
use crate::physics::guideway::BeamSection;
use crate::{Error, Result};

/// Span length of the §4.2 validation beam (m).
pub const SPAN_LENGTH: f64 = 25.0;
/// Largest element count accepted: the dense eigen-solve grows as n³ (300 elements take ~2 s
/// optimised, 500 about 10 s).
pub const MAX_ELEMENTS: usize = 500;

/// Output format.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Json,
    Csv,
}

/// Natural frequencies of the §4.2 beam.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Number of Timoshenko elements over the 25 m span.
    #[arg(long, default_value_t = 20)]
    pub elements: usize,
    /// Number of modes to print, lowest first.
    #[arg(long, default_value_t = 12)]
    pub count: usize,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Json)]
    pub format: Format,
    /// Instead of the §4.2 beam: the paper-5 viaduct (docs/viaduct.md) with this many spans
    /// (35 in the paper), `--elements` per girder, by sparse subspace iteration.
    #[arg(long, value_name = "SPANS", conflicts_with = "scenario")]
    pub viaduct: Option<usize>,
    /// Instead of the §4.2 beam: the guideway of this scenario (a bundled name or a file):
    /// its viaduct, or its single span, at the scenario's elements per span.
    #[arg(long, conflicts_with = "elements")]
    pub scenario: Option<String>,
    /// Override a value of `--scenario` (as `maglev run --set`; repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE", requires = "scenario")]
    pub sets: Vec<String>,
}

#[derive(serde::Serialize)]
struct Row {
    index: usize,
    frequency_hz: f64,
    kind: &'static str,
}

/// The output text for `args`, or a one-line error.
pub fn render(args: &Args) -> Result<String> {
    if args.elements == 0 || args.elements > MAX_ELEMENTS {
        return Err(Error::invalid(
            "--elements",
            format!(
                "must be between 1 and {MAX_ELEMENTS}, got {}",
                args.elements
            ),
        ));
    }
    if let Some(spans) = args.viaduct {
        let mut spec = crate::physics::fe::paper5_viaduct().with_spans(spans);
        spec.elements_per_span = args.elements;
        if spans == 0 || spans > MAX_SPANS {
            return Err(Error::invalid(
                "--viaduct",
                format!("must be between 1 and {MAX_SPANS} spans, got {spans}"),
            ));
        }
        return render_rows(args.format, &viaduct_rows(&spec, args.count)?);
    }
    let (section, length, elements) = match &args.scenario {
        Some(name) => {
            let case = crate::input::case::Case::load(name, &args.sets)?;
            if let Some(spec) = &case.viaduct {
                return render_rows(args.format, &viaduct_first_rows(spec, args.count)?);
            }
            match case.bridge.spans.as_slice() {
                [l] => (case.bridge.section.clone(), *l, case.elements_per_span),
                spans => {
                    return Err(Error::invalid(
                        format!("--scenario {name}"),
                        format!("{} independent simply supported spans each have their own modes; give a single span (--set bridge.spans_m=[L]) or a viaduct", spans.len()),
                    ))
                }
            }
        }
        None => (BeamSection::paper_4_2(), SPAN_LENGTH, args.elements),
    };
    if elements == 0 || elements > MAX_ELEMENTS {
        return Err(Error::invalid(
            "run.elements_per_span",
            format!("must be between 1 and {MAX_ELEMENTS} for modes, got {elements}"),
        ));
    }
    let model = SpanModel::new(&section, length, elements)?;
    let dofs = model.free_dofs();
    if args.count == 0 || args.count > dofs {
        return Err(Error::invalid(
            "--count",
            format!(
                "must be between 1 and {dofs} (free DOFs with {} elements), got {}",
                elements, args.count
            ),
        ));
    }
    let rows: Vec<Row> = natural_modes(&model)?
        .into_iter()
        .take(args.count)
        .enumerate()
        .map(|(i, m)| Row {
            index: i + 1,
            frequency_hz: m.frequency_hz,
            kind: m.kind.as_str(),
        })
        .collect();
    render_rows(args.format, &rows)
}

/// Largest viaduct accepted by `--viaduct`.
pub const MAX_SPANS: usize = 100;

fn viaduct_rows(spec: &crate::physics::fe::ViaductSpec, count: usize) -> Result<Vec<Row>> {
    if spec.elements_per_span > MAX_ELEMENTS {
        return Err(Error::invalid(
            "--elements",
            format!(
                "elements per girder must be at most {MAX_ELEMENTS} for modes, got {}",
                spec.elements_per_span
            ),
        ));
    }
    let (structure, _) = crate::physics::fe::viaduct::assemble(spec)?;
    let modes = crate::physics::fe::lowest_modes(&structure, count)?;
    Ok(modes
        .into_iter()
        .enumerate()
        .map(|(i, m)| Row {
            index: i + 1,
            frequency_hz: m.frequency_hz,
            kind: m.kind.as_str(),
        })
        .collect())
}

/// The lowest `count` modes of a viaduct and the first mode of every kind (axial, lateral,
/// vertical, torsion), each with its rank among the lowest modes.
///
/// Why more modes than asked: every span (and pier) contributes one mode to each family, so
/// the families come in clusters of about `spans + 1` nearly equal frequencies (35 axial
/// modes at 2.70 Hz for paper-5, then 36 lateral, …), and the first vertical and torsion
/// modes lie past the first clusters. Subspace iteration also converges only when its block
/// reaches past a cluster. So 4·(spans + 1) modes are computed: the four families.
fn viaduct_first_rows(spec: &crate::physics::fe::ViaductSpec, count: usize) -> Result<Vec<Row>> {
    let all = viaduct_rows(spec, count.max(4 * (spec.spans + 1)))?;
    let mut seen = Vec::new();
    Ok(all
        .into_iter()
        .filter(|r| {
            let first = !seen.contains(&r.kind);
            if first {
                seen.push(r.kind);
            }
            r.index <= count || first
        })
        .collect())
}

fn render_rows(format: Format, rows: &[Row]) -> Result<String> {
    Ok(match format {
        Format::Json => {
            serde_json::to_string_pretty(&rows).map_err(|e| Error::numerical(e.to_string()))? + "\n"
        }
        Format::Csv => {
            let mut s = String::from("index,frequency_hz,kind\n");
            for r in rows {
                s += &format!("{},{},{}\n", r.index, r.frequency_hz, r.kind);
            }
            s
        }
    })
}

/// Run the subcommand.
pub fn run(args: Args) -> Result<()> {
    crate::cli::stdout::print(&render(&args)?)
}
