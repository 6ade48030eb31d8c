//! §3.7 Done rules and §1.3 monitoring, §1.4 error reaction, §1.1 override.
mod common;
use axis_engine::*;
use common::*;
use motion_core::CommandState;

#[test]
fn done_20ms_after_the_setpoint_end_with_target_monitoring() {
    let mut r = Rig::powered();
    let a = r.id(abs(10.0, 100.0));
    r.until(2000, |r| !r.st().has_job);
    let end = r.tick - 1; // the cycle in which HasJob fell
    assert!(r.out(a).busy, "not Done before InTargetPosition");
    assert!(!r.st().bit(snapshot::bits::IN_TARGET_POSITION));
    assert!(r.st().bit(snapshot::bits::IN_POSITION_AREA));
    r.until(100, |r| r.out(a).done);
    let done = r.when(a, CommandState::Done).unwrap();
    assert_eq!(
        done - end,
        10,
        "AxisTargetPositionMonitoringTime 0.02 s = 10 cycles of 2 ms"
    );
    assert!(r.st().bit(snapshot::bits::IN_TARGET_POSITION));
}

#[test]
fn done_at_once_without_monitoring_or_with_ignore_option() {
    let cfg = AxisConfig {
        en_target_position_monitoring: false,
        en_position_range_monitoring: false,
        ..Default::default()
    };
    let mut r = Rig::powered_with(cfg);
    let a = r.id(abs(10.0, 100.0));
    r.until(2000, |r| !r.st().has_job);
    assert!(r.out(a).done);
    let mut r = Rig::powered();
    let a = r.id(AxisCommand::MoveAbsolute(MoveAbsolute {
        options: MoveOptions {
            ignore_position_monitoring: true,
            ..Default::default()
        },
        ..move_abs(10.0, 100.0)
    }));
    r.until(2000, |r| !r.st().has_job);
    assert!(r.out(a).done);
}

#[test]
fn only_position_range_monitoring() {
    let cfg = AxisConfig {
        en_target_position_monitoring: false,
        ..Default::default()
    };
    let mut r = Rig::powered_with(cfg);
    r.cmd(AxisCommand::Sim(Sim::SetFollowingOffset {
        axis: AX.into(),
        offset: 3.0,
    }))
    .unwrap();
    let a = r.id(abs(10.0, 100.0));
    r.until(2000, |r| !r.st().has_job);
    assert!(r.out(a).done, "|ActPos − Target| = 3 ≤ 5");
}

#[test]
fn in_target_timeout_ends_with_0x4b07() {
    let cfg = AxisConfig {
        en_in_target_timeout: true,
        in_target_timeout: 0.1,
        ..Default::default()
    };
    let mut r = Rig::powered_with(cfg);
    r.cmd(AxisCommand::Sim(Sim::SetFollowingOffset {
        axis: AX.into(),
        offset: 3.0,
    }))
    .unwrap();
    let a = r.id(abs(10.0, 100.0));
    r.until(3000, |r| r.out(a).error);
    assert_eq!(r.out(a).error_id, err(0x4B07));
    assert_eq!(
        r.st().motion_state,
        MotionState::Standstill,
        "FB error, not an axis error"
    );
}

#[test]
fn position_lag_raises_0x4550_after_the_filter_time() {
    let mut r = Rig::powered();
    let a = r.id(vel(100.0));
    r.steps(10);
    r.cmd(AxisCommand::Sim(Sim::SetFollowingOffset {
        axis: AX.into(),
        offset: -6.0,
    }))
    .unwrap();
    let t0 = r.tick;
    r.until(100, |r| r.st().motion_state == MotionState::ErrorStop);
    let n = r.tick - t0;
    assert!((10..=12).contains(&n), "after 0.02 s: {n} cycles");
    assert_eq!(r.st().error_code, 0x4550);
    assert_eq!(r.out(a).error_id, err(0x4550));
}

#[test]
fn error_reaction_stops_with_fast_dec_and_ends_all_fbs_with_the_axis_error() {
    let mut r = Rig::powered();
    let a = r.id(abs(1000.0, 100.0));
    r.steps(300);
    let b = r.id(abs_bm(0.0, 100.0, BufferMode::Buffered));
    let p0 = r.st().set_pos;
    r.cmd(inject(0x4321)).unwrap();
    assert_eq!(r.st().motion_state, MotionState::ErrorStop);
    for id in [a, b] {
        let o = r.out(id);
        assert!(o.error && o.error_id == err(0x4321), "{o:?}");
    }
    r.until(1000, |r| r.st().set_velo == 0.0);
    // v 100, AxisFastDec 5000, AxisFastJerk 1e5: the deceleration limit is not reached
    // (100 < 5000²/1e5), two jerk phases of √(v/j): 100·√(1e-3) = 3.162 u.
    assert!(
        (r.st().set_pos - p0 - 100.0 * (1e-3f64).sqrt()).abs() < 1e-6,
        "{}",
        r.st().set_pos - p0
    );
    assert_eq!(r.st().motion_state, MotionState::ErrorStop);
    let e = r.cmd(abs(0.0, 10.0)).unwrap_err();
    assert_eq!(e.error_id, err(0x4B01));
}

