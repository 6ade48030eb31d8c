//! `MC_AxisParameter` numbers for MC_Read/Write(Bool)Parameter (single_axis.md §6, §4.4.5,
//! §4.4.8).
//!
//! [`PARAMETERS`] is the whole table as data: number, name, type and storage [`Slot`].
//! Aliases (e.g. 2 SWLimitPos ≡ 1019 AxisMaxSoftPosLimit) share one slot, so they stay
//! consistent. Parameters the simulator does not use are stored by their NC index offset
//! (`Slot::Other`), default 0.

use crate::config::AxisConfig;

/// Declared type of a parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamType {
    /// BOOL.
    Bool,
    /// LREAL.
    LReal,
    /// DWORD (read and written as a number).
    DWord,
}

/// Where a parameter lives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slot {
    /// Read-only value from the cyclic interface or axis status.
    Status(StatusValue),
    /// A key of [`AxisConfig`].
    Config(ConfigKey),
    /// Stored without simulator effect, keyed by the NC index offset.
    Other(u32),
    /// AxisGearRatio (3000): only while the axis is a coupled slave.
    GearRatio,
}

/// Read-only values (§6: 1, 10, 11, 1000, 2000–2003, 4000, 4001).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StatusValue {
    /// 1 CommandedPosition (SetPos).
    CommandedPosition,
    /// 10 ActualVelocity.
    ActualVelocity,
    /// 11 CommandedVelocity.
    CommandedVelocity,
    /// 1000 AxisId.
    AxisId,
    /// 2000 AxisTargetPosition.
    TargetPosition,
    /// 2001 AxisRemainingTimeToGo.
    RemainingTimeToGo,
    /// 2002 AxisRemainingDistanceToGo.
    RemainingDistanceToGo,
    /// 2003 AxisMcSetPositionOffset.
    SetPositionOffset,
    /// 4000 NcSafCycleTime.
    SafCycleTime,
    /// 4001 NcSvbCycleTime.
    SvbCycleTime,
}

/// Writable parameters backed by [`AxisConfig`] keys.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum ConfigKey {
    MaxSoftPosLimit,
    MinSoftPosLimit,
    EnMaxSoftPosLimit,
    EnMinSoftPosLimit,
    EnPositionLagMonitoring,
    MaxPosLagValue,
    MaxPosLagFilterTime,
    MaxVelocity,
    Acceleration,
    Deceleration,
    Jerk,
    ManualVelocitySlow,
    ManualVelocityFast,
    RapidTraverseVelocity,
    CalibrationVelocityForward,
    CalibrationVelocityBackward,
    JogIncrementForward,
    JogIncrementBackward,
    EnPositionRangeMonitoring,
    PositionRangeWindow,
    EnTargetPositionMonitoring,
    TargetPositionWindow,
    TargetPositionMonitoringTime,
    EnInTargetTimeout,
    InTargetTimeout,
    Backlash,
    EncoderScalingFactor,
    EncoderOffset,
    ModuloValue,
    ModuloToleranceWindow,
    EnablePosCorrection,
    CycleTime,
    FastAcceleration,
    FastDeceleration,
    FastJerk,
    CoupleSlaveToActualValues,
    AllowMotionCmdToSlaveAxis,
    AllowMotionCmdToExtSetAxis,
    HomingInvDirCamSearch,
    HomingInvDirSyncSearch,
    HomingCalibValue,
    EncoderReferenceMode,
    PositionControlKv,
}

