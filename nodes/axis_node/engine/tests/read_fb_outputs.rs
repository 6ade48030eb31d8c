//! `AxisCommand::ReadFbOutputs`: the outputs of an instance as a PLC reads them (the shell's
//! `~/get_outputs`), equal to `fb_outputs`, without changing anything.
mod common;
use axis_engine::*;
use common::*;
use motion_core::{CmdId, Engine, ErrorId};

#[test]
fn read_fb_outputs_reports_the_instance_and_changes_nothing() {
    let mut r = Rig::powered();
    let id = r.id(abs(10.0, 100.0));
    r.steps(3);
    let before = r.st();
    let reply = r.cmd(AxisCommand::ReadFbOutputs { id }).unwrap();
    assert_eq!(reply.id, id);
    assert!(!reply.tracked);
    let ReplyValue::Outputs(o) = reply.value else {
        panic!("{reply:?}")
    };
    assert_eq!(o.axis, "x");
    assert_eq!(o.kind, FbKind::MoveAbsolute);
    assert_eq!(Some(o.outputs), r.e.fb_outputs(id));
    assert!(o.outputs.standard.busy && o.outputs.standard.active && !o.outputs.standard.done);
    assert_eq!(r.st(), before, "a read changes no axis state");
    r.until(5000, |r| r.out(id).done);
    let ReplyValue::Outputs(o) = r.cmd(AxisCommand::ReadFbOutputs { id }).unwrap().value else {
        panic!()
    };
    assert!(o.outputs.standard.done && !o.outputs.standard.busy);

    let e = r
        .cmd(AxisCommand::ReadFbOutputs { id: CmdId(999_999) })
        .unwrap_err();
    assert_eq!(e.error_id, ErrorId::UNKNOWN_OBJECT);
    assert!(e.message.contains("999999"), "{}", e.message);
    let _ = r.e.snapshot();
}

fn power_outputs(r: &mut Rig, id: CmdId) -> InstanceOutputs {
    let reply = r.cmd(AxisCommand::ReadFbOutputs { id }).unwrap();
    assert_eq!(reply.id, id);
    match reply.value {
        ReplyValue::Outputs(o) => *o,
        v => panic!("{v:?}"),
    }
}

/// Issue 15.12: MC_Power's outputs (Status, Valid, Busy, Active, Error, ErrorID, §4.1) are
/// read by the command id of its call, as every other instance; the axis has one MC_Power
/// instance, so every call answers the same id.
#[test]
fn mc_power_outputs_are_readable_by_command_id() {
    let mut r = Rig::new();
    let id = r
        .power_full(true, true, true, 100.0, BufferMode::Aborting)
        .unwrap()
        .id;
    let o = power_outputs(&mut r, id);
    assert_eq!((o.axis.as_str(), o.kind), ("x", FbKind::Power));
    assert_eq!(o.kind.fb_name(), "MC_Power");
    let s = o.outputs.standard;
    assert!(s.busy && s.active && !s.error && !s.done);
    // Status TRUE one cycle after Enable↑ (§4.1).
    assert_eq!(
        o.extra,
        Some(ExtraOutputs::Power {
            status: false,
            valid: true
        })
    );
    r.step();
    let o = power_outputs(&mut r, id);
    assert_eq!(
        o.extra,
        Some(ExtraOutputs::Power {
            status: true,
            valid: true
        })
    );
    // Override out of range: Error with 0x4B06, the previous override stays.
    let e = r
        .power_full(true, true, true, 150.0, BufferMode::Aborting)
        .unwrap_err();
    assert_eq!(e.error_id, ErrorId(0x4B06));
    let o = power_outputs(&mut r, id);
    assert!(o.outputs.standard.error);
    assert_eq!(o.outputs.standard.error_id, ErrorId(0x4B06));
    assert_eq!(
        o.extra,
        Some(ExtraOutputs::Power {
            status: true,
            valid: false
        })
    );
    // A good call clears it and keeps the same instance id.
    let again = r
        .power_full(false, true, true, 100.0, BufferMode::Aborting)
        .unwrap()
        .id;
    assert_eq!(again, id, "one MC_Power instance per axis");
    r.step();
    let o = power_outputs(&mut r, id);
    let s = o.outputs.standard;
    assert!(!s.busy && !s.active && !s.error);
    assert_eq!(
        o.extra,
        Some(ExtraOutputs::Power {
            status: false,
            valid: false
        })
    );
}
