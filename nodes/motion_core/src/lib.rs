//! Pure, shared pieces of every motion engine.
//!
//! Nothing here knows about DDS, clocks, threads or I/O: an engine is driven by
//! [`Engine::command`] (an Execute edge, admitted or rejected at once) and
//! [`Engine::step`] (one cycle of nominal length `dt`). The ROS shell in
//! `motion_runtime` owns the loop; tests call these functions by hand.

pub mod engine;
pub mod error_id;
pub mod fb;
pub mod refill;
pub mod trajectory;

pub use engine::{Engine, Tick};
pub use error_id::ErrorId;
pub use fb::{CmdId, CommandEvent, CommandState, ExecuteOutputs, ObjectRef, Rejection};
pub use trajectory::{Limits, Profile1, State1, TrajectoryError};