#[test]
fn drive_fault_stops_at_once_and_reset_recovers() {
    let mut r = Rig::powered();
    r.id(vel(100.0));
    r.steps(100);
    r.cmd(AxisCommand::Sim(Sim::DriveFault {
        axis: AX.into(),
        error_id: 0x4650,
    }))
    .unwrap();
    let st = r.st();
    assert_eq!(st.set_velo, 0.0);
    assert!(!st.power_status);
    assert_eq!(st.motion_state, MotionState::ErrorStop);
    let id = r.id(reset());
    r.step();
    assert!(r.out(id).done);
    assert!(r.st().power_status, "power stage back");
    assert_eq!(r.st().motion_state, MotionState::Standstill);
}

#[test]
fn reset_copies_act_into_set() {
    let mut r = Rig::powered();
    r.cmd(AxisCommand::Sim(Sim::SetFollowingOffset {
        axis: AX.into(),
        offset: 0.25,
    }))
    .unwrap();
    r.step();
    assert_eq!(r.st().pos_diff, -0.25);
    r.id(reset());
    r.step();
    let st = r.st();
    assert_eq!(st.pos_diff, 0.0);
    assert_eq!(st.set_pos, 0.25);
}

#[test]
fn override_scales_velocity_and_zero_pauses() {
    let mut r = Rig::powered();
    let a = r.id(abs(1000.0, 100.0));
    r.steps(200);
    r.power_full(true, true, true, 50.0, BufferMode::Aborting)
        .unwrap();
    r.steps(200);
    assert!((r.st().set_velo - 50.0).abs() < 1e-9);
    r.power_full(true, true, true, 0.0, BufferMode::Aborting)
        .unwrap();
    r.steps(200);
    let st = r.st();
    assert_eq!(st.set_velo, 0.0);
    assert_eq!(
        st.motion_state,
        MotionState::DiscreteMotion,
        "command stays active"
    );
    assert_eq!(st.axis_state, snapshot::axis_state::OVERRIDE_ZERO);
    assert!(r.out(a).active);
    r.power_full(true, true, true, 100.0, BufferMode::Aborting)
        .unwrap();
    r.until(30000, |r| r.out(a).done);
    assert_eq!(r.st().set_pos, 1000.0);
    let e = r
        .power_full(true, true, true, 101.0, BufferMode::Aborting)
        .unwrap_err();
    assert_eq!(e.error_id, err(0x4B06));
    assert_eq!(r.st().override_percent, 100.0, "previous override stays");
}

#[test]
fn override_change_aborts_move_velocity_but_the_axis_keeps_moving() {
    let mut r = Rig::powered();
    let v = r.id(vel(100.0));
    r.steps(200);
    r.power_full(true, true, true, 50.0, BufferMode::Aborting)
        .unwrap();
    let o = r.e.fb_outputs(v).unwrap();
    assert!(o.standard.command_aborted && !o.standard.busy && !o.in_velocity);
    r.steps(200);
    assert!((r.st().set_velo - 50.0).abs() < 1e-9);
    assert_eq!(r.st().motion_state, MotionState::ContinuousMotion);
}

#[test]
fn soft_limit_target_is_rejected() {
    let cfg = AxisConfig {
        en_max_soft_pos_limit: true,
        max_soft_pos_limit: 500.0,
        ..Default::default()
    };
    let mut r = Rig::powered_with(cfg);
    let e = r.cmd(abs(600.0, 100.0)).unwrap_err();
    assert_eq!(e.error_id, err(0x4D01));
    r.id(abs(400.0, 100.0));
}

