//! Linearised stability of the levitation law (issue 5): what the paper's α-method PI law on
//! `g = i/h` (Eq. 8–14) does to small perturbations, in continuous time and as discretised.
//!
//! Why a separate analysis: the core implements Eq. 14 and nothing else; whether a given
//! (α, Δt, n_sub) is stable, and what the closed loop leaves of the magnet's own (gap) mode,
//! must be known before anyone runs it on a vehicle. Every result here is a closed form
//! checked against an eigenvalue computation (nalgebra) and, in the tests, against the core
//! itself.
//!
//! * [`inner_loop`]: the g-loop at fixed gap, continuous (Eq. 9 + 10): `τ s² + (1 + kpv) s + ki = 0`.
//! * [`discrete`]: Eq. 14 over one sub-step as an exact 2×2 map of `(x, y)` at fixed gap; its
//!   spectral radius and the critical time step.
//! * [`gauss`]: the accurate scheme at fixed gap — the (2, 2) Padé map, stable for every step.
//! * [`plant`]: one magnet carrying a body through the Fig. 1 spring–damper under a rigid
//!   rail: the closed-loop poles including the gap mode.
//!
//! Per-unit notation is the core's (`maglev_core::levitation`): `x = g/g0 − 1`,
//! `y = KI·e_a/(R0·i0) − 1`, `η = h/h0 − 1`.

pub mod coupled;
pub mod design;
pub mod discrete;
pub mod eig;
pub mod envelope;
#[cfg(test)]
mod fig6_check;
pub mod gap_loop;
pub mod gauss;
pub mod girder;
pub mod guideway_rail;
pub mod headroom;
pub mod inner_loop;
pub mod magnet;
pub mod marginal;
pub mod margins;
pub mod multiloop;
pub mod numerics;
pub mod plant;
pub mod report;
pub mod resolvent;
pub mod schemes;
pub mod state_design;
pub mod suspension;
pub mod targets;
pub mod vehicle;

/// A complex number for reports (`re`, `im`), sorted by descending real part then imaginary.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Complex {
    pub re: f64,
    pub im: f64,
}

impl Complex {
    /// Modulus.
    pub fn abs(self) -> f64 {
        self.re.hypot(self.im)
    }
}

impl From<nalgebra::Complex<f64>> for Complex {
    fn from(c: nalgebra::Complex<f64>) -> Self {
        Complex { re: c.re, im: c.im }
    }
}

/// Sorts poles by descending real part, then descending imaginary part (stable output order).
pub fn sort_poles(p: &mut [Complex]) {
    p.sort_by(|a, b| b.re.total_cmp(&a.re).then(b.im.total_cmp(&a.im)));
}

/// Eigenvalues (from nalgebra's `complex_eigenvalues`) as poles, sorted as [`sort_poles`].
pub fn sorted_poles(ev: impl IntoIterator<Item = nalgebra::Complex<f64>>) -> Vec<Complex> {
    let mut out: Vec<Complex> = ev.into_iter().map(Complex::from).collect();
    sort_poles(&mut out);
    out
}

/// Eigenvalues of a general real matrix as sorted poles ([`sort_poles`]), by [`eig`] (with an
/// iteration limit and exceptional shifts; an error if it does not converge).
pub fn eigenvalues(a: &nalgebra::DMatrix<f64>) -> crate::Result<Vec<Complex>> {
    let mut p = eig::eigenvalues(a)?;
    sort_poles(&mut p);
    Ok(p)
}

#[cfg(test)]
mod tests;
