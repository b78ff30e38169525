//! Wheel–rail contact mechanics: the Hertz contact ellipse, Kalker's linear creep
//! coefficients and the Shen–Hedrick–Elkins saturation. docs/cars.md, "Wheel–rail contact
//! of the high-speed car", gives the equations and sources.
//!
//! # Hertz (K. L. Johnson, *Contact Mechanics*, 1985, §4.2)
//!
//! With the relative curvatures A (rolling direction x) and B (lateral y), the ellipse's
//! semi-axes a (along x) and b (along y), e² = 1 − (minor/major)², K(e) and E(e) the complete
//! elliptic integrals and 1/E* = 2(1 − ν²)/E (two steel bodies):
//!
//! ```text
//! major along x (A ≤ B):  B/A = ((a/b)² E − K)/(K − E),   a³ = 3N (K − E)/(2π E* e² A)
//! ```
//!
//! and the same with x and y exchanged when A > B. As e → 0, (K − E)/e² → π/4 and the
//! circle of Hertz's sphere on a plane, a³ = 3NR/(4E*) with A = B = 1/(2R), is recovered.
//!
//! # Kalker's linear theory
//!
//! ```text
//! F_x = −f11 ξ_x,   F_y = −f22 ξ_y − f23 ξ_sp,   M_z = f23 ξ_y − f33 ξ_sp
//! f11 = G c² C11,  f22 = G c² C22,  f23 = G c³ C23,  f33 = G c⁴ C33,   c = √(ab)
//! ```
//!
//! with Kalker's coefficients C_ij(a/b) from [`KALKER`] (J. J. Kalker, *On the rolling
//! contact of two elastic bodies in the presence of dry friction*, thesis, Delft 1967; the
//! table as reproduced in W. Zhai, *Vehicle–Track Coupled Dynamics*, 2020, for steel),
//! linearly interpolated in a/b and held at the table's ends (a/b in [0.1, 10]).
//!
//! # Shen–Hedrick–Elkins (Shen, Hedrick & Elkins, Veh. Syst. Dyn. 12, 1983)
//!
//! The linear resultant F0 = √(F_x² + F_y²) is limited to the friction μN:
//!
//! ```text
//! F = μN (ε − ε²/3 + ε³/27)  for ε = F0/(μN) ≤ 3,   F = μN  beyond,
//! ```
//!
//! and F_x, F_y and M_z are scaled by F/F0.

use std::f64::consts::PI;

/// Kalker's coefficients: rows (a/b, C11, C22, C23, C33), a/b ascending.
pub const KALKER: [[f64; 5]; 19] = [
    [0.1, 3.618, 2.522, 0.5246, 8.964],
    [0.2, 3.658, 2.636, 0.6442, 4.548],
    [0.3, 3.712, 2.762, 0.7498, 3.112],
    [0.4, 3.788, 2.9, 0.8538, 2.41],
    [0.5, 3.862, 3.036, 0.9572, 1.988],
    [0.6, 3.958, 3.174, 1.06, 1.716],
    [0.7, 4.042, 3.32, 1.17, 1.52],
    [0.8, 4.138, 3.458, 1.28, 1.38],
    [0.9, 4.232, 3.596, 1.39, 1.27],
    [1.0, 4.336, 3.732, 1.502, 1.184],
    [1.0 / 0.9, 4.436, 3.88, 1.626, 1.1],
    [1.0 / 0.8, 4.572, 4.07, 1.788, 1.0228],
    [1.0 / 0.7, 4.748, 4.302, 1.996, 0.9424],
    [1.0 / 0.6, 4.984, 4.608, 2.284, 0.8638],
    [2.0, 5.302, 5.032, 2.688, 0.7852],
    [2.5, 5.77, 5.646, 3.332, 0.7074],
    [1.0 / 0.3, 6.54, 6.622, 4.458, 0.6284],
    [5.0, 7.988, 8.47, 6.882, 0.549],
    [10.0, 11.94, 13.44, 15.28, 0.4664],
];

/// Elastic constants of the wheel and rail steel and the friction coefficient.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Young's modulus E, Pa.
    pub young: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
    /// Friction coefficient μ (Shen–Hedrick–Elkins).
    pub friction: f64,
}

impl Default for Material {
    /// Steel, E = 2.06e11 Pa, ν = 0.3; μ = 0.3 (dry rail, a common choice in running-safety
    /// studies).
    fn default() -> Self {
        Material {
            young: 2.06e11,
            poisson: 0.3,
            friction: 0.3,
        }
    }
}

impl Material {
    /// E* of two bodies of this steel: E/(2(1 − ν²)).
    pub fn e_star(&self) -> f64 {
        self.young / (2.0 * (1.0 - self.poisson * self.poisson))
    }

    /// The shear modulus G = E/(2(1 + ν)).
    pub fn shear(&self) -> f64 {
        self.young / (2.0 * (1.0 + self.poisson))
    }
}

