//! Services of the FBs beyond the basic moves (single_axis.md §4.5, §4.7.10, §4.8.4, §4.8.7,
//! §4.8.8, §4.9, §4.10, §4.12, §4.14): one call = one Execute edge (or, for the Enable-type
//! MC_GearInDyn and MC_SetOverride, one call with the current input levels), plus the later
//! input changes of a running instance (`~/home_calibration_cam`, `~/torque_control_update`,
//! `~/touch_probe_plc_event`, `~/set_execute`), addressed by its command id.

use crate::services::{buffer_mode, direction, label, move_options, respond, Outcome};
use axis_engine::{
    AxisCommand, AxisEngine, HomingMode, HomingOptions, SignalEdge, SuperpositionAbortOption,
    SuperpositionMode, TorqueControlOptions, TouchProbeMode, TouchProbeUnit, TriggerRef,
};
use motion_core::{CmdId, Rejection};
use motion_msgs::srv::*;
use motion_runtime::{CommandLabel, NodeShell, ShellError};

type Decoded = Result<(AxisCommand, CommandLabel), Rejection>;

/// Raw enum value of a request field, refused with 0x7F03 by the engine's `from_raw`.
fn raw<T>(v: u8, from_raw: fn(u32) -> Result<T, Rejection>) -> Result<T, Rejection> {
    from_raw(u32::from(v))
}

