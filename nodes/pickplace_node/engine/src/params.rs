//! The parameter structure `scPar` (`L_TT1P_scPar_TrackPickAndPlaceBase`, pick_and_place.md §3.4)
//! and the belt parameters `ascConveyorBeltPar[i]` (§3.5), with write-time validation.
//!
//! Field names are the manual's names in snake_case without the Hungarian prefix
//! (`lrPathVel` -> `path_vel`); messages name the manual's field. Enums stay integers here so
//! that out-of-range values can be rejected with the spec's ids (90002, 90003).

use crate::error_ids;
use motion_core::Rejection;
use serde::{Deserialize, Serialize};

/// Number of entries of the per-axis arrays (axis index map, §0).
pub const AXIS_ARRAY_LEN: usize = 18;
/// Number of entries of the homing arrays.
pub const HOMING_ARRAY_LEN: usize = 12;
/// Names of the path axes in the order of the `…Max…` arrays and of the TCP pose.
pub const POSE_AXIS_NAMES: [&str; 7] = ["X", "Y", "Z", "A", "B", "C", "Aux1"];

/// Jog dynamics of one axis class (`lrCartesianJogVel/Acc/Dec/Jerk` etc.).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct JogPar {
    /// Velocity [units/s].
    pub vel: f64,
    /// Acceleration [units/s²].
    pub acc: f64,
    /// Deceleration [units/s²].
    pub dec: f64,
    /// Jerk [units/s³].
    pub jerk: f64,
}

impl Default for JogPar {
    fn default() -> Self {
        JogPar {
            vel: 10.0,
            acc: 100.0,
            dec: 100.0,
            jerk: 10_000.0,
        }
    }
}

/// Application homing parameters of one axis (`L_MC1P_HomeParameter`, proposal §6).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HomeParameter {
    /// 0 = direct set, 1 = switch search.
    pub mode: u8,
    /// Search velocity [units/s].
    pub vel: f64,
    /// Search acceleration [units/s²].
    pub acc: f64,
    /// Search in + direction.
    pub positive_direction: bool,
    /// Maximum search distance [units] (0 = unlimited).
    pub max_search_dist: f64,
}

impl Default for HomeParameter {
    fn default() -> Self {
        HomeParameter {
            mode: 0,
            vel: 10.0,
            acc: 100.0,
            positive_direction: true,
            max_search_dist: 1000.0,
        }
    }
}

/// `L_MC4P_CoordSystem` (proposal numbers, §3.6).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoordSystem {
    /// Axis coordinates (not supported as a target).
    Acs,
    /// Machine coordinates.
    Mcs,
    /// World coordinates (converted with `wcs_to_mcs`).
    Wcs,
    /// Product coordinate system of the next workpiece on belt n (1 … 16).
    Pcs(u8),
}

impl CoordSystem {
    /// Decodes the proposal numbering 0 ACS, 1 MCS, 2 WCS, 3…18 PCS1…PCS16.
    pub fn from_u8(v: u8) -> Option<Self> {
        match v {
            0 => Some(CoordSystem::Acs),
            1 => Some(CoordSystem::Mcs),
            2 => Some(CoordSystem::Wcs),
            3..=18 => Some(CoordSystem::Pcs(v - 2)),
            _ => None,
        }
    }
}

/// `L_TT1P_PickAndPlacePathMode`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathMode {
    /// 0: straight segments.
    Linear,
    /// 1: half ellipse between IP1 and IP2.
    Elliptical,
}

