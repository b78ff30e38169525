//! The track on the girder: each rail a beam on discrete fastenings (rail pads) over a slab,
//! the slab on a cement–asphalt (CA) mortar layer on the deck. docs/cars.md, "The track on
//! the girder".
//!
//! # The layered support under a wheel
//!
//! Under a static wheel load P the rail head sinks relative to the deck by c(x)·P, the
//! compliances of the layers in series,
//!
//! ```text
//! c(x) = c_rail(s) + c_slab,    s = x mod a  (the wheel's place within a fastening bay)
//! ```
//!
//! - c_rail(s): the rail (Euler–Bernoulli, E·I) on discrete springs k_p every a metres, a
//!   point load at s from a fastening, solved by the finite-element method with Hermite
//!   cubic elements (exact for a static point load on such a beam) over ±`BAYS` bays, free
//!   at both ends ([`SlabTrack::rail_compliance`]). Its limit of dense fastenings is Hetényi's
//!   beam on a Winkler foundation of modulus k_p/a, w0 = P β/(2k), β = (k/(4EI))^{1/4}
//!   ([`winkler_compliance`]); the difference between the two is the discreteness, which the
//!   wheel feels as a stiffness varying at the fastening passing frequency v/a.
//! - c_slab: the slab (E·I of the slab) on the mortar layer (a Winkler modulus k_m per metre)
//!   under the same point load, Hetényi's w0/P = β_s/(2 k_m): an upper bound, as the pads
//!   spread the load over about 1/β of rail.
//!
//! # The rail's participating mass
//!
//! Under each wheel the rail has one vertical DOF, a mass m_e on a spring 1/c(x) and a
//! damper c_e to the deck ([`super::rail_mass`]), the wheel on it through Hertz. m_e and
//! c_e are the low-frequency expansion of the dynamic stiffness of Hetényi's beam under a
//! point load: with the foundation k + iωc − mω² per metre, 1/α(ω) = 8 EI^{1/4}
//! (k + iωc − mω²)^{3/4} ≈ (2k/β)·(1 + (3/4)(iωc − mω²)/k), so
//!
//! ```text
//! k_e = 2k/β,   c_e = (c_p/a)·3/(2β),   m_e = m_r·3/(2β)
//! ```
//!
//! (k = k_p/a; [`SlabTrack::rail_damping`], [`SlabTrack::rail_effective_mass`]): the rail's
//! mass and the pads' damping over 3/(2β) of rail, the integral of the square of the
//! Winkler rail's deflection shape e^{−β|x|}(cos βx + sin βx). The support's stiffness is
//! the discrete rail's 1/c(x) rather than 2k/β, so the wheel still feels the fastenings.
//!
//! The deck carries the track's mass per metre ([`SlabTrack::mass_per_m`]: both rails, the
//! slab and the mortar), and every wheel force reaches it at the wheel's rail point.

use crate::{Error, Result};

/// The fewest fastening bays on each side of the load in the discrete rail model (the
/// deflection decays as e^{−βx}; β·a ≈ 0.8 for the default track).
pub const BAYS: usize = 40;

/// Sample points over one fastening bay in the compliance table.
pub const SAMPLES: usize = 16;

/// A slab track on the deck, SI (summary.json's names in the serde renames).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SlabTrack {
    /// Rail bending stiffness E·I (vertical), N·m².
    #[serde(rename = "rail_bending_stiffness_N_m2")]
    pub rail_ei: f64,
    /// Rail mass per metre (one rail), kg/m.
    #[serde(rename = "rail_mass_kg_per_m")]
    pub rail_mass: f64,
    /// Vertical stiffness of one fastening (rail pad), N/m.
    #[serde(rename = "pad_stiffness_N_per_m")]
    pub pad_stiffness: f64,
    /// Fastening spacing a, m.
    #[serde(rename = "pad_spacing_m")]
    pub pad_spacing: f64,
    /// Vertical damping of one fastening, N·s/m.
    #[serde(rename = "pad_damping_N_s_per_m")]
    pub pad_damping: f64,
    /// Slab bending stiffness E·I (about the lateral axis), N·m².
    #[serde(rename = "slab_bending_stiffness_N_m2")]
    pub slab_ei: f64,
    /// Slab mass per metre, kg/m.
    #[serde(rename = "slab_mass_kg_per_m")]
    pub slab_mass: f64,
    /// Mortar layer modulus (support stiffness per metre of track), N/m².
    #[serde(rename = "mortar_modulus_N_per_m2")]
    pub mortar_modulus: f64,
    /// Mortar mass per metre, kg/m.
    #[serde(rename = "mortar_mass_kg_per_m")]
    pub mortar_mass: f64,
}

/// A point load's compliance on an infinite Euler beam (`ei`, N·m²) on a Winkler foundation
/// of modulus `k` (N/m²): w0/P = β/(2k), β = (k/(4EI))^{1/4} (Hetényi 1946), m/N.
pub fn winkler_compliance(ei: f64, k: f64) -> f64 {
    let beta = (k / (4.0 * ei)).powf(0.25);
    beta / (2.0 * k)
}

