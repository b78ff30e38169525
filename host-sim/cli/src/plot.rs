//! Line plots as SVG text, on `plotters` and its SVG backend: the run's histories, the
//! validation figures, and whatever else wants a figure (sweeps).
//!
//! Why one module: every figure of the project follows the same rules, so they live in one
//! place. The legend stands in its own column to the right of the data area, so it never
//! covers a peak, and its box is sized from its text. Degenerate data (a constant history, a
//! single point, an empty or all-NaN series) still gives a valid figure: the ranges are padded
//! here before plotters sees them. Long histories are thinned per pixel column to their first,
//! lowest, highest and last points, so every peak survives. Non-finite values break a curve
//! instead of being joined across. The first series (the reference, as a rule) is a broad
//! translucent band and the others opaque lines on top, so a curve that lies on the reference
//! stays visible inside it. A plot may ask for a logarithmic x axis (ticks at 1, 2, 5 × 10ⁿ,
//! labelled in the data's units) and for a marker at every point. Text is left to the SVG
//! viewer's fonts (`<text>` elements): plotters is built without its font features, so neither
//! the build nor the run needs a system font library; box widths are estimated from the
//! character count.
//!
//! The API: [`lines`] for one plot, [`panels`] for several plots in a grid as one SVG, both
//! over [`Plot`]s of [`Series`]. Callers convert to display units (mm, kN) and say so in the
//! axis label.
//!
//! ```
//! use maglev::plot::{self, Plot, Series};
//! let t = vec![0.0, 0.1, 0.2];
//! let svg = plot::lines("a title", "t (s)", "z (mm)", &[Series::new("fe", t, vec![0.0, -1.5, 0.3])])?;
//! assert!(svg.starts_with("<svg"));
//! let grid = plot::panels("two plots", 2, &[
//!     Plot::new("left", "t (s)", "z (mm)", vec![Series::new("a", vec![0.0, 1.0], vec![1.0, 2.0])]),
//!     Plot::new("right", "t (s)", "gap − h0 (mm)", vec![]).zero_line(),
//! ])?;
//! assert!(grid.contains("left") && grid.contains("right"));
//! # Ok::<(), maglev_sim::Error>(())
//! ```

use crate::{Error, Result};
use plotters::coord::ranged1d::{KeyPointHint, NoDefaultFormatting, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// One curve: points `(x[k], y[k])`, in display units.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    pub label: String,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
}

impl Series {
    pub fn new(label: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        Series {
            label: label.into(),
            x,
            y,
        }
    }
}

/// One plot: a title, axis labels (with their units) and curves.
#[derive(Debug, Clone, PartialEq)]
pub struct Plot {
    pub title: String,
    pub xlabel: String,
    pub ylabel: String,
    pub series: Vec<Series>,
    /// Draw the line y = 0 (and keep it in range): for deviations such as gap − h0.
    pub zero_line: bool,
    /// A logarithmic x axis (positive x only; ticks at 1, 2, 5 × 10ⁿ, labelled with x).
    pub log_x: bool,
    /// A marker at every point (for a few points, such as one per sweep run).
    pub markers: bool,
}

impl Plot {
    pub fn new(
        title: impl Into<String>,
        xlabel: impl Into<String>,
        ylabel: impl Into<String>,
        series: Vec<Series>,
    ) -> Self {
        Plot {
            title: title.into(),
            xlabel: xlabel.into(),
            ylabel: ylabel.into(),
            series,
            zero_line: false,
            log_x: false,
            markers: false,
        }
    }

    /// The same plot with a zero line.
    pub fn zero_line(mut self) -> Self {
        self.zero_line = true;
        self
    }

    /// The same plot on a logarithmic x axis.
    pub fn log_x(mut self) -> Self {
        self.log_x = true;
        self
    }

    /// The same plot with a marker at every point.
    pub fn markers(mut self) -> Self {
        self.markers = true;
        self
    }
}

/// One plot's size in pixels (a panel of [`panels`] has this size too).
pub const WIDTH: u32 = 760;
pub const HEIGHT: u32 = 380;

/// An SVG line plot of `series` (the one-plot case of [`panels`]).
pub fn lines(title: &str, xlabel: &str, ylabel: &str, series: &[Series]) -> Result<String> {
    svg(&Plot::new(title, xlabel, ylabel, series.to_vec()))
}

