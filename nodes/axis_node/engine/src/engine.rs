//! [`AxisEngine`]: a set of named axes implementing [`motion_core::Engine`].
//!
//! `command` screens the inputs (NaN/inf → NOT_FINITE, unknown axis → UNKNOWN_OBJECT, ranges
//! → 0x4B06 ...), applies the admission matrix (§2.4) and BufferMode (§3.6) and acts at once
//! (the state changes with the command, §2.1). `step` runs one cycle of every axis in the
//! order of §1.1 and hands out the command events.

use crate::axis::{Axis, Job, JobKind, Lock, Pending, Spec};
use crate::buffer;
use crate::command::*;
use crate::config::AxisConfig;
use crate::error_ids::*;
use crate::gearing::MasterState;
use crate::handshake::{FbKind, FbOutputs, Handshake};
use crate::modulo;
use crate::params::{self, ParamType, Slot, StatusValue};
use crate::snapshot::{AxisSnapshot, AxisStatus};
use crate::state::{admission, Admission, FbClass};
use motion_core::{
    CmdId, CommandEvent, CommandState, Engine, ErrorId, ExecuteOutputs, Limits, Rejection, State1,
    Tick,
};
use std::collections::HashMap;

/// The single-axis engine: all configured axes and their FB instances.
#[derive(Debug)]
pub struct AxisEngine {
    pub(crate) axes: Vec<Axis>,
    pub(crate) index: HashMap<String, usize>,
    pub(crate) fbs: Handshake,
    /// Part 4 axis groups (plcopen_platform.md §3.2, §5).
    pub(crate) groups: crate::group::Groups,
    /// Platform profile, safety functions, start-up (plcopen_platform.md §6–§10).
    pub(crate) platform: crate::platform::Platform,
    /// Raw FB layer state (plcopen_platform.md §12.2).
    pub(crate) raw: crate::platform::raw_state::Raw,
    /// Instantaneous commands reported Done in the next cycle (§3.1 rule 2).
    instant_done: Vec<CmdId>,
    tick: u64,
    /// Step order: masters before their slaves (§4.12).
    order: Vec<usize>,
    /// Collision-avoidance groups (collision_avoidance.md).
    ca: crate::ca::CaGroups,
}

fn reject(id: ErrorId, msg: String) -> Rejection {
    Rejection::new(id, msg)
}

/// NaN/inf screening: `axis 'x': MC_MoveAbsolute.Velocity = NaN is not finite`.
fn finite(axis: &str, fb: &str, field: &str, v: f64) -> Result<(), Rejection> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(Rejection::not_finite(
            &format!("axis '{axis}': {fb}"),
            field,
            v,
        ))
    }
}

fn not_correct(axis: &str, fb: &str, field: &str, v: f64, need: &str) -> Rejection {
    reject(
        PARAMETER_NOT_CORRECT,
        format!("axis '{axis}': {fb}: {field} = {v} {need}"),
    )
}

/// Move dynamics (§3.5): finite, Velocity in (0, AxisMaxVelocity], the rest ≥ 0 (0 = default).
fn move_limits(
    a: &Axis,
    fb: &str,
    velocity: Option<f64>,
    acc: f64,
    dec: f64,
    jerk: f64,
) -> Result<Limits, Rejection> {
    let n = &a.name;
    if let Some(v) = velocity {
        finite(n, fb, "Velocity", v)?;
    }
    finite(n, fb, "Acceleration", acc)?;
    finite(n, fb, "Deceleration", dec)?;
    finite(n, fb, "Jerk", jerk)?;
    if let Some(v) = velocity {
        if v <= 0.0 || v > a.cfg.max_velocity {
            return Err(not_correct(
                n,
                fb,
                "Velocity",
                v,
                &format!("must be in (0, {}]", a.cfg.max_velocity),
            ));
        }
    }
    for (f, x) in [("Acceleration", acc), ("Deceleration", dec), ("Jerk", jerk)] {
        if x < 0.0 {
            return Err(not_correct(n, fb, f, x, "must be >= 0 (0 = axis default)"));
        }
    }
    let or = |x: f64, d: f64| if x > 0.0 { x } else { d };
    Ok(Limits {
        velocity: velocity.unwrap_or(a.cfg.max_velocity),
        acceleration: or(acc, a.cfg.acceleration),
        deceleration: or(dec, a.cfg.deceleration),
        jerk: or(jerk, a.cfg.jerk),
    })
}

/// Outputs of MC_Power.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct PowerOutputs {
    /// Status: axis ready for operation.
    pub status: bool,
    /// Busy: called with Enable TRUE.
    pub busy: bool,
    /// Active: Enable applied.
    pub active: bool,
}

/// EndVelocity of MC_MoveContinuous*: finite, in [0, AxisMaxVelocity] (§4.8.7).
fn end_velocity(a: &Axis, fb: &str, ev: f64) -> Result<f64, Rejection> {
    finite(&a.name, fb, "EndVelocity", ev)?;
    if ev < 0.0 || ev > a.cfg.max_velocity {
        return Err(not_correct(
            &a.name,
            fb,
            "EndVelocity",
            ev,
            &format!("must be in [0, {}]", a.cfg.max_velocity),
        ));
    }
    Ok(ev)
}

