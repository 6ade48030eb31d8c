//! pick_and_place.md §19 W8 — "belt frame and moving pick", and picks at several belt speeds.
#![allow(clippy::needless_range_loop)]
mod common;
use common::*;
use pickplace_engine::belt::BeltFrame;
use pickplace_engine::geometry::Vec3;
use pickplace_engine::{PickPlaceCommand, TmState};

#[test]
fn w8_belt_frame_transform() {
    let f = BeltFrame::from_par(&w8_belt());
    let p = f.to_mcs(Vec3::new(210.0, -50.0, 10.0));
    assert!((p - Vec3::new(190.0, 550.0, 110.0)).norm() < 1e-9, "{p}");
    let p = f.to_mcs(Vec3::new(310.0, -50.0, 10.0));
    assert!((p - Vec3::new(90.0, 550.0, 110.0)).norm() < 1e-9, "{p}");
}

/// Receive + valid + execute in one cycle; returns (cell, trace index of the receive cycle).
fn pick(velocity: f64, x0: f64) -> (Cell, usize) {
    let mut c = belt_cell(velocity, [0.0, 550.0, 200.0, 180.0, 0.0, 180.0, 0.0]);
    c.cmd(PickPlaceCommand::BeltInput {
        belt: 1,
        receive: true,
        valid_pos: true,
        initial_object_position: [x0, -50.0, 10.0, 0.0, 0.0, 0.0],
        aux1_target_pos: 0.0,
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 1 });
    c.step();
    let rx = c.trace.len() - 1;
    c.until(5000, |s| s.outputs.in_target);
    c.until(5000, |s| s.state == TmState::Ready && s.outputs.done);
    (c, rx)
}

fn check_pick(velocity: f64, x0: f64) {
    let (c, rx) = pick(velocity, x0);
    let belt_at = |i: usize| c.trace[i].belts[0].position - c.trace[rx].belts[0].position;
    // At the rising edge of xInTarget the TCP equals the workpiece: (400 − x_b, 550, 110) ± 0.1.
    let hit = c.trace.iter().position(|s| s.outputs.in_target).unwrap();
    let x_b = x0 + belt_at(hit);
    let tcp = c.trace[hit].tcp;
    assert_close("TCP X at xInTarget", tcp[0], 400.0 - x_b, 0.1);
    assert_close("TCP Y at xInTarget", tcp[1], 550.0, 0.1);
    assert_close("TCP Z at xInTarget", tcp[2], 110.0, 0.1);
    assert!((200.0..=800.0).contains(&x_b), "x_b at pick = {x_b}");
    // During the 0.2 s dwell: TCP velocity = (−v, 0, 0) ± 0.5 and xSynchronised.
    let dwell_end = hit + 200;
    for i in hit + 1..dwell_end {
        let s = &c.trace[i];
        assert!(
            s.outputs.synchronised,
            "xSynchronised at dwell cycle {}",
            i - hit
        );
        assert_close("vX during dwell", s.tcp_velocity[0], -velocity, 0.5);
        assert_close("vY during dwell", s.tcp_velocity[1], 0.0, 0.5);
        assert_close("vZ during dwell", s.tcp_velocity[2], 0.0, 0.5);
        let x_b = x0 + belt_at(i);
        assert_close("TCP follows the workpiece", s.tcp[0], 400.0 - x_b, 0.05);
    }
    // The profile (and xDone) completes when the dwell has ended.
    let done = c.trace.iter().position(|s| s.outputs.done).unwrap();
    assert!(
        (done as i64 - dwell_end as i64).abs() <= 1,
        "done at {done}, dwell end {dwell_end}"
    );
    // Orientation of a belt target: C = belt C + workpiece C = 180, A = 180.
    assert_close("C", tcp[5], 180.0, 1e-9);
    assert_close("A", tcp[3], 180.0, 1e-9);
    // The coupling: xAccDecSync during the approach, the TCP never jumps.
    assert!(c.trace.iter().any(|s| s.outputs.acc_dec_sync));
    for w in c.trace.windows(2) {
        let d = ((w[1].tcp[0] - w[0].tcp[0]).powi(2)
            + (w[1].tcp[1] - w[0].tcp[1]).powi(2)
            + (w[1].tcp[2] - w[0].tcp[2]).powi(2))
        .sqrt();
        assert!(
            d <= (500.0 + velocity) * TS * 1.05,
            "jump of {d} in one cycle"
        );
    }
}

#[test]
fn w8_moving_pick_at_100() {
    check_pick(100.0, 210.0);
}

#[test]
fn moving_picks_at_several_belt_speeds() {
    for v in [0.0, 20.0, 50.0, 150.0, 250.0, 400.0] {
        check_pick(v, 210.0);
    }
}

#[test]
fn w8_after_the_dwell_the_tcp_stays_synchronised() {
    let (mut c, _) = pick(100.0, 210.0);
    c.steps(100);
    let s = c.last();
    assert_eq!(s.state, TmState::Ready);
    assert!(s.outputs.synchronised);
    assert_close("vX bound", s.tcp_velocity[0], -100.0, 1e-6);
}

#[test]
fn belt_speed_change_during_the_approach_is_absorbed_by_the_coupling() {
    let mut c = belt_cell(100.0, [0.0, 550.0, 200.0, 180.0, 0.0, 180.0, 0.0]);
    c.cmd(PickPlaceCommand::BeltInput {
        belt: 1,
        receive: true,
        valid_pos: true,
        initial_object_position: [210.0, -50.0, 10.0, 0.0, 0.0, 0.0],
        aux1_target_pos: 0.0,
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 1 });
    c.step();
    let rx = c.trace.len() - 1;
    c.steps(100);
    // The belt slows down after the plan was made: the prediction is wrong by tens of units.
    c.cmd(PickPlaceCommand::SimSetBeltVelocity {
        belt: 1,
        velocity: 40.0,
        acceleration: 2000.0,
    });
    c.until(5000, |s| s.outputs.in_target);
    let hit = c.trace.len() - 1;
    let x_b = 210.0 + c.trace[hit].belts[0].position - c.trace[rx].belts[0].position;
    assert_close("TCP X at xInTarget", c.trace[hit].tcp[0], 400.0 - x_b, 0.05);
    assert_close("TCP Z at xInTarget", c.trace[hit].tcp[2], 110.0, 0.05);
}

#[test]
fn lift_from_belt_to_static_target_stays_synchronised_first() {
    // §15.4 case 2: belt → static, the lift to IP1 moves with the belt.
    let (mut c, _) = pick(100.0, 210.0);
    c.set_par(|p| {
        p.target_pos = [0.0, 550.0, 200.0, 180.0, 0.0, 180.0, 0.0];
        p.z_target_dist = 50.0;
    });
    c.trace.clear();
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(5000, |s| s.state == TmState::Ready && s.outputs.done);
    let t0 = c.motion_start();
    // First cycles of the lift: X keeps moving with the belt (−100 units/s), Z rises.
    for s in &c.trace[t0..t0 + 20] {
        assert_close("vX at lift start", s.tcp_velocity[0], -100.0, 0.5);
        assert!(s.outputs.synchronised);
    }
    assert!(c.trace[t0 + 20].tcp[2] > 110.0);
    let end = c.last().tcp;
    for (q, want) in [0.0, 550.0, 200.0].iter().enumerate() {
        assert_close("static target", end[q], *want, 1e-6);
    }
}

#[test]
fn deterministic_replay() {
    let (a, _) = pick(100.0, 210.0);
    let (b, _) = pick(100.0, 210.0);
    assert_eq!(a.trace, b.trace);
}
