//! Error and warning ids of the ISG platform spec (plcopen_platform.md §7.3). FB ErrorIDs are
//! decimal as in the manual (`1`, `4`, `4013`), MC message ids too (`60241`, `70225`).

use motion_core::ErrorId;

/// 1 `ERR_PLC_AX_MC` (P-ERR-40001): the axis is in ERROR_STOP because of an MC error (§7.2);
/// shown by every FB instance of that axis (and of a group with that member).
pub const ERR_PLC_AX_MC: ErrorId = ErrorId(1);
/// 4 `FB_ERR_MC_DID_NOT_TAKE_ORDER`: the axis' order slot was already used in this cycle
/// (R-HS-3).
pub const FB_ERR_MC_DID_NOT_TAKE_ORDER: ErrorId = ErrorId(4);
/// 4013 `ERR_PO_AX_TNA_INIT_STATE` (P-ERR-44013): order during start-up (§9).
pub const ERR_PO_AX_TNA_INIT_STATE: ErrorId = ErrorId(4013);
/// 4901 `ERR_SIM_TRANSITION_NOT_ALLOWED` (proposal): the state machine forbids the command.
pub const ERR_SIM_TRANSITION_NOT_ALLOWED: ErrorId = ErrorId(4901);
/// 4902 `ERR_SIM_INVALID_PARAMETER` (proposal): an input is out of its range.
pub const ERR_SIM_INVALID_PARAMETER: ErrorId = ErrorId(4902);
/// 4903 `ERR_SIM_AXIS_NOT_REFERENCED` (proposal): absolute positioning on a non-referenced
/// axis (R-SAF-6).
pub const ERR_SIM_AXIS_NOT_REFERENCED: ErrorId = ErrorId(4903);
/// 4904 `ERR_SIM_VERSION_MISMATCH` (proposal): HLI version/size inconsistent (R-SAF-2).
pub const ERR_SIM_VERSION_MISMATCH: ErrorId = ErrorId(4904);
/// 4905 `ERR_SIM_NOT_IMPLEMENTED` (proposal): FB marked * in the catalogue (§3).
pub const ERR_SIM_NOT_IMPLEMENTED: ErrorId = ErrorId(4905);
/// 4906 `ERR_SIM_HLI_ACK_CLOG` (proposal): warning, acknowledgement slot clogged (R-HS-5).
pub const ERR_SIM_HLI_ACK_CLOG: ErrorId = ErrorId(4906);
/// 4907 `ERR_SIM_AXIS_REF_CHANGED` (proposal, R-FB-4).
pub const ERR_SIM_AXIS_REF_CHANGED: ErrorId = ErrorId(4907);
/// MC 60241: programmed velocity exceeds the monitoring limit (SAI command check, R-SAF-1a).
pub const MC_PROGRAMMED_VELOCITY_EXCEEDS_LIMIT: ErrorId = ErrorId(60241);
/// MC 70225: max. actual velocity exceeded during active velocity monitoring (R-SAF-1b).
pub const MC_ACTUAL_VELOCITY_EXCEEDED: ErrorId = ErrorId(70225);
/// MC 70220: max. actual velocity exceeded during active torque limiting (R-SAF-4).
pub const MC_ACTUAL_VELOCITY_TORQUE_LIMIT: ErrorId = ErrorId(70220);
/// MC 91001 (proposal): software/travel limit reached (R-SYS-1).
pub const MC_LIMIT_REACHED: ErrorId = ErrorId(91001);

/// A short text for the ids above (None for others).
pub fn text(id: ErrorId) -> Option<&'static str> {
    Some(match id {
        ERR_PLC_AX_MC => "ERR_PLC_AX_MC: axis is in ERROR_STOP due to an MC error",
        FB_ERR_MC_DID_NOT_TAKE_ORDER => {
            "FB_ERR_MC_DID_NOT_TAKE_ORDER: order slot already used this cycle"
        }
        ERR_PO_AX_TNA_INIT_STATE => "ERR_PO_AX_TNA_INIT_STATE: order during start-up",
        ERR_SIM_TRANSITION_NOT_ALLOWED => "ERR_SIM_TRANSITION_NOT_ALLOWED",
        ERR_SIM_INVALID_PARAMETER => "ERR_SIM_INVALID_PARAMETER",
        ERR_SIM_AXIS_NOT_REFERENCED => "ERR_SIM_AXIS_NOT_REFERENCED",
        ERR_SIM_VERSION_MISMATCH => "ERR_SIM_VERSION_MISMATCH",
        ERR_SIM_NOT_IMPLEMENTED => "ERR_SIM_NOT_IMPLEMENTED",
        ERR_SIM_HLI_ACK_CLOG => "ERR_SIM_HLI_ACK_CLOG",
        ERR_SIM_AXIS_REF_CHANGED => "ERR_SIM_AXIS_REF_CHANGED",
        MC_PROGRAMMED_VELOCITY_EXCEEDS_LIMIT => "programmed velocity exceeds monitoring limit",
        MC_ACTUAL_VELOCITY_EXCEEDED => {
            "max. actual velocity exceeded during active velocity monitoring"
        }
        MC_ACTUAL_VELOCITY_TORQUE_LIMIT => {
            "max. actual velocity exceeded during active torque limiting"
        }
        MC_LIMIT_REACHED => "software/travel limit reached",
        _ => return None,
    })
}
