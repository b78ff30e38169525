//! The banded/sparse FE guideway (free response once per step, one sparse solve per
//! iteration on loaded spans, lazy velocity/acceleration) against a dense reference: the
//! previous implementation's algorithm (dense K and M assembled here from the element
//! matrices, dense Cholesky of the effective stiffness, the full Newmark step per
//! `solve_step`). Same physics, other arithmetic: the two must agree to round-off.

use maglev_core::gap::{DOFS_PER_NODE, ELEMENT_DOFS};
use maglev_host_sim::fe::element;
use maglev_host_sim::fe::{FeGuideway, Rayleigh, SpanModel};
use maglev_host_sim::guideway::{
    BeamSection, Bridge, Guideway, PointLoad, PointMotion, SectionMotion,
};
use maglev_host_sim::simulation::{simulate, Load, Outcome, Profiles};
use nalgebra::{Cholesky, DMatrix, DVector, Dyn};

/// Dense reference: every span is a dense system, stepped in full at every `solve_step`.
struct DenseFe {
    dt: f64,
    model: SpanModel,
    m: DMatrix<f64>,
    c: Option<DMatrix<f64>>,
    keff: Cholesky<f64, Dyn>,
    starts: Vec<f64>,
    /// Per span (d, v, a) committed and trial.
    committed: Vec<[DVector<f64>; 3]>,
    trial: Vec<[DVector<f64>; 3]>,
}

impl DenseFe {
    fn new(bridge: &Bridge, elements: usize, dt: f64, damping: Option<Rayleigh>) -> Self {
        let length = bridge.spans[0];
        assert!(
            bridge.spans.iter().all(|&l| l == length),
            "equal spans only"
        );
        let model = SpanModel::new(&bridge.section, length, elements).unwrap();
        let n = model.free_dofs();
        let le = length / elements as f64;
        let ke = element::stiffness(&bridge.section, le);
        let me = element::mass(&bridge.section, le);
        let (mut k, mut m) = (DMatrix::zeros(n, n), DMatrix::zeros(n, n));
        for e in 0..elements {
            let free = |i: usize| model.free(e + i / DOFS_PER_NODE, i % DOFS_PER_NODE);
            for i in 0..ELEMENT_DOFS {
                for j in 0..ELEMENT_DOFS {
                    if let (Some(fi), Some(fj)) = (free(i), free(j)) {
                        k[(fi, fj)] += ke[(i, j)];
                        m[(fi, fj)] += me[(i, j)];
                    }
                }
            }
        }
        let c = damping.map(|r| &m * r.alpha + &k * r.beta);
        let mut keff = &k + &m * (4.0 / (dt * dt));
        if let Some(c) = &c {
            keff += c * (2.0 / dt);
        }
        let zero = || [DVector::zeros(n), DVector::zeros(n), DVector::zeros(n)];
        let mut starts = vec![0.0];
        for l in &bridge.spans[..bridge.spans.len() - 1] {
            starts.push(starts.last().unwrap() + l);
        }
        DenseFe {
            dt,
            model,
            m,
            c,
            keff: Cholesky::new(keff).unwrap(),
            committed: bridge.spans.iter().map(|_| zero()).collect(),
            trial: bridge.spans.iter().map(|_| zero()).collect(),
            starts,
        }
    }

    fn find(&self, x: f64) -> Option<(usize, f64)> {
        let i = self.starts.partition_point(|&s| s <= x).checked_sub(1)?;
        let local = x - self.starts[i];
        (local <= self.model.length * (1.0 + 1e-12)).then(|| (i, local.min(self.model.length)))
    }
}

impl Guideway for DenseFe {
    fn time_step(&self) -> f64 {
        self.dt
    }

    fn solve_step(&mut self, loads: &[PointLoad]) {
        let n = self.model.free_dofs();
        let mut f = vec![DVector::zeros(n); self.starts.len()];
        for p in loads {
            if let Some((i, local)) = self.find(p.x) {
                self.model
                    .add_point_force(local, p.ey, p.ez, p.fy, p.fz, &mut f[i]);
            }
        }
        let dt = self.dt;
        let (a0, a1, a2) = (4.0 / (dt * dt), 2.0 / dt, 4.0 / dt);
        for (i, f) in f.into_iter().enumerate() {
            let [d, v, a] = &self.committed[i];
            let mut rhs = f + &self.m * (d * a0 + v * a2 + a);
            if let Some(c) = &self.c {
                rhs += c * (d * a1 + v);
            }
            let d1 = self.keff.solve(&rhs);
            let acc1 = (&d1 - d) * a0 - v * a2 - a;
            let v1 = v + (a + &acc1) * (dt / 2.0);
            self.trial[i] = [d1, v1, acc1];
        }
    }

