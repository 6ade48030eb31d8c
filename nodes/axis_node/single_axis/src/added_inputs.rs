//! Inputs of the FBs added to the single axis later: the external set-point generator
//! (MC_ExtSetPointGen*, §4.6), MC_GearInMultiMaster (§4.12.4) and phasing
//! (MC_PhasingAbsolute/Relative, MC_HaltPhasing, §4.13); and their status values
//! ([`ExtStatus`]). Plain data, as the other FB inputs.

pub use crate::added::{GearInMultiMasterOptions, GearInMultiMasterSyncMode};
use crate::inputs::BufferMode;
use motion_core::CmdId;
use serde::{Deserialize, Serialize};

crate::raw_enum! {
    /// `E_PositionType` (§5.3).
    PositionType: "PositionType" {
        /// POSITIONTYPE_ABSOLUTE (1).
        #[default]
        Absolute = 1,
        /// POSITIONTYPE_RELATIVE (2).
        Relative = 2,
    }
}

/// `ST_ExtSetPointEnableOptions` (§5.4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ExtSetPointEnableOptions {
    /// UseTorqueOffset: forward TorqueOffset of MC_ExtSetPointGenFeedWithTorque.
    pub use_torque_offset: bool,
}

/// MC_ExtSetPointGenEnable (§4.6.1). Reply: the instance (Done next cycle); its extra output
/// [`crate::handshake::ExtraOutputs::ExtSetPointGen`] `enabled` is the live generator state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ExtSetPointGenEnable {
    /// Axis name.
    pub axis: String,
    /// Position for the target monitoring only \[u\].
    pub position: f64,
    /// PositionType.
    pub position_type: PositionType,
    /// Options.
    pub options: ExtSetPointEnableOptions,
}

/// MC_ExtSetPointGenDisable (§4.6.2).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ExtSetPointGenDisable {
    /// Axis name.
    pub axis: String,
}

/// MC_ExtSetPointGenFeed (§4.6.3, FUNCTION : BOOL): reply `ReplyValue::Bool(false)`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ExtSetPointGenFeed {
    /// Axis name.
    pub axis: String,
    /// Position \[u\].
    pub position: f64,
    /// Velocity \[u/s\].
    pub velocity: f64,
    /// Acceleration \[u/s²\].
    pub acceleration: f64,
    /// Direction: −1 negative, 0 standstill, +1 positive.
    pub direction: i32,
}

/// MC_ExtSetPointGenFeedWithTorque (§4.6.4, FUNCTION : BOOL): reply `ReplyValue::Bool(false)`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ExtSetPointGenFeedWithTorque {
    /// Axis name.
    pub axis: String,
    /// Position \[u\].
    pub position: f64,
    /// Velocity \[u/s\].
    pub velocity: f64,
    /// Acceleration \[u/s²\].
    pub acceleration: f64,
    /// Direction: −1, 0, +1.
    pub direction: i32,
    /// TorqueOffset (→ `PlcToNc.ExtTorque`) \[%\].
    pub torque_offset: f64,
}

/// MC_GearInMultiMaster (§4.12.4, Enable-type): one call with the current inputs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GearInMultiMaster {
    /// Slave axis name.
    pub slave: String,
    /// Master1 axis name ("" = unused, an empty AXIS_REF).
    pub master1: String,
    /// Master2 axis name ("" = unused).
    pub master2: String,
    /// Master3 axis name ("" = unused).
    pub master3: String,
    /// Master4 axis name ("" = unused).
    pub master4: String,
    /// Enable.
    pub enable: bool,
    /// GearRatio1 (read every call while Enable).
    pub gear_ratio1: f64,
    /// GearRatio2.
    pub gear_ratio2: f64,
    /// GearRatio3.
    pub gear_ratio3: f64,
    /// GearRatio4.
    pub gear_ratio4: f64,
    /// Acceleration (≥ 0; 0 = slave AxisAcc) \[u/s²\].
    pub acceleration: f64,
    /// Deceleration (≥ 0; 0 = slave AxisDec; only with AdvancedSlaveDynamics) \[u/s²\].
    pub deceleration: f64,
    /// Jerk (≥ 0; 0 = slave AxisJerk; only with AdvancedSlaveDynamics) \[u/s³\].
    pub jerk: f64,
    /// BufferMode (not implemented by Tc2_MC2; ignored).
    pub buffer_mode: BufferMode,
    /// Options.
    pub options: GearInMultiMasterOptions,
}

