//! Tracks over ROS (xplanar.md §1.6, §3.2 on-track methods, §3.3, §5.4–§5.9, §9):
//! - services `~/mover_join_track`, `~/mover_leave_track`, `~/mover_move_on_track`,
//!   `~/mover_adopt_track_orientation`, `~/mover_gear_in_pos_on_track_with_master_mover`,
//!   `~/mover_gear_in_pos_on_track` (motion responses: warning and objectInfo),
//!   `~/axis_power|move_absolute|halt` (virtual master axes, §5.8.4) and one per
//!   MC_PlanarTrack method `~/track_<method>` (queries answer their value), and
//!   `~/track_set_init_parameters` (the §1.6 init parameters while the track is Disabled);
//! - actions `~/mover_join_track`, `~/mover_leave_track`, `~/mover_move_on_track` (feedback:
//!   busy/active, pose and the track position) and
//!   `~/mover_gear_in_pos_on_track_with_master_mover` (feedback with `in_sync`; never
//!   succeeds on its own: the coupling runs until cancel = the mover's Halt, or an error);
//! - the track part of `~/state` ([`track_state`], [`axis_state`], [`set_on_track`]) and of
//!   `~/markers` ([`track_markers`]: one LINE_STRIP per track, sampled with GetPositionAt by
//!   [`spawn_sampler`] when a track's geometry or its part's position changes).

use crate::actions::{object_info as end_object_info, pose};
use crate::services::{
    constraint, direction, enum_error, label, object_info, position_response, respond,
    respond_motion, Decoded, Outcome,
};
use motion_core::{CommandState, Engine, ExecuteOutputs, Rejection};
use motion_msgs::action::{
    self as act, MoverGearInPosOnTrackWithMasterMoverFeedback,
    MoverGearInPosOnTrackWithMasterMoverGoal, MoverGearInPosOnTrackWithMasterMoverResult,
    MoverJoinTrackFeedback, MoverJoinTrackGoal, MoverJoinTrackResult, MoverLeaveTrackFeedback,
    MoverLeaveTrackGoal, MoverLeaveTrackResult, MoverMoveOnTrackFeedback, MoverMoveOnTrackGoal,
    MoverMoveOnTrackResult,
};
use motion_msgs::deps::geometry_msgs::msg::{Point, Pose, Quaternion, Vector3};
use motion_msgs::deps::std_msgs::msg::{ColorRGBA, Header};
use motion_msgs::deps::visualization_msgs::msg::Marker;
use motion_msgs::msg::{PlanarAxisState, PlanarMoverState, PlanarTrackState};
use motion_msgs::srv::*;
use motion_runtime::cycle::Stamped;
use motion_runtime::{ActionBinding, CommandLabel, NodeShell, ShellError};
use planar_engine::{
    AdoptTrackOrientationOptions, CollisionRangeMode, GearInPosOnTrackOptions,
    GearInPosOnTrackWithMasterMoverOptions, MoveOnTrackOptions, MoveToPositionOptions,
    MoverSnapshot, PlanarCommand, PlanarEngine, PlanarReply, PlanarSnapshot, PositionXYC,
    ReplyValue, SyncDirections, TrackLinkAdvancedOptions, TrackOperationMode, TrackSnapshot,
    VirtualAxisSnapshot,
};
use ros2_client::ActionTypeName;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

// --- decoding ----------------------------------------------------------------------------------

/// `MC_SYNC_DIRECTIONS` (xplanar.md §4.1) from its number.
pub(crate) fn sync_directions(mover: &str, raw: u8) -> Result<SyncDirections, Rejection> {
    match raw {
        1 => Ok(SyncDirections::Positive),
        2 => Ok(SyncDirections::Negative),
        3 => Ok(SyncDirections::Both),
        v => Err(enum_error(
            mover,
            "allowed_slave_sync_directions",
            v.into(),
            "1 positive, 2 negative, 3 both",
        )),
    }
}