#[test]
fn endless_motion_stops_exactly_at_the_soft_limit_with_0x4d02() {
    let cfg = AxisConfig {
        en_max_soft_pos_limit: true,
        max_soft_pos_limit: 500.0,
        ..Default::default()
    };
    let mut r = Rig::powered_with(cfg);
    let v = r.id(vel(200.0));
    assert_eq!(r.st().motion_state, MotionState::ContinuousMotion);
    r.until(10000, |r| r.out(v).error);
    assert_eq!(r.out(v).error_id, err(0x4D02));
    let st = r.st();
    assert_eq!(st.set_pos, 500.0);
    assert_eq!(st.set_velo, 0.0);
    assert_eq!(
        st.motion_state,
        MotionState::Standstill,
        "axis stays operational"
    );
    // The other direction is free.
    let b = r.id(AxisCommand::MoveVelocity(move_vel(
        50.0,
        Direction::Negative,
    )));
    r.steps(100);
    assert!(r.out(b).active && r.st().set_velo < 0.0);
}

#[test]
fn first_order_following_model_lags_and_settles() {
    let cfg = AxisConfig {
        following_model: FollowingModel::FirstOrder,
        position_control_kv: 50.0,
        ..Default::default()
    };
    let mut r = Rig::powered_with(cfg);
    let a = r.id(abs(100.0, 100.0));
    let mut max_lag: f64 = 0.0;
    r.until(20000, |r| {
        max_lag = max_lag.max(r.st().pos_diff.abs());
        r.out(a).done
    });
    assert!(max_lag > 1e-6, "a lag appears with the P loop");
    assert!(
        max_lag < 5.0,
        "feed-forward keeps it below the lag limit: {max_lag}"
    );
    let st = r.st();
    assert!(
        (st.act_pos - 100.0).abs() <= 2.0,
        "inside the target window"
    );
    assert_eq!(st.motion_state, MotionState::Standstill);
}

#[test]
fn stop_position_monitoring_option_delays_done_until_in_target() {
    let opts = MoveOptions {
        enable_stop_position_monitoring: true,
        ..Default::default()
    };
    for with in [false, true] {
        let mut r = Rig::powered();
        r.id(vel(100.0));
        r.steps(100);
        let o = if with { opts } else { MoveOptions::default() };
        let h = r.id(AxisCommand::Halt(Halt {
            axis: AX.into(),
            deceleration: 0.0,
            jerk: 0.0,
            buffer_mode: BufferMode::Aborting,
            options: o,
        }));
        r.until(2000, |r| !r.st().has_job);
        let rest = r.tick - 1;
        r.until(100, |r| r.out(h).done);
        let n = r.when(h, CommandState::Done).unwrap() - rest;
        assert_eq!(n, if with { 10 } else { 0 }, "MC_Halt with option {with}");

        let mut r = Rig::powered();
        r.id(vel(100.0));
        r.steps(100);
        let s = r.id(AxisCommand::Stop(Stop {
            axis: AX.into(),
            deceleration: 0.0,
            jerk: 0.0,
            options: o,
        }));
        r.until(2000, |r| !r.st().has_job);
        let rest = r.tick - 1;
        r.until(100, |r| r.out(s).done);
        let n = r.when(s, CommandState::Done).unwrap() - rest;
        assert_eq!(n, if with { 10 } else { 0 }, "MC_Stop with option {with}");
        r.cmd(execute(s, false)).unwrap();
        r.steps(3);
        assert_eq!(r.st().motion_state, MotionState::Standstill);
    }
}

#[test]
fn set_override_has_precedence_over_power() {
    let so = |enable: bool, f: f64| {
        AxisCommand::SetOverride(SetOverride {
            axis: AX.into(),
            enable,
            vel_factor: f,
            acc_factor: 1.0,
            jerk_factor: 1.0,
        })
    };
    let mut r = Rig::powered();
    let a = r.id(abs(10000.0, 100.0));
    r.steps(300);
    r.cmd(so(true, 0.5)).unwrap();
    assert_eq!(r.e.set_override_enabled(AX), Some(true));
    r.steps(300);
    assert!((r.st().set_velo - 50.0).abs() < 1e-9);
    assert_eq!(r.st().override_percent, 50.0);
    r.power_full(true, true, true, 20.0, BufferMode::Aborting)
        .unwrap();
    r.steps(300);
    assert!(
        (r.st().set_velo - 50.0).abs() < 1e-9,
        "MC_Power's override waits"
    );
    let e = r.cmd(so(true, 1.5)).unwrap_err();
    assert_eq!(e.error_id, err(0x4B06));
    assert_eq!(r.st().override_percent, 50.0, "previous value kept");
    r.cmd(so(false, 0.5)).unwrap();
    r.steps(300);
    assert!(
        (r.st().set_velo - 20.0).abs() < 1e-9,
        "MC_Power's value applies again"
    );
    assert!(
        r.out(a).active,
        "a positioning FB is not aborted by an override change"
    );
}
