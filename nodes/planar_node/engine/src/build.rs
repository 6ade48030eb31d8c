//! Building an engine from its configuration, in two stages: the objects (`engine.rs`), then
//! the tracks' init parameters (`track::init`), which run as the track commands would.

use crate::config::PlanarConfig;
use crate::engine::PlanarEngine;
use motion_core::Rejection;

impl PlanarEngine {
    /// Builds the engine from a validated configuration; everything starts Disabled.
    pub fn new(cfg: PlanarConfig) -> Result<Self, Rejection> {
        let mut eng = Self::with_objects(&cfg)?;
        crate::track::init::apply(&mut eng, &cfg)?;
        Ok(eng)
    }
}
