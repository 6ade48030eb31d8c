//! E8 — actual velocity fault (plcopen_platform.md §13, R-SAF-1b): with the monitor active,
//! an actual velocity of 260000 u/s (260 mm/s) while standing → 70225 within 1 cycle,
//! ERROR_STOP, power off.
mod p4rig;
use axis_engine::platform::*;
use axis_engine::*;
use p4rig::*;

#[test]
fn e8_injected_actual_velocity_trips_70225() {
    let mut r = P4::isg();
    r.p(PlatformCommand::InjectActualVelocity {
        axis: A0.into(),
        velocity: 260000.0,
        duration_cycles: 5,
    })
    .unwrap();
    r.step();
    assert_eq!(r.a0().error_code, 70225);
    assert_eq!(r.a0().motion_state, MotionState::ErrorStop);
    assert!(!r.safety(A0).drive_enabled);
}

#[test]
fn e8_below_the_limit_nothing_happens() {
    let mut r = P4::isg();
    r.p(PlatformCommand::InjectActualVelocity {
        axis: A0.into(),
        velocity: 249000.0,
        duration_cycles: 5,
    })
    .unwrap();
    r.steps(10);
    assert_eq!(r.a0().error_code, 0);
}
