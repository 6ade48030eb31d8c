//! collision_avoidance.md §4.2: the group state machine, one test per transition row
//! (T1 … T17) plus the rules attached to the states.

mod ca_common;
use axis_engine::ca::types::errors::*;
use axis_engine::ca::*;
use axis_engine::{AxisCommand, Sim};
use ca_common::*;
use motion_core::{CommandState, Engine, ErrorId};

use GroupState::*;

fn two() -> CaRig {
    CaRig::ungrouped(&[("A", 0.0), ("B", 500.0)], open(5000.0))
}

fn enabled_two() -> CaRig {
    let mut r = two();
    r.add("A", 1).unwrap();
    r.add("B", 2).unwrap();
    r.enable();
    r.step();
    r
}

fn inject(r: &mut CaRig, axis: &str, id: u32) {
    r.e.command(AxisCommand::Sim(Sim::InjectAxisError {
        axis: axis.into(),
        error_id: id,
    }))
    .unwrap();
}

fn stop(r: &mut CaRig, execute: bool) -> motion_core::CmdId {
    r.ok(CaCommand::GroupStop {
        group: G.into(),
        execute,
        deceleration: McLreal::Unset,
        jerk: McLreal::Unset,
    })
}

#[test]
fn t1_enable_with_all_loops_closed_is_standby() {
    let mut r = two();
    r.add("A", 1).unwrap();
    r.add("B", 2).unwrap();
    assert_eq!(r.state(), GroupDisabled);
    let id = r.enable();
    assert_eq!(r.state(), GroupStandby);
    r.step();
    assert_eq!(r.cmd_state(id), CommandState::Done);
    assert!(r.group().is_enable_requested);
}

#[test]
fn t2_enable_with_an_open_loop_is_not_ready() {
    let mut r = two();
    r.add("A", 1).unwrap();
    r.add("B", 2).unwrap();
    r.power("B", false);
    r.step();
    r.enable();
    assert_eq!(r.state(), GroupNotReady);
}

#[test]
fn t3_enable_of_an_empty_group_fails_and_stays_disabled() {
    let mut r = two();
    assert_eq!(
        r.err(CaCommand::GroupEnable { group: G.into() }),
        GROUP_EMPTY
    );
    assert_eq!(r.state(), GroupDisabled);
}

#[test]
fn t4_not_ready_becomes_standby_when_all_loops_close() {
    let mut r = two();
    r.add("A", 1).unwrap();
    r.add("B", 2).unwrap();
    r.power("B", false);
    r.step();
    r.enable();
    r.steps(3);
    assert_eq!(r.state(), GroupNotReady);
    r.power("B", true);
    r.steps(3);
    assert_eq!(r.state(), GroupStandby);
}

#[test]
fn t5_open_loop_while_moving_is_error_stop_axis_not_ready() {
    let mut r = enabled_two();
    let a = r.mv_abs("A", 300.0, 1000.0);
    let b = r.mv_abs("B", 3000.0, 1000.0);
    r.steps(100);
    let xa = r.pos("A");
    r.power("A", false);
    r.steps(3);
    assert_eq!(r.state(), GroupErrorStop);
    assert_eq!(r.group().group_error_id, AXIS_NOT_READY.0);
    assert_eq!(r.cmd_state(a), CommandState::Error(AXIS_NOT_READY));
    assert_eq!(r.cmd_state(b), CommandState::Error(AXIS_NOT_READY));
    // The axis without loop froze; the other one brakes (max dynamics) to standstill.
    assert!(
        (r.pos("A") - xa).abs() < 1.0,
        "A froze near {xa}: {}",
        r.pos("A")
    );
    assert_eq!(r.axis("A").velocity, 0.0);
    r.steps(300);
    assert!(r.group().all_axes_standing);
    let id = ErrorId(r.group().group_error_id);
    assert_eq!(id, AXIS_NOT_READY);
}

#[test]
fn t6_accepted_ca_command_makes_standby_moving() {
    let mut r = enabled_two();
    assert_eq!(r.state(), GroupStandby);
    r.mv_abs("B", 600.0, 500.0);
    assert_eq!(r.state(), GroupMoving);
}

