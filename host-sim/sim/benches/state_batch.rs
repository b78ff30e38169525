//! The state law's update of paper-5's 1152 magnets (384 wheels × levitation and two guidance
//! magnets, `wheel_mass_kg = 500`'s loads, Δt = 2 ms: 20 control periods a step) from one
//! committed state, as every pass of the coupled iteration runs it: one
//! `StateLaw::update` per magnet against `law::state::batch::update_batch` (the same bits,
//! its tests). docs/performance.md, "The state law's batch".

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use maglev_core::law::state::{batch::update_batch, StateLaw, StateLawState};
use maglev_core::levitation::{Output, State};
use maglev_core::Params;
use maglev_sim::input::case::Case;

/// Magnets of paper-5's maglev train.
const MAGNETS: usize = 1152;

/// The laws, states and law states of [`magnets`].
type Magnets = (Vec<StateLaw<f64>>, Vec<State<f64>>, Vec<StateLawState<f64>>);

/// The state law of the run's magnets (its gains, controller and step from the scenario),
/// on loads of a few tens of kN differing per wheel as the cars' do; equilibrium states.
fn magnets() -> Magnets {
    let sets = ["geometry=ems", "law=state", "train.wheel_mass_kg=500"].map(String::from);
    let case = Case::load("paper-5", &sets).unwrap();
    let kind = case.law().unwrap().with_geometry(case.geometry);
    let gains = kind.state().unwrap();
    let controller = case.controller.unwrap();
    let mut laws = Vec::new();
    let (mut coil, mut st) = (Vec::new(), Vec::new());
    for i in 0..MAGNETS {
        let m = Params {
            p0: 30e3 + 10.0 * (i / 3) as f64,
            dt: case.dt,
            ..controller
        };
        let law = gains.compile::<f64>(&m).unwrap();
        let c = m.compile::<f64>().unwrap().equilibrium_state(m.h0);
        st.push(law.equilibrium(&c));
        coil.push(c);
        laws.push(law);
    }
    (laws, coil, st)
}

fn state_batch(c: &mut Criterion) {
    let (laws, coil0, st0) = magnets();
    // Gaps and accelerations a few per cent off equilibrium, different per magnet.
    let gap: Vec<f64> = (0..MAGNETS)
        .map(|i| 1.0 + 0.02 * ((i % 7) as f64 - 3.0) / 3.0)
        .collect();
    let accel: Vec<f64> = (0..MAGNETS)
        .map(|i| {
            if i % 3 == 0 {
                0.01 * ((i % 5) as f64 - 2.0)
            } else {
                0.0
            }
        })
        .collect();
    let mut coil = coil0.clone();
    let mut st = st0.clone();
    let mut out = vec![Output::default(); MAGNETS];
    let mut g = c.benchmark_group("state-law/1152-magnets/20-periods");
    g.bench_function("per-magnet", |b| {
        b.iter(|| {
            coil.copy_from_slice(&coil0);
            st.copy_from_slice(&st0);
            for i in 0..MAGNETS {
                let a = (i % 3 == 0).then_some(accel[i]);
                out[i] = laws[i].update(&mut coil[i], &mut st[i], black_box(gap[i]), a);
            }
            black_box(&out);
        })
    });
    g.bench_function("batch", |b| {
        b.iter(|| {
            coil.copy_from_slice(&coil0);
            st.copy_from_slice(&st0);
            let alone = update_batch(&laws, &mut coil, &mut st, black_box(&gap), &accel, &mut out);
            black_box((&out, alone));
        })
    });
    g.finish();
}

criterion_group!(benches, state_batch);
criterion_main!(benches);
