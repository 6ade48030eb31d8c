//! pick_and_place.md §19 W1 — "linear, r = 0, profile points and stops".
#![allow(clippy::needless_range_loop)]
mod common;
use common::*;
use pickplace_engine::{PickPlaceCommand, TmState};

#[test]
fn w1_linear_r0_profile_points_and_stops() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.target_pos[0] = 200.0;
        p.target_pos[1] = 0.0;
        p.target_pos[2] = 50.0;
        p.target_pos[5] = 90.0;
        p.z_start_dist = 50.0;
        p.z_target_dist = 30.0;
        p.path_mode = 0;
        p.blending_radius = 0.0;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(4000, |s| s.state == TmState::Ready && s.outputs.done);
    let t0 = c.motion_start();
    let end = c.trace.len() - 1;
    // lrPreCalcProfileTime = 0.610 + 2.229 + 0.410 = 3.249 s.
    let pre = c.trace[t0].outputs.pre_calc_profile_time;
    assert_close("lrPreCalcProfileTime", pre, 3.249, 0.005);
    // End at t = 3.249 with TCP (200, 0, 50, 180, 0, 90).
    let t_end = c.t(c.trace.iter().position(|s| s.outputs.in_target).unwrap());
    assert_close("end time", t_end, 3.249, 0.005);
    let tcp = c.trace[end].tcp;
    for (q, want) in [200.0, 0.0, 50.0, 180.0, 0.0, 90.0].iter().enumerate() {
        assert_close(&format!("final pose[{q}]"), tcp[q], *want, 0.05);
    }
    // Path velocity 0 at IP1 (t = 0.610) and IP2 (t = 2.839), TCP there.
    for (t, ip) in [(0.610, [0.0, 0.0, 150.0]), (2.839, [200.0, 0.0, 80.0])] {
        let s = c.at(t);
        assert!(
            s.outputs.set_path_vel_out.abs() < 0.5,
            "path velocity at t = {t}: {}",
            s.outputs.set_path_vel_out
        );
        for q in 0..3 {
            assert_close(&format!("TCP at t = {t} [{q}]"), s.tcp[q], ip[q], 0.05);
        }
    }
    // C = 0 until t = 0.610; at t = 1.7245 TCP = (100, 0, 115), C = 45 ± 0.1.
    for i in t0..t0 + 600 {
        assert_eq!(
            c.trace[i].tcp[5], 0.0,
            "C moved before IP1 at trace index {i}"
        );
    }
    let mid = c.at(1.7245);
    assert_close("X at 1.7245", mid.tcp[0], 100.0, 0.1);
    assert_close("Z at 1.7245", mid.tcp[2], 115.0, 0.1);
    assert_close("C at 1.7245", mid.tcp[5], 45.0, 0.1);
    // iProfilePointPassed 0 → 1 → 2 → 3.
    let mut seq: Vec<i16> = c.trace[t0..]
        .iter()
        .map(|s| s.outputs.profile_point_passed)
        .collect();
    seq.dedup();
    assert_eq!(seq, vec![0, 1, 2, 3]);
    // xInTarget, xDone TRUE at the end; MOVE_PP → READY.
    assert!(c.trace[end].outputs.in_target && c.trace[end].outputs.done);
    assert!(c.trace[t0..end].iter().any(|s| s.state == TmState::MovePp));
    assert_eq!(c.trace[end].state, TmState::Ready);
}