/// MC_PhasingAbsolute (§4.13.1): establish the phase shift `phase_shift`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PhasingAbsolute {
    /// Master axis name.
    pub master: String,
    /// Slave axis name (the axis that is shifted).
    pub slave: String,
    /// ContinuousUpdate: inputs may change while running ([`PhasingUpdate`]).
    pub continuous_update: bool,
    /// PhaseShift: the absolute phase shift φ to establish \[slave u\].
    pub phase_shift: f64,
    /// Velocity (≥ 0.01) of the phasing motion \[u/s\].
    pub velocity: f64,
    /// Acceleration (0 = slave AxisAcc) \[u/s²\].
    pub acceleration: f64,
    /// Deceleration (0 = slave AxisDec) \[u/s²\].
    pub deceleration: f64,
    /// Jerk for both ramps (0 = slave AxisJerk) \[u/s³\].
    pub jerk: f64,
    /// BufferMode (only MC_Aborting).
    pub buffer_mode: BufferMode,
}

/// MC_PhasingRelative (§4.13.2): change the phase shift by `phase_shift`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PhasingRelative {
    /// Master axis name.
    pub master: String,
    /// Slave axis name.
    pub slave: String,
    /// ContinuousUpdate: inputs may change while running ([`PhasingUpdate`]).
    pub continuous_update: bool,
    /// PhaseShift: change of φ relative to φ at the edge \[slave u\].
    pub phase_shift: f64,
    /// Velocity (≥ 0.01) \[u/s\].
    pub velocity: f64,
    /// Acceleration (0 = slave AxisAcc) \[u/s²\].
    pub acceleration: f64,
    /// Deceleration (0 = slave AxisDec) \[u/s²\].
    pub deceleration: f64,
    /// Jerk (0 = slave AxisJerk) \[u/s³\].
    pub jerk: f64,
    /// BufferMode (only MC_Aborting).
    pub buffer_mode: BufferMode,
}

/// MC_HaltPhasing (§4.13.3): jerk-limited stop of the running phasing motion.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HaltPhasing {
    /// Master axis name.
    pub master: String,
    /// Slave axis name.
    pub slave: String,
    /// Deceleration (max; 0 = slave AxisDec) \[u/s²\].
    pub deceleration: f64,
    /// Jerk (max; 0 = slave AxisJerk) \[u/s³\].
    pub jerk: f64,
    /// BufferMode (only MC_Aborting).
    pub buffer_mode: BufferMode,
}

/// A later call of a running MC_PhasingAbsolute/Relative instance started with
/// ContinuousUpdate: new PhaseShift and dynamics (ignored without ContinuousUpdate, §3.1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PhasingUpdate {
    /// The instance.
    pub id: CmdId,
    /// PhaseShift (absolute φ or relative to φ at the edge, as the instance's FB).
    pub phase_shift: f64,
    /// Velocity (≥ 0.01).
    pub velocity: f64,
    /// Acceleration (0 = default).
    pub acceleration: f64,
    /// Deceleration (0 = default).
    pub deceleration: f64,
    /// Jerk (0 = default).
    pub jerk: f64,
}

/// Status values of the added functions (NCTOPLC / PLCTONC fields not in [`crate::status::AxisStatus`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ExtStatus {
    /// NcToPlc.AbsPhasingPos: phasing offset φ \[u\].
    pub abs_phasing_pos: f64,
    /// Status.PhasingActive (StateDWord bit 15).
    pub phasing_active: bool,
    /// Status.ExtSetPointGenEnabled (StateDWord bit 14).
    pub ext_set_point_gen_enabled: bool,
    /// PlcToNc.ExtSetPos/ExtSetVelo/ExtSetAcc as last fed.
    pub ext_set_pos: f64,
    /// PlcToNc.ExtSetVelo.
    pub ext_set_velo: f64,
    /// PlcToNc.ExtSetAcc.
    pub ext_set_acc: f64,
    /// PlcToNc.ExtSetDirection.
    pub ext_set_direction: i32,
    /// PlcToNc.ExtTorque (TorqueOffset, only with UseTorqueOffset) \[%\].
    pub ext_torque: f64,
    /// Drive operation mode (E_DriveOperationMode).
    pub drive_operation_mode: crate::extension_inputs::DriveOperationMode,
    /// Total position correction (backlash + limiter + table) \[u\].
    pub position_correction: f64,
    /// NcToPlc.ActPosWithoutPosCorrection \[u\].
    pub act_pos_without_pos_correction: f64,
    /// Set position sent to the drive (SetPos − correction) \[u\].
    pub drive_set_pos: f64,
    /// Encoder scaling factor \[u/inc\] and offset \[u\].
    pub encoder_scaling_factor: f64,
    /// Encoder offset \[u\].
    pub encoder_offset: f64,
    /// Encoder counter (32 bit) at the actual position.
    pub encoder_increments: u32,
    /// NcToPlc.ActiveControlLoopIndex / ControlLoopIndex.
    pub control_loop_index: u16,
    /// ControlDWord bit 8 AcceptBlockedDrive.
    pub accept_blocked_drive: bool,
    /// MC_WriteNcIoOutput images: `[device][output]` (Drive, Encoder × nCtrl1..8,
    /// nDataOut1..6).
    pub nc_io_outputs: [[u32; 14]; 2],
    /// Coupled to several masters (MC_GearInMultiMaster): their names.
    pub masters: Vec<String>,
}
