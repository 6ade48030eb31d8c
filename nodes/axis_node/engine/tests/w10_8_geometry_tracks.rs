//! collision_avoidance.md §10.8 "Geo compensation numbers" (MC_TransformPosition, §5.9) and
//! the track blocks MC_ActivateTrack / MC_ReadTrackPositions (§5.6, §5.7), MC_RegisterCompensation
//! (§5.8).

mod ca_common;
use axis_engine::ca::geometry::*;
use axis_engine::ca::types::errors::*;
use axis_engine::ca::*;
use axis_engine::ReplyValue;
use ca_common::*;
use motion_core::CommandState;

const TPL: u32 = 0x0101_0010;

fn cfg() -> CaGroupConfig {
    CaGroupConfig {
        geometry: CaGeometry {
            rail_offset: 0.0,
            curve_arc_length: 500.0,
            mover_templates: vec![MoverTemplate {
                oid: TPL,
                y_shift: 100.0,
                active: true,
            }],
            parts: vec![
                Part {
                    oid: 0x0102_0001,
                    start: 0.0,
                    length: 1500.0,
                },
                Part {
                    oid: 0x0102_0002,
                    start: 1500.0,
                    length: 1500.0,
                },
            ],
            tracks: vec![
                Track {
                    oid: 0x0103_0001,
                    parts: vec![0x0102_0001, 0x0102_0002],
                },
                Track {
                    oid: 0x0103_0002,
                    parts: vec![0x0102_0002],
                },
            ],
        },
        ..ring(3000.0)
    }
}

fn value(r: &mut CaRig, c: CaCommand) -> CaValue {
    match r.ca(c).unwrap().value {
        ReplyValue::Ca(v) => *v,
        v => panic!("{v:?}"),
    }
}

fn tf(r: &mut CaRig, from: u32, to: u32, x: f64) -> f64 {
    match value(
        r,
        CaCommand::TransformPosition {
            group: G.into(),
            origin_oid: from,
            destination_oid: to,
            origin_position: McLreal::Value(x),
        },
    ) {
        CaValue::Position(y) => y,
        v => panic!("{v:?}"),
    }
}

#[test]
fn transform_position_numbers() {
    let mut r = CaRig::new(&[("A", 0.0)], cfg());
    for (m, t) in [
        (500.0, 500.0),
        (1000.0, 1000.0),
        (1250.0, 1407.080),
        (1500.0, 1814.159),
        (2500.0, 2814.159),
        (3000.0, 3628.319),
    ] {
        let y = tf(&mut r, 0, TPL, m);
        assert!((y - t).abs() < 1e-3, "{m} → {y}, want {t}");
    }
    assert!(
        (tf(&mut r, TPL, 0, 1407.080) - 1250.0).abs() < 1e-3,
        "inverse"
    );
    // Two movers in the first curve, 150 apart on the offset path: 92.12 on the motor path.
    let s = tf(&mut r, 0, TPL, 1300.0);
    let back = tf(&mut r, TPL, 0, s - 150.0);
    assert!(
        (1300.0 - back - 92.12).abs() < 0.01,
        "motor distance {}",
        1300.0 - back
    );
    assert_eq!(tf(&mut r, TPL, TPL, 777.0), 777.0);
    let e = r.err(CaCommand::TransformPosition {
        group: G.into(),
        origin_oid: 0,
        destination_oid: 0x99,
        origin_position: McLreal::Value(1.0),
    });
    assert_eq!(e, COMPENSATION_ERROR);
}

#[test]
fn tracks_activate_read_and_move_in_track_coordinates() {
    let mut r = CaRig::new(&[("A", 1600.0)], cfg());
    // No track: absolute positions, ids 0.
    let v = value(&mut r, CaCommand::ReadTrackPositions { axis: "A".into() });
    assert_eq!(
        v,
        CaValue::TrackPositions {
            valid: true,
            track_position: 1600.0,
            track_id: 0,
            part_position: 1600.0,
            part_id: 0
        }
    );
    // Track 2 starts at 1500: A at track position 100, part position 100.
    r.ok(CaCommand::ActivateTrack {
        axis: "A".into(),
        track_id: 0x0103_0002,
    });
    let v = value(&mut r, CaCommand::ReadTrackPositions { axis: "A".into() });
    assert_eq!(
        v,
        CaValue::TrackPositions {
            valid: true,
            track_position: 100.0,
            track_id: 0x0103_0002,
            part_position: 100.0,
            part_id: 0x0102_0002
        }
    );
    let id = r.mv_abs("A", 300.0, 500.0);
    r.until(3000, |r| r.cmd_state(id) == CommandState::Done);
    assert_eq!(r.pos("A"), 1800.0, "track coordinate 300 = absolute 1800");
    // Errors: unknown track, mover not on a part of the track.
    assert_eq!(
        r.err(CaCommand::ActivateTrack {
            axis: "A".into(),
            track_id: 0x77
        }),
        TRACK_ERROR
    );
    let mut r2 = CaRig::new(&[("B", 100.0)], cfg());
    assert_eq!(
        r2.err(CaCommand::ActivateTrack {
            axis: "B".into(),
            track_id: 0x0103_0002
        }),
        TRACK_ERROR
    );
    assert_eq!(
        r2.err(CaCommand::ReadTrackPositions {
            axis: "nobody".into()
        }),
        AXIS_NOT_IN_GROUP
    );
}

