//! Planar engine step cost: movers moving freely on a grid with the overlap guard on
//! (issue 4: ≤ 500 µs per step at 500 movers). Reference: evaluating three planned profiles
//! (X, Y, C) per mover and step, the floor of any jerk-limited planar set-point generator.

use super::step;
use motion_core::Engine;
use planar_engine::{
    DynamicConstraint, GroupConfig, MoveToPositionOptions, MoverConfig, PlanarCommand,
    PlanarConfig, PlanarEngine, PositionXYC,
};
use std::time::Instant;

/// `n` movers on a grid, 240 mm pitch, 25 per row; every second one of a mixed format.
fn grid(n: usize) -> PlanarConfig {
    let movers = (0..n)
        .map(|k| {
            let (i, j) = (k % 25, k / 25);
            let mut m = MoverConfig::new(&format!("m{k}"), i as f64 * 240.0, j as f64 * 240.0, 0.0);
            m.width = 155.0;
            m.height = 155.0;
            m
        })
        .collect();
    PlanarConfig {
        movers,
        groups: vec![GroupConfig {
            name: "G".into(),
            oid: 0,
        }],
        enable_time: 0.0,
        ..Default::default()
    }
}

/// The engine of [`grid`]`(n)` with every mover enabled, one cycle stepped: (config, engine,
/// the next tick, the event buffer).
fn enabled_grid(
    n: usize,
) -> (
    PlanarConfig,
    PlanarEngine,
    u64,
    Vec<motion_core::CommandEvent>,
) {
    let cfg = grid(n);
    let mut e = PlanarEngine::new(cfg.clone()).expect("planar config");
    let (mut tick, mut ev) = (0, Vec::new());
    for m in &cfg.movers {
        e.command(PlanarCommand::MoverEnable {
            mover: m.name.clone(),
        })
        .expect("enable");
    }
    step(&mut e, &mut tick, &mut ev);
    (cfg, e, tick, ev)
}

/// Every mover shuttles 60 mm within its cell of the grid (even: along X, odd: along Y),
/// so all move at once and the guard checks neighbours that come close.
pub fn step_cost(counts: &[usize], steps: u64) {
    for &n in counts {
        let (cfg, mut e, mut tick, mut ev) = enabled_grid(n);
        let (mut total, mut samples, mut moving_sum) = (0.0, 0u64, 0usize);
        let mut k = 0u64;
        while samples < steps {
            // A new leg whenever the previous one ended (about every 250 cycles).
            if k.is_multiple_of(250) {
                let out = (k / 250).is_multiple_of(2);
                for (i, m) in cfg.movers.iter().enumerate() {
                    let (x, y) = (m.initial_pose.x, m.initial_pose.y);
                    let d = if out { 60.0 } else { 0.0 };
                    let (tx, ty) = if i % 2 == 0 { (x + d, y) } else { (x, y + d) };
                    e.command(PlanarCommand::MoveToPosition {
                        mover: m.name.clone(),
                        target_position: PositionXYC::new(tx, ty, 0.0),
                        constraint: DynamicConstraint::default(),
                        options: MoveToPositionOptions::default(),
                    })
                    .expect("move");
                }
            }
            k += 1;
            let t0 = Instant::now();
            step(&mut e, &mut tick, &mut ev);
            let dt = t0.elapsed().as_secs_f64();
            let moving = e
                .snapshot()
                .movers
                .iter()
                .filter(|m| m.set_velo.x != 0.0 || m.set_velo.y != 0.0)
                .count();
            if moving > 0 {
                total += dt;
                samples += 1;
                moving_sum += moving;
            }
        }
        let per_step = total / samples as f64;
        let floor = super::profile_floor(3 * n, steps);
        println!(
            "planar engine step: {n:4} movers (mean {:.0} moving): {:8.1} us per step, {:6.0} ns per mover | 3 profile evaluations per mover alone {:5.1} us (ratio {:.1}) | target <= 500 us at 500 movers",
            moving_sum as f64 / samples as f64,
            per_step * 1e6,
            per_step * 1e9 / n as f64,
            floor * 1e6,
            per_step / floor
        );
    }
}

/// The engine's snapshot as a lockstep state stream takes it every cycle: built in an older
/// snapshot's buffers (`snapshot_into`) vs a fresh one (`snapshot`, every name and list
/// allocated and later dropped), `n` movers of the grid, all members of the group.
pub fn snapshot_cost(counts: &[usize], reps: u32) {
    for &n in counts {
        let (cfg, mut e, mut tick, mut ev) = enabled_grid(n);
        e.command(PlanarCommand::GroupEnable { group: "G".into() })
            .expect("group enable");
        // Enabling takes a while (enable_time 0 for the movers, not for the group).
        for _ in 0..2000 {
            step(&mut e, &mut tick, &mut ev);
        }
        for m in &cfg.movers {
            e.command(PlanarCommand::MoverAddToGroup {
                mover: m.name.clone(),
                group: "G".into(),
            })
            .expect("join the group");
        }
        step(&mut e, &mut tick, &mut ev);
        let mut kept = e.snapshot();
        assert_eq!(kept.groups[0].movers.len(), n, "all in the group");
        let t0 = Instant::now();
        for _ in 0..reps {
            e.snapshot_into(&mut kept);
            std::hint::black_box(&kept);
        }
        let refilled = t0.elapsed().as_secs_f64() / f64::from(reps);
        let t0 = Instant::now();
        for _ in 0..reps {
            std::hint::black_box(e.snapshot());
        }
        let fresh = t0.elapsed().as_secs_f64() / f64::from(reps);
        println!(
            "planar snapshot: {n:4} movers in a group: {:7.2} us built in an older one's buffers | a fresh one {:7.2} us (ratio {:.2})",
            refilled * 1e6,
            fresh * 1e6,
            refilled / fresh
        );
    }
}
