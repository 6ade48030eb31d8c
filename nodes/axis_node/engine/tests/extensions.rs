//! §4.7 special extensions and §4.4.3/§4.4.6/§4.4.9: drive operation mode, position
//! corrections (W20 backlash, W11 table, limiter), encoder scaling and conversions, control
//! loop, blocked-drive signal, NC I/O outputs, parameter set, axis components, drive address,
//! persistent parameters, bad input.
mod common;
use axis_engine::*;
use common::*;
use motion_core::CmdId;

fn ext(r: &Rig) -> ExtStatus {
    r.e.ext_status(AX).unwrap()
}

fn extra(r: &mut Rig, id: CmdId) -> ExtraOutputs {
    match r.cmd(AxisCommand::ReadFbOutputs { id }).unwrap().value {
        ReplyValue::Outputs(o) => o.extra.expect("extra outputs"),
        v => panic!("{v:?}"),
    }
}

fn value(reply: AxisReply) -> ExtensionValue {
    match reply.value {
        ReplyValue::Extension(v) => *v,
        v => panic!("{v:?}"),
    }
}

fn expect_err(r: &mut Rig, c: AxisCommand, id: u32) {
    let before = (r.st(), ext(r));
    let e = r
        .cmd(c.clone())
        .expect_err(&format!("{c:?} must be rejected"));
    assert_eq!(e.error_id, err(id), "{c:?}: {}", e.message);
    assert_eq!((r.st(), ext(r)), before, "{c:?}: axis unchanged");
}

fn corr_cfg() -> AxisConfig {
    AxisConfig {
        enable_pos_correction: true,
        ..Default::default()
    }
}

// ------------------------------------------------------------------ §4.7.1

fn read_mode(r: &mut Rig) -> DriveOperationMode {
    let reply = r
        .cmd(AxisCommand::ReadDriveOperationMode(
            ReadDriveOperationMode { axis: AX.into() },
        ))
        .unwrap();
    match value(reply) {
        ExtensionValue::DriveOperationMode(m) => m,
        v => panic!("{v:?}"),
    }
}

fn write_mode(m: DriveOperationMode) -> AxisCommand {
    AxisCommand::WriteDriveOperationMode(WriteDriveOperationMode {
        axis: AX.into(),
        drive_operation_mode: m,
    })
}

#[test]
fn drive_operation_mode() {
    let mut r = Rig::powered();
    assert_eq!(read_mode(&mut r), DriveOperationMode::Pos1, "default CSP");
    let id = r.id(write_mode(DriveOperationMode::Velo1));
    r.step();
    assert!(r.out(id).done);
    assert_eq!(read_mode(&mut r), DriveOperationMode::Velo1);
    r.id(write_mode(DriveOperationMode::Default));
    assert_eq!(
        read_mode(&mut r),
        DriveOperationMode::Pos1,
        "Default restores Pos1"
    );
    // Also in Disabled.
    let mut d = Rig::new();
    r.id(write_mode(DriveOperationMode::Torque));
    d.id(write_mode(DriveOperationMode::Pos2));
    assert_eq!(read_mode(&mut d), DriveOperationMode::Pos2);
    // Not while moving (§2.4).
    r.id(abs(100.0, 100.0));
    r.step();
    expect_err(&mut r, write_mode(DriveOperationMode::Pos1), 0x4B01);
    let e = r
        .cmd(AxisCommand::ReadDriveOperationMode(
            ReadDriveOperationMode { axis: AX.into() },
        ))
        .unwrap_err();
    assert_eq!(e.error_id, err(0x4B01));
    assert_eq!(
        DriveOperationMode::from_raw(7).unwrap_err().error_id,
        err(0x7F03)
    );
    assert_eq!(
        DriveOperationMode::from_raw(34).unwrap(),
        DriveOperationMode::VelocityMode
    );
}

