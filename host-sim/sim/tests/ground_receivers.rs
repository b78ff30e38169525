//! Receivers (`maglev_sim::ground::receivers`): superposition over piers, the arrival
//! of a pulse at the Rayleigh speed (from the Rayleigh cubic solved here), and padding that
//! lets nothing wrap around (docs/ground.md).

use maglev_sim::ground::green::Green;
use maglev_sim::ground::receivers::{padded_length, velocities};
use maglev_sim::physics::fe::soil::Soil;
use rustfft::num_complex::Complex64 as C;
use rustfft::FftPlanner;

const SOIL: Soil = Soil {
    shear_wave_velocity: 250.0,
    density: 1900.0,
    poisson: 0.25,
    damping: 0.01,
};
const DT: f64 = 0.004;

/// A smooth force pulse (N, down): Gaussian of width `sigma` centred at `t0`.
fn pulse(n: usize, t0: f64, sigma: f64, amp: f64) -> Vec<f64> {
    (0..n)
        .map(|j| amp * (-0.5 * ((j as f64 * DT - t0) / sigma).powi(2)).exp())
        .collect()
}

fn padded(n: usize, piers: &[[f64; 2]], receivers: &[[f64; 2]]) -> usize {
    let g = Green::new(SOIL.poisson, SOIL.damping).unwrap();
    let r_max = receivers
        .iter()
        .flat_map(|q| piers.iter().map(move |p| (p[0] - q[0]).hypot(p[1] - q[1])))
        .fold(0.0, f64::max);
    padded_length(n, DT, r_max, &SOIL, &g).unwrap()
}

/// Two piers with different forces give, at every receiver, the sum of each pier alone
/// (each alone computed as a one-pier layout).
#[test]
fn two_piers_give_the_sum_of_each_alone() {
    let n = 400;
    let piers = [[0.0, 0.0], [30.0, 0.0]];
    let receivers = [[15.0, 20.0], [40.0, -35.0], [-10.0, 60.0]];
    let f0 = pulse(n, 0.3, 0.02, 1e5);
    let f1: Vec<f64> = pulse(n, 0.5, 0.05, -4e4)
        .iter()
        .enumerate()
        .map(|(j, v)| v + 2e4 * (j as f64 * DT * 7.0).sin())
        .collect();
    let m = padded(n, &piers, &receivers);
    let both = velocities(&SOIL, DT, &[f0.clone(), f1.clone()], &piers, &receivers, m).unwrap();
    let a = velocities(&SOIL, DT, &[f0], &piers[..1], &receivers, m).unwrap();
    let b = velocities(&SOIL, DT, &[f1], &piers[1..], &receivers, m).unwrap();
    for r in 0..receivers.len() {
        let peak = both[r].iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        assert!(peak > 0.0);
        for j in 0..n {
            let d = (both[r][j] - a[r][j] - b[r][j]).abs();
            assert!(
                d <= 1e-12 * peak,
                "receiver {r} sample {j}: {d:e} of {peak:e}"
            );
        }
        // Each pier matters at each receiver.
        let pa = a[r].iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let pb = b[r].iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        assert!(pa > 1e-3 * peak && pb > 1e-3 * peak);
    }
}

/// (c_R/c_s)²: the root in (0, 1) of η³ − 8η² + (24 − 16γ²)η − 16(1 − γ²), by bisection.
fn rayleigh_eta(nu: f64) -> f64 {
    let g2 = (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu));
    let p = |e: f64| e * e * e - 8.0 * e * e + (24.0 - 16.0 * g2) * e - 16.0 * (1.0 - g2);
    let (mut lo, mut hi) = (1e-9, 1.0 - 1e-12);
    for _ in 0..200 {
        let m = 0.5 * (lo + hi);
        if p(m) < 0.0 {
            lo = m;
        } else {
            hi = m;
        }
    }
    0.5 * (lo + hi)
}

