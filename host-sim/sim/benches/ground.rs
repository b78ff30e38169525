//! Issue #27 point 6: 20 ground receivers from a paper-5 run (`maglev run paper-5` with
//! `ground.distances_m` of docs/ground.md "Cost"): the pier-base forces of the maglev train's
//! run are recorded once, outside the timing; the bench times `receivers::of_run` (the Green's
//! function table, 36 piers' FFTs, the 20 receivers' sums and inverse FFTs) on one core, inside
//! a one-thread rayon pool. docs/performance.md.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use maglev_sim::ground::receivers::{self, BaseForces};
use maglev_sim::input::case::Case;
use maglev_sim::setup::simulate;
use maglev_sim::simulation::magnets::CoreMagnets;

/// The 20 distances of docs/ground.md "Cost" (m), across the line at pier 20.
const DISTANCES: [f64; 20] = [
    12.5, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0, 55.0, 60.0, 65.0, 70.0, 75.0, 80.0, 85.0,
    90.0, 95.0, 100.0, -25.0,
];

fn ground(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let case = Case::load("paper-5", &["train=maglev".to_string()]).unwrap();
    let v = case.viaduct.as_ref().unwrap();
    let soil = case.soil.unwrap();
    let f = &v.foundation;
    let mut base = BaseForces::new(v.spans + 1, f.stiffness[2], f.damping[2]);
    pool.install(|| simulate(&case, &mut CoreMagnets::new(), &mut base, &mut ()).unwrap());
    let x = 19.0 * v.span_length;
    let points: Vec<[f64; 2]> = DISTANCES.iter().map(|&d| [x, d]).collect();
    let mut g = c.benchmark_group("ground");
    g.sample_size(10);
    g.bench_function("paper-5 maglev, 20 receivers", |b| {
        b.iter(|| {
            pool.install(|| {
                let out = receivers::of_run(&soil, v.span_length, &base, &points).unwrap();
                black_box(out.len())
            })
        })
    });
    g.finish();
}

criterion_group!(benches, ground);
criterion_main!(benches);
