//! Derived cases (validate's speeds, a sweep's axes): typed [`Changes`] applied to the
//! scenario as written and resolved again by [`Case::new`], so a derived case is checked
//! exactly as a loaded one and equals the case the same `--set` text gives.

use super::Case;
use crate::input::scenario::Model;
use crate::{Error, Result};
use maglev_core::{LawName, Scheme};

/// Typed changes to a case (what validate and a sweep vary), applied by [`Case::with`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Changes {
    pub speed: Option<f64>,
    pub model: Option<Model>,
    pub elements: Option<usize>,
    pub modes: Option<usize>,
    pub dt: Option<f64>,
    pub t_end: Option<f64>,
    pub n_sub: Option<u32>,
    pub scheme: Option<Scheme>,
    pub law: Option<LawName>,
}

impl Case {
    /// This case with `changes` applied to its scenario and resolved again (module docs).
    pub fn with(&self, changes: &Changes) -> Result<Case> {
        let mut sc = self.scenario.clone();
        let r = &mut sc.run;
        if let Some(v) = changes.speed {
            r.speed_m_per_s = v;
        }
        if let Some(v) = changes.model {
            r.model = v;
        }
        if let Some(v) = changes.elements {
            r.elements_per_span = v;
        }
        if let Some(v) = changes.modes {
            r.modes = v;
        }
        if let Some(v) = changes.dt {
            r.dt_s = v;
        }
        if let Some(v) = changes.t_end {
            r.t_end_s = Some(v);
        }
        let controller_change =
            changes.n_sub.is_some() || changes.scheme.is_some() || changes.law.is_some();
        match (&mut sc.controller, controller_change) {
            (Some(c), _) => {
                if let Some(v) = changes.n_sub {
                    c.magnet.n_sub = v;
                }
                if let Some(v) = changes.scheme {
                    c.magnet.scheme = v;
                }
                if let Some(v) = changes.law {
                    c.law.law = v;
                }
            }
            (None, true) => {
                return Err(Error::invalid(
                    "controller",
                    "the case has no [controller] section to change",
                ))
            }
            (None, false) => {}
        }
        Case::new(sc)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A derived case equals the case the same `--set` text gives.
    #[test]
    fn changes_equal_the_set_text() {
        let base = Case::load("paper-4.2", &[]).unwrap();
        let changed = base
            .with(&Changes {
                speed: Some(150.0),
                model: Some(Model::Modal),
                dt: Some(5e-4),
                n_sub: Some(10),
                ..Changes::default()
            })
            .unwrap();
        let text = Case::load(
            "paper-4.2",
            &[
                "speed=150".into(),
                "model=modal".into(),
                "dt=5e-4".into(),
                "nsub=10".into(),
            ],
        )
        .unwrap();
        assert_eq!(changed.record(), text.record());
        assert!((changed.t_end - (40.0 / 150.0 + 0.1)).abs() < 1e-12);
        let e = Case::load("moving-force", &[])
            .unwrap()
            .with(&Changes {
                n_sub: Some(3),
                ..Changes::default()
            })
            .unwrap_err();
        assert!(e.to_string().starts_with("controller"), "{e}");
    }
}
