//! pick_and_place.md §19 W13 — "software limit".
#![allow(clippy::needless_range_loop)]
mod common;
use common::*;
use pickplace_engine::{AxisConfig, PickPlaceCommand, TmState};

#[test]
fn w13_sw_limit_stops_axes_individually_20306() {
    let mut cfg = common_config();
    cfg.axes.insert(
        "x".into(),
        AxisConfig {
            sw_limit_pos: 250.0,
            sw_limit_neg: -1000.0,
            sw_limit_enabled: true,
            ..Default::default()
        },
    );
    let mut c = Cell::ready(cfg);
    c.set_par(|p| {
        p.target_pos[0] = 300.0;
        p.target_pos[2] = 100.0;
        p.stop_dec[0] = 10000.0;
        p.stop_jerk[0] = 100000.0;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(5000, |s| s.state == TmState::Error);
    c.steps(200);
    let s = c.last();
    assert_close("X at standstill", s.tcp[0], 253.16, 0.3);
    assert_eq!(s.state, TmState::Error);
    assert_eq!(s.outputs.error_id, 20306);
    assert!(s.outputs.sw_limit_switch_active);
    assert!(s.outputs.sw_limit_switch_active_axes[0]);
    assert!(s.outputs.error_info[0].error && s.outputs.error_info[0].error_id == 20306);
    assert_eq!(s.tcp_velocity[0], 0.0);
    // Reset at standstill → READY; motion back inside the range is allowed.
    c.cmd(PickPlaceCommand::ResetError);
    c.steps(2);
    assert_eq!(c.last().state, TmState::Ready);
    assert!(
        c.last().outputs.sw_limit_switch_active_axes[0],
        "still beyond the limit"
    );
    c.set_par(|p| p.target_pos[0] = 100.0);
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(5000, |s| s.state == TmState::Ready && s.outputs.done);
    assert_close("back", c.last().tcp[0], 100.0, 1e-9);
    assert!(!c.last().outputs.sw_limit_switch_active);
}

#[test]
fn sw_limit_negative_20307() {
    let mut cfg = common_config();
    cfg.axes.insert(
        "y".into(),
        AxisConfig {
            sw_limit_pos: 1000.0,
            sw_limit_neg: -50.0,
            sw_limit_enabled: true,
            ..Default::default()
        },
    );
    let mut c = Cell::ready(cfg);
    c.set_par(|p| {
        p.target_pos[1] = -100.0;
        p.target_pos[2] = 100.0;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(5000, |s| s.state == TmState::Error);
    assert_eq!(c.last().outputs.error_id, 20307);
    assert!(c.last().outputs.sw_limit_switch_active_axes[1]);
}

#[test]
fn hw_limit_switch_20500_20501() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.target_pos[0] = 300.0;
        p.target_pos[2] = 100.0;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.steps(500);
    let mut pos = [false; 18];
    pos[0] = true;
    c.cmd(PickPlaceCommand::SimSetDigitalInputs {
        hw_limit_pos: pos,
        hw_limit_neg: [false; 18],
        home_switch: [false; 12],
        enable_hw_limit: true,
    });
    c.until(10, |s| s.state == TmState::Error);
    let s = c.last();
    assert_eq!(s.outputs.error_id, 20500);
    assert!(s.outputs.hw_limit_switch_active && s.outputs.hw_limit_switch_pos[0]);
    c.steps(100);
    assert_eq!(c.last().tcp_velocity[0], 0.0);
    // Evaluation disabled: switches are ignored.
    c.cmd(PickPlaceCommand::SimSetDigitalInputs {
        hw_limit_pos: [false; 18],
        hw_limit_neg: [false; 18],
        home_switch: [false; 12],
        enable_hw_limit: false,
    });
    c.cmd(PickPlaceCommand::ResetError);
    c.steps(3);
    assert_eq!(c.last().state, TmState::Ready);
    let mut neg = [false; 18];
    neg[2] = true;
    c.cmd(PickPlaceCommand::SimSetDigitalInputs {
        hw_limit_pos: [false; 18],
        hw_limit_neg: neg,
        home_switch: [false; 12],
        enable_hw_limit: false,
    });
    c.steps(3);
    assert_eq!(c.last().state, TmState::Ready);
    c.cmd(PickPlaceCommand::SimSetDigitalInputs {
        hw_limit_pos: [false; 18],
        hw_limit_neg: neg,
        home_switch: [false; 12],
        enable_hw_limit: true,
    });
    c.steps(3);
    assert_eq!(c.last().outputs.error_id, 20501);
}

#[test]
fn injected_following_error_90011() {
    let mut c = Cell::ready(common_config());
    c.cmd(PickPlaceCommand::SimInjectFault {
        axis: 2,
        kind: pickplace_engine::FaultKind::FollowingError,
    });
    c.step();
    assert_eq!(c.last().state, TmState::Error);
    assert_eq!(c.last().outputs.error_id, 90011);
    assert!(c.last().outputs.error_info[1].error);
}

#[test]
fn drive_lag_and_following_error_limit_90011() {
    // §2.1: optional first-order lag; following error above the limit → ERROR 90011.
    let mut cfg = common_config();
    cfg.axes.insert(
        "x".into(),
        AxisConfig {
            lag_time_constant: 0.01,
            following_error_limit: 0.5,
            ..Default::default()
        },
    );
    let mut c = Cell::ready(cfg);
    c.set_par(|p| {
        p.target_pos[0] = 300.0;
        p.target_pos[2] = 100.0;
        p.path_vel = 20.0; // lag error ≈ v·τ = 0.2 < 0.5
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.steps(2000);
    assert_eq!(c.last().state, TmState::MovePp);
    let lag = c.last().tcp[0] - c.last().outputs.act_pos[0];
    assert_close("following error at 20 units/s", lag, 0.2, 0.01);
    assert_close("alrActVel[1]", c.last().outputs.act_vel[0], 20.0, 0.05);
    // Faster: v·τ = 1.0 > 0.5.
    c.cmd(PickPlaceCommand::SetStopInputs(
        pickplace_engine::StopInputs {
            path_halt: Some(true),
            ..Default::default()
        },
    ));
    c.until(2000, |s| !s.outputs.busy);
    c.cmd(PickPlaceCommand::SetStopInputs(
        pickplace_engine::StopInputs {
            path_halt: Some(false),
            ..Default::default()
        },
    ));
    c.step();
    c.cmd(PickPlaceCommand::Abort);
    c.steps(2);
    c.set_par(|p| p.path_vel = 100.0);
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(3000, |s| s.state == TmState::Error);
    assert_eq!(c.last().outputs.error_id, 90011);
    assert!(c.last().outputs.error_info[0].error);
}
