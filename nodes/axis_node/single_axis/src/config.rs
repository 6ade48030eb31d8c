//! Axis configuration and its defaults (single_axis.md §1.2, §1.1 following model, §1.5 sim).
//!
//! Every key has the default of the spec's §1.2 table; the YAML/JSON configuration only names
//! what differs. [`AxisConfig::validate`] refuses NaN, infinite and negative values with a
//! message naming axis, key and value.

use motion_core::{ErrorId, Rejection};
use serde::{Deserialize, Serialize};

/// Actual-value model of the simulated drive (§1.1, `sim.following_model`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FollowingModel {
    /// ActPos = SetPos (+ the `set_following_offset` hook), PosDiff = 0.
    #[default]
    Ideal,
    /// P position loop with gain Kv (1095) and 100 % velocity feed-forward.
    FirstOrder,
}

/// Configuration of one axis. Units: positions `u`, velocities `u/s`, ... times `s`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AxisConfig {
    /// AxisId (1000); 0 = assigned from the position in the configuration (1, 2, ...).
    pub axis_id: u32,
    /// Start position (set and actual) \[u\].
    pub initial_position: f64,
    /// AxisMaxVelocity (1008, aliases 8/9/1003) \[u/s\].
    pub max_velocity: f64,
    /// AxisAcc (1004, aliases 12/13) \[u/s²\].
    pub acceleration: f64,
    /// AxisDec (1005, aliases 14/15) \[u/s²\].
    pub deceleration: f64,
    /// AxisJerk (1006, aliases 16/17/1007) \[u/s³\].
    pub jerk: f64,
    /// AxisFastAcc (1052) \[u/s²\].
    pub fast_acceleration: f64,
    /// AxisFastDec (1053) \[u/s²\], used by the error reaction and MC_Reset while moving.
    pub fast_deceleration: f64,
    /// AxisFastJerk (1054) \[u/s³\].
    pub fast_jerk: f64,
    /// AxisRapidTraverseVelocity (1009) \[u/s\].
    pub rapid_traverse_velocity: f64,
    /// AxisManualVelocitySlow (1011/1001) \[u/s\].
    pub manual_velocity_slow: f64,
    /// AxisManualVelocityFast (1010/1002) \[u/s\].
    pub manual_velocity_fast: f64,
    /// AxisCalibrationVelocityForward (1012) \[u/s\].
    pub calibration_velocity_forward: f64,
    /// AxisCalibrationVelocityBackward (1013) \[u/s\].
    pub calibration_velocity_backward: f64,
    /// AxisJogIncrementForward (1014) \[u\].
    pub jog_increment_forward: f64,
    /// AxisJogIncrementBackward (1015) \[u\].
    pub jog_increment_backward: f64,
    /// AxisEnPositionRangeMonitoring (1023).
    pub en_position_range_monitoring: bool,
    /// AxisPositionRangeWindow (1024) \[u\].
    pub position_range_window: f64,
    /// AxisEnTargetPositionMonitoring (1025).
    pub en_target_position_monitoring: bool,
    /// AxisTargetPositionWindow (1026) \[u\].
    pub target_position_window: f64,
    /// AxisTargetPositionMonitoringTime (1027) \[s\].
    pub target_position_monitoring_time: f64,
    /// AxisEnInTargetTimeout (1028).
    pub en_in_target_timeout: bool,
    /// AxisInTargetTimeout (1029) \[s\].
    pub in_target_timeout: f64,
    /// AxisEnPositionLagMonitoring (1020, alias 6).
    pub en_position_lag_monitoring: bool,
    /// AxisMaxPosLagValue (1021, alias 7) \[u\].
    pub max_pos_lag_value: f64,
    /// AxisMaxPosLagFilterTime (1022) \[s\].
    pub max_pos_lag_filter_time: f64,
    /// AxisEnMinSoftPosLimit (1016, alias 5).
    pub en_min_soft_pos_limit: bool,
    /// AxisEnMaxSoftPosLimit (1018, alias 4).
    pub en_max_soft_pos_limit: bool,
    /// AxisMinSoftPosLimit (1017, alias 3) \[u\].
    pub min_soft_pos_limit: f64,
    /// AxisMaxSoftPosLimit (1019, alias 2) \[u\].
    pub max_soft_pos_limit: f64,
    /// AxisEncoderModuloValue (1044): modulo period \[u\].
    pub modulo_value: f64,
    /// AxisModuloToleranceWindow (1045) \[u\] (half width).
    pub modulo_tolerance_window: f64,
    /// AxisEnablePosCorrection (1046).
    pub enable_pos_correction: bool,
    /// AxisBacklash (1036) \[u\].
    pub backlash: f64,
    /// AxisAllowMotionCmdToSlaveAxis (1065).
    pub allow_motion_cmd_to_slave_axis: bool,
    /// AxisAllowMotionCmdToExtSetAxis (1066).
    pub allow_motion_cmd_to_ext_set_axis: bool,
    /// AxisCoupleSlaveToActualValues (1064).
    pub couple_slave_to_actual_values: bool,
    /// AxisEncoderHomingInvDirCamSearch (1073).
    pub homing_inv_dir_cam_search: bool,
    /// AxisEncoderHomingInvDirSyncSearch (1074).
    pub homing_inv_dir_sync_search: bool,
    /// AxisEncoderHomingCalibValue (1075) \[u\]: DEFAULT_HOME_POSITION.
    pub homing_calib_value: f64,
    /// AxisEncoderReferenceMode (1076), E_EncoderReferenceMode value.
    pub encoder_reference_mode: u32,
    /// AxisEncoderScalingFactor (1040) \[u/inc\].
    pub encoder_scaling_factor: f64,
    /// AxisEncoderOffset (1041) \[u\].
    pub encoder_offset: f64,
    /// AxisPositionControlKv (1095) \[1/s\].
    pub position_control_kv: f64,
    /// AxisCycleTime (1050) = NcSafCycleTime (4000) \[s\].
    pub cycle_time: f64,
    /// NcSvbCycleTime (4001): status publication period \[s\].
    pub svb_cycle_time: f64,
    /// `sim.following_model` (§1.1).
    pub following_model: FollowingModel,
    /// `sim.home_cam`: virtual homing cam `[low, high]` in raw machine coordinates (§1.5).
    pub home_cam: Option<[f64; 2]>,
    /// `sim.sync_pulse_period` \[u\] (§4.10).
    pub sync_pulse_period: f64,
    /// `sim.homing_search_limit` \[u\] (§4.10).
    pub homing_search_limit: f64,
    /// `sim.probe_marks` of probe unit 1: raw positions at which a rising edge is generated
    /// when the axis crosses them (§1.5).
    pub probe_marks: Vec<f64>,
    /// `sim.probe_marks` of probe unit 2.
    pub probe_marks_2: Vec<f64>,
    /// `sim.torque_gain` k_t \[(u/s²)/%\] of the torque model (§1.1).
    pub torque_gain: f64,
    /// `sim.viscous_damping` b \[1/s\] of the torque model (§1.1).
    pub viscous_damping: f64,
}

