//! Collision-avoidance (CA) groups (collision_avoidance.md, TF5410 model).
//!
//! Owns: the CA groups, their blocks (MC_*CA, group administration) and the group cycle that
//! sets the members' set values. Must not know: the engine that composes it, Part 4 groups,
//! platform profiles, the ROS shell; it works on [`single_axis`]'s public API (the axes and
//! the FB handshake it is given).
//!
//! A [`CaGroup`] bundles axes (of the engine's axis list) that share one rail; every axis keeps
//! at least its gap to the axis in front. While a group is enabled it owns the set values of its
//! members: `CaGroups::step` runs before the single-axis step (which then only derives actual
//! values and monitoring). Submodules: [`types`] (config, commands, state, error ids),
//! `admin` (block admission, §4.2 rules, §5), `cycle` (the group cycle: §4.2 transitions, §8.3
//! order, planner glue), [`planner`] (§8.4–§8.6), `gear` (MC_GearInPosCA, §5.5), [`modulo`]
//! (§5.2.3), [`geometry`] (§3.4, §5.9).

mod admin;
mod cycle;
pub mod errors;
mod gear;
pub mod geometry;
pub mod modulo;
pub mod planner;
pub mod types;

use cycle::*;
use gear::*;
use motion_core::{CmdId, CommandEvent, CommandState, ErrorId, ExecuteOutputs, Rejection, State1};
use planner::{stop_point, stop_point_back, Bound, Kin, Lead, StepIn};
use single_axis::axis::Axis;
use single_axis::handshake::Handshake;
use std::collections::HashMap;
use types::errors as err;
pub use types::*;

/// Tolerance of gap checks and Done \[mm\] (§8.2).
const EPS: f64 = 1e-6;
/// Smallest retreat that starts establishing motion \[mm\] (§1.7: `e_i < x_i − 1e-6`).
const ESTABLISH_MIN: f64 = 1e-6;
/// CA instances above this count are pruned (finished ones) when a new one is admitted.
const PRUNE_ABOVE: usize = 4096;
/// Jerk used for MC_IGNORE (unlimited jerk of group halt/stop) \[mm/s³\].
const JERK_UNLIMITED: f64 = 1e15;

/// MC3 dynamics of one axis (§3.2), derived from its [`single_axis::AxisConfig`]: maxima =
/// `max_velocity`, `fast_acceleration`, `fast_deceleration`, `fast_jerk`; defaults =
/// `acceleration`, `deceleration`, `jerk` (capped at the maxima).
#[derive(Clone, Copy, Debug)]
struct AxisDyn {
    max_v: f64,
    max_a: f64,
    max_d: f64,
    max_j: f64,
    def_a: f64,
    def_d: f64,
    def_j: f64,
}

impl AxisDyn {
    fn of(a: &Axis) -> Self {
        let c = &a.cfg;
        AxisDyn {
            max_v: c.max_velocity,
            max_a: c.fast_acceleration,
            max_d: c.fast_deceleration,
            max_j: c.fast_jerk,
            def_a: c.acceleration.min(c.fast_acceleration),
            def_d: c.deceleration.min(c.fast_deceleration),
            def_j: c.jerk.min(c.fast_jerk),
        }
    }
}

/// Resolved dynamics of a command \[mm/s, mm/s², mm/s², mm/s³\].
#[derive(Clone, Copy, Debug, PartialEq)]
struct Dyn {
    v: f64,
    a: f64,
    d: f64,
    j: f64,
}

/// What a motion request asks for, resolved at admission (relative distances at activation).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Goal {
    Absolute(f64),
    Relative(f64),
    /// Distance on a template's offset path (PositionReferenceSystem, §5.9).
    RelativeOffset(f64, geometry::OffsetPath),
    Brake,
    Gear(Gear),
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Request {
    owner: Option<CmdId>,
    goal: Goal,
    dy: Dyn,
    gap: f64,
    mode: GapControlMode,
    continuous_update: bool,
    /// DynamicsReferenceSystem: plan on this offset path (§5.9); None = motor path.
    dyn_path: Option<geometry::OffsetPath>,
}

/// The active job of a member. `Copy` and stored inline (the coupling variant is the largest):
/// a box would allocate per command, and the cycle must not allocate.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug, PartialEq)]
enum Job {
    Idle,
    /// Move to `target` (absolute).
    Position {
        req: Request,
        target: f64,
    },
    /// Brake to standstill (HaltCA, group halt/stop/error).
    Brake {
        req: Request,
    },
    /// MC_GearInPosCA coupling.
    Gear {
        req: Request,
        gear: Gear,
    },
}

