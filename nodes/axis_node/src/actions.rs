//! Motion commands as ROS actions: goal = Execute edge, feedback = Busy/Active/position/
//! velocity at the state rate, result = Done | CommandAborted | Error with ErrorID.
//! Cancel = MC_Halt with the axis defaults (the engine's `cancel`).

use crate::services::{buffer_mode, direction};
use axis_engine::{AxisCommand, AxisEngine, AxisSnapshot, MoveOptions};
use motion_core::{CommandState, ExecuteOutputs, Rejection};
use motion_msgs::action::*;
use motion_runtime::cycle::Stamped;
use motion_runtime::{ActionBinding, CommandLabel, NodeShell, ShellError};
use ros2_client::ActionTypeName;

fn actual(snap: &Stamped<AxisSnapshot>, axis: &str) -> (f64, f64) {
    snap.state.axes.iter().find(|a| a.name == axis).map(|a| (a.act_pos, a.act_velo)).unwrap_or((0.0, 0.0))
}

macro_rules! motion_action {
    ($binding:ident, $action:ident, $goal:ident, $result:ident, $feedback:ident, $decode:expr) => {
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

            fn feedback(&self, g: &$goal, snap: &Stamped<AxisSnapshot>, state: CommandState) -> $feedback {
                let (position, velocity) = actual(snap, &g.axis);
                let o = ExecuteOutputs::from(state);
                $feedback { busy: o.busy, active: o.active, position, velocity }
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
                        None if o.error => <AxisEngine as motion_core::Engine>::error_text(o.error_id),
                        None => String::new(),
                    },
                    position: actual(snap, &g.axis).0,
                }
            }
        }
    };
}

fn label(axis: &str, command: &str) -> CommandLabel {
    CommandLabel { object: axis.to_string(), command: command.to_string() }
}

motion_action!(
    MoveAbsoluteAction,
    MoveAbsolute,
    MoveAbsoluteGoal,
    MoveAbsoluteResult,
    MoveAbsoluteFeedback,
    |g: &MoveAbsoluteGoal| -> Result<(AxisCommand, CommandLabel), Rejection> {
        Ok((
            AxisCommand::MoveAbsolute(axis_engine::MoveAbsolute {
                axis: g.axis.clone(),
                position: g.position,
                velocity: g.velocity,
                acceleration: g.acceleration,
                deceleration: g.deceleration,
                jerk: g.jerk,
                buffer_mode: buffer_mode(g.buffer_mode)?,
                options: MoveOptions::default(),
            }),
            label(&g.axis, "move_absolute"),
        ))
    }
);

motion_action!(
    MoveRelativeAction,
    MoveRelative,
    MoveRelativeGoal,
    MoveRelativeResult,
    MoveRelativeFeedback,
    |g: &MoveRelativeGoal| -> Result<(AxisCommand, CommandLabel), Rejection> {
        Ok((
            AxisCommand::MoveRelative(axis_engine::MoveRelative {
                axis: g.axis.clone(),
                distance: g.distance,
                velocity: g.velocity,
                acceleration: g.acceleration,
                deceleration: g.deceleration,
                jerk: g.jerk,
                buffer_mode: buffer_mode(g.buffer_mode)?,
                options: MoveOptions::default(),
            }),
            label(&g.axis, "move_relative"),
        ))
    }
);

motion_action!(
    MoveVelocityAction,
    MoveVelocity,
    MoveVelocityGoal,
    MoveVelocityResult,
    MoveVelocityFeedback,
    |g: &MoveVelocityGoal| -> Result<(AxisCommand, CommandLabel), Rejection> {
        Ok((
            AxisCommand::MoveVelocity(axis_engine::MoveVelocity {
                axis: g.axis.clone(),
                velocity: g.velocity,
                acceleration: g.acceleration,
                deceleration: g.deceleration,
                jerk: g.jerk,
                direction: direction(g.direction)?,
                buffer_mode: buffer_mode(g.buffer_mode)?,
                options: MoveOptions::default(),
            }),
            label(&g.axis, "move_velocity"),
        ))
    }
);

pub(crate) fn register(shell: &mut NodeShell<AxisEngine>) -> Result<(), ShellError> {
    shell.action("move_absolute", MoveAbsoluteAction)?;
    shell.action("move_relative", MoveRelativeAction)?;
    shell.action("move_velocity", MoveVelocityAction)?;
    Ok(())
}
