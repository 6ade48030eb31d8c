//! Times `PlanarEngine::step` on the closed-loop benchmark scene (`bench_loop`):
//! `cargo run --release -p planar_engine --example track_bench [cycles]`.

use motion_core::{Engine, Tick};
use std::time::Instant;

fn main() {
    let cycles: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(2000);
    for n in [50, 200, 500] {
        let mut e = planar_engine::bench_loop(n);
        let mut ev = Vec::new();
        let mut times = Vec::with_capacity(cycles);
        for k in 0..cycles {
            let t0 = Instant::now();
            e.step(
                Tick {
                    index: 1_000_000 + k as u64,
                    dt: 0.001,
                },
                &mut ev,
            );
            times.push(t0.elapsed().as_secs_f64() * 1e6);
            ev.clear();
        }
        times.sort_by(|a, b| a.total_cmp(b));
        let mean = times.iter().sum::<f64>() / times.len() as f64;
        let snap = e.snapshot();
        let moving = snap
            .movers
            .iter()
            .filter(|m| m.on_track.as_ref().is_some_and(|o| o.set_velo.abs() > 1.0))
            .count();
        let waiting = snap
            .movers
            .iter()
            .filter(|m| m.on_track.as_ref().is_some_and(|o| o.waiting))
            .count();
        println!(
            "{n:4} movers: step mean {mean:7.1} us, p50 {:7.1}, p99 {:7.1}, max {:7.1} ({} cycles; {moving} moving, {waiting} gap-limited)",
            times[times.len() / 2],
            times[times.len() * 99 / 100],
            times[times.len() - 1],
            cycles
        );
    }
}
