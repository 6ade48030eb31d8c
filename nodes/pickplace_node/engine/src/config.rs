//! Launch configuration of the cell (pick_and_place.md §2.1, §2.2, §8, §18), deserialised from the
//! launch YAML (`deny_unknown_fields`) and validated with messages naming key and value.

use crate::params::{ConveyorBeltPar, ScPar};
use motion_core::{ErrorId, Rejection};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Maximum number of belts CV1 … CV16 (§1).
pub const MAX_BELTS: usize = 16;
/// Names of the axis indices 1 … 13 (§0 axis index map), lower case as YAML keys.
pub const AXIS_NAMES: [&str; 13] = [
    "x", "y", "z", "a", "b", "c", "a1", "a2", "a3", "a4", "a5", "a6", "aux1",
];

/// Group configuration of one axis index (§2.1, proposal).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AxisConfig {
    /// Positive software limit [units].
    pub sw_limit_pos: f64,
    /// Negative software limit [units].
    pub sw_limit_neg: f64,
    /// Software-limit monitoring on.
    pub sw_limit_enabled: bool,
    /// AXIS_REF max velocity [units/s], 0 = none.
    pub max_vel: f64,
    /// AXIS_REF max acceleration [units/s²], 0 = none.
    pub max_acc: f64,
    /// AXIS_REF max jerk [units/s³], 0 = none.
    pub max_jerk: f64,
    /// Following-error limit [units], 0 = off.
    pub following_error_limit: f64,
    /// Time constant of the optional first-order drive lag [s], 0 = ideal drive (§2.1).
    pub lag_time_constant: f64,
    /// Initial position [units].
    pub initial_position: f64,
    /// The axis counts as referenced at start.
    pub initially_homed: bool,
}

impl Default for AxisConfig {
    fn default() -> Self {
        AxisConfig {
            sw_limit_pos: 0.0,
            sw_limit_neg: 0.0,
            sw_limit_enabled: false,
            max_vel: 0.0,
            max_acc: 0.0,
            max_jerk: 0.0,
            following_error_limit: 0.0,
            lag_time_constant: 0.0,
            initial_position: 0.0,
            initially_homed: true,
        }
    }
}

/// One simulated belt axis with its `ascConveyorBeltPar` (§2.2, §3.5).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BeltConfig {
    /// Belt parameters.
    pub params: ConveyorBeltPar,
    /// Initial belt velocity [units/s].
    pub initial_velocity: f64,
    /// Initial belt position s_i [units].
    pub initial_position: f64,
}

/// The cell: cycle, preparation delay, queue, axis group, belts and the initial `scPar`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PickPlaceConfig {
    /// `cycle_time_s` [s], 0.00025 … 0.004 (default 0.001).
    pub cycle_time_s: f64,
    /// `path_prep_cycles`, 1 … 25 (default 3): observable path preparation delay (§8).
    pub path_prep_cycles: u32,
    /// `profile_queue_capacity` ≥ 1 (default 8): running + prepared profiles (§8).
    pub profile_queue_capacity: usize,
    /// Axis group per axis name (`x` … `c`, `a1` … `a6`, `aux1`); missing = defaults.
    pub axes: BTreeMap<String, AxisConfig>,
    /// Belts by number "1" … "16"; missing belts are unconfigured.
    pub belts: BTreeMap<String, BeltConfig>,
    /// Initial `scPar`.
    pub params: ScPar,
    /// WCS → MCS transform X, Y, Z, A, B, C [units, deg] (default identity).
    pub wcs_to_mcs: [f64; 6],
    /// Distance within which a close pulse captures a workpiece [units] (§10).
    pub grip_capture_distance: f64,
    /// Duration of a direct-set homing stage [s] (§6).
    pub homing_stage_time: f64,
    /// TCP pose X, Y, Z, A, B, C, Aux1 at start; overrides the axes' `initial_position`.
    pub initial_tcp: Option<[f64; 7]>,
}

impl Default for PickPlaceConfig {
    fn default() -> Self {
        PickPlaceConfig {
            cycle_time_s: 0.001,
            path_prep_cycles: 3,
            profile_queue_capacity: 8,
            axes: BTreeMap::new(),
            belts: BTreeMap::new(),
            params: ScPar::default(),
            wcs_to_mcs: [0.0; 6],
            grip_capture_distance: 1.0,
            homing_stage_time: 0.1,
            initial_tcp: None,
        }
    }
}

fn bad(key: &str, value: impl std::fmt::Display, rule: &str) -> Rejection {
    Rejection::new(
        ErrorId::VALUE_OUT_OF_RANGE,
        format!("config {key} = {value}: {rule}"),
    )
}

