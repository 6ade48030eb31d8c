//! Seeded random Part 4 / platform command sequences (count from `P4_SWEEP`, default 60):
//! no panic, no NaN in set values, refusals only with documented ids, members never beyond
//! their limits, and determinism (two runs with the same seed give the same snapshot bytes).
mod p4rig;
use axis_engine::group::*;
use axis_engine::platform::*;
use axis_engine::*;
use motion_core::Engine;
use p4rig::*;
use rand::rngs::SmallRng;
use rand::{Rng as _, SeedableRng};

fn wild(g: &mut SmallRng) -> f64 {
    match g.gen_range(0..12) {
        0 => f64::NAN,
        1 => f64::INFINITY,
        2 => -1.0,
        3 => 0.0,
        4 => 1e300,
        _ => g.gen_range(-500.0..500.0),
    }
}

fn pos(g: &mut SmallRng, n: usize) -> Vec<f64> {
    let n = if g.gen_bool(0.05) { n + 1 } else { n };
    (0..n)
        .map(|_| {
            if g.gen_bool(0.05) {
                wild(g)
            } else {
                g.gen_range(-300.0..300.0)
            }
        })
        .collect()
}

fn random_cmd(g: &mut SmallRng) -> AxisCommand {
    let v = if g.gen_bool(0.1) {
        wild(g)
    } else {
        g.gen_range(1.0..3000.0)
    };
    let dynv = |g: &mut SmallRng| {
        if g.gen_bool(0.1) {
            wild(g)
        } else {
            g.gen_range(0.0..3000.0)
        }
    };
    let grp = if g.gen_bool(0.03) { "nope" } else { G };
    let ax = ["x", "y", "z", "w"][g.gen_range(0..4)];
    let lin = |g: &mut SmallRng, rel: bool| {
        let c = MoveLinear {
            group: grp.into(),
            position: pos(g, 2),
            velocity: v,
            acceleration: dynv(g),
            deceleration: dynv(g),
            jerk: dynv(g),
            coord_system: CoordSystem::Acs,
            buffer_mode: BufferMode::Aborting,
            transition_mode: TransitionMode::None,
        };
        if rel {
            GroupCommand::MoveLinearRelative(c)
        } else {
            GroupCommand::MoveLinearAbsolute(c)
        }
    };
    let gc = match g.gen_range(0..22) {
        0..=4 => lin(g, false),
        5..=6 => lin(g, true),
        7 => GroupCommand::GroupHalt(GroupHalt {
            group: grp.into(),
            deceleration: dynv(g),
            jerk: dynv(g),
            buffer_mode: BufferMode::Aborting,
        }),
        8 => GroupCommand::GroupStop(GroupStop {
            group: grp.into(),
            deceleration: dynv(g),
            jerk: dynv(g),
        }),
        9 => GroupCommand::GroupReset { group: grp.into() },
        10 => GroupCommand::GroupDisable { group: grp.into() },
        11 => GroupCommand::GroupEnable { group: grp.into() },
        12 => GroupCommand::AddAxisToGroup(AddAxisToGroup {
            group: grp.into(),
            axis: ax.into(),
            ident_in_group: g.gen_range(0..4),
        }),
        13 => GroupCommand::RemoveAxisFromGroup(RemoveAxisFromGroup {
            group: grp.into(),
            axis: ax.into(),
        }),
        14 => GroupCommand::GroupSetOverride(GroupSetOverride {
            group: grp.into(),
            enable: g.gen_bool(0.8),
            vel_factor: if g.gen_bool(0.1) {
                wild(g)
            } else {
                g.gen_range(0.0..1.0)
            },
            acc_factor: 1.0,
            jerk_factor: 1.0,
        }),
        15 => GroupCommand::PathSelect(PathSelect {
            group: grp.into(),
            points: (0..g.gen_range(0..4)).map(|_| pos(g, 2)).collect(),
        }),
        16 => GroupCommand::MovePath(MovePath {
            group: grp.into(),
            velocity: v,
            acceleration: dynv(g),
            deceleration: dynv(g),
            jerk: dynv(g),
            coord_system: CoordSystem::Acs,
            buffer_mode: BufferMode::Aborting,
        }),
        17 => {
            return AxisCommand::Sim(Sim::InjectAxisError {
                axis: ax.into(),
                error_id: 0,
            })
        }
        18 => {
            return AxisCommand::Power(Power {
                axis: ax.into(),
                enable: g.gen_bool(0.8),
                enable_positive: true,
                enable_negative: true,
                override_percent: 100.0,
                buffer_mode: BufferMode::Aborting,
            })
        }
        19 => return AxisCommand::Reset(Reset { axis: ax.into() }),
        20 => return rel(ax, g.gen_range(-100.0..100.0), g.gen_range(1.0..500.0)),
        _ => GroupCommand::UngroupAllAxes { group: grp.into() },
    };
    AxisCommand::Group(gc)
}

const KNOWN: [u32; 10] = [
    0x7F01, 0x7F02, 0x7F06, 0x4B01, 0x4B03, 0x4B06, 0x4D01, 4901, 4902, 4905,
];

fn run(seed: u64, profile: PlatformProfile) -> String {
    let mut g = SmallRng::seed_from_u64(seed);
    let cfg = EngineConfig {
        platform_profile: profile,
        groups: vec![GroupConfig {
            name: G.into(),
            axes: vec!["x".into(), "y".into()],
        }],
        ..EngineConfig::default()
    };
    let mut r = P4::build(
        ["x", "y", "z"]
            .iter()
            .map(|n| (n.to_string(), axis_cfg()))
            .collect(),
        cfg,
    );
    r.steps(10);
    for a in ["x", "y", "z"] {
        r.power(a, true).unwrap();
    }
    r.step();
    let c = AxisConfig::default();
    for _ in 0..40 {
        let cmd = random_cmd(&mut g);
        if let Err(e) = r.cmd(cmd.clone()) {
            assert!(
                KNOWN.contains(&e.error_id.0) || (e.error_id.0 == 4 || e.error_id.0 == 1),
                "unexpected id {} for {cmd:?}: {}",
                e.error_id,
                e.message
            );
        }
        for _ in 0..g.gen_range(1..400) {
            r.step();
            for a in ["x", "y", "z"] {
                let s = r.ax(a);
                assert!(
                    s.set_pos.is_finite() && s.set_velo.is_finite(),
                    "{a}: {s:?}"
                );
                let grouped = r.gs().axes.iter().any(|m| m == a);
                if grouped && r.gs().state == GroupState::Moving {
                    assert!(
                        s.set_velo.abs() <= c.max_velocity + 1e-6,
                        "{a} v {}",
                        s.set_velo
                    );
                    assert!(
                        s.set_acc.abs() <= c.acceleration.max(c.deceleration) + 1e-6,
                        "{a} a {}",
                        s.set_acc
                    );
                }
            }
        }
    }
    serde_json::to_string(&r.e.snapshot()).unwrap()
}

#[test]
fn random_group_sequences_no_panic_and_deterministic() {
    let n: u64 = std::env::var("P4_SWEEP")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(60);
    for seed in 0..n {
        for profile in [PlatformProfile::Tc2Mc2, PlatformProfile::IsgMcp] {
            let a = run(seed, profile);
            if seed < 5 {
                assert_eq!(a, run(seed, profile), "determinism, seed {seed}");
            }
        }
    }
}
