//! Per-mode Galerkin matrices and natural frequencies of a simply supported Timoshenko span
//! (Eq. 20a–e, docs/model.md §8).
//!
//! Derivation (bending, one plane). With φ the bending rotation of the section (φ ≈ ∂w/∂x
//! when shear is negligible), the Timoshenko equations with the shear area A_s given directly
//! (κA = A_s) are
//!
//! ```text
//! ρA ∂²w/∂t² = G A_s (∂²w/∂x² − ∂φ/∂x) + f(x, t)          (Eq. 20a / 20c)
//! ρI ∂²φ/∂t² = E I ∂²φ/∂x² + G A_s (∂w/∂x − φ)            (Eq. 20b / 20d)
//! ```
//!
//! Simple supports (w = 0, ∂φ/∂x = 0 at both ends) are met term by term by
//! w = Σ q_n sin(k_n x), φ = Σ r_n cos(k_n x), k_n = nπ/L. Substituting, multiplying the first
//! equation by sin(k_n x), the second by cos(k_n x), integrating over the span and dividing by
//! L/2 gives, per n, the 2-DOF system M [q̈ r̈]ᵀ + K [q r]ᵀ = [f_n 0]ᵀ with
//!
//! ```text
//! M = diag(ρA, ρI)
//! K = [[ G A_s k²,  −G A_s k         ],
//!      [ −G A_s k,   E I k² + G A_s  ]]
//! f_n = (2/L) Σ_i F_i sin(k_n x_i)           (point forces F_i at x_i on the span)
//! ```
//!
//! Torsion (Eq. 20e): ρI_p ∂²θ/∂t² = G J ∂²θ/∂x² + m_x(x, t), θ = Σ s_n sin(k_n x), so
//! ρI_p s̈_n + G J k_n² s_n = (2/L) Σ_i T_i sin(k_n x_i).
//!
//! With this normalisation q_n, r_n, s_n are the amplitudes of the series terms themselves.
//! Sign link to the FE DOFs (docs/model.md §5): in X–Z, θy = −φ; in X–Y, θz = +φ.

use nalgebra::{Matrix2, SymmetricEigen};

use crate::physics::guideway::BeamSection;

/// Properties of one bending plane of the span, SI.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneProperties {
    /// ρA = mass per length (kg/m).
    pub mass_per_length: f64,
    /// ρI: rotary inertia per length (kg·m).
    pub rotary_inertia: f64,
    /// E I (N·m²).
    pub flexural_rigidity: f64,
    /// G A_s (N).
    pub shear_rigidity: f64,
}

impl PlaneProperties {
    /// Bending in the X–Z plane (vertical deflection w, Eq. 20c–d): I = Iy, A_s = A_Z.
    pub fn vertical(section: &BeamSection) -> Self {
        PlaneProperties {
            mass_per_length: section.mass_per_length,
            rotary_inertia: section.density() * section.iy,
            flexural_rigidity: section.youngs_modulus * section.iy,
            shear_rigidity: section.shear_modulus * section.shear_area_z,
        }
    }

    /// Bending in the X–Y plane (lateral deflection v, Eq. 20a–b): I = Iz, A_s = A_Y.
    pub fn lateral(section: &BeamSection) -> Self {
        PlaneProperties {
            mass_per_length: section.mass_per_length,
            rotary_inertia: section.density() * section.iz,
            flexural_rigidity: section.youngs_modulus * section.iz,
            shear_rigidity: section.shear_modulus * section.shear_area_y,
        }
    }

    /// Diagonal of the per-mode mass matrix, (ρA, ρI) — see the module docs.
    pub fn mode_mass(&self) -> [f64; 2] {
        [self.mass_per_length, self.rotary_inertia]
    }

    /// Per-mode stiffness matrix for wavenumber `k` = nπ/L (rows/columns: q_n, r_n).
    pub fn mode_stiffness(&self, k: f64) -> [[f64; 2]; 2] {
        let gas = self.shear_rigidity;
        [
            [gas * k * k, -gas * k],
            [-gas * k, self.flexural_rigidity * k * k + gas],
        ]
    }

