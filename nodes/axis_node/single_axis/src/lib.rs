//! The single axis of Beckhoff Tc2_MC2 (specification: `single_axis.md`; user guide:
//! `docs/axis_node.md`), pure and deterministic.
//!
//! Owns: the axis model ([`axis::Axis`]: set-point generator, following error, monitoring,
//! error reaction), the §2 state machine ([`state`]), the §3 Execute handshake of FB instances
//! ([`handshake`]), BufferMode arithmetic ([`buffer`]), the §6 parameter table ([`params`]),
//! the §1.2 configuration ([`config`]), modulo ([`modulo`]), homing, gearing, phasing and
//! multi-master data, superposition, torque, touch probe, the NcToPlc status ([`status`]), and
//! the FB calls on a set of axes ([`AxisSet`], module [`set`]: input screening, admission,
//! BufferMode, each FB's semantics, the cycle of all axes). A platform profile changes
//! single-axis behaviour only through the [`AxisProfile`] trait.
//! Must not know: axis groups (PLCopen Part 4), collision-avoidance groups, platform profiles
//! or the ROS shell; they build on this crate's public API.

pub mod added;
pub mod added_inputs;
pub mod axis;
pub mod buffer;
pub mod calc;
pub mod config;
pub mod error_ids;
pub mod extension_inputs;
pub mod fb_inputs;
pub mod gearing;
pub mod handshake;
pub mod homing;
pub mod inputs;
pub mod modulo;
pub mod params;
pub mod probe;
pub mod set;
pub mod state;
pub mod status;
pub mod superposition;
pub mod torque;

pub use config::{AxisConfig, FollowingModel};
pub use handshake::{FbKind, FbOutputs};
pub use set::{AxisProfile, AxisSet, FbReply, FbValue, InstanceOutputs, PowerOutputs};
pub use state::MotionState;