impl Default for AxisConfig {
    fn default() -> Self {
        AxisConfig {
            axis_id: 0,
            initial_position: 0.0,
            max_velocity: 2000.0,
            acceleration: 1000.0,
            deceleration: 1000.0,
            jerk: 10000.0,
            fast_acceleration: 5000.0,
            fast_deceleration: 5000.0,
            fast_jerk: 100000.0,
            rapid_traverse_velocity: 2000.0,
            manual_velocity_slow: 100.0,
            manual_velocity_fast: 600.0,
            calibration_velocity_forward: 30.0,
            calibration_velocity_backward: 30.0,
            jog_increment_forward: 5.0,
            jog_increment_backward: 5.0,
            en_position_range_monitoring: true,
            position_range_window: 5.0,
            en_target_position_monitoring: true,
            target_position_window: 2.0,
            target_position_monitoring_time: 0.02,
            en_in_target_timeout: false,
            in_target_timeout: 5.0,
            en_position_lag_monitoring: true,
            max_pos_lag_value: 5.0,
            max_pos_lag_filter_time: 0.02,
            en_min_soft_pos_limit: false,
            en_max_soft_pos_limit: false,
            min_soft_pos_limit: -1e9,
            max_soft_pos_limit: 1e9,
            modulo_value: 360.0,
            modulo_tolerance_window: 0.0,
            enable_pos_correction: false,
            backlash: 0.0,
            allow_motion_cmd_to_slave_axis: false,
            allow_motion_cmd_to_ext_set_axis: false,
            couple_slave_to_actual_values: false,
            homing_inv_dir_cam_search: false,
            homing_inv_dir_sync_search: false,
            homing_calib_value: 0.0,
            encoder_reference_mode: 1,
            encoder_scaling_factor: 0.0001,
            encoder_offset: 0.0,
            position_control_kv: 1.0,
            cycle_time: 0.002,
            svb_cycle_time: 0.010,
            following_model: FollowingModel::Ideal,
            home_cam: None,
            sync_pulse_period: 1.0,
            homing_search_limit: 1e6,
            probe_marks: Vec::new(),
            probe_marks_2: Vec::new(),
            torque_gain: 1.0,
            viscous_damping: 0.1,
        }
    }
}

/// How a numeric key must look.
#[derive(Clone, Copy)]
enum Rule {
    /// Finite, any sign.
    Finite,
    /// Finite and ≥ 0.
    NonNegative,
    /// Finite and > 0.
    Positive,
}

