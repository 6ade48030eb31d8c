//! pick_and_place.md §19 W9 — "waiting at the park position".
#![allow(clippy::needless_range_loop)]
mod common;
use common::*;
use pickplace_engine::{PickPlaceCommand, TmState};

#[test]
fn w9_waits_at_park_until_the_workpiece_is_reachable() {
    let park = [-400.0, 500.0, 300.0, 180.0, 0.0, 180.0, 0.0];
    let mut c = belt_cell(100.0, park);
    c.cmd(PickPlaceCommand::BeltInput {
        belt: 1,
        receive: true,
        valid_pos: true,
        initial_object_position: [100.0, -50.0, 10.0, 0.0, 0.0, 0.0],
        aux1_target_pos: 0.0,
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 1 });
    c.step();
    let rx = c.trace.len() - 1;
    c.until(5000, |s| s.outputs.in_target);
    let moved = c.trace.iter().position(|s| s.tcp != park).unwrap();
    // Stays at the park pose, xInParkPos, MOVE_PP, until x_b = 200 (t_rx + 1.000 s).
    for s in &c.trace[rx + 5..moved] {
        assert!(
            s.outputs.in_park_pos,
            "cycle {} state {:?} moved {} {:?}",
            s.cycle, s.state, moved, s.active_profile
        );
        assert_eq!(s.state, TmState::MovePp);
    }
    let t_move = (moved - rx) as f64 * TS;
    assert!(t_move >= 1.000 - 1e-9, "moved at t_rx + {t_move}");
    assert!(
        t_move <= 1.000 + 25.0 * TS + 1e-9,
        "moved at t_rx + {t_move}"
    );
    assert!(!c.trace[moved].outputs.in_park_pos);
    // The pick itself then lands on the workpiece.
    let hit = c.trace.len() - 1;
    let x_b = 100.0 + c.trace[hit].belts[0].position - c.trace[rx].belts[0].position;
    assert_close("TCP X at xInTarget", c.trace[hit].tcp[0], 400.0 - x_b, 0.1);
    assert_close("TCP Z at xInTarget", c.trace[hit].tcp[2], 110.0, 0.1);
}

#[test]
fn no_workpiece_goes_to_park_first() {
    // Mode 0 with a belt target and no visible workpiece: move to the park pose and wait.
    let mut c = belt_cell(100.0, [0.0, 550.0, 200.0, 180.0, 0.0, 180.0, 0.0]);
    c.set_par(|p| p.z_dist_elliptical = 20.0);
    c.cmd(PickPlaceCommand::Execute { set_target: 1 });
    c.until(10000, |s| s.outputs.in_park_pos);
    let s = c.last();
    for (q, want) in [-400.0, 500.0, 300.0].iter().enumerate() {
        assert_close("park", s.tcp[q], *want, 1e-6);
    }
    assert_eq!(s.state, TmState::MovePp);
    c.steps(200);
    assert!(c.last().outputs.in_park_pos && c.last().state == TmState::MovePp);
    // A workpiece arrives inside the working area: the TCP leaves and picks it.
    c.cmd(PickPlaceCommand::DetectWorkpiece {
        belt: 1,
        position: [300.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        valid_delay_cycles: 2,
    });
    c.step();
    let rx = c.trace.len() - 1;
    c.until(10000, |s| s.outputs.in_target);
    let hit = c.trace.len() - 1;
    let x_b = 300.0 + c.trace[hit].belts[0].position - c.trace[rx].belts[0].position;
    assert_close("X at pick", c.trace[hit].tcp[0], 400.0 - x_b, 0.1);
    assert_close("Y at pick", c.trace[hit].tcp[1], 500.0, 0.1);
    assert_close("Z at pick", c.trace[hit].tcp[2], 100.0, 0.1);
}
