//! Movers never overlap (task requirement; §5.11 guard): seeded random commands, footprints
//! checked pairwise after every cycle. Seed and duration from PLANAR_STRESS_SEED /
//! PLANAR_STRESS_SECONDS (defaults 7 and 3 s).

mod common;
use common::*;
use motion_core::{CommandState, Engine, Tick};
use planar_engine::*;
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

fn env_or(name: &str, d: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(d)
}

fn grid_config(nx: usize, ny: usize, pitch: f64, rng: &mut SmallRng) -> PlanarConfig {
    let mut movers = vec![];
    for i in 0..nx {
        for j in 0..ny {
            let mut m = MoverConfig::new(
                &format!("m{i}_{j}"),
                i as f64 * pitch,
                j as f64 * pitch,
                0.0,
            );
            if rng.gen_bool(0.2) {
                m.width = 155.0;
                m.height = 235.0;
            }
            movers.push(m);
        }
    }
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

fn assert_no_overlap(s: &PlanarSnapshot, cfg: &PlanarConfig, step: u64) {
    let f = footprints(s, cfg);
    for i in 0..f.len() {
        assert!(s.movers[i].set_pos.x.is_finite() && s.movers[i].set_pos.y.is_finite());
        for j in 0..i {
            assert!(
                !f[i].intersects(&f[j]),
                "cycle {step}: {} {:?} overlaps {} {:?}",
                s.movers[i].name,
                s.movers[i].set_pos,
                s.movers[j].name,
                s.movers[j].set_pos
            );
        }
    }
}

#[test]
fn random_commands_never_overlap() {
    let seed = env_or("PLANAR_STRESS_SEED", 7);
    let seconds = env_or("PLANAR_STRESS_SECONDS", 3);
    let mut rng = SmallRng::seed_from_u64(seed);
    let cfg = grid_config(6, 5, 240.0, &mut rng);
    let mut eng = PlanarEngine::new(cfg.clone()).unwrap();
    let names: Vec<String> = cfg.movers.iter().map(|m| m.name.clone()).collect();
    let mut events = vec![];
    for n in &names {
        eng.command(PlanarCommand::MoverEnable { mover: n.clone() })
            .unwrap();
    }
    eng.command(PlanarCommand::GroupEnable { group: "G".into() })
        .unwrap();
    let mut t = 0u64;
    for _ in 0..3 {
        eng.step(
            Tick {
                index: t,
                dt: 0.001,
            },
            &mut events,
        );
        t += 1;
    }
    // Half of the movers are group members (area reservation, guard); the others have no
    // collision checks (§3.2) and crash on contact (both then refuse commands in Error).
    for n in names.iter().step_by(2) {
        eng.command(PlanarCommand::MoverAddToGroup {
            mover: n.clone(),
            group: "G".into(),
        })
        .unwrap();
    }
    let (mut accepted, mut refused, mut guard_stops, mut done) = (0, 0, 0, 0);
    for _ in 0..seconds * 1000 {
        if rng.gen_bool(0.05) {
            let n = names[rng.gen_range(0..names.len())].clone();
            let c = match rng.gen_range(0..10) {
                0 => PlanarCommand::Halt {
                    mover: n,
                    constraint: DynamicConstraint::default(),
                },
                1 | 2 => PlanarCommand::MoveC {
                    mover: n,
                    target_position: rng.gen_range(-100.0..100.0),
                    constraint: DynamicConstraint::default(),
                    options: MoveCOptions::default(),
                },
                _ => PlanarCommand::MoveToPosition {
                    mover: n,
                    target_position: PositionXYC::new(
                        rng.gen_range(-200.0..1400.0),
                        rng.gen_range(-200.0..1200.0),
                        rng.gen_range(-10.0..10.0),
                    ),
                    constraint: DynamicConstraint {
                        velocity: rng.gen_range(0.0..4000.0),
                        acceleration: rng.gen_range(0.0..30000.0),
                        deceleration: rng.gen_range(0.0..30000.0),
                        jerk: 0.0,
                    },
                    options: MoveToPositionOptions {
                        use_orientation: rng.gen_bool(0.5),
                    },
                },
            };
            match eng.command(c) {
                Ok(_) => accepted += 1,
                Err(e) => {
                    assert!(
                        matches!(
                            e.error_id,
                            errors::E_COLLISION
                                | errors::E_INVALID_COMMAND_MODE
                                | errors::E_AXIS_BUSY
                                | errors::E_INVALID_STATE
                        ),
                        "{e}"
                    );
                    refused += 1;
                }
            }
        }
        events.clear();
        eng.step(
            Tick {
                index: t,
                dt: 0.001,
            },
            &mut events,
        );
        t += 1;
        for e in &events {
            match e.state {
                CommandState::Error(errors::E_COLLISION) => guard_stops += 1,
                CommandState::Done => done += 1,
                _ => {}
            }
        }
        assert_no_overlap(&eng.snapshot(), &cfg, t);
    }
    eprintln!("seed {seed}: accepted {accepted}, refused {refused}, guard stops {guard_stops}, done {done}");
    assert!(
        accepted > 25 && done > 10,
        "the test exercised motion (accepted {accepted}, done {done})"
    );
}

/// Determinism: two runs with the same commands give identical snapshots.
#[test]
fn deterministic_replay() {
    let run = || {
        let mut rng = SmallRng::seed_from_u64(3);
        let cfg = grid_config(4, 4, 240.0, &mut rng);
        let mut eng = PlanarEngine::new(cfg.clone()).unwrap();
        let names: Vec<String> = cfg.movers.iter().map(|m| m.name.clone()).collect();
        let mut ev = vec![];
        for n in &names {
            eng.command(PlanarCommand::MoverEnable { mover: n.clone() })
                .unwrap();
        }
        for t in 0..1500u64 {
            if t % 37 == 5 {
                let n = names[rng.gen_range(0..names.len())].clone();
                let _ = eng.command(mtp(
                    &n,
                    rng.gen_range(0.0..800.0),
                    rng.gen_range(0.0..800.0),
                    0.0,
                ));
            }
            eng.step(
                Tick {
                    index: t,
                    dt: 0.001,
                },
                &mut ev,
            );
        }
        (format!("{:?}", eng.snapshot()), format!("{ev:?}"))
    };
    assert_eq!(run(), run());
}

/// External set points driving into a standing mover: the guard refuses the set point,
/// the mover gets E_COLLISION with QuickStop, footprints never overlap.
#[test]
fn esg_into_a_standing_mover_is_stopped() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0), ("N", 300.0, 0.0)]);
    s.enable("M");
    s.enable("N");
    let start = s.ok(PlanarCommand::StartExternalSetpointGeneration {
        mover: "M".into(),
        options: Default::default(),
    });
    let base = s.mover("M").set_pos;
    let (mut p, mut v) = (0.0, 0.0);
    for _ in 0..1000 {
        // Accelerate towards N at 5000 mm/s².
        v += 5.0;
        p += v * 0.001;
        let (sp, sv, sa) = sp_x(p, v, 5000.0, base);
        if s.cmd(PlanarCommand::SetExternalSetpoint {
            mover: "M".into(),
            set_position: sp,
            set_velocity: sv,
            set_acceleration: sa,
        })
        .is_err()
        {
            break;
        }
        s.step();
        let (m, n) = (s.mover("M"), s.mover("N"));
        assert!(
            n.set_pos.x - m.set_pos.x >= 155.0 - 1e-6,
            "overlap: M at {}",
            m.set_pos.x
        );
        if s.state(start).is_some_and(|st| st.is_final()) {
            break;
        }
    }
    assert_eq!(
        s.state(start),
        Some(CommandState::Error(errors::E_COLLISION))
    );
    assert_eq!(s.eng.last_object_info().id, s.mover("N").oid);
    // The stopped mover's own objectInfo names the blocker (the action result reads it).
    assert_eq!(
        s.mover("M").object_info,
        PlanarObjectInfo {
            object_type: PlanarObjectType::Mover,
            id: s.mover("N").oid
        }
    );
    s.run_until(1.0, |p| p.mover("M").unwrap().state == PlanarState::Error);
    let (m, n) = (s.mover("M"), s.mover("N"));
    assert!(n.set_pos.x - m.set_pos.x >= 155.0 - 1e-6);
    assert_eq!(m.set_velo.x, 0.0);
}