/// What a motion FB asks for, before the takeover point is known.
#[derive(Clone, Copy, Debug)]
enum Request {
    Absolute(f64),
    Relative(f64),
    Additive(f64),
    Modulo { position: f64, direction: Direction },
    Velocity(Direction),
    Halt,
    ContinuousAbsolute(f64, f64),
    ContinuousRelative(f64, f64),
}

impl AxisEngine {
    /// Builds the engine from `(name, config)` pairs; names must be unique and non-empty,
    /// every config valid (message names axis, key and value).
    pub fn new(axes: Vec<(String, AxisConfig)>) -> Result<Self, Rejection> {
        Self::with_config(axes, &crate::platform::EngineConfig::default())
    }

    /// Builds the engine with an engine-level configuration: `platform_profile`, Part 4
    /// groups and platform settings (plcopen_platform.md). Unknown axis names in it are
    /// refused with `UNKNOWN_OBJECT`.
    pub fn with_config(
        axes: Vec<(String, AxisConfig)>,
        config: &crate::platform::EngineConfig,
    ) -> Result<Self, Rejection> {
        let mut index = HashMap::new();
        let mut list = Vec::with_capacity(axes.len());
        for (i, (name, mut cfg)) in axes.into_iter().enumerate() {
            if name.is_empty() {
                return Err(reject(
                    ErrorId::VALUE_OUT_OF_RANGE,
                    format!("axis #{i}: empty axis name"),
                ));
            }
            if index.insert(name.clone(), i).is_some() {
                return Err(reject(
                    ErrorId::VALUE_OUT_OF_RANGE,
                    format!("axis '{name}' is configured twice"),
                ));
            }
            cfg.validate(&name)?;
            if cfg.axis_id == 0 {
                cfg.axis_id = i as u32 + 1;
            }
            list.push(Axis::new(name, cfg));
        }
        let order = (0..list.len()).collect();
        let mut e = AxisEngine {
            axes: list,
            index,
            fbs: Handshake::new(),
            groups: Default::default(),
            platform: Default::default(),
            raw: Default::default(),
            instant_done: Vec::with_capacity(64),
            tick: 0,
            order,
            ca: crate::ca::CaGroups::default(),
        };
        e.build_groups(&config.groups)?;
        e.build_platform(config)?;
        Ok(e)
    }

    /// The collision-avoidance groups (outputs of CA instances, e.g. MC_GearInPosCA's InSync).
    pub fn ca_groups(&self) -> &crate::ca::CaGroups {
        &self.ca
    }

    /// Adds a collision-avoidance group (startup configuration, collision_avoidance.md §3.1).
    pub fn add_ca_group(
        &mut self,
        name: impl Into<String>,
        cfg: crate::ca::CaGroupConfig,
    ) -> Result<(), Rejection> {
        self.ca.add_group(name.into(), cfg)
    }

    /// Masters before slaves; recomputed when a coupling is made.
    fn recompute_order(&mut self) {
        // Longest master chain above an axis (MC_GearInMultiMaster: over all its masters).
        fn depth(axes: &[Axis], i: usize, guard: usize) -> usize {
            match axes[i].coupling {
                Some(c) if guard > 0 => {
                    1 + c
                        .masters()
                        .map(|m| depth(axes, m, guard - 1))
                        .max()
                        .unwrap_or(0)
                }
                _ => 0,
            }
        }
        let depth = |i: usize| depth(&self.axes, i, self.axes.len());
        let mut order: Vec<(usize, usize)> = (0..self.axes.len()).map(|i| (depth(i), i)).collect();
        order.sort();
        self.order = order.into_iter().map(|(_, i)| i).collect();
    }

    /// CoupleState of axis `i` (0 single, 1 master, 2 master-slave, 3 slave) given whether it
    /// is a master.
    fn couple_state(&self, i: usize, master: bool) -> u32 {
        match (master, self.axes[i].coupling.is_some()) {
            (false, false) => 0,
            (true, false) => 1,
            (true, true) => 2,
            (false, true) => 3,
        }
    }

    fn axis_status(&self, i: usize, master: bool) -> AxisStatus {
        let mut s = self.axes[i].status();
        s.couple_state = self.couple_state(i, master);
        self.ca.patch_status(i, &mut s);
        s
    }

    fn is_master(&self, i: usize) -> bool {
        self.axes
            .iter()
            .any(|a| a.coupling.is_some_and(|c| c.masters().any(|m| m == i)))
    }

    /// Axis names in configuration order.
    pub fn axis_names(&self) -> impl Iterator<Item = &str> {
        self.axes.iter().map(|a| a.name.as_str())
    }

    /// The status of one axis.
    pub fn status(&self, axis: &str) -> Option<AxisStatus> {
        self.index
            .get(axis)
            .map(|&i| self.axis_status(i, self.is_master(i)))
    }

    /// Standard outputs of an admitted Execute-type instance (§3.1–§3.3).
    pub fn outputs(&self, id: CmdId) -> Option<ExecuteOutputs> {
        self.fb_outputs(id)
            .map(|o| o.standard)
            .or_else(|| self.group_outputs(id))
            .or_else(|| self.ca.outputs(id))
    }

