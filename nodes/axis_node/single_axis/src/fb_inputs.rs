//! Inputs of the Tc2_MC2 single-axis FBs (single_axis.md §4): one struct per FB with the
//! manual's input names in snake_case and typed enumerations, and the simulation inputs of
//! §1.5 ([`Sim`]). Plain data: the engine's FB calls take them.

use crate::inputs::*;
use serde::{Deserialize, Serialize};

/// `ST_MoveOptions` (§5.4). Fields left out of a script or config read as the manual's
/// defaults (FALSE, 0).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct MoveOptions {
    /// EnableBlendingPosition: transition at `blending_position` instead of the end position.
    pub enable_blending_position: bool,
    /// BlendingPosition \[u\].
    pub blending_position: f64,
    /// IgnorePositionMonitoring: Done without waiting for InTargetPosition.
    pub ignore_position_monitoring: bool,
    /// EnableStopPositionMonitoring (MC_Halt/MC_Stop).
    pub enable_stop_position_monitoring: bool,
}

/// `ST_SetPositionOptions` (§5.4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SetPositionOptions {
    /// ClearPositionLag: set and actual position both become `position`.
    pub clear_position_lag: bool,
    /// SelectEncoderIndex.
    pub select_encoder_index: bool,
    /// EncoderIndex (only 0 exists).
    pub encoder_index: u16,
    /// ClearPositionOffset: return to the original coordinate system.
    pub clear_position_offset: bool,
}

/// `ST_HomingOptions` (§4.10, §5.4).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct HomingOptions {
    /// ClearPositionLag (MC_Direct only): set and actual position become equal.
    pub clear_position_lag: bool,
    /// SearchDirection (cam search); Undefined → positive (inverted by parameter 1073).
    pub search_direction: Direction,
    /// SearchVelocity; 0 → AxisCalibrationVelocityForward (1012).
    pub search_velocity: f64,
    /// SyncDirection (sync-pulse search); Undefined → positive (inverted by parameter 1074).
    pub sync_direction: Direction,
    /// SyncVelocity; 0 → AxisCalibrationVelocityBackward (1013).
    pub sync_velocity: f64,
    /// ReferenceMode (E_EncoderReferenceMode); 0 = DEFAULT = the encoder's mode (1076).
    pub reference_mode: u32,
}

impl Default for HomingOptions {
    fn default() -> Self {
        HomingOptions {
            clear_position_lag: false,
            search_direction: Direction::Undefined,
            search_velocity: 0.0,
            sync_direction: Direction::Undefined,
            sync_velocity: 0.0,
            reference_mode: 0,
        }
    }
}

/// MC_Home (§4.10).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Home {
    /// Axis name.
    pub axis: String,
    /// Position: absolute reference position (ignored with `use_default_position`).
    pub position: f64,
    /// TRUE = DEFAULT_HOME_POSITION: use AxisEncoderHomingCalibValue (1075).
    pub use_default_position: bool,
    /// HomingMode.
    pub homing_mode: HomingMode,
    /// BufferMode (not implemented by Tc2_MC2; ignored, behaves like Aborting).
    pub buffer_mode: BufferMode,
    /// Options.
    pub options: HomingOptions,
    /// bCalibrationCam: level of the reference cam input (ORed with the virtual cam).
    pub calibration_cam: bool,
}

/// MC_Jog (§4.11): one call = a rising edge of `jog_forward` or `jog_backwards` (forward
/// wins when both are TRUE). Releasing the held button of the continuous modes is
/// `AxisCommand::SetExecute { id, execute: false }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Jog {
    /// Axis name.
    pub axis: String,
    /// JogForward.
    pub jog_forward: bool,
    /// JogBackwards.
    pub jog_backwards: bool,
    /// Mode.
    pub mode: JogMode,
    /// Position: step distance of the INCHING modes \[u\].
    pub position: f64,
    /// Velocity (> 0; not used in the STANDARD modes) \[u/s\].
    pub velocity: f64,
    /// Acceleration (0 = axis default; not used in the STANDARD modes).
    pub acceleration: f64,
    /// Deceleration (0 = axis default; not used in the STANDARD modes).
    pub deceleration: f64,
    /// Jerk (0 = axis default; not used in the STANDARD modes).
    pub jerk: f64,
}

