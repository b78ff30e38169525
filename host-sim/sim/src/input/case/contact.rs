//! `[contact]` in SI, checked: the magnets' skid (docs/contact.md).

use super::checks::{non_negative, positive, within};
use crate::input::scenario::ContactSection;
use crate::physics::skid::Skid;
use crate::{Error, Result};

/// The skid of `[contact]` (each key's default where it is not written), for magnets of
/// nominal gap `h0` (m; `None`: a train without magnets, whose skid is never used).
pub(super) fn skid(c: Option<&ContactSection>, h0: Option<f64>) -> Result<Skid> {
    let d = Skid::DEFAULT;
    // The set-down gap's default is twice the scenario's nominal gap (docs/contact.md).
    let d = Skid {
        setdown: h0.map_or(d.setdown, |h0| 2.0 * h0),
        ..d
    };
    let Some(c) = c else {
        return below_nominal(d, h0);
    };
    let or = |v: Option<f64>, default: f64| v.unwrap_or(default);
    let skid = Skid {
        gap: non_negative("contact.skid_gap_m", or(c.skid_gap_m, d.gap))?,
        setdown: positive("contact.setdown_gap_m", or(c.setdown_gap_m, d.setdown))?,
        stiffness: positive(
            "contact.stiffness_MN_per_m",
            or(c.stiffness_MN_per_m, d.stiffness * 1e-6),
        )? * 1e6,
        damping: non_negative(
            "contact.damping_kN_s_per_m",
            or(c.damping_kN_s_per_m, d.damping * 1e-3),
        )? * 1e3,
        friction: within(
            "contact.friction",
            or(c.friction, d.friction),
            0.0,
            2.0,
            "a sliding friction coefficient (dry steel on steel is about 0.5)",
        )?,
        slip: positive(
            "contact.slip_regularisation_m_per_s",
            or(c.slip_regularisation_m_per_s, d.slip),
        )?,
    };
    below_nominal(skid, h0)
}

/// The skid must sit below the nominal gap and the set-down stop above it: a magnet at h0
/// must fly free of both.
fn below_nominal(s: Skid, h0: Option<f64>) -> Result<Skid> {
    match h0 {
        Some(h0) if s.gap >= h0 => Err(Error::invalid(
            "contact.skid_gap_m",
            format!(
                "must be below the nominal gap controller.h0_m = {h0} m (a magnet at h0 would sit \
                 on its skid), got {} m",
                s.gap
            ),
        )),
        Some(h0) if s.setdown <= h0 => Err(Error::invalid(
            "contact.setdown_gap_m",
            format!(
                "must be above the nominal gap controller.h0_m = {h0} m (a magnet at h0 would be \
                 set down on the guideway), got {} m",
                s.setdown
            ),
        )),
        _ => Ok(s),
    }
}
