//! §5.6.4 collision avoidance at a merging switch: T1 and T2 both end at the start of T3
//! (EndAtTrack), three track ends/starts meet at (500,0). A on T1 and B on T2 both head into
//! T3: never are both inside the collision ranges of their incoming track ends at once; the
//! later one waits at the border of its range and follows; both arrive, no collision error.

mod common;
mod track_common;
use common::*;
use motion_core::CommandState;
use planar_engine::*;
use track_common::*;

#[test]
fn merging_switch_is_exclusive() {
    let mut s = Sim::new(cfg(
        &[("A", 100.0, -300.0), ("B", 20.0, 300.0)],
        &["T1", "T2", "T3"],
    ));
    s.ok(line("T3", (500.0, 0.0), (1200.0, 0.0)));
    s.ok(line("T1", (0.0, -300.0), (200.0, -300.0)));
    s.ok(PlanarCommand::TrackEndAtTrack {
        track: "T1".into(),
        other: "T3".into(),
    });
    s.ok(line("T2", (0.0, 300.0), (200.0, 300.0)));
    s.ok(PlanarCommand::TrackEndAtTrack {
        track: "T2".into(),
        other: "T3".into(),
    });
    for t in ["T1", "T2", "T3"] {
        enable_track(&mut s, t);
    }
    assert_eq!(track(&s, "T3").previous_tracks, vec!["T1", "T2"]);
    let (l1, r1) = (track(&s, "T1").length, track(&s, "T1").collision_range_end);
    let (l2, r2) = (track(&s, "T2").length, track(&s, "T2").collision_range_end);
    assert!(r1 > 0.0 && r2 > 0.0 && track(&s, "T3").collision_range_start > 0.0);
    s.enable("A");
    s.enable("B");
    join_wait(&mut s, "A", "T1", true);
    join_wait(&mut s, "B", "T2", true);
    let a = s.ok(mot("A", "T3", 600.0));
    let b = s.ok(mot("B", "T3", 300.0));
    let mut b_waited = false;
    let mut n = 0;
    while !(s.state(a) == Some(CommandState::Done) && s.state(b) == Some(CommandState::Done)) {
        s.step();
        let (oa, ob) = (on_track(&s, "A"), on_track(&s, "B"));
        let a_in = in_end_range(&oa, "T1", l1, r1);
        let b_in = in_end_range(&ob, "T2", l2, r2);
        assert!(!(a_in && b_in), "both in the merge zone: A {oa:?} B {ob:?}");
        if ob.track == "T2" && ob.waiting && ob.set_velo == 0.0 {
            b_waited = true;
            assert!(
                close(ob.set_pos, l2 - r2, POS_TOL),
                "B waits at its range border"
            );
        }
        n += 1;
        assert!(
            n < 20_000,
            "not finished: A {:?} B {:?}",
            s.history.get(&a),
            s.history.get(&b)
        );
    }
    assert!(b_waited, "B had to wait for A");
    assert!(close(on_track(&s, "A").set_pos, 600.0, POS_TOL));
    assert!(close(on_track(&s, "B").set_pos, 300.0, POS_TOL));
    assert_eq!(track(&s, "T3").movers, vec!["B", "A"]);
}
