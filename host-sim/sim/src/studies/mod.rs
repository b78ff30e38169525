//! Studies above the simulation: what runs passages or linearises the plant and compares the
//! answers with references — the paper's validation and §5 report, the stability analyses and
//! the gain designs they feed, the law on a gap trace, and sweeps over a scenario's keys.
pub mod control;
pub mod design;
pub mod stability;
