//! Services of axis_node: one call = one FB call (an Execute edge, or the level of an
//! Enable-type input), answered at once: accepted with the command id, or rejected with the
//! error id and a message. Outputs then follow on `~/command_status`.

use axis_engine::{
    params, AxisCommand, AxisEngine, AxisReply, BufferMode, Direction, MoveOptions, ReplyValue,
    SetPositionOptions, Sim,
};
use motion_core::{CmdId, ErrorId, Rejection};
use motion_msgs::srv::*;
use motion_msgs::CommandResponse;
use motion_runtime::{CommandLabel, NodeShell, ShellError};
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// Result of one command service call.
pub(crate) type Outcome = Result<AxisReply, Rejection>;

/// The answer of a command service (accepted with the command id, or rejected).
pub(crate) fn respond<R: CommandResponse>(o: Outcome) -> R {
    motion_runtime::shell::respond(&o, |r| r.id)
}

pub(crate) fn label(axis: &str, command: &str) -> CommandLabel {
    CommandLabel {
        object: axis.to_string(),
        command: command.to_string(),
    }
}

pub(crate) fn buffer_mode(raw: u8) -> Result<BufferMode, Rejection> {
    BufferMode::from_raw(u32::from(raw))
}

/// `MC_Direction` from its raw value; `from_raw` refuses unknown values (0x7F03).
pub(crate) fn direction(raw: u8) -> Result<Direction, Rejection> {
    Direction::from_raw(u32::from(raw))
}

pub(crate) fn move_options(
    enable_blending_position: bool,
    blending_position: f64,
    ignore: bool,
) -> MoveOptions {
    MoveOptions {
        enable_blending_position,
        blending_position,
        ignore_position_monitoring: ignore,
        enable_stop_position_monitoring: false,
    }
}

pub(crate) fn decode_power(r: PowerRequest) -> Result<(AxisCommand, CommandLabel), Rejection> {
    let l = label(&r.axis, "power");
    Ok((
        AxisCommand::Power(axis_engine::Power {
            axis: r.axis,
            enable: r.enable,
            enable_positive: r.enable_positive,
            enable_negative: r.enable_negative,
            override_percent: r.r#override,
            buffer_mode: buffer_mode(r.buffer_mode)?,
        }),
        l,
    ))
}

pub(crate) fn respond_power(o: Outcome) -> PowerResponse {
    let status = matches!(
        &o,
        Ok(AxisReply {
            value: ReplyValue::Bool(true),
            ..
        })
    );
    PowerResponse {
        status,
        ..respond(o)
    }
}

fn decode_reset(r: ResetRequest) -> Result<(AxisCommand, CommandLabel), Rejection> {
    let l = label(&r.axis, "reset");
    Ok((AxisCommand::Reset(axis_engine::Reset { axis: r.axis }), l))
}

pub(crate) fn decode_move_absolute(
    r: MoveAbsoluteRequest,
) -> Result<(AxisCommand, CommandLabel), Rejection> {
    let l = label(&r.axis, "move_absolute");
    Ok((
        AxisCommand::MoveAbsolute(axis_engine::MoveAbsolute {
            axis: r.axis,
            position: r.position,
            velocity: r.velocity,
            acceleration: r.acceleration,
            deceleration: r.deceleration,
            jerk: r.jerk,
            buffer_mode: buffer_mode(r.buffer_mode)?,
            options: move_options(
                r.enable_blending_position,
                r.blending_position,
                r.ignore_position_monitoring,
            ),
        }),
        l,
    ))
}

pub(crate) fn decode_move_relative(
    r: MoveRelativeRequest,
) -> Result<(AxisCommand, CommandLabel), Rejection> {
    let l = label(&r.axis, "move_relative");
    Ok((
        AxisCommand::MoveRelative(axis_engine::MoveRelative {
            axis: r.axis,
            distance: r.distance,
            velocity: r.velocity,
            acceleration: r.acceleration,
            deceleration: r.deceleration,
            jerk: r.jerk,
            buffer_mode: buffer_mode(r.buffer_mode)?,
            options: move_options(
                r.enable_blending_position,
                r.blending_position,
                r.ignore_position_monitoring,
            ),
        }),
        l,
    ))
}

fn decode_move_additive(r: MoveAdditiveRequest) -> Result<(AxisCommand, CommandLabel), Rejection> {
    let l = label(&r.axis, "move_additive");
    Ok((
        AxisCommand::MoveAdditive(axis_engine::MoveAdditive {
            axis: r.axis,
            distance: r.distance,
            velocity: r.velocity,
            acceleration: r.acceleration,
            deceleration: r.deceleration,
            jerk: r.jerk,
            buffer_mode: buffer_mode(r.buffer_mode)?,
            options: move_options(
                r.enable_blending_position,
                r.blending_position,
                r.ignore_position_monitoring,
            ),
        }),
        l,
    ))
}

