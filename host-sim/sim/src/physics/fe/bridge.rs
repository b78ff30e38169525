//! [`FeGuideway`]: a [`Bridge`] of simply supported spans as Timoshenko beam elements,
//! advanced by Newmark and driven through the [`Guideway`] interface (Eq. 15, 16, 19).
//!
//! Why this layout: spans are separate beams (each simply supported at both ends with its own
//! end nodes), so the structure is block-diagonal over spans and each span is stepped on its
//! own. Spans of equal length share one assembled model and one factorisation; a span that is
//! at rest and unloaded stays at rest and is skipped, so only the spans under or behind the
//! train cost anything.
//!
//! The step (docs/model.md §7, Eq. 19) is linear in the wheel loads: d₁ = Keff⁻¹ (r + F) with r
//! the load-free right-hand side from the committed state. Each span therefore computes r
//! once per step (on the first [`Guideway::solve_step`] after a commit). On a span small
//! enough to hold Keff⁻¹ densely ([`Flexibility`]: the §4.2 span, the forces train's 30 m
//! spans) the state is held in the span's modal coordinates ([`ModalBasis`]: Keff, M and a
//! Rayleigh C diagonal), so the free response is a few operations a mode, and a
//! Newton–Raphson iteration solves nothing: a query reads d_free + Keff⁻¹ F on the 12 DOFs
//! of its element only (d_free = Φ q_free there), and the modal q₁ = q_free + Φᵀ F is formed
//! on commit. Physical displacements are formed only where queried
//! ([`FeGuideway::trial_state`] forms them all).
//! Where the loads cover more than half of a span's DOFs (a train's axles on every element)
//! and in a step after one that took a single `solve_step` (constant moving forces), such a
//! span forms q₁ = q_free + Φᵀ F at each iteration instead. Spans too large for the dense
//! blocks keep physical coordinates, and each iteration costs one sparse forward/back
//! substitution of r + F on the *loaded* spans (an unloaded span's response is solved once
//! per step and kept). Velocity and acceleration are completed once, on commit. Nothing in
//! the time loop allocates.
//!
//! Wheel loads and guideway motion use the paper's cubic Hermite interpolation (Eq. 15, 16,
//! via [`maglev_core::gap::WheelShape`]), not the Timoshenko element's own shear-dependent
//! shapes. The two are work-conjugate, so energy and reciprocity hold exactly, but a load
//! between nodes is slightly off the exact Timoshenko response (measured: 1.8e-3 relative
//! deflection error for a load at 0.48 of a 1.25 m element of the §4.2 beam); at nodes it is
//! exact.
//!
//! Support motion ([`FeGuideway::with_support_motion`], docs/seismic.md "Spans on rigid
//! supports"): the spans' state is then their motion relative to the rigid-body motion
//! between their bearings, driven by that motion's inertia load (Eq. S4), a load of the whole
//! step added to its load-free right-hand side; the rail's motion the queries return is
//! absolute (Eq. S3). Without it the spans are what they were, bit for bit.

use super::assembly::SpanModel;
use super::cholesky::{Scratch, SparseCholesky};
use super::flexibility::{Flexibility, HotRows, LoadSupport};
use super::modal_basis::ModalBasis;
use super::newmark::{effective_stiffness, rayleigh_matrix, Rayleigh, SpanNewmark, State};
use crate::physics::guideway::{Bridge, Guideway, PointLoad, PointMotion, SectionMotion};
use crate::physics::seismic::support::{GroundState, GroundTrack, SupportMotion};
use crate::Error;
use maglev_core::gap::{ElementVector, WheelShape, ELEMENT_DOFS};
use nalgebra::DVector;
use rayon::prelude::*;
use std::cell::OnceCell;

/// One distinct span model with its integrator and static factor.
#[derive(Debug)]
struct SpanSystem {
    model: SpanModel,
    newmark: SpanNewmark,
    static_factor: SparseCholesky,
    /// Keff⁻¹ by columns, for spans of at most [`super::flexibility::MAX_DOFS`] DOFs whose
    /// damping is Rayleigh (or none): present together with `modal`.
    flex: Option<Flexibility>,
    /// The modal basis of those spans: their state is then held in modal coordinates.
    modal: Option<ModalBasis>,
}

