//! Inputs, enumerations and values of the §4.7 extension FBs (their commands and replies),
//! single_axis.md §4.7: vocabulary of the single axis, knowing no engine.

use serde::{Deserialize, Serialize};

crate::inputs::raw_enum! {
    /// `E_DriveOperationMode` (§5.3).
    DriveOperationMode: "DriveOperationMode" {
        /// DriveOperationMode_Default (0): re-activate the NC default mode (Pos1).
        Default = 0,
        /// DriveOperationMode_Torque (1): CoE CST.
        Torque = 1,
        /// DriveOperationMode_Velo1 (2): CoE CSV.
        Velo1 = 2,
        /// DriveOperationMode_Velo2 (3).
        Velo2 = 3,
        /// DriveOperationMode_Pos1 (4): CoE CSP (the simulator's default).
        #[default]
        Pos1 = 4,
        /// DriveOperationMode_Pos2 (5).
        Pos2 = 5,
        /// DriveOperationMode_TorqueAndCommutationAngle (6).
        TorqueAndCommutationAngle = 6,
        /// DriveOperationMode_VelocityMode (34).
        VelocityMode = 34,
        /// DriveOperationMode_DriveBasedHoming (38).
        DriveBasedHoming = 38,
        /// DriveOperationMode_Index0 (100).
        Index0 = 100,
        /// DriveOperationMode_Index1 (101).
        Index1 = 101,
        /// DriveOperationMode_Index2 (102).
        Index2 = 102,
        /// DriveOperationMode_Index3 (103).
        Index3 = 103,
    }
}

crate::inputs::raw_enum! {
    /// `E_DisableMode` (§5.3).
    DisableMode: "DisableMode" {
        /// DisableModeHold (0, default): keep the last correction.
        #[default]
        Hold = 0,
        /// DisableModeReset (1): set the correction to 0.
        Reset = 1,
    }
}

crate::inputs::raw_enum! {
    /// `E_AxisPositionCorrectionMode` (§5.3; declared as E_PositionCorrectionMode).
    PositionCorrectionMode: "CorrectionMode" {
        /// POSITIONCORRECTION_MODE_UNLIMITED (0): at once.
        #[default]
        Unlimited = 0,
        /// POSITIONCORRECTION_MODE_FAST (1): limited by Acceleration·cycle².
        Fast = 1,
        /// POSITIONCORRECTION_MODE_FULLLENGTH (2): spread over CorrectionLength of travel.
        FullLength = 2,
    }
}

crate::inputs::raw_enum! {
    /// `E_WorkDirection` (§5.3).
    WorkDirection: "Direction" {
        /// WorkDirectionNone (0): no compensation.
        None = 0,
        /// WorkDirectionBoth (1, default).
        #[default]
        Both = 1,
        /// WorkDirectionPositive (2).
        Positive = 2,
        /// WorkDirectionNegative (3).
        Negative = 3,
    }
}

crate::inputs::raw_enum! {
    /// `E_SelectControlLoopType` (§5.3; declared as E_SelectControlLoop).
    SelectControlLoopType: "SelectType" {
        /// SelectControlLoopType_Undefined (0).
        Undefined = 0,
        /// SelectControlLoopType_Standard (1, the only usable one).
        #[default]
        Standard = 1,
        /// SelectControlLoopType_InternalSyncValue (2).
        InternalSyncValue = 2,
        /// SelectControlLoopType_UserSyncValue (3).
        UserSyncValue = 3,
    }
}

crate::inputs::raw_enum! {
    /// `E_SetScalingFactorMode` (§5.3).
    SetScalingFactorMode: "Mode" {
        /// ENCODERSCALINGMODE_ABSOLUTE (0): the position jumps.
        #[default]
        Absolute = 0,
        /// ENCODERSCALINGMODE_RELATIVE (1): the offset keeps the position.
        Relative = 1,
    }
}

crate::inputs::raw_enum! {
    /// `E_NcIoDevice` (§5.3).
    NcIoDevice: "Device" {
        /// NcIoDeviceDrive (0, default).
        #[default]
        Drive = 0,
        /// NcIoDeviceEncoder (1).
        Encoder = 1,
    }
}

