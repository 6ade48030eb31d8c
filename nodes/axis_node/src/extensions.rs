//! Services of the FBs added with phasing, multi-master gearing, the external setpoint
//! generator and the §4.7 extensions (single_axis.md §4.4.3, §4.4.6, §4.4.9, §4.6, §4.7,
//! §4.12.4, §4.13): one service per FB, request fields = the FB inputs, enum inputs as their
//! numbers (out of range -> 0x7F03). Enable-type FBs (MC_GearInMultiMaster,
//! MC_BacklashCompensation, MC_PositionCorrectionLimiter, MC_TableBasedPositionCompensation)
//! follow `~/gear_in_dyn`: Enable TRUE starts or updates (same `command_id`), FALSE ends.
//! Later inputs of a running MC_PhasingAbsolute/Relative: `~/phasing_update` (by command id).
//! MC_Write(Bool)ParameterPersistent (and `~/write_parameter` with `persistent`) store the
//! initialization list in the node's `persistent_parameter_file` when one is configured.

use crate::services::{buffer_mode, label, respond, Outcome};
use axis_engine::{
    AxisCommand, AxisEngine, AxisReply, DisableMode, DriveOperationMode, ExtSetPointEnableOptions,
    ExtensionValue, GearInMultiMasterOptions, GearInMultiMasterSyncMode, NcIoDevice, NcIoOutput,
    NcPositionConversionOptions, PositionCompensationTableElement,
    PositionCompensationTableParameter, PositionCorrectionMode, PositionType, ReplyValue,
    SelectControlLoopType, SetEncoderScalingOptions, SetScalingFactorMode, WorkDirection,
};
use motion_core::{CmdId, Rejection};
use motion_msgs::msg::AxisParameterSet;
use motion_msgs::srv::*;
use motion_runtime::{CommandLabel, NodeShell, ShellError};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

type Decoded = Result<(AxisCommand, CommandLabel), Rejection>;

/// Raw enum value of a request field, refused with 0x7F03 by the engine's `from_raw`.
fn raw<T>(v: impl Into<u32>, from_raw: fn(u32) -> Result<T, Rejection>) -> Result<T, Rejection> {
    from_raw(v.into())
}

// ---------------------------------------------------------------- phasing (§4.13)

/// MC_PhasingAbsolute from its service request (the action's goal converts into it).
pub(crate) fn decode_phasing_absolute(r: PhasingAbsoluteRequest) -> Decoded {
    let l = label(&r.slave, "phasing_absolute");
    let c = axis_engine::PhasingAbsolute {
        master: r.master,
        slave: r.slave,
        continuous_update: r.continuous_update,
        phase_shift: r.phase_shift,
        velocity: r.velocity,
        acceleration: r.acceleration,
        deceleration: r.deceleration,
        jerk: r.jerk,
        buffer_mode: buffer_mode(r.buffer_mode)?,
    };
    Ok((AxisCommand::PhasingAbsolute(c), l))
}

/// MC_PhasingRelative from its service request (the action's goal converts into it).
pub(crate) fn decode_phasing_relative(r: PhasingRelativeRequest) -> Decoded {
    let l = label(&r.slave, "phasing_relative");
    let c = axis_engine::PhasingRelative {
        master: r.master,
        slave: r.slave,
        continuous_update: r.continuous_update,
        phase_shift: r.phase_shift,
        velocity: r.velocity,
        acceleration: r.acceleration,
        deceleration: r.deceleration,
        jerk: r.jerk,
        buffer_mode: buffer_mode(r.buffer_mode)?,
    };
    Ok((AxisCommand::PhasingRelative(c), l))
}

/// MC_HaltPhasing from its service request (the action's goal converts into it).
pub(crate) fn decode_halt_phasing(r: HaltPhasingRequest) -> Decoded {
    let l = label(&r.slave, "halt_phasing");
    Ok((
        AxisCommand::HaltPhasing(axis_engine::HaltPhasing {
            master: r.master,
            slave: r.slave,
            deceleration: r.deceleration,
            jerk: r.jerk,
            buffer_mode: buffer_mode(r.buffer_mode)?,
        }),
        l,
    ))
}

