//! A small dense linear system advanced by Newmark's average-acceleration rule (γ = ½, β = ¼,
//! model.md §7), for the vehicle. Zero-mass DOFs (massless maglev wheels) are allowed as
//! long as each has damping or stiffness: the effective matrix stays regular.
//!
//! Same protocol as [`crate::guideway::Guideway`]: `solve` restarts from the committed state
//! each call (one Newton–Raphson iteration), `commit` accepts the trial.

use nalgebra::{DMatrix, DVector, LU};

const GAMMA: f64 = 0.5;
const BETA: f64 = 0.25;

/// `M ü + C u̇ + K u = f` with a fixed step.
pub struct Newmark {
    dt: f64,
    m: DMatrix<f64>,
    c: DMatrix<f64>,
    keff: LU<f64, nalgebra::Dyn, nalgebra::Dyn>,
    /// Committed displacement, velocity, acceleration at t.
    pub u: DVector<f64>,
    pub v: DVector<f64>,
    pub a: DVector<f64>,
    /// Trial state at t + dt (valid after `solve`).
    pub u1: DVector<f64>,
    pub v1: DVector<f64>,
    pub a1: DVector<f64>,
}

impl Newmark {
    /// Starts at rest (u = v = a = 0: static equilibrium of a system written in deviations).
    /// Errors if the effective matrix is singular.
    pub fn new(m: DMatrix<f64>, c: DMatrix<f64>, k: DMatrix<f64>, dt: f64) -> Result<Self, String> {
        let n = m.nrows();
        let keff = &k + &c * (GAMMA / (BETA * dt)) + &m * (1.0 / (BETA * dt * dt));
        let lu = keff.lu();
        if !lu.is_invertible() {
            return Err("vehicle: effective stiffness is singular (a DOF with no mass, damping or stiffness)".into());
        }
        let z = DVector::zeros(n);
        Ok(Newmark {
            dt,
            m,
            c,
            keff: lu,
            u: z.clone(),
            v: z.clone(),
            a: z.clone(),
            u1: z.clone(),
            v1: z.clone(),
            a1: z,
        })
    }

    /// Solves the step for the load `f` at t + dt.
    pub fn solve(&mut self, f: &DVector<f64>) {
        let dt = self.dt;
        let (a0, a1, a2) = (
            1.0 / (BETA * dt * dt),
            1.0 / (BETA * dt),
            1.0 / (2.0 * BETA) - 1.0,
        );
        let (b0, b1, b2) = (
            GAMMA / (BETA * dt),
            GAMMA / BETA - 1.0,
            dt * (GAMMA / (2.0 * BETA) - 1.0),
        );
        let rhs = f
            + &self.m * (&self.u * a0 + &self.v * a1 + &self.a * a2)
            + &self.c * (&self.u * b0 + &self.v * b1 + &self.a * b2);
        let u1 = self.keff.solve(&rhs).expect("checked invertible in new");
        let a_new = (&u1 - &self.u) * a0 - &self.v * a1 - &self.a * a2;
        self.v1 = &self.v + (&self.a * (1.0 - GAMMA) + &a_new * GAMMA) * dt;
        self.a1 = a_new;
        self.u1 = u1;
    }

    /// Accepts the trial state.
    pub fn commit(&mut self) {
        self.u.copy_from(&self.u1);
        self.v.copy_from(&self.v1);
        self.a.copy_from(&self.a1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn single_oscillator_period_and_amplitude() {
        // m = 1, k = (2π)², free vibration from u(0)=0, v(0)=1: u = sin(2πt)/(2π).
        // Average acceleration conserves energy exactly and lags the phase by
        // (ωΔt)²/12 per radian: check both against those closed forms.
        let w = 2.0 * std::f64::consts::PI;
        let dt = 1e-3;
        let mut s = Newmark::new(
            DMatrix::from_element(1, 1, 1.0),
            DMatrix::zeros(1, 1),
            DMatrix::from_element(1, 1, w * w),
            dt,
        )
        .unwrap();
        s.v[0] = 1.0;
        let f = DVector::zeros(1);
        let steps = 1000;
        for _ in 0..steps {
            s.solve(&f);
            s.commit();
        }
        let energy = 0.5 * s.v[0] * s.v[0] + 0.5 * w * w * s.u[0] * s.u[0];
        assert!((energy - 0.5).abs() < 1e-12, "energy {energy}");
        // Numerical frequency: tan(ω̄Δt/2) = ωΔt/2.
        let wbar = 2.0 * (w * dt / 2.0).atan() / dt;
        let t = steps as f64 * dt;
        // Round-off over 1000 steps on an amplitude of 0.16 m: allow 1e-10 (≈ 6e-10 relative).
        assert!((s.u[0] - (wbar * t).sin() / w).abs() < 1e-10, "{}", s.u[0]);
    }
}
