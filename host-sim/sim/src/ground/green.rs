//! The Green's function of the ground: vertical surface displacement per newton of a
//! vertical point load on the surface of a homogeneous viscoelastic half-space (Lamb's
//! problem, 1904), in the frequency domain, from the wavenumber (Hankel) integral.
//!
//! # Conventions
//!
//! Time factor e^{+iωt}. The load P pushes down, the displacement w is positive down.
//! Hysteretic (frequency-independent) damping ξ enters as complex moduli
//! μ* = μ(1 + 2iξ), λ* = λ(1 + 2iξ): Poisson's ratio ν stays real, both wave speeds become
//! c* = c·√(1 + 2iξ), and a wave e^{i(ωt − k*x)} decays as e^{−ξωx/c} to first order in ξ.
//! Negative frequencies follow from w(−f) = conj(w(f)).
//!
//! # The integral
//!
//! With k_s = ω/c_s* and k_p = ω/c_p*, ν_p = √(k² − k_p²), ν_s = √(k² − k_s²) (principal
//! square roots: Re ≥ 0, the waves decay with depth) and the Rayleigh function
//! F(k) = (2k² − k_s²)² − 4k²ν_pν_s,
//!
//!   w(r) = P/(2πμ*) ∫₀^∞ g(k) J0(kr) k dk,   g(k) = −k_s² ν_p / F(k)          (G1)
//!
//! (e.g. Kausel, *Fundamental Solutions in Elastodynamics*, 2006, §10; Lamb 1904). In the
//! dimensionless wavenumber q = k/k₀, k₀ = ω/c_s the undamped shear wavenumber, and
//! x = k₀r, every quantity depends on x, ν and ξ only:
//!
//!   w(r) = P/(2πμ* r) · W(x),  W(x) = x ∫₀^∞ G(q) J0(qx) q dq,                      (G2)
//!
//! G(q) = −κ² ν̃_p / F̃, κ² = 1/(1 + 2iξ), ν̃_p = √(q² − γ²κ²), ν̃_s = √(q² − κ²),
//! F̃ = (2q² − κ²)² − 4q²ν̃_pν̃_s, γ² = c_s²/c_p² = (1 − 2ν)/(2(1 − ν)).
//!
//! **Branch points and the pole.** G has branch points at q_p = γκ and q_s = κ and the
//! Rayleigh pole at q_R = κ/√η (η = (c_R/c_s)², the root of the Rayleigh equation below
//! 1). Since κ ≈ 1 − iξ, damping moves all three below the real axis by about ξ times
//! their distance from the origin, so the integrand is smooth (if sharply peaked, width
//! ~ξ) on the real axis: ξ > 0 is required, and ξ ≥ 1e-3 is the accepted range.
//! With real moduli the square roots are continuous along the real axis because
//! Im(q² − γ²κ²) > 0 there.
//!
//! **The large-q asymptote, in closed form.** With s = κ²/q²,
//! F̃/q⁴ = −2(1 − γ²)s + B s² + O(s³), B = 1 + (1 − γ²)²/2, hence
//! G = (1 − ν)/q + c₂κ²/q³ + O(q⁻⁵), c₂ = (1 − ν)(B(1 − ν) − γ²/2). Both leading terms are
//! subtracted and added back in closed form: ∫₀^∞ J0(qx) dq = 1/x (the static part,
//! Boussinesq's w = P(1 − ν)/(2πμ* r)) and ∫₀^∞ J0(qx) q/(q² + 1)^{3/2} dq = e^{−x}
//! (Sonine), the second used for the regularised c₂κ²/(q² + 1)^{3/2}. So
//!
//!   W(x) = (1 − ν) + x c₂κ² e^{−x} + x ∫₀^∞ R(q) J0(qx) q dq,
//!   R = G − (1 − ν)/q − c₂κ²/(q² + 1)^{3/2} = O(q⁻⁵).                              (G3)
//!
//! **Quadrature.** The remainder of (G3) is integrated over q ∈ [0, Q] by adaptive
//! Gauss–Kronrod (7/15 points) on panels no wider than one period of J0(qx) (2π/x) and
//! no wider than 1/4, with breakpoints at the real parts of q_p, q_s and q_R. A panel whose
//! Kronrod–Gauss difference exceeds 1e-10·(|panel| + 1e-3) is bisected (at most 40 levels).
//! Q = 20 up to x = 100 and 20·√(100/x) (at least 4) beyond, which keeps the work of one
//! evaluation growing as √x rather than x: R·q falls as c₄q⁻⁴, so the tail beyond Q
//! contributes about x·c₄Q⁻⁴·√(2/(πQx))/x = c₄√(2/π)·Q^−4.5·x^−0.5 to W: below 1e-6·c₄ for
//! Q = 20 at any x, and 2e-6·c₄ at x = 400 (Q = 10).
//! J0 is [`super::bessel::j0`].
//!
//! **Far away.** With damping, every contribution (the pole and both branch points) lies below
//! the real axis, so W decays at least as fast as the slowest wave, the P wave:
//! |W| ≲ x·e^{x·Im q_p}. Beyond x·|Im q_p| = 30 (e^{−30} = 9e-14, so |W| < 1e-8 for
//! x < 1e5) W is returned as 0; this also bounds the work of one evaluation. Far from the
//! load the deformed contour of [`super::far`] is cheaper and more accurate (this
//! quadrature's shrinking Q leaves ~1e-6 at x = 300); [`super::table`] uses it there.
//!
//! **Accuracy** (host-sim/sim/tests/ground_green.rs): the static limit, the Rayleigh far field
//! at x = 200 and an independently written second evaluation of (G1) for x = 0.5 … 100,
//! ν = 0.25, 1/3, 0.45, ξ = 0.01, 0.05 (docs/ground.md has the measured table).

