//! The multi-loop disk margin against closed forms and the SISO disk margin.

use super::*;

/// `L = k/(s(s+1))`: `A_ol = [[0, 1], [0, −1]]`, `B = e_2`, `F = [−k, 0]`.
fn second_order(k: f64) -> (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>) {
    (
        DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, -1.0]),
        DMatrix::from_row_slice(2, 1, &[0.0, 1.0]),
        DMatrix::from_row_slice(1, 2, &[-k, 0.0]),
    )
}

/// `|S − 1/2|² = ((u + k)² + u)/(4((u − k)² + u))`, `u = ω²`, is largest at `u = k`, where it is
/// `(4k + 1)/4`: α = 2/√(4k + 1) (derived in the test's doc, docs/levitation.md).
fn closed_form(k: f64) -> f64 {
    2.0 / (4.0 * k + 1.0).sqrt()
}

fn names(n: usize) -> Vec<String> {
    (0..n).map(|i| format!("l{i}")).collect()
}

#[test]
fn one_loop_is_the_siso_disk_margin_closed_form() {
    for k in [0.5, 4.0, 30.0] {
        let (a_ol, b, f) = second_order(k);
        let cut = Cut {
            a_ol,
            b,
            f,
            delay: 0.0,
        };
        let d = disk_margin(&cut, names(1)).unwrap();
        let alpha = d.alpha.unwrap();
        assert!((alpha - closed_form(k)).abs() < 1e-9, "{k}: {d:?}");
        assert!(
            (d.peak_rad_per_s.unwrap() - k.sqrt()).abs() < 1e-4 * k.sqrt(),
            "{d:?}"
        );
        let g = 20.0 * ((2.0 + alpha) / (2.0 - alpha)).log10();
        assert!((d.gain_db.unwrap() - g).abs() < 1e-12);
        assert!((d.phase_deg.unwrap() - 2.0 * (alpha / 2.0).atan().to_degrees()).abs() < 1e-12);
    }
}

/// A loop with an unstable pole, `L = k/(s + a)`, `a < 0 < a + k`: `|S − 1/2|` is largest at
/// ω = 0, `(k − a)/(2(k + a))`, and the disk's lower gain limit `(2 − α)/(2 + α)` is then
/// exactly the loop's true one, `−a/k` (the pole `−(a + κk)` crosses at `κ = −a/k`).
#[test]
fn an_unstable_plant_s_margin_peaks_at_zero_frequency() {
    let (a, k) = (-1.0, 3.0);
    let cut = Cut {
        a_ol: DMatrix::from_element(1, 1, -a),
        b: DMatrix::from_element(1, 1, 1.0),
        f: DMatrix::from_element(1, 1, -k),
        delay: 0.0,
    };
    let d = disk_margin(&cut, names(1)).unwrap();
    let alpha = d.alpha.unwrap();
    assert!((alpha - 2.0 * (k + a) / (k - a)).abs() < 1e-12, "{d:?}");
    assert!(((2.0 - alpha) / (2.0 + alpha) - (-a / k)).abs() < 1e-12);
}

/// With a delay, against the SISO disk margin `2/max|S − T|` of the hand-written
/// `L = k·e^(−sT)/(s(s+1))` on a grid 100× finer than the margin's.
#[test]
fn one_loop_with_a_delay_is_the_siso_disk_margin() {
    let (k, t) = (4.0, 0.05);
    let (a_ol, b, f) = second_order(k);
    let d = disk_margin(
        &Cut {
            a_ol,
            b,
            f,
            delay: t,
        },
        names(1),
    )
    .unwrap();
    let mut worst: f64 = 0.0;
    for i in 0..=600_000 {
        let w = 10f64.powf(-2.0 + i as f64 / 100_000.0);
        let s = Complex::new(0.0, w);
        let l = Complex::new(k, 0.0) * (-s * t).exp() / (s * (s + 1.0));
        let st = (Complex::new(1.0, 0.0) - l) / (Complex::new(1.0, 0.0) + l);
        worst = worst.max(st.norm());
    }
    let truth = 2.0 / worst;
    assert!(
        (d.alpha.unwrap() - truth).abs() < 1e-7 * truth,
        "{d:?} {truth}"
    );
}

/// Two loops, `L = diag(L1, L2)` and the same with loop 2 driving loop 1 (triangular `L`):
/// either way `μ(S − I/2)` is the larger diagonal entry, so the multi-loop margin is the
/// smaller SISO margin. The unscaled `σ̄` of the triangular case is far larger: the diagonal
/// scaling is what removes it.
#[test]
fn two_decoupled_or_triangular_loops_give_the_smaller_siso_margin() {
    let (k1, k2) = (4.0, 1.0);
    for coupling in [0.0, 50.0] {
        let mut a_ol = DMatrix::zeros(4, 4);
        let (a1, b1, f1) = second_order(k1);
        let (a2, b2, f2) = second_order(k2);
        a_ol.view_mut((0, 0), (2, 2)).copy_from(&a1);
        a_ol.view_mut((2, 2), (2, 2)).copy_from(&a2);
        a_ol[(1, 2)] = coupling; // loop 2's state into loop 1
        let mut b = DMatrix::zeros(4, 2);
        b.view_mut((0, 0), (2, 1)).copy_from(&b1);
        b.view_mut((2, 1), (2, 1)).copy_from(&b2);
        let mut f = DMatrix::zeros(2, 4);
        f.view_mut((0, 0), (1, 2)).copy_from(&f1);
        f.view_mut((1, 2), (1, 2)).copy_from(&f2);
        let cut = Cut {
            a_ol,
            b,
            f,
            delay: 0.0,
        };
        let d = disk_margin(&cut, names(2)).unwrap();
        let want = closed_form(k1).min(closed_form(k2));
        assert!(
            (d.alpha.unwrap() - want).abs() < 1e-6 * want,
            "{coupling}: {d:?}"
        );
        if coupling > 0.0 {
            let m = cut.m_at(k1.sqrt()).unwrap();
            let plain = m.singular_values().max();
            assert!(1.0 / plain < 0.5 * want, "{plain}");
        }
    }
}

