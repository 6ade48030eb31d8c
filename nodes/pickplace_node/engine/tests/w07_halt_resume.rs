//! pick_and_place.md §19 W7 — "halt and resume".
#![allow(clippy::needless_range_loop)]
mod common;
use common::*;
use pickplace_engine::{PickPlaceCommand, StopInputs, TmState};

fn halt_at_150(halt_dec: f64) -> Cell {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.target_pos[0] = 300.0;
        p.target_pos[2] = 100.0;
        p.path_halt_dec = halt_dec;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(5000, |s| s.tcp[0] >= 150.0);
    c.cmd(PickPlaceCommand::SetStopInputs(StopInputs {
        path_halt: Some(true),
        ..Default::default()
    }));
    c.until(2000, |s| s.state == TmState::Stop && !s.outputs.busy);
    c
}

#[test]
fn w7a_halt_with_higher_deceleration_and_resume() {
    let mut c = halt_at_150(2000.0);
    // Braking distance 3.5 from the first cycle with X ≥ 150.
    assert_close("standstill X", c.last().tcp[0], 153.5, 0.15);
    assert!(c.last().outputs.path_hold);
    assert_eq!(c.last().state, TmState::Stop);
    c.cmd(PickPlaceCommand::SetStopInputs(StopInputs {
        path_halt: Some(false),
        ..Default::default()
    }));
    c.steps(10);
    assert_eq!(c.last().state, TmState::Ready);
    assert!(c.last().outputs.path_hold);
    let x_hold = c.last().tcp[0];
    assert_eq!(c.last().tcp_velocity[0], 0.0);
    c.trace.clear();
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(3000, |s| s.state == TmState::Ready && s.outputs.done);
    // Remaining 146.5 units in 1.575 s.
    let end = c.trace.iter().position(|s| s.outputs.in_target).unwrap();
    assert_close(
        "resume duration",
        c.t(end),
        (300.0 - x_hold) / 100.0 + 0.11,
        0.005,
    );
    assert_close("resume duration (spec)", c.t(end), 1.575, 0.02);
    assert_close("end X", c.last().tcp[0], 300.0, 1e-9);
    assert!(!c.last().outputs.path_hold);
}

#[test]
fn w7b_halt_with_lower_deceleration_uses_path_deceleration() {
    let c = halt_at_150(100.0);
    assert_close("standstill X", c.last().tcp[0], 155.5, 0.15);
}

#[test]
fn w7c_abort_discards_the_held_path() {
    let mut c = halt_at_150(2000.0);
    c.cmd(PickPlaceCommand::SetStopInputs(StopInputs {
        path_halt: Some(false),
        ..Default::default()
    }));
    c.steps(5);
    c.cmd(PickPlaceCommand::Abort);
    c.steps(2);
    assert_eq!(c.last().state, TmState::Ready);
    assert!(!c.last().outputs.path_hold);
    let x = c.last().tcp[0];
    // A new execute plans a new profile from (153.5, 0, 100) to the current target.
    c.set_par(|p| p.target_pos[0] = 100.0);
    c.trace.clear();
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(3000, |s| s.state == TmState::Ready && s.outputs.done);
    let t0 = c.motion_start();
    assert!(c.trace[t0].tcp[0] < x, "moves back from the hold point");
    assert_close(
        "precalc of new profile",
        c.trace[t0].outputs.pre_calc_profile_time,
        (x - 100.0) / 100.0 + 0.11,
        0.001,
    );
    assert_close("end X", c.last().tcp[0], 100.0, 1e-9);
}

#[test]
fn path_stop_uses_stop_deceleration() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.target_pos[0] = 300.0;
        p.target_pos[2] = 100.0;
        p.path_stop_dec = 10000.0;
        p.path_stop_jerk = 100000.0;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(5000, |s| s.tcp[0] >= 150.0);
    c.cmd(PickPlaceCommand::SetStopInputs(StopInputs {
        path_stop: Some(true),
        ..Default::default()
    }));
    c.until(2000, |s| s.state == TmState::Stop && !s.outputs.busy);
    // d = 10000 > v²·j... v = 100 < d²/j = 1000: triangular, 100·√(100/100000) = 3.162.
    assert_close("standstill X", c.last().tcp[0], 153.162, 0.15);
    assert!(
        c.last().tcp[1].abs() < 1e-12 && (c.last().tcp[2] - 100.0).abs() < 1e-12,
        "path-true"
    );
}