fn decode_phasing_update(r: PhasingUpdateRequest) -> Decoded {
    Ok((
        AxisCommand::PhasingUpdate(axis_engine::PhasingUpdate {
            id: CmdId(r.command_id),
            phase_shift: r.phase_shift,
            velocity: r.velocity,
            acceleration: r.acceleration,
            deceleration: r.deceleration,
            jerk: r.jerk,
        }),
        label("", "phasing_update"),
    ))
}

// ---------------------------------------------------------------- MC_GearInMultiMaster

fn decode_gear_in_multi_master(r: GearInMultiMasterRequest) -> Decoded {
    let l = label(&r.slave, "gear_in_multi_master");
    Ok((
        AxisCommand::GearInMultiMaster(axis_engine::GearInMultiMaster {
            slave: r.slave,
            master1: r.master1,
            master2: r.master2,
            master3: r.master3,
            master4: r.master4,
            enable: r.enable,
            gear_ratio1: r.gear_ratio1,
            gear_ratio2: r.gear_ratio2,
            gear_ratio3: r.gear_ratio3,
            gear_ratio4: r.gear_ratio4,
            acceleration: r.acceleration,
            deceleration: r.deceleration,
            jerk: r.jerk,
            buffer_mode: buffer_mode(r.buffer_mode)?,
            options: GearInMultiMasterOptions {
                advanced_slave_dynamics: r.advanced_slave_dynamics,
                sync_mode: raw(r.sync_mode, GearInMultiMasterSyncMode::from_raw)?,
            },
        }),
        l,
    ))
}

// ---------------------------------------------------------------- external setpoints (§4.6)

fn decode_ext_set_point_gen_enable(r: ExtSetPointGenEnableRequest) -> Decoded {
    let l = label(&r.axis, "ext_set_point_gen_enable");
    Ok((
        AxisCommand::ExtSetPointGenEnable(axis_engine::ExtSetPointGenEnable {
            axis: r.axis,
            position: r.position,
            position_type: raw(r.position_type, PositionType::from_raw)?,
            options: ExtSetPointEnableOptions {
                use_torque_offset: r.use_torque_offset,
            },
        }),
        l,
    ))
}

fn decode_ext_set_point_gen_disable(r: ExtSetPointGenDisableRequest) -> Decoded {
    let l = label(&r.axis, "ext_set_point_gen_disable");
    Ok((
        AxisCommand::ExtSetPointGenDisable(axis_engine::ExtSetPointGenDisable { axis: r.axis }),
        l,
    ))
}

fn decode_ext_set_point_gen_feed(r: ExtSetPointGenFeedRequest) -> Decoded {
    let l = label(&r.axis, "ext_set_point_gen_feed");
    let cmd = if r.with_torque {
        AxisCommand::ExtSetPointGenFeedWithTorque(axis_engine::ExtSetPointGenFeedWithTorque {
            axis: r.axis,
            position: r.position,
            velocity: r.velocity,
            acceleration: r.acceleration,
            direction: r.direction,
            torque_offset: r.torque_offset,
        })
    } else {
        AxisCommand::ExtSetPointGenFeed(axis_engine::ExtSetPointGenFeed {
            axis: r.axis,
            position: r.position,
            velocity: r.velocity,
            acceleration: r.acceleration,
            direction: r.direction,
        })
    };
    Ok((cmd, l))
}

// ---------------------------------------------------------------- §4.7 extensions

fn decode_read_drive_operation_mode(r: ReadDriveOperationModeRequest) -> Decoded {
    let l = label(&r.axis, "read_drive_operation_mode");
    Ok((
        AxisCommand::ReadDriveOperationMode(axis_engine::ReadDriveOperationMode { axis: r.axis }),
        l,
    ))
}

fn decode_write_drive_operation_mode(r: WriteDriveOperationModeRequest) -> Decoded {
    let l = label(&r.axis, "write_drive_operation_mode");
    Ok((
        AxisCommand::WriteDriveOperationMode(axis_engine::WriteDriveOperationMode {
            axis: r.axis,
            drive_operation_mode: raw(r.drive_operation_mode, DriveOperationMode::from_raw)?,
        }),
        l,
    ))
}

fn decode_backlash_compensation(r: BacklashCompensationRequest) -> Decoded {
    let l = label(&r.axis, "backlash_compensation");
    Ok((
        AxisCommand::BacklashCompensation(axis_engine::BacklashCompensation {
            axis: r.axis,
            enable: r.enable,
            backlash: r.backlash,
            compensation_in_positive_direction: r.compensation_in_positive_direction,
            ramp: r.ramp,
            disable_mode: raw(r.disable_mode, DisableMode::from_raw)?,
        }),
        l,
    ))
}

