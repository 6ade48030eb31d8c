//! XPlanar planar-motion engine (xplanar.md): environment, parts and coordinate systems,
//! movers with six coordinates, groups with area reservation, feedback, the no-overlap guard,
//! and tracks ([`track`]): C² geometry, operation modes, join/leave, MoveOnTrack with gap
//! control and modulo positioning on closed loops, networks with switch collision avoidance,
//! AdoptTrackOrientation, gear-in on a master mover or a virtual axis along a trail.
//!
//! Pure and deterministic: [`PlanarEngine`] implements [`motion_core::Engine`]; time comes
//! only from `step(tick)`.
//!
//! ```text
//! PlanarEngine::new(PlanarConfig) -> Result<PlanarEngine, Rejection>
//! engine.command(PlanarCommand::MoveToPosition { mover, target_position, constraint, options })
//!     -> Ok(PlanarReply { id, warning_id, value }) | Err(Rejection { error_id, message })
//! engine.step(Tick { index, dt }, &mut events)   // CommandEvent { id, state } per change
//! engine.snapshot() -> PlanarSnapshot { environment, movers, groups, parts, tracks, axes }
//! ```
//!
//! Layers (issue 16), each a module over explicit data:
//! * `objects`: the objects in one place (`Objects`: environment, parts, movers, groups;
//!   §1–§3, §5.1–§5.3, §5.10–§5.11), with admission, free movement and the no-overlap guard;
//!   it reaches the tracks only through its `TrackHooks` trait;
//! * [`track`]: the track subsystem (`TrackSystem`: tracks, switches, virtual axes; §1.6,
//!   §2.5, §3.3, §5.4–§5.9, §5.12) with its own state, driving the movers only through its
//!   `MoverDrive` trait (implemented by `Objects`);
//! * `engine`: [`PlanarEngine`], the composition: commands and the cycle's stages, and the
//!   one place where the two traits are wired (`TrackHooks` for `TrackSystem`);
//! * `build` (the engine from its configuration, the tracks' init parameters as commands)
//!   and [`bench`](mod@bench) (the benchmark scene, [`bench_loop`]) use the engine from above.
//!
//! Shared below them: [`config`] (§1.12), `state` (§2.1), [`admission`] (§2.3), [`command`]
//! (§3), [`types`] (§3.8, §4), [`motion`] (§5.1–§5.3), [`geometry`] and `guard` (§5.11 and
//! the no-overlap invariant), [`errors`] (§6.2), [`snapshot`] (§4.4).

pub mod admission;
pub mod bench;
mod build;
pub mod command;
pub mod config;
mod engine;
pub mod errors;
pub mod geometry;
mod guard;
pub mod motion;
mod objects;
mod on_track;
pub mod snapshot;
mod state;
pub mod track;
pub mod types;

pub use admission::{admissible, AdmissionContext, CommandKind};
pub use bench::bench_loop;
pub use command::{ObjectKind, PlanarCommand};
pub use config::{
    CollisionRangeMode, EnvironmentConfig, GroupConfig, InitialPose, MoverConfig, PartConfig,
    PartPositionConfig, PlanarConfig, TrackCircleConfig, TrackConfig, TrackGeometryItem,
    TrackLineConfig, TrackLinkAdvancedConfig, TrackLinkConfig, TrackPositionConfig,
    VirtualAxisConfig,
};
pub use engine::PlanarEngine;
pub use snapshot::{
    ActiveCommands, BusyFlags, EnvironmentSnapshot, GroupSnapshot, MoverSnapshot, OnTrackSnapshot,
    PartSnapshot, PlanarReply, PlanarSnapshot, ReplyValue, TrackSnapshot, VirtualAxisSnapshot,
};
pub use state::Timing;
pub use track::geometry::{TrackGeometry, TrackPose};
pub use types::*;
