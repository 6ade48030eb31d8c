//! E10 — T1 mode (plcopen_platform.md §13, R-SAF-5): in T1 with the enabling switch pressed
//! and START released an order is Busy without motion; START starts it; releasing START is a
//! feed hold (standstill, Busy, no CommandAborted); START again continues to Done. Switching
//! AUTO → T1 while moving disables the drives, the order ends CommandAborted.
mod p4rig;
use axis_engine::platform::*;
use axis_engine::*;
use motion_core::ErrorId;
use p4rig::*;

fn mode(r: &mut P4, m: OperatingMode) {
    r.p(PlatformCommand::OperatingMode { mode: m }).unwrap();
}
fn switch(r: &mut P4, pressed: bool) {
    r.p(PlatformCommand::EnablingSwitch { pressed }).unwrap();
}
fn start(r: &mut P4, pressed: bool) {
    r.p(PlatformCommand::StartButton { pressed }).unwrap();
}

#[test]
fn e10_feed_hold_and_continue() {
    let mut r = P4::isg();
    mode(&mut r, OperatingMode::T1);
    assert_eq!(
        r.a0().motion_state,
        MotionState::Disabled,
        "drive enables removed"
    );
    assert_eq!(
        err(r.cmd(rel(A0, 100000.0, 100000.0))),
        ErrorId(4901),
        "no enabling switch"
    );
    switch(&mut r, true);
    r.power(A0, true).unwrap();
    r.steps(2);
    let id = r.id(rel(A0, 100000.0, 100000.0));
    r.steps(100);
    assert!(r.out(id).busy, "Busy");
    assert_eq!(r.a0().set_pos, 0.0, "no motion without START");
    start(&mut r, true);
    r.until(5000, |r| r.a0().set_pos > 30000.0);
    start(&mut r, false);
    r.until(5000, |r| r.a0().set_velo == 0.0);
    r.steps(100);
    let held = r.a0().set_pos;
    assert!(held < 100000.0);
    assert!(
        r.out(id).busy && !r.out(id).command_aborted,
        "feed hold: still active"
    );
    assert!(r.safety(A0).feed_hold);
    start(&mut r, true);
    r.until(10000, |r| r.out(id).done);
    assert_eq!(r.a0().set_pos, 100000.0);
}

#[test]
fn e10_t1_clamps_the_velocity_to_250_mm_s() {
    let mut r = P4::isg();
    mode(&mut r, OperatingMode::T1);
    switch(&mut r, true);
    start(&mut r, true);
    r.power(A0, true).unwrap();
    r.steps(2);
    // 300 mm/s would trip 60241 in AUTO; in T1 it is clamped first.
    let v = r.id(AxisCommand::MoveVelocity(MoveVelocity {
        axis: A0.into(),
        velocity: 300000.0,
        acceleration: 1e7,
        deceleration: 1e7,
        jerk: 1e9,
        direction: Direction::Positive,
        buffer_mode: BufferMode::Aborting,
        options: MoveOptions::default(),
    }));
    r.until(1000, |r| r.e.fb_outputs(v).unwrap().in_velocity);
    assert!((r.a0().set_velo - 250000.0).abs() < 1e-6);
}

#[test]
fn e10_auto_to_t1_while_moving_aborts() {
    let mut r = P4::isg();
    let id = r.id(rel(A0, 100000.0, 10000.0));
    r.steps(500);
    mode(&mut r, OperatingMode::T1);
    assert!(r.out(id).command_aborted);
    assert!(!r.safety(A0).drive_enabled);
    assert_eq!(r.a0().motion_state, MotionState::Disabled);
}

#[test]
fn e10_feed_hold_does_not_abort_move_velocity() {
    let mut r = P4::isg();
    mode(&mut r, OperatingMode::T2);
    switch(&mut r, true);
    start(&mut r, true);
    r.power(A0, true).unwrap();
    r.steps(2);
    let v = r.id(vel(A0, 10000.0));
    r.until(1000, |r| r.e.fb_outputs(v).unwrap().in_velocity);
    start(&mut r, false);
    r.until(5000, |r| r.a0().set_velo == 0.0);
    let o = r.out(v);
    assert!(o.busy && !o.command_aborted, "held, not aborted");
    start(&mut r, true);
    r.until(5000, |r| r.e.fb_outputs(v).unwrap().in_velocity);
    assert!((r.a0().set_velo - 10000.0).abs() < 1e-6);
}

#[test]
fn e10_override_written_during_the_hold_does_not_release_it() {
    let mut r = P4::isg();
    mode(&mut r, OperatingMode::T1);
    switch(&mut r, true);
    r.power(A0, true).unwrap();
    r.steps(2);
    let id = r.id(rel(A0, 100000.0, 100000.0));
    r.cmd(AxisCommand::SetOverride(SetOverride {
        axis: A0.into(),
        enable: true,
        vel_factor: 1.0,
        acc_factor: 1.0,
        jerk_factor: 1.0,
    }))
    .unwrap();
    r.power(A0, true).unwrap();
    r.steps(200);
    assert_eq!(r.a0().set_pos, 0.0, "still held without START");
    start(&mut r, true);
    r.until(10000, |r| r.out(id).done);
}
