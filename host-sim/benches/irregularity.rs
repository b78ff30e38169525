//! One sample of the rail irregularity (Eq. 3) by the direct 2000-term sum (Table 1, Z), in
//! f64 and f32: the cost a controller pays per time step if it evaluates r(x) itself.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use maglev_core::irregularity::{Direction, Irregularity, PsdParams};

fn one_sample(c: &mut Criterion) {
    let p = PsdParams::TABLE1_Z;
    let g64: Box<Irregularity<f64>> =
        Box::new(Irregularity::new(&p, Direction::Z, 1).expect("Table 1 is valid"));
    let g32: Box<Irregularity<f32>> =
        Box::new(Irregularity::new(&p, Direction::Z, 1).expect("Table 1 is valid"));
    c.bench_function("irregularity_direct_sum_2000_f64", |b| {
        b.iter(|| {
            let mut ov = false;
            g64.eval(black_box(123.456f64), &mut ov)
        })
    });
    c.bench_function("irregularity_direct_sum_2000_f32", |b| {
        b.iter(|| {
            let mut ov = false;
            g32.eval(black_box(123.456f32), &mut ov)
        })
    });
}

criterion_group!(benches, one_sample);
criterion_main!(benches);
