//! pick_and_place.md §19 W3 — "ellipse, r = 0, IP1 lower than IP2".
#![allow(clippy::needless_range_loop)]
mod common;
use common::*;
use pickplace_engine::{PickPlaceCommand, TmState};

fn ellipse_setup(c: &mut Cell, r: f64) {
    c.set_par(|p| {
        p.target_pos[0] = 300.0;
        p.target_pos[2] = 140.0;
        p.target_pos[5] = 90.0;
        p.z_start_dist = 20.0;
        p.z_target_dist = 40.0;
        p.path_mode = 1;
        p.z_dist_elliptical = 60.0;
        p.blending_radius = r;
    });
    c.cmd(PickPlaceCommand::Execute { set_target: 0 });
    c.until(6000, |s| s.state == TmState::Ready && s.outputs.done);
}

#[test]
fn w3_ellipse_r0() {
    let mut c = Cell::ready(common_config());
    ellipse_setup(&mut c, 0.0);
    let t0 = c.motion_start();
    let end = c.trace.iter().position(|s| s.outputs.in_target).unwrap();
    // Sub-profiles 0.310 + 4.162 + 0.510 = 4.982 s.
    assert_close("T", c.t(end), 4.982, 0.005);
    assert_close(
        "lrPreCalcProfileTime",
        c.trace[t0].outputs.pre_calc_profile_time,
        4.982,
        0.002,
    );
    // Velocity 0 only at IP1 (0, 0, 120) and IP2 (300, 0, 180).
    let rests: Vec<usize> = (t0..end)
        .filter(|&i| c.trace[i].outputs.set_path_vel_out.abs() < 1e-9)
        .collect();
    assert!(!rests.is_empty());
    for &i in &rests {
        let p = c.trace[i].tcp;
        let at_ip1 = (p[0]).abs() < 0.05 && (p[2] - 120.0).abs() < 0.05;
        let at_ip2 = (p[0] - 300.0).abs() < 0.05 && (p[2] - 180.0).abs() < 0.05;
        assert!(at_ip1 || at_ip2, "path velocity 0 at {p:?}");
    }
    assert_close("stop at IP1", c.t(rests[0]), 0.310, 0.005);
    // Max Z = 240.00 ± 0.05 at X = 150 ± 0.5.
    let top = c.trace[t0..=end]
        .iter()
        .max_by(|a, b| a.tcp[2].total_cmp(&b.tcp[2]))
        .unwrap();
    assert_close("apex Z", top.tcp[2], 240.0, 0.05);
    assert_close("apex X", top.tcp[0], 150.0, 0.5);
    // C at the apex = 51.66 ± 0.2.
    assert_close("C at apex", top.tcp[5], 51.66, 0.2);
    // X crosses 75 going +X: Z = 231.962 ± 0.1.
    let i = (t0..end).find(|&i| c.trace[i].tcp[0] >= 75.0).unwrap();
    assert_close("Z at X = 75", c.trace[i].tcp[2], 231.962, 0.1);
    // The compensation segment is vertical: X stays 0 up to Z = 180.
    for s in &c.trace[t0..i] {
        if s.tcp[2] < 180.0 - 1e-6 {
            assert!(
                s.tcp[0].abs() < 1e-9,
                "left the vertical at Z = {}",
                s.tcp[2]
            );
        }
    }
}