    fn motion_at(&self, x: f64, ey: f64, ez: f64) -> PointMotion {
        self.find(x)
            .and_then(|(i, l)| self.model.motion(&self.trial[i][0], l, ey, ez))
            .unwrap_or_default()
    }

    fn section_at(&self, x: f64) -> SectionMotion {
        self.find(x)
            .and_then(|(i, l)| self.model.section(&self.trial[i][0], l))
            .unwrap_or_default()
    }

    fn commit(&mut self) {
        self.committed.clone_from(&self.trial);
    }
}

/// Largest |a − b| over the series, divided by the largest |b|.
fn rel_history(a: &[f64], b: &[f64]) -> f64 {
    let peak = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let diff = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(peak > 0.0);
    diff / peak
}

/// Drives both guideways with the same loads (three `solve_step` trials per step, the last
/// one the committed, as a Newton–Raphson loop does) and records the midspan of every span
/// and the motion under every load.
fn drive(
    a: &mut impl Guideway,
    b: &mut impl Guideway,
    spans: &[f64],
    steps: usize,
    loads_at: impl Fn(usize, u32) -> Vec<PointLoad>,
) -> f64 {
    let (mut ha, mut hb) = (Vec::new(), Vec::new());
    for n in 1..=steps {
        for trial in 0..3 {
            let loads = loads_at(n, trial);
            a.solve_step(&loads);
            b.solve_step(&loads);
            for l in &loads {
                let (ma, mb) = (a.motion_at(l.x, l.ey, l.ez), b.motion_at(l.x, l.ey, l.ez));
                ha.extend([ma.y, ma.z]);
                hb.extend([mb.y, mb.z]);
            }
        }
        a.commit();
        b.commit();
        let mut x0 = 0.0;
        for l in spans {
            let (sa, sb) = (a.section_at(x0 + l / 2.0), b.section_at(x0 + l / 2.0));
            ha.extend([sa.y, sa.z, sa.rx]);
            hb.extend([sb.y, sb.z, sb.rx]);
            x0 += l;
        }
    }
    rel_history(&ha, &hb)
}

/// A moving force (eccentric, with a lateral share) at 100 m/s over one 25 m span, 20
/// elements, Δt = 1 ms, then free vibration: every midspan and under-load value within
/// 1e-12 of the peak.
#[test]
fn moving_force_matches_dense_reference() {
    let bridge = Bridge {
        section: BeamSection::paper_4_2(),
        spans: vec![25.0],
    };
    let mut fe = FeGuideway::new(&bridge, 20, 1e-3).unwrap();
    let mut dense = DenseFe::new(&bridge, 20, 1e-3, None);
    let err = drive(&mut fe, &mut dense, &bridge.spans, 400, |n, trial| {
        let x = 0.1 * n as f64;
        if x > 25.0 {
            return vec![];
        }
        vec![PointLoad {
            x,
            ey: 1.5,
            ez: 0.6,
            fy: 2e3 * (1.0 + 0.1 * trial as f64),
            fz: -36.8e3 * (1.0 - 0.05 * trial as f64),
        }]
    });
    println!("moving force, banded vs dense: {err:.2e} of the peak");
    assert!(err <= 1e-12, "{err}");
}

/// A 16-load car (25 kN at 1.5625 m) over three 30 m spans with Rayleigh damping, 16
/// elements per span, Δt = 2 ms: spans at rest, loaded, and vibrating freely all occur.
#[test]
fn train_over_three_damped_spans_matches_dense_reference() {
    let bridge = Bridge {
        section: BeamSection::paper_4_2(),
        spans: vec![30.0; 3],
    };
    let damping = Some(Rayleigh {
        alpha: 0.1,
        beta: 2e-4,
    });
    let dt = 2e-3;
    let mut fe = FeGuideway::with_damping(&bridge, 16, dt, damping).unwrap();
    let mut dense = DenseFe::new(&bridge, 16, dt, damping);
    let err = drive(&mut fe, &mut dense, &bridge.spans, 700, |n, trial| {
        let lead = 83.33 * dt * n as f64;
        (0..16)
            .map(|j| PointLoad {
                x: lead - 1.5625 * j as f64,
                ey: 1.5,
                ez: 0.6,
                fy: 0.0,
                fz: -25e3 * (1.0 + 0.01 * trial as f64),
            })
            .filter(|l| l.x >= 0.0)
            .collect()
    });
    println!("16 loads over 3 damped spans, banded vs dense: {err:.2e} of the peak");
    assert!(err <= 1e-12, "{err}");
}