    /// All outputs of an instance (incl. InVelocity).
    pub fn fb_outputs(&self, id: CmdId) -> Option<FbOutputs> {
        let mut o = self.fbs.outputs_with(id, self.platform.isg())?;
        if o.standard.error {
            o.standard.error_id = self.platform_error_id(id, o.standard.error_id);
        }
        Some(o)
    }

    /// Outputs of the axis' MC_Power (Enable-type, §4.1): Status, Busy (= Enable), Active
    /// (= Enable and the enable applied). FB errors of MC_Power are rejections of the call.
    pub fn power_outputs(&self, axis: &str) -> Option<PowerOutputs> {
        self.index.get(axis).map(|&i| {
            let a = &self.axes[i];
            PowerOutputs {
                status: a.status,
                busy: a.enable,
                active: a.enable && a.controller_on,
            }
        })
    }

    /// The axis an instance belongs to and its FB.
    pub fn instance(&self, id: CmdId) -> Option<(&str, FbKind)> {
        self.fbs
            .get(id)
            .map(|i| (self.axes[i.axis].name.as_str(), i.kind))
    }

    fn axis_index(&self, name: &str) -> Result<usize, Rejection> {
        self.index
            .get(name)
            .copied()
            .ok_or_else(|| Rejection::unknown_object("axis", name))
    }

    fn reply(id: CmdId) -> AxisReply {
        AxisReply {
            id,
            value: ReplyValue::None,
            tracked: true,
        }
    }

    fn untracked(&mut self, value: ReplyValue) -> AxisReply {
        AxisReply {
            id: self.fbs.untracked_id(),
            value,
            tracked: false,
        }
    }

    // ------------------------------------------------------------------ admission

    fn admit_state(&self, ax: usize, fb: FbClass, fb_name: &str) -> Result<Admission, Rejection> {
        self.ext_setpoint_admission(ax, fb, fb_name)?;
        let a = &self.axes[ax];
        let state = a.state();
        match admission(fb, state) {
            Admission::Reject(id) => Err(reject(
                id,
                format!(
                    "axis '{}': {fb_name} not allowed in state {state:?}",
                    a.name
                ),
            )),
            Admission::IfSlaveAllowed(_) => Err(reject(
                AXIS_CANNOT_BE_STARTED,
                format!(
                    "axis '{}': {fb_name} not allowed on a coupled slave",
                    a.name
                ),
            )),
            ok => Ok(ok),
        }
    }

    /// Admission for commands with an "S?" cell (§2.5): on a coupled slave they are allowed
    /// only with AxisAllowMotionCmdToSlaveAxis = TRUE (else 0x4B01) and BufferMode Aborting
    /// (else 0x4B05). Returns whether the slave must be decoupled first.
    fn admit_motion(
        &self,
        ax: usize,
        fb: FbClass,
        fb_name: &str,
        mode: BufferMode,
    ) -> Result<bool, Rejection> {
        let a = &self.axes[ax];
        match admission(fb, a.state()) {
            Admission::IfSlaveAllowed(_) => {
                if !a.cfg.allow_motion_cmd_to_slave_axis {
                    Err(reject(
                        AXIS_CANNOT_BE_STARTED,
                        format!("axis '{}': {fb_name} not allowed on a coupled slave (AxisAllowMotionCmdToSlaveAxis = FALSE)", a.name),
                    ))
                } else if mode != BufferMode::Aborting {
                    Err(reject(
                        COMMAND_NOT_PERMITTED,
                        format!("axis '{}': {fb_name} on a slave needs BufferMode MC_Aborting, not {mode:?}", a.name),
                    ))
                } else {
                    Ok(true)
                }
            }
            _ => self.admit_state(ax, fb, fb_name).map(|_| false),
        }
    }

    // ------------------------------------------------------------------ SetExecute

    fn set_execute(&mut self, id: CmdId, execute: bool) -> Result<AxisReply, Rejection> {
        let inst = self.fbs.set_execute(id, execute).ok_or_else(|| {
            reject(
                ErrorId::UNKNOWN_OBJECT,
                format!("unknown command instance {}", id.0),
            )
        })?;
        self.set_execute_axis3(&inst, id, execute);
        if inst.kind == FbKind::Stop && !execute {
            let a = &mut self.axes[inst.axis];
            if let Some(lock) = a.lock.as_mut().filter(|l| l.owner == id) {
                lock.execute = false;
            }
        }
        if inst.kind == FbKind::Jog && !execute {
            // Jog button released: continuous modes decelerate, Done at rest (§4.11).
            let a = &mut self.axes[inst.axis];
            if let Some(j) = a
                .job
                .filter(|j| j.owner == Some(id) && j.kind == JobKind::Velocity)
            {
                let l = Limits {
                    velocity: a.cfg.max_velocity,
                    ..j.limits
                };
                a.start_spec(
                    id,
                    Spec::Halt {
                        limits: l,
                        monitor: false,
                    },
                    &mut self.fbs,
                );
            }
        }
        Ok(Self::reply(id))
    }

