//! CA block instances report their outputs as `CommandEvent`s of `step` (what the ROS shell
//! turns into `~/command_status` and action results) and through `AxisEngine::outputs`.

mod ca_common;
use axis_engine::ca::*;
use axis_engine::AxisEngine;
use ca_common::*;
use motion_core::{CommandEvent, CommandState, Engine};

#[test]
fn motion_commands_report_their_admission_and_end_with_one_final_event() {
    let mut r = CaRig::new(&[("A", 0.0), ("B", -500.0)], open(5000.0));
    let rep = r
        .ca(CaCommand::MoveAbsolute(MoveAbsoluteCa {
            axis: "A".into(),
            position: McLreal::Value(100.0),
            velocity: McLreal::Value(500.0),
            ..Default::default()
        }))
        .unwrap();
    assert_eq!(
        AxisEngine::reply_id(&rep),
        Some(rep.id),
        "tracked: events follow"
    );
    let o = r.out(rep.id);
    assert!(o.busy && o.active && !o.done);
    let mut log: Vec<CommandEvent> = Vec::new();
    for _ in 0..2000 {
        r.step();
        log.extend(r.events.iter().copied());
    }
    // The admission (Active: in control at once) and then one final event (issue 15 item 6:
    // the admission used to be missing, so ~/command_status never showed a running command).
    let mine: Vec<_> = log
        .iter()
        .map(|e| (e.id, e.state))
        .filter(|e| e.0 == rep.id)
        .collect();
    assert_eq!(
        mine,
        [(rep.id, CommandState::Active), (rep.id, CommandState::Done)],
        "{mine:?}"
    );
    assert!(r.out(rep.id).done);
    // Read blocks are untracked.
    let rd = r
        .ca(CaCommand::GroupReadStatus { group: G.into() })
        .unwrap();
    assert_eq!(AxisEngine::reply_id(&rd), None);
}

#[test]
fn aborted_and_buffered_commands_report_their_transitions() {
    let mut r = CaRig::new(&[("A", 0.0)], open(5000.0));
    let a = r.mv_abs("A", 1000.0, 500.0);
    let b = r.ok(CaCommand::MoveAbsolute(MoveAbsoluteCa {
        axis: "A".into(),
        position: McLreal::Value(50.0),
        velocity: McLreal::Value(500.0),
        buffer_mode: CaBufferMode::Buffered,
        ..Default::default()
    }));
    r.steps(100);
    let c = r.mv_abs("A", 200.0, 500.0);
    let mut log: Vec<CommandEvent> = r.events.clone();
    r.step();
    log.extend(r.events.iter().copied());
    assert!(log
        .iter()
        .any(|e| e.id == a && e.state == CommandState::Aborted));
    assert!(log
        .iter()
        .any(|e| e.id == b && e.state == CommandState::Aborted));
    r.until(3000, |r| r.cmd_state(c) == CommandState::Done);
    assert_eq!(r.pos("A"), 200.0);
}

#[test]
fn single_axis_status_of_members_shows_the_ca_motion() {
    use axis_engine::MotionState;
    let mut r = CaRig::new(&[("A", 0.0), ("B", -100.0)], open(5000.0));
    assert_eq!(
        r.e.status("A").unwrap().motion_state,
        MotionState::Standstill
    );
    let a = r.mv_abs("A", 300.0, 500.0);
    let b = r.mv_abs("B", 300.0, 500.0);
    r.steps(10);
    assert_eq!(
        r.e.status("A").unwrap().motion_state,
        MotionState::DiscreteMotion
    );
    r.until(3000, |r| r.cmd_state(a) == CommandState::Done);
    r.steps(1000);
    assert_eq!(
        r.e.status("A").unwrap().motion_state,
        MotionState::Standstill,
        "A Done"
    );
    assert_eq!(r.cmd_state(b), CommandState::Active);
    assert_eq!(
        r.e.status("B").unwrap().motion_state,
        MotionState::DiscreteMotion,
        "queued follower: its command is still running"
    );
    assert!(
        (r.e.status("B").unwrap().set_pos - 200.0).abs() < 1e-3,
        "rests one gap behind"
    );
}
