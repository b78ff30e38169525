//! The vehicle's suspension on held magnets: the poles the magnets' gains cannot move.
//!
//! Why: the design's pole target (every closed-loop pole ≤ −1 s⁻¹, [`super::state_design`])
//! is a target for the control loops. A car body on its secondary suspension has modes whose
//! damping the suspension sets: with every magnet held rigidly where it is (the limit of
//! stiff magnet loops), the body's modes are those of `M_b·q̈ + C_b·q̇ + K_b·q = 0`, the
//! vehicle's matrices with the magnets' rows and columns removed. The Fig. 1 car's yaw mode
//! there has real part `−Σc·x²/(2·J_z)` (four lateral dampers `c` at `x = ±L`: `−2cL²/J_z`,
//! −0.703 s⁻¹ for the paper's car), and its sway–roll mode −0.42 s⁻¹: slower than −1 s⁻¹
//! whatever the gains, because the magnets can only hold the suspension's lower ends.
//!
//! So the design's pole target is the slower of −1 s⁻¹ and the held suspension's slowest
//! pole ([`pole_target`], with the loops' −1 s⁻¹ from
//! [`super::targets::MAX_REAL_PART`]): the loops may add no pole slower than −1 s⁻¹, and may leave no
//! suspension mode slower than it is on held magnets.

use super::Complex;
use crate::physics::vehicle::VehicleModel;
use nalgebra::DMatrix;

/// The poles of `v`'s suspension with every magnet DOF (each wheel's Z and Y) held, sorted
/// (descending real part); empty when no DOF is left (the bare magnet). An error when a
/// remaining DOF has no mass.
pub fn held_poles(v: &VehicleModel) -> crate::Result<Vec<Complex>> {
    let magnet = |i: usize| v.wheels.iter().any(|w| w.dof_z == i || w.dof_y == Some(i));
    let keep: Vec<usize> = (0..v.m.nrows()).filter(|&i| !magnet(i)).collect();
    let n = keep.len();
    if n == 0 {
        return Ok(Vec::new());
    }
    let pick = |a: &DMatrix<f64>| DMatrix::from_fn(n, n, |r, c| a[(keep[r], keep[c])]);
    let (m, c, k) = (pick(&v.m), pick(&v.c), pick(&v.k));
    let minv = m.try_inverse().ok_or_else(|| {
        crate::Error::numerical("the suspension on held magnets has a DOF without mass")
    })?;
    let (mk, mc) = (&minv * k, &minv * c);
    let mut a = DMatrix::zeros(2 * n, 2 * n);
    for i in 0..n {
        a[(i, n + i)] = 1.0;
        for j in 0..n {
            a[(n + i, j)] = -mk[(i, j)];
            a[(n + i, n + j)] = -mc[(i, j)];
        }
    }
    super::eigenvalues(&a)
}

/// The design's pole target for `v` (module docs): the slower of `loops` (the control loops'
/// own target, 1/s) and the held suspension's slowest pole when that is stable (a suspension
/// with an undamped or unrestrained mode leaves the target at `loops`).
pub fn pole_target(v: &VehicleModel, loops: f64) -> crate::Result<f64> {
    Ok(target_of(&held_poles(v)?, loops))
}

/// [`pole_target`] from the held suspension's poles `held` (sorted, as [`held_poles`]).
pub fn target_of(held: &[Complex], loops: f64) -> f64 {
    match held.first() {
        Some(p) if p.re < 0.0 => loops.max(p.re),
        _ => loops,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::vehicle::Fig1;

    /// paper-4.2's Fig. 1 car with magnets of `wheel_mass` (kg).
    fn paper_params(wheel_mass: f64) -> Fig1 {
        let case = crate::input::case::Case::load("paper-4.2", &[]).unwrap();
        let crate::input::case::TrainCase::Fig1 { car, .. } = case.train else {
            panic!("paper-4.2 carries a Fig. 1 car")
        };
        Fig1 { wheel_mass, ..car }
    }

    fn paper_car(wheel_mass: f64) -> VehicleModel {
        VehicleModel::fig1(&paper_params(wheel_mass), 9.81).unwrap()
    }

    /// The Fig. 1 car's yaw mode on held magnets: the four lateral springs `k` and dampers `c`
    /// at `x = ±L` about the body's centre give `J_z·θ̈ + 4cL²·θ̇ + 4kL²·θ = 0`, so
    /// `s = −2cL²/J_z ± j·√(4kL²/J_z − (2cL²/J_z)²)`; the yaw DOF couples to no other (the
    /// springs sit symmetrically), so the pole is exact. The paper's car: −0.703125 s⁻¹.
    #[test]
    fn fig1_yaw_on_held_magnets_is_the_closed_form() {
        for wheel_mass in [0.0, 200.0, 2000.0] {
            let p = paper_params(wheel_mass);
            let poles = held_poles(&VehicleModel::fig1(&p, 9.81).unwrap()).unwrap();
            assert_eq!(poles.len(), 10, "five body DOFs");
            let l = p.half_length;
            let re = -2.0 * p.c * l * l / p.jz;
            let im = (4.0 * p.k * l * l / p.jz - re * re).sqrt();
            let near = poles
                .iter()
                .map(|s| (s.re - re).hypot(s.im.abs() - im))
                .fold(f64::INFINITY, f64::min);
            assert!(near < 1e-9 * im, "yaw {re} ± j{im} not among {poles:?}");
            assert!((re + 0.703125).abs() < 1e-12, "{re}");
        }
    }

    /// The paper's car's slowest held pole is slower than −1 s⁻¹, so the target is that pole;
    /// the bare magnet (no DOF left) keeps −1 s⁻¹.
    #[test]
    fn the_target_is_the_slower_of_the_loops_and_the_suspension() {
        let v = paper_car(1000.0);
        let slowest = held_poles(&v).unwrap()[0].re;
        assert!(slowest > -1.0 && slowest < -0.1, "{slowest}");
        assert_eq!(pole_target(&v, -1.0).unwrap(), slowest);
        let mut bare = v.clone();
        let keep = bare.wheels[0].clone();
        bare.m = DMatrix::from_element(1, 1, 1000.0);
        bare.c = DMatrix::zeros(1, 1);
        bare.k = DMatrix::zeros(1, 1);
        bare.wheels = vec![crate::physics::vehicle::Wheel {
            dof_z: 0,
            dof_y: None,
            ..keep
        }];
        assert!(held_poles(&bare).unwrap().is_empty());
        assert_eq!(pole_target(&bare, -1.0).unwrap(), -1.0);
    }
}