#[test]
fn register_compensation() {
    let mut r = CaRig::new(&[("A", 0.0)], cfg());
    r.ok(CaCommand::RegisterCompensation {
        axis: "A".into(),
        compensation_type: 1,
        compensation_id: TPL,
    });
    assert_eq!(r.axis("A").compensation_id, TPL);
    let e = r.err(CaCommand::RegisterCompensation {
        axis: "A".into(),
        compensation_type: 0,
        compensation_id: TPL,
    });
    assert_eq!(e, INVALID_MODE);
    r.ok(CaCommand::SetTemplateActive {
        group: G.into(),
        oid: TPL,
        active: false,
    });
    let e = r.err(CaCommand::RegisterCompensation {
        axis: "A".into(),
        compensation_type: 1,
        compensation_id: TPL,
    });
    assert_eq!(e, COMPENSATION_ERROR, "inactive template");
    r.ok(CaCommand::RegisterCompensation {
        axis: "A".into(),
        compensation_type: 1,
        compensation_id: 0,
    });
    assert_eq!(r.axis("A").compensation_id, 0, "id 0 unregisters");
}

#[test]
fn compensated_follower_keeps_its_gap_on_the_offset_path_in_a_curve() {
    let mut r = CaRig::new(&[("L", 1300.0), ("F", 900.0)], cfg());
    r.ok(CaCommand::RegisterCompensation {
        axis: "F".into(),
        compensation_type: 1,
        compensation_id: TPL,
    });
    let f = r.ok(CaCommand::MoveAbsolute(MoveAbsoluteCa {
        axis: "F".into(),
        position: McLreal::Value(1290.0),
        velocity: McLreal::Value(500.0),
        gap: McLreal::Value(150.0),
        ..Default::default()
    }));
    for _ in 0..3000 {
        r.step();
        assert!(
            r.axis("F").gap_actual >= 150.0 - 1e-6,
            "offset-path gap {}",
            r.axis("F").gap_actual
        );
    }
    assert_eq!(r.cmd_state(f), CommandState::Active, "blocked");
    assert!(
        (r.axis("F").gap_actual - 150.0).abs() < 1e-3,
        "offset gap 150: {}",
        r.axis("F").gap_actual
    );
    let motor = r.pos("L") - r.pos("F");
    assert!(
        (motor - 92.12).abs() < 0.01,
        "only 92.12 mm apart on the motor path: {motor}"
    );
}

#[test]
fn position_reference_system_offset_path_targets() {
    let mut r = CaRig::new(&[("A", 0.0)], cfg());
    let mv = |prs: u32| MoveAbsoluteCa {
        axis: "A".into(),
        position: McLreal::Value(1407.080),
        velocity: McLreal::Value(1000.0),
        position_reference_system: prs,
        ..Default::default()
    };
    assert_eq!(
        r.err(CaCommand::MoveAbsolute(mv(TPL))),
        COMPENSATION_ERROR,
        "not registered"
    );
    r.ok(CaCommand::RegisterCompensation {
        axis: "A".into(),
        compensation_type: 1,
        compensation_id: TPL,
    });
    let id = r.ok(CaCommand::MoveAbsolute(mv(TPL)));
    r.until(5000, |r| r.cmd_state(id) == CommandState::Done);
    assert!(
        (r.pos("A") - 1250.0).abs() < 1e-3,
        "offset 1407.080 = motor 1250: {}",
        r.pos("A")
    );
    let id = r.ok(CaCommand::MoveRelative(MoveRelativeCa {
        axis: "A".into(),
        distance: McLreal::Value(1814.159 - 1407.080),
        velocity: McLreal::Value(1000.0),
        position_reference_system: TPL,
        ..Default::default()
    }));
    r.until(5000, |r| r.cmd_state(id) == CommandState::Done);
    assert!(
        (r.pos("A") - 1500.0).abs() < 1e-2,
        "offset 1814.159 = motor 1500: {}",
        r.pos("A")
    );
}

#[test]
fn dynamics_reference_system_limits_the_offset_path_velocity() {
    let mut r = CaRig::new(&[("A", 500.0)], cfg());
    r.ok(CaCommand::RegisterCompensation {
        axis: "A".into(),
        compensation_type: 1,
        compensation_id: TPL,
    });
    let id = r.ok(CaCommand::MoveAbsolute(MoveAbsoluteCa {
        axis: "A".into(),
        position: McLreal::Value(2500.0),
        velocity: McLreal::Value(500.0),
        dynamics_reference_system: TPL,
        ..Default::default()
    }));
    let slope = (500.0 + std::f64::consts::PI * 100.0) / 500.0;
    let (mut in_curve, mut on_straight) = (false, false);
    for _ in 0..6000 {
        r.step();
        let a = r.axis("A");
        if (1100.0..1400.0).contains(&a.position) {
            assert!(
                (a.velocity - 500.0 / slope).abs() < 1e-6,
                "curve: TCP at 500, motor {}",
                a.velocity
            );
            in_curve = true;
        }
        if (1600.0..2000.0).contains(&a.position) {
            assert!(
                (a.velocity - 500.0).abs() < 1e-6,
                "straight: motor 500: {}",
                a.velocity
            );
            on_straight = true;
        }
    }
    assert!(in_curve && on_straight);
    assert_eq!(r.cmd_state(id), CommandState::Done);
    assert!((r.pos("A") - 2500.0).abs() < 1e-6);
}
