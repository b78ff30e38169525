//! The server's protocol semantics and fault reactions, driven with synthetic ADC codes, and
//! the `maglev-firmware` host process answering exactly like the in-process server.

use maglev_firmware_sim::heapless::Vec as HVec;
use maglev_firmware_sim::protocol::*;
use maglev_firmware_sim::server::Server;
use maglev_firmware_sim::supervision::{Event, Mode};
use std::io::{Read, Write};
use std::process::{Command, Stdio};

const LSB: f64 = 0.02 / 65536.0;
const CH: usize = 3;
const TICKS: usize = 10;

fn config(scalar: ScalarKind) -> Config {
    let mut channels = HVec::new();
    for k in 0..CH {
        channels
            .push(ChannelInit {
                p0: 36787.5,
                gap: 0.01 + 1e-4 * k as f64,
            })
            .unwrap();
    }
    Config {
        scalar,
        rate_hz: 10_000,
        ticks_per_step: TICKS as u16,
        delay: false,
        i0: 43.0,
        h0: 0.01,
        r0: 1.0,
        kp: 0.01,
        ki: 6.0,
        alpha: 0.5,
        v_max: f64::INFINITY,
        law: LawKind::Paper,
        channels,
        adc_bits: 16,
        adc_lsb_m: LSB,
        adc_offset_m: 0.0,
        pwm_bits: 12,
        v_dc: 200.0,
        hold_ticks: 20,
        stuck_ticks: 100,
        ramp_ticks: 50,
        watchdog_ticks: 0,
        geometry: Geometry::Ems,
        guidance: None,
    }
}

/// Codes for a gap moving sinusoidally (a few µm) around each channel's initial gap, with a
/// per-tick wobble so that no code sticks.
fn codes(step: u32, override_ch0: Option<u16>) -> HVec<u16, MAX_SAMPLES> {
    let mut v = HVec::new();
    for j in 0..TICKS {
        let t = (step as usize * TICKS + j) as f64 * 1e-4;
        for k in 0..CH {
            let h = 0.01 + 1e-4 * k as f64 + 5e-6 * (40.0 * t).sin() + ((j + k) % 3) as f64 * LSB;
            let c = (h / LSB).round() as u16;
            v.push(if k == 0 { override_ch0.unwrap_or(c) } else { c })
                .unwrap();
        }
    }
    v
}

fn env(seq: u32, msg: Request) -> Envelope<Request> {
    Envelope {
        version: VERSION,
        seq,
        msg,
    }
}

fn reply(r: Envelope<Response>) -> Reply {
    match r.msg {
        Response::Reply(rep) => rep,
        other => panic!("expected a reply, got {other:?}"),
    }
}

#[test]
fn step_restarts_from_committed_and_retransmissions_are_cached() {
    let mut s = Server::new();
    assert!(matches!(
        s.handle(&env(1, Request::Config(config(ScalarKind::I4F28))))
            .msg,
        Response::Ready { channels: 3 }
    ));
    let a = reply(s.handle(&env(
        2,
        Request::Step {
            step: 1,
            codes: codes(1, None),
        },
    )));
    // A Newton iteration with other codes, then the first codes again: same as the first.
    let b = reply(s.handle(&env(
        3,
        Request::Step {
            step: 1,
            codes: codes(7, None),
        },
    )));
    assert_ne!(a, b);
    let c = reply(s.handle(&env(
        4,
        Request::Step {
            step: 1,
            codes: codes(1, None),
        },
    )));
    assert_eq!(a, c);
    // Retransmission of seq 4 answered from the cache even after the state moved.
    assert!(matches!(
        s.handle(&env(5, Request::Commit { step: 1 })).msg,
        Response::Committed { step: 1 }
    ));
    assert_eq!(
        s.handle(&env(5, Request::Commit { step: 1 })).msg,
        Response::Committed { step: 1 }
    );
    // A late duplicate of an older request is not executed.
    assert_eq!(
        s.handle(&env(
            3,
            Request::Step {
                step: 1,
                codes: codes(7, None)
            }
        ))
        .msg,
        Response::Nack(Nack::Stale)
    );
    // Commit of a step that was not run.
    assert_eq!(
        s.handle(&env(6, Request::Commit { step: 9 })).msg,
        Response::Nack(Nack::BadRequest)
    );
    // Wrong sample count.
    let mut short = codes(2, None);
    short.pop();
    assert_eq!(
        s.handle(&env(
            7,
            Request::Step {
                step: 2,
                codes: short
            }
        ))
        .msg,
        Response::Nack(Nack::BadRequest)
    );
}