/// One plot as SVG text.
pub fn svg(plot: &Plot) -> Result<String> {
    let mut s = String::new();
    {
        let root = SVGBackend::with_string(&mut s, (WIDTH, HEIGHT)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| failed(&plot.title, e))?;
        draw(&root, plot, TITLE_PX).map_err(|e| failed(&plot.title, e))?;
        root.present().map_err(|e| failed(&plot.title, e))?;
    }
    Ok(s)
}

/// Several plots in a grid of `cols` columns under a common `title`, as one SVG (Fig. 2's four
/// panels). Each panel has the size of a single plot and its own legend.
pub fn panels(title: &str, cols: usize, plots: &[Plot]) -> Result<String> {
    if cols == 0 {
        return Err(Error::invalid("plot columns", "must be ≥ 1, got 0"));
    }
    let rows = plots.len().div_ceil(cols).max(1);
    let lines = wrap(title, WIDTH as f64 * cols as f64 - 20.0, FIGURE_TITLE_PX);
    let head = title_height(lines.len(), FIGURE_TITLE_PX);
    let (w, h) = (WIDTH * cols as u32, HEIGHT * rows as u32 + head as u32);
    let mut s = String::new();
    {
        let root = SVGBackend::with_string(&mut s, (w, h)).into_drawing_area();
        let e = |e| failed(title, e);
        root.fill(&WHITE).map_err(e)?;
        let body = draw_title(&root, &lines, FIGURE_TITLE_PX).map_err(e)?;
        for (cell, plot) in body.split_evenly((rows, cols)).iter().zip(plots) {
            draw(cell, plot, TITLE_PX).map_err(|e| failed(&plot.title, e))?;
        }
        root.present().map_err(e)?;
    }
    Ok(s)
}

/// A run's `--set` overrides as a title suffix, ` [--set a=1, b=2]` (empty without any).
pub fn overrides(sets: &[String]) -> String {
    if sets.is_empty() {
        String::new()
    } else {
        format!(" [--set {}]", sets.join(", "))
    }
}

/// Font sizes in SVG pixels.
const TITLE_PX: f64 = 14.0;
const FIGURE_TITLE_PX: f64 = 17.0;
const LABEL_PX: f64 = 12.0;
/// plotters writes `font-size = size / 1.24` into the SVG; this undoes it.
const PLOTTERS_FONT_SCALE: f64 = 1.24;
/// An upper estimate of a sans-serif glyph's advance, in em: DejaVu Sans, the usual fallback,
/// averages about 0.55 em over mixed text, its widest common glyphs (m, W) near 1.
const EM_PER_CHAR: f64 = 0.62;

/// The zero line's colour (the axes are black).
const ZERO_LINE: RGBColor = RGBColor(0x44, 0x44, 0x44);

const COLOURS: [RGBColor; 6] = [
    RGBColor(0x1f, 0x77, 0xb4),
    RGBColor(0xd6, 0x27, 0x28),
    RGBColor(0x2c, 0xa0, 0x2c),
    RGBColor(0xff, 0x7f, 0x0e),
    RGBColor(0x94, 0x67, 0xbd),
    RGBColor(0x8c, 0x56, 0x4b),
];

fn failed(title: &str, e: impl std::fmt::Display) -> Error {
    Error::numerical(format!("plot `{title}`: {e}"))
}

fn font(px: f64) -> TextStyle<'static> {
    ("sans-serif", px * PLOTTERS_FONT_SCALE)
        .into_font()
        .color(&BLACK)
}

/// Estimated width of `text` in pixels at `px`.
fn text_width(text: &str, px: f64) -> f64 {
    text.chars().count() as f64 * EM_PER_CHAR * px
}

/// `text` broken at spaces into lines no wider than `width` (a word longer than that stands
/// alone on its line).
fn wrap(text: &str, width: f64, px: f64) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for word in text.split(' ') {
        match out.last_mut() {
            Some(line) if text_width(&format!("{line} {word}"), px) <= width => {
                line.push(' ');
                line.push_str(word);
            }
            _ => out.push(word.to_string()),
        }
    }
    out
}

fn title_height(lines: usize, px: f64) -> f64 {
    (lines as f64 * 1.25 * px + 8.0).ceil()
}