/// `scPar`: all functional and set-point parameters (§3.4). `Default` is the spec's table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ScPar {
    /// `lrPathStopDec` [units/s²]: deceleration for `xPathStop`/`xPathInterrupt` (§9.1).
    pub path_stop_dec: f64,
    /// `lrPathStopJerk` [units/s³].
    pub path_stop_jerk: f64,
    /// `lrPathHaltDec` [units/s²]: deceleration for `xPathHalt`.
    pub path_halt_dec: f64,
    /// `lrPathJerk` [units/s³]: path jerk, also for `xPathHalt`.
    pub path_jerk: f64,
    /// `lrPathVel` [units/s].
    pub path_vel: f64,
    /// `lrPathAcc` [units/s²].
    pub path_acc: f64,
    /// `lrPathDec` [units/s²].
    pub path_dec: f64,
    /// `alrStopDec[1..18]` [units/s²]: per-axis stop (xStopALL, limits, following error).
    pub stop_dec: [f64; AXIS_ARRAY_LEN],
    /// `alrStopJerk[1..18]` [units/s³].
    pub stop_jerk: [f64; AXIS_ARRAY_LEN],
    /// `lrCartesianJog*`: jog of X, Y, Z.
    pub cartesian_jog: JogPar,
    /// `lrOrientationJog*`: jog of A, B, C.
    pub orientation_jog: JogPar,
    /// `lrRealAxisJog*`: jog of A1 … A6, Aux1.
    pub real_axis_jog: JogPar,
    /// `alrHomePosition[1..12]` [units].
    pub home_position: [f64; HOMING_ARRAY_LEN],
    /// `aeHomingOrder[1..12]`: 0 NoHoming, 1 First … 12 Twelfth.
    pub homing_order: [u8; HOMING_ARRAY_LEN],
    /// `xUseHomeExtParameter`.
    pub use_home_ext_parameter: bool,
    /// `ascHomeExtParameter[1..12]`.
    pub home_ext_parameter: [HomeParameter; HOMING_ARRAY_LEN],
    /// `lrXMaxVel … lrCMaxVel, lrAux1MaxVel` [units/s], 0 = no limit.
    pub max_vel: [f64; 7],
    /// `lrXMaxAccDec … lrAux1MaxAccDec` [units/s²], 0 = no limit.
    pub max_acc_dec: [f64; 7],
    /// `lrXMaxJerk … lrAux1MaxJerk` [units/s³], 0 = no limit.
    pub max_jerk: [f64; 7],
    /// `lrGripperClosingTime` [s]: lead time of the closing pulse (§10).
    pub gripper_closing_time: f64,
    /// `lrGripperOpenTime` [s]: lead time of the opening pulse (modes 1 … 4).
    pub gripper_open_time: f64,
    /// `eTargetCoordSystem`: 0 ACS, 1 MCS, 2 WCS, 3 … 18 PCS1 … PCS16.
    pub target_coord_system: u8,
    /// `lrXTargetPos … lrCTargetPos, lrAux1TargetPos` [units]: static target pose.
    pub target_pos: [f64; 7],
    /// `lrZStartDist` [units]: height of IP1 above the start.
    pub z_start_dist: f64,
    /// `ePathMode`: 0 Linear, 1 Elliptical.
    pub path_mode: u8,
    /// `lrZDistElliptical` [units]: height of the half ellipse, also for park paths.
    pub z_dist_elliptical: f64,
    /// `lrZTargetDist` [units]: height of IP2 above the target.
    pub z_target_dist: f64,
    /// `lrBlendingRadius` [units].
    pub blending_radius: f64,
    /// `xPosInWindow`: monitor the tolerance window for `xInPosition`.
    pub pos_in_window: bool,
    /// `lrPosInWindow` [units].
    pub pos_in_window_size: f64,
    /// `lrTimePosInWindow` [ms].
    pub time_pos_in_window: f64,
    /// `eTrackingMode`: 0 … 4 (§11).
    pub tracking_mode: u8,
}

impl Default for ScPar {
    fn default() -> Self {
        ScPar {
            path_stop_dec: 10_000.0,
            path_stop_jerk: 100_000.0,
            path_halt_dec: 100.0,
            path_jerk: 100_000.0,
            path_vel: 10.0,
            path_acc: 100.0,
            path_dec: 100.0,
            stop_dec: [10_000.0; AXIS_ARRAY_LEN],
            stop_jerk: [100_000.0; AXIS_ARRAY_LEN],
            cartesian_jog: JogPar::default(),
            orientation_jog: JogPar::default(),
            real_axis_jog: JogPar::default(),
            home_position: [0.0; HOMING_ARRAY_LEN],
            homing_order: [0; HOMING_ARRAY_LEN],
            use_home_ext_parameter: false,
            home_ext_parameter: [HomeParameter::default(); HOMING_ARRAY_LEN],
            max_vel: [10.0; 7],
            max_acc_dec: [100.0; 7],
            max_jerk: [10_000.0; 7],
            gripper_closing_time: 0.0,
            gripper_open_time: 0.0,
            target_coord_system: 1,
            target_pos: [0.0, 0.0, 0.0, 180.0, 0.0, 0.0, 0.0],
            z_start_dist: 0.0,
            path_mode: 0,
            z_dist_elliptical: 0.0,
            z_target_dist: 0.0,
            blending_radius: 0.0,
            pos_in_window: false,
            pos_in_window_size: 0.5,
            time_pos_in_window: 50.0,
            tracking_mode: 0,
        }
    }
}