pub(crate) fn join_track_req(r: &MoverJoinTrackRequest) -> Decoded {
    Ok((
        PlanarCommand::JoinTrack {
            mover: r.mover.clone(),
            track: r.track.clone(),
            constraint: constraint(r.velocity, r.acceleration, r.deceleration, r.jerk),
            options: MoveToPositionOptions {
                use_orientation: r.use_orientation,
            },
        },
        label(&r.mover, "join_track"),
    ))
}
/// The goal decodes through the service request's path.
pub(crate) fn join_track_goal(g: &MoverJoinTrackGoal) -> Decoded {
    join_track_req(&g.into())
}
pub(crate) fn leave_track_req(r: &MoverLeaveTrackRequest) -> Decoded {
    Ok((
        PlanarCommand::LeaveTrack {
            mover: r.mover.clone(),
            target_position: PositionXYC::with_ref(r.x, r.y, r.c, r.reference_id),
            constraint: constraint(r.velocity, r.acceleration, r.deceleration, r.jerk),
            options: MoveToPositionOptions {
                use_orientation: r.use_orientation,
            },
        },
        label(&r.mover, "leave_track"),
    ))
}
/// The goal decodes through the service request's path.
pub(crate) fn leave_track_goal(g: &MoverLeaveTrackGoal) -> Decoded {
    leave_track_req(&g.into())
}
pub(crate) fn move_on_track_req(r: &MoverMoveOnTrackRequest) -> Decoded {
    Ok((
        PlanarCommand::MoveOnTrack {
            mover: r.mover.clone(),
            track: r.track.clone(),
            target_position: r.target_position,
            constraint: constraint(r.velocity, r.acceleration, r.deceleration, r.jerk),
            options: MoveOnTrackOptions {
                gap: r.gap,
                direction: direction(&r.mover, r.direction)?,
                additional_turns: r.additional_turns,
                modulo_tolerance: r.modulo_tolerance,
            },
        },
        label(&r.mover, "move_on_track"),
    ))
}
/// The goal decodes through the service request's path.
pub(crate) fn move_on_track_goal(g: &MoverMoveOnTrackGoal) -> Decoded {
    move_on_track_req(&g.into())
}
pub(crate) fn gear_master_req(r: &MoverGearInPosOnTrackWithMasterMoverRequest) -> Decoded {
    Ok((
        PlanarCommand::GearInPosOnTrackWithMasterMover {
            mover: r.mover.clone(),
            master_mover: r.master_mover.clone(),
            track_trail: r.track_trail.clone(),
            master_sync_position: r.master_sync_position,
            master_sync_position_track: r.master_sync_position_track.clone(),
            slave_sync_position: r.slave_sync_position,
            slave_sync_position_track: r.slave_sync_position_track.clone(),
            constraint: constraint(r.velocity, r.acceleration, r.deceleration, r.jerk),
            options: GearInPosOnTrackWithMasterMoverOptions {
                gap: r.gap,
                in_sync_tolerance_distance: r.in_sync_tolerance_distance,
                direction_slave_sync_position: direction(
                    &r.mover,
                    r.direction_slave_sync_position,
                )?,
                modulo_tolerance_slave_sync_position: r.modulo_tolerance_slave_sync_position,
                direction_master_sync_position: direction(
                    &r.mover,
                    r.direction_master_sync_position,
                )?,
                modulo_tolerance_master_sync_position: r.modulo_tolerance_master_sync_position,
                allowed_slave_sync_directions: sync_directions(
                    &r.mover,
                    r.allowed_slave_sync_directions,
                )?,
                follow_mover: r.follow_mover,
            },
        },
        label(&r.mover, "gear_in_pos_on_track_with_master_mover"),
    ))
}
/// The goal decodes through the service request's path.
pub(crate) fn gear_master_goal(g: &MoverGearInPosOnTrackWithMasterMoverGoal) -> Decoded {
    gear_master_req(&g.into())
}

pub(crate) fn adopt_req(r: &MoverAdoptTrackOrientationRequest) -> Decoded {
    Ok((
        PlanarCommand::AdoptTrackOrientation {
            mover: r.mover.clone(),
            constraint: constraint(r.velocity, r.acceleration, r.deceleration, r.jerk),
            options: AdoptTrackOrientationOptions {
                additional_turns: r.additional_turns,
                direction: direction(&r.mover, r.direction)?,
            },
        },
        label(&r.mover, "adopt_track_orientation"),
    ))
}

pub(crate) fn gear_axis_req(r: &MoverGearInPosOnTrackRequest) -> Decoded {
    Ok((
        PlanarCommand::GearInPosOnTrack {
            mover: r.mover.clone(),
            master_axis: r.master_axis.clone(),
            track_trail: r.track_trail.clone(),
            master_sync_position: r.master_sync_position,
            slave_sync_position: r.slave_sync_position,
            slave_sync_position_track: r.slave_sync_position_track.clone(),
            constraint: constraint(r.velocity, r.acceleration, r.deceleration, r.jerk),
            options: GearInPosOnTrackOptions {
                gap: r.gap,
                in_sync_tolerance_distance: r.in_sync_tolerance_distance,
                direction_slave_sync_position: direction(
                    &r.mover,
                    r.direction_slave_sync_position,
                )?,
                modulo_tolerance_slave_sync_position: r.modulo_tolerance_slave_sync_position,
                allowed_slave_sync_directions: sync_directions(
                    &r.mover,
                    r.allowed_slave_sync_directions,
                )?,
            },
        },
        label(&r.mover, "gear_in_pos_on_track"),
    ))
}

crate::services::motion_response!(
    MoverJoinTrackResponse,
    MoverLeaveTrackResponse,
    MoverMoveOnTrackResponse,
    MoverAdoptTrackOrientationResponse,
    MoverGearInPosOnTrackWithMasterMoverResponse,
    MoverGearInPosOnTrackResponse,
);

fn track_cmd(track: &str, command: &str, cmd: PlanarCommand) -> Decoded {
    Ok((cmd, label(track, command)))
}

fn scalar(o: &Outcome) -> Option<f64> {
    match o {
        Ok(PlanarReply {
            value: ReplyValue::Scalar(v),
            ..
        }) => Some(*v),
        _ => None,
    }
}

fn advanced(
    this_track_part_position_index: u32,
    other_track_part_position_index: u32,
    link_only_in_specified_part_positions: bool,
) -> TrackLinkAdvancedOptions {
    TrackLinkAdvancedOptions {
        this_track_part_position_index,
        other_track_part_position_index,
        link_only_in_specified_part_positions,
    }
}

pub(crate) fn set_init_parameters_req(r: &TrackSetInitParametersRequest) -> Decoded {
    let collision_range_mode = match r.collision_range_mode {
        TrackSetInitParametersRequest::COLLISION_RANGE_AUTOMATIC => CollisionRangeMode::Automatic,
        TrackSetInitParametersRequest::COLLISION_RANGE_MANUAL => CollisionRangeMode::Manual,
        v => {
            return Err(enum_error(
                &r.track,
                "collision_range_mode",
                v as u32,
                "0 Automatic, 1 Manual",
            ))
        }
    };
    track_cmd(
        &r.track,
        "set_init_parameters",
        PlanarCommand::TrackSetInitParameters {
            track: r.track.clone(),
            max_mover_width: r.max_mover_width,
            max_mover_height: r.max_mover_height,
            check_static_collision: r.check_static_collision,
            collision_range_mode,
            collision_range_start: r.collision_range_start,
            collision_range_end: r.collision_range_end,
        },
    )
}