    // ------------------------------------------------------------------ sim hooks (§1.5)

    fn sim(&mut self, ax: usize, s: Sim) -> Result<AxisReply, Rejection> {
        let a = &mut self.axes[ax];
        match s {
            Sim::InjectAxisError { error_id, .. } => {
                let e = if error_id == 0 {
                    POSITION_LAG
                } else {
                    ErrorId(error_id)
                };
                a.raise_error(e, false, &mut self.fbs);
            }
            Sim::DriveFault { error_id, .. } => {
                let e = if error_id == 0 {
                    POSITION_LAG
                } else {
                    ErrorId(error_id)
                };
                a.raise_error(e, true, &mut self.fbs);
            }
            Sim::ProbeInput { unit, level, .. } => {
                if !(1..=2).contains(&unit) {
                    return Err(reject(
                        ErrorId::VALUE_OUT_OF_RANGE,
                        format!(
                            "axis '{}': sim.probe_input: unit = {unit} must be 1 or 2",
                            a.name
                        ),
                    ));
                }
                a.probe_level[unit as usize - 1] = level;
            }
            Sim::SetFollowingOffset { offset, .. } => {
                finite(&a.name, "sim.set_following_offset", "offset", offset)?;
                a.following_offset = offset;
            }
        }
        Ok(self.untracked(ReplyValue::None))
    }
}

/// Travel direction (±1) of a running job.
fn travel_dir(a: &Axis, j: &Job) -> f64 {
    match j.kind {
        JobKind::Velocity => j.dir,
        _ => {
            let d = j.target + j.offset - a.set.pos;
            if d.abs() > 1e-12 {
                d.signum()
            } else if a.set.vel.abs() > 1e-12 {
                a.set.vel.signum()
            } else {
                1.0
            }
        }
    }
}

/// Installs `pending` behind the running job `j` with the BufferMode's transition velocity
/// (§3.6 rules 4–7), replanning `j` so that it reaches the transition point with it.
fn blend(a: &mut Axis, j: Job, pending: Pending, mode: BufferMode, blend_at: Option<f64>) {
    let dir1 = travel_dir(a, &j);
    let p_trans = blend_at.unwrap_or(j.target + j.offset);
    // A MC_MoveContinuous* arrives with its EndVelocity: that is v1 at the target (§4.8.7).
    let v1 = if j.continuous {
        j.end_vel.abs()
    } else {
        j.velocity
    };
    let (v2, reverse, cap) = match pending.spec {
        Spec::Position { target, limits, .. } => (
            Some(limits.velocity),
            (target - p_trans) * dir1 <= 0.0,
            buffer::stop_capable_velocity(
                (target - p_trans).abs(),
                limits.deceleration,
                limits.jerk,
            ),
        ),
        Spec::Velocity { dir, limits } => (Some(limits.velocity), dir != dir1, f64::INFINITY),
        Spec::Halt { .. } => (None, false, f64::INFINITY),
        Spec::Continuous {
            target,
            end_velocity,
            limits,
        } => (
            Some(limits.velocity),
            (target - p_trans) * dir1 <= 0.0,
            if end_velocity > 0.0 {
                f64::INFINITY
            } else {
                buffer::stop_capable_velocity(
                    (target - p_trans).abs(),
                    limits.deceleration,
                    limits.jerk,
                )
            },
        ),
    };
    let mut v_t = buffer::transition_velocity(mode, v1, v2);
    if reverse || j.kind == JobKind::Halt {
        v_t = 0.0;
    }
    v_t = v_t.min(cap);
    a.pending = Some(pending);
    if v_t <= 0.0 && blend_at.is_none() {
        return; // Buffered: the running job stops at its end, then the follow-up starts.
    }
    let limits = Limits {
        velocity: j.velocity.max(v1).max(v_t),
        ..j.limits
    };
    let try_plan = |a: &Axis, v: f64| {
        a.plan_position(p_trans, v * dir1, &limits)
            .filter(|p| !p.reverses())
    };
    // Rule 5 ("as well as possible"): if v_t cannot be reached at the transition point
    // without a reversal, take the highest reachable velocity below it (0 = like Buffered).
    let (profile, v_t) = match try_plan(a, v_t) {
        Some(p) => (p, v_t),
        None => {
            let Some(mut best) = try_plan(a, 0.0) else {
                return;
            };
            let (mut lo, mut hi) = (0.0, v_t);
            for _ in 0..30 {
                let mid = 0.5 * (lo + hi);
                match try_plan(a, mid) {
                    Some(p) => {
                        best = p;
                        lo = mid;
                    }
                    None => hi = mid,
                }
            }
            (best, lo)
        }
    };
    if let Some(job) = a.job.as_mut() {
        job.kind = JobKind::Position;
        job.profile = profile;
        job.t = 0.0;
        job.offset = 0.0;
        job.target = p_trans;
        job.end_vel = v_t * dir1;
        job.limits = limits;
        job.velocity = limits.velocity;
        job.monitor = false;
        job.owner_aborts_at_end = j.kind == JobKind::Velocity || j.continuous;
        job.paused = a.override_pct <= 0.0;
        job.held = false;
        a.target_pos = p_trans;
    }
}