/// MC_SetOverride (§4.7.10, Enable-type): one call with the current inputs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SetOverride {
    /// Axis name.
    pub axis: String,
    /// Enable.
    pub enable: bool,
    /// VelFactor (1.0 = 100 %), 0..=1.
    pub vel_factor: f64,
    /// AccFactor (not supported by Tc2_MC2; checked for being finite only).
    pub acc_factor: f64,
    /// JerkFactor (not supported by Tc2_MC2; checked for being finite only).
    pub jerk_factor: f64,
}

/// MC_GearIn (§4.12.1): couples `slave` to `master` with RatioNumerator/RatioDenominator.
/// InGear = the instance's Done (the cycle after the edge).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GearIn {
    /// Master axis name.
    pub master: String,
    /// Slave axis name.
    pub slave: String,
    /// RatioNumerator (may be negative or fractional).
    pub ratio_numerator: f64,
    /// RatioDenominator (0 → Error 0x4B06).
    pub ratio_denominator: u32,
    /// Acceleration (not implemented by Tc2_MC2; coupling is instantaneous).
    pub acceleration: f64,
    /// Deceleration (not implemented).
    pub deceleration: f64,
    /// Jerk (not implemented).
    pub jerk: f64,
    /// BufferMode (not implemented; behaves like Aborting).
    pub buffer_mode: BufferMode,
}

/// MC_GearInDyn (§4.12.2, Enable-type): one call with the current inputs. Enable↑ couples
/// (returns the instance id), calls with Enable TRUE update GearRatio/Acceleration of the
/// running instance (same id), Enable↓ ends the instance and freezes the ratio (the slave
/// stays coupled).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GearInDyn {
    /// Master axis name.
    pub master: String,
    /// Slave axis name.
    pub slave: String,
    /// Enable.
    pub enable: bool,
    /// GearRatio.
    pub gear_ratio: f64,
    /// Acceleration (≥ 0; 0 = slave AxisAcc): limits the ratio slew to
    /// Acceleration / master AxisMaxVelocity per second.
    pub acceleration: f64,
    /// Deceleration (not implemented by Tc2_MC2).
    pub deceleration: f64,
    /// Jerk (not implemented by Tc2_MC2).
    pub jerk: f64,
    /// BufferMode (not implemented).
    pub buffer_mode: BufferMode,
}

/// MC_GearOut (§4.12.3): decouples `slave`; a moving slave keeps its velocity.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GearOut {
    /// Slave axis name.
    pub slave: String,
}

/// `ST_TorqueControlOptions` (§4.14).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TorqueControlOptions {
    /// EnableManualTorqueStartValue.
    pub enable_manual_torque_start_value: bool,
    /// ManualTorqueStartValue (start of the ramp instead of the current torque).
    pub manual_torque_start_value: f64,
}

/// MC_TorqueControl (§4.14, W14). Later input changes (with `continuous_update` at the edge):
/// `AxisCommand::TorqueControlUpdate`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TorqueControl {
    /// Axis name.
    pub axis: String,
    /// ContinuousUpdate: inputs may change while running.
    pub continuous_update: bool,
    /// Relative: change the current torque by `torque`.
    pub relative: bool,
    /// Torque set value (or change) \[%\].
    pub torque: f64,
    /// TorqueRamp (> 0) \[%/s\].
    pub torque_ramp: f64,
    /// VelocityLimitHigh \[u/s\].
    pub velocity_limit_high: f64,
    /// VelocityLimitLow \[u/s\].
    pub velocity_limit_low: f64,
    /// BufferMode (only MC_Aborting).
    pub buffer_mode: BufferMode,
    /// Options.
    pub options: TorqueControlOptions,
}