#[test]
fn torque_control_switches_the_drive_mode() {
    let mut r = Rig::powered();
    r.id(AxisCommand::TorqueControl(TorqueControl {
        axis: AX.into(),
        continuous_update: false,
        relative: false,
        torque: 10.0,
        torque_ramp: 100.0,
        velocity_limit_high: 100.0,
        velocity_limit_low: -100.0,
        buffer_mode: BufferMode::Aborting,
        options: TorqueControlOptions::default(),
    }));
    r.steps(10);
    assert_eq!(ext(&r).drive_operation_mode, DriveOperationMode::Torque);
    r.id(halt(0.0, 0.0, BufferMode::Aborting));
    r.steps(2);
    assert_eq!(
        ext(&r).drive_operation_mode,
        DriveOperationMode::Pos1,
        "MC_Halt → CSP"
    );
}

// ------------------------------------------------------------------ W20 backlash

fn backlash(enable: bool, value: f64, positive: bool, ramp: f64, dm: DisableMode) -> AxisCommand {
    AxisCommand::BacklashCompensation(BacklashCompensation {
        axis: AX.into(),
        enable,
        backlash: value,
        compensation_in_positive_direction: positive,
        ramp,
        disable_mode: dm,
    })
}

#[test]
fn w20_positive_backlash_reference_at_the_left_flank() {
    let mut r = Rig::powered_with(corr_cfg());
    // 0.05 backlash, compensation in negative direction, ramp 1 u/s.
    let id = r.id(backlash(true, 0.05, false, 1.0, DisableMode::Hold));
    assert!(r.out(id).busy && r.out(id).active);
    let m = r.id(abs(10.0, 100.0));
    r.until(5000, |r| r.out(m).done);
    assert_eq!(ext(&r).position_correction, 0.0, "moving positive: nothing");
    let m = r.id(abs(5.0, 100.0));
    r.step();
    r.step();
    match extra(&mut r, id) {
        ExtraOutputs::Backlash {
            enabled: true,
            limiting: true,
            current_backlash,
        } => assert!(current_backlash > 0.0 && current_backlash < 0.05),
        o => panic!("{o:?}"),
    }
    r.until(5000, |r| r.out(m).done);
    // 0.05 at 1 u/s = 50 ms: long done.
    let e = ext(&r);
    assert!((e.position_correction - 0.05).abs() < 1e-12);
    assert!((e.act_pos_without_pos_correction - (r.st().act_pos - 0.05)).abs() < 1e-12);
    assert!((e.drive_set_pos - (r.st().set_pos - 0.05)).abs() < 1e-12);
    assert_eq!(
        r.st().act_pos,
        r.st().set_pos,
        "ActPos (corrected) on SetPos"
    );
    match extra(&mut r, id) {
        ExtraOutputs::Backlash { limiting, .. } => assert!(!limiting),
        o => panic!("{o:?}"),
    }
    // Positive travel again: ramps back to 0.
    let m = r.id(abs(20.0, 100.0));
    r.until(5000, |r| r.out(m).done);
    assert_eq!(ext(&r).position_correction, 0.0);
    // Enable↓: Done, outputs reset.
    r.id(backlash(false, 0.0, false, 0.0, DisableMode::Hold));
    assert!(!r.out(id).busy);
}

#[test]
fn backlash_default_value_disable_mode_and_errors() {
    let mut r = Rig::powered_with(AxisConfig {
        enable_pos_correction: true,
        backlash: -0.02,
        ..Default::default()
    });
    r.id(backlash(true, 0.0, true, 0.0, DisableMode::Reset));
    let m = r.id(abs(1.0, 100.0));
    r.until(5000, |r| r.out(m).done);
    assert_eq!(
        ext(&r).position_correction,
        -0.02,
        "AxisBacklash (1036), Ramp 0 = at once"
    );
    r.id(backlash(false, 0.0, true, 0.0, DisableMode::Reset));
    assert_eq!(ext(&r).position_correction, 0.0, "DisableModeReset");
    // Hold keeps it.
    r.id(backlash(true, 0.0, true, 0.0, DisableMode::Hold));
    r.step();
    r.id(backlash(false, 0.0, true, 0.0, DisableMode::Hold));
    assert_eq!(ext(&r).position_correction, -0.02);
    // Position correction not enabled → 0x4B04.
    let mut r = Rig::powered();
    expect_err(
        &mut r,
        backlash(true, 0.05, true, 1.0, DisableMode::Hold),
        0x4B04,
    );
    let mut r = Rig::powered_with(corr_cfg());
    expect_err(
        &mut r,
        backlash(true, f64::NAN, true, 1.0, DisableMode::Hold),
        0x7F02,
    );
    expect_err(
        &mut r,
        backlash(true, 0.05, true, f64::INFINITY, DisableMode::Hold),
        0x7F02,
    );
    expect_err(
        &mut r,
        backlash(true, 0.05, true, -1.0, DisableMode::Hold),
        0x4B06,
    );
    assert_eq!(DisableMode::from_raw(2).unwrap_err().error_id, err(0x7F03));
    // Enable FALSE without an instance: untracked no-op.
    assert!(
        !r.cmd(backlash(false, 0.0, true, 0.0, DisableMode::Hold))
            .unwrap()
            .tracked
    );
}

