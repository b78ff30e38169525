//! Published spectral densities of the track irregularity of high-speed lines: the German
//! spectra (low and high disturbance) and the Chinese high-speed spectrum (TB/T 3352-2014).
//!
//! Every density here is **one-sided** in m²/(rad/m) of the spatial angular frequency Ω
//! (rad/m): the variance of the irregularity over a band is ∫ S(Ω) dΩ over it. (Table 1's
//! G_rr, `maglev_core::irregularity`, is two-sided; these are not.)
//!
//! # The German spectra
//!
//! ```text
//! vertical profile  S_v(Ω) = A_v Ω_c² / ((Ω² + Ω_r²)(Ω² + Ω_c²))
//! alignment         S_a(Ω) = A_a Ω_c² / ((Ω² + Ω_r²)(Ω² + Ω_c²))
//! cross level       S_c(Ω) = (A_v/b²) Ω_c² Ω² / ((Ω² + Ω_r²)(Ω² + Ω_c²)(Ω² + Ω_s²))
//! gauge             S_g(Ω) = A_g Ω_c² Ω² / ((Ω² + Ω_r²)(Ω² + Ω_c²)(Ω² + Ω_s²))
//! ```
//!
//! with Ω_c = 0.8246, Ω_r = 0.0206, Ω_s = 0.438 rad/m, b = 0.75 m, and A_v, A_a, A_g of
//! [`GERMAN_LOW`] and [`GERMAN_HIGH`] (m²·rad/m). These are the forms and values as the
//! vehicle–track literature quotes them (W. Zhai, *Vehicle–Track Coupled Dynamics*, Springer
//! 2020, ch. on track irregularities; the same numbers in the open VTCM_simulation code);
//! the original DB report was not read. The cross level is read as the height difference of
//! the two rails in m (its density in m²/(rad/m)), as those sources use it.
//!
//! # The Chinese high-speed spectrum (TB/T 3352-2014)
//!
//! Piecewise power laws in the spatial frequency f = Ω/2π (1/m), S(f) = A/fⁿ in
//! mm²/(1/m), with the break frequencies and coefficients of [`CHINESE`] (as tabulated in
//! VTCM_simulation; the standard's text was not read). In SI per rad/m:
//! S(Ω) = 10⁻⁶·S_f(Ω/2π)/(2π).

use std::f64::consts::TAU;

/// One irregularity component of a track (both rails: docs/cars.md, "Left and right rails").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Component {
    /// Vertical profile of the track centre (the mean of the two rails' heights).
    Vertical,
    /// Alignment: lateral position of the track centre.
    Alignment,
    /// Cross level: left rail height minus right rail height.
    CrossLevel,
    /// Gauge: widening of the gauge (left rail outward plus right rail outward).
    Gauge,
}

impl Component {
    /// The four components in a fixed order (their profiles' order in
    /// [`super::irregularity::RailIrregularity`]).
    pub const ALL: [Component; 4] = [
        Component::Vertical,
        Component::Alignment,
        Component::CrossLevel,
        Component::Gauge,
    ];

    /// The position of this component in [`Component::ALL`].
    pub const fn index(self) -> usize {
        self as usize
    }
}

/// A published track spectrum.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TrackSpectrum {
    /// The German spectrum of a given disturbance level ([`GERMAN_LOW`], [`GERMAN_HIGH`]).
    German(German),
    /// The Chinese high-speed spectrum, TB/T 3352-2014 ([`CHINESE`]).
    Chinese,
}

/// The German spectrum's coefficients (m²·rad/m) of one disturbance level.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct German {
    /// Vertical profile coefficient A_v.
    pub a_v: f64,
    /// Alignment coefficient A_a.
    pub a_a: f64,
    /// Gauge coefficient A_g.
    pub a_g: f64,
}

/// The German low-disturbance spectrum (high-speed lines).
pub const GERMAN_LOW: German = German {
    a_v: 4.032e-7,
    a_a: 2.119e-7,
    a_g: 5.32e-8,
};

