//! The modal (Fourier series) Timoshenko reference for one simply supported span
//! (paper §4.1, Eq. 20a–e; docs/model.md §8).
//!
//! Why: the paper validates its FE guideway against this semi-analytical solution — exact in
//! space for the truncated series, discretised only in time (Newmark, Δt = 1e-5 s in the
//! paper). It implements the same [`Guideway`](crate::physics::guideway::Guideway) interface as the
//! FE model, so the same vehicles and coupling loop drive either, and its natural
//! frequencies cross-check the FE's.
//!
//! - [`modes`]: per-term mass/stiffness from the Galerkin projection, natural frequencies.
//! - [`newmark`]: the per-term Newmark (γ = ½, β = ¼) stepper.
//! - [`span`]: [`ModalGuideway`], the series on one span behind the `Guideway` trait;
//! - [`spans`]: [`ModalSpans`], one series per span of a line of simply supported spans.
pub mod mode_integrator;
pub mod modes;
pub mod span;
pub mod spans;

pub use modes::{natural_frequencies, ModeFrequencies, PlaneProperties, TorsionProperties};
pub use span::{ModalError, ModalGuideway};
pub use spans::ModalSpans;

/// Default number of series terms per field.
///
/// Two criteria (tests `modal_convergence.rs`, `modal_static.rs`): the peak midspan
/// deflection at 100 m/s converges fast (≈ 1/N², 8e-5 short at N = 40), but the coupling
/// reads the guideway *under the wheels*, where the shear deflection and the twist have a
/// kink and their series converge only like Σ_{odd n>N} 1/n²: the twist under a point torque
/// is short by ≈ 0.4/N of its value (1 % at N = 40, 0.25 % at N = 160), the shear share of
/// the deflection likewise. 160 terms keep both at the 0.25 % level and cost ~0.1 s per
/// 100 m/s passage at Δt = 1e-5.
pub const DEFAULT_MODES: usize = 160;