fn decode_position_correction_limiter(r: PositionCorrectionLimiterRequest) -> Decoded {
    let l = label(&r.axis, "position_correction_limiter");
    Ok((
        AxisCommand::PositionCorrectionLimiter(axis_engine::PositionCorrectionLimiter {
            axis: r.axis,
            enable: r.enable,
            position_correction_value: r.position_correction_value,
            correction_mode: raw(r.correction_mode, PositionCorrectionMode::from_raw)?,
            acceleration: r.acceleration,
            correction_length: r.correction_length,
        }),
        l,
    ))
}

fn decode_table_based_position_compensation(r: TableBasedPositionCompensationRequest) -> Decoded {
    let l = label(&r.axis, "table_based_position_compensation");
    Ok((
        AxisCommand::TableBasedPositionCompensation(axis_engine::TableBasedPositionCompensation {
            axis: r.axis,
            enable: r.enable,
            table: r
                .table
                .iter()
                .map(|e| PositionCompensationTableElement {
                    position: e.position,
                    compensation: e.compensation,
                })
                .collect(),
            table_parameter: PositionCompensationTableParameter {
                min_position: r.min_position,
                max_position: r.max_position,
                no_of_table_elements: r.no_of_table_elements,
                direction: raw(r.direction, WorkDirection::from_raw)?,
                modulo: r.modulo,
            },
            ramp: r.ramp,
            disable_mode: raw(r.disable_mode, DisableMode::from_raw)?,
        }),
        l,
    ))
}

fn decode_read_drive_address(r: ReadDriveAddressRequest) -> Decoded {
    let l = label(&r.axis, "read_drive_address");
    Ok((
        AxisCommand::ReadDriveAddress(axis_engine::ReadDriveAddress { axis: r.axis }),
        l,
    ))
}

fn decode_select_control_loop(r: SelectControlLoopRequest) -> Decoded {
    let l = label(&r.axis, "select_control_loop");
    Ok((
        AxisCommand::SelectControlLoop(axis_engine::SelectControlLoop {
            axis: r.axis,
            encoder_index: r.encoder_index,
            select_type: raw(r.select_type, SelectControlLoopType::from_raw)?,
            sync_value: r.sync_value,
            ext_set_point_gen: r.ext_set_point_gen,
        }),
        l,
    ))
}

fn decode_set_accept_blocked_drive_signal(r: SetAcceptBlockedDriveSignalRequest) -> Decoded {
    let l = label(&r.axis, "set_accept_blocked_drive_signal");
    Ok((
        AxisCommand::SetAcceptBlockedDriveSignal(axis_engine::SetAcceptBlockedDriveSignal {
            axis: r.axis,
            enable: r.enable,
        }),
        l,
    ))
}

fn decode_set_encoder_scaling_factor(r: SetEncoderScalingFactorRequest) -> Decoded {
    let l = label(&r.axis, "set_encoder_scaling_factor");
    Ok((
        AxisCommand::SetEncoderScalingFactor(axis_engine::SetEncoderScalingFactor {
            axis: r.axis,
            scaling_factor: r.scaling_factor,
            mode: raw(r.mode, SetScalingFactorMode::from_raw)?,
            options: SetEncoderScalingOptions {
                select_encoder_index: r.select_encoder_index,
                encoder_index: r.encoder_index,
            },
        }),
        l,
    ))
}

fn decode_write_nc_io_output(r: WriteNcIoOutputRequest) -> Decoded {
    let l = label(&r.axis, "write_nc_io_output");
    Ok((
        AxisCommand::WriteNcIoOutput(axis_engine::WriteNcIoOutput {
            axis: r.axis,
            device: raw(r.device, NcIoDevice::from_raw)?,
            nc_io_output: raw(r.nc_io_output, NcIoOutput::from_raw)?,
            bit_select_mask: r.bit_select_mask,
            bit_values: r.bit_values,
        }),
        l,
    ))
}