pub(crate) fn append_line_req(r: &TrackAppendLineRequest) -> Decoded {
    let p = |x, y| PositionXYC::with_ref(x, y, 0.0, r.reference_id);
    track_cmd(
        &r.track,
        "append_line",
        PlanarCommand::TrackAppendLine {
            track: r.track.clone(),
            start: p(r.start_x, r.start_y),
            end: p(r.end_x, r.end_y),
        },
    )
}

pub(crate) fn append_circle_req(r: &TrackAppendCircleRequest) -> Decoded {
    let p = |x, y| PositionXYC::with_ref(x, y, 0.0, r.reference_id);
    track_cmd(
        &r.track,
        "append_circle",
        PlanarCommand::TrackAppendCircle {
            track: r.track.clone(),
            start: p(r.start_x, r.start_y),
            end: p(r.end_x, r.end_y),
            center: p(r.center_x, r.center_y),
            clockwise: r.clockwise,
        },
    )
}

/// Registers the track services (mover on-track methods, virtual axes, MC_PlanarTrack).
pub(crate) fn register_services(shell: &mut NodeShell<PlanarEngine>) -> Result<(), ShellError> {
    // MC_PlanarMover on tracks (§3.2)
    shell.command_service(
        "mover_join_track",
        MoverJoinTrack::service_type_name(),
        |r: MoverJoinTrackRequest| join_track_req(&r),
        respond_motion::<MoverJoinTrackResponse>,
    )?;
    shell.command_service(
        "mover_leave_track",
        MoverLeaveTrack::service_type_name(),
        |r: MoverLeaveTrackRequest| leave_track_req(&r),
        respond_motion::<MoverLeaveTrackResponse>,
    )?;
    shell.command_service(
        "mover_move_on_track",
        MoverMoveOnTrack::service_type_name(),
        |r: MoverMoveOnTrackRequest| move_on_track_req(&r),
        respond_motion::<MoverMoveOnTrackResponse>,
    )?;
    shell.command_service(
        "mover_adopt_track_orientation",
        MoverAdoptTrackOrientation::service_type_name(),
        |r: MoverAdoptTrackOrientationRequest| adopt_req(&r),
        respond_motion::<MoverAdoptTrackOrientationResponse>,
    )?;
    shell.command_service(
        "mover_gear_in_pos_on_track_with_master_mover",
        MoverGearInPosOnTrackWithMasterMover::service_type_name(),
        |r: MoverGearInPosOnTrackWithMasterMoverRequest| gear_master_req(&r),
        respond_motion::<MoverGearInPosOnTrackWithMasterMoverResponse>,
    )?;
    shell.command_service(
        "mover_gear_in_pos_on_track",
        MoverGearInPosOnTrack::service_type_name(),
        |r: MoverGearInPosOnTrackRequest| gear_axis_req(&r),
        respond_motion::<MoverGearInPosOnTrackResponse>,
    )?;

    // Virtual master axes (§5.8.4)
    shell.command_service(
        "axis_power",
        AxisPower::service_type_name(),
        |r: AxisPowerRequest| {
            Ok((
                PlanarCommand::AxisPower {
                    axis: r.axis.clone(),
                    enable: r.enable,
                },
                label(&r.axis, "power"),
            ))
        },
        respond::<AxisPowerResponse>,
    )?;
    shell.command_service(
        "axis_move_absolute",
        AxisMoveAbsolute::service_type_name(),
        |r: AxisMoveAbsoluteRequest| {
            Ok((
                PlanarCommand::AxisMoveAbsolute {
                    axis: r.axis.clone(),
                    position: r.position,
                    velocity: r.velocity,
                    acceleration: r.acceleration,
                    deceleration: r.deceleration,
                    jerk: r.jerk,
                },
                label(&r.axis, "move_absolute"),
            ))
        },
        respond::<AxisMoveAbsoluteResponse>,
    )?;
    shell.command_service(
        "axis_halt",
        AxisHalt::service_type_name(),
        |r: AxisHaltRequest| {
            Ok((
                PlanarCommand::AxisHalt {
                    axis: r.axis.clone(),
                    deceleration: r.deceleration,
                    jerk: r.jerk,
                },
                label(&r.axis, "halt"),
            ))
        },
        respond::<AxisHaltResponse>,
    )?;

    // MC_PlanarTrack (§3.3)
    shell.command_service(
        "track_append_position",
        TrackAppendPosition::service_type_name(),
        |r: TrackAppendPositionRequest| {
            let position = PositionXYC::with_ref(r.x, r.y, r.c, r.reference_id);
            track_cmd(
                &r.track,
                "append_position",
                PlanarCommand::TrackAppendPosition {
                    track: r.track.clone(),
                    position,
                },
            )
        },
        respond::<TrackAppendPositionResponse>,
    )?;
    shell.command_service(
        "track_append_line",
        TrackAppendLine::service_type_name(),
        |r: TrackAppendLineRequest| append_line_req(&r),
        respond::<TrackAppendLineResponse>,
    )?;
    shell.command_service(
        "track_append_circle",
        TrackAppendCircle::service_type_name(),
        |r: TrackAppendCircleRequest| append_circle_req(&r),
        respond::<TrackAppendCircleResponse>,
    )?;
    shell.command_service(
        "track_close_loop",
        TrackCloseLoop::service_type_name(),
        |r: TrackCloseLoopRequest| {
            let track = r.track.clone();
            track_cmd(
                &r.track,
                "close_loop",
                PlanarCommand::TrackCloseLoop { track },
            )
        },
        respond::<TrackCloseLoopResponse>,
    )?;
    shell.command_service(
        "track_start_from_track",
        TrackStartFromTrack::service_type_name(),
        |r: TrackStartFromTrackRequest| {
            track_cmd(
                &r.track,
                "start_from_track",
                PlanarCommand::TrackStartFromTrack {
                    track: r.track.clone(),
                    other: r.other.clone(),
                },
            )
        },
        respond::<TrackStartFromTrackResponse>,
    )?;
    shell.command_service(
        "track_end_at_track",
        TrackEndAtTrack::service_type_name(),
        |r: TrackEndAtTrackRequest| {
            track_cmd(
                &r.track,
                "end_at_track",
                PlanarCommand::TrackEndAtTrack {
                    track: r.track.clone(),
                    other: r.other.clone(),
                },
            )
        },
        respond::<TrackEndAtTrackResponse>,
    )?;
    shell.command_service(
        "track_start_from_track_advanced",
        TrackStartFromTrackAdvanced::service_type_name(),
        |r: TrackStartFromTrackAdvancedRequest| {
            let options = advanced(
                r.this_track_part_position_index,
                r.other_track_part_position_index,
                r.link_only_in_specified_part_positions,
            );
            track_cmd(
                &r.track,
                "start_from_track_advanced",
                PlanarCommand::TrackStartFromTrackAdvanced {
                    track: r.track.clone(),
                    other: r.other.clone(),
                    options,
                },
            )
        },
        respond::<TrackStartFromTrackAdvancedResponse>,
    )?;
    shell.command_service(
        "track_end_at_track_advanced",
        TrackEndAtTrackAdvanced::service_type_name(),
        |r: TrackEndAtTrackAdvancedRequest| {
            let options = advanced(
                r.this_track_part_position_index,
                r.other_track_part_position_index,
                r.link_only_in_specified_part_positions,
            );
            track_cmd(
                &r.track,
                "end_at_track_advanced",
                PlanarCommand::TrackEndAtTrackAdvanced {
                    track: r.track.clone(),
                    other: r.other.clone(),
                    options,
                },
            )
        },
        respond::<TrackEndAtTrackAdvancedResponse>,
    )?;
    shell.command_service(
        "track_clear",
        TrackClear::service_type_name(),
        |r: TrackClearRequest| {
            let track = r.track.clone();
            track_cmd(&r.track, "clear", PlanarCommand::TrackClear { track })
        },
        respond::<TrackClearResponse>,
    )?;
    shell.command_service(
        "track_enable",
        TrackEnable::service_type_name(),
        |r: TrackEnableRequest| {
            let track = r.track.clone();
            track_cmd(&r.track, "enable", PlanarCommand::TrackEnable { track })
        },
        respond::<TrackEnableResponse>,
    )?;
    shell.command_service(
        "track_disable",
        TrackDisable::service_type_name(),
        |r: TrackDisableRequest| {
            let track = r.track.clone();
            track_cmd(&r.track, "disable", PlanarCommand::TrackDisable { track })
        },
        respond::<TrackDisableResponse>,
    )?;
    shell.command_service(
        "track_reset",
        TrackReset::service_type_name(),
        |r: TrackResetRequest| {
            let track = r.track.clone();
            track_cmd(&r.track, "reset", PlanarCommand::TrackReset { track })
        },
        respond::<TrackResetResponse>,
    )?;
    shell.command_service(
        "track_add_to_group",
        TrackAddToGroup::service_type_name(),
        |r: TrackAddToGroupRequest| {
            track_cmd(
                &r.track,
                "add_to_group",
                PlanarCommand::TrackAddToGroup {
                    track: r.track.clone(),
                    group: r.group.clone(),
                },
            )
        },
        respond::<TrackAddToGroupResponse>,
    )?;
    shell.command_service(
        "track_set_init_parameters",
        TrackSetInitParameters::service_type_name(),
        |r: TrackSetInitParametersRequest| set_init_parameters_req(&r),
        respond::<TrackSetInitParametersResponse>,
    )?;
    shell.command_service(
        "track_remove_from_group",
        TrackRemoveFromGroup::service_type_name(),
        |r: TrackRemoveFromGroupRequest| {
            let track = r.track.clone();
            track_cmd(
                &r.track,
                "remove_from_group",
                PlanarCommand::TrackRemoveFromGroup { track },
            )
        },
        respond::<TrackRemoveFromGroupResponse>,
    )?;
    shell.command_service(
        "track_get_length",
        TrackGetLength::service_type_name(),
        |r: TrackGetLengthRequest| {
            let track = r.track.clone();
            track_cmd(
                &r.track,
                "get_length",
                PlanarCommand::TrackGetLength { track },
            )
        },
        |o| {
            let v = scalar(&o);
            let mut r = respond::<TrackGetLengthResponse>(o);
            r.length = v.unwrap_or(0.0);
            r
        },
    )?;
    shell.command_service(
        "track_get_arc_length_closest_to",
        TrackGetArcLengthClosestTo::service_type_name(),
        |r: TrackGetArcLengthClosestToRequest| {
            track_cmd(
                &r.track,
                "get_arc_length_closest_to",
                PlanarCommand::TrackGetArcLengthClosestTo {
                    track: r.track.clone(),
                    point: PositionXYC::with_ref(r.x, r.y, 0.0, r.reference_id),
                },
            )
        },
        |o| {
            let v = scalar(&o);
            let mut r = respond::<TrackGetArcLengthClosestToResponse>(o);
            r.arc_length = v.unwrap_or(0.0);
            r
        },
    )?;
    shell.command_service(
        "track_get_position_at",
        TrackGetPositionAt::service_type_name(),
        |r: TrackGetPositionAtRequest| {
            track_cmd(
                &r.track,
                "get_position_at",
                PlanarCommand::TrackGetPositionAt {
                    track: r.track.clone(),
                    arc_length: r.arc_length,
                },
            )
        },
        |o| {
            position_response(o, |r: &mut TrackGetPositionAtResponse, p| {
                (r.x, r.y, r.c, r.reference_id) = (p.x, p.y, p.c, p.reference_id)
            })
        },
    )?;
    shell.command_service(
        "track_get_planar_object_info",
        TrackGetPlanarObjectInfo::service_type_name(),
        |r: TrackGetPlanarObjectInfoRequest| {
            let track = r.track.clone();
            track_cmd(
                &r.track,
                "get_planar_object_info",
                PlanarCommand::TrackGetPlanarObjectInfo { track },
            )
        },
        |o| {
            let info = object_info(&o);
            let mut r = respond::<TrackGetPlanarObjectInfoResponse>(o);
            if let Some((t, id)) = info {
                (r.object_type, r.id) = (t, id);
            }
            r
        },
    )?;
    Ok(())
}

