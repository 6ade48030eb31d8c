//! §2.4 admission matrix for the implemented FBs, in every reachable state: accepted commands
//! lead to the table's state, rejected ones return the table's error id and leave the axis
//! unchanged.
mod common;
use axis_engine::*;
use common::*;
use MotionState::*;

const COLS: [MotionState; 6] = [
    Disabled,
    Standstill,
    DiscreteMotion,
    ContinuousMotion,
    Stopping,
    ErrorStop,
];

fn rig_in(state: MotionState) -> Rig {
    let mut r = match state {
        Disabled => Rig::new(),
        _ => Rig::powered(),
    };
    match state {
        Disabled | Standstill => {}
        DiscreteMotion => {
            r.id(abs(1000.0, 100.0));
            r.steps(5);
        }
        ContinuousMotion => {
            r.id(vel(100.0));
            r.steps(5);
        }
        Stopping => {
            r.id(stop(0.0, 0.0));
            r.step();
        }
        ErrorStop => {
            r.cmd(inject(0x4550)).unwrap();
            r.step();
        }
        _ => unreachable!(),
    }
    assert_eq!(r.st().motion_state, state);
    r
}

#[derive(Clone, Copy, Debug)]
enum Exp {
    /// Accepted; state right after the call.
    To(MotionState),
    /// Rejected with this id.
    E(u32),
}
use Exp::*;

fn check_row(name: &str, make: &dyn Fn() -> AxisCommand, row: [Exp; 6]) {
    for (col, exp) in COLS.iter().zip(row) {
        let mut r = rig_in(*col);
        let before = r.st();
        let res = r.cmd(make());
        match exp {
            To(s) => {
                assert!(res.is_ok(), "{name} in {col:?}: rejected {res:?}");
                assert_eq!(r.st().motion_state, s, "{name} in {col:?}");
            }
            E(id) => {
                let rej = res.expect_err(&format!("{name} in {col:?} must be rejected"));
                assert_eq!(rej.error_id, err(id), "{name} in {col:?}: {}", rej.message);
                assert!(
                    rej.message.contains("axis 'x'"),
                    "message names the axis: {}",
                    rej.message
                );
                assert_eq!(
                    r.st(),
                    before,
                    "{name} in {col:?}: a rejection does not affect the axis"
                );
            }
        }
    }
}

#[test]
fn motion_rows() {
    //                                                    Dis         SS                  Dis-M               Con                   Stp         Err
    check_row(
        "MC_MoveAbsolute",
        &|| abs(500.0, 100.0),
        [
            E(0x4B01),
            To(DiscreteMotion),
            To(DiscreteMotion),
            To(DiscreteMotion),
            E(0x4B01),
            E(0x4B01),
        ],
    );
    check_row(
        "MC_MoveRelative",
        &|| rel(500.0, 100.0),
        [
            E(0x4B01),
            To(DiscreteMotion),
            To(DiscreteMotion),
            To(DiscreteMotion),
            E(0x4B01),
            E(0x4B01),
        ],
    );
    check_row(
        "MC_MoveAdditive",
        &|| add(500.0, 100.0),
        [
            E(0x4B01),
            To(DiscreteMotion),
            To(DiscreteMotion),
            To(DiscreteMotion),
            E(0x4B01),
            E(0x4B01),
        ],
    );
    check_row(
        "MC_MoveModulo",
        &|| modulo(350.0, Direction::Positive),
        [
            E(0x4B01),
            To(DiscreteMotion),
            To(DiscreteMotion),
            To(DiscreteMotion),
            E(0x4B01),
            E(0x4B01),
        ],
    );
    check_row(
        "MC_MoveVelocity",
        &|| vel(50.0),
        [
            E(0x4B01),
            To(ContinuousMotion),
            To(ContinuousMotion),
            To(ContinuousMotion),
            E(0x4B01),
            E(0x4B01),
        ],
    );
    check_row(
        "MC_Halt",
        &|| halt(0.0, 0.0, BufferMode::Aborting),
        [
            E(0x4B01),
            To(DiscreteMotion),
            To(DiscreteMotion),
            To(DiscreteMotion),
            E(0x4B01),
            E(0x4B01),
        ],
    );
    check_row(
        "MC_Stop",
        &|| stop(0.0, 0.0),
        [
            E(0x4B01),
            To(Stopping),
            To(Stopping),
            To(Stopping),
            To(Stopping),
            E(0x4B01),
        ],
    );
}

