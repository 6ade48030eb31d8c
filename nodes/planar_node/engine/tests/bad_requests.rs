//! Bad requests return an error id and a message naming object, field and value, and leave
//! the engine exactly as it was (checked against a twin engine that never saw them).

mod common;
use common::*;
use motion_core::Engine as _;
use motion_core::ErrorId;
use planar_engine::*;

fn twin() -> (Sim, Sim) {
    let mk = || {
        let mut s = Sim::new(two_parts());
        s.enable("M");
        s.ok(mtp_ref("M", 60.0, 100.0, 0.0, PART_R));
        s.steps(50);
        s
    };
    (mk(), mk())
}

fn cases() -> Vec<(PlanarCommand, ErrorId, &'static str)> {
    let nan = f64::NAN;
    let inf = f64::INFINITY;
    let dc = DynamicConstraint::default();
    let mv = |x: f64, y: f64, c: f64, r: u32, constraint: DynamicConstraint| {
        PlanarCommand::MoveToPosition {
            mover: "M".into(),
            target_position: PositionXYC::with_ref(x, y, c, r),
            constraint,
            options: Default::default(),
        }
    };
    vec![
        (
            mtp("nobody", 0.0, 0.0, 0.0),
            ErrorId::UNKNOWN_OBJECT,
            "nobody",
        ),
        (
            PlanarCommand::GroupEnable {
                group: "nogroup".into(),
            },
            ErrorId::UNKNOWN_OBJECT,
            "nogroup",
        ),
        (
            PlanarCommand::ActivatePosition {
                part: "nopart".into(),
                position_index: 1,
            },
            ErrorId::UNKNOWN_OBJECT,
            "nopart",
        ),
        (
            mv(nan, 0.0, 0.0, CS, dc),
            ErrorId::NOT_FINITE,
            "target_position.x",
        ),
        (
            mv(0.0, inf, 0.0, CS, dc),
            ErrorId::NOT_FINITE,
            "target_position.y",
        ),
        (
            mv(0.0, 0.0, -inf, CS, dc),
            ErrorId::NOT_FINITE,
            "target_position.c",
        ),
        (
            mv(
                100.0,
                100.0,
                0.0,
                CS,
                DynamicConstraint {
                    velocity: nan,
                    ..dc
                },
            ),
            ErrorId::NOT_FINITE,
            "constraint.velocity",
        ),
        (
            mv(
                100.0,
                100.0,
                0.0,
                CS,
                DynamicConstraint {
                    velocity: -1.0,
                    ..dc
                },
            ),
            errors::E_INVALID_PARAMETER,
            "constraint.velocity = -1",
        ),
        (
            mv(
                100.0,
                100.0,
                0.0,
                CS,
                DynamicConstraint { jerk: -5.0, ..dc },
            ),
            errors::E_INVALID_PARAMETER,
            "constraint.jerk = -5",
        ),
        (
            mv(
                100.0,
                100.0,
                0.0,
                CS,
                DynamicConstraint {
                    deceleration: -0.5,
                    ..dc
                },
            ),
            errors::E_INVALID_PARAMETER,
            "deceleration",
        ),
        (
            mv(100.0, 100.0, 0.0, 0x1234_5678, dc),
            errors::E_INVALID_REFERENCE_ID,
            "0x12345678",
        ),
        (
            PlanarCommand::MoveZ {
                mover: "M".into(),
                target_position: nan,
                constraint: dc,
            },
            ErrorId::NOT_FINITE,
            "target_position",
        ),
        (
            PlanarCommand::MoveZ {
                mover: "M".into(),
                target_position: 100.0,
                constraint: dc,
            },
            errors::E_INVALID_PARAMETER,
            "100",
        ),
        (
            PlanarCommand::MoveB {
                mover: "M".into(),
                target_position: 1.0,
                constraint: DynamicConstraint {
                    acceleration: -3.0,
                    ..dc
                },
            },
            errors::E_INVALID_PARAMETER,
            "acceleration",
        ),
        (
            PlanarCommand::Halt {
                mover: "M".into(),
                constraint: DynamicConstraint { jerk: nan, ..dc },
            },
            ErrorId::NOT_FINITE,
            "constraint.jerk",
        ),
        (
            PlanarCommand::StartExternalSetpointGeneration {
                mover: "M".into(),
                options: ExternalSetpointGenerationOptions {
                    mode: ExternalSetpointMode::None,
                },
            },
            ErrorId::ENUM_OUT_OF_RANGE,
            "None",
        ),
        (
            PlanarCommand::AddStator {
                lower_x: nan,
                lower_y: 0.0,
            },
            ErrorId::NOT_FINITE,
            "lower_x",
        ),
        (
            PlanarCommand::SetPosition {
                mover: "M".into(),
                position: PositionXYC::new(0.0, 0.0, 0.0),
            },
            errors::E_INVALID_STATE,
            "Disabled",
        ),
        (
            PlanarCommand::PartInitialize {
                part: "L".into(),
                part_oid: 0x0101_0099,
            },
            errors::E_INVALID_PART,
            "0x01010099",
        ),
        (
            PlanarCommand::MoverAddToGroup {
                mover: "M".into(),
                group: "nogroup".into(),
            },
            ErrorId::UNKNOWN_OBJECT,
            "nogroup",
        ),
        (
            PlanarCommand::InjectError {
                kind: ObjectKind::Mover,
                name: "M".into(),
                reaction: ErrorReaction::None,
            },
            ErrorId::ENUM_OUT_OF_RANGE,
            "None",
        ),
    ]
}

