//! Part 4 group state machine (plcopen_platform.md §5, proposal): every transition of the
//! group states GROUP_DISABLED / STANDBY / MOVING / STOPPING / ERROR_STOP, row by row, and
//! the refusals (4901 ERR_SIM_TRANSITION_NOT_ALLOWED) of every state.
mod p4rig;
use axis_engine::group::*;
use axis_engine::*;
use motion_core::{CommandState, ErrorId};
use p4rig::*;

const E4901: ErrorId = ErrorId(4901);

#[test]
fn disabled_until_all_members_are_powered_then_standby() {
    let mut r = P4::xy();
    r.step();
    assert_eq!(r.gs().state, GroupState::Disabled, "no member powered");
    r.power("x", true).unwrap();
    r.step();
    assert_eq!(r.gs().state, GroupState::Disabled, "y not powered");
    r.power("y", true).unwrap();
    r.step();
    assert_eq!(r.gs().state, GroupState::Standby, "all members powered");
    r.power("y", false).unwrap();
    r.step();
    assert_eq!(r.gs().state, GroupState::Disabled, "member powered off");
}

#[test]
fn disabled_refuses_motion_halt_stop_with_4901() {
    let mut r = P4::xy();
    r.step();
    assert_eq!(err(r.g(lin_abs(vec![1.0, 1.0], 10.0))), E4901);
    assert_eq!(err(r.g(ghalt())), E4901);
    assert_eq!(err(r.g(gstop())), E4901);
    assert_eq!(r.gs().state, GroupState::Disabled);
}

#[test]
fn standby_to_moving_and_back_to_standby_at_done() {
    let mut r = P4::xy_powered();
    let id = r.gid(lin_abs(vec![30.0, 40.0], 100.0));
    assert_eq!(
        r.gs().state,
        GroupState::Moving,
        "state changes with the command"
    );
    assert!(r.out(id).busy && r.out(id).active);
    r.step();
    assert_eq!(r.ax("x").motion_state, MotionState::SynchronizedMotion);
    r.until(5000, |r| r.out(id).done);
    assert_eq!(r.gs().state, GroupState::Standby);
    assert_eq!(r.ax("x").motion_state, MotionState::Standstill);
    assert_eq!(r.ax("x").set_pos, 30.0);
    assert_eq!(r.ax("y").set_pos, 40.0);
}

#[test]
fn moving_to_moving_new_move_aborts_the_running_one() {
    let mut r = P4::xy_powered();
    let a = r.gid(lin_abs(vec![100.0, 0.0], 100.0));
    r.steps(300);
    let b = r.gid(lin_abs(vec![50.0, 50.0], 100.0));
    assert!(r.out(a).command_aborted, "old move CommandAborted");
    assert_eq!(r.gs().state, GroupState::Moving);
    r.until(10000, |r| r.out(b).done);
    assert_eq!((r.ax("x").set_pos, r.ax("y").set_pos), (50.0, 50.0));
    assert_eq!(r.gs().state, GroupState::Standby);
}

#[test]
fn halt_from_standby_moving_then_standby() {
    let mut r = P4::xy_powered();
    let h = r.gid(ghalt());
    assert_eq!(r.gs().state, GroupState::Moving);
    r.step();
    assert!(r.out(h).done, "at rest: Done in the next cycle");
    assert_eq!(r.gs().state, GroupState::Standby);
}

#[test]
fn halt_while_moving_stays_moving_until_done_then_standby_and_is_path_true() {
    let mut r = P4::xy_powered();
    let m = r.gid(lin_abs(vec![300.0, 400.0], 200.0));
    r.steps(700);
    let h = r.gid(ghalt());
    assert!(r.out(m).command_aborted);
    assert_eq!(r.gs().state, GroupState::Moving);
    let n = r.until(10000, |r| {
        let (x, y) = (r.ax("x").set_pos, r.ax("y").set_pos);
        assert!((x * 4.0 - y * 3.0).abs() < 1e-6, "on the line: {x} {y}");
        r.out(h).done
    });
    assert!(n > 1, "decelerates over several cycles");
    assert_eq!(r.gs().state, GroupState::Standby);
    assert!(r.ax("x").set_pos < 300.0);
    // After a halt the group accepts motion again.
    let m2 = r.gid(lin_abs(vec![0.0, 0.0], 200.0));
    r.until(20000, |r| r.out(m2).done);
}

#[test]
fn stop_stays_stopping_until_done_and_execute_false() {
    let mut r = P4::xy_powered();
    r.gid(lin_abs(vec![300.0, 400.0], 200.0));
    r.steps(500);
    let s = r.gid(gstop());
    assert_eq!(r.gs().state, GroupState::Stopping);
    r.until(10000, |r| r.out(s).done);
    r.steps(5);
    assert_eq!(r.gs().state, GroupState::Stopping, "Execute still TRUE");
    // Every motion is refused while stopping; another stop is accepted.
    assert_eq!(err(r.g(lin_abs(vec![0.0, 0.0], 10.0))), E4901);
    assert_eq!(err(r.g(ghalt())), E4901);
    r.set_execute(s, false);
    r.step();
    assert_eq!(r.gs().state, GroupState::Standby);
}

