//! W(x) of [`super::green`] far from the load, by deforming the wavenumber integral into the
//! lower half-plane: the Rayleigh pole's residue plus one integral down each branch cut, each
//! decaying as e^{−t·x} along the cut, so its cost falls as x grows where the real-axis
//! quadrature's grows as x^1.5.
//!
//! # The deformation (the equation numbers continue green.rs')
//!
//! With J0 = (H0⁽¹⁾ + H0⁽²⁾)/2, the H0⁽¹⁾ half of ∫₀^∞ G(q) J0(qx) q dq is turned onto the
//! positive imaginary axis (the first quadrant holds no singularity of G) and the H0⁽²⁾ half
//! onto the negative one, across the fourth quadrant, which holds the branch points
//! q_p = γκ, q_s = κ and the Rayleigh pole q_R. G depends on q² only and is regular on the
//! imaginary axis, so the two imaginary-axis integrals (both of K0(tx)) cancel, leaving
//!
//!   W(x) = x·[−iπ·Res_{q_R}(G q H0⁽²⁾(qx)) + ½(L_p + L_s)],
//!   L_b = −i ∫₀^∞ [G_r − G_l](q) q H0⁽²⁾(qx) dt,  q = q_b − it,                    (G4)
//!
//! (plus the residue of any other pole of G on this sheet in the fourth quadrant: for ν
//! above about 0.32 a "leaky" root, [`Far::new`]), where the cuts run vertically down from q_b and G_r, G_l are G on their right and left
//! (the root √(q² − q_b²) of that cut changes sign across it). The roots are continued with
//! those vertical cuts: √(q² − q_b²) = √(−i(q − q_b))·√(i(q + q_b)) (principal roots), which
//! is the principal root of (G1) on the real axis (both are analytic in a strip about it and
//! agree at large q). The residue is iπxκ²ν̃_p q_R H0⁽²⁾(q_R x)/F̃'(q_R), the Rayleigh wave.
//!
//! **Along a cut** t = s²/x: H0⁽²⁾(qx) carries e^{−s²}, and G_r − G_l ∝ √t near the branch
//! point, so the integrand is smooth in s; it is integrated over s ∈ [0, 6.5] (e^{−42.25}
//! beyond) by the adaptive Gauss–Kronrod rule of green.rs on panels of 0.5.
//!
//! **H0⁽²⁾(z)** by Hankel's expansion (Abramowitz & Stegun 9.2.8, valid for
//! −2π < arg z < π; here −π/2 < arg z ≤ 0), summed until a term stops falling or drops below
//! 1e-17. Its smallest term is about e^{−2|z|}, so the form is used only where
//! |q_p|·x ≥ [`MIN_ARGUMENT`] (at least x = [`MIN_X`]): below, W is evaluated on the real axis.
//!
//! This form is exact (no asymptotic truncation other than Hankel's series'): the test
//! host-sim/sim/tests/ground_table.rs holds it against the real-axis quadrature at the
//! switch-over and beyond.

use super::green::{adaptive, Green};
use rustfft::num_complex::Complex64 as C;
use std::f64::consts::{FRAC_PI_4, PI};

/// The smallest |q_p|·x at which Hankel's expansion is used (its smallest term ~e^{−2|z|}:
/// e^{−30} = 1e-13 relative).
pub const MIN_ARGUMENT: f64 = 15.0;
/// The smallest x at which the deformed form is used.
pub const MIN_X: f64 = 40.0;
/// The end of the integration along a cut in s = √(t·x) (e^{−s²} = 4.5e-19).
const S_END: f64 = 6.5;
/// The panel width along a cut in s.
const S_PANEL: f64 = 0.5;

