//! §1.6 track init parameters for collision avoidance: "Maximal mover width/height" (default
//! 155/155), "Check collision against static objects" (default FALSE), "Collision range
//! mode" (default Automatic), "Collision range at start/end" (Manual), and the automatic
//! range of §5.6.4 (distance to every other track of the switch beyond the clearance of the
//! track's maximal mover: 2·√2·R + 50 mm, R = half diagonal; see TrackParams).

mod common;
mod track_common;
use common::*;
use motion_core::{CommandState, ErrorId};
use planar_engine::*;
use track_common::*;

fn config(yaml: &str) -> PlanarConfig {
    serde_yaml::from_str(yaml).unwrap_or_else(|e| panic!("{yaml}: {e}"))
}

/// A straight T1 into a switch at (1000, 0) where T2 (straight on) and T3 (branching up)
/// start; `extra` goes into T1's entry.
fn switch(extra: &str) -> PlanarConfig {
    config(&format!(
        "
tracks:
  - {{name: T1, geometry: [{{line: {{start: [0, 0], end: [1000, 0]}}}}]{extra}}}
  - {{name: T2, starts_from: [T1], geometry: [{{line: {{start: [1000, 0], end: [2000, 0]}}}}]}}
  - {{name: T3, starts_from: [T1], geometry: [{{line: {{start: [1300, 300], end: [1300, 1000]}}}}]}}
"
    ))
}

#[test]
fn defaults_are_the_spec_values() {
    let s = Sim::new(switch(""));
    let t = track(&s, "T1");
    assert_eq!((t.max_mover_width, t.max_mover_height), (155.0, 155.0));
    assert!(!t.check_static_collision);
    assert_eq!(t.collision_range_mode, CollisionRangeMode::Automatic);
    // Without a switch at the start the range is 0 (§5.6.4).
    assert_eq!(t.collision_range_start, 0.0);
}

#[test]
fn automatic_range_follows_the_maximal_mover() {
    // Default 155 × 155: R = 109.6, clearance 2·√2·R + 50 = 360 mm. The incoming T1 is
    // straight and the other tracks start at its end, so its range is the clearance
    // (computed in 5 mm steps).
    let s = Sim::new(switch(""));
    let r = track(&s, "T1").collision_range_end;
    assert!((360.0..=365.0 + 1e-9).contains(&r), "{r}");
    // 300 × 300: R = 212.1, clearance 650 mm.
    let s = Sim::new(switch(", max_mover_width: 300, max_mover_height: 300"));
    let r = track(&s, "T1").collision_range_end;
    assert!((650.0..=655.0 + 1e-9).contains(&r), "{r}");
    assert_eq!(track(&s, "T1").max_mover_width, 300.0);
    // The outgoing tracks keep their own (default) maximal mover.
    let (a, b) = (
        track(&s, "T2").collision_range_start,
        track(&s, "T3").collision_range_start,
    );
    assert!(a > 0.0 && b > 0.0, "{a} {b}");
    // T2's range ends where it is farther than 360 mm from T1 and T3 near the switch.
    let q = position_at(&mut Sim::new(switch("")), "T2", a);
    assert!(q.x - 1000.0 >= 360.0 - 1e-6, "{q:?}");
}

#[test]
fn manual_ranges_are_used() {
    let s = Sim::new(switch(
        ", collision_range_mode: manual, collision_range_start: 10, collision_range_end: 420",
    ));
    let t = track(&s, "T1");
    assert_eq!(t.collision_range_mode, CollisionRangeMode::Manual);
    assert_eq!(
        (t.collision_range_start, t.collision_range_end),
        (10.0, 420.0)
    );
    // The other tracks stay automatic.
    assert_eq!(
        track(&s, "T2").collision_range_mode,
        CollisionRangeMode::Automatic
    );
}

