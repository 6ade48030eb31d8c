//! E12 — order numbers (plcopen_platform.md §13, §4.3, R-FB-3): fresh start, g_order_id = 1;
//! FB X orders → order_id 1, g → 2; FB Y orders → order_id 2, g → 3; an FB-level error
//! (error 4) leaves g unchanged. (Re-triggering an ACTIVE instance is part of the raw FB
//! layer of §12.2, which this engine does not model: every call is a fresh instance.)
mod p4rig;
use axis_engine::*;
use motion_core::ErrorId;
use p4rig::*;

#[test]
fn e12_order_numbers() {
    let mut r = P4::isg();
    assert_eq!(r.g_order_id(), 1, "MC_Power placed no order");
    let x = r.id(rel(A0, 1000.0, 10000.0));
    assert_eq!((r.order_id(x), r.g_order_id()), (1, 2));
    r.step();
    let y = r.id(rel(A0, 1000.0, 10000.0));
    assert_eq!((r.order_id(y), r.g_order_id()), (2, 3));
    assert_eq!(err(r.cmd(rel(A0, 1000.0, 10000.0))), ErrorId(4));
    assert_eq!(r.g_order_id(), 3);
    // Other FB-level errors leave it unchanged too.
    r.step();
    assert_eq!(err(r.cmd(rel(A0, 1000.0, -1.0))), ErrorId(4902));
    assert_eq!(r.g_order_id(), 3);
    // Read FBs carry no order number.
    let s = r
        .cmd(AxisCommand::ReadStatus(ReadStatus { axis: A0.into() }))
        .unwrap()
        .id;
    assert_eq!(r.order_id(s), 0);
}
