//! Error ids of the single-axis engine (single_axis.md §7.3).

use motion_core::ErrorId;

/// 0x4B01 "axis cannot be started": rejected because of the axis state (Disabled, ErrorStop,
/// Stopping/locked, Homing, protected slave, feed enable missing).
pub const AXIS_CANNOT_BE_STARTED: ErrorId = ErrorId(0x4B01);
/// 0x4B03 "axis is not moving" (MC_MoveSuperImposed at standstill).
pub const AXIS_NOT_MOVING: ErrorId = ErrorId(0x4B03);
/// 0x4B04 "invalid mode": invalid Direction / mode / BufferMode values.
pub const INVALID_MODE: ErrorId = ErrorId(0x4B04);
/// 0x4B05 "command not permitted": MoveVelocity without a valid direction, parameter type
/// mismatch, GearOut/phasing on an uncoupled axis, non-Aborting command on a slave.
pub const COMMAND_NOT_PERMITTED: ErrorId = ErrorId(0x4B05);
/// 0x4B06 "parameter not correct": invalid numeric inputs (MC_ERROR_PARAMETER_NOT_CORRECT).
pub const PARAMETER_NOT_CORRECT: ErrorId = ErrorId(0x4B06);
/// 0x4B07 "timeout axis function block": InTargetPosition not reached within AxisInTargetTimeout.
pub const FB_TIMEOUT: ErrorId = ErrorId(0x4B07);
/// 0x4292 "Buffer Full": a second buffered command while one is waiting.
pub const BUFFER_FULL: ErrorId = ErrorId(0x4292);
/// 0x4296: blending position not before the end position of the running command.
pub const BLENDING_POSITION_INVALID: ErrorId = ErrorId(0x4296);
/// 0x4243: warning of MC_MoveSuperImposed (overlay cannot be completed).
pub const SUPERPOSITION_INCOMPLETE: ErrorId = ErrorId(0x4243);
/// 0x4550: position lag monitoring (also the default id of the error-injection hook).
pub const POSITION_LAG: ErrorId = ErrorId(0x4550);
/// 0x4D01: target outside the enabled software limits (command rejected).
pub const SOFT_LIMIT_TARGET: ErrorId = ErrorId(0x4D01);
/// 0x4D02: endless motion stopped at a software limit.
pub const SOFT_LIMIT_STOP: ErrorId = ErrorId(0x4D02);
/// 0x4D03: unknown parameter number.
pub const UNKNOWN_PARAMETER: ErrorId = ErrorId(0x4D03);
/// 0x4D04: write to a read-only parameter.
pub const READ_ONLY_PARAMETER: ErrorId = ErrorId(0x4D04);
/// 0x4D05: homing: reference cam / sync pulse not found.
pub const HOMING_NOT_FOUND: ErrorId = ErrorId(0x4D05);

/// A short text for an error id (published with the command status and action results).
pub fn text(id: ErrorId) -> String {
    let t = match id {
        AXIS_CANNOT_BE_STARTED => "axis cannot be started",
        AXIS_NOT_MOVING => "axis is not moving",
        INVALID_MODE => "invalid mode",
        COMMAND_NOT_PERMITTED => "command not permitted",
        PARAMETER_NOT_CORRECT => "parameter not correct",
        FB_TIMEOUT => "timeout axis function block (target not reached in time)",
        BUFFER_FULL => "buffer full",
        BLENDING_POSITION_INVALID => "blending position invalid",
        SUPERPOSITION_INCOMPLETE => "superposition cannot be completed",
        POSITION_LAG => "position lag monitoring",
        SOFT_LIMIT_TARGET => "target outside the software limits",
        SOFT_LIMIT_STOP => "stopped at a software limit",
        UNKNOWN_PARAMETER => "unknown parameter number",
        READ_ONLY_PARAMETER => "parameter is read-only",
        HOMING_NOT_FOUND => "homing: reference cam or sync pulse not found",
        _ => return format!("axis error {id}"),
    };
    format!("{id}: {t}")
}
