//! W7 – Join a track and move (manual 6.2.4, xplanar.md §7).
//! Movers A (0,0), B (240,0); track T (0,0)–(400,0), length 400, Standing after Enable.
//! Both join in one cycle (T Configuring), A at s = 0, B at s = 240; then A → 150, B → 350 in
//! one cycle: s_B − s_A ≥ 200 throughout, T Moving during, Standing after.

mod common;
mod track_common;
use common::*;
use motion_core::CommandState;
use planar_engine::errors::*;
use planar_engine::*;
use track_common::*;

fn setup() -> Sim {
    let mut s = Sim::new(cfg(&[("A", 0.0, 0.0), ("B", 240.0, 0.0)], &["T"]));
    s.ok(line("T", (0.0, 0.0), (400.0, 0.0)));
    assert_eq!(
        track(&s, "T").operation_mode,
        TrackOperationMode::Uninitialized
    );
    enable_track(&mut s, "T");
    let t = track(&s, "T");
    assert_eq!(t.state, PlanarState::Enabled);
    assert_eq!(t.operation_mode, TrackOperationMode::Standing);
    assert_eq!(t.length, 400.0);
    assert_eq!(length(&mut s, "T"), 400.0);
    s.enable("A");
    s.enable("B");
    s
}

#[test]
fn w07_join_and_move() {
    let mut s = setup();
    let ja = s.ok(join("A", "T", true));
    let jb = s.ok(join("B", "T", true));
    // Both joins are one-cycle approaches here; the mode is visible at once.
    assert_eq!(
        track(&s, "T").operation_mode,
        TrackOperationMode::Configuring,
        "T Configuring while joining"
    );
    assert_eq!(s.wait_final(ja, 5.0), CommandState::Done);
    assert_eq!(s.wait_final(jb, 5.0), CommandState::Done);
    s.step();
    assert_eq!(s.mover("A").command_mode, CommandMode::OnTrack);
    assert_eq!(s.mover("B").command_mode, CommandMode::OnTrack);
    assert!(close(on_track(&s, "A").set_pos, 0.0, POS_TOL));
    assert!(close(on_track(&s, "B").set_pos, 240.0, POS_TOL));
    assert_eq!(track(&s, "T").operation_mode, TrackOperationMode::Standing);
    assert_eq!(track(&s, "T").movers, vec!["A", "B"]);

    let ma = s.ok(mot("A", "", 150.0));
    let mb = s.ok(mot("B", "", 350.0));
    s.step();
    assert_eq!(track(&s, "T").operation_mode, TrackOperationMode::Moving);
    let mut n = 0;
    while !(s.state(ma) == Some(CommandState::Done) && s.state(mb) == Some(CommandState::Done)) {
        let d = on_track(&s, "B").set_pos - on_track(&s, "A").set_pos;
        assert!(d >= 200.0 - 1e-6, "gap violated: s_B - s_A = {d}");
        s.step();
        n += 1;
        assert!(n < 10_000, "W7 motion did not finish");
    }
    assert!(close(on_track(&s, "A").set_pos, 150.0, POS_TOL));
    assert!(close(on_track(&s, "B").set_pos, 350.0, POS_TOL));
    assert_pos(&s.mover("A"), 150.0, 0.0);
    assert_pos(&s.mover("B"), 350.0, 0.0);
    s.step();
    assert_eq!(track(&s, "T").operation_mode, TrackOperationMode::Standing);
}

/// §2.5 gating: Moving rejects JoinTrack/LeaveTrack, Configuring rejects MoveOnTrack.
#[test]
fn w07_operation_mode_gating() {
    let mut s = setup();
    let ja = s.ok(join("A", "T", true));
    assert_eq!(s.wait_final(ja, 5.0), CommandState::Done);
    s.step();
    s.ok(mot("A", "", 100.0));
    s.step();
    let e = s.err(join("B", "T", true));
    assert_eq!(e.error_id, E_TRACK_MODE_CONFLICT, "JoinTrack while Moving");
    let e = s.err(PlanarCommand::LeaveTrack {
        mover: "A".into(),
        target_position: p(0.0, 300.0),
        constraint: DynamicConstraint::default(),
        options: MoveToPositionOptions::default(),
    });
    assert_eq!(e.error_id, E_TRACK_MODE_CONFLICT, "LeaveTrack while Moving");
    s.run_until(5.0, |sn| {
        sn.track("T").unwrap().operation_mode == TrackOperationMode::Standing
    });
    // B joins: T Configuring, A's MoveOnTrack is rejected.
    s.ok(join("B", "T", true));
    assert_eq!(
        track(&s, "T").operation_mode,
        TrackOperationMode::Configuring
    );
    let e = s.err(mot("A", "", 0.0));
    assert_eq!(
        e.error_id, E_TRACK_MODE_CONFLICT,
        "MoveOnTrack while Configuring"
    );
}

/// LeaveTrack: the track is left at the start; Done at the free target → FreeMovement.
#[test]
fn w07_leave_track() {
    let mut s = setup();
    join_wait(&mut s, "A", "T", true);
    let id = s.ok(PlanarCommand::LeaveTrack {
        mover: "A".into(),
        target_position: p(0.0, 300.0),
        constraint: DynamicConstraint::default(),
        options: MoveToPositionOptions::default(),
    });
    s.step();
    let m = s.mover("A");
    assert_eq!(m.command_mode, CommandMode::LeavingTrack);
    assert!(m.on_track.is_none(), "left at the start of the motion");
    assert_eq!(track(&s, "T").mover_count, 0);
    assert_eq!(
        track(&s, "T").operation_mode,
        TrackOperationMode::Configuring
    );
    // LeavingTrack accepts no further commands.
    assert_eq!(
        s.err(mtp("A", 0.0, 0.0, 0.0)).error_id,
        E_INVALID_COMMAND_MODE
    );
    assert_eq!(s.wait_final(id, 5.0), CommandState::Done);
    s.step();
    let m = s.mover("A");
    assert_eq!(m.command_mode, CommandMode::FreeMovement);
    assert_pos(&m, 0.0, 300.0);
    assert_eq!(m.c_coordinate_mode, CCoordinateMode::Independent);
    assert_eq!(track(&s, "T").operation_mode, TrackOperationMode::Standing);
}
