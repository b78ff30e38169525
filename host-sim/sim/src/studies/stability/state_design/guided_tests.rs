//! The guidance law's rows in the linear vehicle model against two independent references:
//! the closed-form poles of the pole placement on a bare guided magnet, and a lateral
//! quarter car written out by hand.

use super::{place, place_guidance};
use crate::physics::vehicle::{Fig1, VehicleModel};
use crate::studies::stability::vehicle::*;
use crate::studies::stability::Complex;
use maglev_core::gap::Geometry;
use maglev_core::law::state::StateParams;
use maglev_core::levitation::GRAVITY;
use maglev_core::LawKind;
use maglev_core::Params;
use nalgebra::DMatrix;

fn inner() -> Params {
    Params::paper_wheel(1e-4)
}

fn base() -> StateParams {
    StateParams {
        kp: 0.0,
        kd: 0.0,
        ka: 0.0,
        ki: 0.0,
        kc: 0.0,
        v_max: 500.0,
        rate_hz: 1e4,
        observer_hz: 300.0,
        geometry: Geometry::Ems,
    }
}

/// Every pole of `want` is within `tol·|s|` of one of `all`.
fn contains(all: &[Complex], want: &[Complex], tol: f64) {
    for s in want {
        let d = all
            .iter()
            .map(|a| ((a.re - s.re).powi(2) + (a.im - s.im).powi(2)).sqrt())
            .fold(f64::INFINITY, f64::min);
        assert!(d < tol * s.abs().max(1.0), "{s:?} not among {all:?}");
    }
}

/// The poles the placement puts the bare magnet's loop at: `ω·(−ζ ± j√(1 − ζ²))`, `−ω`,
/// `−ρ·ω` with `ω = r·√c`, `c = 2·p0/(M·h0)`.
fn placed(c: f64, (r, zeta, rho): (f64, f64, f64)) -> Vec<Complex> {
    let w = r * c.sqrt();
    let im = w * (1.0 - zeta * zeta).sqrt();
    vec![
        Complex { re: -zeta * w, im },
        Complex {
            re: -zeta * w,
            im: -im,
        },
        Complex { re: -w, im: 0.0 },
        Complex {
            re: -rho * w,
            im: 0.0,
        },
    ]
}

/// A bare magnet of mass `m` (vertical and lateral DOFs, no springs) with the levitation
/// law and the guidance law placed at different candidates: its nine poles are the four of
/// each placement in closed form (the guidance pair's differential mode with `c = 4·p0/(m·h0)`)
/// and the common mode's `−(1 + Kc)/τ` (G2); no zero pole. Under the levitation law on each
/// guidance magnet instead, the common-mode integral's pole at 0 is there.
#[test]
fn a_bare_guided_magnet_has_the_placed_poles_and_no_zero_pole() {
    let m = 800.0;
    let v = crate::studies::stability::vehicle::tests::bare_magnet(m);
    let p = Params {
        p0: m * GRAVITY,
        ..inner()
    };
    let (lev_c, guide_c) = ((1.5, 0.7, 0.2), (2.0, 0.5, 0.3));
    let lev = place(m, p.p0, &p, &base(), lev_c);
    let guide = place_guidance(m, p.p0, &p, &base(), guide_c);
    let law = LawKind::State(lev);
    let plant = VehiclePlant::guided(&v, &p, &law, Some(&guide), Geometry::Ems).unwrap();
    assert_eq!(plant.a.nrows(), 9);
    assert_eq!(plant.states.len(), 9);
    let poles = plant.poles().unwrap();
    let tau = 2.0 * p.p0 * p.h0 / (p.r0 * p.i0 * p.i0);
    let c = 2.0 * p.p0 / (m * p.h0);
    let mut want = placed(c, lev_c);
    want.extend(placed(2.0 * c, guide_c));
    want.push(Complex {
        re: -(1.0 + guide.kc * p.i0 / p.v_base()) / tau,
        im: 0.0,
    });
    contains(&poles, &want, 1e-8);
    assert_eq!(Verdict::of(poles).zero_poles, 0);
    // The per-magnet law on the pair (the guidance gains ignored): a pole at 0.
    let old = VehiclePlant::new(&v, &p, &law, Geometry::Ems).unwrap();
    assert_eq!(old.verdict().unwrap().zero_poles, 1);
}