// ------------------------------------------------------------------ W11 table

fn w11_table() -> AxisCommand {
    let comp = [
        1.0, 0.9, 0.8, 0.7, 0.6, 0.5, 0.4, 0.3, 0.2, 0.1, 0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.4, 0.3,
        0.2, 0.1, 0.0,
    ];
    AxisCommand::TableBasedPositionCompensation(TableBasedPositionCompensation {
        axis: AX.into(),
        enable: true,
        table: comp
            .iter()
            .enumerate()
            .map(|(k, c)| PositionCompensationTableElement {
                position: -10.0 + k as f64,
                compensation: *c,
            })
            .collect(),
        table_parameter: PositionCompensationTableParameter {
            min_position: -10.0,
            max_position: 10.0,
            no_of_table_elements: 21,
            direction: WorkDirection::Both,
            modulo: false,
        },
        ramp: 0.0,
        disable_mode: DisableMode::Hold,
    })
}

#[test]
fn w11_table_based_position_compensation() {
    let mut r = Rig::powered_with(corr_cfg());
    let id = r.id(w11_table());
    const CASES: [(f64, f64); 7] = [
        (0.0, 0.0),
        (2.5, 0.25),
        (5.0, 0.5),
        (5.5, 0.45),
        (-7.5, 0.75),
        (12.0, 0.0),
        (-12.0, 1.0),
    ];
    for (pos, want) in CASES {
        r.set_pos(pos);
        r.step();
        match extra(&mut r, id) {
            ExtraOutputs::TableCompensation {
                enabled: true,
                current_correction,
                limiting: false,
            } => assert!(
                (current_correction - want).abs() < 1e-12,
                "W11 row {pos}: {current_correction} != {want}"
            ),
            o => panic!("{o:?}"),
        }
        assert!((ext(&r).position_correction - want).abs() < 1e-12);
    }
}

