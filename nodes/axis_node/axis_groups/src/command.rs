//! PLCopen Part 4 FB calls on axis groups (plcopen_platform.md §3.2) and their replies.
//!
//! One [`GroupCommand`] = one FB call (Execute rising edge of a fresh instance, or one call of
//! an Enable-type/read FB with its current inputs). Groups and axes are addressed by their
//! configured names; position arrays are ordered by IdentInGroup (the group's member order).

use crate::GroupState;
use motion_core::{ErrorId, Rejection};
use serde::{Deserialize, Serialize};
use single_axis::inputs::BufferMode;

/// `MC_CoordSystem`: no kinematic transformation is implemented (MC_SetKinTransform* is not
/// offered), so ACS = MCS = PCS.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum CoordSystem {
    /// ACS (1, default): axis coordinate system.
    #[default]
    Acs = 1,
    /// MCS (2): machine coordinate system (identity here).
    Mcs = 2,
    /// PCS (3): product coordinate system (identity here).
    Pcs = 3,
}

impl CoordSystem {
    /// From the raw number; anything else → `ENUM_OUT_OF_RANGE`.
    pub fn from_raw(value: u32) -> Result<Self, Rejection> {
        match value {
            1 => Ok(CoordSystem::Acs),
            2 => Ok(CoordSystem::Mcs),
            3 => Ok(CoordSystem::Pcs),
            _ => Err(Rejection::new(
                ErrorId::ENUM_OUT_OF_RANGE,
                format!("CoordSystem = {value} is not a valid CoordSystem (1 ACS, 2 MCS, 3 PCS)"),
            )),
        }
    }
}

/// `MC_TransitionMode` (Part 4). Only TMNone is implemented (blending between segments is
/// disabled, §3.2 proposal); the others are refused with 4905.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum TransitionMode {
    /// TMNone (0, default): stop between segments.
    #[default]
    None = 0,
    /// TMStartVelocity (1).
    StartVelocity = 1,
    /// TMConstantVelocity (2).
    ConstantVelocity = 2,
    /// TMCornerDistance (3).
    CornerDistance = 3,
    /// TMMaxCornerDeviation (4).
    MaxCornerDeviation = 4,
}

impl TransitionMode {
    /// From the raw number; anything else → `ENUM_OUT_OF_RANGE`.
    pub fn from_raw(value: u32) -> Result<Self, Rejection> {
        Ok(match value {
            0 => TransitionMode::None,
            1 => TransitionMode::StartVelocity,
            2 => TransitionMode::ConstantVelocity,
            3 => TransitionMode::CornerDistance,
            4 => TransitionMode::MaxCornerDeviation,
            _ => {
                return Err(Rejection::new(
                    ErrorId::ENUM_OUT_OF_RANGE,
                    format!("TransitionMode = {value} is not a valid TransitionMode (0..4)"),
                ))
            }
        })
    }
}

/// MC_AddAxisToGroup.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AddAxisToGroup {
    /// AxesGroup.
    pub group: String,
    /// Axis.
    pub axis: String,
    /// IdentInGroup (≥ 1, unique in the group); 0 = the next free one.
    pub ident_in_group: u32,
}

/// MC_RemoveAxisFromGroup (the axis is named instead of its IdentInGroup).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RemoveAxisFromGroup {
    /// AxesGroup.
    pub group: String,
    /// The member axis to remove.
    pub axis: String,
}

/// MC_MoveLinearAbsolute / MC_MoveLinearRelative: a straight line in axis space, jerk-limited
/// along the path; no member axis exceeds its own MaxVelocity/Acc/Dec/Jerk.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MoveLinear {
    /// AxesGroup.
    pub group: String,
    /// Position (absolute) or Distance (relative), one value per member in IdentInGroup
    /// order \[u\].
    pub position: Vec<f64>,
    /// Velocity along the path (> 0) \[u/s\].
    pub velocity: f64,
    /// Acceleration along the path (0 = the largest the members allow) \[u/s²\].
    pub acceleration: f64,
    /// Deceleration along the path (0 = the largest the members allow) \[u/s²\].
    pub deceleration: f64,
    /// Jerk along the path (0 = the largest the members allow) \[u/s³\].
    pub jerk: f64,
    /// CoordSystem.
    pub coord_system: CoordSystem,
    /// BufferMode: only MC_Aborting (others → 4905, ISG has no BufferMode).
    pub buffer_mode: BufferMode,
    /// TransitionMode: only TMNone (others → 4905).
    pub transition_mode: TransitionMode,
}

