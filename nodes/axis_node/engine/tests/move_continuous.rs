//! MC_MoveContinuousAbsolute / MC_MoveContinuousRelative (§4.8.7, §4.8.8) and T16.
mod common;
use axis_engine::*;
use common::*;
use motion_core::CommandState;

fn cont_abs(position: f64, velocity: f64, end_velocity: f64, bm: BufferMode) -> AxisCommand {
    AxisCommand::MoveContinuousAbsolute(MoveContinuousAbsolute {
        axis: AX.into(),
        position,
        velocity,
        end_velocity,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: bm,
        options: MoveOptions::default(),
    })
}

#[test]
fn reaches_the_target_with_end_velocity_and_keeps_it() {
    let mut r = Rig::powered();
    let id = r.id(cont_abs(100.0, 100.0, 50.0, BufferMode::Aborting));
    assert_eq!(r.st().motion_state, MotionState::ContinuousMotion);
    r.until(5000, |r| r.e.fb_outputs(id).unwrap().in_end_velocity);
    let st = r.st();
    assert!(
        (st.set_pos - 100.0).abs() < 1e-9,
        "InEndVelocity at the target: {}",
        st.set_pos
    );
    assert!((st.set_velo - 50.0).abs() < 1e-9);
    let o = r.out(id);
    assert!(o.busy && o.active && !o.done);
    r.steps(500);
    assert!(
        (r.st().set_velo - 50.0).abs() < 1e-9,
        "endless at EndVelocity"
    );
    assert!((r.st().set_pos - 150.0).abs() < 1e-6);
    assert_eq!(r.st().motion_state, MotionState::ContinuousMotion);
    r.id(halt(0.0, 0.0, BufferMode::Aborting));
    assert!(r.out(id).command_aborted);
}

#[test]
fn t16_end_velocity_zero_ends_in_standstill_with_the_fb_still_busy() {
    let mut r = Rig::powered();
    let id = r.id(cont_abs(-50.0, 100.0, 0.0, BufferMode::Aborting));
    assert_eq!(r.st().motion_state, MotionState::ContinuousMotion);
    r.until(5000, |r| r.e.fb_outputs(id).unwrap().in_end_velocity);
    assert_eq!(r.st().set_pos, -50.0);
    assert_eq!(r.st().motion_state, MotionState::Standstill);
    let o = r.out(id);
    assert!(o.busy && o.active, "{o:?}");
    r.steps(100);
    assert!(r.out(id).busy);
    let b = r.id(abs(0.0, 100.0));
    assert!(r.out(id).command_aborted);
    r.until(5000, |r| r.out(b).done);
}

#[test]
fn relative_variant_and_blending_uses_end_velocity_as_v1() {
    let mut r = Rig::powered();
    r.set_pos(10.0);
    let a = r.id(AxisCommand::MoveContinuousRelative(
        MoveContinuousRelative {
            axis: AX.into(),
            distance: 90.0,
            velocity: 100.0,
            end_velocity: 30.0,
            acceleration: 0.0,
            deceleration: 0.0,
            jerk: 0.0,
            buffer_mode: BufferMode::Aborting,
            options: MoveOptions::default(),
        },
    ));
    r.steps(100);
    let b = r.id(abs_bm(300.0, 80.0, BufferMode::BlendingPrevious));
    r.until(5000, |r| r.out(b).active);
    let st = r.st();
    assert!((st.set_pos - 100.0).abs() < 1e-9);
    assert!(
        (st.set_velo - 30.0).abs() < 1e-9,
        "v1 = EndVelocity: {}",
        st.set_velo
    );
    assert_eq!(
        r.state_of(a),
        Some(CommandState::Aborted),
        "endless FB taken over ends with CommandAborted"
    );
    r.until(10000, |r| r.out(b).done);
    assert_eq!(r.st().set_pos, 300.0);
}

#[test]
fn bad_end_velocity() {
    let mut r = Rig::powered();
    let before = r.st();
    let e = r
        .cmd(cont_abs(100.0, 100.0, -1.0, BufferMode::Aborting))
        .unwrap_err();
    assert_eq!(e.error_id, err(0x4B06));
    assert!(e.message.contains("EndVelocity = -1"), "{}", e.message);
    let e = r
        .cmd(cont_abs(100.0, 100.0, f64::NAN, BufferMode::Aborting))
        .unwrap_err();
    assert_eq!(e.error_id, motion_core::ErrorId::NOT_FINITE);
    assert_eq!(r.st(), before);
}
