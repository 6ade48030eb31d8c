//! Collision-avoidance groups over ROS (collision_avoidance.md §9): per configured group, under
//! `~/ca/<group>/`, one service per administrative / read block, one action per motion block
//! and the state topic `~/ca/<group>/state`.
//!
//! - Services (answer at once, README "ROS API rules"): `add_axis`, `remove_axis`,
//!   `group_enable`, `group_disable`, `group_reset`, `ungroup_all`, `reset_diagnostics`,
//!   `group_stop` (Execute level; `stop_done` on the falling edge), `set_override` (Enable-type), `read_status`, `read_error`,
//!   `update_gap`, `activate_track`, `read_track_positions`, `register_compensation`,
//!   `transform_position`, `set_template_active`. Execute-type blocks answer with their
//!   `command_id`; their outputs follow on `~/command_status` (and `~/get_outputs`).
//! - Actions: `move_absolute`, `move_relative`, `halt`, `gear_in_pos`, `group_halt`. Feedback
//!   busy/active/position/velocity/gap_actual/ca_limited (+ start_sync/in_sync) at the state
//!   rate; result done/command_aborted/error/error_id/message/final_position; `gear_in_pos`
//!   succeeds at the first InSync (the coupling runs on). Cancel = the engine's `cancel`:
//!   MC_HaltCA with the command's deceleration and jerk (group_halt: no effect, it runs on).
//! - Screening in the shell: an axis that is not configured is 0x7F01, a non-finite number
//!   0x7F02, a McLreal `kind` above 4 0x7F03; an axis that the latest state shows in another
//!   CA group is AXIS_NOT_IN_GROUP (0x8F08). Enums go through the engine's `from_raw` and are
//!   refused with its ids (INVALID_MODE 0x4B04, INVALID_BUFFER_MODE 0x813C). Every
//!   GearInPosCA option goes to the engine (§5.5.2).

use crate::services::{label, Outcome};
use axis_engine::ca::{
    self, CaAxisStatus, CaBufferMode, CaCommand, CaDirection, CaGroupStatus, CaValue,
    GapControlMode, MasterSignalCorrection, SyncMode, SyncStrategy,
};
use axis_engine::{AxisCommand, AxisEngine, AxisReply, AxisSnapshot, ReplyValue};
use motion_core::{CmdId, CommandState, Engine, ErrorId, ExecuteOutputs, Rejection};
use motion_msgs::action::*;
use motion_msgs::msg::{CaAxisState, CaGroupState, McLreal};
use motion_msgs::srv::*;
use motion_msgs::CommandResponse;
use motion_runtime::cycle::Stamped;
use motion_runtime::shell::stamp;
use motion_runtime::{ActionBinding, CommandLabel, ControllerHandle, NodeShell, ShellError};
use ros2_client::ActionTypeName;
use std::sync::Arc;

type Decoded = Result<(AxisCommand, CommandLabel), Rejection>;

/// One group's screening context.
pub(crate) struct GroupCtx {
    group: String,
    axes: Vec<String>,
    handle: ControllerHandle<AxisEngine>,
}

impl GroupCtx {
    /// A configured axis name (0x7F01 otherwise).
    fn known(&self, axis: &str) -> Result<String, Rejection> {
        if self.axes.iter().any(|a| a == axis) {
            Ok(axis.to_string())
        } else {
            Err(Rejection::unknown_object("axis", axis))
        }
    }

    /// A configured axis that the latest state does not show in another CA group.
    fn member(&self, axis: &str) -> Result<String, Rejection> {
        let axis = self.known(axis)?;
        let snap = self.handle.snapshot();
        let other = snap
            .state
            .ca_groups
            .iter()
            .find(|g| g.name != self.group && g.axes.iter().any(|a| a.name == axis));
        match other {
            Some(g) => Err(Rejection::new(
                ca::types::errors::AXIS_NOT_IN_GROUP,
                format!(
                    "axis '{axis}' is a member of CA group '{}', not '{}'",
                    g.name, self.group
                ),
            )),
            None => Ok(axis),
        }
    }

    fn label(&self, command: &str) -> CommandLabel {
        label(&self.group, command)
    }
}

/// MC_LREAL from its ROS encoding (§9.2).
fn lreal(m: &McLreal, object: &str, field: &str) -> Result<ca::McLreal, Rejection> {
    Ok(match m.kind {
        McLreal::UNSET => ca::McLreal::Unset,
        McLreal::VALUE if m.value.is_finite() => ca::McLreal::Value(m.value),
        McLreal::VALUE => return Err(Rejection::not_finite(object, field, m.value)),
        McLreal::DEFAULT => ca::McLreal::Default,
        McLreal::MAXIMUM => ca::McLreal::Maximum,
        McLreal::IGNORE => ca::McLreal::Ignore,
        k => {
            return Err(Rejection::new(
                ErrorId::ENUM_OUT_OF_RANGE,
                format!("{object}: {field}.kind = {k} is not a McLreal kind (0..4)"),
            ))
        }
    })
}

