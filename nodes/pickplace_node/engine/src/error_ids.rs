//! Error and warning ids of the technology module (pick_and_place.md §16).
//!
//! The manual's ids are decimal (`L_IE1P_Error`); the 900xx ids are the spec's proposals.

use motion_core::ErrorId;

/// Warning: the maximum of 30 tracked workpieces on a belt is reached (§14).
pub const MAX_WORKPIECES: ErrorId = ErrorId(17918);
/// Error: an axis reached its positive software limit (§16).
pub const SW_LIMIT_POS: ErrorId = ErrorId(20306);
/// Error: an axis reached its negative software limit (§16).
pub const SW_LIMIT_NEG: ErrorId = ErrorId(20307);
/// Error: positive hardware limit switch (§16).
pub const HW_LIMIT_POS: ErrorId = ErrorId(20500);
/// Error: negative hardware limit switch (§16).
pub const HW_LIMIT_NEG: ErrorId = ErrorId(20501);
/// Reject/error: a parameter is out of its range (§3.4).
pub const INVALID_PARAMETER: ErrorId = ErrorId(90001);
/// Reject: `ePathMode` not in {0, 1}.
pub const INVALID_PATH_MODE: ErrorId = ErrorId(90002);
/// Reject: `eTrackingMode` not in {0 … 4}.
pub const INVALID_TRACKING_MODE: ErrorId = ErrorId(90003);
/// Error: ACS target at the execute edge (§7.1).
pub const COORD_SYSTEM_NOT_SUPPORTED: ErrorId = ErrorId(90004);
/// Error: target belt not configured or `eSetTarget` out of range.
pub const BELT_NOT_CONFIGURED: ErrorId = ErrorId(90005);
/// Warning: ellipse preconditions not met, planned linear (§7.4).
pub const ELLIPSE_FALLBACK_LINEAR: ErrorId = ErrorId(90007);
/// Warning: execute edge while `xProfileInPreparation` (§8).
pub const PROFILE_BUFFER_FULL: ErrorId = ErrorId(90008);
/// Warning: command edge while the axes are disabled (§4.2).
pub const AXES_NOT_ENABLED: ErrorId = ErrorId(90009);
/// Warning: edge command not allowed in the current state (§4.2).
pub const COMMAND_NOT_ALLOWED: ErrorId = ErrorId(90010);
/// Error: following error above `following_error_limit`.
pub const FOLLOWING_ERROR: ErrorId = ErrorId(90011);
/// Error: `xStopALL` while coupled to a belt (§9.3).
pub const STOP_ALL_DURING_SYNC: ErrorId = ErrorId(90012);
/// Warning: the held workpiece reached the upper sync limit (§15.4).
pub const SYNC_LIMIT_EXCEEDED: ErrorId = ErrorId(90013);
/// Error: homing failed (§6).
pub const HOMING_FAILED: ErrorId = ErrorId(90014);
/// Warning: `lrOverride` outside 0 … 1, clamped (§12).
pub const OVERRIDE_OUT_OF_RANGE: ErrorId = ErrorId(90015);