/// MC_MoveSuperImposed (§4.9.1, W9).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MoveSuperImposed {
    /// Axis name.
    pub axis: String,
    /// Mode.
    pub mode: SuperpositionMode,
    /// Distance: + gains, − loses distance relative to the base motion \[u\].
    pub distance: f64,
    /// VelocityDiff (> 0) \[u/s\].
    pub velocity_diff: f64,
    /// Acceleration (≥ 0; 0 = axis default).
    pub acceleration: f64,
    /// Deceleration (≥ 0; 0 = axis default).
    pub deceleration: f64,
    /// Jerk (not implemented by Tc2_MC2; checked only).
    pub jerk: f64,
    /// VelocityProcess (> 0) \[u/s\].
    pub velocity_process: f64,
    /// Length \[u\].
    pub length: f64,
    /// Options.AbortOption.
    pub abort_option: SuperpositionAbortOption,
}

/// MC_AbortSuperposition (§4.9.2).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AbortSuperposition {
    /// Axis name.
    pub axis: String,
}

/// `TRIGGER_REF` (§5.4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TriggerRef {
    /// EncoderID (informational).
    pub encoder_id: u32,
    /// TouchProbe: the latch unit.
    pub touch_probe: TouchProbeUnit,
    /// SignalSource (E_SignalSource value; informational).
    pub signal_source: u32,
    /// Edge.
    pub edge: SignalEdge,
    /// Mode.
    pub mode: TouchProbeMode,
    /// PlcEvent level (with `touch_probe = PlcEvent`).
    pub plc_event: bool,
    /// ModuloPositions: window and RecordedPosition modulo the axis period.
    pub modulo_positions: bool,
}

/// MC_TouchProbe (§4.5.1, W19).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TouchProbe {
    /// Axis name.
    pub axis: String,
    /// TriggerInput.
    pub trigger_input: TriggerRef,
    /// WindowOnly.
    pub window_only: bool,
    /// FirstPosition \[u\].
    pub first_position: f64,
    /// LastPosition \[u\].
    pub last_position: f64,
}

/// MC_AbortTrigger (§4.5.2).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AbortTrigger {
    /// Axis name.
    pub axis: String,
    /// TriggerInput (its latch unit is disarmed).
    pub trigger_input: TriggerRef,
}

/// MC_Power (§4.1, Enable-type): one call with the current input levels.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Power {
    /// Axis name.
    pub axis: String,
    /// Enable.
    pub enable: bool,
    /// Enable_Positive (feed enable, positive direction).
    pub enable_positive: bool,
    /// Enable_Negative (feed enable, negative direction).
    pub enable_negative: bool,
    /// Override \[%\], 0..=100.
    pub override_percent: f64,
    /// BufferMode (evaluated when Enable goes FALSE).
    pub buffer_mode: BufferMode,
}

/// MC_Reset (§4.2).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Reset {
    /// Axis name.
    pub axis: String,
}

/// MC_MoveAbsolute (§4.8.1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MoveAbsolute {
    /// Axis name.
    pub axis: String,
    /// Position: absolute target \[u\].
    pub position: f64,
    /// Velocity (> 0) \[u/s\].
    pub velocity: f64,
    /// Acceleration (0 = axis default) \[u/s²\].
    pub acceleration: f64,
    /// Deceleration (0 = axis default) \[u/s²\].
    pub deceleration: f64,
    /// Jerk (0 = axis default) \[u/s³\].
    pub jerk: f64,
    /// BufferMode.
    pub buffer_mode: BufferMode,
    /// Options.
    pub options: MoveOptions,
}