fn finite(v: f64, object: &str, field: &str) -> Result<f64, Rejection> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(Rejection::not_finite(object, field, v))
    }
}

/// The four answer fields: `command_id` only for instances whose outputs follow.
fn answer<R: CommandResponse>(o: &Outcome) -> R {
    motion_runtime::shell::respond(o, |r: &AxisReply| if r.tracked { r.id } else { CmdId(0) })
}

/// The CA value of a reply (None when rejected or without one).
fn value(o: &Outcome) -> Option<CaValue> {
    match o {
        Ok(AxisReply {
            value: ReplyValue::Ca(v),
            ..
        }) => Some(**v),
        _ => None,
    }
}

// ------------------------------------------------------------------ decoders

fn decode_add_axis(c: &GroupCtx, r: CaAddAxisRequest) -> Decoded {
    let axis = c.known(&r.axis)?;
    Ok((
        AxisCommand::Ca(CaCommand::AddAxisToGroup {
            group: c.group.clone(),
            axis,
            ident_in_group: ca::udint_to_identingroup(r.ident_in_group),
        }),
        c.label("add_axis_to_group"),
    ))
}

fn decode_remove_axis(c: &GroupCtx, r: CaRemoveAxisRequest) -> Decoded {
    Ok((
        AxisCommand::Ca(CaCommand::RemoveAxisFromGroup {
            group: c.group.clone(),
            ident_in_group: ca::udint_to_identingroup(r.ident_in_group),
        }),
        c.label("remove_axis_from_group"),
    ))
}

/// The input-less group blocks, by service name.
fn group_block(name: &str) -> fn(String) -> CaCommand {
    match name {
        "group_enable" => |group| CaCommand::GroupEnable { group },
        "group_disable" => |group| CaCommand::GroupDisable { group },
        "group_reset" => |group| CaCommand::GroupReset { group },
        "ungroup_all" => |group| CaCommand::UngroupAllAxes { group },
        _ => |group| CaCommand::ResetDiagnostics { group },
    }
}

fn decode_group_stop(c: &GroupCtx, r: CaGroupStopRequest) -> Decoded {
    let o = "MC_GroupStop";
    Ok((
        AxisCommand::Ca(CaCommand::GroupStop {
            group: c.group.clone(),
            execute: r.execute,
            deceleration: lreal(&r.deceleration, o, "deceleration")?,
            jerk: lreal(&r.jerk, o, "jerk")?,
        }),
        c.label("group_stop"),
    ))
}

fn decode_set_override(c: &GroupCtx, r: CaSetOverrideRequest) -> Decoded {
    Ok((
        AxisCommand::Ca(CaCommand::GroupSetOverride {
            group: c.group.clone(),
            enable: r.enable,
            vel_factor: finite(r.vel_factor, "MC_GroupSetOverride", "vel_factor")?,
        }),
        c.label("group_set_override"),
    ))
}

fn decode_read_status(c: &GroupCtx, _r: CaReadStatusRequest) -> Decoded {
    Ok((
        AxisCommand::Ca(CaCommand::GroupReadStatus {
            group: c.group.clone(),
        }),
        c.label("group_read_status"),
    ))
}

fn decode_read_error(c: &GroupCtx, _r: CaReadErrorRequest) -> Decoded {
    Ok((
        AxisCommand::Ca(CaCommand::GroupReadError {
            group: c.group.clone(),
        }),
        c.label("group_read_error"),
    ))
}

fn decode_update_gap(c: &GroupCtx, r: CaUpdateGapRequest) -> Decoded {
    let axis = c.member(&r.axis)?;
    let gap = lreal(&r.gap, "update_gap", "gap")?;
    let l = label(&axis, "update_gap");
    Ok((AxisCommand::Ca(CaCommand::UpdateGap { axis, gap }), l))
}

fn decode_activate_track(c: &GroupCtx, r: CaActivateTrackRequest) -> Decoded {
    let axis = c.member(&r.axis)?;
    let l = label(&axis, "activate_track");
    Ok((
        AxisCommand::Ca(CaCommand::ActivateTrack {
            axis,
            track_id: r.track_id,
        }),
        l,
    ))
}

fn decode_read_track_positions(c: &GroupCtx, r: CaReadTrackPositionsRequest) -> Decoded {
    let axis = c.member(&r.axis)?;
    let l = label(&axis, "read_track_positions");
    Ok((AxisCommand::Ca(CaCommand::ReadTrackPositions { axis }), l))
}

fn decode_register_compensation(c: &GroupCtx, r: CaRegisterCompensationRequest) -> Decoded {
    let axis = c.member(&r.axis)?;
    let l = label(&axis, "register_compensation");
    Ok((
        AxisCommand::Ca(CaCommand::RegisterCompensation {
            axis,
            compensation_type: u32::from(r.compensation_type),
            compensation_id: r.compensation_id,
        }),
        l,
    ))
}