impl SlabTrack {
    /// A CRTS II-type slab track with 60 kg/m rails (module docs; docs/cars.md states the
    /// sources): rail E·I = 2.059e11 × 3.217e−5 N·m² and 60.64 kg/m (CHN60, as in Zhai, Wang &
    /// Lin, JSV 270 (2004) 673–683); fastenings 6.0e7 N/m every 0.6 m (the standard fastening
    /// of VTCM_simulation's `configs/standard/fastener_kv.yaml`); the slab 2.55 m × 0.2 m of
    /// C55 concrete (E = 3.55e10 Pa, 2500 kg/m³) on 30 mm of CA mortar (E = 8e9 Pa,
    /// 1950 kg/m³) — the slab and mortar values are **estimates** of a CRTS II section.
    pub fn crts2() -> Self {
        let (w, h, t) = (2.55, 0.2, 0.03);
        SlabTrack {
            rail_ei: 2.059e11 * 3.217e-5,
            rail_mass: 60.64,
            pad_stiffness: 6.0e7,
            pad_spacing: 0.6,
            pad_damping: 5.0e4,
            slab_ei: 3.55e10 * w * h * h * h / 12.0,
            slab_mass: 2500.0 * w * h,
            mortar_modulus: 8.0e9 * w / t,
            mortar_mass: 1950.0 * w * t,
        }
    }

    /// Refuses a non-positive or non-finite value, naming its key under `track.`.
    pub fn check(&self) -> Result<()> {
        for (key, v) in [
            ("rail_bending_stiffness_N_m2", self.rail_ei),
            ("rail_mass_kg_per_m", self.rail_mass),
            ("pad_stiffness_N_per_m", self.pad_stiffness),
            ("pad_spacing_m", self.pad_spacing),
            ("slab_bending_stiffness_N_m2", self.slab_ei),
            ("mortar_modulus_N_per_m2", self.mortar_modulus),
        ] {
            if !(v.is_finite() && v > 0.0 && v < 1e15) {
                return Err(Error::invalid(
                    format!("track.{key}"),
                    format!("must be finite, > 0 and < 1e15, got {v}"),
                ));
            }
        }
        for (key, v) in [
            ("pad_damping_N_s_per_m", self.pad_damping),
            ("slab_mass_kg_per_m", self.slab_mass),
            ("mortar_mass_kg_per_m", self.mortar_mass),
        ] {
            if !(v.is_finite() && (0.0..1e6).contains(&v)) {
                return Err(Error::invalid(
                    format!("track.{key}"),
                    format!("must be in [0, 1e6) (SI: kg/m, N·s/m), got {v}"),
                ));
            }
        }
        if self.pad_spacing > 5.0 {
            return Err(Error::invalid(
                "track.pad_spacing_m",
                format!("must be at most 5 m, got {}", self.pad_spacing),
            ));
        }
        Ok(())
    }

    /// The track's mass per metre of deck (two rails, slab, mortar), kg/m.
    pub fn mass_per_m(&self) -> f64 {
        2.0 * self.rail_mass + self.slab_mass + self.mortar_mass
    }

    /// The compliance of one rail on its discrete fastenings under a point load at `s`
    /// (m, 0 ≤ s ≤ a) from a fastening, m/N (module docs).
    pub fn rail_compliance(&self, s: f64) -> Result<f64> {
        discrete_beam_compliance(self.rail_ei, self.pad_stiffness, self.pad_spacing, s)
    }

    /// β = (k/(4EI))^{1/4} of the rail on its pads smeared to the modulus k = k_p/a, 1/m.
    pub fn beta(&self) -> f64 {
        (self.pad_stiffness / self.pad_spacing / (4.0 * self.rail_ei)).powf(0.25)
    }

    /// The rail's participating mass under a wheel, kg: the rail's mass per metre over
    /// 3/(2β) of rail, m_r·3/(2β) (module docs, "The rail's participating mass").
    pub fn rail_effective_mass(&self) -> f64 {
        self.rail_mass * 1.5 / self.beta()
    }

    /// The pads' damping under a wheel, N·s/m: the smeared damping c_p/a over 3/(2β) of
    /// rail, (c_p/a)·3/(2β) (module docs, "The rail's participating mass").
    pub fn rail_damping(&self) -> f64 {
        self.pad_damping / self.pad_spacing * 1.5 / self.beta()
    }

    /// The slab's compliance on its mortar, m/N (module docs).
    pub fn slab_compliance(&self) -> f64 {
        winkler_compliance(self.slab_ei, self.mortar_modulus)
    }
}

