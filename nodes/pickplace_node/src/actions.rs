//! Actions (pick_and_place.md §18): `~/pick_and_place` = optional `scPar` changes and the
//! `xExecutePickAndPlace` edge, ending when its profile ends; `~/home` = the
//! `xGroupHomeExecute` edge, ending when homing ends. Feedback at the state rate; result Done
//! (SUCCEEDED) / CommandAborted (ABORTED, CANCELED after a cancel) / Error (ABORTED with the
//! id). Cancel of a pick-and-place goal = the engine's `cancel`: `xPathHalt` pulse-and-release,
//! then `xAbort` at standstill.

use crate::cell::{parse_patch, Cell, CellCommand, CellSnapshot};
use crate::services::{finite, label, set_target};
use motion_core::{CommandState, Engine, ExecuteOutputs, Rejection};
use motion_msgs::action::*;
use motion_runtime::cycle::Stamped;
use motion_runtime::{ActionBinding, CommandLabel, NodeShell, ShellError};
use pickplace_engine::PickPlaceCommand;
use ros2_client::ActionTypeName;

fn message(o: &ExecuteOutputs, rejection: Option<&Rejection>) -> String {
    match rejection {
        Some(r) => r.message.clone(),
        None if o.error => Cell::error_text(o.error_id),
        None => String::new(),
    }
}

struct PickAndPlaceAction;

impl ActionBinding<Cell> for PickAndPlaceAction {
    type Goal = PickPlaceExecuteGoal;
    type Result = PickPlaceExecuteResult;
    type Feedback = PickPlaceExecuteFeedback;

    fn action_type_name() -> ActionTypeName {
        PickPlaceExecute::action_type_name()
    }

    fn command(&self, g: &PickPlaceExecuteGoal) -> Result<(CellCommand, CommandLabel), Rejection> {
        let t = set_target(g.set_target)?;
        let target_pose = if g.use_target_pose {
            finite("target_pose", &g.target_pose)?;
            Some(g.target_pose)
        } else {
            None
        };
        let params = parse_patch(&g.params, "params")?;
        let object = if t == 0 {
            "cell".to_string()
        } else {
            format!("cv{t}")
        };
        Ok((
            CellCommand::ExecuteWith {
                set_target: t,
                target_pose,
                params,
            },
            label(&object, "pick_and_place"),
        ))
    }

    fn feedback(
        &self,
        _: &PickPlaceExecuteGoal,
        snap: &Stamped<CellSnapshot>,
        _: CommandState,
    ) -> PickPlaceExecuteFeedback {
        let c = &snap.state.cell;
        PickPlaceExecuteFeedback {
            state: c.state as u8,
            profile_point_passed: c.outputs.profile_point_passed,
            set_path_vel_out: c.outputs.set_path_vel_out,
            synchronised: c.outputs.synchronised,
            in_park_pos: c.outputs.in_park_pos,
            tcp: c.tcp,
        }
    }

    fn result(
        &self,
        _: &PickPlaceExecuteGoal,
        snap: &Stamped<CellSnapshot>,
        end: CommandState,
        rejection: Option<&Rejection>,
    ) -> PickPlaceExecuteResult {
        let o = ExecuteOutputs::from(end);
        PickPlaceExecuteResult {
            done: o.done,
            command_aborted: o.command_aborted,
            error: o.error,
            error_id: o.error_id.0,
            message: message(&o, rejection),
            tcp: snap.state.cell.tcp,
        }
    }
}

struct HomeAction;

impl ActionBinding<Cell> for HomeAction {
    type Goal = PickPlaceHomeGoal;
    type Result = PickPlaceHomeResult;
    type Feedback = PickPlaceHomeFeedback;

    fn action_type_name() -> ActionTypeName {
        PickPlaceHome::action_type_name()
    }

    fn command(&self, _: &PickPlaceHomeGoal) -> Result<(CellCommand, CommandLabel), Rejection> {
        Ok((
            CellCommand::Engine(PickPlaceCommand::GroupHome),
            label("cell", "home"),
        ))
    }

    fn feedback(
        &self,
        _: &PickPlaceHomeGoal,
        snap: &Stamped<CellSnapshot>,
        _: CommandState,
    ) -> PickPlaceHomeFeedback {
        let c = &snap.state.cell;
        PickPlaceHomeFeedback {
            state: c.state as u8,
            act_pos: c.outputs.act_pos,
        }
    }

    fn result(
        &self,
        _: &PickPlaceHomeGoal,
        snap: &Stamped<CellSnapshot>,
        end: CommandState,
        rejection: Option<&Rejection>,
    ) -> PickPlaceHomeResult {
        let o = ExecuteOutputs::from(end);
        PickPlaceHomeResult {
            done: o.done,
            command_aborted: o.command_aborted,
            error: o.error,
            error_id: o.error_id.0,
            message: message(&o, rejection),
            axes_group_homed: snap.state.cell.outputs.axes_group_homed,
        }
    }
}

pub(crate) fn register(shell: &mut NodeShell<Cell>) -> Result<(), ShellError> {
    shell.action("pick_and_place", PickAndPlaceAction)?;
    shell.action("home", HomeAction)?;
    Ok(())
}