/// The German high-disturbance spectrum.
pub const GERMAN_HIGH: German = German {
    a_v: 1.08e-6,
    a_a: 6.125e-7,
    a_g: 1.032e-7,
};

/// Ω_c of the German spectra, rad/m.
pub const OMEGA_C: f64 = 0.8246;
/// Ω_r of the German spectra, rad/m.
pub const OMEGA_R: f64 = 0.0206;
/// Ω_s of the German spectra, rad/m.
pub const OMEGA_S: f64 = 0.438;
/// b of the German cross-level spectrum, m (half the distance between the rolling circles).
pub const B_CROSS: f64 = 0.75;

/// One piecewise power law of TB/T 3352-2014: `breaks` (1/m, ascending) split the axis into
/// `breaks.len() + 1` pieces, piece i has S = a[i]/f^n[i] mm²/(1/m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PowerLaws {
    /// Break frequencies, 1/m.
    pub breaks: &'static [f64],
    /// Coefficients A, mm²/(1/m)·(1/m)ⁿ.
    pub a: &'static [f64],
    /// Exponents n.
    pub n: &'static [f64],
}

impl PowerLaws {
    /// S(f) in mm²/(1/m), f in 1/m.
    pub fn at(&self, f: f64) -> f64 {
        let i = self.breaks.iter().take_while(|&&b| f >= b).count();
        self.a[i] / f.powf(self.n[i])
    }
}

/// The Chinese high-speed spectrum, per component in [`Component::ALL`]'s order.
pub const CHINESE: [PowerLaws; 4] = [
    PowerLaws {
        breaks: &[0.0187, 0.0474, 0.1533],
        a: &[1.0544e-5, 3.5588e-3, 1.9784e-2, 3.9488e-4],
        n: &[3.3891, 1.9271, 1.3643, 3.4516],
    },
    PowerLaws {
        breaks: &[0.045, 0.1234],
        a: &[3.9513e-3, 1.1047e-2, 7.5633e-4],
        n: &[1.867, 1.5354, 2.8171],
    },
    PowerLaws {
        breaks: &[0.0258, 0.1163],
        a: &[3.6148e-3, 4.3685e-2, 4.5867e-3],
        n: &[1.7278, 1.0461, 2.0939],
    },
    PowerLaws {
        breaks: &[0.1090, 0.2938],
        a: &[5.4978e-2, 5.0701e-3, 1.8778e-4],
        n: &[0.8282, 1.9037, 4.5948],
    },
];

impl TrackSpectrum {
    /// The spectrum a scenario names: `german-low`, `german-high` or `chinese`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "german-low" => Some(Self::German(GERMAN_LOW)),
            "german-high" => Some(Self::German(GERMAN_HIGH)),
            "chinese" => Some(Self::Chinese),
            _ => None,
        }
    }

    /// The one-sided density of `component` at Ω = `omega` > 0 rad/m, m²/(rad/m).
    pub fn density(&self, component: Component, omega: f64) -> f64 {
        match self {
            Self::German(g) => g.density(component, omega),
            Self::Chinese => 1e-6 * CHINESE[component.index()].at(omega / TAU) / TAU,
        }
    }
}

impl German {
    /// The one-sided density of `component` at Ω = `omega` rad/m, m²/(rad/m) (module docs).
    pub fn density(&self, component: Component, omega: f64) -> f64 {
        let w2 = omega * omega;
        let (c2, r2, s2) = (OMEGA_C * OMEGA_C, OMEGA_R * OMEGA_R, OMEGA_S * OMEGA_S);
        let base = c2 / ((w2 + r2) * (w2 + c2));
        match component {
            Component::Vertical => self.a_v * base,
            Component::Alignment => self.a_a * base,
            Component::CrossLevel => self.a_v / (B_CROSS * B_CROSS) * base * w2 / (w2 + s2),
            Component::Gauge => self.a_g * base * w2 / (w2 + s2),
        }
    }
}
