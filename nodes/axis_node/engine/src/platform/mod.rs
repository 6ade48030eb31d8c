//! The platform profile in the axis engine: crate `isg_platform` (re-exported here: profile,
//! configuration, safety, start-up, services, the hooks [`PlatformCx`]), the engine's
//! configuration [`EngineConfig`], the engine's glue to the hooks (`hooks`) and the raw FB
//! layer ([`raw`], plcopen_platform.md §12.2), a PLC program over the composed engine.

mod hooks;
pub use isg_platform::*;
pub mod raw;
pub(crate) mod raw_state;

use serde::Deserialize;

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