impl ConfigKey {
    /// The configuration key name (for messages).
    pub fn key(self) -> &'static str {
        use ConfigKey::*;
        match self {
            MaxSoftPosLimit => "max_soft_pos_limit",
            MinSoftPosLimit => "min_soft_pos_limit",
            EnMaxSoftPosLimit => "en_max_soft_pos_limit",
            EnMinSoftPosLimit => "en_min_soft_pos_limit",
            EnPositionLagMonitoring => "en_position_lag_monitoring",
            MaxPosLagValue => "max_pos_lag_value",
            MaxPosLagFilterTime => "max_pos_lag_filter_time",
            MaxVelocity => "max_velocity",
            Acceleration => "acceleration",
            Deceleration => "deceleration",
            Jerk => "jerk",
            ManualVelocitySlow => "manual_velocity_slow",
            ManualVelocityFast => "manual_velocity_fast",
            RapidTraverseVelocity => "rapid_traverse_velocity",
            CalibrationVelocityForward => "calibration_velocity_forward",
            CalibrationVelocityBackward => "calibration_velocity_backward",
            JogIncrementForward => "jog_increment_forward",
            JogIncrementBackward => "jog_increment_backward",
            EnPositionRangeMonitoring => "en_position_range_monitoring",
            PositionRangeWindow => "position_range_window",
            EnTargetPositionMonitoring => "en_target_position_monitoring",
            TargetPositionWindow => "target_position_window",
            TargetPositionMonitoringTime => "target_position_monitoring_time",
            EnInTargetTimeout => "en_in_target_timeout",
            InTargetTimeout => "in_target_timeout",
            Backlash => "backlash",
            EncoderScalingFactor => "encoder_scaling_factor",
            EncoderOffset => "encoder_offset",
            ModuloValue => "modulo_value",
            ModuloToleranceWindow => "modulo_tolerance_window",
            EnablePosCorrection => "enable_pos_correction",
            CycleTime => "cycle_time",
            FastAcceleration => "fast_acceleration",
            FastDeceleration => "fast_deceleration",
            FastJerk => "fast_jerk",
            CoupleSlaveToActualValues => "couple_slave_to_actual_values",
            AllowMotionCmdToSlaveAxis => "allow_motion_cmd_to_slave_axis",
            AllowMotionCmdToExtSetAxis => "allow_motion_cmd_to_ext_set_axis",
            HomingInvDirCamSearch => "homing_inv_dir_cam_search",
            HomingInvDirSyncSearch => "homing_inv_dir_sync_search",
            HomingCalibValue => "homing_calib_value",
            EncoderReferenceMode => "encoder_reference_mode",
            PositionControlKv => "position_control_kv",
        }
    }

    /// Reads the key (BOOL as 0/1).
    pub fn get(self, c: &AxisConfig) -> f64 {
        use ConfigKey::*;
        let b = |x: bool| if x { 1.0 } else { 0.0 };
        match self {
            MaxSoftPosLimit => c.max_soft_pos_limit,
            MinSoftPosLimit => c.min_soft_pos_limit,
            EnMaxSoftPosLimit => b(c.en_max_soft_pos_limit),
            EnMinSoftPosLimit => b(c.en_min_soft_pos_limit),
            EnPositionLagMonitoring => b(c.en_position_lag_monitoring),
            MaxPosLagValue => c.max_pos_lag_value,
            MaxPosLagFilterTime => c.max_pos_lag_filter_time,
            MaxVelocity => c.max_velocity,
            Acceleration => c.acceleration,
            Deceleration => c.deceleration,
            Jerk => c.jerk,
            ManualVelocitySlow => c.manual_velocity_slow,
            ManualVelocityFast => c.manual_velocity_fast,
            RapidTraverseVelocity => c.rapid_traverse_velocity,
            CalibrationVelocityForward => c.calibration_velocity_forward,
            CalibrationVelocityBackward => c.calibration_velocity_backward,
            JogIncrementForward => c.jog_increment_forward,
            JogIncrementBackward => c.jog_increment_backward,
            EnPositionRangeMonitoring => b(c.en_position_range_monitoring),
            PositionRangeWindow => c.position_range_window,
            EnTargetPositionMonitoring => b(c.en_target_position_monitoring),
            TargetPositionWindow => c.target_position_window,
            TargetPositionMonitoringTime => c.target_position_monitoring_time,
            EnInTargetTimeout => b(c.en_in_target_timeout),
            InTargetTimeout => c.in_target_timeout,
            Backlash => c.backlash,
            EncoderScalingFactor => c.encoder_scaling_factor,
            EncoderOffset => c.encoder_offset,
            ModuloValue => c.modulo_value,
            ModuloToleranceWindow => c.modulo_tolerance_window,
            EnablePosCorrection => b(c.enable_pos_correction),
            CycleTime => c.cycle_time,
            FastAcceleration => c.fast_acceleration,
            FastDeceleration => c.fast_deceleration,
            FastJerk => c.fast_jerk,
            CoupleSlaveToActualValues => b(c.couple_slave_to_actual_values),
            AllowMotionCmdToSlaveAxis => b(c.allow_motion_cmd_to_slave_axis),
            AllowMotionCmdToExtSetAxis => b(c.allow_motion_cmd_to_ext_set_axis),
            HomingInvDirCamSearch => b(c.homing_inv_dir_cam_search),
            HomingInvDirSyncSearch => b(c.homing_inv_dir_sync_search),
            HomingCalibValue => c.homing_calib_value,
            EncoderReferenceMode => c.encoder_reference_mode as f64,
            PositionControlKv => c.position_control_kv,
        }
    }

    /// Writes the key (BOOL: value ≠ 0). The caller validates the resulting config.
    pub fn set(self, c: &mut AxisConfig, v: f64) {
        use ConfigKey::*;
        let b = v != 0.0;
        match self {
            MaxSoftPosLimit => c.max_soft_pos_limit = v,
            MinSoftPosLimit => c.min_soft_pos_limit = v,
            EnMaxSoftPosLimit => c.en_max_soft_pos_limit = b,
            EnMinSoftPosLimit => c.en_min_soft_pos_limit = b,
            EnPositionLagMonitoring => c.en_position_lag_monitoring = b,
            MaxPosLagValue => c.max_pos_lag_value = v,
            MaxPosLagFilterTime => c.max_pos_lag_filter_time = v,
            MaxVelocity => c.max_velocity = v,
            Acceleration => c.acceleration = v,
            Deceleration => c.deceleration = v,
            Jerk => c.jerk = v,
            ManualVelocitySlow => c.manual_velocity_slow = v,
            ManualVelocityFast => c.manual_velocity_fast = v,
            RapidTraverseVelocity => c.rapid_traverse_velocity = v,
            CalibrationVelocityForward => c.calibration_velocity_forward = v,
            CalibrationVelocityBackward => c.calibration_velocity_backward = v,
            JogIncrementForward => c.jog_increment_forward = v,
            JogIncrementBackward => c.jog_increment_backward = v,
            EnPositionRangeMonitoring => c.en_position_range_monitoring = b,
            PositionRangeWindow => c.position_range_window = v,
            EnTargetPositionMonitoring => c.en_target_position_monitoring = b,
            TargetPositionWindow => c.target_position_window = v,
            TargetPositionMonitoringTime => c.target_position_monitoring_time = v,
            EnInTargetTimeout => c.en_in_target_timeout = b,
            InTargetTimeout => c.in_target_timeout = v,
            Backlash => c.backlash = v,
            EncoderScalingFactor => c.encoder_scaling_factor = v,
            EncoderOffset => c.encoder_offset = v,
            ModuloValue => c.modulo_value = v,
            ModuloToleranceWindow => c.modulo_tolerance_window = v,
            EnablePosCorrection => c.enable_pos_correction = b,
            CycleTime => c.cycle_time = v,
            FastAcceleration => c.fast_acceleration = v,
            FastDeceleration => c.fast_deceleration = v,
            FastJerk => c.fast_jerk = v,
            CoupleSlaveToActualValues => c.couple_slave_to_actual_values = b,
            AllowMotionCmdToSlaveAxis => c.allow_motion_cmd_to_slave_axis = b,
            AllowMotionCmdToExtSetAxis => c.allow_motion_cmd_to_ext_set_axis = b,
            HomingInvDirCamSearch => c.homing_inv_dir_cam_search = b,
            HomingInvDirSyncSearch => c.homing_inv_dir_sync_search = b,
            HomingCalibValue => c.homing_calib_value = v,
            // Out-of-range values are caught by `AxisConfig::validate`.
            EncoderReferenceMode => {
                c.encoder_reference_mode = if (0.0..=7.0).contains(&v) {
                    v as u32
                } else {
                    u32::MAX
                }
            }
            PositionControlKv => c.position_control_kv = v,
        }
    }
}

