//! The mover command admissibility matrix (xplanar.md §2.3), one `match` laid out like the
//! spec's table. Rejections use `E_INVALID_COMMAND_MODE`.

use crate::types::CommandMode;
use serde::{Deserialize, Serialize};

/// The matrix rows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum CommandKind {
    /// MoveToPosition.
    MoveToPosition,
    /// JoinTrack.
    JoinTrack,
    /// LeaveTrack.
    LeaveTrack,
    /// MoveOnTrack.
    MoveOnTrack,
    /// GearInPosOnTrack / …WithMasterMover.
    GearIn,
    /// MoveC.
    MoveC,
    /// AdoptTrackOrientation.
    AdoptTrackOrientation,
    /// MoveZ / MoveA / MoveB.
    MoveZab,
    /// Halt.
    Halt,
    /// StartExternalSetpointGeneration, Absolute.
    StartEsgAbsolute,
    /// StartExternalSetpointGeneration, Relative.
    StartEsgRelative,
    /// StopExternalSetpointGeneration.
    StopEsg,
    /// AddToGroup / RemoveFromGroup.
    GroupMembership,
}

/// Mover facts the matrix depends on besides the mode.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AdmissionContext {
    /// XY stands still (no XY command, zero velocity).
    pub standing: bool,
    /// External set-point generation (absolute or relative) is active.
    pub esg_active: bool,
}

/// True if `kind` is admissible in `mode` (§2.3). Planar state, track modes, groups and
/// parameters are checked afterwards.
pub fn admissible(kind: CommandKind, mode: CommandMode, ctx: AdmissionContext) -> bool {
    use CommandKind as K;
    use CommandMode::*;
    let st = ctx.standing;
    match kind {
        //                                  FM    CRF   JT    OT    CRO   LT    ESG
        K::MoveToPosition => matches!(mode, FreeMovement),
        K::JoinTrack => matches!(mode, FreeMovement),
        K::LeaveTrack => matches!(mode, OnTrack),
        K::MoveOnTrack => matches!(mode, OnTrack),
        K::GearIn => matches!(mode, OnTrack),
        K::MoveC => match mode {
            FreeMovement | CRotationFreeMovement | CRotationOnTrack => true,
            OnTrack => st,
            _ => false,
        },
        K::AdoptTrackOrientation => match mode {
            OnTrack => st,
            CRotationOnTrack => true,
            _ => false,
        },
        K::MoveZab => matches!(
            mode,
            FreeMovement | CRotationFreeMovement | OnTrack | CRotationOnTrack
        ),
        K::Halt => matches!(
            mode,
            FreeMovement
                | CRotationFreeMovement
                | OnTrack
                | CRotationOnTrack
                | ExternalSetpointGeneration
        ),
        K::StartEsgAbsolute => mode == FreeMovement && st && !ctx.esg_active,
        K::StartEsgRelative => {
            matches!(
                mode,
                FreeMovement | CRotationFreeMovement | OnTrack | CRotationOnTrack
            ) && !ctx.esg_active
        }
        K::StopEsg => ctx.esg_active,
        K::GroupMembership => {
            matches!(
                mode,
                FreeMovement | CRotationFreeMovement | OnTrack | CRotationOnTrack
            ) && st
        }
    }
}