impl Job {
    fn req(&self) -> Option<&Request> {
        match self {
            Job::Idle => None,
            Job::Position { req, .. } | Job::Brake { req } | Job::Gear { req, .. } => Some(req),
        }
    }
    fn owner(&self) -> Option<CmdId> {
        self.req().and_then(|r| r.owner)
    }
}

#[derive(Clone, Debug)]
struct Member {
    axis: usize,
    ident: u32,
    dynamics: AxisDyn,
    /// Pair gap to the predecessor, tracked continuously (§1.3) \[mm\]; NaN without one.
    gap: f64,
    job: Job,
    pending: Option<Request>,
    /// Gap of the last valid command (§1.3 rule 2).
    last_gap: f64,
    /// Committed CA braking dynamics (§8.4).
    d_ca: f64,
    j_ca: f64,
    /// Braking dynamics used for C4 in the last cycle (neighbours' committed stop).
    d_b: f64,
    j_b: f64,
    ca_limited: bool,
    min_margin: f64,
    updated: bool,
    /// Establishing (§1.7): how far this axis has to retreat to open its gap \[mm\].
    retreat: f64,
    /// Active track (0 = absolute).
    track: u32,
    /// Registered mover template (0 = none).
    compensation: u32,
}

#[derive(Clone, Copy, Debug)]
struct Instance {
    kind: CaFbKind,
    state: CommandState,
    /// GroupStop: Execute level; Done is shown with Busy/Active while held.
    execute: bool,
}

/// One CA group.
#[derive(Clone, Debug)]
pub struct CaGroup {
    name: String,
    cfg: CaGroupConfig,
    state: GroupState,
    enable_requested: bool,
    error_id: ErrorId,
    /// Members in CA order, front first.
    members: Vec<Member>,
    /// Override: desired factor, effective factor, ramp rate \[1/s\].
    ovr_target: f64,
    ovr_actual: f64,
    ovr_rate: f64,
    halt: Option<CmdId>,
    stop: Option<CmdId>,
    stop_done: bool,
    gap_budget_exceeded: bool,
    /// Scratch: processing order (no alloc in steady state).
    order: Vec<usize>,
    back: Vec<usize>,
}

/// All CA groups of an engine.
#[derive(Clone, Debug, Default)]
pub struct CaGroups {
    groups: Vec<CaGroup>,
    by_name: HashMap<String, usize>,
    /// Axis index → group index.
    axis_group: HashMap<usize, usize>,
    instances: HashMap<CmdId, Instance>,
    /// Admin instances reported Done in the next cycle.
    instant_done: Vec<CmdId>,
}

fn rej(id: ErrorId, msg: impl Into<String>) -> Rejection {
    Rejection::new(id, msg)
}

fn finite_or(v: f64, id: ErrorId, what: &str) -> Result<f64, Rejection> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(rej(id, format!("{what} = {v} is not finite")))
    }
}

impl CaGroup {
    fn new(name: String, cfg: CaGroupConfig) -> Self {
        CaGroup {
            name,
            cfg,
            state: GroupState::GroupDisabled,
            enable_requested: false,
            error_id: ErrorId::NONE,
            members: Vec::new(),
            ovr_target: 1.0,
            ovr_actual: 1.0,
            ovr_rate: 0.0,
            halt: None,
            stop: None,
            stop_done: false,
            gap_budget_exceeded: false,
            order: Vec::new(),
            back: Vec::new(),
        }
    }

    fn enabled(&self) -> bool {
        !matches!(
            self.state,
            GroupState::GroupDisabled | GroupState::GroupErrorDisabled
        )
    }

    fn n(&self) -> usize {
        self.members.len()
    }

    /// Index of the predecessor of member `k`.
    fn pred(&self, k: usize) -> Option<usize> {
        let n = self.n();
        if n < 2 {
            None
        } else if k > 0 {
            Some(k - 1)
        } else if self.cfg.rail_is_ring {
            Some(n - 1)
        } else {
            None
        }
    }

    /// Index of the successor of member `k`.
    fn succ(&self, k: usize) -> Option<usize> {
        let n = self.n();
        if n < 2 {
            None
        } else if k + 1 < n {
            Some(k + 1)
        } else if self.cfg.rail_is_ring {
            Some(0)
        } else {
            None
        }
    }