/// The envelope |analytic signal| of `v` (FFT Hilbert transform, written here).
fn envelope(v: &[f64]) -> Vec<f64> {
    let n = v.len();
    let mut planner = FftPlanner::<f64>::new();
    let mut s: Vec<C> = v.iter().map(|&x| C::new(x, 0.0)).collect();
    planner.plan_fft_forward(n).process(&mut s);
    for (k, x) in s.iter_mut().enumerate() {
        if k == 0 || (n.is_multiple_of(2) && k == n / 2) {
            continue;
        }
        *x *= if k < n.div_ceil(2) { 2.0 } else { 0.0 };
    }
    planner.plan_fft_inverse(n).process(&mut s);
    s.iter().map(|x| x.norm() / n as f64).collect()
}

/// A force pulse at one pier reaches a receiver 150 m away at t0 + r/c_R: the envelope of the
/// vertical velocity peaks within one sample of it (c_R = c_s·√η from the Rayleigh cubic;
/// the P and S waves arrive 306 and 53 ms earlier and are weaker at the surface).
#[test]
fn a_pulse_arrives_at_the_rayleigh_speed() {
    let n = 500;
    let (t0, r) = (0.1, 150.0);
    let piers = [[0.0, 0.0]];
    let receivers = [[r * 0.6, r * 0.8]];
    let f = pulse(n, t0, 0.008, 1e5);
    let m = padded(n, &piers, &receivers);
    let v = velocities(&SOIL, DT, &[f], &piers, &receivers, m).unwrap();
    let env = envelope(&v[0]);
    let (jmax, _) = env
        .iter()
        .enumerate()
        .fold((0, 0.0), |b, (j, &e)| if e > b.1 { (j, e) } else { b });
    let c_r = SOIL.shear_wave_velocity * rayleigh_eta(SOIL.poisson).sqrt();
    let expect = t0 + r / c_r;
    let got = jmax as f64 * DT;
    println!("c_R = {c_r:.3} m/s: envelope peak at {got:.3} s, r/c_R + t0 = {expect:.4} s");
    assert!((got - expect).abs() <= DT, "{got} against {expect}");
    // Causal: nothing before the P wave beyond the hysteretic model's small precursor.
    let c_p = SOIL.shear_wave_velocity * 3f64.sqrt();
    let before = ((t0 - 0.04 + r / c_p) / DT) as usize;
    let quiet = env[..before].iter().fold(0.0_f64, |m, &e| m.max(e));
    assert!(
        quiet < 1e-2 * env[jmax],
        "{quiet:e} before the P wave, peak {:e}",
        env[jmax]
    );
}

/// Doubling the padding changes the record very little: nothing wraps around. For forces
/// that end at rest the change is below 1e-4 of the peak (measured 2e-5: the two FFT grids
/// interpolate the tabulated Green's function at different points, and the hysteretic tail
/// below). For forces held high after the
/// record (a run that ends mid-train) it is below 1e-3 of the peak: the hysteretic model's
/// μ* = μ(1 + 2i·ξ·sign ω) jumps at 0 Hz, so the response to a held step has a slowly
/// decaying (~1/t, non-causal) tail of relative size ~ξ, whose periodic copies shrink as 1/M
/// (docs/ground.md).
#[test]
fn padding_leaves_nothing_to_wrap_around() {
    let n = 500;
    let piers = [[0.0, 0.0], [30.0, 0.0], [60.0, 0.0]];
    let receivers = [[30.0, 12.5], [30.0, 100.0]];
    for (ramp, bound) in [(0.0, 1e-4), (5e4, 1e-3)] {
        let forces: Vec<Vec<f64>> = (0..3)
            .map(|k| {
                pulse(n, 0.4 + 0.3 * k as f64, 0.05, 1e5)
                    .iter()
                    .enumerate()
                    .map(|(j, v)| v + ramp * (j as f64 / n as f64))
                    .collect()
            })
            .collect();
        let m = padded(n, &piers, &receivers);
        let a = velocities(&SOIL, DT, &forces, &piers, &receivers, m).unwrap();
        let b = velocities(&SOIL, DT, &forces, &piers, &receivers, 2 * m).unwrap();
        for r in 0..receivers.len() {
            let peak = a[r].iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            let diff = a[r]
                .iter()
                .zip(&b[r])
                .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
            println!(
                "end {ramp:e} N, receiver {r}: M = {m}, change on doubling {:.2e} of the peak",
                diff / peak
            );
            assert!(diff < bound * peak, "receiver {r}: {diff:e} of {peak:e}");
        }
    }
}
