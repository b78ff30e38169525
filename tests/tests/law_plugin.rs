//! A law written outside the core, behind its open interface (`maglev_core::Control`), runs
//! through the simulator's own magnets (`CoreMagnets::with_laws`) and its coupled time loop
//! with no change to either: a constant-voltage hold, which holds the coil at one voltage
//! whatever the gap.
//!
//! Checked against a closed form: at a constant gap `h` the coil of Eq. 9 under a constant
//! voltage `V`, `G0·dg/dt + R0·h·g = V` with `G0 = 2·K0`, relaxes exponentially,
//! `g(t) = g∞ + (g0 − g∞)·e^(−t/τ)`, `g∞ = V/(R0·h)`, `τ = G0/(R0·h)`, and the force is
//! `K0·g²` (Eq. 1).

use maglev_core::levitation::State;
use maglev_core::{Control, Levitation, Measurement, Output, ParamError, Params, Sensors};
use maglev_sim::input::case::Case;
use maglev_sim::probes::NoRecorder;
use maglev_sim::setup::Passage;
use maglev_sim::simulation::magnets::CoreMagnets;
use maglev_sim::simulation::{couple, Load, Magnets, Start};

/// Holds the coil at `V` (V): the paper's coil with no gains, its voltage `V_b·(1 + y)` with
/// `y` fixed.
struct Hold {
    coil: Levitation<f64>,
    y: f64,
}

impl Hold {
    fn new(magnet: Params, volts: f64) -> Result<Self, ParamError> {
        let coil = Params {
            kp: 0.0,
            ki: 0.0,
            v_max: f64::INFINITY,
            ..magnet
        }
        .compile::<f64>()?;
        Ok(Hold {
            coil,
            y: volts / magnet.v_base() - 1.0,
        })
    }
}

impl Control<f64> for Hold {
    type State = State<f64>;

    fn coil(&self) -> &Levitation<f64> {
        &self.coil
    }

    fn coil_state(st: &State<f64>) -> &State<f64> {
        st
    }

    fn coil_state_mut(st: &mut State<f64>) -> &mut State<f64> {
        st
    }

    fn sensors(&self) -> Sensors {
        Sensors::GAP
    }

    fn voltage_bound(&self) -> Option<f64> {
        None
    }

    fn control_period(&self) -> f64 {
        self.coil.params().dt / self.coil.params().n_sub as f64
    }

    /// The coil's flux at `g0` and the gap taken to have been `h`; the voltage the hold's.
    fn equilibrium_state(&self, h: f64) -> State<f64> {
        let mut st = self.coil.equilibrium_state(h);
        st.y = self.y;
        st.v = 1.0 + self.y;
        st
    }

    fn update(&self, st: &mut State<f64>, m: Measurement<f64>) -> Output<f64> {
        self.coil.update(st, m.gap)
    }
}

/// paper-4.2's car for `t_end` seconds, ten sub-steps a step.
fn case(t_end: f64) -> Case {
    Case::load(
        "paper-4.2",
        &[format!("t_end={t_end}"), "nsub=10".to_string()],
    )
    .unwrap()
}

/// At a gap held 10 % open, every levitation magnet's force follows the closed form over
/// 0.5 s (1.4 time constants), to 1e-7 of the force's change; the guidance pairs at `h0`
/// stay balanced.
#[test]
fn a_hold_written_here_runs_in_the_hosts_magnets() {
    let case = case(0.5);
    let p = Passage::new(&case).unwrap();
    let Load::Vehicle(train) = &p.load else {
        panic!("paper-4.2 runs a vehicle")
    };
    let s = &p.settings;
    let h0 = s.controller.h0;
    let h1 = 1.1 * h0;
    let volts = s.controller.v_base();
    let mut magnets = CoreMagnets::with_laws(move |_, m| Hold::new(m, volts));
    let gaps0 = vec![(h1, 0.0); train.wheels.len()];
    magnets
        .start(&Start {
            train,
            gaps: &gaps0,
            settings: s,
        })
        .unwrap();
    let gaps = vec![(h1, 0.0); train.wheels.len()];
    let accels = vec![0.0; train.wheels.len()];
    let mut out = vec![(0.0, 0.0); train.wheels.len()];
    let steps = (0.5 / s.dt).round() as u32;
    let mut worst: f64 = 0.0;
    for step in 1..=steps {
        let t = step as f64 * s.dt;
        magnets
            .forces(step, t, &gaps, &gaps, &accels, &mut out)
            .unwrap();
        magnets.commit(step, t).unwrap();
        for (&(fz, fy), &p0) in out.iter().zip(&train.p0) {
            let m = Params { p0, ..s.controller };
            let (g0, k0) = (m.g0(), m.k0());
            let g_inf = volts / (m.r0 * h1);
            let tau = 2.0 * k0 / (m.r0 * h1);
            let g = g_inf + (g0 - g_inf) * (-t / tau).exp();
            let want = k0 * g * g;
            let change = p0 - k0 * g_inf * g_inf;
            worst = worst.max(((fz - want) / change).abs());
            assert_eq!(fy, 0.0, "step {step}");
        }
    }
    assert!(
        worst < 1e-7,
        "largest error {worst:e} of the force's change"
    );
    // Every coil at the held voltage, never clamped.
    for c in magnets.coils().iter().flatten() {
        assert_eq!(c.voltage, volts);
        assert!(!c.saturated);
    }
}

/// Through the coupled time loop (guideway, vehicle, Newton–Raphson): every magnet's coil
/// is at the held voltage in every step, where the paper's law on the same case moves it.
#[test]
fn a_hold_written_here_runs_in_the_coupled_loop() {
    let case = case(0.05);
    let run = |hold: bool| {
        let mut p = Passage::new(&case).unwrap();
        let Load::Vehicle(train) = &p.load else {
            panic!("paper-4.2 runs a vehicle")
        };
        let s = &p.settings;
        let gaps0 = maglev_sim::simulation::initial_gaps(train, &p.profiles, s.controller.h0);
        let volts = s.controller.v_base();
        let mut magnets: Box<dyn Magnets> = if hold {
            Box::new(CoreMagnets::with_laws(move |_, m| Hold::new(m, volts)))
        } else {
            Box::new(CoreMagnets::new())
        };
        magnets
            .start(&Start {
                train,
                gaps: &gaps0,
                settings: s,
            })
            .unwrap();
        let outcome = couple(
            &mut p.guideway,
            train,
            &p.profiles,
            s,
            magnets.as_mut(),
            &mut NoRecorder,
            &mut (),
        )
        .unwrap();
        (outcome, volts)
    };
    let (held, volts) = run(true);
    assert_eq!(held.steps, 50);
    assert_eq!(held.coil_ranges.len(), 4);
    for c in held.coil_ranges.iter().flatten() {
        assert_eq!(c.peak_voltage, volts);
        assert_eq!(c.saturated_steps, 0);
    }
    let (paper, _) = run(false);
    let moved = paper
        .coil_ranges
        .iter()
        .flatten()
        .any(|c| c.peak_voltage > volts * (1.0 + 1e-6));
    assert!(
        moved,
        "the paper's law held its voltages too: the check sees nothing"
    );
}
