//! Ground-borne vibration: the pier-base forces of a run carried to receivers on the ground
//! surface by the Green's function of the soil (docs/ground.md).
//!
//! Why a reduced model: the paper meshes the soil with millions of solid-element DOFs to
//! show the ground surface moving; environmental assessments need levels at receivers, and
//! a homogeneous half-space's point-load Green's function (Lamb's problem) applied to each
//! pier's vertical base force gives them at a tiny fraction of that cost.
//!
//! - [`green`]: the half-space Green's function (wavenumber integral, its numerics);
//! - [`far`]: W far from the load, by the contour deformed past the pole and branch points;
//! - [`table`]: W tabulated to a stated bound, and the cache of tables ([`table::Tables`]);
//! - [`bessel`]: J0 for it;
//! - [`receivers`]: the pier-base forces of a run to the receivers' velocities (ground.csv);
//! - [`levels`]: a receiver's velocity levels (ground-levels.csv);
//! - [`criteria`]: the FTA and DIN 4150-3 verdicts on them (summary.json `ground`).
pub mod bessel;
pub mod criteria;
pub mod far;
pub mod green;
pub mod levels;
pub mod receivers;
pub mod table;
