//! Seeded random sequences of the phasing, multi-master, external-setpoint and §4.7 commands
//! mixed with motion, coupling, stop, reset and power calls on three axes: never a panic, the
//! set and actual values stay finite, a rejection leaves every axis (status and ext status)
//! as it was, and two runs with the same seed give the same bytes. Count: env
//! `AXIS3_SWEEPS` (default 40 sequences of 400 calls).
use axis_engine::*;
use motion_core::{CmdId, Engine, Tick};
use rand::rngs::SmallRng;
use rand::{Rng as _, SeedableRng};

const NAMES: [&str; 5] = ["m1", "m2", "s", "nope", ""];

fn num(g: &mut SmallRng, lo: f64, hi: f64) -> f64 {
    match g.gen_range(0..40) {
        0 => f64::NAN,
        1 => f64::INFINITY,
        2 => -1.0,
        3 => 0.0,
        _ => g.gen_range(lo..hi),
    }
}

fn name(g: &mut SmallRng) -> String {
    let k = if g.gen_bool(0.9) {
        g.gen_range(0..3)
    } else {
        g.gen_range(3..5)
    };
    NAMES[k].to_string()
}

fn cmd(g: &mut SmallRng, ids: &[CmdId]) -> AxisCommand {
    let id = if ids.is_empty() || g.gen_bool(0.05) {
        CmdId(g.gen_range(0..100_000))
    } else {
        ids[g.gen_range(0..ids.len())]
    };
    let bm = BufferMode::from_raw(if g.gen_bool(0.8) {
        0
    } else {
        g.gen_range(0..6)
    })
    .unwrap();
    match g.gen_range(0..34) {
        0 => AxisCommand::PhasingAbsolute(PhasingAbsolute {
            master: name(g),
            slave: name(g),
            continuous_update: g.gen_bool(0.5),
            phase_shift: num(g, -50.0, 50.0),
            velocity: num(g, 0.0, 200.0),
            acceleration: num(g, 0.0, 3000.0),
            deceleration: num(g, 0.0, 3000.0),
            jerk: num(g, 0.0, 1e5),
            buffer_mode: bm,
        }),
        1 => AxisCommand::PhasingRelative(PhasingRelative {
            master: name(g),
            slave: name(g),
            continuous_update: g.gen_bool(0.5),
            phase_shift: num(g, -50.0, 50.0),
            velocity: num(g, 0.0, 200.0),
            acceleration: num(g, 0.0, 3000.0),
            deceleration: num(g, 0.0, 3000.0),
            jerk: num(g, 0.0, 1e5),
            buffer_mode: bm,
        }),
        2 => AxisCommand::HaltPhasing(HaltPhasing {
            master: name(g),
            slave: name(g),
            deceleration: num(g, 0.0, 3000.0),
            jerk: num(g, 0.0, 1e5),
            buffer_mode: bm,
        }),
        3 => AxisCommand::PhasingUpdate(PhasingUpdate {
            id,
            phase_shift: num(g, -50.0, 50.0),
            velocity: num(g, 0.0, 200.0),
            acceleration: num(g, 0.0, 3000.0),
            deceleration: 0.0,
            jerk: 0.0,
        }),
        4 | 5 => AxisCommand::GearInMultiMaster(GearInMultiMaster {
            slave: name(g),
            master1: name(g),
            master2: if g.gen_bool(0.5) {
                name(g)
            } else {
                String::new()
            },
            master3: String::new(),
            master4: if g.gen_bool(0.1) {
                name(g)
            } else {
                String::new()
            },
            enable: g.gen_bool(0.7),
            gear_ratio1: num(g, -3.0, 3.0),
            gear_ratio2: num(g, -3.0, 3.0),
            gear_ratio3: 0.0,
            gear_ratio4: num(g, -3.0, 3.0),
            acceleration: num(g, 0.0, 3000.0),
            deceleration: num(g, 0.0, 3000.0),
            jerk: num(g, 0.0, 1e5),
            buffer_mode: bm,
            options: GearInMultiMasterOptions {
                advanced_slave_dynamics: g.gen_bool(0.5),
                sync_mode: GearInMultiMasterSyncMode::from_raw(g.gen_range(0..3)).unwrap(),
            },
        }),
        6 => AxisCommand::ExtSetPointGenEnable(ExtSetPointGenEnable {
            axis: name(g),
            position: num(g, -100.0, 100.0),
            position_type: PositionType::from_raw(g.gen_range(1..3)).unwrap(),
            options: ExtSetPointEnableOptions {
                use_torque_offset: g.gen_bool(0.5),
            },
        }),
        7 => AxisCommand::ExtSetPointGenDisable(ExtSetPointGenDisable { axis: name(g) }),
        8 | 9 => AxisCommand::ExtSetPointGenFeedWithTorque(ExtSetPointGenFeedWithTorque {
            axis: name(g),
            position: num(g, -100.0, 100.0),
            velocity: num(g, -100.0, 100.0),
            acceleration: num(g, -100.0, 100.0),
            direction: g.gen_range(-2..3),
            torque_offset: num(g, -10.0, 10.0),
        }),
        10 => AxisCommand::WriteDriveOperationMode(WriteDriveOperationMode {
            axis: name(g),
            drive_operation_mode: DriveOperationMode::from_raw(g.gen_range(0..7)).unwrap(),
        }),
        11 => AxisCommand::ReadDriveOperationMode(ReadDriveOperationMode { axis: name(g) }),
        12 => AxisCommand::BacklashCompensation(BacklashCompensation {
            axis: name(g),
            enable: g.gen_bool(0.7),
            backlash: num(g, -0.1, 0.1),
            compensation_in_positive_direction: g.gen_bool(0.5),
            ramp: num(g, 0.0, 2.0),
            disable_mode: DisableMode::from_raw(g.gen_range(0..2)).unwrap(),
        }),
        13 => AxisCommand::PositionCorrectionLimiter(PositionCorrectionLimiter {
            axis: name(g),
            enable: g.gen_bool(0.7),
            position_correction_value: num(g, -1.0, 1.0),
            correction_mode: PositionCorrectionMode::from_raw(g.gen_range(0..3)).unwrap(),
            acceleration: num(g, 0.0, 1000.0),
            correction_length: num(g, 0.0, 20.0),
        }),
        14 => {
            let n = g.gen_range(0..6);
            AxisCommand::TableBasedPositionCompensation(TableBasedPositionCompensation {
                axis: name(g),
                enable: g.gen_bool(0.7),
                table: (0..n)
                    .map(|k| PositionCompensationTableElement {
                        position: k as f64 * 10.0 - 20.0,
                        compensation: num(g, -0.5, 0.5),
                    })
                    .collect(),
                table_parameter: PositionCompensationTableParameter {
                    min_position: -20.0,
                    max_position: if g.gen_bool(0.9) {
                        20.0
                    } else {
                        num(g, -30.0, 30.0)
                    },
                    no_of_table_elements: if g.gen_bool(0.9) { 5 } else { n },
                    direction: WorkDirection::from_raw(g.gen_range(0..4)).unwrap(),
                    modulo: g.gen_bool(0.3),
                },
                ramp: num(g, 0.0, 2.0),
                disable_mode: DisableMode::Hold,
            })
        }
        15 => AxisCommand::SetEncoderScalingFactor(SetEncoderScalingFactor {
            axis: name(g),
            scaling_factor: num(g, 1e-5, 1e-2),
            mode: SetScalingFactorMode::from_raw(g.gen_range(0..2)).unwrap(),
            options: SetEncoderScalingOptions::default(),
        }),
        16 => AxisCommand::ConvertPosToIncPos(ConvertPosToIncPos {
            axis: name(g),
            position: num(g, -1e6, 1e6),
            options: NcPositionConversionOptions::default(),
        }),
        17 => AxisCommand::ConvertIncPosToPos(ConvertIncPosToPos {
            axis: name(g),
            inc_pos: g.gen(),
            options: NcPositionConversionOptions::default(),
        }),
        18 => AxisCommand::SetAcceptBlockedDriveSignal(SetAcceptBlockedDriveSignal {
            axis: name(g),
            enable: g.gen_bool(0.5),
        }),
        19 => AxisCommand::WriteNcIoOutput(WriteNcIoOutput {
            axis: name(g),
            device: NcIoDevice::from_raw(g.gen_range(0..2)).unwrap(),
            nc_io_output: NcIoOutput::from_raw(g.gen_range(0..14)).unwrap(),
            bit_select_mask: g.gen(),
            bit_values: g.gen(),
        }),
        20 => AxisCommand::SelectControlLoop(SelectControlLoop {
            axis: name(g),
            encoder_index: g.gen_range(0..2),
            select_type: SelectControlLoopType::from_raw(g.gen_range(0..4)).unwrap(),
            sync_value: num(g, -1.0, 1.0),
            ext_set_point_gen: false,
        }),
        21 => AxisCommand::ReadParameterSet(ReadParameterSet { axis: name(g) }),
        22 => AxisCommand::WriteParameterPersistent(WriteParameter {
            axis: name(g),
            parameter_number: [2, 3, 1, 9999, 1004][g.gen_range(0..5)],
            value: num(g, -1000.0, 1000.0),
        }),
        23 | 24 => AxisCommand::MoveAbsolute(MoveAbsolute {
            axis: name(g),
            position: g.gen_range(-100.0..100.0),
            velocity: g.gen_range(1.0..200.0),
            acceleration: 0.0,
            deceleration: 0.0,
            jerk: 0.0,
            buffer_mode: bm,
            options: MoveOptions::default(),
        }),
        25 => AxisCommand::MoveVelocity(MoveVelocity {
            axis: name(g),
            velocity: g.gen_range(1.0..200.0),
            acceleration: 0.0,
            deceleration: 0.0,
            jerk: 0.0,
            direction: if g.gen_bool(0.5) {
                Direction::Positive
            } else {
                Direction::Negative
            },
            buffer_mode: BufferMode::Aborting,
            options: MoveOptions::default(),
        }),
        26 | 27 => AxisCommand::GearIn(GearIn {
            master: name(g),
            slave: name(g),
            ratio_numerator: g.gen_range(-2.0..2.0),
            ratio_denominator: 1,
            acceleration: 0.0,
            deceleration: 0.0,
            jerk: 0.0,
            buffer_mode: bm,
        }),
        28 => AxisCommand::GearOut(GearOut { slave: name(g) }),
        29 => AxisCommand::Stop(Stop {
            axis: name(g),
            deceleration: 0.0,
            jerk: 0.0,
            options: MoveOptions::default(),
        }),
        30 => AxisCommand::Reset(Reset { axis: name(g) }),
        31 => AxisCommand::Power(Power {
            axis: name(g),
            enable: g.gen_bool(0.85),
            enable_positive: true,
            enable_negative: true,
            override_percent: 100.0,
            buffer_mode: BufferMode::Aborting,
        }),
        32 => AxisCommand::Sim(Sim::InjectAxisError {
            axis: name(g),
            error_id: 0,
        }),
        _ => AxisCommand::SetExecute {
            id,
            execute: g.gen_bool(0.3),
        },
    }
}