/// MC_MoveRelative (§4.8.2).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MoveRelative {
    /// Axis name.
    pub axis: String,
    /// Distance from the set position at takeover \[u\].
    pub distance: f64,
    /// Velocity (> 0) \[u/s\].
    pub velocity: f64,
    /// Acceleration (0 = axis default).
    pub acceleration: f64,
    /// Deceleration (0 = axis default).
    pub deceleration: f64,
    /// Jerk (0 = axis default).
    pub jerk: f64,
    /// BufferMode.
    pub buffer_mode: BufferMode,
    /// Options.
    pub options: MoveOptions,
}

/// MC_MoveAdditive (§4.8.3).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MoveAdditive {
    /// Axis name.
    pub axis: String,
    /// Distance added to the last commanded target \[u\].
    pub distance: f64,
    /// Velocity (> 0) \[u/s\].
    pub velocity: f64,
    /// Acceleration (0 = axis default).
    pub acceleration: f64,
    /// Deceleration (0 = axis default).
    pub deceleration: f64,
    /// Jerk (0 = axis default).
    pub jerk: f64,
    /// BufferMode.
    pub buffer_mode: BufferMode,
    /// Options.
    pub options: MoveOptions,
}

/// MC_MoveModulo (§4.8.4).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MoveModulo {
    /// Axis name.
    pub axis: String,
    /// Position: modulo target (≥ 0; ≥ period requests extra turns) \[u\].
    pub position: f64,
    /// Velocity (> 0) \[u/s\].
    pub velocity: f64,
    /// Acceleration (0 = axis default).
    pub acceleration: f64,
    /// Deceleration (0 = axis default).
    pub deceleration: f64,
    /// Jerk (0 = axis default).
    pub jerk: f64,
    /// Direction.
    pub direction: Direction,
    /// BufferMode.
    pub buffer_mode: BufferMode,
    /// Options.
    pub options: MoveOptions,
}

/// MC_MoveVelocity (§4.8.6).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MoveVelocity {
    /// Axis name.
    pub axis: String,
    /// Velocity (> 0) \[u/s\].
    pub velocity: f64,
    /// Acceleration (0 = axis default).
    pub acceleration: f64,
    /// Deceleration (0 = axis default).
    pub deceleration: f64,
    /// Jerk (0 = axis default).
    pub jerk: f64,
    /// Direction (Positive, Negative or Current).
    pub direction: Direction,
    /// BufferMode.
    pub buffer_mode: BufferMode,
    /// Options.
    pub options: MoveOptions,
}

/// MC_MoveContinuousAbsolute (§4.8.7): to `position`, then endless at `end_velocity`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MoveContinuousAbsolute {
    /// Axis name.
    pub axis: String,
    /// Position: absolute target \[u\].
    pub position: f64,
    /// Velocity (> 0) \[u/s\].
    pub velocity: f64,
    /// EndVelocity (≥ 0) in the direction of approach \[u/s\].
    pub end_velocity: f64,
    /// Acceleration (0 = axis default).
    pub acceleration: f64,
    /// Deceleration (0 = axis default).
    pub deceleration: f64,
    /// Jerk (0 = axis default).
    pub jerk: f64,
    /// BufferMode.
    pub buffer_mode: BufferMode,
    /// Options.
    pub options: MoveOptions,
}

/// MC_MoveContinuousRelative (§4.8.8): as MC_MoveContinuousAbsolute with a distance.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MoveContinuousRelative {
    /// Axis name.
    pub axis: String,
    /// Distance from the set position at takeover \[u\].
    pub distance: f64,
    /// Velocity (> 0) \[u/s\].
    pub velocity: f64,
    /// EndVelocity (≥ 0) in the direction of approach \[u/s\].
    pub end_velocity: f64,
    /// Acceleration (0 = axis default).
    pub acceleration: f64,
    /// Deceleration (0 = axis default).
    pub deceleration: f64,
    /// Jerk (0 = axis default).
    pub jerk: f64,
    /// BufferMode.
    pub buffer_mode: BufferMode,
    /// Options.
    pub options: MoveOptions,
}

