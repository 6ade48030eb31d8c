//! The planar objects in one place ([`Objects`]: environment, parts, movers, groups;
//! xplanar.md §1–§3, §5), with command admission, free movement and the no-overlap guard.
//! Commands are admitted at once (no queue, §2.4): a new command aborts the active command of
//! its axis domain. Where a mover's motion touches a track, the objects call the track
//! subsystem through [`TrackHooks`] (implemented by the tracks, wired in `crate::engine`); they do not
//! know its state.
//!
//! Children by concept: `records` (the object records), `basics` (construction, lookups,
//! admission checks, collisions, snapshots), `dispatch`, `environment`, `movers` (the
//! commands), `cycle` (one cycle of the plane), `track_hooks` (their way to the tracks;
//! the tracks' way to the movers, `MoverDrive`, is implemented in `crate::engine`).

use crate::admission::{admissible, AdmissionContext, CommandKind};
use crate::command::{ObjectKind, PlanarCommand};
use crate::config::PlanarConfig;
use crate::errors::*;
use crate::geometry::{boundary_elements, tiles_overlap, ConvexPolygon, V2};
use crate::guard::Grid;
use crate::motion::{in_c_window, modulo_target, range_in_one_window, Axis1, Kin2, PathPlan};
use crate::snapshot::*;
use crate::state::{Accepted, PlanarStateMachine, Timing};
use crate::types::*;
use motion_core::refill::{refill_vec, reuse_opt_str, reuse_str, reuse_strs};
use motion_core::trajectory::State1;
use motion_core::{CmdId, CommandEvent, CommandState, ErrorId, Rejection};
use std::collections::HashMap;

pub(crate) use records::*;
pub(crate) use track_hooks::TrackHooks;

/// The planar objects (environment, parts, movers, groups; xplanar.md §1) in one place, with
/// what their commands share: timing, ids, pending events, the no-overlap guard's grid.
pub struct Objects {
    pub(crate) timing: Timing,
    pub(crate) cycle_time: f64,
    pub(crate) part_move_time: f64,
    pub(crate) esg_timeout_cycles: u32,
    pub(crate) time: f64,
    pub(crate) coordinate_systems: Vec<u32>,
    pub(crate) env: Environment,
    pub(crate) parts: Vec<Part>,
    pub(crate) movers: Vec<Mover>,
    pub(crate) groups: Vec<Group>,
    pub(crate) mover_idx: HashMap<String, usize>,
    pub(crate) group_idx: HashMap<String, usize>,
    pub(crate) part_idx: HashMap<String, usize>,
    pub(crate) next_id: u64,
    /// Status changes produced by `command`, reported in the next `step`.
    pub(crate) pending: Vec<CommandEvent>,
    pub(crate) grid: Grid,
    pub(crate) scratch: Vec<u32>,
    pub(crate) last_object_info: PlanarObjectInfo,
    /// False while every mover is on one track (the guard grid is skipped, see step_motion).
    pub(crate) guard_full: bool,
}

pub(crate) fn ev(events: &mut Vec<CommandEvent>, id: CmdId, state: CommandState) {
    events.push(CommandEvent { id, state });
}

/// A motion command of mover `m` takes over: its warning (W_DYNAMICS_REDUCED when the
/// dynamics had to be reduced), Active, and the reply carrying that warning.
pub(crate) fn started(
    events: &mut Vec<CommandEvent>,
    m: &mut Mover,
    id: CmdId,
    reduced: bool,
) -> Result<PlanarReply, Rejection> {
    m.warning = if reduced {
        W_DYNAMICS_REDUCED
    } else {
        ErrorId::NONE
    };
    ev(events, id, CommandState::Active);
    Ok(PlanarReply {
        id,
        warning_id: m.warning,
        value: ReplyValue::None,
    })
}

pub(crate) fn end(events: &mut Vec<CommandEvent>, slot: &mut Option<CmdId>, state: CommandState) {
    if let Some(id) = slot.take() {
        ev(events, id, state);
    }
}

pub(crate) fn traj_err(who: &str, e: motion_core::trajectory::TrajectoryError) -> Rejection {
    reject(E_INVALID_PARAMETER, format!("{who}: {e}"))
}

mod basics;
mod cycle;
mod dispatch;
mod environment;
mod movers;
mod records;
mod track_hooks;
