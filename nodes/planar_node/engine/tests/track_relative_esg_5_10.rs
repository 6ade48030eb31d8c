//! §3.2 / §5.10 relative external set points on a track: StartExternalSetpointGeneration
//! (Relative) is admissible OnTrack (§2.3); the mover stays OnTrack and the user values are
//! added as offsets to the internally generated on-track set points, in parallel with
//! MoveOnTrack; the track position (arc length) and gap control use the internal set point;
//! Stop freezes the offsets (no jump); Absolute mode stays refused OnTrack.

mod common;
mod track_common;
use common::*;
use motion_core::CommandState;
use planar_engine::errors::*;
use planar_engine::*;
use track_common::*;

fn start(mover: &str, mode: ExternalSetpointMode) -> PlanarCommand {
    PlanarCommand::StartExternalSetpointGeneration {
        mover: mover.into(),
        options: ExternalSetpointGenerationOptions { mode },
    }
}

fn offset(mover: &str, y: f64, vy: f64, c: f64) -> PlanarCommand {
    PlanarCommand::SetExternalSetpoint {
        mover: mover.into(),
        set_position: MoverVector {
            y,
            c,
            ..Default::default()
        },
        set_velocity: MoverVector {
            y: vy,
            ..Default::default()
        },
        set_acceleration: MoverVector::default(),
    }
}

/// A straight track T (0,0)-(1000,0) with A joined at s = 100 (C follows the heading, 0°)
/// and B at s = 400.
fn setup() -> Sim {
    let mut s = Sim::new(cfg(&[("A", 100.0, 0.0), ("B", 400.0, 0.0)], &["T"]));
    s.ok(line("T", (0.0, 0.0), (1000.0, 0.0)));
    enable_track(&mut s, "T");
    s.enable("A");
    s.enable("B");
    join_wait(&mut s, "A", "T", true);
    join_wait(&mut s, "B", "T", true);
    s
}

#[test]
fn offsets_ride_on_top_of_the_on_track_set_points() {
    let mut s = setup();
    // Absolute ESG is refused OnTrack (§2.3).
    let e = s.err(start("A", ExternalSetpointMode::Absolute));
    assert_eq!(e.error_id, E_INVALID_COMMAND_MODE, "{e}");
    let session = s.ok(start("A", ExternalSetpointMode::Relative));
    let mv = s.ok(mot("A", "", 150.0));
    // 100 cycles: y offset ramps 0.05 mm per cycle (50 mm/s), c offset 0.01° per cycle.
    for k in 1..=100 {
        let y = 0.05 * k as f64;
        s.ok(offset("A", y, 50.0, 0.01 * k as f64));
        s.step();
        let m = s.mover("A");
        let o = m.on_track.as_ref().expect("still on the track");
        assert_eq!(
            m.command_mode,
            CommandMode::OnTrack,
            "relative mode keeps OnTrack"
        );
        // Internal on-track set point + offset.
        assert!(close(m.set_pos.x, o.set_pos, 1e-9), "{m:?}");
        assert!(close(m.set_pos.y, y, 1e-9), "{m:?}");
        assert!(close(m.set_pos.c, 0.01 * k as f64, 1e-9), "{m:?}");
        assert!(close(m.set_velo.x, o.set_velo, 1e-9));
        assert!(close(m.set_velo.y, 50.0, 1e-9));
    }
    // Stop: the offsets stay at their last values (no jump), velocity offsets end.
    let stop = s.ok(PlanarCommand::StopExternalSetpointGeneration { mover: "A".into() });
    assert_eq!(s.wait_final(stop, 1.0), CommandState::Done);
    assert_eq!(s.state(session), Some(CommandState::Ended));
    assert_eq!(s.wait_final(mv, 5.0), CommandState::Done);
    let m = s.mover("A");
    let o = m.on_track.as_ref().unwrap();
    assert!(close(o.set_pos, 150.0, POS_TOL));
    assert!(close(m.set_pos.x, 150.0, POS_TOL));
    assert!(close(m.set_pos.y, 5.0, 1e-9), "frozen offset: {m:?}");
    assert!(close(m.set_pos.c, 1.0, 1e-9), "frozen offset: {m:?}");
    assert_eq!(m.set_velo.y, 0.0);
    // A further Stop is refused: no ESG active.
    let e = s.err(PlanarCommand::StopExternalSetpointGeneration { mover: "A".into() });
    assert_eq!(e.error_id, E_INVALID_COMMAND_MODE, "{e}");
}

#[test]
fn gap_control_uses_the_internal_track_position() {
    // B stands at s = 400; A, with a relative x offset of 30 mm ahead, is sent to 390: gap
    // control on the internal arc length holds A at 400 − 200 = 200 (the offset does not
    // count), the displayed x is 230.
    let mut s = setup();
    s.ok(start("A", ExternalSetpointMode::Relative));
    let hold = |s: &mut Sim| {
        s.ok(PlanarCommand::SetExternalSetpoint {
            mover: "A".into(),
            set_position: MoverVector {
                x: 30.0,
                ..Default::default()
            },
            set_velocity: MoverVector::default(),
            set_acceleration: MoverVector::default(),
        });
    };
    hold(&mut s);
    let mv = s.ok(mot("A", "", 390.0));
    for _ in 0..3000 {
        hold(&mut s);
        s.step();
        let o = on_track(&s, "A");
        assert!(o.set_pos <= 200.0 + 1e-6, "gap: {o:?}");
        if o.waiting && o.set_velo == 0.0 {
            break;
        }
    }
    let o = on_track(&s, "A");
    assert!(o.waiting, "{o:?}");
    assert!(close(o.set_pos, 200.0, POS_TOL), "{o:?}");
    assert!(close(s.mover("A").set_pos.x, 230.0, POS_TOL));
    assert_eq!(s.state(mv), Some(CommandState::Active));
    // A set point missing for longer than the timeout ends the session with its error; the
    // mover stops on the track (offsets frozen).
    s.steps(50);
    let m = s.mover("A");
    assert_eq!(m.error_id, E_EXT_SETPOINT_MISSING, "{m:?}");
}
