//! Collision-avoidance step cost (issue 6: ≤ 200 ns per axis per step at 1000 axes in one
//! group on a ring). Reference in the same run: the plain single-axis step of the same number
//! of axes, each running its own move without CA.

use motion_core::Engine;
use std::time::Instant;

pub fn step_cost(counts: &[usize], steps: u64) {
    for (scene, build) in [
        (
            "ring, 300 mm apart",
            axis_engine::bench_ring as fn(usize) -> _,
        ),
        (
            "dense ring, 150 mm apart",
            axis_engine::ca_bench::bench_dense_train,
        ),
    ] {
        scene_cost(scene, build, counts, steps);
    }
}

fn scene_cost(
    scene: &str,
    build: fn(usize) -> axis_engine::AxisEngine,
    counts: &[usize],
    steps: u64,
) {
    for &n in counts {
        let mut e = build(n);
        let mut ev = Vec::with_capacity(4 * n);
        let mut tick = 10_000;
        let t0 = Instant::now();
        for _ in 0..steps {
            super::step(&mut e, &mut tick, &mut ev);
        }
        let per = t0.elapsed().as_secs_f64() / (steps as f64 * n as f64);
        let s = e.snapshot();
        let g = &s.ca_groups[0];
        let moving = g.axes.iter().filter(|a| a.velocity != 0.0).count();
        let limited = g.axes.iter().filter(|a| a.ca_limited).count();
        let violations = g.axes.iter().filter(|a| a.gap_violation).count();
        let plain = super::axis_step_seconds(n, steps);
        println!(
            "CA group step, {scene}: {n:5} axes ({moving} moving, {limited} CA-limited, {violations} gap violations): {:7.1} ns per axis per step | plain single-axis step {:5.1} ns (ratio {:.1}) | target <= 200 ns at 1000 axes",
            per * 1e9,
            plain * 1e9,
            per / plain
        );
    }
}
