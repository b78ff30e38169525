//! `[support]`: the ground motion at the viaduct's piers as a scenario gives it, and its
//! conversion into the [`SupportMotion`] the viaduct takes (docs/seismic.md "Support motion").
//!
//! Why a file of its own: the section is data for one model (the viaduct on its footings);
//! its keys, limits and conversion stay together, and `Scenario`/`Case` hold it as one field
//! each (`Case::new` converts it through `input/case/viaduct.rs`).

use crate::physics::seismic::accelerogram::{synthesize, Envelope, GroundFilter, KeyName, Spec, G};
use crate::physics::seismic::support::{GroundRecord, SupportMotion};
use crate::Error;
use crate::Result;
use serde::{Deserialize, Serialize};

/// The largest settlement a pier may be given (m): a metre is far beyond any pier that still
/// carries a guideway; a larger value is a slip of the unit.
pub const MAX_SETTLEMENT_M: f64 = 1.0;

/// The slowest and fastest apparent wave speed along the line (m/s): below the slowest soft
/// soil's shear waves (~50 m/s), above which the delay over a 30 m span is below a
/// microsecond.
pub const APPARENT_SPEED_M_PER_S: (f64, f64) = (10.0, 1e8);

/// `support.spatial`: how the piers share the record.
#[derive(Deserialize, Serialize, Debug, Clone, Copy, Default, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum Spatial {
    /// Every pier at once.
    #[default]
    Uniform,
    /// Pier k delayed by its distance from pier 1 over `apparent_speed_m_per_s`.
    WavePassage,
}

/// `[[support.settlement]]`: pier `pier` (1-based, pier 1 at x = 0) displaced statically.
#[derive(Deserialize, Serialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct SettlementSection {
    pub pier: usize,
    #[serde(default)]
    pub dx_m: f64,
    #[serde(default)]
    pub dy_m: f64,
    #[serde(default)]
    pub dz_m: f64,
}

/// `[support]` (module docs).
#[derive(Deserialize, Serialize, Debug, Clone, Default)]
#[serde(deny_unknown_fields)]
pub struct SupportSection {
    /// A ground-acceleration CSV (`maglev accelerogram`'s shape) every pier follows.
    pub record: Option<String>,
    /// One such CSV per pier, pier 1 first (instead of `record`).
    pub records: Option<Vec<String>>,
    #[serde(default)]
    pub spatial: Spatial,
    /// Apparent speed of the ground wave along the line, for `spatial = "wave-passage"`.
    pub apparent_speed_m_per_s: Option<f64>,
    /// A synthetic record every pier follows (instead of `record`; `maglev accelerogram`'s
    /// model, docs/seismic.md).
    pub synthetic: Option<SyntheticSection>,
    #[serde(default)]
    pub settlement: Vec<SettlementSection>,
}

/// The most samples a `[support.synthetic]` record may have: 2²⁰, over an hour at the default
/// 5 ms and 105 s at the finest 0.1 ms. A case is checked before anything large is allocated
/// (the record is made while the case resolves); this keeps every buffer of the synthesis
/// (about 16 B per sample each) in tens of MB.
pub const MAX_SYNTHETIC_SAMPLES: usize = 1 << 20;

/// `[support.synthetic]` and the arguments of `maglev accelerogram`: one struct, read by serde
/// from a scenario and by clap from the command line (`maglev accelerogram` flattens it, with
/// this crate's `clap` feature), so
/// the keys, their defaults and their conversion to the model's [`Spec`] are written once and
/// the same values give the same bits either way.
#[derive(Deserialize, Serialize, Debug, Clone)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
#[serde(deny_unknown_fields)]
pub struct SyntheticSection {
    /// Peak ground acceleration of each horizontal component, in g.
    #[cfg_attr(feature = "clap", arg(long, allow_negative_numbers = true))]
    pub pga_g: f64,
    /// Ground class for the filter: firm, medium or soft (Der Kiureghian & Neuenhofer 1992).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = default_ground()))]
    #[serde(default = "default_ground")]
    pub ground: String,
    /// Vertical peak over horizontal peak.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = default_vertical_ratio(), allow_negative_numbers = true))]
    #[serde(default = "default_vertical_ratio")]
    pub vertical_ratio: f64,
    /// Record length, s.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = default_duration(), allow_negative_numbers = true))]
    #[serde(default = "default_duration")]
    pub duration_s: f64,
    /// Sample step, s.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = default_dt(), allow_negative_numbers = true))]
    #[serde(default = "default_dt")]
    pub dt_s: f64,
    /// Seed of the phases (u64); x, y and z are independent streams of it.
    #[cfg_attr(feature = "clap", arg(long, default_value_t))]
    #[serde(default)]
    pub seed: u64,
    /// Envelope: end of the quadratic rise, s.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = default_rise(), allow_negative_numbers = true))]
    #[serde(default = "default_rise")]
    pub rise_s: f64,
    /// Envelope: end of the strong motion, s.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = default_strong_end(), allow_negative_numbers = true))]
    #[serde(default = "default_strong_end")]
    pub strong_end_s: f64,
    /// Envelope: exponential decay rate after the strong motion, 1/s.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = default_decay(), allow_negative_numbers = true))]
    #[serde(default = "default_decay")]
    pub decay_per_s: f64,
}
fn default_ground() -> String {
    "medium".into()
}
fn default_vertical_ratio() -> f64 {
    2.0 / 3.0
}
fn default_duration() -> f64 {
    20.0
}
fn default_dt() -> f64 {
    0.005
}
fn default_rise() -> f64 {
    2.0
}
fn default_strong_end() -> f64 {
    10.0
}
fn default_decay() -> f64 {
    0.4
}