/// H0⁽²⁾(z) by Hankel's expansion (module docs; |z| ≳ 15).
pub fn hankel2(z: C) -> C {
    // b_n = Π_{j≤n} (2j − 1)² / (n! (8z)^n); P = b0 − b2 + b4 − …, Q = −b1 + b3 − ….
    let (mut p, mut q) = (C::new(1.0, 0.0), C::new(0.0, 0.0));
    let mut b = C::new(1.0, 0.0);
    let mut last = 1.0_f64;
    for n in 1..60 {
        let nf = n as f64;
        b *= (2.0 * nf - 1.0).powi(2) / (nf * 8.0 * z);
        let size = b.norm();
        if size > last || size < 1e-17 {
            break;
        }
        last = size;
        let sign = if (n / 2) % 2 == 0 { 1.0 } else { -1.0 };
        if n % 2 == 0 {
            p += sign * b;
        } else {
            q -= sign * b;
        }
    }
    let i = C::new(0.0, 1.0);
    (2.0 / (PI * z)).sqrt() * (-i * (z - FRAC_PI_4)).exp() * (p - i * q)
}

/// √(q² − b²) continued with a vertical cut down from `b` (and up from −b) (module docs).
fn vertical_root(q: C, b: C) -> C {
    let i = C::new(0.0, 1.0);
    (-i * (q - b)).sqrt() * (i * (q + b)).sqrt()
}

/// The far field's parts at fixed ν and ξ: the branch points and the poles.
#[derive(Clone, Debug)]
pub struct Far {
    q_p: C,
    q_s: C,
    kappa2: C,
    /// Each pole q_j of G on the sheet of the vertical cuts in the fourth quadrant, with
    /// κ²ν̃_p(q_j) q_j / F̃'(q_j), its residue's factor without H0⁽²⁾; the first is the
    /// Rayleigh pole.
    poles: Vec<(C, C)>,
}

impl Far {
    /// The far field of `green`.
    pub fn new(green: &Green) -> crate::Result<Self> {
        let (q_p, q_s, kappa2) = green.branch_points();
        let q_r = green.rayleigh_pole()?;
        let mut far = Far {
            q_p,
            q_s,
            kappa2,
            poles: Vec::new(),
        };
        let mut poles = vec![q_r];
        for q in far.other_poles() {
            if (q - q_r).norm() > 1e-8 {
                poles.push(q);
            }
        }
        far.poles = poles
            .into_iter()
            .map(|q| {
                let (_, df) = far.secular(q);
                (q, kappa2 * vertical_root(q, q_p) * q / df)
            })
            .collect();
        Ok(far)
    }

    /// F̃ and dF̃/dq with the roots of the vertical cuts.
    fn secular(&self, q: C) -> (C, C) {
        let q2 = q * q;
        let np = vertical_root(q, self.q_p);
        let ns = vertical_root(q, self.q_s);
        let a = 2.0 * q2 - self.kappa2;
        let f = a * a - 4.0 * q2 * np * ns;
        let df = 8.0 * q * a - 8.0 * q * np * ns - 4.0 * q2 * (q * ns / np + q * np / ns);
        (f, df)
    }