pub(crate) fn decode_move_velocity(
    r: MoveVelocityRequest,
) -> Result<(AxisCommand, CommandLabel), Rejection> {
    let l = label(&r.axis, "move_velocity");
    Ok((
        AxisCommand::MoveVelocity(axis_engine::MoveVelocity {
            axis: r.axis,
            velocity: r.velocity,
            acceleration: r.acceleration,
            deceleration: r.deceleration,
            jerk: r.jerk,
            direction: direction(r.direction)?,
            buffer_mode: buffer_mode(r.buffer_mode)?,
            options: MoveOptions::default(),
        }),
        l,
    ))
}

pub(crate) fn decode_halt(r: HaltRequest) -> Result<(AxisCommand, CommandLabel), Rejection> {
    let l = label(&r.axis, "halt");
    Ok((
        AxisCommand::Halt(axis_engine::Halt {
            axis: r.axis,
            deceleration: r.deceleration,
            jerk: r.jerk,
            buffer_mode: buffer_mode(r.buffer_mode)?,
            options: MoveOptions::default(),
        }),
        l,
    ))
}

pub(crate) fn decode_set_position(
    r: SetPositionRequest,
) -> Result<(AxisCommand, CommandLabel), Rejection> {
    let l = label(&r.axis, "set_position");
    Ok((
        AxisCommand::SetPosition(axis_engine::SetPosition {
            axis: r.axis,
            position: r.position,
            mode: r.mode,
            options: SetPositionOptions {
                clear_position_lag: r.clear_position_lag,
                ..Default::default()
            },
        }),
        l,
    ))
}

/// MC_Write(Bool)Parameter, or with `persistent` MC_Write(Bool)ParameterPersistent (served
/// by `extensions`, which stores the persistent writes).
pub(crate) fn decode_write_parameter(
    r: WriteParameterRequest,
) -> Result<(AxisCommand, CommandLabel), Rejection> {
    let l = label(&r.axis, "write_parameter");
    let cmd = match (r.is_bool, r.persistent) {
        (true, persistent) => {
            let c = axis_engine::WriteBoolParameter {
                axis: r.axis,
                parameter_number: r.parameter_number,
                value: r.bool_value,
            };
            if persistent {
                AxisCommand::WriteBoolParameterPersistent(c)
            } else {
                AxisCommand::WriteBoolParameter(c)
            }
        }
        (false, persistent) => {
            let c = axis_engine::WriteParameter {
                axis: r.axis,
                parameter_number: r.parameter_number,
                value: r.value,
            };
            if persistent {
                AxisCommand::WriteParameterPersistent(c)
            } else {
                AxisCommand::WriteParameter(c)
            }
        }
    };
    Ok((cmd, l))
}

pub(crate) fn register(shell: &mut NodeShell<AxisEngine>) -> Result<(), ShellError> {
    shell.command_service(
        "power",
        Power::service_type_name(),
        decode_power,
        respond_power,
    )?;
    shell.command_service(
        "reset",
        Reset::service_type_name(),
        decode_reset,
        respond::<ResetResponse>,
    )?;
    shell.command_service(
        "move_absolute",
        MoveAbsolute::service_type_name(),
        decode_move_absolute,
        respond::<MoveAbsoluteResponse>,
    )?;
    shell.command_service(
        "move_relative",
        MoveRelative::service_type_name(),
        decode_move_relative,
        respond::<MoveRelativeResponse>,
    )?;
    shell.command_service(
        "move_additive",
        MoveAdditive::service_type_name(),
        decode_move_additive,
        respond::<MoveAdditiveResponse>,
    )?;
    shell.command_service(
        "move_velocity",
        MoveVelocity::service_type_name(),
        decode_move_velocity,
        respond::<MoveVelocityResponse>,
    )?;
    shell.command_service(
        "halt",
        Halt::service_type_name(),
        decode_halt,
        respond::<HaltResponse>,
    )?;
    shell.command_service(
        "set_position",
        SetPosition::service_type_name(),
        decode_set_position,
        respond::<SetPositionResponse>,
    )?;
    register_stop(shell)?;
    register_read_parameter(shell)?;
    register_sim(shell)?;
    crate::fbs::register(shell)?;
    Ok(())
}