/// One row of the §6 table.
#[derive(Clone, Copy, Debug)]
pub struct ParamDef {
    /// MC_AxisParameter number.
    pub number: u32,
    /// Tc2_MC2 name.
    pub name: &'static str,
    /// Declared type.
    pub ty: ParamType,
    /// Storage.
    pub slot: Slot,
}

impl ParamDef {
    /// Read-only numbers (§6: 1, 10, 11, 1000, 2000–2003, 4000, 4001).
    pub fn read_only(&self) -> bool {
        matches!(self.slot, Slot::Status(_))
    }
}

macro_rules! table {
    ($($num:literal $name:ident $ty:ident $slot:expr;)*) => {
        /// The MC_AxisParameter table of §6.
        pub const PARAMETERS: &[ParamDef] = &[
            $(ParamDef { number: $num, name: stringify!($name), ty: ParamType::$ty, slot: $slot },)*
        ];
    };
}

use ConfigKey as C;
use Slot::{Config as K, Other as O, Status as S};
use StatusValue as V;

table! {
    1 CommandedPosition LReal S(V::CommandedPosition);
    2 SWLimitPos LReal K(C::MaxSoftPosLimit);
    3 SWLimitNeg LReal K(C::MinSoftPosLimit);
    4 EnableLimitPos Bool K(C::EnMaxSoftPosLimit);
    5 EnableLimitNeg Bool K(C::EnMinSoftPosLimit);
    6 EnablePosLagMonitoring Bool K(C::EnPositionLagMonitoring);
    7 MaxPositionLag LReal K(C::MaxPosLagValue);
    8 MaxVelocitySystem LReal K(C::MaxVelocity);
    9 MaxVelocityAppl LReal K(C::MaxVelocity);
    10 ActualVelocity LReal S(V::ActualVelocity);
    11 CommandedVelocity LReal S(V::CommandedVelocity);
    12 MaxAccelerationSystem LReal K(C::Acceleration);
    13 MaxAccelerationAppl LReal K(C::Acceleration);
    14 MaxDecelerationSystem LReal K(C::Deceleration);
    15 MaxDecelerationAppl LReal K(C::Deceleration);
    16 MaxJerkSystem LReal K(C::Jerk);
    17 MaxJerkAppl LReal K(C::Jerk);
    1000 AxisId LReal S(V::AxisId);
    1001 AxisVeloManSlow LReal K(C::ManualVelocitySlow);
    1002 AxisVeloManFast LReal K(C::ManualVelocityFast);
    1003 AxisVeloMax LReal K(C::MaxVelocity);
    1004 AxisAcc LReal K(C::Acceleration);
    1005 AxisDec LReal K(C::Deceleration);
    1006 AxisJerk LReal K(C::Jerk);
    1007 MaxJerk LReal K(C::Jerk);
    1008 AxisMaxVelocity LReal K(C::MaxVelocity);
    1009 AxisRapidTraverseVelocity LReal K(C::RapidTraverseVelocity);
    1010 AxisManualVelocityFast LReal K(C::ManualVelocityFast);
    1011 AxisManualVelocitySlow LReal K(C::ManualVelocitySlow);
    1012 AxisCalibrationVelocityForward LReal K(C::CalibrationVelocityForward);
    1013 AxisCalibrationVelocityBackward LReal K(C::CalibrationVelocityBackward);
    1014 AxisJogIncrementForward LReal K(C::JogIncrementForward);
    1015 AxisJogIncrementBackward LReal K(C::JogIncrementBackward);
    1016 AxisEnMinSoftPosLimit Bool K(C::EnMinSoftPosLimit);
    1017 AxisMinSoftPosLimit LReal K(C::MinSoftPosLimit);
    1018 AxisEnMaxSoftPosLimit Bool K(C::EnMaxSoftPosLimit);
    1019 AxisMaxSoftPosLimit LReal K(C::MaxSoftPosLimit);
    1020 AxisEnPositionLagMonitoring Bool K(C::EnPositionLagMonitoring);
    1021 AxisMaxPosLagValue LReal K(C::MaxPosLagValue);
    1022 AxisMaxPosLagFilterTime LReal K(C::MaxPosLagFilterTime);
    1023 AxisEnPositionRangeMonitoring Bool K(C::EnPositionRangeMonitoring);
    1024 AxisPositionRangeWindow LReal K(C::PositionRangeWindow);
    1025 AxisEnTargetPositionMonitoring Bool K(C::EnTargetPositionMonitoring);
    1026 AxisTargetPositionWindow LReal K(C::TargetPositionWindow);
    1027 AxisTargetPositionMonitoringTime LReal K(C::TargetPositionMonitoringTime);
    1028 AxisEnInTargetTimeout Bool K(C::EnInTargetTimeout);
    1029 AxisInTargetTimeout LReal K(C::InTargetTimeout);
    1030 AxisEnMotionMonitoring Bool O(0x0000_0011);
    1031 AxisMotionMonitoringWindow LReal O(0x0000_0028);
    1032 AxisMotionMonitoringTime LReal O(0x0000_0012);
    1033 AxisDelayTimeVeloPosition LReal O(0x0000_0104);
    1034 AxisEnLoopingDistance Bool O(0x0000_0013);
    1035 AxisLoopingDistance LReal O(0x0000_0014);
    1036 AxisBacklash LReal K(C::Backlash);
    1037 AxisEnDataPersistence Bool O(0x0000_0030);
    1038 AxisRefVeloOnRefOutput LReal O(0x0003_0101);
    1039 AxisOverrideType LReal O(0x0000_0105);
    1040 AxisEncoderScalingFactor LReal K(C::EncoderScalingFactor);
    1041 AxisEncoderOffset LReal K(C::EncoderOffset);
    1042 AxisEncoderDirectionInverse Bool O(0x0001_0008);
    1043 AxisEncoderMask DWord O(0x0001_0015);
    1044 AxisEncoderModuloValue LReal K(C::ModuloValue);
    1045 AxisModuloToleranceWindow LReal K(C::ModuloToleranceWindow);
    1046 AxisEnablePosCorrection Bool K(C::EnablePosCorrection);
    1047 AxisPosCorrectionFilterTime LReal O(0x0001_0017);
    1048 AxisUnitInterpretation LReal O(0x0000_0026);
    1049 AxisMotorDirectionInverse Bool O(0x0003_0006);
    1050 AxisCycleTime LReal K(C::CycleTime);
    1051 AxisFastStopSignalType DWord O(0x0000_001E);
    1052 AxisFastAcc LReal K(C::FastAcceleration);
    1053 AxisFastDec LReal K(C::FastDeceleration);
    1054 AxisFastJerk LReal K(C::FastJerk);
    1055 AxisEncoderScalingNumerator LReal O(0x0001_0023);
    1056 AxisEncoderScalingDenominator LReal O(0x0001_0024);
    1057 AxisMaximumAcceleration LReal O(0x0000_00F1);
    1058 AxisMaximumDeceleration LReal O(0x0000_00F2);
    1059 AxisVeloJumpFactor LReal O(0x0000_0106);
    1060 AxisToleranceBallAuxAxis LReal O(0x0000_0108);
    1061 AxisMaxPositionDeviationAuxAxis LReal O(0x0000_0109);
    1062 AxisErrorPropagationMode DWord O(0x0000_001A);
    1063 AxisErrorPropagationDelay LReal O(0x0000_001B);
    1064 AxisCoupleSlaveToActualValues Bool K(C::CoupleSlaveToActualValues);
    1065 AxisAllowMotionCmdToSlaveAxis Bool K(C::AllowMotionCmdToSlaveAxis);
    1066 AxisAllowMotionCmdToExtSetAxis Bool K(C::AllowMotionCmdToExtSetAxis);
    1067 AxisEncoderSubMask DWord O(0x0001_0108);
    1068 AxisEncoderReferenceSystem DWord O(0x0001_0019);
    1069 AxisEncoderPositionFilterPT1 LReal O(0x0001_0010);
    1070 AxisEncoderVelocityFilterPT1 LReal O(0x0001_0011);
    1071 AxisEncoderAccelerationFilterPT1 LReal O(0x0001_0012);
    1072 AxisEncoderMode DWord O(0x0001_000A);
    1073 AxisEncoderHomingInvDirCamSearch Bool K(C::HomingInvDirCamSearch);
    1074 AxisEncoderHomingInvDirSyncSearch Bool K(C::HomingInvDirSyncSearch);
    1075 AxisEncoderHomingCalibValue LReal K(C::HomingCalibValue);
    1076 AxisEncoderReferenceMode DWord K(C::EncoderReferenceMode);
    1077 AxisRefVeloOutputRatio LReal O(0x0003_0102);
    1078 AxisDrivePositionOutputScaling LReal O(0x0003_0109);
    1079 AxisDriveVelocityOutputScaling LReal O(0x0003_0105);
    1080 AxisDriveVelocityOutputDelay LReal O(0x0003_010D);
    1081 AxisDriveMinOutputLimitation LReal O(0x0003_000B);
    1082 AxisDriveMaxOutputLimitation LReal O(0x0003_000C);
    1083 AxisTorqueInputScaling LReal O(0x0003_0031);
    1084 AxisTorqueInputFilterPT1 LReal O(0x0003_0032);
    1085 AxisTorqueDerivationInputFilterPT1 LReal O(0x0003_0033);
    1086 AxisTorqueOutputScaling LReal O(0x0003_010B);
    1087 AxisTorqueOutputDelay LReal O(0x0003_010F);
    1088 AxisAccelerationOutputScaling LReal O(0x0003_010A);
    1089 AxisAccelerationOutputDelay LReal O(0x0003_010E);
    1090 AxisDrivePosOutputSmoothFilterType DWord O(0x0003_0110);
    1091 AxisDrivePosOutputSmoothFilterTime LReal O(0x0003_0111);
    1092 AxisDrivePosOutputSmoothFilterOrder DWord O(0x0003_0112);
    1093 AxisDriveMode DWord O(0x0003_000A);
    1094 AxisDriftCompensationOffset LReal O(0x0003_0104);
    1095 AxisPositionControlKv LReal K(C::PositionControlKv);
    1096 AxisCtrlVelocityPreCtrlWeight LReal O(0x0002_000B);
    1097 AxisControllerMode DWord O(0x0002_000A);
    1098 AxisCtrlAutoOffset Bool O(0x0002_0110);
    1099 AxisCtrlAutoOffsetTimer LReal O(0x0002_0115);
    1100 AxisCtrlAutoOffsetLimit LReal O(0x0002_0114);
    1101 AxisSlaveCouplingControlKcp LReal O(0x0002_010F);
    1102 AxisCtrlOutputLimit LReal O(0x0002_0100);
    2000 AxisTargetPosition LReal S(V::TargetPosition);
    2001 AxisRemainingTimeToGo LReal S(V::RemainingTimeToGo);
    2002 AxisRemainingDistanceToGo LReal S(V::RemainingDistanceToGo);
    2003 AxisMcSetPositionOffset LReal S(V::SetPositionOffset);
    3000 AxisGearRatio LReal Slot::GearRatio;
    4000 NcSafCycleTime LReal S(V::SafCycleTime);
    4001 NcSvbCycleTime LReal S(V::SvbCycleTime);
}