/// Sets the effective override and replans if it changed.
pub(crate) fn apply_override(a: &mut Axis, pct: f64, fbs: &mut Handshake) {
    if pct != a.override_pct {
        a.override_pct = pct;
        override_changed(a, fbs);
    }
}

/// Replans the running job after an override change (§1.1, §4.8.6).
fn override_changed(a: &mut Axis, fbs: &mut Handshake) {
    let Some(mut j) = a.job else { return };
    let paused = a.override_pct <= 0.0;
    match j.kind {
        JobKind::Position => {
            let target = j.target + j.offset;
            if let Some(p) = a.plan_position(target, j.end_vel, &j.limits) {
                j.profile = p;
                j.t = 0.0;
                j.offset = 0.0;
                j.target = target;
                j.paused = paused;
            }
        }
        JobKind::Velocity => {
            // MC_MoveVelocity reports CommandAborted; the axis keeps moving (§4.8.6).
            if let Some(id) = j
                .owner
                .filter(|&id| fbs.get(id).is_some_and(|i| i.kind == FbKind::MoveVelocity))
            {
                fbs.aborted(id);
                j.owner = None;
            }
            if let Some((p, limit)) = a.plan_velocity(j.dir, &j.limits) {
                j.profile = p;
                j.t = 0.0;
                j.offset = 0.0;
                j.target = limit.unwrap_or(f64::NAN);
                j.paused = paused;
                j.held = false;
            }
        }
        _ => return,
    }
    a.job = Some(j);
}

pub(crate) use crate::axis::shift_coordinates;

/// MC_MoveModulo target (§4.8.4).
#[allow(clippy::too_many_arguments)]
fn modulo_target(
    a: &Axis,
    name: &str,
    fb: &str,
    position: f64,
    direction: Direction,
    limits: &Limits,
    buffered: bool,
    base: f64,
) -> Result<f64, Rejection> {
    let period = a.cfg.modulo_value;
    let tol = a.cfg.modulo_tolerance_window;
    if position < 0.0 {
        return Err(not_correct(name, fb, "Position", position, "must be >= 0"));
    }
    let moving = a.set.vel.abs() > 1e-9;
    if direction == Direction::Undefined
        || (direction == Direction::Current && (!moving || buffered))
    {
        return Err(reject(
            INVALID_MODE,
            format!("axis '{name}': {fb}: Direction {direction:?} not allowed here"),
        ));
    }
    if direction == Direction::ShortestWay && position >= period {
        return Err(not_correct(
            name,
            fb,
            "Position",
            position,
            &format!("must be < {period} for MC_Shortest_Way"),
        ));
    }
    if !moving || buffered {
        let d = modulo::standstill_distance(base, position, period, tol, direction).ok_or_else(
            || {
                reject(
                    INVALID_MODE,
                    format!("axis '{name}': {fb}: Direction {direction:?} not allowed here"),
                )
            },
        )?;
        return Ok(base + d);
    }
    // Moving and aborting: first position with that modulo value at or beyond the stopping
    // point; no reversal allowed.
    let travel = a.set.vel.signum();
    let wanted = match direction {
        Direction::Positive => 1.0,
        Direction::Negative => -1.0,
        _ => travel,
    };
    if wanted != travel && direction != Direction::ShortestWay {
        return Err(reject(
            INVALID_MODE,
            format!("axis '{name}': {fb}: Direction {direction:?} opposite to the current travel"),
        ));
    }
    let stop = a.plan_stop(limits).end().pos;
    Ok(modulo::moving_target(stop, position, period, travel))
}