    /// Pair gap initialisation (§1.3): `(x_pred − x) mod L` on a ring, the difference otherwise.
    fn init_gap(&mut self, k: usize, axes: &[Axis]) {
        self.members[k].gap = match self.pred(k) {
            None => f64::NAN,
            Some(p) => {
                let d = axes[self.members[p].axis].set.pos - axes[self.members[k].axis].set.pos;
                if self.cfg.rail_is_ring {
                    d.rem_euclid(self.cfg.rail_length)
                } else {
                    d
                }
            }
        };
    }

    fn init_all_gaps(&mut self, axes: &[Axis]) {
        for k in 0..self.n() {
            self.init_gap(k, axes);
        }
    }

    fn default_mode(&self) -> GapControlMode {
        match self.cfg.default_gap_control_mode {
            DefaultGapControlMode::Standard => GapControlMode::Standard,
            DefaultGapControlMode::Fast => GapControlMode::Fast,
        }
    }

    /// Mode of an axis' own motion (§1.4): its active command's (resolved) or the default.
    fn mode_of(&self, k: usize) -> GapControlMode {
        match self.members[k].job.req().map(|r| r.mode) {
            Some(GapControlMode::GroupDefault) | None => self.default_mode(),
            Some(m) => m,
        }
    }

    /// Effective gap of member `k` (§1.3).
    fn eff_gap(&self, k: usize) -> f64 {
        match self.members[k].job.req() {
            Some(r) if r.mode != GapControlMode::None => r.gap,
            _ => self.members[k].last_gap,
        }
    }

    /// Offset of member `k`'s registered, active mover template (0: motor path, §1.13).
    fn comp_y(&self, k: usize) -> f64 {
        match self.members[k].compensation {
            0 => 0.0,
            oid => self.cfg.geometry.y_shift(oid).unwrap_or(0.0),
        }
    }

    /// Motor position `d` further along the offset path of shift `y` from motor position `x`.
    fn offset_shift(&self, y: f64, x: f64, d: f64) -> f64 {
        let (geo, l) = (&self.cfg.geometry, self.cfg.rail_length);
        geo.from_offset(l, y, geo.to_offset(l, y, x) + d)
    }

    /// Pair gap of member `k` as CA measures it: on the offset path of a compensated axis.
    fn gap_measured(&self, k: usize, axes: &[Axis]) -> f64 {
        let m = &self.members[k];
        let y = self.comp_y(k);
        if y == 0.0 || !m.gap.is_finite() {
            return m.gap;
        }
        let (geo, l) = (&self.cfg.geometry, self.cfg.rail_length);
        let x = axes[m.axis].set.pos;
        geo.to_offset(l, y, x + m.gap) - geo.to_offset(l, y, x)
    }

    /// The offset path of a PositionReferenceSystem OID for member `k`: it must be the
    /// axis' registered, active template (§5.2.2, §7.2 COMPENSATION_ERROR).
    fn reference_path(&self, k: usize, oid: u32) -> Result<geometry::OffsetPath, Rejection> {
        if self.members[k].compensation != oid {
            return Err(rej(
                err::COMPENSATION_ERROR,
                format!("PositionReferenceSystem {oid:#x} is not registered for this axis"),
            ));
        }
        let y = self.cfg.geometry.y_shift(oid)?;
        Ok(self.cfg.geometry.path(self.cfg.rail_length, y))
    }

    /// DynamicsReferenceSystem of member `k` (0 = motor path).
    fn dyn_path(&self, k: usize, oid: u32) -> Result<Option<geometry::OffsetPath>, Rejection> {
        match oid {
            0 => Ok(None),
            oid => self.reference_path(k, oid).map(Some),
        }
    }

    fn all_standing(&self, axes: &[Axis]) -> bool {
        self.members.iter().all(|m| {
            let s = axes[m.axis].set;
            s.vel == 0.0 && s.acc == 0.0
        })
    }

    fn busy(&self) -> bool {
        self.members
            .iter()
            .any(|m| m.job != Job::Idle || m.retreat > ESTABLISH_MIN)
    }

