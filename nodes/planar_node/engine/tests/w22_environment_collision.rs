//! W22 – Collision with the environment (manual 6.7.2): AddStator(−120,−120), CreateBoundary;
//! M at (0,0); M and environment in G; MoveToPosition((100,100)) → E_COLLISION, objectInfo
//! {Environment (304), env OID}; M stays at (0,0).

mod common;
use common::*;
use motion_core::CommandState;
use planar_engine::*;

#[test]
fn w22_environment_collision() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    s.ok(PlanarCommand::AddStator {
        lower_x: -120.0,
        lower_y: -120.0,
    });
    s.ok(PlanarCommand::CreateBoundary);
    s.enable("M");
    s.enable_group("G");
    s.ok(PlanarCommand::MoverAddToGroup {
        mover: "M".into(),
        group: "G".into(),
    });
    s.ok(PlanarCommand::EnvironmentAddToGroup { group: "G".into() });
    s.step();
    assert_eq!(
        s.snap().environment.group_oid,
        s.snap().group("G").unwrap().oid
    );
    let e = s.err(mtp("M", 100.0, 100.0, 0.0));
    assert_eq!(e.error_id, errors::E_COLLISION, "{e}");
    let info = s.eng.last_object_info();
    assert_eq!(info.object_type, PlanarObjectType::Environment);
    assert_eq!(info.object_type as u32, 304);
    assert_eq!(info.id, s.snap().environment.oid);
    // The rejection itself carries objectInfo (the FB's outputs at the edge).
    assert_eq!(
        e.object,
        Some(motion_core::ObjectRef {
            kind: 304,
            id: s.snap().environment.oid
        })
    );
    s.steps(50);
    assert_pos(&s.mover("M"), 0.0, 0.0);
    // Without the environment in the group the boundary is not checked.
    s.ok(PlanarCommand::EnvironmentRemoveFromGroup);
    let id = s.ok(mtp("M", 100.0, 100.0, 0.0));
    assert_eq!(s.wait_final(id, 5.0), CommandState::Done);
    // A target centre off the stators (issue 15.3): accepted, the boundary is not checked;
    // the centre stops at the stators' edge x = 120 and the mover goes to Error with
    // E_COLLISION and objectInfo = the environment.
    let id = s.ok(mtp("M", 200.0, 0.0, 0.0));
    assert_stopped_at_edge(&mut s, id, "M", 120.0);
}
