//! The levitation unit's linear analysis against models written here by hand (not the code
//! under test): the Routh boundary of the PD law on a bare magnet, the loop transfer at the
//! coil voltage, and the margins from an independent Nyquist scan (docs/levitation.md).
//!
//! The bare magnet (mass M, static load p0 = M·g, EMS: the gap closes as the magnet rises),
//! in SI with the coil of docs/model.md Eq. 9 linearised (x = g/g0 − 1, τ = 2·p0·h0/(R0·i0²)):
//! ```text
//! M·Δḧ = −2·p0·x,   τ·ẋ + x + Δh/h0 = ΔV/Vb,   Δi/i0 = x + Δh/h0,   Vb = R0·i0
//! ΔV = kp·Δh + kd·Δḣ − ka·z̈ + ki·∫Δh − kc·Δi,   z̈ = −Δḧ
//! P(s) = Δh/ΔV = 1 / (Vb·(1/h0 − (τs + 1)·M·s²/(2·p0)))
//! C(s) = kp + kd·s + ka·s² + ki/s − kc·i0·(1/h0 − M·s²/(2·p0))
//! L(s) = −C(s)·P(s)·e^(−sT)      (closed loop 1 + L = 0)
//! ```
//! With kp, kd alone the characteristic polynomial is the cubic
//! `M·τ·s³ + M·s² + (2·p0·kd/Vb)·s + 2·p0·(kp/Vb − 1/h0)`; Routh: `kp > Vb/h0`, and
//! `kd > τ·(kp − Vb/h0)`.

use maglev_sim::input::case::{Case, TrainCase};
use maglev_sim::physics::vehicle::VehicleModel;
use maglev_sim::studies::stability::margins::{margins, BrokenLoop};
use maglev_sim::studies::stability::vehicle::VehiclePlant;
use nalgebra::Complex;

const G: f64 = 9.81;

struct Bare {
    m: f64,
    p0: f64,
    h0: f64,
    i0: f64,
    r0: f64,
    tau: f64,
}

/// The bundled unit with no body, magnet `mass`, the state law with `gains` (scenario text).
fn unit(mass: f64, gains: &str) -> (VehiclePlant, Bare) {
    let sets = vec![
        "vehicle.body_mass_t=0".to_string(),
        format!("vehicle.magnet_mass_kg={mass}"),
        "model=rigid".into(),
        format!("controller.state={{{gains}, vmax_V=500.0}}"),
    ];
    let case = Case::load("unit", &sets).unwrap();
    let TrainCase::Unit(u) = &case.train else {
        panic!("not a unit")
    };
    let v = VehicleModel::unit(u, maglev_core::levitation::GRAVITY).unwrap();
    let inner = case.controller.unwrap();
    let plant = VehiclePlant::new(&v, &inner, &case.law().unwrap(), case.geometry).unwrap();
    let p0 = mass * G;
    let (h0, i0, r0) = (0.01, 43.0, 1.0);
    let b = Bare {
        m: mass,
        p0,
        h0,
        i0,
        r0,
        tau: 2.0 * p0 * h0 / (r0 * i0 * i0),
    };
    (plant, b)
}

fn gains(kp: f64, kd: f64, ka: f64, ki: f64, kc: f64) -> String {
    format!(
        "kp_V_per_m={kp:e}, kd_V_s_per_m={kd:e}, ka_V_s2_per_m={ka:e}, ki_V_per_m_s={ki:e}, \
         kc_V_per_A={kc:e}"
    )
}

/// The largest real part, the integral's pole left out: with ki = 0 it sits at exactly 0
/// (`u̇ = 0`), outside the loop.
fn max_re(p: &VehiclePlant) -> f64 {
    p.verdict().unwrap().max_real_part
}

