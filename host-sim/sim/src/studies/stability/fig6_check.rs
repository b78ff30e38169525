//! The Fig. 6 carriage on a rigid rail under the paper's law: linearised with all its 32
//! magnets (`stability::vehicle`, docs/model.md §2 item 3), it must be stable — the check the
//! train's runs rely on.

use super::vehicle::VehiclePlant;
use crate::physics::cars::fig6::Fig6;
use maglev_core::gap::Geometry;
use maglev_core::LawKind;
use maglev_core::Params;

fn verdict(p: &Fig6) -> super::vehicle::Verdict {
    let v = p.build(9.81).unwrap();
    VehiclePlant::new(
        &v,
        &Params::paper_wheel(1e-3),
        &LawKind::Paper,
        Geometry::Paper,
    )
    .unwrap()
    .verdict()
    .unwrap()
}

#[test]
fn fig6_carriage_is_stable_under_the_paper_law_on_a_rigid_rail() {
    let v = verdict(&Fig6::default());
    eprintln!(
        "zero poles {}, max real part {}",
        v.zero_poles, v.max_real_part
    );
    // The five rigid motions (v, w, θx, θy, θz of the whole carriage) are zero poles.
    assert_eq!(v.zero_poles, 5, "{:?}", &v.poles[..8]);
    assert!(v.stable, "max real part {}", v.max_real_part);
}