/// MC_GroupHalt: path-true stop; the group stays movable (GroupMoving → GroupStandby at Done).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GroupHalt {
    /// AxesGroup.
    pub group: String,
    /// Deceleration along the path (0 = the largest the members allow) \[u/s²\].
    pub deceleration: f64,
    /// Jerk along the path (0 = the largest the members allow) \[u/s³\].
    pub jerk: f64,
    /// BufferMode: only MC_Aborting.
    pub buffer_mode: BufferMode,
}

/// MC_GroupStop: path-true stop; the group stays GroupStopping until Done and Execute FALSE
/// (`AxisCommand::SetExecute { execute: false }`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GroupStop {
    /// AxesGroup.
    pub group: String,
    /// Deceleration along the path (0 = the largest the members allow) \[u/s²\].
    pub deceleration: f64,
    /// Jerk along the path (0 = the largest the members allow) \[u/s³\].
    pub jerk: f64,
}

/// MC_GroupSetOverride (Enable-type: one call with the current inputs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GroupSetOverride {
    /// AxesGroup.
    pub group: String,
    /// Enable: FALSE keeps the last factor (PLCopen).
    pub enable: bool,
    /// VelFactor in [0, 1] (0 = path-true stop, the move stays active).
    pub vel_factor: f64,
    /// AccFactor in [0, 1] (checked, not applied).
    pub acc_factor: f64,
    /// JerkFactor in [0, 1] (checked, not applied).
    pub jerk_factor: f64,
}

/// MC_PathSelect (proposal §3.2): loads a polyline of absolute group positions.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PathSelect {
    /// AxesGroup.
    pub group: String,
    /// Path points, each one value per member in IdentInGroup order \[u\].
    pub points: Vec<Vec<f64>>,
}

/// MC_MovePath (proposal §3.2): runs the selected polyline, blending disabled (rest at every
/// point); Done at the last point.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MovePath {
    /// AxesGroup.
    pub group: String,
    /// Velocity along the path (> 0) \[u/s\].
    pub velocity: f64,
    /// Acceleration (0 = the largest the members allow) \[u/s²\].
    pub acceleration: f64,
    /// Deceleration (0 = the largest the members allow) \[u/s²\].
    pub deceleration: f64,
    /// Jerk (0 = the largest the members allow) \[u/s³\].
    pub jerk: f64,
    /// CoordSystem.
    pub coord_system: CoordSystem,
    /// BufferMode: only MC_Aborting.
    pub buffer_mode: BufferMode,
}

/// One Part 4 FB call.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum GroupCommand {
    /// MC_AddAxisToGroup.
    AddAxisToGroup(AddAxisToGroup),
    /// MC_RemoveAxisFromGroup.
    RemoveAxisFromGroup(RemoveAxisFromGroup),
    /// MC_UngroupAllAxes.
    UngroupAllAxes {
        /// AxesGroup.
        group: String,
    },
    /// MC_GroupReadConfiguration: reply [`GroupReply::Configuration`].
    GroupReadConfiguration {
        /// AxesGroup.
        group: String,
        /// IdentInGroup; 0 = all members.
        ident_in_group: u32,
    },
    /// MCV_GroupEnable (vendor/simulator extension: MC_GroupEnable is not implemented).
    GroupEnable {
        /// AxesGroup.
        group: String,
    },
    /// MC_GroupDisable.
    GroupDisable {
        /// AxesGroup.
        group: String,
    },
    /// MC_GrpReset (MC_GroupReset).
    GroupReset {
        /// AxesGroup.
        group: String,
    },
    /// MC_GroupReadStatus: reply [`GroupReply::Status`].
    GroupReadStatus {
        /// AxesGroup.
        group: String,
    },
    /// MC_GroupReadError: reply [`GroupReply::Error`].
    GroupReadError {
        /// AxesGroup.
        group: String,
    },
    /// MC_GroupReadActualPosition: reply [`GroupReply::Values`].
    GroupReadActualPosition {
        /// AxesGroup.
        group: String,
        /// CoordSystem.
        coord_system: CoordSystem,
    },
    /// MC_GroupReadActualVelocity: reply [`GroupReply::Values`] (marked * in the ISG
    /// catalogue: refused with 4905 in `isg_mcp`).
    GroupReadActualVelocity {
        /// AxesGroup.
        group: String,
        /// CoordSystem.
        coord_system: CoordSystem,
    },
    /// MC_GroupSetOverride.
    GroupSetOverride(GroupSetOverride),
    /// MC_MoveLinearAbsolute.
    MoveLinearAbsolute(MoveLinear),
    /// MC_MoveLinearRelative.
    MoveLinearRelative(MoveLinear),
    /// MC_GroupHalt.
    GroupHalt(GroupHalt),
    /// MC_GroupStop.
    GroupStop(GroupStop),
    /// MC_PathSelect.
    PathSelect(PathSelect),
    /// MC_MovePath.
    MovePath(MovePath),
    /// An FB of the catalogue marked * (MC_GroupEnable, MC_GroupHome, MC_GroupInterrupt,
    /// MC_MoveCircular*, ...), named by its manual name: always refused with 4905.
    NotImplemented {
        /// AxesGroup.
        group: String,
        /// The manual's FB name, e.g. "MC_GroupHome".
        fb: String,
    },
}