#[test]
fn continuous_jog_home_override_rows() {
    let ca = || {
        AxisCommand::MoveContinuousAbsolute(MoveContinuousAbsolute {
            axis: AX.into(),
            position: 500.0,
            velocity: 100.0,
            end_velocity: 10.0,
            acceleration: 0.0,
            deceleration: 0.0,
            jerk: 0.0,
            buffer_mode: BufferMode::Aborting,
            options: MoveOptions::default(),
        })
    };
    check_row(
        "MC_MoveContinuousAbsolute",
        &ca,
        [
            E(0x4B01),
            To(ContinuousMotion),
            To(ContinuousMotion),
            To(ContinuousMotion),
            E(0x4B01),
            E(0x4B01),
        ],
    );
    let jog = |mode: JogMode| {
        move || {
            AxisCommand::Jog(Jog {
                axis: AX.into(),
                jog_forward: true,
                jog_backwards: false,
                mode,
                position: 5.0,
                velocity: 10.0,
                acceleration: 0.0,
                deceleration: 0.0,
                jerk: 0.0,
            })
        }
    };
    check_row(
        "MC_Jog continuous",
        &jog(JogMode::Continous),
        [
            E(0x4B01),
            To(ContinuousMotion),
            To(ContinuousMotion),
            To(ContinuousMotion),
            E(0x4B01),
            E(0x4B01),
        ],
    );
    check_row(
        "MC_Jog inching",
        &jog(JogMode::Inching),
        [
            E(0x4B01),
            To(DiscreteMotion),
            To(DiscreteMotion),
            To(DiscreteMotion),
            E(0x4B01),
            E(0x4B01),
        ],
    );
    let home = |mode: HomingMode| {
        move || {
            AxisCommand::Home(Home {
                axis: AX.into(),
                position: 0.0,
                use_default_position: false,
                homing_mode: mode,
                buffer_mode: BufferMode::Aborting,
                options: HomingOptions::default(),
                calibration_cam: false,
            })
        }
    };
    check_row(
        "MC_Home default",
        &home(HomingMode::DefaultHoming),
        [
            E(0x4B01),
            To(Homing),
            E(0x4B01),
            E(0x4B01),
            E(0x4B01),
            E(0x4B01),
        ],
    );
    check_row(
        "MC_Home direct",
        &home(HomingMode::Direct),
        [
            E(0x4B01),
            To(Standstill),
            E(0x4B01),
            E(0x4B01),
            E(0x4B01),
            E(0x4B01),
        ],
    );
    let so = || {
        AxisCommand::SetOverride(SetOverride {
            axis: AX.into(),
            enable: true,
            vel_factor: 0.5,
            acc_factor: 1.0,
            jerk_factor: 1.0,
        })
    };
    check_row(
        "MC_SetOverride",
        &so,
        [
            To(Disabled),
            To(Standstill),
            To(DiscreteMotion),
            To(ContinuousMotion),
            To(Stopping),
            To(ErrorStop),
        ],
    );
}

#[test]
fn organisation_rows() {
    check_row(
        "MC_SetPosition",
        &|| set_position(5.0),
        [
            To(Disabled),
            To(Standstill),
            To(DiscreteMotion),
            To(ContinuousMotion),
            To(Stopping),
            E(0x4B01),
        ],
    );
    let rd = || {
        AxisCommand::ReadParameter(ReadParameter {
            axis: AX.into(),
            parameter_number: 1004,
        })
    };
    check_row(
        "MC_ReadParameter",
        &rd,
        [
            To(Disabled),
            To(Standstill),
            To(DiscreteMotion),
            To(ContinuousMotion),
            To(Stopping),
            To(ErrorStop),
        ],
    );
    let wr = || {
        AxisCommand::WriteParameter(WriteParameter {
            axis: AX.into(),
            parameter_number: 1024,
            value: 3.0,
        })
    };
    check_row(
        "MC_WriteParameter",
        &wr,
        [
            To(Disabled),
            To(Standstill),
            To(DiscreteMotion),
            To(ContinuousMotion),
            To(Stopping),
            To(ErrorStop),
        ],
    );
    let rs = || AxisCommand::ReadStatus(ReadStatus { axis: AX.into() });
    check_row(
        "MC_ReadStatus",
        &rs,
        [
            To(Disabled),
            To(Standstill),
            To(DiscreteMotion),
            To(ContinuousMotion),
            To(Stopping),
            To(ErrorStop),
        ],
    );
}

