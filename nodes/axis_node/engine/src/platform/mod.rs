//! Platform profile (plcopen_platform.md): `tc2_mc2` (default, single_axis.md normative) or
//! `isg_mcp` (ISG Motion Control Platform). The profile switches on, in small hooks around
//! the unchanged Tc2_MC2 engine:
//!
//! * §6 handshake: Done/CommandAborted/Error latched until Execute falls (R-HS-2); one order
//!   per axis and cycle, the second → FB error 4 (R-HS-3), MC_Stop overwrites (R-HS-4);
//!   global order numbers `g_order_id` (§4.3); no BufferMode (new commands always abort);
//!   FBs of §3 marked * or not listed → 4905.
//! * §7 error handling: FB-level ids 4901 (transition not allowed) / 4902 (invalid
//!   parameter); instances of an axis in ERROR_STOP show ErrorID 1; MC messages with remedy
//!   and reaction class, a 6-entry buffer per axis, cleared by MC_Reset.
//! * §8 safety R-SAF-0 … R-SAF-6 (in `tc2_mc2` only with `safety_monitors: true`).
//! * §9 start-up (INIT_STATE for `nr_cycles_chk_mc_runs` cycles, orders → 4013) and §10
//!   versioning (HLI congruence, mismatch → 4904 at every FB).
//! * §12.2 raw FB layer ([`raw`]): FB_IDLE/ACTIVE/ERROR, re-trigger with the same order
//!   number, the per-axis (per-group for Part 4 FBs) acknowledgement queue with clogging
//!   (4906).
//!
//! * §11 R-SYS-1: enabled software limits of linear axes are travel limits, monitored every
//!   cycle: crossing one → MC error 91001 (reaction class 2: braking with `a_limit`);
//!   R-SYS-2: on modulo axes a discrete motion started while moving positions on its target
//!   modulo after braking (linear axes travel back, as the planner does anyway).
//!
//! Not modelled: `msgs_interface_hash` of R-VER-1 (ROS layer), the unused globals of §2.3
//! (accepted in the config). A feed hold (R-SAF-5) is an effective
//! override of 0 (path-true for groups); overrides written during the hold apply after it.

pub mod axis_rules;
mod hooks;
pub use axis_groups::ids;
pub mod raw;
pub(crate) mod raw_state;
pub(crate) use hooks::classify;

use motion_core::{CmdId, ErrorId};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, HashMap, VecDeque};

/// `platform_profile` (node parameter, §0 of the spec).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PlatformProfile {
    /// Beckhoff Tc2_MC2 (single_axis.md normative): the engine behaves exactly as before.
    #[default]
    Tc2Mc2,
    /// ISG Motion Control Platform (plcopen_platform.md normative where it differs).
    IsgMcp,
}

/// Axis kind for velocity monitoring (R-SAF-1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AxisKind {
    /// Linear axis: monitoring limit fixed at 250 mm/s.
    #[default]
    Linear,
    /// Rotary axis / spindle: limit `vb_monitor` (or `vb_not_referenced` if 0).
    Rotary,
}

/// Platform settings of one axis (§8, §11).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AxisPlatformConfig {
    /// Linear or rotary.
    pub kind: AxisKind,
    /// Units per mm of a linear axis (default 1000: 1 unit = 1 µm, R-SAF-1).
    pub units_per_mm: f64,
    /// Units per degree of a rotary axis.
    pub units_per_deg: f64,
    /// `vb_monitor` (P-AXIS-00311) of rotary axes \[u/s\]; 0 = use `vb_not_referenced`.
    pub vb_monitor: f64,
    /// `getriebe[0].vb_not_referenced` (P-AXIS-00268) \[u/s\] (R-SAF-6).
    pub vb_not_referenced: f64,
    /// `vb_torq_limit_max` (P-AXIS-00314) \[u/s\] (R-SAF-4).
    pub vb_torq_limit_max: f64,
    /// Referenced at start (R-SAF-6).
    pub referenced: bool,
    /// Modulo axis (period = the axis' `modulo_value`): no limit-switch monitoring
    /// (R-SYS-1); a discrete motion aborting a motion positions on its target modulo
    /// after braking over as many revolutions as needed (R-SYS-2).
    pub modulo: bool,
    /// Rapid-traverse (limit) deceleration \[u/s²\] for braking at a travel limit (R-SYS-1)
    /// and for error reaction class 2; 0 = the axis' `fast_deceleration`.
    pub a_limit: f64,
}

