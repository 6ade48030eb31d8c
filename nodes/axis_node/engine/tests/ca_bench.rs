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
        let cycles = (200_000 / n).max(200) as u64;
        let t0 = Instant::now();
        for k in 0..cycles {
            ev.clear();
            e.step(
                Tick {
                    index: 10_000 + k,
                    dt: 0.001,
                },
                &mut ev,
            );
        }
        let ns = t0.elapsed().as_nanos() as f64 / (cycles as f64 * n as f64);
        let s = e.snapshot();
        let moving = s.ca_groups[0]
            .axes
            .iter()
            .filter(|a| a.velocity > 1.0)
            .count();
        println!("{n} axes: {ns:.1} ns per axis per step ({moving} moving)");
    }
}
