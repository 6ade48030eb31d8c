//! Services of planar_node: one call = one method call of an MC_Planar… object (an Execute
//! edge), answered at once: accepted with the command id, or rejected with the error id and a
//! message (xplanar.md §3, §6.2). The command's feedback then follows on `~/command_status`.
//! Queries (`Get…`) answer their value in the response.

use motion_core::{ErrorId, Rejection};
use motion_msgs::srv::*;
use motion_msgs::CommandResponse;
use motion_runtime::{CommandLabel, NodeShell, ShellError};
use planar_engine::{
    Direction, DynamicConstraint, ErrorReaction, ExternalSetpointGenerationOptions,
    ExternalSetpointMode, MoveCOptions, MoveToPositionOptions, MoverVector, ObjectKind,
    PlanarCommand, PlanarEngine, PlanarReply, PositionXYC, ReplyValue,
};

/// Result of one command service call.
pub(crate) type Outcome = Result<PlanarReply, Rejection>;

/// The answer of a command service (accepted with the command id, or rejected).
pub(crate) fn respond<R: CommandResponse>(o: Outcome) -> R {
    motion_runtime::shell::respond(&o, |r| r.id)
}

/// Responses of the motion services also carry the command's warning (W_DYNAMICS_REDUCED)
/// and, for E_COLLISION, objectInfo: the blocking object (§6.1).
pub(crate) trait MotionResponse {
    fn set_warning(&mut self, warning_id: u32);
    fn set_object(&mut self, object_type: u16, object_id: u32);
}

macro_rules! motion_response {
    ($($resp:ident),* $(,)?) => {$(
        impl $crate::services::MotionResponse for $resp {
            fn set_warning(&mut self, warning_id: u32) {
                self.warning_id = warning_id;
            }
            fn set_object(&mut self, object_type: u16, object_id: u32) {
                self.object_type = object_type;
                self.object_id = object_id;
            }
        }
    )*};
}
pub(crate) use motion_response;

motion_response!(
    MoverMoveToPositionResponse,
    MoverMoveZResponse,
    MoverMoveAResponse,
    MoverMoveBResponse,
    MoverMoveCResponse,
    MoverHaltResponse,
);

/// [`respond`] plus the warning id of an accepted motion command, or the objectInfo of a
/// rejected one.
pub(crate) fn respond_motion<R: CommandResponse + MotionResponse>(o: Outcome) -> R {
    let warning = o.as_ref().map(|r| r.warning_id.0).unwrap_or(0);
    let object = o.as_ref().err().and_then(|e| e.object);
    let mut r: R = respond(o);
    r.set_warning(warning);
    if let Some(obj) = object {
        r.set_object(obj.kind, obj.id);
    }
    r
}

pub(crate) fn label(object: &str, command: &str) -> CommandLabel {
    CommandLabel {
        object: object.to_string(),
        command: command.to_string(),
    }
}

pub(crate) fn enum_error(object: &str, field: &str, value: u32, allowed: &str) -> Rejection {
    Rejection::new(
        ErrorId::ENUM_OUT_OF_RANGE,
        format!("{object}: {field} = {value} is out of range ({allowed})"),
    )
}

/// `MC_DIRECTION` (xplanar.md §4.1) from its number.
pub(crate) fn direction(mover: &str, raw: u8) -> Result<Direction, Rejection> {
    match raw {
        0 => Ok(Direction::NonModulo),
        1 => Ok(Direction::Positive),
        2 => Ok(Direction::ShortestWay),
        3 => Ok(Direction::Negative),
        v => Err(enum_error(
            mover,
            "direction",
            v.into(),
            "0 non-modulo, 1 positive, 2 shortest way, 3 negative",
        )),
    }
}

fn esg_mode(mover: &str, raw: u8) -> Result<ExternalSetpointMode, Rejection> {
    match raw {
        1 => Ok(ExternalSetpointMode::Absolute),
        2 => Ok(ExternalSetpointMode::Relative),
        v => Err(enum_error(
            mover,
            "mode",
            v.into(),
            "1 absolute, 2 relative",
        )),
    }
}

fn reaction(name: &str, raw: u8) -> Result<ErrorReaction, Rejection> {
    match raw {
        1 => Ok(ErrorReaction::QuickStop),
        2 => Ok(ErrorReaction::Abort),
        v => Err(enum_error(
            name,
            "reaction",
            v.into(),
            "1 quick stop, 2 abort",
        )),
    }
}

