//! `[output] probes` checked against the case: which wheels, cars, spans and magnets a probe
//! name may refer to (`crate::probes` reads the names).

use super::train::TrainCase;
use crate::input::scenario::Scenario;
use crate::physics::guideway::Bridge;
use crate::probes::{Extent, Probes};
use crate::Result;

/// The case's probes (`[output] probes`, else the default columns), checked against it.
pub(super) fn probes(sc: &Scenario, bridge: &Bridge, train: &TrainCase) -> Result<Probes> {
    let spans = bridge.spans.len();
    let extent = match train {
        TrainCase::Fig1 { cars, .. } => Extent {
            spans,
            wheels: 4 * cars,
            cars: *cars,
            magnets: true,
        },
        TrainCase::Maglev { cars, nodes, .. } => Extent {
            spans,
            wheels: *nodes,
            cars: *cars,
            magnets: true,
        },
        TrainCase::WheelRail { cars, nodes, .. } => Extent {
            spans,
            wheels: *nodes,
            cars: *cars,
            magnets: false,
        },
        // The 3-D cars record their figures in summary.json's `safety`, not as probes.
        TrainCase::HighSpeed { .. } => Extent {
            spans,
            wheels: 0,
            cars: 0,
            magnets: false,
        },
        TrainCase::Forces(f) => Extent {
            spans,
            wheels: f.len(),
            cars: 0,
            magnets: false,
        },
        TrainCase::Unit(_) => Extent {
            spans,
            wheels: 1,
            cars: 1,
            magnets: true,
        },
    };
    Probes::new(sc.output.as_ref().map(|o| o.probes.as_slice()), &extent)
}