#[test]
fn stop_from_standby_and_stop_while_stopping() {
    let mut r = P4::xy_powered();
    let s1 = r.gid(gstop());
    assert_eq!(r.gs().state, GroupState::Stopping);
    let s2 = r.gid(gstop());
    assert!(r.out(s1).command_aborted, "taken over before Done");
    r.step();
    assert!(r.out(s2).done);
    r.set_execute(s2, false);
    r.step();
    assert_eq!(r.gs().state, GroupState::Standby);
}

#[test]
fn execute_falling_before_done_releases_at_done() {
    let mut r = P4::xy_powered();
    r.gid(lin_abs(vec![300.0, 400.0], 200.0));
    r.steps(500);
    let s = r.gid(gstop());
    r.set_execute(s, false);
    r.until(10000, |r| r.gs().state == GroupState::Standby);
    assert!(r.when(s, CommandState::Done).is_some());
}

#[test]
fn disable_from_standby_and_moving_then_enable() {
    let mut r = P4::xy_powered();
    r.gid(GroupCommand::GroupDisable { group: G.into() });
    assert_eq!(r.gs().state, GroupState::Disabled);
    assert_eq!(err(r.g(lin_abs(vec![1.0, 1.0], 10.0))), E4901);
    r.gid(GroupCommand::GroupEnable { group: G.into() });
    assert_eq!(r.gs().state, GroupState::Standby);
    let m = r.gid(lin_abs(vec![300.0, 400.0], 200.0));
    r.steps(500);
    r.gid(GroupCommand::GroupDisable { group: G.into() });
    assert!(r.out(m).command_aborted);
    assert_eq!(r.gs().state, GroupState::Disabled);
    // The members brake on their own and come to rest.
    r.until(10000, |r| r.ax("x").motion_state == MotionState::Standstill);
}

#[test]
fn member_error_latches_error_stop_and_reset_returns_to_standby() {
    let mut r = P4::xy_powered();
    let m = r.gid(lin_abs(vec![300.0, 400.0], 200.0));
    r.steps(300);
    r.cmd(inject("y")).unwrap();
    r.step();
    assert_eq!(r.gs().state, GroupState::ErrorStop);
    assert_eq!(
        r.out(m).error_id,
        ErrorId(1),
        "group FB: ErrorID 1 (member error)"
    );
    assert_eq!(r.gs().error_id, ErrorId(1));
    // The healthy member brakes with the group, on the path (group_error_stop.rs).
    r.until(10000, |r| r.ax("x").set_velo == 0.0);
    // Refusals in GROUP_ERROR_STOP.
    assert_eq!(err(r.g(lin_abs(vec![0.0, 0.0], 10.0))), E4901);
    assert_eq!(err(r.g(ghalt())), E4901);
    assert_eq!(err(r.g(gstop())), E4901);
    assert_eq!(
        err(r.g(GroupCommand::GroupEnable { group: G.into() })),
        E4901
    );
    let reset = r.gid(greset());
    r.until(5000, |r| r.out(reset).done);
    r.step();
    assert_eq!(r.ax("y").error_code, 0, "member axis reset with the group");
    assert_eq!(r.gs().state, GroupState::Standby);
    assert_eq!(r.gs().error_id, ErrorId::NONE);
}

#[test]
fn error_at_standstill_latches_until_reset_even_after_axis_reset() {
    let mut r = P4::xy_powered();
    r.cmd(inject("x")).unwrap();
    r.step();
    assert_eq!(r.gs().state, GroupState::ErrorStop);
    r.cmd(AxisCommand::Reset(Reset { axis: "x".into() }))
        .unwrap();
    r.steps(3);
    assert_eq!(r.ax("x").motion_state, MotionState::Standstill);
    assert_eq!(
        r.gs().state,
        GroupState::ErrorStop,
        "latched until MC_GrpReset"
    );
    r.gid(greset());
    r.step();
    assert_eq!(r.gs().state, GroupState::Standby);
}

#[test]
fn reset_in_standby_is_done_and_refused_while_moving() {
    let mut r = P4::xy_powered();
    let id = r.gid(greset());
    r.step();
    assert!(r.out(id).done);
    assert_eq!(r.gs().state, GroupState::Standby);
    r.gid(lin_abs(vec![300.0, 400.0], 200.0));
    assert_eq!(err(r.g(greset())), E4901);
}

#[test]
fn ungroup_while_moving_disables_and_frees_the_members() {
    let mut r = P4::xy_powered();
    let m = r.gid(lin_abs(vec![300.0, 400.0], 200.0));
    r.steps(300);
    r.gid(GroupCommand::UngroupAllAxes { group: G.into() });
    assert!(r.out(m).command_aborted);
    assert_eq!(r.gs().state, GroupState::Disabled);
    assert!(r.gs().axes.is_empty());
    r.until(10000, |r| r.ax("x").motion_state == MotionState::Standstill);
    // Free for single-axis motion now.
    r.id(rel("x", 1.0, 10.0));
}