fn object_kind(name: &str, raw: u8) -> Result<ObjectKind, Rejection> {
    match raw {
        0 => Ok(ObjectKind::Mover),
        1 => Ok(ObjectKind::Group),
        2 => Ok(ObjectKind::Part),
        v => Err(enum_error(
            name,
            "kind",
            v.into(),
            "0 mover, 1 group, 2 part",
        )),
    }
}

pub(crate) fn constraint(
    velocity: f64,
    acceleration: f64,
    deceleration: f64,
    jerk: f64,
) -> DynamicConstraint {
    DynamicConstraint {
        velocity,
        acceleration,
        deceleration,
        jerk,
    }
}

fn vector(v: [f64; 6]) -> MoverVector {
    MoverVector::from_array(v)
}

// --- mover motions (shared with the actions) -------------------------------------------------

macro_rules! decode_aux {
    ($name:ident, $ty:ty, $variant:ident, $cmd:literal) => {
        pub(crate) fn $name(r: &$ty) -> Result<(PlanarCommand, CommandLabel), Rejection> {
            Ok((
                PlanarCommand::$variant {
                    mover: r.mover.clone(),
                    target_position: r.target_position,
                    constraint: constraint(r.velocity, r.acceleration, r.deceleration, r.jerk),
                },
                label(&r.mover, $cmd),
            ))
        }
    };
}

pub(crate) fn move_to_position_req(
    r: &MoverMoveToPositionRequest,
) -> Result<(PlanarCommand, CommandLabel), Rejection> {
    Ok((
        PlanarCommand::MoveToPosition {
            mover: r.mover.clone(),
            target_position: PositionXYC::with_ref(r.x, r.y, r.c, r.reference_id),
            constraint: constraint(r.velocity, r.acceleration, r.deceleration, r.jerk),
            options: MoveToPositionOptions {
                use_orientation: r.use_orientation,
            },
        },
        label(&r.mover, "move_to_position"),
    ))
}
/// The goal decodes through the service request's path.
pub(crate) fn move_to_position_goal(g: &motion_msgs::action::MoverMoveToPositionGoal) -> Decoded {
    move_to_position_req(&g.into())
}
decode_aux!(move_z_req, MoverMoveZRequest, MoveZ, "move_z");
/// The goal decodes through the service request's path.
pub(crate) fn move_z_goal(g: &motion_msgs::action::MoverMoveZGoal) -> Decoded {
    move_z_req(&g.into())
}
decode_aux!(move_a_req, MoverMoveARequest, MoveA, "move_a");
/// The goal decodes through the service request's path.
pub(crate) fn move_a_goal(g: &motion_msgs::action::MoverMoveAGoal) -> Decoded {
    move_a_req(&g.into())
}
decode_aux!(move_b_req, MoverMoveBRequest, MoveB, "move_b");
/// The goal decodes through the service request's path.
pub(crate) fn move_b_goal(g: &motion_msgs::action::MoverMoveBGoal) -> Decoded {
    move_b_req(&g.into())
}
pub(crate) fn move_c_req(
    r: &MoverMoveCRequest,
) -> Result<(PlanarCommand, CommandLabel), Rejection> {
    Ok((
        PlanarCommand::MoveC {
            mover: r.mover.clone(),
            target_position: r.target_position,
            constraint: constraint(r.velocity, r.acceleration, r.deceleration, r.jerk),
            options: MoveCOptions {
                additional_turns: r.additional_turns,
                direction: direction(&r.mover, r.direction)?,
            },
        },
        label(&r.mover, "move_c"),
    ))
}
/// The goal decodes through the service request's path.
pub(crate) fn move_c_goal(g: &motion_msgs::action::MoverMoveCGoal) -> Decoded {
    move_c_req(&g.into())
}

pub(crate) type Decoded = Result<(PlanarCommand, CommandLabel), Rejection>;

fn mover_cmd(mover: &str, command: &str, cmd: PlanarCommand) -> Decoded {
    Ok((cmd, label(mover, command)))
}

pub(crate) fn position_response<R: CommandResponse>(
    o: Outcome,
    set: impl FnOnce(&mut R, PositionXYC),
) -> R {
    let p = match &o {
        Ok(PlanarReply {
            value: ReplyValue::Position(p),
            ..
        }) => Some(*p),
        _ => None,
    };
    let mut r = respond::<R>(o);
    if let Some(p) = p {
        set(&mut r, p);
    }
    r
}

