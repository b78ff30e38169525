//! Finite-element guideway: 3-D Timoshenko beam elements on simply supported spans, Newmark
//! in time, wheel loads and displacements through [`maglev_core::gap`] (paper §3, Eq. 15, 16,
//! 19).
//!
//! - [`element`]: the 12-DOF element matrices;
//! - [`assembly`]: one span, supports, load distribution and interpolation;
//! - [`newmark`]: average-acceleration Newmark with a once-factorised effective stiffness;
//! - [`bridge`]: [`FeGuideway`], a whole [`crate::guideway::Bridge`] behind the
//!   [`crate::guideway::Guideway`] interface;
//! - [`modes`]: natural frequencies and mode kinds.
pub mod assembly;
pub mod bridge;
pub mod element;
pub mod modes;
pub mod newmark;

pub use assembly::{DofFamily, SpanModel};
pub use bridge::FeGuideway;
pub use modes::{natural_modes, Mode, ModeKind};
pub use newmark::{Newmark, Rayleigh, State};
