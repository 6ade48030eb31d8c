//! PLCopen Part 4 axis groups (plcopen_platform.md §3.2, §5, §12.1) over ROS: per configured
//! group, under `~/groups/<group>/`:
//! - services for the administrative, read and override blocks (`add_axis`, `remove_axis`,
//!   `ungroup_all`, `group_enable` (MCV_GroupEnable), `group_disable`, `group_reset`,
//!   `read_configuration`, `read_status`, `read_error`, `read_actual_position`,
//!   `read_actual_velocity`, `set_override`, `path_select`) and `group_stop` (Execute level:
//!   `execute: false` releases the group's latest MC_GroupStop);
//! - actions `move_linear_absolute`, `move_linear_relative`, `move_path`, `group_halt`
//!   (feedback busy/active/positions; result Done | CommandAborted | Error; cancel =
//!   MC_GroupHalt, the engine's `cancel`), and services of the same names and fields (one
//!   Execute edge; the goal decodes through the service request);
//! - the state topic `~/groups/<group>/state` (`motion_msgs/AxesGroupState`).
//!
//! The group is named by the service path, so requests carry only the FB's inputs.

use crate::services::{buffer_mode, label, respond, Outcome};
use axis_engine::group::{
    AddAxisToGroup, CoordSystem, GroupHalt, GroupSetOverride, GroupStop, MoveLinear,
    MovePath as MovePathCommand, PathSelect, RemoveAxisFromGroup, TransitionMode,
};
use axis_engine::{
    AxisCommand, AxisEngine, AxisSnapshot, GroupCommand, GroupReply, GroupStatus, ReplyValue,
};
use motion_core::{CmdId, CommandState, ExecuteOutputs, Rejection};
use motion_msgs::action::*;
use motion_msgs::deps::builtin_interfaces::msg::Time;
use motion_msgs::msg::AxesGroupState;
use motion_msgs::srv::*;
use motion_runtime::cycle::Stamped;
use motion_runtime::shell::{header, stamp};
use motion_runtime::{ActionBinding, CommandLabel, NodeShell, ShellError};
use ros2_client::{ActionTypeName, Message, ServiceTypeName};
use std::sync::{Arc, Mutex};

/// The group's state as `motion_msgs/AxesGroupState`.
pub fn group_state(s: &GroupStatus, stamp: Time) -> AxesGroupState {
    AxesGroupState {
        header: header(stamp),
        name: s.name.clone(),
        state: s.state as u8,
        constant_velocity: s.constant_velocity,
        accelerating: s.accelerating,
        decelerating: s.decelerating,
        in_position: s.in_position,
        axes: s.axes.clone(),
        idents: s.idents.clone(),
        error_id: s.error_id.0,
        override_factor: s.override_factor,
        path_velocity: s.path_velocity,
        path_acceleration: s.path_acceleration,
        set_position: s.set_position.clone(),
        act_position: s.act_position.clone(),
        path_points: s.path_points as u32,
    }
}

fn coord(raw: u8) -> Result<CoordSystem, Rejection> {
    CoordSystem::from_raw(u32::from(raw))
}

fn transition(raw: u8) -> Result<TransitionMode, Rejection> {
    TransitionMode::from_raw(u32::from(raw))
}

/// A reply that does not carry the value this read expects (never from this engine).
fn unexpected(v: &ReplyValue) -> Rejection {
    Rejection::new(
        motion_core::ErrorId::NOT_RUNNING,
        format!("unexpected reply {v:?}"),
    )
}

/// The group value of a read's reply, or the rejection to answer with.
fn group_value(o: Outcome) -> (Outcome, Option<GroupReply>) {
    match o {
        Ok(r) => match &r.value {
            ReplyValue::Group(g) => {
                let g = g.clone();
                (Ok(r), Some(g))
            }
            v => (Err(unexpected(v)), None),
        },
        Err(e) => (Err(e), None),
    }
}

