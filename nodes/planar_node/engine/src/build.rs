//! Building an engine from its configuration, in two stages: the objects (`engine.rs`), then
//! the tracks' init parameters (`build::tracks`), which run as the track commands would.

use crate::config::PlanarConfig;
use crate::engine::PlanarEngine;
use motion_core::Rejection;

impl PlanarEngine {
    /// Builds the engine from a validated configuration; everything starts Disabled.
    pub fn new(cfg: PlanarConfig) -> Result<Self, Rejection> {
        let objects = crate::objects::Objects::build(&cfg)?;
        let tracks = crate::track::TrackSystem::new(&cfg, &objects);
        let mut eng = PlanarEngine { objects, tracks };
        tracks::apply(&mut eng, &cfg)?;
        Ok(eng)
    }
}

mod tracks;