/// Draws title lines centred at the top of `area`; returns the area below them.
fn draw_title<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    lines: &[String],
    px: f64,
) -> std::result::Result<DrawingArea<DB, Shift>, DrawingAreaErrorKind<DB::ErrorType>> {
    let (w, _) = area.dim_in_pixel();
    let style = font(px).pos(Pos::new(HPos::Center, VPos::Top));
    for (k, line) in lines.iter().enumerate() {
        let y = 4.0 + k as f64 * 1.25 * px;
        area.draw(&Text::new(line.as_str(), (w as i32 / 2, y as i32), &style))?;
    }
    Ok(area
        .split_vertically(title_height(lines.len(), px) as i32)
        .1)
}

/// Pixel rectangles of one drawn plot, in the coordinates of the SVG: `(x0, y0, x1, y1)`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Layout {
    plotting: (i32, i32, i32, i32),
    legend: Option<(i32, i32, i32, i32)>,
}

/// Points of a series that a plot `px` pixels wide shows: for each pixel column, the first,
/// lowest, highest and last points in their order. Short series are kept whole.
fn thin(points: &[(f64, f64)], x0: f64, x1: f64, px: usize) -> Vec<(f64, f64)> {
    if points.len() <= 4 * px || x1 <= x0 {
        return points.to_vec();
    }
    let column = |x: f64| (((x - x0) / (x1 - x0) * px as f64) as i64).clamp(0, px as i64);
    let mut out = Vec::with_capacity(4 * px + 4);
    let mut k = 0;
    while k < points.len() {
        let c = column(points[k].0);
        let mut end = k + 1;
        while end < points.len() && column(points[end].0) == c {
            end += 1;
        }
        let run = &points[k..end];
        let lo = (0..run.len())
            .min_by(|&a, &b| run[a].1.total_cmp(&run[b].1))
            .unwrap_or(0);
        let hi = (0..run.len())
            .max_by(|&a, &b| run[a].1.total_cmp(&run[b].1))
            .unwrap_or(0);
        let mut keep = [0, lo, hi, run.len() - 1];
        keep.sort_unstable();
        for (i, &j) in keep.iter().enumerate() {
            if i == 0 || j != keep[i - 1] {
                out.push(run[j]);
            }
        }
        k = end;
    }
    out
}

/// The finite stretches of a series (a non-finite x or y ends a stretch), x mapped by `fx`
/// (log10 on a logarithmic axis, where x ≤ 0 is non-finite).
fn stretches(s: &Series, fx: fn(f64) -> f64) -> Vec<Vec<(f64, f64)>> {
    let mut out = vec![Vec::new()];
    for (x, &y) in s.x.iter().map(|&x| fx(x)).zip(&s.y) {
        if x.is_finite() && y.is_finite() {
            out.last_mut().expect("never empty").push((x, y));
        } else if !out.last().expect("never empty").is_empty() {
            out.push(Vec::new());
        }
    }
    out.retain(|v| !v.is_empty());
    out
}

/// `[lo, hi]` widened when empty or flat, so every range has a positive width.
fn widen(lo: f64, hi: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    let scale = lo.abs().max(hi.abs());
    if hi - lo <= 1e-9 * scale || hi - lo <= f64::MIN_POSITIVE {
        let pad = if scale > 0.0 { 0.1 * scale } else { 1.0 };
        return (lo - pad, hi + pad);
    }
    (lo, hi)
}

