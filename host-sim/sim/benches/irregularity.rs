//! One sample of the rail irregularity (Eq. 3) by the direct 2000-term sum (Table 1, Z), in
//! f64 and f32: the cost a controller pays per time step if it evaluates r(x) itself; and by
//! the core's fast generator (`irregularity_fast::Table`, cubic interpolation on a 5 cm grid:
//! relative RMS error ≤ 1.8e-6), in f64 (host Vec) and f32 (fixed-capacity array). And the
//! start-up cost a run pays once: building the Y and Z tables (5 mm grid, chirp-z synthesis,
//! `profile::Profile::table1_y_z`) over the extent `maglev run paper-4.2` samples.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use maglev_core::irregularity::{Direction, Irregularity, PsdParams};
use maglev_core::irregularity_fast::{fill, FixedTable, Table};
use maglev_sim::physics::profile::Profile;

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

fn fast_sample(c: &mut Criterion) {
    let p = PsdParams::TABLE1_Z;
    let g64: Irregularity<f64> = Irregularity::new(&p, Direction::Z, 1).expect("Table 1 is valid");
    let g32: Irregularity<f32> = Irregularity::new(&p, Direction::Z, 1).expect("Table 1 is valid");
    let h = 0.05;
    let mut ov = false;
    let mut v = vec![0.0f64; 4096];
    fill(&g64, 0.0, h, &mut v, &mut ov);
    let t64 = Table::new(0.0, h, v).expect("valid grid");
    let mut a = [0.0f32; 4096];
    fill(&g32, 0.0, h, &mut a, &mut ov);
    let t32: FixedTable<f32, 4096> = Table::new(0.0, h, a).expect("valid grid");
    c.bench_function("irregularity_table_cubic_f64", |b| {
        b.iter(|| {
            let (mut out, mut ov) = (false, false);
            t64.eval(black_box(123.456f64), &mut out, &mut ov)
        })
    });
    c.bench_function("irregularity_table_cubic_f32", |b| {
        b.iter(|| {
            let (mut out, mut ov) = (false, false);
            t32.eval(black_box(123.456f64), &mut out, &mut ov)
        })
    });
}

/// `maglev run paper-4.2` tabulates x from −16 m to 51 m (`setup::profiles_for`: the car's
/// nodes ± 1 m and the distance it travels): 13 406 samples a profile.
fn table_build(c: &mut Criterion) {
    c.bench_function("irregularity_table_build_y_z_67m", |b| {
        b.iter(|| Profile::table1_y_z(black_box(1), -16.0, 51.0).expect("Table 1 is valid"))
    });
}

criterion_group!(benches, one_sample, fast_sample, table_build);
criterion_main!(benches);
