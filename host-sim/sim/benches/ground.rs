//! The ground step of a paper-5 run (issue #40 point 2, docs/performance.md "Ground"): the
//! pier-base forces of the maglev train's run are recorded once, outside the timing; the
//! bench times `receivers::of_run` (the table of W, 36 piers' FFTs, the receivers' sums and
//! inverse FFTs; one thread) for the 4 receivers of `maglev run paper-5 --set
//! 'ground.distances_m=[12.5,25,50,100]' --set ground.pier=20` and the 20 of docs/ground.md
//! "Cost", and the table of W alone (the paper-5 soil, to the x the 4 receivers need).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use maglev_sim::ground::receivers::{self, BaseForces};
use maglev_sim::ground::table::Tables;
use maglev_sim::input::case::Case;
use maglev_sim::setup::simulate;
use maglev_sim::simulation::magnets::CoreMagnets;

/// The 4 distances of the command (m), across the line at pier 20.
const FOUR: [f64; 4] = [12.5, 25.0, 50.0, 100.0];
/// The 20 distances of docs/ground.md "Cost" (m).
const TWENTY: [f64; 20] = [
    12.5, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0, 55.0, 60.0, 65.0, 70.0, 75.0, 80.0, 85.0,
    90.0, 95.0, 100.0, -25.0,
];

fn ground(c: &mut Criterion) {
    let case = Case::load("paper-5", &["train=maglev".to_string()]).unwrap();
    let v = case.viaduct.as_ref().unwrap();
    let soil = case.soil.unwrap();
    let f = &v.foundation;
    let mut base = BaseForces::new(v.spans + 1, f.stiffness[2], f.damping[2]);
    simulate(&case, &mut CoreMagnets::new(), &mut base, &mut ()).unwrap();
    let x = 19.0 * v.span_length;
    let mut g = c.benchmark_group("ground");
    g.sample_size(10);
    for (name, d) in [("4", &FOUR[..]), ("20", &TWENTY[..])] {
        let points: Vec<[f64; 2]> = d.iter().map(|&d| [x, d]).collect();
        g.bench_function(format!("paper-5 maglev, {name} receivers"), |b| {
            b.iter(|| {
                let out = receivers::of_run(&soil, v.span_length, &base, &points).unwrap();
                black_box(out.len())
            })
        });
    }
    // The whole table, to its cut-off (the 4 receivers' Nyquist × farthest pier is beyond it).
    g.bench_function("table of W, paper-5 soil, to its cut-off", |b| {
        b.iter(|| {
            let mut t = Tables::new();
            let table = t.get(soil.poisson, soil.damping, 1e9).unwrap();
            black_box(table.nodes())
        })
    });
    g.finish();
}

criterion_group!(benches, ground);
criterion_main!(benches);
