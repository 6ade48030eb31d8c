//! W17 – Group (manual 6.3.2): A (0,0), B (240,0) in group G; in one cycle (A first)
//! A.MoveToPosition((0,240)), B.MoveToPosition((0,0)). A ends at (0,240); B is rejected with
//! E_COLLISION, objectInfo {Mover, A}; B stays at (240,0).

mod common;
use common::*;
use motion_core::CommandState;
use planar_engine::*;

fn setup() -> Sim {
    let mut s = Sim::with_movers(&[("A", 0.0, 0.0), ("B", 240.0, 0.0)]);
    s.enable("A");
    s.enable("B");
    s.enable_group("G");
    for m in ["A", "B"] {
        let id = s.ok(PlanarCommand::MoverAddToGroup {
            mover: m.into(),
            group: "G".into(),
        });
        assert_eq!(s.wait_final(id, 1.0), CommandState::Done);
    }
    s
}

#[test]
fn w17_group_reservation() {
    let mut s = setup();
    let g = s.snap().group("G").unwrap().oid;
    assert_eq!(s.mover("A").group_oid, g);
    assert_eq!(s.mover("B").group_oid, g);
    let a = s.ok(mtp("A", 0.0, 240.0, 0.0));
    let e = s.err(mtp("B", 0.0, 0.0, 0.0));
    assert_eq!(e.error_id, errors::E_COLLISION, "{e}");
    let info = s.eng.last_object_info();
    assert_eq!(
        info,
        PlanarObjectInfo {
            object_type: PlanarObjectType::Mover,
            id: s.mover("A").oid
        }
    );
    assert!(e.message.contains("'A'"), "the blocker is named: {e}");
    assert_eq!(s.wait_final(a, 10.0), CommandState::Done);
    assert_pos(&s.mover("A"), 0.0, 240.0);
    assert_pos(&s.mover("B"), 240.0, 0.0);
    // After A's command ended its reservation shrank to its footprint: B may go now.
    let b = s.ok(mtp("B", 0.0, 0.0, 0.0));
    assert_eq!(s.wait_final(b, 10.0), CommandState::Done);
    assert_pos(&s.mover("B"), 0.0, 0.0);
}

/// §3.4: a member's motion needs an Enabled group; Disable is refused while members move.
#[test]
fn w17_group_state_gates_members() {
    let mut s = setup();
    let a = s.ok(mtp("A", 0.0, 240.0, 0.0));
    s.step();
    let e = s.err(PlanarCommand::GroupDisable { group: "G".into() });
    assert_eq!(e.error_id, errors::E_INVALID_STATE);
    assert_eq!(s.wait_final(a, 10.0), CommandState::Done);
    let d = s.ok(PlanarCommand::GroupDisable { group: "G".into() });
    assert_eq!(s.wait_final(d, 1.0), CommandState::Done);
    assert_eq!(
        s.err(mtp("A", 0.0, 480.0, 0.0)).error_id,
        errors::E_GROUP_NOT_READY
    );
    assert_eq!(
        s.mover("A").group_oid,
        s.snap().group("G").unwrap().oid,
        "membership kept"
    );
    s.enable_group("G");
    let a = s.ok(mtp("A", 0.0, 480.0, 0.0));
    assert_eq!(s.wait_final(a, 10.0), CommandState::Done);
}

/// §3.2 AddToGroup preconditions.
#[test]
fn w17_add_to_group_preconditions() {
    let mut s = Sim::with_movers(&[("A", 0.0, 0.0), ("B", 240.0, 0.0)]);
    // Group not Enabled.
    s.enable("A");
    let e = s.err(PlanarCommand::MoverAddToGroup {
        mover: "A".into(),
        group: "G".into(),
    });
    assert_eq!(e.error_id, errors::E_GROUP_NOT_READY);
    s.enable_group("G");
    // Mover not Enabled.
    let e = s.err(PlanarCommand::MoverAddToGroup {
        mover: "B".into(),
        group: "G".into(),
    });
    assert_eq!(e.error_id, errors::E_INVALID_STATE);
    // Moving.
    s.enable("B");
    let mv = s.ok(mtp("B", 600.0, 0.0, 0.0));
    s.steps(3);
    let e = s.err(PlanarCommand::MoverAddToGroup {
        mover: "B".into(),
        group: "G".into(),
    });
    assert_eq!(
        e.error_id,
        errors::E_INVALID_COMMAND_MODE,
        "§2.3: AddToGroup only standing"
    );
    s.wait_final(mv, 5.0);
    s.ok(PlanarCommand::MoverAddToGroup {
        mover: "A".into(),
        group: "G".into(),
    });
    // Already a member.
    let e = s.err(PlanarCommand::MoverAddToGroup {
        mover: "A".into(),
        group: "G".into(),
    });
    assert_eq!(e.error_id, errors::E_GROUP_NOT_READY);
    // Footprint inside a reserved area of the group. B is busy (lifting), so A's command is
    // not refused by the idle-mover check; the guard stops A short of B afterwards.
    let z = s.ok(PlanarCommand::MoveZ {
        mover: "B".into(),
        target_position: 6.0,
        constraint: DynamicConstraint::default(),
    });
    let a = s.ok(mtp("A", 600.0, 150.0, 0.0));
    s.step();
    let e = s.err(PlanarCommand::MoverAddToGroup {
        mover: "B".into(),
        group: "G".into(),
    });
    assert_eq!(e.error_id, errors::E_COLLISION, "{e}");
    assert!(e.message.contains("'A'"), "{e}");
    assert_eq!(
        s.wait_final(a, 5.0),
        CommandState::Error(errors::E_COLLISION),
        "A stopped short of B"
    );
    s.run_until(1.0, |p| {
        p.mover("A").unwrap().set_velo == MoverVector::default()
    });
    let (pa, pb) = (s.mover("A").set_pos, s.mover("B").set_pos);
    assert!(
        pa.y - pb.y >= 155.0 - 1e-6 || (pa.x - pb.x).abs() >= 155.0 - 1e-6,
        "no overlap: A {pa:?} B {pb:?}"
    );
    s.wait_final(z, 5.0);
    // Straight up is free.
    let a = s.ok(mtp("A", pa.x, 400.0, 0.0));
    assert_eq!(s.wait_final(a, 5.0), CommandState::Done);
    s.ok(PlanarCommand::MoverAddToGroup {
        mover: "B".into(),
        group: "G".into(),
    });
    // RemoveFromGroup: not in a group → Done without effect.
    s.ok(PlanarCommand::MoverRemoveFromGroup { mover: "B".into() });
    let r = s.ok(PlanarCommand::MoverRemoveFromGroup { mover: "B".into() });
    assert_eq!(s.wait_final(r, 1.0), CommandState::Done);
    assert_eq!(s.mover("B").group_oid, 0);
}
