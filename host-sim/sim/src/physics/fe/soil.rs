//! A reduced soil impedance: frequency-independent springs and dashpots for a rigid
//! rectangular footing on a homogeneous half-space (docs/model.md §10 "Soil"; values and
//! sources in docs/viaduct.md).
//!
//! Why this reduction: the paper meshes 8.5 million DOFs of soil; a footing impedance keeps
//! the pier base flexible and dissipative (it moves, so `pier{K}.base.{z,az}` mean
//! something) at six DOFs per pier.
//!
//! Springs: the static stiffnesses of Gazetas (1991, J. Geotech. Eng. 117(9), Table 1,
//! surface foundation of arbitrary shape), for a footing of plan 2L × 2B (L ≥ B, x_G along
//! L), χ = A_b / (4 L²), I_bx, I_by the plan's second moments about x_G, y_G:
//!
//! - vertical: K_z = 2 G L / (1 − ν) · (0.73 + 1.54 χ^0.75);
//! - horizontal across the long side (y_G): K_y = 2 G L / (2 − ν) · (2 + 2.5 χ^0.85);
//! - horizontal along it (x_G): K_x = K_y − 0.2 / (0.75 − ν) · G L (1 − B/L);
//! - rocking about x_G: K_rx = G / (1 − ν) · I_bx^0.75 (L/B)^0.25 (2.4 + 0.5 B/L);
//! - rocking about y_G: K_ry = 3 G / (1 − ν) · I_by^0.75 (L/B)^0.15;
//! - torsion: K_t = 3.5 G I_bz^0.75 (B/L)^0.4 (I_bz / B⁴)^0.2, I_bz = I_bx + I_by.
//!
//! Dashpots: the radiation dashpots of the same paper in their high-frequency form,
//! C = ρ V A_b for translation and C = ρ V I_b for rotation, with V = V_s for horizontal
//! motion and torsion and Lysmer's analogue V_La = 3.4 V_s / (π (1 − ν)) for vertical motion
//! and rocking. Held constant (frequency-independent): at the bridge's 2–6.5 Hz the true
//! rocking dashpot is smaller (Gazetas' c̃_r < 1 at small a₀ = ω B / V_s), so rocking
//! damping is overestimated; translational dashpots are close to their constant value.
//!
//! The soil's hysteretic damping ratio ξ ([`Soil::damping`], the same soil as the ground's
//! Green's function, `crate::ground`) is not added to the footing: in the frequency domain it
//! adds 2ξK to the imaginary part of each impedance, a dashpot 2ξK/ω that no constant
//! time-domain dashpot can carry; at ξ = 0.03 and the bridge's 2–6.5 Hz it is 6–20 % of the
//! vertical radiation dashpot (docs/ground.md). The springs use the real modulus G = ρV_s².

use crate::physics::check::positive;
use crate::Error;

/// Homogeneous half-space.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Soil {
    /// Shear-wave velocity V_s (m/s).
    #[serde(rename = "shear_wave_velocity_m_per_s")]
    pub shear_wave_velocity: f64,
    /// Density ρ (kg/m³).
    #[serde(rename = "density_kg_per_m3")]
    pub density: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
    /// Hysteretic damping ratio ξ (μ* = μ(1 + 2iξ)); 0 when not given. Used by the ground's
    /// Green's function only (module docs).
    #[serde(rename = "damping_ratio")]
    pub damping: f64,
}

impl Soil {
    /// Shear modulus G = ρ V_s² (Pa).
    pub fn shear_modulus(&self) -> f64 {
        self.density * self.shear_wave_velocity * self.shear_wave_velocity
    }

    /// Lysmer's analogue velocity V_La = 3.4 V_s / (π (1 − ν)) (m/s).
    pub fn lysmer_velocity(&self) -> f64 {
        3.4 * self.shear_wave_velocity / (std::f64::consts::PI * (1.0 - self.poisson))
    }
}

/// Springs and dashpots of a footing, in the viaduct's axes, per DOF (u, v, w, θx, θy, θz).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Impedance {
    /// N/m (translations), N·m/rad (rotations).
    pub stiffness: [f64; 6],
    /// N·s/m, N·m·s/rad.
    pub damping: [f64; 6],
}