crate::inputs::raw_enum! {
    /// `E_NcIoOutput` (§5.3).
    NcIoOutput: "NcIoOutput" {
        /// NcIoOutputnCtrl1 (0, default).
        #[default]
        NCtrl1 = 0,
        /// NcIoOutputnCtrl2 (1).
        NCtrl2 = 1,
        /// NcIoOutputnCtrl3 (2).
        NCtrl3 = 2,
        /// NcIoOutputnCtrl4 (3).
        NCtrl4 = 3,
        /// NcIoOutputnCtrl5 (4).
        NCtrl5 = 4,
        /// NcIoOutputnCtrl6 (5).
        NCtrl6 = 5,
        /// NcIoOutputnCtrl7 (6).
        NCtrl7 = 6,
        /// NcIoOutputnCtrl8 (7).
        NCtrl8 = 7,
        /// NcIoOutputnDataOut1 (8).
        NDataOut1 = 8,
        /// NcIoOutputnDataOut2 (9).
        NDataOut2 = 9,
        /// NcIoOutputnDataOut3 (10).
        NDataOut3 = 10,
        /// NcIoOutputnDataOut4 (11).
        NDataOut4 = 11,
        /// NcIoOutputnDataOut5 (12).
        NDataOut5 = 12,
        /// NcIoOutputnDataOut6 (13).
        NDataOut6 = 13,
    }
}

/// MC_ReadDriveOperationMode (§4.7.1). Reply [`ExtensionValue::DriveOperationMode`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReadDriveOperationMode {
    /// Axis name.
    pub axis: String,
}

/// MC_WriteDriveOperationMode (§4.7.1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WriteDriveOperationMode {
    /// Axis name.
    pub axis: String,
    /// DriveOperationMode (Default = back to Pos1).
    pub drive_operation_mode: DriveOperationMode,
}

/// MC_BacklashCompensation (§4.7.2, W20; Enable-type).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BacklashCompensation {
    /// Axis name.
    pub axis: String,
    /// Enable.
    pub enable: bool,
    /// Backlash: signed compensation value; 0 = AxisBacklash (1036) \[u\].
    pub backlash: f64,
    /// CompensationInPositiveDirection: TRUE compensates while moving positive.
    pub compensation_in_positive_direction: bool,
    /// Ramp: rate of change of the correction (0 = at once) \[u/s\].
    pub ramp: f64,
    /// DisableMode at Enable↓.
    pub disable_mode: DisableMode,
}

/// MC_PositionCorrectionLimiter (§4.7.5; Enable-type).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PositionCorrectionLimiter {
    /// Axis name.
    pub axis: String,
    /// Enable.
    pub enable: bool,
    /// PositionCorrectionValue \[u\] (read every call).
    pub position_correction_value: f64,
    /// CorrectionMode.
    pub correction_mode: PositionCorrectionMode,
    /// Acceleration (FAST: max change per cycle = Acceleration·cycle²; 0 = no limit) \[u/s²\].
    pub acceleration: f64,
    /// CorrectionLength (FULLLENGTH: travel over which a change is spread, > 0) \[u\].
    pub correction_length: f64,
}

/// `ST_PositionCompensationTableElement` (§5.4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PositionCompensationTableElement {
    /// Position (uncorrected, e.g. SetPos) \[u\].
    pub position: f64,
    /// Compensation (additive) \[u\].
    pub compensation: f64,
}

/// `ST_PositionCompensationTableParameter` (§5.4).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PositionCompensationTableParameter {
    /// MinPosition \[u\] (= first table position).
    pub min_position: f64,
    /// MaxPosition \[u\] (= last table position).
    pub max_position: f64,
    /// NoOfTableElements (= table length).
    pub no_of_table_elements: u32,
    /// Direction.
    pub direction: WorkDirection,
    /// Modulo: FALSE linear, TRUE cyclic over [MinPosition, MaxPosition).
    pub modulo: bool,
}

/// MC_TableBasedPositionCompensation (§4.7.12, W11; Enable-type). `pTable`/`TableSize` are
/// the `table` array.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TableBasedPositionCompensation {
    /// Axis name.
    pub axis: String,
    /// Enable.
    pub enable: bool,
    /// The table (pTable, TableSize): equidistant, strictly increasing positions.
    pub table: Vec<PositionCompensationTableElement>,
    /// TableParameter.
    pub table_parameter: PositionCompensationTableParameter,
    /// Ramp: rate of change of the correction (0 = at once) \[u/s\].
    pub ramp: f64,
    /// DisableMode at Enable↓.
    pub disable_mode: DisableMode,
}

/// MC_ReadDriveAddress (§4.7.6). Reply [`ExtensionValue::DriveAddress`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReadDriveAddress {
    /// Axis name.
    pub axis: String,
}