impl AxisEngine {
    /// One FB call: group and platform calls, instance updates, then single-axis FBs through
    /// the profile hooks.
    pub(crate) fn dispatch(&mut self, mut cmd: AxisCommand) -> Result<AxisReply, Rejection> {
        match cmd {
            AxisCommand::Group(g) => return self.group_command_screened(g),
            AxisCommand::Platform(p) => return self.platform_command(p),
            AxisCommand::SetExecute { id, execute } => {
                if let Some(r) = self.group_set_execute(id, execute) {
                    return Ok(r);
                }
                return self.set_execute(id, execute);
            }
            AxisCommand::ReadFbOutputs { id } => {
                if let Some(o) = self.group_outputs(id) {
                    return Ok(AxisReply {
                        id,
                        value: ReplyValue::Group(crate::group::GroupReply::Outputs(o)),
                        tracked: false,
                    });
                }
                if self.fbs.get(id).is_none() {
                    if let Some(outputs) = self.ca.outputs(id) {
                        let gear = self.ca.gear_outputs(id);
                        let v = crate::ca::CaValue::Outputs { outputs, gear };
                        return Ok(AxisReply {
                            id,
                            value: ReplyValue::Ca(Box::new(v)),
                            tracked: false,
                        });
                    }
                }
                return self.read_fb_outputs(id);
            }
            AxisCommand::Ca(c) => {
                return self
                    .ca
                    .command(c, &mut self.axes, &self.index, &mut self.fbs)
                    .map(AxisReply::from)
            }
            AxisCommand::HomeCalibrationCam {
                id,
                calibration_cam,
            } => return self.home_cam(id, calibration_cam),
            AxisCommand::TouchProbePlcEvent { id, plc_event } => {
                return self.probe_plc_event(id, plc_event)
            }
            AxisCommand::TorqueControlUpdate {
                id,
                torque,
                torque_ramp,
                velocity_limit_high,
                velocity_limit_low,
            } => {
                return self.torque_update(
                    id,
                    torque,
                    torque_ramp,
                    velocity_limit_high,
                    velocity_limit_low,
                )
            }
            // A later call of a running phasing instance (by id, like the updates above).
            AxisCommand::PhasingUpdate(_) => return self.command_axis3(cmd),
            _ => {}
        }
        let ax = self.axis_index(cmd.axis().unwrap_or_default())?;
        // Profile hooks (plcopen_platform.md): screening, then bookkeeping of the result.
        self.platform_pre(ax, &mut cmd)?;
        self.group_screen_axis_command(ax, &cmd)?;
        if cmd.is_plain_motion() {
            self.ca.screen_single_axis_motion(ax)?;
        }
        let (order, kind) = crate::platform::classify(&cmd);
        // The FBs of engine/phasing.rs, multi_master.rs, ext_setpoint.rs, extensions.rs.
        let res = if is_axis3(&cmd) {
            self.command_axis3(cmd)
        } else {
            self.axis_command(ax, cmd)
        };
        self.platform_post(ax, order, kind, res)
    }
}