fn decode_convert_inc_pos_to_pos(r: ConvertIncPosToPosRequest) -> Decoded {
    let l = label(&r.axis, "convert_inc_pos_to_pos");
    Ok((
        AxisCommand::ConvertIncPosToPos(axis_engine::ConvertIncPosToPos {
            axis: r.axis,
            inc_pos: r.inc_pos,
            options: NcPositionConversionOptions {
                sub_index: r.sub_index,
                ctrl_mask: r.ctrl_mask,
            },
        }),
        l,
    ))
}

fn decode_convert_pos_to_inc_pos(r: ConvertPosToIncPosRequest) -> Decoded {
    let l = label(&r.axis, "convert_pos_to_inc_pos");
    Ok((
        AxisCommand::ConvertPosToIncPos(axis_engine::ConvertPosToIncPos {
            axis: r.axis,
            position: r.position,
            options: NcPositionConversionOptions {
                sub_index: r.sub_index,
                ctrl_mask: r.ctrl_mask,
            },
        }),
        l,
    ))
}

fn decode_read_parameter_set(r: ReadParameterSetRequest) -> Decoded {
    let l = label(&r.axis, "read_parameter_set");
    Ok((
        AxisCommand::ReadParameterSet(axis_engine::ReadParameterSet { axis: r.axis }),
        l,
    ))
}

fn decode_read_axis_components(r: ReadAxisComponentsRequest) -> Decoded {
    let l = label(&r.axis, "read_axis_components");
    Ok((
        AxisCommand::ReadAxisComponents(axis_engine::ReadAxisComponents { axis: r.axis }),
        l,
    ))
}

// ---------------------------------------------------------------- responses with values

fn extension(o: &Outcome) -> Option<&ExtensionValue> {
    match o {
        Ok(AxisReply {
            value: ReplyValue::Extension(v),
            ..
        }) => Some(v),
        _ => None,
    }
}

fn respond_read_drive_operation_mode(o: Outcome) -> ReadDriveOperationModeResponse {
    let mode = match extension(&o) {
        Some(ExtensionValue::DriveOperationMode(m)) => m.raw() as u8,
        _ => 0,
    };
    ReadDriveOperationModeResponse {
        drive_operation_mode: mode,
        ..respond(o)
    }
}

fn respond_read_drive_address(o: Outcome) -> ReadDriveAddressResponse {
    let r: ReadDriveAddressResponse = respond(o.clone());
    match extension(&o) {
        Some(ExtensionValue::DriveAddress(d)) => ReadDriveAddressResponse {
            net_id: d.net_id.clone(),
            net_id_bytes: d.net_id_bytes,
            slave_address: d.slave_address,
            channel: d.channel,
            nc_drive_id: d.nc_drive_id,
            nc_drive_index: d.nc_drive_index,
            nc_drive_type: d.nc_drive_type,
            nc_encoder_id: d.nc_encoder_id,
            nc_encoder_index: d.nc_encoder_index,
            nc_encoder_type: d.nc_encoder_type,
            nc_axis_id: d.nc_axis_id,
            nc_axis_type: d.nc_axis_type,
            tc_drive_object_id: d.tc_drive_object_id,
            tc_encoder_object_id: d.tc_encoder_object_id,
            tc_axis_object_id: d.tc_axis_object_id,
            ..r
        },
        _ => r,
    }
}

