//! Newmark (γ = ½, β = ¼, average acceleration) for one small undamped system
//! M ẍ + K x = f with fixed step (docs/model.md §7, used per mode by the modal reference).
//!
//! Why per mode: the Galerkin modes of Eq. 20 decouple the span into independent 2-DOF
//! (bending) and 1-DOF (torsion) systems, so each is advanced on its own with its effective
//! stiffness K + M/(β Δt²) inverted once at construction.

use nalgebra::{SMatrix, SVector};

const GAMMA: f64 = 0.5;
const BETA: f64 = 0.25;

/// Displacement, velocity and acceleration of one N-DOF mode.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModeState<const N: usize> {
    pub d: SVector<f64, N>,
    pub v: SVector<f64, N>,
    pub a: SVector<f64, N>,
}

impl<const N: usize> ModeState<N> {
    /// At rest (zero initial conditions of Eq. 20).
    pub fn zero() -> Self {
        ModeState {
            d: SVector::zeros(),
            v: SVector::zeros(),
            a: SVector::zeros(),
        }
    }
}

/// Newmark stepper for M ẍ + K x = f, M and K constant.
#[derive(Clone, Debug)]
pub struct NewmarkMode<const N: usize> {
    mass: SMatrix<f64, N, N>,
    keff_inv: SMatrix<f64, N, N>,
    dt: f64,
}

impl<const N: usize> NewmarkMode<N> {
    /// `None` if the effective stiffness is singular (cannot happen for M > 0, K ≥ 0).
    pub fn new(mass: SMatrix<f64, N, N>, stiffness: SMatrix<f64, N, N>, dt: f64) -> Option<Self> {
        let keff = stiffness + mass / (BETA * dt * dt);
        Some(NewmarkMode {
            mass,
            keff_inv: keff.try_inverse()?,
            dt,
        })
    }

    /// One step from `s` (state at t) under the force `f` at t + Δt.
    #[inline]
    pub fn step(&self, s: &ModeState<N>, f: &SVector<f64, N>) -> ModeState<N> {
        let dt = self.dt;
        let c0 = 1.0 / (BETA * dt * dt);
        let c1 = 1.0 / (BETA * dt);
        let c2 = 1.0 / (2.0 * BETA) - 1.0;
        let rhs = f + self.mass * (s.d * c0 + s.v * c1 + s.a * c2);
        let d = self.keff_inv * rhs;
        let a = (d - s.d) * c0 - s.v * c1 - s.a * c2;
        let v = s.v + (s.a * (1.0 - GAMMA) + a * GAMMA) * dt;
        ModeState { d, v, a }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix1, Vector1};

    /// Free vibration of a 1-DOF oscillator: the average-acceleration rule conserves energy
    /// exactly and its period error is (ωΔt)²/12 to leading order, both closed-form facts
    /// about the method, not about this code.
    #[test]
    fn free_oscillator_conserves_energy_and_period() {
        let (m, k): (f64, f64) = (2.0, 800.0); // ω = 20 rad/s
        let w = (k / m).sqrt();
        let dt = 1e-3;
        let nm = NewmarkMode::new(Matrix1::new(m), Matrix1::new(k), dt).unwrap();
        let mut s = ModeState::<1> {
            d: Vector1::new(1.0),
            v: Vector1::new(0.0),
            a: Vector1::new(-k / m),
        };
        let e0 = 0.5 * k;
        let f = Vector1::new(0.0);
        // step to t = 2π/ω (one period); the discrete solution is cos(ω̃ t) with
        // ω̃ = (2/Δt) atan(ωΔt/2).
        let steps = (2.0 * core::f64::consts::PI / w / dt).round() as usize;
        for _ in 0..steps {
            s = nm.step(&s, &f);
            let e = 0.5 * k * s.d[0] * s.d[0] + 0.5 * m * s.v[0] * s.v[0];
            assert!((e - e0).abs() < 1e-9 * e0, "energy drift {e} vs {e0}");
        }
        let wt = 2.0 / dt * (w * dt / 2.0).atan();
        let expect = (wt * steps as f64 * dt).cos();
        assert!((s.d[0] - expect).abs() < 1e-9, "{} vs {expect}", s.d[0]);
    }
}
