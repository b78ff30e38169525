//! Which parameter an error is about, as data ([`Field`]): the law it belongs to and its key,
//! so that every edge (the scenario's keys, the C API's error codes, the firmware's fault
//! keys) names it without reading the message back.

use super::LawName;

/// A parameter (or a coefficient derived from parameters) that a [`crate::ParamError`] is
/// about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Field {
    /// The law whose own parameter it is; `None` for the magnet's, its coil's and the
    /// paper's inner law's ([`crate::Params`]) and for the gap.
    pub law: Option<LawName>,
    /// Its key as the core's serde names spell it, units in the name (`h0_m`,
    /// `kd_V_s_per_m`); `None` for a coefficient derived from several parameters (a
    /// sub-step's `c`, the state law's `ω²·δ`).
    pub key: Option<&'static str>,
    /// How messages name it (`h0`, `state kd`, `state v_max − R0·i0`).
    pub name: &'static str,
}

impl Field {
    /// A parameter of the magnet, its coil or the paper's inner law.
    pub const fn magnet(key: &'static str, name: &'static str) -> Self {
        Field {
            law: None,
            key: Some(key),
            name,
        }
    }

    /// A parameter of `law`.
    pub const fn of(law: LawName, key: &'static str, name: &'static str) -> Self {
        Field {
            law: Some(law),
            key: Some(key),
            name,
        }
    }

    /// A coefficient derived from `law`'s parameters (`None`: from the magnet's).
    pub const fn derived(law: Option<LawName>, name: &'static str) -> Self {
        Field {
            law,
            key: None,
            name,
        }
    }

    /// Whether `self` and `other` are the same parameter (the message's wording aside: a
    /// bound may be named with what it is compared to).
    pub fn is(&self, other: Field) -> bool {
        self.law == other.law && self.key == other.key
    }
}

impl core::fmt::Display for Field {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name)
    }
}