/// Complete elliptic integrals (K(e), E(e)) of modulus e in [0, 1), by the arithmetic–
/// geometric mean (Abramowitz & Stegun 17.6).
pub fn elliptic_ke(e: f64) -> (f64, f64) {
    let (mut a, mut g) = (1.0f64, (1.0 - e * e).sqrt());
    let mut c = e;
    let (mut sum, mut pow) = (0.5 * c * c, 0.5);
    for _ in 0..40 {
        if c.abs() < 1e-17 {
            break;
        }
        let an = 0.5 * (a + g);
        c = 0.5 * (a - g);
        g = (a * g).sqrt();
        a = an;
        pow *= 2.0;
        sum += pow * c * c;
    }
    let k = PI / (2.0 * a);
    (k, k * (1.0 - sum))
}

/// A Hertz contact ellipse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ellipse {
    /// Semi-axis along the rolling direction, m.
    pub a: f64,
    /// Semi-axis across it, m.
    pub b: f64,
}

/// The Hertz ellipse under the normal force `n` (N, > 0) for the relative curvatures `ca`
/// (rolling direction) and `cb` (lateral), 1/m, both > 0 (module docs).
pub fn hertz_ellipse(n: f64, ca: f64, cb: f64, m: &Material) -> Ellipse {
    let (small, large) = if ca <= cb { (ca, cb) } else { (cb, ca) };
    let ratio = large / small;
    // B/A = ((1/(1−e²)) E − K)/(K − E) rises from 1 at e = 0; bisect on e.
    let f = |e: f64| {
        let (k, el) = elliptic_ke(e);
        (el / (1.0 - e * e) - k) / (k - el)
    };
    let (mut lo, mut hi) = (0.0f64, 1.0 - 1e-15);
    let e = if ratio <= 1.0 + 1e-12 {
        0.0
    } else {
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if f(mid.max(1e-8)) < ratio {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    };
    let shape = if e < 1e-6 {
        PI / 4.0
    } else {
        let (k, el) = elliptic_ke(e);
        (k - el) / (e * e)
    };
    let major = (3.0 * n * shape / (2.0 * PI * m.e_star() * small)).cbrt();
    let minor = major * (1.0 - e * e).sqrt();
    if ca <= cb {
        Ellipse { a: major, b: minor }
    } else {
        Ellipse { a: minor, b: major }
    }
}

/// Kalker's creep coefficients (f11, f22, f23, f33) in N, N, N·m, N·m² for `ellipse`.
pub fn kalker(ellipse: &Ellipse, m: &Material) -> [f64; 4] {
    let g = (ellipse.a / ellipse.b).clamp(KALKER[0][0], KALKER[KALKER.len() - 1][0]);
    let i = KALKER
        .iter()
        .position(|row| row[0] >= g)
        .unwrap_or(KALKER.len() - 1)
        .max(1);
    let (lo, hi) = (&KALKER[i - 1], &KALKER[i]);
    let t = (g - lo[0]) / (hi[0] - lo[0]);
    let c = |j: usize| lo[j] + t * (hi[j] - lo[j]);
    let c2 = ellipse.a * ellipse.b;
    let gm = m.shear();
    [
        gm * c2 * c(1),
        gm * c2 * c(2),
        gm * c2.powf(1.5) * c(3),
        gm * c2 * c2 * c(4),
    ]
}

/// Creepages of one contact: longitudinal, lateral (1) and spin (1/m).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Creepage {
    /// ξ_x.
    pub x: f64,
    /// ξ_y.
    pub y: f64,
    /// ξ_sp, 1/m.
    pub spin: f64,
}

/// Creep forces of one contact in the contact plane: F_x, F_y (N) and the spin moment M_z
/// (N·m), and the saturation factor F/F0 applied.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Creep {
    /// Longitudinal force on the wheel, N.
    pub fx: f64,
    /// Lateral force on the wheel, N.
    pub fy: f64,
    /// Spin moment on the wheel about the contact normal, N·m.
    pub mz: f64,
    /// F/F0 of Shen–Hedrick–Elkins (1 in the linear range).
    pub saturation: f64,
}

/// Shen–Hedrick–Elkins: the saturated resultant for the linear one `f0` (N) under the
/// friction limit `limit` = μN (N).
pub fn she(f0: f64, limit: f64) -> f64 {
    if limit <= 0.0 {
        return 0.0;
    }
    let e = f0 / limit;
    if e <= 3.0 {
        limit * (e - e * e / 3.0 + e * e * e / 27.0)
    } else {
        limit
    }
}

/// Kalker's linear creep forces for `c` with coefficients `f`, saturated by
/// Shen–Hedrick–Elkins under the normal force `n` (module docs). No force when n ≤ 0.
pub fn creep_forces(c: &Creepage, f: &[f64; 4], n: f64, friction: f64) -> Creep {
    if n <= 0.0 {
        return Creep::default();
    }
    let fx = -f[0] * c.x;
    let fy = -f[1] * c.y - f[2] * c.spin;
    let mz = f[2] * c.y - f[3] * c.spin;
    let f0 = (fx * fx + fy * fy).sqrt();
    let s = if f0 > 0.0 {
        she(f0, friction * n) / f0
    } else {
        1.0
    };
    Creep {
        fx: s * fx,
        fy: s * fy,
        mz: s * mz,
        saturation: s,
    }
}