/// Serves `~/groups/<group>/<fb>`: `decode` screens the request into the group's engine
/// command (a rejection answers at once); `answer` builds the response from the outcome and
/// the simulated time. Tracked instances get their label for `~/command_status`.
fn group_service<Req, Resp, D, A>(
    shell: &mut NodeShell<AxisEngine>,
    group: &str,
    fb: &'static str,
    ty: ServiceTypeName,
    decode: D,
    answer: A,
) -> Result<(), ShellError>
where
    Req: Message + Clone + Send + Sync + 'static,
    Resp: Message + Send + Sync + 'static,
    D: Fn(String, Req) -> Result<GroupCommand, Rejection> + Send + Sync + 'static,
    A: Fn(Outcome, Time) -> Resp + Send + Sync + 'static,
{
    let handle = shell.handle.clone();
    let g = group.to_string();
    let decode = Arc::new(decode);
    let answer = Arc::new(answer);
    shell.service::<Req, Resp, _, _>(&format!("groups/{group}/{fb}"), ty, move |req: Req| {
        let (handle, g) = (handle.clone(), g.clone());
        let (decode, answer) = (decode.clone(), answer.clone());
        async move {
            let o = match decode(g.clone(), req) {
                Err(r) => Err(r),
                Ok(cmd) => {
                    handle
                        .call_labeled(AxisCommand::Group(cmd), label(&g, fb))
                        .await
                }
            };
            answer(o, stamp(&handle.snapshot()))
        }
    })
}

