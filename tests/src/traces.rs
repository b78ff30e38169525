//! Canned gap traces (SI): constant, step and sinusoidal gaps around the paper's h0 = 10 mm.

use maglev_sim::studies::control::Trace;

fn make(dt: f64, steps: usize, h: impl Fn(f64) -> f64) -> Trace {
    let t: Vec<f64> = (0..=steps).map(|k| k as f64 * dt).collect();
    let h = t.iter().map(|&t| h(t)).collect();
    Trace { t, h, dt }
}

/// 1 s at the nominal gap.
pub fn constant(dt: f64) -> Trace {
    make(dt, (1.0 / dt) as usize, |_| 0.01)
}

/// The gap closes by 1 mm at t = 0.1 s and stays there for 0.9 s.
pub fn step(dt: f64) -> Trace {
    make(dt, (1.0 / dt) as usize, |t| {
        if t < 0.1 - 1e-12 {
            0.01
        } else {
            0.009
        }
    })
}

/// 1 mm amplitude at 5 Hz for 1 s.
pub fn sine(dt: f64) -> Trace {
    make(dt, (1.0 / dt) as usize, |t| {
        0.01 + 0.001 * (2.0 * std::f64::consts::PI * 5.0 * t).sin()
    })
}

/// All three, named.
pub fn all(dt: f64) -> [(&'static str, Trace); 3] {
    [
        ("constant", constant(dt)),
        ("step", step(dt)),
        ("sine", sine(dt)),
    ]
}