/// Done-when of issue 26: the PD law's stability boundary on the unit without a body is the
/// Routh boundary of the hand-derived cubic, to 1e-6 relative.
#[test]
fn the_pd_boundary_is_routh_s() {
    for mass in [200.0, 600.0, 2000.0] {
        let (_, b) = unit(mass, &gains(1e5, 1e3, 0.0, 0.0, 0.0));
        let vb_h0 = b.r0 * b.i0 / b.h0;
        let kp = 3.0 * vb_h0;
        let want = b.tau * (kp - vb_h0);
        let stable = |kd: f64| max_re(&unit(mass, &gains(kp, kd, 0.0, 0.0, 0.0)).0) < 0.0;
        let (mut lo, mut hi) = (0.5 * want, 2.0 * want);
        assert!(!stable(lo) && stable(hi));
        while hi / lo - 1.0 > 1e-10 {
            let mid = 0.5 * (lo + hi);
            if stable(mid) {
                hi = mid
            } else {
                lo = mid
            }
        }
        assert!((hi / want - 1.0).abs() < 1e-6, "{mass} kg: {hi} vs {want}");
        // kp = Vb/h0: the static stiffness vanishes, whatever kd.
        // (kd = 1 V·s/m keeps the real pole (kp − Vb/h0)/kd far from the zero-pole cut.)
        let kd = 1.0;
        assert!(max_re(&unit(mass, &gains(vb_h0 * (1.0 + 1e-6), kd, 0.0, 0.0, 0.0)).0) < 0.0);
        assert!(max_re(&unit(mass, &gains(vb_h0 * (1.0 - 1e-6), kd, 0.0, 0.0, 0.0)).0) > 0.0);
    }
}

/// The hand-derived `L(jω)` (module docs).
fn l_hand(b: &Bare, g: [f64; 5], delay: f64, w: f64) -> Complex<f64> {
    let [kp, kd, ka, ki, kc] = g;
    let s = Complex::new(0.0, w);
    let vb = b.r0 * b.i0;
    let q = b.m * s * s / (2.0 * b.p0);
    let p = Complex::new(1.0, 0.0) / (vb * (1.0 / b.h0 - (b.tau * s + 1.0) * q));
    let c = kp + kd * s + ka * s * s + ki / s - kc * b.i0 * (1.0 / b.h0 - q);
    -c * p * (-s * delay).exp()
}

/// Independent margins of the hand-derived loop: a dense log scan (20 000 points a decade)
/// with linear interpolation at each sign change. Returns (gain low dB, gain high dB, phase
/// deg, Ms).
fn hand_margins(b: &Bare, g: [f64; 5], delay: f64) -> (f64, f64, f64, f64) {
    scan(|w| l_hand(b, g, delay, w))
}

/// The scan of [`hand_margins`] on any `L(jω)`.
fn scan(l: impl Fn(f64) -> Complex<f64>) -> (f64, f64, f64, f64) {
    let n = 160_000;
    let ws: Vec<f64> = (0..=n)
        .map(|i| 10f64.powf(-2.0 + 8.0 * i as f64 / n as f64))
        .collect();
    let ls: Vec<Complex<f64>> = ws.iter().map(|&w| l(w)).collect();
    let (mut low, mut high, mut pm, mut ms) = (0.0f64, f64::INFINITY, f64::INFINITY, 0.0f64);
    for i in 1..ws.len() {
        let (a, c) = (ls[i - 1], ls[i]);
        if (a.im > 0.0) != (c.im > 0.0) {
            let t = a.im / (a.im - c.im);
            let re = a.re + t * (c.re - a.re);
            if re < 0.0 {
                let k = -1.0 / re;
                if k < 1.0 {
                    low = low.max(k)
                } else {
                    high = high.min(k)
                }
            }
        }
        if (a.norm() > 1.0) != (c.norm() > 1.0) {
            let t = (a.norm() - 1.0) / (a.norm() - c.norm());
            let z = a + (c - a) * t;
            let d = z.arg().to_degrees() + 180.0;
            pm = pm.min((d - 360.0 * (d / 360.0).round()).abs());
        }
        ms = ms.max(1.0 / (c + 1.0).norm());
    }
    (-20.0 * low.log10(), 20.0 * high.log10(), pm, ms)
}

#[test]
fn the_loop_at_the_coil_is_the_hand_derived_one() {
    let g = [1.5e5, 2.5e3, 10.0, 5.0e5, 20.0];
    for mass in [200.0, 2000.0] {
        let (plant, b) = unit(mass, &gains(g[0], g[1], g[2], g[3], g[4]));
        let lp = BrokenLoop::new(&plant, 0, 1.5e-4).unwrap();
        for w in [0.3, 3.0, 30.0, 300.0, 3000.0] {
            let (got, want) = (lp.at_freq(w), l_hand(&b, g, 1.5e-4, w));
            assert!(
                (got - want).norm() < 1e-9 * want.norm(),
                "{mass} kg, ω = {w}: {got} vs {want}"
            );
        }
    }
}

