//! §3.3 track methods, §5.4 geometry rules and the bad requests of tracks and on-track mover
//! commands (§6.2 ids; shell-level ids for unknown names and non-finite values).

mod common;
mod track_common;
use common::*;
use motion_core::{CommandState, ErrorId};
use planar_engine::errors::*;
use planar_engine::*;
use track_common::*;

fn sim() -> Sim {
    Sim::new(cfg(&[("A", 0.0, 0.0), ("B", 0.0, 400.0)], &["T", "U"]))
}

#[test]
fn geometry_rules() {
    let mut s = sim();
    assert_eq!(length(&mut s, "T"), 0.0, "empty track");
    let e = s.err(PlanarCommand::TrackEnable { track: "T".into() });
    assert_eq!(e.error_id, E_GEOMETRY_INVALID, "Enable without geometry");
    assert_eq!(
        s.err(line("T", (0.0, 0.0), (0.0, 0.0))).error_id,
        E_GEOMETRY_INVALID
    );
    s.ok(line("T", (0.0, 0.0), (100.0, 0.0)));
    // Same point, same heading, curvature 0: continuous.
    s.ok(line("T", (100.0, 0.0), (200.0, 0.0)));
    assert_eq!(length(&mut s, "T"), 200.0);
    // Same point, other heading: not C².
    assert_eq!(
        s.err(line("T", (200.0, 0.0), (200.0, 100.0))).error_id,
        E_GEOMETRY_INVALID
    );
    // A tangent circle at the same point has curvature 1/r ≠ 0: not C².
    let circle =
        |a: (f64, f64), b: (f64, f64), c: (f64, f64), cw| PlanarCommand::TrackAppendCircle {
            track: "T".into(),
            start: p(a.0, a.1),
            end: p(b.0, b.1),
            center: p(c.0, c.1),
            clockwise: cw,
        };
    assert_eq!(
        s.err(circle((200.0, 0.0), (300.0, 100.0), (200.0, 100.0), false))
            .error_id,
        E_GEOMETRY_INVALID
    );
    // Radius mismatch and radius 0.
    assert_eq!(
        s.err(circle((300.0, 0.0), (400.0, 150.0), (300.0, 100.0), false))
            .error_id,
        E_GEOMETRY_INVALID
    );
    assert_eq!(
        s.err(circle((300.0, 0.0), (300.0, 0.0), (300.0, 0.0), false))
            .error_id,
        E_GEOMETRY_INVALID
    );
    // A circle with a gap before it: a transition is generated, the arc is exact.
    let before = length(&mut s, "T");
    s.ok(circle(
        (400.0, 100.0),
        (500.0, 200.0),
        (400.0, 200.0),
        false,
    ));
    let after = length(&mut s, "T");
    let arc = 100.0 * std::f64::consts::FRAC_PI_2;
    assert!(after - before > arc + 200.0f64.hypot(100.0) * 0.95 - 100.0);
    let q = position_at(&mut s, "T", after);
    assert!(close(q.x, 500.0, 1e-9) && close(q.y, 200.0, 1e-9) && close(q.c, 90.0, 1e-9));
    // Non-finite and unknown.
    assert_eq!(
        s.err(line("T", (f64::NAN, 0.0), (1.0, 0.0))).error_id,
        ErrorId::NOT_FINITE
    );
    assert_eq!(
        s.err(line("nope", (0.0, 0.0), (1.0, 0.0))).error_id,
        ErrorId::UNKNOWN_OBJECT
    );
    // Enabled: no geometry changes.
    enable_track(&mut s, "T");
    assert_eq!(
        s.err(line("T", (900.0, 0.0), (950.0, 0.0))).error_id,
        E_INVALID_STATE
    );
    assert_eq!(
        s.err(PlanarCommand::TrackClear { track: "T".into() })
            .error_id,
        E_INVALID_STATE
    );
}

#[test]
fn append_position_sets_start_and_heading() {
    let mut s = sim();
    let ap = |x, y, c| PlanarCommand::TrackAppendPosition {
        track: "T".into(),
        position: PositionXYC::new(x, y, c),
    };
    s.ok(ap(0.0, 0.0, 0.0));
    assert_eq!(length(&mut s, "T"), 0.0);
    s.ok(ap(400.0, 0.0, 0.0));
    assert_eq!(
        length(&mut s, "T"),
        400.0,
        "collinear transition = exact line"
    );
    s.ok(ap(600.0, 200.0, 90.0));
    let l = length(&mut s, "T");
    let q = position_at(&mut s, "T", l);
    assert!(close(q.x, 600.0, 1e-9) && close(q.y, 200.0, 1e-9) && close(q.c, 90.0, 1e-9));
    // A reversing transition is refused (§5.4).
    assert_eq!(s.err(ap(600.0, 100.0, 90.0)).error_id, E_GEOMETRY_INVALID);
}