pub(crate) fn object_info(o: &Outcome) -> Option<(u16, u32)> {
    match o {
        Ok(PlanarReply {
            value: ReplyValue::ObjectInfo(i),
            ..
        }) => Some((i.object_type as u16, i.id)),
        _ => None,
    }
}

pub(crate) fn register(
    shell: &mut NodeShell<PlanarEngine>,
    env_name: String,
) -> Result<(), ShellError> {
    register_environment(shell, env_name)?;

    // MC_PlanarMover (§3.2)
    shell.command_service(
        "mover_move_to_position",
        MoverMoveToPosition::service_type_name(),
        |r: MoverMoveToPositionRequest| move_to_position_req(&r),
        respond_motion::<MoverMoveToPositionResponse>,
    )?;
    shell.command_service(
        "mover_move_z",
        MoverMoveZ::service_type_name(),
        |r: MoverMoveZRequest| move_z_req(&r),
        respond_motion::<MoverMoveZResponse>,
    )?;
    shell.command_service(
        "mover_move_a",
        MoverMoveA::service_type_name(),
        |r: MoverMoveARequest| move_a_req(&r),
        respond_motion::<MoverMoveAResponse>,
    )?;
    shell.command_service(
        "mover_move_b",
        MoverMoveB::service_type_name(),
        |r: MoverMoveBRequest| move_b_req(&r),
        respond_motion::<MoverMoveBResponse>,
    )?;
    shell.command_service(
        "mover_move_c",
        MoverMoveC::service_type_name(),
        |r: MoverMoveCRequest| move_c_req(&r),
        respond_motion::<MoverMoveCResponse>,
    )?;
    shell.command_service(
        "mover_halt",
        MoverHalt::service_type_name(),
        |r: MoverHaltRequest| {
            let constraint = constraint(0.0, 0.0, r.deceleration, r.jerk);
            mover_cmd(
                &r.mover,
                "halt",
                PlanarCommand::Halt {
                    mover: r.mover.clone(),
                    constraint,
                },
            )
        },
        respond_motion::<MoverHaltResponse>,
    )?;
    shell.command_service(
        "mover_enable",
        MoverEnable::service_type_name(),
        |r: MoverEnableRequest| {
            mover_cmd(
                &r.mover,
                "enable",
                PlanarCommand::MoverEnable {
                    mover: r.mover.clone(),
                },
            )
        },
        respond::<MoverEnableResponse>,
    )?;
    shell.command_service(
        "mover_disable",
        MoverDisable::service_type_name(),
        |r: MoverDisableRequest| {
            mover_cmd(
                &r.mover,
                "disable",
                PlanarCommand::MoverDisable {
                    mover: r.mover.clone(),
                },
            )
        },
        respond::<MoverDisableResponse>,
    )?;
    shell.command_service(
        "mover_reset",
        MoverReset::service_type_name(),
        |r: MoverResetRequest| {
            mover_cmd(
                &r.mover,
                "reset",
                PlanarCommand::MoverReset {
                    mover: r.mover.clone(),
                },
            )
        },
        respond::<MoverResetResponse>,
    )?;
    shell.command_service(
        "mover_set_position",
        MoverSetPosition::service_type_name(),
        |r: MoverSetPositionRequest| {
            let position = PositionXYC::with_ref(r.x, r.y, r.c, r.reference_id);
            mover_cmd(
                &r.mover,
                "set_position",
                PlanarCommand::SetPosition {
                    mover: r.mover.clone(),
                    position,
                },
            )
        },
        respond::<MoverSetPositionResponse>,
    )?;
    shell.command_service(
        "mover_start_external_setpoint_generation",
        MoverStartExternalSetpointGeneration::service_type_name(),
        |r: MoverStartExternalSetpointGenerationRequest| {
            let options = ExternalSetpointGenerationOptions {
                mode: esg_mode(&r.mover, r.mode)?,
            };
            mover_cmd(
                &r.mover,
                "start_external_setpoint_generation",
                PlanarCommand::StartExternalSetpointGeneration {
                    mover: r.mover.clone(),
                    options,
                },
            )
        },
        respond::<MoverStartExternalSetpointGenerationResponse>,
    )?;
    shell.command_service(
        "mover_stop_external_setpoint_generation",
        MoverStopExternalSetpointGeneration::service_type_name(),
        |r: MoverStopExternalSetpointGenerationRequest| {
            mover_cmd(
                &r.mover,
                "stop_external_setpoint_generation",
                PlanarCommand::StopExternalSetpointGeneration {
                    mover: r.mover.clone(),
                },
            )
        },
        respond::<MoverStopExternalSetpointGenerationResponse>,
    )?;
    shell.command_service(
        "mover_set_external_setpoint",
        MoverSetExternalSetpoint::service_type_name(),
        |r: MoverSetExternalSetpointRequest| {
            mover_cmd(
                &r.mover,
                "set_external_setpoint",
                PlanarCommand::SetExternalSetpoint {
                    mover: r.mover.clone(),
                    set_position: vector(r.set_position),
                    set_velocity: vector(r.set_velocity),
                    set_acceleration: vector(r.set_acceleration),
                },
            )
        },
        respond::<MoverSetExternalSetpointResponse>,
    )?;
    shell.command_service(
        "mover_set_external_setpoint_reference_id",
        MoverSetExternalSetpointReferenceId::service_type_name(),
        |r: MoverSetExternalSetpointReferenceIdRequest| {
            mover_cmd(
                &r.mover,
                "set_external_setpoint_reference_id",
                PlanarCommand::SetExternalSetpointReferenceId {
                    mover: r.mover.clone(),
                    set_position: vector(r.set_position),
                    set_velocity: vector(r.set_velocity),
                    set_acceleration: vector(r.set_acceleration),
                    reference_system_oid: r.reference_system_oid,
                },
            )
        },
        respond::<MoverSetExternalSetpointReferenceIdResponse>,
    )?;
    shell.command_service(
        "mover_add_to_group",
        MoverAddToGroup::service_type_name(),
        |r: MoverAddToGroupRequest| {
            mover_cmd(
                &r.mover,
                "add_to_group",
                PlanarCommand::MoverAddToGroup {
                    mover: r.mover.clone(),
                    group: r.group,
                },
            )
        },
        respond::<MoverAddToGroupResponse>,
    )?;
    shell.command_service(
        "mover_remove_from_group",
        MoverRemoveFromGroup::service_type_name(),
        |r: MoverRemoveFromGroupRequest| {
            mover_cmd(
                &r.mover,
                "remove_from_group",
                PlanarCommand::MoverRemoveFromGroup {
                    mover: r.mover.clone(),
                },
            )
        },
        respond::<MoverRemoveFromGroupResponse>,
    )?;
    shell.command_service(
        "mover_get_position_on_current_part",
        MoverGetPositionOnCurrentPart::service_type_name(),
        |r: MoverGetPositionOnCurrentPartRequest| {
            mover_cmd(
                &r.mover,
                "get_position_on_current_part",
                PlanarCommand::GetPositionOnCurrentPart {
                    mover: r.mover.clone(),
                },
            )
        },
        |o| {
            position_response(o, |r: &mut MoverGetPositionOnCurrentPartResponse, p| {
                (r.x, r.y, r.c, r.reference_id) = (p.x, p.y, p.c, p.reference_id)
            })
        },
    )?;
    shell.command_service(
        "mover_get_planar_object_info",
        MoverGetPlanarObjectInfo::service_type_name(),
        |r: MoverGetPlanarObjectInfoRequest| {
            mover_cmd(
                &r.mover,
                "get_planar_object_info",
                PlanarCommand::MoverGetPlanarObjectInfo {
                    mover: r.mover.clone(),
                },
            )
        },
        |o| {
            let info = object_info(&o);
            let mut r = respond::<MoverGetPlanarObjectInfoResponse>(o);
            if let Some((t, id)) = info {
                (r.object_type, r.id) = (t, id);
            }
            r
        },
    )?;

    // MC_PlanarGroup (§3.4)
    shell.command_service(
        "group_enable",
        GroupEnable::service_type_name(),
        |r: GroupEnableRequest| {
            Ok((
                PlanarCommand::GroupEnable {
                    group: r.group.clone(),
                },
                label(&r.group, "enable"),
            ))
        },
        respond::<GroupEnableResponse>,
    )?;
    shell.command_service(
        "group_disable",
        GroupDisable::service_type_name(),
        |r: GroupDisableRequest| {
            Ok((
                PlanarCommand::GroupDisable {
                    group: r.group.clone(),
                },
                label(&r.group, "disable"),
            ))
        },
        respond::<GroupDisableResponse>,
    )?;
    shell.command_service(
        "group_reset",
        GroupReset::service_type_name(),
        |r: GroupResetRequest| {
            Ok((
                PlanarCommand::GroupReset {
                    group: r.group.clone(),
                },
                label(&r.group, "reset"),
            ))
        },
        respond::<GroupResetResponse>,
    )?;

    // MC_PlanarPart (§3.5)
    shell.command_service(
        "part_initialize",
        PartInitialize::service_type_name(),
        |r: PartInitializeRequest| {
            Ok((
                PlanarCommand::PartInitialize {
                    part: r.part.clone(),
                    part_oid: r.part_oid,
                },
                label(&r.part, "initialize"),
            ))
        },
        respond::<PartInitializeResponse>,
    )?;
    shell.command_service(
        "part_activate_position",
        PartActivatePosition::service_type_name(),
        |r: PartActivatePositionRequest| {
            Ok((
                PlanarCommand::ActivatePosition {
                    part: r.part.clone(),
                    position_index: r.position_index,
                },
                label(&r.part, "activate_position"),
            ))
        },
        respond::<PartActivatePositionResponse>,
    )?;
    shell.command_service(
        "part_allow_enable",
        PartAllowEnable::service_type_name(),
        |r: PartAllowEnableRequest| {
            Ok((
                PlanarCommand::AllowEnable {
                    part: r.part.clone(),
                },
                label(&r.part, "allow_enable"),
            ))
        },
        respond::<PartAllowEnableResponse>,
    )?;
    shell.command_service(
        "part_force_disable",
        PartForceDisable::service_type_name(),
        |r: PartForceDisableRequest| {
            Ok((
                PlanarCommand::ForceDisable {
                    part: r.part.clone(),
                },
                label(&r.part, "force_disable"),
            ))
        },
        respond::<PartForceDisableResponse>,
    )?;
    shell.command_service(
        "part_reset",
        PartReset::service_type_name(),
        |r: PartResetRequest| {
            Ok((
                PlanarCommand::PartReset {
                    part: r.part.clone(),
                },
                label(&r.part, "reset"),
            ))
        },
        respond::<PartResetResponse>,
    )?;
    shell.command_service(
        "part_get_position",
        PartGetPosition::service_type_name(),
        |r: PartGetPositionRequest| {
            Ok((
                PlanarCommand::PartGetPosition {
                    part: r.part.clone(),
                },
                label(&r.part, "get_position"),
            ))
        },
        |o| {
            position_response(o, |r: &mut PartGetPositionResponse, p| {
                (r.x, r.y, r.c, r.reference_id) = (p.x, p.y, p.c, p.reference_id)
            })
        },
    )?;

    // Simulation hook (§6.2)
    shell.command_service(
        "sim/inject_error",
        PlanarInjectError::service_type_name(),
        |r: PlanarInjectErrorRequest| {
            let kind = object_kind(&r.name, r.kind)?;
            let reaction = reaction(&r.name, r.reaction)?;
            Ok((
                PlanarCommand::InjectError {
                    kind,
                    name: r.name.clone(),
                    reaction,
                },
                label(&r.name, "sim/inject_error"),
            ))
        },
        respond::<PlanarInjectErrorResponse>,
    )?;
    Ok(())
}

