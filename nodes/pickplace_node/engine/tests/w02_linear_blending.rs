//! pick_and_place.md §19 W2 — "linear, r = 20 (blending)".
#![allow(clippy::needless_range_loop)]
mod common;
use common::*;
use pickplace_engine::{PickPlaceCommand, TmState};

fn dist(a: &[f64; 7], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

#[test]
fn w2_linear_blending_r20() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.target_pos[0] = 200.0;
        p.target_pos[2] = 50.0;
        p.target_pos[5] = 90.0;
        p.z_start_dist = 50.0;
        p.z_target_dist = 30.0;
        p.blending_radius = 20.0;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(4000, |s| s.state == TmState::Ready && s.outputs.done);
    let t0 = c.motion_start();
    let end = c.trace.iter().position(|s| s.outputs.in_target).unwrap();
    // Single profile T = 2.8867 s.
    assert_close("T", c.t(end), 2.8867, 0.005);
    assert_close(
        "lrPreCalcProfileTime",
        c.trace[t0].outputs.pre_calc_profile_time,
        2.8867,
        0.001,
    );
    // Path velocity > 0 for 0 < t < T, = 100 between 0.11 s and T − 0.11 s.
    for i in t0..end {
        let v = c.trace[i].outputs.set_path_vel_out;
        assert!(v > 0.0, "path velocity {v} at t = {}", c.t(i));
        let t = c.t(i);
        if t > 0.111 && t < 2.8867 - 0.111 {
            assert_close(&format!("plateau at t = {t}"), v, 100.0, 1e-6);
        }
    }
    // Closest approach to IP1 = 8.156, to IP2 = 4.340 (± 0.05).
    let d1 = c.trace[t0..=end]
        .iter()
        .map(|s| dist(&s.tcp, [0.0, 0.0, 150.0]))
        .fold(f64::MAX, f64::min);
    let d2 = c.trace[t0..=end]
        .iter()
        .map(|s| dist(&s.tcp, [200.0, 0.0, 80.0]))
        .fold(f64::MAX, f64::min);
    assert_close("closest approach IP1", d1, 8.156, 0.05);
    assert_close("closest approach IP2", d2, 4.340, 0.05);
    // Path length 277.673 (sum of chords of the 1 ms samples).
    let mut arc = vec![0.0];
    for i in t0..=end {
        let (a, b) = (&c.trace[i - 1].tcp, &c.trace[i].tcp);
        arc.push(arc.last().unwrap() + dist(a, [b[0], b[1], b[2]]));
    }
    assert_close("path length", *arc.last().unwrap(), 277.673, 0.05);
    // C = 0 until (0, 0, 130) going up, C = 90 from (200, 0, 65) going down, linear in arc
    // length in the window [30, 262.673].
    for (k, i) in (t0 - 1..=end).enumerate() {
        let s = &c.trace[i];
        let a = arc[k];
        if s.tcp[0] < 1e-9 && s.tcp[2] < 130.0 - 0.01 {
            assert_eq!(s.tcp[5], 0.0, "C before the window at Z = {}", s.tcp[2]);
        }
        if s.tcp[0] > 200.0 - 1e-9 && s.tcp[2] < 65.0 - 0.01 {
            assert_close("C after the window", s.tcp[5], 90.0, 1e-9);
        }
        if a > 30.5 && a < 262.0 {
            assert_close(
                &format!("C at arc {a}"),
                s.tcp[5],
                90.0 * (a - 30.0) / 232.673,
                0.1,
            );
        }
    }
}