fn decode_transform_position(c: &GroupCtx, r: CaTransformPositionRequest) -> Decoded {
    Ok((
        AxisCommand::Ca(CaCommand::TransformPosition {
            group: c.group.clone(),
            origin_oid: r.origin_oid,
            destination_oid: r.destination_oid,
            origin_position: lreal(
                &r.origin_position,
                "MC_TransformPosition",
                "origin_position",
            )?,
        }),
        c.label("transform_position"),
    ))
}

fn decode_set_template_active(c: &GroupCtx, r: CaSetTemplateActiveRequest) -> Decoded {
    Ok((
        AxisCommand::Ca(CaCommand::SetTemplateActive {
            group: c.group.clone(),
            oid: r.oid,
            active: r.active,
        }),
        c.label("set_template_active"),
    ))
}

// ------------------------------------------------------------------ responses

fn respond_read_status(o: Outcome) -> CaReadStatusResponse {
    let r = answer::<CaReadStatusResponse>(&o);
    match value(&o) {
        Some(CaValue::Status(s)) => CaReadStatusResponse {
            group_moving: s.group_moving,
            group_homing: s.group_homing,
            group_error_stop: s.group_error_stop,
            group_not_ready: s.group_not_ready,
            group_standby: s.group_standby,
            group_stopping: s.group_stopping,
            group_disabled: s.group_disabled,
            all_axes_standing: s.all_axes_standing,
            in_position: s.in_position,
            ..r
        },
        _ => r,
    }
}

/// The falling edge answers with the group status: Done = Stopping and standing.
fn respond_group_stop(o: Outcome) -> CaGroupStopResponse {
    let r = answer::<CaGroupStopResponse>(&o);
    match value(&o) {
        Some(CaValue::Status(s)) => CaGroupStopResponse {
            stop_done: s.group_stopping && s.all_axes_standing,
            ..r
        },
        _ => r,
    }
}

fn respond_read_error(o: Outcome) -> CaReadErrorResponse {
    let r = answer::<CaReadErrorResponse>(&o);
    match value(&o) {
        Some(CaValue::GroupErrorId(e)) => CaReadErrorResponse {
            group_error_id: e,
            ..r
        },
        _ => r,
    }
}

fn respond_set_override(o: Outcome) -> CaSetOverrideResponse {
    let r = answer::<CaSetOverrideResponse>(&o);
    match value(&o) {
        Some(CaValue::Override {
            enabled,
            actual_vel_factor,
        }) => CaSetOverrideResponse {
            enabled,
            actual_vel_factor,
            ..r
        },
        _ => r,
    }
}

fn respond_read_track_positions(o: Outcome) -> CaReadTrackPositionsResponse {
    let r = answer::<CaReadTrackPositionsResponse>(&o);
    match value(&o) {
        Some(CaValue::TrackPositions {
            valid,
            track_position,
            track_id,
            part_position,
            part_id,
        }) => CaReadTrackPositionsResponse {
            valid,
            track_position,
            track_id,
            part_position,
            part_id,
            ..r
        },
        _ => r,
    }
}

fn respond_transform_position(o: Outcome) -> CaTransformPositionResponse {
    let r = answer::<CaTransformPositionResponse>(&o);
    match value(&o) {
        Some(CaValue::Position(p)) => CaTransformPositionResponse {
            destination_position: p,
            ..r
        },
        _ => r,
    }
}

/// `~/get_outputs` of a CA block instance (the engine answers `CaValue::Outputs`).
pub(crate) fn get_outputs(v: &CaValue) -> Option<GetOutputsResponse> {
    let CaValue::Outputs { outputs: s, gear } = *v else {
        return None;
    };
    Some(GetOutputsResponse {
        accepted: true,
        fb: "CA block".into(),
        done: s.done,
        busy: s.busy,
        active: s.active,
        command_aborted: s.command_aborted,
        error: s.error,
        fb_error_id: s.error_id.0,
        in_gear: gear.is_some_and(|g| g.in_sync),
        ..Default::default()
    })
}

// ------------------------------------------------------------------ registration

/// Serves `~/ca/<group>/<name>`: `decode` screens (a rejection answers at once), the engine
/// admits, tracked instances get their label for `~/command_status`, `respond` answers.
fn serve<Req, Resp>(
    shell: &mut NodeShell<AxisEngine>,
    ctx: &Arc<GroupCtx>,
    name: &str,
    ty: ros2_client::ServiceTypeName,
    decode: fn(&GroupCtx, Req) -> Decoded,
    respond: fn(Outcome) -> Resp,
) -> Result<(), ShellError>
where
    Req: ros2_client::Message + Clone + Send + Sync + 'static,
    Resp: ros2_client::Message + Send + Sync + 'static,
{
    let ctx = ctx.clone();
    let path = format!("ca/{}/{name}", ctx.group);
    shell.service::<Req, Resp, _, _>(&path, ty, move |req: Req| {
        let ctx = ctx.clone();
        async move {
            let o = match decode(&ctx, req) {
                Err(r) => Err(r),
                Ok((cmd, label)) => ctx.handle.call_labeled(cmd, label).await,
            };
            respond(o)
        }
    })
}