fn parameter_set(p: &axis_engine::extensions::AxisParameterSet) -> AxisParameterSet {
    AxisParameterSet {
        axis_id: p.axis_id,
        axis_type: p.axis_type,
        axis_name: p.axis_name.clone(),
        axis_cycle_time: p.axis_cycle_time,
        enable_position_area_control: p.enable_position_area_control,
        position_area_control_range: p.position_area_control_range,
        enable_target_pos_control: p.enable_target_pos_control,
        target_pos_control_range: p.target_pos_control_range,
        target_pos_control_time: p.target_pos_control_time,
        velo_maximum: p.velo_maximum,
        ref_velo_search: p.ref_velo_search,
        ref_velo_sync: p.ref_velo_sync,
        velo_slow_manual: p.velo_slow_manual,
        velo_fast_manual: p.velo_fast_manual,
        enable_peh_time_control: p.enable_peh_time_control,
        peh_control_time: p.peh_control_time,
        enable_backlash_compensation: p.enable_backlash_compensation,
        backlash: p.backlash,
        ams_net_id: p.ams_net_id.clone(),
        port: p.port,
        chn_no: p.chn_no,
        acceleration: p.acceleration,
        deceleration: p.deceleration,
        jerk: p.jerk,
        enc_id: p.enc_id,
        enc_type: p.enc_type,
        enc_scale_factor: p.enc_scale_factor,
        enc_offset: p.enc_offset,
        enc_modulo_factor: p.enc_modulo_factor,
        enc_enable_soft_end_min_control: p.enc_enable_soft_end_min_control,
        enc_enable_soft_end_max_control: p.enc_enable_soft_end_max_control,
        enc_soft_end_min: p.enc_soft_end_min,
        enc_soft_end_max: p.enc_soft_end_max,
        enc_max_increment: p.enc_max_increment,
        enc_enable_pos_correction: p.enc_enable_pos_correction,
        enc_ref_search_inverse: p.enc_ref_search_inverse,
        enc_ref_sync_inverse: p.enc_ref_sync_inverse,
        enc_ref_mode: p.enc_ref_mode,
        enc_ref_position: p.enc_ref_position,
        ctrl_id: p.ctrl_id,
        ctrl_enable_pos_diff_control: p.ctrl_enable_pos_diff_control,
        ctrl_pos_diff_max: p.ctrl_pos_diff_max,
        ctrl_pos_diff_max_time: p.ctrl_pos_diff_max_time,
        ctrl_pos_kp: p.ctrl_pos_kp,
        drive_id: p.drive_id,
        drive_type: p.drive_type,
        acceleration_max: p.acceleration_max,
        deceleration_max: p.deceleration_max,
    }
}

fn respond_read_parameter_set(o: Outcome) -> ReadParameterSetResponse {
    let parameter = match extension(&o) {
        Some(ExtensionValue::ParameterSet(p)) => parameter_set(p),
        _ => AxisParameterSet::default(),
    };
    ReadParameterSetResponse {
        parameter,
        ..respond(o)
    }
}

fn respond_read_axis_components(o: Outcome) -> ReadAxisComponentsResponse {
    let c = match extension(&o) {
        Some(ExtensionValue::AxisComponents(c)) => *c,
        _ => Default::default(),
    };
    ReadAxisComponentsResponse {
        encoder_ids: c.encoder_ids,
        controller_ids: c.controller_ids,
        drive_ids: c.drive_ids,
        ..respond(o)
    }
}

fn respond_convert_inc_pos_to_pos(o: Outcome) -> ConvertIncPosToPosResponse {
    let position = match &o {
        Ok(AxisReply {
            value: ReplyValue::Real(p),
            ..
        }) => *p,
        _ => 0.0,
    };
    ConvertIncPosToPosResponse {
        position,
        ..respond(o)
    }
}

fn respond_convert_pos_to_inc_pos(o: Outcome) -> ConvertPosToIncPosResponse {
    let inc_pos = match &o {
        Ok(AxisReply {
            value: ReplyValue::DWord(d),
            ..
        }) => *d,
        _ => 0,
    };
    ConvertPosToIncPosResponse {
        inc_pos,
        ..respond(o)
    }
}

fn respond_ext_enable(o: Outcome) -> ExtSetPointGenEnableResponse {
    ExtSetPointGenEnableResponse {
        enabled: o.is_ok(),
        ..respond(o)
    }
}

fn respond_ext_disable(o: Outcome) -> ExtSetPointGenDisableResponse {
    // MC_ExtSetPointGenDisable is admitted in every state: the generator is off afterwards.
    ExtSetPointGenDisableResponse {
        enabled: false,
        ..respond(o)
    }
}

// ---------------------------------------------------------------- Enable-type services

/// An Enable-type FB whose response reports `enabled` (Enable TRUE and the call accepted).
fn enable_service<Req, Resp>(
    shell: &mut NodeShell<AxisEngine>,
    name: &str,
    ty: ros2_client::ServiceTypeName,
    decode: fn(Req) -> Decoded,
    enable: fn(&Req) -> bool,
    answer: fn(Outcome, bool) -> Resp,
) -> Result<(), ShellError>
where
    Req: ros2_client::Message + Clone + Send + Sync + 'static,
    Resp: ros2_client::Message + Send + Sync + 'static,
{
    let handle = shell.handle.clone();
    shell.service::<Req, Resp, _, _>(name, ty, move |r: Req| {
        let handle = handle.clone();
        async move {
            let en = enable(&r);
            let o = match decode(r) {
                Ok((cmd, l)) => handle.call_labeled(cmd, l).await,
                Err(e) => Err(e),
            };
            let enabled = en && o.is_ok();
            answer(o, enabled)
        }
    })
}

