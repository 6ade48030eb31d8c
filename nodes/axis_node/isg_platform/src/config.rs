//! The profile choice and the platform configuration (§2.3, §8, §11).

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

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