/// The merge of the §5.6.4 test (T1, T2 into T3) with a manual range of 500 mm at T2's end
/// (the automatic one is smaller): A on T1 takes the switch first, B waits exactly at the
/// border of its manual range (manual example (a)).
#[test]
fn a_waiting_mover_stops_at_the_manual_range() {
    let mut s = Sim::new(config(
        "
movers:
  - {name: A, initial_pose: {x: 100, y: -300}}
  - {name: B, initial_pose: {x: 20, y: 300}}
tracks:
  - {name: T1, geometry: [{line: {start: [0, -300], end: [200, -300]}}], ends_at: [T3]}
  - {name: T2, geometry: [{line: {start: [0, 300], end: [200, 300]}}], ends_at: [T3],
     collision_range_mode: manual, collision_range_end: 500}
  - {name: T3, geometry: [{line: {start: [500, 0], end: [1200, 0]}}]}
",
    ));
    for t in ["T1", "T2", "T3"] {
        enable_track(&mut s, t);
    }
    let (l1, r1) = (track(&s, "T1").length, track(&s, "T1").collision_range_end);
    let (l2, r2) = (track(&s, "T2").length, track(&s, "T2").collision_range_end);
    assert_eq!(r2, 500.0);
    assert!(r1 > 0.0 && r1 < 500.0, "automatic {r1}");
    assert!(l2 - r2 > 20.0, "B starts outside its zone: {l2}");
    s.enable("A");
    s.enable("B");
    join_wait(&mut s, "A", "T1", true);
    join_wait(&mut s, "B", "T2", true);
    let a = s.ok(mot("A", "T3", 600.0));
    let b = s.ok(mot("B", "T3", 300.0));
    let mut b_waited = false;
    for _ in 0..20_000 {
        if s.state(a) == Some(CommandState::Done) && s.state(b) == Some(CommandState::Done) {
            break;
        }
        s.step();
        let (oa, ob) = (on_track(&s, "A"), on_track(&s, "B"));
        let a_in = in_end_range(&oa, "T1", l1, r1);
        let b_in = in_end_range(&ob, "T2", l2, r2);
        assert!(!(a_in && b_in), "both in the merge zone: A {oa:?} B {ob:?}");
        if ob.track == "T2" && ob.waiting && ob.set_velo == 0.0 {
            b_waited = true;
            assert!(
                close(ob.set_pos, l2 - r2, POS_TOL),
                "B waits at its manual range border: {ob:?}"
            );
        }
    }
    assert_eq!(s.state(a), Some(CommandState::Done));
    assert_eq!(s.state(b), Some(CommandState::Done));
    assert!(b_waited, "B had to wait for A");
    assert_eq!(track(&s, "T3").movers, vec!["B", "A"]);
}

#[test]
fn bad_parameters_are_refused() {
    for (extra, key) in [
        (", max_mover_width: 0", "tracks[0].max_mover_width"),
        (", max_mover_height: -155", "tracks[0].max_mover_height"),
        (", max_mover_width: .nan", "tracks[0].max_mover_width"),
        (
            ", collision_range_mode: manual, collision_range_end: -1",
            "tracks[0].collision_range_end",
        ),
        (
            ", collision_range_mode: manual, collision_range_start: .inf",
            "tracks[0].collision_range_start",
        ),
        // A manual value without Manual mode would be silently ignored.
        (
            ", collision_range_end: 100",
            "tracks[0].collision_range_end",
        ),
    ] {
        let e = match PlanarEngine::new(switch(extra)) {
            Ok(_) => panic!("accepted: {extra}"),
            Err(e) => e,
        };
        assert_eq!(e.error_id, ErrorId::VALUE_OUT_OF_RANGE, "{extra}: {e}");
        assert!(e.message.contains(key), "{extra}: {e}");
    }
    assert!(serde_yaml::from_str::<PlanarConfig>(
        "tracks: [{name: T, collision_range_mode: semi}]"
    )
    .is_err());
}

