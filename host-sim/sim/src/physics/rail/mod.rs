//! The wheel/rail track and running gear of a high-speed train (issue 41): the rail
//! irregularity of a real track ([`spectrum`], [`irregularity`]), the wheel–rail contact
//! ([`contact`]), one wheelset on its rails ([`wheelset`]), the 3-D car ([`car`]), the track
//! ([`track`], [`rail_mass`]) and the cars in a run ([`run`]).
//! docs/cars.md, "The high-speed track and wheelset", states every value and its source.

pub mod car;
pub mod contact;
pub mod irregularity;
pub mod rail_mass;
pub mod run;
pub mod spectrum;
pub mod track;
pub mod wheelset;