fn register_admin(shell: &mut NodeShell<AxisEngine>, group: &str) -> Result<(), ShellError> {
    group_service(
        shell,
        group,
        "add_axis",
        AxesGroupAddAxis::service_type_name(),
        |group, r: AxesGroupAddAxisRequest| {
            Ok(GroupCommand::AddAxisToGroup(AddAxisToGroup {
                group,
                axis: r.axis,
                ident_in_group: r.ident_in_group,
            }))
        },
        |o, _| respond::<AxesGroupAddAxisResponse>(o),
    )?;
    group_service(
        shell,
        group,
        "remove_axis",
        AxesGroupRemoveAxis::service_type_name(),
        |group, r: AxesGroupRemoveAxisRequest| {
            Ok(GroupCommand::RemoveAxisFromGroup(RemoveAxisFromGroup {
                group,
                axis: r.axis,
            }))
        },
        |o, _| respond::<AxesGroupRemoveAxisResponse>(o),
    )?;
    type Plain = fn(String) -> GroupCommand;
    let plain: [(&'static str, Plain); 4] = [
        ("ungroup_all", |group| GroupCommand::UngroupAllAxes {
            group,
        }),
        ("group_enable", |group| GroupCommand::GroupEnable { group }),
        ("group_disable", |group| GroupCommand::GroupDisable {
            group,
        }),
        ("group_reset", |group| GroupCommand::GroupReset { group }),
    ];
    for (fb, make) in plain {
        group_service(
            shell,
            group,
            fb,
            AxesGroupCommand::service_type_name(),
            move |group, _r: AxesGroupCommandRequest| Ok(make(group)),
            |o, _| respond::<AxesGroupCommandResponse>(o),
        )?;
    }
    group_service(
        shell,
        group,
        "path_select",
        AxesGroupPathSelect::service_type_name(),
        |group, r: AxesGroupPathSelectRequest| {
            Ok(GroupCommand::PathSelect(PathSelect {
                group,
                points: r.points.into_iter().map(|p| p.position).collect(),
            }))
        },
        |o, _| respond::<AxesGroupPathSelectResponse>(o),
    )?;
    group_service(
        shell,
        group,
        "set_override",
        AxesGroupSetOverride::service_type_name(),
        |group, r: AxesGroupSetOverrideRequest| {
            Ok(GroupCommand::GroupSetOverride(GroupSetOverride {
                group,
                enable: r.enable,
                vel_factor: r.vel_factor,
                acc_factor: r.acc_factor,
                jerk_factor: r.jerk_factor,
            }))
        },
        |o, _| {
            let (o, v) = group_value(o);
            AxesGroupSetOverrideResponse {
                enabled: matches!(v, Some(GroupReply::Enabled(true))),
                ..respond(o)
            }
        },
    )
}

fn register_reads(shell: &mut NodeShell<AxisEngine>, group: &str) -> Result<(), ShellError> {
    group_service(
        shell,
        group,
        "read_configuration",
        AxesGroupReadConfiguration::service_type_name(),
        |group, r: AxesGroupReadConfigurationRequest| {
            Ok(GroupCommand::GroupReadConfiguration {
                group,
                ident_in_group: r.ident_in_group,
            })
        },
        |o, _| {
            let (o, v) = group_value(o);
            let list = match v {
                Some(GroupReply::Configuration(l)) => l,
                _ => Vec::new(),
            };
            AxesGroupReadConfigurationResponse {
                axes: list.iter().map(|m| m.0.clone()).collect(),
                idents: list.iter().map(|m| m.1).collect(),
                ..respond(o)
            }
        },
    )?;
    group_service(
        shell,
        group,
        "read_status",
        AxesGroupReadStatus::service_type_name(),
        |group, _r: AxesGroupReadStatusRequest| Ok(GroupCommand::GroupReadStatus { group }),
        |o, t| {
            let (o, v) = group_value(o);
            match v {
                Some(GroupReply::Status(s)) => AxesGroupReadStatusResponse {
                    group_moving: s.group_moving,
                    group_homing: s.group_homing,
                    group_error_stop: s.group_error_stop,
                    group_standby: s.group_standby,
                    group_stopping: s.group_stopping,
                    group_disabled: s.group_disabled,
                    constant_velocity: s.constant_velocity,
                    accelerating: s.accelerating,
                    decelerating: s.decelerating,
                    in_position: s.in_position,
                    status: group_state(&s, t),
                    ..respond(o)
                },
                _ => respond(o),
            }
        },
    )?;
    group_service(
        shell,
        group,
        "read_error",
        AxesGroupReadError::service_type_name(),
        |group, _r: AxesGroupReadErrorRequest| Ok(GroupCommand::GroupReadError { group }),
        |o, _| {
            let (o, v) = group_value(o);
            AxesGroupReadErrorResponse {
                group_error_id: match v {
                    Some(GroupReply::Error(e)) => e.0,
                    _ => 0,
                },
                ..respond(o)
            }
        },
    )?;
    let values = |o: Outcome, _t: Time| {
        let (o, v) = group_value(o);
        AxesGroupReadActualResponse {
            values: match v {
                Some(GroupReply::Values(v)) => v,
                _ => Vec::new(),
            },
            ..respond(o)
        }
    };
    group_service(
        shell,
        group,
        "read_actual_position",
        AxesGroupReadActual::service_type_name(),
        |group, r: AxesGroupReadActualRequest| {
            Ok(GroupCommand::GroupReadActualPosition {
                group,
                coord_system: coord(r.coord_system)?,
            })
        },
        values,
    )?;
    group_service(
        shell,
        group,
        "read_actual_velocity",
        AxesGroupReadActual::service_type_name(),
        |group, r: AxesGroupReadActualRequest| {
            Ok(GroupCommand::GroupReadActualVelocity {
                group,
                coord_system: coord(r.coord_system)?,
            })
        },
        values,
    )
}

/// `~/groups/<group>/group_stop`: `execute = true` is the rising edge of a fresh MC_GroupStop
/// instance; `execute = false` the falling edge of the group's latest one, which releases the
/// group (GroupStopping → GroupStandby once stopped).
fn register_group_stop(shell: &mut NodeShell<AxisEngine>, group: &str) -> Result<(), ShellError> {
    let latest: Arc<Mutex<Option<CmdId>>> = Arc::default();
    let handle = shell.handle.clone();
    let g = group.to_string();
    shell.service::<AxesGroupStopRequest, AxesGroupStopResponse, _, _>(
        &format!("groups/{group}/group_stop"),
        AxesGroupStop::service_type_name(),
        move |r: AxesGroupStopRequest| {
            let (handle, latest, g) = (handle.clone(), latest.clone(), g.clone());
            async move {
                let outcome = if r.execute {
                    let cmd = AxisCommand::Group(GroupCommand::GroupStop(GroupStop {
                        group: g.clone(),
                        deceleration: r.deceleration,
                        jerk: r.jerk,
                    }));
                    let o = handle.call_labeled(cmd, label(&g, "group_stop")).await;
                    if let Ok(reply) = &o {
                        *latest.lock().unwrap_or_else(|e| e.into_inner()) = Some(reply.id);
                    }
                    o
                } else {
                    let id = latest.lock().unwrap_or_else(|e| e.into_inner()).take();
                    match id {
                        Some(id) => {
                            handle
                                .call(AxisCommand::SetExecute { id, execute: false })
                                .await
                        }
                        // No MC_GroupStop instance is held: a falling edge changes nothing.
                        None => Ok(axis_engine::AxisReply {
                            id: CmdId(0),
                            value: ReplyValue::None,
                            tracked: false,
                        }),
                    }
                };
                respond::<AxesGroupStopResponse>(outcome)
            }
        },
    )
}

fn group_of<'a>(snap: &'a Stamped<AxisSnapshot>, group: &str) -> Option<&'a GroupStatus> {
    snap.state.groups.iter().find(|g| g.name == group)
}

