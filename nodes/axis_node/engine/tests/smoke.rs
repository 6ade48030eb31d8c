//! Smoke test: one move from power-on to Done.
mod common;
use axis_engine::*;
use common::*;

#[test]
fn move_absolute_reaches_target_and_reports_done() {
    let mut r = Rig::powered();
    let id = r.id(abs(100.0, 100.0));
    assert!(r.out(id).busy && r.out(id).active);
    assert_eq!(r.st().motion_state, MotionState::DiscreteMotion);
    r.until(5000, |r| r.out(id).done);
    let s = r.st();
    assert_eq!(s.set_pos, 100.0);
    assert_eq!(s.motion_state, MotionState::Standstill);
}
