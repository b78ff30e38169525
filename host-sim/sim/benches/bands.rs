//! `bands::analyse` on the paper's record length (5000 samples at 2 ms, 27 bands): the
//! whole-record levels (one forward FFT) and the maximum running rms (one inverse FFT per band).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use maglev_sim::bands::{analyse, Averaging, Level, Motion, Settings};

fn record() -> Vec<f64> {
    // A deterministic broadband signal: a sum of incommensurate sines.
    (0..5000)
        .map(|j| {
            let t = j as f64 * 0.002;
            (1..40)
                .map(|k| (std::f64::consts::TAU * 1.37 * k as f64 * t + k as f64).sin() / k as f64)
                .sum()
        })
        .collect()
}

fn bands_5000(c: &mut Criterion) {
    let x = record();
    let whole = Settings {
        input: Motion::Acceleration,
        level: Level::Acceleration,
        averaging: Averaging::WholeRecord,
    };
    let running = Settings {
        averaging: Averaging::MaxRunning { window_s: 1.0 },
        ..whole
    };
    c.bench_function("bands_5000_whole_record", |b| {
        b.iter(|| analyse(black_box(&x), 0.002, &whole).unwrap())
    });
    c.bench_function("bands_5000_max_running_1s", |b| {
        b.iter(|| analyse(black_box(&x), 0.002, &running).unwrap())
    });
}

criterion_group!(benches, bands_5000);
criterion_main!(benches);
