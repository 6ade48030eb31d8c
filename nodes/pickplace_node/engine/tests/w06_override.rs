//! pick_and_place.md §19 W6 — "override".
#![allow(clippy::needless_range_loop)]
mod common;
use common::*;
use pickplace_engine::{CellEvent, PickPlaceCommand, TmState};

fn run(ov: f64, closing: f64) -> (Cell, Vec<CellEvent>) {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.target_pos[0] = 100.0;
        p.target_pos[2] = 100.0;
        p.path_vel = 50.0;
        p.path_acc = 500.0;
        p.path_dec = 500.0;
        p.gripper_closing_time = closing;
    });
    c.cmd(PickPlaceCommand::SetOverride(ov));
    c.step();
    c.eng.drain_events();
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(8000, |s| s.state == TmState::Ready && s.outputs.done);
    let ev = c.eng.drain_events();
    (c, ev)
}

#[test]
fn w6_override_one() {
    let (c, _) = run(1.0, 0.0);
    let end = c.trace.iter().position(|s| s.outputs.in_target).unwrap();
    assert_close("T(ov = 1)", c.t(end), 2.105, 0.005);
    let peak = c
        .trace
        .iter()
        .map(|s| s.outputs.set_path_vel_out)
        .fold(0.0, f64::max);
    assert_close("plateau", peak, 50.0, 1e-6);
}

#[test]
fn w6_override_half_scales_v_a_j_not_time() {
    let (c, _) = run(0.5, 0.0);
    let end = c.trace.iter().position(|s| s.outputs.in_target).unwrap();
    // 4.105 s, not the pure time scaling 4.21 s.
    assert_close("T(ov = 0.5)", c.t(end), 4.105, 0.005);
    let peak = c
        .trace
        .iter()
        .map(|s| s.outputs.set_path_vel_out)
        .fold(0.0, f64::max);
    assert_close("plateau", peak, 25.0, 1e-6);
    // lrPreCalcProfileTime is at override 1.0.
    assert_close(
        "lrPreCalcProfileTime",
        c.last().outputs.pre_calc_profile_time,
        2.105,
        0.001,
    );
}

#[test]
fn w6_override_deactivates_gripper_control() {
    let (c, ev) = run(0.5, 0.1);
    let t0 = c.motion_start();
    let end = c.trace.iter().position(|s| s.outputs.in_target).unwrap();
    assert!(c.trace[t0..end]
        .iter()
        .all(|s| !s.outputs.gripper_ctrl_active));
    let pulses: Vec<usize> = (t0..c.trace.len())
        .filter(|&i| c.trace[i].outputs.pulse_gripper)
        .collect();
    assert_eq!(pulses, vec![end], "single pulse at the profile end");
    assert_eq!(
        ev.iter()
            .filter(|e| matches!(e, CellEvent::GripperPulse { .. }))
            .count(),
        1
    );
}

#[test]
fn override_change_during_motion_slows_path_and_keeps_target() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.target_pos[0] = 100.0;
        p.target_pos[2] = 100.0;
        p.path_vel = 50.0;
        p.path_acc = 500.0;
        p.path_dec = 500.0;
        p.gripper_closing_time = 0.2;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(400, |s| s.outputs.set_path_vel_out > 49.9);
    assert!(c.last().outputs.gripper_ctrl_active);
    c.cmd(PickPlaceCommand::SetOverride(0.4));
    c.steps(400);
    assert_close("new plateau", c.last().outputs.set_path_vel_out, 20.0, 1e-6);
    assert!(
        !c.last().outputs.gripper_ctrl_active,
        "override change deactivates the gripper control"
    );
    c.until(10000, |s| s.state == TmState::Ready && s.outputs.done);
    assert_close("X at end", c.last().tcp[0], 100.0, 1e-9);
}

#[test]
fn override_out_of_range_is_clamped_with_warning_90015() {
    let mut c = Cell::ready(common_config());
    c.cmd(PickPlaceCommand::SetOverride(1.5));
    c.step();
    assert!(c.last().outputs.warning);
    assert_eq!(c.last().outputs.error_id, 90015);
    c.set_par(|p| {
        p.target_pos[0] = 10.0;
        p.target_pos[2] = 100.0;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(2000, |s| s.state == TmState::Ready && s.outputs.done);
    let peak = c
        .trace
        .iter()
        .map(|s| s.outputs.set_path_vel_out)
        .fold(0.0, f64::max);
    assert!(peak <= 100.0 + 1e-9, "clamped to 1.0: {peak}");
}
