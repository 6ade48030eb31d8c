//! Error ids of the CA group (collision_avoidance.md §7.2).

use motion_core::ErrorId;
/// 0x4B04 unknown enum value (Direction, GapControlMode, ...).
pub const INVALID_MODE: ErrorId = ErrorId(0x4B04);
/// 0x4B06 non-finite numeric input not covered below, non-finite override.
pub const PARAMETER_NOT_CORRECT: ErrorId = ErrorId(0x4B06);
/// 0x813C BufferMode other than Aborting/Buffered.
pub const INVALID_BUFFER_MODE: ErrorId = ErrorId(0x813C);
/// 0x813E command not permitted in the current group state (§4).
pub const NOT_ALLOWED_IN_GROUP_STATE: ErrorId = ErrorId(0x813E);
/// 0x813F GearInPosCA cannot reach sync within its limits.
pub const SLAVE_CANNOT_SYNC: ErrorId = ErrorId(0x813F);
/// 0x8140 Acceleration/Deceleration < 1, Jerk < 100, Jerk MC_MAXIMUM, invalid marker.
pub const INVALID_DYNAMICS: ErrorId = ErrorId(0x8140);
/// 0x8141 IdentInGroup 0 or duplicate.
pub const INVALID_IDENT_IN_GROUP: ErrorId = ErrorId(0x8141);
/// 0x8F01 Velocity missing, MC_DEFAULT/MC_IGNORE, ≤ 0 or non-finite.
pub const INVALID_VELOCITY: ErrorId = ErrorId(0x8F01);
/// 0x8F02 Position/Distance missing or non-finite; modulo target outside [0, M].
pub const INVALID_TARGET_POSITION: ErrorId = ErrorId(0x8F02);
/// 0x8F03 AdditionalTurns > 0 with NonModulo or ShortestWay.
pub const INVALID_ADDITIONAL_TURNS: ErrorId = ErrorId(0x8F03);
/// 0x8F04 Gap < 0, non-finite, MC_MAXIMUM/MC_IGNORE, or ≥ rail_length on a ring.
pub const INVALID_GAP: ErrorId = ErrorId(0x8F04);
/// 0x8F05 a modulo Direction on an open rail.
pub const MODULO_ON_OPEN_RAIL: ErrorId = ErrorId(0x8F05);
/// 0x8F06 MC_GroupEnable on an empty group.
pub const GROUP_EMPTY: ErrorId = ErrorId(0x8F06);
/// 0x8F07 add/remove of a moving axis.
pub const AXIS_MOVING: ErrorId = ErrorId(0x8F07);
/// 0x8F08 axis not in this group / unknown axis name.
pub const AXIS_NOT_IN_GROUP: ErrorId = ErrorId(0x8F08);
/// 0x8F09 adding an axis that already belongs to a group.
pub const AXIS_IN_OTHER_GROUP: ErrorId = ErrorId(0x8F09);
/// 0x8F0A Undershoot and Overshoot both FALSE; MinimalSlavePosition not a finite value.
pub const INVALID_SYNC_OPTIONS: ErrorId = ErrorId(0x8F0A);
/// 0x8F0B unknown track; mover not on a part of the track.
pub const TRACK_ERROR: ErrorId = ErrorId(0x8F0B);
/// 0x8F0C unknown/inactive template.
pub const COMPENSATION_ERROR: ErrorId = ErrorId(0x8F0C);
/// 0x8F0D TF5420-only blocks on a CA group.
pub const NOT_SUPPORTED_FOR_GROUP_TYPE: ErrorId = ErrorId(0x8F0D);
/// 0x8F0E axis without closed loop / direction enables; group error on loop loss.
pub const AXIS_NOT_READY: ErrorId = ErrorId(0x8F0E);
/// 0x8F0F `update_gap` without ContinuousUpdate or without an active command.
pub const CONTINUOUS_UPDATE_NOT_ENABLED: ErrorId = ErrorId(0x8F0F);
/// 0x4292 second pending Buffered command on one axis.
pub const BUFFER_FULL: ErrorId = ErrorId(0x4292);
