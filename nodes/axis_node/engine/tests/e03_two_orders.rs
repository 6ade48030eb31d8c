//! E3 — two orders in one cycle (plcopen_platform.md §13, R-HS-3): MC_MoveAbsolute(50000)
//! places its order (order_id n, g_order_id n+1); MC_MoveRelative(1000) in the same cycle
//! → Error, ErrorID 4, g_order_id unchanged; the axis moves towards 50000.
mod p4rig;
use axis_engine::*;
use motion_core::ErrorId;
use p4rig::*;

#[test]
fn e3_second_order_same_cycle_is_error_4() {
    let mut r = P4::isg();
    let n = r.g_order_id();
    let a = r.id(abs(A0, 50000.0, 10000.0));
    assert_eq!(r.order_id(a), n);
    assert_eq!(r.g_order_id(), n + 1);
    assert_eq!(err(r.cmd(rel(A0, 1000.0, 10000.0))), ErrorId(4));
    assert_eq!(r.g_order_id(), n + 1, "unchanged by the failed order");
    assert_eq!(r.a0().motion_state, MotionState::DiscreteMotion);
    // Read FBs and MC_Power do not use the order slot.
    r.cmd(AxisCommand::ReadStatus(ReadStatus { axis: A0.into() }))
        .unwrap();
    r.power(A0, true).unwrap();
    // Next cycle the slot is free again.
    r.step();
    let b = r.id(rel(A0, 1000.0, 10000.0));
    assert!(r.out(a).command_aborted, "a newer order aborts");
    assert_eq!(r.order_id(b), n + 1);
}

#[test]
fn e3_tc2_mc2_takes_both_orders() {
    // Profile-dependent: in tc2_mc2 the second order of a cycle is admitted (aborting).
    let mut r = P4::xy_powered();
    r.id(abs("x", 50.0, 10.0));
    r.id(rel("x", 10.0, 10.0));
}
