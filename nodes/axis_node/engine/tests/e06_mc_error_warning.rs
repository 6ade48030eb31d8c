//! E6 — MC error vs warning (plcopen_platform.md §13, §7.2, R-ERR-2/3): a message with
//! remedy class 0 is a warning (buffer only); class 2 during a move → ERROR_STOP, the axis
//! decelerates, the moving FB and MC_ReadActualPosition show ErrorID 1, MC_ReadAxisError
//! returns the MC id, the buffer holds both; MC_MoveRelative → 4901; MC_Reset → STANDSTILL,
//! buffer cleared.
mod p4rig;
use axis_engine::platform::*;
use axis_engine::*;
use motion_core::{CommandState, ErrorId};
use p4rig::*;

fn msg(id: u32, b: u16, r: u16) -> PlatformCommand {
    PlatformCommand::InjectMcMessage {
        axis: A0.into(),
        error_id: id,
        behebungs_klasse: b,
        reaktions_klasse: r,
    }
}

#[test]
fn e6_warning_then_error() {
    let mut r = P4::isg();
    let m = r.id(rel(A0, 100000.0, 10000.0));
    r.steps(500);
    r.p(msg(12345, 0, 0)).unwrap();
    r.step();
    assert_eq!(
        r.a0().motion_state,
        MotionState::DiscreteMotion,
        "warning: no state change"
    );
    assert!(r.out(m).busy && !r.out(m).error);
    assert_eq!(r.messages(A0).len(), 1);
    let v_before = r.a0().set_velo;
    r.p(msg(23456, 2, 1)).unwrap();
    r.step();
    assert_eq!(r.a0().motion_state, MotionState::ErrorStop);
    assert!(
        r.a0().set_velo < v_before && r.a0().set_velo > 0.0,
        "decelerates"
    );
    assert!(r.out(m).error);
    assert_eq!(r.out(m).error_id, ErrorId(1), "ERR_PLC_AX_MC");
    assert!(r
        .log
        .iter()
        .any(|(_, e)| e.id == m && e.state == CommandState::Error(ErrorId(1))));
    assert_eq!(
        err(r.cmd(AxisCommand::ReadActualPosition(ReadActualPosition {
            axis: A0.into()
        }))),
        ErrorId(1)
    );
    let e = r
        .cmd(AxisCommand::ReadAxisError(ReadAxisError {
            axis: A0.into(),
        }))
        .unwrap()
        .value;
    assert_eq!(e, ReplyValue::DWord(23456));
    let buf = r.messages(A0);
    assert_eq!(
        buf.iter().map(|m| m.error_id).collect::<Vec<_>>(),
        vec![23456, 12345],
        "newest first"
    );
    assert_eq!(err(r.cmd(rel(A0, 1000.0, 10000.0))), ErrorId(4901));
    assert_eq!(r.a0().motion_state, MotionState::ErrorStop);
    r.until(5000, |r| r.a0().set_velo == 0.0);
    r.cmd(AxisCommand::Reset(Reset { axis: A0.into() }))
        .unwrap();
    r.steps(2);
    assert_eq!(r.a0().motion_state, MotionState::Standstill);
    assert!(r.messages(A0).is_empty(), "buffer cleared by MC_Reset");
}

#[test]
fn e6_buffer_keeps_six_entries() {
    let mut r = P4::isg();
    for k in 1..=8 {
        r.p(msg(k, 0, 0)).unwrap();
    }
    let b = r.messages(A0);
    assert_eq!(b.len(), 6);
    assert_eq!(b[0].error_id, 8);
    assert_eq!(b[5].error_id, 3, "oldest dropped");
}

#[test]
fn e6_reaction_class_3_removes_the_enable() {
    let mut r = P4::isg();
    r.id(rel(A0, 100000.0, 10000.0));
    r.steps(200);
    r.p(msg(30000, 1, 3)).unwrap();
    r.step();
    assert_eq!(r.a0().motion_state, MotionState::ErrorStop);
    assert!(!r.safety(A0).drive_enabled);
    assert_eq!(r.a0().set_velo, 0.0, "brake closed");
}

#[test]
fn e6_error_id_1_stays_after_the_reset() {
    let mut r = P4::isg();
    let m = r.id(rel(A0, 100000.0, 10000.0));
    r.steps(100);
    r.p(msg(23456, 2, 1)).unwrap();
    r.until(5000, |r| r.a0().set_velo == 0.0);
    r.cmd(AxisCommand::Reset(Reset { axis: A0.into() }))
        .unwrap();
    r.steps(2);
    assert_eq!(r.out(m).error_id, ErrorId(1));
}

/// Peak |deceleration| of the error reaction after a message with `reaction` during a move
/// with Deceleration 200000 (fast deceleration of the axis: 5e6).
fn reaction_decel(reaction: u16) -> f64 {
    let mut r = P4::isg();
    r.id(rel_full(A0, 1e6, 100000.0, 200000.0, 200000.0, 1e8));
    r.steps(1500);
    r.p(msg(40000, 1, reaction)).unwrap();
    let mut peak: f64 = 0.0;
    r.until(10000, |r| {
        peak = peak.max(r.a0().set_acc.abs());
        r.a0().set_velo == 0.0
    });
    peak
}

#[test]
fn e6_reaction_classes_1_and_2() {
    let d1 = reaction_decel(1);
    let d2 = reaction_decel(2);
    assert!(
        (d1 - 200000.0).abs() < 1.0,
        "class 1: programmed deceleration, {d1}"
    );
    assert!(d2 > 1e6, "class 2: quick stop with the limit values, {d2}");
}
