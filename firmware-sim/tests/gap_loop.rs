//! The firmware under `LawKind::GapLoop` runs the core's outer gap loop once per control
//! tick on each channel's sampled gap: bit for bit `GapLoop::update` compiled for
//! `Δt = 1/rate` (I4F28), and different from the paper's law on the same samples.

use maglev_core::gap_control::GapState;
use maglev_core::scalar::I4F28;
use maglev_core::{Interpolation, Params, Scalar, Scheme};
use maglev_firmware_sim::heapless::Vec as HVec;
use maglev_firmware_sim::protocol::*;
use maglev_firmware_sim::server::Server;

/// 0–20 mm over 16 bits with h0 = 10 mm: the per-unit gap of code c is exactly c/32768.
const LSB: f64 = 0.02 / 65536.0;
const TICKS: usize = 10;
const RATE: u32 = 10_000;
const GAP0: f64 = 0.0105;

fn inner_params() -> Params {
    Params {
        i0: 43.0,
        h0: 0.01,
        r0: 1.0,
        kp: 0.01,
        ki: 6.0,
        p0: 36787.5,
        alpha: 0.5,
        dt: 1.0 / RATE as f64,
        n_sub: 1,
        interpolation: Interpolation::Linear,
        v_max: f64::INFINITY,
        scheme: Scheme::Paper,
    }
}

fn config(law: LawKind) -> Config {
    let p = inner_params();
    let mut channels = HVec::new();
    channels
        .push(ChannelInit {
            p0: p.p0,
            gap: GAP0,
        })
        .unwrap();
    Config {
        scalar: ScalarKind::I4F28,
        rate_hz: RATE,
        ticks_per_step: TICKS as u16,
        delay: false,
        i0: p.i0,
        h0: p.h0,
        r0: p.r0,
        kp: p.kp,
        ki: p.ki,
        alpha: p.alpha,
        v_max: p.v_max,
        law,
        channels,
        adc_bits: 16,
        adc_lsb_m: LSB,
        adc_offset_m: 0.0,
        pwm_bits: 12,
        v_dc: 200.0,
        hold_ticks: 20,
        stuck_ticks: 0,
        ramp_ticks: 50,
        watchdog_ticks: 0,
        geometry: Geometry::Ems,
        guidance: None,
    }
}

fn gap_loop() -> LawKind {
    LawKind::GapLoop(GapParams::designed())
}

/// The code of tick `k`: the gap steps 0.1 mm open, then oscillates by a few codes.
fn code(k: usize) -> u16 {
    let c0 = (GAP0 / LSB).round() as i32 + 328;
    (c0 + [0, 3, -2, 5, 1, -4, 2][k % 7]) as u16
}

/// `g_q28` of channel 0 after each of `steps` committed steps.
fn firmware_run(law: LawKind, steps: usize) -> Vec<i32> {
    let mut s = Server::new();
    let mut seq = 1;
    let mut call = |msg| {
        seq += 1;
        s.handle(&Envelope {
            version: VERSION,
            seq,
            msg,
        })
        .msg
    };
    assert!(matches!(
        call(Request::Config(config(law))),
        Response::Ready { channels: 1 }
    ));
    let mut out = Vec::new();
    for n in 0..steps {
        let codes = (0..TICKS).map(|j| code(n * TICKS + j)).collect();
        let step = n as u32 + 1;
        match call(Request::Step { step, codes }) {
            Response::Reply(r) => out.push(r.channels[0].g_q28),
            other => panic!("{other:?}"),
        }
        assert_eq!(call(Request::Commit { step }), Response::Committed { step });
    }
    out
}

#[test]
fn firmware_gap_loop_is_the_cores_loop_once_per_tick() {
    let steps = 30;
    let fw = firmware_run(gap_loop(), steps);
    let law = inner_params().compile::<I4F28>().unwrap();
    let outer = GapParams::designed()
        .compile::<I4F28>(1.0 / RATE as f64)
        .unwrap();
    let inner = law.equilibrium_state(GAP0);
    let mut st = GapState {
        inner,
        q: inner.eta,
    };
    let mut want = Vec::new();
    let mut ov = false;
    for n in 0..steps {
        let mut g = 0;
        for j in 0..TICKS {
            let h = I4F28::from_f64(code(n * TICKS + j) as f64 / 32768.0, &mut ov);
            let o = outer.update(&law, &mut st, h);
            assert!(o.inner.status.is_empty() && !o.reference_limited);
            g = (o.inner.g.to_f64() * (1u64 << 28) as f64).round() as i32;
        }
        want.push(g);
    }
    assert!(!ov);
    assert_eq!(fw, want);
    // The gap opened by 0.1 mm: the gap loop raises the flux above the paper's law's.
    let paper = firmware_run(LawKind::Paper, steps);
    assert_ne!(fw, paper);
    assert!(fw[steps - 1] > paper[steps - 1], "{fw:?} vs {paper:?}");
}
