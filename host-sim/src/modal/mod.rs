//! The modal (Fourier series) Timoshenko reference for one simply supported span
//! (paper §4.1, Eq. 20a–e; model.md §8).
//!
//! Why: the paper validates its FE guideway against this semi-analytical solution — exact in
//! space for the truncated series, discretised only in time (Newmark, Δt = 1e-5 s in the
//! paper). It implements the same [`Guideway`](crate::guideway::Guideway) interface as the
//! FE model, so the same vehicles and coupling loop drive either, and its natural
//! frequencies cross-check the FE's.
//!
//! - [`modes`]: per-term mass/stiffness from the Galerkin projection, natural frequencies.
//! - [`newmark`]: the per-term Newmark (γ = ½, β = ¼) stepper.
//! - [`span`]: [`ModalGuideway`], the series on one span behind the `Guideway` trait.
pub mod modes;
pub mod newmark;
pub mod span;

pub use modes::{natural_frequencies, ModeFrequencies, PlaneProperties, TorsionProperties};
pub use span::{ModalError, ModalGuideway};

/// Default number of series terms per field. See `tests/modal_convergence.rs`: with 40 terms
/// the peak midspan deflection of the §4.2 span at 100 m/s is within 1e-4 of its converged
/// value (8e-5 measured). A load exactly at the probed point converges more slowly (shear
/// term ~1/N: 3.6e-4 at N = 40, `tests/modal_static.rs`).
pub const DEFAULT_MODES: usize = 40;