#[test]
fn unconfigured_and_bad_config_are_refused() {
    let mut s = Server::new();
    assert_eq!(
        s.handle(&env(1, Request::Commit { step: 1 })).msg,
        Response::Nack(Nack::NotConfigured)
    );
    let mut cfg = config(ScalarKind::I4F28);
    cfg.channels.clear();
    assert_eq!(
        s.handle(&env(2, Request::Config(cfg))).msg,
        Response::Nack(Nack::BadConfig(ConfigFault {
            key: ConfigKey::Channels,
            channel: None,
            problem: Problem::OutOfRange,
        }))
    );
    let mut old = env(3, Request::Ping);
    old.version = 0;
    assert_eq!(s.handle(&old).msg, Response::Nack(Nack::Version));
}

/// Runs `steps` committed steps with channel 0 replaced from step `from` on.
fn run_with(ch0: u16, from: u32, steps: u32) -> std::vec::Vec<Reply> {
    let mut s = Server::new();
    s.handle(&env(1, Request::Config(config(ScalarKind::I4F28))));
    let mut seq = 1;
    let mut out = std::vec::Vec::new();
    for step in 1..=steps {
        seq += 1;
        let o = if step >= from { Some(ch0) } else { None };
        out.push(reply(s.handle(&env(
            seq,
            Request::Step {
                step,
                codes: codes(step, o),
            },
        ))));
        seq += 1;
        s.handle(&env(seq, Request::Commit { step }));
    }
    out
}

fn mid(r: &Reply, k: usize) -> i32 {
    r.channels[k].duty as i32 - 4095 / 2
}

#[test]
fn contact_faults_at_once_then_voltage_ramps_to_zero() {
    let r = run_with(0, 5, 14);
    assert!(r[..4].iter().all(|x| x.events & Event::FAULT.0 == 0));
    assert!(r[4].events & (Event::CONTACT.0 | Event::FAULT.0) == Event::CONTACT.0 | Event::FAULT.0);
    assert_eq!(r[4].mode, Mode::Ramp as u8);
    // 50-tick ramp = 5 steps: |V| falls monotonically on every channel, then 0 V, mode Off.
    for k in 0..CH {
        let v: std::vec::Vec<i32> = r[4..].iter().map(|x| mid(x, k).abs()).collect();
        assert!(v.windows(2).all(|w| w[1] <= w[0]), "channel {k}: {v:?}");
    }
    assert_eq!(r[9].mode, Mode::Off as u8);
    assert!(r[9..].iter().all(|x| (0..CH).all(|k| mid(x, k).abs() <= 1)));
}

#[test]
fn out_of_range_holds_for_hold_ticks_then_faults() {
    let r = run_with(65535, 5, 10);
    // 20 hold ticks = steps 5 and 6 hold; the 21st bad tick (step 7, first tick) faults.
    assert!(r[4].events & Event::HOLD.0 != 0 && r[4].events & Event::FAULT.0 == 0);
    assert!(r[5].events & Event::FAULT.0 == 0);
    assert!(r[6].events & Event::FAULT.0 != 0);
    assert_eq!(r[6].mode, Mode::Ramp as u8);
}

#[test]
fn stuck_sensor_is_detected_then_held_then_faults() {
    // A constant code: 100 repeats (10 steps) to detect, then 20 held ticks, then fault.
    let r = run_with(30000, 1, 14);
    let first = |e: Event| r.iter().position(|x| x.events & e.0 != 0).map(|i| i + 1);
    assert_eq!(first(Event::STUCK), Some(11));
    assert_eq!(first(Event::FAULT), Some(13));
}

