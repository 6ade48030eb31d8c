//! Error and warning ids of the planar engine (xplanar.md §6.2, all ids are proposals).
//!
//! The manual names error conditions but no numbers; the spec numbers them 0x4A01.. and the
//! dynamics warning 0x4B01. Shell-level ids (unknown object, not finite, ...) come from
//! [`motion_core::ErrorId`].

use motion_core::{ErrorId, Rejection};

/// Command not allowed in the object's planar state (§2.1).
pub const E_INVALID_STATE: ErrorId = ErrorId(0x4A01);
/// Command not allowed in the mover's command mode (§2.3).
pub const E_INVALID_COMMAND_MODE: ErrorId = ErrorId(0x4A02);
/// Target track not Enabled / Uninitialized.
pub const E_TRACK_NOT_READY: ErrorId = ErrorId(0x4A03);
/// Track operation mode forbids the command (§2.5).
pub const E_TRACK_MODE_CONFLICT: ErrorId = ErrorId(0x4A04);
/// Group area conflict or physical footprint conflict (§5.11); objectInfo names the blocker.
pub const E_COLLISION: ErrorId = ErrorId(0x4A05);
/// ReferenceId not valid in this configuration (§1.4).
pub const E_INVALID_REFERENCE_ID: ErrorId = ErrorId(0x4A06);
/// Parameter invalid (turns, ranges, negative limits ...).
pub const E_INVALID_PARAMETER: ErrorId = ErrorId(0x4A07);
/// Target not reachable (other CS, outside the stator area, direction).
pub const E_TARGET_UNREACHABLE: ErrorId = ErrorId(0x4A08);
/// GearIn stopped at the end of its trail.
pub const E_TRACK_BOUNDARY_REACHED: ErrorId = ErrorId(0x4A09);
/// Track geometry invalid.
pub const E_GEOMETRY_INVALID: ErrorId = ErrorId(0x4A0A);
/// Track change blocked by a link.
pub const E_TRACK_LOCKED: ErrorId = ErrorId(0x4A0B);
/// Track end already linked.
pub const E_ALREADY_CONNECTED: ErrorId = ErrorId(0x4A0C);
/// Group not Enabled, or already a member of a group.
pub const E_GROUP_NOT_READY: ErrorId = ErrorId(0x4A0D);
/// Unknown part OID in Initialize.
pub const E_INVALID_PART: ErrorId = ErrorId(0x4A0E);
/// Unknown part position index.
pub const E_INVALID_POSITION_INDEX: ErrorId = ErrorId(0x4A0F);
/// Part command before Initialize.
pub const E_PART_NOT_INITIALIZED: ErrorId = ErrorId(0x4A10);
/// Mover error caused by a part (ForceDisable / part error); Enable on a force-disabled part.
pub const E_PART_DISABLED: ErrorId = ErrorId(0x4A11);
/// No external set point for too many cycles.
pub const E_EXT_SETPOINT_MISSING: ErrorId = ErrorId(0x4A12);
/// External set points exceed the maximum dynamics.
pub const E_DYNAMICS_VIOLATION: ErrorId = ErrorId(0x4A13);
/// Track trail invalid.
pub const E_TRACKTRAIL_INVALID: ErrorId = ErrorId(0x4A14);
/// C command conflicting with an active XY command (§2.4).
pub const E_AXIS_BUSY: ErrorId = ErrorId(0x4A15);
/// Command ended because its object went to ErrorPending/Error.
pub const E_OBJECT_ERROR: ErrorId = ErrorId(0x4A16);
/// Warning: requested limits above the maximum dynamics were reduced (§5.1).
pub const W_DYNAMICS_REDUCED: ErrorId = ErrorId(0x4B01);

/// The manual name of an id, for messages.
pub fn error_name(id: ErrorId) -> &'static str {
    match id.0 {
        0 => "E_NONE",
        0x4A01 => "E_INVALID_STATE",
        0x4A02 => "E_INVALID_COMMAND_MODE",
        0x4A03 => "E_TRACK_NOT_READY",
        0x4A04 => "E_TRACK_MODE_CONFLICT",
        0x4A05 => "E_COLLISION",
        0x4A06 => "E_INVALID_REFERENCE_ID",
        0x4A07 => "E_INVALID_PARAMETER",
        0x4A08 => "E_TARGET_UNREACHABLE",
        0x4A09 => "E_TRACK_BOUNDARY_REACHED",
        0x4A0A => "E_GEOMETRY_INVALID",
        0x4A0B => "E_TRACK_LOCKED",
        0x4A0C => "E_ALREADY_CONNECTED",
        0x4A0D => "E_GROUP_NOT_READY",
        0x4A0E => "E_INVALID_PART",
        0x4A0F => "E_INVALID_POSITION_INDEX",
        0x4A10 => "E_PART_NOT_INITIALIZED",
        0x4A11 => "E_PART_DISABLED",
        0x4A12 => "E_EXT_SETPOINT_MISSING",
        0x4A13 => "E_DYNAMICS_VIOLATION",
        0x4A14 => "E_TRACKTRAIL_INVALID",
        0x4A15 => "E_AXIS_BUSY",
        0x4A16 => "E_OBJECT_ERROR",
        0x4B01 => "W_DYNAMICS_REDUCED",
        0x7F01 => "UNKNOWN_OBJECT",
        0x7F02 => "NOT_FINITE",
        0x7F03 => "ENUM_OUT_OF_RANGE",
        0x7F06 => "VALUE_OUT_OF_RANGE",
        0x7F07 => "NOT_IMPLEMENTED",
        _ => "E_UNKNOWN",
    }
}

/// A rejection with the manual's error name prefixed to the message.
pub fn reject(id: ErrorId, message: impl AsRef<str>) -> Rejection {
    Rejection::new(id, format!("{}: {}", error_name(id), message.as_ref()))
}

/// Checks that a request field is finite (NaN/inf → `NOT_FINITE`, naming object and field).
pub fn finite(object: &str, field: &str, value: f64) -> Result<f64, Rejection> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Rejection::not_finite(object, field, value))
    }
}