/// The Fig. 1 car with its CoM on the target line: a lateral translation of body and wheels
/// exerts no roll moment, so the car's poles include those of one lateral quarter car — a
/// wheel of mass `m` on the spring and damper to a quarter body, its guidance pair under the
/// guidance law with a lateral accelerometer — written out here by hand (states `y_w, y_b,
/// ẏ_w, ẏ_b, x_L, x_R, u`).
#[test]
fn lateral_is_the_hand_written_quarter_car_under_the_guidance_law() {
    let m = 500.0;
    let fig = Fig1 {
        body_height: 0.0,
        wheel_mass: m,
        ..Fig1::default()
    };
    let v = VehicleModel::fig1(&fig, GRAVITY).unwrap();
    let p = Params {
        p0: v.p0[0],
        ..inner()
    };
    let lev = place(m, p.p0, &p, &base(), (1.5, 0.7, 0.2));
    let mut g = place_guidance(m, p.p0, &p, &base(), (2.0, 0.7, 0.2));
    g.ka = 30.0;
    let plant =
        VehiclePlant::guided(&v, &p, &LawKind::State(lev), Some(&g), Geometry::Ems).unwrap();
    let all = plant.poles().unwrap();

    let (k, c, mb) = (fig.k, fig.c, fig.body_mass / 4.0);
    let (h0, vb, i0) = (p.h0, p.v_base(), p.i0);
    let tau = 2.0 * p.p0 * h0 / (p.r0 * i0 * i0);
    let (kp, kd, ki, kc) = (
        g.kp * h0 / vb,
        g.kd * h0 / vb,
        g.ki * h0 / vb,
        g.kc * i0 / vb,
    );
    // Rows: wheel acceleration a_w over the state (F_y = 2·p0·(x_R − x_L) under EMS).
    let f = 2.0 * p.p0;
    let aw = [-k / m, k / m, -c / m, c / m, -f / m, f / m, 0.0];
    let ab = [k / mb, -k / mb, c / mb, -c / mb, 0.0, 0.0, 0.0];
    let mut dvd = [0.0; 7];
    let mut dvc = [0.0; 7];
    for j in 0..7 {
        dvd[j] = g.ka / vb * aw[j];
    }
    // Kp·η_d + Kd·η̇_d + u − Kc·Δi_d, η_d = y_w/h0, Δi_d = (x_L − x_R)/2 + y_w/h0.
    dvd[0] += (kp - kc) / h0;
    dvd[2] += kd / h0;
    dvd[6] += 1.0;
    dvd[4] -= 0.5 * kc;
    dvd[5] += 0.5 * kc;
    // −Kc·Δi_c, Δi_c = (x_L + x_R)/2.
    dvc[4] = -0.5 * kc;
    dvc[5] = -0.5 * kc;
    let mut a = DMatrix::zeros(7, 7);
    a[(0, 2)] = 1.0;
    a[(1, 3)] = 1.0;
    for j in 0..7 {
        a[(2, j)] = aw[j];
        a[(3, j)] = ab[j];
        a[(4, j)] = (dvc[j] + dvd[j]) / tau;
        a[(5, j)] = (dvc[j] - dvd[j]) / tau;
    }
    // The gaps: η_L = y_w/h0, η_R = −y_w/h0.
    a[(4, 0)] -= 1.0 / (h0 * tau);
    a[(5, 0)] += 1.0 / (h0 * tau);
    a[(4, 4)] -= 1.0 / tau;
    a[(5, 5)] -= 1.0 / tau;
    a[(6, 0)] = ki / h0;
    let quarter = crate::studies::stability::eigenvalues(&a).unwrap();
    contains(&all, &quarter, 1e-7);
    assert!(quarter.iter().all(|s| s.re < 0.0), "{quarter:?}");
    assert_eq!(plant.verdict().unwrap().zero_poles, 0);
}