// --- actions -----------------------------------------------------------------------------------

/// (track, unwrapped arc position, modulo) of a mover: its SETONTRACK, or the track it is
/// joining or leaving at 0; empty when free.
fn track_position(snap: &Stamped<PlanarSnapshot>, mover: &str) -> (String, f64, f64) {
    let Some(m) = snap.state.mover(mover) else {
        return (String::new(), 0.0, 0.0);
    };
    match (&m.on_track, &m.joining_or_leaving) {
        (Some(t), _) => (t.track.clone(), t.set_pos, t.set_pos_modulo),
        (None, Some(track)) => (track.clone(), 0.0, 0.0),
        (None, None) => (String::new(), 0.0, 0.0),
    }
}

fn in_sync(snap: &Stamped<PlanarSnapshot>, mover: &str) -> bool {
    snap.state
        .mover(mover)
        .and_then(|m| m.on_track.as_ref())
        .is_some_and(|t| t.in_sync)
}

/// A mover action on tracks: as `mover_action!` (actions.rs) plus the track position in the
/// feedback and the result; `$extra` completes the feedback (gear-in: `in_sync`).
macro_rules! track_action {
    ($binding:ident, $action:path, $goal:ident, $result:ident, $feedback:ident, $decode:path,
     $extra:expr) => {
        struct $binding;

        impl ActionBinding<PlanarEngine> for $binding {
            type Goal = $goal;
            type Result = $result;
            type Feedback = $feedback;

            fn action_type_name() -> ActionTypeName {
                <$action>::action_type_name()
            }

            fn command(&self, g: &$goal) -> Result<(PlanarCommand, CommandLabel), Rejection> {
                $decode(g)
            }

            // (`..Default::default()` fills `in_sync` of the gear-in feedback.)
            #[allow(clippy::needless_update)]
            fn feedback(
                &self,
                g: &$goal,
                snap: &Stamped<PlanarSnapshot>,
                state: CommandState,
            ) -> $feedback {
                let p = pose(snap, &g.mover);
                let o = ExecuteOutputs::from(state);
                let (track, track_position, track_position_modulo) = track_position(snap, &g.mover);
                let mut f = $feedback {
                    busy: o.busy,
                    active: o.active,
                    x: p.x,
                    y: p.y,
                    z: p.z,
                    a: p.a,
                    b: p.b,
                    c: p.c,
                    track,
                    track_position,
                    track_position_modulo,
                    ..Default::default()
                };
                let extra: fn(&mut $feedback, &Stamped<PlanarSnapshot>, &str) = $extra;
                extra(&mut f, snap, &g.mover);
                f
            }

            fn result(
                &self,
                g: &$goal,
                snap: &Stamped<PlanarSnapshot>,
                end: CommandState,
                rejection: Option<&Rejection>,
            ) -> $result {
                let p = pose(snap, &g.mover);
                let o = ExecuteOutputs::from(end);
                let (object_type, object_id) =
                    end_object_info(snap, &g.mover, o.error_id, rejection);
                let (track, track_position, track_position_modulo) = track_position(snap, &g.mover);
                $result {
                    done: o.done,
                    command_aborted: o.command_aborted,
                    error: o.error,
                    error_id: o.error_id.0,
                    message: match rejection {
                        Some(r) => r.message.clone(),
                        None if o.error => PlanarEngine::error_text(o.error_id),
                        None => String::new(),
                    },
                    x: p.x,
                    y: p.y,
                    z: p.z,
                    a: p.a,
                    b: p.b,
                    c: p.c,
                    object_type,
                    object_id,
                    track,
                    track_position,
                    track_position_modulo,
                }
            }
        }
    };
}