#[test]
fn bad_requests_are_rejected_and_change_nothing() {
    let (mut a, mut b) = twin();
    for (cmd, id, needle) in cases() {
        let before = format!("{:?}", a.snap());
        let dbg = format!("{cmd:?}");
        let e = a.cmd(cmd).expect_err(&dbg);
        assert_eq!(e.error_id, id, "{dbg}: {e}");
        assert!(
            e.message.contains(needle),
            "{dbg}: message '{}' should name '{needle}'",
            e.message
        );
        assert_eq!(before, format!("{:?}", a.snap()), "{dbg} changed the state");
    }
    // Identical futures: the rejected commands left no trace in the running motion.
    for _ in 0..400 {
        a.step();
        b.step();
    }
    assert_eq!(format!("{:?}", a.snap()), format!("{:?}", b.snap()));
    assert_pos(&a.mover("M"), 300.0, 100.0);
}

/// Zero in a constraint field means the mover default (§3.8, manual "0 = Default Dynamics").
#[test]
fn zero_constraint_means_default() {
    let mut s = Sim::with_movers(&[("M", 0.0, 0.0)]);
    s.enable("M");
    let id = s.ok(mtp("M", 500.0, 0.0, 0.0));
    let n0 = s.index;
    s.wait_final(id, 5.0);
    // 500 mm with v 1000, a 10000, j 100000: 0.5 + 0.1 + 0.1 s.
    assert!(((s.index - n0) as f64 * 0.001 - 0.7).abs() < 0.003);
}

/// Config validation names key and value.
#[test]
fn config_rejections_name_key_and_value() {
    let base = || PlanarConfig {
        movers: vec![MoverConfig::new("A", 0.0, 0.0, 0.0)],
        ..Default::default()
    };
    let check = |cfg: PlanarConfig, needle: &str| {
        let e = PlanarEngine::new(cfg).err().expect("accepted");
        assert_eq!(e.error_id, ErrorId::VALUE_OUT_OF_RANGE);
        assert!(
            e.message.contains(needle),
            "'{}' should contain '{needle}'",
            e.message
        );
    };
    let mut c = base();
    c.cycle_time = 0.0;
    check(c, "cycle_time = 0");
    let mut c = base();
    c.movers[0].max_dynamics.jerk = -1.0;
    check(c, "movers[0].max_dynamics.jerk = -1");
    let mut c = base();
    c.movers[0].width = f64::NAN;
    check(c, "movers[0].width = NaN");
    let mut c = base();
    c.movers.push(MoverConfig::new("B", 100.0, 0.0, 0.0));
    check(c, "overlaps mover 'A'");
    let mut c = base();
    c.movers.push(MoverConfig::new("A", 500.0, 0.0, 0.0));
    check(c, "movers[1].name = A");
    let mut c = two_parts();
    c.movers[0].part_oid = 0;
    check(c, "movers[0].part_oid = 0");
    let mut c = two_parts();
    c.parts[1].positions.get_mut(&1).unwrap().x = 100.0;
    check(c, "overlaps part 'L'");
    let mut c = two_parts();
    c.parts[0].initial_index = 2;
    check(c, "parts[0].initial_index = 2");
    let mut c = base();
    c.movers[0].c_min = 5.0;
    check(c, "c_min/c_max");
    assert!(PlanarEngine::new(base()).is_ok());
    assert!(PlanarEngine::new(two_parts()).is_ok());
}