/// Per-span state and preallocated work space.
#[derive(Debug)]
struct Span {
    start: f64,
    system: usize,
    /// Physical, or modal on a span with a [`ModalBasis`] (as are `trial` and `rhs_free`,
    /// which is then the step's free response itself).
    committed: State,
    /// Trial state: `d` after each [`Guideway::solve_step`]; `v` and `a` completed on commit.
    trial: State,
    /// The physical trial state of a modal span, formed on request ([`FeGuideway::trial_state`]).
    phys: State,
    /// `free` holds this step's free response at the hot elements' DOFs (modal spans).
    free_hot: bool,
    /// Nodal loads of the current iteration (Eq. 15).
    load: DVector<f64>,
    /// The step's load-free right-hand side (valid when `free_valid`).
    rhs_free: DVector<f64>,
    /// Scratch for the right-hand-side predictor.
    pred: DVector<f64>,
    scratch: Scratch,
    committed_at_rest: bool,
    trial_at_rest: bool,
    /// Loaded in the current iteration.
    loaded: bool,
    /// `rhs_free` is computed for the current step.
    free_valid: bool,
    /// `trial.d` is the unloaded response of the current step.
    trial_is_free: bool,
    /// The step's physical free response at the hot elements' DOFs (valid when `free_hot`).
    free: DVector<f64>,
    /// The loaded DOFs of the current iteration (flexibility spans).
    support: Option<LoadSupport>,
    /// The trial displacement is `free + Z·load`, not yet formed in `trial.d`.
    lazy: bool,
    /// `support` and `hot` hold every loaded DOF and element of `load` (recorded in steps
    /// that use the columns, while the loads cover at most half the DOFs).
    tracking: bool,
    /// The midspan section's element and rows (the probes' and records' query), by its
    /// span-local x.
    mid: (f64, Option<(usize, WheelShape<f64>)>),
    /// The midspan element's trial displacement once queried (records and probes read it
    /// after each commit; on a modal span each read is a product with Φ's rows).
    mid_value: OnceCell<ElementVector<f64>>,
    /// The loaded elements of the current iteration and, when `lazy`, their trial
    /// displacement (the queries of a coupling loop fall on them; flexibility spans).
    hot: Vec<(usize, ElementVector<f64>)>,
    /// `hot` holds the trial displacement of its elements (set by the iterations that use
    /// the columns, kept through the commit: the queries after it read them too).
    hot_valid: bool,
    /// Keff⁻¹'s rows at the hot elements' DOFs over the support (flexibility spans), to be
    /// gathered again when `rows_dirty`.
    rows: Option<HotRows>,
    rows_dirty: bool,
    /// The step's inertia load of the ground, −Σ_j M r_j ü_gj (Eq. S4), when the spans
    /// follow support motion (empty otherwise).
    ground: DVector<f64>,
    /// `ground` is not zero this step.
    driven: bool,
}