use crate::physics::fe::soil::Soil;
use crate::Error;
use rustfft::num_complex::Complex64 as C;

/// The smallest hysteretic damping ratio accepted: the integrand's peaks at the branch
/// points and the Rayleigh pole are ~ξ wide, and a vanishing ξ leaves them on the axis.
pub const MIN_DAMPING: f64 = 1e-3;
/// The largest accepted damping ratio (soils: 0.01–0.1).
pub const MAX_DAMPING: f64 = 0.25;
/// The largest accepted Poisson's ratio (0.5 is incompressible: c_p infinite).
pub const MAX_POISSON: f64 = 0.49;

/// Beyond x·|Im q_p| = 30 every wave has decayed by e^{−30} (module docs): W = 0.
const ATTENUATED: f64 = 30.0;

/// Upper limit of the remainder's integration (dimensionless wavenumber) up to x = 100.
const Q_MAX: f64 = 20.0;

/// The upper limit at `x`: [`Q_MAX`] up to x = 100, then Q_MAX·√(100/x), at least 4 (module
/// docs: the tail's share of W falls as Q^−4.5·x^−0.5).
fn upper_limit(x: f64) -> f64 {
    if x <= 100.0 {
        Q_MAX
    } else {
        (Q_MAX * (100.0 / x).sqrt()).max(4.0)
    }
}

/// The half-space's dimensionless Green's function W(x) at fixed ν and ξ (module docs).
#[derive(Clone, Debug)]
pub struct Green {
    nu: f64,
    gamma2: f64,
    kappa2: C,
    c2: f64,
    /// The Rayleigh pole q_R (complex).
    q_rayleigh: C,
}

/// Principal square root (Re ≥ 0).
fn csqrt(z: C) -> C {
    z.sqrt()
}

