//! [`ModalSpans`]: the modal reference over a line of simply supported spans.
//!
//! Why it is exact per span: simply supported spans with their own end supports share no
//! DOF, so each span is the single-span problem of Eq. 20 driven by the loads on it alone
//! ([`ModalGuideway`], with the loads shifted to its local X). A load on a shared support
//! gives sin(nπ·0) = sin(nπ) = 0 on both sides, so where it is counted does not matter.

use super::span::{ModalError, ModalGuideway};
use crate::physics::guideway::{Bridge, Guideway, PointLoad, PointMotion, SectionMotion};

/// The modal reference for every span of a [`Bridge`] (see the module docs).
#[derive(Clone, Debug)]
pub struct ModalSpans {
    dt: f64,
    /// (X of the left support, the span's series).
    spans: Vec<(f64, ModalGuideway)>,
    /// Per-span local loads of the current step (reused; grows only to the largest count).
    local: Vec<PointLoad>,
}

impl ModalSpans {
    /// `modes` series terms per field on every span, step `dt`.
    ///
    /// ```
    /// use maglev_host_sim::physics::guideway::{BeamSection, Bridge, Guideway, PointLoad};
    /// use maglev_host_sim::physics::modal::ModalSpans;
    ///
    /// let bridge = Bridge { section: BeamSection::paper_4_2(), spans: vec![25.0, 30.0] };
    /// let mut g = ModalSpans::new(&bridge, 40, 1e-4).unwrap();
    /// g.solve_step(&[PointLoad { x: 40.0, fz: -1e5, ..Default::default() }]);
    /// g.commit();
    /// assert!(g.section_at(40.0).z < 0.0);
    /// assert_eq!(g.section_at(12.5).z, 0.0); // the first span carries nothing
    /// ```
    pub fn new(bridge: &Bridge, modes: usize, dt: f64) -> Result<Self, ModalError> {
        if bridge.spans.is_empty() {
            return Err(ModalError::SpanCount(0));
        }
        let mut start = 0.0;
        let mut spans = Vec::with_capacity(bridge.spans.len());
        for &length in &bridge.spans {
            spans.push((
                start,
                ModalGuideway::new(bridge.section.clone(), length, modes, dt)?,
            ));
            start += length;
        }
        Ok(ModalSpans {
            dt,
            spans,
            local: Vec::new(),
        })
    }

    /// Number of spans.
    pub fn span_count(&self) -> usize {
        self.spans.len()
    }

    /// The span containing `x` (a shared support belongs to the span on its right) and the
    /// local coordinate.
    fn find(&self, x: f64) -> Option<(usize, f64)> {
        let i = self
            .spans
            .partition_point(|(s, _)| *s <= x)
            .checked_sub(1)?;
        let (start, g) = &self.spans[i];
        let local = x - start;
        (local <= g.length()).then_some((i, local))
    }
}

impl Guideway for ModalSpans {
    fn time_step(&self) -> f64 {
        self.dt
    }

    fn solve_step(&mut self, loads: &[PointLoad]) {
        for (start, g) in &mut self.spans {
            self.local.clear();
            self.local.extend(
                loads
                    .iter()
                    .map(|l| PointLoad {
                        x: l.x - *start,
                        ..*l
                    })
                    .filter(|l| (0.0..=g.length()).contains(&l.x)),
            );
            g.solve_step(&self.local);
        }
    }

    fn motion_at(&self, x: f64, ey: f64, ez: f64) -> PointMotion {
        self.find(x)
            .map(|(i, local)| self.spans[i].1.motion_at(local, ey, ez))
            .unwrap_or_default()
    }

    fn section_at(&self, x: f64) -> SectionMotion {
        self.find(x)
            .map(|(i, local)| self.spans[i].1.section_at(local))
            .unwrap_or_default()
    }

    fn commit(&mut self) {
        for (_, g) in &mut self.spans {
            g.commit();
        }
    }
}