/// MC_PlanarEnvironment (§3.1): there is one environment; requests name it (or leave the
/// name empty). The engine's commands take no name, so the shell checks it.
fn register_environment(
    shell: &mut NodeShell<PlanarEngine>,
    env_name: String,
) -> Result<(), ShellError> {
    fn env_service<Req, Resp>(
        shell: &mut NodeShell<PlanarEngine>,
        name: &'static str,
        type_name: ros2_client::ServiceTypeName,
        env_name: &str,
        decode: fn(Req) -> (String, PlanarCommand),
        respond: fn(Outcome) -> Resp,
    ) -> Result<(), ShellError>
    where
        Req: ros2_client::Message + Clone + Send + Sync + 'static,
        Resp: ros2_client::Message + Send + Sync + 'static,
    {
        let handle = shell.handle.clone();
        let env_name = env_name.to_string();
        shell.service::<Req, Resp, _, _>(name, type_name, move |req: Req| {
            let handle = handle.clone();
            let env_name = env_name.clone();
            async move {
                let (named, cmd) = decode(req);
                let outcome = if !named.is_empty() && named != env_name {
                    Err(Rejection::unknown_object("environment", &named))
                } else {
                    let l = label(&env_name, name.trim_start_matches("environment_"));
                    handle.call_labeled(cmd, l).await
                };
                respond(outcome)
            }
        })
    }

    let e = env_name.as_str();
    env_service(
        shell,
        "environment_clear",
        EnvironmentClear::service_type_name(),
        e,
        |r: EnvironmentClearRequest| (r.environment, PlanarCommand::EnvironmentClear),
        respond::<EnvironmentClearResponse>,
    )?;
    env_service(
        shell,
        "environment_add_stator",
        EnvironmentAddStator::service_type_name(),
        e,
        |r: EnvironmentAddStatorRequest| {
            (
                r.environment,
                PlanarCommand::AddStator {
                    lower_x: r.lower_x,
                    lower_y: r.lower_y,
                },
            )
        },
        respond::<EnvironmentAddStatorResponse>,
    )?;
    env_service(
        shell,
        "environment_create_boundary",
        EnvironmentCreateBoundary::service_type_name(),
        e,
        |r: EnvironmentCreateBoundaryRequest| (r.environment, PlanarCommand::CreateBoundary),
        respond::<EnvironmentCreateBoundaryResponse>,
    )?;
    env_service(
        shell,
        "environment_add_to_group",
        EnvironmentAddToGroup::service_type_name(),
        e,
        |r: EnvironmentAddToGroupRequest| {
            (
                r.environment,
                PlanarCommand::EnvironmentAddToGroup { group: r.group },
            )
        },
        respond::<EnvironmentAddToGroupResponse>,
    )?;
    env_service(
        shell,
        "environment_remove_from_group",
        EnvironmentRemoveFromGroup::service_type_name(),
        e,
        |r: EnvironmentRemoveFromGroupRequest| {
            (r.environment, PlanarCommand::EnvironmentRemoveFromGroup)
        },
        respond::<EnvironmentRemoveFromGroupResponse>,
    )?;
    env_service(
        shell,
        "environment_get_planar_object_info",
        EnvironmentGetPlanarObjectInfo::service_type_name(),
        e,
        |r: EnvironmentGetPlanarObjectInfoRequest| {
            (r.environment, PlanarCommand::EnvironmentGetPlanarObjectInfo)
        },
        |o| {
            let info = object_info(&o);
            let mut r = respond::<EnvironmentGetPlanarObjectInfoResponse>(o);
            if let Some((t, id)) = info {
                (r.object_type, r.id) = (t, id);
            }
            r
        },
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn enums_out_of_range_are_rejected_with_their_field() {
        let e = direction("m1", 4).unwrap_err();
        assert_eq!(e.error_id, ErrorId::ENUM_OUT_OF_RANGE);
        assert!(
            e.message.contains("m1") && e.message.contains("direction = 4"),
            "{}",
            e.message
        );
        assert_eq!(direction("m1", 2).unwrap(), Direction::ShortestWay);
        assert_eq!(
            esg_mode("m1", 0).unwrap_err().error_id,
            ErrorId::ENUM_OUT_OF_RANGE
        );
        assert_eq!(esg_mode("m1", 2).unwrap(), ExternalSetpointMode::Relative);
        assert_eq!(
            reaction("g", 0).unwrap_err().error_id,
            ErrorId::ENUM_OUT_OF_RANGE
        );
        assert_eq!(
            object_kind("g", 3).unwrap_err().error_id,
            ErrorId::ENUM_OUT_OF_RANGE
        );
        assert_eq!(object_kind("g", 1).unwrap(), ObjectKind::Group);
    }

    #[test]
    fn move_c_request_maps_options() {
        let r = MoverMoveCRequest {
            mover: "m1".into(),
            target_position: 20.0,
            direction: 1,
            additional_turns: 2,
            ..Default::default()
        };
        let (cmd, l) = move_c_req(&r).unwrap();
        assert_eq!(l.command, "move_c");
        match cmd {
            PlanarCommand::MoveC {
                options,
                target_position,
                ..
            } => {
                assert_eq!(options.direction, Direction::Positive);
                assert_eq!(options.additional_turns, 2);
                assert_eq!(target_position, 20.0);
            }
            other => panic!("{other:?}"),
        }
        let bad = MoverMoveCRequest { direction: 9, ..r };
        assert_eq!(
            move_c_req(&bad).unwrap_err().error_id,
            ErrorId::ENUM_OUT_OF_RANGE
        );
    }
}