impl Green {
    /// The Green's function for Poisson's ratio `nu` and hysteretic damping ratio `xi`.
    pub fn new(nu: f64, xi: f64) -> crate::Result<Self> {
        if !(0.0..=MAX_POISSON).contains(&nu) {
            return Err(Error::invalid(
                "poisson",
                format!("must be in [0, {MAX_POISSON}], got {nu}"),
            ));
        }
        if !(MIN_DAMPING..=MAX_DAMPING).contains(&xi) {
            return Err(Error::invalid(
                "damping",
                format!("must be in [{MIN_DAMPING}, {MAX_DAMPING}], got {xi}"),
            ));
        }
        let gamma2 = (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu));
        let kappa2 = C::new(1.0, 0.0) / C::new(1.0, 2.0 * xi);
        let b = 1.0 + (1.0 - gamma2).powi(2) / 2.0;
        let c2 = (1.0 - nu) * (b * (1.0 - nu) - gamma2 / 2.0);
        let mut g = Green {
            nu,
            gamma2,
            kappa2,
            c2,
            q_rayleigh: C::new(0.0, 0.0),
        };
        g.q_rayleigh = g.rayleigh_pole()?;
        Ok(g)
    }

    /// Poisson's ratio.
    pub fn poisson(&self) -> f64 {
        self.nu
    }

    /// The x beyond which [`Green::scaled`] is 0 (every wave decayed by e^{−30}).
    pub fn negligible_beyond(&self) -> f64 {
        ATTENUATED / -(self.gamma2.sqrt() * self.kappa2.sqrt()).im
    }

    /// The Rayleigh pole q_R = k_R/k₀ (complex; c_R = c_s/Re q_R to first order in ξ).
    pub fn rayleigh_pole(&self) -> crate::Result<C> {
        // Newton on F̃ from Viktorov's estimate c_R/c_s ≈ (0.87 + 1.12ν)/(1 + ν).
        let kappa = self.kappa2.sqrt();
        let mut q = kappa * (1.0 + self.nu) / (0.87 + 1.12 * self.nu);
        for _ in 0..50 {
            let (f, df) = self.rayleigh_function(q);
            let step = f / df;
            q -= step;
            if step.norm() < 1e-15 * q.norm() {
                return Ok(q);
            }
        }
        Err(Error::numerical(format!(
            "the Rayleigh pole did not converge for poisson = {}",
            self.nu
        )))
    }

    /// The branch points q_p = γκ, q_s = κ and κ² (module docs).
    pub(super) fn branch_points(&self) -> (C, C, C) {
        let kappa = self.kappa2.sqrt();
        (self.gamma2.sqrt() * kappa, kappa, self.kappa2)
    }

    /// F̃(q) and dF̃/dq.
    pub(super) fn rayleigh_function(&self, q: C) -> (C, C) {
        let q2 = q * q;
        let np = csqrt(q2 - self.gamma2 * self.kappa2);
        let ns = csqrt(q2 - self.kappa2);
        let a = 2.0 * q2 - self.kappa2;
        let f = a * a - 4.0 * q2 * np * ns;
        let df = 8.0 * q * a - 8.0 * q * np * ns - 4.0 * q2 * (q * ns / np + q * np / ns);
        (f, df)
    }

    /// G(q) of (G2).
    fn kernel(&self, q: f64) -> C {
        let q2 = C::new(q * q, 0.0);
        let np = csqrt(q2 - self.gamma2 * self.kappa2);
        let ns = csqrt(q2 - self.kappa2);
        let a = 2.0 * q2 - self.kappa2;
        let f = a * a - 4.0 * q2 * np * ns;
        -self.kappa2 * np / f
    }

    /// R(q)·q of (G3): the remainder's integrand without J0.
    fn remainder(&self, q: f64) -> C {
        if q == 0.0 {
            // G·q → 0, (1 − ν)/q·q = 1 − ν, the regularised term vanishes.
            return C::new(-(1.0 - self.nu), 0.0);
        }
        let reg = self.kappa2 * (self.c2 / (q * q + 1.0).powf(1.5));
        (self.kernel(q) - reg) * q - (1.0 - self.nu)
    }

    /// W(x) of (G2): w·2πμ*r/P at x = ωr/c_s (x ≥ 0; W(0) = 1 − ν, the static limit).
    pub fn scaled(&self, x: f64) -> C {
        if x == 0.0 {
            return C::new(1.0 - self.nu, 0.0);
        }
        if x * -(self.gamma2.sqrt() * self.kappa2.sqrt()).im > ATTENUATED {
            return C::new(0.0, 0.0);
        }
        let integral = self.remainder_integral(x);
        C::new(1.0 - self.nu, 0.0) + x * self.c2 * self.kappa2 * (-x).exp() + x * integral
    }

    /// ∫₀^Q R(q) J0(qx) q dq by adaptive Gauss–Kronrod on the panels of the module docs.
    fn remainder_integral(&self, x: f64) -> C {
        let width = (2.0 * std::f64::consts::PI / x).min(0.25);
        let q_max = upper_limit(x);
        let mut breaks: Vec<f64> = vec![
            (self.gamma2.sqrt() * self.kappa2.sqrt()).re,
            self.kappa2.sqrt().re,
            self.q_rayleigh.re,
        ];
        breaks.sort_by(f64::total_cmp);
        let mut edges = vec![0.0];
        let mut at = 0.0;
        let mut next = breaks.iter().copied().peekable();
        while at < q_max {
            let mut to = (at + width).min(q_max);
            while let Some(&b) = next.peek() {
                if b <= at {
                    next.next();
                } else {
                    if b < to {
                        to = b;
                    }
                    break;
                }
            }
            edges.push(to);
            at = to;
        }
        let f = |q: f64| self.remainder(q) * super::bessel::j0(q * x);
        edges
            .windows(2)
            .map(|w| adaptive(&f, w[0], w[1], 0))
            .fold(C::new(0.0, 0.0), |s, v| s + v)
    }
}