    /// Establishing targets (§1.7): from the anchor backwards, each axis retreats by
    /// `δ_i = max(0, δ_pred + g_i − gap_i)`. Only where establishing applies (idle axes with
    /// standby gap control, commanded ones with active establishing). No alloc.
    fn plan_establishing(&mut self) {
        let n = self.n();
        let standby = self.cfg.standby_gap_control;
        let active = self.cfg.active_gap_establishing;
        for m in &mut self.members {
            m.retreat = 0.0;
        }
        self.gap_budget_exceeded = false;
        if !(standby || active) || n < 2 {
            return;
        }
        let mut anchor = 0;
        if self.cfg.rail_is_ring {
            let total: f64 = (0..n).map(|k| self.eff_gap(k)).sum();
            if total > self.cfg.rail_length {
                self.gap_budget_exceeded = true;
                return;
            }
            for k in 1..n {
                let (a, b) = (&self.members[k], &self.members[anchor]);
                if a.gap > b.gap || (a.gap == b.gap && a.ident < b.ident) {
                    anchor = k;
                }
            }
        }
        let mut delta = 0.0;
        for i in 1..n {
            let k = (anchor + i) % n;
            let d = (delta + self.eff_gap(k) - self.members[k].gap).max(0.0);
            let applies = match self.members[k].job {
                Job::Idle => standby,
                Job::Position { req, .. } => active && req.mode != GapControlMode::None,
                Job::Brake { .. } | Job::Gear { .. } => false,
            };
            self.members[k].retreat = if applies { d } else { 0.0 };
            delta = d;
        }
    }

    fn status(&self, axes: &[Axis]) -> GroupReadStatus {
        use GroupState::*;
        GroupReadStatus {
            group_moving: self.state == GroupMoving,
            group_homing: false,
            group_error_stop: self.state == GroupErrorStop,
            group_not_ready: self.state == GroupNotReady,
            group_standby: self.state == GroupStandby,
            group_stopping: self.state == GroupStopping,
            group_disabled: matches!(self.state, GroupDisabled | GroupErrorDisabled),
            all_axes_standing: self.all_standing(axes),
            in_position: false,
        }
    }
}

/// A member axis ready for a CA group: closed control loop.
fn loop_closed(a: &Axis) -> bool {
    a.controller_on && a.status
}

impl CaGroups {
    /// Adds a configured group (startup; §3.1 validation).
    pub fn add_group(&mut self, name: String, cfg: CaGroupConfig) -> Result<(), Rejection> {
        if name.is_empty() || self.by_name.contains_key(&name) {
            return Err(rej(
                ErrorId::VALUE_OUT_OF_RANGE,
                format!("CA group name '{name}' is empty or configured twice"),
            ));
        }
        cfg.validate(&name)?;
        self.by_name.insert(name.clone(), self.groups.len());
        self.groups.push(CaGroup::new(name, cfg));
        Ok(())
    }

    fn group_index(&self, name: &str) -> Result<usize, Rejection> {
        self.by_name
            .get(name)
            .copied()
            .ok_or_else(|| Rejection::unknown_object("CA group", name))
    }

    /// Refuses a plain single-axis motion command on axis `ax` when the axis is a member of a
    /// group that is not Disabled/ErrorDisabled (§4.2). Which commands are motion commands is
    /// the caller's (the engine's) knowledge.
    pub fn screen_single_axis_motion(&self, ax: usize) -> Result<(), Rejection> {
        match self.axis_group.get(&ax) {
            Some(&g) if self.groups[g].enabled() => Err(rej(
                err::NOT_ALLOWED_IN_GROUP_STATE,
                format!(
                    "axis is a member of the enabled CA group '{}': single-axis motion not allowed",
                    self.groups[g].name
                ),
            )),
            _ => Ok(()),
        }
    }

    /// Outputs of a CA block instance.
    pub fn outputs(&self, id: CmdId) -> Option<ExecuteOutputs> {
        self.instances.get(&id).map(|i| {
            let mut o = ExecuteOutputs::from(i.state);
            if i.kind == CaFbKind::GroupStop && i.state == CommandState::Done && i.execute {
                o.busy = true;
                o.active = true;
            }
            o
        })
    }