impl GroupCommand {
    /// The group the call addresses.
    pub fn group(&self) -> &str {
        use GroupCommand::*;
        match self {
            AddAxisToGroup(c) => &c.group,
            RemoveAxisFromGroup(c) => &c.group,
            UngroupAllAxes { group }
            | GroupReadConfiguration { group, .. }
            | GroupEnable { group }
            | GroupDisable { group }
            | GroupReset { group }
            | GroupReadStatus { group }
            | GroupReadError { group }
            | GroupReadActualPosition { group, .. }
            | GroupReadActualVelocity { group, .. }
            | NotImplemented { group, .. } => group,
            GroupSetOverride(c) => &c.group,
            MoveLinearAbsolute(c) | MoveLinearRelative(c) => &c.group,
            GroupHalt(c) => &c.group,
            GroupStop(c) => &c.group,
            PathSelect(c) => &c.group,
            MovePath(c) => &c.group,
        }
    }
}

/// MC_GroupReadStatus outputs.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct GroupStatus {
    /// Group name.
    pub name: String,
    /// The state (§5).
    pub state: GroupState,
    /// GroupMoving.
    pub group_moving: bool,
    /// GroupHoming (never: MC_GroupHome is not implemented).
    pub group_homing: bool,
    /// GroupErrorStop.
    pub group_error_stop: bool,
    /// GroupStandby.
    pub group_standby: bool,
    /// GroupStopping.
    pub group_stopping: bool,
    /// GroupDisabled.
    pub group_disabled: bool,
    /// ConstantVelocity (path velocity ≠ 0, path acceleration 0).
    pub constant_velocity: bool,
    /// Accelerating (|path velocity| increasing).
    pub accelerating: bool,
    /// Decelerating (|path velocity| decreasing).
    pub decelerating: bool,
    /// InPosition: no motion and every member at its set position.
    pub in_position: bool,
    /// Member axes in IdentInGroup order.
    pub axes: Vec<String>,
    /// IdentInGroup of each member.
    pub idents: Vec<u32>,
    /// Group error id (0 = none; 1 = a member axis is in ErrorStop).
    pub error_id: ErrorId,
    /// Velocity override factor in [0, 1].
    pub override_factor: f64,
    /// Path velocity (set, ≥ 0) \[u/s\].
    pub path_velocity: f64,
    /// Path acceleration (set) \[u/s²\].
    pub path_acceleration: f64,
    /// Set positions of the members \[u\].
    pub set_position: Vec<f64>,
    /// Actual positions of the members \[u\].
    pub act_position: Vec<f64>,
    /// Points loaded by MC_PathSelect.
    pub path_points: usize,
}

/// Values returned at once by group read FBs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum GroupReply {
    /// MC_GroupReadStatus.
    Status(Box<GroupStatus>),
    /// MC_GroupReadError: the group error id.
    Error(ErrorId),
    /// MC_GroupReadActualPosition / Velocity: one value per member.
    Values(Vec<f64>),
    /// MC_GroupReadConfiguration: the member axes (name, IdentInGroup).
    Configuration(Vec<(String, u32)>),
    /// MC_GroupSetOverride: Enabled.
    Enabled(bool),
    /// `AxisCommand::ReadFbOutputs` of a group instance.
    Outputs(motion_core::ExecuteOutputs),
}
