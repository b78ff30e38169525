//! A dense Newmark integrator written in the tests, independently of the code's, shared by
//! the support-motion tests (`support_motion.rs`, `support_spans.rs`) as their second method.

use nalgebra::{DMatrix, DVector};

/// Dense average-acceleration Newmark of M ẍ + C ẋ + K x = F(t_n) from rest, written here
/// independently of the code's (LU of the dense effective stiffness); `each(n, d_n)` after
/// every step.
pub fn dense_newmark(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
    c: &DMatrix<f64>,
    dt: f64,
    steps: usize,
    load: impl Fn(usize) -> DVector<f64>,
    mut each: impl FnMut(usize, &DVector<f64>),
) {
    let (a0, a1, a2) = (4.0 / (dt * dt), 2.0 / dt, 4.0 / dt);
    let keff = (k + m * a0 + c * a1).lu();
    let n = k.nrows();
    let (mut d, mut v, mut a) = (DVector::zeros(n), DVector::zeros(n), DVector::zeros(n));
    for step in 1..=steps {
        let f = load(step) + m * (&d * a0 + &v * a2 + &a) + c * (&d * a1 + &v);
        let d1 = keff.solve(&f).unwrap();
        let acc1 = (&d1 - &d) * a0 - &v * a2 - &a;
        v += (&a + &acc1) * (dt / 2.0);
        a = acc1;
        d = d1;
        each(step, &d);
    }
}