/// MC_SelectControlLoop (§4.7.7).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SelectControlLoop {
    /// Axis name.
    pub axis: String,
    /// EncoderIndex: control loop to activate (only 0 exists).
    pub encoder_index: u16,
    /// SelectType (only Standard).
    pub select_type: SelectControlLoopType,
    /// SyncValue (not applicable; must be finite).
    pub sync_value: f64,
    /// ExtSetPointGen (not applicable).
    pub ext_set_point_gen: bool,
}

/// MC_SetAcceptBlockedDriveSignal (§4.7.8, FUNCTION : BOOL): reply `Bool(false)`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SetAcceptBlockedDriveSignal {
    /// Axis name.
    pub axis: String,
    /// Enable: ControlDWord bit 8 AcceptBlockedDrive.
    pub enable: bool,
}

/// `ST_SetEncoderScalingOptions` (§5.4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SetEncoderScalingOptions {
    /// SelectEncoderIndex.
    pub select_encoder_index: bool,
    /// EncoderIndex (only 0 exists).
    pub encoder_index: u16,
}

/// MC_SetEncoderScalingFactor (§4.7.9).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SetEncoderScalingFactor {
    /// Axis name.
    pub axis: String,
    /// ScalingFactor (> 0) \[u/inc\].
    pub scaling_factor: f64,
    /// Mode.
    pub mode: SetScalingFactorMode,
    /// Options.
    pub options: SetEncoderScalingOptions,
}

/// MC_WriteNcIoOutput (§4.7.11).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WriteNcIoOutput {
    /// Axis name.
    pub axis: String,
    /// Device.
    pub device: NcIoDevice,
    /// NcIoOutput.
    pub nc_io_output: NcIoOutput,
    /// BitSelectMask.
    pub bit_select_mask: u32,
    /// BitValues.
    pub bit_values: u32,
}

/// `ST_NcPositionConversionOptions` (§5.4; informational).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct NcPositionConversionOptions {
    /// SubIndex.
    pub sub_index: u16,
    /// CtrlMask.
    pub ctrl_mask: u16,
}

/// MC_ConvertIncPosToPos (§4.7.13). Reply `Real(Position)`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ConvertIncPosToPos {
    /// Axis name.
    pub axis: String,
    /// IncPos: encoder increments (32-bit counter).
    pub inc_pos: u32,
    /// Options.
    pub options: NcPositionConversionOptions,
}

/// MC_ConvertPosToIncPos (§4.7.13). Reply `DWord(IncPos)`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ConvertPosToIncPos {
    /// Axis name.
    pub axis: String,
    /// Position \[u\].
    pub position: f64,
    /// Options.
    pub options: NcPositionConversionOptions,
}

/// MC_ReadParameterSet (§4.4.6). Reply [`ExtensionValue::ParameterSet`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReadParameterSet {
    /// Axis name.
    pub axis: String,
}

/// MC_ReadAxisComponents (§4.4.3). Reply [`ExtensionValue::AxisComponents`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReadAxisComponents {
    /// Axis name.
    pub axis: String,
}

/// `ST_AxisComponents` (§4.4.3): ids of the NC sub-objects, ARRAY\[1..9\] each (index 0 here
/// = element 1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AxisComponents {
    /// EncoderIDs.
    pub encoder_ids: [u32; 9],
    /// ControllerIDs.
    pub controller_ids: [u32; 9],
    /// DriveIDs.
    pub drive_ids: [u32; 9],
}

/// `ST_DriveAddress` (§5.2).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DriveAddress {
    /// NetID (T_AmsNetId).
    pub net_id: String,
    /// NetIdBytes.
    pub net_id_bytes: [u8; 6],
    /// SlaveAddress (AMS port).
    pub slave_address: u16,
    /// Channel.
    pub channel: u8,
    /// NcDriveId.
    pub nc_drive_id: u32,
    /// NcDriveIndex.
    pub nc_drive_index: u32,
    /// NcDriveType (E_NcDriveType).
    pub nc_drive_type: u32,
    /// NcEncoderId.
    pub nc_encoder_id: u32,
    /// NcEncoderIndex.
    pub nc_encoder_index: u32,
    /// NcEncoderType (E_NcEncoderType; 1 = Simulation).
    pub nc_encoder_type: u32,
    /// NcAxisId.
    pub nc_axis_id: u32,
    /// NcAxisType (E_NcAxisType; 1 = Continious).
    pub nc_axis_type: u32,
    /// TcDriveObjectId.
    pub tc_drive_object_id: u32,
    /// TcEncoderObjectId.
    pub tc_encoder_object_id: u32,
    /// TcAxisObjectId.
    pub tc_axis_object_id: u32,
}

