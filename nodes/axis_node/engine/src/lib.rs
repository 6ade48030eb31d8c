//! The axis node's engine, pure and deterministic: the composition [`AxisEngine`] of the
//! [`single_axis`] (axes and their FB calls), [`axis_groups`] (PLCopen Part 4),
//! [`collision_avoidance`] and [`isg_platform`] (the ISG profile) crates, and the raw FB layer
//! over it. Must not know: DDS, ROS, clocks or threads (the `axis_node` shell does).
//! Specifications: `single_axis.md`, `collision_avoidance.md`, `plcopen_platform.md`; user
//! guide: `docs/axis_node.md`.
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
//! # Part 4 axis groups and the platform profile (plcopen_platform.md)
//!
//! * Build with [`AxisEngine::with_config`]`(axes, &EngineConfig)`; [`EngineConfig`]
//!   deserializes with `deny_unknown_fields`: `platform_profile: tc2_mc2 | isg_mcp` (default
//!   `tc2_mc2` = exactly the behaviour of `AxisEngine::new`), `groups: [{name, axes}]`
//!   (members from the start, R-ARCH-4) and `platform` (globals of §2.3, `safety_monitors`,
//!   `lease_cycles`, per-axis `axes.<name>: {kind, units_per_mm, vb_monitor,
//!   vb_not_referenced, vb_torq_limit_max, referenced}`).
//! * Group FBs: `AxisCommand::Group(`[`GroupCommand`]`::MoveLinearAbsolute(..))` etc. Replies
//!   as for axes (`tracked` for Execute-type FBs; reads carry `ReplyValue::Group(`
//!   [`GroupReply`]`)`); outputs of a group instance via [`AxisEngine::outputs`] or
//!   `ReadFbOutputs` (`GroupReply::Outputs`); `SetExecute` releases MC_GroupStop; `cancel`
//!   = MC_GroupHalt. State: `snapshot().groups` ([`GroupStatus`]) or
//!   [`AxisEngine::group`].
//! * Safety/simulation/session services: `AxisCommand::Platform(`[`PlatformCommand`]`)`;
//!   state in `snapshot().platform` ([`platform::PlatformStatus`]: start-up, order number,
//!   operating mode, per-axis monitors, referenced, DriveEnabled, MC message buffer).
//! * Error ids of the platform spec: [`platform::ids`] (1, 4, 4013, 4901…4907, 60241,
//!   70220, 70225).
//!
//! Layers (issue 16), each its own crate on the public API of the ones below it:
//! * [`single_axis`]: axis model, §2 state machine, §3 handshake, BufferMode, parameters,
//!   homing, gearing, superposition, torque, probe, status, and the FB calls on a set of axes
//!   ([`AxisSet`]: screening, admission, FB semantics); it knows nothing of groups, CA or
//!   platforms. Where a profile changes a single axis, it defines the trait
//!   ([`single_axis::AxisProfile`]);
//! * [`collision_avoidance`] ([`ca`]) and [`axis_groups`] ([`group`]) on the axes;
//! * [`isg_platform`] (re-exported as [`platform`]): the ISG profile's handshake, error
//!   handling, safety, start-up and versions, as hooks ([`platform::PlatformCx`]) around
//!   the single axes and groups; it implements `AxisProfile` and the groups' `GroupProfile`;
//! * this crate: the composition (`engine`: each call routed to its layer through the
//!   profile's hooks, the cycle's order), the engine configuration, and the raw FB layer
//!   ([`platform::raw`], §12.2), a PLC program that drives the composed engine.
//!
//! The single axis' modules are re-exported here under their old paths ([`state`],
//! [`handshake`], [`buffer`], [`params`], [`modulo`], [`superposition`], [`probe`], [`calc`],
//! [`config`], ...).
//!
//! Added later, in `single_axis::set`, routed like every single-axis FB (`engine.rs`):
//! [`phasing`] (§4.13), [`multi_master`] (MC_GearInMultiMaster, §4.12.4), [`ext_setpoint`]
//! (§4.6) and [`extensions`] (§4.7, MC_ReadParameterSet, MC_ReadAxisComponents,
//! MC_Write(Bool)ParameterPersistent). For the shell: later inputs of a running
//! MC_PhasingAbsolute/Relative with ContinuousUpdate are `AxisCommand::PhasingUpdate`;
//! MC_GearInMultiMaster, MC_BacklashCompensation, MC_PositionCorrectionLimiter and
//! MC_TableBasedPositionCompensation are Enable-type (Enable↑ = new instance, calls with
//! Enable TRUE = same id with new inputs, Enable↓ = end); their extra outputs
//! (AbsolutePhaseShift, Enabled, CurrentBacklash, Limiting, ...) are
//! [`InstanceOutputs::extra`]; NCTOPLC values of these functions (AbsPhasingPos,
//! ActPosWithoutPosCorrection, drive mode, encoder counter, ...) are
//! [`AxisEngine::ext_status`]; the persistent-parameter list for the shell to store is
//! [`AxisEngine::persistent_parameters`] / [`AxisEngine::apply_persistent_parameters`].
//!
//! Collision-avoidance groups (collision_avoidance.md) live in [`ca`]: groups are configured
//! with [`AxisEngine::add_ca_group`], every CA block is `AxisCommand::Ca(`[`ca::CaCommand`]`)`,
//! values of read/enable blocks come back as `ReplyValue::Ca(`[`ca::CaValue`]`)`, the groups
//! are published in [`AxisSnapshot::ca_groups`] (per axis: order, predecessor, gap to it,
//! effective gap, CA limitation), instance outputs through [`AxisEngine::outputs`] and
//! [`ca::CaGroups::gear_outputs`]. [`bench_ring`] builds a moving ring for benchmarks.

pub use collision_avoidance as ca;
pub mod ca_bench;
pub mod command;
mod engine;
pub use axis_groups as group;
pub mod platform;
pub mod snapshot;

// The single axis (its own crate, issue 16): re-exported under the paths this crate and its
// users have always used.
pub use single_axis::{
    buffer, calc, config, error_ids, extension_inputs, handshake, inputs, modulo, params, probe,
    state, status, superposition,
};

pub use ca_bench::bench_ring;
pub use command::*;
pub use config::{AxisConfig, FollowingModel};
pub use engine::AxisEngine;
pub use group::{GroupCommand, GroupConfig, GroupReply, GroupState, GroupStatus};
pub use handshake::{FbKind, FbOutputs};
pub use platform::{EngineConfig, PlatformCommand, PlatformProfile};
pub use single_axis::set::{ext_setpoint, extensions, multi_master, phasing};
pub use single_axis::{AxisSet, PowerOutputs};
pub use snapshot::{AxisSnapshot, AxisStatus, ExtValues};
pub use state::MotionState;
