//! The guidance pairs under the core's guidance law in the firmware (`Config::guidance`,
//! `maglev_firmware_sim::guide`): the pair's law reads the lateral offset from its two gap
//! sensors and the lateral accelerometer on its left magnet, drives both coils, and leaves the
//! levitation channel as it is without guidance.
//!
//! The reference runs the core's `GuidanceLaw` directly on the per-unit inputs the test
//! computes from the codes by the documented conversions: `h/h0 = code·lsb/h0` (exact in f64
//! for h0 = 0.01 m, lsb = 0.02/65536 m: `code/32768`), `d/h0 = (h_L − h_R)/(2·h0)`,
//! `a_y/g_n = code·0.488e-3` (no gravity on the lateral part).

use maglev_core::gap::Geometry;
use maglev_core::law::guidance::{GuidanceParams, PairMeasurement};
use maglev_core::law::state::StateParams;
use maglev_core::{LawKind, Params, Scheme};
use maglev_firmware_sim::accel::{AccelChip, AccelModel, LSB_G_16G};
use maglev_firmware_sim::adc::AdcChip;
use maglev_firmware_sim::board::{car_tick::car_config, state_law};
use maglev_firmware_sim::firmware::Firmware;
use maglev_firmware_sim::hbridge::HBridge;
use maglev_firmware_sim::heapless::Vec as HVec;
use maglev_firmware_sim::protocol::{Config, ConfigKey, ScalarKind, MAX_CHANNELS};

const H0: f64 = 0.01;
const LSB: f64 = 0.02 / 65536.0;
/// The pair's lateral offset at the start (m): left gap h0 + D, right h0 − D
/// (`car_tick::car_config`'s).
const D: f64 = 1e-4;

fn state() -> StateParams {
    state_law::gains()
}

fn gains() -> GuidanceParams {
    GuidanceParams {
        kp: 20_000.0,
        kd: 900.0,
        ka: 25.0,
        ki: 3_000.0,
        kc: 8.0,
    }
}

/// The first wheel of the Fig. 1 car's configuration (levitation at h0, the pair at h0 ± D)
/// under the state law, f32 on the wire.
fn config(guidance: Option<GuidanceParams>) -> Config {
    let mut cfg = car_config(
        ScalarKind::F32,
        f64::INFINITY,
        LawKind::State(state()),
        guidance,
    );
    cfg.channels.truncate(3);
    cfg
}

type Fw = Firmware<f64, AdcChip, HBridge, AccelChip>;

fn firmware(cfg: &Config) -> Result<Fw, maglev_firmware_sim::protocol::ConfigFault> {
    let n = cfg.channels.len();
    let mut pwm: HVec<HBridge, MAX_CHANNELS> = HVec::new();
    let mut accels: HVec<AccelChip, MAX_CHANNELS> = HVec::new();
    for _ in 0..n {
        let _ = pwm.push(HBridge::new(cfg.pwm_bits));
        let _ = accels.push(AccelChip::default());
    }
    Firmware::new(cfg, AdcChip::default(), pwm, accels)
}

/// Tick `t`'s codes: levitation still, the pair moving laterally by a few µm, lateral
/// acceleration codes changing sign.
fn inputs(t: usize) -> ([u16; 3], i16) {
    let d = D + 4e-6 * ((t % 7) as f64 - 3.0);
    let code = |h: f64| (h / LSB).round() as u16;
    let wobble = (t % 3) as u16;
    let a = 40 * ((t % 5) as i16 - 2);
    ([code(H0) + wobble, code(H0 + d), code(H0 - d)], a)
}

fn feed(fw: &mut Fw, codes: [u16; 3], a_y: i16) {
    for (k, &c) in codes.iter().enumerate() {
        fw.bus_mut().set_input(k, c);
    }
    fw.accel_mut(0).unwrap().set_sample(AccelModel.code(0.0)); // the levitation magnet at rest
    fw.accel_mut(1).unwrap().set_sample(a_y);
}