#[test]
fn table_ramp_direction_modulo_and_errors() {
    let mut r = Rig::powered_with(corr_cfg());
    let AxisCommand::TableBasedPositionCompensation(base) = w11_table() else {
        unreachable!()
    };
    // Ramp 1 u/s: 0.5 needs 0.5 s.
    r.set_pos(5.0);
    let id = r.id(AxisCommand::TableBasedPositionCompensation(
        TableBasedPositionCompensation {
            ramp: 1.0,
            ..base.clone()
        },
    ));
    r.step();
    match extra(&mut r, id) {
        ExtraOutputs::TableCompensation {
            current_correction,
            limiting: true,
            ..
        } => assert!((current_correction - 0.002).abs() < 1e-12),
        o => panic!("{o:?}"),
    }
    r.steps(300);
    assert!((ext(&r).position_correction - 0.5).abs() < 1e-12);
    // DisableModeReset.
    r.id(AxisCommand::TableBasedPositionCompensation(
        TableBasedPositionCompensation {
            enable: false,
            disable_mode: DisableMode::Reset,
            ..base.clone()
        },
    ));
    assert_eq!(
        ext(&r).position_correction,
        0.0,
        "DisableModeReset of the Enable↓ call"
    );
    // Modulo: 15 → −5 in the period [−10, 10).
    let mut r = Rig::powered_with(corr_cfg());
    r.set_pos(15.0);
    let mut p = base.clone();
    p.table_parameter.modulo = true;
    r.id(AxisCommand::TableBasedPositionCompensation(p));
    r.step();
    assert!((ext(&r).position_correction - 0.5).abs() < 1e-12);
    // Direction positive: after negative travel the target is 0.
    let mut r = Rig::powered_with(corr_cfg());
    let mut p = base.clone();
    p.table_parameter.direction = WorkDirection::Positive;
    r.id(AxisCommand::TableBasedPositionCompensation(p));
    let m = r.id(abs(-5.0, 100.0));
    r.until(5000, |r| r.out(m).done);
    assert_eq!(ext(&r).position_correction, 0.0);
    let m = r.id(abs(-2.0, 100.0));
    r.until(5000, |r| r.out(m).done);
    assert!((ext(&r).position_correction - 0.2).abs() < 1e-12);
    // Errors.
    let mut r = Rig::powered_with(corr_cfg());
    let with = |f: &dyn Fn(&mut TableBasedPositionCompensation)| {
        let mut c = base.clone();
        f(&mut c);
        AxisCommand::TableBasedPositionCompensation(c)
    };
    expect_err(
        &mut r,
        with(&|c| c.table_parameter.no_of_table_elements = 20),
        0x4B06,
    );
    expect_err(&mut r, with(&|c| c.table[3].position = -6.5), 0x4B06);
    expect_err(
        &mut r,
        with(&|c| c.table_parameter.max_position = 11.0),
        0x4B06,
    );
    expect_err(&mut r, with(&|c| c.table.truncate(1)), 0x4B06);
    expect_err(
        &mut r,
        with(&|c| c.table[2].compensation = f64::NAN),
        0x7F02,
    );
    expect_err(&mut r, with(&|c| c.ramp = -1.0), 0x4B06);
    let mut r = Rig::powered();
    expect_err(&mut r, with(&|_| {}), 0x4B04);
    assert_eq!(
        WorkDirection::from_raw(4).unwrap_err().error_id,
        err(0x7F03)
    );
}

// ------------------------------------------------------------------ §4.7.5 limiter

fn limiter(value: f64, mode: PositionCorrectionMode, acc: f64, len: f64) -> AxisCommand {
    AxisCommand::PositionCorrectionLimiter(PositionCorrectionLimiter {
        axis: AX.into(),
        enable: true,
        position_correction_value: value,
        correction_mode: mode,
        acceleration: acc,
        correction_length: len,
    })
}

#[test]
fn position_correction_limiter_modes() {
    use PositionCorrectionMode::*;
    let mut r = Rig::powered_with(corr_cfg());
    let id = r.id(limiter(0.3, Unlimited, 0.0, 0.0));
    r.step();
    assert!((ext(&r).position_correction - 0.3).abs() < 1e-12);
    assert_eq!(
        extra(&mut r, id),
        ExtraOutputs::CorrectionLimiter { limiting: false }
    );
    // FAST: at most Acceleration·cycle² = 1000·0.002² = 0.004 per cycle.
    assert_eq!(r.id(limiter(0.5, Fast, 1000.0, 0.0)), id, "same instance");
    r.step();
    assert!((ext(&r).position_correction - 0.304).abs() < 1e-12);
    assert_eq!(
        extra(&mut r, id),
        ExtraOutputs::CorrectionLimiter { limiting: true }
    );
    r.steps(49);
    assert!((ext(&r).position_correction - 0.5).abs() < 1e-12);
    // FULLLENGTH: a change of 1.0 spread over 10 u of travel; nothing at standstill.
    r.id(limiter(1.5, FullLength, 0.0, 10.0));
    r.steps(10);
    assert!((ext(&r).position_correction - 0.5).abs() < 1e-12);
    let m = r.id(rel(5.0, 100.0));
    r.until(5000, |r| r.out(m).done);
    assert!(
        (ext(&r).position_correction - 1.0).abs() < 1e-9,
        "half the length, half the change"
    );
    let m = r.id(rel(-5.0, 100.0));
    r.until(5000, |r| r.out(m).done);
    assert!((ext(&r).position_correction - 1.5).abs() < 1e-9);
    // Errors.
    expect_err(&mut r, limiter(f64::NAN, Unlimited, 0.0, 0.0), 0x7F02);
    expect_err(&mut r, limiter(1.0, Fast, -1.0, 0.0), 0x4B06);
    expect_err(&mut r, limiter(1.0, FullLength, 0.0, 0.0), 0x4B06);
    let mut r = Rig::powered();
    expect_err(&mut r, limiter(1.0, Unlimited, 0.0, 0.0), 0x4B04);
    assert_eq!(
        PositionCorrectionMode::from_raw(3).unwrap_err().error_id,
        err(0x7F03)
    );
}

