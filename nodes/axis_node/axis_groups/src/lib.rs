//! PLCopen Part 4 axis groups (plcopen_platform.md §3.2, §5).
//!
//! Owns: the groups, their FB instances and their path motion ([`GroupCx`] runs the FBs and
//! the group cycle on the axes it is given). Must not know: the engine that composes it, CA
//! groups, the ROS shell; where a platform profile changes the behaviour (ISG error ids and
//! latched outputs, safety caps, feed hold), it asks its [`GroupProfile`].
//!
//! A group is an ordered set of member axes (by IdentInGroup). Group motions are straight
//! lines in axis space: one jerk-limited 1-DOF [`Profile1`] over the path length `s`, each
//! member at `start_i + u_i · s(t)` with the unit direction `u`. The path limits are the
//! FB's dynamics capped so that no member exceeds its own AxisMaxVelocity (1008), AxisAcc
//! (1004), AxisDec (1005) and AxisJerk (1006): `L_path = min(L_fb, min_i L_i / |u_i|)`, exact
//! because velocity, acceleration and jerk of a member are `u_i` times the path's.
//!
//! While a group motion runs, the members are driven by the group (no single-axis job, state
//! SynchronizedMotion) and single-axis motion commands on them are refused. A member error
//! latches GROUP_ERROR_STOP (group error 1); the remaining members then brake on their own
//! with AxisFastDec/AxisFastJerk (proposal: the error reaction is per axis, not path-true).
//! A newer group motion aborts the running one: parallel same-direction lines continue from
//! the current path velocity, anything else stops path-true first (with the new command's
//! deceleration) and then starts the new line (no blending, TMNone).

pub mod command;
mod fbs;
pub mod ids;
pub mod state;

use motion_core::Rejection;
use motion_core::{CmdId, CommandEvent, CommandState, ErrorId, ExecuteOutputs, Limits, Profile1};
use serde::Deserialize;
use single_axis::axis::Axis;
use single_axis::handshake::Handshake;
use std::collections::{HashMap, VecDeque};

pub use command::*;
pub use state::{derive_group_state, group_admission, GroupAdmission, GroupFbClass, GroupState};

/// Configuration of one group (R-ARCH-4: members configured here belong to the group from
/// the start, without MC_AddAxisToGroup).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GroupConfig {
    /// Group name (unique, not empty).
    pub name: String,
    /// Member axes in IdentInGroup order (IdentInGroup = 1, 2, ...).
    pub axes: Vec<String>,
}

/// Which Part 4 FB an instance belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, Deserialize)]
pub enum GroupFbKind {
    /// MC_MoveLinearAbsolute.
    MoveLinearAbsolute,
    /// MC_MoveLinearRelative.
    MoveLinearRelative,
    /// MC_MovePath.
    MovePath,
    /// MC_GroupHalt.
    GroupHalt,
    /// MC_GroupStop.
    GroupStop,
    /// MC_GrpReset.
    GroupReset,
    /// MC_AddAxisToGroup, MC_RemoveAxisFromGroup, MC_UngroupAllAxes, MC_GroupDisable,
    /// MCV_GroupEnable, MC_PathSelect (Done in the next cycle).
    Administrative,
}

/// An admitted Execute-type instance of a group FB.
#[derive(Clone, Copy, Debug)]
pub struct GroupInstance {
    /// The group (index) the instance commands.
    pub group: usize,
    /// Which FB.
    pub kind: GroupFbKind,
    /// Its state: Busy/Active, or final.
    pub state: CommandState,
    /// Its Execute input as last called.
    pub execute: bool,
    /// Cycle in which the final state became visible.
    pub ended_cycle: u64,
    /// Outputs reset by a falling Execute edge.
    pub cleared: bool,
}

/// What the path job does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathKind {
    /// MoveLinear*/MovePath.
    Move,
    /// MC_GroupHalt ramp.
    Halt,
    /// MC_GroupStop ramp.
    Stop,
    /// The group's error reaction after a member error (no FB instance).
    ErrorStop,
}

/// Requested path dynamics (0 = the largest the members allow).
#[derive(Clone, Copy, Debug, Default)]
pub struct Dyn {
    /// Path velocity \[u/s\].
    pub velocity: f64,
    /// Path acceleration \[u/s²\].
    pub acceleration: f64,
    /// Path deceleration \[u/s²\].
    pub deceleration: f64,
    /// Path jerk \[u/s³\].
    pub jerk: f64,
}

