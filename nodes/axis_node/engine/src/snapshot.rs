//! The published state of the whole axis engine: every axis' status ([`crate::status`]), the
//! Part 4 groups, the platform and the collision-avoidance groups (the composition's view).

pub use crate::status::*;
use serde::{Deserialize, Serialize};

/// State of all axes, in configuration order.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AxisSnapshot {
    /// Cycle index of the last step.
    pub tick: u64,
    /// One entry per axis.
    pub axes: Vec<AxisStatus>,
    /// One entry per Part 4 axis group (plcopen_platform.md §5).
    pub groups: Vec<crate::group::GroupStatus>,
    /// Platform profile, start-up and safety state (plcopen_platform.md §8–§10).
    pub platform: isg_platform::PlatformStatus,
    /// Collision-avoidance groups (collision_avoidance.md §9.5).
    #[serde(default)]
    pub ca_groups: Vec<crate::ca::CaGroupStatus>,
}

impl AxisSnapshot {
    /// The status of the named axis.
    pub fn axis(&self, name: &str) -> Option<&AxisStatus> {
        self.axes.iter().find(|a| &*a.name == name)
    }
}
