//! Services of pickplace_node (pick_and_place.md §18): each call sets level inputs or raises a
//! pulse of `L_TT1P_TrackPickAndPlaceBase` and is answered at once, accepted with the command
//! id or rejected with the error id and a message. Inputs act at the start of the next cycle;
//! the execute and homing edges then report on `~/command_status`, everything else on `~/state`
//! and `~/events`.

use crate::cell::{parse_patch, Cell, CellCommand, CellReply};
use motion_core::{ErrorId, Rejection};
use motion_msgs::srv::*;
use motion_msgs::CommandResponse;
use motion_runtime::{CommandLabel, NodeShell, ShellError};
use pickplace_engine::config::MAX_BELTS;
use pickplace_engine::{FaultKind, PickPlaceCommand, ServiceRequest, StopInputs};

/// Result of one command service call.
pub(crate) type Outcome = Result<CellReply, Rejection>;

/// The answer of a command service (accepted with the command id, or rejected).
fn respond<R: CommandResponse>(o: Outcome) -> R {
    motion_runtime::shell::respond(&o, |r| r.id)
}

/// Commands act on the one cell; belt commands name the belt (`cv<n>`).
pub(crate) fn label(object: &str, command: &str) -> CommandLabel {
    CommandLabel {
        object: object.to_string(),
        command: command.to_string(),
    }
}

type Decoded = Result<(CellCommand, CommandLabel), Rejection>;

fn engine(cmd: PickPlaceCommand, command: &str) -> Decoded {
    Ok((CellCommand::Engine(cmd), label("cell", command)))
}

/// Belt numbers 1 … 16 (CV1 … CV16).
pub(crate) fn belt(n: u8) -> Result<u8, Rejection> {
    if (1..=MAX_BELTS as u8).contains(&n) {
        Ok(n)
    } else {
        Err(Rejection::new(
            ErrorId::UNKNOWN_OBJECT,
            format!("belt {n}: unknown belt (belts are 1 … {MAX_BELTS})"),
        ))
    }
}

/// `eSetTarget` 0 … 5 (§3.6); a configured-belt check follows at the edge (90005).
pub(crate) fn set_target(v: u8) -> Result<u8, Rejection> {
    if v <= 5 {
        Ok(v)
    } else {
        Err(Rejection::new(
            ErrorId::ENUM_OUT_OF_RANGE,
            format!("set_target = {v}: eSetTarget is 0 (static) or 1 … 5 (CV1 … CV5)"),
        ))
    }
}

pub(crate) fn finite(field: &str, values: &[f64]) -> Result<(), Rejection> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) if values.len() == 1 => Err(Rejection::not_finite("pickplace", field, values[i])),
        Some(i) => Err(Rejection::not_finite(
            "pickplace",
            &format!("{field}[{i}]"),
            values[i],
        )),
    }
}

fn decode_set_enable(r: PickPlaceSetEnableRequest) -> Decoded {
    engine(PickPlaceCommand::SetEnable(r.enable), "set_enable")
}

fn decode_set_regulator_on(r: PickPlaceSetRegulatorOnRequest) -> Decoded {
    engine(
        PickPlaceCommand::SetRegulatorOn(r.regulator_on),
        "set_regulator_on",
    )
}

fn decode_set_internal_control(r: PickPlaceSetInternalControlRequest) -> Decoded {
    engine(
        PickPlaceCommand::SetEnableInternalControl(r.enable_internal_control),
        "set_internal_control",
    )
}

fn decode_reset_error(_: PickPlaceTriggerRequest) -> Decoded {
    engine(PickPlaceCommand::ResetError, "reset_error")
}

fn decode_abort(_: PickPlaceTriggerRequest) -> Decoded {
    engine(PickPlaceCommand::Abort, "abort")
}

fn decode_ack_gripper(_: PickPlaceTriggerRequest) -> Decoded {
    engine(PickPlaceCommand::AckGripper, "ack_gripper")
}

fn decode_group_home(_: PickPlaceTriggerRequest) -> Decoded {
    engine(PickPlaceCommand::GroupHome, "group_home")
}

fn decode_set_stop_inputs(r: PickPlaceSetStopInputsRequest) -> Decoded {
    let pick = |set: bool, v: bool| set.then_some(v);
    engine(
        PickPlaceCommand::SetStopInputs(StopInputs {
            path_stop: pick(r.set_path_stop, r.path_stop),
            path_halt: pick(r.set_path_halt, r.path_halt),
            stop_all: pick(r.set_stop_all, r.stop_all),
            path_interrupt: pick(r.set_path_interrupt, r.path_interrupt),
        }),
        "set_stop_inputs",
    )
}

