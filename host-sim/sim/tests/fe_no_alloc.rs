//! The FE guideway's time loop does not allocate: the counting global allocator of
//! `counting_alloc` counts the allocations made on this thread by `solve_step`, `motion_at`,
//! `section_at` and `commit` over a train crossing three spans, serial mode, for the FE spans
//! and for the coupled viaduct. (The rayon mode hands work to the pool, whose job queues may
//! allocate; it is not covered.)

mod counting_alloc;

use counting_alloc::count;
use maglev_sim::physics::fe::FeGuideway;
use maglev_sim::physics::guideway::{BeamSection, Bridge, Guideway, PointLoad};

/// The FE spans' time loop, and the same spans with their bearings driven by support motion
/// (a record in y and z and a settled support, docs/seismic.md "Spans on rigid supports").
#[test]
fn time_loop_does_not_allocate() {
    use maglev_sim::physics::seismic::support::{GroundRecord, SupportMotion};
    let bridge = Bridge {
        section: BeamSection::paper_4_2(),
        spans: vec![30.0; 3],
    };
    let dt = 2e-3;
    let record = GroundRecord::new(
        dt,
        (0..=800)
            .map(|n| {
                let t = n as f64 * dt;
                [0.0, 0.3 * (13.0 * t).sin(), -0.5 * (9.0 * t).sin()]
            })
            .collect(),
    )
    .unwrap();
    let driven = SupportMotion::uniform(record, 4)
        .with_settlement(1, [0.0, 0.0, -0.01])
        .unwrap();
    for mut fe in [
        FeGuideway::new(&bridge, 16, dt).unwrap(),
        FeGuideway::with_support_motion(&bridge, 16, dt, None, driven).unwrap(),
    ] {
        let mut loads = vec![PointLoad::default(); 32];
        let before = count();
        let mut sum = 0.0;
        for n in 1..=800 {
            let lead = 83.33 * dt * n as f64;
            for (j, l) in loads.iter_mut().enumerate() {
                *l = PointLoad {
                    x: lead - 1.5625 * j as f64,
                    ey: 1.5,
                    ez: 0.6,
                    fy: 1e3,
                    fz: -25e3,
                };
            }
            for _ in 0..3 {
                fe.solve_step(&loads);
                sum += loads
                    .iter()
                    .map(|l| fe.motion_at(l.x, l.ey, l.ez).z)
                    .sum::<f64>();
            }
            fe.commit();
            sum += fe.section_at(45.0).z;
        }
        let allocations = count() - before;
        assert!(
            sum < 0.0,
            "the loads (and the ground, downwards) deflect the spans"
        );
        assert_eq!(allocations, 0, "allocations in the time loop");
        // The counter works: an allocation is seen.
        let v = std::hint::black_box(vec![1u8; 10]);
        assert_eq!(count() - before, 1);
        drop(v);
    }
}

/// The same for the coupled viaduct (host-sim/sim/src/physics/fe/viaduct.rs), including the pier-base
/// query the `pier{K}.base.*` probes use; and the same viaduct driven by support motion (a
/// uniform record and a settled pier, docs/seismic.md "Support motion").
#[test]
fn viaduct_time_loop_does_not_allocate() {
    use maglev_sim::physics::fe::{paper5_viaduct, Viaduct};
    use maglev_sim::physics::seismic::support::{GroundRecord, SupportMotion};
    let mut spec = paper5_viaduct().with_spans(3);
    spec.elements_per_span = 8;
    let dt = 2e-3;
    let record = GroundRecord::new(
        dt,
        (0..=600)
            .map(|n| {
                let t = n as f64 * dt;
                [0.5 * (9.0 * t).sin(), 0.3 * (13.0 * t).sin(), 0.0]
            })
            .collect(),
    )
    .unwrap();
    let driven = SupportMotion::uniform(record, 4)
        .with_settlement(1, [0.0, 0.0, -0.01])
        .unwrap();
    for mut v in [
        Viaduct::new(&spec, dt).unwrap(),
        Viaduct::with_support_motion(&spec, dt, driven).unwrap(),
    ] {
        let mut loads = vec![PointLoad::default(); 32];
        let before = count();
        let mut sum = 0.0;
        for n in 1..=600 {
            let lead = 83.33 * dt * n as f64;
            for (j, l) in loads.iter_mut().enumerate() {
                *l = PointLoad {
                    x: lead - 1.5625 * (j / 2) as f64,
                    ey: if j % 2 == 0 { 1.25 } else { 3.25 },
                    ez: 1.0,
                    fy: 1e3,
                    fz: -25e3,
                };
            }
            for _ in 0..3 {
                v.solve_step(&loads);
                sum += loads
                    .iter()
                    .map(|l| v.motion_at(l.x, l.ey, l.ez).z)
                    .sum::<f64>();
            }
            v.commit();
            sum += v.section_at(45.0).z + v.pier_base(2).map_or(0.0, |b| b.az);
        }
        let allocations = count() - before;
        assert!(
            sum < 0.0,
            "the loads (and the settlement) deflect the spans: {sum}"
        );
        assert_eq!(allocations, 0, "allocations in the viaduct time loop");
    }
}
