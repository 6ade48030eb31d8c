//! Read FBs (single_axis.md §4.4.1, §4.4.2, §4.4.4, §4.4.7), read once per call with their
//! values in the response, and `~/get_outputs`: the outputs of any FB instance by command id,
//! so a client can poll an instance as a PLC reads it (the engine's `fb_outputs`).

use crate::convert::axis_state;
use axis_engine::{
    AxisCommand, AxisEngine, AxisReply, ExtraOutputs, FbKind, MotionState, ReplyValue,
};
use motion_core::{CmdId, Rejection};
use motion_msgs::deps::builtin_interfaces::msg::Time;
use motion_msgs::srv::*;
use motion_runtime::shell::stamp;
use motion_runtime::{NodeShell, ShellError};

/// Serves a read: `build` makes the engine call, `answer` the response from its outcome and
/// the simulated time of the latest snapshot.
fn read_service<Req, Resp>(
    shell: &mut NodeShell<AxisEngine>,
    name: &str,
    ty: ros2_client::ServiceTypeName,
    build: fn(Req) -> AxisCommand,
    answer: fn(Result<AxisReply, Rejection>, Time) -> Resp,
) -> Result<(), ShellError>
where
    Req: ros2_client::Message + Clone + Send + Sync + 'static,
    Resp: ros2_client::Message + Send + Sync + 'static,
{
    let handle = shell.handle.clone();
    shell.service::<Req, Resp, _, _>(name, ty, move |r: Req| {
        let handle = handle.clone();
        async move {
            let o = handle.call(build(r)).await;
            answer(o, stamp(&handle.snapshot()))
        }
    })
}

/// A reply that does not carry the value this read expects (never from this engine).
fn unexpected(v: &ReplyValue) -> Rejection {
    Rejection::new(
        motion_core::ErrorId::NOT_RUNNING,
        format!("unexpected reply {v:?}"),
    )
}

fn read_status(o: Result<AxisReply, Rejection>, t: Time) -> ReadStatusResponse {
    let s = match o.map(|r| r.value) {
        Ok(ReplyValue::Status(s)) => s,
        Ok(v) => {
            return ReadStatusResponse {
                error_id: unexpected(&v).error_id.0,
                message: unexpected(&v).message,
                ..Default::default()
            }
        }
        Err(e) => {
            return ReadStatusResponse {
                error_id: e.error_id.0,
                message: e.message,
                ..Default::default()
            }
        }
    };
    let m = s.motion_state;
    ReadStatusResponse {
        accepted: true,
        error_id: 0,
        message: String::new(),
        error_stop: m == MotionState::ErrorStop,
        disabled: m == MotionState::Disabled,
        stopping: m == MotionState::Stopping,
        standstill: m == MotionState::Standstill,
        discrete_motion: m == MotionState::DiscreteMotion,
        continuous_motion: m == MotionState::ContinuousMotion,
        synchronized_motion: m == MotionState::SynchronizedMotion,
        homing: m == MotionState::Homing,
        constant_velocity: s.constant_velocity(),
        accelerating: s.accelerating(),
        decelerating: s.decelerating(),
        status: axis_state(&s, t),
    }
}

fn read_axis_error(o: Result<AxisReply, Rejection>, _t: Time) -> ReadAxisErrorResponse {
    match o.map(|r| r.value) {
        Ok(ReplyValue::DWord(e)) => ReadAxisErrorResponse {
            accepted: true,
            axis_error_id: e,
            ..Default::default()
        },
        Ok(v) => ReadAxisErrorResponse {
            error_id: unexpected(&v).error_id.0,
            message: unexpected(&v).message,
            ..Default::default()
        },
        Err(e) => ReadAxisErrorResponse {
            error_id: e.error_id.0,
            message: e.message,
            ..Default::default()
        },
    }
}

fn read_actual_position(o: Result<AxisReply, Rejection>, _t: Time) -> ReadActualPositionResponse {
    match o.map(|r| r.value) {
        Ok(ReplyValue::Real(p)) => ReadActualPositionResponse {
            accepted: true,
            position: p,
            ..Default::default()
        },
        Ok(v) => ReadActualPositionResponse {
            error_id: unexpected(&v).error_id.0,
            message: unexpected(&v).message,
            ..Default::default()
        },
        Err(e) => ReadActualPositionResponse {
            error_id: e.error_id.0,
            message: e.message,
            ..Default::default()
        },
    }
}

fn read_actual_velocity(o: Result<AxisReply, Rejection>, _t: Time) -> ReadActualVelocityResponse {
    match o.map(|r| r.value) {
        Ok(ReplyValue::Real(v)) => ReadActualVelocityResponse {
            accepted: true,
            actual_velocity: v,
            ..Default::default()
        },
        Ok(v) => ReadActualVelocityResponse {
            error_id: unexpected(&v).error_id.0,
            message: unexpected(&v).message,
            ..Default::default()
        },
        Err(e) => ReadActualVelocityResponse {
            error_id: e.error_id.0,
            message: e.message,
            ..Default::default()
        },
    }
}

/// The manual's FB name of an instance kind.
pub(crate) fn fb_name(k: FbKind) -> &'static str {
    k.fb_name()
}

