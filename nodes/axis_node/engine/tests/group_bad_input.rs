//! Bad input to the Part 4 FBs and the engine config: a `Rejection` with the spec's id,
//! never a panic, nothing changed (plcopen_platform.md §3.2, §7.3; shell ids 0x7F01..0x7F03).
mod p4rig;
use axis_engine::group::*;
use axis_engine::platform::*;
use axis_engine::*;
use motion_core::ErrorId;
use p4rig::*;

const UNKNOWN: ErrorId = ErrorId(0x7F01);
const NOT_FINITE: ErrorId = ErrorId(0x7F02);
const ENUM: ErrorId = ErrorId(0x7F03);
const INVALID: ErrorId = ErrorId(4902);
const NOT_IMPL: ErrorId = ErrorId(4905);

#[test]
fn unknown_group_and_unknown_axis() {
    let mut r = P4::xy_powered();
    let mut c = lin(vec![1.0, 1.0], 10.0);
    c.group = "nope".into();
    assert_eq!(err(r.g(GroupCommand::MoveLinearAbsolute(c))), UNKNOWN);
    assert_eq!(
        err(r.g(GroupCommand::GroupReadStatus {
            group: "nope".into()
        })),
        UNKNOWN
    );
    let add = |axis: &str| {
        GroupCommand::AddAxisToGroup(AddAxisToGroup {
            group: G.into(),
            axis: axis.into(),
            ident_in_group: 0,
        })
    };
    assert_eq!(err(r.g(add("w"))), UNKNOWN);
    assert_eq!(
        err(r.g(GroupCommand::RemoveAxisFromGroup(RemoveAxisFromGroup {
            group: G.into(),
            axis: "w".into()
        }))),
        UNKNOWN
    );
}

#[test]
fn axis_already_in_a_group_and_duplicate_ident() {
    let mut r = P4::xy_powered();
    let add = |axis: &str, ident| {
        GroupCommand::AddAxisToGroup(AddAxisToGroup {
            group: G.into(),
            axis: axis.into(),
            ident_in_group: ident,
        })
    };
    assert_eq!(err(r.g(add("x", 0))), INVALID, "x is already a member");
    assert_eq!(err(r.g(add("z", 1))), INVALID, "IdentInGroup 1 is taken");
    assert_eq!(
        err(r.g(GroupCommand::RemoveAxisFromGroup(RemoveAxisFromGroup {
            group: G.into(),
            axis: "z".into()
        }))),
        INVALID,
        "z is not a member"
    );
    assert_eq!(r.gs().axes, vec!["x", "y"]);
}

#[test]
fn nan_and_infinite_inputs() {
    let mut r = P4::xy_powered();
    assert_eq!(err(r.g(lin_abs(vec![f64::NAN, 1.0], 10.0))), NOT_FINITE);
    assert_eq!(
        err(r.g(lin_rel(vec![1.0, f64::INFINITY], 10.0))),
        NOT_FINITE
    );
    assert_eq!(err(r.g(lin_abs(vec![1.0, 1.0], f64::NAN))), NOT_FINITE);
    let mut c = lin(vec![1.0, 1.0], 10.0);
    c.jerk = f64::NEG_INFINITY;
    assert_eq!(err(r.g(GroupCommand::MoveLinearAbsolute(c))), NOT_FINITE);
    assert_eq!(
        err(r.g(GroupCommand::GroupHalt(GroupHalt {
            group: G.into(),
            deceleration: f64::NAN,
            jerk: 0.0,
            buffer_mode: BufferMode::Aborting
        }))),
        NOT_FINITE
    );
    assert_eq!(
        err(r.g(GroupCommand::GroupSetOverride(GroupSetOverride {
            group: G.into(),
            enable: true,
            vel_factor: f64::NAN,
            acc_factor: 1.0,
            jerk_factor: 1.0
        }))),
        NOT_FINITE
    );
    assert_eq!(
        err(r.g(GroupCommand::PathSelect(PathSelect {
            group: G.into(),
            points: vec![vec![0.0, f64::INFINITY]]
        }))),
        NOT_FINITE
    );
    assert_eq!(r.gs().state, GroupState::Standby);
}

#[test]
fn out_of_range_values() {
    let mut r = P4::xy_powered();
    assert_eq!(
        err(r.g(lin_abs(vec![1.0, 1.0], 0.0))),
        INVALID,
        "Velocity 0"
    );
    assert_eq!(err(r.g(lin_abs(vec![1.0, 1.0], -5.0))), INVALID);
    assert_eq!(
        err(r.g(lin_abs(vec![1.0], 10.0))),
        INVALID,
        "one value for two axes"
    );
    let mut c = lin(vec![1.0, 1.0], 10.0);
    c.acceleration = -1.0;
    assert_eq!(err(r.g(GroupCommand::MoveLinearAbsolute(c))), INVALID);
    assert_eq!(
        err(r.g(GroupCommand::GroupSetOverride(GroupSetOverride {
            group: G.into(),
            enable: true,
            vel_factor: 1.5,
            acc_factor: 1.0,
            jerk_factor: 1.0
        }))),
        INVALID
    );
    assert_eq!(
        err(r.g(GroupCommand::PathSelect(PathSelect {
            group: G.into(),
            points: vec![]
        }))),
        INVALID
    );
    assert_eq!(
        err(r.g(GroupCommand::PathSelect(PathSelect {
            group: G.into(),
            points: vec![vec![1.0, 2.0, 3.0]]
        }))),
        INVALID
    );
    let mp = GroupCommand::MovePath(MovePath {
        group: G.into(),
        velocity: 10.0,
        acceleration: 0.0,
        deceleration: 0.0,
        jerk: 0.0,
        coord_system: CoordSystem::Acs,
        buffer_mode: BufferMode::Aborting,
    });
    assert_eq!(err(r.g(mp)), INVALID, "no path selected");
    assert_eq!(
        err(r.g(GroupCommand::GroupReadConfiguration {
            group: G.into(),
            ident_in_group: 9
        })),
        INVALID
    );
}