    /// The published state of every group.
    pub fn snapshot(&self, axes: &[Axis]) -> Vec<CaGroupStatus> {
        self.groups
            .iter()
            .map(|g| CaGroupStatus {
                name: g.name.clone(),
                state: g.state,
                is_enable_requested: g.enable_requested,
                all_axes_standing: g.all_standing(axes),
                in_position: false,
                group_error_id: g.error_id.0,
                group_axes_count: g.n() as u32,
                act_override_factor: g.ovr_actual,
                gap_budget_exceeded: g.gap_budget_exceeded,
                axes: (0..g.n())
                    .map(|k| {
                        let m = &g.members[k];
                        let a = &axes[m.axis];
                        let target = g.eff_gap(k);
                        CaAxisStatus {
                            name: str::to_owned(&a.name),
                            ident_in_group: m.ident,
                            predecessor: g.pred(k).map(|p| str::to_owned(&axes[g.members[p].axis].name)),
                            position: a.set.pos,
                            modulo_position: if g.cfg.rail_is_ring {
                                a.set.pos.rem_euclid(g.cfg.rail_length)
                            } else {
                                a.set.pos
                            },
                            velocity: a.set.vel,
                            acceleration: a.set.acc,
                            active_command_id: m.job.owner(),
                            command_kind: self.command_kind(g, m),
                            gap_target: target,
                            gap_actual: g.gap_measured(k, axes),
                            ca_limited: m.ca_limited,
                            gap_violation: g.gap_measured(k, axes) < target - EPS,
                            min_gap_margin: m.min_margin,
                            track_id: m.track,
                            compensation_id: m.compensation,
                            start_sync: matches!(m.job, Job::Gear { gear, .. } if gear.started && !gear.in_sync),
                            in_sync: matches!(m.job, Job::Gear { gear, .. } if gear.in_sync),
                        }
                    })
                    .collect(),
            })
            .collect()
    }

    /// What member `m` of group `g` is doing (§9.5 `command_kind`): the block of its active
    /// command; a job without an instance is group braking (halt, stop, error) or a
    /// cancelled goal's MC_HaltCA; an idle axis may be in standby gap control.
    fn command_kind(&self, g: &CaGroup, m: &Member) -> CaCommandKind {
        use CaCommandKind as K;
        if m.job == Job::Idle {
            return if m.retreat > ESTABLISH_MIN {
                K::StandbyGapControl
            } else {
                K::None
            };
        }
        match m.job.owner().and_then(|id| self.instances.get(&id)) {
            Some(i) => match i.kind {
                CaFbKind::MoveAbsolute => K::MoveAbsolute,
                CaFbKind::MoveRelative => K::MoveRelative,
                CaFbKind::Halt => K::Halt,
                CaFbKind::GearInPos => K::GearInPos,
                CaFbKind::GroupHalt => K::GroupHalt,
                CaFbKind::GroupStop => K::GroupStop,
                CaFbKind::Admin => K::None,
            },
            None if g.stop.is_some() => K::GroupStop,
            None if g.halt.is_some() => K::GroupHalt,
            None if g.state == GroupState::GroupErrorStop => K::ErrorStop,
            None => K::Halt,
        }
    }

    /// StartSync / InSync of a running MC_GearInPosCA instance (None: not a running coupling).
    pub fn gear_outputs(&self, id: CmdId) -> Option<GearOutputs> {
        self.groups
            .iter()
            .flat_map(|g| g.members.iter())
            .find_map(|m| match m.job {
                Job::Gear { req, gear } if req.owner == Some(id) => Some(GearOutputs {
                    start_sync: gear.started && !gear.in_sync,
                    in_sync: gear.in_sync,
                }),
                _ => None,
            })
    }

    /// The single-axis view of a member of an enabled group (its set values come from CA, not
    /// from a single-axis job): DiscreteMotion while a CA move/halt runs (or the axis moves),
    /// SynchronizedMotion while coupled by MC_GearInPosCA, HasJob set accordingly. Error and
    /// disabled states of the axis are left as they are.
    pub fn patch_status(&self, ax: usize, st: &mut single_axis::status::AxisStatus) {
        use single_axis::state::MotionState;
        use single_axis::status::bits;
        let Some(&g) = self.axis_group.get(&ax) else {
            return;
        };
        let gr = &self.groups[g];
        if !gr.enabled() || st.motion_state != MotionState::Standstill {
            return;
        }
        let Some(m) = gr.members.iter().find(|m| m.axis == ax) else {
            return;
        };
        let moving = st.set_velo != 0.0 || st.set_acc != 0.0;
        let state = match m.job {
            Job::Gear { .. } => MotionState::SynchronizedMotion,
            Job::Position { .. } | Job::Brake { .. } => MotionState::DiscreteMotion,
            Job::Idle if moving || m.retreat > ESTABLISH_MIN => MotionState::DiscreteMotion,
            Job::Idle => return,
        };
        st.motion_state = state;
        st.state_dword |= bits::HAS_JOB;
        st.state_dword &= !bits::NOT_MOVING;
    }