#[test]
fn margins_agree_with_an_independent_scan_and_routh() {
    // PD without delay: κ·C is stable for κ·kp > Vb/h0 and κ·(kd − τ·kp) > −τ·Vb/h0
    // (τ = 0.064 s at 600 kg: kd = 600 lies between τ·(kp − Vb/h0) = 490 and τ·kp = 764).
    let mass = 600.0;
    let (plant, b) = unit(mass, &gains(1.2e4, 600.0, 0.0, 0.0, 0.0));
    let (kp, kd) = (1.2e4, 600.0);
    let vb_h0 = b.r0 * b.i0 / b.h0;
    let k_low = vb_h0 / kp;
    let k_high = b.tau * vb_h0 / (b.tau * kp - kd);
    let m = margins(&plant, 0, 0.0).unwrap();
    assert!(m.stable_with_delay);
    let close =
        |a: f64, b: f64, tol: f64, what: &str| assert!((a - b).abs() < tol, "{what}: {a} vs {b}");
    close(m.gain_low_db.unwrap(), -20.0 * k_low.log10(), 1e-6, "low");
    close(m.gain_high_db.unwrap(), 20.0 * k_high.log10(), 1e-6, "high");
    // Every gain with a delay: against the scan.
    let g = [1.5e5, 2.5e3, 10.0, 5.0e5, 20.0];
    for mass in [200.0, 600.0, 2000.0] {
        let (plant, b) = unit(mass, &gains(g[0], g[1], g[2], g[3], g[4]));
        let m = margins(&plant, 0, 1.5e-4).unwrap();
        let (lo, hi, pm, ms) = hand_margins(&b, g, 1.5e-4);
        close(m.gain_low_db.unwrap(), lo, 1e-3, "low");
        close(m.gain_high_db.unwrap(), hi, 1e-3, "high");
        close(m.phase_deg.unwrap(), pm, 1e-2, "phase");
        close(m.sensitivity_peak.unwrap(), ms, 1e-4 * ms, "Ms");
    }
}

/// The bundled unit (600 kg magnet... as given by `--set`, 3.75 t body on 200 kN/m and
/// 10 kN·s/m) written here as its own state space, SI: states `z_m, v_m, z_b, v_b, x, u`
/// (module docs' equations with the body; `u = ki·∫Δh` in volts), the law's `ΔV` a row `K`
/// over them, the coil's input column `B = e_x/(τ·V_b)`. Returns (A_open, B, K).
fn unit_model(
    m: f64,
    g: [f64; 5],
) -> (
    nalgebra::DMatrix<f64>,
    nalgebra::DVector<f64>,
    nalgebra::DVector<f64>,
) {
    let [kp, kd, ka, ki, kc] = g;
    let (mb, k, c) = (3750.0, 200e3, 10e3);
    let (h0, i0, r0) = (0.01, 43.0, 1.0);
    let vb = r0 * i0;
    let p0 = (m + mb) * G;
    let tau = 2.0 * p0 * h0 / (r0 * i0 * i0);
    let mut a = nalgebra::DMatrix::zeros(6, 6);
    // Δh = −z_m; magnet and body.
    a[(0, 1)] = 1.0;
    a[(1, 0)] = -k / m;
    a[(1, 1)] = -c / m;
    a[(1, 2)] = k / m;
    a[(1, 3)] = c / m;
    a[(1, 4)] = 2.0 * p0 / m;
    a[(2, 3)] = 1.0;
    a[(3, 0)] = k / mb;
    a[(3, 1)] = c / mb;
    a[(3, 2)] = -k / mb;
    a[(3, 3)] = -c / mb;
    // Coil without the law: τ·ẋ = −x − Δh/h0 = −x + z_m/h0.
    a[(4, 4)] = -1.0 / tau;
    a[(4, 0)] = 1.0 / (h0 * tau);
    // u̇ = ki·Δh.
    a[(5, 0)] = -ki;
    // ΔV = kp·Δh + kd·Δḣ − ka·a_m + u − kc·i0·(x + Δh/h0).
    let mut kr = nalgebra::DVector::zeros(6);
    kr[0] = -kp + kc * i0 / h0;
    kr[1] = -kd;
    for j in 0..6 {
        kr[j] -= ka * a[(1, j)];
    }
    kr[5] += 1.0;
    kr[4] -= kc * i0;
    let mut b = nalgebra::DVector::zeros(6);
    b[4] = 1.0 / (tau * vb);
    (a, b, kr)
}

