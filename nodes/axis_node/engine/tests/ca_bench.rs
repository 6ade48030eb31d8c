//! Timing of `step` with CA rings of 10/100/1000 movers (`bench_ring`). Ignored by default;
//! run in release: `cargo test -p axis_engine --release --test ca_bench -- --ignored --nocapture`.

use axis_engine::bench_ring;
use motion_core::{Engine, Tick};
use std::time::Instant;

#[test]
#[ignore]
fn ns_per_axis_per_step() {
    for n in [10usize, 100, 1000] {
        let mut e = bench_ring(n);
        let mut ev = Vec::new();
        // Best of 7 runs: the machine is shared, the least disturbed run counts.
        let cycles = (100_000 / n).max(100) as u64;
        let mut ns = f64::INFINITY;
        for rep in 0..7u64 {
            let t0 = Instant::now();
            for k in 0..cycles {
                ev.clear();
                let index = 10_000 + rep * cycles + k;
                e.step(Tick { index, dt: 0.001 }, &mut ev);
            }
            ns = ns.min(t0.elapsed().as_nanos() as f64 / (cycles as f64 * n as f64));
        }
        let s = e.snapshot();
        let moving = s.ca_groups[0]
            .axes
            .iter()
            .filter(|a| a.velocity > 1.0)
            .count();
        println!("{n} axes: {ns:.1} ns per axis per step ({moving} moving)");
    }
}

/// A dense ring (150 mm spacing; a Standard follower at 1000 mm/s needs ≈ 200 mm): every
/// follower is CA-limited, so the planner's bisections run.
#[test]
#[ignore]
fn ns_per_axis_per_step_dense_train() {
    use axis_engine::ca::bench::ca_engine;
    use axis_engine::ca::*;
    use axis_engine::AxisCommand;
    let n = 1000;
    let movers: Vec<(String, f64)> = (0..n)
        .map(|i| (format!("m{i}"), (n - 1 - i) as f64 * 150.0))
        .collect();
    let cfg = CaGroupConfig {
        rail_length: n as f64 * 150.0 + 1000.0,
        ..CaGroupConfig::default()
    };
    let mut e = ca_engine(&movers, "g", cfg, 0.001).unwrap();
    for (name, _) in &movers {
        e.command(AxisCommand::Ca(CaCommand::MoveRelative(MoveRelativeCa {
            axis: name.clone(),
            distance: McLreal::Value(1e9),
            velocity: McLreal::Value(1000.0),
            ..Default::default()
        })))
        .unwrap();
    }
    let mut ev = Vec::new();
    for k in 0..1000 {
        ev.clear();
        e.step(
            Tick {
                index: 2 + k,
                dt: 0.001,
            },
            &mut ev,
        );
    }
    // Best of 5 runs: the machine is shared, the least disturbed run counts.
    let cycles = 100u64;
    let mut ns = f64::INFINITY;
    for rep in 0..5u64 {
        let t0 = Instant::now();
        for k in 0..cycles {
            ev.clear();
            let index = 10_000 + rep * cycles + k;
            e.step(Tick { index, dt: 0.001 }, &mut ev);
        }
        ns = ns.min(t0.elapsed().as_nanos() as f64 / (cycles as f64 * n as f64));
    }
    let limited = e.snapshot().ca_groups[0]
        .axes
        .iter()
        .filter(|a| a.ca_limited)
        .count();
    println!("dense {n} axes: {ns:.1} ns per axis per step ({limited} CA-limited)");
}
