//! W9 – CRotationOnTrack (manual 6.2.6) and W10 – AdoptTrackOrientation (manual 6.2.7).
//! Geometry of W7: A (0,0), B (240,0), T (0,0)–(400,0).

mod common;
mod track_common;
use common::*;
use motion_core::CommandState;
use planar_engine::errors::*;
use planar_engine::*;
use track_common::*;

fn setup(use_orientation: bool) -> Sim {
    let mut s = Sim::new(cfg(&[("A", 0.0, 0.0), ("B", 240.0, 0.0)], &["T"]));
    s.ok(line("T", (0.0, 0.0), (400.0, 0.0)));
    enable_track(&mut s, "T");
    s.enable("A");
    s.enable("B");
    join_wait(&mut s, "A", "T", use_orientation);
    join_wait(&mut s, "B", "T", use_orientation);
    s
}

/// W9: joined with useOrientation FALSE; A.MoveC(20), B.MoveC(90): both CRotationOnTrack while
/// rotating; afterwards A stays CRotationOnTrack (20° outside the windows), B back OnTrack.
#[test]
fn w09_crotation_on_track() {
    let mut s = setup(false);
    assert_eq!(s.mover("A").c_coordinate_mode, CCoordinateMode::Independent);
    let a = s.ok(move_c("A", 20.0));
    let b = s.ok(move_c("B", 90.0));
    s.step();
    assert_eq!(s.mover("A").command_mode, CommandMode::CRotationOnTrack);
    assert_eq!(s.mover("B").command_mode, CommandMode::CRotationOnTrack);
    assert_eq!(s.wait_final(a, 5.0), CommandState::Done);
    assert_eq!(s.wait_final(b, 5.0), CommandState::Done);
    s.step();
    let (ma, mb) = (s.mover("A"), s.mover("B"));
    assert!(close(ma.set_pos.c, 20.0, ANG_TOL) && close(mb.set_pos.c, 90.0, ANG_TOL));
    assert_eq!(ma.command_mode, CommandMode::CRotationOnTrack);
    assert_eq!(mb.command_mode, CommandMode::OnTrack);
    // A accepts only C (and Z/A/B/Halt): MoveOnTrack and LeaveTrack are refused.
    assert_eq!(s.err(mot("A", "", 100.0)).error_id, E_INVALID_COMMAND_MODE);
    let leave = |m: &str| PlanarCommand::LeaveTrack {
        mover: m.into(),
        target_position: p(0.0, 300.0),
        constraint: DynamicConstraint::default(),
        options: MoveToPositionOptions::default(),
    };
    assert_eq!(s.err(leave("A")).error_id, E_INVALID_COMMAND_MODE);
    let z = s.ok(PlanarCommand::MoveZ {
        mover: "A".into(),
        target_position: 2.0,
        constraint: DynamicConstraint::default(),
    });
    assert_eq!(s.wait_final(z, 5.0), CommandState::Done);
    // B may move on the track.
    let id = s.ok(mot("B", "", 380.0));
    assert_eq!(s.wait_final(id, 5.0), CommandState::Done);
    assert!(close(on_track(&s, "B").set_pos, 380.0, POS_TOL));
    assert!(
        close(s.mover("B").set_pos.c, 90.0, ANG_TOL),
        "independent C stays"
    );
}