fn invalid(field: &str, value: f64, rule: &str) -> Rejection {
    Rejection::new(
        error_ids::INVALID_PARAMETER,
        format!("scPar.{field} = {value}: {rule}"),
    )
}

/// Checks `value` is finite and > 0.
pub(crate) fn check_positive(field: &str, value: f64) -> Result<(), Rejection> {
    if !value.is_finite() || value <= 0.0 {
        return Err(invalid(field, value, "must be finite and > 0"));
    }
    Ok(())
}

/// Checks `value` is finite and ≥ 0.
pub(crate) fn check_non_negative(field: &str, value: f64) -> Result<(), Rejection> {
    if !value.is_finite() || value < 0.0 {
        return Err(invalid(field, value, "must be finite and >= 0"));
    }
    Ok(())
}

fn check_finite(field: &str, value: f64) -> Result<(), Rejection> {
    if !value.is_finite() {
        return Err(invalid(field, value, "must be finite"));
    }
    Ok(())
}

fn check_jog(prefix: &str, j: &JogPar) -> Result<(), Rejection> {
    check_positive(&format!("lr{prefix}JogVel"), j.vel)?;
    check_positive(&format!("lr{prefix}JogAcc"), j.acc)?;
    check_positive(&format!("lr{prefix}JogDec"), j.dec)?;
    check_positive(&format!("lr{prefix}JogJerk"), j.jerk)
}

impl ScPar {
    /// Write-time validation of §3.4: the first violated rule, with its id and the manual's name.
    pub fn validate(&self) -> Result<(), Rejection> {
        check_positive("lrPathVel", self.path_vel)?;
        check_positive("lrPathAcc", self.path_acc)?;
        check_positive("lrPathDec", self.path_dec)?;
        check_positive("lrPathJerk", self.path_jerk)?;
        check_positive("lrPathStopDec", self.path_stop_dec)?;
        check_positive("lrPathStopJerk", self.path_stop_jerk)?;
        check_positive("lrPathHaltDec", self.path_halt_dec)?;
        check_jog("Cartesian", &self.cartesian_jog)?;
        check_jog("Orientation", &self.orientation_jog)?;
        check_jog("RealAxis", &self.real_axis_jog)?;
        for i in 0..AXIS_ARRAY_LEN {
            check_positive(&format!("alrStopDec[{}]", i + 1), self.stop_dec[i])?;
            check_positive(&format!("alrStopJerk[{}]", i + 1), self.stop_jerk[i])?;
        }
        for (q, name) in POSE_AXIS_NAMES.iter().enumerate() {
            check_non_negative(&format!("lr{name}MaxVel"), self.max_vel[q])?;
            check_non_negative(&format!("lr{name}MaxAccDec"), self.max_acc_dec[q])?;
            check_non_negative(&format!("lr{name}MaxJerk"), self.max_jerk[q])?;
            check_finite(&format!("lr{name}TargetPos"), self.target_pos[q])?;
        }
        for i in 0..HOMING_ARRAY_LEN {
            check_finite(
                &format!("alrHomePosition[{}]", i + 1),
                self.home_position[i],
            )?;
            if self.homing_order[i] > 12 {
                return Err(invalid(
                    &format!("aeHomingOrder[{}]", i + 1),
                    self.homing_order[i] as f64,
                    "must be 0 … 12",
                ));
            }
            let h = &self.home_ext_parameter[i];
            let f = format!("ascHomeExtParameter[{}]", i + 1);
            if h.mode > 1 {
                return Err(invalid(
                    &format!("{f}.eMode"),
                    h.mode as f64,
                    "must be 0 or 1",
                ));
            }
            check_positive(&format!("{f}.lrVel"), h.vel)?;
            check_positive(&format!("{f}.lrAcc"), h.acc)?;
            check_non_negative(&format!("{f}.lrMaxSearchDist"), h.max_search_dist)?;
        }
        check_finite("lrGripperClosingTime", self.gripper_closing_time)?;
        check_finite("lrGripperOpenTime", self.gripper_open_time)?;
        if CoordSystem::from_u8(self.target_coord_system).is_none() {
            return Err(invalid(
                "eTargetCoordSystem",
                self.target_coord_system as f64,
                "must be 0 … 18",
            ));
        }
        check_non_negative("lrZStartDist", self.z_start_dist)?;
        check_non_negative("lrZTargetDist", self.z_target_dist)?;
        check_non_negative("lrZDistElliptical", self.z_dist_elliptical)?;
        check_non_negative("lrBlendingRadius", self.blending_radius)?;
        check_non_negative("lrPosInWindow", self.pos_in_window_size)?;
        check_non_negative("lrTimePosInWindow", self.time_pos_in_window)?;
        if self.path_mode > 1 {
            return Err(Rejection::new(
                error_ids::INVALID_PATH_MODE,
                format!(
                    "scPar.ePathMode = {}: must be 0 (Linear) or 1 (Elliptical)",
                    self.path_mode
                ),
            ));
        }
        if self.tracking_mode > 4 {
            return Err(Rejection::new(
                error_ids::INVALID_TRACKING_MODE,
                format!(
                    "scPar.eTrackingMode = {}: must be 0 … 4",
                    self.tracking_mode
                ),
            ));
        }
        Ok(())
    }