/// MC_Halt (§4.8.9).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Halt {
    /// Axis name.
    pub axis: String,
    /// Deceleration (≤ 0 → last move's; never weaker than the active command).
    pub deceleration: f64,
    /// Jerk (≤ 0 → last move's; never weaker than the active command).
    pub jerk: f64,
    /// BufferMode.
    pub buffer_mode: BufferMode,
    /// Options.
    pub options: MoveOptions,
}

/// MC_Stop (§4.8.10): stops and locks the axis until Execute falls (see
/// `AxisCommand::SetExecute` of the axis engine, or [`crate::AxisSet::set_execute`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Stop {
    /// Axis name.
    pub axis: String,
    /// Deceleration (≤ 0 → last move's; never weaker than the active command).
    pub deceleration: f64,
    /// Jerk (≤ 0 → last move's; never weaker than the active command).
    pub jerk: f64,
    /// Options.
    pub options: MoveOptions,
}

/// MC_SetPosition (§4.3).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SetPosition {
    /// Axis name.
    pub axis: String,
    /// Position (absolute) or shift (relative) \[u\].
    pub position: f64,
    /// Mode: FALSE = absolute, TRUE = relative.
    pub mode: bool,
    /// Options.
    pub options: SetPositionOptions,
}

/// MC_ReadParameter (§4.4.5), read once; the reply carries the value.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReadParameter {
    /// Axis name.
    pub axis: String,
    /// ParameterNumber (MC_AxisParameter, §6).
    pub parameter_number: u32,
}

/// MC_ReadBoolParameter (§4.4.5).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReadBoolParameter {
    /// Axis name.
    pub axis: String,
    /// ParameterNumber (MC_AxisParameter, §6).
    pub parameter_number: u32,
}

/// MC_WriteParameter (§4.4.8).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WriteParameter {
    /// Axis name.
    pub axis: String,
    /// ParameterNumber (MC_AxisParameter, §6).
    pub parameter_number: u32,
    /// Value.
    pub value: f64,
}

/// MC_WriteBoolParameter (§4.4.8).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WriteBoolParameter {
    /// Axis name.
    pub axis: String,
    /// ParameterNumber (MC_AxisParameter, §6).
    pub parameter_number: u32,
    /// Value.
    pub value: bool,
}

/// MC_ReadStatus (§4.4.7); the reply carries the status.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReadStatus {
    /// Axis name.
    pub axis: String,
}

/// MC_ReadActualPosition (§4.4.1); the reply carries ActPos.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReadActualPosition {
    /// Axis name.
    pub axis: String,
}

/// MC_ReadActualVelocity (§4.4.2); the reply carries ActVelo.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReadActualVelocity {
    /// Axis name.
    pub axis: String,
}

/// MC_ReadAxisError (§4.4.4); the reply carries the axis error id.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReadAxisError {
    /// Axis name.
    pub axis: String,
}

/// Simulation hooks (§1.5, not part of Tc2_MC2).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Sim {
    /// `inject_axis_error(axis, error_id)`: raise an axis error (0 → 0x4550).
    InjectAxisError {
        /// Axis name.
        axis: String,
        /// Axis error id.
        error_id: u32,
    },
    /// A drive fault: the power stage switches off (Status FALSE), the axis stops at once and
    /// goes to ErrorStop with `error_id` (0 → 0x4550); cleared by MC_Reset.
    DriveFault {
        /// Axis name.
        axis: String,
        /// Axis error id reported for the fault.
        error_id: u32,
    },
    /// Level of the virtual touch-probe input of unit 1 or 2 (§1.5).
    ProbeInput {
        /// Axis name.
        axis: String,
        /// Probe unit (1 or 2).
        unit: u32,
        /// Level.
        level: bool,
    },
    /// `set_following_offset(axis, offset)`: ActPos = SetPos + offset.
    SetFollowingOffset {
        /// Axis name.
        axis: String,
        /// Offset \[u\].
        offset: f64,
    },
}
