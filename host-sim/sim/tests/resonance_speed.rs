//! Resonance and cancellation speeds of a train of equally spaced loads (issue #10, "the
//! train's resonance speeds v = f·d/k against a speed sweep"; docs/resonance.md).
//!
//! A train of N identical loads at spacing d crossing a simply supported span of first
//! frequency f leaves the span vibrating freely. In the first mode each load leaves the same
//! residual vibration, delayed by the passing period T = d/v, so the train's residual
//! amplitude is the single load's times the array factor |sin(Nπ f T)/sin(π f T)|, which
//! peaks (at N) where f T = k: the resonance speeds v_k = f·d/k. The single load's residual,
//! for a load on the span for τ = L/v, is (first mode, undamped; derived in docs/resonance.md)
//!
//! ```text
//! A₁ = 2 (P_1/ω²) (Ω/ω)/(1 − (Ω/ω)²) · |cos(ω τ/2)|,   Ω = π v/L,
//! ```
//!
//! zero where ω τ/2 = (2i + 1) π/2, i.e. at the cancellation speeds v = 2 f L/(2i + 1).
//!
//! f comes from the closed form, never from the sweep: the lowest root of the simply
//! supported Timoshenko beam's frequency equation (shear and rotary inertia, the FE element's
//! physics) from the scenario's section values.

use maglev_sim::input::case::Case;
use maglev_sim::physics::guideway::BeamSection;
use maglev_sim::probes::Rows;
use maglev_sim::setup::simulate;
use maglev_sim::simulation::magnets::CoreMagnets;

/// Span (m) and load spacing (m): L = d puts every resonance T_k = k/f where the single
/// load's factor |cos(ω L/(2v))| = |cos(k π)| is 1 and stationary, so it does not pull the
/// train's peak aside (docs/resonance.md).
const L: f64 = 25.0;
const D: f64 = 25.0;
const CARS: usize = 12;
const DT: f64 = 1e-3;
/// Free vibration recorded after the last load has left the span (s): longer than one
/// period of the first mode (0.163 s), so its maximum |z| is the amplitude.
const TAIL: f64 = 0.25;

/// First vertical bending frequency (Hz) of a simply supported Timoshenko beam: with
/// w = W sin(kx), ψ = Ψ cos(kx), k = π/L, the equations
/// κGA(w'' − ψ') = ρA ẅ and EI ψ'' + κGA(w' − ψ) = ρI ψ̈ give
/// (ρA ω² − κGA k²)(ρI ω² − EI k² − κGA) − (κGA k)² = 0, a quadratic in ω²; its lower root
/// is the bending mode. ρI = (mass per length / A)·I (a solid section's rotary inertia).
fn timoshenko_f1(s: &BeamSection, l: f64) -> f64 {
    let k = std::f64::consts::PI / l;
    let (ra, ei, kga) = (
        s.mass_per_length,
        s.youngs_modulus * s.iy,
        s.shear_modulus * s.shear_area_z,
    );
    let ri = s.mass_per_length / s.area * s.iy;
    let a = ra * ri;
    let b = -(ra * (ei * k * k + kga) + kga * k * k * ri);
    let c = kga * k * k * (ei * k * k + kga) - (kga * k).powi(2);
    let w2 = (-b - (b * b - 4.0 * a * c).sqrt()) / (2.0 * a);
    w2.sqrt() / (2.0 * std::f64::consts::PI)
}

fn case(speed: f64, repeat: usize) -> Case {
    let exit = (L + (repeat - 1) as f64 * D) / speed;
    let sets = [
        format!("bridge.spans_m=[{L:?}]"),
        "elements=8".into(),
        format!("dt={DT:?}"),
        format!("t_end={:?}", exit + TAIL),
        "train.loads_kN=[100.0]".into(),
        "train.offsets_m=[0.0]".into(),
        format!("train.repeat={repeat}"),
        format!("train.car_length_m={D:?}"),
        r#"output.probes=["span1.midspan.z"]"#.into(),
        format!("speed={speed:?}"),
    ];
    Case::load("train-forces", &sets).unwrap()
}