impl Span {
    /// The trial displacement for this iteration's loads (module docs).
    fn advance(&mut self, sys: &SpanSystem, columns: bool) {
        self.hot_valid = false;
        self.mid_value.take();
        if self.committed_at_rest && !self.loaded && !self.driven {
            if !self.trial_at_rest {
                self.trial.d.fill(0.0);
                self.trial_at_rest = true;
            }
            return;
        }
        self.trial_at_rest = false;
        self.lazy = false;
        if !self.free_valid {
            if self.committed_at_rest {
                self.rhs_free.fill(0.0);
            } else if let Some(modal) = &sys.modal {
                let dt = sys.newmark.time_step();
                modal.free_response(dt, &self.committed, self.rhs_free.as_mut_slice());
            } else {
                sys.newmark
                    .free_rhs(&self.committed, &mut self.pred, &mut self.rhs_free);
            }
            if self.driven {
                // A load of the whole step, as the train's: into r, or q_free += Φᵀ f_g.
                match &sys.modal {
                    Some(modal) => {
                        modal.add_loads(self.ground.as_slice(), self.rhs_free.as_mut_slice())
                    }
                    None => self.rhs_free += &self.ground,
                }
            }
            self.free_valid = true;
            self.trial_is_free = false;
        }
        if let (true, true, Some(flex), Some(modal), Some(support)) =
            (columns, self.tracking, &sys.flex, &sys.modal, &self.support)
        {
            // The columns pay while the loads cover at most half the DOFs (module docs).
            if 2 * support.len() <= flex.nrows() {
                if let Some(rows) = &mut self.rows {
                    if self.rows_dirty {
                        let dofs = self
                            .hot
                            .iter()
                            .flat_map(|&(e, _)| sys.model.element_free(e).iter().copied());
                        rows.build(flex, support, dofs);
                        self.rows_dirty = false;
                        self.free_hot = false;
                    }
                }
                if !self.free_hot {
                    // The physical free response where the iterations read it: Φ q_free.
                    let (q, free) = (self.rhs_free.as_slice(), self.free.as_mut_slice());
                    for &(e, _) in &self.hot {
                        for &f in sys.model.element_free(e).iter().flatten() {
                            free[f] = modal.value_at(q, f);
                        }
                    }
                    self.free_hot = true;
                }
                let (free, load) = (self.free.as_slice(), self.load.as_slice());
                match &mut self.rows {
                    Some(rows) if rows.is_ready() => {
                        let values = self.hot.iter_mut().flat_map(|(_, de)| de.iter_mut());
                        rows.eval(support, free, load, values);
                    }
                    _ => {
                        for (e, de) in &mut self.hot {
                            *de = sys
                                .model
                                .gather_with(*e, |f| flex.response_at(support, free, load, f));
                        }
                    }
                }
                self.lazy = true;
                self.hot_valid = true;
                self.trial_is_free = false;
                return;
            }
        }
        if let Some(modal) = &sys.modal {
            // Keff is the identity in modal coordinates: q₁ = q_free + Φᵀ F.
            if self.loaded {
                self.trial.d.copy_from(&self.rhs_free);
                modal.add_loads(self.load.as_slice(), self.trial.d.as_mut_slice());
                self.trial_is_free = false;
            } else if !self.trial_is_free {
                self.trial.d.copy_from(&self.rhs_free);
                self.trial_is_free = true;
            }
            return;
        }
        if self.loaded {
            // d = r + F (nalgebra's `copy_from` and `+=` as slice loops: the same additions).
            let d = self.trial.d.as_mut_slice();
            let (r, f) = (self.rhs_free.as_slice(), self.load.as_slice());
            let (r, f) = (&r[..d.len()], &f[..d.len()]);
            for (i, d) in d.iter_mut().enumerate() {
                *d = r[i] + f[i];
            }
            sys.newmark
                .solve_in_place(&mut self.trial.d, &mut self.scratch);
            self.trial_is_free = false;
        } else if !self.trial_is_free {
            self.trial.d.copy_from(&self.rhs_free);
            sys.newmark
                .solve_in_place(&mut self.trial.d, &mut self.scratch);
            self.trial_is_free = true;
        }
    }

    /// Form `trial.d` if it is held as free response plus flexibility.
    fn materialise(&mut self, sys: &SpanSystem) {
        if let (true, Some(modal), Some(support)) = (self.lazy, &sys.modal, &self.support) {
            self.trial.d.copy_from(&self.rhs_free);
            let (load, q) = (self.load.as_slice(), self.trial.d.as_mut_slice());
            for j in support.dofs() {
                modal.add_load(j, load[j], q);
            }
            self.lazy = false;
        }
    }

    /// Trial displacement on element `e`'s 12 DOFs.
    fn element(&self, sys: &SpanSystem, e: usize) -> ElementVector<f64> {
        self.element_where(sys, e, |_| true)
    }

