//! W15 — parameters and positions (§8, §4.3, §4.4.5, §4.4.8, §6).
mod common;
use axis_engine::*;
use common::*;

fn read(r: &mut Rig, n: u32) -> f64 {
    match r
        .cmd(AxisCommand::ReadParameter(ReadParameter {
            axis: AX.into(),
            parameter_number: n,
        }))
        .unwrap()
        .value
    {
        ReplyValue::Real(v) => v,
        v => panic!("{v:?}"),
    }
}

fn write(r: &mut Rig, n: u32, value: f64) -> Result<AxisReply, motion_core::Rejection> {
    r.cmd(AxisCommand::WriteParameter(WriteParameter {
        axis: AX.into(),
        parameter_number: n,
        value,
    }))
}

#[test]
fn write_sw_limit_pos_reads_back_through_its_alias() {
    let mut r = Rig::powered();
    let id = write(&mut r, 2, 2000.0).unwrap().id;
    r.step();
    assert!(r.out(id).done);
    assert_eq!(read(&mut r, 2), 2000.0);
    assert_eq!(read(&mut r, 1019), 2000.0);
}

#[test]
fn set_position_offset_accumulates_and_clears() {
    let mut r = Rig::powered();
    let origin = r.st().act_pos;
    for _ in 0..2 {
        let id = r.id(AxisCommand::SetPosition(SetPosition {
            axis: AX.into(),
            position: 100.0,
            mode: true,
            options: Default::default(),
        }));
        r.step();
        assert!(r.out(id).done);
    }
    assert_eq!(read(&mut r, 2003), 200.0);
    assert_eq!(r.st().act_pos, origin + 200.0);
    let id = r.id(AxisCommand::SetPosition(SetPosition {
        axis: AX.into(),
        position: 12345.0, // irrelevant
        mode: false,
        options: SetPositionOptions {
            clear_position_offset: true,
            ..Default::default()
        },
    }));
    r.step();
    assert!(r.out(id).done);
    assert_eq!(r.st().act_pos, origin);
    assert_eq!(read(&mut r, 2003), 0.0);
}

#[test]
fn set_position_absolute_keeps_or_clears_the_lag() {
    for (clear, want_set) in [(false, 50.3), (true, 50.0)] {
        let mut r = Rig::powered();
        // Following error 0.3: SetPos − ActPos = 0.3.
        r.cmd(AxisCommand::Sim(Sim::SetFollowingOffset {
            axis: AX.into(),
            offset: -0.3,
        }))
        .unwrap();
        r.step();
        assert!((r.st().pos_diff - 0.3).abs() < 1e-12);
        let id = r.id(AxisCommand::SetPosition(SetPosition {
            axis: AX.into(),
            position: 50.0,
            mode: false,
            options: SetPositionOptions {
                clear_position_lag: clear,
                ..Default::default()
            },
        }));
        r.step();
        assert!(r.out(id).done);
        let st = r.st();
        assert!(
            (st.act_pos - 50.0).abs() < 1e-12,
            "clear {clear}: ActPos {}",
            st.act_pos
        );
        assert!(
            (st.set_pos - want_set).abs() < 1e-12,
            "clear {clear}: SetPos {}",
            st.set_pos
        );
    }
}

#[test]
fn parameter_errors() {
    let mut r = Rig::powered();
    let e = write(&mut r, 1, 5.0).unwrap_err();
    assert_eq!(e.error_id, err(0x4D04), "read-only: {}", e.message);
    let e = write(&mut r, 77, 5.0).unwrap_err();
    assert_eq!(e.error_id, err(0x4D03), "unknown: {}", e.message);
    let e = write(&mut r, 4, 1.0).unwrap_err();
    assert_eq!(
        e.error_id,
        err(0x4B05),
        "BOOL parameter via WriteParameter: {}",
        e.message
    );
    let e = r
        .cmd(AxisCommand::ReadBoolParameter(ReadBoolParameter {
            axis: AX.into(),
            parameter_number: 1004,
        }))
        .unwrap_err();
    assert_eq!(
        e.error_id,
        err(0x4B05),
        "LREAL via ReadBoolParameter: {}",
        e.message
    );
    let e = write(&mut r, 1004, -5.0).unwrap_err();
    assert_eq!(e.error_id, err(0x4B06), "{}", e.message);
    assert!(
        e.message.contains("acceleration") && e.message.contains("-5"),
        "{}",
        e.message
    );
    let e = write(&mut r, 1004, f64::NAN).unwrap_err();
    assert_eq!(e.error_id, motion_core::ErrorId::NOT_FINITE);
    assert_eq!(read(&mut r, 1004), 1000.0, "unchanged");
    let e = r
        .cmd(AxisCommand::ReadParameter(ReadParameter {
            axis: AX.into(),
            parameter_number: 3000,
        }))
        .unwrap_err();
    assert_eq!(e.error_id, err(0x4B05), "gear ratio on a non-slave");
}