/// The midspan's free-vibration amplitude after the last of `repeat` loads has left the span
/// at `speed`: max |z| over the steps after the exit.
fn residual(speed: f64, repeat: usize) -> f64 {
    let c = case(speed, repeat);
    let exit = (L + (repeat - 1) as f64 * D) / speed;
    let mut rows = Rows::new(c.probes.clone());
    let run = simulate(&c, &mut CoreMagnets::new(), &mut rows, &mut ()).unwrap();
    assert_eq!(run.outcome.unconverged_steps, 0);
    let z = rows.column("span1.midspan.z").unwrap();
    z.iter()
        .enumerate()
        .filter(|(i, _)| *i as f64 * DT > exit + DT)
        .map(|(_, z)| z.abs())
        .fold(0.0, f64::max)
}

/// Indices of the interior points of `a` that are strictly beyond both neighbours (`better`
/// says which way) and the best of all points whose abscissa lies within `window` of theirs.
fn extrema(x: &[f64], a: &[f64], window: f64, better: impl Fn(f64, f64) -> bool) -> Vec<usize> {
    (1..a.len() - 1)
        .filter(|&i| better(a[i], a[i - 1]) && better(a[i], a[i + 1]))
        .filter(|&i| {
            (0..a.len())
                .filter(|&j| j != i && (x[j] - x[i]).abs() <= window)
                .all(|j| better(a[i], a[j]))
        })
        .collect()
}

/// 12 loads at d = 25 m over the 25 m §4.2 span, passing periods T = d/v from 0.120 to
/// 0.560 s in steps of ΔT = 1 ms (v = 208 … 44.6 m/s): the sharp peaks of the residual
/// amplitude sit at T_k = k/f, k = 1, 2, 3.
///
/// Tolerance, fixed before the run: |T_peak − k/f| ≤ ΔT + 0.005·k/f.
/// - ΔT: the main lobe is unimodal and about 2/(N f) = 27 ms wide at its base, 27 samples;
///   the grid's maximum is one of the two samples around the true maximum, within ΔT of it.
/// - 0.5 %: where the sampled function's maximum departs from k/f. The first-mode closed form
///   above (the array factor times A₁, evaluated offline in docs/resonance.md) puts the
///   maximum at +0.35 % of v_1, +0.06 % of v_2, +0.02 % of v_3 (A₁'s (Ω/ω)/(1 − (Ω/ω)²)
///   slope; its |cos| factor is stationary there because L = d); the average-acceleration
///   Newmark scheme lengthens the period by (ωΔt)²/12 = 1.2e-4 and the 8-element span's
///   first frequency is 2e-4 above the closed form (`maglev modes`).
///
/// "Sharp peak": a local maximum that is the largest within ±0.1 s of T, which is less than
/// the 1/f = 0.163 s between two resonances and more than the main lobe's half-width, so
/// the array factor's side lobes (at most ≈ 0.22 N) are not counted.
#[test]
fn resonance_speeds_of_a_train_are_f_d_over_k() {
    let c = case(100.0, CARS);
    let f = timoshenko_f1(&c.bridge.section, L);
    let ei = c.bridge.section.youngs_modulus * c.bridge.section.iy;
    let f_eb =
        std::f64::consts::PI / (2.0 * L * L) * (ei / c.bridge.section.mass_per_length).sqrt();
    println!("f1: Timoshenko {f:.6} Hz (Euler–Bernoulli {f_eb:.6} Hz)");
    // The §4.2 beam's published first frequency (docs/model.md §9, docs/sweeps.md: 6.13 Hz).
    assert!((f - 6.13).abs() < 0.01, "{f}");

    let dt_pass = 1e-3;
    let periods: Vec<f64> = (0..=440).map(|i| 0.120 + dt_pass * i as f64).collect();
    let amps: Vec<f64> = periods.iter().map(|t| residual(D / t, CARS)).collect();
    let peaks = extrema(&periods, &amps, 0.1, |a, b| a > b);
    println!("k | f·d/k (m/s) | sweep peak (m/s) | T_k = k/f (s) | T_peak (s) | amplitude (m)");
    for &i in &peaks {
        let k = (f * periods[i]).round();
        println!(
            "{k} | {:.3} | {:.3} | {:.5} | {:.3} | {:.4e}",
            f * D / k,
            D / periods[i],
            k / f,
            periods[i],
            amps[i]
        );
    }
    assert_eq!(peaks.len(), 3, "{peaks:?}");
    for (k, &i) in (1..=3).zip(&peaks) {
        let t_k = k as f64 / f;
        let tol = dt_pass + 0.005 * t_k;
        assert!(
            (periods[i] - t_k).abs() <= tol,
            "k = {k}: T_peak {} s, k/f {t_k} s, tolerance {tol} s",
            periods[i]
        );
    }
    // Resonance amplifies: each peak is the train's N loads nearly in phase, several times
    // the amplitude midway between two resonances (where the array factor is about 1).
    for w in peaks.windows(2) {
        let mid = (periods[w[0]] + periods[w[1]]) / 2.0;
        let j = (0..periods.len())
            .min_by(|&a, &b| {
                (periods[a] - mid)
                    .abs()
                    .total_cmp(&(periods[b] - mid).abs())
            })
            .unwrap();
        assert!(amps[w[1]] > 3.0 * amps[j], "{} vs {}", amps[w[1]], amps[j]);
    }
}