/// The extra outputs of phasing, external-setpoint and position-correction instances as the
/// tail fields of `GetOutputs` (the rest default).
fn extra_outputs(x: Option<ExtraOutputs>) -> GetOutputsResponse {
    let mut r = GetOutputsResponse::default();
    match x {
        Some(ExtraOutputs::Phasing {
            absolute_phase_shift,
            covered_phase_shift,
        }) => {
            r.absolute_phase_shift = absolute_phase_shift.unwrap_or(0.0);
            r.covered_phase_shift = covered_phase_shift.unwrap_or(0.0);
        }
        Some(ExtraOutputs::ExtSetPointGen { enabled }) => r.enabled = enabled,
        Some(ExtraOutputs::Backlash {
            enabled,
            current_backlash,
            limiting,
        }) => {
            r.enabled = enabled;
            r.current_backlash = current_backlash;
            r.limiting = limiting;
        }
        Some(ExtraOutputs::CorrectionLimiter { limiting }) => r.limiting = limiting,
        Some(ExtraOutputs::Power { status, valid }) => {
            r.status = status;
            r.valid = valid;
        }
        Some(ExtraOutputs::TableCompensation {
            enabled,
            current_correction,
            limiting,
        }) => {
            r.enabled = enabled;
            r.current_correction = current_correction;
            r.limiting = limiting;
        }
        None => {}
    }
    r
}

fn get_outputs(o: Result<AxisReply, Rejection>, _t: Time) -> GetOutputsResponse {
    let out = match o.map(|r| r.value) {
        Ok(ReplyValue::Outputs(out)) => out,
        Ok(ReplyValue::Ca(v)) if crate::ca::get_outputs(&v).is_some() => {
            return crate::ca::get_outputs(&v).unwrap_or_default()
        }
        // An instance of a Part 4 group FB: its Execute outputs (groups.rs).
        Ok(ReplyValue::Group(axis_engine::GroupReply::Outputs(s))) => {
            return GetOutputsResponse {
                accepted: true,
                done: s.done,
                busy: s.busy,
                active: s.active,
                command_aborted: s.command_aborted,
                error: s.error,
                fb_error_id: s.error_id.0,
                ..Default::default()
            }
        }
        Ok(v) => {
            return GetOutputsResponse {
                error_id: unexpected(&v).error_id.0,
                message: unexpected(&v).message,
                ..Default::default()
            }
        }
        Err(e) => {
            return GetOutputsResponse {
                error_id: e.error_id.0,
                message: e.message,
                ..Default::default()
            }
        }
    };
    let s = out.outputs.standard;
    let si = out.superimposed.unwrap_or_default();
    let p = out.probe;
    let x = extra_outputs(out.extra);
    GetOutputsResponse {
        accepted: true,
        error_id: 0,
        message: String::new(),
        axis: out.axis.clone(),
        fb: fb_name(out.kind).to_string(),
        done: s.done,
        busy: s.busy,
        active: s.active,
        command_aborted: s.command_aborted,
        error: s.error,
        fb_error_id: s.error_id.0,
        in_velocity: out.outputs.in_velocity,
        in_end_velocity: out.outputs.in_end_velocity,
        in_torque: out.outputs.in_torque,
        in_gear: out.outputs.in_gear,
        warning: si.warning,
        warning_id: si.warning_id.0,
        actual_velocity_diff: si.actual_velocity_diff,
        actual_distance: si.actual_distance,
        actual_length: si.actual_length,
        actual_acceleration: si.actual_acceleration,
        actual_deceleration: si.actual_deceleration,
        recorded: p.is_some(),
        recorded_position: p.map_or(0.0, |p| p.recorded_position),
        recorded_counter: p.map_or(0.0, |p| p.counter),
        recorded_absolute_position: p.map_or(0.0, |p| p.absolute_position),
        recorded_modulo_position: p.map_or(0.0, |p| p.modulo_position),
        ..x
    }
}

pub(crate) fn register(shell: &mut NodeShell<AxisEngine>) -> Result<(), ShellError> {
    read_service(
        shell,
        "read_status",
        ReadStatus::service_type_name(),
        |r: ReadStatusRequest| AxisCommand::ReadStatus(axis_engine::ReadStatus { axis: r.axis }),
        read_status,
    )?;
    read_service(
        shell,
        "read_axis_error",
        ReadAxisError::service_type_name(),
        |r: ReadAxisErrorRequest| {
            AxisCommand::ReadAxisError(axis_engine::ReadAxisError { axis: r.axis })
        },
        read_axis_error,
    )?;
    read_service(
        shell,
        "read_actual_position",
        ReadActualPosition::service_type_name(),
        |r: ReadActualPositionRequest| {
            AxisCommand::ReadActualPosition(axis_engine::ReadActualPosition { axis: r.axis })
        },
        read_actual_position,
    )?;
    read_service(
        shell,
        "read_actual_velocity",
        ReadActualVelocity::service_type_name(),
        |r: ReadActualVelocityRequest| {
            AxisCommand::ReadActualVelocity(axis_engine::ReadActualVelocity { axis: r.axis })
        },
        read_actual_velocity,
    )?;
    read_service(
        shell,
        "get_outputs",
        GetOutputs::service_type_name(),
        |r: GetOutputsRequest| AxisCommand::ReadFbOutputs {
            id: CmdId(r.command_id),
        },
        get_outputs,
    )
}