    /// [`Self::element`] on the element DOFs `k` with `keep(k)` (the others zero, or as
    /// stored for a hot element).
    fn element_where(
        &self,
        sys: &SpanSystem,
        e: usize,
        keep: impl Fn(usize) -> bool,
    ) -> ElementVector<f64> {
        if self.hot_valid {
            if let Some((_, de)) = self.hot.iter().find(|h| h.0 == e) {
                return *de;
            }
        }
        match (self.lazy, &sys.flex, &sys.modal, &self.support) {
            (true, Some(flex), Some(modal), Some(support)) => {
                let (q, load) = (self.rhs_free.as_slice(), self.load.as_slice());
                sys.model.gather_where(e, keep, |f| {
                    flex.response_with(support, modal.value_at(q, f), load, f)
                })
            }
            _ => match &sys.modal {
                Some(modal) => {
                    let q = self.trial.d.as_slice();
                    sys.model.gather_where(e, keep, |f| modal.value_at(q, f))
                }
                None => {
                    let d = self.trial.d.as_slice();
                    sys.model.gather_where(e, keep, |f| d[f])
                }
            },
        }
    }

    /// Accept the trial displacement; complete velocity and acceleration.
    fn commit(&mut self, sys: &SpanSystem) {
        self.materialise(sys);
        self.mid_value.take();
        // A trial at rest implies a committed state at rest (see `advance`): nothing to do.
        if !self.trial_at_rest {
            sys.newmark.finish(&mut self.committed, &mut self.trial);
        }
        self.committed_at_rest = self.trial_at_rest;
        self.free_valid = false;
        self.free_hot = false;
        self.trial_is_free = false;
    }
}

/// Loads whose places are remembered from one `solve_step` to the next (the coupling loop's
/// points do not move within a step); more loads are located afresh each time.
const PLACES: usize = 64;

/// Where a load or query point sits: span, element and the element's rows there (Eq. 15,
/// 16), `None` off the bridge.
#[derive(Clone, Copy, Debug)]
struct Place {
    x: f64,
    ey: f64,
    ez: f64,
    at: Option<(usize, usize, WheelShape<f64>)>,
}

impl Place {
    fn is(&self, x: f64, ey: f64, ez: f64) -> bool {
        self.x == x && self.ey == ey && self.ez == ez
    }
}

/// The FE guideway (see the module docs).
#[derive(Debug)]
pub struct FeGuideway {
    dt: f64,
    systems: Vec<SpanSystem>,
    spans: Vec<Span>,
    /// Spans loaded in the current iteration (capacity: every span, so pushes never allocate).
    loaded: Vec<usize>,
    /// Advance the spans on rayon's pool.
    parallel: bool,
    /// A solve since the last commit.
    solved: bool,
    /// The places of the last `solve_step`'s loads (at most [`PLACES`]; capacity reserved).
    places: Vec<Place>,
    /// `solve_step` calls since the last commit, and whether the step uses the flexibility
    /// columns: not after a step of one call (constant moving forces), where the direct
    /// solve is one solve and the columns would add a second (module docs).
    calls: u32,
    columns: bool,
    /// The ground at the supports when the spans follow support motion
    /// ([`Self::with_support_motion`]).
    drive: Option<GroundTrack>,
}

impl FeGuideway {
    /// Model `bridge` with `elements_per_span` equal elements per span, undamped, step `dt`.
    pub fn new(bridge: &Bridge, elements_per_span: usize, dt: f64) -> crate::Result<Self> {
        Self::with_damping(bridge, elements_per_span, dt, None)
    }