/// Gauss–Kronrod 7/15 nodes on [−1, 1] (the positive half and zero), Kronrod and Gauss weights.
const XK: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
const WK: [f64; 8] = [
    0.022_935_322_010_529_22,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_2,
    0.140_653_259_715_525_9,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_727_8,
];
/// Gauss weights of the nodes XK[1], XK[3], XK[5], XK[7].
const WG: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// Kronrod estimate and |Kronrod − Gauss| on [a, b].
fn gk15(f: &impl Fn(f64) -> C, a: f64, b: f64) -> (C, f64) {
    let (c, h) = ((a + b) / 2.0, (b - a) / 2.0);
    let mid = f(c);
    let mut k = mid * WK[7];
    let mut g = mid * WG[3];
    for i in 0..7 {
        let s = f(c - h * XK[i]) + f(c + h * XK[i]);
        k += s * WK[i];
        if i % 2 == 1 {
            g += s * WG[i / 2];
        }
    }
    (k * h, ((k - g) * h).norm())
}

/// ∫_a^b f by Gauss–Kronrod 7/15, bisected while |K − G| > 1e-10·(|K| + 1e-3) (at most 40
/// levels).
pub(super) fn adaptive(f: &impl Fn(f64) -> C, a: f64, b: f64, depth: u32) -> C {
    let (k, err) = gk15(f, a, b);
    if err <= 1e-10 * (k.norm() + 1e-3) || depth >= 40 {
        return k;
    }
    let m = (a + b) / 2.0;
    adaptive(f, a, m, depth + 1) + adaptive(f, m, b, depth + 1)
}

/// μ* = ρc_s²(1 + 2iξ) of `soil` (Pa).
pub fn complex_shear_modulus(soil: &Soil) -> C {
    C::new(1.0, 2.0 * soil.damping) * soil.shear_modulus()
}

/// The vertical surface displacement per newton at distance `r` (m) and frequency `f` (Hz,
/// ≥ 0) from a vertical point load on the surface of `soil` (module docs; `green` must be
/// built for this soil's ν and ξ): w = W(x)/(2πμ*r), x = 2πfr/c_s.
pub fn displacement_per_newton(soil: &Soil, green: &Green, f: f64, r: f64) -> C {
    let x = 2.0 * std::f64::consts::PI * f * r / soil.shear_wave_velocity;
    green.scaled(x) / (2.0 * std::f64::consts::PI * r * complex_shear_modulus(soil))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 15-point rule integrates polynomials up to degree 22 exactly, the 7-point one up
    /// to degree 13: x^22 on [0, 1] gives 1/23 and the pair differs for x^14 only.
    #[test]
    fn gauss_kronrod_weights_are_exact_for_their_degrees() {
        for deg in [0, 1, 5, 13, 22] {
            let (k, _) = gk15(&|q: f64| C::new(q.powi(deg), 0.0), 0.0, 1.0);
            assert!(
                (k.re - 1.0 / (deg as f64 + 1.0)).abs() < 1e-14,
                "degree {deg}"
            );
        }
        let (_, e13) = gk15(&|q: f64| C::new(q.powi(13), 0.0), 0.0, 1.0);
        let (_, e14) = gk15(&|q: f64| C::new(q.powi(14), 0.0), 0.0, 1.0);
        assert!(e13 < 1e-15 && e14 > 1e-9, "{e13} {e14}");
    }

    /// The subtracted remainder falls as q⁻⁵ (R·q as q⁻⁴): c₂ is the right coefficient.
    #[test]
    fn the_remainder_falls_as_q_to_the_minus_four() {
        let g = Green::new(0.3, 0.02).unwrap();
        let (a, b) = (g.remainder(100.0).norm(), g.remainder(200.0).norm());
        let order = (a / b).log2();
        assert!((order - 4.0).abs() < 0.05, "{order}");
    }

    #[test]
    fn out_of_range_soils_are_refused() {
        assert!(Green::new(0.5, 0.02).is_err());
        assert!(Green::new(-0.1, 0.02).is_err());
        assert!(Green::new(0.3, 0.0).is_err());
        assert!(Green::new(0.3, 0.3).is_err());
    }
}
