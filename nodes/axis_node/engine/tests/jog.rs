//! MC_Jog (§4.11): standard, continuous and inching modes.
mod common;
use axis_engine::*;
use common::*;
use motion_core::Engine;

fn jog(fwd: bool, back: bool, mode: JogMode, position: f64, velocity: f64) -> AxisCommand {
    AxisCommand::Jog(Jog {
        axis: AX.into(),
        jog_forward: fwd,
        jog_backwards: back,
        mode,
        position,
        velocity,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
    })
}

#[test]
fn standard_modes_use_the_manual_velocities_until_released() {
    for (mode, v) in [
        (JogMode::StandardSlow, 100.0),
        (JogMode::StandardFast, 600.0),
    ] {
        let mut r = Rig::powered();
        let id = r.id(jog(true, false, mode, 0.0, 0.0));
        assert_eq!(r.st().motion_state, MotionState::ContinuousMotion);
        r.steps(1000);
        assert!((r.st().set_velo - v).abs() < 1e-9, "{mode:?}");
        assert!(r.out(id).busy && r.out(id).active);
        r.cmd(execute(id, false)).unwrap();
        r.until(5000, |r| r.out(id).done);
        assert_eq!(r.st().set_velo, 0.0);
        assert_eq!(r.st().motion_state, MotionState::Standstill);
    }
}

#[test]
fn continuous_mode_uses_the_inputs_and_backwards_goes_negative() {
    let mut r = Rig::powered();
    let id = r.id(jog(false, true, JogMode::Continous, 0.0, 42.0));
    r.steps(500);
    assert!((r.st().set_velo + 42.0).abs() < 1e-9);
    r.cmd(execute(id, false)).unwrap();
    r.until(5000, |r| r.out(id).done);
    // Forward wins when both are TRUE.
    let id = r.id(jog(true, true, JogMode::Continous, 0.0, 10.0));
    r.steps(200);
    assert!(r.st().set_velo > 0.0);
    let _ = id;
}

#[test]
fn inching_moves_one_step_per_edge_and_ignores_the_release() {
    let mut r = Rig::powered();
    r.set_pos(2.0);
    let id = r.id(jog(true, false, JogMode::Inching, 5.0, 50.0));
    assert_eq!(r.st().motion_state, MotionState::DiscreteMotion);
    r.cmd(execute(id, false)).unwrap();
    r.until(5000, |r| r.st().motion_state == MotionState::Standstill);
    assert_eq!(r.st().set_pos, 7.0);
    let id = r.id(jog(false, true, JogMode::Inching, 5.0, 50.0));
    r.until(5000, |r| r.out(id).done);
    assert_eq!(r.st().set_pos, 2.0);
}

#[test]
fn inching_modulo_snaps_to_multiples() {
    // Position 10: 12.3 → 20 forward, → 10 backward; 20 → 30 forward.
    for (start, fwd, want) in [(12.3, true, 20.0), (12.3, false, 10.0), (20.0, true, 30.0)] {
        let mut r = Rig::powered();
        r.set_pos(start);
        let id = r.id(jog(fwd, !fwd, JogMode::InchingModulo, 10.0, 50.0));
        r.until(5000, |r| r.out(id).done);
        assert!(
            (r.st().set_pos - want).abs() < 1e-9,
            "{start} {fwd}: {}",
            r.st().set_pos
        );
    }
}

#[test]
fn jog_aborts_a_running_command_and_bad_inputs_are_rejected() {
    let mut r = Rig::powered();
    let a = r.id(abs(1000.0, 100.0));
    r.steps(10);
    let j = r.id(jog(true, false, JogMode::StandardSlow, 0.0, 0.0));
    assert!(r.out(a).command_aborted && r.out(j).active);
    let mut r = Rig::powered();
    let before = r.st();
    assert_eq!(
        r.cmd(jog(true, false, JogMode::Inching, 0.0, 10.0))
            .unwrap_err()
            .error_id,
        err(0x4B06)
    );
    assert_eq!(
        r.cmd(jog(true, false, JogMode::Continous, 0.0, 0.0))
            .unwrap_err()
            .error_id,
        err(0x4B06)
    );
    assert_eq!(
        r.cmd(jog(false, false, JogMode::Continous, 0.0, 10.0))
            .unwrap_err()
            .error_id,
        motion_core::ErrorId::VALUE_OUT_OF_RANGE
    );
    assert_eq!(
        r.cmd(jog(true, false, JogMode::Inching, f64::NAN, 10.0))
            .unwrap_err()
            .error_id,
        motion_core::ErrorId::NOT_FINITE
    );
    assert_eq!(r.st(), before);
    r.power(false);
    assert_eq!(
        r.cmd(jog(true, false, JogMode::StandardSlow, 0.0, 0.0))
            .unwrap_err()
            .error_id,
        err(0x4B01)
    );
}

#[test]
fn stop_aborts_a_jog() {
    let mut r = Rig::powered();
    let j = r.id(jog(true, false, JogMode::StandardFast, 0.0, 0.0));
    r.steps(100);
    r.id(stop(0.0, 0.0));
    assert!(r.out(j).command_aborted);
}

/// The ROS layer's cancel of a jog goal is the button release: the axis brakes with the jog's
/// deceleration and the instance ends Done (a move's cancel is MC_Halt and ends Aborted).
#[test]
fn cancel_of_a_jog_releases_the_button() {
    let mut r = Rig::powered();
    let id = r.id(jog(true, false, JogMode::Continous, 0.0, 42.0));
    r.steps(500);
    assert!((r.st().set_velo - 42.0).abs() < 1e-9);
    r.e.cancel(id).unwrap();
    r.until(5000, |r| r.out(id).done);
    assert!(!r.out(id).command_aborted);
    assert_eq!(r.st().set_velo, 0.0);
    assert_eq!(r.st().motion_state, MotionState::Standstill);
    // Inching: the step is finished, the release changes nothing.
    let p0 = r.st().set_pos;
    let id = r.id(jog(true, false, JogMode::Inching, 5.0, 50.0));
    r.e.cancel(id).unwrap();
    r.until(5000, |r| r.out(id).done);
    assert!((r.st().set_pos - (p0 + 5.0)).abs() < 1e-9);
}
