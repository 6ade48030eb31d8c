//! Step cost with 1000 moving axes (target ≤ 100 ns per moving axis per step).
//! Run: `cargo run --release -p axis_engine --example bench_step`.
use axis_engine::*;
use motion_core::{Engine, Tick};
use std::time::Instant;

fn main() {
    let n = 1000;
    let axes = (0..n)
        .map(|i| (format!("a{i}"), AxisConfig::default()))
        .collect();
    let mut e = AxisEngine::new(axes).unwrap();
    for i in 0..n {
        e.command(AxisCommand::Power(Power {
            axis: format!("a{i}"),
            enable: true,
            enable_positive: true,
            enable_negative: true,
            override_percent: 100.0,
            buffer_mode: BufferMode::Aborting,
        }))
        .unwrap();
    }
    let mut events = Vec::with_capacity(4096);
    let mut tick = 0u64;
    let mut step = |e: &mut AxisEngine, events: &mut Vec<_>| {
        e.step(
            Tick {
                index: tick,
                dt: 0.001,
            },
            events,
        );
        events.clear();
        tick += 1;
    };
    step(&mut e, &mut events);
    for i in 0..n {
        let axis = format!("a{i}");
        let c = if i % 2 == 0 {
            AxisCommand::MoveAbsolute(MoveAbsolute {
                axis,
                position: 1e6,
                velocity: 100.0 + i as f64 * 0.1,
                acceleration: 0.0,
                deceleration: 0.0,
                jerk: 0.0,
                buffer_mode: BufferMode::Aborting,
                options: MoveOptions::default(),
            })
        } else {
            AxisCommand::MoveVelocity(MoveVelocity {
                axis,
                velocity: 50.0,
                acceleration: 0.0,
                deceleration: 0.0,
                jerk: 0.0,
                direction: Direction::Negative,
                buffer_mode: BufferMode::Aborting,
                options: MoveOptions::default(),
            })
        };
        e.command(c).unwrap();
    }
    for _ in 0..100 {
        step(&mut e, &mut events);
    }
    let cycles = 5000;
    let t0 = Instant::now();
    for _ in 0..cycles {
        step(&mut e, &mut events);
    }
    let dt = t0.elapsed().as_secs_f64();
    let per_axis = dt / cycles as f64 / n as f64 * 1e9;
    let moving = e
        .snapshot()
        .axes
        .iter()
        .filter(|a| a.set_velo != 0.0)
        .count();
    println!(
        "{n} axes ({moving} moving): {:.1} µs per step, {per_axis:.1} ns per axis per step",
        dt / cycles as f64 * 1e6
    );
    let t0 = Instant::now();
    let s = e.snapshot();
    println!(
        "snapshot: {:.1} µs ({} axes)",
        t0.elapsed().as_secs_f64() * 1e6,
        s.axes.len()
    );
}