    /// The zeros of F̃ on the sheet of the vertical cuts in the fourth quadrant, away from
    /// the branch points: among the roots of the rationalised secular equation
    /// (2u − κ²)⁴ = 16u²(u − q_p²)(u − q_s²), u = q², a cubic in u, those where F̃ itself
    /// vanishes with these roots. Besides the Rayleigh pole, for ν above about 0.32 a
    /// "leaky" root (an unphysical zero of the principal sheet, below the principal S cut)
    /// lies on this sheet, and its residue belongs to (G4).
    fn other_poles(&self) -> Vec<C> {
        let (k, p, s) = (self.kappa2, self.q_p * self.q_p, self.q_s * self.q_s);
        let a3 = 16.0 * (p + s) - 32.0 * k;
        let c = [
            (24.0 * k * k - 16.0 * p * s) / a3,
            -8.0 * k * k * k / a3,
            k * k * k * k / a3,
        ];
        let cubic = |u: C| ((u + c[0]) * u + c[1]) * u + c[2];
        // Durand–Kerner from the usual spread-out starts.
        let mut u: [C; 3] = [0, 1, 2].map(|j| C::new(0.4, 0.9).powu(j));
        for _ in 0..500 {
            let prev = u;
            for i in 0..3 {
                let mut d = C::new(1.0, 0.0);
                for j in 0..3 {
                    if j != i {
                        d *= u[i] - u[j];
                    }
                }
                u[i] -= cubic(u[i]) / d;
            }
            if (0..3).all(|i| (u[i] - prev[i]).norm() < 1e-16 * (1.0 + u[i].norm())) {
                break;
            }
        }
        let mut out = Vec::new();
        for ui in u {
            let r = ui.sqrt();
            let q = if r.im < 0.0 { r } else { -r };
            let near_branch = (q - self.q_p).norm().min((q - self.q_s).norm()) < 1e-6;
            if q.re <= 0.0 || q.im >= 0.0 || near_branch {
                continue;
            }
            let (f, _) = self.secular(q);
            let scale = (2.0 * q * q - k).norm_sqr().max(1.0);
            if f.norm() < 1e-10 * scale {
                out.push(q);
            }
        }
        out
    }

    /// The smallest x at which [`Far::scaled`] holds (module docs).
    pub fn from_x(&self) -> f64 {
        (MIN_ARGUMENT / self.q_p.norm()).max(MIN_X)
    }

    /// The Rayleigh wave's part of W(x), iπxκ²ν̃_p q_R H0⁽²⁾(q_R x)/F̃'(q_R).
    pub fn rayleigh(&self, x: f64) -> C {
        self.residue(self.poles[0], x)
    }

    /// −iπx·Res of G q H0⁽²⁾(qx) at one pole.
    fn residue(&self, (q, factor): (C, C), x: f64) -> C {
        C::new(0.0, PI * x) * factor * hankel2(q * x)
    }

    /// (G4): W(x) for x ≥ [`Far::from_x`].
    pub fn scaled(&self, x: f64) -> C {
        let poles = self
            .poles
            .iter()
            .fold(C::new(0.0, 0.0), |s, &p| s + self.residue(p, x));
        poles + 0.5 * x * (self.cut(x, true) + self.cut(x, false))
    }

    /// The poles of G taken into (G4), the Rayleigh pole first (for the tests and docs).
    pub fn poles(&self) -> Vec<C> {
        self.poles.iter().map(|p| p.0).collect()
    }

    /// L_b of (G4) for the P cut (`p`) or the S cut.
    fn cut(&self, x: f64, p: bool) -> C {
        let i = C::new(0.0, 1.0);
        let b = if p { self.q_p } else { self.q_s };
        let k2 = self.kappa2;
        let f = |s: f64| {
            let t = s * s / x;
            let q = b - i * t;
            // The cut's own root on its right side: √(q − b) → √t·e^{−iπ/4}.
            let own = C::new(0.0, -t.sqrt()) * (i * (q + b)).sqrt();
            let (np, ns) = if p {
                (own, vertical_root(q, self.q_s))
            } else {
                (vertical_root(q, self.q_p), own)
            };
            let q2 = q * q;
            let a = 2.0 * q2 - k2;
            let g = |np: C, ns: C| -k2 * np / (a * a - 4.0 * q2 * np * ns);
            let jump = if p {
                g(np, ns) - g(-np, ns)
            } else {
                g(np, ns) - g(np, -ns)
            };
            -i * jump * q * hankel2(q * x) * (2.0 * s / x)
        };
        let panels = (S_END / S_PANEL).round() as usize;
        (0..panels)
            .map(|k| adaptive(&f, k as f64 * S_PANEL, (k + 1) as f64 * S_PANEL, 0))
            .fold(C::new(0.0, 0.0), |s, v| s + v)
    }
}
