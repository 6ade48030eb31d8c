//! §3.1–§3.3 FB lifecycle: output exclusivity, Execute edges, one-cycle results, MC_Stop's
//! exception, events on every state change.
mod common;
use axis_engine::*;
use common::*;
use motion_core::{CommandState, Engine};

#[test]
fn outputs_are_exclusive_through_a_whole_scenario() {
    let mut r = Rig::powered();
    let mut ids = vec![];
    ids.push(r.id(abs(50.0, 100.0)));
    for k in 0..600 {
        match k {
            50 => ids.push(r.id(abs_bm(80.0, 50.0, BufferMode::BlendingHigh))),
            300 => ids.push(r.id(vel(30.0))),
            400 => ids.push(r.id(halt(0.0, 0.0, BufferMode::Aborting))),
            500 => ids.push(r.id(rel(10.0, 50.0))),
            _ => {}
        }
        r.step();
        for &id in &ids {
            assert_exclusive(&r.out(id), false);
        }
    }
}

#[test]
fn events_report_every_state_change_once() {
    let mut r = Rig::powered();
    let a = r.id(abs(100.0, 50.0));
    r.steps(10);
    let b = r.id(abs_bm(0.0, 50.0, BufferMode::Buffered));
    r.until(20000, |r| r.out(b).done);
    let evs: Vec<_> = r
        .log
        .iter()
        .filter(|(_, e)| e.id == a || e.id == b)
        .map(|(_, e)| (e.id, e.state))
        .collect();
    assert_eq!(
        evs,
        vec![
            (a, CommandState::Active),
            (b, CommandState::Busy),
            (a, CommandState::Done),
            (b, CommandState::Active),
            (b, CommandState::Done)
        ]
    );
    // An abort made by a command is reported in the next step.
    let c = r.id(abs(50.0, 50.0));
    r.steps(5);
    let n = r.log.len();
    let d = r.id(abs(60.0, 50.0));
    r.step();
    assert!(r.log[n..]
        .iter()
        .any(|(_, e)| e.id == c && e.state == CommandState::Aborted));
    let _ = d;
}

#[test]
fn execute_falling_after_the_end_resets_the_outputs() {
    let mut r = Rig::powered();
    let a = r.id(abs(1.0, 100.0));
    r.until(1000, |r| r.out(a).done);
    r.steps(5);
    assert!(r.out(a).done, "Done stays while Execute is TRUE");
    r.cmd(execute(a, false)).unwrap();
    assert_eq!(
        r.out(a),
        Default::default(),
        "falling edge resets Done (rule 5)"
    );
}

#[test]
fn result_after_execute_fell_is_shown_for_exactly_one_cycle() {
    let mut r = Rig::powered();
    let a = r.id(abs(1.0, 100.0));
    r.steps(3);
    r.cmd(execute(a, false)).unwrap();
    assert!(
        r.out(a).busy,
        "a falling edge never influences the running command"
    );
    let mut shown = 0;
    for _ in 0..1000 {
        r.step();
        if r.out(a).done {
            shown += 1;
        }
    }
    assert_eq!(shown, 1, "Done visible for exactly one cycle (rule 6)");
    assert_eq!(r.st().set_pos, 1.0);
}

#[test]
fn error_result_also_pulses_when_execute_is_low() {
    let mut r = Rig::powered();
    let a = r.id(vel(50.0));
    r.cmd(execute(a, false)).unwrap();
    r.cmd(inject(0x4550)).unwrap();
    r.step();
    let o = r.out(a);
    assert!(o.error && o.error_id == err(0x4550), "{o:?}");
    r.step();
    assert_eq!(r.out(a), Default::default());
}

#[test]
fn move_velocity_stays_busy_active_with_in_velocity() {
    let mut r = Rig::powered();
    let v = r.id(vel(100.0));
    assert!(!r.e.fb_outputs(v).unwrap().in_velocity);
    r.until(1000, |r| r.e.fb_outputs(v).unwrap().in_velocity);
    assert!((r.st().set_velo - 100.0).abs() < 1e-9);
    let o = r.out(v);
    assert!(o.busy && o.active && !o.done);
    r.steps(100);
    assert!(r.e.fb_outputs(v).unwrap().in_velocity);
    r.id(halt(0.0, 0.0, BufferMode::Aborting));
    let o = r.e.fb_outputs(v).unwrap();
    assert!(o.standard.command_aborted && !o.in_velocity);
}