/// Looks a parameter number up.
pub fn lookup(number: u32) -> Option<&'static ParamDef> {
    PARAMETERS.iter().find(|p| p.number == number)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_is_complete_and_unique() {
        // 1..17, 1000..1102, 2000..2003, 3000, 4000, 4001.
        assert_eq!(PARAMETERS.len(), 17 + 103 + 4 + 1 + 2);
        for (i, p) in PARAMETERS.iter().enumerate() {
            assert!(
                PARAMETERS[i + 1..].iter().all(|q| q.number != p.number),
                "{}",
                p.number
            );
        }
        assert!(lookup(18).is_none() && lookup(999).is_none() && lookup(1103).is_none());
    }

    #[test]
    fn aliases_share_one_slot() {
        assert_eq!(lookup(2).unwrap().slot, lookup(1019).unwrap().slot);
        for n in [8, 9, 1003] {
            assert_eq!(lookup(n).unwrap().slot, lookup(1008).unwrap().slot);
        }
        assert_eq!(lookup(17).unwrap().slot, lookup(1007).unwrap().slot);
    }

    #[test]
    fn read_only_numbers() {
        let ro: Vec<u32> = PARAMETERS
            .iter()
            .filter(|p| p.read_only())
            .map(|p| p.number)
            .collect();
        assert_eq!(
            ro,
            vec![1, 10, 11, 1000, 2000, 2001, 2002, 2003, 4000, 4001]
        );
    }
}