/// Tick labels for a range of width `span`: enough decimals to tell ticks apart, exponents
/// for very large or very small magnitudes.
fn tick_label(v: f64, span: f64, magnitude: f64) -> String {
    if v.abs() < 1e-9 * span {
        return "0".into();
    }
    if !(1e-3..1e5).contains(&magnitude) {
        return format!("{v:.2e}");
    }
    let step = span / 8.0;
    let decimals = (-step.log10().floor()).clamp(0.0, 8.0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    plot: &Plot,
    title_px: f64,
) -> std::result::Result<Layout, DrawingAreaErrorKind<DB::ErrorType>> {
    let (w, _) = area.dim_in_pixel();
    let lines = wrap(&plot.title, w as f64 - 20.0, title_px);
    let body = draw_title(area, &lines, title_px)?;
    // The legend column: swatch, gap, the longest label, padding.
    let legend_w = if plot.series.is_empty() {
        0
    } else {
        let text = plot
            .series
            .iter()
            .map(|s| text_width(&s.label, LABEL_PX))
            .fold(0.0, f64::max);
        (text + 24.0 + 6.0 + 2.0 * 8.0).ceil() as i32 + 10
    };
    let (chart_area, legend_area) = body.split_horizontally(w as i32 - legend_w);

    let fx: fn(f64) -> f64 = if plot.log_x {
        |x| if x > 0.0 { x.log10() } else { f64::NAN }
    } else {
        |x| x
    };
    let segments: Vec<Vec<Vec<(f64, f64)>>> =
        plot.series.iter().map(|s| stretches(s, fx)).collect();
    let all = || segments.iter().flatten().flatten();
    let (x0, x1) = widen(
        all().map(|p| p.0).fold(f64::INFINITY, f64::min),
        all().map(|p| p.0).fold(f64::NEG_INFINITY, f64::max),
    );
    let (mut ylo, mut yhi) = (
        all().map(|p| p.1).fold(f64::INFINITY, f64::min),
        all().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max),
    );
    if plot.zero_line {
        (ylo, yhi) = (ylo.min(0.0), yhi.max(0.0));
    }
    let (ylo, yhi) = widen(ylo, yhi);
    let pad = 0.05 * (yhi - ylo);
    let (y0, y1) = (ylo - pad, yhi + pad);

    let builder = || {
        let mut b = ChartBuilder::on(&chart_area);
        b.margin_top(6)
            .margin_right(12)
            .margin_left(6)
            .x_label_area_size(42)
            .y_label_area_size(70);
        b
    };
    let (px_x, px_y) = if plot.log_x {
        let axis = Log10Axis::new(x0, x1);
        draw_data(
            builder().build_cartesian_2d(axis, y0..y1)?,
            plot,
            &segments,
            (y0, y1),
        )?
    } else {
        let chart = builder().build_cartesian_2d(x0..x1, y0..y1)?;
        draw_data(chart, plot, &segments, (y0, y1))?
    };
    let plotting = (px_x.start, px_y.start, px_x.end, px_y.end);
    if plot.series.is_empty() {
        return Ok(Layout {
            plotting,
            legend: None,
        });
    }
    // The legend: its own column, top-aligned with the data area.
    let (lx, ly) = legend_area.get_base_pixel();
    let row = (1.6 * LABEL_PX).round() as i32;
    let top = px_y.start - ly;
    let rect = (
        0,
        top,
        legend_w - 10,
        top + row * plot.series.len() as i32 + 8,
    );
    legend_area.draw(&Rectangle::new(
        [(rect.0, rect.1), (rect.2, rect.3)],
        RGBColor(0xaa, 0xaa, 0xaa).stroke_width(1),
    ))?;
    for (i, s) in plot.series.iter().enumerate() {
        let y = top + 4 + row * i as i32 + row / 2;
        legend_area.draw(&PathElement::new(vec![(8, y), (32, y)], style(i)))?;
        if plot.markers {
            draw_markers(&legend_area, i, &[(20, y)])?;
        }
        legend_area.draw(&Text::new(
            s.label.as_str(),
            (38, y),
            font(LABEL_PX).pos(Pos::new(HPos::Left, VPos::Center)),
        ))?;
    }
    Ok(Layout {
        plotting,
        legend: Some((rect.0 + lx, rect.1 + ly, rect.2 + lx, rect.3 + ly)),
    })
}

/// The data area's x and y pixel ranges.
type PixelRanges = (std::ops::Range<i32>, std::ops::Range<i32>);