#[test]
fn t7_standby_gap_control_starts_establishing_motion() {
    let cfg = CaGroupConfig {
        standby_gap_control: true,
        ..open(5000.0)
    };
    let mut r = CaRig::ungrouped(&[("A", 450.0), ("B", 500.0)], cfg);
    r.add("A", 1).unwrap();
    r.add("B", 2).unwrap();
    r.enable();
    r.steps(2);
    assert_eq!(r.state(), GroupMoving, "establishing motion: Moving");
    r.steps(2000);
    assert!(
        (r.pos("A") - 400.0).abs() < 1e-3,
        "A retreated to 400: {}",
        r.pos("A")
    );
    assert_eq!(r.pos("B"), 500.0, "the predecessor never moves");
    assert_eq!(r.state(), GroupStandby, "T8 after establishing");
}

#[test]
fn t8_moving_returns_to_standby_when_done_and_standing() {
    let mut r = enabled_two();
    let id = r.mv_abs("B", 600.0, 500.0);
    r.until(2000, |r| r.state() == GroupStandby);
    assert_eq!(r.cmd_state(id), CommandState::Done);
    assert!(r.group().all_axes_standing);
    assert_eq!(r.pos("B"), 600.0);
}

#[test]
fn t9_group_stop_from_standby_moving_and_not_ready() {
    let mut r = enabled_two();
    stop(&mut r, true);
    assert_eq!(r.state(), GroupStopping, "from Standby");

    let mut r = enabled_two();
    let m = r.mv_abs("B", 3000.0, 1000.0);
    r.steps(50);
    let s = stop(&mut r, true);
    assert_eq!(r.state(), GroupStopping, "from Moving");
    r.step();
    assert_eq!(
        r.cmd_state(m),
        CommandState::Aborted,
        "all commands aborted"
    );
    assert_eq!(r.cmd_state(s), CommandState::Active);

    let mut r = two();
    r.add("A", 1).unwrap();
    r.add("B", 2).unwrap();
    r.power("B", false);
    r.step();
    r.enable();
    stop(&mut r, true);
    assert_eq!(r.state(), GroupStopping, "from NotReady");
}

#[test]
fn t10_stopping_ends_at_standstill_with_execute_false() {
    let mut r = enabled_two();
    r.mv_abs("B", 3000.0, 1000.0);
    r.steps(200);
    let s = stop(&mut r, true);
    r.until(1000, |r| r.group().all_axes_standing);
    r.step();
    let o = r.out(s);
    assert!(o.done && o.busy && o.active, "Done while held: {o:?}");
    assert_eq!(r.state(), GroupStopping, "held while Execute TRUE");
    assert_eq!(
        r.err(CaCommand::MoveAbsolute(MoveAbsoluteCa {
            axis: "A".into(),
            position: McLreal::Value(10.0),
            velocity: McLreal::Value(10.0),
            ..Default::default()
        })),
        NOT_ALLOWED_IN_GROUP_STATE,
        "nothing executes while Stopping"
    );
    stop(&mut r, false);
    r.step();
    assert_eq!(r.state(), GroupStandby);
}

#[test]
fn t11_disable_from_every_non_error_state() {
    // Standby
    let mut r = enabled_two();
    r.disable();
    assert_eq!(r.state(), GroupDisabled);
    // Moving: instant stop, commands aborted
    let mut r = enabled_two();
    let m = r.mv_abs("B", 3000.0, 1000.0);
    r.steps(100);
    r.disable();
    r.step();
    assert_eq!(r.state(), GroupDisabled);
    assert_eq!(r.cmd_state(m), CommandState::Aborted);
    assert_eq!(r.axis("B").velocity, 0.0, "instant stop");
    // Stopping: the stop is cancelled (CommandAborted)
    let mut r = enabled_two();
    let s = stop(&mut r, true);
    r.disable();
    r.step();
    assert_eq!(r.state(), GroupDisabled);
    assert_eq!(r.cmd_state(s), CommandState::Aborted);
    // NotReady, and MC_UngroupAllAxes
    let mut r = two();
    r.add("A", 1).unwrap();
    r.add("B", 2).unwrap();
    r.power("B", false);
    r.step();
    r.enable();
    r.ok(CaCommand::UngroupAllAxes { group: G.into() });
    assert_eq!(r.state(), GroupDisabled);
    assert_eq!(r.group().group_axes_count, 0);
}