pub(crate) fn decode_move_modulo(r: MoveModuloRequest) -> Decoded {
    let l = label(&r.axis, "move_modulo");
    Ok((
        AxisCommand::MoveModulo(axis_engine::MoveModulo {
            axis: r.axis,
            position: r.position,
            velocity: r.velocity,
            acceleration: r.acceleration,
            deceleration: r.deceleration,
            jerk: r.jerk,
            direction: direction(r.direction)?,
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

pub(crate) fn decode_move_continuous_absolute(r: MoveContinuousAbsoluteRequest) -> Decoded {
    let l = label(&r.axis, "move_continuous_absolute");
    Ok((
        AxisCommand::MoveContinuousAbsolute(axis_engine::MoveContinuousAbsolute {
            axis: r.axis,
            position: r.position,
            velocity: r.velocity,
            end_velocity: r.end_velocity,
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

pub(crate) fn decode_move_continuous_relative(r: MoveContinuousRelativeRequest) -> Decoded {
    let l = label(&r.axis, "move_continuous_relative");
    Ok((
        AxisCommand::MoveContinuousRelative(axis_engine::MoveContinuousRelative {
            axis: r.axis,
            distance: r.distance,
            velocity: r.velocity,
            end_velocity: r.end_velocity,
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

/// The fields MC_Home has in both its service and its action.
#[allow(clippy::too_many_arguments)]
/// MC_Home from its service request (the action's goal converts into it).
pub(crate) fn decode_home(r: HomeRequest) -> Decoded {
    let l = label(&r.axis, "home");
    Ok((
        AxisCommand::Home(axis_engine::Home {
            axis: r.axis,
            position: r.position,
            use_default_position: r.use_default_position,
            homing_mode: raw(r.homing_mode, HomingMode::from_raw)?,
            buffer_mode: buffer_mode(r.buffer_mode)?,
            options: HomingOptions {
                clear_position_lag: r.clear_position_lag,
                search_direction: direction(r.search_direction)?,
                search_velocity: r.search_velocity,
                sync_direction: direction(r.sync_direction)?,
                sync_velocity: r.sync_velocity,
                reference_mode: r.reference_mode,
            },
            calibration_cam: r.calibration_cam,
        }),
        l,
    ))
}

fn decode_home_calibration_cam(r: HomeCalibrationCamRequest) -> Decoded {
    let l = label("", "home_calibration_cam");
    Ok((
        AxisCommand::HomeCalibrationCam {
            id: CmdId(r.command_id),
            calibration_cam: r.calibration_cam,
        },
        l,
    ))
}

/// MC_GearIn from its service request (the action's goal converts into it).
pub(crate) fn decode_gear_in(r: GearInRequest) -> Decoded {
    let l = label(&r.slave, "gear_in");
    Ok((
        AxisCommand::GearIn(axis_engine::GearIn {
            master: r.master,
            slave: r.slave,
            ratio_numerator: r.ratio_numerator,
            ratio_denominator: u32::from(r.ratio_denominator),
            acceleration: r.acceleration,
            deceleration: r.deceleration,
            jerk: r.jerk,
            buffer_mode: buffer_mode(r.buffer_mode)?,
        }),
        l,
    ))
}

fn decode_gear_out(r: GearOutRequest) -> Decoded {
    let l = label(&r.slave, "gear_out");
    Ok((
        AxisCommand::GearOut(axis_engine::GearOut { slave: r.slave }),
        l,
    ))
}

fn decode_gear_in_dyn(r: GearInDynRequest) -> Decoded {
    let l = label(&r.slave, "gear_in_dyn");
    Ok((
        AxisCommand::GearInDyn(axis_engine::GearInDyn {
            master: r.master,
            slave: r.slave,
            enable: r.enable,
            gear_ratio: r.gear_ratio,
            acceleration: r.acceleration,
            deceleration: r.deceleration,
            jerk: r.jerk,
            buffer_mode: buffer_mode(r.buffer_mode)?,
        }),
        l,
    ))
}

pub(crate) fn decode_torque_control(r: TorqueControlRequest) -> Decoded {
    let l = label(&r.axis, "torque_control");
    Ok((
        AxisCommand::TorqueControl(axis_engine::TorqueControl {
            axis: r.axis,
            continuous_update: r.continuous_update,
            relative: r.relative,
            torque: r.torque,
            torque_ramp: r.torque_ramp,
            velocity_limit_high: r.velocity_limit_high,
            velocity_limit_low: r.velocity_limit_low,
            buffer_mode: buffer_mode(r.buffer_mode)?,
            options: TorqueControlOptions {
                enable_manual_torque_start_value: r.enable_manual_torque_start_value,
                manual_torque_start_value: r.manual_torque_start_value,
            },
        }),
        l,
    ))
}

fn decode_torque_control_update(r: TorqueControlUpdateRequest) -> Decoded {
    let l = label("", "torque_control_update");
    Ok((
        AxisCommand::TorqueControlUpdate {
            id: CmdId(r.command_id),
            torque: r.torque,
            torque_ramp: r.torque_ramp,
            velocity_limit_high: r.velocity_limit_high,
            velocity_limit_low: r.velocity_limit_low,
        },
        l,
    ))
}

/// MC_MoveSuperImposed from its service request (the action's goal converts into it).
pub(crate) fn decode_move_superimposed(r: MoveSuperImposedRequest) -> Decoded {
    let l = label(&r.axis, "move_superimposed");
    Ok((
        AxisCommand::MoveSuperImposed(axis_engine::MoveSuperImposed {
            axis: r.axis,
            mode: raw(r.mode, SuperpositionMode::from_raw)?,
            distance: r.distance,
            velocity_diff: r.velocity_diff,
            acceleration: r.acceleration,
            deceleration: r.deceleration,
            jerk: r.jerk,
            velocity_process: r.velocity_process,
            length: r.length,
            abort_option: raw(r.abort_option, SuperpositionAbortOption::from_raw)?,
        }),
        l,
    ))
}

fn decode_abort_superposition(r: AbortSuperpositionRequest) -> Decoded {
    let l = label(&r.axis, "abort_superposition");
    Ok((
        AxisCommand::AbortSuperposition(axis_engine::AbortSuperposition { axis: r.axis }),
        l,
    ))
}

/// `TRIGGER_REF` from its request fields.
#[allow(clippy::too_many_arguments)]
fn trigger_ref(
    encoder_id: u32,
    touch_probe: u8,
    signal_source: u32,
    edge: u8,
    mode: u8,
    plc_event: bool,
    modulo_positions: bool,
) -> Result<TriggerRef, Rejection> {
    Ok(TriggerRef {
        encoder_id,
        touch_probe: raw(touch_probe, TouchProbeUnit::from_raw)?,
        signal_source,
        edge: raw(edge, SignalEdge::from_raw)?,
        mode: raw(mode, TouchProbeMode::from_raw)?,
        plc_event,
        modulo_positions,
    })
}

fn decode_touch_probe(r: TouchProbeRequest) -> Decoded {
    let l = label(&r.axis, "touch_probe");
    let trigger_input = trigger_ref(
        r.encoder_id,
        r.touch_probe,
        r.signal_source,
        r.edge,
        r.mode,
        r.plc_event,
        r.modulo_positions,
    )?;
    Ok((
        AxisCommand::TouchProbe(axis_engine::TouchProbe {
            axis: r.axis,
            trigger_input,
            window_only: r.window_only,
            first_position: r.first_position,
            last_position: r.last_position,
        }),
        l,
    ))
}

fn decode_touch_probe_plc_event(r: TouchProbePlcEventRequest) -> Decoded {
    let l = label("", "touch_probe_plc_event");
    Ok((
        AxisCommand::TouchProbePlcEvent {
            id: CmdId(r.command_id),
            plc_event: r.plc_event,
        },
        l,
    ))
}

fn decode_abort_trigger(r: AbortTriggerRequest) -> Decoded {
    let l = label(&r.axis, "abort_trigger");
    let trigger_input = trigger_ref(
        r.encoder_id,
        r.touch_probe,
        r.signal_source,
        r.edge,
        r.mode,
        r.plc_event,
        r.modulo_positions,
    )?;
    Ok((
        AxisCommand::AbortTrigger(axis_engine::AbortTrigger {
            axis: r.axis,
            trigger_input,
        }),
        l,
    ))
}

fn decode_set_execute(r: SetExecuteRequest) -> Decoded {
    let l = label("", "set_execute");
    Ok((
        AxisCommand::SetExecute {
            id: CmdId(r.command_id),
            execute: r.execute,
        },
        l,
    ))
}

fn decode_set_override(r: SetOverrideRequest) -> Decoded {
    let l = label(&r.axis, "set_override");
    Ok((
        AxisCommand::SetOverride(axis_engine::SetOverride {
            axis: r.axis,
            enable: r.enable,
            vel_factor: r.vel_factor,
            acc_factor: r.acc_factor,
            jerk_factor: r.jerk_factor,
        }),
        l,
    ))
}

/// A later input of a running instance (addressed by its command id): like
/// `command_service`, but the instance keeps the label it was started with.
fn later_input<Req, Resp>(
    shell: &mut NodeShell<AxisEngine>,
    name: &str,
    ty: ros2_client::ServiceTypeName,
    decode: fn(Req) -> Decoded,
    respond: fn(Outcome) -> Resp,
) -> Result<(), ShellError>
where
    Req: ros2_client::Message + Clone + Send + Sync + 'static,
    Resp: ros2_client::Message + Send + Sync + 'static,
{
    let handle = shell.handle.clone();
    shell.service::<Req, Resp, _, _>(name, ty, move |r: Req| {
        let handle = handle.clone();
        async move {
            let o = match decode(r) {
                Ok((cmd, _)) => handle.call(cmd).await,
                Err(e) => Err(e),
            };
            respond(o)
        }
    })
}

pub(crate) fn register(shell: &mut NodeShell<AxisEngine>) -> Result<(), ShellError> {
    shell.command_service(
        "move_modulo",
        MoveModulo::service_type_name(),
        decode_move_modulo,
        respond::<MoveModuloResponse>,
    )?;
    shell.command_service(
        "move_continuous_absolute",
        MoveContinuousAbsolute::service_type_name(),
        decode_move_continuous_absolute,
        respond::<MoveContinuousAbsoluteResponse>,
    )?;
    shell.command_service(
        "move_continuous_relative",
        MoveContinuousRelative::service_type_name(),
        decode_move_continuous_relative,
        respond::<MoveContinuousRelativeResponse>,
    )?;
    shell.command_service(
        "home",
        Home::service_type_name(),
        decode_home,
        respond::<HomeResponse>,
    )?;
    later_input(
        shell,
        "home_calibration_cam",
        HomeCalibrationCam::service_type_name(),
        decode_home_calibration_cam,
        respond::<HomeCalibrationCamResponse>,
    )?;
    shell.command_service(
        "gear_in",
        GearIn::service_type_name(),
        decode_gear_in,
        respond::<GearInResponse>,
    )?;
    shell.command_service(
        "gear_out",
        GearOut::service_type_name(),
        decode_gear_out,
        respond::<GearOutResponse>,
    )?;
    shell.command_service(
        "gear_in_dyn",
        GearInDyn::service_type_name(),
        decode_gear_in_dyn,
        respond::<GearInDynResponse>,
    )?;
    shell.command_service(
        "torque_control",
        TorqueControl::service_type_name(),
        decode_torque_control,
        respond::<TorqueControlResponse>,
    )?;
    later_input(
        shell,
        "torque_control_update",
        TorqueControlUpdate::service_type_name(),
        decode_torque_control_update,
        respond::<TorqueControlUpdateResponse>,
    )?;
    shell.command_service(
        "move_superimposed",
        MoveSuperImposed::service_type_name(),
        decode_move_superimposed,
        respond::<MoveSuperImposedResponse>,
    )?;
    shell.command_service(
        "abort_superposition",
        AbortSuperposition::service_type_name(),
        decode_abort_superposition,
        respond::<AbortSuperpositionResponse>,
    )?;
    shell.command_service(
        "touch_probe",
        TouchProbe::service_type_name(),
        decode_touch_probe,
        respond::<TouchProbeResponse>,
    )?;
    later_input(
        shell,
        "touch_probe_plc_event",
        TouchProbePlcEvent::service_type_name(),
        decode_touch_probe_plc_event,
        respond::<TouchProbePlcEventResponse>,
    )?;
    shell.command_service(
        "abort_trigger",
        AbortTrigger::service_type_name(),
        decode_abort_trigger,
        respond::<AbortTriggerResponse>,
    )?;
    later_input(
        shell,
        "set_execute",
        SetExecute::service_type_name(),
        decode_set_execute,
        respond::<SetExecuteResponse>,
    )?;
    register_set_override(shell)
}

/// `~/set_override`: `enabled` = MC_SetOverride.Enabled after the call (Enable TRUE and the
/// factors accepted; a refused VelFactor keeps the previous value and reports the error).
fn register_set_override(shell: &mut NodeShell<AxisEngine>) -> Result<(), ShellError> {
    let handle = shell.handle.clone();
    shell.service::<SetOverrideRequest, SetOverrideResponse, _, _>(
        "set_override",
        SetOverride::service_type_name(),
        move |r: SetOverrideRequest| {
            let handle = handle.clone();
            async move {
                let enable = r.enable;
                let o: Outcome = match decode_set_override(r) {
                    Ok((cmd, _)) => handle.call(cmd).await,
                    Err(e) => Err(e),
                };
                let enabled = enable && o.is_ok();
                SetOverrideResponse {
                    enabled,
                    ..respond(o)
                }
            }
        },
    )
}