/// The running group motion.
#[derive(Clone, Debug)]
pub struct PathJob {
    /// The FB instance that owns the job; None for the error reaction.
    pub owner: Option<CmdId>,
    /// What the job does.
    pub kind: PathKind,
    /// Start point of the current segment (one value per member).
    pub start: Vec<f64>,
    /// Unit direction of the current segment.
    pub dir: Vec<f64>,
    /// Profile over the path coordinate s (0 at `start`).
    pub profile: Profile1,
    /// Time since the profile start \[s\].
    pub t: f64,
    /// The dynamics of the command (a stop that takes over keeps them).
    pub dynamics: Dyn,
    /// Absolute targets still to reach after this segment (rest between them).
    pub queue: VecDeque<Vec<f64>>,
    /// Override 0: stopped, still active.
    pub paused: bool,
    /// The segment's end point.
    pub end: Vec<f64>,
}

/// MC_GroupStop lock.
#[derive(Clone, Copy, Debug)]
pub struct GroupLock {
    /// The MC_GroupStop instance that holds the lock.
    pub owner: CmdId,
    /// Its Execute input (the lock lasts while it is TRUE).
    pub execute: bool,
    /// Done has been reported.
    pub done: bool,
}

/// Runtime state of one group.
#[derive(Clone, Debug)]
pub struct Group {
    /// Group name.
    pub name: String,
    /// (IdentInGroup, axis index), sorted by IdentInGroup.
    pub members: Vec<(u32, usize)>,
    /// MC_GroupDisable (cleared by MCV_GroupEnable).
    pub disabled: bool,
    /// GroupErrorID: the group error (latched until MC_GrpReset).
    pub error: ErrorId,
    /// The running path motion.
    pub job: Option<PathJob>,
    /// The MC_GroupStop lock.
    pub lock: Option<GroupLock>,
    /// MC_GroupSetOverride VelFactor (1 = 100 %).
    pub override_factor: f64,
    /// MC_GroupSetOverride is enabled.
    pub override_enabled: bool,
    /// The path of MC_PathSelect (one point per member per entry).
    pub path: Vec<Vec<f64>>,
    /// Feed hold of R-SAF-5 (T1/T2 without enabling switch + START): path-true stop, the
    /// move stays active.
    pub held: bool,
    /// `isg_mcp`: the channel's order slot is used in this cycle (R-HS-3).
    pub slot: bool,
    /// Path velocity/acceleration of the last cycle (status).
    pub path_vel: f64,
    /// Path acceleration of the last cycle (status).
    pub path_acc: f64,
}

impl Group {
    fn new(name: String) -> Self {
        Group {
            name,
            members: Vec::new(),
            disabled: false,
            error: ErrorId::NONE,
            job: None,
            lock: None,
            override_factor: 1.0,
            override_enabled: false,
            path: Vec::new(),
            slot: false,
            held: false,
            path_vel: 0.0,
            path_acc: 0.0,
        }
    }

    /// Effective velocity factor: the override, 0 during a feed hold.
    pub fn factor(&self) -> f64 {
        if self.held {
            0.0
        } else {
            self.override_factor
        }
    }

    /// Member axis indices in IdentInGroup order.
    pub fn axes(&self) -> impl Iterator<Item = usize> + '_ {
        self.members.iter().map(|m| m.1)
    }

    /// The facts the group state is derived from.
    pub fn facts(&self, axes: &[Axis]) -> state::GroupFacts {
        let enabled = !self.disabled
            && !self.members.is_empty()
            && self.axes().all(|i| axes[i].controller_on && axes[i].status);
        state::GroupFacts {
            error: !self.error.is_none(),
            enabled,
            stopping: self.lock.is_some(),
            moving: self.job.as_ref().is_some_and(|j| j.kind != PathKind::Stop),
        }
    }

    /// The group state (plcopen_platform.md §5).
    pub fn state(&self, axes: &[Axis]) -> GroupState {
        derive_group_state(&self.facts(axes))
    }
}

/// All groups, their FB instances and the axis → group map.
#[derive(Debug, Default)]
pub struct Groups {
    /// Groups in configuration order.
    pub list: Vec<Group>,
    /// Group name → index in `list`.
    pub index: HashMap<String, usize>,
    /// Group of each axis (Part 4 membership; one group per axis).
    pub of_axis: Vec<Option<usize>>,
    /// Admitted Execute-type instances of group FBs.
    pub instances: HashMap<CmdId, GroupInstance>,
    /// Instances reported Done in the next step.
    pub instant_done: Vec<CmdId>,
}