/// Gazetas' footing impedance (module docs) for a rectangle `along_x` × `across_y` (m).
pub fn gazetas_rectangle(soil: &Soil, along_x: f64, across_y: f64) -> crate::Result<Impedance> {
    for (key, v) in [
        ("foundation.along_x", along_x),
        ("foundation.across_y", across_y),
        ("soil.shear_wave_velocity", soil.shear_wave_velocity),
        ("soil.density", soil.density),
    ] {
        positive(key, v)?;
    }
    let nu = soil.poisson;
    if !(0.0..0.5).contains(&nu) {
        return Err(Error::invalid(
            "soil.poisson",
            format!("must be in [0, 0.5), got {nu}"),
        ));
    }
    let (l, b) = (along_x.max(across_y) / 2.0, along_x.min(across_y) / 2.0);
    let g = soil.shear_modulus();
    let area = 4.0 * l * b;
    let chi = area / (4.0 * l * l);
    let ibx = (2.0 * l) * (2.0 * b).powi(3) / 12.0;
    let iby = (2.0 * b) * (2.0 * l).powi(3) / 12.0;
    let ibz = ibx + iby;
    let kz = 2.0 * g * l / (1.0 - nu) * (0.73 + 1.54 * chi.powf(0.75));
    let ky = 2.0 * g * l / (2.0 - nu) * (2.0 + 2.5 * chi.powf(0.85));
    let kx = ky - 0.2 / (0.75 - nu) * g * l * (1.0 - b / l);
    let krx = g / (1.0 - nu) * ibx.powf(0.75) * (l / b).powf(0.25) * (2.4 + 0.5 * b / l);
    let kry = 3.0 * g / (1.0 - nu) * iby.powf(0.75) * (l / b).powf(0.15);
    let kt = 3.5 * g * ibz.powf(0.75) * (b / l).powf(0.4) * (ibz / b.powi(4)).powf(0.2);
    let (rho, vs, vla) = (
        soil.density,
        soil.shear_wave_velocity,
        soil.lysmer_velocity(),
    );
    let (cx, cz, crx, cry, ct) = (
        rho * vs * area,
        rho * vla * area,
        rho * vla * ibx,
        rho * vla * iby,
        rho * vs * ibz,
    );
    // Gazetas' x_G is the long side: along X if the footing is longer along the track.
    let long_along_x = along_x >= across_y;
    let (k_u, k_v, k_ru, k_rv) = if long_along_x {
        (kx, ky, krx, kry)
    } else {
        (ky, kx, kry, krx)
    };
    let (c_ru, c_rv) = if long_along_x { (crx, cry) } else { (cry, crx) };
    Ok(Impedance {
        stiffness: [k_u, k_v, kz, k_ru, k_rv, kt],
        damping: [cx, cx, cz, c_ru, c_rv, ct],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square footing: the two horizontal values coincide, the two rocking ones differ by
    /// exactly the spread of Gazetas' fits, and the
    /// vertical one matches the circle of equal area within Gazetas' few per cent
    /// (K_z,circle = 4 G R / (1 − ν)).
    #[test]
    fn square_footing_is_symmetric_and_near_the_circle() {
        let soil = Soil {
            shear_wave_velocity: 200.0,
            density: 1800.0,
            poisson: 0.3,
            damping: 0.0,
        };
        let z = gazetas_rectangle(&soil, 8.0, 8.0).unwrap();
        assert_eq!(z.stiffness[0], z.stiffness[1]);
        // Gazetas' two rocking fits do not coincide for a square: 2.9 (K_rx, (2.4 + 0.5 B/L)
        // at B = L) against 3 (K_ry) times G/(1 − ν)·I^0.75, a 3.4 % spread of the fits.
        let spread = z.stiffness[3].max(z.stiffness[4]) / z.stiffness[3].min(z.stiffness[4]);
        assert!((spread - 3.0 / 2.9).abs() < 1e-12, "{spread}");
        let r = (64.0 / std::f64::consts::PI).sqrt();
        let circle = 4.0 * soil.shear_modulus() * r / (1.0 - 0.3);
        let rel = z.stiffness[2] / circle - 1.0;
        assert!(rel.abs() < 0.05, "{rel}");
        assert!(gazetas_rectangle(&soil, -1.0, 8.0).is_err());
    }
}
