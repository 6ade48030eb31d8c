//! The ISG Motion Control Platform profile (plcopen_platform.md) on the single axes
//! (crate `single_axis`) and the Part 4 groups (crate `axis_groups`). Owns: the profile
//! choice (`tc2_mc2`, default and single_axis.md normative, or `isg_mcp`), the platform
//! configuration, safety functions, start-up, versions, MC messages, order numbers and the
//! hooks around each call and cycle ([`PlatformCx`]), and the raw FB layer ([`raw`]) that
//! drives an engine like a PLC program. Must not know: the composed command type (the raw
//! layer is generic over it, [`raw::RawHost`]), collision avoidance, or the ROS shell. The profile switches on, in small hooks around the
//! unchanged Tc2_MC2 axes:
//!
//! * §6 handshake: Done/CommandAborted/Error latched until Execute falls (R-HS-2); one order
//!   per axis and cycle, the second → FB error 4 (R-HS-3), MC_Stop overwrites (R-HS-4);
//!   global order numbers `g_order_id` (§4.3); no BufferMode (new commands always abort);
//!   FBs of §3 marked * or not listed → 4905.
//! * §7 error handling: FB-level ids 4901 (transition not allowed) / 4902 (invalid
//!   parameter); instances of an axis in ERROR_STOP show ErrorID 1; MC messages with remedy
//!   and reaction class, a 6-entry buffer per axis, cleared by MC_Reset.
//! * §8 safety R-SAF-0 … R-SAF-6 (in `tc2_mc2` only with `safety_monitors: true`).
//! * §9 start-up (INIT_STATE for `nr_cycles_chk_mc_runs` cycles, orders → 4013) and §10
//!   versioning (HLI congruence, mismatch → 4904 at every FB).
//! * §12.2 raw FB layer ([`raw`]): FB_IDLE/ACTIVE/ERROR, re-trigger with the same order
//!   number, the per-axis (per-group for Part 4 FBs) acknowledgement queue with clogging
//!   (4906).
//!
//! * §11 R-SYS-1: enabled software limits of linear axes are travel limits, monitored every
//!   cycle: crossing one → MC error 91001 (reaction class 2: braking with `a_limit`);
//!   R-SYS-2: on modulo axes a discrete motion started while moving positions on its target
//!   modulo after braking (linear axes travel back, as the planner does anyway).
//!
//! Not modelled: `msgs_interface_hash` of R-VER-1 (ROS layer), the unused globals of §2.3
//! (accepted in the config). A feed hold (R-SAF-5) is an effective
//! override of 0 (path-true for groups); overrides written during the hold apply after it.

pub mod axis_rules;
mod config;
mod hooks;
pub mod raw;
mod services;
mod state;
mod status;

pub use axis_groups::ids;
pub use config::*;
pub use hooks::{AxisCall, PlatformCx, PostKind, SIM};
pub use services::*;
pub use state::Platform;
pub use status::*;