// ---------------------------------------------------------------- persistent parameters

/// The MC_Write(Bool)ParameterPersistent initialization lists of the node's axes and the file
/// they are stored in (`persistent_parameter_file`): YAML `{axis: [[number, value], ...]}`.
/// The list mirrors the engine's (`AxisEngine::persistent_parameters`: same entry replaced,
/// appended in write order); the engine stays free of I/O.
#[derive(Debug, Default)]
pub struct Persistence {
    path: Option<PathBuf>,
    lists: Mutex<BTreeMap<String, Vec<(u32, f64)>>>,
}

/// The stored lists of a file.
pub type PersistentLists = BTreeMap<String, Vec<(u32, f64)>>;

/// Reads a persistent-parameter file; a missing file is an empty list.
pub fn read_persistent_file(path: &Path) -> Result<PersistentLists, String> {
    match std::fs::read_to_string(path) {
        Ok(text) if text.trim().is_empty() => Ok(PersistentLists::new()),
        Ok(text) => serde_yaml::from_str(&text).map_err(|e| format!("{}: {e}", path.display())),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(PersistentLists::new()),
        Err(e) => Err(format!("{}: {e}", path.display())),
    }
}

impl Persistence {
    /// Storage in `path` (None: lists are kept in memory only), starting from `lists`.
    pub fn new(path: Option<PathBuf>, lists: PersistentLists) -> Self {
        Persistence {
            path,
            lists: Mutex::new(lists),
        }
    }

    /// Records an accepted persistent write and stores the lists.
    fn record(&self, axis: &str, number: u32, value: f64) {
        let mut lists = self.lists.lock().unwrap_or_else(|e| e.into_inner());
        let list = lists.entry(axis.to_string()).or_default();
        list.retain(|(n, _)| *n != number);
        list.push((number, value));
        let Some(path) = &self.path else { return };
        let text = match serde_yaml::to_string(&*lists) {
            Ok(t) => t,
            Err(e) => {
                tracing::error!("persistent parameters: {e}");
                return;
            }
        };
        // Write a sibling and rename: a crash never leaves a half-written file.
        let tmp = path.with_extension("tmp");
        let r = std::fs::write(&tmp, text).and_then(|()| std::fs::rename(&tmp, path));
        if let Err(e) = r {
            tracing::error!("persistent parameters: writing {}: {e}", path.display());
        }
    }
}

/// A persistent write service: the command, then (accepted) the list entry is stored.
fn persistent_service<Req, Resp>(
    shell: &mut NodeShell<AxisEngine>,
    name: &str,
    ty: ros2_client::ServiceTypeName,
    decode: fn(Req) -> Decoded,
    respond: fn(Outcome) -> Resp,
    persistence: Arc<Persistence>,
) -> Result<(), ShellError>
where
    Req: ros2_client::Message + Clone + Send + Sync + 'static,
    Resp: ros2_client::Message + Send + Sync + 'static,
{
    let handle = shell.handle.clone();
    shell.service::<Req, Resp, _, _>(name, ty, move |r: Req| {
        let handle = handle.clone();
        let persistence = persistence.clone();
        async move {
            let o = match decode(r) {
                Ok((cmd, l)) => {
                    let entry = match &cmd {
                        AxisCommand::WriteParameterPersistent(c) => {
                            Some((c.axis.clone(), c.parameter_number, c.value))
                        }
                        AxisCommand::WriteBoolParameterPersistent(c) => Some((
                            c.axis.clone(),
                            c.parameter_number,
                            if c.value { 1.0 } else { 0.0 },
                        )),
                        _ => None,
                    };
                    let o = handle.call_labeled(cmd, l).await;
                    if o.is_ok() {
                        if let Some((axis, n, v)) = entry {
                            persistence.record(&axis, n, v);
                        }
                    }
                    o
                }
                Err(e) => Err(e),
            };
            respond(o)
        }
    })
}