#[test]
fn queries() {
    let mut s = sim();
    s.ok(line("T", (0.0, 0.0), (400.0, 0.0)));
    let closest = |s: &mut Sim, t: &str, x: f64, y: f64| match s
        .cmd(PlanarCommand::TrackGetArcLengthClosestTo {
            track: t.into(),
            point: p(x, y),
        })
        .unwrap()
        .value
    {
        ReplyValue::Scalar(v) => v,
        v => panic!("{v:?}"),
    };
    assert!(close(closest(&mut s, "T", 123.0, 50.0), 123.0, 1e-9));
    assert!(close(closest(&mut s, "T", -50.0, 10.0), 0.0, 1e-9));
    assert!(close(closest(&mut s, "T", 999.0, -10.0), 400.0, 1e-9));
    assert_eq!(
        s.err(PlanarCommand::TrackGetPositionAt {
            track: "T".into(),
            arc_length: 400.5
        })
        .error_id,
        E_INVALID_PARAMETER,
        "open track outside [0, L]"
    );
    // Closed loop: every point of the circle is equally close to the centre → smallest s;
    // GetPositionAt wraps modulo L.
    let r = 200.0;
    s.ok(PlanarCommand::TrackAppendCircle {
        track: "U".into(),
        start: p(r, 0.0),
        end: p(r, 0.0),
        center: p(0.0, 0.0),
        clockwise: false,
    });
    s.ok(PlanarCommand::TrackCloseLoop { track: "U".into() });
    assert_eq!(closest(&mut s, "U", 0.0, 0.0), 0.0);
    let l = length(&mut s, "U");
    let a = position_at(&mut s, "U", l / 4.0);
    let b = position_at(&mut s, "U", l / 4.0 + 3.0 * l);
    assert!(close(a.x, b.x, 1e-9) && close(a.y, b.y, 1e-9));
    assert!(close(a.x, 0.0, 1e-9) && close(a.y, r, 1e-9) && close(a.c, 180.0, 1e-9));
    match s
        .cmd(PlanarCommand::TrackGetPlanarObjectInfo { track: "U".into() })
        .unwrap()
        .value
    {
        ReplyValue::ObjectInfo(i) => assert_eq!(i.object_type, PlanarObjectType::Track),
        v => panic!("{v:?}"),
    }
}