#[test]
fn t12_error_stop_to_error_disabled_by_disable_ungroup_or_last_removal() {
    let mut r = enabled_two();
    inject(&mut r, "A", 0);
    r.steps(2);
    assert_eq!(r.state(), GroupErrorStop);
    r.disable();
    assert_eq!(r.state(), GroupErrorDisabled, "MC_GroupDisable");

    let mut r = enabled_two();
    inject(&mut r, "A", 0);
    r.steps(2);
    r.ok(CaCommand::UngroupAllAxes { group: G.into() });
    assert_eq!(r.state(), GroupErrorDisabled, "MC_UngroupAllAxes");

    let mut r = enabled_two();
    inject(&mut r, "A", 0);
    r.steps(2);
    r.remove(1).unwrap();
    assert_eq!(r.state(), GroupErrorStop, "one axis left");
    r.remove(2).unwrap();
    assert_eq!(r.state(), GroupErrorDisabled, "last axis removed");
}

#[test]
fn t13_axis_error_in_an_enabled_group_is_error_stop_with_its_id() {
    for st in [GroupStandby, GroupMoving, GroupNotReady, GroupStopping] {
        let mut r = two();
        r.add("A", 1).unwrap();
        r.add("B", 2).unwrap();
        if st == GroupNotReady {
            r.power("B", false);
            r.step();
        }
        r.enable();
        r.step();
        let mut cmd = None;
        match st {
            GroupMoving => cmd = Some(r.mv_abs("B", 3000.0, 1000.0)),
            GroupStopping => {
                stop(&mut r, true);
            }
            _ => {}
        }
        r.step();
        assert_eq!(r.state(), st);
        inject(&mut r, "A", 0x4550);
        r.steps(2);
        assert_eq!(r.state(), GroupErrorStop, "from {st:?}");
        assert_eq!(r.group().group_error_id, 0x4550);
        if let Some(c) = cmd {
            assert_eq!(r.cmd_state(c), CommandState::Error(ErrorId(0x4550)));
        }
        let e = r.ca(CaCommand::GroupReadError { group: G.into() }).unwrap();
        assert_eq!(
            e.value,
            axis_engine::ReplyValue::Ca(Box::new(CaValue::GroupErrorId(0x4550)))
        );
    }
}

#[test]
fn t14_axis_error_while_disabled_is_error_disabled() {
    let mut r = two();
    r.add("A", 1).unwrap();
    inject(&mut r, "A", 0x4550);
    r.steps(2);
    assert_eq!(r.state(), GroupErrorDisabled);
    assert_eq!(r.group().group_error_id, 0x4550);
}

#[test]
fn t15_reset_from_error_stop_is_standby_and_clears_axis_errors() {
    let mut r = enabled_two();
    inject(&mut r, "A", 0x4550);
    r.steps(2);
    assert_eq!(r.state(), GroupErrorStop);
    assert_eq!(
        r.err(CaCommand::GroupEnable { group: G.into() }),
        NOT_ALLOWED_IN_GROUP_STATE
    );
    r.reset();
    assert_eq!(r.state(), GroupStandby);
    r.steps(2);
    assert_eq!(r.state(), GroupStandby, "the axis error is gone too");
    assert_eq!(r.group().group_error_id, 0);
    let id = r.mv_abs("B", 600.0, 500.0);
    r.until(2000, |r| r.cmd_state(id) == CommandState::Done);
}

#[test]
fn t16_reset_from_error_disabled_is_disabled() {
    let mut r = two();
    r.add("A", 1).unwrap();
    inject(&mut r, "A", 0x4550);
    r.steps(2);
    assert_eq!(r.state(), GroupErrorDisabled);
    r.reset();
    assert_eq!(r.state(), GroupDisabled);
    r.steps(2);
    assert_eq!(r.state(), GroupDisabled);
}

#[test]
fn t17_removal_of_the_last_axis_disables() {
    for st in [GroupStandby, GroupMoving, GroupNotReady] {
        let mut r = CaRig::ungrouped(&[("A", 0.0)], open(5000.0));
        r.add("A", 1).unwrap();
        if st == GroupNotReady {
            r.power("A", false);
            r.step();
        }
        r.enable();
        if st == GroupMoving {
            // A command that cannot progress (override 0) keeps a standing group Moving.
            r.ok(CaCommand::GroupSetOverride {
                group: G.into(),
                enable: true,
                vel_factor: 0.0,
            });
            r.steps(200);
            r.mv_abs("A", 100.0, 100.0);
            r.steps(10);
            assert!(r.group().all_axes_standing);
        }
        assert_eq!(r.state(), st);
        r.remove(1).unwrap();
        assert_eq!(r.state(), GroupDisabled, "from {st:?}");
    }
}