#[test]
fn fixed_and_float_firmware_agree_closely() {
    let run = |k| {
        let mut s = Server::new();
        s.handle(&env(1, Request::Config(config(k))));
        reply(s.handle(&env(
            2,
            Request::Step {
                step: 1,
                codes: codes(1, None),
            },
        )))
    };
    let (a, b) = (run(ScalarKind::I4F28), run(ScalarKind::F32));
    for k in 0..CH {
        let d = (a.channels[k].g_q28 - b.channels[k].g_q28).abs() as f64 / (1u64 << 28) as f64;
        assert!(d < 1e-5, "channel {k}: {d}");
    }
}

#[test]
fn host_process_answers_bit_identically() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_maglev-firmware"))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("spawn maglev-firmware");
    let mut stdin = child.stdin.take().unwrap();
    let mut stdout = child.stdout.take().unwrap();
    let mut local = Server::new();
    let mut reader = FrameReader::new();
    let mut seq = 0;
    let mut call = |msg: Request| {
        seq += 1;
        let e = env(seq, msg);
        let mut buf = [0u8; MAX_FRAME];
        let n = encode(&e, &mut buf).unwrap();
        stdin.write_all(&buf[..n]).unwrap();
        stdin.flush().unwrap();
        let mut byte = [0u8; 1];
        let remote: Envelope<Response> = loop {
            stdout.read_exact(&mut byte).unwrap();
            if let Some(f) = reader.push(byte[0]) {
                break decode(f.unwrap()).unwrap();
            }
        };
        assert_eq!(remote, local.handle(&e));
    };
    call(Request::Config(config(ScalarKind::I4F28)));
    for step in 1..=30 {
        let o = (step > 20).then_some(0);
        call(Request::Step {
            step,
            codes: codes(step + 3, o),
        });
        call(Request::Step {
            step,
            codes: codes(step, o),
        });
        call(Request::Commit { step });
    }
    call(Request::Config(config(ScalarKind::F32)));
    call(Request::Step {
        step: 1,
        codes: codes(1, None),
    });
    drop(stdin);
    assert!(child.wait().unwrap().success());
}

/// The refusal of a Config changed by `f`, in both scalar types (they must agree).
fn refusal(f: impl Fn(&mut Config)) -> Option<ConfigFault> {
    let mut out = None;
    for scalar in [ScalarKind::I4F28, ScalarKind::F32] {
        let mut cfg = config(scalar);
        f(&mut cfg);
        let got = match Server::new().handle(&env(1, Request::Config(cfg))).msg {
            Response::Ready { .. } => None,
            Response::Nack(Nack::BadConfig(fault)) => Some(fault),
            other => panic!("unexpected {other:?}"),
        };
        if scalar == ScalarKind::F32 {
            assert_eq!(got, out, "f32 and i4f28 refuse alike");
        }
        out = got;
    }
    out
}

