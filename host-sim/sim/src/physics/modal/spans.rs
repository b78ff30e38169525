//! [`ModalSpans`]: the modal reference over a line of simply supported spans.
//!
//! Why it is exact per span: simply supported spans with their own end supports share no
//! DOF, so each span is the single-span problem of Eq. 20 driven by the loads on it alone
//! ([`ModalGuideway`], with the loads shifted to its local X). A load on a shared support
//! gives sin(nπ·0) = sin(nπ) = 0 on both sides, so where it is counted does not matter.
//!
//! Support motion ([`ModalSpans::with_support_motion`], docs/seismic.md "Spans on rigid
//! supports"): each series then holds its span's motion relative to the rigid-body motion
//! between its bearings, loaded by that motion's inertia in closed form (Eq. S5); the
//! queries add the rigid-body motion back (Eq. S3).

use super::span::{ModalError, ModalGuideway};
use crate::physics::guideway::{Bridge, Guideway, PointLoad, PointMotion, SectionMotion};
use crate::physics::seismic::support::{GroundState, GroundTrack, SupportMotion};
use crate::Error;

/// The modal reference for every span of a [`Bridge`] (see the module docs).
#[derive(Clone, Debug)]
pub struct ModalSpans {
    dt: f64,
    /// (X of the left support, the span's series).
    spans: Vec<(f64, ModalGuideway)>,
    /// Per-span local loads of the current step (reused; grows only to the largest count).
    local: Vec<PointLoad>,
    /// The ground at the supports when the spans follow support motion
    /// ([`Self::with_support_motion`]).
    drive: Option<GroundTrack>,
}

impl ModalSpans {
    /// `modes` series terms per field on every span, step `dt`.
    ///
    /// ```
    /// use maglev_sim::physics::guideway::{BeamSection, Bridge, Guideway, PointLoad};
    /// use maglev_sim::physics::modal::ModalSpans;
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
            drive: None,
        })
    }

    /// As [`Self::new`], with the bearings of span k at supports k and k + 1 following
    /// `motion` (docs/seismic.md "Spans on rigid supports"): each series holds its span's
    /// motion relative to the rigid-body motion between its bearings (Eq. S3), driven by that
    /// motion's inertia in closed form (Eq. S5); the rail's motion is absolute. A settlement
    /// tilts the spans rigidly from t = 0; motion along x enters none of y, z, θx.
    /// `motion` must give `spans + 1` supports.
    pub fn with_support_motion(
        bridge: &Bridge,
        modes: usize,
        dt: f64,
        motion: SupportMotion,
    ) -> crate::Result<Self> {
        let mut s = Self::new(bridge, modes, dt).map_err(|e| Error::numerical(e.to_string()))?;
        let supports = s.spans.len() + 1;
        let track = GroundTrack::new(motion, supports, &format!("the spans have {supports}"))?;
        s.drive = Some(track);
        Ok(s)
    }

    /// The ground at each support on the committed state (`None` without support motion).
    pub fn ground(&self) -> Option<&[GroundState]> {
        self.drive.as_ref().map(GroundTrack::committed)
    }

    /// The quasi-static rigid-body motion (y, z) of span `i` at local `x` on the trial
    /// ground (Eq. S3); zero without support motion.
    fn rigid_body(&self, i: usize, x: f64) -> (f64, f64) {
        match &self.drive {
            Some(track) => track.rigid_body(i, x / self.spans[i].1.length()),
            None => (0.0, 0.0),
        }
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
        if let Some(track) = &mut self.drive {
            track.prepare(self.dt);
            for (i, (_, g)) in self.spans.iter_mut().enumerate() {
                g.set_bearing_acceleration(track.bearing_accelerations(i));
            }
        }
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
            .map(|(i, local)| {
                let m = self.spans[i].1.motion_at(local, ey, ez);
                let (y, z) = self.rigid_body(i, local);
                PointMotion {
                    y: m.y + y,
                    z: m.z + z,
                }
            })
            .unwrap_or_default()
    }

    fn section_at(&self, x: f64) -> SectionMotion {
        self.find(x)
            .map(|(i, local)| {
                let m = self.spans[i].1.section_at(local);
                let (y, z) = self.rigid_body(i, local);
                SectionMotion {
                    y: m.y + y,
                    z: m.z + z,
                    rx: m.rx,
                }
            })
            .unwrap_or_default()
    }

    fn commit(&mut self) {
        for (_, g) in &mut self.spans {
            g.commit();
        }
        if let Some(track) = &mut self.drive {
            track.commit();
        }
    }
}
