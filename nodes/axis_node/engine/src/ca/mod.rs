//! Collision-avoidance (CA) groups (collision_avoidance.md, TF5410 model).
//!
//! A [`CaGroup`] bundles axes of the [`crate::AxisEngine`] that share one rail; every axis keeps
//! at least its gap to the axis in front. While a group is enabled it owns the set values of its
//! members: `CaGroups::step` runs before the single-axis step (which then only derives actual
//! values and monitoring). Submodules: [`types`] (config, commands, state), [`planner`] (§8),
//! [`modulo`] (§5.2.3).

pub mod bench;
pub mod geometry;
pub mod modulo;
pub mod planner;
pub mod types;

use crate::axis::Axis;
use crate::command::{AxisCommand, AxisReply, ReplyValue};
use crate::handshake::Handshake;
use motion_core::{CmdId, CommandEvent, CommandState, ErrorId, ExecuteOutputs, Rejection, State1};
use planner::{stop_point, stop_point_back, Bound, Kin, StepIn};
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

/// MC3 dynamics of one axis (§3.2), derived from its [`crate::AxisConfig`]: maxima =
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
}

/// The active job of a member.
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

/// State of an MC_GearInPosCA coupling (§5.5).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Gear {
    master: usize,
    ratio: f64,
    msp: f64,
    ssp: f64,
    strategy: SyncStrategy,
    started: bool,
    in_sync: bool,
    failed: bool,
    cam: Option<Cam>,
    /// Coupled target at the end of the current cycle \[mm\].
    target: f64,
}

/// Quintic cam `s(m)` over the master position (§5.5.3 Late/Slow): from the slave's state at
/// `m0` to (MasterSyncPosition, SlaveSyncPosition, ratio, 0).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Cam {
    m0: f64,
    h: f64,
    c: [f64; 6],
}

impl Cam {
    fn new(m0: f64, s: State1, mv: f64, msp: f64, ssp: f64, r: f64) -> Option<Cam> {
        let h = msp - m0;
        if !(h > 1e-9 && mv > 0.0) {
            return None;
        }
        let (c0, c1, c2) = (s.pos, s.vel / mv, s.acc / (mv * mv) / 2.0);
        let d0 = ssp - (c0 + c1 * h + c2 * h * h);
        let d1 = r - (c1 + 2.0 * c2 * h);
        let d2 = -2.0 * c2;
        let c3 = (20.0 * d0 - 8.0 * d1 * h + d2 * h * h) / (2.0 * h.powi(3));
        let c4 = (-30.0 * d0 + 14.0 * d1 * h - 2.0 * d2 * h * h) / (2.0 * h.powi(4));
        let c5 = (12.0 * d0 - 6.0 * d1 * h + d2 * h * h) / (2.0 * h.powi(5));
        Some(Cam {
            m0,
            h,
            c: [c0, c1, c2, c3, c4, c5],
        })
    }

    /// s, ds/dm, d²s/dm² at master position `m`.
    fn eval(&self, m: f64) -> (f64, f64, f64) {
        let u = (m - self.m0).clamp(0.0, self.h);
        let c = &self.c;
        let p = c[0] + u * (c[1] + u * (c[2] + u * (c[3] + u * (c[4] + u * c[5]))));
        let d1 = c[1] + u * (2.0 * c[2] + u * (3.0 * c[3] + u * (4.0 * c[4] + u * 5.0 * c[5])));
        let d2 = 2.0 * c[2] + u * (6.0 * c[3] + u * (12.0 * c[4] + u * 20.0 * c[5]));
        (p, d1, d2)
    }

    /// Within the sync dynamics at a constant master velocity `mv` (33 samples).
    fn feasible(&self, mv: f64, dy: &Dyn) -> bool {
        let c = &self.c;
        let tol = 1.0 + 1e-9;
        (0..=32).all(|i| {
            let u = self.h * i as f64 / 32.0;
            let (_, d1, d2) = self.eval(self.m0 + u);
            let d3 = 6.0 * c[3] + u * (24.0 * c[4] + u * 60.0 * c[5]);
            let (v, a, j) = (d1 * mv, d2 * mv * mv, d3 * mv * mv * mv);
            v.abs() <= dy.v * tol && a <= dy.a * tol && -a <= dy.d * tol && j.abs() <= dy.j * tol
        })
    }
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

    /// True when a plain single-axis motion command on axis `ax` must be refused (§4.2: member
    /// of a group that is not Disabled/ErrorDisabled).
    pub(crate) fn screen_single_axis(&self, ax: usize, cmd: &AxisCommand) -> Result<(), Rejection> {
        use AxisCommand as C;
        let motion = matches!(
            cmd,
            C::MoveAbsolute(_)
                | C::MoveRelative(_)
                | C::MoveAdditive(_)
                | C::MoveModulo(_)
                | C::MoveVelocity(_)
                | C::MoveContinuousAbsolute(_)
                | C::MoveContinuousRelative(_)
                | C::Halt(_)
                | C::Stop(_)
                | C::SetPosition(_)
                | C::Home(_)
                | C::Jog(_)
                | C::GearIn(_)
                | C::GearInDyn(_)
                | C::TorqueControl(_)
                | C::MoveSuperImposed(_)
        );
        match self.axis_group.get(&ax) {
            Some(&g) if motion && self.groups[g].enabled() => Err(rej(
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
    pub(crate) fn snapshot(&self, axes: &[Axis]) -> Vec<CaGroupStatus> {
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
                            name: a.name.clone(),
                            ident_in_group: m.ident,
                            predecessor: g.pred(k).map(|p| axes[g.members[p].axis].name.clone()),
                            position: a.set.pos,
                            modulo_position: if g.cfg.rail_is_ring {
                                a.set.pos.rem_euclid(g.cfg.rail_length)
                            } else {
                                a.set.pos
                            },
                            velocity: a.set.vel,
                            acceleration: a.set.acc,
                            active_command_id: m.job.owner(),
                            gap_target: target,
                            gap_actual: m.gap,
                            ca_limited: m.ca_limited,
                            gap_violation: m.gap < target - EPS,
                            min_gap_margin: m.min_margin,
                            track_id: m.track,
                            compensation_id: m.compensation,
                        }
                    })
                    .collect(),
            })
            .collect()
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

    /// True when `id` is a CA block instance.
    pub(crate) fn owns(&self, id: CmdId) -> bool {
        self.instances.contains_key(&id)
    }