fn decode_move_linear_absolute(
    group: String,
    g: MoveLinearAbsoluteRequest,
) -> Result<GroupCommand, Rejection> {
    Ok(GroupCommand::MoveLinearAbsolute(MoveLinear {
        group,
        position: g.position,
        velocity: g.velocity,
        acceleration: g.acceleration,
        deceleration: g.deceleration,
        jerk: g.jerk,
        coord_system: coord(g.coord_system)?,
        buffer_mode: buffer_mode(g.buffer_mode)?,
        transition_mode: transition(g.transition_mode)?,
    }))
}

fn decode_move_linear_relative(
    group: String,
    g: MoveLinearRelativeRequest,
) -> Result<GroupCommand, Rejection> {
    Ok(GroupCommand::MoveLinearRelative(MoveLinear {
        group,
        position: g.distance,
        velocity: g.velocity,
        acceleration: g.acceleration,
        deceleration: g.deceleration,
        jerk: g.jerk,
        coord_system: coord(g.coord_system)?,
        buffer_mode: buffer_mode(g.buffer_mode)?,
        transition_mode: transition(g.transition_mode)?,
    }))
}

fn decode_move_path(group: String, g: MovePathRequest) -> Result<GroupCommand, Rejection> {
    Ok(GroupCommand::MovePath(MovePathCommand {
        group,
        velocity: g.velocity,
        acceleration: g.acceleration,
        deceleration: g.deceleration,
        jerk: g.jerk,
        coord_system: coord(g.coord_system)?,
        buffer_mode: buffer_mode(g.buffer_mode)?,
    }))
}

fn decode_group_halt(group: String, g: AxesGroupHaltRequest) -> Result<GroupCommand, Rejection> {
    Ok(GroupCommand::GroupHalt(GroupHalt {
        group,
        deceleration: g.deceleration,
        jerk: g.jerk,
        buffer_mode: buffer_mode(g.buffer_mode)?,
    }))
}