fn set_params(
    track: &str,
    w: f64,
    mode: CollisionRangeMode,
    start: f64,
    end: f64,
) -> PlanarCommand {
    PlanarCommand::TrackSetInitParameters {
        track: track.into(),
        max_mover_width: w,
        max_mover_height: 155.0,
        check_static_collision: true,
        collision_range_mode: mode,
        collision_range_start: start,
        collision_range_end: end,
    }
}

/// TrackSetInitParameters sets the same parameters as the launch config while the track is
/// Disabled; the switch ranges follow at once.
#[test]
fn init_parameters_by_command_while_disabled() {
    let mut s = Sim::new(switch(""));
    let auto = track(&s, "T1").collision_range_end;
    s.ok(set_params(
        "T1",
        300.0,
        CollisionRangeMode::Manual,
        0.0,
        420.0,
    ));
    s.step();
    let t = track(&s, "T1");
    assert_eq!((t.max_mover_width, t.max_mover_height), (300.0, 155.0));
    assert!(t.check_static_collision);
    assert_eq!(t.collision_range_mode, CollisionRangeMode::Manual);
    assert_eq!(
        (t.collision_range_start, t.collision_range_end),
        (0.0, 420.0)
    );
    // Back to Automatic: the range follows the wider mover (R = 171.7 → clearance 535.6).
    s.ok(set_params(
        "T1",
        300.0,
        CollisionRangeMode::Automatic,
        0.0,
        0.0,
    ));
    s.step();
    let r = track(&s, "T1").collision_range_end;
    assert!(r > auto + 100.0, "{r} vs {auto}");
    // Once enabled, the init parameters are fixed.
    enable_track(&mut s, "T1");
    let e = s.err(set_params(
        "T1",
        155.0,
        CollisionRangeMode::Automatic,
        0.0,
        0.0,
    ));
    assert_eq!(e.error_id, errors::E_INVALID_STATE, "{e}");
    assert_eq!(track(&s, "T1").max_mover_width, 300.0);
}

#[test]
fn bad_init_parameters_by_command_are_refused() {
    let mut s = Sim::new(switch(""));
    let before = track(&s, "T1");
    for (c, key) in [
        (
            set_params("T1", f64::NAN, CollisionRangeMode::Automatic, 0.0, 0.0),
            "max_mover_width",
        ),
        (
            set_params("T1", -1.0, CollisionRangeMode::Automatic, 0.0, 0.0),
            "max_mover_width",
        ),
        (
            set_params("T1", f64::INFINITY, CollisionRangeMode::Automatic, 0.0, 0.0),
            "max_mover_width",
        ),
        (
            set_params("T1", 155.0, CollisionRangeMode::Manual, -5.0, 0.0),
            "collision_range_start",
        ),
        (
            set_params("T1", 155.0, CollisionRangeMode::Manual, 0.0, f64::NAN),
            "collision_range_end",
        ),
        // A manual value in Automatic mode would be silently ignored.
        (
            set_params("T1", 155.0, CollisionRangeMode::Automatic, 0.0, 100.0),
            "collision_range_end",
        ),
    ] {
        let e = s.err(c);
        assert_eq!(e.error_id, ErrorId::VALUE_OUT_OF_RANGE, "{e}");
        assert!(e.message.contains(key), "{key}: {e}");
        assert!(e.message.contains("T1"), "{e}");
    }
    let e = s.err(set_params(
        "T9",
        155.0,
        CollisionRangeMode::Automatic,
        0.0,
        0.0,
    ));
    assert_eq!(e.error_id, ErrorId::UNKNOWN_OBJECT, "{e}");
    s.step();
    let after = track(&s, "T1");
    assert_eq!(
        (
            after.max_mover_width,
            after.check_static_collision,
            after.collision_range_end
        ),
        (
            before.max_mover_width,
            before.check_static_collision,
            before.collision_range_end
        )
    );
}