    /// The two natural circular frequencies (rad/s, ascending) of the mode with wavenumber
    /// `k`: the bending branch and the shear/rotation branch.
    ///
    /// The larger eigenvalue comes from the symmetric eigenproblem of M^{-1/2} K M^{-1/2};
    /// the smaller from det(K)/det(M) = λ₁λ₂ with det(K) = G A_s · E I · k⁴ written out, since
    /// an eigen-solver's absolute rounding (~ε·λ₂) would swamp λ₁ when shear is very stiff
    /// (the two can differ by 1e15 in the Euler–Bernoulli limit).
    pub fn frequencies(&self, k: f64) -> [f64; 2] {
        let [m1, m2] = self.mode_mass();
        let kk = self.mode_stiffness(k);
        let s = [1.0 / m1.sqrt(), 1.0 / m2.sqrt()];
        let a = Matrix2::new(
            kk[0][0] * s[0] * s[0],
            kk[0][1] * s[0] * s[1],
            kk[1][0] * s[1] * s[0],
            kk[1][1] * s[1] * s[1],
        );
        let e = SymmetricEigen::new(a).eigenvalues;
        let high = e[0].max(e[1]);
        let det_k = self.shear_rigidity * self.flexural_rigidity * k.powi(4);
        let low = det_k / (m1 * m2 * high);
        [low.sqrt(), high.sqrt()]
    }
}

/// Torsion properties of the span, SI.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TorsionProperties {
    /// ρI_p: polar mass per length (kg·m), [`BeamSection::polar_mass_per_length`].
    pub polar_mass: f64,
    /// G J (N·m²).
    pub torsional_rigidity: f64,
}

impl TorsionProperties {
    pub fn new(section: &BeamSection) -> Self {
        TorsionProperties {
            polar_mass: section.polar_mass_per_length(),
            torsional_rigidity: section.shear_modulus * section.torsion_constant,
        }
    }

    /// Per-mode torsional stiffness G J k² (Eq. 20e projected).
    pub fn mode_stiffness(&self, k: f64) -> f64 {
        self.torsional_rigidity * k * k
    }

    /// Natural circular frequency (rad/s) of torsion mode with wavenumber `k`.
    pub fn frequency(&self, k: f64) -> f64 {
        (self.mode_stiffness(k) / self.polar_mass).sqrt()
    }
}

/// Natural circular frequencies (rad/s) of series term n of a simply supported span.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModeFrequencies {
    /// Series index n ≥ 1 (half-waves along the span).
    pub n: usize,
    /// X–Z bending: [bending branch, shear/rotation branch].
    pub vertical: [f64; 2],
    /// X–Y bending: [bending branch, shear/rotation branch].
    pub lateral: [f64; 2],
    /// Torsion.
    pub torsion: f64,
}

/// Natural frequencies of series term `n` (≥ 1) for a span of length `length` (m).
pub fn natural_frequencies(section: &BeamSection, length: f64, n: usize) -> ModeFrequencies {
    let k = wavenumber(length, n);
    ModeFrequencies {
        n,
        vertical: PlaneProperties::vertical(section).frequencies(k),
        lateral: PlaneProperties::lateral(section).frequencies(k),
        torsion: TorsionProperties::new(section).frequency(k),
    }
}

/// The generalised force of series term `n` (≥ 1) of one bending plane from the inertia of
/// the span's rigid-body motion between its bearings (docs/seismic.md Eq. S5): the load per
/// length −ρA ü_qs(x), ü_qs = (1 − x/L) a_left + (x/L) a_right, projected as the loads are,
/// (2/L) ∫₀ᴸ −ρA ü_qs sin(nπx/L) dx = −(2ρA/(nπ)) (a_left − (−1)ⁿ a_right). The rotation
/// equation takes nothing: the rigid-body rotation is constant along the span and
/// ∫₀ᴸ cos(nπx/L) dx = 0.
pub fn bearing_force(n: usize, rho_a: f64, a_left: f64, a_right: f64) -> f64 {
    let sign = if n.is_multiple_of(2) { 1.0 } else { -1.0 };
    -2.0 * rho_a / (n as f64 * core::f64::consts::PI) * (a_left - sign * a_right)
}

/// k_n = nπ/L (rad/m).
pub fn wavenumber(length: f64, n: usize) -> f64 {
    n as f64 * core::f64::consts::PI / length
}