impl SyntheticSection {
    /// The model's SI spec (g → m/s² here, at the edge; the ground class by name, any case),
    /// an unknown class named by `name` (`support.synthetic.ground`, `--ground`).
    pub fn spec(&self, name: KeyName) -> Result<Spec> {
        let filter = GroundFilter::class(&self.ground).ok_or_else(|| {
            Error::invalid(
                name("ground"),
                format!(
                    "unknown ground class {:?}: expected firm, medium or soft",
                    self.ground
                ),
            )
        })?;
        Ok(Spec {
            filter,
            envelope: Envelope {
                rise_s: self.rise_s,
                strong_end_s: self.strong_end_s,
                decay_per_s: self.decay_per_s,
            },
            duration_s: self.duration_s,
            dt_s: self.dt_s,
            pga: self.pga_g * G,
            vertical_ratio: self.vertical_ratio,
            seed: self.seed,
        })
    }

    /// The record, its values checked with their `support.synthetic.*` keys.
    pub fn record(&self) -> Result<GroundRecord> {
        let key = |k: &str| format!("support.synthetic.{k}");
        let spec = self.spec(&key)?;
        let n = spec.samples(&key)?;
        if n > MAX_SYNTHETIC_SAMPLES {
            return Err(Error::invalid(
                format!("{}/{}", key("duration_s"), key("dt_s")),
                format!(
                    "give {n} samples, more than {MAX_SYNTHETIC_SAMPLES} (a scenario's record is made when it loads)"
                ),
            ));
        }
        let a = synthesize(&spec, &key)?;
        let samples = (0..a.x.len()).map(|j| [a.x[j], a.y[j], a.z[j]]).collect();
        GroundRecord::new(a.dt_s, samples)
    }
}

impl SupportSection {
    /// The record files the section reads (`record`, then `records` in order): the inputs of
    /// a case besides its scenario text, which a sweep hashes to notice a changed record.
    pub fn files(&self) -> Vec<&str> {
        self.record
            .iter()
            .chain(self.records.iter().flatten())
            .map(String::as_str)
            .collect()
    }

    /// The motion of the `piers` piers, `span_length` apart; `read` returns a record file's
    /// text (the caller resolves the path against the scenario's folder).
    pub fn to_motion(
        &self,
        piers: usize,
        span_length: f64,
        read: impl Fn(&str) -> Result<String>,
    ) -> Result<SupportMotion> {
        let x: Vec<f64> = (0..piers).map(|k| k as f64 * span_length).collect();
        self.to_motion_at(&x, read)
    }

    /// As [`Self::to_motion`] for supports at `positions` (m along the line, support 1
    /// first; one per pier, or per span end for spans on rigid supports).
    pub fn to_motion_at(
        &self,
        positions: &[f64],
        read: impl Fn(&str) -> Result<String>,
    ) -> Result<SupportMotion> {
        let piers = positions.len();
        let load = |path: &str| GroundRecord::from_csv(path, &read(path)?);
        let given = [
            self.record.is_some(),
            self.records.is_some(),
            self.synthetic.is_some(),
        ];
        if given.iter().filter(|g| **g).count() > 1 {
            return Err(Error::invalid(
                "support.records",
                "give one of support.record, support.records and [support.synthetic]",
            ));
        }
        let mut motion = match (&self.record, &self.records) {
            (None, Some(list)) => {
                if list.len() != piers {
                    return Err(Error::invalid(
                        "support.records",
                        format!(
                            "must list one record per pier ({piers}), got {}",
                            list.len()
                        ),
                    ));
                }
                if self.spatial != Spatial::Uniform {
                    return Err(Error::invalid(
                        "support.spatial",
                        "must be \"uniform\" with one record per pier",
                    ));
                }
                SupportMotion::per_support(list.iter().map(|p| load(p)).collect::<Result<_>>()?)
            }
            (Some(path), None) => self.shared(load(path)?, positions)?,
            (None, None) => match &self.synthetic {
                Some(syn) => self.shared(syn.record()?, positions)?,
                None => SupportMotion::at_rest(piers),
            },
            (Some(_), Some(_)) => unreachable!("refused above"),
        };
        for s in &self.settlement {
            if s.pier == 0 || s.pier > piers {
                return Err(Error::invalid(
                    "support.settlement.pier",
                    format!("must be a pier from 1 to {piers}, got {}", s.pier),
                ));
            }
            for (key, v) in [("dx_m", s.dx_m), ("dy_m", s.dy_m), ("dz_m", s.dz_m)] {
                if !(v.is_finite() && v.abs() <= MAX_SETTLEMENT_M) {
                    return Err(Error::invalid(
                        format!("support.settlement.{key}"),
                        format!("must be at most {MAX_SETTLEMENT_M} m in magnitude, got {v}"),
                    ));
                }
            }
            motion = motion.with_settlement(s.pier - 1, [s.dx_m, s.dy_m, s.dz_m])?;
        }
        Ok(motion)
    }