/// A group motion FB served under `~/groups/<group>/<fb>` both as an action and as a
/// service of the same name and fields (the goal decodes through the service request).
macro_rules! group_action {
    ($binding:ident, $action:ident, $goal:ident, $result:ident, $feedback:ident, $response:ident, $fb:literal, $decode:expr) => {
        struct $binding {
            group: String,
        }

        impl $binding {
            fn register(shell: &mut NodeShell<AxisEngine>, group: &str) -> Result<(), ShellError> {
                group_service(
                    shell,
                    group,
                    $fb,
                    motion_msgs::srv::$action::service_type_name(),
                    $decode,
                    |o, _| respond::<$response>(o),
                )?;
                shell.action(
                    &format!("groups/{group}/{}", $fb),
                    $binding {
                        group: group.to_string(),
                    },
                )
            }
        }

        impl ActionBinding<AxisEngine> for $binding {
            type Goal = $goal;
            type Result = $result;
            type Feedback = $feedback;

            fn action_type_name() -> ActionTypeName {
                motion_msgs::action::$action::action_type_name()
            }

            fn instance(&self, g: &$goal) -> Option<String> {
                Some(g.fb_instance.clone())
            }

            // The goal decodes through the service request's path.
            fn command(&self, g: &$goal) -> Result<(AxisCommand, CommandLabel), Rejection> {
                Ok((
                    AxisCommand::Group($decode(self.group.clone(), g.into())?),
                    label(&self.group, $fb),
                ))
            }

            fn feedback(
                &self,
                _g: &$goal,
                snap: &Stamped<AxisSnapshot>,
                state: CommandState,
            ) -> $feedback {
                let o = ExecuteOutputs::from(state);
                let s = group_of(snap, &self.group);
                $feedback {
                    busy: o.busy,
                    active: o.active,
                    positions: s.map(|s| s.act_position.clone()).unwrap_or_default(),
                    path_velocity: s.map_or(0.0, |s| s.path_velocity),
                    order_id: 0,
                    group_state: s.map_or(0, |s| s.state as u8),
                }
            }

            fn feedback_of(
                &self,
                g: &$goal,
                id: CmdId,
                snap: &Stamped<AxisSnapshot>,
                state: CommandState,
            ) -> $feedback {
                $feedback {
                    order_id: crate::actions::order_id(snap, id),
                    ..self.feedback(g, snap, state)
                }
            }

            fn result(
                &self,
                _g: &$goal,
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
                    message: match rejection {
                        Some(r) => r.message.clone(),
                        None if o.error => {
                            <AxisEngine as motion_core::Engine>::error_text(o.error_id)
                        }
                        None => String::new(),
                    },
                    positions: group_of(snap, &self.group)
                        .map(|s| s.act_position.clone())
                        .unwrap_or_default(),
                }
            }
        }
    };
}

group_action!(
    MoveLinearAbsoluteAction,
    MoveLinearAbsolute,
    MoveLinearAbsoluteGoal,
    MoveLinearAbsoluteResult,
    MoveLinearAbsoluteFeedback,
    MoveLinearAbsoluteResponse,
    "move_linear_absolute",
    decode_move_linear_absolute
);

group_action!(
    MoveLinearRelativeAction,
    MoveLinearRelative,
    MoveLinearRelativeGoal,
    MoveLinearRelativeResult,
    MoveLinearRelativeFeedback,
    MoveLinearRelativeResponse,
    "move_linear_relative",
    decode_move_linear_relative
);

group_action!(
    MovePathAction,
    MovePath,
    MovePathGoal,
    MovePathResult,
    MovePathFeedback,
    MovePathResponse,
    "move_path",
    decode_move_path
);

group_action!(
    GroupHaltAction,
    AxesGroupHalt,
    AxesGroupHaltGoal,
    AxesGroupHaltResult,
    AxesGroupHaltFeedback,
    AxesGroupHaltResponse,
    "group_halt",
    decode_group_halt
);

/// Registers everything of the configured groups (names in configuration order, as in the
/// snapshot's `groups`).
pub(crate) fn register(
    shell: &mut NodeShell<AxisEngine>,
    groups: &[String],
) -> Result<(), ShellError> {
    for (i, group) in groups.iter().enumerate() {
        register_admin(shell, group)?;
        register_reads(shell, group)?;
        register_group_stop(shell, group)?;
        MoveLinearAbsoluteAction::register(shell, group)?;
        MoveLinearRelativeAction::register(shell, group)?;
        MovePathAction::register(shell, group)?;
        GroupHaltAction::register(shell, group)?;
        shell.state_publisher(
            &format!("~/groups/{group}/state"),
            AxesGroupState::type_name(),
            move |s| match s.state.groups.get(i) {
                Some(gs) => group_state(gs, stamp(s)),
                None => AxesGroupState::default(),
            },
        )?;
    }
    Ok(())
}
