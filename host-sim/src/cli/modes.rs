//! `maglev modes`: natural frequencies of the §4.2 beam (one simply supported span of 25 m,
//! docs/model.md §9) from the FE model, as JSON or CSV on stdout.

use crate::fe::{natural_modes, SpanModel};
use crate::guideway::BeamSection;

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
    #[arg(long, value_name = "SPANS")]
    pub viaduct: Option<usize>,
}

#[derive(serde::Serialize)]
struct Row {
    index: usize,
    frequency_hz: f64,
    kind: &'static str,
}

/// The output text for `args`, or a one-line error.
pub fn render(args: &Args) -> Result<String, String> {
    if args.elements == 0 || args.elements > MAX_ELEMENTS {
        return Err(format!(
            "--elements must be between 1 and {MAX_ELEMENTS}, got {}",
            args.elements
        ));
    }
    if let Some(spans) = args.viaduct {
        return render_rows(args.format, &viaduct_rows(args, spans)?);
    }
    let model = SpanModel::new(&BeamSection::paper_4_2(), SPAN_LENGTH, args.elements)
        .map_err(|e| e.to_string())?;
    let dofs = model.free_dofs();
    if args.count == 0 || args.count > dofs {
        return Err(format!(
            "--count must be between 1 and {dofs} (free DOFs with {} elements), got {}",
            args.elements, args.count
        ));
    }
    let rows: Vec<Row> = natural_modes(&model)
        .map_err(|e| e.to_string())?
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

fn viaduct_rows(args: &Args, spans: usize) -> Result<Vec<Row>, String> {
    if spans == 0 || spans > MAX_SPANS {
        return Err(format!(
            "--viaduct must be between 1 and {MAX_SPANS} spans, got {spans}"
        ));
    }
    let mut spec = crate::fe::paper5_viaduct().with_spans(spans);
    spec.elements_per_span = args.elements;
    let (structure, _) = crate::fe::viaduct::assemble(&spec).map_err(|e| e.to_string())?;
    let modes = crate::fe::lowest_modes(&structure, args.count).map_err(|e| e.to_string())?;
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

fn render_rows(format: Format, rows: &[Row]) -> Result<String, String> {
    Ok(match format {
        Format::Json => serde_json::to_string_pretty(&rows).map_err(|e| e.to_string())? + "\n",
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
pub fn run(args: Args) -> Result<(), String> {
    print!("{}", render(&args)?);
    Ok(())
}