/// The deflection per unit load under a point load at `s` from a support, of an Euler beam
/// (`ei`) on springs `k` every `a` metres, free at both ends, over enough bays each side
/// that the deflection has decayed to e^{−30} (at least [`BAYS`]; module docs). The stiffness
/// matrix is banded (half-bandwidth 3) and solved by a banded Cholesky factorisation.
pub fn discrete_beam_compliance(ei: f64, k: f64, a: f64, s: f64) -> Result<f64> {
    let s = s.clamp(0.0, a);
    let beta = (k / a / (4.0 * ei)).powf(0.25);
    let bays = ((30.0 / (beta * a)).ceil() as usize).clamp(BAYS, 100_000);
    // Nodes: the supports at j·a, j = −bays..=bays, and the load point if between two.
    let mut xs: Vec<f64> = (0..=2 * bays)
        .map(|j| (j as f64 - bays as f64) * a)
        .collect();
    if s != 0.0 && s != a {
        xs.push(s);
        xs.sort_by(f64::total_cmp);
    }
    let n = 2 * xs.len();
    // Lower band: band[i][d] = K[i][i − d], d = 0..=3.
    let mut band = vec![[0.0f64; 4]; n];
    let mut add = |i: usize, j: usize, v: f64| {
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        band[i][i - j] += v;
    };
    for e in 0..xs.len() - 1 {
        let l = xs[e + 1] - xs[e];
        let c = ei / (l * l * l);
        let ke = [
            [12.0, 6.0 * l, -12.0, 6.0 * l],
            [6.0 * l, 4.0 * l * l, -6.0 * l, 2.0 * l * l],
            [-12.0, -6.0 * l, 12.0, -6.0 * l],
            [6.0 * l, 2.0 * l * l, -6.0 * l, 4.0 * l * l],
        ];
        for (i, row) in ke.iter().enumerate() {
            for (j, v) in row.iter().enumerate().take(i + 1) {
                add(2 * e + i, 2 * e + j, c * v);
            }
        }
    }
    let tol = 1e-9 * a;
    let mut load = 0;
    for (i, &x) in xs.iter().enumerate() {
        if ((x / a).round() * a - x).abs() < tol {
            add(2 * i, 2 * i, k);
        }
        if (x - s).abs() < tol {
            load = 2 * i;
        }
    }
    let singular = || Error::numerical("track: the rail on its fastenings is singular");
    // Banded Cholesky in place: band[i][d] becomes L[i][i − d].
    for i in 0..n {
        for d in (0..=3.min(i)).rev() {
            let j = i - d;
            let mut v = band[i][d];
            for m in (j.saturating_sub(3).max(i.saturating_sub(3)))..j {
                v -= band[i][i - m] * band[j][j - m];
            }
            if d == 0 {
                if v.is_nan() || v <= 0.0 {
                    return Err(singular());
                }
                band[i][0] = v.sqrt();
            } else {
                band[i][d] = v / band[j][0];
            }
        }
    }
    let mut y = vec![0.0; n];
    y[load] = 1.0;
    for i in 0..n {
        let mut v = y[i];
        for m in i.saturating_sub(3)..i {
            v -= band[i][i - m] * y[m];
        }
        y[i] = v / band[i][0];
    }
    for i in (0..n).rev() {
        let mut v = y[i];
        for (m, ym) in y.iter().enumerate().take((i + 4).min(n)).skip(i + 1) {
            v -= band[m][m - i] * ym;
        }
        y[i] = v / band[i][0];
    }
    Ok(y[load])
}

/// The compliance of the layered support along the track, tabulated over one fastening bay
/// (the fastenings at x = j·a), m/N.
#[derive(Clone, Debug, PartialEq)]
pub struct TrackSupport {
    /// The track.
    pub track: SlabTrack,
    /// c(s) at s = i·a/SAMPLES, i = 0..SAMPLES (the last equals the first).
    table: Vec<f64>,
}

impl TrackSupport {
    /// The support of `track` (module docs).
    pub fn new(track: &SlabTrack) -> Result<Self> {
        track.check()?;
        let a = track.pad_spacing;
        let slab = track.slab_compliance();
        let table = (0..=SAMPLES)
            .map(|i| Ok(track.rail_compliance(a * i as f64 / SAMPLES as f64)? + slab))
            .collect::<Result<Vec<f64>>>()?;
        Ok(TrackSupport {
            track: *track,
            table,
        })
    }

    /// The compliance under a wheel at x (m), linear between the table's samples.
    pub fn compliance_at(&self, x: f64) -> f64 {
        let a = self.track.pad_spacing;
        let u = (x / a).rem_euclid(1.0) * SAMPLES as f64;
        let i = (u.floor() as usize).min(SAMPLES - 1);
        let f = u - i as f64;
        self.table[i] * (1.0 - f) + self.table[i + 1] * f
    }

    /// The mean compliance over a bay (trapezoidal over the table), m/N: the reference the
    /// rail masses' rest is taken at ([`super::rail_mass`]).
    pub fn mean(&self) -> f64 {
        let n = SAMPLES as f64;
        let inner: f64 = self.table[1..SAMPLES].iter().sum();
        (inner + 0.5 * (self.table[0] + self.table[SAMPLES])) / n
    }
}