    /// As [`Self::new`], with optional Rayleigh damping.
    pub fn with_damping(
        bridge: &Bridge,
        elements_per_span: usize,
        dt: f64,
        damping: Option<Rayleigh>,
    ) -> crate::Result<Self> {
        if bridge.spans.is_empty() {
            return Err(Error::invalid(
                "bridge.spans",
                "must hold at least 1 span, got 0",
            ));
        }
        let mut systems: Vec<SpanSystem> = Vec::new();
        let mut spans = Vec::with_capacity(bridge.spans.len());
        let mut start = 0.0;
        for &length in &bridge.spans {
            let system = match systems.iter().position(|s| s.model.length == length) {
                Some(i) => i,
                None => {
                    let model = SpanModel::new(&bridge.section, length, elements_per_span)?;
                    let (k, m) = (&model.k, &model.m);
                    let c = damping.map(|r| rayleigh_matrix(k, m, r));
                    let newmark = SpanNewmark::with_damping_matrix(k, m, c.clone(), dt)?;
                    let static_factor = model.stiffness_factor()?;
                    let mut scratch = newmark.factor().scratch();
                    let flex = Flexibility::new(newmark.components(), |x| {
                        newmark.solve_in_place_slice(x, &mut scratch)
                    });
                    let modal = flex.as_ref().and_then(|_| {
                        let keff = effective_stiffness(k, m, c.as_ref(), dt);
                        ModalBasis::new(newmark.components(), k, &keff, m, c.as_ref())
                    });
                    // The columns serve the modal state only (module docs).
                    let flex = flex.filter(|_| modal.is_some());
                    systems.push(SpanSystem {
                        model,
                        newmark,
                        static_factor,
                        flex,
                        modal,
                    });
                    systems.len() - 1
                }
            };
            let sys = &systems[system];
            let n = sys.model.free_dofs();
            spans.push(Span {
                start,
                system,
                committed: State::zeros(n),
                trial: State::zeros(n),
                phys: State::zeros(if sys.modal.is_some() { n } else { 0 }),
                free_hot: false,
                load: DVector::zeros(n),
                rhs_free: DVector::zeros(n),
                pred: DVector::zeros(sys.newmark.pred_len()),
                scratch: sys.newmark.factor().scratch(),
                committed_at_rest: true,
                trial_at_rest: true,
                loaded: false,
                free_valid: false,
                trial_is_free: false,
                free: DVector::zeros(n),
                support: sys.flex.as_ref().map(LoadSupport::new),
                lazy: false,
                tracking: false,
                rows: sys
                    .flex
                    .as_ref()
                    .map(|f| HotRows::new(f, ELEMENT_DOFS * elements_per_span)),
                rows_dirty: true,
                hot_valid: false,
                mid_value: OnceCell::new(),
                mid: (
                    sys.model.length / 2.0,
                    sys.model.shape_at(sys.model.length / 2.0, 0.0, 0.0),
                ),
                hot: Vec::with_capacity(if sys.flex.is_some() {
                    elements_per_span
                } else {
                    0
                }),
                ground: DVector::zeros(0),
                driven: false,
            });
            start += length;
        }
        let loaded = Vec::with_capacity(spans.len());
        Ok(FeGuideway {
            dt,
            systems,
            spans,
            loaded,
            parallel: false,
            solved: false,
            places: Vec::with_capacity(PLACES),
            calls: 0,
            columns: true,
            drive: None,
        })
    }

    /// As [`Self::with_damping`], with the bearings of span k at supports k and k + 1 (support
    /// k at the start of span k) following `motion` (docs/seismic.md "Spans on rigid
    /// supports"): the spans' state is the motion relative to their rigid-body motion between
    /// the bearings (Eq. S3), driven by the ground's inertia load (Eq. S4) and damped on that
    /// relative motion; the rail's motion ([`Guideway::motion_at`], [`Guideway::section_at`])
    /// is absolute. A settlement tilts the spans rigidly from t = 0. Motion along x moves a
    /// span rigidly along the line and enters none of y, z, θx.
    pub fn with_support_motion(
        bridge: &Bridge,
        elements_per_span: usize,
        dt: f64,
        damping: Option<Rayleigh>,
        motion: SupportMotion,
    ) -> crate::Result<Self> {
        let mut g = Self::with_damping(bridge, elements_per_span, dt, damping)?;
        let supports = g.spans.len() + 1;
        let track = GroundTrack::new(motion, supports, &format!("the spans have {supports}"))?;
        for s in &mut g.spans {
            s.ground = DVector::zeros(s.load.len());
        }
        g.drive = Some(track);
        Ok(g)
    }

