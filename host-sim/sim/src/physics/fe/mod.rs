//! Finite-element guideway: 3-D Timoshenko beam elements on simply supported spans, Newmark
//! in time, wheel loads and displacements through [`maglev_core::gap`] (paper §3, Eq. 15, 16,
//! 19).
//!
//! - [`element`]: the 12-DOF element matrices;
//! - [`banded`]: symmetric band storage of the span matrices;
//! - [`cholesky`]: sparse Cholesky (faer, AMD ordering) of the span's effective stiffness;
//! - [`component_band`]: the same matrix factorised as narrow bands over its decoupled DOF
//!   families, for the time loop's solves;
//! - [`assembly`]: one span, supports, load distribution and interpolation;
//! - [`newmark`]: average-acceleration Newmark with a once-factorised effective stiffness;
//! - [`flexibility`]: a small span's Keff⁻¹ by columns, so iterations query without solving;
//! - [`modal_basis`]: a small span's step in the coordinates that diagonalise it;
//! - [`bridge`]: [`FeGuideway`], a whole [`crate::physics::guideway::Bridge`] behind the
//!   [`crate::physics::guideway::Guideway`] interface;
//! - [`modes`]: natural frequencies and mode kinds;
//! - [`structure`]: a general coupled frame (beams along X or Z, springs, dashpots, lumped
//!   masses) and its modes;
//! - [`soil`]: Gazetas' footing impedance;
//! - [`viaduct`]: [`Viaduct`], the §5 viaduct (girders, bearings, piers, foundations) as one
//!   coupled structure behind [`crate::physics::guideway::Guideway`].
//!
//! Building and stepping a bridge (one Newton–Raphson iteration per `solve_step`):
//!
//! ```
//! use maglev_sim::physics::fe::FeGuideway;
//! use maglev_sim::physics::guideway::{BeamSection, Bridge, Guideway, PointLoad};
//!
//! let bridge = Bridge { section: BeamSection::paper_4_2(), spans: vec![25.0, 25.0] };
//! let mut fe = FeGuideway::new(&bridge, 20, 1e-3).unwrap();
//! // A magnet at x = 3 m on a target line 1.5 m off the axis, 0.6 m above it, pulling
//! // itself up with 36.8 kN pulls the rail down:
//! let load = PointLoad { x: 3.0, ey: 1.5, ez: 0.6, fy: 0.0, fz: -36.8e3 };
//! fe.solve_step(&[load]); // state at t + dt for this load estimate (from the committed state)
//! let z_g = fe.motion_at(3.0, 1.5, 0.6).z; // Eq. 16, for the gap (Eq. 2)
//! fe.commit(); // accept once the coupling has converged
//! assert!(z_g < 0.0);
//! ```
pub mod assembly;
pub mod banded;
pub mod bridge;
pub mod cholesky;
pub mod component_band;
pub mod element;
pub mod flexibility;
pub mod modal_basis;
pub mod modes;
pub mod newmark;
pub mod soil;
pub mod structure;
pub mod viaduct;

pub use assembly::{DofFamily, SpanModel};
pub use banded::{SymBanded, SymSparse};
pub use bridge::FeGuideway;
pub use modes::{natural_modes, Mode, ModeKind};
pub use newmark::{Newmark, Rayleigh, SpanNewmark, State};
pub use structure::{dense_modes, lowest_modes, Structure};
pub use viaduct::{paper5_viaduct, Viaduct, ViaductSpec};