    /// A cancelled goal (§9.3): MC_HaltCA on that axis with the command's deceleration and
    /// jerk; the command ends CommandAborted. A buffered command is just aborted; group
    /// blocks are left alone (their own semantics apply).
    pub(crate) fn cancel(
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

    fn admin_reply(&mut self, fbs: &mut Handshake) -> AxisReply {
        let id = self.admit(fbs, CaFbKind::Admin, CommandState::Active);
        self.instant_done.push(id);
        AxisReply {
            id,
            value: ReplyValue::None,
            tracked: true,
        }
    }

    fn value_reply(fbs: &mut Handshake, v: CaValue) -> AxisReply {
        AxisReply {
            id: fbs.untracked_id(),
            value: ReplyValue::Ca(Box::new(v)),
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

    // ------------------------------------------------------------------ commands

    /// One CA block call.
    pub(crate) fn command(
        &mut self,
        cmd: CaCommand,
        axes: &mut [Axis],
        index: &HashMap<String, usize>,
        fbs: &mut Handshake,
    ) -> Result<AxisReply, Rejection> {
        match cmd {
            CaCommand::AddAxisToGroup {
                group,
                axis,
                ident_in_group,
            } => self.add_axis(&group, &axis, ident_in_group, axes, index, fbs),
            CaCommand::RemoveAxisFromGroup {
                group,
                ident_in_group,
            } => {
                let g = self.group_index(&group)?;
                self.not_stopping(g, "MC_RemoveAxisFromGroup")?;
                if let Some(k) = self.groups[g]
                    .members
                    .iter()
                    .position(|m| m.ident == ident_in_group.0)
                {
                    let ax = self.groups[g].members[k].axis;
                    if axes[ax].moving() {
                        return Err(rej(
                            err::AXIS_MOVING,
                            format!("MC_RemoveAxisFromGroup: axis '{}' is moving", axes[ax].name),
                        ));
                    }
                    self.remove_member(g, k, axes, fbs);
                }
                Ok(self.admin_reply(fbs))
            }
            CaCommand::UngroupAllAxes { group } => {
                let g = self.group_index(&group)?;
                self.disable(g, axes, fbs);
                while self.groups[g].n() > 0 {
                    let k = self.groups[g].n() - 1;
                    self.remove_member(g, k, axes, fbs);
                }
                Ok(self.admin_reply(fbs))
            }
            CaCommand::GroupEnable { group } => {
                let g = self.group_index(&group)?;
                use GroupState::*;
                match self.groups[g].state {
                    GroupErrorStop | GroupErrorDisabled => {
                        return Err(rej(
                            err::NOT_ALLOWED_IN_GROUP_STATE,
                            format!("MC_GroupEnable: group '{group}' is in an error state"),
                        ))
                    }
                    GroupDisabled => {
                        if self.groups[g].n() == 0 {
                            return Err(rej(
                                err::GROUP_EMPTY,
                                format!("MC_GroupEnable: group '{group}' has no axes"),
                            ));
                        }
                        let gr = &mut self.groups[g];
                        for m in &gr.members {
                            let a = &mut axes[m.axis];
                            a.abort_motion(fbs);
                            a.job = None;
                        }
                        gr.init_all_gaps(axes);
                        for m in &mut gr.members {
                            m.min_margin = f64::INFINITY;
                        }
                        gr.enable_requested = true;
                        let ready = gr.members.iter().all(|m| loop_closed(&axes[m.axis]));
                        gr.state = if ready { GroupStandby } else { GroupNotReady };
                    }
                    _ => {}
                }
                Ok(self.admin_reply(fbs))
            }
            CaCommand::GroupDisable { group } => {
                let g = self.group_index(&group)?;
                self.disable(g, axes, fbs);
                Ok(self.admin_reply(fbs))
            }
            CaCommand::GroupReset { group } => {
                let g = self.group_index(&group)?;
                let gr = &mut self.groups[g];
                let to = match gr.state {
                    GroupState::GroupErrorStop => Some(GroupState::GroupStandby),
                    GroupState::GroupErrorDisabled => Some(GroupState::GroupDisabled),
                    _ => None,
                };
                if let Some(to) = to {
                    gr.state = to;
                    gr.error_id = ErrorId::NONE;
                    for m in &gr.members {
                        let a = &mut axes[m.axis];
                        if !a.error_id.is_none() {
                            a.error_id = ErrorId::NONE;
                            if a.drive_fault {
                                a.drive_fault = false;
                                a.status_pending = a.controller_on;
                            }
                        }
                    }
                }
                Ok(self.admin_reply(fbs))
            }
            CaCommand::GroupReadStatus { group } => {
                let g = self.group_index(&group)?;
                let s = self.groups[g].status(axes);
                Ok(Self::value_reply(fbs, CaValue::Status(s)))
            }
            CaCommand::GroupReadError { group } => {
                let g = self.group_index(&group)?;
                let e = self.groups[g].error_id.0;
                Ok(Self::value_reply(fbs, CaValue::GroupErrorId(e)))
            }
            CaCommand::GroupSetOverride {
                group,
                enable,
                vel_factor,
            } => {
                let g = self.group_index(&group)?;
                let f = finite_or(
                    vel_factor,
                    err::PARAMETER_NOT_CORRECT,
                    "MC_GroupSetOverride.VelFactor",
                )?;
                let gr = &mut self.groups[g];
                if enable {
                    let f = f.clamp(0.0, 1.0);
                    gr.ovr_target = f;
                    gr.ovr_rate = if gr.cfg.override_ramp_time > 0.0 {
                        (f - gr.ovr_actual).abs() / gr.cfg.override_ramp_time
                    } else {
                        f64::INFINITY
                    };
                }
                let v = CaValue::Override {
                    enabled: enable,
                    actual_vel_factor: gr.ovr_actual,
                };
                Ok(Self::value_reply(fbs, v))
            }
            CaCommand::GroupHalt {
                group,
                deceleration,
                jerk,
            } => self.group_halt(&group, deceleration, jerk, false, axes, fbs),
            CaCommand::GroupStop {
                group,
                execute,
                deceleration,
                jerk,
            } => {
                if execute {
                    self.group_halt(&group, deceleration, jerk, true, axes, fbs)
                } else {
                    let g = self.group_index(&group)?;
                    if let Some(id) = self.groups[g].stop {
                        if let Some(i) = self.instances.get_mut(&id) {
                            i.execute = false;
                        }
                    }
                    Ok(Self::value_reply(
                        fbs,
                        CaValue::Status(self.groups[g].status(axes)),
                    ))
                }
            }
            CaCommand::MoveAbsolute(c) => {
                let (g, k) = self.member_of(&c.axis, index)?;
                self.motion_admissible(g, k, axes, "MC_MoveAbsoluteCA")?;
                let ad = self.groups[g].members[k].dynamics;
                let dy = resolve_move(&ad, c.velocity, c.acceleration, c.deceleration, c.jerk)?;
                let gap = self.resolve_gap(g, c.gap)?;
                let p = match c.position {
                    McLreal::Value(p) if p.is_finite() => p,
                    other => {
                        return Err(rej(
                            err::INVALID_TARGET_POSITION,
                            format!("MC_MoveAbsoluteCA.Position = {other:?} is not a valid target"),
                        ))
                    }
                };
                let cfg = &self.groups[g].cfg;
                // An active track: Position is a track coordinate (§5.6).
                let p = match cfg.geometry.track(self.groups[g].members[k].track) {
                    None => p,
                    Some(t) => {
                        let origin = cfg.geometry.part(t.parts[0]).map_or(0.0, |q| q.start);
                        if c.direction == CaDirection::NonModulo {
                            p + origin
                        } else if (0.0..=cfg.rail_length).contains(&p) {
                            (p + origin).rem_euclid(cfg.rail_length)
                        } else {
                            return Err(rej(
                                err::INVALID_TARGET_POSITION,
                                format!("modulo track target {p} outside [0, {}]", cfg.rail_length),
                            ));
                        }
                    }
                };
                let x0 = axes[self.groups[g].members[k].axis].set.pos;
                let target = modulo::target(
                    x0,
                    cfg.rail_length,
                    axes[self.groups[g].members[k].axis]
                        .cfg
                        .modulo_tolerance_window,
                    p,
                    c.direction,
                    c.additional_turns,
                    cfg.rail_is_ring,
                )?;
                let req = Request {
                    owner: None,
                    goal: Goal::Absolute(target),
                    dy,
                    gap,
                    mode: c.gap_control_mode,
                    continuous_update: c.continuous_update,
                };
                self.start(g, k, req, c.buffer_mode, CaFbKind::MoveAbsolute, axes, fbs)
            }
            CaCommand::MoveRelative(c) => {
                let (g, k) = self.member_of(&c.axis, index)?;
                self.motion_admissible(g, k, axes, "MC_MoveRelativeCA")?;
                let ad = self.groups[g].members[k].dynamics;
                let dy = resolve_move(&ad, c.velocity, c.acceleration, c.deceleration, c.jerk)?;
                let gap = self.resolve_gap(g, c.gap)?;
                let d = match c.distance {
                    McLreal::Value(d) if d.is_finite() => d,
                    other => {
                        return Err(rej(
                            err::INVALID_TARGET_POSITION,
                            format!("MC_MoveRelativeCA.Distance = {other:?} is not valid"),
                        ))
                    }
                };
                let req = Request {
                    owner: None,
                    goal: Goal::Relative(d),
                    dy,
                    gap,
                    mode: c.gap_control_mode,
                    continuous_update: c.continuous_update,
                };
                self.start(g, k, req, c.buffer_mode, CaFbKind::MoveRelative, axes, fbs)
            }
            CaCommand::Halt(c) => {
                let (g, k) = self.member_of(&c.axis, index)?;
                self.motion_admissible(g, k, axes, "MC_HaltCA")?;
                let ad = self.groups[g].members[k].dynamics;
                let d = resolve_acc(c.deceleration, ad.def_d, ad.max_d, "Deceleration")?;
                let j = resolve_jerk(c.jerk, ad.def_j, ad.max_j, false)?;
                let gap = self.resolve_gap(g, c.gap)?;
                let req = Request {
                    owner: None,
                    goal: Goal::Brake,
                    dy: Dyn {
                        v: ad.max_v,
                        a: ad.max_a,
                        d,
                        j,
                    },
                    gap,
                    mode: c.gap_control_mode,
                    continuous_update: false,
                };
                self.start(g, k, req, CaBufferMode::Aborting, CaFbKind::Halt, axes, fbs)
            }
            CaCommand::GearInPos(c) => {
                let fb = "MC_GearInPosCA";
                let (g, k) = self.member_of(&c.slave, index)?;
                self.motion_admissible(g, k, axes, fb)?;
                let master = *index.get(&c.master).ok_or_else(|| {
                    rej(
                        err::AXIS_NOT_IN_GROUP,
                        format!("{fb}: unknown master '{}'", c.master),
                    )
                })?;
                if master == self.groups[g].members[k].axis {
                    return Err(rej(
                        err::PARAMETER_NOT_CORRECT,
                        format!("{fb}: Master = Slave"),
                    ));
                }
                let pos = |x: McLreal, what: &str| match x {
                    McLreal::Value(v) if v.is_finite() => Ok(v),
                    other => Err(rej(
                        err::INVALID_TARGET_POSITION,
                        format!("{fb}.{what} = {other:?}"),
                    )),
                };
                let msp = pos(c.master_sync_position, "MasterSyncPosition")?;
                let ssp = pos(c.slave_sync_position, "SlaveSyncPosition")?;
                let num = match c.ratio_numerator {
                    McLreal::Unset | McLreal::Default => 1.0,
                    McLreal::Value(v) if v.is_finite() => v,
                    other => {
                        return Err(rej(
                            err::PARAMETER_NOT_CORRECT,
                            format!("{fb}.RatioNumerator = {other:?}"),
                        ))
                    }
                };
                if c.ratio_denumerator == 0 {
                    return Err(rej(
                        err::PARAMETER_NOT_CORRECT,
                        format!("{fb}.RatioDenumerator = 0"),
                    ));
                }
                let ad = self.groups[g].members[k].dynamics;
                let dy = resolve_move(&ad, c.velocity, c.acceleration, c.deceleration, c.jerk)?;
                let gap = self.resolve_gap(g, c.gap)?;
                let gear = Gear {
                    master,
                    ratio: num / c.ratio_denumerator as f64,
                    msp,
                    ssp,
                    strategy: c.sync_strategy,
                    started: false,
                    in_sync: false,
                    failed: false,
                    cam: None,
                    target: axes[self.groups[g].members[k].axis].set.pos,
                };
                let req = Request {
                    owner: None,
                    goal: Goal::Gear(gear),
                    dy,
                    gap,
                    mode: c.gap_control_mode,
                    continuous_update: c.continuous_update,
                };
                self.start(g, k, req, c.buffer_mode, CaFbKind::GearInPos, axes, fbs)
            }
            CaCommand::UpdateGap { axis, gap } => {
                let (g, k) = self.member_of(&axis, index)?;
                let gap = self.resolve_gap(g, gap)?;
                let m = &mut self.groups[g].members[k];
                match &mut m.job {
                    Job::Position { req, .. } | Job::Brake { req } | Job::Gear { req, .. }
                        if req.continuous_update =>
                    {
                        req.gap = gap;
                        Ok(Self::value_reply(fbs, CaValue::GroupErrorId(0)))
                    }
                    _ => Err(rej(
                        err::CONTINUOUS_UPDATE_NOT_ENABLED,
                        format!(
                            "update_gap: axis '{axis}' has no active command with ContinuousUpdate"
                        ),
                    )),
                }
            }
            CaCommand::ActivateTrack { axis, track_id } => {
                let (g, k) = self.member_of(&axis, index)?;
                let gr = &self.groups[g];
                if track_id != 0 {
                    let geo = &gr.cfg.geometry;
                    let t = geo.track(track_id).ok_or_else(|| {
                        rej(
                            err::TRACK_ERROR,
                            format!("MC_ActivateTrack: unknown track {track_id:#x}"),
                        )
                    })?;
                    let x = axes[gr.members[k].axis].set.pos;
                    let on = geo
                        .part_at(x, gr.cfg.rail_length, gr.cfg.rail_is_ring)
                        .is_some_and(|p| t.parts.contains(&p.oid));
                    if !on {
                        return Err(rej(
                            err::TRACK_ERROR,
                            format!("MC_ActivateTrack: axis '{axis}' is not on a part of track {track_id:#x}"),
                        ));
                    }
                }
                self.groups[g].members[k].track = track_id;
                Ok(self.admin_reply(fbs))
            }
            CaCommand::ReadTrackPositions { axis } => {
                let (g, k) = self.member_of(&axis, index)?;
                let gr = &self.groups[g];
                let (l, ring) = (gr.cfg.rail_length, gr.cfg.rail_is_ring);
                let geo = &gr.cfg.geometry;
                let x = axes[gr.members[k].axis].set.pos;
                let wrap = |d: f64| if ring { d.rem_euclid(l) } else { d };
                let v = match geo.track(gr.members[k].track) {
                    None => CaValue::TrackPositions {
                        valid: true,
                        track_position: x,
                        track_id: 0,
                        part_position: x,
                        part_id: 0,
                    },
                    Some(t) => {
                        let origin = geo.part(t.parts[0]).map_or(0.0, |q| q.start);
                        let part = geo.part_at(x, l, ring);
                        CaValue::TrackPositions {
                            valid: true,
                            track_position: wrap(x - origin),
                            track_id: t.oid,
                            part_position: part.map_or(f64::NAN, |p| wrap(x - p.start)),
                            part_id: part.map_or(0, |p| p.oid),
                        }
                    }
                };
                Ok(Self::value_reply(fbs, v))
            }
            CaCommand::RegisterCompensation {
                axis,
                compensation_type,
                compensation_id,
            } => {
                let (g, k) = self.member_of(&axis, index)?;
                if compensation_type != 1 {
                    return Err(rej(
                        err::INVALID_MODE,
                        format!("MC_RegisterCompensation: CompensationType = {compensation_type} is not geo (1)"),
                    ));
                }
                if compensation_id != 0 {
                    self.groups[g].cfg.geometry.y_shift(compensation_id)?;
                }
                self.groups[g].members[k].compensation = compensation_id;
                Ok(self.admin_reply(fbs))
            }
            CaCommand::TransformPosition {
                group,
                origin_oid,
                destination_oid,
                origin_position,
            } => {
                let g = self.group_index(&group)?;
                let x = match origin_position {
                    McLreal::Value(x) if x.is_finite() => x,
                    other => {
                        return Err(rej(
                            err::INVALID_TARGET_POSITION,
                            format!("MC_TransformPosition.OriginPosition = {other:?}"),
                        ))
                    }
                };
                let cfg = &self.groups[g].cfg;
                let y = cfg
                    .geometry
                    .transform(cfg.rail_length, origin_oid, destination_oid, x)?;
                Ok(Self::value_reply(fbs, CaValue::Position(y)))
            }
            CaCommand::SetTemplateActive { group, oid, active } => {
                let g = self.group_index(&group)?;
                let t = self.groups[g]
                    .cfg
                    .geometry
                    .mover_templates
                    .iter_mut()
                    .find(|t| t.oid == oid)
                    .ok_or_else(|| {
                        rej(
                            err::COMPENSATION_ERROR,
                            format!("unknown mover template {oid:#x}"),
                        )
                    })?;
                t.active = active;
                Ok(self.admin_reply(fbs))
            }
            CaCommand::ResetDiagnostics { group } => {
                let g = self.group_index(&group)?;
                for m in &mut self.groups[g].members {
                    m.min_margin = f64::INFINITY;
                }
                Ok(self.admin_reply(fbs))
            }
        }
    }

    fn not_stopping(&self, g: usize, fb: &str) -> Result<(), Rejection> {
        if self.groups[g].state == GroupState::GroupStopping {
            Err(rej(
                err::NOT_ALLOWED_IN_GROUP_STATE,
                format!("{fb}: group '{}' is Stopping", self.groups[g].name),
            ))
        } else {
            Ok(())
        }
    }

    fn member_of(
        &self,
        axis: &str,
        index: &HashMap<String, usize>,
    ) -> Result<(usize, usize), Rejection> {
        let not_in = || {
            rej(
                err::AXIS_NOT_IN_GROUP,
                format!("axis '{axis}' is not in a CA group"),
            )
        };
        let ax = *index.get(axis).ok_or_else(not_in)?;
        let g = *self.axis_group.get(&ax).ok_or_else(not_in)?;
        let k = self.groups[g]
            .members
            .iter()
            .position(|m| m.axis == ax)
            .ok_or_else(not_in)?;
        Ok((g, k))
    }

    fn motion_admissible(
        &self,
        g: usize,
        k: usize,
        axes: &[Axis],
        fb: &str,
    ) -> Result<(), Rejection> {
        let gr = &self.groups[g];
        if !matches!(gr.state, GroupState::GroupStandby | GroupState::GroupMoving) {
            return Err(rej(
                err::NOT_ALLOWED_IN_GROUP_STATE,
                format!("{fb}: group '{}' is {:?}", gr.name, gr.state),
            ));
        }
        let a = &axes[gr.members[k].axis];
        if !(loop_closed(a) && a.enable_positive && a.enable_negative) {
            return Err(rej(
                err::AXIS_NOT_READY,
                format!("{fb}: axis '{}' has no closed loop or feed enables", a.name),
            ));
        }
        Ok(())
    }

    fn resolve_gap(&self, g: usize, gap: McLreal) -> Result<f64, Rejection> {
        let cfg = &self.groups[g].cfg;
        match gap {
            McLreal::Unset | McLreal::Default => Ok(cfg.default_gap),
            McLreal::Value(v)
                if v.is_finite() && v >= 0.0 && !(cfg.rail_is_ring && v >= cfg.rail_length) =>
            {
                Ok(v)
            }
            other => Err(rej(
                err::INVALID_GAP,
                format!("Gap = {other:?} is not valid"),
            )),
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn start(
        &mut self,
        g: usize,
        k: usize,
        mut req: Request,
        mode: CaBufferMode,
        kind: CaFbKind,
        axes: &[Axis],
        fbs: &mut Handshake,
    ) -> Result<AxisReply, Rejection> {
        let m = &self.groups[g].members[k];
        let buffered = mode == CaBufferMode::Buffered && m.job.owner().is_some();
        if buffered && m.pending.is_some() {
            return Err(rej(
                err::BUFFER_FULL,
                "a buffered command is already waiting on this axis",
            ));
        }
        // A new motion command ends a running group halt (not locking, §1.8).
        if let Some(h) = self.groups[g].halt.take() {
            self.set_state(fbs, h, CommandState::Aborted);
        }
        let state = if buffered {
            CommandState::Busy
        } else {
            CommandState::Active
        };
        let id = self.admit(fbs, kind, state);
        req.owner = Some(id);
        if buffered {
            self.groups[g].members[k].pending = Some(req);
        } else {
            self.end_member(fbs, g, k, CommandState::Aborted);
            let x = axes[self.groups[g].members[k].axis].set.pos;
            self.groups[g].members[k].job = activate(req, x);
            if self.groups[g].state == GroupState::GroupStandby {
                self.groups[g].state = GroupState::GroupMoving;
            }
        }
        Ok(AxisReply {
            id,
            value: ReplyValue::None,
            tracked: true,
        })
    }

    fn group_halt(
        &mut self,
        group: &str,
        dec: McLreal,
        jerk: McLreal,
        stop: bool,
        axes: &[Axis],
        fbs: &mut Handshake,
    ) -> Result<AxisReply, Rejection> {
        let g = self.group_index(group)?;
        let fb = if stop { "MC_GroupStop" } else { "MC_GroupHalt" };
        use GroupState::*;
        let st = self.groups[g].state;
        let ok = if stop {
            matches!(st, GroupStandby | GroupMoving | GroupNotReady)
        } else {
            matches!(st, GroupStandby | GroupMoving)
        };
        if !ok {
            return Err(rej(
                err::NOT_ALLOWED_IN_GROUP_STATE,
                format!("{fb}: group '{group}' is {st:?}"),
            ));
        }
        // Validate the markers once (per-axis resolution below cannot fail then).
        match dec {
            McLreal::Value(v) if !(v.is_finite() && v >= 1.0) => {
                return Err(rej(
                    err::INVALID_DYNAMICS,
                    format!("{fb}.Deceleration = {v}"),
                ))
            }
            McLreal::Ignore => {
                return Err(rej(
                    err::INVALID_DYNAMICS,
                    format!("{fb}.Deceleration = IGNORE"),
                ))
            }
            _ => {}
        }
        if let McLreal::Value(v) = jerk {
            if !(v.is_finite() && v >= 100.0) {
                return Err(rej(err::INVALID_DYNAMICS, format!("{fb}.Jerk = {v}")));
            }
        }
        self.end_group_blocks(fbs, g, CommandState::Aborted);
        for k in 0..self.groups[g].n() {
            self.end_member(fbs, g, k, CommandState::Aborted);
            let m = &mut self.groups[g].members[k];
            let ad = m.dynamics;
            let d = resolve_acc(dec, ad.def_d, ad.max_d, "Deceleration").unwrap_or(ad.def_d);
            let j = match jerk {
                McLreal::Ignore => JERK_UNLIMITED,
                McLreal::Maximum => ad.max_j,
                other => resolve_jerk(other, ad.def_j, ad.max_j, false).unwrap_or(ad.def_j),
            };
            if axes[m.axis].moving() {
                m.job = Job::Brake {
                    req: Request {
                        owner: None,
                        goal: Goal::Brake,
                        dy: Dyn {
                            v: ad.max_v,
                            a: ad.max_a,
                            d,
                            j,
                        },
                        gap: m.last_gap,
                        mode: GapControlMode::GroupDefault,
                        continuous_update: false,
                    },
                };
            }
        }
        let kind = if stop {
            CaFbKind::GroupStop
        } else {
            CaFbKind::GroupHalt
        };
        let id = self.admit(fbs, kind, CommandState::Active);
        let gr = &mut self.groups[g];
        if stop {
            gr.stop = Some(id);
            gr.stop_done = false;
            gr.state = GroupStopping;
        } else {
            gr.halt = Some(id);
            if gr.busy() {
                gr.state = GroupMoving;
            }
        }
        Ok(AxisReply {
            id,
            value: ReplyValue::None,
            tracked: true,
        })
    }

    fn add_axis(
        &mut self,
        group: &str,
        axis: &str,
        ident: IdentInGroup,
        axes: &mut [Axis],
        index: &HashMap<String, usize>,
        fbs: &mut Handshake,
    ) -> Result<AxisReply, Rejection> {
        let g = self.group_index(group)?;
        self.not_stopping(g, "MC_AddAxisToGroup")?;
        let ax = *index.get(axis).ok_or_else(|| {
            rej(
                err::AXIS_NOT_IN_GROUP,
                format!("MC_AddAxisToGroup: unknown axis '{axis}'"),
            )
        })?;
        let gr = &self.groups[g];
        if ident.0 == 0 || gr.members.iter().any(|m| m.ident == ident.0) {
            return Err(rej(
                err::INVALID_IDENT_IN_GROUP,
                format!(
                    "MC_AddAxisToGroup: IdentInGroup {} is 0 or already used",
                    ident.0
                ),
            ));
        }
        if let Some(&other) = self.axis_group.get(&ax) {
            return Err(rej(
                err::AXIS_IN_OTHER_GROUP,
                format!(
                    "MC_AddAxisToGroup: axis '{axis}' already belongs to group '{}'",
                    self.groups[other].name
                ),
            ));
        }
        if gr.enabled() && axes[ax].moving() {
            return Err(rej(
                err::AXIS_MOVING,
                format!("MC_AddAxisToGroup: axis '{axis}' is moving"),
            ));
        }
        if gr.enabled() {
            axes[ax].abort_motion(fbs);
            axes[ax].job = None;
        }
        let gr = &mut self.groups[g];
        let key = |x: f64| {
            if gr.cfg.rail_is_ring {
                x.rem_euclid(gr.cfg.rail_length)
            } else {
                x
            }
        };
        let u = key(axes[ax].set.pos);
        // Front first; ties: the new axis goes in front of the tied ones (§1.2).
        let k = gr
            .members
            .iter()
            .position(|m| key(axes[m.axis].set.pos) <= u)
            .unwrap_or(gr.n());
        let ad = AxisDyn::of(&axes[ax]);
        gr.members.insert(
            k,
            Member {
                axis: ax,
                ident: ident.0,
                dynamics: ad,
                gap: f64::NAN,
                job: Job::Idle,
                pending: None,
                last_gap: gr.cfg.default_gap,
                d_ca: ad.def_d,
                j_ca: ad.def_j,
                d_b: ad.def_d,
                j_b: ad.def_j,
                ca_limited: false,
                min_margin: f64::INFINITY,
                updated: false,
                retreat: 0.0,
                track: 0,
                compensation: 0,
            },
        );
        gr.init_all_gaps(axes);
        self.axis_group.insert(ax, g);
        Ok(self.admin_reply(fbs))
    }

    fn remove_member(&mut self, g: usize, k: usize, axes: &mut [Axis], fbs: &mut Handshake) {
        self.end_member(fbs, g, k, CommandState::Aborted);
        let gr = &mut self.groups[g];
        let m = gr.members.remove(k);
        axes[m.axis].set.vel = 0.0;
        axes[m.axis].set.acc = 0.0;
        axes[m.axis].target_pos = axes[m.axis].set.pos;
        self.axis_group.remove(&m.axis);
        gr.init_all_gaps(axes);
        if gr.n() == 0 {
            gr.enable_requested = false;
            gr.state = match gr.state {
                GroupState::GroupErrorStop | GroupState::GroupErrorDisabled => {
                    GroupState::GroupErrorDisabled
                }
                _ => GroupState::GroupDisabled,
            };
        }
    }

    /// MC_GroupDisable (§5.13): instant stop, all commands aborted.
    fn disable(&mut self, g: usize, axes: &mut [Axis], fbs: &mut Handshake) {
        self.end_group_blocks(fbs, g, CommandState::Aborted);
        for k in 0..self.groups[g].n() {
            self.end_member(fbs, g, k, CommandState::Aborted);
            let a = &mut axes[self.groups[g].members[k].axis];
            a.set.vel = 0.0;
            a.set.acc = 0.0;
            a.target_pos = a.set.pos;
        }
        let gr = &mut self.groups[g];
        gr.enable_requested = false;
        gr.state = match gr.state {
            GroupState::GroupErrorStop | GroupState::GroupErrorDisabled => {
                GroupState::GroupErrorDisabled
            }
            _ => GroupState::GroupDisabled,
        };
    }

    // ------------------------------------------------------------------ cycle

    /// One cycle of every group (§8.3). Runs before the single-axis step. No alloc in steady
    /// state (scratch vectors are reused), no lock.
    pub(crate) fn step(&mut self, dt: f64, axes: &mut [Axis], fbs: &mut Handshake) {
        for i in 0..self.instant_done.len() {
            let id = self.instant_done[i];
            self.set_state(fbs, id, CommandState::Done);
        }
        self.instant_done.clear();
        for g in 0..self.groups.len() {
            self.step_group(g, dt, axes, fbs);
        }
    }

    fn raise_group_error(&mut self, g: usize, id: ErrorId, axes: &mut [Axis], fbs: &mut Handshake) {
        let how = CommandState::Error(id);
        self.end_group_blocks(fbs, g, how);
        for k in 0..self.groups[g].n() {
            self.end_member(fbs, g, k, how);
            let m = &mut self.groups[g].members[k];
            let ad = m.dynamics;
            if axes[m.axis].moving() {
                m.job = Job::Brake {
                    req: Request {
                        owner: None,
                        goal: Goal::Brake,
                        dy: Dyn {
                            v: ad.max_v,
                            a: ad.max_a,
                            d: ad.max_d,
                            j: ad.max_j,
                        },
                        gap: m.last_gap,
                        mode: GapControlMode::GroupDefault,
                        continuous_update: false,
                    },
                };
            }
        }
        let gr = &mut self.groups[g];
        gr.error_id = id;
        gr.state = GroupState::GroupErrorStop;
    }

    fn step_group(&mut self, g: usize, dt: f64, axes: &mut [Axis], fbs: &mut Handshake) {
        use GroupState::*;
        // Transitions driven by the axes (T4, T5, T13, T14).
        let axis_error = self.groups[g]
            .members
            .iter()
            .map(|m| axes[m.axis].error_id)
            .find(|e| !e.is_none());
        let all_ready = self.groups[g]
            .members
            .iter()
            .all(|m| loop_closed(&axes[m.axis]));
        match (self.groups[g].state, axis_error) {
            (GroupDisabled, Some(e)) => {
                self.groups[g].error_id = e;
                self.groups[g].state = GroupErrorDisabled;
            }
            (GroupStandby | GroupMoving | GroupStopping | GroupNotReady, Some(e)) => {
                self.raise_group_error(g, e, axes, fbs)
            }
            (GroupNotReady, None) if all_ready && self.groups[g].n() > 0 => {
                self.groups[g].state = GroupStandby
            }
            (GroupStandby | GroupMoving, None) if !all_ready => {
                // T5: the axis without loop freezes (its set values are already 0).
                self.raise_group_error(g, err::AXIS_NOT_READY, axes, fbs)
            }
            _ => {}
        }
        let gr = &mut self.groups[g];
        if !gr.enabled() {
            // Disabled: single-axis control; keep the published gaps current.
            gr.init_all_gaps(axes);
            return;
        }
        // Override ramp (§1.11).
        if gr.ovr_actual != gr.ovr_target {
            let step = gr.ovr_rate * dt;
            gr.ovr_actual = if (gr.ovr_target - gr.ovr_actual).abs() <= step {
                gr.ovr_target
            } else {
                gr.ovr_actual + step * (gr.ovr_target - gr.ovr_actual).signum()
            };
        }
        if gr.state == GroupNotReady {
            return;
        }
        if !matches!(self.groups[g].state, GroupStopping | GroupErrorStop) {
            self.groups[g].plan_establishing();
        } else {
            for m in &mut self.groups[g].members {
                m.retreat = 0.0;
            }
        }
        self.plan_cycle(g, dt, axes);
        self.finish_jobs(g, axes, fbs);
        // Group blocks and T8/T10.
        let standing = self.groups[g].all_standing(axes);
        let busy = self.groups[g].busy();
        if standing {
            if let Some(h) = self.groups[g].halt {
                if !busy {
                    self.groups[g].halt = None;
                    self.set_state(fbs, h, CommandState::Done);
                }
            }
            if let Some(s) = self.groups[g].stop {
                if !self.groups[g].stop_done {
                    self.groups[g].stop_done = true;
                    self.set_state(fbs, s, CommandState::Done);
                }
                let exec = self.instances.get(&s).is_some_and(|i| i.execute);
                if !exec {
                    self.groups[g].stop = None;
                    self.groups[g].stop_done = false;
                    self.groups[g].state = GroupStandby;
                }
            }
        }
        let gr = &mut self.groups[g];
        match gr.state {
            GroupStandby if busy || !standing => gr.state = GroupMoving,
            GroupMoving if !busy && standing => gr.state = GroupStandby,
            _ => {}
        }
        // Diagnostics (§8.7).
        for k in 0..gr.n() {
            let target = gr.eff_gap(k);
            let m = &mut gr.members[k];
            if m.gap.is_finite() {
                m.min_margin = m.min_margin.min(m.gap - target);
            }
        }
    }

    /// Ends reached positions (Done), finished brakes, activates buffered commands.
    fn finish_jobs(&mut self, g: usize, axes: &mut [Axis], fbs: &mut Handshake) {
        for k in 0..self.groups[g].n() {
            let ax = self.groups[g].members[k].axis;
            let s = axes[ax].set;
            let at_rest = s.vel == 0.0 && s.acc == 0.0;
            if let Job::Gear { req, gear } = self.groups[g].members[k].job {
                let m = &mut self.groups[g].members[k];
                if gear.failed {
                    // Late/Slow: no feasible sync profile (§5.5.3).
                    m.job = if at_rest {
                        Job::Idle
                    } else {
                        Job::Brake {
                            req: Request {
                                owner: None,
                                goal: Goal::Brake,
                                ..req
                            },
                        }
                    };
                    if let Some(id) = req.owner {
                        self.set_state(fbs, id, CommandState::Error(err::SLAVE_CANNOT_SYNC));
                    }
                } else if gear.in_sync {
                    // A buffered command starts when the coupling first becomes InSync.
                    if let Some(p) = m.pending.take() {
                        m.job = activate(p, s.pos);
                        if let Some(id) = req.owner {
                            self.set_state(fbs, id, CommandState::Aborted);
                        }
                        if let Some(id) = p.owner {
                            self.set_state(fbs, id, CommandState::Active);
                        }
                    }
                }
                continue;
            }
            if !at_rest {
                continue;
            }
            let job = self.groups[g].members[k].job;
            let finished = match job {
                Job::Position { target, .. } => {
                    if (s.pos - target).abs() <= EPS {
                        let dx = target - s.pos;
                        axes[ax].set.pos = target;
                        self.groups[g].shift(k, dx);
                        true
                    } else {
                        false
                    }
                }
                Job::Brake { .. } => true,
                Job::Idle | Job::Gear { .. } => false,
            };
            if finished {
                let m = &mut self.groups[g].members[k];
                if let Some(r) = job.req() {
                    if r.mode != GapControlMode::None {
                        m.last_gap = r.gap;
                    }
                }
                m.job = Job::Idle;
                axes[ax].target_pos = axes[ax].set.pos;
                if let Some(id) = job.owner() {
                    self.set_state(fbs, id, CommandState::Done);
                }
                if let Some(p) = self.groups[g].members[k].pending.take() {
                    if let Some(id) = p.owner {
                        self.set_state(fbs, id, CommandState::Active);
                    }
                    self.groups[g].members[k].job = activate(p, axes[ax].set.pos);
                }
            }
        }
    }

    /// Runs the planner for every member in the order of §8.3.
    fn plan_cycle(&mut self, g: usize, dt: f64, axes: &mut [Axis]) {
        let gr = &mut self.groups[g];
        let n = gr.n();
        if n == 0 {
            return;
        }
        // Front-to-back order; on a ring from the axis with the largest gap (ties: lowest ident).
        let mut start = 0;
        if gr.cfg.rail_is_ring && n > 1 {
            for k in 1..n {
                let (a, b) = (&gr.members[k], &gr.members[start]);
                if a.gap > b.gap || (a.gap == b.gap && a.ident < b.ident) {
                    start = k;
                }
            }
        }
        let mut order = std::mem::take(&mut gr.order);
        let mut back = std::mem::take(&mut gr.back);
        order.clear();
        back.clear();
        for i in 0..n {
            let k = (start + i) % n;
            gr.members[k].updated = false;
            let m = &gr.members[k];
            if frame_sign(axes[m.axis].set, &m.job, m.retreat) < 0.0 {
                back.push(k);
            } else {
                order.push(k);
            }
        }
        order.extend(back.iter().rev());
        for &k in &order {
            gr.step_member(k, dt, axes);
        }
        gr.order = order;
        gr.back = back;
    }
}

/// The travel frame of an axis: +1 forward, −1 backward (§8.5, mirrored).
fn frame_sign(s: State1, job: &Job, retreat: f64) -> f64 {
    if s.vel > 0.0 {
        1.0
    } else if s.vel < 0.0 {
        -1.0
    } else if s.acc > 0.0 {
        1.0
    } else if s.acc < 0.0 || retreat > ESTABLISH_MIN {
        -1.0
    } else {
        match job {
            Job::Position { target, .. } if *target < s.pos => -1.0,
            Job::Gear { gear, .. } if gear.target < s.pos => -1.0,
            _ => 1.0,
        }
    }
}

fn moving_back(s: State1) -> bool {
    s.vel < 0.0 || (s.vel == 0.0 && s.acc < 0.0)
}

fn moving_fwd(s: State1) -> bool {
    s.vel > 0.0 || (s.vel == 0.0 && s.acc > 0.0)
}

fn kin(s: State1) -> Kin {
    Kin {
        x: s.pos,
        v: s.vel,
        a: s.acc,
    }
}

fn activate(req: Request, x: f64) -> Job {
    match req.goal {
        Goal::Absolute(t) => Job::Position { req, target: t },
        Goal::Relative(d) => Job::Position { req, target: x + d },
        Goal::Brake => Job::Brake { req },
        Goal::Gear(gear) => Job::Gear { req, gear },
    }
}

impl CaGroup {
    /// Member `k` moved by `dx`: its own gap shrinks, its successor's grows.
    fn shift(&mut self, k: usize, dx: f64) {
        if dx == 0.0 {
            return;
        }
        if self.members[k].gap.is_finite() {
            self.members[k].gap -= dx;
        }
        if let Some(s) = self.succ(k) {
            self.members[s].gap += dx;
        }
    }

    /// The pair constraint C4 of member `k` in frame `sg` (§1.5, §8.6) and, in Fast mode, the
    /// neighbour's maximum deceleration (else +inf).
    #[allow(clippy::too_many_arguments)]
    fn c4_bound(
        &self,
        k: usize,
        s: State1,
        sg: f64,
        own_mode: GapControlMode,
        establishing: bool,
        dt: f64,
        axes: &[Axis],
    ) -> (Option<Bound>, f64) {
        let mut fast_dmax = f64::INFINITY;
        let c4 = if own_mode == GapControlMode::None {
            None
        } else if sg > 0.0 {
            self.pred(k).map(|l| {
                let g = self.eff_gap(k);
                let ls = axes[self.members[l].axis].set;
                let xl = s.pos + self.members[k].gap;
                let dl = self.members[l].dynamics.max_d;
                if moving_back(ls) {
                    let sp = stop_point_back(
                        Kin { x: xl, ..kin(ls) },
                        self.members[l].d_b,
                        self.members[l].j_b,
                    );
                    Bound {
                        pos_bound: f64::INFINITY,
                        stop_bound: sp - g,
                    }
                } else if own_mode == GapControlMode::Fast {
                    fast_dmax = dl;
                    let vl = ls.vel;
                    let tau = dt.min(vl / dl);
                    let xh = if self.members[l].updated {
                        xl
                    } else {
                        xl + vl * tau - dl * tau * tau / 2.0
                    };
                    Bound {
                        pos_bound: xh - g,
                        stop_bound: xl + vl * vl / (2.0 * dl) - g,
                    }
                } else {
                    Bound {
                        pos_bound: f64::INFINITY,
                        stop_bound: xl - g,
                    }
                }
            })
        } else if self.cfg.gap_control_direction == GapControlDirection::Both || establishing {
            self.succ(k).map(|b| {
                let g = self.eff_gap(b);
                let bs = axes[self.members[b].axis].set;
                let xb = s.pos - self.members[b].gap;
                let db = self.members[b].dynamics.max_d;
                if moving_fwd(bs) {
                    let sp = stop_point(
                        Kin { x: xb, ..kin(bs) },
                        self.members[b].d_b,
                        self.members[b].j_b,
                    );
                    Bound {
                        pos_bound: f64::INFINITY,
                        stop_bound: -sp - g,
                    }
                } else if self.mode_of(b) == GapControlMode::Fast {
                    fast_dmax = db;
                    let vb = -bs.vel;
                    let tau = dt.min(vb / db);
                    let yb = -xb;
                    let yh = if self.members[b].updated {
                        yb
                    } else {
                        yb + vb * tau - db * tau * tau / 2.0
                    };
                    Bound {
                        pos_bound: yh - g,
                        stop_bound: yb + vb * vb / (2.0 * db) - g,
                    }
                } else {
                    Bound {
                        pos_bound: f64::INFINITY,
                        stop_bound: -xb - g,
                    }
                }
            })
        } else {
            None
        };
        (c4, fast_dmax)
    }

    /// One cycle of an MC_GearInPosCA slave (§5.5.3): the coupled, cam or tracking candidate;
    /// `None` when CA (C4) rejects it (the caller then runs the position planner toward the
    /// coupled target, InSync drops).
    fn step_gear(
        &mut self,
        k: usize,
        req: Request,
        mut gear: Gear,
        dt: f64,
        axes: &mut [Axis],
    ) -> Option<State1> {
        let ax = self.members[k].axis;
        let s = axes[ax].set;
        let ms = axes[gear.master].set;
        let master_updated = self
            .members
            .iter()
            .any(|m| m.axis == gear.master && m.updated);
        // Master at the start and at the end of this cycle (constant acceleration).
        let (m0, mv0, m1, mv1, ma) = if master_updated {
            let mv0 = ms.vel - ms.acc * dt;
            (
                ms.pos - mv0 * dt - ms.acc * dt * dt / 2.0,
                mv0,
                ms.pos,
                ms.vel,
                ms.acc,
            )
        } else {
            let m1 = ms.pos + ms.vel * dt + ms.acc * dt * dt / 2.0;
            (ms.pos, ms.vel, m1, ms.vel + ms.acc * dt, ms.acc)
        };
        let r = gear.ratio;
        let star = |m: f64| gear.ssp + r * (m - gear.msp);
        gear.target = star(m1);
        let coupled = State1 {
            pos: star(m1),
            vel: r * mv1,
            acc: r * ma,
        };
        let dy = Dyn {
            v: req.dy.v * self.ovr_actual,
            ..req.dy
        };
        let cand = if gear.in_sync {
            coupled
        } else {
            if !gear.started && gear.cam.is_none() && gear.strategy != SyncStrategy::Early {
                // Late/Slow: a cam over the master position, only toward a master moving
                // to its sync position with the slave at rest; otherwise Early tracking.
                let at_rest = s.vel == 0.0 && s.acc == 0.0;
                let cam = Cam::new(m0, s, mv0, gear.msp, gear.ssp, r);
                match cam {
                    Some(c) if at_rest && mv0 > 0.0 => {
                        let now_ok = c.feasible(mv0, &dy);
                        let start = match gear.strategy {
                            SyncStrategy::Slow => true,
                            _ => {
                                // Late: start when waiting one more cycle becomes infeasible.
                                let next = Cam::new(m1, s, mv0, gear.msp, gear.ssp, r);
                                !next.is_some_and(|n| n.feasible(mv0, &dy))
                            }
                        };
                        if start {
                            if now_ok {
                                gear.cam = Some(c);
                                gear.started = true;
                            } else {
                                gear.failed = true;
                            }
                        }
                    }
                    _ => gear.strategy = SyncStrategy::Early,
                }
            }
            if let Some(c) = gear.cam {
                if m1 >= gear.msp {
                    gear.in_sync = true;
                    coupled
                } else {
                    let (p, d1, d2) = c.eval(m1);
                    State1 {
                        pos: p,
                        vel: d1 * mv1,
                        acc: d2 * mv1 * mv1 + d1 * ma,
                    }
                }
            } else if gear.strategy == SyncStrategy::Early || gear.started {
                gear.started = true;
                // Early: jerk-limited tracking of s*(t) in the relative frame.
                let rel = Kin {
                    x: s.pos - star(m0),
                    v: s.vel - r * mv0,
                    a: s.acc - r * ma,
                };
                let sgr = if rel.v > 0.0
                    || (rel.v == 0.0 && (rel.a > 0.0 || (rel.a == 0.0 && rel.x < 0.0)))
                {
                    1.0
                } else {
                    -1.0
                };
                let vmax = (dy.v - sgr * r * mv0).max(0.0);
                let o = planner::step(&StepIn {
                    s: if sgr > 0.0 { rel } else { rel.mirror() },
                    vmax,
                    amax: dy.a,
                    dmax: dy.d,
                    jmax: dy.j,
                    target: Some(0.0),
                    d_ca: dy.d,
                    j_ca: dy.j,
                    c4: None,
                    t: dt,
                });
                let e = if sgr > 0.0 { o.s } else { o.s.mirror() };
                if e.x.abs() <= 1e-3 && e.v.abs() <= 1e-3 {
                    gear.in_sync = true;
                    coupled
                } else {
                    State1 {
                        pos: coupled.pos + e.x,
                        vel: coupled.vel + e.v,
                        acc: coupled.acc + e.a,
                    }
                }
            } else {
                s
            }
        };
        // CA outranks the coupling (§1.10).
        let own_mode = self.mode_of(k);
        let sgc = if cand.vel < 0.0 { -1.0 } else { 1.0 };
        let (b, _) = self.c4_bound(k, s, sgc, own_mode, false, dt, axes);
        let m = &mut self.members[k];
        m.d_ca = m.d_ca.max(dy.d.min(m.dynamics.max_d));
        m.j_ca = m.j_ca.max(dy.j);
        let kc = if sgc > 0.0 {
            kin(cand)
        } else {
            kin(cand).mirror()
        };
        let ok = b.is_none_or(|b| planner::c4_ok(&b, kc, m.d_ca, m.j_ca));
        if !ok {
            gear.in_sync = false;
            gear.cam = None;
            gear.strategy = SyncStrategy::Early;
        }
        m.job = Job::Gear { req, gear };
        if !ok {
            return None;
        }
        m.ca_limited = false;
        m.updated = true;
        m.d_b = m.d_ca;
        m.j_b = m.j_ca;
        let dx = cand.pos - s.pos;
        axes[ax].set = cand;
        self.shift(k, dx);
        Some(cand)
    }

    /// One planner step of member `k` (§8.5, §8.6).
    fn step_member(&mut self, k: usize, dt: f64, axes: &mut [Axis]) {
        let ax = self.members[k].axis;
        // CA owns the set values of its members (drops a single-axis error-reaction job).
        axes[ax].job = None;
        if let Job::Gear { req, gear } = self.members[k].job {
            if self.step_gear(k, req, gear, dt, axes).is_some() {
                return;
            }
        }
        let s = axes[ax].set;
        let job = self.members[k].job;
        let ad = self.members[k].dynamics;
        let own_mode = self.mode_of(k);
        let retreat = self.members[k].retreat;
        let establishing = retreat > ESTABLISH_MIN;
        let sg = frame_sign(s, &job, retreat);
        let cfg = &self.cfg;
        // Command limits (idle: brake with the axis defaults if moving; establishing: retreat
        // by `retreat`, with the group defaults when idle, §1.7).
        let (dy, target) = match job {
            Job::Position { req, target } => (
                Dyn {
                    v: req.dy.v * self.ovr_actual,
                    ..req.dy
                },
                Some(
                    if establishing {
                        s.pos - retreat
                    } else {
                        target
                    } * sg,
                ),
            ),
            Job::Brake { req } => (req.dy, None),
            Job::Gear { req, gear } => (
                Dyn {
                    v: req.dy.v * self.ovr_actual,
                    ..req.dy
                },
                Some(gear.target * sg),
            ),
            Job::Idle if establishing => (
                Dyn {
                    v: cfg.default_velocity * self.ovr_actual,
                    a: cfg.default_acceleration,
                    d: cfg.default_deceleration,
                    j: cfg.default_jerk,
                },
                Some((s.pos - retreat) * sg),
            ),
            Job::Idle => {
                if s.vel == 0.0 && s.acc == 0.0 {
                    self.members[k].ca_limited = false;
                    self.members[k].updated = true;
                    return;
                }
                (
                    Dyn {
                        v: ad.max_v,
                        a: ad.max_a,
                        d: ad.def_d,
                        j: ad.def_j,
                    },
                    None,
                )
            }
        };
        let (c4, fast_dmax) = self.c4_bound(k, s, sg, own_mode, establishing, dt, axes);
        // Committed CA braking dynamics (§8.4).
        let m = &mut self.members[k];
        let mut dcmd = dy.d.min(ad.max_d);
        if fast_dmax.is_finite() {
            m.d_ca = ad.max_d.min(fast_dmax);
            m.j_ca = ad.max_j;
            dcmd = dcmd.min(fast_dmax);
        } else if s.vel == 0.0 && s.acc == 0.0 {
            m.d_ca = dcmd;
            m.j_ca = dy.j;
        } else {
            m.d_ca = m.d_ca.max(dcmd);
            m.j_ca = m.j_ca.max(dy.j);
        }
        let fs = if sg > 0.0 { kin(s) } else { kin(s).mirror() };
        let out = planner::step(&StepIn {
            s: fs,
            vmax: dy.v.min(ad.max_v),
            amax: dy.a.min(ad.max_a),
            dmax: dcmd,
            jmax: dy.j,
            target,
            d_ca: m.d_ca,
            j_ca: m.j_ca,
            c4,
            t: dt,
        });
        let e = if sg > 0.0 { out.s } else { out.s.mirror() };
        m.ca_limited = out.ca_limited;
        m.d_b = out.d_b;
        m.j_b = out.j_b;
        m.updated = true;
        let dx = e.x - s.pos;
        axes[ax].set = State1 {
            pos: e.x,
            vel: e.v,
            acc: e.a,
        };
        self.shift(k, dx);
    }
}

/// Velocity/Acceleration/Deceleration/Jerk of a CA move (§5.1), clamped to the maxima.
fn resolve_move(
    ad: &AxisDyn,
    v: McLreal,
    a: McLreal,
    d: McLreal,
    j: McLreal,
) -> Result<Dyn, Rejection> {
    let v = match v {
        McLreal::Value(v) if v.is_finite() && v > 0.0 => v.min(ad.max_v),
        McLreal::Maximum => ad.max_v,
        other => {
            return Err(rej(
                err::INVALID_VELOCITY,
                format!("Velocity = {other:?} is not valid (> 0 required)"),
            ))
        }
    };
    Ok(Dyn {
        v,
        a: resolve_acc(a, ad.def_a, ad.max_a, "Acceleration")?,
        d: resolve_acc(d, ad.def_d, ad.max_d, "Deceleration")?,
        j: resolve_jerk(j, ad.def_j, ad.max_j, false)?,
    })
}

fn resolve_acc(x: McLreal, def: f64, max: f64, what: &str) -> Result<f64, Rejection> {
    match x {
        McLreal::Unset | McLreal::Default => Ok(def),
        McLreal::Maximum => Ok(max),
        McLreal::Value(v) if v.is_finite() && v >= 1.0 => Ok(v.min(max)),
        other => Err(rej(
            err::INVALID_DYNAMICS,
            format!("{what} = {other:?} is not valid (>= 1 required)"),
        )),
    }
}

fn resolve_jerk(x: McLreal, def: f64, max: f64, ignore_ok: bool) -> Result<f64, Rejection> {
    match x {
        McLreal::Unset | McLreal::Default => Ok(def),
        McLreal::Ignore if ignore_ok => Ok(JERK_UNLIMITED),
        McLreal::Value(v) if v.is_finite() && v >= 100.0 => Ok(v.min(max)),
        other => Err(rej(
            err::INVALID_DYNAMICS,
            format!("Jerk = {other:?} is not valid (>= 100 required, MAXIMUM not allowed)"),
        )),
    }
}