    /// The ground at each support on the committed state (`None` without support motion).
    pub fn ground(&self) -> Option<&[GroundState]> {
        self.drive.as_ref().map(GroundTrack::committed)
    }

    /// The step's ground and each span's inertia load of it (Eq. S4), once per step.
    fn prepare_ground(&mut self) {
        let Some(track) = &mut self.drive else {
            return;
        };
        if self.calls > 1 {
            return;
        }
        track.prepare(self.dt);
        for (i, span) in self.spans.iter_mut().enumerate() {
            let a = track.bearing_accelerations(i);
            let inertia = &self.systems[span.system].model.bearing_inertia;
            span.ground.fill(0.0);
            for (m, a) in inertia.iter().zip(a) {
                if a != 0.0 {
                    span.ground.axpy(-a, m, 1.0);
                }
            }
            span.driven = a.iter().any(|&a| a != 0.0);
        }
    }

    /// The quasi-static rigid-body motion (y, z) at `local` on span `i` (Eq. S3); zero without
    /// support motion.
    fn rigid_body(&self, i: usize, local: f64) -> (f64, f64) {
        self.drive.as_ref().map_or((0.0, 0.0), |track| {
            track.rigid_body(i, local / self.span_model(i).length)
        })
    }

    /// Advance the spans of each step on rayon's thread pool (off by default). Results are
    /// bit-identical either way: each span's arithmetic is the same and independent.
    pub fn set_parallel(&mut self, parallel: bool) {
        self.parallel = parallel;
    }

    /// Stored entries of the band matrices, the sparse products and factors (values; factor
    /// indices not counted) plus the per-span vectors, in 8-byte words: O(n·b) per span.
    pub fn storage_words(&self) -> usize {
        let systems: usize = self
            .systems
            .iter()
            .map(|s| {
                let n = s.model.free_dofs();
                let band = |b: usize| n * (b + 1);
                2 * band(s.model.k.bandwidth())
                    + s.newmark.storage_words()
                    + s.static_factor.factor_nonzeros()
                    + s.flex.as_ref().map_or(0, Flexibility::stored)
                    + s.modal.as_ref().map_or(0, ModalBasis::stored)
            })
            .sum();
        let spans: usize = self.spans.iter().map(|s| 10 * s.load.len()).sum();
        systems + spans
    }

    /// Number of spans.
    pub fn span_count(&self) -> usize {
        self.spans.len()
    }

    /// X of span `i`'s left support (m).
    pub fn span_start(&self, i: usize) -> f64 {
        self.spans[i].start
    }

    /// The assembled model of span `i`.
    pub fn span_model(&self, i: usize) -> &SpanModel {
        &self.systems[self.spans[i].system].model
    }

    /// Trial state of span `i` (free DOFs; see [`SpanModel`]). Its displacement is current
    /// after every `solve_step` (formed here if the span holds it as free response plus
    /// flexibility); its velocity and acceleration are completed on `commit` (after a commit
    /// the trial equals the committed state).
    pub fn trial_state(&mut self, i: usize) -> &State {
        let span = &mut self.spans[i];
        let sys = &self.systems[span.system];
        span.materialise(sys);
        match &sys.modal {
            Some(modal) => {
                let (t, p) = (&span.trial, &mut span.phys);
                modal.to_physical(t.d.as_slice(), p.d.as_mut_slice());
                modal.to_physical(t.v.as_slice(), p.v.as_mut_slice());
                modal.to_physical(t.a.as_slice(), p.a.as_mut_slice());
                &span.phys
            }
            None => &span.trial,
        }
    }

    /// The span containing global `x` and the span-local coordinate, `None` off the bridge.
    /// A shared support point belongs to the span on its right (the last span keeps its end).
    fn find(&self, x: f64) -> Option<(usize, f64)> {
        if !x.is_finite() {
            return None;
        }
        let i = self
            .spans
            .partition_point(|s| s.start <= x)
            .checked_sub(1)?;
        let span = &self.spans[i];
        let length = self.systems[span.system].model.length;
        let local = x - span.start;
        if local > length * (1.0 + 1e-12) {
            return None;
        }
        Some((i, local.min(length)))
    }

