//! Motion commands as ROS actions: goal = Execute edge, feedback = Busy/Active/position/
//! velocity, the ISG order number and the axis state at the state rate, result = Done |
//! CommandAborted | Error with ErrorID.
//! Cancel = MC_Halt with the axis defaults (the engine's `cancel`).

use axis_engine::{AxisCommand, AxisEngine, AxisReply, AxisSnapshot, FbOutputs, ReplyValue};
use motion_core::{CmdId, CommandState, ExecuteOutputs, Rejection};
use motion_msgs::action::*;
use motion_runtime::cycle::Stamped;
use motion_runtime::{ActionBinding, CommandLabel, NodeShell, ShellError};
use ros2_client::ActionTypeName;

fn actual(snap: &Stamped<AxisSnapshot>, axis: &str) -> (f64, f64) {
    snap.state
        .axis(axis)
        .map(|a| (a.act_pos, a.act_velo))
        .unwrap_or((0.0, 0.0))
}

/// MC_AxisStates of `axis` in the snapshot.
fn axis_state(snap: &Stamped<AxisSnapshot>, axis: &str) -> u8 {
    snap.state.axis(axis).map_or(0, |a| a.motion_state as u8)
}

/// The ISG order number of command `id` while it controls or is buffered on an axis
/// (`isg_mcp`), else 0.
pub(crate) fn order_id(snap: &Stamped<AxisSnapshot>, id: CmdId) -> u32 {
    snap.state
        .platform
        .orders
        .iter()
        .find(|o| o.0 == id.0)
        .map_or(0, |o| o.1)
}

/// The Done-type flag of an instance's outputs (`~/get_outputs` data), for actions that
/// succeed while their command runs on.
fn flag_reached(reply: &AxisReply, flag: fn(&FbOutputs) -> bool) -> bool {
    matches!(&reply.value, ReplyValue::Outputs(o) if flag(&o.outputs))
}

macro_rules! motion_action {
    ($binding:ident, $action:ident, $goal:ident, $result:ident, $feedback:ident, $decode:expr) => {
        motion_action!($binding, $action, $goal, $result, $feedback, $decode, axis);
    };
    ($binding:ident, $action:ident, $goal:ident, $result:ident, $feedback:ident, $decode:expr, $axis:ident) => {
        motion_action!($binding, $action, $goal, $result, $feedback, $decode, $axis, None);
    };
    ($binding:ident, $action:ident, $goal:ident, $result:ident, $feedback:ident, $decode:expr, $axis:ident, $reached:expr) => {
        struct $binding;

        impl ActionBinding<AxisEngine> for $binding {
            type Goal = $goal;
            type Result = $result;
            type Feedback = $feedback;

            fn action_type_name() -> ActionTypeName {
                $action::action_type_name()
            }

            fn command(&self, g: &$goal) -> Result<(AxisCommand, CommandLabel), Rejection> {
                #[allow(clippy::redundant_closure_call)]
                ($decode)(g)
            }

            fn instance(&self, g: &$goal) -> Option<String> {
                Some(g.fb_instance.clone())
            }

            fn reached_query(&self, id: CmdId) -> Option<AxisCommand> {
                let flag: Option<fn(&FbOutputs) -> bool> = $reached;
                flag.map(|_| AxisCommand::ReadFbOutputs { id })
            }

            fn reached(&self, reply: &AxisReply) -> bool {
                let flag: Option<fn(&FbOutputs) -> bool> = $reached;
                flag.is_some_and(|f| flag_reached(reply, f))
            }

            fn feedback(
                &self,
                g: &$goal,
                snap: &Stamped<AxisSnapshot>,
                state: CommandState,
            ) -> $feedback {
                let (position, velocity) = actual(snap, &g.$axis);
                let o = ExecuteOutputs::from(state);
                $feedback {
                    busy: o.busy,
                    active: o.active,
                    position,
                    velocity,
                    order_id: 0,
                    axis_state: axis_state(snap, &g.$axis),
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
                    order_id: order_id(snap, id),
                    ..self.feedback(g, snap, state)
                }
            }

            fn result(
                &self,
                g: &$goal,
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
                    position: actual(snap, &g.$axis).0,
                }
            }
        }
    };
}

