//! §5.6.3 gap control, seeded stress: 20 movers on a closed loop get random MoveOnTrack
//! commands (every direction mode, random targets and dynamics) and random Halts. Every cycle:
//! the arc-length distance between neighbours never falls below the gap (200 mm), and the
//! tangential velocity, acceleration and jerk never exceed the mover's limits; no command ends
//! with an error. Seed and duration: `TRACK_STRESS_SEED`, `TRACK_STRESS_SECONDS`.

mod common;
mod track_common;
use common::*;
use motion_core::CommandState;
use planar_engine::*;
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use track_common::*;

fn env_or(key: &str, d: u64) -> u64 {
    std::env::var(key)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(d)
}

const N: usize = 20;
const L: f64 = 8000.0;
const GAP: f64 = 200.0;

#[test]
fn twenty_movers_keep_the_gap_and_the_limits() {
    let seed = env_or("TRACK_STRESS_SEED", 11);
    let seconds = env_or("TRACK_STRESS_SECONDS", 20);
    let mut rng = SmallRng::seed_from_u64(seed);
    let r = L / std::f64::consts::TAU;
    let names: Vec<String> = (0..N).map(|k| format!("m{k}")).collect();
    let movers: Vec<(&str, f64, f64)> = names
        .iter()
        .enumerate()
        .map(|(k, n)| {
            let phi = std::f64::consts::TAU * k as f64 / N as f64;
            (n.as_str(), r * phi.cos(), r * phi.sin())
        })
        .collect();
    let mut s = Sim::new(cfg(&movers, &["L"]));
    circle_loop(&mut s, r);
    for n in &names {
        s.enable(n);
    }
    for n in &names {
        join_wait(&mut s, n, "L", true);
    }
    // Per-mover limits (velocity, acceleration = deceleration, jerk), fixed for the run.
    let lim: Vec<(f64, f64, f64)> = (0..N)
        .map(|_| {
            (
                rng.gen_range(300.0..2000.0),
                rng.gen_range(2000.0..20000.0),
                rng.gen_range(20000.0..400000.0),
            )
        })
        .collect();
    let constraint = |k: usize| DynamicConstraint {
        velocity: lim[k].0,
        acceleration: lim[k].1,
        deceleration: lim[k].1,
        jerk: lim[k].2,
    };
    let mut ids = vec![];
    let mut prev_acc = [0.0; N];
    let mut waited = 0usize;
    let cycles = (seconds * 1000) as usize;
    let mut next_cmd = 0usize;
    for cycle in 0..cycles {
        if cycle == next_cmd {
            next_cmd += rng.gen_range(5..120);
            let k = rng.gen_range(0..N);
            let cmd = if rng.gen_bool(0.2) {
                PlanarCommand::Halt {
                    mover: names[k].clone(),
                    constraint: constraint(k),
                }
            } else {
                let dir = [
                    Direction::NonModulo,
                    Direction::Positive,
                    Direction::ShortestWay,
                    Direction::Negative,
                ][rng.gen_range(0..4)];
                let here = on_track(&s, &names[k]).set_pos;
                let (target, turns, tol) = match dir {
                    Direction::NonModulo => (here + rng.gen_range(-3000.0..3000.0), 0, 0.0),
                    Direction::ShortestWay => (rng.gen_range(0.0..L), 0, rng.gen_range(0.0..50.0)),
                    _ => (
                        rng.gen_range(0.0..L),
                        rng.gen_range(0..2),
                        rng.gen_range(0.0..50.0),
                    ),
                };
                PlanarCommand::MoveOnTrack {
                    mover: names[k].clone(),
                    track: String::new(),
                    target_position: target,
                    constraint: constraint(k),
                    options: MoveOnTrackOptions {
                        gap: GAP,
                        direction: dir,
                        additional_turns: turns,
                        modulo_tolerance: tol,
                    },
                }
            };
            ids.push(s.ok(cmd));
        }
        s.step();
        let snap = s.snap();
        // Gap: neighbours in cyclic order.
        let mut pos: Vec<(f64, usize)> = (0..N)
            .map(|k| (snap.movers[k].on_track.as_ref().unwrap().set_pos_modulo, k))
            .collect();
        pos.sort_by(|a, b| a.0.total_cmp(&b.0));
        for w in 0..N {
            let (a, ka) = pos[w];
            let (b, kb) = pos[(w + 1) % N];
            let d = (b - a).rem_euclid(L);
            assert!(
                d >= GAP - 1e-6,
                "cycle {cycle}: {} at {a:.4} and {} at {b:.4} only {d:.6} mm apart (seed {seed})",
                names[ka],
                names[kb]
            );
        }
        // Tangential limits.
        for k in 0..N {
            let o = snap.movers[k].on_track.as_ref().unwrap();
            let (v, a, j) = lim[k];
            assert!(
                o.set_velo.abs() <= v + 1e-6,
                "cycle {cycle}: {} v {}",
                names[k],
                o.set_velo
            );
            assert!(
                o.set_acc.abs() <= a + 1e-6,
                "cycle {cycle}: {} a {}",
                names[k],
                o.set_acc
            );
            let jerk = (o.set_acc - prev_acc[k]).abs() / 0.001;
            assert!(
                jerk <= j * (1.0 + 1e-6) + 1e-3,
                "cycle {cycle}: {} jerk {jerk} > {j}",
                names[k]
            );
            prev_acc[k] = o.set_acc;
            waited += o.waiting as usize;
        }
    }
    for id in ids {
        assert!(
            !matches!(s.state(id), Some(CommandState::Error(_))),
            "a command failed: {:?}",
            s.history.get(&id)
        );
    }
    assert!(
        waited > 0,
        "gap control never held a mover back (test not exercising it)"
    );
}