/// `~/stop`: `execute = true` is the rising edge of a fresh MC_Stop instance; `execute = false`
/// the falling edge of the axis's latest one, which unlocks the axis once it has stopped (N6).
fn register_stop(shell: &mut NodeShell<AxisEngine>) -> Result<(), ShellError> {
    let latest: Arc<Mutex<HashMap<String, CmdId>>> = Arc::default();
    let handle = shell.handle.clone();
    shell.service::<StopRequest, StopResponse, _, _>(
        "stop",
        Stop::service_type_name(),
        move |r: StopRequest| {
            let handle = handle.clone();
            let latest = latest.clone();
            async move {
                let outcome = if r.execute {
                    let cmd = AxisCommand::Stop(axis_engine::Stop {
                        axis: r.axis.clone(),
                        deceleration: r.deceleration,
                        jerk: r.jerk,
                        options: MoveOptions::default(),
                    });
                    let o = handle.call_labeled(cmd, label(&r.axis, "stop")).await;
                    if let Ok(reply) = &o {
                        latest
                            .lock()
                            .unwrap_or_else(|e| e.into_inner())
                            .insert(r.axis.clone(), reply.id);
                    }
                    o
                } else {
                    let id = latest
                        .lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .remove(&r.axis);
                    match id {
                        Some(id) => {
                            handle
                                .call(AxisCommand::SetExecute { id, execute: false })
                                .await
                        }
                        // No MC_Stop instance is held for this axis: a falling edge changes nothing.
                        None if known_axis(&handle, &r.axis) => Ok(AxisReply {
                            id: CmdId(0),
                            value: ReplyValue::None,
                            tracked: false,
                        }),
                        None => Err(Rejection::unknown_object("axis", &r.axis)),
                    }
                };
                respond::<StopResponse>(outcome)
            }
        },
    )
}

pub(crate) fn known_axis(
    handle: &motion_runtime::ControllerHandle<AxisEngine>,
    axis: &str,
) -> bool {
    handle.snapshot().state.axis(axis).is_some()
}

/// `~/read_parameter`: MC_ReadParameter or MC_ReadBoolParameter by the parameter's type.
fn register_read_parameter(shell: &mut NodeShell<AxisEngine>) -> Result<(), ShellError> {
    let handle = shell.handle.clone();
    shell.service::<ReadParameterRequest, ReadParameterResponse, _, _>(
        "read_parameter",
        ReadParameter::service_type_name(),
        move |r: ReadParameterRequest| {
            let handle = handle.clone();
            async move {
                let is_bool = matches!(params::lookup(r.parameter_number), Some(d) if d.ty == params::ParamType::Bool);
                let cmd = if is_bool {
                    AxisCommand::ReadBoolParameter(axis_engine::ReadBoolParameter {
                        axis: r.axis,
                        parameter_number: r.parameter_number,
                    })
                } else {
                    AxisCommand::ReadParameter(axis_engine::ReadParameter {
                        axis: r.axis,
                        parameter_number: r.parameter_number,
                    })
                };
                match handle.call(cmd).await {
                    Ok(reply) => {
                        let (value, bool_value) = match reply.value {
                            ReplyValue::Real(v) => (v, false),
                            ReplyValue::Bool(b) => (if b { 1.0 } else { 0.0 }, b),
                            ReplyValue::DWord(d) => (f64::from(d), false),
                            _ => (0.0, false),
                        };
                        ReadParameterResponse {
                            accepted: true,
                            error_id: 0,
                            message: String::new(),
                            value,
                            bool_value,
                            is_bool,
                        }
                    }
                    Err(e) => ReadParameterResponse {
                        accepted: false,
                        error_id: e.error_id.0,
                        message: e.message,
                        ..Default::default()
                    },
                }
            }
        },
    )
}

/// `~/sim/inject_error`: the simulation hook of single_axis.md §1.5 (axis error or drive fault).
fn register_sim(shell: &mut NodeShell<AxisEngine>) -> Result<(), ShellError> {
    shell.command_service(
        "sim/set_following_offset",
        SetFollowingOffset::service_type_name(),
        |r: SetFollowingOffsetRequest| {
            let l = label(&r.axis, "sim/set_following_offset");
            Ok((
                AxisCommand::Sim(Sim::SetFollowingOffset {
                    axis: r.axis,
                    offset: r.offset,
                }),
                l,
            ))
        },
        respond::<SetFollowingOffsetResponse>,
    )?;
    shell.command_service(
        "sim/probe_input",
        SetProbeInput::service_type_name(),
        |r: SetProbeInputRequest| {
            let l = label(&r.axis, "sim/probe_input");
            Ok((
                AxisCommand::Sim(Sim::ProbeInput {
                    axis: r.axis,
                    unit: r.unit,
                    level: r.level,
                }),
                l,
            ))
        },
        respond::<SetProbeInputResponse>,
    )?;
    shell.command_service(
        "sim/inject_error",
        InjectError::service_type_name(),
        |r: InjectErrorRequest| {
            let l = label(&r.axis, "sim/inject_error");
            if r.error_id == 0 {
                return Err(Rejection::new(
                    ErrorId::VALUE_OUT_OF_RANGE,
                    "error_id = 0 is not an error",
                ));
            }
            let sim = if r.drive_fault {
                Sim::DriveFault {
                    axis: r.axis,
                    error_id: r.error_id,
                }
            } else {
                Sim::InjectAxisError {
                    axis: r.axis,
                    error_id: r.error_id,
                }
            };
            Ok((AxisCommand::Sim(sim), l))
        },
        respond::<InjectErrorResponse>,
    )
}
