//! The platform profile in the axis engine: crate `isg_platform` (re-exported here: profile,
//! configuration, safety, start-up, services, the hooks [`PlatformCx`], the raw FB layer),
//! and the engine's configuration [`EngineConfig`]. The engine's glue to the hooks
//! ([`PlatformCx`] for each call and cycle, [`isg_platform::raw::RawHost`] for the raw layer)
//! is a child of the composition, `engine/platform.rs`.

pub use isg_platform::*;

/// The raw FB layer (plcopen_platform.md §12.2) over this engine's commands.
pub mod raw {
    pub use isg_platform::raw::{AckKind, FbOut, FbState};
    pub use isg_platform::RawWarning;
    /// One FB call of a PLC cycle on the axis engine.
    pub type FbCall = isg_platform::raw::FbCall<crate::command::AxisCommand>;
}

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
