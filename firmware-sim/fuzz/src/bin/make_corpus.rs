//! Writes the seed corpus (`corpus/decode`, `corpus/handler`): valid requests of every kind
//! in the handler's input format, and their frames for the decoder. Run once from
//! `firmware-sim/fuzz`: `cargo run --bin make-corpus`; the files are committed.
use maglev_firmware_sim::heapless::Vec as HVec;
use maglev_firmware_sim::protocol::*;
use std::fs;

fn config(scalar: ScalarKind, law: LawKind) -> Config {
    let mut channels = HVec::new();
    // One Fig. 1 wheel: levitation and the guidance pair.
    for gap in [0.01, 0.0101, 0.0099] {
        channels.push(ChannelInit { p0: 36787.5, gap }).unwrap();
    }
    Config {
        scalar,
        rate_hz: 10_000,
        ticks_per_step: 2,
        delay: false,
        i0: 43.0,
        h0: 0.01,
        r0: 1.0,
        kp: 0.01,
        ki: 6.0,
        alpha: 0.5,
        v_max: f64::INFINITY,
        law,
        channels,
        adc_bits: 16,
        adc_lsb_m: 0.02 / 65536.0,
        adc_offset_m: 0.0,
        pwm_bits: 12,
        v_dc: 200.0,
        hold_ticks: 2,
        stuck_ticks: 3,
        ramp_ticks: 4,
        watchdog_ticks: 3,
        geometry: Geometry::Ems,
        guidance: None,
    }
}

fn body(seq: u32, msg: Request) -> Vec<u8> {
    postcard::to_allocvec(&Envelope {
        version: VERSION,
        seq,
        msg,
    })
    .unwrap()
}

/// A `StepAccel` body (sequence `seq`) with channel 0's accelerometer wired.
fn step_accel(
    seq: u32,
    step: u32,
    codes: HVec<u16, MAX_SAMPLES>,
    accel: HVec<i16, MAX_SAMPLES>,
) -> Vec<u8> {
    body(
        seq,
        Request::StepAccel {
            step,
            codes,
            wired: 0b001,
            accel,
        },
    )
}

fn prefixed(bodies: &[Vec<u8>]) -> Vec<u8> {
    let mut v = Vec::new();
    for b in bodies {
        v.extend_from_slice(&(b.len() as u16).to_le_bytes());
        v.extend_from_slice(b);
    }
    v
}

fn main() {
    let gap_loop = LawKind::GapLoop(GapParams {
        kp: 2.0,
        kd: 0.02,
        tf: 0.002,
        x_ref_max: 0.5,
    });
    let codes = |c: u16| -> HVec<u16, MAX_SAMPLES> {
        let mut v = HVec::new();
        for k in 0..6 {
            v.push(c + k % 3).unwrap();
        }
        v
    };
    let mut seeds: Vec<(&str, Vec<Vec<u8>>)> = Vec::new();
    for (name, scalar, law) in [
        ("paper-i4f28", ScalarKind::I4F28, LawKind::Paper),
        ("paper-f32", ScalarKind::F32, LawKind::Paper),
        ("gaploop-i4f28", ScalarKind::I4F28, gap_loop),
    ] {
        seeds.push((
            name,
            vec![
                body(1, Request::Config(config(scalar, law))),
                body(
                    2,
                    Request::Step {
                        step: 1,
                        codes: codes(32768),
                    },
                ),
                body(3, Request::Commit { step: 1 }),
                body(
                    4,
                    Request::Step {
                        step: 2,
                        codes: codes(0),
                    },
                ),
                body(
                    4,
                    Request::Step {
                        step: 2,
                        codes: codes(0),
                    },
                ),
                body(5, Request::Ping),
            ],
        ));
    }
    // The state law (f32) with channel 0's accelerometer: StepAccel, 2 ticks × 1 code.
    let state = LawKind::State(StateParams {
        kp: 51_600.0,
        kd: 1_600.0,
        ka: 40.0,
        ki: 4_300.0,
        kc: 10.0,
        v_max: 500.0,
        rate_hz: 10_000.0,
        observer_hz: 300.0,
        geometry: Geometry::Ems,
    });
    let accel = |z: i16| -> HVec<i16, MAX_SAMPLES> { HVec::from_slice(&[z, z + 1]).unwrap() };
    seeds.push((
        "state-f32",
        vec![
            body(1, Request::Config(config(ScalarKind::F32, state))),
            step_accel(2, 1, codes(32768), accel(2049)),
            body(3, Request::Commit { step: 1 }),
            step_accel(4, 2, codes(32770), accel(-30000)),
            body(5, Request::Ping),
        ],
    ));
    // The designed Fig. 6 carriage's laws (docs/levitation.md): the state law on the
    // levitation channel, the guidance law on the pair (channels 1 and 2).
    let designed = LawKind::State(StateParams {
        kp: 345_418.9,
        kd: 2_710.3,
        ka: 0.0,
        ki: 1_523_272.0,
        kc: 50.19,
        v_max: 500.0,
        rate_hz: 10_000.0,
        observer_hz: 300.0,
        geometry: Geometry::Ems,
    });
    let mut guided = config(ScalarKind::F32, designed);
    guided.guidance = Some(GuidanceParams {
        kp: 94_873.7,
        kd: 1_482.2,
        ka: 0.0,
        ki: 3_308.5,
        kc: 20.34,
    });
    seeds.push((
        "state-guided-f32",
        vec![
            body(1, Request::Config(guided)),
            step_accel(2, 1, codes(32768), accel(2049)),
            body(3, Request::Commit { step: 1 }),
            body(5, Request::Ping),
        ],
    ));
    seeds.push(("ping", vec![body(1, Request::Ping)]));
    fs::create_dir_all("corpus/handler").unwrap();
    fs::create_dir_all("corpus/decode").unwrap();
    for (name, bodies) in &seeds {
        fs::write(format!("corpus/handler/{name}"), prefixed(bodies)).unwrap();
        for (k, b) in bodies.iter().enumerate() {
            let frame = maglev_firmware_fuzz::frame_body(b).unwrap();
            fs::write(
                format!("corpus/decode/{name}-{k}"),
                &frame[..frame.len() - 1],
            )
            .unwrap();
        }
    }
}
