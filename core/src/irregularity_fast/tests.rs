//! The table against the direct sum (Eq. 3) it replaces.

extern crate std;
use super::*;
use crate::irregularity::{Direction, PsdParams};
use std::vec;
use std::vec::Vec;

fn direct() -> Irregularity<f64> {
    Irregularity::new(&PsdParams::TABLE1_Z, Direction::Z, 11).unwrap()
}

/// Relative RMS error of a table with spacing `h` against the direct sum at 1500 points
/// spread over `length` m (a step incommensurate with `h`), and the module's bound.
fn rel_rms(h: f64, length: f64) -> (f64, f64) {
    let g = direct();
    let x0 = -1.0;
    let n = ((length + 2.0) / h) as usize + 4;
    let mut buf = vec![0.0; n];
    let mut ov = false;
    fill(&g, x0, h, &mut buf, &mut ov);
    let t = Table::new(x0, h, buf).unwrap();
    let (mut e2, mut r2) = (0.0, 0.0);
    for k in 0..1500 {
        let x = k as f64 * length / 1500.0 * 0.999_731;
        let mut out = false;
        let want = g.eval(x, &mut ov);
        let got = t.eval(x, &mut out, &mut ov);
        assert!(!out);
        e2 += (got - want) * (got - want);
        r2 += want * want;
    }
    assert!(!ov);
    ((e2 / r2).sqrt(), rms_error_bound(g.terms(), h))
}

#[test]
fn table_matches_the_direct_sum_within_the_bound() {
    // The shortest wavelength is 1 m: 20 m holds 20 of them, 200 m the longest (63 m) thrice.
    for (h, length) in [(0.005, 20.0), (0.05, 200.0), (0.1, 200.0)] {
        let (e, bound) = rel_rms(h, length);
        std::println!("h = {h} m: relative RMS error {e:.3e}, bound {bound:.3e}");
        // The bound takes every term at its worst phase in the cell; an RMS over x averages
        // u over [0, 1) and cannot exceed it, save for rounding (~1e-16 of r).
        assert!(e <= bound + 1e-14, "h = {h}: {e:e} > {bound:e}");
        assert!(e <= 1e-4);
    }
    // The bound itself at Table 1, by hand from the module docs: 2.9e-5 at 10 cm.
    let b = rms_error_bound(direct().terms(), 0.1);
    assert!((2.8e-5..3.0e-5).contains(&b), "{b:e}");
}

#[test]
fn nodes_are_exact_and_outside_is_flagged() {
    let g = direct();
    let mut s = [0.0f64; 64];
    let mut ov = false;
    fill(&g, 2.0, 0.05, &mut s, &mut ov);
    let t: FixedTable<f64, 64> = Table::new(2.0, 0.05, s).unwrap();
    let mut out = false;
    // Interior nodes (x0 + h itself may round into the first cell, which has no left node).
    for (j, node) in s.iter().enumerate().take(62).skip(2) {
        let x = 2.0 + j as f64 * 0.05;
        let got = t.eval(x, &mut out, &mut ov);
        // At a node u is 0 or within rounding of it: the weights are (0, 1, 0, 0) to ~1e-15.
        assert!((got - node).abs() < 1e-15, "node {j}");
    }
    assert!(!out);
    let (lo, hi) = t.range();
    assert!((lo - 2.05).abs() < 1e-12 && (hi - (2.0 + 62.0 * 0.05)).abs() < 1e-12);
    for x in [lo - 1e-3, hi + 0.05, f64::NAN] {
        let mut out = false;
        assert_eq!(t.eval(x, &mut out, &mut ov), 0.0);
        assert!(out);
    }
    assert_eq!(
        Table::<f64, _>::new(0.0, 0.0, [0.0; 8]).err(),
        Some(TableError::BadGrid)
    );
    assert_eq!(
        Table::<f64, _>::new(0.0, 0.1, [0.0; 3]).err(),
        Some(TableError::TooShort)
    );
}

#[test]
fn f32_fixed_capacity_table_follows_f64() {
    // An f32 table filled from the f32 direct sum, near the origin (small x keeps f32's phase
    // error ~|x|·f·2⁻²³ turns negligible): differences are the f32 sum's own rounding and
    // micromath's cosine (≤ 0.002 absolute per term, random in sign: ~0.002·RMS(a)·√N).
    let g64 = direct();
    let g32: Irregularity<f32> = Irregularity::new(&PsdParams::TABLE1_Z, Direction::Z, 11).unwrap();
    let mut s = [0.0f32; 256];
    let mut ov = false;
    fill(&g32, 0.0, 0.05, &mut s, &mut ov);
    let t: FixedTable<f32, 256> = Table::new(0.0, 0.05, s).unwrap();
    let a_rms =
        (g64.terms().iter().map(|t| t.amp * t.amp).sum::<f64>() / g64.terms().len() as f64).sqrt();
    let tol = 3.0 * 0.002 * a_rms * (g64.terms().len() as f64).sqrt();
    let xs: Vec<f64> = (0..500).map(|k| 0.1 + k as f64 * 0.0243).collect();
    let mut out = false;
    for x in xs {
        let got = t.eval(x, &mut out, &mut ov) as f64;
        let want = g64.eval(x, &mut ov);
        assert!((got - want).abs() < tol, "x = {x}: {got} vs {want}");
    }
    assert!(!out && !ov);
}

/// The plain-f64 evaluation gives `eval`'s bits wherever it answers, and answers everywhere
/// inside the range: 2000 points across a 64-sample table (nodes, cell interiors, both ends),
/// and `None` outside, at NaN, and on a table holding an infinite sample near it.
#[test]
fn nominal_eval_gives_the_bits_of_eval() {
    let g = direct();
    let mut s = [0.0f64; 64];
    let mut ov = false;
    fill(&g, 2.0, 0.05, &mut s, &mut ov);
    let t: FixedTable<f64, 64> = Table::new(2.0, 0.05, s).unwrap();
    let (lo, hi) = t.range();
    for k in 0..2000 {
        let x = lo - 0.2 + (hi - lo + 0.4) * k as f64 / 1999.0;
        let (mut out, mut ov) = (false, false);
        let want = t.eval(x, &mut out, &mut ov);
        match t.eval_nominal(x) {
            Some(got) => {
                assert_eq!(got.to_bits(), want.to_bits(), "x = {x}");
                assert!(!out && !ov);
            }
            None => assert!(out, "x = {x} inside the range, but no nominal value"),
        }
    }
    assert_eq!(t.eval_nominal(f64::NAN), None);
    let mut bad = s;
    bad[30] = f64::INFINITY;
    let t: FixedTable<f64, 64> = Table::new(2.0, 0.05, bad).unwrap();
    let x = 2.0 + 30.2 * 0.05;
    assert_eq!(t.eval_nominal(x), None);
    let (mut out, mut ov) = (false, false);
    t.eval(x, &mut out, &mut ov);
    assert!(
        ov,
        "the checked evaluation flags what the nominal one declines"
    );
}
