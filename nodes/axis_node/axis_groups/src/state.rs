//! Group state machine (plcopen_platform.md §5, proposal after PLCopen Part 4): the states,
//! the derived-state rule and the admission matrix.

use crate::ids::ERR_SIM_TRANSITION_NOT_ALLOWED;
use motion_core::ErrorId;
use serde::{Deserialize, Serialize};

/// Group states (§5). Numbers are ours (proposal).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[repr(u8)]
pub enum GroupState {
    /// GROUP_DISABLED (0): no members, a member not powered, or disabled by MC_GroupDisable.
    #[default]
    Disabled = 0,
    /// GROUP_STANDBY (1): enabled, not moving.
    Standby = 1,
    /// GROUP_HOMING (2): MC_GroupHome is not implemented, so this state is never entered.
    Homing = 2,
    /// GROUP_MOVING (3): a group motion (MoveLinear*, MovePath, GroupHalt) is running.
    Moving = 3,
    /// GROUP_STOPPING (4): MC_GroupStop until Done and Execute FALSE.
    Stopping = 4,
    /// GROUP_ERROR_STOP (5): a member axis error (latched until MC_GrpReset).
    ErrorStop = 5,
}

/// The facts the group state is derived from.
#[derive(Clone, Copy, Debug, Default)]
pub struct GroupFacts {
    /// Group error latched.
    pub error: bool,
    /// Enabled: members present, all powered, not disabled by MC_GroupDisable.
    pub enabled: bool,
    /// MC_GroupStop ramp running or its lock held.
    pub stopping: bool,
    /// A group motion is running.
    pub moving: bool,
}

/// Derived-state rule: the first matching rule wins.
pub fn derive_group_state(f: &GroupFacts) -> GroupState {
    if f.error {
        GroupState::ErrorStop
    } else if !f.enabled {
        GroupState::Disabled
    } else if f.stopping {
        GroupState::Stopping
    } else if f.moving {
        GroupState::Moving
    } else {
        GroupState::Standby
    }
}

/// Part 4 FBs as rows of the admission matrix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GroupFbClass {
    /// MC_AddAxisToGroup, MC_RemoveAxisFromGroup.
    Membership,
    /// MC_UngroupAllAxes.
    Ungroup,
    /// MCV_GroupEnable.
    Enable,
    /// MC_GroupDisable.
    Disable,
    /// MC_GrpReset.
    Reset,
    /// MC_MoveLinearAbsolute/Relative, MC_MovePath.
    Move,
    /// MC_GroupHalt.
    Halt,
    /// MC_GroupStop.
    Stop,
    /// Read FBs, MC_GroupSetOverride, MC_PathSelect.
    ReadWrite,
}

/// One cell of the matrix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GroupAdmission {
    /// Accepted, no state change.
    Keep,
    /// Accepted; the group enters this state (Standby/Disabled for Reset and Enable depend
    /// on the members' power, see the FB).
    To(GroupState),
    /// Rejected with this id; nothing changes.
    Reject(ErrorId),
}

/// The admission matrix; columns Disabled, Standby, Homing, Moving, Stopping, ErrorStop.
pub fn group_admission(fb: GroupFbClass, state: GroupState) -> GroupAdmission {
    use GroupAdmission::{Keep as K, To};
    use GroupState::*;
    const E: GroupAdmission = GroupAdmission::Reject(ERR_SIM_TRANSITION_NOT_ALLOWED);
    let col = state as usize;
    let (dis, sb, mv, stp) = (To(Disabled), To(Standby), To(Moving), To(Stopping));
    #[rustfmt::skip]
    let row: [GroupAdmission; 6] = match fb {
        //                          Dis   SB    Hom   Mov   Stp   Err
        GroupFbClass::Membership => [K,    K,    E,    E,    E,    K],
        GroupFbClass::Ungroup =>    [K,    dis,  dis,  dis,  dis,  dis],
        GroupFbClass::Enable =>     [sb,   K,    K,    K,    K,    E],
        GroupFbClass::Disable =>    [K,    dis,  dis,  dis,  dis,  dis],
        GroupFbClass::Reset =>      [K,    K,    E,    E,    E,    sb],
        GroupFbClass::Move =>       [E,    mv,   E,    mv,   E,    E],
        GroupFbClass::Halt =>       [E,    mv,   E,    mv,   E,    E],
        GroupFbClass::Stop =>       [E,    stp,  stp,  stp,  stp,  E],
        GroupFbClass::ReadWrite =>  [K,    K,    K,    K,    K,    K],
    };
    row[col]
}