fn finite(key: &str, v: f64) -> Result<(), Rejection> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(Rejection::new(
            ErrorId::NOT_FINITE,
            format!("config {key} = {v} is not finite"),
        ))
    }
}

fn non_negative(key: &str, v: f64) -> Result<(), Rejection> {
    finite(key, v)?;
    if v < 0.0 {
        return Err(bad(key, v, "must be >= 0"));
    }
    Ok(())
}

impl PickPlaceConfig {
    /// Validates every key; the first violation names the key and its value.
    pub fn validate(&self) -> Result<(), Rejection> {
        finite("cycle_time_s", self.cycle_time_s)?;
        if !(0.00025..=0.004).contains(&self.cycle_time_s) {
            return Err(bad(
                "cycle_time_s",
                self.cycle_time_s,
                "must be 0.00025 … 0.004",
            ));
        }
        if !(1..=25).contains(&self.path_prep_cycles) {
            return Err(bad(
                "path_prep_cycles",
                self.path_prep_cycles,
                "must be 1 … 25",
            ));
        }
        if self.profile_queue_capacity < 1 {
            return Err(bad(
                "profile_queue_capacity",
                self.profile_queue_capacity,
                "must be >= 1",
            ));
        }
        for (name, a) in &self.axes {
            if !AXIS_NAMES.contains(&name.as_str()) {
                return Err(Rejection::new(
                    ErrorId::UNKNOWN_OBJECT,
                    format!(
                        "config axes.{name}: unknown axis (expected one of {})",
                        AXIS_NAMES.join(", ")
                    ),
                ));
            }
            let k = |f: &str| format!("axes.{name}.{f}");
            finite(&k("sw_limit_pos"), a.sw_limit_pos)?;
            finite(&k("sw_limit_neg"), a.sw_limit_neg)?;
            if a.sw_limit_enabled && a.sw_limit_neg >= a.sw_limit_pos {
                return Err(bad(
                    &k("sw_limit_neg"),
                    a.sw_limit_neg,
                    "must be < sw_limit_pos when enabled",
                ));
            }
            non_negative(&k("max_vel"), a.max_vel)?;
            non_negative(&k("max_acc"), a.max_acc)?;
            non_negative(&k("max_jerk"), a.max_jerk)?;
            non_negative(&k("following_error_limit"), a.following_error_limit)?;
            non_negative(&k("lag_time_constant"), a.lag_time_constant)?;
            finite(&k("initial_position"), a.initial_position)?;
        }
        if self.belts.len() > MAX_BELTS {
            return Err(bad("belts", self.belts.len(), "at most 16 belts"));
        }
        for (name, b) in &self.belts {
            let idx = belt_index(name).ok_or_else(|| {
                Rejection::new(
                    ErrorId::UNKNOWN_OBJECT,
                    format!("config belts.{name}: unknown belt (expected 1 … 16)"),
                )
            })?;
            b.params.validate(idx).map_err(|r| {
                Rejection::new(r.error_id, format!("config belts.{name}: {}", r.message))
            })?;
            finite(
                &format!("belts.{name}.initial_velocity"),
                b.initial_velocity,
            )?;
            finite(
                &format!("belts.{name}.initial_position"),
                b.initial_position,
            )?;
        }
        self.params
            .validate()
            .map_err(|r| Rejection::new(r.error_id, format!("config params: {}", r.message)))?;
        for (i, v) in self.wcs_to_mcs.iter().enumerate() {
            finite(&format!("wcs_to_mcs[{i}]"), *v)?;
        }
        non_negative("grip_capture_distance", self.grip_capture_distance)?;
        non_negative("homing_stage_time", self.homing_stage_time)?;
        if let Some(p) = &self.initial_tcp {
            for (i, v) in p.iter().enumerate() {
                finite(&format!("initial_tcp[{i}]"), *v)?;
            }
        }
        Ok(())
    }

    /// The axis configuration of axis index 1 … 13.
    pub fn axis(&self, index: usize) -> AxisConfig {
        AXIS_NAMES
            .get(index.wrapping_sub(1))
            .and_then(|n| self.axes.get(*n))
            .copied()
            .unwrap_or_default()
    }
}

/// Parses a belt key "1" … "16" (also "cv1" … "cv16").
pub fn belt_index(name: &str) -> Option<usize> {
    let n = name.trim_start_matches("cv").trim_start_matches("CV");
    let i: usize = n.parse().ok()?;
    (1..=MAX_BELTS).contains(&i).then_some(i)
}