/// The bundled unit's one loop: the margin equals `2/max|S − T|` of the loop-at-a-time
/// margins' own `L(jω)` ([`super::super::margins::BrokenLoop`]) on a grid 20× finer.
#[test]
fn the_unit_s_multi_loop_margin_is_its_siso_disk_margin() {
    use super::super::margins::BrokenLoop;
    use super::super::report::DELAY_PERIODS;
    let case = crate::studies::design::load("unit", &["run.model=rigid".to_string()]).unwrap();
    let (v, _, _) = super::super::vehicle::vehicle_of(&case).unwrap();
    let inner = case.controller.unwrap();
    let law = case.law().unwrap();
    let plant = VehiclePlant::new(&v, &inner, &law, case.geometry).unwrap();
    let delay = DELAY_PERIODS * law.control_period(&inner, case.dt);
    let d = vehicle_disk_margin(&plant, delay).unwrap();
    assert_eq!(d.loops, ["lev1"]);
    let lp = BrokenLoop::new(&plant, 0, delay).unwrap();
    let mut worst: f64 = 0.0;
    for i in 0..=16_000 {
        let w = 10f64.powf(-2.0 + i as f64 / 2000.0);
        let l = lp.at_freq(w);
        let one = Complex::new(1.0, 0.0);
        worst = worst.max(((one - l) / (one + l)).norm());
    }
    let truth = 2.0 / worst;
    assert!(
        (d.alpha.unwrap() - truth).abs() < 1e-5 * truth,
        "{d:?} {truth}"
    );
}

/// The descent's bound on a non-normal 6 × 6 matrix against a second method, coordinate
/// descent (golden section on each `log d_k`, sweeps until no gain): at least as tight
/// (coordinate descent stalls where `σ̄(D·M·D⁻¹)`, convex in `log d`, is not smooth: the top
/// singular value repeated), tighter than Osborne's scaling alone, and never below the
/// spectral radius, a lower bound of `μ` (`Δ = I/ρ(M)` up to a phase).
#[test]
fn the_descent_is_at_least_as_tight_as_coordinate_descent() {
    let n = 6;
    let v = |i: usize, j: usize| ((i * 7 + j * 3) as f64 * 0.83).sin();
    let m = DMatrix::from_fn(n, n, |i, j| {
        let scale = if j > i { 30.0 } else { 1.0 };
        Complex::new(v(i, j), v(j, i + 1)) * scale
    });
    let mut d = super::osborne(&m);
    let osborne = super::scaled_norm(&m, &d);
    let mut best = osborne;
    for _ in 0..50 {
        let before = best;
        for i in 0..n {
            let (x, val) = super::golden(d[i] - 3.0, d[i] + 3.0, |x| {
                let mut e = d.clone();
                e[i] = x;
                super::scaled_norm(&m, &e)
            });
            if val < best {
                best = val;
                d[i] = x;
            }
        }
        if before - best <= 1e-12 * before {
            break;
        }
    }
    let got = super::mu_upper(&m, true);
    assert!(
        osborne > best * (1.0 + 1e-3),
        "Osborne's {osborne} already at {best}"
    );
    assert!(
        got <= best * (1.0 + 1e-9),
        "descent {got}, coordinate descent {best}"
    );
    let rho = m
        .clone()
        .schur()
        .eigenvalues()
        .unwrap()
        .iter()
        .map(|e| e.norm())
        .fold(0.0, f64::max);
    assert!(got >= rho, "the bound {got} is below ρ(M) = {rho}");
}

/// A rank-one `M = x·yᴴ` has `μ = Σ|x_i|·|y_i|` for diagonal complex `Δ`, and the scaled
/// bound reaches it (`d_i² = |y_i|/|x_i|`, Cauchy–Schwarz): the descent finds it to 1e-9 on
/// twelve loops.
#[test]
fn a_rank_one_matrix_s_mu_is_its_closed_form() {
    let n = 12;
    let x: Vec<Complex<f64>> = (0..n)
        .map(|i| Complex::from_polar(0.2 + (i as f64 * 0.7).sin().abs() * 3.0, i as f64))
        .collect();
    let y: Vec<Complex<f64>> = (0..n)
        .map(|i| Complex::from_polar(0.1 + (i as f64 * 1.3).cos().abs(), 0.5 * i as f64))
        .collect();
    let m = DMatrix::from_fn(n, n, |i, j| x[i] * y[j].conj());
    let want: f64 = (0..n).map(|i| x[i].norm() * y[i].norm()).sum();
    let got = super::mu_upper(&m, true);
    assert!(got >= want * (1.0 - 1e-12), "{got} below μ = {want}");
    assert!(got <= want * (1.0 + 1e-9), "{got} vs μ = {want}");
}