// ------------------------------------------------------------------ §4.7.9, §4.7.13

fn scaling(f: f64, mode: SetScalingFactorMode) -> AxisCommand {
    AxisCommand::SetEncoderScalingFactor(SetEncoderScalingFactor {
        axis: AX.into(),
        scaling_factor: f,
        mode,
        options: SetEncoderScalingOptions::default(),
    })
}

fn scaled_rig() -> Rig {
    let mut r = Rig::powered_with(AxisConfig {
        encoder_scaling_factor: 0.001,
        ..Default::default()
    });
    let m = r.id(abs(100.0, 100.0));
    r.until(5000, |r| r.out(m).done);
    assert_eq!(ext(&r).encoder_increments, 100_000);
    r
}

#[test]
fn encoder_scaling_factor_example() {
    // §4.7.9: at 100 u with factor 0.001 (100 000 inc, offset 0).
    let mut r = scaled_rig();
    let id = r.id(scaling(0.002, SetScalingFactorMode::Absolute));
    assert!(
        (r.st().act_pos - 200.0).abs() < 1e-9,
        "ABSOLUTE: the position jumps"
    );
    r.step();
    assert!(r.out(id).done);
    let mut r = scaled_rig();
    r.id(scaling(0.002, SetScalingFactorMode::Relative));
    assert!((r.st().act_pos - 100.0).abs() < 1e-9, "RELATIVE: no jump");
    assert!((ext(&r).encoder_offset + 100.0).abs() < 1e-9, "offset −100");
    let v = r
        .cmd(AxisCommand::ReadParameter(ReadParameter {
            axis: AX.into(),
            parameter_number: 1040,
        }))
        .unwrap()
        .value;
    assert_eq!(
        v,
        ReplyValue::Real(0.002),
        "AxisEncoderScalingFactor (1040)"
    );
    // Errors.
    for f in [0.0, -0.001] {
        expect_err(&mut r, scaling(f, SetScalingFactorMode::Absolute), 0x4B06);
    }
    expect_err(
        &mut r,
        scaling(f64::NAN, SetScalingFactorMode::Absolute),
        0x7F02,
    );
    expect_err(
        &mut r,
        AxisCommand::SetEncoderScalingFactor(SetEncoderScalingFactor {
            axis: AX.into(),
            scaling_factor: 0.001,
            mode: SetScalingFactorMode::Relative,
            options: SetEncoderScalingOptions {
                select_encoder_index: true,
                encoder_index: 1,
            },
        }),
        0x4B06,
    );
    assert_eq!(
        SetScalingFactorMode::from_raw(2).unwrap_err().error_id,
        err(0x7F03)
    );
}

#[test]
fn convert_inc_pos_and_pos() {
    let mut r = scaled_rig();
    let to_inc = |p: f64| {
        AxisCommand::ConvertPosToIncPos(ConvertPosToIncPos {
            axis: AX.into(),
            position: p,
            options: NcPositionConversionOptions::default(),
        })
    };
    let to_pos = |i: u32| {
        AxisCommand::ConvertIncPosToPos(ConvertIncPosToPos {
            axis: AX.into(),
            inc_pos: i,
            options: NcPositionConversionOptions::default(),
        })
    };
    assert_eq!(
        r.cmd(to_inc(100.0)).unwrap().value,
        ReplyValue::DWord(100_000)
    );
    assert_eq!(
        r.cmd(to_inc(100.5)).unwrap().value,
        ReplyValue::DWord(100_500)
    );
    assert_eq!(
        r.cmd(to_pos(100_500)).unwrap().value,
        ReplyValue::Real(100.5)
    );
    // Negative positions wrap the 32-bit counter; converting back gives the position.
    let ReplyValue::DWord(i) = r.cmd(to_inc(-1.0)).unwrap().value else {
        panic!()
    };
    assert_eq!(i, u32::MAX - 999);
    let ReplyValue::Real(p) = r.cmd(to_pos(i)).unwrap().value else {
        panic!()
    };
    assert!((p + 1.0).abs() < 1e-9);
    // Ambiguous: farther than half the counter range (2^31 · 0.001 ≈ 2.1e6 u).
    expect_err(&mut r, to_inc(3.0e6), 0x4B06);
    expect_err(&mut r, to_inc(f64::NAN), 0x7F02);
}