track_action!(
    JoinTrackAction,
    act::MoverJoinTrack,
    MoverJoinTrackGoal,
    MoverJoinTrackResult,
    MoverJoinTrackFeedback,
    join_track_goal,
    |_, _, _| {}
);
track_action!(
    LeaveTrackAction,
    act::MoverLeaveTrack,
    MoverLeaveTrackGoal,
    MoverLeaveTrackResult,
    MoverLeaveTrackFeedback,
    leave_track_goal,
    |_, _, _| {}
);
track_action!(
    MoveOnTrackAction,
    act::MoverMoveOnTrack,
    MoverMoveOnTrackGoal,
    MoverMoveOnTrackResult,
    MoverMoveOnTrackFeedback,
    move_on_track_goal,
    |_, _, _| {}
);
track_action!(
    GearMasterAction,
    act::MoverGearInPosOnTrackWithMasterMover,
    MoverGearInPosOnTrackWithMasterMoverGoal,
    MoverGearInPosOnTrackWithMasterMoverResult,
    MoverGearInPosOnTrackWithMasterMoverFeedback,
    gear_master_goal,
    |f, snap, mover| f.in_sync = in_sync(snap, mover)
);

/// Registers the track actions.
pub(crate) fn register_actions(shell: &mut NodeShell<PlanarEngine>) -> Result<(), ShellError> {
    shell.action("mover_join_track", JoinTrackAction)?;
    shell.action("mover_leave_track", LeaveTrackAction)?;
    shell.action("mover_move_on_track", MoveOnTrackAction)?;
    shell.action(
        "mover_gear_in_pos_on_track_with_master_mover",
        GearMasterAction,
    )?;
    Ok(())
}

