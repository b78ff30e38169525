//! Cross-crate integration and validation tests live in `tests/tests/`; this library holds
//! the shared pieces they need: canned inputs and independent reference implementations
//! written straight from docs/model.md, never from the code under test.

pub mod control_reference;
pub mod rigid_vehicle_reference;
pub mod traces;