/// `ST_AxisParameterSet` (§5.6), the members the simulator has a value for (others omitted;
/// names as the manual's without type prefix).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AxisParameterSet {
    /// AxisId.
    pub axis_id: u32,
    /// nAxisType (E_NcAxisType).
    pub axis_type: u32,
    /// sAxisName.
    pub axis_name: String,
    /// fAxisCycleTime \[s\].
    pub axis_cycle_time: f64,
    /// bEnablePositionAreaControl.
    pub enable_position_area_control: bool,
    /// fPositionAreaControlRange \[u\].
    pub position_area_control_range: f64,
    /// bEnableTargetPosControl.
    pub enable_target_pos_control: bool,
    /// fTargetPosControlRange \[u\].
    pub target_pos_control_range: f64,
    /// fTargetPosControlTime \[s\].
    pub target_pos_control_time: f64,
    /// fVeloMaximum \[u/s\].
    pub velo_maximum: f64,
    /// fRefVeloSearch \[u/s\].
    pub ref_velo_search: f64,
    /// fRefVeloSync \[u/s\].
    pub ref_velo_sync: f64,
    /// fVeloSlowManual \[u/s\].
    pub velo_slow_manual: f64,
    /// fVeloFastManual \[u/s\].
    pub velo_fast_manual: f64,
    /// bEnablePEHTimeControl.
    pub enable_peh_time_control: bool,
    /// fPEHControlTime \[s\].
    pub peh_control_time: f64,
    /// bEnableBacklashCompensation.
    pub enable_backlash_compensation: bool,
    /// fBacklash \[u\].
    pub backlash: f64,
    /// sAmsNetId.
    pub ams_net_id: String,
    /// nPort.
    pub port: u16,
    /// nChnNo.
    pub chn_no: u16,
    /// fAcceleration \[u/s²\].
    pub acceleration: f64,
    /// fDeceleration \[u/s²\].
    pub deceleration: f64,
    /// fJerk \[u/s³\].
    pub jerk: f64,
    /// nEncId.
    pub enc_id: u32,
    /// nEncType (E_NcEncoderType).
    pub enc_type: u32,
    /// fEncScaleFactor \[u/inc\].
    pub enc_scale_factor: f64,
    /// fEncOffset \[u\].
    pub enc_offset: f64,
    /// fEncModuloFactor \[u\].
    pub enc_modulo_factor: f64,
    /// bEncEnableSoftEndMinControl.
    pub enc_enable_soft_end_min_control: bool,
    /// bEncEnableSoftEndMaxControl.
    pub enc_enable_soft_end_max_control: bool,
    /// fEncSoftEndMin \[u\].
    pub enc_soft_end_min: f64,
    /// fEncSoftEndMax \[u\].
    pub enc_soft_end_max: f64,
    /// nEncMaxIncrement (32-bit counter).
    pub enc_max_increment: u32,
    /// bEncEnablePosCorrection.
    pub enc_enable_pos_correction: bool,
    /// bEncRefSearchInverse.
    pub enc_ref_search_inverse: bool,
    /// bEncRefSyncInverse.
    pub enc_ref_sync_inverse: bool,
    /// nEncRefMode (E_EncoderReferenceMode).
    pub enc_ref_mode: u32,
    /// fEncRefPosition \[u\].
    pub enc_ref_position: f64,
    /// nCtrlId.
    pub ctrl_id: u32,
    /// bCtrlEnablePosDiffControl.
    pub ctrl_enable_pos_diff_control: bool,
    /// fCtrlPosDiffMax \[u\].
    pub ctrl_pos_diff_max: f64,
    /// fCtrlPosDiffMaxTime \[s\].
    pub ctrl_pos_diff_max_time: f64,
    /// fCtrlPosKp \[1/s\].
    pub ctrl_pos_kp: f64,
    /// nDriveId.
    pub drive_id: u32,
    /// nDriveType (E_NcDriveType).
    pub drive_type: u32,
    /// fAccelerationMax \[u/s²\].
    pub acceleration_max: f64,
    /// fDecelerationMax \[u/s²\].
    pub deceleration_max: f64,
}

/// Structured reply values of the extension read FBs (the engine's `ReplyValue::Extension`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ExtensionValue {
    /// MC_ReadDriveOperationMode.DriveOperationMode.
    DriveOperationMode(DriveOperationMode),
    /// MC_ReadParameterSet.Parameter.
    ParameterSet(AxisParameterSet),
    /// MC_ReadAxisComponents.AxisComponents.
    AxisComponents(AxisComponents),
    /// MC_ReadDriveAddress.DriveAddress.
    DriveAddress(DriveAddress),
}