/// An eigenvalue of `a` polished from `s`: Newton on `det(sI − a)`, whose logarithmic
/// derivative is `trace((sI − a)⁻¹)` (nalgebra's eigenvalues of this unbalanced matrix are
/// good to about 1e-5 only).
fn newton(a: &nalgebra::DMatrix<f64>, mut s: Complex<f64>) -> Complex<f64> {
    let n = a.nrows();
    for _ in 0..20 {
        let m = nalgebra::DMatrix::from_fn(n, n, |i, j| {
            (if i == j { s } else { Complex::new(0.0, 0.0) }) - a[(i, j)]
        });
        let Some(inv) = m.try_inverse() else { break };
        let step = Complex::new(1.0, 0.0) / inv.trace();
        s -= step;
        if step.norm() < 1e-14 * s.norm() {
            break;
        }
    }
    s
}

/// Done-when of issue 26 point 3: the designed gains of the bundled unit at 200, 600 and
/// 2000 kg meet every target, checked on the model above (poles and a Nyquist scan), and
/// the report's poles and margins are those of this model.
#[test]
fn designed_gains_meet_every_target_on_an_independent_model() {
    for m in [200.0, 600.0, 2000.0] {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_maglev"))
            .args(["stability", "--scenario", "unit", "--set", "law=state"])
            .args([
                "--set",
                &format!("vehicle.magnet_mass_kg={m}"),
                "--format",
                "json",
            ])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let r: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let gain = |k: &str| r["gains"][k].as_f64().unwrap();
        let g = [
            gain("kp_V_per_m"),
            gain("kd_V_s_per_m"),
            gain("ka_V_s2_per_m"),
            gain("ki_V_per_m_s"),
            gain("kc_V_per_A"),
        ];
        let (a, b, k) = unit_model(m, g);
        let closed = &a + &b * k.transpose();
        let mut ours: Vec<Complex<f64>> = closed
            .complex_eigenvalues()
            .iter()
            .map(|&s0| newton(&closed, s0))
            .collect();
        ours.sort_by(|x, y| y.re.total_cmp(&x.re).then(y.im.total_cmp(&x.im)));
        let theirs = r["ideal_poles"].as_array().unwrap();
        assert_eq!(theirs.len(), ours.len(), "{m} kg");
        for (p, q) in ours.iter().zip(theirs) {
            let q = Complex::new(q[0].as_f64().unwrap(), q[1].as_f64().unwrap());
            assert!(
                (p - q).norm() < 1e-6 * p.norm().max(1.0),
                "{m} kg: {p} vs {q}"
            );
            assert!(p.re <= -1.0, "{m} kg: pole {p}");
        }
        // The loop at the coil voltage, 1.5 periods of 100 µs in series.
        let delay = 1.5e-4;
        let l = |w: f64| {
            let s = Complex::new(0.0, w);
            let n = a.nrows();
            let mat = nalgebra::DMatrix::from_fn(n, n, |i, j| {
                (if i == j { s } else { Complex::new(0.0, 0.0) }) - a[(i, j)]
            });
            let x = mat.lu().solve(&b.map(|v| Complex::new(v, 0.0))).unwrap();
            let kx: Complex<f64> = k.iter().zip(x.iter()).map(|(ki, xi)| xi * *ki).sum();
            -kx * (-s * delay).exp()
        };
        let (lo, hi, pm, ms) = scan(l);
        assert!(
            lo >= 6.0 && hi >= 6.0 && pm >= 35.0 && ms <= 2.0,
            "{m} kg: {lo} {hi} {pm} {ms}"
        );
        let mg = &r["margins"][0];
        let close = |x: &serde_json::Value, y: f64, tol: f64, what: &str| {
            let x = x.as_f64().unwrap();
            assert!((x - y).abs() < tol, "{m} kg {what}: {x} vs {y}")
        };
        assert!((mg["delay_s"].as_f64().unwrap() - delay).abs() < 1e-18);
        close(&mg["gain_low_db"], lo, 1e-3, "low");
        close(&mg["gain_high_db"], hi, 1e-3, "high");
        close(&mg["phase_deg"], pm, 1e-2, "phase");
        close(&mg["sensitivity_peak"], ms, 1e-4, "Ms");
    }
}