#[test]
fn bool_parameters_and_defaults() {
    let mut r = Rig::powered();
    let rb = |r: &mut Rig, n| match r
        .cmd(AxisCommand::ReadBoolParameter(ReadBoolParameter {
            axis: AX.into(),
            parameter_number: n,
        }))
        .unwrap()
        .value
    {
        ReplyValue::Bool(b) => b,
        v => panic!("{v:?}"),
    };
    assert!(
        rb(&mut r, 1025),
        "AxisEnTargetPositionMonitoring default TRUE"
    );
    assert!(!rb(&mut r, 1016));
    r.cmd(AxisCommand::WriteBoolParameter(WriteBoolParameter {
        axis: AX.into(),
        parameter_number: 5,
        value: true,
    }))
    .unwrap();
    assert!(
        rb(&mut r, 1016),
        "EnableLimitNeg (5) ≡ AxisEnMinSoftPosLimit (1016)"
    );
    assert_eq!(
        read(&mut r, 1016),
        1.0,
        "BOOL read with MC_ReadParameter gives 1.0"
    );
    // §1.2 defaults.
    for (n, v) in [
        (1008, 2000.0),
        (1004, 1000.0),
        (1005, 1000.0),
        (1006, 10000.0),
        (1053, 5000.0),
        (1054, 100000.0),
        (1011, 100.0),
        (1010, 600.0),
        (1024, 5.0),
        (1026, 2.0),
        (1027, 0.02),
        (1021, 5.0),
        (1044, 360.0),
        (1095, 1.0),
        (1050, 0.002),
        (4000, 0.002),
        (4001, 0.010),
        (1000, 1.0),
    ] {
        assert_eq!(read(&mut r, n), v, "parameter {n}");
    }
    // Parameters without simulator effect are stored.
    write(&mut r, 1031, 0.5).unwrap();
    assert_eq!(read(&mut r, 1031), 0.5);
}

#[test]
fn written_dynamics_are_used_as_defaults() {
    let mut r = Rig::powered();
    write(&mut r, 1004, 100.0).unwrap();
    write(&mut r, 1005, 100.0).unwrap();
    write(&mut r, 1006, 1000.0).unwrap();
    let id = r.id(abs(100.0, 50.0));
    let n = r.until(10000, |r| !r.st().has_job);
    // 0 -> 100 with v 50, a = d = 100, j = 1000: 2.6 s (cf. the trajectory oracle).
    assert!(
        (n as f64 * DT - 2.6).abs() <= DT + 1e-9,
        "{}",
        n as f64 * DT
    );
    let _ = id;
}

#[test]
fn set_position_while_moving_shifts_the_target_with_the_coordinates() {
    let mut r = Rig::powered();
    let a = r.id(abs(100.0, 100.0));
    r.steps(100);
    let id = r.id(AxisCommand::SetPosition(SetPosition {
        axis: AX.into(),
        position: 10.0,
        mode: true,
        options: Default::default(),
    }));
    r.until(5000, |r| r.out(a).done);
    assert!(r.out(id).done);
    assert!(
        (r.st().set_pos - 110.0).abs() < 1e-9,
        "same physical end point: {}",
        r.st().set_pos
    );
    assert!((r.st().raw_pos - 100.0).abs() < 1e-9);
}