motion_action!(
    MoveAbsoluteAction,
    MoveAbsolute,
    MoveAbsoluteGoal,
    MoveAbsoluteResult,
    MoveAbsoluteFeedback,
    |g: &MoveAbsoluteGoal| -> Result<(AxisCommand, CommandLabel), Rejection> {
        // The goal is the service request without the ST_MoveOptions: one decoding path.
        crate::services::decode_move_absolute(g.into())
    }
);

motion_action!(
    MoveRelativeAction,
    MoveRelative,
    MoveRelativeGoal,
    MoveRelativeResult,
    MoveRelativeFeedback,
    |g: &MoveRelativeGoal| -> Result<(AxisCommand, CommandLabel), Rejection> {
        crate::services::decode_move_relative(g.into())
    }
);

motion_action!(
    MoveVelocityAction,
    MoveVelocity,
    MoveVelocityGoal,
    MoveVelocityResult,
    MoveVelocityFeedback,
    |g: &MoveVelocityGoal| -> Result<(AxisCommand, CommandLabel), Rejection> {
        crate::services::decode_move_velocity(g.into())
    },
    axis,
    Some(|o: &FbOutputs| o.in_velocity)
);

motion_action!(
    MoveModuloAction,
    MoveModulo,
    MoveModuloGoal,
    MoveModuloResult,
    MoveModuloFeedback,
    |g: &MoveModuloGoal| -> Result<(AxisCommand, CommandLabel), Rejection> {
        crate::fbs::decode_move_modulo(g.into())
    }
);

motion_action!(
    JogAction,
    Jog,
    JogGoal,
    JogResult,
    JogFeedback,
    |g: &JogGoal| -> Result<(AxisCommand, CommandLabel), Rejection> {
        let mode = axis_engine::JogMode::from_raw(u32::from(g.mode))?;
        if !(g.jog_forward || g.jog_backwards) {
            return Err(Rejection::new(
                motion_core::ErrorId::VALUE_OUT_OF_RANGE,
                format!(
                    "axis '{}': MC_Jog goal without a button (jog_forward or jog_backwards)",
                    g.axis
                ),
            ));
        }
        let r: motion_msgs::srv::JogRequest = g.into();
        Ok((
            crate::jog::jog_fb(&r, mode, g.jog_forward, g.jog_backwards),
            crate::services::label(&g.axis, "jog"),
        ))
    }
);

motion_action!(
    HaltAction,
    Halt,
    HaltGoal,
    HaltResult,
    HaltFeedback,
    |g: &HaltGoal| -> Result<(AxisCommand, CommandLabel), Rejection> {
        crate::services::decode_halt(g.into())
    }
);

motion_action!(
    HomeAction,
    Home,
    HomeGoal,
    HomeResult,
    HomeFeedback,
    |g: &HomeGoal| -> Result<(AxisCommand, CommandLabel), Rejection> {
        crate::fbs::decode_home(g.into())
    }
);

// Succeeds at InGear: MC_GearIn's Done-type output, which the engine reports as the
// instance's Done (the cycle after the edge, §4.12.1). Feedback and result show the slave.
motion_action!(
    GearInAction,
    GearIn,
    GearInGoal,
    GearInResult,
    GearInFeedback,
    |g: &GearInGoal| -> Result<(AxisCommand, CommandLabel), Rejection> {
        crate::fbs::decode_gear_in(g.into())
    },
    slave
);

motion_action!(
    MoveSuperImposedAction,
    MoveSuperImposed,
    MoveSuperImposedGoal,
    MoveSuperImposedResult,
    MoveSuperImposedFeedback,
    |g: &MoveSuperImposedGoal| -> Result<(AxisCommand, CommandLabel), Rejection> {
        crate::fbs::decode_move_superimposed(g.into())
    }
);

