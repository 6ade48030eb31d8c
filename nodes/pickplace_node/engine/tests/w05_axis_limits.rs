//! pick_and_place.md §19 W5 — "axis limits".
#![allow(clippy::needless_range_loop)]
mod common;
use common::*;
use pickplace_engine::{PickPlaceCommand, TmState};

#[test]
fn w5_axis_limits_reduce_path_velocity() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.target_pos[0] = 60.0;
        p.target_pos[1] = 80.0;
        p.target_pos[2] = 100.0;
        p.path_vel = 50.0;
        p.path_acc = 500.0;
        p.path_dec = 500.0;
        p.max_vel[0] = 20.0;
        p.max_vel[1] = 20.0;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(6000, |s| s.state == TmState::Ready && s.outputs.done);
    let t0 = c.motion_start();
    let end = c.trace.iter().position(|s| s.outputs.in_target).unwrap();
    // T = 100/25 + 25/500 + 500/100000 = 4.055 s.
    assert_close("T", c.t(end), 4.055, 0.005);
    let peak = c.trace[t0..=end]
        .iter()
        .map(|s| s.outputs.set_path_vel_out)
        .fold(0.0, f64::max);
    assert_close("plateau path velocity", peak, 25.0, 0.05);
    let vx = c.trace[t0..=end]
        .iter()
        .map(|s| s.tcp_velocity[0].abs())
        .fold(0.0, f64::max);
    let vy = c.trace[t0..=end]
        .iter()
        .map(|s| s.tcp_velocity[1].abs())
        .fold(0.0, f64::max);
    assert_close("peak |vX|", vx, 15.0, 0.05);
    assert_close("peak |vY|", vy, 20.0, 0.05);
    assert!(vy <= 20.05);
    assert_close(
        "alrActVel[1] at plateau",
        c.at(2.0).outputs.act_vel[0],
        15.0,
        0.05,
    );
}

#[test]
fn axis_ref_limits_of_the_group_slow_the_path_down() {
    // §7.8 (2): AXIS_REF max velocity of Y (config) = 20 with the TM limits off.
    let mut cfg = common_config();
    cfg.axes.insert(
        "y".into(),
        pickplace_engine::AxisConfig {
            max_vel: 20.0,
            ..Default::default()
        },
    );
    let mut c = Cell::ready(cfg);
    c.set_par(|p| {
        p.target_pos[0] = 60.0;
        p.target_pos[1] = 80.0;
        p.target_pos[2] = 100.0;
        p.path_vel = 50.0;
        p.path_acc = 500.0;
        p.path_dec = 500.0;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(6000, |s| s.state == TmState::Ready && s.outputs.done);
    let vy = c
        .trace
        .iter()
        .map(|s| s.tcp_velocity[1].abs())
        .fold(0.0, f64::max);
    assert_close("peak |vY|", vy, 20.0, 0.05);
    let peak = c
        .trace
        .iter()
        .map(|s| s.outputs.set_path_vel_out)
        .fold(0.0, f64::max);
    assert_close("path velocity", peak, 25.0, 0.05);
}

#[test]
fn set_target_above_five_is_90005_even_if_the_belt_is_configured() {
    let mut cfg = common_config();
    cfg.belts.insert(
        "6".into(),
        pickplace_engine::BeltConfig {
            params: w8_belt(),
            ..Default::default()
        },
    );
    let mut c = Cell::ready(cfg);
    c.cmd(PickPlaceCommand::Execute { set_target: 6 });
    c.steps(5);
    assert_eq!(c.last().state, TmState::Error);
    assert_eq!(c.last().outputs.error_id, 90005);
}