    /// Span, element and rows at global `x`, offset `(ey, ez)`; `None` off the bridge.
    fn place(&self, x: f64, ey: f64, ez: f64) -> Option<(usize, usize, WheelShape<f64>)> {
        let (i, local) = self.find(x)?;
        let (e, shape) = self.span_model(i).shape_at(local, ey, ez)?;
        Some((i, e, shape))
    }

    /// Loads on the free DOFs of every span (Eq. 15); loads off the bridge are ignored.
    /// Clears only the spans loaded in the previous iteration: O(loads + loaded DOFs). When
    /// the loads sit where they sat in the previous call (the iterations of one step), their
    /// places, the loaded spans and the loaded DOFs are kept and only the values change.
    fn distribute(&mut self, loads: &[PointLoad]) {
        let same = loads.len() == self.places.len()
            && loads
                .iter()
                .zip(&self.places)
                .all(|(l, p)| p.is(l.x, l.ey, l.ez));
        if !same {
            self.places.clear();
            if loads.len() <= PLACES {
                for l in loads {
                    let at = self.place(l.x, l.ey, l.ez);
                    self.places.push(Place {
                        x: l.x,
                        ey: l.ey,
                        ez: l.ez,
                        at,
                    });
                }
            }
        }
        for &i in &self.loaded {
            let s = &mut self.spans[i];
            match (&mut s.support, s.tracking) {
                (Some(support), true) => support.zero(s.load.as_mut_slice()),
                _ => s.load.as_mut_slice().fill(0.0),
            }
            if !same {
                if let Some(support) = &mut s.support {
                    support.clear();
                }
                s.hot.clear();
                s.hot_valid = false;
                s.loaded = false;
                s.tracking = false;
                s.rows_dirty = true;
            }
        }
        if !same {
            self.loaded.clear();
        }
        for (k, p) in loads.iter().enumerate() {
            let fresh;
            let at = match self.places.get(k) {
                Some(place) => &place.at,
                None => {
                    fresh = self.place(p.x, p.ey, p.ez);
                    &fresh
                }
            };
            let Some((i, e, shape)) = at else {
                continue;
            };
            let (i, e) = (*i, *e);
            let span = &mut self.spans[i];
            let sys = &self.systems[span.system];
            if !same && !span.loaded {
                span.loaded = true;
                span.rows_dirty = true;
                span.tracking = self.columns && span.support.is_some();
                self.loaded.push(i);
            }
            let track = !same && span.tracking;
            let (load, support) = (span.load.as_mut_slice(), &mut span.support);
            sys.model.add_shaped_force(e, shape, p.fy, p.fz, load, |j| {
                if let (true, Some(flex), Some(support)) = (track, &sys.flex, support.as_mut()) {
                    support.add(flex, j);
                }
            });
            if !track {
                continue;
            }
            // Past half the DOFs the columns do not pay (module docs): stop recording.
            if span
                .support
                .as_ref()
                .is_some_and(|s| 2 * s.len() > sys.model.free_dofs())
            {
                span.tracking = false;
            } else if !span.hot.iter().any(|h| h.0 == e) {
                span.hot.push((e, ElementVector::zeros()));
            }
        }
    }

    /// Static displacements K d = F per span (free DOFs), for the loads (Eq. 15); loads off
    /// the bridge are ignored.
    pub fn solve_static(&self, loads: &[PointLoad]) -> Vec<DVector<f64>> {
        let mut f: Vec<DVector<f64>> = self
            .spans
            .iter()
            .map(|s| DVector::zeros(self.systems[s.system].model.free_dofs()))
            .collect();
        for p in loads {
            if let Some((i, local)) = self.find(p.x) {
                self.span_model(i)
                    .add_point_force(local, p.ey, p.ez, p.fy, p.fz, &mut f[i]);
            }
        }
        self.spans
            .iter()
            .zip(f)
            .map(|(s, mut f)| {
                let factor = &self.systems[s.system].static_factor;
                factor.solve_in_place(f.as_mut_slice(), &mut factor.scratch());
                f
            })
            .collect()
    }

