//! W18 – Stators and boundary (manual 6.4.2): four stators, CreateBoundary → 4 stators,
//! 8 boundary elements (one per exposed 240 mm edge, §1.2 proposal).

mod common;
use common::*;
use planar_engine::*;

#[test]
fn w18_stators_and_boundary() {
    let mut s = Sim::with_movers(&[("M", 120.0, 120.0)]);
    for (x, y) in [(0.0, 0.0), (240.0, 0.0), (0.0, 240.0), (240.0, 240.0)] {
        s.ok(PlanarCommand::AddStator {
            lower_x: x,
            lower_y: y,
        });
    }
    s.ok(PlanarCommand::CreateBoundary);
    let env = s.snap().environment;
    assert_eq!(env.stator_count, 4);
    assert_eq!(env.boundary_element_count, 8);
    // Overlapping stator → E_INVALID_PARAMETER, nothing added.
    let e = s.err(PlanarCommand::AddStator {
        lower_x: 100.0,
        lower_y: 0.0,
    });
    assert_eq!(e.error_id, errors::E_INVALID_PARAMETER);
    assert_eq!(s.snap().environment.stator_count, 4);
    // The area is [0, 480]²: inside reachable, outside not.
    s.enable("M");
    let id = s.ok(mtp("M", 360.0, 360.0, 0.0));
    assert_eq!(s.wait_final(id, 5.0), motion_core::CommandState::Done);
    // Off the area (issue 15.3): accepted, nothing checks the boundary outside a group with
    // the environment; the mover's centre stops at the edge x = 480, where it could no longer
    // levitate, and it goes to Error with E_COLLISION naming the environment.
    let id = s.ok(mtp("M", 500.0, 100.0, 0.0));
    assert_stopped_at_edge(&mut s, id, "M", 480.0);
    // Clear removes stators and boundary; CreateBoundary without stators fails.
    s.ok(PlanarCommand::EnvironmentClear);
    assert_eq!(s.snap().environment.stator_count, 0);
    assert_eq!(s.snap().environment.boundary_element_count, 0);
    assert_eq!(
        s.err(PlanarCommand::CreateBoundary).error_id,
        errors::E_INVALID_PARAMETER
    );
    let info = s
        .cmd(PlanarCommand::EnvironmentGetPlanarObjectInfo)
        .unwrap()
        .value;
    assert_eq!(
        info,
        ReplyValue::ObjectInfo(PlanarObjectInfo {
            object_type: PlanarObjectType::Environment,
            id: s.snap().environment.oid
        })
    );
}
