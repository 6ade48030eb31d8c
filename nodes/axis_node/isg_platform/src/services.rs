//! The safety, simulation and session services of §12.1 and their values.

use motion_core::{CmdId, ErrorId};
use serde::{Deserialize, Serialize};

/// Safety functions that `~/safety/deactivate` can switch off for a lease (R-SAF-0).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum SafetyFunction {
    /// Actual and commanded velocity monitoring (R-SAF-1).
    VelocityMonitoring = 1,
    /// Velocity monitoring during torque limiting (R-SAF-4).
    TorqueLimitMonitoring = 2,
}

impl SafetyFunction {
    /// From the raw number (1, 2); else `ENUM_OUT_OF_RANGE`.
    pub fn from_raw(v: u32) -> Result<Self, motion_core::Rejection> {
        match v {
            1 => Ok(SafetyFunction::VelocityMonitoring),
            2 => Ok(SafetyFunction::TorqueLimitMonitoring),
            _ => Err(motion_core::Rejection::new(
                ErrorId::ENUM_OUT_OF_RANGE,
                format!("function = {v} is not a SafetyFunction (1 velocity_monitoring, 2 torque_limit_monitoring)"),
            )),
        }
    }
}

/// Operating mode (R-SAF-5).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum OperatingMode {
    /// AUTO (0).
    #[default]
    Auto = 0,
    /// T1 (1): set-up mode with reduced speed.
    T1 = 1,
    /// T2 (2): set-up mode without reduced speed.
    T2 = 2,
}

impl OperatingMode {
    /// From the raw number (0, 1, 2); else `ENUM_OUT_OF_RANGE`.
    pub fn from_raw(v: u32) -> Result<Self, motion_core::Rejection> {
        match v {
            0 => Ok(OperatingMode::Auto),
            1 => Ok(OperatingMode::T1),
            2 => Ok(OperatingMode::T2),
            _ => Err(motion_core::Rejection::new(
                ErrorId::ENUM_OUT_OF_RANGE,
                format!("mode = {v} is not an OperatingMode (0 AUTO, 1 T1, 2 T2)"),
            )),
        }
    }
}

/// One MC message (`HLI_ERROR_SATZ`, §7.2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct McMessage {
    /// error_id.
    pub error_id: u32,
    /// Cycle of occurrence (fb_zeitangabe).
    pub cycle: u64,
    /// behebungs_klasse (remedy class): 0 = warning, > 0 = error.
    pub behebungs_klasse: u16,
    /// reaktions_klasse: 0 none, 1 decelerate, 2 quick stop, 3 brake + enable off.
    pub reaktions_klasse: u16,
}

/// Platform commands (safety, simulation and session services of §12.1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum PlatformCommand {
    /// `~/safety/deactivate {axis, function, lease_cycles}` (R-SAF-0); 0 = default lease.
    SafetyDeactivate {
        /// Axis name.
        axis: String,
        /// The function.
        function: SafetyFunction,
        /// Lease \[cycles\] (0 = `lease_cycles` of the config).
        lease_cycles: u32,
    },
    /// `~/safety/operating_mode` (R-SAF-5).
    OperatingMode {
        /// AUTO, T1 or T2.
        mode: OperatingMode,
    },
    /// `~/safety/enabling_switch` (R-SAF-5).
    EnablingSwitch {
        /// Pressed.
        pressed: bool,
    },
    /// `~/safety/start_button` (R-SAF-5).
    StartButton {
        /// Pressed.
        pressed: bool,
    },
    /// `~/sim/inject_mc_message` (§7.2).
    InjectMcMessage {
        /// Axis name.
        axis: String,
        /// error_id (> 0).
        error_id: u32,
        /// Remedy class (0 = warning).
        behebungs_klasse: u16,
        /// Reaction class 0..3.
        reaktions_klasse: u16,
    },
    /// `~/sim/inject_actual_velocity` (R-SAF-1b): the actual velocity seen by the monitor.
    InjectActualVelocity {
        /// Axis name.
        axis: String,
        /// Velocity \[u/s\].
        velocity: f64,
        /// Duration \[cycles\].
        duration_cycles: u32,
    },
    /// `~/sim/torque_limit` (R-SAF-4).
    TorqueLimit {
        /// Axis name.
        axis: String,
        /// Torque limiting active.
        active: bool,
    },
    /// `~/sim/set_referenced` (R-SAF-6).
    SetReferenced {
        /// Axis name.
        axis: String,
        /// Referenced.
        referenced: bool,
    },
    /// Session start of a raw FB client with its HLI replica (R-SAF-2): a mismatch makes
    /// every FB fail with 4904.
    SessionStart {
        /// Client's HLI version id.
        hli_version: u32,
        /// Client's HLI size.
        hli_size: u32,
    },
    /// `~/platform/versions` (R-VER-1): reply [`PlatformReply::Versions`].
    ReadVersions,
    /// The MC message buffer of an axis (MC_ReadAxisError's buffer, §7.2): reply
    /// [`PlatformReply::Messages`].
    ReadMessages {
        /// Axis name.
        axis: String,
    },
    /// Order number of an instance (R-FB-3): reply [`PlatformReply::OrderId`].
    ReadOrderId {
        /// The instance.
        id: CmdId,
    },
}

/// Replies of platform commands.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum PlatformReply {
    /// Versions (R-VER-1).
    Versions(Versions),
    /// MC messages, newest first.
    Messages(Vec<McMessage>),
    /// Order number (0 = none placed).
    OrderId(u32),
}

/// `~/platform/versions` (R-VER-1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Versions {
    /// HLI version id.
    pub hli_version: u32,
    /// HLI size.
    pub hli_size: u32,
    /// McpBase library version.
    pub mcp_base: String,
    /// McpPLCopenP1 library version.
    pub mcp_plcopen_p1: String,
    /// McpPLCopenP4 library version.
    pub mcp_plcopen_p4: String,
    /// Engine crate version.
    pub node_version: String,
}
