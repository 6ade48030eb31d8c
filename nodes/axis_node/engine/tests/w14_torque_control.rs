//! W14 — MC_TorqueControl (§8, §4.14, §1.1 torque model).
mod common;
use axis_engine::*;
use common::*;

fn torque(t: f64, ramp: f64, hi: f64, lo: f64) -> AxisCommand {
    AxisCommand::TorqueControl(TorqueControl {
        axis: AX.into(),
        continuous_update: true,
        relative: false,
        torque: t,
        torque_ramp: ramp,
        velocity_limit_high: hi,
        velocity_limit_low: lo,
        buffer_mode: BufferMode::Aborting,
        options: TorqueControlOptions::default(),
    })
}

#[test]
fn manual_example() {
    let mut r = Rig::powered();
    let id = r.id(torque(35.0, 10.0, 400.0, -500.0));
    assert_eq!(r.st().motion_state, MotionState::ContinuousMotion);
    let n = r.until(5000, |r| r.e.fb_outputs(id).unwrap().in_torque);
    // SetTorque ramps 0 → 35 in 3.5 s.
    assert!(
        (n as f64 * DT - 3.5).abs() <= 2.0 * DT,
        "InTorque after {} s",
        n as f64 * DT
    );
    assert!((r.st().set_torque - 35.0).abs() < 1e-12);
    let o = r.out(id);
    assert!(o.busy && o.active);
    // Terminal velocity k_t·T/b = 35/0.1 = 350 (< 400).
    r.steps(60_000);
    assert!((r.st().set_velo - 350.0).abs() < 0.1, "{}", r.st().set_velo);
    assert!(r.e.fb_outputs(id).unwrap().in_torque);
    // MC_Halt ends torque mode and stops the axis.
    let h = r.id(halt(0.0, 0.0, BufferMode::Aborting));
    assert!(r.out(id).command_aborted);
    r.until(10000, |r| r.out(h).done);
    assert_eq!(r.st().set_velo, 0.0);
}

#[test]
fn velocity_limit_clamps_and_clears_in_torque() {
    let mut r = Rig::powered();
    let id = r.id(torque(100.0, 1000.0, 50.0, -50.0));
    r.steps(3000);
    assert!((r.st().set_velo - 50.0).abs() < 1e-9);
    assert!(!r.e.fb_outputs(id).unwrap().in_torque, "velocity limited");
    assert!(r.st().bit(snapshot::bits::DRIVE_LIMIT_ACTIVE));
    // ContinuousUpdate: raise the limit; the axis accelerates towards 1000 u/s.
    r.cmd(AxisCommand::TorqueControlUpdate {
        id,
        torque: 100.0,
        torque_ramp: 1000.0,
        velocity_limit_high: 2000.0,
        velocity_limit_low: -50.0,
    })
    .unwrap();
    r.steps(500);
    assert!(r.st().set_velo > 50.0);
    assert!(r.e.fb_outputs(id).unwrap().in_torque);
}

#[test]
fn bad_inputs() {
    let mut r = Rig::powered();
    let before = r.st();
    assert_eq!(
        r.cmd(torque(f64::NAN, 1.0, 1.0, -1.0))
            .unwrap_err()
            .error_id,
        motion_core::ErrorId::NOT_FINITE
    );
    assert_eq!(
        r.cmd(torque(1.0, 0.0, 1.0, -1.0)).unwrap_err().error_id,
        err(0x4B06)
    );
    assert_eq!(
        r.cmd(torque(1.0, 1.0, -1.0, 1.0)).unwrap_err().error_id,
        err(0x4B06)
    );
    let mut c = torque(1.0, 1.0, 1.0, -1.0);
    if let AxisCommand::TorqueControl(t) = &mut c {
        t.buffer_mode = BufferMode::Buffered;
    }
    assert_eq!(r.cmd(c).unwrap_err().error_id, err(0x4B04));
    assert_eq!(r.st(), before);
}