impl AxisConfig {
    /// Numeric keys with their rule, used by [`AxisConfig::validate`].
    fn numeric_keys(&self) -> [(&'static str, f64, Rule); 37] {
        use Rule::*;
        [
            ("initial_position", self.initial_position, Finite),
            ("max_velocity", self.max_velocity, Positive),
            ("acceleration", self.acceleration, Positive),
            ("deceleration", self.deceleration, Positive),
            ("jerk", self.jerk, Positive),
            ("fast_acceleration", self.fast_acceleration, Positive),
            ("fast_deceleration", self.fast_deceleration, Positive),
            ("fast_jerk", self.fast_jerk, Positive),
            (
                "rapid_traverse_velocity",
                self.rapid_traverse_velocity,
                Positive,
            ),
            ("manual_velocity_slow", self.manual_velocity_slow, Positive),
            ("manual_velocity_fast", self.manual_velocity_fast, Positive),
            (
                "calibration_velocity_forward",
                self.calibration_velocity_forward,
                Positive,
            ),
            (
                "calibration_velocity_backward",
                self.calibration_velocity_backward,
                Positive,
            ),
            (
                "jog_increment_forward",
                self.jog_increment_forward,
                NonNegative,
            ),
            (
                "jog_increment_backward",
                self.jog_increment_backward,
                NonNegative,
            ),
            (
                "position_range_window",
                self.position_range_window,
                NonNegative,
            ),
            (
                "target_position_window",
                self.target_position_window,
                NonNegative,
            ),
            (
                "target_position_monitoring_time",
                self.target_position_monitoring_time,
                NonNegative,
            ),
            ("in_target_timeout", self.in_target_timeout, NonNegative),
            ("max_pos_lag_value", self.max_pos_lag_value, NonNegative),
            (
                "max_pos_lag_filter_time",
                self.max_pos_lag_filter_time,
                NonNegative,
            ),
            ("min_soft_pos_limit", self.min_soft_pos_limit, Finite),
            ("max_soft_pos_limit", self.max_soft_pos_limit, Finite),
            ("modulo_value", self.modulo_value, Positive),
            (
                "modulo_tolerance_window",
                self.modulo_tolerance_window,
                NonNegative,
            ),
            ("backlash", self.backlash, Finite),
            ("homing_calib_value", self.homing_calib_value, Finite),
            (
                "encoder_scaling_factor",
                self.encoder_scaling_factor,
                Positive,
            ),
            ("encoder_offset", self.encoder_offset, Finite),
            ("position_control_kv", self.position_control_kv, Positive),
            ("cycle_time", self.cycle_time, Positive),
            ("svb_cycle_time", self.svb_cycle_time, Positive),
            ("sync_pulse_period", self.sync_pulse_period, Positive),
            ("homing_search_limit", self.homing_search_limit, Positive),
            ("torque_gain", self.torque_gain, Positive),
            ("viscous_damping", self.viscous_damping, NonNegative),
            (
                "home_cam",
                self.home_cam.map_or(0.0, |c| c[0] + c[1]),
                Finite,
            ),
        ]
    }

    /// Checks every key; the first bad one is reported with axis, key and value.
    pub fn validate(&self, axis: &str) -> Result<(), Rejection> {
        for (key, value, rule) in self.numeric_keys() {
            if !value.is_finite() {
                return Err(Rejection::new(
                    ErrorId::NOT_FINITE,
                    format!("axis '{axis}': config key {key} = {value} is not finite"),
                ));
            }
            let ok = match rule {
                Rule::Finite => true,
                Rule::NonNegative => value >= 0.0,
                Rule::Positive => value > 0.0,
            };
            if !ok {
                let need = if matches!(rule, Rule::Positive) {
                    "> 0"
                } else {
                    ">= 0"
                };
                return Err(Rejection::new(
                    ErrorId::VALUE_OUT_OF_RANGE,
                    format!("axis '{axis}': config key {key} = {value} must be {need}"),
                ));
            }
        }
        for (key, marks) in [
            ("probe_marks", &self.probe_marks),
            ("probe_marks_2", &self.probe_marks_2),
        ] {
            if let Some(m) = marks.iter().find(|m| !m.is_finite()) {
                return Err(Rejection::new(
                    ErrorId::NOT_FINITE,
                    format!("axis '{axis}': config key {key} contains {m}, which is not finite"),
                ));
            }
        }
        if let Some([lo, hi]) = self.home_cam {
            if !(lo.is_finite() && hi.is_finite()) || lo > hi {
                return Err(Rejection::new(
                    ErrorId::VALUE_OUT_OF_RANGE,
                    format!("axis '{axis}': config key home_cam = [{lo}, {hi}] must be finite with low <= high"),
                ));
            }
        }
        if self.min_soft_pos_limit > self.max_soft_pos_limit {
            return Err(Rejection::new(
                ErrorId::VALUE_OUT_OF_RANGE,
                format!(
                    "axis '{axis}': config key min_soft_pos_limit = {} exceeds max_soft_pos_limit = {}",
                    self.min_soft_pos_limit, self.max_soft_pos_limit
                ),
            ));
        }
        if self.encoder_reference_mode > 7 {
            return Err(Rejection::new(
                ErrorId::ENUM_OUT_OF_RANGE,
                format!(
                    "axis '{axis}': config key encoder_reference_mode = {} is not an E_EncoderReferenceMode (0..7)",
                    self.encoder_reference_mode
                ),
            ));
        }
        Ok(())
    }
}
