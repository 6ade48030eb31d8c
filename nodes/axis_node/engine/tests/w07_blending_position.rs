//! W7 — blending position (ST_MoveOptions, single_axis.md §8, §3.6 rule 6).
mod common;
use axis_engine::*;
use common::*;
use motion_core::CommandState;

fn with_bp(position: f64, velocity: f64, bm: BufferMode, bp: f64) -> AxisCommand {
    AxisCommand::MoveAbsolute(MoveAbsolute {
        buffer_mode: bm,
        options: MoveOptions {
            enable_blending_position: true,
            blending_position: bp,
            ..Default::default()
        },
        ..move_abs(position, velocity)
    })
}

#[test]
fn move_velocity_blends_into_move_absolute_at_the_blending_position() {
    let mut r = Rig::powered();
    let v = r.id(vel(100.0));
    r.steps(250); // 0.5 s: running at 100 u/s, well before 150
    assert!((r.st().set_velo - 100.0).abs() < 1e-9);
    assert!(r.st().set_pos < 100.0);
    let b = r.id(with_bp(300.0, 50.0, BufferMode::BlendingNext, 150.0));
    assert!(r.out(b).busy && !r.out(b).active);
    assert!(
        !r.out(v).command_aborted,
        "MoveVelocity keeps control until the blending point"
    );
    r.until(10000, |r| r.out(b).active);
    let st = r.st();
    assert!(
        (st.set_pos - 150.0).abs() < 1e-9,
        "passes 150 ({})",
        st.set_pos
    );
    assert!(
        (st.set_velo - 50.0).abs() < 1e-9,
        "at v2 = 50 ({})",
        st.set_velo
    );
    assert_eq!(
        r.state_of(v),
        Some(CommandState::Aborted),
        "the endless FB ends with CommandAborted"
    );
    r.until(20000, |r| r.out(b).done);
    assert_eq!(r.st().set_pos, 300.0);
}

#[test]
fn blending_position_beyond_the_running_end_position_is_rejected() {
    let mut r = Rig::powered();
    let a = r.id(abs(100.0, 100.0));
    r.steps(20);
    let before = r.st();
    let e = r
        .cmd(with_bp(300.0, 50.0, BufferMode::BlendingNext, 150.0))
        .unwrap_err();
    assert_eq!(e.error_id, err(0x4296), "{}", e.message);
    assert_eq!(r.st(), before);
    assert!(r.out(a).active);
}

#[test]
fn blending_position_already_passed_executes_at_once() {
    let mut r = Rig::powered();
    let a = r.id(abs(100.0, 100.0));
    r.steps(300);
    assert!(r.st().set_pos > 30.0);
    let b = r.id(with_bp(300.0, 50.0, BufferMode::BlendingNext, 20.0));
    assert!(r.out(a).command_aborted, "like Aborting");
    assert!(r.out(b).active);
    r.until(20000, |r| r.out(b).done);
    assert_eq!(r.st().set_pos, 300.0);
}

#[test]
fn buffered_behind_endless_motion_without_blending_position_acts_like_aborting() {
    let mut r = Rig::powered();
    let v = r.id(vel(100.0));
    r.steps(100);
    let b = r.id(abs_bm(500.0, 50.0, BufferMode::Buffered));
    assert!(r.out(v).command_aborted);
    assert!(r.out(b).active);
}