#[test]
fn bad_on_track_requests() {
    let mut s = sim();
    s.ok(line("T", (0.0, 0.0), (400.0, 0.0)));
    s.enable("A");
    s.enable("B");
    assert_eq!(
        s.err(join("A", "T", true)).error_id,
        E_TRACK_NOT_READY,
        "Uninitialized"
    );
    assert_eq!(
        s.err(join("A", "nope", true)).error_id,
        ErrorId::UNKNOWN_OBJECT
    );
    assert_eq!(
        s.err(mot("A", "", 10.0)).error_id,
        E_INVALID_COMMAND_MODE,
        "not on a track"
    );
    enable_track(&mut s, "T");
    join_wait(&mut s, "A", "T", true);
    assert_eq!(s.err(mot("A", "", 401.0)).error_id, E_TARGET_UNREACHABLE);
    assert_eq!(s.err(mot("A", "", -1.0)).error_id, E_TARGET_UNREACHABLE);
    let id = s.ok(mot("A", "", 200.0));
    assert_eq!(s.wait_final(id, 5.0), CommandState::Done);
    let pos = |d| dir_opt(d, 0, 0.0);
    assert_eq!(
        s.err(mot_opt("A", "", 100.0, pos(Direction::Positive)))
            .error_id,
        E_TARGET_UNREACHABLE,
        "Positive only forward"
    );
    assert_eq!(
        s.err(mot_opt("A", "", 300.0, pos(Direction::Negative)))
            .error_id,
        E_TARGET_UNREACHABLE,
        "Negative only backward"
    );
    assert_eq!(
        s.err(mot_opt(
            "A",
            "",
            300.0,
            dir_opt(Direction::Positive, 1, 0.0)
        ))
        .error_id,
        E_INVALID_PARAMETER,
        "additional turns on an open track"
    );
    let c = DynamicConstraint {
        velocity: -1.0,
        ..Default::default()
    };
    let e = s.err(PlanarCommand::MoveOnTrack {
        mover: "A".into(),
        track: String::new(),
        target_position: 300.0,
        constraint: c,
        options: MoveOnTrackOptions::default(),
    });
    assert_eq!(e.error_id, E_INVALID_PARAMETER);
    // Above the maximum dynamics: reduced with a warning (§5.1).
    let r = s
        .cmd(PlanarCommand::MoveOnTrack {
            mover: "A".into(),
            track: String::new(),
            target_position: 300.0,
            constraint: DynamicConstraint {
                velocity: 1e9,
                ..Default::default()
            },
            options: MoveOnTrackOptions::default(),
        })
        .unwrap();
    assert_eq!(r.warning_id, W_DYNAMICS_REDUCED);
    assert_eq!(s.wait_final(r.id, 5.0), CommandState::Done);
    // JoinTrack onto a mover already on the track: the footprints would overlap.
    let id = s.ok(mtp("B", 300.0, 160.0, 0.0));
    assert_eq!(s.wait_final(id, 5.0), CommandState::Done);
    let e = s.err(join("B", "T", true));
    assert_eq!(e.error_id, E_COLLISION);
    assert_eq!(
        s.eng.last_object_info().object_type,
        PlanarObjectType::Mover
    );
    // Track Disable with a mover on it.
    assert_eq!(
        s.err(PlanarCommand::TrackDisable { track: "T".into() })
            .error_id,
        E_INVALID_STATE
    );
}

/// Halt on a track stops along the track (§3.2); Disable detaches the mover (§2.1); a QuickStop
/// error stops along the track as well.
#[test]
fn halt_disable_and_errors_on_a_track() {
    let mut s = sim();
    s.ok(line("T", (0.0, 0.0), (300.0, 0.0)));
    s.ok(line("T", (500.0, 200.0), (500.0, 2000.0)));
    enable_track(&mut s, "T");
    s.enable("A");
    join_wait(&mut s, "A", "T", true);
    let id = s.ok(mot("A", "", 1500.0));
    s.steps(700);
    let h = s.ok(PlanarCommand::Halt {
        mover: "A".into(),
        constraint: DynamicConstraint::default(),
    });
    assert_eq!(s.wait_final(h, 5.0), CommandState::Done);
    assert_eq!(s.state(id), Some(CommandState::Aborted));
    let o = on_track(&s, "A");
    let q = position_at(&mut s, "T", o.set_pos);
    assert_pos(&s.mover("A"), q.x, q.y);
    assert_eq!(s.mover("A").command_mode, CommandMode::OnTrack);
    assert_eq!(o.set_velo, 0.0);
    // QuickStop error while moving: stops on the track.
    let id = s.ok(mot("A", "", 1500.0));
    s.steps(300);
    s.ok(PlanarCommand::InjectError {
        kind: ObjectKind::Mover,
        name: "A".into(),
        reaction: ErrorReaction::QuickStop,
    });
    s.run_until(5.0, |sn| sn.mover("A").unwrap().state == PlanarState::Error);
    assert!(matches!(s.state(id), Some(CommandState::Error(_))));
    let o = on_track(&s, "A");
    let q = position_at(&mut s, "T", o.set_pos);
    assert_pos(&s.mover("A"), q.x, q.y);
    // Reset (QuickStop → Enabled, still on the track), then Disable: detached (§2.1).
    let r = s.ok(PlanarCommand::MoverReset { mover: "A".into() });
    assert_eq!(s.wait_final(r, 5.0), CommandState::Done);
    assert_eq!(s.mover("A").command_mode, CommandMode::OnTrack);
    let d = s.ok(PlanarCommand::MoverDisable { mover: "A".into() });
    assert_eq!(s.wait_final(d, 5.0), CommandState::Done);
    assert!(s.mover("A").on_track.is_none());
    assert_eq!(track(&s, "T").mover_count, 0);
}