impl Default for AxisPlatformConfig {
    fn default() -> Self {
        AxisPlatformConfig {
            kind: AxisKind::Linear,
            units_per_mm: 1000.0,
            units_per_deg: 1000.0,
            vb_monitor: 0.0,
            vb_not_referenced: 20000.0,
            vb_torq_limit_max: 10000.0,
            referenced: true,
            modulo: false,
            a_limit: 0.0,
        }
    }
}

/// Platform globals (§2.3) and safety settings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PlatformConfig {
    /// `MAX_RETRIALS` (proposal): cycles a raw-layer instance retries an order that found
    /// the slot occupied before error 4 (0 = error 4 at once).
    pub max_retrials: u32,
    /// `MAX_RESET_RETRIALS` (accepted, not used: MC_Reset is taken at once here).
    pub max_reset_retrials: u32,
    /// `MAX_RESET_WAIT_CYCLES` (accepted, not used).
    pub max_reset_wait_cycles: u32,
    /// `g_axis_idx_offset` (accepted, not used: axes are addressed by name).
    pub g_axis_idx_offset: i32,
    /// `MAX_USED_INSTANCES` (accepted, not used).
    pub max_used_instances: u32,
    /// `NR_MAX_PLC_CYCLES_CHK_MC_RUNS` (accepted, not used: the simulated MC always runs).
    pub nr_max_plc_cycles_chk_mc_runs: u32,
    /// `NR_CYCLES_CHK_MC_RUNS`: start-up length in cycles (R-INIT-1).
    pub nr_cycles_chk_mc_runs: u32,
    /// Initial `g_order_id`.
    pub g_order_id: u32,
    /// Power all axes at the end of start-up (R-INIT-1).
    pub auto_power: bool,
    /// The node's HLI version id (R-SAF-2).
    pub hli_version: u32,
    /// The node's HLI size \[byte\] (R-SAF-2).
    pub hli_size: u32,
    /// Safety monitors of §8 in `tc2_mc2` (always on in `isg_mcp`).
    pub safety_monitors: bool,
    /// Default lease of `~/safety/deactivate` \[cycles\] (R-SAF-0).
    pub lease_cycles: u32,
    /// Per-axis settings by axis name (unlisted axes: defaults).
    pub axes: BTreeMap<String, AxisPlatformConfig>,
}

impl Default for PlatformConfig {
    fn default() -> Self {
        PlatformConfig {
            max_retrials: 0,
            max_reset_retrials: 50000,
            max_reset_wait_cycles: 1_000_000,
            g_axis_idx_offset: 0,
            max_used_instances: 3,
            nr_max_plc_cycles_chk_mc_runs: 1000,
            nr_cycles_chk_mc_runs: 10,
            g_order_id: 1,
            auto_power: false,
            hli_version: HLI_VERSION,
            hli_size: HLI_SIZE,
            safety_monitors: false,
            lease_cycles: 100,
            axes: BTreeMap::new(),
        }
    }
}

/// The engine's HLI version id (R-SAF-2, R-VER-1).
pub const HLI_VERSION: u32 = 0x0103;
/// The engine's HLI size \[byte\].
pub const HLI_SIZE: u32 = 65536;
/// Linear axes: actual-velocity monitoring limit \[mm/s\], compiled in (R-SAF-1).
pub const LINEAR_LIMIT_MM_S: f64 = 250.0;
/// T1 mode: commanded velocities are clamped to this \[mm/s\] (R-SAF-5 proposal).
pub const T1_LIMIT_MM_S: f64 = 250.0;
/// Entries of the per-axis MC message buffer (§7.2).
pub const ERROR_BUFFER_LEN: usize = 6;

