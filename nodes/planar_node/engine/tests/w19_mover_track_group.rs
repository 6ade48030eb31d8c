//! W19 – Mover, track and group (manual 6.5): A (0,0), B (240,0); track T (0,0)–(400,0); T and
//! G enabled; A, B enabled; A, B, T in G. A joins (s = 0). In one cycle A.MoveOnTrack(150) and
//! B.MoveToPosition((240,320)): A's command fails with E_COLLISION, objectInfo {Mover, B} (T
//! would become Moving and block its area, which B occupies); B moves. After B stands, A's
//! MoveOnTrack(150) is Done at (150,0). While T is Moving it blocks its area for B (§5.11).

mod common;
mod track_common;
use common::*;
use motion_core::CommandState;
use planar_engine::errors::*;
use planar_engine::*;
use track_common::*;

#[test]
fn w19_mover_track_and_group() {
    let mut s = group_with_track(&[("A", 0.0, 0.0), ("B", 240.0, 0.0)], &["A", "B"]);
    let g = s.snap().group("G").unwrap().clone();
    assert_eq!(g.member_count, 3);
    assert_eq!(g.tracks, vec!["T"]);
    join_wait(&mut s, "A", "T", true);
    let e = s.err(mot("A", "", 150.0));
    assert_eq!(e.error_id, E_COLLISION);
    let info = s.eng.last_object_info();
    assert_eq!(info.object_type, PlanarObjectType::Mover);
    assert_eq!(info.id, s.mover("B").oid);
    let b = s.ok(mtp("B", 240.0, 320.0, 0.0));
    assert_eq!(s.wait_final(b, 5.0), CommandState::Done);
    assert_pos(&s.mover("B"), 240.0, 320.0);
    s.step();
    let a = s.ok(mot("A", "", 150.0));
    s.step();
    assert_eq!(track(&s, "T").operation_mode, TrackOperationMode::Moving);
    // The Moving member track blocks its area for the other members.
    let e = s.err(mtp("B", 240.0, 0.0, 0.0));
    assert_eq!(e.error_id, E_COLLISION);
    let info = s.eng.last_object_info();
    assert_eq!(info.object_type, PlanarObjectType::Track);
    assert_eq!(info.id, track(&s, "T").oid);
    assert_eq!(s.wait_final(a, 5.0), CommandState::Done);
    assert_pos(&s.mover("A"), 150.0, 0.0);
    s.step();
    // Standing again: no blocking.
    let b = s.ok(mtp("B", 240.0, 200.0, 0.0));
    assert_eq!(s.wait_final(b, 5.0), CommandState::Done);
    // Bad requests.
    assert_eq!(
        s.err(PlanarCommand::TrackAddToGroup {
            track: "T".into(),
            group: "G".into()
        })
        .error_id,
        E_GROUP_NOT_READY,
        "already a member"
    );
    assert_eq!(
        s.err(PlanarCommand::TrackAddToGroup {
            track: "T".into(),
            group: "nope".into()
        })
        .error_id,
        motion_core::ErrorId::UNKNOWN_OBJECT
    );
}
