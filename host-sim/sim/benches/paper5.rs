//! Issue #10's runs: `maglev run paper-5 --set train=maglev` and `--set train=wheel-rail`,
//! each the full case (12 cars, 35 spans, 5000 steps of 2 ms, Table 1 irregularity) through
//! `setup::simulate` with a recorder that keeps nothing, set-up included (the viaduct's
//! factorisation is part of a run). On one core: everything runs inside a one-thread rayon
//! pool, so the train's and the spans' `par_iter`s stay on it. docs/performance.md, docs/paper5.md.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use maglev_sim::input::case::Case;
use maglev_sim::probes::NoRecorder;
use maglev_sim::setup::simulate;
use maglev_sim::simulation::magnets::CoreMagnets;

fn paper5(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let mut g = c.benchmark_group("paper-5");
    g.sample_size(10);
    for train in ["maglev", "wheel-rail"] {
        let case = Case::load("paper-5", &[format!("train={train}")]).unwrap();
        g.bench_function(train, |b| {
            b.iter(|| {
                pool.install(|| {
                    let run =
                        simulate(&case, &mut CoreMagnets::new(), &mut NoRecorder, &mut ()).unwrap();
                    black_box(run.outcome.steps)
                })
            })
        });
    }
    g.finish();
}

criterion_group!(benches, paper5);
criterion_main!(benches);