/// Registers every configured CA group (names from the engine's snapshot).
pub(crate) fn register(shell: &mut NodeShell<AxisEngine>) -> Result<(), ShellError> {
    register_sim(shell)?;
    let snap = shell.handle.snapshot();
    let axes: Vec<String> = snap
        .state
        .axes
        .iter()
        .map(|a| str::to_owned(&a.name))
        .collect();
    let groups: Vec<String> = snap
        .state
        .ca_groups
        .iter()
        .map(|g| g.name.clone())
        .collect();
    for group in groups {
        let ctx = Arc::new(GroupCtx {
            group: group.clone(),
            axes: axes.clone(),
            handle: shell.handle.clone(),
        });
        register_group(shell, &ctx)?;
    }
    Ok(())
}

/// Default error id of `~/sim/inject_axis_error` (§9.4, as the single-axis spec).
const DEFAULT_INJECTED_AXIS_ERROR: u32 = 0x4550;

/// The simulation helpers of collision_avoidance.md §9.4 under `~/sim/`, on the existing
/// blocks and hooks: `step` (lockstep, the runtime's `~/step`), `set_position` (MC_SetPosition,
/// refused with 0x813E while the axis is in an enabled group), `inject_axis_error` (the
/// `~/sim/inject_error` hook; `error_id` 0 = 0x4550), `set_axis_power` (MC_Power's level).
fn register_sim(shell: &mut NodeShell<AxisEngine>) -> Result<(), ShellError> {
    if shell.settings.lockstep {
        shell.step_service("sim/step")?;
    }
    shell.command_service(
        "sim/set_position",
        SetPosition::service_type_name(),
        crate::services::decode_set_position,
        crate::services::respond::<SetPositionResponse>,
    )?;
    shell.command_service(
        "sim/set_axis_power",
        Power::service_type_name(),
        crate::services::decode_power,
        crate::services::respond_power,
    )?;
    shell.command_service(
        "sim/inject_axis_error",
        InjectError::service_type_name(),
        |r: InjectErrorRequest| {
            let l = label(&r.axis, "sim/inject_axis_error");
            let error_id = match r.error_id {
                0 => DEFAULT_INJECTED_AXIS_ERROR,
                e => e,
            };
            let sim = if r.drive_fault {
                axis_engine::Sim::DriveFault {
                    axis: r.axis,
                    error_id,
                }
            } else {
                axis_engine::Sim::InjectAxisError {
                    axis: r.axis,
                    error_id,
                }
            };
            Ok((AxisCommand::Sim(sim), l))
        },
        crate::services::respond::<InjectErrorResponse>,
    )
}

fn register_group(
    shell: &mut NodeShell<AxisEngine>,
    ctx: &Arc<GroupCtx>,
) -> Result<(), ShellError> {
    let c = ctx;
    serve(
        shell,
        c,
        "add_axis",
        CaAddAxis::service_type_name(),
        decode_add_axis,
        |o| answer::<CaAddAxisResponse>(&o),
    )?;
    serve(
        shell,
        c,
        "remove_axis",
        CaRemoveAxis::service_type_name(),
        decode_remove_axis,
        |o| answer::<CaRemoveAxisResponse>(&o),
    )?;
    for (name, fb) in [
        ("group_enable", "group_enable"),
        ("group_disable", "group_disable"),
        ("group_reset", "group_reset"),
        ("ungroup_all", "ungroup_all_axes"),
        ("reset_diagnostics", "reset_diagnostics"),
    ] {
        let ctx = ctx.clone();
        let make = group_block(name);
        shell.service::<CaGroupCommandRequest, CaGroupCommandResponse, _, _>(
            &format!("ca/{}/{name}", ctx.group),
            CaGroupCommand::service_type_name(),
            move |_r| {
                let ctx = ctx.clone();
                async move {
                    let o = ctx
                        .handle
                        .call_labeled(AxisCommand::Ca(make(ctx.group.clone())), ctx.label(fb))
                        .await;
                    answer::<CaGroupCommandResponse>(&o)
                }
            },
        )?;
    }
    serve(
        shell,
        c,
        "group_stop",
        CaGroupStop::service_type_name(),
        decode_group_stop,
        respond_group_stop,
    )?;
    serve(
        shell,
        c,
        "set_override",
        CaSetOverride::service_type_name(),
        decode_set_override,
        respond_set_override,
    )?;
    serve(
        shell,
        c,
        "read_status",
        CaReadStatus::service_type_name(),
        decode_read_status,
        respond_read_status,
    )?;
    serve(
        shell,
        c,
        "read_error",
        CaReadError::service_type_name(),
        decode_read_error,
        respond_read_error,
    )?;
    serve(
        shell,
        c,
        "update_gap",
        CaUpdateGap::service_type_name(),
        decode_update_gap,
        |o| answer::<CaUpdateGapResponse>(&o),
    )?;
    serve(
        shell,
        c,
        "activate_track",
        CaActivateTrack::service_type_name(),
        decode_activate_track,
        |o| answer::<CaActivateTrackResponse>(&o),
    )?;
    serve(
        shell,
        c,
        "read_track_positions",
        CaReadTrackPositions::service_type_name(),
        decode_read_track_positions,
        respond_read_track_positions,
    )?;
    serve(
        shell,
        c,
        "register_compensation",
        CaRegisterCompensation::service_type_name(),
        decode_register_compensation,
        |o| answer::<CaRegisterCompensationResponse>(&o),
    )?;
    serve(
        shell,
        c,
        "transform_position",
        CaTransformPosition::service_type_name(),
        decode_transform_position,
        respond_transform_position,
    )?;
    serve(
        shell,
        c,
        "set_template_active",
        CaSetTemplateActive::service_type_name(),
        decode_set_template_active,
        |o| answer::<CaSetTemplateActiveResponse>(&o),
    )?;
    let base = format!("ca/{}", ctx.group);
    shell.action(
        &format!("{base}/move_absolute"),
        MoveAbsoluteCaAction(ctx.clone()),
    )?;
    shell.action(
        &format!("{base}/move_relative"),
        MoveRelativeCaAction(ctx.clone()),
    )?;
    shell.action(&format!("{base}/halt"), HaltCaAction(ctx.clone()))?;
    shell.action(
        &format!("{base}/gear_in_pos"),
        GearInPosCaAction(ctx.clone()),
    )?;
    shell.action(&format!("{base}/group_halt"), GroupHaltAction(ctx.clone()))?;
    let group = ctx.group.clone();
    shell.state_publisher(
        &format!("~/{base}/state"),
        CaGroupState::type_name(),
        move |s| group_state(s, &group),
    )
}

