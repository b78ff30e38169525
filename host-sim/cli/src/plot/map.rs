//! A plan-view colour map as SVG: one filled cell per grid point, a colour bar to its right
//! (the paper-5 report's map of peak surface velocity around the piers).
//!
//! Why in the plot module: every figure of the project follows its rules (fonts, titles,
//! errors); a map is one more kind of figure. Colours run linearly in the value from blue
//! (lowest) through green to red (highest); non-finite cells stay white.

use super::{failed, font, HEIGHT, LABEL_PX, TITLE_PX, WIDTH};
use crate::Result;
use plotters::prelude::*;

/// A grid of values `z[j][i]` at `(x[i], y[j])` (both ascending, uniformly spaced), in
/// display units.
pub struct Grid<'a> {
    pub x: &'a [f64],
    pub y: &'a [f64],
    pub z: &'a [Vec<f64>],
}

/// The colour of `t` in [0, 1]: hue from blue (0) to red (1).
fn colour(t: f64) -> RGBColor {
    let (r, g, b) = HSLColor((1.0 - t.clamp(0.0, 1.0)) * 240.0 / 360.0, 0.85, 0.5).rgb();
    RGBColor(r, g, b)
}

/// Half a grid step of `v` (1 for a single value).
fn half_step(v: &[f64]) -> f64 {
    if v.len() > 1 {
        0.5 * (v[1] - v[0])
    } else {
        1.0
    }
}

/// The map as SVG text; `zlabel` names the value and its unit; `marks` are points drawn as
/// black squares (the piers).
pub fn svg(
    title: &str,
    xlabel: &str,
    ylabel: &str,
    zlabel: &str,
    grid: &Grid,
    marks: &[(f64, f64)],
) -> Result<String> {
    let finite: Vec<f64> = grid
        .z
        .iter()
        .flatten()
        .copied()
        .filter(|v| v.is_finite())
        .collect();
    let lo = finite.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = finite.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let (lo, hi) = if lo.is_finite() && hi > lo {
        (lo, hi)
    } else {
        (0.0, 1.0)
    };
    let (hx, hy) = (half_step(grid.x), half_step(grid.y));
    let x0 = grid.x.first().copied().unwrap_or(0.0) - hx;
    let x1 = grid.x.last().copied().unwrap_or(0.0) + hx;
    let y0 = grid.y.first().copied().unwrap_or(0.0) - hy;
    let y1 = grid.y.last().copied().unwrap_or(0.0) + hy;
    let e = |e| failed(title, e);
    let mut s = String::new();
    {
        let root = SVGBackend::with_string(&mut s, (WIDTH, HEIGHT)).into_drawing_area();
        root.fill(&WHITE).map_err(e)?;
        let (left, right) = root.split_horizontally(WIDTH as i32 - 110);
        let mut chart = ChartBuilder::on(&left)
            .caption(title, font(TITLE_PX))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(55)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(e)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(xlabel)
            .y_desc(ylabel)
            .label_style(font(LABEL_PX))
            .axis_desc_style(font(LABEL_PX))
            .draw()
            .map_err(e)?;
        let cells = grid.y.iter().enumerate().flat_map(|(j, &y)| {
            grid.x.iter().enumerate().filter_map(move |(i, &x)| {
                let v = grid.z[j][i];
                v.is_finite().then(|| {
                    Rectangle::new(
                        [(x - hx, y - hy), (x + hx, y + hy)],
                        colour((v - lo) / (hi - lo)).filled(),
                    )
                })
            })
        });
        chart.draw_series(cells).map_err(e)?;
        let r = 0.6 * hx.min(hy);
        chart
            .draw_series(
                marks.iter().map(|&(x, y)| {
                    Rectangle::new([(x - r, y - r), (x + r, y + r)], BLACK.filled())
                }),
            )
            .map_err(e)?;
        let mut bar = ChartBuilder::on(&right)
            .margin_top(40)
            .margin_bottom(50)
            .margin_right(45)
            .y_label_area_size(0)
            .right_y_label_area_size(40)
            .caption(zlabel, font(LABEL_PX))
            .build_cartesian_2d(0.0..1.0, lo..hi)
            .map_err(e)?;
        bar.configure_mesh()
            .disable_mesh()
            .disable_x_axis()
            .label_style(font(LABEL_PX))
            .draw()
            .map_err(e)?;
        let n = 64;
        bar.draw_series((0..n).map(|k| {
            let a = lo + (hi - lo) * k as f64 / n as f64;
            let b = lo + (hi - lo) * (k + 1) as f64 / n as f64;
            Rectangle::new(
                [(0.0, a), (1.0, b)],
                colour((k as f64 + 0.5) / n as f64).filled(),
            )
        }))
        .map_err(e)?;
        root.present().map_err(e)?;
    }
    Ok(s)
}
