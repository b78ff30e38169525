//! The physics below the simulation: the guideway models behind one interface
//! ([`guideway::Guideway`]), the vehicles and cars with their integrator, the rail
//! irregularity under the wheels and the motion of the supports.
//! Nothing here knows about scenarios, runs or commands: it is matrices, integrators and
//! closed forms, built from SI values.
pub mod cars;
pub mod check;
pub mod fe;
pub mod guideway;
pub mod modal;
pub mod profile;
pub mod rail;
pub mod seismic;
pub mod skid;
pub mod train;
pub mod vehicle;
pub mod vehicle_integrator;
