//! `maglev stability --scenario S --speeds A:B:N [--plot FILE.svg]`: the speed envelope
//! (`crate::studies::stability::envelope`), its JSON on stdout and its figure: four panels
//! against speed (smallest gap, |V|/V_max, time saturated, body acceleration), the resonance
//! speeds `v = f·L/k` as vertical lines.

use crate::plot::{self, Plot, Series};
use crate::studies::stability::envelope::{Envelope, Resonance};
use crate::{Error, Result};
use std::path::Path;

/// `A:B:N`: N speeds evenly from A to B (m/s); `A` alone is one speed.
pub fn parse_speeds(spec: &str) -> Result<Vec<f64>> {
    let bad = || {
        Error::invalid(
            "--speeds",
            format!("expected A:B:N (m/s, N ≥ 2 speeds from A to B) or one speed, got {spec:?}"),
        )
    };
    let parts: Vec<&str> = spec.split(':').collect();
    let num = |s: &str| s.trim().parse::<f64>().ok().filter(|v| v.is_finite());
    match parts.as_slice() {
        [a] => Ok(vec![num(a).ok_or_else(bad)?]),
        [a, b, n] => {
            let (a, b) = (num(a).ok_or_else(bad)?, num(b).ok_or_else(bad)?);
            let n: usize = n.trim().parse().map_err(|_| bad())?;
            if !(2..=1000).contains(&n) || b <= a {
                return Err(Error::invalid(
                    "--speeds",
                    format!("needs A < B and 2 ≤ N ≤ 1000, got {spec:?}"),
                ));
            }
            Ok((0..n)
                .map(|i| a + (b - a) * i as f64 / (n - 1) as f64)
                .collect())
        }
        _ => Err(bad()),
    }
}

/// Vertical lines at the resonance speeds, spanning `[lo, hi]` of a panel.
fn resonance_lines(res: &[Resonance], lo: f64, hi: f64) -> Vec<Series> {
    res.iter()
        .map(|r| {
            Series::new(
                format!("v = f·L/k: {}", r.label),
                vec![r.speed_m_per_s; 2],
                vec![lo, hi],
            )
        })
        .collect()
}

/// The envelope's figure (SVG text).
pub fn figure(e: &Envelope) -> Result<String> {
    let v: Vec<f64> = e.points.iter().map(|p| p.speed_m_per_s).collect();
    let panel = |title: &str, ylabel: &str, y: Vec<f64>| {
        let finite = y.iter().copied().filter(|x| x.is_finite());
        let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
        let (lo, hi) = if lo.is_finite() { (lo, hi) } else { (0.0, 1.0) };
        let mut series = vec![Series::new(title, v.clone(), y)];
        series.extend(resonance_lines(&e.resonances, lo, hi));
        Plot::new(title, "speed (m/s)", ylabel, series).markers()
    };
    let nan = f64::NAN;
    let plots = [
        panel(
            "smallest levitation gap",
            "gap (mm)",
            e.points.iter().map(|p| p.gap_min_m * 1e3).collect(),
        ),
        panel(
            "largest |V| / V_max",
            "|V| / V_max",
            e.points
                .iter()
                .map(|p| p.voltage_ratio.unwrap_or(nan))
                .collect(),
        ),
        panel(
            "longest time at ±V_max",
            "saturated (s)",
            e.points
                .iter()
                .map(|p| p.saturated_s.unwrap_or(nan))
                .collect(),
        ),
        panel(
            "body peak vertical acceleration",
            "acceleration (m/s²)",
            e.points
                .iter()
                .map(|p| p.body_acceleration_m_per_s2)
                .collect(),
        ),
    ];
    plot::panels(&format!("speed envelope: {}", e.scenario), 2, &plots)
}

/// Runs the envelope of `name` with `sets` over `speeds`, prints its JSON and writes the
/// figure to `plot_path` (when given).
pub fn run(name: &str, sets: &[String], speeds: &str, plot_path: Option<&Path>) -> Result<()> {
    let speeds = parse_speeds(speeds)?;
    let base = crate::studies::design::load(name, sets)?;
    let e = crate::studies::stability::envelope::envelope(name, sets, &base, &speeds)?;
    if let Some(p) = plot_path {
        crate::output::staging::write_atomic(p, figure(&e)?.as_bytes())?;
    }
    crate::cli::stdout::print(
        &(serde_json::to_string_pretty(&e).map_err(|x| Error::numerical(x.to_string()))? + "\n"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn speeds_parse_and_bad_ones_name_the_flag() {
        assert_eq!(parse_speeds("10:30:3").unwrap(), [10.0, 20.0, 30.0]);
        assert_eq!(parse_speeds("50").unwrap(), [50.0]);
        for bad in ["", "a:b:c", "10:5:3", "1:2:1", "1:2", "1:2:3:4", "nan"] {
            let e = parse_speeds(bad).unwrap_err().to_string();
            assert!(e.contains("--speeds"), "{bad}: {e}");
        }
    }
}
