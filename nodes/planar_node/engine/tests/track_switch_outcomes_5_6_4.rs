//! The manual example outcomes (a)-(d) of §5.6.4 at a merging switch (T1 and T2 end where T3
//! starts), with the simulator rule (proposal): a mover may not enter the switch zone while a
//! mover on another track of the switch is inside its own zone part; first reservation wins;
//! a waiting mover stops at the zone border.
//! (a) M2 heading to T3 stops exactly where the collision range of its own track begins
//!     because M1 stands inside T1's end range;
//! (b) with a collision range shorter than the gap, M2 stops exactly one gap before the end of
//!     T2 while M1 stands at the start of T3;
//! (c) both continue once M1 has moved far enough that their distance exceeds both gaps;
//! (d) if M2 is farther than its collision range from the switch, M1 passes unhindered.

mod common;
mod track_common;
use common::*;
use motion_core::CommandState;
use track_common::*;

/// T1 (0,-300)-(200,-300) and T2 (0,300)-(200,300) end at T3's start (500,0); T3 runs to
/// (1500,0). T2's end range is manual (`r2`); M1 starts on T1, M2 on T2.
fn merge(r2: f64, m1: (f64, f64), m2: (f64, f64)) -> Sim {
    let yaml = format!(
        "
movers:
  - {{name: M1, initial_pose: {{x: {}, y: {}}}}}
  - {{name: M2, initial_pose: {{x: {}, y: {}}}}}
tracks:
  - {{name: T1, geometry: [{{line: {{start: [0, -300], end: [200, -300]}}}}], ends_at: [T3]}}
  - {{name: T2, geometry: [{{line: {{start: [0, 300], end: [200, 300]}}}}], ends_at: [T3],
     collision_range_mode: manual, collision_range_end: {r2}}}
  - {{name: T3, geometry: [{{line: {{start: [500, 0], end: [1500, 0]}}}}]}}
",
        m1.0, m1.1, m2.0, m2.1
    );
    let mut s = Sim::new(serde_yaml::from_str(&yaml).unwrap());
    for t in ["T1", "T2", "T3"] {
        enable_track(&mut s, t);
    }
    s.enable("M1");
    s.enable("M2");
    s
}

/// Runs until `m` stands still waiting (or `limit` cycles).
fn until_waiting(s: &mut Sim, m: &str, limit: usize) -> bool {
    for _ in 0..limit {
        s.step();
        let o = on_track(s, m);
        if o.waiting && o.set_velo == 0.0 && o.set_acc == 0.0 {
            return true;
        }
    }
    false
}

#[test]
fn a_m2_stops_where_its_collision_range_begins() {
    let mut s = merge(300.0, (20.0, -300.0), (20.0, 300.0));
    join_wait(&mut s, "M1", "T1", true);
    join_wait(&mut s, "M2", "T2", true);
    let (l1, r1) = (track(&s, "T1").length, track(&s, "T1").collision_range_end);
    let l2 = track(&s, "T2").length;
    assert_eq!(track(&s, "T2").collision_range_end, 300.0);
    // M1 moves into T1's end range and stands there.
    let m1 = s.ok(mot("M1", "T1", l1 - r1 / 2.0));
    assert_eq!(s.wait_final(m1, 10.0), CommandState::Done);
    let m2 = s.ok(mot("M2", "T3", 300.0));
    assert!(until_waiting(&mut s, "M2", 20_000), "M2 waits");
    let o = on_track(&s, "M2");
    assert_eq!(o.track, "T2");
    assert!(
        close(o.set_pos, l2 - 300.0, POS_TOL),
        "{o:?} vs {}",
        l2 - 300.0
    );
    // It keeps waiting while M1 stands in its range.
    s.steps(500);
    assert!(close(on_track(&s, "M2").set_pos, l2 - 300.0, POS_TOL));
    assert_eq!(s.state(m2), Some(CommandState::Active));
    // (c) M1 moves on along T3: M2 follows, both arrive, the merge stays exclusive.
    let m1 = s.ok(mot("M1", "T3", 700.0));
    assert_eq!(s.wait_final(m1, 20.0), CommandState::Done);
    assert_eq!(s.wait_final(m2, 20.0), CommandState::Done);
    assert_eq!(track(&s, "T3").movers, vec!["M2", "M1"]);
}

