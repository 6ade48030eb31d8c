//! E12 — order numbers (plcopen_platform.md §13, §4.3, R-FB-3): fresh start, g_order_id = 1;
//! FB X orders → order_id 1, g → 2; FB Y orders → order_id 2, g → 3; an FB-level error
//! (error 4) leaves g unchanged; FB X re-triggered while ACTIVE (raw FB layer, §12.2) keeps
//! order_id 1 with 2 orders in flight.
mod p4rig;
use axis_engine::platform::raw;
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

#[test]
fn e12_raw_retrigger_keeps_the_number() {
    let mut r = P4::isg();
    let x = |e| call("X", e, rel(A0, 1000.0, 10000.0));
    let o = r.cycle(&[x(true)]);
    assert_eq!((o[0].order_id, r.g_order_id()), (1, 2));
    r.cycle(&[x(false)]);
    let o = r.cycle(&[x(true)]);
    assert_eq!(o[0].fb_state, raw::FbState::Active);
    assert_eq!((o[0].order_id, o[0].in_flight, r.g_order_id()), (1, 2, 2));
    // Y orders in the next cycle; Z in the same cycle fails with 4.
    let o = r.cycle(&[
        x(true),
        call("Y", true, rel(A0, 10.0, 10000.0)),
        call("Z", true, rel(A0, 10.0, 10000.0)),
    ]);
    assert_eq!((o[1].order_id, r.g_order_id()), (2, 3));
    assert!(o[2].error && o[2].error_id == ErrorId(4));
    assert_eq!(o[2].fb_state, raw::FbState::Error);
    assert_eq!(r.g_order_id(), 3);
    // X finishes only when both of its orders are acknowledged (here: aborted by Y).
    let mut done = None;
    for _ in 0..100 {
        let o = r.cycle(&[x(true), call("Y", true, rel(A0, 10.0, 10000.0))]);
        if o[0].command_aborted {
            done = Some(o[0].in_flight);
            break;
        }
    }
    assert_eq!(done, Some(0));
}
