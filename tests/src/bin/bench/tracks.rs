//! Movers on a closed-loop track with gap control (issue 7: ≤ 500 µs per step at 500
//! movers). Reference in the same run: evaluating one planned arc-length profile per mover.

use motion_core::Engine;
use std::time::Instant;

pub fn step_cost(counts: &[usize], steps: u64) {
    for &n in counts {
        let mut e = planar_engine::bench_loop(n);
        let mut ev = Vec::new();
        let mut tick = 1_000_000;
        let mut times = Vec::with_capacity(steps as usize);
        for _ in 0..steps {
            let t0 = Instant::now();
            super::step(&mut e, &mut tick, &mut ev);
            times.push(t0.elapsed().as_secs_f64());
        }
        let mean = times.iter().sum::<f64>() / times.len() as f64;
        let p50 = super::percentile(&mut times, 0.5);
        let p99 = super::percentile(&mut times, 0.99);
        let snap = e.snapshot();
        let on = |f: fn(&planar_engine::OnTrackSnapshot) -> bool| {
            snap.movers
                .iter()
                .filter(|m| m.on_track.as_ref().is_some_and(f))
                .count()
        };
        let moving = on(|o| o.set_velo.abs() > 1.0);
        let waiting = on(|o| o.waiting);
        let floor = super::profile_floor(n, steps);
        println!(
            "track loop step: {n:4} movers ({moving} moving, {waiting} gap-limited): mean {:7.1} us, p50 {:7.1} us, p99 {:7.1} us | one profile evaluation per mover {:5.1} us (ratio {:.0}) | target <= 500 us at 500 movers",
            mean * 1e6,
            p50 * 1e6,
            p99 * 1e6,
            floor * 1e6,
            mean / floor
        );
    }
}