    /// Motion of a point for given per-span displacements (as from [`Self::solve_static`]);
    /// zero off the bridge (Eq. 16 with the rigid link).
    pub fn motion_in(&self, disp: &[DVector<f64>], x: f64, ey: f64, ez: f64) -> PointMotion {
        self.find(x)
            .and_then(|(i, local)| {
                let model = self.span_model(i);
                model.motion(disp.get(i)?, local, ey, ez)
            })
            .unwrap_or_default()
    }

    /// Axis motion for given per-span displacements; zero off the bridge.
    pub fn section_in(&self, disp: &[DVector<f64>], x: f64) -> SectionMotion {
        self.find(x)
            .and_then(|(i, local)| self.span_model(i).section(disp.get(i)?, local))
            .unwrap_or_default()
    }
}

impl Guideway for FeGuideway {
    fn time_step(&self) -> f64 {
        self.dt
    }

    fn solve_step(&mut self, loads: &[PointLoad]) {
        self.distribute(loads);
        self.calls += 1;
        self.prepare_ground();
        let (systems, columns) = (&self.systems, self.columns);
        if self.parallel {
            self.spans
                .par_iter_mut()
                .for_each(|s| s.advance(&systems[s.system], columns));
        } else {
            for s in &mut self.spans {
                s.advance(&systems[s.system], columns);
            }
        }
        self.solved = true;
    }

    fn motion_at(&self, x: f64, ey: f64, ez: f64) -> PointMotion {
        let motion = |&(i, e, ref shape): &(usize, usize, WheelShape<f64>)| {
            let span = &self.spans[i];
            let de = span.element(&self.systems[span.system], e);
            PointMotion {
                y: shape.y_at(&de),
                z: shape.z_at(&de),
            }
        };
        // A load's point is found among the remembered places (the gaps of the coupling loop).
        let relative = match self.places.iter().find(|p| p.is(x, ey, ez)) {
            Some(p) => p.at.as_ref().map(motion),
            None => self.place(x, ey, ez).as_ref().map(motion),
        }
        .unwrap_or_default();
        if self.drive.is_none() {
            return relative;
        }
        let (y, z) = self
            .find(x)
            .map_or((0.0, 0.0), |(i, local)| self.rigid_body(i, local));
        PointMotion {
            y: relative.y + y,
            z: relative.z + z,
        }
    }

    fn section_at(&self, x: f64) -> SectionMotion {
        let Some((i, local)) = self.find(x) else {
            return SectionMotion::default();
        };
        let relative = {
            let span = &self.spans[i];
            let sys = &self.systems[span.system];
            match span.mid {
                (mid, Some((e, ref s))) if mid == local => {
                    // At a node only that node's translations and twist count.
                    let used = |k: usize| s.z[k] != 0.0 || s.y[k] != 0.0 || s.rx[k] != 0.0;
                    let de = *span
                        .mid_value
                        .get_or_init(|| span.element_where(sys, e, used));
                    Some(SectionMotion {
                        y: s.y_at(&de),
                        z: s.z_at(&de),
                        rx: s.rx_at(&de),
                    })
                }
                _ => sys.model.section_with(local, |e| span.element(sys, e)),
            }
        }
        .unwrap_or_default();
        if self.drive.is_none() {
            return relative;
        }
        let (y, z) = self.rigid_body(i, local);
        SectionMotion {
            y: relative.y + y,
            z: relative.z + z,
            ..relative
        }
    }

    fn commit(&mut self) {
        if !self.solved {
            return;
        }
        let systems = &self.systems;
        if self.parallel {
            self.spans
                .par_iter_mut()
                .for_each(|s| s.commit(&systems[s.system]));
        } else {
            for s in &mut self.spans {
                s.commit(&systems[s.system]);
            }
        }
        self.solved = false;
        self.columns = self.calls > 1;
        self.calls = 0;
        if let Some(track) = &mut self.drive {
            track.commit();
        }
    }
}
