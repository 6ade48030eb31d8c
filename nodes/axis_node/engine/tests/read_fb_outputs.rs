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