impl AxisEngine {
    /// The Tc2_MC2 FB semantics of one single-axis call (after the profile hooks).
    fn axis_command(&mut self, ax: usize, cmd: AxisCommand) -> Result<AxisReply, Rejection> {
        // A move FB: its dynamics screened (§3.5), then admitted through the buffer logic (§3.6).
        macro_rules! positioning {
            ($c:expr, $kind:ident, $req:expr) => {{
                let fb = concat!("MC_", stringify!($kind));
                let l = move_limits(
                    &self.axes[ax],
                    fb,
                    Some($c.velocity),
                    $c.acceleration,
                    $c.deceleration,
                    $c.jerk,
                )?;
                self.motion(ax, FbKind::$kind, fb, $req, l, $c.buffer_mode, $c.options)
            }};
        }
        match cmd {
            AxisCommand::Power(c) => self.power(ax, c),
            AxisCommand::Reset(_) => self.reset(ax),
            AxisCommand::MoveAbsolute(c) => {
                finite(&c.axis, "MC_MoveAbsolute", "Position", c.position)?;
                positioning!(c, MoveAbsolute, Request::Absolute(c.position))
            }
            AxisCommand::MoveRelative(c) => {
                finite(&c.axis, "MC_MoveRelative", "Distance", c.distance)?;
                positioning!(c, MoveRelative, Request::Relative(c.distance))
            }
            AxisCommand::MoveAdditive(c) => {
                finite(&c.axis, "MC_MoveAdditive", "Distance", c.distance)?;
                positioning!(c, MoveAdditive, Request::Additive(c.distance))
            }
            AxisCommand::MoveModulo(c) => {
                finite(&c.axis, "MC_MoveModulo", "Position", c.position)?;
                let req = Request::Modulo {
                    position: c.position,
                    direction: c.direction,
                };
                positioning!(c, MoveModulo, req)
            }
            AxisCommand::MoveVelocity(c) => {
                positioning!(c, MoveVelocity, Request::Velocity(c.direction))
            }
            AxisCommand::MoveContinuousAbsolute(c) => {
                let fb = "MC_MoveContinuousAbsolute";
                finite(&c.axis, fb, "Position", c.position)?;
                let ev = end_velocity(&self.axes[ax], fb, c.end_velocity)?;
                positioning!(
                    c,
                    MoveContinuousAbsolute,
                    Request::ContinuousAbsolute(c.position, ev)
                )
            }
            AxisCommand::MoveContinuousRelative(c) => {
                let fb = "MC_MoveContinuousRelative";
                finite(&c.axis, fb, "Distance", c.distance)?;
                let ev = end_velocity(&self.axes[ax], fb, c.end_velocity)?;
                positioning!(
                    c,
                    MoveContinuousRelative,
                    Request::ContinuousRelative(c.distance, ev)
                )
            }
            AxisCommand::Halt(c) => {
                let l = self.halt_limits(ax, "MC_Halt", c.deceleration, c.jerk)?;
                self.motion(
                    ax,
                    FbKind::Halt,
                    "MC_Halt",
                    Request::Halt,
                    l,
                    c.buffer_mode,
                    c.options,
                )
            }
            AxisCommand::Stop(c) => self.stop(ax, c),
            AxisCommand::SetPosition(c) => self.set_position(ax, c),
            AxisCommand::ReadParameter(c) => {
                let v = self.read_param(ax, "MC_ReadParameter", c.parameter_number, false)?;
                Ok(self.untracked(ReplyValue::Real(v)))
            }
            AxisCommand::ReadBoolParameter(c) => {
                let v = self.read_param(ax, "MC_ReadBoolParameter", c.parameter_number, true)?;
                Ok(self.untracked(ReplyValue::Bool(v != 0.0)))
            }
            AxisCommand::WriteParameter(c) => {
                self.write_param(ax, "MC_WriteParameter", c.parameter_number, c.value, false)
            }
            AxisCommand::WriteBoolParameter(c) => self.write_param(
                ax,
                "MC_WriteBoolParameter",
                c.parameter_number,
                c.value as u8 as f64,
                true,
            ),
            AxisCommand::ReadStatus(_) => {
                // The same source as the snapshot (CoupleState 1/2 of a master, CA fields).
                let s = self.axis_status(ax, self.is_master(ax));
                Ok(self.untracked(ReplyValue::Status(Box::new(s))))
            }
            AxisCommand::ReadActualPosition(_) => {
                let v = self.axes[ax].act_pos;
                Ok(self.untracked(ReplyValue::Real(v)))
            }
            AxisCommand::ReadActualVelocity(_) => {
                let v = self.axes[ax].act_velo;
                Ok(self.untracked(ReplyValue::Real(v)))
            }
            AxisCommand::ReadAxisError(_) => {
                let v = self.axes[ax].error_id.0;
                Ok(self.untracked(ReplyValue::DWord(v)))
            }
            AxisCommand::Sim(s) => self.sim(ax, s),
            AxisCommand::Home(c) => self.home(ax, c),
            AxisCommand::Jog(c) => self.jog(ax, c),
            AxisCommand::SetOverride(c) => self.set_override(ax, c),
            AxisCommand::GearIn(c) => self.gear_in(ax, c),
            AxisCommand::GearOut(_) => self.gear_out(ax),
            AxisCommand::GearInDyn(c) => self.gear_in_dyn(ax, c),
            AxisCommand::TorqueControl(c) => self.torque_control(ax, c),
            AxisCommand::MoveSuperImposed(c) => self.move_superimposed(ax, c),
            AxisCommand::TouchProbe(c) => self.touch_probe(ax, c),
            AxisCommand::AbortTrigger(c) => self.abort_trigger(ax, c),
            AxisCommand::AbortSuperposition(_) => self.abort_superposition(ax),
            AxisCommand::SetExecute { .. }
            | AxisCommand::HomeCalibrationCam { .. }
            | AxisCommand::TorqueControlUpdate { .. }
            | AxisCommand::TouchProbePlcEvent { .. }
            | AxisCommand::ReadFbOutputs { .. }
            | AxisCommand::Group(_)
            | AxisCommand::Platform(_)
            | AxisCommand::Ca(_) => {
                unreachable!("handled above")
            }
            AxisCommand::PhasingAbsolute(_)
            | AxisCommand::PhasingRelative(_)
            | AxisCommand::HaltPhasing(_)
            | AxisCommand::PhasingUpdate(_)
            | AxisCommand::GearInMultiMaster(_)
            | AxisCommand::ExtSetPointGenEnable(_)
            | AxisCommand::ExtSetPointGenDisable(_)
            | AxisCommand::ExtSetPointGenFeed(_)
            | AxisCommand::ExtSetPointGenFeedWithTorque(_)
            | AxisCommand::ReadDriveOperationMode(_)
            | AxisCommand::WriteDriveOperationMode(_)
            | AxisCommand::BacklashCompensation(_)
            | AxisCommand::PositionCorrectionLimiter(_)
            | AxisCommand::ReadDriveAddress(_)
            | AxisCommand::SelectControlLoop(_)
            | AxisCommand::SetAcceptBlockedDriveSignal(_)
            | AxisCommand::SetEncoderScalingFactor(_)
            | AxisCommand::WriteNcIoOutput(_)
            | AxisCommand::TableBasedPositionCompensation(_)
            | AxisCommand::ConvertIncPosToPos(_)
            | AxisCommand::ConvertPosToIncPos(_)
            | AxisCommand::ReadParameterSet(_)
            | AxisCommand::ReadAxisComponents(_)
            | AxisCommand::WriteParameterPersistent(_)
            | AxisCommand::WriteBoolParameterPersistent(_) => {
                unreachable!("handled by command_axis3")
            }
        }
    }
}

impl Engine for AxisEngine {
    type Command = AxisCommand;
    type Reply = AxisReply;
    type Snapshot = AxisSnapshot;

    fn command(&mut self, cmd: AxisCommand) -> Result<AxisReply, Rejection> {
        self.dispatch(cmd)
    }

    /// MC_Stop on every axis with its AxisFastDec/AxisFastJerk (the error reaction's
    /// dynamics); an axis that cannot take it (disabled, already stopping) is left as it is.
    fn fail_safe_stop(&mut self) {
        for i in 0..self.axes.len() {
            let cfg = &self.axes[i].cfg;
            let stop = Stop {
                axis: self.axes[i].name.clone(),
                deceleration: cfg.fast_deceleration,
                jerk: cfg.fast_jerk,
                options: MoveOptions::default(),
            };
            let _ = self.dispatch(AxisCommand::Stop(stop));
        }
    }