#[test]
fn b_and_c_m2_stops_one_gap_before_the_end_of_t2() {
    // T2's range (100) is shorter than the gap (200): M2 waits for M1 on T3 by gap control,
    // one gap before T2's end while M1 stands at T3's start.
    let mut s = merge(100.0, (20.0, -300.0), (20.0, 300.0));
    join_wait(&mut s, "M1", "T1", true);
    join_wait(&mut s, "M2", "T2", true);
    let l1 = track(&s, "T1").length;
    let l2 = track(&s, "T2").length;
    let r3 = track(&s, "T3").collision_range_start;
    let m1 = s.ok(mot("M1", "T3", 0.0));
    assert_eq!(s.wait_final(m1, 10.0), CommandState::Done);
    assert_eq!(on_track(&s, "M1").track, "T3");
    assert!(l1 > 0.0 && r3 > 0.0);
    let m2 = s.ok(mot("M2", "T3", 300.0));
    assert!(until_waiting(&mut s, "M2", 20_000), "M2 waits");
    let o = on_track(&s, "M2");
    assert_eq!(o.track, "T2");
    assert!(
        close(o.set_pos, l2 - 200.0, POS_TOL),
        "{o:?} vs {}",
        l2 - 200.0
    );
    // (c) M1 moves to 150 on T3: M2 closes up to one gap behind it (T2's range border does
    // not hold M2: M1 is on M2's own route, ahead of it).
    let m1 = s.ok(mot("M1", "T3", 150.0));
    assert_eq!(s.wait_final(m1, 10.0), CommandState::Done);
    assert!(until_waiting(&mut s, "M2", 20_000), "M2 waits again");
    // (Gap control may come to rest a fraction of a mm early and then creep up; let it settle.)
    s.steps(2000);
    let o = on_track(&s, "M2");
    let behind = if o.track == "T2" {
        l2 - o.set_pos + 150.0
    } else {
        150.0 - o.set_pos
    };
    assert!(close(behind, 200.0, POS_TOL), "{o:?}: {behind}");
    // M1 leaves for the end of T3: M2 reaches its target.
    let m1 = s.ok(mot("M1", "T3", 900.0));
    assert_eq!(s.wait_final(m2, 20.0), CommandState::Done);
    assert_eq!(s.wait_final(m1, 20.0), CommandState::Done);
    assert!(close(on_track(&s, "M2").set_pos, 300.0, POS_TOL));
}

#[test]
fn d_m1_passes_unhindered_when_m2_is_outside_its_range() {
    // M2 stands on T2 at s = 20, 180 mm from the switch with T2's range 100: M1 passes from T1
    // into T3 without waiting, in the time of its own profile.
    let free_time = {
        let mut s = merge(100.0, (20.0, -300.0), (20.0, 700.0));
        join_wait(&mut s, "M1", "T1", true);
        let m1 = s.ok(mot("M1", "T3", 400.0));
        let mut n = 0;
        while s.state(m1) != Some(CommandState::Done) {
            s.step();
            n += 1;
            assert!(n < 20_000);
        }
        n
    };
    let mut s = merge(100.0, (20.0, -300.0), (20.0, 300.0));
    join_wait(&mut s, "M1", "T1", true);
    join_wait(&mut s, "M2", "T2", true);
    assert!(track(&s, "T2").length - on_track(&s, "M2").set_pos > 100.0);
    let m1 = s.ok(mot("M1", "T3", 400.0));
    let mut n = 0;
    while s.state(m1) != Some(CommandState::Done) {
        s.step();
        assert!(!on_track(&s, "M1").waiting, "M1 never waits");
        n += 1;
        assert!(n < 20_000);
    }
    assert_eq!(n, free_time, "same time as with no mover on T2");
    // And M2, now behind M1 by more than its gap, follows into T3 without waiting either.
    let m2 = s.ok(mot("M2", "T3", 100.0));
    assert_eq!(s.wait_final(m2, 10.0), CommandState::Done);
}
