//! collision_avoidance.md §5.0, §5.1, §7.2: bad requests are rejected with the spec's error
//! id (never a panic) and never disturb the running command.

mod ca_common;
use axis_engine::ca::types::errors::*;
use axis_engine::ca::*;
use ca_common::*;
use motion_core::{CommandState, Engine, ErrorId};

fn rig() -> CaRig {
    CaRig::new(&[("A", 0.0), ("B", 500.0)], ring(3000.0))
}

fn mv(axis: &str) -> MoveAbsoluteCa {
    MoveAbsoluteCa {
        axis: axis.into(),
        position: McLreal::Value(100.0),
        velocity: McLreal::Value(100.0),
        ..Default::default()
    }
}

#[test]
fn unknown_group_and_axis() {
    let mut r = rig();
    assert_eq!(
        r.err(CaCommand::GroupEnable {
            group: "nope".into()
        }),
        ErrorId::UNKNOWN_OBJECT
    );
    let c = CaCommand::AddAxisToGroup {
        group: G.into(),
        axis: "nope".into(),
        ident_in_group: udint_to_identingroup(7),
    };
    assert_eq!(r.err(c), AXIS_NOT_IN_GROUP);
    assert_eq!(
        r.err(CaCommand::MoveAbsolute(mv("nope"))),
        AXIS_NOT_IN_GROUP
    );
}

#[test]
fn membership_and_ident() {
    let mut r = CaRig::ungrouped(&[("A", 0.0), ("B", 500.0)], ring(3000.0));
    r.add("A", 1).unwrap();
    assert_eq!(
        r.add("A", 2).unwrap_err().error_id,
        AXIS_IN_OTHER_GROUP,
        "already in the group"
    );
    assert_eq!(
        r.add("B", 1).unwrap_err().error_id,
        INVALID_IDENT_IN_GROUP,
        "duplicate ident"
    );
    assert_eq!(
        r.add("B", 0).unwrap_err().error_id,
        INVALID_IDENT_IN_GROUP,
        "ident 0"
    );
    r.e.add_ca_group("other", ring(3000.0)).unwrap();
    let c = CaCommand::AddAxisToGroup {
        group: "other".into(),
        axis: "A".into(),
        ident_in_group: udint_to_identingroup(1),
    };
    assert_eq!(r.err(c), AXIS_IN_OTHER_GROUP);
    // Move on an axis outside every group.
    r.enable();
    assert_eq!(r.err(CaCommand::MoveAbsolute(mv("B"))), AXIS_NOT_IN_GROUP);
}

#[test]
fn dynamics_and_targets() {
    let mut r = rig();
    let running = r.mv_abs("A", 400.0, 100.0);
    r.steps(10);
    let cases: Vec<(MoveAbsoluteCa, ErrorId, &str)> = vec![
        (
            MoveAbsoluteCa {
                velocity: McLreal::Value(f64::NAN),
                ..mv("A")
            },
            INVALID_VELOCITY,
            "NaN velocity",
        ),
        (
            MoveAbsoluteCa {
                velocity: McLreal::Unset,
                ..mv("A")
            },
            INVALID_VELOCITY,
            "velocity missing",
        ),
        (
            MoveAbsoluteCa {
                velocity: McLreal::Default,
                ..mv("A")
            },
            INVALID_VELOCITY,
            "velocity DEFAULT",
        ),
        (
            MoveAbsoluteCa {
                velocity: McLreal::Value(0.0),
                ..mv("A")
            },
            INVALID_VELOCITY,
            "velocity 0",
        ),
        (
            MoveAbsoluteCa {
                position: McLreal::Value(f64::INFINITY),
                ..mv("A")
            },
            INVALID_TARGET_POSITION,
            "inf position",
        ),
        (
            MoveAbsoluteCa {
                position: McLreal::Unset,
                ..mv("A")
            },
            INVALID_TARGET_POSITION,
            "position missing",
        ),
        (
            MoveAbsoluteCa {
                acceleration: McLreal::Value(0.5),
                ..mv("A")
            },
            INVALID_DYNAMICS,
            "acc < 1",
        ),
        (
            MoveAbsoluteCa {
                deceleration: McLreal::Value(f64::NAN),
                ..mv("A")
            },
            INVALID_DYNAMICS,
            "NaN dec",
        ),
        (
            MoveAbsoluteCa {
                jerk: McLreal::Value(99.0),
                ..mv("A")
            },
            INVALID_DYNAMICS,
            "jerk < 100",
        ),
        (
            MoveAbsoluteCa {
                jerk: McLreal::Maximum,
                ..mv("A")
            },
            INVALID_DYNAMICS,
            "jerk MAXIMUM",
        ),
        (
            MoveAbsoluteCa {
                gap: McLreal::Value(-1.0),
                ..mv("A")
            },
            INVALID_GAP,
            "gap < 0",
        ),
        (
            MoveAbsoluteCa {
                gap: McLreal::Value(f64::NAN),
                ..mv("A")
            },
            INVALID_GAP,
            "NaN gap",
        ),
        (
            MoveAbsoluteCa {
                gap: McLreal::Value(3000.0),
                ..mv("A")
            },
            INVALID_GAP,
            "gap ≥ rail on a ring",
        ),
        (
            MoveAbsoluteCa {
                gap: McLreal::Maximum,
                ..mv("A")
            },
            INVALID_GAP,
            "gap MAXIMUM",
        ),
        (
            MoveAbsoluteCa {
                additional_turns: 1,
                ..mv("A")
            },
            INVALID_ADDITIONAL_TURNS,
            "turns NonModulo",
        ),
        (
            MoveAbsoluteCa {
                direction: CaDirection::Positive,
                position: McLreal::Value(3000.5),
                ..mv("A")
            },
            INVALID_TARGET_POSITION,
            "modulo target > M",
        ),
    ];
    for (c, id, what) in cases {
        assert_eq!(r.err(CaCommand::MoveAbsolute(c)), id, "{what}");
    }
    let rel = MoveRelativeCa {
        axis: "A".into(),
        distance: McLreal::Value(f64::NAN),
        velocity: McLreal::Value(100.0),
        ..Default::default()
    };
    assert_eq!(r.err(CaCommand::MoveRelative(rel)), INVALID_TARGET_POSITION);
    let halt = HaltCa {
        axis: "A".into(),
        jerk: McLreal::Maximum,
        ..Default::default()
    };
    assert_eq!(r.err(CaCommand::Halt(halt)), INVALID_DYNAMICS);
    r.step();
    assert_eq!(
        r.cmd_state(running),
        CommandState::Active,
        "running command undisturbed"
    );
    assert_eq!(r.axis("A").active_command_id, Some(running));
}