/// The mesh, the zero line and the curves of `plot` on `chart` (x in log10 units on a
/// logarithmic axis); returns the data area's pixel ranges.
fn draw_data<'a, DB, X>(
    mut chart: ChartContext<'a, DB, Cartesian2d<X, RangedCoordf64>>,
    plot: &Plot,
    segments: &[Vec<Vec<(f64, f64)>>],
    (y0, y1): (f64, f64),
) -> std::result::Result<PixelRanges, DrawingAreaErrorKind<DB::ErrorType>>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let range = chart.x_range();
    let (x0, x1) = (range.start, range.end);
    let xmag = x0.abs().max(x1.abs());
    let ymag = y0.abs().max(y1.abs());
    let xfmt = |v: &f64| {
        if plot.log_x {
            decimal(10f64.powf(*v))
        } else {
            tick_label(*v, x1 - x0, xmag)
        }
    };
    let yfmt = |v: &f64| tick_label(*v, y1 - y0, ymag);
    chart
        .configure_mesh()
        .x_labels(8)
        .y_labels(7)
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(0xdd, 0xdd, 0xdd))
        .x_label_formatter(&xfmt)
        .y_label_formatter(&yfmt)
        .label_style(font(LABEL_PX))
        .axis_desc_style(font(LABEL_PX))
        .x_desc(plot.xlabel.as_str())
        .y_desc(plot.ylabel.as_str())
        .draw()?;
    if plot.zero_line {
        chart.draw_series(std::iter::once(PathElement::new(
            vec![(x0, 0.0), (x1, 0.0)],
            ZERO_LINE.stroke_width(1),
        )))?;
    }
    let (px_x, px_y) = chart.plotting_area().get_pixel_range();
    let columns = (px_x.end - px_x.start).max(1) as usize;
    for (i, segs) in segments.iter().enumerate() {
        for seg in segs {
            let points = thin(seg, x0, x1, columns);
            chart.draw_series(std::iter::once(PathElement::new(points.clone(), style(i))))?;
            if plot.markers {
                draw_markers(chart.plotting_area(), i, &points)?;
            }
        }
    }
    Ok((px_x, px_y))
}

/// Series `i`'s line: the first (the reference, as a rule) a broad translucent band, the
/// others opaque lines on top, so that a curve lying on the reference shows inside its band
/// and one leaving it shows beside it.
fn style(i: usize) -> ShapeStyle {
    let colour = COLOURS[i % COLOURS.len()];
    if i == 0 {
        colour.mix(0.45).stroke_width(6)
    } else {
        colour.stroke_width(2)
    }
}

/// Series `i`'s point markers at `points` of `area`: filled circles (series 0) or open
/// squares (the others), so that coinciding points of two series both show.
fn draw_markers<DB, CT, C>(
    area: &DrawingArea<DB, CT>,
    i: usize,
    points: &[C],
) -> std::result::Result<(), DrawingAreaErrorKind<DB::ErrorType>>
where
    DB: DrawingBackend,
    CT: CoordTranslate<From = C>,
    C: Clone,
{
    let colour = COLOURS[i % COLOURS.len()];
    for p in points {
        let at = EmptyElement::at(p.clone());
        if i == 0 {
            area.draw(&(at + Circle::new((0, 0), 4, colour.filled())))?;
        } else {
            area.draw(&(at + Rectangle::new([(-4, -4), (4, 4)], colour.stroke_width(2))))?;
        }
    }
    Ok(())
}

/// A logarithmic x axis: linear in log10(x) over `[x0, x1]` (log10 units), its ticks the
/// 1, 2, 5 × 10ⁿ inside the range (plotters' own logarithmic axis labels decades only, or
/// every 1…9 × 10ⁿ).
struct Log10Axis {
    inner: RangedCoordf64,
    ticks: Vec<f64>,
}

impl Log10Axis {
    fn new(x0: f64, x1: f64) -> Self {
        let (lo, hi) = (x0.floor() as i32, x1.ceil() as i32);
        let ticks = (lo..=hi)
            .flat_map(|e| [1.0f64, 2.0, 5.0].map(|m| m.log10() + f64::from(e)))
            .filter(|v| (x0..=x1).contains(v))
            .collect();
        Log10Axis {
            inner: (x0..x1).into(),
            ticks,
        }
    }
}

impl Ranged for Log10Axis {
    type FormatOption = NoDefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        self.inner.map(value, limit)
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            Vec::new()
        } else {
            self.ticks.clone()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.inner.range()
    }
}

impl ValueFormatter<f64> for Log10Axis {
    fn format_ext(&self, value: &f64) -> String {
        decimal(10f64.powf(*value))
    }
}

/// A logarithmic axis' tick label: `v` as a plain decimal with its significant digits only
/// (0.5, 1, 20, 200).
fn decimal(v: f64) -> String {
    let digits = (2.0 - v.log10().floor()).clamp(0.0, 12.0) as usize;
    let s = format!("{v:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

pub mod map;

#[cfg(test)]
mod tests;