#[test]
fn every_config_value_is_validated_by_name() {
    use ConfigKey::*;
    use Problem::*;
    let at = |key, problem| {
        Some(ConfigFault {
            key,
            channel: None,
            problem,
        })
    };
    let on = |key, k, problem| {
        Some(ConfigFault {
            key,
            channel: Some(k),
            problem,
        })
    };
    assert_eq!(refusal(|_| {}), None);
    // adc_bits = 1 once panicked in `clamp(1, 0)`; 0 and 17 are out of range too.
    for bits in [0, 1, 17, 255] {
        assert_eq!(
            refusal(|c| c.adc_bits = bits),
            at(AdcBits, OutOfRange),
            "{bits}"
        );
    }
    assert_eq!(refusal(|c| c.adc_bits = 2), on(Gap, 0, OutOfRange)); // 4 codes: 0..1.2 µm
    assert_eq!(refusal(|c| c.rate_hz = 0), at(Rate, OutOfRange));
    assert_eq!(
        refusal(|c| c.ticks_per_step = 0),
        at(TicksPerStep, OutOfRange)
    );
    assert_eq!(
        refusal(|c| c.ticks_per_step = 401),
        at(TicksPerStep, OutOfRange)
    );
    assert_eq!(refusal(|c| c.adc_lsb_m = f64::NAN), at(AdcLsb, NotFinite));
    assert_eq!(refusal(|c| c.adc_lsb_m = -1e-6), at(AdcLsb, OutOfRange));
    assert_eq!(
        refusal(|c| c.adc_offset_m = f64::INFINITY),
        at(AdcOffset, NotFinite)
    );
    assert_eq!(refusal(|c| c.pwm_bits = 0), at(PwmBits, OutOfRange));
    assert_eq!(refusal(|c| c.pwm_bits = 17), at(PwmBits, OutOfRange));
    assert_eq!(refusal(|c| c.v_dc = 0.0), at(VDc, OutOfRange));
    assert_eq!(refusal(|c| c.v_dc = f64::NAN), at(VDc, NotFinite));
    // hold_ticks = 65535 once turned escalation off.
    assert_eq!(refusal(|c| c.hold_ticks = 65535), at(HoldTicks, OutOfRange));
    assert_eq!(refusal(|c| c.hold_ticks = 10_000), None);
    assert_eq!(refusal(|c| c.stuck_ticks = 1), at(StuckTicks, OutOfRange));
    assert_eq!(refusal(|c| c.ramp_ticks = 0), at(RampTicks, OutOfRange));
    assert_eq!(
        refusal(|c| c.watchdog_ticks = TICKS as u16),
        at(WatchdogTicks, OutOfRange)
    );
    assert_eq!(refusal(|c| c.watchdog_ticks = TICKS as u16 + 1), None);
    // A NaN gap was accepted once; a gap outside the sensor's range is refused too.
    assert_eq!(
        refusal(|c| c.channels[2].gap = f64::NAN),
        on(Gap, 2, NotFinite)
    );
    assert_eq!(
        refusal(|c| c.channels[1].gap = 0.03),
        on(Gap, 1, OutOfRange)
    );
    assert_eq!(
        refusal(|c| c.channels[2].p0 = f64::NAN),
        on(P0, 2, NotFinite)
    );
    assert_eq!(refusal(|c| c.channels[0].p0 = -1.0), on(P0, 0, OutOfRange));
    // The law's parameters, through the core's checks.
    assert_eq!(refusal(|c| c.i0 = f64::NAN), at(I0, NotFinite));
    assert_eq!(refusal(|c| c.h0 = 0.0), at(H0, OutOfRange));
    assert_eq!(refusal(|c| c.r0 = f64::INFINITY), at(R0, NotFinite));
    assert_eq!(refusal(|c| c.kp = -1.0), at(Kp, OutOfRange));
    assert_eq!(refusal(|c| c.ki = f64::NAN), at(Ki, NotFinite));
    assert_eq!(refusal(|c| c.alpha = 1.5), at(Alpha, OutOfRange));
    assert_eq!(refusal(|c| c.v_max = f64::NAN), at(VMax, NotFinite));
    assert_eq!(
        refusal(|c| c.law = LawKind::GapLoop(GapParams {
            kp: f64::NAN,
            kd: 0.0,
            tf: 0.0,
            x_ref_max: 0.1
        })),
        at(GapLoop, NotFinite)
    );
    // The message names the key and its limit.
    let f = refusal(|c| c.adc_bits = 1).unwrap();
    assert_eq!(f.to_string(), "adc_bits is out of range (accepted: 2..=16)");
}