#[test]
fn out_of_range_enums() {
    assert_eq!(CoordSystem::from_raw(0).unwrap_err().error_id, ENUM);
    assert_eq!(CoordSystem::from_raw(4).unwrap_err().error_id, ENUM);
    assert_eq!(CoordSystem::from_raw(2).unwrap(), CoordSystem::Mcs);
    assert_eq!(TransitionMode::from_raw(5).unwrap_err().error_id, ENUM);
    assert_eq!(SafetyFunction::from_raw(3).unwrap_err().error_id, ENUM);
    assert_eq!(OperatingMode::from_raw(3).unwrap_err().error_id, ENUM);
    assert_eq!(BufferMode::from_raw(6).unwrap_err().error_id, ENUM);
}

#[test]
fn not_implemented_modes_and_fbs_give_4905() {
    let mut r = P4::xy_powered();
    let mut c = lin(vec![1.0, 1.0], 10.0);
    c.buffer_mode = BufferMode::Buffered;
    assert_eq!(err(r.g(GroupCommand::MoveLinearAbsolute(c))), NOT_IMPL);
    let mut c = lin(vec![1.0, 1.0], 10.0);
    c.transition_mode = TransitionMode::CornerDistance;
    assert_eq!(err(r.g(GroupCommand::MoveLinearAbsolute(c))), NOT_IMPL);
    for fb in [
        "MC_GroupHome",
        "MC_GroupEnable",
        "MC_MoveCircularAbsolute",
        "MC_GroupInterrupt",
    ] {
        assert_eq!(
            err(r.g(GroupCommand::NotImplemented {
                group: G.into(),
                fb: fb.into()
            })),
            NOT_IMPL,
            "{fb}"
        );
    }
    assert_eq!(r.gs().state, GroupState::Standby);
}

#[test]
fn engine_config_is_screened() {
    let axes = || vec![("x".to_string(), axis_cfg()), ("y".to_string(), axis_cfg())];
    let bad_axis = EngineConfig {
        groups: vec![GroupConfig {
            name: "g".into(),
            axes: vec!["x".into(), "q".into()],
        }],
        ..EngineConfig::default()
    };
    assert_eq!(
        AxisEngine::with_config(axes(), &bad_axis)
            .unwrap_err()
            .error_id,
        UNKNOWN
    );
    let twice = EngineConfig {
        groups: vec![
            GroupConfig {
                name: "a".into(),
                axes: vec!["x".into()],
            },
            GroupConfig {
                name: "b".into(),
                axes: vec!["x".into()],
            },
        ],
        ..EngineConfig::default()
    };
    assert_eq!(
        AxisEngine::with_config(axes(), &twice)
            .unwrap_err()
            .error_id,
        INVALID
    );
    let dup = EngineConfig {
        groups: vec![
            GroupConfig {
                name: "a".into(),
                axes: vec![],
            },
            GroupConfig {
                name: "a".into(),
                axes: vec![],
            },
        ],
        ..EngineConfig::default()
    };
    assert_eq!(
        AxisEngine::with_config(axes(), &dup).unwrap_err().error_id,
        ErrorId::VALUE_OUT_OF_RANGE
    );
    // serde: defaults, snake_case profile names, unknown keys refused.
    let c: EngineConfig = serde_json::from_str(r#"{"platform_profile": "isg_mcp"}"#).unwrap();
    assert_eq!(c.platform_profile, PlatformProfile::IsgMcp);
    let d: EngineConfig = serde_json::from_str("{}").unwrap();
    assert_eq!(d.platform_profile, PlatformProfile::Tc2Mc2);
    assert!(serde_json::from_str::<EngineConfig>(r#"{"platform_profil": "isg_mcp"}"#).is_err());
    assert!(serde_json::from_str::<EngineConfig>(r#"{"platform_profile": "tc3"}"#).is_err());
    assert!(
        serde_json::from_str::<EngineConfig>(r#"{"groups": [{"name": "g", "axis": []}]}"#).is_err()
    );
    assert!(
        serde_json::from_str::<EngineConfig>(r#"{"platform": {"axes": {"x": {"unit": 1}}}}"#)
            .is_err()
    );
    let bad_num = EngineConfig {
        platform: PlatformConfig {
            axes: [(
                "x".to_string(),
                AxisPlatformConfig {
                    units_per_mm: f64::NAN,
                    ..Default::default()
                },
            )]
            .into(),
            ..Default::default()
        },
        ..EngineConfig::default()
    };
    assert_eq!(
        AxisEngine::with_config(axes(), &bad_num)
            .unwrap_err()
            .error_id,
        NOT_FINITE
    );
}

#[test]
fn read_actual_velocity_is_not_offered_in_isg_mcp() {
    let cfg = EngineConfig {
        platform_profile: PlatformProfile::IsgMcp,
        groups: vec![GroupConfig {
            name: G.into(),
            axes: vec!["x".into()],
        }],
        ..EngineConfig::default()
    };
    let mut r = P4::build(vec![("x".into(), axis_cfg())], cfg);
    r.steps(10);
    assert_eq!(
        err(r.g(GroupCommand::GroupReadActualVelocity {
            group: G.into(),
            coord_system: CoordSystem::Acs
        })),
        NOT_IMPL
    );
}
