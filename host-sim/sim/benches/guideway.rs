//! The FE guideway solver (docs/performance.md, "Benches"), driven directly with
//! point loads:
//!
//! - `step/moving-force/e=<n>`: one step (solve, commit, a midspan and an under-load query)
//!   of a 36.79 kN force at 100 m/s over one 25 m §4.2 span of n elements, Δt = 0.1 ms;
//! - `train/<cars>cars-<spans>spans[-rayon]`: a whole 5000-step run of a `forces` train,
//!   16 loads of 25 kN per car at 1.5625 m, cars 25 m apart, over spans of 30 m (§4.2
//!   section), 83.33 m/s, 16 elements per span, Δt = 2 ms.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use maglev_sim::physics::fe::FeGuideway;
use maglev_sim::physics::guideway::{BeamSection, Bridge, Guideway, PointLoad};
use std::time::Duration;

fn moving_force(c: &mut Criterion) {
    let mut g = c.benchmark_group("step/moving-force");
    g.sample_size(20)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    let (length, dt, speed) = (25.0, 1e-4, 100.0);
    for elements in [20, 80, 320, 1280, 5120] {
        let bridge = Bridge {
            section: BeamSection::paper_4_2(),
            spans: vec![length],
        };
        let mut fe = FeGuideway::new(&bridge, elements, dt).unwrap();
        let mut n = 0u64;
        g.bench_function(format!("e={elements}"), |b| {
            b.iter(|| {
                n += 1;
                let x = (speed * dt * n as f64) % length;
                let load = PointLoad {
                    x,
                    fz: -36.79e3,
                    ..Default::default()
                };
                fe.solve_step(&[load]);
                fe.commit();
                black_box(fe.section_at(length / 2.0).z + fe.motion_at(x, 0.0, 0.0).z)
            })
        });
    }
    g.finish();
}

/// One 5000-step run of the train; returns the last midspan deflection of span 1.
pub fn train_run(cars: usize, spans: usize, parallel: bool) -> f64 {
    let bridge = Bridge {
        section: BeamSection::paper_4_2(),
        spans: vec![30.0; spans],
    };
    let dt = 2e-3;
    let mut fe = FeGuideway::new(&bridge, 16, dt).unwrap();
    fe.set_parallel(parallel);
    let offsets: Vec<f64> = (0..cars)
        .flat_map(|car| (0..16).map(move |j| 25.0 * car as f64 + 1.5625 * j as f64))
        .collect();
    let mut loads = vec![PointLoad::default(); offsets.len()];
    for n in 1..=5000 {
        let lead = 83.33 * dt * n as f64;
        for (l, o) in loads.iter_mut().zip(&offsets) {
            *l = PointLoad {
                x: lead - o,
                ey: 0.0,
                ez: 0.0,
                fy: 0.0,
                fz: -25e3,
            };
        }
        fe.solve_step(&loads);
        fe.commit();
    }
    fe.section_at(15.0).z
}

fn train(c: &mut Criterion) {
    let mut g = c.benchmark_group("train");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(100))
        .measurement_time(Duration::from_secs(5));
    let cases = [
        (12, 5),
        (12, 10),
        (12, 20),
        (12, 35),
        (1, 35),
        (3, 35),
        (6, 35),
    ];
    for (cars, spans) in cases {
        g.bench_function(format!("{cars}cars-{spans}spans"), |b| {
            b.iter(|| black_box(train_run(cars, spans, false)))
        });
    }
    for (cars, spans) in [(12, 35), (1, 35)] {
        g.bench_function(format!("{cars}cars-{spans}spans-rayon"), |b| {
            b.iter(|| black_box(train_run(cars, spans, true)))
        });
    }
    g.finish();
}

criterion_group!(benches, moving_force, train);
criterion_main!(benches);