/// The config structs refuse unknown keys (launch-YAML typos) and fill defaults.
#[test]
fn config_denies_unknown_keys() {
    use serde::de::value::{Error as DeError, MapDeserializer};
    use serde::Deserialize;
    let ok = EnvironmentConfig::deserialize(MapDeserializer::<_, DeError>::new(
        vec![("oid", 5u32), ("processing_unit_oid", 7u32)].into_iter(),
    ))
    .unwrap();
    assert_eq!(
        (ok.name.as_str(), ok.oid, ok.processing_unit_oid),
        ("environment", 5, 7)
    );
    let e = EnvironmentConfig::deserialize(MapDeserializer::<_, DeError>::new(
        vec![("oid", 5u32), ("procesing_unit_oid", 7u32)].into_iter(),
    ))
    .unwrap_err();
    assert!(e.to_string().contains("procesing_unit_oid"), "{e}");
    let e = InitialPose::deserialize(MapDeserializer::<_, DeError>::new(
        vec![("x", 1.0f64), ("z", 2.0f64)].into_iter(),
    ))
    .unwrap_err();
    assert!(e.to_string().contains("unknown field `z`"), "{e}");
    let p = InitialPose::deserialize(MapDeserializer::<_, DeError>::new(
        vec![("x", 1.0f64), ("c", 2.0f64)].into_iter(),
    ))
    .unwrap();
    assert_eq!((p.x, p.y, p.c), (1.0, 0.0, 2.0));
}

/// Issue 15.5: automatic OIDs come from a reserved block (0xFE000000..0xFEFFFFFF) that
/// configured OIDs may not use, so a user OID such as 0x01040001 (the old automatic
/// environment OID) no longer clashes; every automatic OID can be set in the config instead.
#[test]
fn automatic_oids_never_clash_with_configured_ones() {
    let mut c = PlanarConfig {
        movers: vec![
            MoverConfig::new("A", 0.0, 0.0, 0.0),
            MoverConfig::new("B", 480.0, 0.0, 0.0),
        ],
        groups: vec![GroupConfig {
            name: "G".into(),
            oid: 0,
        }],
        tracks: vec![TrackConfig::new("T")],
        axes: vec![VirtualAxisConfig {
            name: "X".into(),
            oid: 0,
        }],
        ..Default::default()
    };
    c.movers[1].oid = 0x0104_0001;
    let e = PlanarEngine::new(c.clone()).expect("a user OID 0x01040001 is accepted");
    let s = e.snapshot();
    assert_eq!(s.environment.oid, 0xFE04_0001);
    assert_eq!(s.movers[0].oid, 0xFE02_0001);
    assert_eq!(s.movers[1].oid, 0x0104_0001);
    assert_eq!(s.groups[0].oid, 0xFE03_0001);
    assert_eq!(s.tracks[0].oid, 0xFE05_0001);
    assert_eq!(s.axes[0].oid, 0xFE06_0001);
    // Every one of them can be configured.
    let mut d = c.clone();
    d.environment.oid = 0x0101_0001;
    d.movers[0].oid = 0x0101_0101;
    d.groups[0].oid = 0x0101_0201;
    d.tracks[0].oid = 0x0101_0301;
    d.axes[0].oid = 0x0101_0401;
    let s = PlanarEngine::new(d).unwrap().snapshot();
    assert_eq!(
        (
            s.environment.oid,
            s.movers[0].oid,
            s.groups[0].oid,
            s.tracks[0].oid,
            s.axes[0].oid
        ),
        (
            0x0101_0001,
            0x0101_0101,
            0x0101_0201,
            0x0101_0301,
            0x0101_0401
        )
    );
    // The reserved block is refused with the key.
    let mut r = c;
    r.tracks[0].oid = 0xFE02_0001;
    let e = PlanarEngine::new(r).err().expect("reserved OID accepted");
    assert_eq!(e.error_id, ErrorId::VALUE_OUT_OF_RANGE);
    assert!(
        e.message.contains("tracks[0].oid") && e.message.contains("reserved"),
        "{}",
        e.message
    );
}