fn passage(g: &mut impl Guideway) -> Outcome {
    let case = maglev_host_sim::case::Case::load("paper-4.2", &["scheme=accurate".into()]).unwrap();
    let settings = maglev_host_sim::setup::Passage::new(&case)
        .unwrap()
        .settings;
    let v = case.vehicle_train().unwrap().unwrap();
    // A rail with a smooth but non-trivial irregularity so the Newton–Raphson loop works.
    let profiles = Profiles {
        y: Box::new(|x: f64| 1e-3 * (0.7 * x).sin()),
        z: Box::new(|x: f64| 2e-3 * (0.45 * x).cos()),
    };
    simulate(
        g,
        &Load::Vehicle(v),
        &profiles,
        &settings,
        &mut maglev_host_sim::probes::NoRecorder,
        |_| {},
    )
    .unwrap()
}

/// The §4.2 vehicle passage (Fig. 1 vehicle, 100 m/s, accurate scheme) through the coupling
/// loop: midspan and wheel-1 histories and iteration counts agree with the dense reference.
#[test]
fn vehicle_passage_matches_dense_reference() {
    let bridge = Bridge {
        section: BeamSection::paper_4_2(),
        spans: vec![25.0],
    };
    let mut fe = FeGuideway::new(&bridge, 20, 1e-3).unwrap();
    let mut dense = DenseFe::new(&bridge, 20, 1e-3, None);
    let (a, b) = (passage(&mut fe), passage(&mut dense));
    assert_eq!(a.records.len(), b.records.len());
    let it = |o: &Outcome| o.records.iter().map(|r| r.iterations).collect::<Vec<_>>();
    assert_eq!(it(&a), it(&b));
    assert!(it(&a).iter().any(|&i| i > 2), "the loop iterates");
    type Get = fn(&maglev_host_sim::simulation::Record) -> f64;
    let columns: [(&str, Get); 6] = [
        ("midspan z", |r| r.midspan.z),
        ("midspan y", |r| r.midspan.y),
        ("midspan rx", |r| r.midspan.rx),
        ("wheel 1 z", |r| r.wheel1_z),
        ("wheel 1 gap", |r| r.wheel1_gap_z - 0.01),
        ("wheel 1 force", |r| r.wheel1_force_z),
    ];
    for (name, get) in columns {
        let ha: Vec<f64> = a.records.iter().map(get).collect();
        let hb: Vec<f64> = b.records.iter().map(get).collect();
        let err = rel_history(&ha, &hb);
        println!("passage {name}: banded vs dense {err:.2e} of the peak");
        assert!(err <= 1e-12, "{name}: {err}");
    }
}

/// rayon over spans changes nothing: the trial states of every span are bit-identical with
/// and without it (a train of 32 loads over 5 spans, three trials per step).
#[test]
fn parallel_spans_are_bit_identical() {
    let bridge = Bridge {
        section: BeamSection::paper_4_2(),
        spans: vec![30.0; 5],
    };
    let run = |parallel: bool| {
        let mut fe = FeGuideway::new(&bridge, 16, 2e-3).unwrap();
        fe.set_parallel(parallel);
        for n in 1..=1200 {
            let lead = 83.33 * 2e-3 * n as f64;
            for trial in 0..3 {
                let loads: Vec<PointLoad> = (0..32)
                    .map(|j| PointLoad {
                        x: lead - 1.5625 * j as f64,
                        ey: 1.5,
                        ez: 0.6,
                        fy: 1e3,
                        fz: -25e3 * (1.0 + 0.01 * trial as f64),
                    })
                    .collect();
                fe.solve_step(&loads);
            }
            fe.commit();
        }
        (0..5)
            .map(|i| fe.trial_state(i).clone())
            .collect::<Vec<_>>()
    };
    let (a, b) = (run(false), run(true));
    assert!(a.iter().all(|s| s.d.iter().any(|&x| x != 0.0)));
    assert_eq!(a, b);
}