// ------------------------------------------------------------------ state topic

fn axis_state(a: &CaAxisStatus) -> CaAxisState {
    CaAxisState {
        name: a.name.clone(),
        ident_in_group: a.ident_in_group,
        predecessor: a.predecessor.clone().unwrap_or_default(),
        position: a.position,
        modulo_position: a.modulo_position,
        velocity: a.velocity,
        acceleration: a.acceleration,
        active_command_id: a.active_command_id.map_or(0, |c| c.0),
        command_kind: a.command_kind.raw() as u8,
        gap_target: a.gap_target,
        gap_actual: a.gap_actual,
        ca_limited: a.ca_limited,
        gap_violation: a.gap_violation,
        min_gap_margin: a.min_gap_margin,
        track_id: a.track_id,
        compensation_id: a.compensation_id,
        start_sync: a.start_sync,
        in_sync: a.in_sync,
    }
}

/// `~/ca/<group>/state` from a snapshot.
pub(crate) fn group_state(s: &Stamped<AxisSnapshot>, group: &str) -> CaGroupState {
    let Some(g) = s.state.ca_groups.iter().find(|g| g.name == group) else {
        return CaGroupState {
            stamp: stamp(s),
            cycle: s.cycle,
            name: group.to_string(),
            ..Default::default()
        };
    };
    CaGroupState {
        stamp: stamp(s),
        cycle: s.cycle,
        name: g.name.clone(),
        state: g.state as u32,
        is_enable_requested: g.is_enable_requested,
        all_axes_standing: g.all_axes_standing,
        in_position: g.in_position,
        group_error_id: g.group_error_id,
        group_axes_count: g.group_axes_count,
        act_override_factor: g.act_override_factor,
        gap_budget_exceeded: g.gap_budget_exceeded,
        axes: g.axes.iter().map(axis_state).collect(),
    }
}

// ------------------------------------------------------------------ actions

/// Kinematics of an axis for feedback and results: (position, velocity, gap_actual,
/// ca_limited, start_sync, in_sync, active command); outside the group: its single-axis set
/// values.
type Kin = (f64, f64, f64, bool, bool, bool, Option<CmdId>);

fn kin(snap: &Stamped<AxisSnapshot>, group: &str, axis: &str) -> Kin {
    let member = snap
        .state
        .ca_groups
        .iter()
        .filter(|g: &&CaGroupStatus| g.name == group)
        .flat_map(|g| g.axes.iter())
        .find(|a| a.name == axis);
    match member {
        Some(a) => (
            a.position,
            a.velocity,
            a.gap_actual,
            a.ca_limited,
            a.start_sync,
            a.in_sync,
            a.active_command_id,
        ),
        None => snap
            .state
            .axis(axis)
            .map_or((0.0, 0.0, f64::NAN, false, false, false, None), |a| {
                (a.set_pos, a.set_velo, f64::NAN, false, false, false, None)
            }),
    }
}

fn end_message(o: &ExecuteOutputs, rejection: Option<&Rejection>) -> String {
    match rejection {
        Some(r) => r.message.clone(),
        None if o.error => <AxisEngine as Engine>::error_text(o.error_id),
        None => String::new(),
    }
}

