//! PLCopen single-axis engine (Beckhoff Tc2_MC2), pure and deterministic
//! (specification: /work/shared/spec/single_axis.md).
//!
//! [`AxisEngine`] holds a set of named axes and implements [`motion_core::Engine`]:
//! `command` = one FB call ([`AxisCommand`], one variant per FB), `step` = one NC cycle,
//! `snapshot` = [`AxisSnapshot`] (NCTOPLC_AXIS_REF essentials per axis). Outputs of admitted
//! FB instances: [`AxisEngine::outputs`] / [`AxisEngine::fb_outputs`] and the
//! [`motion_core::CommandEvent`]s of `step`.
//!
//! # For the ROS shell
//!
//! * Build: `AxisEngine::new(vec![(name, AxisConfig)])` (`AxisConfig` deserializes with
//!   defaults = spec §1.2 and `deny_unknown_fields`; invalid values are refused with a message
//!   naming axis, key and value).
//! * Each FB call: `engine.command(AxisCommand::MoveAbsolute(MoveAbsolute { .. }))` →
//!   `Ok(AxisReply { id, value })` (the FB instance is Busy/Active at once; read FBs carry the
//!   value) or `Err(Rejection)` = the FB's Error output at the edge, with the spec's error id.
//!   Later input changes of an instance: `AxisCommand::SetExecute { id, execute }` (Execute
//!   falling: output reset, MC_Stop unlock, MC_Jog button release) and
//!   `AxisCommand::HomeCalibrationCam`.
//! * Each cycle: `engine.step(tick, &mut events)`; `events` get every later state change of an
//!   instance (Active for a buffered command taking over, Done, Aborted, Error).
//! * Outputs of a live instance: [`AxisEngine::outputs`] (Done/Busy/Active/CommandAborted/Error/
//!   ErrorID with the Execute rules of §3.1) or [`AxisEngine::fb_outputs`] (+ InVelocity);
//!   MC_Power: [`AxisEngine::power_outputs`].
//! * State topics: `engine.snapshot()` → [`AxisSnapshot`] with one [`AxisStatus`] per axis
//!   (the fields of `msgs/msg/AxisState.msg` plus modulo set values, homing state, raw
//!   position, SetPosition offset).
//!
//! Modules per concept: [`state`] (§2 state machine and admission matrix), [`handshake`]
//! (§3 Execute handshake), [`buffer`] (§3.6 BufferMode arithmetic), [`params`] (§6 parameter
//! table), [`modulo`] (§4.8.4), [`superposition`] (§4.9), [`probe`] (§4.5), [`calc`] (§4.7.3,
//! §4.7.4), `axis` (setpoint generator, monitoring, error reaction), `homing` (§4.10),
//! `gearing` (§4.12), `torque` (§4.14), `engine` (command screening and FB semantics),
//! [`config`] (§1.2 defaults).
//!
//! Collision-avoidance groups (collision_avoidance.md) live in [`ca`]: groups are configured
//! with [`AxisEngine::add_ca_group`], every CA block is `AxisCommand::Ca(`[`ca::CaCommand`]`)`,
//! values of read/enable blocks come back as `ReplyValue::Ca(`[`ca::CaValue`]`)`, the groups
//! are published in [`AxisSnapshot::ca_groups`] (per axis: order, predecessor, gap to it,
//! effective gap, CA limitation), instance outputs through [`AxisEngine::outputs`] and
//! [`ca::CaGroups::gear_outputs`]. [`bench_ring`] builds a moving ring for benchmarks.

mod axis;
pub mod buffer;
pub mod ca;
pub mod calc;
pub mod command;
pub mod config;
mod engine;
pub mod error_ids;
mod gearing;
pub mod handshake;
mod homing;
pub mod modulo;
pub mod params;
pub mod probe;
pub mod snapshot;
pub mod state;
pub mod superposition;
mod torque;

pub use ca::bench::bench_ring;
pub use command::*;
pub use config::{AxisConfig, FollowingModel};
pub use engine::{AxisEngine, PowerOutputs};
pub use handshake::{FbKind, FbOutputs};
pub use snapshot::{AxisSnapshot, AxisStatus};
pub use state::MotionState;
