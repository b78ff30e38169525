//! One controller update per scalar type: the paper scheme (Eq. 14 with its internal loop) at
//! n_sub = 1 and 1000 (i4f28 only at n_sub = 1 and 10: it refuses 1000, see the core's docs),
//! and the accurate scheme (Gauss–Legendre, one interval at Δt = 1 ms); and one coupled §4.3
//! passage (100 m/s, 20 elements, Δt = 1 ms) with either scheme.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use maglev_core::scalar::{I32F32, I4F28};
use maglev_core::{Params, Scalar, Scheme};

fn update<S: Scalar>(c: &mut Criterion, n_sub: u32) {
    let mut p = Params::paper_wheel(1e-3);
    p.n_sub = n_sub;
    bench_update::<S>(c, &p, &format!("update/{}/nsub={n_sub}", S::NAME));
}

fn update_accurate<S: Scalar>(c: &mut Criterion) {
    let mut p = Params::paper_wheel(1e-3);
    p.scheme = Scheme::Accurate;
    bench_update::<S>(c, &p, &format!("update/{}/accurate", S::NAME));
}

fn bench_update<S: Scalar>(c: &mut Criterion, p: &Params, name: &str) {
    let ctrl = p.compile::<S>().unwrap();
    let mut st = ctrl.initial_state(p.h0);
    let mut ov = false;
    let gaps = [S::from_f64(1.01, &mut ov), S::from_f64(0.99, &mut ov)];
    let mut k = 0;
    c.bench_function(name, |b| {
        b.iter(|| {
            k ^= 1;
            black_box(ctrl.update(&mut st, black_box(gaps[k])))
        })
    });
}

fn controllers(c: &mut Criterion) {
    for n in [1, 1000] {
        update::<f64>(c, n);
        update::<f32>(c, n);
        update::<I32F32>(c, n);
    }
    update::<I4F28>(c, 1);
    update::<I4F28>(c, 10);
    update_accurate::<f64>(c);
    update_accurate::<f32>(c);
    update_accurate::<I32F32>(c);
    update_accurate::<I4F28>(c);
}

fn passage(c: &mut Criterion) {
    let mut g = c.benchmark_group("passage");
    g.sample_size(10);
    for (name, sets) in [
        (
            "fe-100mps-dt1ms-nsub1000",
            vec!["speed=100", "model=fe", "dt=1e-3", "nsub=1000"],
        ),
        (
            "fe-100mps-dt1ms-accurate",
            vec!["speed=100", "model=fe", "dt=1e-3", "scheme=accurate"],
        ),
        (
            "modal-100mps-dt1e-5",
            vec!["speed=100", "model=modal", "dt=1e-5", "nsub=1"],
        ),
    ] {
        let sets: Vec<String> = sets.into_iter().map(String::from).collect();
        let case = maglev_sim::input::case::Case::load("paper-4.2", &sets).unwrap();
        g.bench_function(name, |b| {
            b.iter(|| {
                black_box(
                    maglev_sim::setup::simulate(
                        &case,
                        &mut maglev_sim::simulation::magnets::CoreMagnets::new(),
                        &mut maglev_sim::probes::NoRecorder,
                        &mut (),
                    )
                    .unwrap()
                    .wall,
                )
            })
        });
    }
    g.finish();
}

criterion_group!(benches, controllers, passage);
criterion_main!(benches);