/// One CA motion action: `$decode` builds the command from the goal, `$axis` names the
/// goal's axis field; feedback and result fields are common (+ `$fb_extra` for gear).
macro_rules! ca_action {
    ($binding:ident, $action:ident, $goal:ident, $result:ident, $feedback:ident, $axis:ident,
     $decode:expr, $reached:expr, |$k:ident| { $($fb_extra:tt)* }) => {
        struct $binding(Arc<GroupCtx>);

        impl ActionBinding<AxisEngine> for $binding {
            type Goal = $goal;
            type Result = $result;
            type Feedback = $feedback;

            fn action_type_name() -> ActionTypeName {
                $action::action_type_name()
            }

            fn command(&self, g: &$goal) -> Decoded {
                #[allow(clippy::redundant_closure_call)]
                ($decode)(&self.0, g)
            }

            fn reached_query(&self, id: CmdId) -> Option<AxisCommand> {
                $reached.then_some(AxisCommand::ReadFbOutputs { id })
            }

            fn reached(&self, reply: &AxisReply) -> bool {
                $reached
                    && matches!(
                        &reply.value,
                        ReplyValue::Ca(v) if matches!(**v, CaValue::Outputs { gear: Some(g), .. } if g.in_sync)
                    )
            }

            fn feedback(&self, g: &$goal, snap: &Stamped<AxisSnapshot>, state: CommandState) -> $feedback {
                self.feedback_of(g, CmdId(0), snap, state)
            }

            fn feedback_of(
                &self,
                g: &$goal,
                id: CmdId,
                snap: &Stamped<AxisSnapshot>,
                state: CommandState,
            ) -> $feedback {
                let $k = kin(snap, &self.0.group, &g.$axis);
                let o = ExecuteOutputs::from(state);
                $feedback {
                    busy: o.busy,
                    // Active = the block controls the axis (the engine reports a command
                    // admitted as Active without an event; the state shows its owner).
                    active: o.active || (o.busy && $k.6 == Some(id)),
                    command_id: id.0,
                    position: $k.0,
                    velocity: $k.1,
                    gap_actual: $k.2,
                    ca_limited: $k.3,
                    $($fb_extra)*
                }
            }

            fn result(
                &self,
                g: &$goal,
                snap: &Stamped<AxisSnapshot>,
                end: CommandState,
                rejection: Option<&Rejection>,
            ) -> $result {
                self.result_of(g, None, snap, end, rejection)
            }

            fn result_of(
                &self,
                g: &$goal,
                id: Option<CmdId>,
                snap: &Stamped<AxisSnapshot>,
                end: CommandState,
                rejection: Option<&Rejection>,
            ) -> $result {
                let o = ExecuteOutputs::from(end);
                $result {
                    done: o.done,
                    command_aborted: o.command_aborted,
                    error: o.error,
                    error_id: o.error_id.0,
                    message: end_message(&o, rejection),
                    command_id: id.map_or(0, |c| c.0),
                    final_position: kin(snap, &self.0.group, &g.$axis).0,
                }
            }
        }
    };
}

fn decode_move_absolute(c: &GroupCtx, g: &MoveAbsoluteCaGoal) -> Decoded {
    let axis = c.member(&g.axis)?;
    let o = "MC_MoveAbsoluteCA";
    let cmd = ca::MoveAbsoluteCa {
        axis: axis.clone(),
        continuous_update: g.continuous_update,
        position: lreal(&g.position, o, "position")?,
        velocity: lreal(&g.velocity, o, "velocity")?,
        acceleration: lreal(&g.acceleration, o, "acceleration")?,
        deceleration: lreal(&g.deceleration, o, "deceleration")?,
        jerk: lreal(&g.jerk, o, "jerk")?,
        gap: lreal(&g.gap, o, "gap")?,
        buffer_mode: CaBufferMode::from_raw(u32::from(g.buffer_mode))?,
        direction: CaDirection::from_raw(u32::from(g.direction))?,
        gap_control_mode: GapControlMode::from_raw(g.gap_control_mode)?,
        additional_turns: g.additional_turns,
        position_reference_system: g.position_reference_system,
        dynamics_reference_system: g.dynamics_reference_system,
    };
    Ok((
        AxisCommand::Ca(CaCommand::MoveAbsolute(cmd)),
        label(&axis, "move_absolute_ca"),
    ))
}

fn decode_move_relative(c: &GroupCtx, g: &MoveRelativeCaGoal) -> Decoded {
    let axis = c.member(&g.axis)?;
    let o = "MC_MoveRelativeCA";
    let cmd = ca::MoveRelativeCa {
        axis: axis.clone(),
        continuous_update: g.continuous_update,
        distance: lreal(&g.distance, o, "distance")?,
        velocity: lreal(&g.velocity, o, "velocity")?,
        acceleration: lreal(&g.acceleration, o, "acceleration")?,
        deceleration: lreal(&g.deceleration, o, "deceleration")?,
        jerk: lreal(&g.jerk, o, "jerk")?,
        gap: lreal(&g.gap, o, "gap")?,
        buffer_mode: CaBufferMode::from_raw(u32::from(g.buffer_mode))?,
        gap_control_mode: GapControlMode::from_raw(g.gap_control_mode)?,
        position_reference_system: g.position_reference_system,
        dynamics_reference_system: g.dynamics_reference_system,
    };
    Ok((
        AxisCommand::Ca(CaCommand::MoveRelative(cmd)),
        label(&axis, "move_relative_ca"),
    ))
}