#[test]
fn reset_outside_error_states_has_no_effect() {
    let mut r = enabled_two();
    let id = r.reset();
    r.step();
    assert_eq!(r.cmd_state(id), CommandState::Done);
    assert_eq!(r.state(), GroupStandby);
}

#[test]
fn motion_commands_need_standby_or_moving() {
    let mut r = two();
    r.add("A", 1).unwrap();
    let c = CaCommand::MoveAbsolute(MoveAbsoluteCa {
        axis: "A".into(),
        position: McLreal::Value(10.0),
        velocity: McLreal::Value(10.0),
        ..Default::default()
    });
    assert_eq!(r.err(c), NOT_ALLOWED_IN_GROUP_STATE, "Disabled");
}

#[test]
fn add_remove_while_moving_only_for_standing_axes() {
    let mut r = CaRig::ungrouped(&[("A", 0.0), ("B", 500.0), ("C", 2000.0)], open(5000.0));
    r.add("A", 1).unwrap();
    r.add("B", 2).unwrap();
    r.enable();
    r.mv_abs("B", 1500.0, 1000.0);
    r.steps(100);
    assert_eq!(r.state(), GroupMoving);
    assert_eq!(r.remove(2).unwrap_err().error_id, AXIS_MOVING);
    r.add("C", 3).unwrap();
    assert_eq!(r.group().group_axes_count, 3);
    assert_eq!(r.group().axes[0].name, "C", "inserted by position");
    r.remove(1).unwrap();
    assert_eq!(r.group().group_axes_count, 2);
    r.remove(99).unwrap(); // never a member: Done
}

#[test]
fn single_axis_motion_on_a_member_only_while_disabled() {
    let mut r = enabled_two();
    let mv = AxisCommand::MoveAbsolute(axis_engine::MoveAbsolute {
        axis: "A".into(),
        position: 10.0,
        velocity: 10.0,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        buffer_mode: axis_engine::BufferMode::Aborting,
        options: Default::default(),
    });
    assert_eq!(
        r.e.command(mv.clone()).unwrap_err().error_id,
        NOT_ALLOWED_IN_GROUP_STATE
    );
    r.disable();
    r.e.command(mv).unwrap();
}

/// Regression (found through the ROS shell): a follower waiting behind its leader with the
/// single-axis default dynamics (A 1000, J 10000) kept a set velocity of ≈ 2e-12 mm/s
/// forever, so AllAxesStanding stayed FALSE and the group GroupMoving. Now it stands exactly.
#[test]
fn waiting_follower_stands_exactly() {
    let cfg = |x: f64| axis_engine::AxisConfig {
        initial_position: x,
        max_velocity: 2000.0,
        fast_acceleration: 20000.0,
        fast_deceleration: 20000.0,
        fast_jerk: 200000.0,
        ..Default::default()
    };
    let mut e =
        axis_engine::AxisEngine::new(vec![("a".into(), cfg(1000.0)), ("b".into(), cfg(500.0))])
            .unwrap();
    e.add_ca_group(G, ring(3000.0)).unwrap();
    let mut r = CaRig {
        e,
        events: Vec::new(),
        tick: 0,
        worst_margin: f64::INFINITY,
        check_gaps: true,
        prev: Vec::new(),
        max_jerk_ratio: 0.0,
    };
    r.power("a", true);
    r.power("b", true);
    r.step();
    r.add("a", 1).unwrap();
    r.add("b", 2).unwrap();
    r.enable();
    r.step();
    let id = r.mv_abs("b", 950.0, 500.0);
    r.steps(5000);
    let b = r.axis("b");
    assert!((b.position - 900.0).abs() < 1e-6, "waits at 900: {b:?}");
    assert_eq!((b.velocity, b.acceleration), (0.0, 0.0), "{b:?}");
    assert_eq!(b.active_command_id, Some(id), "still waiting");
    assert!(r.group().all_axes_standing);
    assert!(r.worst_margin >= -1e-6);
}