impl Groups {
    /// Sets an instance's state and queues the event (final states never change again).
    pub fn set(&mut self, fbs: &mut Handshake, id: CmdId, state: CommandState) {
        let visible = if fbs.in_step {
            fbs.cycle
        } else {
            fbs.cycle + 1
        };
        if let Some(i) = self.instances.get_mut(&id) {
            if i.state.is_final() || i.state == state {
                return;
            }
            i.state = state;
            if state.is_final() {
                i.ended_cycle = visible;
            }
            fbs.events.push(CommandEvent { id, state });
        }
    }

    /// The outputs of a group instance. `latch` (isg_mcp, R-HS-2): a final result stays
    /// until Execute falls; else (tc2_mc2) it shows for one cycle when Execute is already
    /// FALSE.
    pub fn outputs(&self, id: CmdId, cycle: u64, latch: bool) -> Option<ExecuteOutputs> {
        let i = self.instances.get(&id)?;
        if i.state.is_final() && !i.execute && (i.cleared || (!latch && cycle > i.ended_cycle)) {
            return Some(ExecuteOutputs::default());
        }
        Some(ExecuteOutputs::from(i.state))
    }
}

/// Path limits along unit direction `dir` (module doc). `velocity` None = no FB bound.
pub fn path_limits(axes: &[Axis], members: &[usize], dir: &[f64], d: &Dyn) -> Limits {
    let or_inf = |x: f64| if x > 0.0 { x } else { f64::INFINITY };
    let mut l = Limits {
        velocity: or_inf(d.velocity),
        acceleration: or_inf(d.acceleration),
        deceleration: or_inf(d.deceleration),
        jerk: or_inf(d.jerk),
    };
    for (k, &i) in members.iter().enumerate() {
        let u = dir.get(k).copied().unwrap_or(0.0).abs();
        if u > 1e-12 {
            let c = &axes[i].cfg;
            l.velocity = l.velocity.min(c.max_velocity / u);
            l.acceleration = l.acceleration.min(c.acceleration / u);
            l.deceleration = l.deceleration.min(c.deceleration / u);
            l.jerk = l.jerk.min(c.jerk / u);
        }
    }
    // A zero direction (zero-length move): any finite limits do.
    for x in [
        &mut l.velocity,
        &mut l.acceleration,
        &mut l.deceleration,
        &mut l.jerk,
    ] {
        if !x.is_finite() {
            *x = 1.0;
        }
    }
    l
}

/// What a platform profile decides for the groups (implemented by the engine's platform).
pub trait GroupProfile {
    /// The ISG profile is active: its error ids, latched outputs (R-HS-2) and FB catalogue.
    fn isg(&self) -> bool;
    /// A feed hold is in effect (R-SAF-5): paths stop path-true and stay active.
    fn feed_hold(&self) -> bool;
    /// Velocity cap of axis `ax` from the profile's safety functions \[u/s\] (infinite: none).
    fn velocity_cap(&self, ax: usize) -> f64;
    /// The profile's safety checks of a group motion order before it is admitted (R-SAF-1a,
    /// R-SAF-6): `dir` is the unit direction over `members`, `velocity` the path velocity. A
    /// refusal may raise an MC error on a member (in `axes`, reported through `fbs`).
    #[allow(clippy::too_many_arguments)]
    fn check_group_motion(
        &mut self,
        axes: &mut [Axis],
        fbs: &mut Handshake,
        group: &str,
        fb: &str,
        members: &[usize],
        absolute: bool,
        dir: &[f64],
        velocity: f64,
    ) -> Result<(), Rejection>;
}

/// What one Part 4 FB call or group cycle works on: the groups, the axes and FB handshake of
/// the engine, the axis name index and the profile.
pub struct GroupCx<'a> {
    /// The groups.
    pub groups: &'a mut Groups,
    /// Every axis of the engine (members are indices into it).
    pub axes: &'a mut [Axis],
    /// Axis name → index.
    pub index: &'a HashMap<String, usize>,
    /// The FB handshake (instance ids, events).
    pub fbs: &'a mut Handshake,
    /// The platform profile.
    pub profile: &'a mut dyn GroupProfile,
}

/// The answer to an accepted group FB call (the engine turns it into its `AxisReply`).
#[derive(Clone, Debug, PartialEq)]
pub struct GroupCallReply {
    /// Identity of the FB instance started by this call.
    pub id: CmdId,
    /// Value of read FBs.
    pub value: Option<GroupReply>,
    /// True when the id names a tracked instance whose outputs follow as events.
    pub tracked: bool,
}