fn decode_halt(c: &GroupCtx, g: &HaltCaGoal) -> Decoded {
    let axis = c.member(&g.axis)?;
    let o = "MC_HaltCA";
    let cmd = ca::HaltCa {
        axis: axis.clone(),
        deceleration: lreal(&g.deceleration, o, "deceleration")?,
        jerk: lreal(&g.jerk, o, "jerk")?,
        gap: lreal(&g.gap, o, "gap")?,
        gap_control_mode: GapControlMode::from_raw(g.gap_control_mode)?,
        dynamics_reference_system: g.dynamics_reference_system,
    };
    Ok((
        AxisCommand::Ca(CaCommand::Halt(cmd)),
        label(&axis, "halt_ca"),
    ))
}

fn decode_gear_in_pos(c: &GroupCtx, g: &GearInPosCaGoal) -> Decoded {
    let slave = c.member(&g.slave)?;
    let master = c.known(&g.master)?;
    let o = "MC_GearInPosCA";
    let cmd = ca::GearInPosCa {
        master,
        slave: slave.clone(),
        continuous_update: g.continuous_update,
        ratio_numerator: lreal(&g.ratio_numerator, o, "ratio_numerator")?,
        ratio_denumerator: g.ratio_denumerator,
        master_sync_position: lreal(&g.master_sync_position, o, "master_sync_position")?,
        slave_sync_position: lreal(&g.slave_sync_position, o, "slave_sync_position")?,
        sync_strategy: match g.sync_strategy {
            0 => SyncStrategy::Late,
            s => SyncStrategy::from_raw(u32::from(s))?,
        },
        sync_mode: SyncMode::from_raw(u32::from(g.sync_mode))?,
        master_start_distance: lreal(&g.master_start_distance, o, "master_start_distance")?,
        velocity: lreal(&g.velocity, o, "velocity")?,
        acceleration: lreal(&g.acceleration, o, "acceleration")?,
        deceleration: lreal(&g.deceleration, o, "deceleration")?,
        jerk: lreal(&g.jerk, o, "jerk")?,
        gap: lreal(&g.gap, o, "gap")?,
        buffer_mode: CaBufferMode::from_raw(u32::from(g.buffer_mode))?,
        gap_control_mode: GapControlMode::from_raw(g.gap_control_mode)?,
        forbid_master_velocity_undershoot: g.forbid_master_velocity_undershoot,
        forbid_master_velocity_overshoot: g.forbid_master_velocity_overshoot,
        after_sync_velocity: lreal(&g.after_sync_velocity, o, "after_sync_velocity")?,
        after_sync_acceleration: lreal(&g.after_sync_acceleration, o, "after_sync_acceleration")?,
        after_sync_deceleration: lreal(&g.after_sync_deceleration, o, "after_sync_deceleration")?,
        after_sync_jerk: lreal(&g.after_sync_jerk, o, "after_sync_jerk")?,
        override_slave_dynamic_restrictions: g.override_slave_dynamic_restrictions,
        forbid_direction_reversal: g.forbid_direction_reversal,
        minimal_slave_position: lreal(&g.minimal_slave_position, o, "minimal_slave_position")?,
        slave_sync_position_reference_system: g.slave_sync_position_reference_system,
        dynamics_reference_system: g.dynamics_reference_system,
        master_signal_correction: MasterSignalCorrection::from_raw(u32::from(
            g.master_signal_correction,
        ))?,
    };
    Ok((
        AxisCommand::Ca(CaCommand::GearInPos(cmd)),
        label(&slave, "gear_in_pos_ca"),
    ))
}

ca_action!(
    MoveAbsoluteCaAction,
    MoveAbsoluteCa,
    MoveAbsoluteCaGoal,
    MoveAbsoluteCaResult,
    MoveAbsoluteCaFeedback,
    axis,
    decode_move_absolute,
    false,
    |k| {}
);

ca_action!(
    MoveRelativeCaAction,
    MoveRelativeCa,
    MoveRelativeCaGoal,
    MoveRelativeCaResult,
    MoveRelativeCaFeedback,
    axis,
    decode_move_relative,
    false,
    |k| {}
);

ca_action!(
    HaltCaAction,
    HaltCa,
    HaltCaGoal,
    HaltCaResult,
    HaltCaFeedback,
    axis,
    decode_halt,
    false,
    |k| {}
);

ca_action!(
    GearInPosCaAction,
    GearInPosCa,
    GearInPosCaGoal,
    GearInPosCaResult,
    GearInPosCaFeedback,
    slave,
    decode_gear_in_pos,
    true,
    |k| { start_sync: k.4, in_sync: k.5, }
);

/// MC_GroupHalt as an action: Done when every axis of the group stands.
struct GroupHaltAction(Arc<GroupCtx>);

impl ActionBinding<AxisEngine> for GroupHaltAction {
    type Goal = CaGroupHaltGoal;
    type Result = CaGroupHaltResult;
    type Feedback = CaGroupHaltFeedback;