fn decode_set_override(r: PickPlaceSetOverrideRequest) -> Decoded {
    finite("override", &[r.r#override])?;
    engine(PickPlaceCommand::SetOverride(r.r#override), "set_override")
}

fn decode_jog(r: PickPlaceJogRequest) -> Decoded {
    if r.select_axis > 13 {
        return Err(Rejection::new(
            ErrorId::ENUM_OUT_OF_RANGE,
            format!("select_axis = {}: eSelectAxis is 0 (none), 1 … 6 (X … C), 7 … 12 (A1 … A6), 13 (Aux1)", r.select_axis),
        ));
    }
    engine(
        PickPlaceCommand::Jog {
            select_axis: r.select_axis,
            jog_pos: r.jog_pos,
            jog_neg: r.jog_neg,
        },
        "jog",
    )
}

fn decode_execute(r: PickPlaceExecuteRequest) -> Decoded {
    let t = set_target(r.set_target)?;
    engine(PickPlaceCommand::Execute { set_target: t }, "execute")
}

fn decode_set_params(r: PickPlaceSetParamsRequest) -> Decoded {
    let patch = parse_patch(&r.params, "params")?.unwrap_or_default();
    Ok((CellCommand::MergeParams(patch), label("cell", "set_params")))
}

fn decode_set_belt_params(r: PickPlaceSetBeltParamsRequest) -> Decoded {
    let b = belt(r.belt)?;
    let patch = parse_patch(&r.params, "params")?.unwrap_or_default();
    Ok((
        CellCommand::MergeBeltParams {
            belt: b,
            params: patch,
        },
        label(&format!("cv{b}"), "set_belt_params"),
    ))
}

fn decode_belt_input(r: PickPlaceBeltInputRequest) -> Decoded {
    let b = belt(r.belt)?;
    finite("initial_object_position", &r.initial_object_position)?;
    finite("aux1_target_pos", &[r.aux1_target_pos])?;
    Ok((
        CellCommand::Engine(PickPlaceCommand::BeltInput {
            belt: b,
            receive: r.receive,
            valid_pos: r.valid_pos,
            initial_object_position: r.initial_object_position,
            aux1_target_pos: r.aux1_target_pos,
        }),
        label(&format!("cv{b}"), "belt_input"),
    ))
}

fn decode_detect_workpiece(r: PickPlaceDetectWorkpieceRequest) -> Decoded {
    let b = belt(r.belt)?;
    finite("position", &r.position)?;
    Ok((
        CellCommand::Engine(PickPlaceCommand::DetectWorkpiece {
            belt: b,
            position: r.position,
            valid_delay_cycles: r.valid_delay_cycles,
        }),
        label(&format!("cv{b}"), "detect_workpiece"),
    ))
}

fn decode_service_request(r: PickPlaceServiceRequestRequest) -> Decoded {
    finite("position", &[r.position])?;
    finite("velocity", &[r.velocity])?;
    finite("acceleration", &[r.acceleration])?;
    finite("deceleration", &[r.deceleration])?;
    finite("jerk", &[r.jerk])?;
    engine(
        PickPlaceCommand::Service(ServiceRequest {
            move_abs: r.move_abs,
            axis: r.axis,
            pos: r.position,
            vel: r.velocity,
            acc: r.acceleration,
            dec: r.deceleration,
            jerk: r.jerk,
        }),
        "service_request",
    )
}

fn decode_sim_set_belt_velocity(r: PickPlaceSimSetBeltVelocityRequest) -> Decoded {
    let b = belt(r.belt)?;
    finite("velocity", &[r.velocity])?;
    finite("acceleration", &[r.acceleration])?;
    Ok((
        CellCommand::Engine(PickPlaceCommand::SimSetBeltVelocity {
            belt: b,
            velocity: r.velocity,
            acceleration: r.acceleration,
        }),
        label(&format!("cv{b}"), "sim/set_belt_velocity"),
    ))
}

fn decode_sim_set_digital_inputs(r: PickPlaceSimSetDigitalInputsRequest) -> Decoded {
    engine(
        PickPlaceCommand::SimSetDigitalInputs {
            hw_limit_pos: r.hw_limit_pos,
            hw_limit_neg: r.hw_limit_neg,
            home_switch: r.home_switch,
            enable_hw_limit: r.enable_hw_limit,
        },
        "sim/set_digital_inputs",
    )
}

fn decode_sim_inject_fault(r: PickPlaceSimInjectFaultRequest) -> Decoded {
    let kind = match r.kind {
        PickPlaceSimInjectFaultRequest::FOLLOWING_ERROR => FaultKind::FollowingError,
        PickPlaceSimInjectFaultRequest::DRIVE_FAULT => FaultKind::DriveFault,
        k => {
            return Err(Rejection::new(
                ErrorId::ENUM_OUT_OF_RANGE,
                format!("kind = {k}: 0 (FOLLOWING_ERROR) or 1 (DRIVE_FAULT)"),
            ))
        }
    };
    engine(
        PickPlaceCommand::SimInjectFault { axis: r.axis, kind },
        "sim/inject_fault",
    )
}

/// `~/hmi/set_internal_control`: switch Internal Control on (allowed while
/// xEnableInternalControl is TRUE) or off (§3.1).
fn decode_hmi_set_internal_control(r: PickPlaceSetInternalControlRequest) -> Decoded {
    engine(
        PickPlaceCommand::HmiSetInternalControl(r.enable_internal_control),
        "hmi/set_internal_control",
    )
}

/// The same command from the visualisation (`~/hmi/<name>`): accepted only under Internal
/// Control, when the other command inputs are ignored (§3.1).
fn hmi(d: Decoded) -> Decoded {
    match d? {
        (CellCommand::Engine(c), l) => Ok((
            CellCommand::Engine(PickPlaceCommand::Hmi(Box::new(c))),
            label(&l.object, &format!("hmi/{}", l.command)),
        )),
        (_, l) => Err(Rejection::new(
            ErrorId::NOT_IMPLEMENTED,
            format!("{} is not offered under ~/hmi", l.command),
        )),
    }
}

macro_rules! hmi_decoders {
    ($($hmi:ident = $decode:ident($req:ident)),* $(,)?) => {$(
        fn $hmi(r: $req) -> Decoded {
            hmi($decode(r))
        }
    )*};
}

hmi_decoders!(
    hmi_set_enable = decode_set_enable(PickPlaceSetEnableRequest),
    hmi_set_regulator_on = decode_set_regulator_on(PickPlaceSetRegulatorOnRequest),
    hmi_reset_error = decode_reset_error(PickPlaceTriggerRequest),
    hmi_abort = decode_abort(PickPlaceTriggerRequest),
    hmi_ack_gripper = decode_ack_gripper(PickPlaceTriggerRequest),
    hmi_group_home = decode_group_home(PickPlaceTriggerRequest),
    hmi_set_stop_inputs = decode_set_stop_inputs(PickPlaceSetStopInputsRequest),
    hmi_set_override = decode_set_override(PickPlaceSetOverrideRequest),
    hmi_jog = decode_jog(PickPlaceJogRequest),
    hmi_execute = decode_execute(PickPlaceExecuteRequest),
);

macro_rules! serve {
    ($shell:expr, $name:expr, $srv:ident, $decode:expr, $resp:ident) => {
        $shell.command_service($name, $srv::service_type_name(), $decode, respond::<$resp>)?
    };
}

pub(crate) fn register(shell: &mut NodeShell<Cell>) -> Result<(), ShellError> {
    serve!(
        shell,
        "set_enable",
        PickPlaceSetEnable,
        decode_set_enable,
        PickPlaceSetEnableResponse
    );
    serve!(
        shell,
        "set_regulator_on",
        PickPlaceSetRegulatorOn,
        decode_set_regulator_on,
        PickPlaceSetRegulatorOnResponse
    );
    serve!(
        shell,
        "set_internal_control",
        PickPlaceSetInternalControl,
        decode_set_internal_control,
        PickPlaceSetInternalControlResponse
    );
    serve!(
        shell,
        "reset_error",
        PickPlaceTrigger,
        decode_reset_error,
        PickPlaceTriggerResponse
    );
    serve!(
        shell,
        "abort",
        PickPlaceTrigger,
        decode_abort,
        PickPlaceTriggerResponse
    );
    serve!(
        shell,
        "ack_gripper",
        PickPlaceTrigger,
        decode_ack_gripper,
        PickPlaceTriggerResponse
    );
    serve!(
        shell,
        "group_home",
        PickPlaceTrigger,
        decode_group_home,
        PickPlaceTriggerResponse
    );
    serve!(
        shell,
        "set_stop_inputs",
        PickPlaceSetStopInputs,
        decode_set_stop_inputs,
        PickPlaceSetStopInputsResponse
    );
    serve!(
        shell,
        "set_override",
        PickPlaceSetOverride,
        decode_set_override,
        PickPlaceSetOverrideResponse
    );
    serve!(shell, "jog", PickPlaceJog, decode_jog, PickPlaceJogResponse);
    serve!(
        shell,
        "execute",
        PickPlaceExecute,
        decode_execute,
        PickPlaceExecuteResponse
    );
    serve!(
        shell,
        "set_params",
        PickPlaceSetParams,
        decode_set_params,
        PickPlaceSetParamsResponse
    );
    serve!(
        shell,
        "set_belt_params",
        PickPlaceSetBeltParams,
        decode_set_belt_params,
        PickPlaceSetBeltParamsResponse
    );
    serve!(
        shell,
        "belt_input",
        PickPlaceBeltInput,
        decode_belt_input,
        PickPlaceBeltInputResponse
    );
    serve!(
        shell,
        "detect_workpiece",
        PickPlaceDetectWorkpiece,
        decode_detect_workpiece,
        PickPlaceDetectWorkpieceResponse
    );
    serve!(
        shell,
        "service_request",
        PickPlaceServiceRequest,
        decode_service_request,
        PickPlaceServiceRequestResponse
    );
    serve!(
        shell,
        "sim/set_belt_velocity",
        PickPlaceSimSetBeltVelocity,
        decode_sim_set_belt_velocity,
        PickPlaceSimSetBeltVelocityResponse
    );
    serve!(
        shell,
        "sim/set_digital_inputs",
        PickPlaceSimSetDigitalInputs,
        decode_sim_set_digital_inputs,
        PickPlaceSimSetDigitalInputsResponse
    );
    serve!(
        shell,
        "sim/inject_fault",
        PickPlaceSimInjectFault,
        decode_sim_inject_fault,
        PickPlaceSimInjectFaultResponse
    );
    register_hmi(shell)?;
    register_get_params(shell)
}

/// `~/hmi/*`: the commands of the visualisation under Internal Control (§3.1).
fn register_hmi(shell: &mut NodeShell<Cell>) -> Result<(), ShellError> {
    serve!(
        shell,
        "hmi/set_internal_control",
        PickPlaceSetInternalControl,
        decode_hmi_set_internal_control,
        PickPlaceSetInternalControlResponse
    );
    serve!(
        shell,
        "hmi/set_enable",
        PickPlaceSetEnable,
        hmi_set_enable,
        PickPlaceSetEnableResponse
    );
    serve!(
        shell,
        "hmi/set_regulator_on",
        PickPlaceSetRegulatorOn,
        hmi_set_regulator_on,
        PickPlaceSetRegulatorOnResponse
    );
    serve!(
        shell,
        "hmi/reset_error",
        PickPlaceTrigger,
        hmi_reset_error,
        PickPlaceTriggerResponse
    );
    serve!(
        shell,
        "hmi/abort",
        PickPlaceTrigger,
        hmi_abort,
        PickPlaceTriggerResponse
    );
    serve!(
        shell,
        "hmi/ack_gripper",
        PickPlaceTrigger,
        hmi_ack_gripper,
        PickPlaceTriggerResponse
    );
    serve!(
        shell,
        "hmi/group_home",
        PickPlaceTrigger,
        hmi_group_home,
        PickPlaceTriggerResponse
    );
    serve!(
        shell,
        "hmi/set_stop_inputs",
        PickPlaceSetStopInputs,
        hmi_set_stop_inputs,
        PickPlaceSetStopInputsResponse
    );
    serve!(
        shell,
        "hmi/set_override",
        PickPlaceSetOverride,
        hmi_set_override,
        PickPlaceSetOverrideResponse
    );
    serve!(
        shell,
        "hmi/jog",
        PickPlaceJog,
        hmi_jog,
        PickPlaceJogResponse
    );
    serve!(
        shell,
        "hmi/execute",
        PickPlaceExecute,
        hmi_execute,
        PickPlaceExecuteResponse
    );
    Ok(())
}

/// `~/get_params`: `scPar` (belt 0) or `ascConveyorBeltPar[belt]` as YAML, read between cycles
/// through the query path (no command id, nothing on `~/command_status`).
fn register_get_params(shell: &mut NodeShell<Cell>) -> Result<(), ShellError> {
    let handle = shell.handle.clone();
    shell.service::<PickPlaceGetParamsRequest, PickPlaceGetParamsResponse, _, _>(
        "get_params",
        PickPlaceGetParams::service_type_name(),
        move |r: PickPlaceGetParamsRequest| {
            let handle = handle.clone();
            async move {
                let outcome = match r.belt {
                    0 => Ok(0),
                    n => belt(n),
                };
                let outcome = match outcome {
                    Ok(b) => handle.query(move |c: &Cell| c.params_yaml(b)).await,
                    Err(e) => Err(e),
                };
                match outcome {
                    Ok(Ok(text)) => PickPlaceGetParamsResponse {
                        accepted: true,
                        error_id: 0,
                        message: String::new(),
                        params: text,
                    },
                    Ok(Err(e)) | Err(e) => PickPlaceGetParamsResponse {
                        accepted: false,
                        error_id: e.error_id.0,
                        message: e.message,
                        params: String::new(),
                    },
                }
            }
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn screening_names_field_and_value() {
        let e = decode_jog(PickPlaceJogRequest {
            select_axis: 14,
            ..Default::default()
        })
        .unwrap_err();
        assert_eq!(e.error_id, ErrorId::ENUM_OUT_OF_RANGE);
        assert!(e.message.contains("select_axis = 14"), "{}", e.message);
        let e = decode_execute(PickPlaceExecuteRequest { set_target: 6 }).unwrap_err();
        assert_eq!(e.error_id, ErrorId::ENUM_OUT_OF_RANGE);
        let e = decode_belt_input(PickPlaceBeltInputRequest {
            belt: 0,
            ..Default::default()
        })
        .unwrap_err();
        assert_eq!(e.error_id, ErrorId::UNKNOWN_OBJECT);
        assert!(e.message.contains("belt 0"), "{}", e.message);
        let e = decode_belt_input(PickPlaceBeltInputRequest {
            belt: 1,
            initial_object_position: [0.0, f64::NAN, 0.0, 0.0, 0.0, 0.0],
            ..Default::default()
        })
        .unwrap_err();
        assert_eq!(e.error_id, ErrorId::NOT_FINITE);
        assert!(
            e.message.contains("initial_object_position[1]"),
            "{}",
            e.message
        );
        let e = decode_set_override(PickPlaceSetOverrideRequest {
            r#override: f64::INFINITY,
        })
        .unwrap_err();
        assert_eq!(e.error_id, ErrorId::NOT_FINITE);
        let e = decode_sim_inject_fault(PickPlaceSimInjectFaultRequest { axis: 1, kind: 2 })
            .unwrap_err();
        assert_eq!(e.error_id, ErrorId::ENUM_OUT_OF_RANGE);
        let e = decode_sim_set_belt_velocity(PickPlaceSimSetBeltVelocityRequest {
            belt: 17,
            ..Default::default()
        })
        .unwrap_err();
        assert_eq!(e.error_id, ErrorId::UNKNOWN_OBJECT);
        let e = decode_set_params(PickPlaceSetParamsRequest {
            params: "{path_vel: [".into(),
        })
        .unwrap_err();
        assert_eq!(e.error_id.0, 90001);
    }

    #[test]
    fn hmi_commands_wrap_the_same_decoding() {
        let (cmd, l) = hmi_jog(PickPlaceJogRequest {
            select_axis: 3,
            jog_pos: true,
            jog_neg: false,
        })
        .unwrap();
        assert_eq!(l.command, "hmi/jog");
        match cmd {
            CellCommand::Engine(PickPlaceCommand::Hmi(inner)) => {
                assert_eq!(
                    *inner,
                    PickPlaceCommand::Jog {
                        select_axis: 3,
                        jog_pos: true,
                        jog_neg: false
                    }
                )
            }
            other => panic!("{other:?}"),
        }
        let e = hmi_jog(PickPlaceJogRequest {
            select_axis: 20,
            ..Default::default()
        })
        .unwrap_err();
        assert_eq!(e.error_id, ErrorId::ENUM_OUT_OF_RANGE);
    }

    #[test]
    fn stop_inputs_change_only_what_is_set() {
        let (cmd, _) = decode_set_stop_inputs(PickPlaceSetStopInputsRequest {
            set_path_halt: true,
            path_halt: true,
            path_stop: true, // ignored: set_path_stop is false
            ..Default::default()
        })
        .unwrap();
        match cmd {
            CellCommand::Engine(PickPlaceCommand::SetStopInputs(s)) => {
                assert_eq!(
                    s,
                    StopInputs {
                        path_halt: Some(true),
                        ..Default::default()
                    }
                )
            }
            other => panic!("{other:?}"),
        }
    }
}
