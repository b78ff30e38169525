//! `[track]` in SI: the slab track of a `high-speed` train (`crate::physics::rail::track`),
//! where its rails lie on the girder and the spectrum of their irregularity.

use super::checks::finite;
use crate::input::scenario::TrackSection;
use crate::physics::rail::spectrum::TrackSpectrum;
use crate::physics::rail::track::SlabTrack;
use crate::{Error, Result};
use serde::Serialize;

/// The track in SI; summary.json's `case.track`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TrackCase {
    /// The layered support.
    #[serde(flatten)]
    pub slab: SlabTrack,
    /// Y of the track centre from the beam axis, m.
    #[serde(rename = "track_y_m")]
    pub track_y: f64,
    /// Z of the rail heads from the beam axis, m.
    #[serde(rename = "rail_z_m")]
    pub rail_z: f64,
    /// The irregularity's spectrum, by its scenario name.
    pub spectrum: String,
}

impl TrackCase {
    /// The spectrum named by `spectrum` (checked when the case was made).
    pub fn spectrum(&self) -> TrackSpectrum {
        TrackSpectrum::from_name(&self.spectrum).unwrap_or(TrackSpectrum::Chinese)
    }
}

/// The section in SI, checked.
pub(super) fn track(t: &TrackSection) -> Result<TrackCase> {
    let slab = SlabTrack {
        rail_ei: t.rail_bending_stiffness_N_m2,
        rail_mass: t.rail_mass_kg_per_m,
        pad_stiffness: t.pad_stiffness_N_per_m,
        pad_spacing: t.pad_spacing_m,
        pad_damping: t.pad_damping_N_s_per_m,
        slab_ei: t.slab_bending_stiffness_N_m2,
        slab_mass: t.slab_mass_kg_per_m,
        mortar_modulus: t.mortar_modulus_N_per_m2,
        mortar_mass: t.mortar_mass_kg_per_m,
    };
    slab.check()?;
    if TrackSpectrum::from_name(&t.spectrum).is_none() {
        return Err(Error::invalid(
            "track.spectrum",
            format!(
                "must be german-low, german-high or chinese, got {:?}",
                t.spectrum
            ),
        ));
    }
    Ok(TrackCase {
        slab,
        track_y: finite("track.track_y_m", t.track_y_m)?,
        rail_z: finite("track.rail_z_m", t.rail_z_m)?,
        spectrum: t.spectrum.clone(),
    })
}

#[cfg(test)]
mod tests {
    use crate::input::case::Case;

    /// paper-5-hsr's track is the CRTS II-type track of the library, and bad values are
    /// named by their key.
    #[test]
    fn the_bundled_track_is_the_librarys_and_bad_values_name_their_key() {
        let c = Case::load("paper-5-hsr", &[]).unwrap();
        let t = c.track.as_ref().unwrap();
        let want = crate::physics::rail::track::SlabTrack::crts2();
        for (got, want) in [
            (t.slab.rail_ei, want.rail_ei),
            (t.slab.pad_stiffness, want.pad_stiffness),
            (t.slab.slab_ei, want.slab_ei),
            (t.slab.mortar_modulus, want.mortar_modulus),
            (t.slab.mass_per_m(), want.mass_per_m()),
        ] {
            assert!((got - want).abs() <= 1e-9 * want, "{got} against {want}");
        }
        for (set, key) in [
            ("track.pad_spacing_m=0", "track.pad_spacing_m"),
            (
                "track.pad_stiffness_N_per_m=nan",
                "track.pad_stiffness_N_per_m",
            ),
            ("track.spectrum=\"flat\"", "track.spectrum"),
            ("track.track_y_m=inf", "track.track_y_m"),
        ] {
            let e = Case::load("paper-5-hsr", &[set.into()])
                .unwrap_err()
                .to_string();
            assert!(e.starts_with(key), "{set}: {e}");
        }
    }
}