#[test]
fn link_loss_watchdog_starts_the_fault_reaction_and_latches() {
    let mut s = Server::new();
    let mut cfg = config(ScalarKind::I4F28);
    cfg.watchdog_ticks = 30;
    cfg.ramp_ticks = 20;
    assert!(matches!(
        s.handle(&env(1, Request::Config(cfg))).msg,
        Response::Ready { .. }
    ));
    let mut seq = 2;
    let mut run = |s: &mut Server, step: u32| -> Reply {
        let Response::Reply(r) = s
            .handle(&env(
                seq,
                Request::Step {
                    step,
                    codes: codes(step, None),
                },
            ))
            .msg
        else {
            panic!("step refused")
        };
        s.handle(&env(seq + 1, Request::Commit { step }));
        seq += 2;
        r
    };
    let before = run(&mut s, 1);
    assert_eq!(before.mode, Mode::Normal as u8);
    // The timer runs on; Steps keep the watchdog quiet.
    for _ in 0..25 {
        assert_eq!(s.timer_tick(), 0);
    }
    run(&mut s, 2);
    for _ in 0..30 {
        assert_eq!(s.timer_tick(), 0, "within watchdog_ticks of the last Step");
    }
    // Period 31 without a Step: link lost, fault reaction.
    let e = Event(s.timer_tick());
    assert!(
        e.contains(Event::LINK_LOST) && e.contains(Event::FAULT),
        "{e:?}"
    );
    // The reaction runs on the timer: the ramp reaches 0 V after ramp_ticks periods.
    for _ in 0..19 {
        let e = Event(s.timer_tick());
        assert!(e.contains(Event::LINK_LOST) && !e.contains(Event::FAULT));
    }
    // Latched: a Step after the link returns still reports the fault mode, coils at 0 V.
    let after = run(&mut s, 3);
    assert_eq!(after.mode, Mode::Off as u8);
    let mid = ((1u32 << 12) - 1) as u16 / 2;
    for ch in &after.channels {
        assert!(
            ch.duty.abs_diff(mid) <= 1,
            "0 V is mid duty, got {}",
            ch.duty
        );
    }
    // A new Config clears it.
    let mut cfg = config(ScalarKind::I4F28);
    cfg.watchdog_ticks = 30;
    assert!(matches!(
        s.handle(&env(100, Request::Config(cfg))).msg,
        Response::Ready { .. }
    ));
    assert_eq!(s.timer_tick(), 0);
}

/// The state law with gains for this magnet (those of host-sim/cli/tests/state_law.rs).
fn state_config(scalar: ScalarKind) -> Config {
    use maglev_core::law::state::StateParams;
    Config {
        law: LawKind::State(StateParams {
            kp: 51_600.0,
            kd: 1_600.0,
            ka: 40.0,
            ki: 4_300.0,
            kc: 10.0,
            v_max: 500.0,
            rate_hz: 10_000.0,
            observer_hz: 300.0,
            geometry: Geometry::Ems,
        }),
        ..config(scalar)
    }
}

/// `StepAccel`: channel 0 wired, one code a tick (`g` g of specific force, as the part reads).
fn step_accel(step: u32, g: f64, wired: u16, per_tick: usize) -> Request {
    let code = maglev_firmware_sim::accel::AccelModel.code((g - 1.0) * 9.81);
    let mut accel = HVec::new();
    for _ in 0..TICKS * per_tick {
        accel.push(code).unwrap();
    }
    Request::StepAccel {
        step,
        codes: codes(step, None),
        wired,
        accel,
    }
}

#[test]
fn step_accel_feeds_the_state_law_and_checks_its_shape() {
    let mut s = Server::new();
    assert!(matches!(
        s.handle(&env(1, Request::Config(state_config(ScalarKind::F32))))
            .msg,
        Response::Ready { channels: 3 }
    ));
    // At rest (+1 g) and with the magnet accelerating upward at 0.5 g: channel 0's voltage
    // (duty) differs, the unwired channels do not.
    let rest = reply(s.handle(&env(2, step_accel(1, 1.0, 0b001, 1))));
    let up = reply(s.handle(&env(3, step_accel(1, 1.5, 0b001, 1))));
    assert_ne!(rest.channels[0], up.channels[0]);
    assert_eq!(rest.channels[1..], up.channels[1..]);
    // The same request again gives the same reply (it starts from the committed state).
    assert_eq!(rest, reply(s.handle(&env(4, step_accel(1, 1.0, 0b001, 1)))));
    // Too few or too many codes, or a wired channel that does not exist: refused.
    for (seq, req) in [
        (5, step_accel(1, 1.0, 0b011, 1)),
        (6, step_accel(1, 1.0, 0b001, 2)),
        (7, step_accel(1, 1.0, 0b1000, 1)),
    ] {
        assert_eq!(
            s.handle(&env(seq, req)).msg,
            Response::Nack(Nack::BadRequest)
        );
    }
    // Fixed point cannot hold the state law: refused by its key.
    match s
        .handle(&env(8, Request::Config(state_config(ScalarKind::I4F28))))
        .msg
    {
        Response::Nack(Nack::BadConfig(f)) => assert_eq!(f.key, ConfigKey::StateLaw),
        other => panic!("{other:?}"),
    }
}
