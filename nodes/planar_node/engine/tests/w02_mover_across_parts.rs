//! W2 – Mover across two parts (manual 6.1.4): MoveToPosition((100,100,0), ReferenceId =
//! Part R) → CS position (340,100); GetPositionOnCurrentPart = (100,100) ref Part R.

mod common;
use common::*;
use motion_core::CommandState;
use planar_engine::*;

#[test]
fn w02_mover_across_two_parts() {
    let mut s = Sim::new(two_parts());
    assert_eq!(s.mover("M").part_oid, PART_L);
    assert_eq!(s.mover("M").coordinate_system_oid, CS);
    s.enable("M");
    let id = s.ok(mtp_ref("M", 100.0, 100.0, 0.0, PART_R));
    assert_eq!(s.wait_final(id, 5.0), CommandState::Done);
    let m = s.mover("M");
    assert_pos(&m, 340.0, 100.0);
    assert_eq!(m.part_oid, PART_R);
    let r = s
        .cmd(PlanarCommand::GetPositionOnCurrentPart { mover: "M".into() })
        .unwrap();
    match r.value {
        ReplyValue::Position(p) => {
            assert!(close(p.x, 100.0, POS_TOL) && close(p.y, 100.0, POS_TOL));
            assert_eq!(p.reference_id, PART_R);
        }
        v => panic!("unexpected {v:?}"),
    }
    // §1.4: CS OID and ReferenceId 0 (one CS, static parts) are valid; anything else not.
    let id = s.ok(mtp_ref("M", 120.0, 120.0, 0.0, CS));
    assert_eq!(s.wait_final(id, 5.0), CommandState::Done);
    assert_pos(&s.mover("M"), 120.0, 120.0);
    let id = s.ok(mtp_ref("M", 300.0, 120.0, 0.0, 0));
    assert_eq!(s.wait_final(id, 5.0), CommandState::Done);
    let e = s.err(mtp_ref("M", 100.0, 100.0, 0.0, 0x0BAD_0BAD));
    assert_eq!(e.error_id, errors::E_INVALID_REFERENCE_ID);
    // A target outside every part is accepted (issue 15.3; see mover_crash.rs).
    // Part conversion example of §1.3 for a static layout: (100,100,R) = (340,100,CS).
    let p = s.cmd(PlanarCommand::PartInitialize {
        part: "R".into(),
        part_oid: PART_R,
    });
    assert!(p.is_ok());
    match s
        .cmd(PlanarCommand::PartGetPosition { part: "R".into() })
        .unwrap()
        .value
    {
        ReplyValue::Position(p) => assert_eq!((p.x, p.y, p.reference_id), (240.0, 0.0, CS)),
        v => panic!("{v:?}"),
    }
}
