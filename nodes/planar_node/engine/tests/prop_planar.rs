//! Property tests of the XPlanar movers in a group (issue 33 §2), with proptest: a grid of
//! movers of random sizes, all members of one group, then a random sequence of mover calls
//! whose arguments are random and also extreme (NaN, ±inf, huge, negative, zero, tiny), each
//! followed by a random number of cycles. After every call and every cycle:
//! - nothing panics, and every set position, velocity and acceleration is finite;
//! - no two members of the group overlap (xplanar.md §5.11: the group reserves areas);
//! - every admitted command ends at most once and reports nothing after its end;
//! - the same calls give a bit-identical run (determinism).
//!
//! A failure shrinks to a minimal sequence. `PROPTEST_CASES` sets the number of cases
//! (default 32 here; a long run:
//! `PROPTEST_CASES=10000 cargo test --release -p planar_engine --test prop_planar`).
mod common;
use common::*;
use planar_engine::*;
use proptest::prelude::*;

#[derive(Debug, Clone)]
struct Call {
    kind: u8,
    mover: usize,
    args: [f64; 7],
    cycles: u16,
}

fn arg() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => -200.0..1200.0f64,
        1 => Just(0.0),
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(1e300),
        1 => Just(-1e300),
        1 => 1e-9..1e-3f64,
        1 => -1e9..1e9f64,
    ]
}

fn call() -> impl Strategy<Value = Call> {
    (
        0u8..8,
        0usize..9,
        prop::array::uniform7(arg()),
        prop_oneof![3 => 0u16..50, 1 => 50u16..1500],
    )
        .prop_map(|(kind, mover, args, cycles)| Call {
            kind,
            mover,
            args,
            cycles,
        })
}

/// 3 x 3 movers 240 mm apart, some of them 155 x 235 mm, all free in the plane.
fn config(big: [bool; 9]) -> PlanarConfig {
    let movers = (0..9)
        .map(|i| {
            let mut m = MoverConfig::new(
                &format!("m{i}"),
                (i % 3) as f64 * 240.0,
                (i / 3) as f64 * 240.0,
                0.0,
            );
            if big[i] {
                m.width = 155.0;
                m.height = 235.0;
            }
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

fn command(c: &Call) -> PlanarCommand {
    let mover = format!("m{}", c.mover);
    let [x, y, r, v, a, d, j] = c.args;
    let constraint = DynamicConstraint {
        velocity: v,
        acceleration: a,
        deceleration: d,
        jerk: j,
    };
    match c.kind {
        0..=2 => PlanarCommand::MoveToPosition {
            mover,
            target_position: PositionXYC::new(x, y, r),
            constraint,
            options: MoveToPositionOptions {
                use_orientation: c.kind == 1,
            },
        },
        3 => PlanarCommand::MoveC {
            mover,
            target_position: r,
            constraint,
            options: MoveCOptions::default(),
        },
        4 => PlanarCommand::Halt { mover, constraint },
        5 => PlanarCommand::MoverDisable { mover },
        6 => PlanarCommand::MoverEnable { mover },
        _ => PlanarCommand::MoverReset { mover },
    }
}

/// Runs the calls; checks the invariants on the way; returns the run's trace.
fn run(cfg: &PlanarConfig, calls: &[Call]) -> Result<Vec<String>, TestCaseError> {
    let mut s = Sim::new(cfg.clone());
    for i in 0..cfg.movers.len() {
        s.enable(&format!("m{i}"));
    }
    s.enable_group("G");
    for i in 0..cfg.movers.len() {
        s.ok(PlanarCommand::MoverAddToGroup {
            mover: format!("m{i}"),
            group: "G".into(),
        });
    }
    s.steps(2);
    let mut trace = Vec::new();
    let check = |s: &Sim, what: &str| -> Result<(), TestCaseError> {
        let snap = s.snap();
        for m in &snap.movers {
            for vec in [m.set_pos, m.set_velo, m.set_acc] {
                for x in [vec.x, vec.y, vec.z, vec.a, vec.b, vec.c] {
                    prop_assert!(x.is_finite(), "{what}: {} {vec:?}", m.name);
                }
            }
        }
        let f = footprints(&snap, cfg);
        for i in 0..f.len() {
            for k in 0..i {
                prop_assert!(
                    !f[i].intersects(&f[k]),
                    "{what}: {} {:?} overlaps {} {:?}",
                    snap.movers[i].name,
                    snap.movers[i].set_pos,
                    snap.movers[k].name,
                    snap.movers[k].set_pos
                );
            }
        }
        for (id, h) in &s.history {
            let ends = h.iter().filter(|st| st.is_final()).count();
            prop_assert!(
                ends <= 1 && (ends == 0 || h.last().unwrap().is_final()),
                "{what}: {id:?} went {h:?}"
            );
        }
        Ok(())
    };
    check(&s, "start")?;
    for (i, c) in calls.iter().enumerate() {
        let cmd = command(c);
        trace.push(format!("{:?}", s.cmd(cmd.clone())));
        check(&s, &format!("call {i} {cmd:?}"))?;
        for n in 0..c.cycles {
            s.step();
            check(&s, &format!("call {i}, cycle {n} after {cmd:?}"))?;
        }
        trace.push(format!("{:?}", s.snap()));
    }
    Ok(trace)
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(32),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn random_calls_keep_the_group_apart(
        big in prop::array::uniform9(any::<bool>()),
        calls in prop::collection::vec(call(), 1..30),
    ) {
        let cfg = config(big);
        let first = run(&cfg, &calls)?;
        let again = run(&cfg, &calls)?;
        prop_assert_eq!(first, again, "the same calls gave another run");
    }
}