// --- state -------------------------------------------------------------------------------------

/// One track as `motion_msgs/PlanarTrackState`.
pub fn track_state(t: &TrackSnapshot) -> PlanarTrackState {
    PlanarTrackState {
        name: t.name.clone(),
        oid: t.oid,
        state: t.state as u8,
        operation_mode: t.operation_mode as u8,
        length: t.length,
        closed_loop: t.closed_loop,
        movers: t.movers.clone(),
        previous_tracks: t.previous_tracks.clone(),
        subsequent_tracks: t.subsequent_tracks.clone(),
        traversable_subsequent_tracks: t.traversable_subsequent_tracks.clone(),
        part_oid: t.part_oid,
        collision_range_start: t.collision_range_start,
        collision_range_end: t.collision_range_end,
        collision_range_mode: match t.collision_range_mode {
            CollisionRangeMode::Automatic => PlanarTrackState::COLLISION_RANGE_AUTOMATIC,
            CollisionRangeMode::Manual => PlanarTrackState::COLLISION_RANGE_MANUAL,
        },
        max_mover_width: t.max_mover_width,
        max_mover_height: t.max_mover_height,
        check_static_collision: t.check_static_collision,
    }
}

/// One virtual master axis as `motion_msgs/PlanarAxisState`.
pub fn axis_state(a: &VirtualAxisSnapshot) -> PlanarAxisState {
    PlanarAxisState {
        name: a.name.clone(),
        oid: a.oid,
        powered: a.powered,
        busy: a.busy,
        position: a.position,
        velocity: a.velocity,
        acceleration: a.acceleration,
    }
}

/// The SETONTRACK fields of a mover's state (empty / 0 while not on a track).
pub fn set_on_track(m: &MoverSnapshot, out: &mut PlanarMoverState) {
    out.joining_or_leaving_track = m.joining_or_leaving.clone().unwrap_or_default();
    let Some(t) = &m.on_track else {
        return;
    };
    out.track = t.track.clone();
    out.track_oid = t.track_oid;
    out.track_position = t.set_pos;
    out.track_position_modulo = t.set_pos_modulo;
    out.track_velocity = t.set_velo;
    out.track_acceleration = t.set_acc;
    out.gap = t.gap;
    out.waiting = t.waiting;
    out.in_sync = t.in_sync;
    out.gear_master = t.gear_master.clone().unwrap_or_default();
}

// --- markers -----------------------------------------------------------------------------------

/// What a track's drawn path depends on: its length and loop flag, and the part positions
/// (tracks move with their part, §1.6).
#[derive(Clone, Debug, PartialEq)]
struct PathKey {
    length: f64,
    closed: bool,
    parts: Vec<(f64, f64, u32)>,
}

impl PathKey {
    fn of(s: &PlanarSnapshot, t: &TrackSnapshot) -> Self {
        PathKey {
            length: t.length,
            closed: t.closed_loop,
            parts: s
                .parts
                .iter()
                .map(|p| (p.position.x, p.position.y, p.position_index))
                .collect(),
        }
    }
}

/// Sampled track paths \[mm\] by track name, kept by [`spawn_sampler`] and drawn by
/// [`track_markers`].
#[derive(Clone, Debug, Default)]
pub struct TrackPaths(Arc<Mutex<PathMap>>);

/// Track name -> (what the path was sampled for, points \[mm\]).
type PathMap = HashMap<String, (PathKey, Vec<[f64; 2]>)>;

impl TrackPaths {
    /// The sampled path of a track, if any.
    pub fn path(&self, track: &str) -> Option<Vec<[f64; 2]>> {
        let g = self.0.lock().unwrap_or_else(|e| e.into_inner());
        g.get(track).map(|(_, p)| p.clone())
    }

    fn stale(&self, name: &str, key: &PathKey) -> bool {
        let g = self.0.lock().unwrap_or_else(|e| e.into_inner());
        g.get(name).is_none_or(|(k, _)| k != key)
    }

    fn set(&self, name: &str, key: PathKey, path: Vec<[f64; 2]>) {
        let mut g = self.0.lock().unwrap_or_else(|e| e.into_inner());
        g.insert(name.to_string(), (key, path));
    }
}

/// Samples per track: about every 20 mm, 16..=256.
fn sample_count(length: f64) -> usize {
    ((length / 20.0).ceil() as usize).clamp(16, 256)
}

/// Keeps [`TrackPaths`] up to date: when a track's [`PathKey`] changes, its path is sampled
/// with GetPositionAt (the engine's own geometry, in the current part positions), read
/// through the runtime's query path, so sampling issues no commands.
pub(crate) fn spawn_sampler(shell: &NodeShell<PlanarEngine>, paths: TrackPaths) {
    let handle = shell.handle.clone();
    shell.spawn(async move {
        let mut snaps = handle.snapshots();
        loop {
            let snap = snaps.borrow_and_update().clone();
            for t in &snap.state.tracks {
                let key = PathKey::of(&snap.state, t);
                if !paths.stale(&t.name, &key) {
                    continue;
                }
                let path = if t.length > 0.0 {
                    let n = sample_count(t.length);
                    let (name, len) = (t.name.clone(), t.length);
                    // One read-only query per track: no command ids, nothing on
                    // `~/command_status`, no share of the clients' command queue.
                    let pts = handle
                        .query(move |e: &PlanarEngine| {
                            (0..=n)
                                .map(|k| {
                                    e.track_position_at(&name, len * k as f64 / n as f64)
                                        .map(|p| [p.x, p.y])
                                })
                                .collect::<Result<Vec<_>, _>>()
                        })
                        .await;
                    match pts {
                        Ok(Ok(p)) => p,
                        // Changed meanwhile (e.g. cleared) or the queue was full: the
                        // next snapshot retries.
                        _ => continue,
                    }
                } else {
                    Vec::new()
                };
                paths.set(&t.name, key, path);
            }
            if snaps.changed().await.is_err() {
                return;
            }
        }
    });
}

