//! E4 — MC_Stop overwrites (plcopen_platform.md §13, R-HS-4 / R-SAF-3): MC_MoveAbsolute then
//! MC_Stop in the same cycle on a standing axis → MoveAbsolute CommandAborted, no motion,
//! STOPPING; Stop Done at standstill; STOPPING while Stop.Execute is TRUE; MC_MoveRelative
//! then → 4901, axis unchanged; Stop.Execute FALSE → STANDSTILL.
mod p4rig;
use axis_engine::*;
use motion_core::ErrorId;
use p4rig::*;

#[test]
fn e4_stop_overwrites_the_order_of_the_cycle() {
    let mut r = P4::isg();
    let m = r.id(abs(A0, 50000.0, 10000.0));
    let s = r.id(stop(A0, 5000.0));
    assert!(r.out(m).command_aborted);
    assert_eq!(r.a0().motion_state, MotionState::Stopping);
    r.until(100, |r| r.out(s).done);
    r.steps(50);
    assert_eq!(r.a0().set_pos, 0.0, "no motion");
    assert_eq!(
        r.a0().motion_state,
        MotionState::Stopping,
        "Execute still TRUE"
    );
    assert_eq!(err(r.cmd(rel(A0, 1000.0, 10000.0))), ErrorId(4901));
    assert_eq!(r.a0().motion_state, MotionState::Stopping);
    r.set_execute(s, false);
    r.until(10, |r| r.a0().motion_state == MotionState::Standstill);
}

#[test]
fn e4_a_later_stop_overwrites_an_earlier_one() {
    let mut r = P4::isg();
    let s1 = r.id(stop(A0, 5000.0));
    let s2 = r.id(stop(A0, 5000.0));
    assert!(r.out(s1).command_aborted);
    r.step();
    assert!(r.out(s2).done);
}