/// W10: joined with useOrientation TRUE (C dependent, c = 0); MoveC(20) / MoveC(190) make C
/// independent (A CRotationOnTrack, B OnTrack); AdoptTrackOrientation (ShortestWay) brings
/// both back: OnTrack, dependent, A c = 0, B c = 360.
#[test]
fn w10_adopt_track_orientation() {
    let mut s = setup(true);
    assert_eq!(s.mover("A").c_coordinate_mode, CCoordinateMode::Dependent);
    assert!(close(s.mover("A").set_pos.c, 0.0, ANG_TOL));
    let a = s.ok(move_c("A", 20.0));
    let b = s.ok(move_c("B", 190.0));
    assert_eq!(s.wait_final(a, 5.0), CommandState::Done);
    assert_eq!(s.wait_final(b, 5.0), CommandState::Done);
    s.step();
    let (ma, mb) = (s.mover("A"), s.mover("B"));
    assert!(ma.set_pos.c >= 19.9 && mb.set_pos.c >= 189.9 && !ma.busy.busy_mover);
    assert_eq!(ma.c_coordinate_mode, CCoordinateMode::Independent);
    assert_eq!(mb.c_coordinate_mode, CCoordinateMode::Independent);
    assert_eq!(ma.command_mode, CommandMode::CRotationOnTrack);
    assert_eq!(mb.command_mode, CommandMode::OnTrack, "190 ∈ [165, 195]");
    let adopt = |m: &str| PlanarCommand::AdoptTrackOrientation {
        mover: m.into(),
        constraint: DynamicConstraint::default(),
        options: AdoptTrackOrientationOptions::default(),
    };
    let a = s.ok(adopt("A"));
    let b = s.ok(adopt("B"));
    s.step();
    assert_eq!(
        s.mover("B").command_mode,
        CommandMode::CRotationOnTrack,
        "190 → 360 passes outside the windows (§5.3)"
    );
    assert_eq!(s.wait_final(a, 5.0), CommandState::Done);
    assert_eq!(s.wait_final(b, 5.0), CommandState::Done);
    s.step();
    let (ma, mb) = (s.mover("A"), s.mover("B"));
    assert_eq!(ma.command_mode, CommandMode::OnTrack);
    assert_eq!(mb.command_mode, CommandMode::OnTrack);
    assert_eq!(ma.c_coordinate_mode, CCoordinateMode::Dependent);
    assert_eq!(mb.c_coordinate_mode, CCoordinateMode::Dependent);
    assert!(close(ma.set_pos.c, 0.0, ANG_TOL), "A c {}", ma.set_pos.c);
    assert!(close(mb.set_pos.c, 360.0, ANG_TOL), "B c {}", mb.set_pos.c);
    // AdoptTrackOrientation is not a FreeMovement command.
    let id = s.ok(PlanarCommand::LeaveTrack {
        mover: "A".into(),
        target_position: p(0.0, -300.0),
        constraint: DynamicConstraint::default(),
        options: MoveToPositionOptions::default(),
    });
    assert_eq!(s.wait_final(id, 5.0), CommandState::Done);
    s.step();
    assert_eq!(s.err(adopt("A")).error_id, E_INVALID_COMMAND_MODE);
}

/// §5.9: dependent C follows the heading along a curved track.
#[test]
fn dependent_c_follows_the_heading() {
    let mut s = Sim::new(cfg(&[("M", 0.0, 0.0)], &["T"]));
    s.ok(line("T", (0.0, 0.0), (300.0, 0.0)));
    s.ok(line("T", (500.0, 200.0), (500.0, 600.0)));
    enable_track(&mut s, "T");
    s.enable("M");
    join_wait(&mut s, "M", "T", true);
    let len = track(&s, "T").length;
    let id = s.ok(mot("M", "", len));
    let mut n = 0;
    while s.state(id) != Some(CommandState::Done) {
        s.step();
        let o = on_track(&s, "M");
        let q = position_at(&mut s, "T", o.set_pos);
        let m = s.mover("M");
        assert!(
            close(m.set_pos.c, q.c, 1e-9),
            "c {} heading {}",
            m.set_pos.c,
            q.c
        );
        assert!(close(m.set_pos.x, q.x, 1e-9) && close(m.set_pos.y, q.y, 1e-9));
        n += 1;
        assert!(n < 5000);
    }
    assert!(close(s.mover("M").set_pos.c, 90.0, ANG_TOL));
    assert_pos(&s.mover("M"), 500.0, 600.0);
}