motion_action!(
    MoveContinuousAbsoluteAction,
    MoveContinuousAbsolute,
    MoveContinuousAbsoluteGoal,
    MoveContinuousAbsoluteResult,
    MoveContinuousAbsoluteFeedback,
    |g: &MoveContinuousAbsoluteGoal| -> Result<(AxisCommand, CommandLabel), Rejection> {
        crate::fbs::decode_move_continuous_absolute(g.into())
    },
    axis,
    Some(|o: &FbOutputs| o.in_end_velocity)
);

motion_action!(
    MoveContinuousRelativeAction,
    MoveContinuousRelative,
    MoveContinuousRelativeGoal,
    MoveContinuousRelativeResult,
    MoveContinuousRelativeFeedback,
    |g: &MoveContinuousRelativeGoal| -> Result<(AxisCommand, CommandLabel), Rejection> {
        crate::fbs::decode_move_continuous_relative(g.into())
    },
    axis,
    Some(|o: &FbOutputs| o.in_end_velocity)
);

motion_action!(
    TorqueControlAction,
    TorqueControl,
    TorqueControlGoal,
    TorqueControlResult,
    TorqueControlFeedback,
    |g: &TorqueControlGoal| -> Result<(AxisCommand, CommandLabel), Rejection> {
        crate::fbs::decode_torque_control(g.into())
    },
    axis,
    Some(|o: &FbOutputs| o.in_torque)
);

// MC_PhasingAbsolute/Relative/HaltPhasing (§4.13): succeed at Done; feedback and result show
// the slave; cancel = the engine's cancel (MC_HaltPhasing for the phasing FBs).
motion_action!(
    PhasingAbsoluteAction,
    PhasingAbsolute,
    PhasingAbsoluteGoal,
    PhasingAbsoluteResult,
    PhasingAbsoluteFeedback,
    |g: &PhasingAbsoluteGoal| -> Result<(AxisCommand, CommandLabel), Rejection> {
        crate::extensions::decode_phasing_absolute(g.into())
    },
    slave
);

motion_action!(
    PhasingRelativeAction,
    PhasingRelative,
    PhasingRelativeGoal,
    PhasingRelativeResult,
    PhasingRelativeFeedback,
    |g: &PhasingRelativeGoal| -> Result<(AxisCommand, CommandLabel), Rejection> {
        crate::extensions::decode_phasing_relative(g.into())
    },
    slave
);

motion_action!(
    HaltPhasingAction,
    HaltPhasing,
    HaltPhasingGoal,
    HaltPhasingResult,
    HaltPhasingFeedback,
    |g: &HaltPhasingGoal| -> Result<(AxisCommand, CommandLabel), Rejection> {
        crate::extensions::decode_halt_phasing(g.into())
    },
    slave
);

pub(crate) fn register(shell: &mut NodeShell<AxisEngine>) -> Result<(), ShellError> {
    shell.action("move_continuous_absolute", MoveContinuousAbsoluteAction)?;
    shell.action("move_continuous_relative", MoveContinuousRelativeAction)?;
    shell.action("torque_control", TorqueControlAction)?;
    shell.action("move_absolute", MoveAbsoluteAction)?;
    shell.action("move_relative", MoveRelativeAction)?;
    shell.action("move_velocity", MoveVelocityAction)?;
    shell.action("move_modulo", MoveModuloAction)?;
    shell.action("halt", HaltAction)?;
    shell.action("jog", JogAction)?;
    shell.action("home", HomeAction)?;
    shell.action("gear_in", GearInAction)?;
    shell.action("move_superimposed", MoveSuperImposedAction)?;
    shell.action("phasing_absolute", PhasingAbsoluteAction)?;
    shell.action("phasing_relative", PhasingRelativeAction)?;
    shell.action("halt_phasing", HaltPhasingAction)?;
    Ok(())
}