    fn at_rest(&self) -> bool {
        (0..self.axes.len()).all(|i| self.axis_status(i, false).set_velo == 0.0)
    }

    fn step(&mut self, tick: Tick, events: &mut Vec<CommandEvent>) {
        // A non-positive or non-finite cycle time cannot advance anything (defensive: the
        // runtime always passes the configured period).
        if !(tick.dt > 0.0 && tick.dt.is_finite()) {
            events.append(&mut self.fbs.events);
            return;
        }
        self.fbs.cycle += 1;
        self.fbs.in_step = true;
        self.tick = tick.index;
        for i in 0..self.instant_done.len() {
            let id = self.instant_done[i];
            self.fbs.done(id);
        }
        self.instant_done.clear();
        self.platform_step_pre();
        self.groups_step(tick.dt);
        self.ca.step(tick.dt, &mut self.axes, &mut self.fbs);
        for k in 0..self.order.len() {
            let i = self.order[k];
            let master = self.axes[i]
                .coupling
                .map(|c| MasterState::of(&self.axes[c.master]));
            self.pre_step_axis3(i, tick.dt);
            self.axes[i].step(tick.dt, master, &mut self.fbs);
            self.post_step_axis3(i, tick.dt);
        }
        self.platform_step_post();
        self.fbs.in_step = false;
        let from = events.len();
        events.append(&mut self.fbs.events);
        self.platform_map_events(&mut events[from..]);
        self.raw_route(events, from);
    }

    fn snapshot(&self) -> AxisSnapshot {
        AxisSnapshot {
            tick: self.tick,
            axes: {
                let mut master = vec![false; self.axes.len()];
                for a in &self.axes {
                    if let Some(c) = a.coupling {
                        for m in c.masters() {
                            master[m] = true;
                        }
                    }
                }
                let starting = self.platform.starting();
                (0..self.axes.len())
                    .map(|i| {
                        let mut s = self.axis_status(i, master[i]);
                        s.ext = self.ext_values(i);
                        if starting {
                            // INIT_STATE during start-up (§9).
                            s.motion_state = crate::state::MotionState::Undefined;
                        }
                        s
                    })
                    .collect()
            },
            groups: (0..self.groups.list.len())
                .map(|g| self.group_status(g))
                .collect(),
            platform: self.platform_status(),
            ca_groups: self.ca.snapshot(&self.axes),
        }
    }

    fn reply_id(reply: &AxisReply) -> Option<CmdId> {
        // Read-type calls and MC_Power have no lifetime of their own: nothing to watch.
        reply.tracked.then_some(reply.id)
    }

    fn error_text(id: ErrorId) -> String {
        if let Some(t) = crate::platform::ids::text(id) {
            return format!("{}: {t}", id.0);
        }
        crate::error_ids::text(id)
    }

    fn cancel(&mut self, id: CmdId) -> Result<(), Rejection> {
        if let Some(r) = self.group_cancel(id) {
            return r;
        }
        // A cancelled goal halts the axis with the command's own dynamics (MC_Halt semantics).
        if self.fbs.get(id).is_none() && self.ca.owns(id) {
            return self.ca.cancel(id, &self.axes, &mut self.fbs);
        }
        let Some(inst) = self.fbs.get(id).copied() else {
            return Err(reject(
                ErrorId::UNKNOWN_OBJECT,
                format!("unknown command instance {}", id.0),
            ));
        };
        if inst.state.is_final() {
            return Ok(());
        }
        if self.cancel_axis3(&inst, id) {
            return Ok(());
        }
        if inst.kind == FbKind::Jog {
            // A jog goal's cancel lets go of its button (Execute falling, §4.11): continuous
            // modes brake with the jog's own deceleration and end Done, as for an operator.
            return self.set_execute(id, false).map(|_| ());
        }
        let a = &mut self.axes[inst.axis];
        if a.pending.is_some_and(|p| p.owner == id) {
            a.pending = None;
            self.fbs.aborted(id);
            return Ok(());
        }
        if a.job
            .is_some_and(|j| j.owner == Some(id) && j.kind != JobKind::Stop)
        {
            let j = a.job.unwrap_or_else(|| unreachable!());
            a.abort_motion(&mut self.fbs);
            let profile = a.plan_stop(&j.limits);
            let stop = profile.end().pos;
            a.start_job(Job::internal(JobKind::Halt, profile, stop, j.limits));
        } else if a.settle.is_some_and(|s| s.owner == id) {
            a.settle = None;
            self.fbs.aborted(id);
        }
        Ok(())
    }
}

// ---- FBs added after the first release (phasing, multi-master gearing, external setpoint
// generator, §4.7 extensions): child modules, so they can use the engine's private helpers;
// `hooks` is the one place where they plug into `command` and `step`.
// ---- The FBs' calls by concept: child modules of the engine (its private helpers are
// theirs too).
mod coupling;
mod groups;
mod home;
mod jog;
mod moves;
mod parameters;
mod power;
mod superimposed;
mod torque_control;
mod touch_probe;

pub mod ext_setpoint;
pub mod extensions;
pub mod hooks;
pub(crate) use hooks::is_axis3;
pub mod multi_master;
pub mod phasing;