#[test]
fn stop_locks_until_execute_falls_and_rejects_motion_meanwhile() {
    let mut r = Rig::powered();
    r.id(vel(100.0));
    r.steps(100);
    let s = r.id(stop(0.0, 0.0));
    for k in 0..400 {
        r.step();
        assert_exclusive(&r.out(s), true);
        if k == 10 {
            let e = r.cmd(abs(0.0, 10.0)).unwrap_err();
            assert_eq!(e.error_id, err(0x4B01), "locked while braking");
        }
    }
    assert!(r.out(s).done && r.out(s).busy && r.out(s).active);
    for c in [
        abs(0.0, 10.0),
        vel(10.0),
        halt(0.0, 0.0, BufferMode::Aborting),
        rel(1.0, 1.0),
    ] {
        assert_eq!(
            r.cmd(c).unwrap_err().error_id,
            err(0x4B01),
            "locked at rest"
        );
    }
    assert!(r.st().bit(snapshot::bits::HAS_BEEN_STOPPED));
    r.cmd(execute(s, false)).unwrap();
    r.steps(3);
    assert_eq!(r.st().motion_state, MotionState::Standstill);
    let m = r.id(abs(0.0, 100.0));
    assert!(r.out(m).active, "{:?} {:?}", r.out(m), r.st());
    assert!(
        !r.st().bit(snapshot::bits::HAS_BEEN_STOPPED),
        "cleared by the next motion command"
    );
}

#[test]
fn stop_execute_falling_before_rest_completes_the_ramp_then_unlocks() {
    let mut r = Rig::powered();
    r.id(vel(100.0));
    r.steps(100);
    let s = r.id(stop(0.0, 0.0));
    r.step();
    r.cmd(execute(s, false)).unwrap();
    assert_eq!(r.st().motion_state, MotionState::Stopping);
    r.until(1000, |r| r.out(s).done);
    assert_eq!(r.st().set_velo, 0.0);
    r.until(10, |r| r.st().motion_state == MotionState::Standstill);
    assert_eq!(r.out(s), Default::default());
}

#[test]
fn second_stop_takes_over_and_the_first_is_aborted() {
    let mut r = Rig::powered();
    r.id(vel(100.0));
    r.steps(100);
    let s1 = r.id(stop(0.0, 0.0));
    r.step();
    let s2 = r.id(stop(5000.0, 0.0));
    assert!(r.out(s1).command_aborted);
    r.until(1000, |r| r.out(s2).done);
    assert_eq!(r.st().motion_state, MotionState::Stopping);
}

#[test]
fn instantaneous_commands_are_busy_then_done_next_cycle() {
    let mut r = Rig::powered();
    let id = r.id(set_position(3.0));
    assert!(r.out(id).busy && !r.out(id).done);
    r.step();
    assert!(r.out(id).done && !r.out(id).busy);
    let id = r.id(reset());
    assert!(r.out(id).busy);
    r.step();
    assert!(r.out(id).done);
}

#[test]
fn unknown_instance_in_set_execute() {
    let mut r = Rig::powered();
    let e = r
        .cmd(execute(motion_core::CmdId(999_999), false))
        .unwrap_err();
    assert_eq!(e.error_id, motion_core::ErrorId::UNKNOWN_OBJECT);
}

#[test]
fn cancel_halts_with_the_commands_dynamics() {
    let mut r = Rig::powered();
    let a = r.id(vel(100.0));
    r.steps(100);
    r.e.cancel(a).unwrap();
    assert!(r.out(a).command_aborted);
    r.until(1000, |r| r.st().motion_state == MotionState::Standstill);
}

#[test]
fn cmd_no_counts_accepted_commands() {
    let mut r = Rig::powered();
    let n0 = r.st().cmd_no;
    r.id(abs(10.0, 10.0));
    r.id(abs(20.0, 10.0));
    let _ = r.cmd(abs(f64::NAN, 10.0));
    assert_eq!(r.st().cmd_no, n0.wrapping_add(2));
}

#[test]
fn read_status_flags() {
    let mut r = Rig::powered();
    r.id(abs(100.0, 100.0));
    r.steps(10);
    let rs = || AxisCommand::ReadStatus(ReadStatus { axis: AX.into() });
    let s = match r.cmd(rs()).unwrap().value {
        ReplyValue::Status(s) => s,
        v => panic!("{v:?}"),
    };
    assert!(s.accelerating() && !s.decelerating() && !s.constant_velocity());
    r.steps(300);
    let s = r.st();
    assert!(s.constant_velocity() && !s.accelerating());
    r.until(2000, |r| r.st().decelerating());
    r.until(2000, |r| !r.st().has_job);
    let s = r.st();
    assert!(!s.accelerating() && !s.decelerating() && !s.constant_velocity());
    match r
        .cmd(AxisCommand::ReadActualPosition(ReadActualPosition {
            axis: AX.into(),
        }))
        .unwrap()
        .value
    {
        ReplyValue::Real(p) => assert_eq!(p, 100.0),
        v => panic!("{v:?}"),
    }
}

#[test]
fn power_reply_carries_status() {
    let mut r = Rig::new();
    let first = r
        .power_full(true, true, true, 100.0, BufferMode::Aborting)
        .unwrap();
    assert_eq!(
        first.value,
        ReplyValue::Bool(false),
        "Status becomes TRUE in the next cycle"
    );
    r.step();
    let again = r
        .power_full(true, true, true, 100.0, BufferMode::Aborting)
        .unwrap();
    assert_eq!(again.value, ReplyValue::Bool(true));
}