#[test]
fn enums_out_of_range() {
    assert_eq!(
        CaBufferMode::from_raw(2).unwrap_err().error_id,
        INVALID_BUFFER_MODE
    );
    assert_eq!(CaDirection::from_raw(4).unwrap_err().error_id, INVALID_MODE);
    assert_eq!(
        GapControlMode::from_raw(4).unwrap_err().error_id,
        INVALID_MODE
    );
    assert_eq!(
        GapControlDirection::from_raw(0).unwrap_err().error_id,
        INVALID_MODE
    );
    assert_eq!(
        DefaultGapControlMode::from_raw(3).unwrap_err().error_id,
        INVALID_MODE
    );
    assert_eq!(CaDirection::from_raw(3).unwrap(), CaDirection::Negative);
}

#[test]
fn buffer_full_and_buffered_start() {
    let mut r = rig();
    let a = r.mv_abs("A", 400.0, 500.0);
    let b = r.ok(CaCommand::MoveAbsolute(MoveAbsoluteCa {
        position: McLreal::Value(200.0),
        buffer_mode: CaBufferMode::Buffered,
        ..mv("A")
    }));
    assert_eq!(
        r.cmd_state(b),
        CommandState::Busy,
        "buffered: Busy, not Active"
    );
    let c = CaCommand::MoveAbsolute(MoveAbsoluteCa {
        buffer_mode: CaBufferMode::Buffered,
        ..mv("A")
    });
    assert_eq!(r.err(c), BUFFER_FULL);
    r.until(5000, |r| r.cmd_state(b) == CommandState::Done);
    assert_eq!(r.cmd_state(a), CommandState::Done);
    assert_eq!(r.pos("A"), 200.0);
}

#[test]
fn axis_not_ready_and_override_nan() {
    let mut r = rig();
    r.power("A", false);
    r.step();
    // The group went to ErrorStop (T5): motion is refused by state first.
    assert_eq!(
        r.err(CaCommand::MoveAbsolute(mv("B"))),
        NOT_ALLOWED_IN_GROUP_STATE
    );
    let e = r.err(CaCommand::GroupSetOverride {
        group: G.into(),
        enable: true,
        vel_factor: f64::INFINITY,
    });
    assert_eq!(e, PARAMETER_NOT_CORRECT);
}

#[test]
fn feed_enable_missing_is_axis_not_ready() {
    let mut r = rig();
    r.e.command(axis_engine::AxisCommand::Power(axis_engine::Power {
        axis: "B".into(),
        enable: true,
        enable_positive: false,
        enable_negative: true,
        override_percent: 100.0,
        buffer_mode: axis_engine::BufferMode::Aborting,
    }))
    .unwrap();
    r.step();
    assert_eq!(r.err(CaCommand::MoveAbsolute(mv("B"))), AXIS_NOT_READY);
}

#[test]
fn group_halt_dynamics_markers() {
    let mut r = rig();
    let e = r.err(CaCommand::GroupHalt {
        group: G.into(),
        deceleration: McLreal::Value(0.0),
        jerk: McLreal::Unset,
    });
    assert_eq!(e, INVALID_DYNAMICS);
    let e = r.err(CaCommand::GroupHalt {
        group: G.into(),
        deceleration: McLreal::Ignore,
        jerk: McLreal::Unset,
    });
    assert_eq!(e, INVALID_DYNAMICS);
    r.ok(CaCommand::GroupHalt {
        group: G.into(),
        deceleration: McLreal::Maximum,
        jerk: McLreal::Ignore,
    });
}
