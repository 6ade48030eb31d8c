//! pick_and_place.md §17 performance anchor: one `step()` of the cell (identity kinematics,
//! 2 belts with 30 tracked workpieces each, a blended ellipse profile running) must average
//! ≤ 200 µs and stay ≤ 511 µs at the 99.9th percentile. Timing is only meaningful in a release
//! build: `cargo test --release -p pickplace_engine --test perf_step -- --ignored`.
mod common;
use common::*;
use motion_core::{Engine, Tick};
use pickplace_engine::PickPlaceCommand;
use std::time::Instant;

#[test]
#[ignore = "timing; run in release"]
fn step_time_with_two_full_belts_and_an_ellipse() {
    let mut c = two_belt_cell(1.0, 1.0);
    for b in [1u8, 2] {
        for k in 0..30 {
            c.cmd(PickPlaceCommand::DetectWorkpiece {
                belt: b,
                position: [-3000.0 + k as f64, 0.0, 0.0, 0.0, 0.0, 0.0],
                valid_delay_cycles: 0,
            });
        }
    }
    c.steps(100);
    assert_eq!(c.last().belts[0].workpieces.len(), 30);
    assert_eq!(c.last().belts[1].workpieces.len(), 30);
    c.set_par(|p| {
        p.path_mode = 1;
        p.z_dist_elliptical = 60.0;
        p.blending_radius = 10.0;
        p.z_start_dist = 20.0;
        p.z_target_dist = 40.0;
        p.path_vel = 5.0;
        p.target_pos = [300.0, 0.0, 140.0, 180.0, 0.0, 90.0, 0.0];
    });
    let mut events = Vec::new();
    let mut times = Vec::with_capacity(100_000);
    for (tick, k) in (c.tick..).zip(0..100_000u64) {
        if k % 20_000 == 0 {
            c.eng
                .command(PickPlaceCommand::Execute { set_target: 0 })
                .unwrap();
        }
        let t = Instant::now();
        c.eng.step(
            Tick {
                index: tick,
                dt: TS,
            },
            &mut events,
        );
        times.push(t.elapsed().as_secs_f64());
        events.clear();
        c.eng.drain_events();
    }
    assert!(c.eng.snapshot().tcp[0] > 100.0, "the ellipse profile ran");
    times.sort_by(f64::total_cmp);
    let mean = times.iter().sum::<f64>() / times.len() as f64;
    let p999 = times[(times.len() as f64 * 0.999) as usize];
    println!(
        "step: mean {:.1} µs, p99.9 {:.1} µs, max {:.1} µs",
        mean * 1e6,
        p999 * 1e6,
        times[times.len() - 1] * 1e6
    );
    assert!(mean <= 200e-6, "mean {mean}");
    assert!(p999 <= 511e-6, "p99.9 {p999}");
}