// ------------------------------------------------------------------ the rest

#[test]
fn select_control_loop() {
    let mut r = Rig::powered();
    let c = |index: u16, ty: SelectControlLoopType| {
        AxisCommand::SelectControlLoop(SelectControlLoop {
            axis: AX.into(),
            encoder_index: index,
            select_type: ty,
            sync_value: 0.0,
            ext_set_point_gen: false,
        })
    };
    let id = r.id(c(0, SelectControlLoopType::Standard));
    r.step();
    assert!(r.out(id).done);
    expect_err(&mut r, c(1, SelectControlLoopType::Standard), 0x4B06);
    expect_err(
        &mut r,
        c(0, SelectControlLoopType::InternalSyncValue),
        0x4B04,
    );
    expect_err(
        &mut r,
        AxisCommand::SelectControlLoop(SelectControlLoop {
            axis: AX.into(),
            encoder_index: 0,
            select_type: SelectControlLoopType::Standard,
            sync_value: f64::INFINITY,
            ext_set_point_gen: false,
        }),
        0x7F02,
    );
}

#[test]
fn accept_blocked_drive_suppresses_the_lag_error() {
    let mut r = Rig::powered();
    let c = |enable| {
        AxisCommand::SetAcceptBlockedDriveSignal(SetAcceptBlockedDriveSignal {
            axis: AX.into(),
            enable,
        })
    };
    assert_eq!(r.cmd(c(true)).unwrap().value, ReplyValue::Bool(false));
    assert!(ext(&r).accept_blocked_drive);
    r.cmd(AxisCommand::Sim(Sim::SetFollowingOffset {
        axis: AX.into(),
        offset: 10.0,
    }))
    .unwrap();
    r.steps(100);
    assert_eq!(r.st().motion_state, MotionState::Standstill, "no lag error");
    r.cmd(c(false)).unwrap();
    r.steps(100);
    assert_eq!(r.st().motion_state, MotionState::ErrorStop);
    assert_eq!(r.st().error_code, 0x4550);
}

#[test]
fn write_nc_io_output_masks_bits() {
    let mut r = Rig::powered();
    let w = |dev, out, mask, vals| {
        AxisCommand::WriteNcIoOutput(WriteNcIoOutput {
            axis: AX.into(),
            device: dev,
            nc_io_output: out,
            bit_select_mask: mask,
            bit_values: vals,
        })
    };
    let id = r.id(w(NcIoDevice::Drive, NcIoOutput::NCtrl2, 0xFF, 0xABCD));
    r.step();
    assert!(r.out(id).done);
    r.id(w(NcIoDevice::Drive, NcIoOutput::NCtrl2, 0xF0F, 0x0F0));
    r.id(w(NcIoDevice::Encoder, NcIoOutput::NDataOut6, 0, 0xFFFF));
    let e = ext(&r);
    assert_eq!(
        e.nc_io_outputs[0][1], 0x0C0,
        "(0xCD & !0xF0F) | (0x0F0 & 0xF0F)"
    );
    assert_eq!(e.nc_io_outputs[1][13], 0, "mask 0 writes nothing");
    assert_eq!(NcIoOutput::from_raw(14).unwrap_err().error_id, err(0x7F03));
    assert_eq!(NcIoDevice::from_raw(2).unwrap_err().error_id, err(0x7F03));
}