    /// True when `id` is a CA block instance.
    pub fn owns(&self, id: CmdId) -> bool {
        self.instances.contains_key(&id)
    }

    /// A cancelled goal (§9.3): MC_HaltCA on that axis with the command's deceleration and
    /// jerk; the command ends CommandAborted. A buffered command is just aborted; group
    /// blocks are left alone (their own semantics apply).
    pub fn cancel(
        &mut self,
        id: CmdId,
        axes: &[Axis],
        fbs: &mut Handshake,
    ) -> Result<(), Rejection> {
        for g in 0..self.groups.len() {
            for k in 0..self.groups[g].n() {
                let m = &mut self.groups[g].members[k];
                if m.pending.is_some_and(|p| p.owner == Some(id)) {
                    m.pending = None;
                    self.set_state(fbs, id, CommandState::Aborted);
                    return Ok(());
                }
                if m.job.owner() == Some(id) {
                    let Some(req) = m.job.req().copied() else {
                        return Ok(());
                    };
                    let moving = axes[m.axis].moving();
                    if req.mode != GapControlMode::None {
                        m.last_gap = req.gap;
                    }
                    m.job = if moving {
                        Job::Brake {
                            req: Request {
                                owner: None,
                                goal: Goal::Brake,
                                ..req
                            },
                        }
                    } else {
                        Job::Idle
                    };
                    self.set_state(fbs, id, CommandState::Aborted);
                    return Ok(());
                }
            }
        }
        Ok(())
    }

    // ------------------------------------------------------------------ instances

    fn admit(&mut self, fbs: &mut Handshake, kind: CaFbKind, state: CommandState) -> CmdId {
        // Bounded table: finished instances are dropped once it grows large (as the
        // single-axis handshake does).
        if self.instances.len() > PRUNE_ABOVE {
            self.instances.retain(|_, i| !i.state.is_final());
        }
        let id = fbs.untracked_id();
        self.instances.insert(
            id,
            Instance {
                kind,
                state,
                execute: true,
            },
        );
        // The admission is an output change too (Busy, or Active when in control at once),
        // shown on ~/command_status like the single-axis handshake's (issue 15 item 6).
        fbs.events.push(CommandEvent { id, state });
        id
    }

    fn set_state(&mut self, fbs: &mut Handshake, id: CmdId, state: CommandState) {
        if let Some(i) = self.instances.get_mut(&id) {
            if i.state.is_final() || i.state == state {
                return;
            }
            i.state = state;
            fbs.events.push(CommandEvent { id, state });
        }
    }

    fn admin_reply(&mut self, fbs: &mut Handshake) -> CaReply {
        let id = self.admit(fbs, CaFbKind::Admin, CommandState::Active);
        self.instant_done.push(id);
        CaReply {
            id,
            value: None,
            tracked: true,
        }
    }

    fn value_reply(fbs: &mut Handshake, v: CaValue) -> CaReply {
        CaReply {
            id: fbs.untracked_id(),
            value: Some(v),
            tracked: false,
        }
    }

    /// Ends the active and the buffered request of member `k` (`how`: Aborted or Error).
    fn end_member(&mut self, fbs: &mut Handshake, g: usize, k: usize, how: CommandState) {
        let m = &mut self.groups[g].members[k];
        let owner = m.job.owner();
        let pend = m.pending.take().and_then(|p| p.owner);
        if let Some(r) = m.job.req() {
            if r.mode != GapControlMode::None {
                m.last_gap = r.gap;
            }
        }
        m.job = Job::Idle;
        for id in [owner, pend].into_iter().flatten() {
            self.set_state(fbs, id, how);
        }
    }

    fn end_group_blocks(&mut self, fbs: &mut Handshake, g: usize, how: CommandState) {
        if let Some(id) = self.groups[g].halt.take() {
            self.set_state(fbs, id, how);
        }
        if let Some(id) = self.groups[g].stop.take() {
            if let Some(i) = self.instances.get_mut(&id) {
                i.execute = false;
            }
            self.set_state(fbs, id, how);
        }
        self.groups[g].stop_done = false;
    }
}