#[test]
fn membership_changes_in_standby_refused_while_moving() {
    let mut r = P4::xy_powered();
    r.gid(GroupCommand::AddAxisToGroup(AddAxisToGroup {
        group: G.into(),
        axis: "z".into(),
        ident_in_group: 0,
    }));
    assert_eq!(r.gs().axes, vec!["x", "y", "z"]);
    assert_eq!(r.gs().idents, vec![1, 2, 3]);
    r.gid(lin_rel(vec![10.0, 10.0, 10.0], 50.0));
    assert_eq!(
        err(r.g(GroupCommand::RemoveAxisFromGroup(RemoveAxisFromGroup {
            group: G.into(),
            axis: "z".into(),
        }))),
        E4901
    );
    r.until(10000, |r| r.gs().state == GroupState::Standby);
    r.gid(GroupCommand::RemoveAxisFromGroup(RemoveAxisFromGroup {
        group: G.into(),
        axis: "z".into(),
    }));
    assert_eq!(r.gs().axes, vec!["x", "y"]);
}

#[test]
fn member_power_off_while_moving_aborts_and_disables() {
    let mut r = P4::xy_powered();
    let m = r.gid(lin_abs(vec![300.0, 400.0], 200.0));
    r.steps(300);
    r.power("x", false).unwrap();
    r.step();
    assert!(r.out(m).command_aborted);
    assert_eq!(r.gs().state, GroupState::Disabled);
}

#[test]
fn admission_matrix_cells_as_specified() {
    use GroupAdmission::*;
    use GroupFbClass as F;
    use GroupState as S;
    let e = Reject(E4901);
    // (row, state, expected) for the cells the spec fixes (§5 pattern).
    let cases = [
        (F::Move, S::Standby, To(S::Moving)),
        (F::Move, S::Moving, To(S::Moving)),
        (F::Move, S::Disabled, e),
        (F::Move, S::Stopping, e),
        (F::Move, S::ErrorStop, e),
        (F::Stop, S::Standby, To(S::Stopping)),
        (F::Stop, S::Moving, To(S::Stopping)),
        (F::Stop, S::ErrorStop, e),
        (F::Reset, S::ErrorStop, To(S::Standby)),
        (F::Disable, S::Moving, To(S::Disabled)),
        (F::Halt, S::Stopping, e),
        (F::ReadWrite, S::ErrorStop, Keep),
    ];
    for (fb, st, want) in cases {
        assert_eq!(group_admission(fb, st), want, "row {fb:?}, state {st:?}");
    }
}

#[test]
fn stopping_to_error_stop_on_member_error() {
    let mut r = P4::xy_powered();
    r.gid(lin_abs(vec![300.0, 400.0], 200.0));
    r.steps(500);
    let s = r.gid(gstop());
    r.steps(5);
    r.cmd(inject("x")).unwrap();
    r.step();
    assert_eq!(r.gs().state, GroupState::ErrorStop);
    assert_eq!(r.out(s).error_id, ErrorId(1));
}

#[test]
fn stopping_to_disabled_by_group_disable() {
    let mut r = P4::xy_powered();
    r.gid(lin_abs(vec![300.0, 400.0], 200.0));
    r.steps(500);
    let s = r.gid(gstop());
    r.gid(GroupCommand::GroupDisable { group: G.into() });
    assert!(r.out(s).command_aborted);
    assert_eq!(r.gs().state, GroupState::Disabled);
}

#[test]
fn error_stop_to_disabled_by_group_disable_clears_the_group_error() {
    let mut r = P4::xy_powered();
    r.cmd(inject("x")).unwrap();
    r.step();
    assert_eq!(r.gs().state, GroupState::ErrorStop);
    r.gid(GroupCommand::GroupDisable { group: G.into() });
    assert_eq!(r.gs().state, GroupState::Disabled);
    assert_eq!(r.gs().error_id, ErrorId::NONE);
    // A user-disabled group does not latch member errors.
    r.step();
    assert_eq!(r.gs().state, GroupState::Disabled);
    // Re-enabled while the member error persists: the latch comes back.
    r.gid(GroupCommand::GroupEnable { group: G.into() });
    r.step();
    assert_eq!(r.gs().state, GroupState::ErrorStop);
}

#[test]
fn error_stop_to_disabled_by_ungroup() {
    let mut r = P4::xy_powered();
    r.cmd(inject("y")).unwrap();
    r.step();
    r.gid(GroupCommand::UngroupAllAxes { group: G.into() });
    assert_eq!(r.gs().state, GroupState::Disabled);
    assert_eq!(r.gs().error_id, ErrorId::NONE);
}
