//! pick_and_place.md §19 W4 — "ellipse, r = 10".
#![allow(clippy::needless_range_loop)]
mod common;
use common::*;
use pickplace_engine::{PickPlaceCommand, TmState};

#[test]
fn w4_ellipse_r10() {
    let mut c = Cell::ready(common_config());
    c.set_par(|p| {
        p.target_pos[0] = 300.0;
        p.target_pos[2] = 140.0;
        p.target_pos[5] = 90.0;
        p.z_start_dist = 20.0;
        p.z_target_dist = 40.0;
        p.path_mode = 1;
        p.z_dist_elliptical = 60.0;
        p.blending_radius = 10.0;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(6000, |s| s.state == TmState::Ready && s.outputs.done);
    let t0 = c.motion_start();
    let end = c.trace.iter().position(|s| s.outputs.in_target).unwrap();
    // One profile of length 465.197: T = 4.762 s, no stop at IP1/IP2.
    assert_close("T", c.t(end), 4.762, 0.005);
    for i in t0..end {
        assert!(
            c.trace[i].outputs.set_path_vel_out > 0.0,
            "stopped at t = {}",
            c.t(i)
        );
    }
    // Identical geometry: apex (150, 0, 240), (75, 0, 231.962) on the path.
    let top = c.trace[t0..=end]
        .iter()
        .max_by(|a, b| a.tcp[2].total_cmp(&b.tcp[2]))
        .unwrap();
    assert_close("apex Z", top.tcp[2], 240.0, 0.05);
    assert_close("apex X", top.tcp[0], 150.0, 0.5);
    let i = (t0..end).find(|&i| c.trace[i].tcp[0] >= 75.0).unwrap();
    assert_close("Z at X = 75", c.trace[i].tcp[2], 231.962, 0.1);
    // Orientation window from (0, 0, 110) going up to (300, 0, 170) going down.
    for s in &c.trace[t0..=end] {
        if s.tcp[0].abs() < 1e-9 && s.tcp[2] < 110.0 - 0.01 {
            assert_eq!(s.tcp[5], 0.0);
        }
        if (s.tcp[0] - 300.0).abs() < 1e-9 && s.tcp[2] < 170.0 - 0.01 {
            assert_close("C after window", s.tcp[5], 90.0, 1e-9);
        }
    }
    let first_c = (t0..end).find(|&i| c.trace[i].tcp[5] > 0.0).unwrap();
    assert_close("window start Z", c.trace[first_c].tcp[2], 110.0, 0.15);
    // C at the apex = 51.35 ± 0.2.
    assert_close("C at apex", top.tcp[5], 51.35, 0.2);
}