/// Engine-level configuration: profile, Part 4 groups, platform globals.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct EngineConfig {
    /// `platform_profile`: `tc2_mc2` (default) or `isg_mcp`.
    pub platform_profile: PlatformProfile,
    /// Part 4 axis groups configured at start (R-ARCH-4).
    pub groups: Vec<crate::group::GroupConfig>,
    /// Platform globals and safety settings.
    pub platform: PlatformConfig,
}

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
    pub recent_clog_warnings: Vec<raw::RawWarning>,
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

/// Runtime safety state of one axis.
#[derive(Clone, Debug, Default)]
pub(crate) struct AxisPlatform {
    pub cfg: AxisPlatformConfig,
    pub referenced: bool,
    /// Cycles left with velocity monitoring off (0 = active).
    pub velocity_lease: u32,
    pub torque_lease: u32,
    pub torque_limiting: bool,
    /// Injected actual velocity and cycles left.
    pub injected: Option<(f64, u32)>,
    pub messages: VecDeque<McMessage>,
    pub feed_hold: bool,
    /// Order slot of this cycle: the instance that placed its order.
    pub slot: Option<(CmdId, bool)>,
    /// The configured software-limit enables (min, max), suspended while not referenced
    /// (R-SAF-6: no machine-fixed reference, no software limit monitoring).
    pub soft_limits: Option<(bool, bool)>,
}

impl AxisPlatform {
    /// The R-SYS-1 braking deceleration: `a_limit`, or `fast_deceleration` when 0.
    pub fn a_limit(&self, fast_deceleration: f64) -> f64 {
        if self.cfg.a_limit > 0.0 {
            self.cfg.a_limit
        } else {
            fast_deceleration
        }
    }

    /// Velocity monitoring limit \[u/s\] (R-SAF-1).
    pub fn velocity_limit(&self) -> f64 {
        match self.cfg.kind {
            AxisKind::Linear => LINEAR_LIMIT_MM_S * self.cfg.units_per_mm,
            AxisKind::Rotary => {
                if self.cfg.vb_monitor > 0.0 {
                    self.cfg.vb_monitor
                } else {
                    self.cfg.vb_not_referenced
                }
            }
        }
    }

    /// T1 velocity clamp \[u/s\].
    pub fn t1_limit(&self) -> f64 {
        match self.cfg.kind {
            AxisKind::Linear => T1_LIMIT_MM_S * self.cfg.units_per_mm,
            AxisKind::Rotary => self.velocity_limit(),
        }
    }
}

/// Runtime platform state.
#[derive(Clone, Debug, Default)]
pub(crate) struct Platform {
    pub profile: PlatformProfile,
    pub cfg: PlatformConfig,
    pub axes: Vec<AxisPlatform>,
    /// Steps run so far.
    pub cycles: u64,
    pub version_mismatch: bool,
    pub g_order_id: u32,
    pub order_ids: HashMap<CmdId, u32>,
    pub mode: OperatingMode,
    pub enabling_switch: bool,
    pub start_button: bool,
    /// MC_Home instances whose Done marks the axis referenced (R-SAF-6).
    pub homes: Vec<(CmdId, usize)>,
}

impl Platform {
    /// The `isg_mcp` profile is active.
    pub fn isg(&self) -> bool {
        self.profile == PlatformProfile::IsgMcp
    }

    /// Safety monitors of §8 active (always in `isg_mcp`).
    pub fn safety(&self) -> bool {
        self.isg() || self.cfg.safety_monitors
    }

    /// Start-up running (R-INIT-1): `isg_mcp` only.
    pub fn starting(&self) -> bool {
        self.isg() && self.cycles < u64::from(self.cfg.nr_cycles_chk_mc_runs)
    }

    /// Motion in T1/T2 needs the enabling switch and START (R-SAF-5).
    pub fn feed_hold(&self) -> bool {
        self.safety()
            && self.mode != OperatingMode::Auto
            && !(self.enabling_switch && self.start_button)
    }
}