#[test]
fn parameter_set_components_and_drive_address() {
    let mut r = Rig::powered();
    let ExtensionValue::ParameterSet(p) = value(
        r.cmd(AxisCommand::ReadParameterSet(ReadParameterSet {
            axis: AX.into(),
        }))
        .unwrap(),
    ) else {
        panic!()
    };
    assert_eq!(p.axis_id, 1);
    assert_eq!(p.axis_name, "x");
    assert_eq!(p.velo_maximum, 2000.0);
    assert_eq!(p.acceleration, 1000.0);
    assert_eq!(p.jerk, 10000.0);
    assert_eq!(p.enc_scale_factor, 0.0001);
    assert_eq!(p.enc_type, 1, "NcEncoderType_Simulation");
    let reply = r
        .cmd(AxisCommand::ReadAxisComponents(ReadAxisComponents {
            axis: AX.into(),
        }))
        .unwrap();
    let id = reply.id;
    let ExtensionValue::AxisComponents(c) = value(reply) else {
        panic!()
    };
    assert_eq!(c.encoder_ids, [1, 0, 0, 0, 0, 0, 0, 0, 0]);
    assert_eq!(c.drive_ids[0], 1);
    assert_eq!(c.controller_ids[0], 1);
    r.step();
    assert!(r.out(id).done);
    let ExtensionValue::DriveAddress(d) = value(
        r.cmd(AxisCommand::ReadDriveAddress(ReadDriveAddress {
            axis: AX.into(),
        }))
        .unwrap(),
    ) else {
        panic!()
    };
    assert_eq!(d.net_id, "127.0.0.1.1.1");
    assert_eq!(d.slave_address, 0);
    assert_eq!((d.nc_axis_id, d.nc_encoder_type, d.nc_axis_type), (1, 1, 1));
    let e = r
        .cmd(AxisCommand::ReadDriveAddress(ReadDriveAddress {
            axis: "nope".into(),
        }))
        .unwrap_err();
    assert_eq!(e.error_id, err(0x7F01));
}

#[test]
fn persistent_parameters() {
    let mut r = Rig::powered();
    let id = r.id(AxisCommand::WriteParameterPersistent(WriteParameter {
        axis: AX.into(),
        parameter_number: 2,
        value: 2000.0,
    }));
    r.step();
    assert!(r.out(id).done);
    r.id(AxisCommand::WriteBoolParameterPersistent(
        WriteBoolParameter {
            axis: AX.into(),
            parameter_number: 4,
            value: true,
        },
    ));
    r.id(AxisCommand::WriteParameterPersistent(WriteParameter {
        axis: AX.into(),
        parameter_number: 2,
        value: 1500.0,
    }));
    let list = r.e.persistent_parameters(AX).unwrap();
    assert_eq!(list, vec![(4, 1.0), (2, 1500.0)], "last write wins");
    let read = |r: &mut Rig, n| {
        r.cmd(AxisCommand::ReadParameter(ReadParameter {
            axis: AX.into(),
            parameter_number: n,
        }))
        .unwrap()
        .value
    };
    assert_eq!(read(&mut r, 1019), ReplyValue::Real(1500.0), "alias of 2");
    // A new engine (system start) gets the list back.
    let mut fresh = Rig::powered();
    fresh.e.apply_persistent_parameters(AX, &list).unwrap();
    assert_eq!(read(&mut fresh, 2), ReplyValue::Real(1500.0));
    assert_eq!(read(&mut fresh, 4), ReplyValue::Real(1.0));
    // Same errors as MC_WriteParameter; a refused write is not stored.
    for (n, v, e) in [
        (1u32, 1.0, 0x4D04),
        (9999, 1.0, 0x4D03),
        (2, f64::NAN, 0x7F02),
        (4, 1.0, 0x4B05),
    ] {
        let got = r
            .cmd(AxisCommand::WriteParameterPersistent(WriteParameter {
                axis: AX.into(),
                parameter_number: n,
                value: v,
            }))
            .unwrap_err();
        assert_eq!(got.error_id, err(e), "{n}: {}", got.message);
    }
    assert_eq!(r.e.persistent_parameters(AX).unwrap().len(), 2);
}

#[test]
fn fb_names_of_the_added_kinds() {
    assert_eq!(FbKind::PhasingAbsolute.fb_name(), "MC_PhasingAbsolute");
    assert_eq!(
        FbKind::TableBasedPositionCompensation.fb_name(),
        "MC_TableBasedPositionCompensation"
    );
    assert_eq!(FbKind::MoveAbsolute.fb_name(), "MC_MoveAbsolute");
}