/// The pair's coils and law state follow the core's guidance law on the documented inputs.
#[test]
fn the_pair_runs_the_cores_guidance_law_on_both_gaps_and_the_lateral_accelerometer() {
    let cfg = config(Some(gains()));
    let mut fw = firmware(&cfg).unwrap();
    fw.wire_accelerometers(0b011);
    let magnet = Params {
        i0: cfg.i0,
        h0: H0,
        r0: cfg.r0,
        kp: cfg.kp,
        ki: cfg.ki,
        p0: cfg.channels[1].p0,
        alpha: cfg.alpha,
        dt: 1e-4,
        n_sub: 1,
        interpolation: maglev_core::Interpolation::Linear,
        v_max: cfg.v_max,
        scheme: Scheme::Paper,
    };
    let law = gains().compile::<f64>(&state(), &magnet).unwrap();
    let mut st = law.equilibrium(D);
    assert_eq!(fw.state().pairs[0], st, "equilibrium at the initial gaps");
    let mut moved = 0.0f64;
    for t in 0..200 {
        let (codes, a_y) = inputs(t);
        feed(&mut fw, codes, a_y);
        let events = fw.tick();
        assert_eq!(events.0, 0, "tick {t}");
        let d = (codes[1] as f64 - codes[2] as f64) / 65536.0;
        let m = PairMeasurement {
            d,
            accel: Some(a_y as f64 * LSB_G_16G),
        };
        law.update(&mut st, m, Geometry::Ems);
        let got = fw.state();
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * (1.0 + b.abs());
        for (a, b) in [
            (got.pairs[0].left.x, st.left.x),
            (got.pairs[0].right.x, st.right.x),
            (got.pairs[0].left.v, st.left.v),
            (got.pairs[0].right.v, st.right.v),
            (got.pairs[0].integral, st.integral),
            (got.pairs[0].rate_est, st.rate_est),
        ] {
            assert!(close(a, b), "tick {t}: firmware {a} core {b}");
        }
        // The outputs and duties are the pair's coils.
        assert_eq!(got.ch[1].law.inner, got.pairs[0].left);
        assert_eq!(got.ch[2].law.inner, got.pairs[0].right);
        moved = moved.max((st.left.v - st.right.v).abs());
    }
    assert!(
        moved > 1e-3,
        "the pair's differential voltage moved: {moved}"
    );
}

/// A left gap that opens raises the left voltage and lowers the right one (EMS: the pair
/// pulls the magnet back); the levitation channel is the same as without guidance.
#[test]
fn an_opening_left_gap_raises_the_left_voltage_and_the_levitation_channel_is_unchanged() {
    let mut guided = firmware(&config(Some(gains()))).unwrap();
    let mut plain = firmware(&config(None)).unwrap();
    for fw in [&mut guided, &mut plain] {
        fw.wire_accelerometers(0b001);
    }
    let step = 30e-6; // 30 µm more lateral offset
    let code = |h: f64| (h / LSB).round() as u16;
    let codes = [code(H0), code(H0 + D + step), code(H0 - D - step)];
    for fw in [&mut guided, &mut plain] {
        for _ in 0..3 {
            feed(fw, codes, 0);
            fw.tick();
        }
    }
    let (g, p) = (guided.state(), plain.state());
    let v0 = g.pairs[0].left.v; // the base is 1 (per unit) in equilibrium
    assert!(
        g.ch[1].law.inner.v > 1.0 && g.ch[2].law.inner.v < 1.0,
        "{v0}"
    );
    assert!(guided.output(1).duty > guided.output(2).duty);
    assert_eq!(g.ch[0], p.ch[0], "levitation channel");
    // Without guidance the pair's channels run their own laws (other voltages).
    assert_ne!(g.ch[1].law.inner.v, p.ch[1].law.inner.v);
}

/// Guidance outside the state law, channels not in threes, or a bad gain: refused by the
/// guidance key.
#[test]
fn a_guidance_the_firmware_cannot_pair_is_refused_by_its_key() {
    let mut paper = config(Some(gains()));
    paper.law = LawKind::Paper;
    let mut four = config(Some(gains()));
    let lev = four.channels[0];
    four.channels.push(lev).unwrap();
    let bad = config(Some(GuidanceParams {
        kd: -1.0,
        ..gains()
    }));
    for cfg in [paper, four, bad] {
        let fault = firmware(&cfg).err().expect("refused");
        assert_eq!(fault.key, ConfigKey::Guidance, "{fault}");
        assert!(
            fault.to_string().starts_with("controller.guidance "),
            "{fault}"
        );
    }
}