#[test]
fn power_rows() {
    // Enable↑: Dis → SS (Status in the next cycle); "=" elsewhere.
    for col in COLS {
        let mut r = rig_in(col);
        r.power(true);
        r.step();
        let want = match col {
            Disabled => Standstill,
            DiscreteMotion | ContinuousMotion | Stopping | Standstill | ErrorStop => col,
            _ => unreachable!(),
        };
        // A running move may have changed nothing but time; the state stays.
        assert_eq!(r.st().motion_state, want, "Enable↑ in {col:?}");
    }
    // Enable↓: Dis everywhere except ErrorStop (stays).
    for col in COLS {
        let mut r = rig_in(col);
        r.power(false);
        let want = if col == ErrorStop {
            ErrorStop
        } else {
            Disabled
        };
        assert_eq!(r.st().motion_state, want, "Enable↓ in {col:?}");
    }
}

#[test]
fn reset_row() {
    // MC_Reset: Dis "=" (Done), SS "=", moving states → SS after the stop, Stp → SS, Err → SS.
    for col in COLS {
        let mut r = rig_in(col);
        let id = r.id(reset());
        r.until(5000, |r| r.out(id).done);
        let want = if col == Disabled {
            Disabled
        } else {
            Standstill
        };
        assert_eq!(r.st().motion_state, want, "MC_Reset in {col:?}");
    }
}

#[test]
fn the_matrix_function_matches_the_table_for_unimplemented_rows() {
    use axis_engine::state::{admission, Admission, FbClass};
    // Homing and SynchronizedMotion columns cannot be reached without MC_Home / gearing;
    // check the function itself for them.
    assert_eq!(
        admission(FbClass::MoveDiscrete, Homing),
        Admission::Reject(err(0x4B01))
    );
    assert_eq!(admission(FbClass::Stop, Homing), Admission::To(Stopping));
    assert_eq!(
        admission(FbClass::MoveDiscrete, SynchronizedMotion),
        Admission::IfSlaveAllowed(DiscreteMotion)
    );
    assert_eq!(
        admission(FbClass::GearOut, Standstill),
        Admission::Reject(err(0x4B05))
    );
    assert_eq!(
        admission(FbClass::MoveSuperImposed, Standstill),
        Admission::Reject(err(0x4B03))
    );
    assert_eq!(
        admission(FbClass::HomeDefault, Standstill),
        Admission::To(Homing)
    );
    assert_eq!(
        admission(FbClass::Reset, ErrorStop),
        Admission::ToStandstillOrDisabled
    );
    assert_eq!(
        admission(FbClass::GearInMultiMaster { asd: true }, ContinuousMotion),
        Admission::To(SynchronizedMotion)
    );
    assert_eq!(
        admission(FbClass::GearInMultiMaster { asd: false }, ContinuousMotion),
        Admission::Reject(err(0x4B01))
    );
}

#[test]
fn feed_enable_missing_rejects_the_start_direction() {
    let mut r = Rig::powered();
    r.power_full(true, false, true, 100.0, BufferMode::Aborting)
        .unwrap();
    let before = r.st();
    let e = r.cmd(abs(100.0, 100.0)).unwrap_err();
    assert_eq!(e.error_id, err(0x4B01));
    assert_eq!(r.st(), before);
    // The other direction is allowed.
    r.id(abs(-10.0, 100.0));
    assert_eq!(r.st().motion_state, DiscreteMotion);
}

#[test]
fn feed_enable_dropping_while_moving_stops_with_axis_dec_and_aborts() {
    let mut r = Rig::powered();
    let id = r.id(vel(100.0));
    r.steps(100);
    r.power_full(true, false, true, 100.0, BufferMode::Aborting)
        .unwrap();
    assert!(r.out(id).command_aborted);
    r.until(1000, |r| r.st().set_velo == 0.0);
    assert_eq!(r.st().motion_state, Standstill);
}