    /// One record for every pier, uniform or with wave passage.
    fn shared(&self, record: GroundRecord, positions: &[f64]) -> Result<SupportMotion> {
        match (self.spatial, self.apparent_speed_m_per_s) {
            (Spatial::Uniform, None) => Ok(SupportMotion::uniform(record, positions.len())),
            (Spatial::Uniform, Some(_)) => Err(Error::invalid(
                "support.apparent_speed_m_per_s",
                "is for spatial = \"wave-passage\" only",
            )),
            (Spatial::WavePassage, None) => Err(Error::invalid(
                "support.apparent_speed_m_per_s",
                "is required with spatial = \"wave-passage\"",
            )),
            (Spatial::WavePassage, Some(c)) => {
                let (lo, hi) = APPARENT_SPEED_M_PER_S;
                if !(c.is_finite() && (lo..=hi).contains(&c)) {
                    return Err(Error::invalid(
                        "support.apparent_speed_m_per_s",
                        format!("must be within [{lo}, {hi:e}] m/s, got {c}"),
                    ));
                }
                SupportMotion::wave_passage(record, positions, c)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::seismic::support::HEADER;

    fn section(text: &str) -> SupportSection {
        toml::from_str(text).unwrap()
    }

    fn read(_: &str) -> Result<String> {
        Ok(format!(
            "{HEADER}\n0.0,0,0,0\n0.1,0,0,2\n0.2,0,0,-2\n0.3,0,0,0\n"
        ))
    }

    /// Wave passage over 30 m spans at 300 m/s: pier 3 is 0.2 s behind pier 1; a settlement
    /// lands on its pier (1-based).
    #[test]
    fn wave_passage_and_settlement_from_keys() {
        let s = section(
            "record = \"q.csv\"\nspatial = \"wave-passage\"\napparent_speed_m_per_s = 300.0\n\
             [[settlement]]\npier = 2\ndz_m = -0.01\n",
        );
        let m = s.to_motion(3, 30.0, read).unwrap();
        assert_eq!(m.supports(), 3);
        let (late, early) = (m.acceleration(2, 0.45)[2], m.acceleration(0, 0.25)[2]);
        assert!(
            (late - early).abs() < 1e-12 && (early + 1.0).abs() < 1e-12,
            "{late} {early}"
        );
        assert_eq!(m.settlement(1), [0.0, 0.0, -0.01]);
        assert_eq!(m.settlement(0), [0.0; 3]);
    }

    /// A synthetic value out of its limits names its scenario key.
    #[test]
    fn synthetic_values_name_their_scenario_key() {
        let bad = |text: &str| {
            section(text)
                .to_motion(2, 30.0, read)
                .unwrap_err()
                .to_string()
        };
        assert!(bad("[synthetic]\npga_g = 3.0\n").contains("support.synthetic.pga_g"));
        assert!(bad("[synthetic]\npga_g = 0.1\nground = \"clay\"\n")
            .contains("support.synthetic.ground"));
        assert!(bad("record = \"q.csv\"\n[synthetic]\npga_g = 0.1\n").contains("one of"));
        let long = bad("[synthetic]\npga_g = 0.1\nduration_s = 600.0\ndt_s = 0.0005\n");
        assert!(
            long.contains("support.synthetic.duration_s/support.synthetic.dt_s")
                && long.contains("1200001 samples, more than 1048576"),
            "{long}"
        );
    }

    /// Bad values are refused naming the key.
    #[test]
    fn bad_keys_are_refused_naming_them() {
        for (text, key) in [
            (
                "record = \"q.csv\"\nspatial = \"wave-passage\"\n",
                "support.apparent_speed_m_per_s",
            ),
            (
                "record = \"q.csv\"\nspatial = \"wave-passage\"\napparent_speed_m_per_s = 1.0\n",
                "support.apparent_speed_m_per_s",
            ),
            ("records = [\"a\", \"b\"]\n", "support.records"),
            (
                "[[settlement]]\npier = 4\ndz_m = -0.01\n",
                "support.settlement.pier",
            ),
            (
                "[[settlement]]\npier = 1\ndz_m = -2.0\n",
                "support.settlement.dz_m",
            ),
        ] {
            let e = section(text)
                .to_motion(3, 30.0, read)
                .unwrap_err()
                .to_string();
            assert!(e.contains(key), "{text}: {e}");
        }
        assert!(toml::from_str::<SupportSection>("recrd = \"q.csv\"\n").is_err());
    }
}
