//! Bad input: NaN, inf, negative, out of range, unknown names, out-of-range enums. Each is a
//! `Rejection` with an error id and a message naming object, field and value; the axis state
//! stays as it was.
mod common;
use axis_engine::*;
use common::*;
use motion_core::ErrorId;

fn moving_rig() -> Rig {
    let mut r = Rig::powered();
    r.id(abs(1000.0, 100.0));
    r.steps(20);
    r
}

fn expect(r: &mut Rig, c: AxisCommand, id: ErrorId, words: &[&str]) {
    let before = r.st();
    let e = r
        .cmd(c.clone())
        .expect_err(&format!("{c:?} must be rejected"));
    assert_eq!(e.error_id, id, "{c:?}: {}", e.message);
    for w in words {
        assert!(e.message.contains(w), "message '{}' lacks '{w}'", e.message);
    }
    assert_eq!(r.st(), before, "{c:?}: state unchanged");
}

#[test]
fn non_finite_inputs() {
    let nf = ErrorId::NOT_FINITE;
    let mut r = moving_rig();
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let s = format!("{bad}");
        expect(
            &mut r,
            abs(bad, 10.0),
            nf,
            &["axis 'x'", "MC_MoveAbsolute", "Position", &s],
        );
        expect(&mut r, abs(10.0, bad), nf, &["Velocity", &s]);
        expect(
            &mut r,
            abs_dyn(10.0, 10.0, bad, 0.0, 0.0, BufferMode::Aborting),
            nf,
            &["Acceleration"],
        );
        expect(
            &mut r,
            abs_dyn(10.0, 10.0, 0.0, bad, 0.0, BufferMode::Aborting),
            nf,
            &["Deceleration"],
        );
        expect(
            &mut r,
            abs_dyn(10.0, 10.0, 0.0, 0.0, bad, BufferMode::Aborting),
            nf,
            &["Jerk"],
        );
        expect(&mut r, rel(bad, 10.0), nf, &["MC_MoveRelative", "Distance"]);
        expect(&mut r, add(bad, 10.0), nf, &["MC_MoveAdditive", "Distance"]);
        expect(
            &mut r,
            modulo(bad, Direction::Positive),
            nf,
            &["MC_MoveModulo", "Position"],
        );
        expect(&mut r, vel(bad), nf, &["MC_MoveVelocity", "Velocity"]);
        expect(
            &mut r,
            halt(bad, 0.0, BufferMode::Aborting),
            nf,
            &["MC_Halt", "Deceleration"],
        );
        expect(&mut r, stop(0.0, bad), nf, &["MC_Stop", "Jerk"]);
        expect(
            &mut r,
            set_position(bad),
            nf,
            &["MC_SetPosition", "Position"],
        );
        let p = AxisCommand::Power(Power {
            axis: AX.into(),
            enable: true,
            enable_positive: true,
            enable_negative: true,
            override_percent: bad,
            buffer_mode: BufferMode::Aborting,
        });
        expect(&mut r, p, nf, &["MC_Power", "Override"]);
        let w = AxisCommand::WriteParameter(WriteParameter {
            axis: AX.into(),
            parameter_number: 1004,
            value: bad,
        });
        expect(&mut r, w, nf, &["Value"]);
        let o = AxisCommand::Sim(Sim::SetFollowingOffset {
            axis: AX.into(),
            offset: bad,
        });
        expect(&mut r, o, nf, &["offset"]);
        let bp = AxisCommand::MoveAbsolute(MoveAbsolute {
            buffer_mode: BufferMode::BlendingNext,
            options: MoveOptions {
                enable_blending_position: true,
                blending_position: bad,
                ..Default::default()
            },
            ..move_abs(10.0, 10.0)
        });
        expect(&mut r, bp, nf, &["BlendingPosition"]);
    }
}

#[test]
fn out_of_range_numbers() {
    let pnc = err(0x4B06);
    let mut r = moving_rig();
    expect(&mut r, abs(10.0, 0.0), pnc, &["Velocity = 0"]);
    expect(&mut r, abs(10.0, -5.0), pnc, &["Velocity = -5"]);
    expect(&mut r, abs(10.0, 2000.1), pnc, &["Velocity = 2000.1"]);
    expect(
        &mut r,
        abs_dyn(10.0, 10.0, -1.0, 0.0, 0.0, BufferMode::Aborting),
        pnc,
        &["Acceleration = -1"],
    );
    expect(
        &mut r,
        abs_dyn(10.0, 10.0, 0.0, -1.0, 0.0, BufferMode::Aborting),
        pnc,
        &["Deceleration = -1"],
    );
    expect(
        &mut r,
        abs_dyn(10.0, 10.0, 0.0, 0.0, -1.0, BufferMode::Aborting),
        pnc,
        &["Jerk = -1"],
    );
    expect(&mut r, vel(-1.0), pnc, &["Velocity"]);
    let p = AxisCommand::Power(Power {
        axis: AX.into(),
        enable: true,
        enable_positive: true,
        enable_negative: true,
        override_percent: -0.5,
        buffer_mode: BufferMode::Aborting,
    });
    expect(&mut r, p, pnc, &["Override = -0.5"]);
    let sp = AxisCommand::SetPosition(SetPosition {
        axis: AX.into(),
        position: 1.0,
        mode: false,
        options: SetPositionOptions {
            select_encoder_index: true,
            encoder_index: 1,
            ..Default::default()
        },
    });
    expect(&mut r, sp, pnc, &["EncoderIndex"]);
}

