//! W18 — MC_Halt/MC_Stop never weaker than the active command (§8, §4.8.9, §4.8.10).
mod common;
use axis_engine::*;
use common::*;

fn velocity_100(r: &mut Rig) {
    r.id(AxisCommand::MoveVelocity(MoveVelocity {
        deceleration: 1000.0,
        jerk: 1e5,
        ..move_vel(100.0, Direction::Positive)
    }));
    r.steps(200);
    assert!((r.st().set_velo - 100.0).abs() < 1e-9 && r.st().set_acc == 0.0);
}

#[test]
fn stop_with_weaker_deceleration_uses_the_active_one() {
    for (dec, jerk) in [(500.0, 1e5), (0.0, 0.0), (-1.0, -1.0)] {
        let mut r = Rig::powered();
        velocity_100(&mut r);
        let p0 = r.st().set_pos;
        let s = r.id(stop(dec, jerk));
        r.until(5000, |r| r.out(s).done);
        let d = r.st().set_pos - p0;
        assert!((d - 5.5).abs() < 1e-6, "dec {dec}: stopping distance {d}");
    }
}

#[test]
fn halt_with_weaker_deceleration_uses_the_active_one() {
    let mut r = Rig::powered();
    velocity_100(&mut r);
    let p0 = r.st().set_pos;
    let h = r.id(halt(500.0, 1e5, BufferMode::Aborting));
    r.until(5000, |r| r.out(h).done);
    assert!((r.st().set_pos - p0 - 5.5).abs() < 1e-6);
    assert_eq!(r.st().motion_state, MotionState::Standstill);
}

#[test]
fn stronger_deceleration_is_used() {
    let mut r = Rig::powered();
    velocity_100(&mut r);
    let p0 = r.st().set_pos;
    let h = r.id(halt(2000.0, 1e5, BufferMode::Aborting));
    r.until(5000, |r| r.out(h).done);
    // 100²/4000 + 100·2000/2e5 = 3.5
    assert!((r.st().set_pos - p0 - 3.5).abs() < 1e-6);
}