    /// The path mode (valid after [`ScPar::validate`]).
    pub fn path_mode(&self) -> PathMode {
        if self.path_mode == 1 {
            PathMode::Elliptical
        } else {
            PathMode::Linear
        }
    }

    /// The target frame (valid after [`ScPar::validate`]).
    pub fn coord_system(&self) -> CoordSystem {
        CoordSystem::from_u8(self.target_coord_system).unwrap_or(CoordSystem::Mcs)
    }
}

/// `ascConveyorBeltPar[i]` (`L_TT1P_scPar_ConveyorBelt`, §3.5). Defaults all 0 (proposal).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ConveyorBeltPar {
    /// `alrParkPos[1..6]`: park pose X, Y, Z, A, B, C in MCS.
    pub park_pos: [f64; 6],
    /// `lrZDistBelt` [units]: approach/lift height above the workpiece.
    pub z_dist_belt: f64,
    /// `alrConveyorBeltOrigin[1..6]`: belt frame in MCS (X, Y, Z, A, B, C [deg]).
    pub conveyor_belt_origin: [f64; 6],
    /// `lrSyncTimeOnBelt` [s]: synchronous dwell before the lift (0 = one cycle).
    pub sync_time_on_belt: f64,
    /// `lrLowerSyncLimit` [units]: start of the working area on belt X.
    pub lower_sync_limit: f64,
    /// `lrUpperSyncLimit` [units]: end of the working area on belt X.
    pub upper_sync_limit: f64,
}

impl ConveyorBeltPar {
    /// A belt is configured iff its working area is not empty (§3.5).
    pub fn is_configured(&self) -> bool {
        self.upper_sync_limit > self.lower_sync_limit
    }

    /// Write-time validation; `belt` is 1-based for the message.
    pub fn validate(&self, belt: usize) -> Result<(), Rejection> {
        let name = |f: &str| format!("ascConveyorBeltPar[{belt}].{f}");
        let bad = |f: &str, v: f64, rule: &str| {
            Err(Rejection::new(
                error_ids::INVALID_PARAMETER,
                format!("{} = {v}: {rule}", name(f)),
            ))
        };
        for i in 0..6 {
            if !self.park_pos[i].is_finite() {
                return bad(
                    &format!("alrParkPos[{}]", i + 1),
                    self.park_pos[i],
                    "must be finite",
                );
            }
            if !self.conveyor_belt_origin[i].is_finite() {
                return bad(
                    &format!("alrConveyorBeltOrigin[{}]", i + 1),
                    self.conveyor_belt_origin[i],
                    "must be finite",
                );
            }
        }
        if !self.z_dist_belt.is_finite() || self.z_dist_belt < 0.0 {
            return bad("lrZDistBelt", self.z_dist_belt, "must be finite and >= 0");
        }
        if !self.sync_time_on_belt.is_finite() || self.sync_time_on_belt < 0.0 {
            return bad(
                "lrSyncTimeOnBelt",
                self.sync_time_on_belt,
                "must be finite and >= 0",
            );
        }
        if !self.lower_sync_limit.is_finite() {
            return bad("lrLowerSyncLimit", self.lower_sync_limit, "must be finite");
        }
        if !self.upper_sync_limit.is_finite() {
            return bad("lrUpperSyncLimit", self.upper_sync_limit, "must be finite");
        }
        Ok(())
    }
}
