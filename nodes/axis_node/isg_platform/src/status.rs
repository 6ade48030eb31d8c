//! The platform state as published (snapshot, `~/platform/status`).

use crate::{McMessage, OperatingMode, PlatformProfile};
use motion_core::ErrorId;
use serde::{Deserialize, Serialize};

/// Safety and platform state of one axis (snapshot).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AxisSafetyStatus {
    /// Axis name.
    pub name: String,
    /// Referenced (R-SAF-6).
    pub referenced: bool,
    /// Velocity monitoring active (not leased off).
    pub velocity_monitoring: bool,
    /// Torque-limit monitoring active.
    pub torque_limit_monitoring: bool,
    /// Torque limiting active (sim).
    pub torque_limiting: bool,
    /// Monitoring limit \[u/s\].
    pub velocity_limit: f64,
    /// DriveEnabled (controller enable and power stage).
    pub drive_enabled: bool,
    /// Feed hold active (START released in T1/T2).
    pub feed_hold: bool,
    /// MC message buffer, newest first (§7.2).
    pub messages: Vec<McMessage>,
}

/// Clog warnings kept in the snapshot.
pub const RECENT_CLOG_WARNINGS: usize = 8;

/// Platform state (snapshot, `~/platform/status`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PlatformStatus {
    /// The profile.
    pub profile: PlatformProfile,
    /// HLI initialised (start-up over).
    pub hli_initialized: bool,
    /// MCV_PlatformBase Done (start-up over and versions congruent).
    pub platform_base_done: bool,
    /// Cycles of start-up done.
    pub init_cycles: u64,
    /// Version mismatch detected (4904).
    pub version_mismatch: bool,
    /// Platform errors (§9 `errors`): 4904 on an HLI mismatch.
    pub errors: Vec<ErrorId>,
    /// Raw-layer warnings so far (4906 acknowledgement clog, R-HS-5).
    pub clog_warnings: usize,
    /// The last [`RECENT_CLOG_WARNINGS`] of them, oldest first (for `~/events`).
    pub recent_clog_warnings: Vec<RawWarning>,
    /// Order numbers of the commands in control of an axis or group, or buffered on an axis
    /// (`isg_mcp`): (command id, order number), for the action feedback (§12.1).
    pub orders: Vec<(u64, u32)>,
    /// Next order number.
    pub g_order_id: u32,
    /// Operating mode.
    pub operating_mode: OperatingMode,
    /// Enabling switch.
    pub enabling_switch: bool,
    /// START button.
    pub start_button: bool,
    /// Per axis (only with safety active or `isg_mcp`).
    pub axes: Vec<AxisSafetyStatus>,
}

/// A warning of the raw FB layer (4906 clog, R-HS-5).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RawWarning {
    /// Cycle of detection.
    pub cycle: u64,
    /// Axis name (the group's name for a group FB's channel).
    pub axis: String,
    /// Warning id (4906).
    pub id: ErrorId,
    /// Order number of the acknowledgement lying in the slot.
    pub order_id: u32,
}
