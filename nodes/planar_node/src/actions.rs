//! Mover motions as ROS actions (xplanar.md §9): goal = Execute edge, feedback = Busy/Active
//! and the mover's pose at the state rate, result = Done | CommandAborted | Error with the
//! error id. Cancel = the mover's Halt with its default dynamics (the engine's `cancel`);
//! a command superseded by another one on the same domain ends CommandAborted (§2.4).

use crate::services::{move_a_goal, move_b_goal, move_c_goal, move_to_position_goal, move_z_goal};
use motion_core::{CommandState, Engine, ErrorId, ExecuteOutputs, Rejection};
use motion_msgs::action::*;
use motion_runtime::cycle::Stamped;
use motion_runtime::{ActionBinding, CommandLabel, NodeShell, ShellError};
use planar_engine::{MoverVector, PlanarCommand, PlanarEngine, PlanarSnapshot};
use ros2_client::ActionTypeName;

/// The mover's pose (x, y, z [mm], a, b, c [deg]); zeros for an unknown mover.
pub(crate) fn pose(snap: &Stamped<PlanarSnapshot>, mover: &str) -> MoverVector {
    snap.state
        .mover(mover)
        .map(|m| m.set_pos)
        .unwrap_or_default()
}

/// objectInfo of an E_COLLISION end (§6.1): from the rejection at the edge, or the mover's
/// own record of its guard stop; (0, 0) otherwise.
pub(crate) fn object_info(
    snap: &Stamped<PlanarSnapshot>,
    mover: &str,
    error_id: ErrorId,
    rejection: Option<&Rejection>,
) -> (u16, u32) {
    if let Some(o) = rejection.and_then(|r| r.object) {
        return (o.kind, o.id);
    }
    match snap.state.mover(mover) {
        Some(m) if error_id == planar_engine::errors::E_COLLISION => {
            (m.object_info.object_type as u16, m.object_info.id)
        }
        _ => (0, 0),
    }
}

macro_rules! mover_action {
    ($binding:ident, $action:ident, $goal:ident, $result:ident, $feedback:ident, $decode:path) => {
        struct $binding;

        impl ActionBinding<PlanarEngine> for $binding {
            type Goal = $goal;
            type Result = $result;
            type Feedback = $feedback;

            fn action_type_name() -> ActionTypeName {
                $action::action_type_name()
            }

            fn command(&self, g: &$goal) -> Result<(PlanarCommand, CommandLabel), Rejection> {
                $decode(g)
            }

            fn feedback(
                &self,
                g: &$goal,
                snap: &Stamped<PlanarSnapshot>,
                state: CommandState,
            ) -> $feedback {
                let p = pose(snap, &g.mover);
                let o = ExecuteOutputs::from(state);
                $feedback {
                    busy: o.busy,
                    active: o.active,
                    x: p.x,
                    y: p.y,
                    z: p.z,
                    a: p.a,
                    b: p.b,
                    c: p.c,
                }
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
                let (object_type, object_id) = object_info(snap, &g.mover, o.error_id, rejection);
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
                }
            }
        }
    };
}

mover_action!(
    MoveToPositionAction,
    MoverMoveToPosition,
    MoverMoveToPositionGoal,
    MoverMoveToPositionResult,
    MoverMoveToPositionFeedback,
    move_to_position_goal
);
mover_action!(
    MoveZAction,
    MoverMoveZ,
    MoverMoveZGoal,
    MoverMoveZResult,
    MoverMoveZFeedback,
    move_z_goal
);
mover_action!(
    MoveAAction,
    MoverMoveA,
    MoverMoveAGoal,
    MoverMoveAResult,
    MoverMoveAFeedback,
    move_a_goal
);
mover_action!(
    MoveBAction,
    MoverMoveB,
    MoverMoveBGoal,
    MoverMoveBResult,
    MoverMoveBFeedback,
    move_b_goal
);
mover_action!(
    MoveCAction,
    MoverMoveC,
    MoverMoveCGoal,
    MoverMoveCResult,
    MoverMoveCFeedback,
    move_c_goal
);

pub(crate) fn register(shell: &mut NodeShell<PlanarEngine>) -> Result<(), ShellError> {
    shell.action("mover_move_to_position", MoveToPositionAction)?;
    shell.action("mover_move_z", MoveZAction)?;
    shell.action("mover_move_a", MoveAAction)?;
    shell.action("mover_move_b", MoveBAction)?;
    shell.action("mover_move_c", MoveCAction)?;
    Ok(())
}