    fn action_type_name() -> ActionTypeName {
        CaGroupHalt::action_type_name()
    }

    fn command(&self, g: &CaGroupHaltGoal) -> Decoded {
        let o = "MC_GroupHalt";
        Ok((
            AxisCommand::Ca(CaCommand::GroupHalt {
                group: self.0.group.clone(),
                deceleration: lreal(&g.deceleration, o, "deceleration")?,
                jerk: lreal(&g.jerk, o, "jerk")?,
            }),
            self.0.label("group_halt"),
        ))
    }

    fn feedback(
        &self,
        g: &CaGroupHaltGoal,
        snap: &Stamped<AxisSnapshot>,
        state: CommandState,
    ) -> CaGroupHaltFeedback {
        self.feedback_of(g, CmdId(0), snap, state)
    }

    fn feedback_of(
        &self,
        _g: &CaGroupHaltGoal,
        id: CmdId,
        _snap: &Stamped<AxisSnapshot>,
        state: CommandState,
    ) -> CaGroupHaltFeedback {
        let o = ExecuteOutputs::from(state);
        CaGroupHaltFeedback {
            busy: o.busy,
            active: o.active,
            command_id: id.0,
        }
    }

    fn result(
        &self,
        g: &CaGroupHaltGoal,
        snap: &Stamped<AxisSnapshot>,
        end: CommandState,
        rejection: Option<&Rejection>,
    ) -> CaGroupHaltResult {
        self.result_of(g, None, snap, end, rejection)
    }

    fn result_of(
        &self,
        _g: &CaGroupHaltGoal,
        id: Option<CmdId>,
        _snap: &Stamped<AxisSnapshot>,
        end: CommandState,
        rejection: Option<&Rejection>,
    ) -> CaGroupHaltResult {
        let o = ExecuteOutputs::from(end);
        CaGroupHaltResult {
            done: o.done,
            command_aborted: o.command_aborted,
            error: o.error,
            error_id: o.error_id.0,
            message: end_message(&o, rejection),
            command_id: id.map_or(0, |c| c.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// McLreal's ROS encoding: kinds 0..4, a non-finite VALUE 0x7F02, a bad kind 0x7F03.
    #[test]
    fn mc_lreal_encoding() {
        let m = |kind, value| McLreal { kind, value };
        let ok = |k, v| lreal(&m(k, v), "o", "f").unwrap();
        assert_eq!(ok(McLreal::UNSET, 5.0), ca::McLreal::Unset);
        assert_eq!(ok(McLreal::VALUE, 5.0), ca::McLreal::Value(5.0));
        assert_eq!(ok(McLreal::DEFAULT, f64::NAN), ca::McLreal::Default);
        assert_eq!(ok(McLreal::MAXIMUM, 0.0), ca::McLreal::Maximum);
        assert_eq!(ok(McLreal::IGNORE, 0.0), ca::McLreal::Ignore);
        assert_eq!(McLreal::default().kind, McLreal::UNSET, "default = preset");
        let e = lreal(&m(McLreal::VALUE, f64::INFINITY), "o", "f").unwrap_err();
        assert_eq!(e.error_id, ErrorId::NOT_FINITE);
        let e = lreal(&m(5, 1.0), "o", "f.x").unwrap_err();
        assert_eq!(e.error_id, ErrorId::ENUM_OUT_OF_RANGE);
        assert!(e.message.contains("f.x.kind = 5"), "{}", e.message);
    }

    /// `ca_groups` in a launch-config entry: errors name the key and the problem.
    #[test]
    fn ca_groups_config_errors_name_key_and_problem() {
        let check = |text: &str| {
            let v: serde_yaml::Value = serde_yaml::from_str(text).unwrap();
            crate::check(
                &motion_runtime::CommonConfig::default(),
                v,
                "f.yaml: nodes[0] (axis_node)",
            )
        };
        check("axes: {x: {}}\nca_groups: {ring: {rail_length: 1200.0}, other: ~}\n")
            .expect("valid");
        for (text, needles) in [
            (
                "axes: {x: {}}\nca_groups: {ring: {rail_lenght: 5}}\n",
                &[
                    "nodes[0] (axis_node).ca_groups.ring",
                    "unknown field `rail_lenght`",
                ][..],
            ),
            (
                "axes: {x: {}}\nca_groups: {ring: {rail_length: -5}}\n",
                &["ca_groups.ring", "rail_length = -5 is out of range"][..],
            ),
            (
                "axes: {x: {}}\nca_groups: {ring: {default_gap: 1500, rail_length: 1200}}\n",
                &["ca_groups.ring", "default_gap"][..],
            ),
            (
                "axes: {x: {}}\nca_groups: [ring]\n",
                &["ca_groups", "expected a mapping"][..],
            ),
        ] {
            let e = check(text).expect_err(text).to_string();
            for n in needles {
                assert!(e.contains(n), "{text:?}: '{n}' not in {e}");
            }
        }
    }
}