/// One load over the same span: its residual free vibration vanishes at the cancellation
/// speeds v = 2 f L/(2i + 1), i.e. after τ = L/v = (i + ½)/f on the span. Times on the span
/// τ = 0.200 … 0.600 s in steps of 1 ms (v = 125 … 41.7 m/s) contain i = 1, 2, 3.
///
/// Tolerance, fixed before the run: |τ_min − (i + ½)/f| ≤ Δτ + 0.001·τ. A₁'s zero is a
/// V-shaped minimum (|cos|), so the grid's minimum is within Δτ of it; the higher modes add
/// a residual that does not vanish there but varies slowly in τ and leaves the minimum in
/// place; Newmark and the FE shift f by ≤ 3e-4.
/// "Cancellation": a local minimum that is the smallest within ±0.05 s of τ (the zeros are
/// 1/f = 0.163 s apart).
#[test]
fn a_single_load_leaves_no_free_vibration_at_the_cancellation_speeds() {
    let c = case(100.0, 1);
    let f = timoshenko_f1(&c.bridge.section, L);
    let step = 1e-3;
    let taus: Vec<f64> = (0..=400).map(|i| 0.200 + step * i as f64).collect();
    let amps: Vec<f64> = taus.iter().map(|t| residual(L / t, 1)).collect();
    let largest = amps.iter().cloned().fold(0.0, f64::max);
    let minima = extrema(&taus, &amps, 0.05, |a, b| a < b);
    println!("i | 2fL/(2i+1) (m/s) | sweep minimum (m/s) | amplitude / largest");
    for &j in &minima {
        let i = (f * taus[j] - 0.5).round();
        println!(
            "{i} | {:.3} | {:.3} | {:.2e}",
            2.0 * f * L / (2.0 * i + 1.0),
            L / taus[j],
            amps[j] / largest
        );
    }
    assert_eq!(minima.len(), 3, "{minima:?}");
    for (i, &j) in (1..=3).zip(&minima) {
        let tau_i = (i as f64 + 0.5) / f;
        let tol = step + 0.001 * tau_i;
        assert!(
            (taus[j] - tau_i).abs() <= tol,
            "i = {i}: τ_min {} s, (i + ½)/f {tau_i} s, tolerance {tol} s",
            taus[j]
        );
        // A cancellation, not a shallow dip: far below the largest residual of the sweep.
        assert!(amps[j] < 0.05 * largest, "{} vs {largest}", amps[j]);
    }
}
