//! The coupled passage's time loop alone (set-up outside the timing): the §4.2 car at
//! 100 m/s over the 25 m FE span with either scheme, and trains of Fig. 1 cars over a
//! multi-span FE viaduct (serial and with the cars on rayon). docs/performance.md.

use criterion::{black_box, criterion_group, criterion_main, BatchSize, Criterion};
use maglev_sim::input::case::Case;
use maglev_sim::probes::NoRecorder;
use maglev_sim::setup::Passage;
use maglev_sim::simulation::magnets::CoreMagnets;
use maglev_sim::simulation::{simulate, Load};

fn passage(sets: &[&str]) -> Passage {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    Passage::new(&Case::load("paper-4.2", &sets).unwrap()).unwrap()
}

fn run(mut p: Passage) -> usize {
    simulate(
        &mut p.guideway,
        &p.load,
        &p.profiles,
        &p.settings,
        &mut CoreMagnets::new(),
        &mut NoRecorder,
        &mut (),
    )
    .unwrap()
    .steps
}

/// The §4.2 passage (0.5 s simulated).
fn paper_4_2(c: &mut Criterion) {
    let mut g = c.benchmark_group("passage");
    g.sample_size(10);
    for (name, sets) in [
        ("paper-4.2-nsub1000", vec![]),
        ("paper-4.2-accurate", vec!["scheme=accurate"]),
    ] {
        g.bench_function(name, |b| {
            b.iter_batched(
                || passage(&sets),
                |p| black_box(run(p)),
                BatchSize::PerIteration,
            )
        });
    }
    g.finish();
}

/// `cars` Fig. 1 cars 25 m apart over 10 spans of 25 m (FE, 20 elements a span), accurate
/// scheme, 0.5 s simulated (50 m travelled).
pub fn train_passage(cars: usize, parallel: bool) -> Passage {
    let repeat = format!("vehicle.repeat={cars}");
    let mut p = passage(&[
        "scheme=accurate",
        "t_end=0.5",
        "vehicle.car_length_m=25.0",
        &repeat,
        "bridge.spans_m=[25.0,25.0,25.0,25.0,25.0,25.0,25.0,25.0,25.0,25.0]",
    ]);
    if let Load::Vehicle(t) = &mut p.load {
        t.parallel = parallel;
    }
    p
}

fn trains(c: &mut Criterion) {
    let mut g = c.benchmark_group("train");
    g.sample_size(10);
    for cars in [1, 3, 6, 12] {
        g.bench_function(format!("fig1-{cars}cars-10spans"), |b| {
            b.iter_batched(
                || train_passage(cars, false),
                |p| black_box(run(p)),
                BatchSize::PerIteration,
            )
        });
    }
    g.bench_function("fig1-12cars-10spans-rayon", |b| {
        b.iter_batched(
            || train_passage(12, true),
            |p| black_box(run(p)),
            BatchSize::PerIteration,
        )
    });
    g.finish();
}

criterion_group!(benches, paper_4_2, trains);
criterion_main!(benches);
