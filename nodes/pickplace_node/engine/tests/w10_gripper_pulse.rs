//! pick_and_place.md §19 W10 — "gripper pulse".
#![allow(clippy::needless_range_loop)]
mod common;
use common::*;
use pickplace_engine::{PickPlaceCommand, StopInputs, TmState};

fn setup() -> Cell {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.target_pos[0] = 150.0;
        p.target_pos[2] = 100.0;
        p.gripper_closing_time = 0.3;
        p.path_stop_dec = 1000.0;
    });
    c
}

#[test]
fn w10_single_pulse_lead_time_before_the_end() {
    let mut c = setup();
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(3000, |s| s.state == TmState::Ready && s.outputs.done);
    let t0 = c.motion_start();
    let end = c.trace.iter().position(|s| s.outputs.in_target).unwrap();
    assert_close("T", c.t(end), 1.610, 0.005);
    let pulses: Vec<usize> = (0..c.trace.len())
        .filter(|&i| c.trace[i].outputs.pulse_gripper)
        .collect();
    assert_eq!(pulses.len(), 1, "exactly one one-cycle pulse");
    assert_close("pulse time", c.t(pulses[0]), 1.310, 0.002);
    assert!(c.trace[t0..end]
        .iter()
        .all(|s| s.outputs.gripper_ctrl_active));
}

#[test]
fn w10_interrupt_cancels_gripper_control_and_pulses_at_the_end() {
    let mut c = setup();
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(100, |s| s.outputs.set_path_vel_out > 0.0);
    let t0 = c.trace.len() - 1;
    c.steps(499); // xPathInterrupt TRUE at t = 0.5 s
    c.cmd(PickPlaceCommand::SetStopInputs(StopInputs {
        path_interrupt: Some(true),
        ..Default::default()
    }));
    c.steps(500);
    assert_eq!(c.last().state, TmState::PathInterrupt);
    assert!(c.last().outputs.path_hold);
    assert!(!c.last().outputs.gripper_ctrl_active);
    assert_eq!(c.last().outputs.set_path_vel_out, 0.0);
    c.cmd(PickPlaceCommand::SetStopInputs(StopInputs {
        path_interrupt: Some(false),
        ..Default::default()
    }));
    c.until(3000, |s| s.state == TmState::Ready && s.outputs.done);
    let reach = (t0..c.trace.len())
        .find(|&i| (c.trace[i].tcp[0] - 150.0).abs() < 1e-9)
        .unwrap();
    let pulses: Vec<usize> = (0..c.trace.len())
        .filter(|&i| c.trace[i].outputs.pulse_gripper)
        .collect();
    assert_eq!(pulses.len(), 1);
    assert!(
        (pulses[0] as i64 - reach as i64).abs() <= 1,
        "pulse at {} vs target reached at {reach}",
        pulses[0]
    );
    assert!(c.trace[t0 + 500..]
        .iter()
        .all(|s| !s.outputs.gripper_ctrl_active));
}