fn mode_color(t: &TrackSnapshot) -> ColorRGBA {
    let (r, g, b) = match t.operation_mode {
        TrackOperationMode::Moving => (0.2, 0.5, 1.0),
        TrackOperationMode::Standing => (0.1, 0.8, 0.3),
        TrackOperationMode::Configuring => (0.9, 0.7, 0.1),
        TrackOperationMode::Uninitialized | TrackOperationMode::Invalid => (0.6, 0.6, 0.6),
    };
    ColorRGBA { r, g, b, a: 1.0 }
}

/// Tracks for RViz (ns `tracks`, id = configuration index): a LINE_STRIP along each sampled
/// path, 2 mm above the stators, coloured by operation mode (grey uninitialized, green
/// standing, yellow configuring, blue moving); DELETE while a track has no geometry.
pub fn track_markers(paths: &TrackPaths, s: &Stamped<PlanarSnapshot>, h: &Header) -> Vec<Marker> {
    const MM: f64 = 1e-3;
    s.state
        .tracks
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let pts = if t.length > 0.0 {
                paths.path(&t.name).unwrap_or_default()
            } else {
                Vec::new()
            };
            Marker {
                header: h.clone(),
                ns: "tracks".into(),
                id: i as i32,
                r#type: Marker::LINE_STRIP,
                action: if pts.is_empty() {
                    Marker::DELETE
                } else {
                    Marker::ADD
                },
                pose: Pose {
                    position: Point::default(),
                    orientation: Quaternion {
                        x: 0.0,
                        y: 0.0,
                        z: 0.0,
                        w: 1.0,
                    },
                },
                scale: Vector3 {
                    x: 0.006,
                    y: 0.0,
                    z: 0.0,
                },
                color: mode_color(t),
                points: pts
                    .iter()
                    .map(|p| Point {
                        x: p[0] * MM,
                        y: p[1] * MM,
                        z: 0.002,
                    })
                    .collect(),
                ..Default::default()
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use motion_core::{ErrorId, Tick};
    use planar_engine::errors::E_TRACK_MODE_CONFLICT;

    /// The loop of the DDS test: two straights joined by half circles (generated
    /// transitions fill the gaps), three movers (m1, m2 on the bottom straight, m3 inside).
    pub(crate) const CFG: &str = "movers: [{name: m1, initial_pose: {x: 1000, y: 200}}, {name: m2, initial_pose: {x: 1500, y: 200}}, {name: m3, initial_pose: {x: 1300, y: 500}}]
tracks: [{name: loop}]
axes: [{name: v1}]
";

    struct Sim {
        e: PlanarEngine,
        index: u64,
    }

    impl Sim {
        fn new() -> Self {
            let cfg = serde_yaml::from_str(CFG).unwrap();
            Sim {
                e: PlanarEngine::new(cfg).unwrap(),
                index: 0,
            }
        }
        fn run(&mut self, cycles: u64) {
            let mut ev = Vec::new();
            for _ in 0..cycles {
                self.e.step(
                    Tick {
                        index: self.index,
                        dt: 0.001,
                    },
                    &mut ev,
                );
                self.index += 1;
                ev.clear();
            }
        }
        fn cmd(&mut self, d: Decoded) -> Outcome {
            let (c, _) = d?;
            self.e.command(c)
        }
        fn snap(&self) -> PlanarSnapshot {
            self.e.snapshot()
        }
    }

    fn line(sx: f64, sy: f64, ex: f64, ey: f64) -> TrackAppendLineRequest {
        TrackAppendLineRequest {
            track: "loop".into(),
            start_x: sx,
            start_y: sy,
            end_x: ex,
            end_y: ey,
            reference_id: 0,
        }
    }

    fn circle(s: (f64, f64), e: (f64, f64), c: (f64, f64)) -> TrackAppendCircleRequest {
        TrackAppendCircleRequest {
            track: "loop".into(),
            start_x: s.0,
            start_y: s.1,
            end_x: e.0,
            end_y: e.1,
            center_x: c.0,
            center_y: c.1,
            clockwise: false,
            reference_id: 0,
        }
    }

    fn join(mover: &str) -> MoverJoinTrackRequest {
        MoverJoinTrackRequest {
            mover: mover.into(),
            track: "loop".into(),
            use_orientation: true,
            ..Default::default()
        }
    }

    fn move_on(mover: &str, target: f64, velocity: f64, gap: f64) -> MoverMoveOnTrackRequest {
        MoverMoveOnTrackRequest {
            mover: mover.into(),
            target_position: target,
            velocity,
            gap,
            ..Default::default()
        }
    }

    fn on_track(s: &PlanarSnapshot, m: &str) -> planar_engine::OnTrackSnapshot {
        s.mover(m).unwrap().on_track.clone().expect("on track")
    }

    #[test]
    fn loop_join_and_gap_through_the_decoders() {
        let mut s = Sim::new();
        s.cmd(append_line_req(&line(800.0, 200.0, 1800.0, 200.0)))
            .unwrap();
        s.cmd(append_circle_req(&circle(
            (2100.0, 200.0),
            (2100.0, 800.0),
            (2100.0, 500.0),
        )))
        .unwrap();
        s.cmd(append_line_req(&line(1800.0, 800.0, 800.0, 800.0)))
            .unwrap();
        s.cmd(append_circle_req(&circle(
            (500.0, 800.0),
            (500.0, 200.0),
            (500.0, 500.0),
        )))
        .unwrap();
        for c in [
            PlanarCommand::TrackCloseLoop {
                track: "loop".into(),
            },
            PlanarCommand::TrackEnable {
                track: "loop".into(),
            },
        ] {
            s.e.command(c).unwrap();
        }
        for m in ["m1", "m2", "m3"] {
            s.e.command(PlanarCommand::MoverEnable { mover: m.into() })
                .unwrap();
        }
        s.run(300);
        let snap = s.snap();
        let t = track_state(&snap.tracks[0]);
        assert!(t.closed_loop);
        let arcs = 2.0 * std::f64::consts::PI * 300.0;
        assert!(t.length > 2000.0 + arcs, "{}", t.length);
        let l = match s
            .e
            .command(PlanarCommand::TrackGetLength {
                track: "loop".into(),
            })
            .unwrap()
            .value
        {
            ReplyValue::Scalar(v) => v,
            v => panic!("{v:?}"),
        };
        assert_eq!(l, t.length);

        s.cmd(join_track_req(&join("m1"))).unwrap();
        s.cmd(join_track_req(&join("m2"))).unwrap();
        s.run(3000);
        let snap = s.snap();
        assert_eq!(snap.tracks[0].operation_mode, TrackOperationMode::Standing);
        let (p1, p2) = (on_track(&snap, "m1").set_pos, on_track(&snap, "m2").set_pos);
        assert!(
            (p1 - 200.0).abs() < 1.0 && (p2 - 700.0).abs() < 1.0,
            "{p1} {p2}"
        );
        let m = mover_state_of(&snap, "m1");
        assert_eq!(m.track, "loop");
        assert_eq!(m.command_mode, PlanarMoverState::MODE_ON_TRACK);

        // The follower into the leader: held back at the gap.
        s.cmd(move_on_track_req(&move_on("m1", 1200.0, 500.0, 300.0)))
            .unwrap();
        s.run(3000);
        let snap = s.snap();
        let f = on_track(&snap, "m1");
        assert!(f.waiting, "{f:?}");
        assert_eq!(f.gap, 300.0);
        assert!((on_track(&snap, "m2").set_pos - f.set_pos - 300.0).abs() < 1.0);
        // Moving: a join is refused.
        assert_eq!(snap.tracks[0].operation_mode, TrackOperationMode::Moving);
        let e = s.cmd(join_track_req(&join("m3"))).unwrap_err();
        assert_eq!(e.error_id, E_TRACK_MODE_CONFLICT, "{}", e.message);
        // Bad requests: enum, NaN, unknown track.
        let bad = MoverMoveOnTrackRequest {
            direction: 7,
            ..move_on("m1", 1.0, 0.0, 200.0)
        };
        assert_eq!(
            move_on_track_req(&bad).unwrap_err().error_id,
            ErrorId::ENUM_OUT_OF_RANGE
        );
        let e = s
            .cmd(move_on_track_req(&move_on("m1", f64::NAN, 0.0, 200.0)))
            .unwrap_err();
        assert_eq!(e.error_id, ErrorId::NOT_FINITE);
        let e = s
            .cmd(join_track_req(&MoverJoinTrackRequest {
                track: "nope".into(),
                ..join("m3")
            }))
            .unwrap_err();
        assert_eq!(e.error_id, ErrorId::UNKNOWN_OBJECT);
        assert_eq!(
            sync_directions("m1", 0).unwrap_err().error_id,
            ErrorId::ENUM_OUT_OF_RANGE
        );
    }

    fn mover_state_of(s: &PlanarSnapshot, m: &str) -> PlanarMoverState {
        crate::convert::mover_state(s.mover(m).unwrap())
    }

    #[test]
    fn markers_draw_sampled_paths_by_mode() {
        let mut s = Sim::new();
        s.cmd(append_line_req(&line(800.0, 200.0, 1800.0, 200.0)))
            .unwrap();
        let snap = Stamped {
            cycle: 0,
            sim_time: 0.0,
            ros_time_ns: 0,
            state: s.snap(),
        };
        let paths = TrackPaths::default();
        let h = Header::default();
        // Not sampled yet: DELETE.
        assert_eq!(track_markers(&paths, &snap, &h)[0].action, Marker::DELETE);
        let key = PathKey::of(&snap.state, &snap.state.tracks[0]);
        assert!(paths.stale("loop", &key));
        paths.set("loop", key.clone(), vec![[800.0, 200.0], [1800.0, 200.0]]);
        assert!(!paths.stale("loop", &key));
        let m = &track_markers(&paths, &snap, &h)[0];
        assert_eq!((m.ns.as_str(), m.r#type), ("tracks", Marker::LINE_STRIP));
        assert_eq!(m.action, Marker::ADD);
        assert!((m.points[1].x - 1.8).abs() < 1e-12);
        assert_eq!(sample_count(1000.0), 50);
        assert_eq!(sample_count(1.0), 16);
        assert_eq!(sample_count(1e6), 256);
    }

    #[test]
    fn axes_and_tracks_are_in_the_state_message() {
        let s = Sim::new();
        let m = crate::convert::planar_state(&Stamped {
            cycle: 0,
            sim_time: 0.0,
            ros_time_ns: 0,
            state: s.snap(),
        });
        assert_eq!(m.tracks[0].name, "loop");
        assert_eq!(
            m.tracks[0].operation_mode,
            PlanarTrackState::MODE_UNINITIALIZED
        );
        assert_eq!(m.axes[0].name, "v1");
        assert!(!m.axes[0].powered);
        assert_eq!(m.movers[0].track, "");
    }
}