fn state(e: &AxisEngine) -> String {
    let s = e.snapshot();
    let x: Vec<_> = ["m1", "m2", "s"]
        .iter()
        .map(|n| e.ext_status(n).unwrap())
        .collect();
    format!("{s:?}{x:?}")
}

fn run(seed: u64, calls: usize) -> String {
    let mut g = SmallRng::seed_from_u64(seed);
    let cfg = AxisConfig {
        enable_pos_correction: true,
        ..Default::default()
    };
    let mut e = AxisEngine::new(
        ["m1", "m2", "s"]
            .iter()
            .map(|n| (n.to_string(), cfg.clone()))
            .collect(),
    )
    .unwrap();
    let mut ev = Vec::new();
    let mut ids = Vec::new();
    let mut tick = 0;
    for n in ["m1", "m2", "s"] {
        e.command(AxisCommand::Power(Power {
            axis: n.into(),
            enable: true,
            enable_positive: true,
            enable_negative: true,
            override_percent: 100.0,
            buffer_mode: BufferMode::Aborting,
        }))
        .unwrap();
    }
    for _ in 0..calls {
        let c = cmd(&mut g, &ids);
        let before = state(&e);
        match e.command(c.clone()) {
            Ok(r) => {
                if r.tracked {
                    ids.push(r.id);
                }
            }
            Err(rej) => assert_eq!(
                state(&e),
                before,
                "seed {seed}: rejected {c:?} ({rej}) changed the axes"
            ),
        }
        for _ in 0..g.gen_range(0..40) {
            e.step(
                Tick {
                    index: tick,
                    dt: 0.002,
                },
                &mut ev,
            );
            tick += 1;
            ev.clear();
        }
        for s in e.snapshot().axes {
            assert!(
                s.set_pos.is_finite() && s.set_velo.is_finite() && s.act_pos.is_finite(),
                "seed {seed}: not finite after {c:?}: {s:?}"
            );
        }
    }
    state(&e)
}

#[test]
fn random_sequences_of_the_added_fbs() {
    let n: u64 = std::env::var("AXIS3_SWEEPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(40);
    for seed in 0..n {
        run(seed, 400);
    }
}

#[test]
fn deterministic() {
    assert_eq!(run(7, 300), run(7, 300));
}