/// §5.6.3: the leader stops hard (Halt with its maximum dynamics) in front of a close
/// follower: the follower brakes jerk-limited with its own limits, the gap holds, and its
/// command waits (Active) and resumes when the leader moves on.
#[test]
fn leader_stops_hard() {
    let mut s = Sim::new(cfg(&[("A", 0.0, 0.0), ("B", 250.0, 0.0)], &["T"]));
    s.ok(line("T", (0.0, 0.0), (6000.0, 0.0)));
    enable_track(&mut s, "T");
    s.enable("A");
    s.enable("B");
    join_wait(&mut s, "A", "T", true);
    join_wait(&mut s, "B", "T", true);
    let fa = s.ok(mot("A", "", 5000.0));
    let fb = s.ok(mot("B", "", 5800.0));
    s.steps(1500);
    let hard = DynamicConstraint {
        deceleration: 30000.0,
        jerk: 1_000_000.0,
        ..Default::default()
    };
    s.ok(PlanarCommand::Halt {
        mover: "B".into(),
        constraint: hard,
    });
    let mut prev_acc = 0.0;
    for _ in 0..2000 {
        s.step();
        let (a, b) = (on_track(&s, "A"), on_track(&s, "B"));
        assert!(
            b.set_pos - a.set_pos >= 200.0 - 1e-6,
            "gap {}",
            b.set_pos - a.set_pos
        );
        assert!(
            a.set_acc.abs() <= 10000.0 + 1e-6,
            "A within its own deceleration"
        );
        assert!(
            (a.set_acc - prev_acc).abs() <= 100000.0 * 0.001 + 1e-6,
            "A jerk-limited"
        );
        prev_acc = a.set_acc;
    }
    assert_eq!(
        s.state(fa),
        Some(CommandState::Active),
        "A waits, neither Done nor Error"
    );
    assert!(on_track(&s, "A").waiting);
    let d = on_track(&s, "B").set_pos - on_track(&s, "A").set_pos;
    assert!(
        close(d, 200.0, POS_TOL),
        "A waits at the gap boundary, distance {d}"
    );
    assert_eq!(s.state(fb), Some(CommandState::Aborted));
    // B moves on: A resumes and arrives.
    s.ok(mot("B", "", 5800.0));
    assert_eq!(s.wait_final(fa, 20.0), CommandState::Done);
    assert!(close(on_track(&s, "A").set_pos, 5000.0, POS_TOL));
}

/// Extreme but finite requests are answered (accepted or rejected with an id), never panic,
/// and never put non-finite values into the state.
#[test]
fn extreme_values_never_panic() {
    let mut s = Sim::new(cfg(&[("A", 100.0, 0.0)], &["L", "T"]));
    circle_loop_named(&mut s, "L", 100.0);
    s.ok(line("T", (0.0, 500.0), (400.0, 500.0)));
    enable_track(&mut s, "T");
    s.enable("A");
    join_wait(&mut s, "A", "L", true);
    for (target, dir, turns, tol, gap) in [
        (1e300, Direction::NonModulo, 0, 0.0, 200.0),
        (-1e300, Direction::NonModulo, 0, 0.0, 200.0),
        (1e18, Direction::Positive, u32::MAX, 0.0, 200.0),
        (5.0, Direction::Negative, 3, 1e300, 200.0),
        (5.0, Direction::ShortestWay, 0, 0.0, 1e300),
        (f64::MAX, Direction::Positive, 0, 0.0, 0.0),
    ] {
        let _ = s.cmd(mot_opt(
            "A",
            "",
            target,
            MoveOnTrackOptions {
                gap,
                direction: dir,
                additional_turns: turns,
                modulo_tolerance: tol,
            },
        ));
        s.steps(20);
        let m = s.mover("A");
        assert!(m.set_pos.x.is_finite() && m.set_pos.y.is_finite() && m.set_pos.c.is_finite());
    }
    for arc in [f64::MAX, -f64::MAX, 1e300] {
        let _ = s.cmd(PlanarCommand::TrackGetPositionAt {
            track: "L".into(),
            arc_length: arc,
        });
    }
    let _ = s.cmd(PlanarCommand::TrackGetArcLengthClosestTo {
        track: "L".into(),
        point: p(1e300, -1e300),
    });
    let _ = s.cmd(line("T", (1e300, 0.0), (-1e300, 0.0)));
    let _ = s.cmd(PlanarCommand::TrackAppendCircle {
        track: "T".into(),
        start: p(1e300, 0.0),
        end: p(1e300, 0.0),
        center: p(0.0, 0.0),
        clockwise: false,
    });
}