fn decode_write_parameter_persistent(r: WriteParameterPersistentRequest) -> Decoded {
    let l = label(&r.axis, "write_parameter_persistent");
    Ok((
        AxisCommand::WriteParameterPersistent(axis_engine::WriteParameter {
            axis: r.axis,
            parameter_number: r.parameter_number,
            value: r.value,
        }),
        l,
    ))
}

fn decode_write_bool_parameter_persistent(r: WriteBoolParameterPersistentRequest) -> Decoded {
    let l = label(&r.axis, "write_bool_parameter_persistent");
    Ok((
        AxisCommand::WriteBoolParameterPersistent(axis_engine::WriteBoolParameter {
            axis: r.axis,
            parameter_number: r.parameter_number,
            value: r.value,
        }),
        l,
    ))
}

// ---------------------------------------------------------------- registration

/// Registers the services of this module (actions: `actions.rs`).
pub(crate) fn register(
    shell: &mut NodeShell<AxisEngine>,
    persistence: Arc<Persistence>,
) -> Result<(), ShellError> {
    shell.command_service(
        "phasing_absolute",
        PhasingAbsolute::service_type_name(),
        decode_phasing_absolute,
        respond::<PhasingAbsoluteResponse>,
    )?;
    shell.command_service(
        "phasing_relative",
        PhasingRelative::service_type_name(),
        decode_phasing_relative,
        respond::<PhasingRelativeResponse>,
    )?;
    shell.command_service(
        "halt_phasing",
        HaltPhasing::service_type_name(),
        decode_halt_phasing,
        respond::<HaltPhasingResponse>,
    )?;
    // A later input of a running instance: it keeps the label it was started with.
    let handle = shell.handle.clone();
    shell.service::<PhasingUpdateRequest, PhasingUpdateResponse, _, _>(
        "phasing_update",
        PhasingUpdate::service_type_name(),
        move |r| {
            let handle = handle.clone();
            async move {
                let o = match decode_phasing_update(r) {
                    Ok((cmd, _)) => handle.call(cmd).await,
                    Err(e) => Err(e),
                };
                respond::<PhasingUpdateResponse>(o)
            }
        },
    )?;
    shell.command_service(
        "gear_in_multi_master",
        GearInMultiMaster::service_type_name(),
        decode_gear_in_multi_master,
        respond::<GearInMultiMasterResponse>,
    )?;
    shell.command_service(
        "ext_set_point_gen_enable",
        ExtSetPointGenEnable::service_type_name(),
        decode_ext_set_point_gen_enable,
        respond_ext_enable,
    )?;
    shell.command_service(
        "ext_set_point_gen_disable",
        ExtSetPointGenDisable::service_type_name(),
        decode_ext_set_point_gen_disable,
        respond_ext_disable,
    )?;
    shell.command_service(
        "ext_set_point_gen_feed",
        ExtSetPointGenFeed::service_type_name(),
        decode_ext_set_point_gen_feed,
        respond::<ExtSetPointGenFeedResponse>,
    )?;
    shell.command_service(
        "read_drive_operation_mode",
        ReadDriveOperationMode::service_type_name(),
        decode_read_drive_operation_mode,
        respond_read_drive_operation_mode,
    )?;
    shell.command_service(
        "write_drive_operation_mode",
        WriteDriveOperationMode::service_type_name(),
        decode_write_drive_operation_mode,
        respond::<WriteDriveOperationModeResponse>,
    )?;
    enable_service(
        shell,
        "backlash_compensation",
        BacklashCompensation::service_type_name(),
        decode_backlash_compensation,
        |r: &BacklashCompensationRequest| r.enable,
        |o, enabled| BacklashCompensationResponse {
            enabled,
            ..respond(o)
        },
    )?;
    enable_service(
        shell,
        "position_correction_limiter",
        PositionCorrectionLimiter::service_type_name(),
        decode_position_correction_limiter,
        |r: &PositionCorrectionLimiterRequest| r.enable,
        |o, enabled| PositionCorrectionLimiterResponse {
            enabled,
            ..respond(o)
        },
    )?;
    enable_service(
        shell,
        "table_based_position_compensation",
        TableBasedPositionCompensation::service_type_name(),
        decode_table_based_position_compensation,
        |r: &TableBasedPositionCompensationRequest| r.enable,
        |o, enabled| TableBasedPositionCompensationResponse {
            enabled,
            ..respond(o)
        },
    )?;
    shell.command_service(
        "read_drive_address",
        ReadDriveAddress::service_type_name(),
        decode_read_drive_address,
        respond_read_drive_address,
    )?;
    shell.command_service(
        "select_control_loop",
        SelectControlLoop::service_type_name(),
        decode_select_control_loop,
        respond::<SelectControlLoopResponse>,
    )?;
    shell.command_service(
        "set_accept_blocked_drive_signal",
        SetAcceptBlockedDriveSignal::service_type_name(),
        decode_set_accept_blocked_drive_signal,
        respond::<SetAcceptBlockedDriveSignalResponse>,
    )?;
    shell.command_service(
        "set_encoder_scaling_factor",
        SetEncoderScalingFactor::service_type_name(),
        decode_set_encoder_scaling_factor,
        respond::<SetEncoderScalingFactorResponse>,
    )?;
    shell.command_service(
        "write_nc_io_output",
        WriteNcIoOutput::service_type_name(),
        decode_write_nc_io_output,
        respond::<WriteNcIoOutputResponse>,
    )?;
    shell.command_service(
        "convert_inc_pos_to_pos",
        ConvertIncPosToPos::service_type_name(),
        decode_convert_inc_pos_to_pos,
        respond_convert_inc_pos_to_pos,
    )?;
    shell.command_service(
        "convert_pos_to_inc_pos",
        ConvertPosToIncPos::service_type_name(),
        decode_convert_pos_to_inc_pos,
        respond_convert_pos_to_inc_pos,
    )?;
    shell.command_service(
        "read_parameter_set",
        ReadParameterSet::service_type_name(),
        decode_read_parameter_set,
        respond_read_parameter_set,
    )?;
    shell.command_service(
        "read_axis_components",
        ReadAxisComponents::service_type_name(),
        decode_read_axis_components,
        respond_read_axis_components,
    )?;
    persistent_service(
        shell,
        "write_parameter_persistent",
        WriteParameterPersistent::service_type_name(),
        decode_write_parameter_persistent,
        respond::<WriteParameterPersistentResponse>,
        persistence.clone(),
    )?;
    persistent_service(
        shell,
        "write_bool_parameter_persistent",
        WriteBoolParameterPersistent::service_type_name(),
        decode_write_bool_parameter_persistent,
        respond::<WriteBoolParameterPersistentResponse>,
        persistence.clone(),
    )?;
    // `~/write_parameter` (MC_Write(Bool)Parameter, or the persistent variants with
    // `persistent`): served here so its persistent writes are stored too.
    persistent_service(
        shell,
        "write_parameter",
        WriteParameter::service_type_name(),
        crate::services::decode_write_parameter,
        respond::<WriteParameterResponse>,
        persistence,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn enum_inputs_out_of_range_are_0x7f03() {
        let e = decode_write_drive_operation_mode(WriteDriveOperationModeRequest {
            axis: "x".into(),
            drive_operation_mode: 7,
        })
        .unwrap_err();
        assert_eq!(e.error_id, motion_core::ErrorId::ENUM_OUT_OF_RANGE);
        let e = decode_gear_in_multi_master(GearInMultiMasterRequest {
            slave: "x".into(),
            sync_mode: 3,
            ..Default::default()
        })
        .unwrap_err();
        assert_eq!(e.error_id, motion_core::ErrorId::ENUM_OUT_OF_RANGE);
        let e = decode_backlash_compensation(BacklashCompensationRequest {
            axis: "x".into(),
            disable_mode: 2,
            ..Default::default()
        })
        .unwrap_err();
        assert_eq!(e.error_id, motion_core::ErrorId::ENUM_OUT_OF_RANGE);
    }

    #[test]
    fn persistent_lists_round_trip_through_the_file() {
        let dir = std::env::temp_dir().join(format!("axis_node_persist_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("persistent.yaml");
        let _ = std::fs::remove_file(&path);
        assert!(read_persistent_file(&path).unwrap().is_empty());
        let p = Persistence::new(Some(path.clone()), PersistentLists::new());
        p.record("x", 1036, 0.5);
        p.record("x", 1046, 1.0);
        p.record("x", 1036, 0.25);
        let lists = read_persistent_file(&path).unwrap();
        assert_eq!(lists["x"], vec![(1046, 1.0), (1036, 0.25)]);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