#[test]
fn directions_without_motion_direction() {
    let mut r = Rig::powered();
    for d in [
        Direction::ShortestWay,
        Direction::Undefined,
        Direction::Current,
    ] {
        expect(
            &mut r,
            AxisCommand::MoveVelocity(move_vel(10.0, d)),
            err(0x4B05),
            &["Direction"],
        );
    }
}

#[test]
fn unknown_axis() {
    let mut r = moving_rig();
    let mut c = move_abs(1.0, 1.0);
    c.axis = "nope".into();
    expect(
        &mut r,
        AxisCommand::MoveAbsolute(c),
        ErrorId::UNKNOWN_OBJECT,
        &["nope"],
    );
    expect(
        &mut r,
        AxisCommand::Reset(Reset { axis: "".into() }),
        ErrorId::UNKNOWN_OBJECT,
        &["axis"],
    );
}

#[test]
fn out_of_range_enums() {
    let cases: Vec<(Result<(), motion_core::Rejection>, &str)> = vec![
        (BufferMode::from_raw(6).map(|_| ()), "BufferMode = 6"),
        (Direction::from_raw(0).map(|_| ()), "Direction = 0"),
        (Direction::from_raw(5).map(|_| ()), "Direction = 5"),
        (JogMode::from_raw(5).map(|_| ()), "Mode = 5"),
        (HomingMode::from_raw(4).map(|_| ()), "HomingMode = 4"),
    ];
    for (res, words) in cases {
        let e = res.unwrap_err();
        assert_eq!(e.error_id, ErrorId::ENUM_OUT_OF_RANGE);
        assert!(e.message.contains(words), "{}", e.message);
    }
    assert_eq!(BufferMode::from_raw(5).unwrap(), BufferMode::BlendingHigh);
    assert_eq!(Direction::from_raw(128).unwrap(), Direction::Undefined);
}

#[test]
fn config_validation_names_axis_key_and_value() {
    let bad = [
        (
            AxisConfig {
                acceleration: f64::NAN,
                ..Default::default()
            },
            ErrorId::NOT_FINITE,
            "acceleration = NaN",
        ),
        (
            AxisConfig {
                max_velocity: -1.0,
                ..Default::default()
            },
            ErrorId::VALUE_OUT_OF_RANGE,
            "max_velocity = -1",
        ),
        (
            AxisConfig {
                jerk: 0.0,
                ..Default::default()
            },
            ErrorId::VALUE_OUT_OF_RANGE,
            "jerk = 0",
        ),
        (
            AxisConfig {
                target_position_window: -0.1,
                ..Default::default()
            },
            ErrorId::VALUE_OUT_OF_RANGE,
            "target_position_window = -0.1",
        ),
        (
            AxisConfig {
                modulo_value: f64::INFINITY,
                ..Default::default()
            },
            ErrorId::NOT_FINITE,
            "modulo_value = inf",
        ),
        (
            AxisConfig {
                encoder_reference_mode: 9,
                ..Default::default()
            },
            ErrorId::ENUM_OUT_OF_RANGE,
            "encoder_reference_mode = 9",
        ),
    ];
    for (cfg, id, words) in bad {
        let e = AxisEngine::new(vec![("ax1".into(), cfg)]).unwrap_err();
        assert_eq!(e.error_id, id, "{}", e.message);
        assert!(
            e.message.contains("ax1") && e.message.contains(words),
            "{}",
            e.message
        );
    }
    let e = AxisEngine::new(vec![
        ("a".into(), AxisConfig::default()),
        ("a".into(), AxisConfig::default()),
    ])
    .unwrap_err();
    assert!(e.message.contains("'a'"));
}

#[test]
fn config_deserialization_defaults_and_unknown_keys() {
    let cfg: AxisConfig =
        serde_json::from_str(r#"{"max_velocity": 500, "following_model": "first_order"}"#).unwrap();
    assert_eq!(cfg.max_velocity, 500.0);
    assert_eq!(cfg.acceleration, 1000.0, "§1.2 default");
    assert_eq!(cfg.following_model, FollowingModel::FirstOrder);
    let e = serde_json::from_str::<AxisConfig>(r#"{"max_velocty": 500}"#).unwrap_err();
    assert!(e.to_string().contains("max_velocty"), "{e}");
}

#[test]
fn degenerate_ticks_do_nothing() {
    use motion_core::{Engine, Tick};
    let mut r = moving_rig();
    let before = r.st();
    let mut ev = Vec::new();
    for dt in [0.0, -0.001, f64::NAN, f64::INFINITY] {
        r.e.step(Tick { index: 0, dt }, &mut ev);
    }
    assert_eq!(r.st(), before);
}
